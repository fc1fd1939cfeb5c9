#!/usr/bin/env python3
"""scenes/water-bottle.ron rendered by Mitsuba 3, an independent path
tracer, as the reference glint's path tracer is compared with on a real,
textured asset (docs/scenes.md, "Materials").

The glTF file goes to Mitsuba through gltf_asset.py (its one node's
transform, then the RON file's placement): a PLY mesh; its textures
Mitsuba's own bitmap textures (base colour and emission as sRGB,
metallic-roughness and normals as data), its normal texture bending the
metallic-roughness BSDF of glint_mitsuba.py (its `glint_normalmap`), its
emission Mitsuba's area emitter.

    pip install mitsuba        # 3.x; the LLVM variant wants libLLVM
    tools/mitsuba/water_bottle.py --spp 4096 --size 256 --out ref.exr
    glint render scenes/water-bottle.ron --graph passes/pathtrace.ron \\
        --size 256x256 --frames 4096 --out glint.exr
    glint compare ref.exr glint.exr
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from glint_mitsuba import cornell_box, main  # noqa: E402
from gltf_asset import Asset, placement  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ASSET = os.path.join(REPO, "scenes", "assets", "water-bottle", "WaterBottle.gltf")

# scenes/water-bottle.ron's Gltf(...) placement and light, number for number.
TRANSLATE = (0.0, -0.349, -0.1)
SCALE = 5.0
ROTATE_DEG = (0.0, 300.0, 0.0)
LIGHT_CENTER = (0.0, 0.75, 0.2)


def bottle(folder, translate=TRANSLATE, scale=SCALE, rotate_deg=ROTATE_DEG):
    """The bottle as a Mitsuba shape (gltf_asset.py): its PLY, its textured
    metallic-roughness BSDF under its normal map, its emission. (Its
    material is single-sided, but the mesh is closed: no ray meets a back
    face, so both sides shaded or not give the same image.)"""
    shapes = Asset(ASSET).shapes(folder, "bottle", placement(translate, scale, rotate_deg))
    assert len(shapes) == 1, "one material"
    return next(iter(shapes.values()))


def scene(size, folder):
    d = cornell_box(size, folder, light_center=LIGHT_CENTER)
    d["bottle"] = bottle(folder)
    return d


if __name__ == "__main__":
    main(__doc__, scene)

#!/usr/bin/env python3
"""scenes/dungeon.ron rendered by Mitsuba 3, an independent path tracer, as
the reference glint's path tracer is compared with on a room-sized real
asset (docs/scenes.md, "Materials"): the dungeon's glTF file through
gltf_asset.py (its textures, vertex colours, alpha-masked gate and lights)
under the sky map of scenes/sky.ron turned as the scene turns it.

    tools/fetch-dungeon
    pip install mitsuba pillow   # 3.x; the LLVM variant wants libLLVM
    tools/mitsuba/dungeon.py --spp 1024 --size 256 --out ref.exr
    glint render scenes/dungeon.ron --graph passes/pathtrace.ron \\
        --size 256x256 --frames 1024 --out glint.exr
    glint compare ref.exr glint.exr
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mitsuba as mi  # noqa: E402  (glint_mitsuba sets the variant)
from glint_mitsuba import base_scene, main  # noqa: E402
from gltf_asset import Asset, placement  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ASSET = os.path.join(REPO, "scenes", "assets", "dungeon", "level-dungeon.gltf")
SKY = os.path.join(REPO, "scenes", "assets", "sky", "sky.pfm")


def scene(size, folder):
    # scenes/dungeon.ron, number for number.
    d = base_scene(size, (-26.0, 1.6, 0.0), (0.0, 1.4, 0.0), 55.0)
    d["sky"] = {"type": "envmap", "filename": SKY, "scale": 1.0, "to_world": mi.ScalarTransform4f().rotate(axis=[0, 1, 0], angle=270.0)}
    asset = Asset(ASSET)
    d.update(asset.shapes(folder, "dungeon", placement()))
    d.update(asset.lights(placement()))
    return d


if __name__ == "__main__":
    main(__doc__, scene)

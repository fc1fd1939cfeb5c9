#!/usr/bin/env python3
"""scenes/cornell-pbr.ron rendered by Mitsuba 3, an independent path tracer,
as the reference glint's path tracer is compared with (docs/scenes.md,
"Materials").

The scene is written out here from the RON file's numbers; the metallic-
roughness BRDF is the Mitsuba BSDF plugin of glint_mitsuba.py.

    pip install mitsuba        # 3.x; the LLVM variant wants libLLVM
    tools/mitsuba/cornell_pbr.py --spp 4096 --size 256 --out ref.exr
    glint render scenes/cornell-pbr.ron --graph passes/pathtrace.ron \\
        --size 256x256 --frames 4096 --out glint.exr
    glint compare ref.exr glint.exr
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from glint_mitsuba import cornell_box, main, metal_rough  # noqa: E402


def scene(size, folder):
    # scenes/cornell-pbr.ron, number for number.
    gold = metal_rough([1.0, 0.766, 0.336], 1.0, 0.35)
    plastic = metal_rough([0.1, 0.25, 0.8], 0.0, 0.2)
    steel = metal_rough([0.56, 0.57, 0.58], 1.0, 0.55)
    d = cornell_box(size, folder, floor=steel)
    d["gold"] = {"type": "sphere", "center": [-0.4, -0.65, -0.3], "radius": 0.35, "bsdf": gold}
    d["plastic"] = {"type": "sphere", "center": [0.45, -0.65, 0.25], "radius": 0.35, "bsdf": plastic}
    return d


if __name__ == "__main__":
    main(__doc__, scene)

#!/usr/bin/env python3
"""scenes/courtyard.ron rendered by Mitsuba 3, an independent path tracer,
as the reference glint's path tracer is compared with on a real asset
under a real HDRI (docs/scenes.md, "Environment"): the water bottle as
water_bottle.py hands it over, a mirror sphere, a ground quad, and the
courtyard map through Mitsuba's `envmap`, turned about +y as glint turns
it.

    pip install mitsuba        # 3.x; the LLVM variant wants libLLVM
    tools/mitsuba/courtyard.py --spp 2048 --size 256 --out ref.exr
    glint render scenes/courtyard.ron --graph passes/pathtrace.ron \\
        --size 256x256 --frames 2048 --out glint.exr
    glint compare ref.exr glint.exr
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mitsuba as mi  # noqa: E402  (glint_mitsuba sets the variant)
from glint_mitsuba import base_scene, ground, lambert, main, mirror  # noqa: E402
from water_bottle import bottle  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HDRI = os.path.join(REPO, "scenes", "assets", "hdri", "courtyard.exr")


def scene(size, folder):
    # scenes/courtyard.ron, number for number.
    d = base_scene(size, (0.0, 0.8, 3.2), (0.1, 0.4, 0.0), 36.0)
    d["sky"] = {"type": "envmap", "filename": HDRI, "scale": 0.6, "to_world": mi.ScalarTransform4f().rotate(axis=[0, 1, 0], angle=90.0)}
    d["ground"] = ground(folder, 8.0, lambert([0.42, 0.41, 0.40]))
    d["bottle"] = bottle(folder, translate=(-0.25, 0.39, 0.0), scale=3.0, rotate_deg=(0.0, 300.0, 0.0))
    d["mirror"] = {"type": "sphere", "center": [0.45, 0.28, -0.25], "radius": 0.28, "bsdf": mirror([0.9, 0.9, 0.9])}
    return d


if __name__ == "__main__":
    main(__doc__, scene)

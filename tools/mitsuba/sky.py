#!/usr/bin/env python3
"""scenes/sky.ron rendered by Mitsuba 3, an independent path tracer, as
the reference glint's environment light is compared with (docs/scenes.md,
"Environment"): the same latitude-longitude map through Mitsuba's
`envmap` emitter (its mapping is glint's), a ground quad, a diffuse
sphere, a mirror and a rough gold sphere (the metallic-roughness BSDF of
glint_mitsuba.py).

    pip install mitsuba        # 3.x; the LLVM variant wants libLLVM
    tools/mitsuba/sky.py --spp 4096 --size 256 --out ref.exr
    glint render scenes/sky.ron --graph passes/pathtrace.ron \\
        --size 256x256 --frames 4096 --out glint.exr
    glint compare ref.exr glint.exr
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from glint_mitsuba import base_scene, ground, lambert, main, metal_rough, mirror  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SKY = os.path.join(REPO, "scenes", "assets", "sky", "sky.pfm")


def scene(size, folder):
    # scenes/sky.ron, number for number.
    d = base_scene(size, (0.0, 1.2, 4.5), (0.0, 0.4, 0.0), 40.0)
    d["sky"] = {"type": "envmap", "filename": SKY, "scale": 1.0}
    d["ground"] = ground(folder, 6.0, lambert([0.5, 0.48, 0.45]))
    d["white"] = {"type": "sphere", "center": [-1.1, 0.5, 0.0], "radius": 0.5, "bsdf": lambert([0.8, 0.8, 0.8])}
    d["mirror"] = {"type": "sphere", "center": [0.0, 0.5, -0.6], "radius": 0.5, "bsdf": mirror([0.9, 0.9, 0.9])}
    d["gold"] = {"type": "sphere", "center": [1.1, 0.5, 0.2], "radius": 0.5, "bsdf": metal_rough([1.0, 0.766, 0.336], 1.0, 0.3)}
    return d


if __name__ == "__main__":
    main(__doc__, scene)

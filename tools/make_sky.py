#!/usr/bin/env python3
"""Writes a procedural sky as a latitude-longitude PFM (linear RGB):
a blue gradient above the horizon, a warm glow around a small sun, and
a grey-brown ground below. glint's environment light and Mitsuba's
`envmap` read the same file (docs/scenes.md, "Environment").

    tools/make_sky.py scenes/assets/sky/sky.pfm [--width 128]

The mapping is glint's (and Mitsuba's): column u = atan2(x, -z) / 2 pi,
row v = acos(y) / pi from the top. No dependencies beyond Python."""
import argparse
import math
import struct


def sky(d, sun):
    x, y, z = d
    cos_sun = max(-1.0, min(1.0, x * sun[0] + y * sun[1] + z * sun[2]))
    if y >= 0.0:
        t = y ** 0.5
        c = [0.9 * (1 - t) + 0.25 * t, 1.0 * (1 - t) + 0.45 * t, 1.1 * (1 - t) + 1.0 * t]
        glow = 2.0 * math.exp((cos_sun - 1.0) * 12.0)
        c = [c[0] + glow * 1.0, c[1] + glow * 0.75, c[2] + glow * 0.45]
    else:
        c = [0.3, 0.25, 0.2]
    if cos_sun > math.cos(math.radians(3.0)):
        c = [300.0, 270.0, 225.0]
    return c


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--width", type=int, default=128)
    args = ap.parse_args()
    w = args.width
    h = w // 2
    el, az = math.radians(35.0), math.radians(60.0)
    sun = (math.cos(el) * math.sin(az), math.sin(el), -math.cos(el) * math.cos(az))
    rows = []
    for j in range(h):
        theta = math.pi * (j + 0.5) / h
        row = []
        for i in range(w):
            phi = 2 * math.pi * (i + 0.5) / w
            d = (math.sin(phi) * math.sin(theta), math.cos(theta), -math.cos(phi) * math.sin(theta))
            row.append(sky(d, sun))
        rows.append(row)
    with open(args.out, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        # PFM rows go from the bottom up.
        for row in reversed(rows):
            for c in row:
                f.write(struct.pack("<3f", *c))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Write a triangle mesh as OBJ (positions, unit vertex normals, CCW faces).

    tools/gen_mesh.py --shape torus-knot --tris 4000 --out scenes/meshes/knot.obj
    tools/gen_mesh.py --shape sphere --tris 20000 --out /tmp/sphere.obj --kd 0.8,0.2,0.2

Shapes are tessellated on a grid, so the triangle count is the grid's count
nearest to --tris (printed on stdout). Output is deterministic: the same
arguments give the same bytes. Standard library only.

--kd R,G,B also writes FILE.mtl (same stem) with one material of that albedo,
and --ks S / --ns N add a specular weight and a Phong exponent to it.
"""

import argparse
import math
import os
import sys


def torus_knot(tris, radius, tube, p, q):
    """(p, q) torus knot: a tube of radius `tube` around the curve
    (radius * (2 + cos(qt/p)) / 2 * (cos t, sin t), radius * sin(qt/p) / 2),
    t in [0, 2 pi p). The ring lies in the xy plane; the bounding box is
    centred on the origin."""
    # A tube of `sides` segments around, `rings` along: 2 * rings * sides
    # triangles. Keep the quads roughly square: rings ~ 8 * sides.
    sides = max(3, round(math.sqrt(tris / 16.0)))
    rings = max(3, round(tris / (2.0 * sides)))

    def curve(t):
        r = radius * (2.0 + math.cos(q / p * t)) * 0.5
        return (r * math.cos(t), r * math.sin(t), radius * math.sin(q / p * t) * 0.5)

    verts, normals = [], []
    for i in range(rings):
        t = 2.0 * math.pi * p * i / rings
        c0 = curve(t)
        c1 = curve(t + 0.01)
        tangent = sub(c1, c0)
        # Frame from the curve point and its tangent (as three.js does):
        # periodic in t, so the tube closes without a twist seam.
        binormal = normalize(cross(tangent, add(c1, c0)))
        normal = normalize(cross(binormal, tangent))
        for j in range(sides):
            a = 2.0 * math.pi * j / sides
            cx, cy = -tube * math.cos(a), tube * math.sin(a)
            off = add(scale(normal, cx), scale(binormal, cy))
            verts.append(add(c0, off))
            normals.append(normalize(off))
    faces = []
    for i in range(rings):
        for j in range(sides):
            a = i * sides + j
            b = ((i + 1) % rings) * sides + j
            c = ((i + 1) % rings) * sides + (j + 1) % sides
            d = i * sides + (j + 1) % sides
            faces.append((a, b, d))
            faces.append((b, c, d))
    return orient_outward(recenter(verts), normals, faces)


def sphere(tris, radius):
    """UV sphere: `stacks` bands, `slices` = 2 * stacks around; the pole
    bands are fans. 2 * slices * (stacks - 1) triangles."""
    stacks = max(2, round((1.0 + math.sqrt(1.0 + tris)) / 2.0))
    slices = 2 * stacks
    verts, normals = [], []
    verts.append((0.0, radius, 0.0))
    normals.append((0.0, 1.0, 0.0))
    for i in range(1, stacks):
        theta = math.pi * i / stacks
        for j in range(slices):
            phi = 2.0 * math.pi * j / slices
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            verts.append(scale(n, radius))
            normals.append(n)
    verts.append((0.0, -radius, 0.0))
    normals.append((0.0, -1.0, 0.0))
    bottom = len(verts) - 1

    def ring(i, j):  # vertex j of ring i (1 .. stacks - 1)
        return 1 + (i - 1) * slices + j % slices

    faces = []
    for j in range(slices):
        faces.append((0, ring(1, j), ring(1, j + 1)))
    for i in range(1, stacks - 1):
        for j in range(slices):
            a, b = ring(i, j), ring(i, j + 1)
            c, d = ring(i + 1, j), ring(i + 1, j + 1)
            faces.append((a, c, d))
            faces.append((a, d, b))
    for j in range(slices):
        faces.append((ring(stacks - 1, j), bottom, ring(stacks - 1, j + 1)))
    return orient_outward(verts, normals, faces)


def recenter(verts):
    """Moves the bounding box centre to the origin."""
    mid = [(min(v[k] for v in verts) + max(v[k] for v in verts)) * 0.5 for k in range(3)]
    return [sub(v, mid) for v in verts]


def orient_outward(verts, normals, faces):
    """Flip any face whose winding disagrees with its vertex normals, so
    counter-clockwise is always the outside."""
    out = []
    for f in faces:
        p0, p1, p2 = (verts[k] for k in f)
        n = cross(sub(p1, p0), sub(p2, p0))
        avg = add(add(normals[f[0]], normals[f[1]]), normals[f[2]])
        out.append(f if dot(n, avg) >= 0.0 else (f[0], f[2], f[1]))
    return verts, normals, out


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(a):
    length = math.sqrt(dot(a, a))
    return scale(a, 1.0 / length) if length > 0.0 else (0.0, 1.0, 0.0)


def fmt(x):
    s = "%.6f" % x
    return "0.000000" if s == "-0.000000" else s


def write(path, verts, normals, faces, shape, mtl):
    lines = ["# glint tools/gen_mesh.py: %s, %d vertices, %d triangles" % (shape, len(verts), len(faces))]
    if mtl:
        lines.append("mtllib %s" % os.path.basename(mtl[0]))
    lines.append("o %s" % shape)
    lines += ["v %s %s %s" % tuple(map(fmt, v)) for v in verts]
    lines += ["vn %s %s %s" % tuple(map(fmt, n)) for n in normals]
    if mtl:
        lines.append("usemtl %s" % mtl[1])
    lines += ["f %d//%d %d//%d %d//%d" % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1) for a, b, c in faces]
    with open(path, "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--shape", choices=["torus-knot", "sphere"], default="torus-knot")
    ap.add_argument("--tris", type=int, required=True, help="wanted triangle count (nearest grid is used)")
    ap.add_argument("--out", required=True, help="OBJ file to write")
    ap.add_argument("--radius", type=float, default=1.0, help="sphere radius / knot radius (default 1)")
    ap.add_argument("--tube", type=float, default=0.3, help="torus-knot tube radius (default 0.3)")
    ap.add_argument("--pq", default="2,3", help="torus-knot winding numbers p,q (default 2,3)")
    ap.add_argument("--kd", help="R,G,B: also write an MTL file with this albedo")
    ap.add_argument("--ks", type=float, default=0.0, help="MTL specular weight (with --kd)")
    ap.add_argument("--ns", type=float, default=0.0, help="MTL Phong exponent (with --kd)")
    args = ap.parse_args()
    if args.tris < 8:
        ap.error("--tris must be at least 8")

    if args.shape == "sphere":
        verts, normals, faces = sphere(args.tris, args.radius)
    else:
        p, q = (int(x) for x in args.pq.split(","))
        verts, normals, faces = torus_knot(args.tris, args.radius, args.tube, p, q)

    mtl = None
    if args.kd:
        kd = [float(x) for x in args.kd.split(",")]
        if len(kd) != 3:
            ap.error("--kd takes R,G,B")
        name = os.path.splitext(os.path.basename(args.out))[0]
        mtl = (os.path.splitext(args.out)[0] + ".mtl", name)
        with open(mtl[0], "w", newline="\n") as f:
            f.write("# glint tools/gen_mesh.py\nnewmtl %s\nKd %s %s %s\n" % ((name,) + tuple(map(fmt, kd))))
            if args.ks > 0.0:
                f.write("Ks %s %s %s\nNs %s\n" % (fmt(args.ks), fmt(args.ks), fmt(args.ks), fmt(args.ns)))
    write(args.out, verts, normals, faces, args.shape, mtl)

    lo = [min(v[k] for v in verts) for k in range(3)]
    hi = [max(v[k] for v in verts) for k in range(3)]
    print("%s: %d triangles, %d vertices, bounds (%s) .. (%s)" % (
        args.out, len(faces), len(verts), ", ".join(map(fmt, lo)), ", ".join(map(fmt, hi))))
    return 0


if __name__ == "__main__":
    sys.exit(main())

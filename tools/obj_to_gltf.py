#!/usr/bin/env python3
"""Writes an OBJ mesh (v, vn, f; its MTL's Kd as the base colour) as a glTF 2.0
file: one mesh under a root node that carries an optional placement, and an
optional KHR_lights_punctual point light. Test fixtures for glint's glTF
reader (tests/gltf.rs); not a general converter (no UVs, one material).

  tools/obj_to_gltf.py scenes/meshes/knot.obj --out scenes/meshes/knot.gltf
  tools/obj_to_gltf.py in.obj --out out.glb --translate 0,1,0 --rotate-deg 0,25,0 --scale 0.5
"""
import argparse
import base64
import json
import math
import os
import struct


def read_obj(path):
    v, vn, faces, mtllib = [], [], [], None
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "v":
                v.append(tuple(float(x) for x in w[1:4]))
            elif w[0] == "vn":
                vn.append(tuple(float(x) for x in w[1:4]))
            elif w[0] == "f":
                corners = []
                for c in w[1:]:
                    parts = c.split("/")
                    corners.append((int(parts[0]) - 1, int(parts[2]) - 1 if len(parts) > 2 and parts[2] else None))
                for k in range(1, len(corners) - 1):
                    faces.append((corners[0], corners[k], corners[k + 1]))
            elif w[0] == "mtllib":
                mtllib = w[1]
    kd = None
    if mtllib:
        mtl = os.path.join(os.path.dirname(path), mtllib)
        if os.path.exists(mtl):
            for line in open(mtl):
                w = line.split()
                if w and w[0] == "Kd":
                    kd = [float(x) for x in w[1:4]]
    return v, vn, faces, kd


def quat_xyz(deg):
    """Rotation about x, then y, then z (glam's EulerRot::XYZ) as (x, y, z, w)."""
    def axis(i, a):
        q = [0.0, 0.0, 0.0, math.cos(a / 2)]
        q[i] = math.sin(a / 2)
        return q

    def mul(a, b):
        ax, ay, az, aw = a
        bx, by, bz, bw = b
        return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz]

    x, y, z = (math.radians(d) for d in deg)
    return mul(mul(axis(0, x), axis(1, y)), axis(2, z))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("obj")
    ap.add_argument("--out", required=True, help=".gltf (with a .bin beside it) or .glb")
    ap.add_argument("--translate", default="0,0,0")
    ap.add_argument("--rotate-deg", default="0,0,0")
    ap.add_argument("--scale", type=float, default=1.0)
    ap.add_argument("--point-light", help="x,y,z,candela: a white point light at the root")
    a = ap.parse_args()
    v, vn, faces, kd = read_obj(a.obj)
    # One glTF vertex per distinct (position, normal) pair.
    index, pos, nrm, idx = {}, [], [], []
    for face in faces:
        for c in face:
            if c not in index:
                index[c] = len(pos)
                pos.append(v[c[0]])
                nrm.append(vn[c[1]] if c[1] is not None else (0.0, 0.0, 0.0))
            idx.append(index[c])
    wide = len(pos) > 65535
    blob = b"".join(struct.pack("<3f", *p) for p in pos) + b"".join(struct.pack("<3f", *n) for n in nrm)
    ioff = len(blob)
    blob += struct.pack("<%d%s" % (len(idx), "I" if wide else "H"), *idx)
    while len(blob) % 4:
        blob += b"\0"
    n = len(pos)
    lo = [min(p[k] for p in pos) for k in range(3)]
    hi = [max(p[k] for p in pos) for k in range(3)]
    root = {"name": "placement", "children": [1]}
    t = [float(x) for x in a.translate.split(",")]
    r = [float(x) for x in a.rotate_deg.split(",")]
    if any(t):
        root["translation"] = t
    if any(r):
        root["rotation"] = quat_xyz(r)
    if a.scale != 1.0:
        root["scale"] = [a.scale] * 3
    doc = {
        "asset": {"version": "2.0", "generator": "glint tools/obj_to_gltf.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [root, {"name": os.path.basename(a.obj), "mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": (kd or [0.8, 0.8, 0.8]) + [1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 0, "byteOffset": 12 * n, "componentType": 5126, "count": n, "type": "VEC3"},
            {"bufferView": 1, "componentType": 5125 if wide else 5123, "count": len(idx), "type": "SCALAR"},
        ],
        "bufferViews": [{"buffer": 0, "byteLength": 24 * n}, {"buffer": 0, "byteOffset": ioff, "byteLength": len(blob) - ioff}],
        "buffers": [{"byteLength": len(blob)}],
    }
    if a.point_light:
        x, y, z, cd = (float(s) for s in a.point_light.split(","))
        doc["extensionsUsed"] = ["KHR_lights_punctual"]
        doc["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": cd}]}}
        doc["nodes"].append({"name": "light", "translation": [x, y, z], "extensions": {"KHR_lights_punctual": {"light": 0}}})
        doc["scenes"][0]["nodes"].append(2)
    if a.out.endswith(".glb"):
        js = json.dumps(doc, separators=(",", ":")).encode()
        js += b" " * (-len(js) % 4)
        body = struct.pack("<I4s", len(js), b"JSON") + js + struct.pack("<I4s", len(blob), b"BIN\0") + blob
        with open(a.out, "wb") as f:
            f.write(struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body)
    else:
        bin_name = os.path.splitext(os.path.basename(a.out))[0] + ".bin"
        doc["buffers"][0]["uri"] = bin_name
        with open(os.path.join(os.path.dirname(a.out) or ".", bin_name), "wb") as f:
            f.write(blob)
        with open(a.out, "w") as f:
            json.dump(doc, f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""scenes/water-bottle.ron rendered by Mitsuba 3, an independent path
tracer, as the reference glint's path tracer is compared with on a real,
textured asset (docs/scenes.md, "Materials").

The glTF file's triangles, normals and uvs are read here (its one node's
transform, then the RON file's placement) and handed to Mitsuba as a PLY
mesh; its textures are Mitsuba's own bitmap textures (base colour and
emission as sRGB, metallic-roughness and normals as data), its normal
texture Mitsuba's `normalmap` BSDF around the metallic-roughness BSDF of
glint_mitsuba.py, its emission Mitsuba's area emitter.

    pip install mitsuba        # 3.x; the LLVM variant wants libLLVM
    tools/mitsuba/water_bottle.py --spp 4096 --size 256 --out ref.exr
    glint render scenes/water-bottle.ron --graph passes/pathtrace.ron \\
        --size 256x256 --frames 4096 --out glint.exr
    glint compare ref.exr glint.exr
"""

import json
import math
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from glint_mitsuba import cornell_box, main  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ASSET = os.path.join(REPO, "scenes", "assets", "water-bottle", "WaterBottle.gltf")

# scenes/water-bottle.ron's Gltf(...) placement and light, number for number.
TRANSLATE = (0.0, -0.349, -0.1)
SCALE = 5.0
ROTATE_DEG = (0.0, 300.0, 0.0)
LIGHT_CENTER = (0.0, 0.75, 0.2)

COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}
FORMATS = {5121: "B", 5123: "H", 5125: "I", 5126: "f"}


def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def translation(t):
    return [[1, 0, 0, t[0]], [0, 1, 0, t[1]], [0, 0, 1, t[2]], [0, 0, 0, 1]]


def scaling(s):
    return [[s[0], 0, 0, 0], [0, s[1], 0, 0], [0, 0, s[2], 0], [0, 0, 0, 1]]


def quat_matrix(q):
    x, y, z, w = q
    return [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w), 0],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w), 0],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y), 0],
        [0, 0, 0, 1],
    ]


def euler_xyz(deg):
    """glam's EulerRot::XYZ, as glint's loader composes it: Rx Ry Rz."""
    x, y, z = (math.radians(d) for d in deg)
    rx = [[1, 0, 0, 0], [0, math.cos(x), -math.sin(x), 0], [0, math.sin(x), math.cos(x), 0], [0, 0, 0, 1]]
    ry = [[math.cos(y), 0, math.sin(y), 0], [0, 1, 0, 0], [-math.sin(y), 0, math.cos(y), 0], [0, 0, 0, 1]]
    rz = [[math.cos(z), -math.sin(z), 0, 0], [math.sin(z), math.cos(z), 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    return mat_mul(mat_mul(rx, ry), rz)


def node_matrix(node):
    if "matrix" in node:
        m = node["matrix"]  # column-major
        return [[m[c * 4 + r] for c in range(4)] for r in range(4)]
    t = translation(node.get("translation", [0, 0, 0]))
    r = quat_matrix(node.get("rotation", [0, 0, 0, 1]))
    s = scaling(node.get("scale", [1, 1, 1]))
    return mat_mul(mat_mul(t, r), s)


def accessor(gltf, blob, index):
    a = gltf["accessors"][index]
    view = gltf["bufferViews"][a["bufferView"]]
    n = COMPONENTS[a["type"]]
    fmt = FORMATS[a["componentType"]]
    size = struct.calcsize("<" + fmt)
    stride = view.get("byteStride", n * size)
    base = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    return [struct.unpack_from("<" + fmt * n, blob, base + i * stride) for i in range(a["count"])]


def apply(m, p, w):
    return [sum(m[r][c] * (p[c] if c < 3 else w) for c in range(4)) for r in range(3)]


def bottle_ply(path, translate=TRANSLATE, scale=SCALE, rotate_deg=ROTATE_DEG):
    """The asset's meshes in the scene's world space (placed as a RON
    `Gltf(translate, scale, rotate_deg)` places them), as one binary PLY
    with normals and uvs; returns the material of its (single) primitive."""
    with open(ASSET) as f:
        gltf = json.load(f)
    folder = os.path.dirname(ASSET)
    with open(os.path.join(folder, gltf["buffers"][0]["uri"]), "rb") as f:
        blob = f.read()
    placement = mat_mul(mat_mul(translation(translate), euler_xyz(rotate_deg)), scaling([scale] * 3))
    vertices, faces, materials = [], [], set()

    def visit(i, parent):
        node = gltf["nodes"][i]
        m = mat_mul(parent, node_matrix(node))
        if "mesh" in node:
            for prim in gltf["meshes"][node["mesh"]]["primitives"]:
                attrs = prim["attributes"]
                pos = accessor(gltf, blob, attrs["POSITION"])
                nrm = accessor(gltf, blob, attrs["NORMAL"])
                uv = accessor(gltf, blob, attrs["TEXCOORD_0"])
                idx = [i[0] for i in accessor(gltf, blob, prim["indices"])]
                first = len(vertices)
                for p, n, t in zip(pos, nrm, uv):
                    wp = apply(m, p, 1.0)
                    wn = apply(m, n, 0.0)
                    ln = math.sqrt(sum(c * c for c in wn)) or 1.0
                    vertices.append((*wp, *(c / ln for c in wn), *t))
                faces.extend((first + idx[k], first + idx[k + 1], first + idx[k + 2]) for k in range(0, len(idx), 3))
                materials.add(prim["material"])
        for c in node.get("children", []):
            visit(c, m)

    for root in gltf["scenes"][gltf.get("scene", 0)]["nodes"]:
        visit(root, placement)
    assert len(materials) == 1, "one material is written out"
    with open(path, "wb") as f:
        f.write(b"ply\nformat binary_little_endian 1.0\n")
        f.write(b"element vertex %d\n" % len(vertices))
        for p in (b"x", b"y", b"z", b"nx", b"ny", b"nz", b"u", b"v"):
            f.write(b"property float " + p + b"\n")
        f.write(b"element face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(faces))
        for v in vertices:
            f.write(struct.pack("<8f", *v))
        for t in faces:
            f.write(struct.pack("<B3i", 3, *t))
    return gltf, gltf["materials"][materials.pop()], folder


def bitmap(gltf, folder, texture, raw):
    image = gltf["images"][gltf["textures"][texture["index"]]["source"]]
    return {"type": "bitmap", "filename": os.path.join(folder, image["uri"]), "raw": raw, "filter_type": "bilinear", "wrap_mode": "repeat"}


def bottle(folder, **placement):
    """The bottle as a Mitsuba shape: its PLY, its textured
    metallic-roughness BSDF under its normal map, its emission."""
    gltf, mat, asset_folder = bottle_ply(os.path.join(folder, "bottle.ply"), **placement)
    pbr = mat.get("pbrMetallicRoughness", {})
    bsdf = {
        "type": "gltf_metal_rough",
        "base_color": bitmap(gltf, asset_folder, pbr["baseColorTexture"], False),
        "metallic_roughness": bitmap(gltf, asset_folder, pbr["metallicRoughnessTexture"], True),
        "metallic": pbr.get("metallicFactor", 1.0),
        "roughness": pbr.get("roughnessFactor", 1.0),
    }
    bsdf = {"type": "normalmap", "normalmap": bitmap(gltf, asset_folder, mat["normalTexture"], True), "bsdf": bsdf}
    # (Its material is single-sided, but the mesh is closed: no ray meets
    # a back face, so both sides shaded or not give the same image.)
    return {
        "type": "ply",
        "filename": os.path.join(folder, "bottle.ply"),
        "bsdf": {"type": "twosided", "material": bsdf},
        "emitter": {"type": "area", "radiance": bitmap(gltf, asset_folder, mat["emissiveTexture"], False)},
    }


def scene(size, folder):
    d = cornell_box(size, folder, light_center=LIGHT_CENTER)
    d["bottle"] = bottle(folder)
    return d


if __name__ == "__main__":
    main(__doc__, scene)

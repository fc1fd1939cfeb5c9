#!/usr/bin/env python3
"""Writes a Sponza-class glTF asset for measuring load time (docs/scenes.md,
"Load time"): as many triangles and textures as Crytek Sponza's glTF
(262,267 triangles; 69 images, 1024 x 1024 JPEG), laid out as a hall: a
floor and two rows of columns, each material's columns tessellated
cylinders with uvs, normals and a base-colour, a metallic-roughness and a
normal texture of its own. The images are noise over gradients (JPEG
decoding time depends on content: flat images decode far faster), so
each file is about the size of Sponza's (300-900 KB).

Needs Pillow (`pip install pillow`) for the JPEG encoder.

    tools/make_heavy_asset.py target/heavy            # writes target/heavy/hall.gltf
    time glint render target/heavy/hall.gltf --size 64x64 --frames 1 --out x.png
"""

import argparse
import json
import math
import os
import random
import struct

from PIL import Image, ImageChops

MATERIALS = 23  # x 3 textures = 69 images
TRIANGLES = 262_267
SIDE = 1024


def texture(path, seed, kind):
    """A SIDE x SIDE JPEG: gaussian noise over a coloured gradient
    (base colour), a bumpy normal map or a roughness/metal map."""
    rnd = random.Random(seed)
    noise = Image.effect_noise((SIDE, SIDE), 40 + rnd.random() * 30)
    grad = Image.linear_gradient("L").resize((SIDE, SIDE))
    if kind == "base":
        c = [rnd.randint(60, 220) for _ in range(3)]
        chans = [ImageChops.add(ImageChops.multiply(grad, Image.new("L", (SIDE, SIDE), v)), noise, 2.0, -64) for v in c]
        im = Image.merge("RGB", chans)
    elif kind == "normal":
        flat = Image.new("L", (SIDE, SIDE), 128)
        bump = ImageChops.add(flat, noise, 4.0, -32)
        im = Image.merge("RGB", (bump, bump.transpose(Image.Transpose.ROTATE_90), Image.new("L", (SIDE, SIDE), 255)))
    else:
        rough = ImageChops.add(grad, noise, 2.0, -32)
        metal = Image.new("L", (SIDE, SIDE), 255 if rnd.random() < 0.3 else 0)
        im = Image.merge("RGB", (Image.new("L", (SIDE, SIDE), 255), rough, metal))
    im.save(path, quality=90)


def cylinder(cx, cz, radius, height, segments, rings):
    """Positions, normals, uvs and indices of an open cylinder standing on
    y = 0 at (cx, cz): segments x rings quads, 2 triangles each."""
    pos, nrm, uv, idx = [], [], [], []
    for r in range(rings + 1):
        y = height * r / rings
        for s in range(segments + 1):
            a = 2 * math.pi * s / segments
            nx, nz = math.cos(a), math.sin(a)
            pos.append((cx + radius * nx, y, cz + radius * nz))
            nrm.append((nx, 0.0, nz))
            uv.append((4.0 * s / segments, 8.0 * (1.0 - r / rings)))
    row = segments + 1
    for r in range(rings):
        for s in range(segments):
            a = r * row + s
            b = a + row
            idx += [a, a + 1, b, a + 1, b + 1, b]
    return pos, nrm, uv, idx


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", help="folder to write hall.gltf, hall.bin and the images into")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    blob = bytearray()
    gltf = {
        "asset": {"version": "2.0", "generator": "glint tools/make_heavy_asset.py"},
        "scene": 0,
        "scenes": [{"nodes": []}],
        "nodes": [],
        "meshes": [],
        "materials": [],
        "textures": [],
        "images": [],
        "samplers": [{"magFilter": 9729, "minFilter": 9987}],
        "accessors": [],
        "bufferViews": [],
        "buffers": [],
    }

    def view(data, target):
        while len(blob) % 4:
            blob.append(0)
        gltf["bufferViews"].append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
        blob.extend(data)
        return len(gltf["bufferViews"]) - 1

    def accessor(values, kind, comp, fmt, target, bounds=False):
        n = len(values[0]) if isinstance(values[0], tuple) else 1
        flat = [c for v in values for c in v] if n > 1 else values
        acc = {"bufferView": view(struct.pack("<%d%s" % (len(flat), fmt), *flat), target), "componentType": comp, "count": len(values), "type": kind}
        if bounds:
            acc["min"] = [min(v[k] for v in values) for k in range(n)]
            acc["max"] = [max(v[k] for v in values) for k in range(n)]
        gltf["accessors"].append(acc)
        return len(gltf["accessors"]) - 1

    for m in range(MATERIALS):
        slots = []
        for kind in ("base", "mr", "normal"):
            name = "m%02d_%s.jpg" % (m, kind)
            texture(os.path.join(a.out, name), m * 3 + len(slots), kind)
            gltf["images"].append({"uri": name})
            gltf["textures"].append({"sampler": 0, "source": len(gltf["images"]) - 1})
            slots.append(len(gltf["textures"]) - 1)
        gltf["materials"].append({
            "pbrMetallicRoughness": {"baseColorTexture": {"index": slots[0]}, "metallicRoughnessTexture": {"index": slots[1]}},
            "normalTexture": {"index": slots[2]},
            "doubleSided": True,
        })

    # Columns in two rows along z, MATERIALS of them, sharing out the triangles.
    segments, per = 48, TRIANGLES // MATERIALS
    rings = per // (2 * segments)
    for m in range(MATERIALS):
        side = 1 if m % 2 else -1
        pos, nrm, uv, idx = cylinder(side * 4.0, -22.0 + 2.0 * m, 0.5, 8.0, segments, rings)
        prim = {
            "attributes": {
                "POSITION": accessor(pos, "VEC3", 5126, "f", 34962, bounds=True),
                "NORMAL": accessor(nrm, "VEC3", 5126, "f", 34962),
                "TEXCOORD_0": accessor(uv, "VEC2", 5126, "f", 34962),
            },
            "indices": accessor(idx, "SCALAR", 5125, "I", 34963),
            "material": m,
        }
        gltf["meshes"].append({"primitives": [prim]})
        gltf["nodes"].append({"mesh": len(gltf["meshes"]) - 1})
        gltf["scenes"][0]["nodes"].append(len(gltf["nodes"]) - 1)
    gltf["buffers"].append({"byteLength": len(blob), "uri": "hall.bin"})
    with open(os.path.join(a.out, "hall.bin"), "wb") as f:
        f.write(blob)
    with open(os.path.join(a.out, "hall.gltf"), "w") as f:
        json.dump(gltf, f)
    tris = sum(gltf["accessors"][p["indices"]]["count"] // 3 for mesh in gltf["meshes"] for p in mesh["primitives"])
    print("wrote %s: %d triangles, %d images" % (os.path.join(a.out, "hall.gltf"), tris, len(gltf["images"])))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Writes scenes/meshes/tiles.gltf: a small glTF test asset for the textured
material path (scenes/textured.ron, the goldens of tests/golden.rs).

Two quads, each 2 x 2 units in its own node:
  - "card", upright: a checker base colour texture whose alpha cuts round
    holes (alphaMode MASK, cutoff 0.5), a normal texture of horizontal
    ridges, dielectric, roughness 0.5;
  - "tile", flat: a copper base colour and a metallic-roughness texture of
    stripes (blue 255 / green 64: polished metal; blue 0 / green 200: a
    rough dielectric).
Images are 64 x 64 PNGs beside the file, written with zlib alone (no image
library), so the asset is the same byte for byte wherever it is made.

    tools/make_textured_asset.py scenes/meshes
"""

import base64
import json
import math
import os
import struct
import sys
import zlib

SIDE = 64


def png(path, texel):
    """A SIDE x SIDE RGBA8 PNG of texel(x, y) -> (r, g, b, a)."""
    rows = b"".join(b"\x00" + bytes(c for x in range(SIDE) for c in texel(x, y)) for y in range(SIDE))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", SIDE, SIDE, 8, 6, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))


def card_colour(x, y):
    # An 4 x 4 checker of cream and teal; round holes (alpha 0) at the
    # centres of the teal squares.
    cell = SIDE // 4
    cx, cy = x // cell, y // cell
    teal = (cx + cy) % 2 == 1
    dx, dy = x % cell - cell / 2 + 0.5, y % cell - cell / 2 + 0.5
    hole = teal and dx * dx + dy * dy < (cell * 0.3) ** 2
    rgb = (40, 150, 140) if teal else (235, 220, 190)
    return rgb + ((0 if hole else 255),)


def card_normal(x, y):
    # Ridges across the card: the normal tilts up and down in y, four
    # ridges over the image (tangent-space, +y toward the image's top).
    ty = 0.6 * math.sin(2 * math.pi * 4 * (y + 0.5) / SIDE)
    n = (0.0, ty, 1.0)
    length = math.sqrt(sum(c * c for c in n))
    return tuple(int(round((c / length * 0.5 + 0.5) * 255)) for c in n) + (255,)


def tile_metal_rough(x, y):
    # Eight stripes along u: polished metal and rough dielectric in turn.
    metal = (x * 8 // SIDE) % 2 == 0
    return (255, 64, 255, 255) if metal else (255, 200, 0, 255)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "scenes/meshes"
    png(os.path.join(out, "tiles_colour.png"), card_colour)
    png(os.path.join(out, "tiles_normal.png"), card_normal)
    png(os.path.join(out, "tiles_metal_rough.png"), tile_metal_rough)
    # One quad: positions, normals (+z), uvs (v down), two triangles.
    pos = [(-1.0, -1.0, 0.0), (1.0, -1.0, 0.0), (1.0, 1.0, 0.0), (-1.0, 1.0, 0.0)]
    nrm = [(0.0, 0.0, 1.0)] * 4
    uv = [(0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)]
    blob = b"".join(struct.pack("<3f", *p) for p in pos)
    blob += b"".join(struct.pack("<3f", *n) for n in nrm)
    blob += b"".join(struct.pack("<2f", *t) for t in uv)
    blob += struct.pack("<6H", 0, 1, 2, 0, 2, 3)
    blob += b"\x00" * (-len(blob) % 4)
    doc = {
        "asset": {"version": "2.0", "generator": "glint tools/make_textured_asset.py"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            # The card stands on the tile's far half; the tile lies flat.
            {"name": "card", "mesh": 0, "translation": [0.0, 1.0, -0.5]},
            {"name": "tile", "mesh": 1, "rotation": [-math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)]},
        ],
        "meshes": [
            {"name": "card", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]},
            {"name": "tile", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 1}]},
        ],
        "materials": [
            {
                "name": "card",
                "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0, "roughnessFactor": 0.5},
                "normalTexture": {"index": 1, "scale": 1.0},
                "alphaMode": "MASK",
                "alphaCutoff": 0.5,
                "doubleSided": True,
            },
            {
                "name": "tile",
                "pbrMetallicRoughness": {"baseColorFactor": [0.95, 0.64, 0.54, 1.0], "metallicRoughnessTexture": {"index": 2}},
                # glint shades both sides of every surface; saying so keeps
                # the loader's single-sided warning off the shipped scene.
                "doubleSided": True,
            },
        ],
        "textures": [{"source": 0}, {"source": 1}, {"source": 2}],
        "images": [{"uri": "tiles_colour.png"}, {"uri": "tiles_normal.png"}, {"uri": "tiles_metal_rough.png"}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 32},
            {"buffer": 0, "byteOffset": 128, "byteLength": 12},
        ],
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
    }
    with open(os.path.join(out, "tiles.gltf"), "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    print(f"wrote {out}/tiles.gltf and its three 64x64 PNGs", file=sys.stderr)


if __name__ == "__main__":
    main()

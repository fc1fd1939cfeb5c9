#!/usr/bin/env python3
"""Writes a variant of a glTF file for measuring what its materials cost
(docs/scenes.md, "A room-sized asset"): the same meshes and buffers, with

  --opaque       every alphaMode MASK or BLEND material made opaque;
  --no-textures  also every texture and COLOR_0 left out, each base colour
                 texture replaced by its mean colour (linear) in
                 baseColorFactor, each metallic-roughness texture by its
                 means in roughnessFactor and metallicFactor.

The output refers to the input's buffers and images where they are.

    tools/gltf_variant.py --no-textures scenes/assets/dungeon/level-dungeon.gltf out/plain.gltf
"""

import argparse
import json
import os

from PIL import Image


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("input")
    ap.add_argument("output")
    kind = ap.add_mutually_exclusive_group(required=True)
    kind.add_argument("--opaque", action="store_true")
    kind.add_argument("--no-textures", action="store_true")
    a = ap.parse_args()
    with open(a.input) as f:
        d = json.load(f)
    src = os.path.dirname(os.path.abspath(a.input))
    dst = os.path.dirname(os.path.abspath(a.output))
    for m in d.get("materials", []):
        m.pop("alphaMode", None)
        m.pop("alphaCutoff", None)
        if not a.no_textures:
            continue
        pbr = m.setdefault("pbrMetallicRoughness", {})
        if "baseColorTexture" in pbr:
            image = d["images"][d["textures"][pbr["baseColorTexture"]["index"]]["source"]]
            mean = Image.open(os.path.join(src, image["uri"])).convert("RGB").resize((1, 1), Image.BOX).getpixel((0, 0))
            factor = pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0])
            pbr["baseColorFactor"] = [f * (c / 255.0) ** 2.2 for f, c in zip(factor, mean)] + [1.0]
        if "metallicRoughnessTexture" in pbr:
            # Linear data: roughness in green, metalness in blue.
            image = d["images"][d["textures"][pbr["metallicRoughnessTexture"]["index"]]["source"]]
            mean = Image.open(os.path.join(src, image["uri"])).convert("RGB").resize((1, 1), Image.BOX).getpixel((0, 0))
            pbr["roughnessFactor"] = pbr.get("roughnessFactor", 1.0) * mean[1] / 255.0
            pbr["metallicFactor"] = pbr.get("metallicFactor", 1.0) * mean[2] / 255.0
        for key in ("baseColorTexture", "metallicRoughnessTexture"):
            pbr.pop(key, None)
        for key in ("normalTexture", "emissiveTexture", "occlusionTexture"):
            m.pop(key, None)
    if a.no_textures:
        for key in ("textures", "images", "samplers"):
            d.pop(key, None)
        for mesh in d.get("meshes", []):
            for prim in mesh["primitives"]:
                prim["attributes"].pop("COLOR_0", None)
    for item in d.get("buffers", []) + d.get("images", []):
        if "uri" in item and not item["uri"].startswith("data:"):
            item["uri"] = os.path.relpath(os.path.join(src, item["uri"]), dst)
    with open(a.output, "w") as f:
        json.dump(d, f)


if __name__ == "__main__":
    main()

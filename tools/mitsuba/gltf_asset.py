"""A glTF 2.0 asset as Mitsuba 3 shapes, placed as a RON `Gltf(translate,
scale, rotate_deg)` places it: its nodes' transforms, one binary PLY per
material (positions, normals, uvs and, where the file has them, vertex
colours), each material as glint reads it (docs/scenes.md, "glTF files"):
the metallic-roughness BSDF of glint_mitsuba.py with its base colour
(times the vertex colours), metallic-roughness and normal textures
(glint_mitsuba.py's `glint_normalmap`), emission as an area emitter, alphaMode MASK as
Mitsuba's `mask` with the base colour texture's alpha thresholded at the
cutoff (nearest texel, as glint's alpha test reads it), and its
`KHR_lights_punctual` point and directional lights (candela and lux over
683 lm/W).

What differs from glint on purpose: normal textures bend here in each
triangle's own uv frame, in glint in MikkTSpace's smooth per-vertex
tangents; single-sided materials are shaded two-sided here (glint lets
rays through their backs), so an asset with open single-sided surfaces is
not compared this way.
"""

import json
import math
import os
import struct

COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}
FORMATS = {5121: "B", 5123: "H", 5125: "I", 5126: "f"}
NORMALISED = {5121: 255.0, 5123: 65535.0}
LUMENS_PER_WATT = 683.0


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


def placement(translate=(0.0, 0.0, 0.0), scale=1.0, rotate_deg=(0.0, 0.0, 0.0)):
    """A RON `Gltf(...)` placement as a matrix."""
    return mat_mul(mat_mul(translation(translate), euler_xyz(rotate_deg)), scaling([scale] * 3))


def accessor(gltf, blob, index):
    """An accessor's elements as tuples (normalised integers as floats)."""
    a = gltf["accessors"][index]
    view = gltf["bufferViews"][a["bufferView"]]
    n = COMPONENTS[a["type"]]
    fmt = FORMATS[a["componentType"]]
    size = struct.calcsize("<" + fmt)
    stride = view.get("byteStride", n * size)
    base = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    out = [struct.unpack_from("<" + fmt * n, blob, base + i * stride) for i in range(a["count"])]
    if a.get("normalized") and a["componentType"] in NORMALISED:
        scale = NORMALISED[a["componentType"]]
        out = [tuple(c / scale for c in e) for e in out]
    return out


def normal_matrix(m):
    """The cofactor matrix of m's 3x3 part times the sign of its
    determinant: normals go by it (m's inverse transpose, up to a positive
    scale), as glint's loader takes them."""
    a = [row[:3] for row in m[:3]]
    cof = [[a[(r + 1) % 3][(c + 1) % 3] * a[(r + 2) % 3][(c + 2) % 3] - a[(r + 1) % 3][(c + 2) % 3] * a[(r + 2) % 3][(c + 1) % 3] for c in range(3)] for r in range(3)]
    det = sum(a[0][c] * cof[0][c] for c in range(3))
    sign = -1.0 if det < 0 else 1.0
    return [[sign * cof[r][c] for c in range(3)] + [0.0] for r in range(3)] + [[0.0, 0.0, 0.0, 1.0]], det


def apply(m, p, w):
    return [sum(m[r][c] * (p[c] if c < 3 else w) for c in range(4)) for r in range(3)]


class Asset:
    """A glTF file's JSON, binary buffer and folder."""

    def __init__(self, path):
        with open(path) as f:
            self.gltf = json.load(f)
        self.folder = os.path.dirname(path)
        with open(os.path.join(self.folder, self.gltf["buffers"][0]["uri"]), "rb") as f:
            self.blob = f.read()

    def image_path(self, texture):
        image = self.gltf["images"][self.gltf["textures"][texture["index"]]["source"]]
        return os.path.join(self.folder, image["uri"])

    def bitmap(self, texture, raw):
        return {"type": "bitmap", "filename": self.image_path(texture), "raw": raw, "filter_type": "bilinear", "wrap_mode": "repeat"}

    def placed_nodes(self, matrix):
        """Every node of the default scene with its world matrix, `matrix`
        placing the file."""
        stack = [(root, matrix) for root in reversed(self.gltf["scenes"][self.gltf.get("scene", 0)]["nodes"])]
        while stack:
            i, parent = stack.pop()
            node = self.gltf["nodes"][i]
            m = mat_mul(parent, node_matrix(node))
            yield node, m
            stack.extend((c, m) for c in reversed(node.get("children", [])))

    def groups(self, matrix):
        """Per material index (None: the default material): the world-space
        vertices (x y z nx ny nz u v r g b) and triangles of every placed
        primitive, strips and fans left out (none in the assets compared)."""
        out = {}
        for node, m in self.placed_nodes(matrix):
            if "mesh" in node:
                for prim in self.gltf["meshes"][node["mesh"]]["primitives"]:
                    assert prim.get("mode", 4) == 4, "triangle lists only"
                    attrs = prim["attributes"]
                    pos = accessor(self.gltf, self.blob, attrs["POSITION"])
                    nrm = accessor(self.gltf, self.blob, attrs["NORMAL"])
                    uv = accessor(self.gltf, self.blob, attrs["TEXCOORD_0"]) if "TEXCOORD_0" in attrs else [(0.0, 0.0)] * len(pos)
                    col = accessor(self.gltf, self.blob, attrs["COLOR_0"]) if "COLOR_0" in attrs else [(1.0, 1.0, 1.0)] * len(pos)
                    idx = [e[0] for e in accessor(self.gltf, self.blob, prim["indices"])] if "indices" in prim else list(range(len(pos)))
                    vertices, faces = out.setdefault(prim.get("material"), ([], []))
                    first = len(vertices)
                    nm, det = normal_matrix(m)
                    for p, n, t, c in zip(pos, nrm, uv, col):
                        wn = apply(nm, n, 0.0)
                        ln = math.sqrt(sum(x * x for x in wn)) or 1.0
                        vertices.append((*apply(m, p, 1.0), *(x / ln for x in wn), *t, *(min(max(x, 0.0), 1.0) for x in c[:3])))
                    # A mirroring transform turns the winding back (as glint does).
                    for k in range(0, len(idx) - 2, 3):
                        a, b, c = first + idx[k], first + idx[k + 1], first + idx[k + 2]
                        faces.append((a, c, b) if det < 0 else (a, b, c))
        return out

    def lights(self, matrix):
        """The file's KHR_lights_punctual point and directional lights as
        Mitsuba emitters, in glint's radiometric units."""
        table = self.gltf.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
        out = {}
        for node, m in self.placed_nodes(matrix):
            ref = node.get("extensions", {}).get("KHR_lights_punctual")
            if ref is not None:
                light = table[ref["light"]]
                value = [c * light.get("intensity", 1.0) / LUMENS_PER_WATT for c in light.get("color", [1.0, 1.0, 1.0])]
                name = "light%d" % len(out)
                if light["type"] == "directional":
                    out[name] = {"type": "directional", "direction": apply(m, (0.0, 0.0, -1.0), 0.0), "irradiance": {"type": "rgb", "value": value}}
                elif light["type"] == "point":
                    out[name] = {"type": "point", "position": apply(m, (0.0, 0.0, 0.0), 1.0), "intensity": {"type": "rgb", "value": value}}
                else:
                    raise ValueError("spot lights are not converted")
        return out

    def alpha_mask(self, texture, cutoff, folder):
        """The base colour texture's alpha, thresholded at `cutoff`, as a
        grey image in `folder` (Mitsuba's bitmaps drop alpha)."""
        from PIL import Image

        path = os.path.join(folder, "alpha-%d.png" % texture["index"])
        alpha = Image.open(self.image_path(texture)).convert("RGBA").getchannel("A")
        alpha.point(lambda a: 255 if a / 255.0 >= cutoff else 0).save(path)
        return {"type": "bitmap", "filename": path, "raw": True, "filter_type": "nearest", "wrap_mode": "repeat"}

    def shape(self, material, vertices, faces, path, folder):
        """One material's triangles as a Mitsuba PLY shape with its BSDF."""
        with open(path, "wb") as f:
            f.write(b"ply\nformat binary_little_endian 1.0\n")
            f.write(b"element vertex %d\n" % len(vertices))
            for p in (b"x", b"y", b"z", b"nx", b"ny", b"nz", b"u", b"v", b"r", b"g", b"b"):
                f.write(b"property float " + p + b"\n")
            f.write(b"element face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(faces))
            for v in vertices:
                f.write(struct.pack("<11f", *v))
            for t in faces:
                f.write(struct.pack("<B3i", 3, *t))
        mat = self.gltf["materials"][material] if material is not None else {}
        pbr = mat.get("pbrMetallicRoughness", {})
        factor = pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0])
        base = self.bitmap(pbr["baseColorTexture"], False) if "baseColorTexture" in pbr else {"type": "rgb", "value": [1.0, 1.0, 1.0]}
        bsdf = {
            "type": "gltf_metal_rough",
            "base_color": base,
            "base_factor": factor[:3],
            "vertex_color": {"type": "mesh_attribute", "name": "vertex_color"},
            "metallic": pbr.get("metallicFactor", 1.0),
            "roughness": pbr.get("roughnessFactor", 1.0),
        }
        if "metallicRoughnessTexture" in pbr:
            bsdf["metallic_roughness"] = self.bitmap(pbr["metallicRoughnessTexture"], True)
        if "normalTexture" in mat:
            # (It shades both sides itself.)
            assert mat["normalTexture"].get("scale", 1.0) == 1.0, "normal texture scales are not converted"
            bsdf = {"type": "glint_normalmap", "normalmap": self.bitmap(mat["normalTexture"], True), "bsdf": bsdf}
        else:
            bsdf = {"type": "twosided", "material": bsdf}
        if mat.get("alphaMode") in ("MASK", "BLEND") and "baseColorTexture" in pbr:
            cutoff = mat.get("alphaCutoff", 0.5) if mat["alphaMode"] == "MASK" else 0.5
            bsdf = {"type": "mask", "opacity": self.alpha_mask(pbr["baseColorTexture"], cutoff / factor[3], folder), "material": bsdf}
        shape = {"type": "ply", "filename": path, "bsdf": bsdf}
        emissive = [c * mat.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0) for c in mat.get("emissiveFactor", [0.0, 0.0, 0.0])]
        if max(emissive) > 0.0:
            radiance = self.bitmap(mat["emissiveTexture"], False) if "emissiveTexture" in mat else {"type": "rgb", "value": emissive}
            if "emissiveTexture" in mat:
                assert emissive == [1.0, 1.0, 1.0], "an emissive texture's factor is not converted"
            shape["emitter"] = {"type": "area", "radiance": radiance}
        return shape

    def shapes(self, folder, prefix, matrix):
        """Every material's shape, named prefix-N."""
        out = {}
        for k, (material, (vertices, faces)) in enumerate(sorted(self.groups(matrix).items(), key=lambda g: -1 if g[0] is None else g[0])):
            path = os.path.join(folder, "%s-%d.ply" % (prefix, k))
            out["%s-%d" % (prefix, k)] = self.shape(material, vertices, faces, path, folder)
        return out

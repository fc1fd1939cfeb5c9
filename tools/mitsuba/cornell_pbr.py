#!/usr/bin/env python3
"""scenes/cornell-pbr.ron rendered by Mitsuba 3, an independent path tracer,
as the reference glint's path tracer is compared with (docs/scenes.md,
"Materials").

The scene is written out here from the RON file's numbers; the metallic-
roughness BRDF is a Mitsuba BSDF plugin written from the glTF
specification's appendix B with glint's one change (the diffuse lobe
weighed by 1 - F(n.v)): its evaluation, sampling (Mitsuba's own GGX
visible-normal sampler) and pdf are Mitsuba's to use, with Mitsuba's path
integrator, light sampling and MIS.

    pip install mitsuba        # 3.x; the LLVM variant wants libLLVM
    tools/mitsuba/cornell_pbr.py --spp 4096 --size 256 --out ref.exr
    glint render scenes/cornell-pbr.ron --graph passes/pathtrace.ron \\
        --size 256x256 --frames 4096 --out glint.exr
    glint compare ref.exr glint.exr
"""

import argparse
import glob
import os
import sys
import tempfile

# The newest libLLVM on the system (Dr.Jit needs 15 or newer), unless set.
_llvm = sorted(glob.glob("/usr/lib/*/libLLVM*.so*"))
if _llvm:
    os.environ.setdefault("DRJIT_LIBLLVM_PATH", _llvm[-1])

import drjit as dr  # noqa: E402
import mitsuba as mi  # noqa: E402

mi.set_variant("llvm_ad_rgb")

F0_DIELECTRIC = 0.04


# (Selects, not dr.maximum / dr.clip: LLVM 15 cannot lower the fmaximum
# those become on x86.)
def clamp01(x):
    return dr.select(x < 0.0, 0.0, dr.select(x > 1.0, 1.0, x))


def schlick(f0, c):
    m = clamp01(1.0 - c)
    m2 = m * m
    return f0 + (1.0 - f0) * (m2 * m2 * m)


class GltfMetalRough(mi.BSDF):
    """glTF metallic-roughness: (1 - F(n.v)) c_diff / pi + F(v.h) D V,
    F0 = mix(0.04, base, metallic), alpha = max(roughness^2, 0.002)."""

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.base = mi.Color3f(props["base_color"])
        self.metallic = mi.Float(props["metallic"])
        roughness = props["roughness"]
        self.alpha = max(roughness * roughness, 0.002)
        self.dist = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, self.alpha, True)
        flags = mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
        self.m_components = [flags]
        self.m_flags = flags

    def f0(self):
        return dr.lerp(mi.Color3f(F0_DIELECTRIC), self.base, self.metallic)

    def c_diff(self):
        return self.base * (1.0 - self.metallic)

    def spec_probability(self, cos_v):
        f = schlick(self.f0(), cos_v)
        spec = mi.luminance(f)
        diff = mi.luminance(self.c_diff() * (1.0 - f))
        return dr.select(spec + diff > 0.0, spec / (spec + diff), 1.0)

    def eval(self, ctx, si, wo, active=True):
        cos_v = mi.Frame3f.cos_theta(si.wi)
        cos_l = mi.Frame3f.cos_theta(wo)
        valid = active & (cos_v > 0.0) & (cos_l > 0.0)
        h = dr.normalize(si.wi + wo)
        a2 = self.alpha * self.alpha
        nh = mi.Frame3f.cos_theta(h)
        t = nh * nh * (a2 - 1.0) + 1.0
        d = a2 / (dr.pi * t * t)
        gv = cos_l * dr.sqrt(a2 + (1.0 - a2) * cos_v * cos_v)
        gl = cos_v * dr.sqrt(a2 + (1.0 - a2) * cos_l * cos_l)
        v = 0.5 / (gv + gl)
        f = schlick(self.f0(), clamp01(dr.dot(si.wi, h)))
        value = (1.0 - schlick(self.f0(), cos_v)) * self.c_diff() / dr.pi + f * d * v
        return dr.select(valid, value * cos_l, 0.0)

    def pdf(self, ctx, si, wo, active=True):
        cos_v = mi.Frame3f.cos_theta(si.wi)
        cos_l = mi.Frame3f.cos_theta(wo)
        valid = active & (cos_v > 0.0) & (cos_l > 0.0)
        h = dr.normalize(si.wi + wo)
        p_spec = self.dist.pdf(si.wi, h) / (4.0 * dr.dot(wo, h))
        p = self.spec_probability(cos_v)
        return dr.select(valid, p * p_spec + (1.0 - p) * cos_l / dr.pi, 0.0)

    def sample(self, ctx, si, sample1, sample2, active=True):
        cos_v = mi.Frame3f.cos_theta(si.wi)
        active = active & (cos_v > 0.0)
        spec = sample1 < self.spec_probability(cos_v)
        m, _ = self.dist.sample(si.wi, sample2)
        wo_spec = mi.reflect(si.wi, m)
        wo_diff = mi.warp.square_to_cosine_hemisphere(sample2)
        wo = dr.select(spec, wo_spec, wo_diff)
        bs = mi.BSDFSample3f()
        bs.wo = wo
        bs.pdf = self.pdf(ctx, si, wo, active)
        bs.eta = 1.0
        bs.sampled_type = dr.select(spec, mi.UInt32(+mi.BSDFFlags.GlossyReflection), mi.UInt32(+mi.BSDFFlags.DiffuseReflection))
        bs.sampled_component = 0
        ok = active & (bs.pdf > 0.0) & (mi.Frame3f.cos_theta(wo) > 0.0)
        value = self.eval(ctx, si, wo, ok)
        return bs, dr.select(ok, value / bs.pdf, 0.0)

    def traverse(self, callback):
        pass

    def to_string(self):
        return "GltfMetalRough"


mi.register_bsdf("gltf_metal_rough", lambda props: GltfMetalRough(props))


def lambert(rgb):
    return {"type": "twosided", "material": {"type": "diffuse", "reflectance": {"type": "rgb", "value": rgb}}}


def metal_rough(base, metallic, roughness):
    return {"type": "twosided", "material": {"type": "gltf_metal_rough", "base_color": mi.ScalarColor3f(base), "metallic": metallic, "roughness": roughness}}


def quad_obj(folder, name, vertices):
    path = os.path.join(folder, name + ".obj")
    with open(path, "w") as f:
        for v in vertices:
            f.write("v %r %r %r\n" % tuple(v))
        f.write("f 1 2 3\nf 1 3 4\n")
    return path


def scene(size, folder):
    # scenes/cornell-pbr.ron, number for number.
    white = lambert([0.725, 0.71, 0.68])
    red = lambert([0.63, 0.065, 0.05])
    green = lambert([0.14, 0.45, 0.091])
    gold = metal_rough([1.0, 0.766, 0.336], 1.0, 0.35)
    plastic = metal_rough([0.1, 0.25, 0.8], 0.0, 0.2)
    steel = metal_rough([0.56, 0.57, 0.58], 1.0, 0.55)
    walls = {
        "floor": ([(-1, -1, -1), (-1, -1, 1), (1, -1, 1), (1, -1, -1)], steel),
        "ceiling": ([(-1, 1, -1), (1, 1, -1), (1, 1, 1), (-1, 1, 1)], white),
        "back": ([(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1)], white),
        "left": ([(-1, -1, -1), (-1, 1, -1), (-1, 1, 1), (-1, -1, 1)], red),
        "right": ([(1, -1, -1), (1, -1, 1), (1, 1, 1), (1, 1, -1)], green),
    }
    d = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 65, "rr_depth": 5},
        "sensor": {
            "type": "perspective",
            "fov": 40.0,
            "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 3.4], target=[0, 0, 0], up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": size, "height": size, "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        },
    }
    for name, (vertices, bsdf) in walls.items():
        d[name] = {"type": "obj", "filename": quad_obj(folder, name, vertices), "bsdf": bsdf, "face_normals": True}
    d["gold"] = {"type": "sphere", "center": [-0.4, -0.65, -0.3], "radius": 0.35, "bsdf": gold}
    d["plastic"] = {"type": "sphere", "center": [0.45, -0.65, 0.25], "radius": 0.35, "bsdf": plastic}
    d["light"] = {
        "type": "sphere",
        "center": [0.0, 0.75, 0.0],
        "radius": 0.15,
        "bsdf": lambert([0.0, 0.0, 0.0]),
        "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [10.0, 10.0, 10.0]}},
    }
    return d


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--spp", type=int, default=1024)
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        s = mi.load_dict(scene(a.size, folder))
        # In passes of 64 samples (the LLVM backend holds a pass's paths at once).
        total, done = None, 0
        while done < a.spp:
            n = min(64, a.spp - done)
            img = mi.render(s, spp=n, seed=done)
            total = img * n if total is None else total + img * n
            done += n
        mi.util.write_bitmap(a.out, total / a.spp)
    print(f"wrote {a.out} ({a.size}x{a.size}, {a.spp} spp)", file=sys.stderr)


if __name__ == "__main__":
    main()

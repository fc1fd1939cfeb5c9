"""What tools/mitsuba's scene scripts share: Mitsuba 3 set up on this
machine's LLVM, glTF's metallic-roughness BRDF as a Mitsuba BSDF plugin
(constant or textured), the Cornell box's walls and light, and a render
loop in passes.

The BSDF is written from the glTF specification's appendix B with glint's
one change (the diffuse lobe weighed by 1 - F(n.v)): its evaluation,
sampling (Mitsuba's own GGX visible-normal sampler) and pdf are Mitsuba's
to use, with Mitsuba's path integrator, light sampling and MIS.
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
    F0 = mix(0.04, base, metallic), alpha = max(roughness^2, 0.002).
    base_color is a texture (an "rgb" for a constant); a
    metallic_roughness texture, if given, scales the factors by its blue
    (metallic) and green (roughness) channels, as glTF's does."""

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.base = props["base_color"]
        self.metallic = props["metallic"]
        self.roughness = props["roughness"]
        self.mr = props["metallic_roughness"] if props.has_property("metallic_roughness") else None
        # glTF's baseColorFactor and COLOR_0 (a mesh_attribute texture),
        # both multiplying the base colour texture.
        self.factor = mi.Color3f(props["base_factor"]) if props.has_property("base_factor") else None
        self.vertex_color = props["vertex_color"] if props.has_property("vertex_color") else None
        flags = mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
        varying = self.vertex_color is not None or self.mr is not None
        if varying or not isinstance(self.base, mi.Texture) or self.base.is_spatially_varying():
            flags = flags | mi.BSDFFlags.SpatiallyVarying
        self.m_components = [flags]
        self.m_flags = flags

    def params(self, si):
        """(base colour, metallic, alpha) at si."""
        base = self.base.eval(si)
        if self.factor is not None:
            base = base * self.factor
        if self.vertex_color is not None:
            base = base * self.vertex_color.eval(si)
        metallic = mi.Float(self.metallic)
        roughness = mi.Float(self.roughness)
        if self.mr is not None:
            mr = self.mr.eval(si)
            metallic = metallic * mr.z
            roughness = roughness * mr.y
        alpha = roughness * roughness
        alpha = dr.select(alpha < 0.002, 0.002, alpha)
        return base, metallic, alpha

    @staticmethod
    def f0(base, metallic):
        return dr.lerp(mi.Color3f(F0_DIELECTRIC), base, metallic)

    @staticmethod
    def spec_probability(base, metallic, cos_v):
        f = schlick(GltfMetalRough.f0(base, metallic), cos_v)
        spec = mi.luminance(f)
        diff = mi.luminance(base * (1.0 - metallic) * (1.0 - f))
        return dr.select(spec + diff > 0.0, spec / (spec + diff), 1.0)

    @staticmethod
    def geometry(si, wo, active):
        """(cos_v, cos_l, whether both are above the surface, half vector)."""
        cos_v = mi.Frame3f.cos_theta(si.wi)
        cos_l = mi.Frame3f.cos_theta(wo)
        return cos_v, cos_l, active & (cos_v > 0.0) & (cos_l > 0.0), dr.normalize(si.wi + wo)

    def eval(self, ctx, si, wo, active=True):
        base, metallic, alpha = self.params(si)
        cos_v, cos_l, valid, h = self.geometry(si, wo, active)
        a2 = alpha * alpha
        nh = mi.Frame3f.cos_theta(h)
        t = nh * nh * (a2 - 1.0) + 1.0
        d = a2 / (dr.pi * t * t)
        gv = cos_l * dr.sqrt(a2 + (1.0 - a2) * cos_v * cos_v)
        gl = cos_v * dr.sqrt(a2 + (1.0 - a2) * cos_l * cos_l)
        v = 0.5 / (gv + gl)
        f0 = self.f0(base, metallic)
        f = schlick(f0, clamp01(dr.dot(si.wi, h)))
        value = (1.0 - schlick(f0, cos_v)) * base * (1.0 - metallic) / dr.pi + f * d * v
        return dr.select(valid, value * cos_l, 0.0)

    def pdf(self, ctx, si, wo, active=True):
        base, metallic, alpha = self.params(si)
        cos_v, cos_l, valid, h = self.geometry(si, wo, active)
        dist = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, alpha, True)
        p_spec = dist.pdf(si.wi, h) / (4.0 * dr.dot(wo, h))
        p = self.spec_probability(base, metallic, cos_v)
        return dr.select(valid, p * p_spec + (1.0 - p) * cos_l / dr.pi, 0.0)

    def sample(self, ctx, si, sample1, sample2, active=True):
        base, metallic, alpha = self.params(si)
        cos_v = mi.Frame3f.cos_theta(si.wi)
        active = active & (cos_v > 0.0)
        spec = sample1 < self.spec_probability(base, metallic, cos_v)
        dist = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, alpha, True)
        m, _ = dist.sample(si.wi, sample2)
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


class GlintNormalMap(mi.BSDF):
    """A normal texture bending a nested BSDF's shading normal as glint
    bends it (shaders/shared/textures.wgsl, bent_normal): x along u, y
    toward the image's top (glTF's v runs down it), z the normal, in the
    triangle's uv frame with its handedness. Mitsuba's own `normalmap`
    takes y as n x s whichever way v runs, which bends mirrored uvs (about
    half of a typical game asset's triangles) the wrong way. Both sides
    are shaded (no `twosided` around it): seen from the back, the whole
    frame turns over and the bent normal with it, as glTF says of
    double-sided materials (a `twosided` mirrors the view instead, which
    turns the bend's tangent part the other way). Where the bent normal
    faces away from the viewer, the unbent one shades, as in glint
    (facing, shared/intersect.wgsl)."""

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.normalmap = props["normalmap"]
        self.nested = props["bsdf"]
        self.m_components = [self.nested.flags(i) | mi.BSDFFlags.BackSide for i in range(self.nested.component_count())]
        self.m_flags = self.nested.flags() | mi.BSDFFlags.BackSide

    def perturbed(self, si, active):
        """si with its shading frame around the bent normal on the
        viewer's side."""
        c = self.normalmap.eval(si, active) * 2.0 - 1.0
        n = si.sh_frame.n
        s = dr.normalize(si.dp_du - n * dr.dot(n, si.dp_du))
        b = dr.cross(n, s)
        b = dr.select(dr.dot(b, si.dp_dv) > 0.0, -b, b)
        bent = s * c.x + b * c.y + n * c.z
        ok = (dr.dot(bent, bent) > 0.0) & (dr.dot(si.dp_du, si.dp_du) > 0.0)
        bent = dr.select(ok, dr.normalize(bent), n)
        side = dr.select(mi.Frame3f.cos_theta(si.wi) < 0.0, -1.0, 1.0)
        wi = si.to_world(si.wi)
        bent = dr.select(dr.dot(bent * side, wi) > 0.0, bent * side, n * side)
        p = mi.SurfaceInteraction3f(si)
        p.sh_frame = mi.Frame3f(bent)
        p.wi = p.to_local(wi)
        return p

    @staticmethod
    def same_side(si, wo):
        return mi.Frame3f.cos_theta(si.wi) * mi.Frame3f.cos_theta(wo) > 0.0

    def eval(self, ctx, si, wo, active=True):
        p = self.perturbed(si, active)
        return self.nested.eval(ctx, p, p.to_local(si.to_world(wo)), active & self.same_side(si, wo))

    def pdf(self, ctx, si, wo, active=True):
        p = self.perturbed(si, active)
        return self.nested.pdf(ctx, p, p.to_local(si.to_world(wo)), active & self.same_side(si, wo))

    def sample(self, ctx, si, sample1, sample2, active=True):
        p = self.perturbed(si, active)
        bs, weight = self.nested.sample(ctx, p, sample1, sample2, active)
        bs.wo = si.to_local(p.to_world(bs.wo))
        return bs, dr.select(self.same_side(si, bs.wo), weight, 0.0)

    def traverse(self, callback):
        pass

    def to_string(self):
        return "GlintNormalMap"


mi.register_bsdf("glint_normalmap", lambda props: GlintNormalMap(props))


def rgb(value):
    return {"type": "rgb", "value": value}


def lambert(value):
    return {"type": "twosided", "material": {"type": "diffuse", "reflectance": rgb(value)}}


def metal_rough(base, metallic, roughness):
    return {"type": "twosided", "material": {"type": "gltf_metal_rough", "base_color": rgb(base), "metallic": metallic, "roughness": roughness}}


def mirror(reflectance):
    """The thesis material's perfect mirror (specular 1, roughness 0)."""
    return {"type": "conductor", "material": "none", "specular_reflectance": rgb(reflectance)}


def base_scene(size, origin, target, vfov):
    """A scene dict with glint's path tracer's settings and a square
    camera at `origin` looking at `target`, `vfov` degrees high (a RON
    `Camera`, up +y)."""
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 65, "rr_depth": 5},
        "sensor": {
            "type": "perspective",
            "fov": vfov,
            "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(origin=list(origin), target=list(target), up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": size, "height": size, "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        },
    }


def ground(folder, half, bsdf):
    """A square ground quad at y = 0, `half` wide each way."""
    vertices = [(-half, 0.0, -half), (-half, 0.0, half), (half, 0.0, half), (half, 0.0, -half)]
    return {"type": "obj", "filename": quad_obj(folder, "ground", vertices), "bsdf": bsdf, "face_normals": True}


def quad_obj(folder, name, vertices):
    path = os.path.join(folder, name + ".obj")
    with open(path, "w") as f:
        for v in vertices:
            f.write("v %r %r %r\n" % tuple(v))
        f.write("f 1 2 3\nf 1 3 4\n")
    return path


WHITE = [0.725, 0.71, 0.68]
RED = [0.63, 0.065, 0.05]
GREEN = [0.14, 0.45, 0.091]


def cornell_box(size, folder, floor=None, light_center=(0.0, 0.75, 0.0)):
    """scenes/cornell.ron's camera, walls (white, red, green; the floor's
    BSDF given or white) and sphere light, as a Mitsuba scene dict."""
    white = lambert(WHITE)
    walls = {
        "floor": ([(-1, -1, -1), (-1, -1, 1), (1, -1, 1), (1, -1, -1)], floor or white),
        "ceiling": ([(-1, 1, -1), (1, 1, -1), (1, 1, 1), (-1, 1, 1)], white),
        "back": ([(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1)], white),
        "left": ([(-1, -1, -1), (-1, 1, -1), (-1, 1, 1), (-1, -1, 1)], lambert(RED)),
        "right": ([(1, -1, -1), (1, -1, 1), (1, 1, 1), (1, 1, -1)], lambert(GREEN)),
    }
    d = base_scene(size, (0, 0, 3.4), (0, 0, 0), 40.0)
    for name, (vertices, bsdf) in walls.items():
        d[name] = {"type": "obj", "filename": quad_obj(folder, name, vertices), "bsdf": bsdf, "face_normals": True}
    d["light"] = {
        "type": "sphere",
        "center": list(light_center),
        "radius": 0.15,
        "bsdf": lambert([0.0, 0.0, 0.0]),
        "emitter": {"type": "area", "radiance": rgb([10.0, 10.0, 10.0])},
    }
    return d


def render(scene_dict, spp, size, out):
    """Renders in passes of 64 samples (the LLVM backend holds a pass's
    paths at once) and writes their mean to out."""
    s = mi.load_dict(scene_dict)
    total, done = None, 0
    while done < spp:
        n = min(64, spp - done)
        img = mi.render(s, spp=n, seed=done)
        total = img * n if total is None else total + img * n
        done += n
    mi.util.write_bitmap(out, total / spp)
    print(f"wrote {out} ({size}x{size}, {spp} spp)", file=sys.stderr)


def main(doc, scene):
    """The scripts' command line: --spp, --size and --out; scene(size,
    folder) gives the scene dict (folder: scratch space for its meshes)."""
    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    ap.add_argument("--spp", type=int, default=1024)
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        render(scene(a.size, folder), a.spp, a.size, a.out)

// The metallic-roughness BRDF of glTF 2.0 (its specification's appendix
// B), mirrored in src/brdf.rs (whose tests check it: chi-square, white
// furnace, known albedo): Lambert diffuse plus GGX with height-correlated
// Smith masking and Schlick's Fresnel,
//   f = (1 - F(n.v)) c_diff / pi + F(v.h) D V,
//   F0 = mix(0.04, base, metallic), c_diff = base (1 - metallic),
//   alpha = roughness^2
// (the diffuse lobe weighed by 1 - F(n.v), not the appendix's 1 - F(v.h),
// which reflects more than arrives at oblique views: src/brdf.rs),
// sampled as a mixture (GGX's visible normals, Heitz 2018, or the
// cosine), the lobe chosen by its share of the reflectance at the view.
// n: the shading normal on the view's side; v: toward the viewer.
#import sampling

const MIN_ALPHA: f32 = 0.002;
const DIELECTRIC_F0: f32 = 0.04;

struct MetalRough {
    base: vec3f,
    metallic: f32,
    roughness: f32,
}

fn mr_alpha(m: MetalRough) -> f32 {
    return max(m.roughness * m.roughness, MIN_ALPHA);
}

fn mr_f0(m: MetalRough) -> vec3f {
    return mix(vec3f(DIELECTRIC_F0), m.base, m.metallic);
}

fn mr_c_diff(m: MetalRough) -> vec3f {
    return m.base * (1.0 - m.metallic);
}

fn schlick(f0: vec3f, c: f32) -> vec3f {
    let m = clamp(1.0 - c, 0.0, 1.0);
    let m2 = m * m;
    return f0 + (vec3f(1.0) - f0) * (m2 * m2 * m);
}

fn ggx_d(nh: f32, a2: f32) -> f32 {
    if nh <= 0.0 {
        return 0.0;
    }
    let t = nh * nh * (a2 - 1.0) + 1.0;
    return a2 / (PI * t * t);
}

fn smith_g1(c: f32, a2: f32) -> f32 {
    return 2.0 * c / (c + sqrt(a2 + (1.0 - a2) * c * c));
}

// G2 / (4 |n.l| |n.v|), height-correlated.
fn smith_v(nl: f32, nv: f32, a2: f32) -> f32 {
    let gv = nl * sqrt(a2 + (1.0 - a2) * nv * nv);
    let gl = nv * sqrt(a2 + (1.0 - a2) * nl * nl);
    return 0.5 / (gv + gl);
}

// The view's cosine, kept off zero (a shading normal may face away from a
// view the geometric normal faces).
fn mr_view_cos(n: vec3f, v: vec3f) -> f32 {
    return max(dot(n, v), 1e-4);
}

// f(v, l), not times the cosine; 0 below the surface.
fn mr_eval(m: MetalRough, n: vec3f, v: vec3f, l: vec3f) -> vec3f {
    if dot(n, l) <= 0.0 {
        return vec3f(0.0);
    }
    return (vec3f(1.0) - schlick(mr_f0(m), mr_view_cos(n, v))) * mr_c_diff(m) / PI + mr_specular(m, n, v, l);
}

// What the specular lobe's terms share for view v and light l: the
// cosines, the half vector h and alpha^2 (nl <= 0: l is below).
struct LobeAt {
    nl: f32,
    nv: f32,
    h: vec3f,
    a2: f32,
}

fn lobe_at(m: MetalRough, n: vec3f, v: vec3f, l: vec3f) -> LobeAt {
    let hv = v + l;
    let a = mr_alpha(m);
    return LobeAt(dot(n, l), mr_view_cos(n, v), select(vec3f(0.0), normalize(hv), dot(hv, hv) > 0.0), a * a);
}

// The GGX lobe of f(v, l) alone, F(v.h) D V; 0 below the surface.
fn mr_specular(m: MetalRough, n: vec3f, v: vec3f, l: vec3f) -> vec3f {
    let s = lobe_at(m, n, v, l);
    if s.nl <= 0.0 {
        return vec3f(0.0);
    }
    let f = schlick(mr_f0(m), max(dot(v, s.h), 0.0));
    return f * (ggx_d(dot(n, s.h), s.a2) * smith_v(s.nl, s.nv, s.a2));
}

fn mr_luminance(c: vec3f) -> f32 {
    return dot(c, vec3f(0.2126, 0.7152, 0.0722));
}

fn mr_specular_probability(m: MetalRough, nv: f32) -> f32 {
    let f = schlick(mr_f0(m), nv);
    let spec = mr_luminance(f);
    let diff = mr_luminance(mr_c_diff(m) * (vec3f(1.0) - f));
    if spec + diff <= 0.0 {
        return 1.0;
    }
    return clamp(spec / (spec + diff), 0.0, 1.0);
}

// A visible microfacet normal for local view v (z the normal).
fn sample_vndf(v: vec3f, alpha: f32, u: vec2f) -> vec3f {
    let vh = normalize(vec3f(alpha * v.x, alpha * v.y, v.z));
    let lensq = vh.x * vh.x + vh.y * vh.y;
    let t1 = select(vec3f(1.0, 0.0, 0.0), vec3f(-vh.y, vh.x, 0.0) / sqrt(lensq), lensq > 0.0);
    let t2 = cross(vh, t1);
    let r = sqrt(u.x);
    let phi = 2.0 * PI * u.y;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * sqrt(max(0.0, 1.0 - p1 * p1)) + s * r * sin(phi);
    let nh = t1 * p1 + t2 * p2 + vh * sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2));
    return normalize(vec3f(alpha * nh.x, alpha * nh.y, max(nh.z, 0.0)));
}

// A direction from the mixture (may lie below the surface: the path
// ends there, as the lobe's masking says).
fn mr_sample(m: MetalRough, n: vec3f, v: vec3f, u_lobe: f32, u: vec2f) -> vec3f {
    if u_lobe < mr_specular_probability(m, mr_view_cos(n, v)) {
        return mr_sample_specular(m, n, v, u);
    }
    return sample_cosine(n, u);
}

// A direction from the specular lobe alone: v reflected about one of its
// visible normals (may lie below the surface).
fn mr_sample_specular(m: MetalRough, n: vec3f, v: vec3f, u: vec2f) -> vec3f {
    let frame = basis(n);
    let lv = transpose(frame) * v;
    let local_v = normalize(vec3f(lv.x, lv.y, max(lv.z, 1e-4)));
    let h = frame * sample_vndf(local_v, mr_alpha(m), u);
    return normalize(2.0 * dot(v, h) * h - v);
}

// What l, drawn by mr_sample_specular, carries: the lobe's f cos / pdf,
// F(v.h) G2(v, l) / G1(v) (D cancels: it holds for near-mirrors too); 0
// below the surface. Its mean over draws is the lobe's albedo at v.
fn mr_specular_weight(m: MetalRough, n: vec3f, v: vec3f, l: vec3f) -> vec3f {
    let s = lobe_at(m, n, v, l);
    if s.nl <= 0.0 {
        return vec3f(0.0);
    }
    let g2_over_g1 = smith_v(s.nl, s.nv, s.a2) * 4.0 * s.nl * s.nv / smith_g1(s.nv, s.a2);
    return schlick(mr_f0(m), max(dot(v, s.h), 0.0)) * g2_over_g1;
}

fn mr_specular_pdf(m: MetalRough, n: vec3f, v: vec3f, l: vec3f) -> f32 {
    if dot(n, l) <= 0.0 {
        return 0.0;
    }
    let nv = mr_view_cos(n, v);
    let hv = v + l;
    let h = select(vec3f(0.0), normalize(hv), dot(hv, hv) > 0.0);
    let a = mr_alpha(m);
    let a2 = a * a;
    return ggx_d(dot(n, h), a2) * smith_g1(nv, a2) / (4.0 * nv);
}

// The mixture's solid-angle pdf of l.
fn mr_pdf(m: MetalRough, n: vec3f, v: vec3f, l: vec3f) -> f32 {
    let nl = dot(n, l);
    if nl <= 0.0 {
        return 0.0;
    }
    let p = mr_specular_probability(m, mr_view_cos(n, v));
    return p * mr_specular_pdf(m, n, v, l) + (1.0 - p) * nl / PI;
}

//! The metallic-roughness BRDF of glTF 2.0 (its specification's appendix
//! B), the Rust mirror of shaders/shared/brdf.wgsl: Lambert diffuse plus a
//! GGX (Trowbridge-Reitz) specular lobe with height-correlated Smith
//! masking and Schlick's Fresnel,
//!
//!   f = (1 - F(n.v)) c_diff / pi + F(v.h) D V,
//!   F0 = mix(0.04, base, metallic),  c_diff = base (1 - metallic),
//!   alpha = roughness^2,
//!
//! with one change: the appendix weighs the diffuse lobe by 1 - F(v.h),
//! which reflects more than arrives at oblique views (a white dielectric
//! seen at 60 degrees reflects 1.03 of it, at 85 degrees 1.57, measured by
//! the furnace test below); weighed by 1 - F(n.v), what a smooth coat lets
//! through toward the viewer, the lobes share at most what arrives.
//!
//! sampled as a mixture: the specular lobe by GGX's visible normals
//! (Heitz 2018, "Sampling the GGX Distribution of Visible Normals"), the
//! diffuse one by the cosine, the lobe chosen by its share of the Fresnel-
//! weighted reflectance at the view; `pdf` is the mixture's, for multiple
//! importance sampling against light sampling. src/brdf/tests.rs checks
//! the sampler against `pdf` (chi-square) and the lobe's energy.
//!
//! Vectors are in world space; `n` is the shading normal on the side of
//! the view `v` (both unit, pointing away from the surface).

use glam::{Vec2, Vec3};

use crate::sampling::{basis, sample_cosine, PI};

#[cfg(test)]
mod tests;

/// The smallest alpha used: a smoother surface would make D a spike f32
/// cannot hold (roughness 0.045, as Filament clamps it).
pub const MIN_ALPHA: f32 = 0.002;
/// A dielectric's reflectance at normal incidence (index of refraction 1.5).
pub const DIELECTRIC_F0: f32 = 0.04;

/// A metallic-roughness material at a point: base colour (linear), metallic
/// and perceptual roughness in 0..1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MetalRough {
    /// Base colour.
    pub base: Vec3,
    /// Metalness.
    pub metallic: f32,
    /// Perceptual roughness (alpha = roughness^2).
    pub roughness: f32,
}

impl MetalRough {
    /// GGX's alpha, at least MIN_ALPHA.
    pub fn alpha(&self) -> f32 {
        (self.roughness * self.roughness).max(MIN_ALPHA)
    }

    /// Reflectance at normal incidence.
    pub fn f0(&self) -> Vec3 {
        Vec3::splat(DIELECTRIC_F0).lerp(self.base, self.metallic)
    }

    /// The diffuse colour.
    pub fn c_diff(&self) -> Vec3 {
        self.base * (1.0 - self.metallic)
    }
}

/// Schlick's Fresnel at cosine `c` between the view and the microfacet.
pub fn schlick(f0: Vec3, c: f32) -> Vec3 {
    let m = (1.0 - c).clamp(0.0, 1.0);
    let m2 = m * m;
    f0 + (Vec3::ONE - f0) * (m2 * m2 * m)
}

/// GGX's normal distribution at cos(theta_h) = `nh`, for alpha^2 `a2`.
pub fn ggx_d(nh: f32, a2: f32) -> f32 {
    if nh <= 0.0 {
        return 0.0;
    }
    let t = nh * nh * (a2 - 1.0) + 1.0;
    a2 / (PI * t * t)
}

/// Smith's masking of one direction at cosine `c` to the normal: G1.
pub fn smith_g1(c: f32, a2: f32) -> f32 {
    2.0 * c / (c + (a2 + (1.0 - a2) * c * c).sqrt())
}

/// Height-correlated Smith masking-shadowing over the BRDF's cosines:
/// V = G2 / (4 |n.l| |n.v|).
pub fn smith_v(nl: f32, nv: f32, a2: f32) -> f32 {
    let gv = nl * (a2 + (1.0 - a2) * nv * nv).sqrt();
    let gl = nv * (a2 + (1.0 - a2) * nl * nl).sqrt();
    0.5 / (gv + gl)
}

/// The view's cosine to the normal, kept off zero: a shading normal can
/// face away from a view the geometric normal faces.
fn view_cos(n: Vec3, v: Vec3) -> f32 {
    n.dot(v).max(1e-4)
}

/// What the specular lobe's terms share for view `v` and light `l`: n.l,
/// the view's cosine, the half vector and alpha^2; None below the surface.
fn lobe_at(m: &MetalRough, n: Vec3, v: Vec3, l: Vec3) -> Option<(f32, f32, Vec3, f32)> {
    let nl = n.dot(l);
    (nl > 0.0).then(|| (nl, view_cos(n, v), (v + l).normalize_or_zero(), m.alpha() * m.alpha()))
}

/// f(v, l): the BRDF (not times the cosine); 0 below the surface.
pub fn eval(m: &MetalRough, n: Vec3, v: Vec3, l: Vec3) -> Vec3 {
    let Some((nl, nv, h, a2)) = lobe_at(m, n, v, l) else {
        return Vec3::ZERO;
    };
    let f = schlick(m.f0(), v.dot(h).max(0.0));
    let spec = f * (ggx_d(n.dot(h), a2) * smith_v(nl, nv, a2));
    (Vec3::ONE - schlick(m.f0(), nv)) * m.c_diff() / PI + spec
}

/// The probability of sampling the specular lobe at view cosine `nv`: its
/// share of the reflectance, Fresnel at the view weighing the lobes.
pub fn specular_probability(m: &MetalRough, nv: f32) -> f32 {
    let f = schlick(m.f0(), nv);
    let spec = luminance(f);
    let diff = luminance(m.c_diff() * (Vec3::ONE - f));
    if spec + diff <= 0.0 {
        return 1.0;
    }
    (spec / (spec + diff)).clamp(0.0, 1.0)
}

/// Rec. 709 luminance.
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// A microfacet normal from GGX's visible normals for view `v` (both in
/// the local frame, z the normal), isotropic `alpha` (Heitz 2018).
pub fn sample_vndf(v: Vec3, alpha: f32, u: Vec2) -> Vec3 {
    let vh = Vec3::new(alpha * v.x, alpha * v.y, v.z).normalize();
    let lensq = vh.x * vh.x + vh.y * vh.y;
    let t1 = if lensq > 0.0 { Vec3::new(-vh.y, vh.x, 0.0) / lensq.sqrt() } else { Vec3::X };
    let t2 = vh.cross(t1);
    let r = u.x.sqrt();
    let phi = 2.0 * PI * u.y;
    let p1 = r * phi.cos();
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
    let nh = t1 * p1 + t2 * p2 + vh * (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
    Vec3::new(alpha * nh.x, alpha * nh.y, nh.z.max(0.0)).normalize()
}

/// A direction from the mixture: the specular lobe (its visible normal
/// reflected) if `u_lobe` < specular_probability, else the cosine.
pub fn sample(m: &MetalRough, n: Vec3, v: Vec3, u_lobe: f32, u: Vec2) -> Vec3 {
    if u_lobe < specular_probability(m, view_cos(n, v)) {
        sample_specular(m, n, v, u)
    } else {
        sample_cosine(n, u)
    }
}

/// A direction from the specular lobe alone: a visible normal for `v`,
/// `v` reflected about it (may lie below the surface).
pub fn sample_specular(m: &MetalRough, n: Vec3, v: Vec3, u: Vec2) -> Vec3 {
    let frame = basis(n);
    let local_v = frame.transpose() * v;
    let local_v = Vec3::new(local_v.x, local_v.y, local_v.z.max(1e-4)).normalize();
    let h = frame * sample_vndf(local_v, m.alpha(), u);
    (2.0 * v.dot(h) * h - v).normalize()
}

/// What a direction `l` drawn by `sample_specular` carries: the specular
/// lobe's f cos / pdf, F(v.h) G2(v, l) / G1(v) (D cancels, so it holds for
/// near-mirrors too); 0 below the surface. Its mean over draws is the
/// lobe's albedo at `v`.
pub fn specular_weight(m: &MetalRough, n: Vec3, v: Vec3, l: Vec3) -> Vec3 {
    let Some((nl, nv, h, a2)) = lobe_at(m, n, v, l) else {
        return Vec3::ZERO;
    };
    let g2_over_g1 = smith_v(nl, nv, a2) * 4.0 * nl * nv / smith_g1(nv, a2);
    schlick(m.f0(), v.dot(h).max(0.0)) * g2_over_g1
}

/// The specular lobe's solid-angle pdf of `l`: D_v(h) / (4 v.h) =
/// G1(v) D(h) / (4 n.v).
pub fn specular_pdf(m: &MetalRough, n: Vec3, v: Vec3, l: Vec3) -> f32 {
    if n.dot(l) <= 0.0 {
        return 0.0;
    }
    let nv = view_cos(n, v);
    let h = (v + l).normalize_or_zero();
    let a2 = m.alpha() * m.alpha();
    ggx_d(n.dot(h), a2) * smith_g1(nv, a2) / (4.0 * nv)
}

/// The mixture's solid-angle pdf of `l` (what `sample` draws).
pub fn pdf(m: &MetalRough, n: Vec3, v: Vec3, l: Vec3) -> f32 {
    let nl = n.dot(l);
    if nl <= 0.0 {
        return 0.0;
    }
    let p = specular_probability(m, view_cos(n, v));
    p * specular_pdf(m, n, v, l) + (1.0 - p) * nl / PI
}

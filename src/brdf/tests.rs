//! The metallic-roughness BRDF against what it must satisfy: GGX's normals
//! and visible normals integrate to one, the sampler draws what `pdf` says
//! (chi-square, src/chi2.rs), the lobe reflects at most what arrives (a
//! white furnace) and the known albedo of a white GGX conductor.

use super::*;
use crate::chi2::{sidak, test};
use crate::sampling::Rng;
use std::f64::consts::PI as PI64;

const SAMPLES: usize = 1_000_000;
/// The chi-square tests below, for Sidak's correction.
const TESTS: usize = 10;

/// A unit view at `deg` from the normal `n`, in the plane of n and x-ish.
fn view_at(n: Vec3, deg: f32) -> Vec3 {
    let b = basis(n);
    let r = deg.to_radians();
    (b.x_axis * r.sin() + n * r.cos()).normalize()
}

/// The midpoint rule over the hemisphere about `n` in (cos theta, phi):
/// `steps` x 4 `steps` points.
fn hemisphere_integral(n: Vec3, steps: usize, f: impl Fn(Vec3) -> f64) -> f64 {
    let b = basis(n);
    let (dz, dphi) = (1.0 / steps as f64, 2.0 * PI64 / (4 * steps) as f64);
    let mut sum = 0.0;
    for i in 0..steps {
        let z = (i as f64 + 0.5) * dz;
        let s = (1.0 - z * z).sqrt();
        for j in 0..4 * steps {
            let phi = (j as f64 + 0.5) * dphi;
            let local = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, z as f32);
            sum += f(b * local);
        }
    }
    sum * dz * dphi
}

/// The midpoint rule in GGX's own coordinates: h = the microfacet normal
/// whose slope CDF is (u1, u2) (tan^2 theta = alpha^2 u1 / (1 - u1)), so
/// that the integral of g over the hemisphere of h is the mean of
/// g / (D cos theta_h) over the unit square; smooth where D is a spike.
fn microfacet_integral(n: Vec3, alpha: f32, steps: usize, g: impl Fn(Vec3) -> f64) -> f64 {
    let b = basis(n);
    let a2 = f64::from(alpha * alpha);
    let mut sum = 0.0;
    for i in 0..steps {
        let u1 = (i as f64 + 0.5) / steps as f64;
        let cos2 = (1.0 - u1) / (1.0 + (a2 - 1.0) * u1);
        let (c, s) = (cos2.sqrt(), (1.0 - cos2).max(0.0).sqrt());
        let t = cos2 * (a2 - 1.0) + 1.0;
        let d = a2 / (PI64 * t * t);
        for j in 0..steps {
            let phi = 2.0 * PI64 * (j as f64 + 0.5) / steps as f64;
            let h = b * Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32);
            sum += g(h) / (d * c);
        }
    }
    sum / (steps * steps) as f64
}

#[test]
fn ggx_normals_and_visible_normals_integrate_to_one() {
    let n = Vec3::new(0.2, -0.3, 0.9).normalize();
    for alpha in [0.1f32, 0.3, 0.6, 1.0] {
        let a2 = alpha * alpha;
        // The projected normal area is the macro-surface's: int D cos = 1.
        let area = hemisphere_integral(n, 2000, |h| f64::from(ggx_d(n.dot(h), a2) * n.dot(h)));
        // The visible normals of any view, G1(v) (v.h)+ D / (n.v), too
        // (the weak white furnace, Heitz 2014).
        for deg in [0.0f32, 45.0, 80.0] {
            let v = view_at(n, deg);
            let nv = n.dot(v);
            let visible = hemisphere_integral(n, 2000, |h| f64::from(smith_g1(nv, a2) * v.dot(h).max(0.0) * ggx_d(n.dot(h), a2) / nv));
            eprintln!("alpha {alpha}: int D cos = {area:.5}, visible normals at {deg} deg = {visible:.5}");
            assert!((visible - 1.0).abs() < 2e-3, "alpha {alpha}, view {deg} deg: visible normals integrate to {visible}");
        }
        assert!((area - 1.0).abs() < 2e-3, "alpha {alpha}: int D cos = {area}");
    }
}

/// E(v) = int f(v, l) cos(l) dl, the specular part in microfacet
/// coordinates (dl = 4 (v.h) dh), the diffuse one over the hemisphere.
fn albedo(m: &MetalRough, n: Vec3, v: Vec3) -> Vec3 {
    let mut e = [0.0f64; 3];
    for k in 0..3 {
        let pick = |c: Vec3| f64::from(c[k]);
        let spec = microfacet_integral(n, m.alpha(), 600, |h| {
            let l = 2.0 * v.dot(h) * h - v;
            if v.dot(h) <= 0.0 || n.dot(l) <= 0.0 {
                return 0.0;
            }
            let a2 = m.alpha() * m.alpha();
            let f = schlick(m.f0(), v.dot(h));
            let s = f * (ggx_d(n.dot(h), a2) * smith_v(n.dot(l), n.dot(v).max(1e-4), a2));
            pick(s) * f64::from(n.dot(l)) * 4.0 * f64::from(v.dot(h))
        });
        let diff = hemisphere_integral(n, 300, |l| {
            let f = schlick(m.f0(), n.dot(v).max(1e-4));
            pick((Vec3::ONE - f) * m.c_diff() / PI) * f64::from(n.dot(l))
        });
        e[k] = spec + diff;
    }
    Vec3::new(e[0] as f32, e[1] as f32, e[2] as f32)
}

/// The same by Monte Carlo through `sample` and `pdf`: independent of the
/// quadrature, so the two agreeing checks the sampler's weights too.
fn albedo_sampled(m: &MetalRough, n: Vec3, v: Vec3, count: u32) -> Vec3 {
    let mut sum = Vec3::ZERO;
    for i in 0..count {
        let mut rng = Rng::new((i & 0xffff, i >> 16), 0, 0xb2df, 3);
        let (u_lobe, u) = (rng.next_f32(), rng.next2());
        let l = sample(m, n, v, u_lobe, u);
        let p = pdf(m, n, v, l);
        if p > 0.0 {
            sum += eval(m, n, v, l) * n.dot(l) / p;
        }
    }
    sum / count as f32
}

#[test]
fn a_white_furnace_reflects_at_most_what_arrives() {
    let n = Vec3::new(-0.1, 0.4, 0.9).normalize();
    for metallic in [0.0f32, 1.0, 0.5] {
        for roughness in [0.1f32, 0.4, 0.7, 1.0] {
            let m = MetalRough { base: Vec3::ONE, metallic, roughness };
            for deg in [0.0f32, 60.0, 85.0] {
                let v = view_at(n, deg);
                let e = albedo(&m, n, v);
                let mc = albedo_sampled(&m, n, v, 200_000);
                eprintln!("metallic {metallic} roughness {roughness} view {deg} deg: E = {:.4} (sampled {:.4})", e.x, mc.x);
                assert!(e.max_element() <= 1.0 + 2e-3, "{m:?} at {deg} deg reflects {e}");
                assert!((e - mc).abs().max_element() < 0.01 + 0.01 * e.max_element(), "{m:?} at {deg} deg: quadrature {e}, sampled {mc}");
            }
        }
    }
}

/// A white GGX conductor (F = 1) seen head-on reflects E(alpha) =
/// int G1(l) D(h) cos(theta_h) dh over the normals that send l above the
/// surface (theta_h < 45 degrees): with u the CDF of D cos (tan^2 theta_h
/// = alpha^2 u / (1 - u)), the 1-D integral of G1(l(u)) over u < 1 / (1 +
/// alpha^2), where theta_l = 2 theta_h. At alpha = 1 it is 1 - ln 2
/// exactly. Written here from those formulas alone, in f64.
fn head_on_conductor_albedo(alpha: f64) -> f64 {
    let a2 = alpha * alpha;
    let u_max = 1.0 / (1.0 + a2);
    let steps = 200_000;
    let mut sum = 0.0;
    for i in 0..steps {
        let u = u_max * (i as f64 + 0.5) / steps as f64;
        let theta_h = (a2 * u / (1.0 - u)).sqrt().atan();
        let c = (2.0 * theta_h).cos();
        sum += 2.0 * c / (c + (a2 + (1.0 - a2) * c * c).sqrt());
    }
    sum * u_max / steps as f64
}

#[test]
fn a_white_conductor_has_the_known_ggx_albedo() {
    assert!((head_on_conductor_albedo(1.0) - (1.0 - 2f64.ln())).abs() < 1e-6);
    for roughness in [0.05f32, 0.3, 0.5, 0.8, 1.0] {
        let m = MetalRough { base: Vec3::ONE, metallic: 1.0, roughness };
        let want = head_on_conductor_albedo(f64::from(m.alpha())) as f32;
        let e = albedo(&m, Vec3::Z, Vec3::Z).x;
        let mc = albedo_sampled(&m, Vec3::Z, Vec3::Z, 200_000).x;
        eprintln!("white conductor, roughness {roughness}: E(head-on) = {want:.4}; quadrature {e:.4}, sampled {mc:.4}");
        assert!((e - want).abs() < 2e-3 && (mc - want).abs() < 5e-3, "roughness {roughness}: want {want}, quadrature {e}, sampled {mc}");
    }
}

/// Where `sample` puts directions, on the whole sphere: the specular
/// lobe's reflected visible normals may fall below the surface (the path
/// ends there), which `pdf` (upper hemisphere only) leaves out.
fn sphere_pdf(m: &MetalRough, n: Vec3, v: Vec3, l: Vec3) -> f64 {
    let nv = n.dot(v).max(1e-4);
    let p = specular_probability(m, nv);
    let h = (v + l).normalize_or_zero();
    let a2 = m.alpha() * m.alpha();
    let spec = if v.dot(h) > 0.0 { ggx_d(n.dot(h), a2) * smith_g1(nv, a2) / (4.0 * nv) } else { 0.0 };
    let diff = n.dot(l).max(0.0) / PI;
    f64::from(p * spec + (1.0 - p) * diff)
}

/// A polar grid about `pole`: `ROWS` rings whose edges sit at theta =
/// pi (i / ROWS)^2 (fine near the pole, where a smooth lobe puts its
/// samples) by `COLS` sectors; a lobe narrower than an equal-area grid's
/// cells is resolved.
const ROWS: usize = 40;
const COLS: usize = 60;

fn polar_cell(pole: Vec3, d: Vec3) -> usize {
    let local = (basis(pole).transpose() * d).as_dvec3().normalize();
    let theta = local.z.clamp(-1.0, 1.0).acos();
    let row = (((theta / PI64).sqrt() * ROWS as f64) as usize).min(ROWS - 1);
    let mut phi = local.y.atan2(local.x);
    if phi < 0.0 {
        phi += 2.0 * PI64;
    }
    row * COLS + ((phi / (2.0 * PI64) * COLS as f64) as usize).min(COLS - 1)
}

/// Expected counts: the pdf integrated over each cell by the midpoint rule
/// in (theta, phi), d omega = sin theta d theta d phi; `None` for a cell
/// the pdf is zero on at some of its points and not at others (it meets
/// the edge of the lobe, which the rule cannot place).
fn polar_expected(pole: Vec3, n: usize, pdf: impl Fn(Vec3) -> f64) -> Vec<Option<f64>> {
    let sub = 12;
    let b = basis(pole);
    let mut e = vec![None; ROWS * COLS];
    for row in 0..ROWS {
        let (t0, t1) = (PI64 * (row as f64 / ROWS as f64).powi(2), PI64 * ((row + 1) as f64 / ROWS as f64).powi(2));
        for col in 0..COLS {
            let (mut sum, mut zeros) = (0.0, 0);
            for i in 0..sub {
                let theta = t0 + (t1 - t0) * (i as f64 + 0.5) / sub as f64;
                for j in 0..sub {
                    let phi = 2.0 * PI64 * (col as f64 + (j as f64 + 0.5) / sub as f64) / COLS as f64;
                    let d = Vec3::new((theta.sin() * phi.cos()) as f32, (theta.sin() * phi.sin()) as f32, theta.cos() as f32);
                    let p = pdf(b * d);
                    zeros += usize::from(p <= 0.0);
                    sum += p * theta.sin();
                }
            }
            if zeros == 0 {
                e[row * COLS + col] = Some(n as f64 * sum * (t1 - t0) * (2.0 * PI64 / COLS as f64) / (sub * sub) as f64);
            }
        }
    }
    e
}

/// Bins `sample`'s directions about the mirror direction and tests them
/// against `sphere_pdf`: every sample where the pdf is above zero, the
/// cells the lobe covers one by one, the rest (its edge and beyond) as one
/// bin expecting what the others leave of the total.
fn sampler_outcome(m: &MetalRough, n: Vec3, v: Vec3, sampler: impl Fn(f32, Vec2) -> Vec3) -> crate::chi2::Outcome {
    let pole = (2.0 * v.dot(n) * n - v).normalize();
    let (mut o, mut at_zero) = (vec![0u64; ROWS * COLS], 0);
    for i in 0..SAMPLES as u32 {
        let mut rng = Rng::new((i & 0xffff, i >> 16), 0, 0x99f, 5);
        let (u_lobe, u) = (rng.next_f32(), rng.next2());
        let l = sampler(u_lobe, u);
        at_zero += u64::from(sphere_pdf(m, n, v, l) <= 0.0);
        o[polar_cell(pole, l)] += 1;
    }
    let e = polar_expected(pole, SAMPLES, |l| sphere_pdf(m, n, v, l));
    let (mut observed, mut expected) = (vec![0u64], vec![SAMPLES as f64]);
    for (o, e) in o.iter().zip(&e) {
        match e {
            Some(e) => {
                observed.push(*o);
                expected.push(*e);
                expected[0] -= e;
            }
            None => observed[0] += o,
        }
    }
    expected[0] = expected[0].max(0.0);
    let out = test(&observed, &expected);
    if at_zero > 0 {
        return crate::chi2::Outcome { p_value: 0.0, in_zero_cells: at_zero, ..out };
    }
    out
}

#[test]
fn the_sampler_draws_what_pdf_says() {
    let level = sidak(0.01, TESTS);
    let n = Vec3::new(0.3, 0.1, -0.95).normalize();
    let cases = [(0.0f32, 0.3f32, 30.0f32), (1.0, 0.2, 0.0), (1.0, 0.5, 70.0), (0.5, 0.7, 45.0), (0.0, 1.0, 85.0), (1.0, 0.9, 20.0)];
    for (metallic, roughness, deg) in cases {
        let m = MetalRough { base: Vec3::new(0.9, 0.6, 0.3), metallic, roughness };
        let v = view_at(n, deg);
        let r = sampler_outcome(&m, n, v, |ul, u| sample(&m, n, v, ul, u));
        eprintln!("metallic {metallic} roughness {roughness} view {deg} deg: chi2 {:.1}, dof {}, p {:.4}", r.chi2, r.dof, r.p_value);
        assert_eq!(r.in_zero_cells, 0, "{m:?}: samples where the pdf is 0");
        assert!(r.p_value > level, "{m:?} at {deg} deg: p {} <= {level}", r.p_value);
    }
    // Sampling D cos instead of the visible normals, against the same pdf,
    // fails: the test sees a sampler that ignores masking.
    let m = MetalRough { base: Vec3::ONE, metallic: 1.0, roughness: 0.8 };
    let v = view_at(n, 70.0);
    let wrong = |_: f32, u: Vec2| {
        let a2 = m.alpha() * m.alpha();
        let cos2 = (1.0 - u.x) / (1.0 + (a2 - 1.0) * u.x);
        let s = (1.0 - cos2).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let h = basis(n) * Vec3::new(s * phi.cos(), s * phi.sin(), cos2.sqrt());
        (2.0 * v.dot(h) * h - v).normalize()
    };
    let r = sampler_outcome(&m, n, v, wrong);
    assert!(r.p_value < 1e-6, "the test cannot tell a sampler without masking: p {}", r.p_value);
}

/// The specular lobe is reciprocal (the diffuse one, weighed by the view's
/// Fresnel, is not: see the module's comment).
#[test]
fn the_specular_lobe_is_reciprocal_and_zero_below() {
    let n = Vec3::new(0.0, 0.6, 0.8);
    let m = MetalRough { base: Vec3::new(0.8, 0.5, 0.2), metallic: 1.0, roughness: 0.45 };
    let (a, b) = (view_at(n, 20.0), (view_at(n, 65.0) + Vec3::new(0.2, 0.0, 0.0)).normalize());
    let (ab, ba) = (eval(&m, n, a, b), eval(&m, n, b, a));
    assert!((ab - ba).abs().max_element() < 1e-5 * ab.max_element(), "{ab} != {ba}");
    assert_eq!(eval(&m, n, a, -n), Vec3::ZERO);
    assert_eq!(pdf(&m, n, a, -b), 0.0);
    // A mirror-smooth conductor still evaluates finitely.
    let smooth = MetalRough { base: Vec3::ONE, metallic: 1.0, roughness: 0.0 };
    let r = 2.0 * a.dot(n) * n - a;
    assert!(eval(&smooth, n, a, r).is_finite() && pdf(&smooth, n, a, r).is_finite());
}

/// The specular lobe sampled alone (the hybrid graphs' glossy reflections):
/// `specular_weight` is f cos / pdf of what `sample_specular` draws, and its
/// mean over draws is the lobe's albedo (a metal's, which has no diffuse
/// lobe, by the quadrature above; a near-mirror's, whose D the quadrature
/// cannot resolve, is Schlick's F(n.v)).
#[test]
fn the_specular_lobe_alone_carries_its_albedo() {
    let n = Vec3::new(0.0, 0.6, 0.8);
    for roughness in [0.05, 0.3, 0.7, 1.0] {
        let m = MetalRough { base: Vec3::new(0.95, 0.64, 0.54), metallic: 1.0, roughness };
        for deg in [0.0, 45.0, 80.0] {
            let v = view_at(n, deg);
            let count = 200_000u32;
            let mut sum = Vec3::ZERO;
            for i in 0..count {
                let mut rng = Rng::new((i & 0xffff, i >> 16), 0, 0x5be, 5);
                let l = sample_specular(&m, n, v, rng.next2());
                let w = specular_weight(&m, n, v, l);
                if i < 64 && w != Vec3::ZERO {
                    // Pointwise: the weight is f cos / pdf (where D is no spike).
                    let direct = eval(&m, n, v, l) * n.dot(l) / specular_pdf(&m, n, v, l);
                    assert!((w - direct).abs().max_element() < 2e-3 * direct.max_element().max(1.0), "roughness {roughness}, {deg} deg: {w} != {direct}");
                }
                sum += w;
            }
            let mean = sum / count as f32;
            let want = if roughness < 0.1 { schlick(m.f0(), n.dot(v)) } else { albedo(&m, n, v) };
            let err = ((mean - want) / want).abs().max_element();
            assert!(err < 0.01, "roughness {roughness}, view {deg} deg: sampled albedo {mean} against {want} ({err:.4})");
        }
    }
}

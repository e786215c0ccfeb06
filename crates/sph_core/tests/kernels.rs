//! Kernel normalisation and gradients against finite differences.

use sph_core::glam::Vec3;
use sph_core::rng::SplitMix64;
use sph_core::Kernels;
use std::f64::consts::PI;

/// 4π ∫₀ʰ r² W(r) dr by the midpoint rule in f64.
fn radial_integral(h: f32, w: impl Fn(f32) -> f32) -> f64 {
    let n = 200_000;
    let dr = h as f64 / n as f64;
    (0..n)
        .map(|k| {
            let r = (k as f64 + 0.5) * dr;
            4.0 * PI * r * r * w(r as f32) as f64 * dr
        })
        .sum()
}

#[test]
fn poly6_integrates_to_one_over_its_support() {
    for h in [0.04f32, 0.1, 1.0] {
        let k = Kernels::new(h);
        let integral = radial_integral(h, |r| k.poly6(r * r));
        assert!((integral - 1.0).abs() < 1e-3, "h {h}: ∫W = {integral}");
    }
}

#[test]
fn spiky_and_viscosity_kernels_integrate_to_one() {
    let h = 0.1;
    let k = Kernels::new(h);
    let spiky = radial_integral(h, |r| k.spiky(r));
    let viscosity = radial_integral(h, |r| k.viscosity(r));
    assert!((spiky - 1.0).abs() < 1e-3, "∫W_spiky = {spiky}");
    assert!((viscosity - 1.0).abs() < 1e-3, "∫W_visc = {viscosity}");
}

#[test]
fn poly6_is_zero_outside_the_support_and_branch_free_form_agrees() {
    let k = Kernels::new(0.5);
    assert_eq!(k.poly6(0.25), 0.0);
    assert_eq!(k.poly6(1.0), 0.0);
    let mut rng = SplitMix64::new(1);
    for _ in 0..1000 {
        let r2 = rng.range(0.0, 0.4);
        assert_eq!(k.poly6(r2), k.poly6_unchecked(r2));
    }
}

/// Central-difference gradient of a radial function f(|x|) in f64.
fn fd_gradient(f: impl Fn(f64) -> f64, x: [f64; 3], eps: f64) -> [f64; 3] {
    let mut g = [0.0; 3];
    for axis in 0..3 {
        let (mut a, mut b) = (x, x);
        a[axis] += eps;
        b[axis] -= eps;
        let len = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        g[axis] = (f(len(a)) - f(len(b))) / (2.0 * eps);
    }
    g
}

fn random_points_in_support(h: f32, count: usize, seed: u64) -> Vec<Vec3> {
    let mut rng = SplitMix64::new(seed);
    let mut out = Vec::new();
    while out.len() < count {
        let p = Vec3::new(rng.range(-h, h), rng.range(-h, h), rng.range(-h, h));
        let r = p.length();
        if r > 0.05 * h && r < 0.95 * h {
            out.push(p);
        }
    }
    out
}

fn assert_close(analytic: Vec3, numeric: [f64; 3], scale: f64, what: &str) {
    for axis in 0..3 {
        let err = (analytic[axis] as f64 - numeric[axis]).abs();
        assert!(
            err <= 2e-3 * scale,
            "{what}: axis {axis} analytic {} numeric {} (scale {scale})",
            analytic[axis],
            numeric[axis]
        );
    }
}

#[test]
fn poly6_gradient_matches_finite_differences() {
    let h = 0.1f32;
    let k = Kernels::new(h);
    let hd = h as f64;
    let c = 315.0 / (64.0 * PI * hd.powi(9));
    let w = |r: f64| {
        if r < hd {
            c * (hd * hd - r * r).powi(3)
        } else {
            0.0
        }
    };
    let scale = 945.0 / (32.0 * PI * hd.powi(9)) * hd.powi(5);
    for p in random_points_in_support(h, 200, 2) {
        let numeric = fd_gradient(w, [p.x as f64, p.y as f64, p.z as f64], 1e-6);
        assert_close(
            k.poly6_grad(p, p.length_squared()),
            numeric,
            scale,
            "grad poly6",
        );
    }
}

#[test]
fn spiky_gradient_matches_finite_differences() {
    let h = 0.1f32;
    let k = Kernels::new(h);
    let hd = h as f64;
    let w = |r: f64| {
        if r < hd {
            15.0 / (PI * hd.powi(6)) * (hd - r).powi(3)
        } else {
            0.0
        }
    };
    let scale = 45.0 / (PI * hd.powi(6)) * hd * hd;
    for p in random_points_in_support(h, 200, 3) {
        let numeric = fd_gradient(w, [p.x as f64, p.y as f64, p.z as f64], 1e-6);
        assert_close(k.spiky_grad(p, p.length()), numeric, scale, "grad spiky");
    }
}

#[test]
fn viscosity_laplacian_matches_finite_differences() {
    let h = 0.1f32;
    let k = Kernels::new(h);
    let hd = h as f64;
    let w = |r: f64| {
        15.0 / (2.0 * PI * hd.powi(3))
            * (-r.powi(3) / (2.0 * hd.powi(3)) + r * r / (hd * hd) + hd / (2.0 * r) - 1.0)
    };
    // Radial Laplacian: f'' + 2 f' / r.
    let eps = 1e-5;
    for r in [0.2, 0.35, 0.5, 0.65, 0.8, 0.9].map(|f| f * hd) {
        let d1 = (w(r + eps) - w(r - eps)) / (2.0 * eps);
        let d2 = (w(r + eps) - 2.0 * w(r) + w(r - eps)) / (eps * eps);
        let numeric = d2 + 2.0 * d1 / r;
        let analytic = k.viscosity_laplacian(r as f32) as f64;
        let scale = 45.0 / (PI * hd.powi(5));
        assert!(
            (analytic - numeric).abs() < 1e-3 * scale,
            "r {r}: analytic {analytic} numeric {numeric}"
        );
    }
}

#[test]
fn papers_constants_not_the_designs_typos() {
    let h = 0.5f32;
    let k = Kernels::new(h);
    let pi = std::f32::consts::PI;
    assert!((k.viscosity_laplacian(0.2) - 45.0 / (pi * h.powi(6)) * (h - 0.2)).abs() < 1e-3);
    let r = Vec3::new(0.3, 0.0, 0.0);
    let expected = -45.0 / (pi * h.powi(6)) * (h - 0.3) * (h - 0.3);
    assert!((k.spiky_grad(r, 0.3).x - expected).abs() < 1e-3);
    // Akinci 2013 eq. 2 outer branch: 32/(π h⁹) (h - r)³ r³.
    let c = 32.0 / (pi * h.powi(9)) * (h - 0.3f32).powi(3) * 0.3f32.powi(3);
    assert!((k.cohesion(0.3) - c).abs() < 1e-4 * c.abs());
}

#[test]
fn cohesion_spline_is_continuous_repulsive_near_and_attractive_far() {
    let h = 0.2f32;
    let k = Kernels::new(h);
    let below = k.cohesion(0.5 * h - 1e-5);
    let above = k.cohesion(0.5 * h + 1e-5);
    assert!(
        (below - above).abs() < 1e-3 * above.abs(),
        "{below} vs {above}"
    );
    assert!(k.cohesion(0.05 * h) < 0.0, "repulsive at short range");
    assert!(k.cohesion(0.7 * h) > 0.0, "attractive at long range");
    assert_eq!(k.cohesion(h), 0.0);
    assert_eq!(k.cohesion(0.0), 0.0);
}

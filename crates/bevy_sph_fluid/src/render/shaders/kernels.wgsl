// Müller 2003 kernels, Akinci 2013 cohesion, the equations of state and the wall collision.
// Rust twins: sph_core::{kernel, eos, container}.
#define_import_path sph::kernels

#import sph::bindings::params

// W_poly6 = 315/(64π h⁹) (h² - r²)³, branch-free (Müller 2003 eq. 20).
fn poly6(r2: f32) -> f32 {
    let d = max(params.h_squared - r2, 0.0);
    return params.poly6_scale * d * d * d;
}

// ∇W_poly6 = -945/(32π h⁹) (h² - r²)² r.
fn poly6_grad(r: vec3<f32>, r2: f32) -> vec3<f32> {
    if r2 >= params.h_squared {
        return vec3<f32>(0.0);
    }
    let d = params.h_squared - r2;
    return r * (params.poly6_grad * d * d);
}

// ∇W_spiky = -45/(π h⁶) (h - r)² r/|r|; zero for coincident particles.
fn spiky_grad(r: vec3<f32>, r_len: f32) -> vec3<f32> {
    let h = params.h;
    if r_len >= h || r_len <= 0.0 {
        return vec3<f32>(0.0);
    }
    let d = h - r_len;
    return r * (params.spiky_grad * d * d / r_len);
}

// ∇²W_viscosity = 45/(π h⁶) (h - r) (Müller 2003 eq. 22).
fn viscosity_laplacian(r_len: f32) -> f32 {
    let h = params.h;
    if r_len >= h {
        return 0.0;
    }
    return params.viscosity_laplacian * (h - r_len);
}

// Akinci 2013 eq. 2 cohesion spline.
fn cohesion(r_len: f32) -> f32 {
    let h = params.h;
    if r_len >= h || r_len <= 0.0 {
        return 0.0;
    }
    let d = h - r_len;
    let core = d * d * d * r_len * r_len * r_len;
    if 2.0 * r_len > h {
        return params.cohesion * core;
    }
    return params.cohesion * (2.0 * core - params.cohesion_offset);
}

// PBF's cubic spline (sph_core::kernel::CubicSpline, normalised on the rest lattice):
// W = k (6q²(q - 1) + 1) for q = r/h <= 1/2, k 2(1 - q)³ up to 1.
fn cubic(r_len: f32) -> f32 {
    let q = r_len / params.h;
    if q >= 1.0 {
        return 0.0;
    }
    if q <= 0.5 {
        return params.pbf_cubic_k * (6.0 * q * q * (q - 1.0) + 1.0);
    }
    let d = 1.0 - q;
    return params.pbf_cubic_k * 2.0 * d * d * d;
}

// ∇W of the cubic spline for r = x_i - x_j: l q(3q - 2) r/|r| up to q = 1/2, -l (1 - q)² r/|r|
// beyond; zero at r = 0 and beyond h.
fn cubic_grad(r: vec3<f32>, r_len: f32) -> vec3<f32> {
    let h = params.h;
    let q = r_len / h;
    if q >= 1.0 || r_len <= 1.0e-9 * h {
        return vec3<f32>(0.0);
    }
    var slope: f32;
    if q <= 0.5 {
        slope = params.pbf_cubic_l * q * (3.0 * q - 2.0);
    } else {
        let d = 1.0 - q;
        slope = -params.pbf_cubic_l * d * d;
    }
    return r * (slope / r_len);
}

// Linear p = k (ρ - ρ0) or Tait p = k ((ρ/ρ0)⁷ - 1), optionally clamped at zero.
fn eos_pressure(rho: f32) -> f32 {
    let rho0 = params.rest_density;
    let k = params.stiffness;
    var p: f32;
    if params.tait == 1u {
        let ratio = rho / rho0;
        let r2 = ratio * ratio;
        let r3 = r2 * ratio;
        p = k * (r3 * r3 * ratio - 1.0);
    } else {
        p = k * (rho - rho0);
    }
    if params.clamp_negative_pressure == 1u {
        p = max(p, 0.0);
    }
    return p;
}

struct PositionVelocity {
    x: vec3<f32>,
    v: vec3<f32>,
}

// One axis of the design's wall collision: clamp, and reflect + damp an outward velocity.
fn collide_axis(x: f32, v: f32, lo: f32, hi: f32, damping: f32) -> vec2<f32> {
    if x <= lo {
        return vec2<f32>(lo, select(v, -v * damping, v < 0.0));
    }
    if x >= hi {
        return vec2<f32>(hi, select(v, -v * damping, v > 0.0));
    }
    return vec2<f32>(x, v);
}

fn collide(x: vec3<f32>, v: vec3<f32>) -> PositionVelocity {
    let lo = params.box_min;
    let hi = params.box_max;
    let damping = params.wall_damping;
    let cx = collide_axis(x.x, v.x, lo.x, hi.x, damping);
    let cy = collide_axis(x.y, v.y, lo.y, hi.y, damping);
    let cz = collide_axis(x.z, v.z, lo.z, hi.z, damping);
    return PositionVelocity(vec3<f32>(cx.x, cy.x, cz.x), vec3<f32>(cx.y, cy.y, cz.y));
}

// Whether x lies beyond the box (the guard's clamp then counts a correction; sph_core::boundary::guard).
fn outside_box(x: vec3<f32>) -> bool {
    return any(x < params.box_min) || any(x > params.box_max);
}

//! Position-based fluids (Macklin & Müller 2013, "Position based fluids"): the density
//! constraint C_i = ρ_i/ρ0 - 1 on predicted positions, solved by Jacobi iterations of λ_i and
//! position corrections Δp_i, with the artificial pressure s_corr against tensile clumping and
//! XSPH viscosity, and optional vorticity confinement. The step that strings them together is `CpuSolver`'s (`solver/pbf.rs`).
//!
//! The passes read the neighbour indices of [`IndexLists`] (built on the predicted positions
//! once per step) and evaluate the kernel at the current predicted positions, which move with
//! every iteration, in one branch-free evaluation per pair
//! ([`CubicSpline::value_and_gradient_factor`]). The kernel is DFSPH's cubic spline ([`CubicSpline`], normalised on the rest
//! lattice), so the rest lattice satisfies the constraint exactly. Boundary samples (Akinci 2012)
//! take part in the density and push with the particle's own λ_i.

use crate::boundary::{BodyForceSum, Boundary};
use crate::kernel::CubicSpline;
use crate::neighbor_lists::IndexLists;
use crate::pair_lanes::{lane_sum, Lanes, LANES};
use crate::params::SphParams;
use crate::solvers::PbfSettings;
use glam::Vec3;
use rayon::prelude::*;

/// The constants of the PBF passes for one parameter set.
#[derive(Clone, Copy, Debug)]
pub struct PbfContext {
    /// The kernel of density and gradients.
    pub kernel: CubicSpline,
    /// Particle mass m.
    pub mass: f32,
    /// Rest density ρ0.
    pub rest_density: f32,
    /// The relaxation ε of λ, absolute [1/m²].
    pub epsilon: f32,
    /// s_corr's k in λ's units: k / Σ|∇C|² of the rest lattice (the paper's λ and s_corr are
    /// both dimensionless in its units; ours is m², so s_corr takes the rest lattice's scale).
    pub s_corr_k: f32,
    /// s_corr's n.
    pub s_corr_n: i32,
    /// 1 / W(Δq).
    pub inverse_w_dq: f32,
    /// XSPH c.
    pub xsph_c: f32,
    /// Vorticity confinement ε [m/s] (0: the stage is skipped).
    pub vorticity_epsilon: f32,
    /// The longest correction of one iteration [m]: [`MAX_CORRECTION`] h, or what gravity moves
    /// a particle in the step when that is longer ([`PbfContext::for_step`]).
    pub max_correction: f32,
    /// The over-relaxation ω of the iterations after the first ([`over_relax`]).
    pub over_relaxation: f32,
}

/// The longest position correction of one iteration, as a fraction of h, unless gravity moves
/// a particle further in the step (see [`PbfContext::for_step`]): it bounds what a degenerate
/// start (64 particles spawned into one cell, 8 ρ0) throws. Measured (docs/pbf.md): 0.5 h put
/// the Martin & Moyce front at RMS Z 1.13 against 0.22 at 0.1 h.
pub const MAX_CORRECTION: f32 = 0.1;

impl PbfContext {
    /// The constants of `params` (its PBF settings, h, spacing, m and ρ0).
    pub fn of(params: &SphParams) -> Self {
        Self::new(
            &params.pbf,
            params.smoothing_radius,
            params.spacing(),
            params.particle_mass,
            params.rest_density,
        )
    }

    /// The constants of `settings` for support radius `h`, spacing `spacing`, mass and ρ0.
    pub fn new(settings: &PbfSettings, h: f32, spacing: f32, mass: f32, rest_density: f32) -> Self {
        let kernel = CubicSpline::new(h, spacing);
        // Σ_k |∇_k C_i|² of a rest-lattice particle: Σ_j |m/ρ0 ∇W|² twice (its own gradient is
        // zero on the lattice; each neighbour's term and i's share of it).
        let mut rest = 0.0;
        for i in -2i32..=2 {
            for j in -2i32..=2 {
                for k in -2i32..=2 {
                    let r = Vec3::new(i as f32, j as f32, k as f32) * spacing;
                    rest +=
                        (kernel.gradient(r, r.length()) * (mass / rest_density)).length_squared();
                }
            }
        }
        let w_dq = kernel.value(settings.s_corr_dq * h);
        Self {
            kernel,
            mass,
            rest_density,
            epsilon: settings.relaxation * rest.max(f32::MIN_POSITIVE),
            s_corr_k: settings.s_corr_k / rest.max(f32::MIN_POSITIVE),
            s_corr_n: settings.s_corr_n as i32,
            inverse_w_dq: if w_dq > 0.0 { 1.0 / w_dq } else { 0.0 },
            xsph_c: settings.xsph_c,
            vorticity_epsilon: settings.vorticity_epsilon,
            max_correction: MAX_CORRECTION * h,
            over_relaxation: settings.over_relaxation,
        }
    }
}

impl PbfContext {
    /// The constants for a step of `dt` under gravity `g` [m/s²]: the correction cap grows to
    /// 2 g dt² when that is longer than [`MAX_CORRECTION`] h, so water can climb back what
    /// gravity moved it at a frame's dt (1/30 s moves a particle 1.5 spacings at Δx = 7 mm).
    pub fn for_step(mut self, g: f32, dt: f32) -> Self {
        let fall = 2.0 * g * dt * dt;
        if fall.is_finite() {
            self.max_correction = self.max_correction.max(fall);
        }
        self
    }
}

/// Iteration `k`'s move of a particle from its capped correction `delta` and the previous
/// iteration's move `previous` (zero before the first): x_{k+1} = x_{k-1} + ω (x_k + Δp_k - x_{k-1})
/// written as a move, u_k = ω Δp_k + (ω - 1) u_{k-1}, with ω = 1 in the first iteration (the
/// stationary Chebyshev semi-iterative method, Wang 2015; see
/// [`crate::PbfSettings::over_relaxation`]).
#[inline]
pub fn over_relax(ctx: &PbfContext, k: u32, delta: Vec3, previous: Vec3) -> Vec3 {
    if k == 0 {
        delta
    } else {
        delta * ctx.over_relaxation + previous * (ctx.over_relaxation - 1.0)
    }
}

/// The share of iteration `k`'s correction in the moves of a step of `iterations` iterations:
/// with the over-relaxation, Δp_k reaches the particle through u_k and every later u (each
/// carries (ω - 1) of the one before), so Σ_k u_k = Σ_k c_k Δp_k with
/// c_0 = Σ_{m < K} (ω - 1)^m and c_k = ω Σ_{m < K - k} (ω - 1)^m. The bodies' reactions are
/// weighted by it, so that they match the moves the boundary caused (1 for every k at ω = 1).
pub fn correction_weight(ctx: &PbfContext, k: u32, iterations: u32) -> f32 {
    let omega = ctx.over_relaxation;
    let (mut sum, mut power) = (0.0, 1.0);
    for _ in k..iterations {
        sum += power;
        power *= omega - 1.0;
    }
    if k == 0 {
        sum
    } else {
        omega * sum
    }
}

/// A particle's constraint state after the λ pass.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Constraint {
    /// λ_i.
    pub lambda: f32,
    /// ρ_i at the predicted positions [kg/m³].
    pub density: f32,
}

/// λ_i = -C_i / (Σ_k |∇_k C_i|² + ε) with C_i = max(ρ_i/ρ0 - 1, 0) (only compression is a
/// violation: a free surface is not pulled together), ρ_i at the predicted `positions`
/// (fluid and boundary), ∇_i C_i = Σ_j (m/ρ0) ∇W_ij + Σ_b V_b ∇W_ib and ∇_j C_i = -(m/ρ0) ∇W_ij
/// (Macklin & Müller 2013, the constraint and its λ). Returns Σ_i C_i.
pub fn compute_lambdas(
    ctx: &PbfContext,
    lists: &IndexLists,
    positions: &[Vec3],
    boundary: Option<&Boundary>,
    out: &mut [Constraint],
) -> f64 {
    let k = &ctx.kernel;
    let scale = ctx.mass / ctx.rest_density;
    let self_weight = k.value(0.0);
    let beyond = 2.0 * k.h;
    lists.update(out, |i, pairs, o| {
        let x_i = positions[i];
        let [mut w_sum, mut gx, mut gy, mut gz, mut squares] = [[0.0f32; LANES]; 5];
        for block in pairs.fluid.chunks(LANES) {
            let r = Lanes::gather(x_i, positions, block, beyond);
            for l in 0..LANES {
                let (w, f) = k.value_and_gradient_factor(r.r2[l]);
                let f = f * scale;
                let g = [r.x[l] * f, r.y[l] * f, r.z[l] * f];
                w_sum[l] += w;
                gx[l] += g[0];
                gy[l] += g[1];
                gz[l] += g[2];
                squares[l] += g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
            }
        }
        let fluid = self_weight + lane_sum(&w_sum);
        let mut grad_i = Vec3::new(lane_sum(&gx), lane_sum(&gy), lane_sum(&gz));
        let squares = lane_sum(&squares);
        let mut solid = 0.0;
        if let Some(b) = boundary {
            for &s in pairs.boundary {
                let s = s as usize;
                let r = x_i - b.position[s];
                let (w, f) = k.value_and_gradient_factor(r.length_squared());
                solid += b.volume[s] * w;
                grad_i += r * (f * b.volume[s]);
            }
        }
        let rho = ctx.mass * fluid + ctx.rest_density * solid;
        let c = (rho / ctx.rest_density - 1.0).max(0.0);
        *o = Constraint {
            lambda: -c / (grad_i.length_squared() + squares + ctx.epsilon),
            density: rho,
        };
    });
    out.par_iter()
        .map(|o| (o.density / ctx.rest_density - 1.0).max(0.0) as f64)
        .sum()
}

/// The densities at the final positions (fluid and boundary), for the diagnostics and the next
/// XSPH weights: the λ pass without its gradients.
pub fn compute_densities(
    ctx: &PbfContext,
    lists: &IndexLists,
    positions: &[Vec3],
    boundary: Option<&Boundary>,
    density: &mut [f32],
) {
    let k = &ctx.kernel;
    lists.update(density, |i, pairs, rho| {
        let x_i = positions[i];
        let mut fluid = k.value(0.0);
        for &j in pairs.fluid {
            let r = x_i - positions[j as usize];
            fluid += k.value_and_gradient_factor(r.length_squared()).0;
        }
        let solid = boundary_volume_sum(k, x_i, boundary, pairs.boundary);
        *rho = ctx.mass * fluid + ctx.rest_density * solid;
    });
}

/// Σ_b V_b W(x_i - x_b) over the boundary samples `samples` of `boundary` (0 without one).
#[inline]
fn boundary_volume_sum(
    k: &CubicSpline,
    x_i: Vec3,
    boundary: Option<&Boundary>,
    samples: &[u32],
) -> f32 {
    let Some(b) = boundary else {
        return 0.0;
    };
    samples
        .iter()
        .map(|&s| {
            let s = s as usize;
            b.volume[s]
                * k.value_and_gradient_factor((x_i - b.position[s]).length_squared())
                    .0
        })
        .sum()
}

/// Δp_i = Σ_j (m/ρ0) (λ_i + λ_j + s_corr) ∇W_ij + Σ_b V_b λ_i ∇W_ib with
/// s_corr = -k (W(r_ij) / W(Δq))^n (Macklin & Müller 2013, the position update and the
/// artificial pressure), at most `ctx.max_correction` long.
pub fn compute_corrections(
    ctx: &PbfContext,
    lists: &IndexLists,
    positions: &[Vec3],
    boundary: Option<&Boundary>,
    constraint: &[Constraint],
    delta: &mut [Vec3],
) {
    // n is a constant of each loop, so the power is a few multiplications the lanes share.
    let pass = Corrections {
        ctx,
        lists,
        positions,
        boundary,
        constraint,
    };
    match ctx.s_corr_n {
        1 => pass.run::<1>(delta),
        2 => pass.run::<2>(delta),
        3 => pass.run::<3>(delta),
        4 => pass.run::<4>(delta),
        5 => pass.run::<5>(delta),
        6 => pass.run::<6>(delta),
        7 => pass.run::<7>(delta),
        _ => pass.run::<8>(delta),
    }
}

/// The inputs of [`compute_corrections`].
struct Corrections<'a> {
    ctx: &'a PbfContext,
    lists: &'a IndexLists,
    positions: &'a [Vec3],
    boundary: Option<&'a Boundary>,
    constraint: &'a [Constraint],
}

impl Corrections<'_> {
    /// The pass with s_corr's exponent n = `N`.
    fn run<const N: i32>(&self, delta: &mut [Vec3]) {
        let Self {
            ctx,
            lists,
            positions,
            boundary,
            constraint,
        } = *self;
        let k = &ctx.kernel;
        let scale = ctx.mass / ctx.rest_density;
        let (s_corr_k, inverse_w_dq) = (ctx.s_corr_k, ctx.inverse_w_dq);
        let beyond = 2.0 * k.h;
        lists.update(delta, |i, pairs, d| {
            let x_i = positions[i];
            let l_i = constraint[i].lambda;
            let [mut fx, mut fy, mut fz] = [[0.0f32; LANES]; 3];
            for block in pairs.fluid.chunks(LANES) {
                let r = Lanes::gather(x_i, positions, block, beyond);
                let mut l_j = [0.0f32; LANES];
                for (l, &j) in block.iter().enumerate() {
                    l_j[l] = constraint[j as usize].lambda;
                }
                for l in 0..LANES {
                    let (w, f) = k.value_and_gradient_factor(r.r2[l]);
                    let s_corr = -s_corr_k * power::<N>(w * inverse_w_dq);
                    let f = f * (l_i + l_j[l] + s_corr);
                    fx[l] += r.x[l] * f;
                    fy[l] += r.y[l] * f;
                    fz[l] += r.z[l] * f;
                }
            }
            let fluid = Vec3::new(lane_sum(&fx), lane_sum(&fy), lane_sum(&fz));
            let mut solid = Vec3::ZERO;
            if let Some(b) = boundary {
                for &s in pairs.boundary {
                    let s = s as usize;
                    let r = x_i - b.position[s];
                    solid += r * (k.value_and_gradient_factor(r.length_squared()).1 * b.volume[s]);
                }
            }
            *d = (fluid * scale + solid * l_i).clamp_length_max(ctx.max_correction);
        });
    }
}

/// x^N by multiplications (`powi` with an exponent unknown at compile time is a library call
/// per pair).
#[inline(always)]
fn power<const N: i32>(x: f32) -> f32 {
    let mut p = x;
    for _ in 1..N {
        p *= x;
    }
    p
}

/// The fluid's force on each boundary body from one iteration's corrections (Akinci 2012's
/// two-way coupling in PBF's position form): sample b moves particle i by Δp_ib = V_b λ_i ∇W_ib,
/// which changes i's momentum by m Δp_ib / dt over the step of `dt`, so the body feels
/// -m Δp_ib / dt² at the sample, with its torque about the body's origin. Indexed like
/// [`Boundary::friction`]. The [`MAX_CORRECTION`] cap, which acts only far from rest, is not
/// applied here. `weight` is the iteration's [`correction_weight`].
pub fn boundary_reactions(
    ctx: &PbfContext,
    lists: &IndexLists,
    positions: &[Vec3],
    boundary: &Boundary,
    constraint: &[Constraint],
    dt: f32,
    weight: f32,
) -> Vec<BodyForceSum> {
    let k = &ctx.kernel;
    let bodies = boundary.body_count();
    let scale = -ctx.mass * weight / (dt * dt);
    lists.fold(
        || vec![BodyForceSum::default(); bodies],
        |mut sums, i, pairs| {
            let l_i = constraint[i].lambda;
            if l_i != 0.0 {
                for &s in pairs.boundary {
                    let s = s as usize;
                    let r = positions[i] - boundary.position[s];
                    let f = k.value_and_gradient_factor(r.length_squared()).1;
                    let moved = r * (f * boundary.volume[s] * l_i);
                    let body = boundary.body[s] as usize;
                    sums[body].add(moved * scale, boundary.position[s], boundary.origin[body]);
                }
            }
            sums
        },
        |mut a, b| {
            a.iter_mut().zip(&b).for_each(|(a, b)| a.merge(b));
            a
        },
    )
}

/// XSPH viscosity, v_i + c Σ_j (m/ρ_j) (v_j - v_i) W_ij into `velocity_out` (ρ_j from the last λ
/// pass, in `constraint`), and the densities at the final `positions` (fluid and boundary, as
/// [`compute_densities`]) into `density`: one pass, as both weigh the same W_ij.
#[allow(clippy::too_many_arguments)]
pub fn xsph_and_densities(
    ctx: &PbfContext,
    lists: &IndexLists,
    positions: &[Vec3],
    boundary: Option<&Boundary>,
    constraint: &[Constraint],
    velocity: &[Vec3],
    velocity_out: &mut [Vec3],
    density: &mut [f32],
) {
    let k = &ctx.kernel;
    let self_weight = k.value(0.0);
    let beyond = 2.0 * k.h;
    lists.update_pair(velocity_out, density, |i, pairs, v, rho| {
        let (x_i, v_i) = (positions[i], velocity[i]);
        let [mut w_sum, mut sx, mut sy, mut sz] = [[0.0f32; LANES]; 4];
        for block in pairs.fluid.chunks(LANES) {
            let r = Lanes::gather(x_i, positions, block, beyond);
            let [mut dx, mut dy, mut dz, mut volume] = [[0.0f32; LANES]; 4];
            for (l, &j) in block.iter().enumerate() {
                let j = j as usize;
                let dv = velocity[j] - v_i;
                (dx[l], dy[l], dz[l]) = (dv.x, dv.y, dv.z);
                volume[l] = ctx.mass / constraint[j].density;
            }
            for l in 0..LANES {
                let w = k.value_and_gradient_factor(r.r2[l]).0;
                w_sum[l] += w;
                let weight = volume[l] * w;
                sx[l] += dx[l] * weight;
                sy[l] += dy[l] * weight;
                sz[l] += dz[l] * weight;
            }
        }
        let smoothing = Vec3::new(lane_sum(&sx), lane_sum(&sy), lane_sum(&sz));
        *v = v_i + smoothing * ctx.xsph_c;
        let solid = boundary_volume_sum(k, x_i, boundary, pairs.boundary);
        *rho = ctx.mass * (self_weight + lane_sum(&w_sum)) + ctx.rest_density * solid;
    });
}

/// The vorticity ω_i = ∇ × v = Σ_j (m/ρ_j) (v_j - v_i) × ∇_j W_ij with ∇_j W_ij = -∇_i W_ij
/// (Macklin & Müller 2013, eq. 15, with the SPH volume m/ρ_j so that ω is in 1/s).
pub fn vorticity(
    ctx: &PbfContext,
    lists: &IndexLists,
    positions: &[Vec3],
    density: &[f32],
    velocity: &[Vec3],
    omega: &mut [Vec3],
) {
    let k = &ctx.kernel;
    lists.update(omega, |i, pairs, w| {
        let (x_i, v_i) = (positions[i], velocity[i]);
        let mut curl = Vec3::ZERO;
        for &j in pairs.fluid {
            let j = j as usize;
            let r = x_i - positions[j];
            let grad_j = -k.gradient(r, r.length());
            curl += (velocity[j] - v_i).cross(grad_j) * (ctx.mass / density[j]);
        }
        *w = curl;
    });
}

/// Vorticity confinement: v_i += dt ε (N_i × ω_i) with N = η/|η| and
/// η_i = ∇|ω|_i = Σ_j (m/ρ_j) (|ω_j| - |ω_i|) ∇_i W_ij (Macklin & Müller 2013, eq. 16, after
/// Fedkiw et al. 2001): the force turns the flow around the local peaks of |ω|.
#[allow(clippy::too_many_arguments)]
pub fn confine_vorticity(
    ctx: &PbfContext,
    lists: &IndexLists,
    positions: &[Vec3],
    density: &[f32],
    omega: &[Vec3],
    dt: f32,
    velocity_in: &[Vec3],
    velocity_out: &mut [Vec3],
) {
    let k = &ctx.kernel;
    lists.update(velocity_out, |i, pairs, v| {
        let (x_i, w_i) = (positions[i], omega[i].length());
        let mut eta = Vec3::ZERO;
        for &j in pairs.fluid {
            let j = j as usize;
            let r = x_i - positions[j];
            eta += k.gradient(r, r.length()) * ((omega[j].length() - w_i) * ctx.mass / density[j]);
        }
        let n = eta.normalize_or_zero();
        *v = velocity_in[i] + n.cross(omega[i]) * (ctx.vorticity_epsilon * dt);
    });
}

//! Position-based fluids (Macklin & Müller 2013, "Position based fluids"): the density
//! constraint C_i = ρ_i/ρ0 - 1 on predicted positions, solved by Jacobi iterations of λ_i and
//! position corrections Δp_i, with the artificial pressure s_corr against tensile clumping and
//! XSPH viscosity, and optional vorticity confinement. The step that strings them together is `CpuSolver`'s (`solver/pbf/mod.rs`).
//!
//! The passes read the neighbour indices of [`IndexLists`] (built on the predicted positions
//! once per step) and evaluate the kernel at the current predicted positions, which move with
//! every iteration, in one branch-free evaluation per pair
//! ([`CubicSpline::value_and_gradient_factor`]). The kernel is DFSPH's cubic spline ([`CubicSpline`], normalised on the rest
//! lattice), so the rest lattice satisfies the constraint exactly. Boundary samples (Akinci 2012)
//! take part in the density and push with λ_i + λ_b, λ_b the water's λ extrapolated onto them
//! ([`crate::solver::pbf::wall_lambda`]).

use crate::boundary::samples::{BodyForceSum, Boundary};
use crate::kernel::CubicSpline;
use crate::neighbor::lists::IndexLists;
use crate::neighbor::pair_lanes::{lane_sum, wide_lanes, Lanes, LANES};
use crate::params::SphParams;
use crate::solver::pbf::settings::PbfSettings;
use crate::solver::pbf::solid_contact::project_out_of_solids;
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
    /// The longest correction of one iteration [m]: [`MAX_CORRECTION`] h (at most
    /// [`MAX_STEP_CORRECTION`] h over the step's iterations), or what gravity moves
    /// a particle in the step when that is longer ([`PbfContext::for_step`]).
    pub max_correction: f32,
    /// The over-relaxation ω of the iterations after the first ([`over_relax`]).
    pub over_relaxation: f32,
    /// The weight w of each iteration's λ ([`crate::PbfSettings::jacobi_weight`]).
    pub jacobi_weight: f32,
}

/// The longest position correction of one iteration, as a fraction of h, unless gravity moves
/// a particle further in the step (see [`PbfContext::for_step`]): it bounds what a degenerate
/// start (64 particles spawned into one cell, 8 ρ0) throws. Measured (docs/pbf.md): 0.5 h put
/// the Martin & Moyce front at RMS Z 1.13 against 0.22 at 0.1 h.
pub const MAX_CORRECTION: f32 = 0.1;

/// The longest sum of a step's capped corrections, as a fraction of h: past
/// 4 × [`MAX_CORRECTION`] the cap of one iteration shrinks to this over the iteration count.
/// The time-step rule lets a particle move λ h = 0.5 h in a step; with s_corr's Δq at 0.9 h
/// (s_corr's largest, pushing every pair apart at the cap) six iterations of 0.1 h drove the
/// step down from step to step until the state overflowed, four never did
/// (`tests/stability_extremes.rs`).
pub const MAX_STEP_CORRECTION: f32 = 0.4;

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
            max_correction: MAX_CORRECTION
                .min(MAX_STEP_CORRECTION / settings.iterations.max(1) as f32)
                * h,
            over_relaxation: settings.over_relaxation,
            jacobi_weight: settings.jacobi_weight,
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
    let carried = carried_weight(ctx, k, iterations);
    if k == 0 {
        carried
    } else {
        ctx.over_relaxation * carried
    }
}

/// The share of a move made at the end of iteration `k` (after its over-relaxed correction: the
/// contact's projection, [`crate::solver::pbf::solid_contact`]) in the moves of a step of
/// `iterations` iterations: each later u carries (ω - 1) of the one before, so
/// Σ_{m < K - k} (ω - 1)^m.
pub fn carried_weight(ctx: &PbfContext, k: u32, iterations: u32) -> f32 {
    let omega = ctx.over_relaxation;
    let (mut sum, mut power) = (0.0, 1.0);
    for _ in k..iterations {
        sum += power;
        power *= omega - 1.0;
    }
    sum
}

/// A particle's constraint state after the λ pass.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Constraint {
    /// λ_i.
    pub lambda: f32,
    /// ρ_i at the predicted positions [kg/m³].
    pub density: f32,
}

/// λ_i = -w C_i / (Σ_k |∇_k C_i|² + ε) with C_i = max(ρ_i/ρ0 - 1, 0) (only compression is a
/// violation: a free surface is not pulled together), ρ_i at the predicted `positions`
/// (fluid and boundary), ∇_i C_i = Σ_j (m/ρ0) ∇W_ij + Σ_b V_b ∇W_ib and ∇_j C_i = -(m/ρ0) ∇W_ij
/// (Macklin & Müller 2013, the constraint and its λ), with the weight w of weighted Jacobi
/// ([`crate::PbfSettings::jacobi_weight`]).
pub fn compute_lambdas(
    ctx: &PbfContext,
    lists: &IndexLists,
    positions: &[Vec3],
    boundary: Option<&Boundary>,
    out: &mut [Constraint],
) {
    let k = &ctx.kernel;
    let self_weight = k.value(0.0);
    let wide = wide_lanes();
    lists.update(out, |i, pairs, o| {
        let x_i = positions[i];
        let sums = fluid_lambda_sums(wide, ctx, x_i, pairs.fluid, positions);
        let mut grad_i = sums.gradient;
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
        let rho = ctx.mass * (self_weight + sums.weight) + ctx.rest_density * solid;
        let c = (rho / ctx.rest_density - 1.0).max(0.0);
        *o = Constraint {
            lambda: -ctx.jacobi_weight * c / (grad_i.length_squared() + sums.squares + ctx.epsilon),
            density: rho,
        };
    });
}

/// Σ_i C_i = Σ_i max(ρ_i/ρ0 - 1, 0) over the densities of a λ pass.
pub fn constraint_violation(ctx: &PbfContext, constraint: &[Constraint]) -> f64 {
    constraint
        .par_iter()
        .map(|o| (o.density / ctx.rest_density - 1.0).max(0.0) as f64)
        .sum()
}

/// The fluid pairs' sums of one particle's λ: Σ_j W_ij, ∇_i C_i's fluid part
/// Σ_j (m/ρ0) ∇W_ij, and Σ_j |(m/ρ0) ∇W_ij|².
#[derive(Clone, Copy, Debug)]
struct LambdaSums {
    weight: f32,
    gradient: Vec3,
    squares: f32,
}

/// [`LambdaSums`] of the particle at `x_i` with the neighbours `fluid`, in the AVX2 copy when
/// `wide` ([`wide_lanes`]).
#[inline]
fn fluid_lambda_sums(
    wide: bool,
    ctx: &PbfContext,
    x_i: Vec3,
    fluid: &[u32],
    positions: &[Vec3],
) -> LambdaSums {
    #[cfg(target_arch = "x86_64")]
    if wide {
        #[target_feature(enable = "avx2,fma")]
        fn avx2(ctx: &PbfContext, x_i: Vec3, fluid: &[u32], positions: &[Vec3]) -> LambdaSums {
            lambda_sums_in_lanes::<true>(ctx, x_i, fluid, positions)
        }
        // SAFETY: `wide` comes from `wide_lanes()`: this CPU has AVX2 and FMA.
        return unsafe { avx2(ctx, x_i, fluid, positions) };
    }
    let _ = wide;
    lambda_sums_in_lanes::<false>(ctx, x_i, fluid, positions)
}

#[inline(always)]
fn lambda_sums_in_lanes<const WIDE: bool>(
    ctx: &PbfContext,
    x_i: Vec3,
    fluid: &[u32],
    positions: &[Vec3],
) -> LambdaSums {
    let k = &ctx.kernel;
    let scale = ctx.mass / ctx.rest_density;
    let beyond = 2.0 * k.h;
    let [mut w_sum, mut gx, mut gy, mut gz, mut squares] = [[0.0f32; LANES]; 5];
    for block in fluid.chunks(LANES) {
        let r = Lanes::gather::<WIDE>(x_i, positions, block, beyond);
        for l in 0..LANES {
            let (w, f) = k.value_and_gradient_factor(r.r2::<WIDE>(l));
            let f = f * scale;
            let g = [r.x[l] * f, r.y[l] * f, r.z[l] * f];
            w_sum[l] += w;
            gx[l] += g[0];
            gy[l] += g[1];
            gz[l] += g[2];
            squares[l] += g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
        }
    }
    LambdaSums {
        weight: lane_sum(&w_sum),
        gradient: Vec3::new(lane_sum(&gx), lane_sum(&gy), lane_sum(&gz)),
        squares: lane_sum(&squares),
    }
}

/// A pass that depends on s_corr's exponent n, compiled once per n (`powi` with an exponent
/// known only at run time is a library call per pair).
trait SCorrPass {
    /// The pass with n = `N`.
    fn run<const N: i32>(self);
}

/// Runs `pass` with n = `n` (1..=8; larger values run as 8, the settings' limit).
fn with_s_corr_power(n: i32, pass: impl SCorrPass) {
    match n {
        1 => pass.run::<1>(),
        2 => pass.run::<2>(),
        3 => pass.run::<3>(),
        4 => pass.run::<4>(),
        5 => pass.run::<5>(),
        6 => pass.run::<6>(),
        7 => pass.run::<7>(),
        _ => pass.run::<8>(),
    }
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
pub(crate) fn boundary_volume_sum(
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

/// A particle's correction in one iteration, with what its boundary samples take of it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Correction {
    /// Δp_i, capped [m].
    pub delta: Vec3,
    /// The body of the particle's boundary samples: [`NO_BODY`] without samples,
    /// [`SEVERAL_BODIES`] when they belong to more than one.
    pub body: u32,
    /// Δp_i's boundary part, Σ_b V_b (λ_i + λ_b) ∇W_ib over the samples [m]. Each term lies
    /// along x_i - x_b, so the sum's moment about a point o is (x_i - o) × `wall_move`.
    pub wall_move: Vec3,
}

/// [`Correction::body`] of a particle with no boundary sample in reach.
pub const NO_BODY: u32 = u32::MAX;
/// [`Correction::body`] of a particle whose samples belong to more than one body.
pub const SEVERAL_BODIES: u32 = u32::MAX - 1;

/// Δp_i = Σ_j (m/ρ0) (λ_i + λ_j + s_corr) ∇W_ij + Σ_b V_b (λ_i + λ_b) ∇W_ib with
/// s_corr = -k (W(r_ij) / W(Δq))^n (Macklin & Müller 2013, the position update and the
/// artificial pressure), λ_b the samples' λ (`wall_lambda`, by sample;
/// [`crate::solver::pbf::wall_lambda`]), at most `ctx.max_correction` long, with what the
/// boundary samples take of it for [`apply_corrections`].
pub fn compute_corrections(
    ctx: &PbfContext,
    lists: &IndexLists,
    positions: &[Vec3],
    boundary: Option<(&Boundary, &[f32])>,
    constraint: &[Constraint],
    out: &mut [Correction],
) {
    with_s_corr_power(
        ctx.s_corr_n,
        Corrections {
            ctx,
            lists,
            positions,
            boundary,
            constraint,
            out,
        },
    );
}

/// The inputs and outputs of [`compute_corrections`].
struct Corrections<'a> {
    ctx: &'a PbfContext,
    lists: &'a IndexLists,
    positions: &'a [Vec3],
    /// The samples and their λ_b.
    boundary: Option<(&'a Boundary, &'a [f32])>,
    constraint: &'a [Constraint],
    out: &'a mut [Correction],
}

impl SCorrPass for Corrections<'_> {
    fn run<const N: i32>(self) {
        let Self {
            ctx,
            lists,
            positions,
            boundary,
            constraint,
            out,
        } = self;
        let k = &ctx.kernel;
        let scale = ctx.mass / ctx.rest_density;
        let wide = wide_lanes();
        lists.update(out, |i, pairs, o| {
            let x_i = positions[i];
            let l_i = constraint[i].lambda;
            let sums = FluidCorrection {
                ctx,
                x_i,
                l_i,
                fluid: pairs.fluid,
                positions,
                constraint,
            };
            let fluid = sums.sum::<N>(wide) * scale;
            let (mut push, mut body) = (Vec3::ZERO, NO_BODY);
            if let Some((b, wall_lambda)) = boundary {
                for &s in pairs.boundary {
                    let s = s as usize;
                    let r = x_i - b.position[s];
                    let f = k.value_and_gradient_factor(r.length_squared()).1;
                    push += r * (f * b.volume[s] * (l_i + wall_lambda[s]));
                    let of = b.body[s];
                    body = if body == NO_BODY || body == of {
                        of
                    } else {
                        SEVERAL_BODIES
                    };
                }
            }
            *o = Correction {
                delta: (fluid + push).clamp_length_max(ctx.max_correction),
                body,
                wall_move: push,
            };
        });
    }
}

/// One particle's fluid sum Σ_j (λ_i + λ_j + s_corr) ∇W_ij of [`compute_corrections`] (before
/// the factor m/ρ0).
struct FluidCorrection<'a> {
    ctx: &'a PbfContext,
    x_i: Vec3,
    l_i: f32,
    fluid: &'a [u32],
    positions: &'a [Vec3],
    constraint: &'a [Constraint],
}

impl FluidCorrection<'_> {
    /// The sum with s_corr's n = `N`, in the AVX2 copy when `wide` ([`wide_lanes`]).
    #[inline]
    fn sum<const N: i32>(&self, wide: bool) -> Vec3 {
        #[cfg(target_arch = "x86_64")]
        if wide {
            #[target_feature(enable = "avx2,fma")]
            fn avx2<const N: i32>(pass: &FluidCorrection) -> Vec3 {
                pass.in_lanes::<true, N>()
            }
            // SAFETY: `wide` comes from `wide_lanes()`: this CPU has AVX2 and FMA.
            return unsafe { avx2::<N>(self) };
        }
        let _ = wide;
        self.in_lanes::<false, N>()
    }

    #[inline(always)]
    fn in_lanes<const WIDE: bool, const N: i32>(&self) -> Vec3 {
        let Self {
            ctx,
            x_i,
            l_i,
            fluid,
            positions,
            constraint,
        } = *self;
        let k = &ctx.kernel;
        let (s_corr_k, inverse_w_dq) = (ctx.s_corr_k, ctx.inverse_w_dq);
        let beyond = 2.0 * k.h;
        let [mut fx, mut fy, mut fz] = [[0.0f32; LANES]; 3];
        for block in fluid.chunks(LANES) {
            let r = Lanes::gather::<WIDE>(x_i, positions, block, beyond);
            let mut l_j = [0.0f32; LANES];
            for (l, &j) in block.iter().enumerate() {
                l_j[l] = constraint[j as usize].lambda;
            }
            for l in 0..LANES {
                let (w, f) = k.value_and_gradient_factor(r.r2::<WIDE>(l));
                let s_corr = -s_corr_k * power::<N>(w * inverse_w_dq);
                let f = f * (l_i + l_j[l] + s_corr);
                fx[l] += r.x[l] * f;
                fy[l] += r.y[l] * f;
                fz[l] += r.z[l] * f;
            }
        }
        Vec3::new(lane_sum(&fx), lane_sum(&fy), lane_sum(&fz))
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

/// What [`apply_corrections`] needs besides the positions: the iteration's corrections and
/// what the bodies take of them.
#[derive(Clone, Copy)]
pub struct CorrectionStep<'a> {
    /// The iteration k (0 first) of `iterations`.
    pub iteration: u32,
    /// Iterations in the step.
    pub iterations: u32,
    /// The step's dt [s].
    pub dt: f32,
    /// The boundary samples.
    pub boundary: &'a Boundary,
    /// The samples' λ_b of the iteration ([`crate::solver::pbf::wall_lambda`]).
    pub wall_lambda: &'a [f32],
    /// The iteration's λ.
    pub constraint: &'a [Constraint],
    /// The iteration's corrections ([`compute_corrections`]).
    pub corrections: &'a [Correction],
    /// The distance the contact with the solids keeps from their surfaces after the move
    /// ([`crate::solver::pbf::solid_contact`]); `None` leaves it out.
    pub contact_margin: Option<f32>,
}

/// The pressure equivalent to a particle's λ over a step of `dt` at its density `density`,
/// p_i = -(ρ_i² / ρ0) Λ_i / dt² with Λ_i = Σ_k c_k λ_k the step's λ weighted as its corrections
/// reach the moves ([`correction_weight`]). The step moves particle i by
/// Σ_k u_k = (m/ρ0) Σ_j (Λ_i + Λ_j) ∇W_ij (and V_b (Λ_i + Λ_b) ∇W_ib at the samples), where
/// Monaghan's symmetric SPH pressure force, the form WCSPH uses, would move it by
/// dt² a_i = -dt² Σ_j m (p_i/ρ_i² + p_j/ρ_j²) ∇W_ij: the two agree for this p. So a tank at
/// rest reads ρ0 g depth where its λ holds the water up against gravity's dt² of prediction.
/// With ρ0 in place of ρ_i (the incompressible form) that form's density-gradient error puts a
/// column compressed by a few per cent about 12 % under ρ0 g depth at its floor, as a fixed
/// iteration count leaves the water more compressed the deeper it is (docs/pbf.md). The
/// artificial pressure s_corr and
/// the correction cap are not in it. Never negative (λ ≤ 0: only compression is a violation).
#[inline]
pub fn equivalent_pressure(ctx: &PbfContext, lambda_sum: f32, density: f32, dt: f32) -> f32 {
    let p = -density * density * lambda_sum / (ctx.rest_density * dt * dt);
    if p.is_finite() {
        p.max(0.0)
    } else {
        0.0
    }
}

/// Moves every particle by its over-relaxed correction, x += u_k ([`over_relax`]; `moved`
/// holds u_{k-1} and receives u_k), and returns the fluid's force on each boundary body from
/// the iteration (Akinci 2012's two-way coupling in PBF's position form): sample b moves
/// particle i by Δp_ib = V_b (λ_i + λ_b) ∇W_ib, which changes i's momentum by m Δp_ib / dt over the
/// step of `dt`, so the body feels -m Δp_ib / dt² at the sample, with its torque about the
/// body's origin, weighted by the iteration's [`correction_weight`]. Summed per particle by
/// [`compute_corrections`], pair by pair for a particle whose samples belong to several
/// bodies. Indexed like [`Boundary::friction`]. The [`MAX_CORRECTION`] cap, which acts only far
/// from rest, is not applied to the reactions. With a `contact_margin`, each particle is then
/// projected out of the solids ([`crate::solver::pbf::solid_contact`]): the projection δ joins
/// u_k and its body feels -m c δ / dt², c = [`carried_weight`]. One pass.
pub fn apply_corrections(
    ctx: &PbfContext,
    lists: &IndexLists,
    step: CorrectionStep,
    positions: &mut [Vec3],
    moved: &mut [Vec3],
) -> Vec<BodyForceSum> {
    let CorrectionStep {
        iteration,
        iterations,
        dt,
        boundary,
        wall_lambda,
        constraint,
        corrections,
        contact_margin,
    } = step;
    let k = &ctx.kernel;
    let bodies = boundary.body_count();
    let scale = -ctx.mass * correction_weight(ctx, iteration, iterations) / (dt * dt);
    let contact_scale = -ctx.mass * carried_weight(ctx, iteration, iterations) / (dt * dt);
    lists.update_fold(
        positions,
        moved,
        || vec![BodyForceSum::default(); bodies],
        |mut sums, i, pairs, x, u| {
            let l_i = constraint[i].lambda;
            let c = &corrections[i];
            if c.wall_move != Vec3::ZERO && c.body != NO_BODY {
                if c.body != SEVERAL_BODIES {
                    let sum = &mut sums[c.body as usize];
                    sum.force += (c.wall_move * scale).as_dvec3();
                    let arm = *x - boundary.origin[c.body as usize];
                    sum.torque += (arm.cross(c.wall_move) * scale).as_dvec3();
                } else {
                    for &s in pairs.boundary {
                        let s = s as usize;
                        let r = *x - boundary.position[s];
                        let f = k.value_and_gradient_factor(r.length_squared()).1;
                        let moved = r * (f * boundary.volume[s] * (l_i + wall_lambda[s]));
                        let body = boundary.body[s] as usize;
                        sums[body].add(moved * scale, boundary.position[s], boundary.origin[body]);
                    }
                }
            }
            *u = over_relax(ctx, iteration, c.delta, *u);
            *x += *u;
            if let Some(margin) = contact_margin {
                project_out_of_solids(boundary, x, margin, |body, delta, at| {
                    *u += delta;
                    let origin = boundary.body_origin(body);
                    sums[body as usize].add(delta * contact_scale, at, origin);
                });
            }
            sums
        },
        |mut a, b| {
            a.iter_mut().zip(&b).for_each(|(a, b)| a.merge(b));
            a
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::container::BoxContainer;
    use crate::neighbor::Neighbors;
    use crate::params::SphParams;
    use crate::rng::SplitMix64;
    use crate::solver::pbf::wall_lambda::{extrapolate_wall_lambda, SampleNeighbors};
    use crate::solver::pbf::xsph_vorticity::FluidXsph;

    /// The AVX2 copies of the pair loops (taken on this CPU when it has AVX2 and FMA) give the
    /// baseline copies' sums: the same arithmetic in the same order, only wider.
    #[test]
    fn the_wide_pair_loops_match_the_baseline_ones() {
        let params = SphParams::water();
        let (h, dx) = (params.smoothing_radius, params.spacing());
        let ctx = PbfContext::of(&params);
        let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(20.0 * dx));
        let mut rng = SplitMix64::new(7);
        let raw: Vec<Vec3> = (0..1000)
            .map(|k| {
                let lattice = Vec3::new((k % 10) as f32, ((k / 10) % 10) as f32, (k / 100) as f32);
                let jitter = Vec3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), 0.0);
                (lattice + jitter + Vec3::splat(5.0)) * 0.9 * dx
            })
            .collect();
        let mut neighbors = Neighbors::new(params.neighbor_search, &container, h, 1000).unwrap();
        let order = neighbors.sort(&raw).to_vec();
        let positions: Vec<Vec3> = order.iter().map(|&i| raw[i as usize]).collect();
        let velocity: Vec<Vec3> = (0..1000)
            .map(|_| Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0))
            .collect();
        let mut lists = IndexLists::default();
        lists.rebuild_indices(&neighbors, &positions, None);
        let mut constraint = vec![Constraint::default(); 1000];
        compute_lambdas(&ctx, &lists, &positions, None, &mut constraint);
        let wide = wide_lanes();
        println!("AVX2 and FMA on this CPU: {wide} (false: the baseline is compared with itself)");
        let close = |a: f32, b: f32| (a - b).abs() <= 1e-6 * a.abs().max(b.abs()).max(1e-12);
        lists.fold(
            || (),
            |_, i, pairs| {
                let x_i = positions[i];
                let a = fluid_lambda_sums(wide, &ctx, x_i, pairs.fluid, &positions);
                let b = fluid_lambda_sums(false, &ctx, x_i, pairs.fluid, &positions);
                assert!(close(a.weight, b.weight) && close(a.squares, b.squares));
                assert!((a.gradient - b.gradient).length() <= 1e-6 * b.gradient.length().max(1e-3));
                let pass = FluidCorrection {
                    ctx: &ctx,
                    x_i,
                    l_i: constraint[i].lambda,
                    fluid: pairs.fluid,
                    positions: &positions,
                    constraint: &constraint,
                };
                let (a, b) = (pass.sum::<4>(wide), pass.sum::<4>(false));
                assert!((a - b).length() <= 1e-6 * b.length().max(1e-3), "{a} {b}");
                let pass = FluidXsph {
                    ctx: &ctx,
                    x_i,
                    v_i: velocity[i],
                    fluid: pairs.fluid,
                    positions: &positions,
                    velocity: &velocity,
                    constraint: &constraint,
                };
                let (a, b) = (pass.sums(wide), pass.sums(false));
                assert!(close(a.0, b.0) && (a.1 - b.1).length() <= 1e-6 * b.1.length().max(1e-3));
            },
            |_, _| (),
        );
        let (fluid_pairs, _) = lists.pair_counts();
        assert!(
            fluid_pairs > 20_000,
            "{fluid_pairs} pairs: the block is dense enough to test"
        );
    }

    /// The pressure the step's λ stand for moves the water as the λ do: with s_corr off and no
    /// cap, the corrections (m/ρ0) Σ_j (λ_i + λ_j) ∇W_ij of a random λ field equal Monaghan's
    /// symmetric SPH pressure's dt² a_i = -dt² Σ_j m (p_i/ρ_i² + p_j/ρ_j²) ∇W_ij at
    /// p = equivalent_pressure, with densities up to 5 % over ρ0.
    #[test]
    fn the_equivalent_pressure_moves_the_water_as_its_lambda_do() {
        let params = SphParams::water();
        let (h, dx) = (params.smoothing_radius, params.spacing());
        let mut ctx = PbfContext::of(&params);
        ctx.s_corr_k = 0.0;
        ctx.max_correction = f32::MAX;
        let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(12.0 * dx));
        let mut rng = SplitMix64::new(11);
        let raw: Vec<Vec3> = (0..512)
            .map(|k| {
                let lattice = Vec3::new((k % 8) as f32, ((k / 8) % 8) as f32, (k / 64) as f32);
                let jitter = Vec3::new(rng.range(-0.2, 0.2), rng.range(-0.2, 0.2), 0.0);
                (lattice + jitter + Vec3::splat(2.0)) * dx
            })
            .collect();
        let mut neighbors = Neighbors::new(params.neighbor_search, &container, h, 512).unwrap();
        let order = neighbors.sort(&raw).to_vec();
        let positions: Vec<Vec3> = order.iter().map(|&i| raw[i as usize]).collect();
        let mut lists = IndexLists::default();
        lists.rebuild_indices(&neighbors, &positions, None);
        // λ [m²] of a squeezed block.
        let scale = 0.03 * dx * dx;
        let constraint: Vec<Constraint> = (0..512)
            .map(|_| Constraint {
                lambda: -scale * rng.range(0.0, 1.0),
                density: params.rest_density * rng.range(1.0, 1.05),
            })
            .collect();
        let mut corrections = vec![Correction::default(); 512];
        let (lambdas, out) = (&constraint, &mut corrections);
        compute_corrections(&ctx, &lists, &positions, None, lambdas, out);
        let dt = 1.0 / 120.0;
        let p: Vec<f32> = constraint
            .iter()
            .map(|c| equivalent_pressure(&ctx, c.lambda, c.density, dt))
            .collect();
        assert!(p.iter().all(|&p| p >= 0.0) && p.iter().any(|&p| p > 0.0));
        // p_i / ρ_i².
        let q: Vec<f32> = p
            .iter()
            .zip(&constraint)
            .map(|(p, c)| p / (c.density * c.density))
            .collect();
        let factor = -dt * dt * ctx.mass;
        let mut worst: f32 = 0.0;
        let mut largest: f32 = 0.0;
        for i in 0..512 {
            let mut moved = Vec3::ZERO;
            for j in 0..512 {
                let r = positions[i] - positions[j];
                let r2 = r.length_squared();
                if j == i || r2 >= h * h {
                    continue;
                }
                let f = ctx.kernel.value_and_gradient_factor(r2).1;
                moved += r * (f * (q[i] + q[j]) * factor);
            }
            worst = worst.max((moved - corrections[i].delta).length());
            largest = largest.max(corrections[i].delta.length());
        }
        assert!(largest > 1e-6 * dx, "the λ move the water ({largest} m)");
        assert!(worst <= 1e-4 * largest, "{worst} m of {largest} m");
    }

    /// The bodies' reactions summed per particle in the correction pass equal the pair-by-pair
    /// sums, with a ball on the floor so that some particles see two bodies.
    #[test]
    fn reactions_summed_per_particle_match_the_pair_by_pair_sums() {
        use crate::boundary::collider::{Collider, ColliderShape, Pose, Slip};
        let params = SphParams::water();
        let (h, dx) = (params.smoothing_radius, params.spacing());
        let ctx = PbfContext::of(&params);
        let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(0.3));
        let mut boundary = Boundary::new(&container, &params, Slip::Free).unwrap();
        let radius = 4.0 * dx;
        let centre = Vec3::new(0.15, radius + 0.5 * dx, 0.15);
        let pose = Pose {
            translation: centre,
            ..Default::default()
        };
        boundary
            .add(Collider::new(ColliderShape::Sphere { radius }, pose))
            .unwrap();
        boundary.sort();
        // A squeezed layer of water on the floor around the ball.
        let raw: Vec<Vec3> = (0..20 * 20 * 6)
            .map(|k| {
                let c = Vec3::new((k % 20) as f32, (k / 400) as f32, ((k / 20) % 20) as f32);
                Vec3::new(0.05, 0.0, 0.05) + (c + 0.5) * 0.9 * dx
            })
            .filter(|x| (*x - centre).length() > radius + 0.5 * dx)
            .collect();
        let n = raw.len();
        let mut neighbors = Neighbors::new(params.neighbor_search, &container, h, n).unwrap();
        let order = neighbors.sort(&raw).to_vec();
        let mut positions: Vec<Vec3> = order.iter().map(|&i| raw[i as usize]).collect();
        let mut lists = IndexLists::default();
        lists.rebuild_indices(&neighbors, &positions, Some(&boundary));
        let mut constraint = vec![Constraint::default(); n];
        compute_lambdas(&ctx, &lists, &positions, Some(&boundary), &mut constraint);
        let mut samples = SampleNeighbors::default();
        samples.rebuild(&lists, boundary.position.len());
        let mut wall_lambda = Vec::new();
        let (x, c) = (&positions, &constraint);
        extrapolate_wall_lambda(&ctx, &samples, x, &boundary, c, &mut wall_lambda);
        assert!(wall_lambda.iter().filter(|&&l| l < 0.0).count() > 100);
        let mut corrections = vec![Correction::default(); n];
        let b = Some((&boundary, &wall_lambda[..]));
        compute_corrections(&ctx, &lists, &positions, b, &constraint, &mut corrections);
        let shared = corrections
            .iter()
            .zip(&constraint)
            .filter(|(c, k)| c.body == SEVERAL_BODIES && k.lambda != 0.0)
            .count();
        assert!(shared > 10, "{shared} compressed particles see both bodies");
        // Pair by pair, at the positions before the move.
        let dt = 1.0 / 120.0;
        let scale = -ctx.mass / (dt * dt);
        let expected = lists.fold(
            || vec![BodyForceSum::default(); boundary.body_count()],
            |mut sums, i, pairs| {
                for &s in pairs.boundary {
                    let s = s as usize;
                    let r = positions[i] - boundary.position[s];
                    let f = ctx.kernel.value_and_gradient_factor(r.length_squared()).1;
                    let l = constraint[i].lambda + wall_lambda[s];
                    let moved = r * (f * boundary.volume[s] * l);
                    let body = boundary.body[s] as usize;
                    let (at, origin) = (boundary.position[s], boundary.origin[body]);
                    sums[body].add(moved * scale, at, origin);
                }
                sums
            },
            |mut a, b| {
                a.iter_mut().zip(&b).for_each(|(a, b)| a.merge(b));
                a
            },
        );
        let step = CorrectionStep {
            iteration: 0,
            iterations: 1,
            dt,
            boundary: &boundary,
            wall_lambda: &wall_lambda,
            constraint: &constraint,
            corrections: &corrections,
            contact_margin: None,
        };
        let mut moved = vec![Vec3::ZERO; n];
        let got = apply_corrections(&ctx, &lists, step, &mut positions, &mut moved);
        for (body, (e, g)) in expected.iter().zip(&got).enumerate() {
            let tolerance = 1e-4 * e.force.length().max(1e-3);
            assert!(e.force.length() > 1e-3, "body {body} is pushed");
            assert!(
                (e.force - g.force).length() < tolerance,
                "body {body}: {} against {}",
                g.force,
                e.force
            );
            assert!((e.torque - g.torque).length() < tolerance, "body {body}");
        }
        // And every particle moved by its correction (the first iteration: u = Δp).
        assert!(moved.iter().zip(&corrections).all(|(u, c)| *u == c.delta));
    }
}

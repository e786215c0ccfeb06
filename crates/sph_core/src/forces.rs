//! Forces pass: Monaghan's symmetric pressure force (Monaghan 1992, the symmetric form, p_i/ρ_i² + p_j/ρ_j²),
//! viscosity (design eq. 10, Müller 2003 eq. 14), gravity, Akinci 2013 surface tension when
//! γ > 0, and the boundary samples' pressure and friction (Akinci 2012, the
//! pressure mirrored onto the sample). Writes accelerations a_i and the fluid's reaction on every
//! boundary body.

use crate::boundary::samples::{BodyForceSum, Boundary};
use crate::boundary::speculative_contact::{speculative_contact_at, NextDrift, SURFACE_MARGIN};
use crate::neighbor::Neighbors;
use crate::stage::StageContext;
use crate::surface_tension_akinci2013::surface_tension_pair;
use glam::Vec3;
use rayon::prelude::*;

/// The particle fields the forces pass reads (sorted order).
#[derive(Clone, Copy)]
pub struct ForceInputs<'a> {
    /// Positions.
    pub position: &'a [Vec3],
    /// Velocities seen by the viscosity term (current or predicted, per integrator).
    pub velocity: &'a [Vec3],
    /// Velocities the boundary's contact stops (see [`boundary_acceleration_at`]): the ones the
    /// next drift starts from before this evaluation's acceleration, v½ in kick-drift-kick's
    /// closing evaluation; `velocity` otherwise.
    pub contact_velocity: &'a [Vec3],
    /// Densities from the density pass.
    pub density: &'a [f32],
    /// Pressures from the density pass.
    pub pressure: &'a [f32],
    /// Akinci normals (read only when surface tension is on).
    pub normal: &'a [Vec3],
    /// The boundary samples, if the walls or any collider are sampled.
    pub boundary: Option<&'a Boundary>,
    /// Include the pressure terms; false gives the non-pressure accelerations alone (viscosity,
    /// surface tension, gravity, boundary friction), what DFSPH's solves start from.
    pub with_pressure: bool,
}

/// The fluid's acceleration of particle i:
/// a_i = -Σ_j m (p_i/ρ̂_i² + p_j/ρ̂_j²) ∇W_spiky (Monaghan 1992, the symmetric form, with
///       ρ̂ = max(ρ, ρ0), [`pressure_density_squared`])
///       + (μ/ρ_i) Σ_j m (v_j - v_i) / ρ_j ∇²W_visc (Müller 2003 eq. 14) + Σ_j F_ij^st / m + g.
/// The pairwise forces m_i a_ij are antisymmetric, so internal forces conserve momentum.
#[inline]
pub fn acceleration_at(
    ctx: &StageContext,
    neighbors: &Neighbors,
    input: &ForceInputs,
    i: usize,
) -> Vec3 {
    let x_i = input.position[i];
    let v_i = input.velocity[i];
    let rho_i = input.density[i];
    let p_i = input.pressure[i] / pressure_density_squared(ctx, rho_i);
    let n_i = input.normal.get(i).copied().unwrap_or(Vec3::ZERO);
    let with_viscosity = ctx.viscosity > 0.0;
    let with_surface_tension = ctx.surface_tension > 0.0;
    let mut pressure = Vec3::ZERO;
    let mut viscosity = Vec3::ZERO;
    let mut surface_tension = Vec3::ZERO;
    neighbors.for_each_neighbor(input.position, x_i, |j, r, r2| {
        if j == i {
            return;
        }
        let r_len = r2.sqrt();
        let rho_j = input.density[j];
        if input.with_pressure {
            // Monaghan 1992, the symmetric form: a_i^p = -Σ m (p_i/ρ_i² + p_j/ρ_j²) ∇W_spiky(r_ij).
            pressure -= ctx.kernels.spiky_grad(r, r_len)
                * (p_i + input.pressure[j] / pressure_density_squared(ctx, rho_j));
        }
        if with_viscosity {
            // Design eq. 10: f_i^v = μ Σ m (v_j - v_i) / ρ_j ∇²W_visc(r_ij).
            viscosity +=
                (input.velocity[j] - v_i) * (ctx.kernels.viscosity_laplacian(r_len) / rho_j);
        }
        if with_surface_tension {
            surface_tension +=
                surface_tension_pair(ctx, r, r_len, rho_i, rho_j, n_i, input.normal[j]);
        }
    });
    pressure * (ctx.mass * ctx.pressure_gradient_scale)
        + viscosity * (ctx.viscosity * ctx.mass / rho_i)
        + surface_tension
        + ctx.gravity
}

/// max(ρ, ρ0)², the density the pressure terms divide by. A particle whose SPH density is
/// under ρ0 and that still carries pressure is a free-surface one given the pressure of the
/// water around it ([`crate::free_surface_pressure`]): its density is short only by the air's
/// share of its kernel, and with ρ² its pressure pushed like p (ρ0/ρ)², about 1.56 times too
/// hard in the tank's top row (docs/boundary.md). Everywhere else ρ ≥ ρ0 or p = 0 (the clamp),
/// and nothing changes; with the clamp off, a negative pressure at ρ < ρ0 pulls with p/ρ0².
#[inline]
pub fn pressure_density_squared(ctx: &StageContext, rho: f32) -> f32 {
    let rho = rho.max(ctx.rest_density);
    rho * rho
}

/// p̄_i = Σ_j V_j p_j W_ij / Σ_j V_j W_ij (V_j = m/ρ_j, i included): the Shepard average of the
/// fluid's pressure around particle i.
pub fn pressure_around(
    ctx: &StageContext,
    neighbors: &Neighbors,
    input: &ForceInputs,
    i: usize,
) -> f32 {
    let (mut weighted, mut weights) = (0.0, 0.0);
    neighbors.for_each_neighbor(input.position, input.position[i], |j, _, r2| {
        let w = ctx.kernels.poly6(r2) / input.density[j];
        weighted += w * input.pressure[j];
        weights += w;
    });
    if weights > 0.0 {
        weighted / weights
    } else {
        0.0
    }
}

/// The boundary's acceleration of particle i, with the pressure p_w mirrored onto each sample
/// (ρ_b = ρ0) and the pseudo-mass Ψ_b = ρ0 V_b (Akinci 2012, in Monaghan's
/// form). p_w = p_i, or where the clamp made p_i zero, `p_around()` ([`pressure_around`], called
/// only then and only if a sample is within h): next to a wall at a free surface p_i is zero while
/// the water beside it pushes it on, and the wall answers with the pressure of the water around
/// it (a pressure extrapolated onto the wall, after Adami et al. 2012, evaluated at the particle).
/// Each sample adds the hydrostatic rise between the particle and itself (Adami et al. 2012,
/// their (g - a_w) term for a wall at rest):
/// p_b = max(p_w + ρ0 g·(x_b - x_i), 0);
/// a_i^p = -Σ_b ρ0 V_b (p_w/ρ_i² + p_b/ρ0²) ∇W_spiky(x_i - x_b).
/// (Without the rise, the floor under a column at rest holds its first layer with half the push it
/// needs, `tests/boundary.rs`, and a box held under water felt 19.6 % more than ρ0 g V,
/// docs/boundary.md.) On no-slip bodies, the fluid's viscosity against the sample's velocity, times
/// the body's friction f (Akinci 2012 with Müller's Laplacian):
/// a_i^v = (f μ/ρ_i) Σ_b V_b (v_b - v_i) ∇²W_visc.
/// Samples closer than Δx add the contact ([`crate::stage::BoundaryContact`]): their pushes,
/// summed and scaled so that they stop i's approach within the step without reversing it, given
/// `a_fluid` (the fluid's acceleration of i, gravity included) and the terms above. The approach
/// is that of `input.contact_velocity`, the velocity the next drift starts from: in
/// kick-drift-kick's closing evaluation v½, which the closing kick and the next step's first
/// half-kick take to v½ + a dt before the particle moves. (Stopping the viscosity's prediction
/// v* = v½ + a_old dt/2 instead let a particle pushed off a wall last step come back unchecked:
/// a lone particle thrown at a wall at 16 m/s reached it, `tests/boundary.rs`, docs/boundary.md.)
/// With `input.with_pressure` false (DFSPH's non-pressure forces) only the friction acts: DFSPH's
/// boundary is its solves' (a stopping contact there left a sinking body on a trapped layer of
/// water, docs/boundary.md).
/// `reaction(body, force, at)` receives the force on the sample's body, -m a_ib (Akinci 2012's
/// two-way coupling).
#[inline]
pub fn boundary_acceleration_at(
    ctx: &StageContext,
    boundary: &Boundary,
    input: &ForceInputs,
    i: usize,
    a_fluid: Vec3,
    p_around: impl FnOnce() -> f32,
    mut reaction: impl FnMut(u32, Vec3, Vec3),
) -> Vec3 {
    let x_i = input.position[i];
    let v_i = input.velocity[i];
    let rho_i = input.density[i];
    let rho0 = ctx.rest_density;
    let mut p_around = Some(p_around);
    let mut wall_pressure = None;
    let viscous = ctx.viscosity / rho_i;
    let mut total = Vec3::ZERO;
    // The contact's pushes, and the samples' velocities weighted by their push.
    let (mut push_sum, mut push_velocity, mut push_weight) = (Vec3::ZERO, Vec3::ZERO, 0.0);
    boundary
        .grid
        .for_each_neighbor(&boundary.position, x_i, |b, r, r2| {
            let r_len = r2.sqrt();
            let volume = boundary.volume[b];
            let body = boundary.body[b];
            let friction = boundary.friction[body as usize];
            // The velocity is read only within the contact's range.
            if input.with_pressure && r_len < ctx.contact.radius {
                let v_b = boundary.velocity[b];
                let push = ctx.contact.push(ctx, r, r_len, volume);
                let weight = push.length();
                push_sum += push;
                push_velocity += v_b * weight;
                push_weight += weight;
            }
            if !input.with_pressure && friction == 0.0 {
                return;
            }
            let mut a = Vec3::ZERO;
            if input.with_pressure {
                // p_w and the particle's own term p_w/ρ_i², once per particle.
                let (p_w, own) = *wall_pressure.get_or_insert_with(|| {
                    let p_i = input.pressure[i];
                    let p_w = match p_around.take() {
                        Some(around) if p_i <= 0.0 => around(),
                        _ => p_i,
                    };
                    (p_w, p_w / pressure_density_squared(ctx, rho_i))
                });
                // r = x_i - x_b, so g·(x_b - x_i) = -g·r.
                let p_b = (p_w - rho0 * ctx.gravity.dot(r)).max(0.0);
                let mirrored = own + p_b / (rho0 * rho0);
                a = ctx.kernels.spiky_grad(r, r_len)
                    * (-rho0 * volume * mirrored * ctx.pressure_gradient_scale);
            }
            if friction > 0.0 {
                a += (boundary.velocity[b] - v_i)
                    * (friction * viscous * volume * ctx.kernels.viscosity_laplacian(r_len));
            }
            reaction(body, a * -ctx.mass, boundary.position[b]);
            total += a;
        });
    if push_weight > 0.0 {
        let v_rel = input.contact_velocity[i] - push_velocity / push_weight;
        let scale = ctx.contact.stopping_scale(push_sum, v_rel, a_fluid + total);
        if scale > 0.0 {
            // The particle takes s Σ push. Its reaction, -m s Σ push, goes to the samples that
            // push along n = Σ push/|Σ push|, in proportion to (push_b·n)₊: a sample pushing
            // against n (a sinking body's, over a particle it traps on the floor) does not lean
            // on the particle, or the trapped layer would hold the body up like a strut.
            let n = push_sum.normalize_or_zero();
            let along = contact_shares(ctx, boundary, x_i, n, |_, _| {});
            if along > 0.0 {
                let force = push_sum * (-ctx.mass * scale / along);
                contact_shares(ctx, boundary, x_i, n, |b, w| {
                    reaction(boundary.body[b], force * w, boundary.position[b])
                });
            }
            total += push_sum * scale;
        }
    }
    total
}

/// Σ_b (push_b·n)₊ over the samples within Δx of `x_i`, calling `each(b, (push_b·n)₊)` for the
/// samples where it is positive (the contact's reaction is shared along n in these proportions).
fn contact_shares(
    ctx: &StageContext,
    boundary: &Boundary,
    x_i: Vec3,
    n: Vec3,
    mut each: impl FnMut(usize, f32),
) -> f32 {
    let mut along = 0.0;
    boundary
        .grid
        .for_each_neighbor(&boundary.position, x_i, |b, r, r2| {
            let r_len = r2.sqrt();
            if r_len < ctx.contact.radius {
                let w = ctx
                    .contact
                    .push(ctx, r, r_len, boundary.volume[b])
                    .dot(n)
                    .max(0.0);
                if w > 0.0 {
                    along += w;
                    each(b, w);
                }
            }
        });
    along
}

/// Fills `acceleration` for every (sorted) particle; returns the fluid's force and torque on
/// every boundary body (indexed like [`Boundary::friction`]; empty without a boundary). With the
/// pressure terms (WCSPH), each particle's acceleration ends with the solids' speculative contact
/// ([`crate::boundary::speculative_contact`]), which keeps its next drift a tenth of a spacing from every
/// surface.
pub fn compute_accelerations(
    ctx: &StageContext,
    neighbors: &Neighbors,
    input: &ForceInputs,
    acceleration: &mut [Vec3],
) -> Vec<BodyForceSum> {
    let Some(boundary) = input.boundary else {
        acceleration
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, a)| *a = acceleration_at(ctx, neighbors, input, i));
        return Vec::new();
    };
    let bodies = boundary.body_count();
    acceleration
        .par_iter_mut()
        .enumerate()
        .fold(
            || vec![BodyForceSum::default(); bodies],
            |mut sums, (i, a)| {
                let around = || pressure_around(ctx, neighbors, input, i);
                let fluid = acceleration_at(ctx, neighbors, input, i);
                let mut react = |body: u32, f: Vec3, at: Vec3| {
                    sums[body as usize].add(f, at, boundary.origin[body as usize])
                };
                let wall =
                    boundary_acceleration_at(ctx, boundary, input, i, fluid, around, &mut react);
                *a = fluid + wall;
                if input.with_pressure {
                    let drift = NextDrift {
                        dt: ctx.contact.time_step,
                        kick: ctx.contact.drift_kick,
                        margin: SURFACE_MARGIN * ctx.contact.radius,
                    };
                    *a += speculative_contact_at(
                        boundary,
                        input.position[i],
                        input.contact_velocity[i],
                        *a,
                        drift,
                        ctx.mass,
                        react,
                    );
                }
                sums
            },
        )
        .reduce(
            || vec![BodyForceSum::default(); bodies],
            |mut a, b| {
                a.iter_mut().zip(&b).for_each(|(a, b)| a.merge(b));
                a
            },
        )
}

//! The pressure a free-surface particle carries (WCSPH): where the clamped equation of state
//! gives a particle no pressure, it takes the average of the equation of state's pressures
//! around it over the neighbours that have one,
//! p_i = Σ_j V_j p_j W_poly6(x_i − x_j) / Σ_{j: p_j > 0} V_j W_poly6(x_i − x_j), V_j = m/ρ_j,
//! at most [`StageContext::max_surface_pressure`] (ρ0 |g| Δx/2,
//! [`crate::stage::max_surface_pressure`]). The forces pass divides its pressure terms by
//! max(ρ, ρ0)² ([`crate::forces::pressure_density_squared`]), so such a particle pushes with the
//! pressure it was given.
//!
//! Why: a particle of the top row misses the neighbours above it, so its density reads low and
//! the clamped equation of state gives it no pressure, where the water at its depth (half a
//! spacing under the surface) holds ρ0 g Δx/2. The row under it then carries the top row's
//! weight alone and reads too high, and the row under that, anchored through the top row
//! (rows Δx apart interact only with the rows next to them at h = 2 Δx), too low. Measured on
//! `sph-bench validate`'s 8,000-particle tank against the weight of the water above
//! (docs/boundary.md), layers 0 (the top row), 1 and 2:
//! - the clamped pressure: layers 1 and 2 +17 % and −10 % (against ρ0 g depth);
//! - the SPH interpolant Σ_j V_j p_j W: the top row −40.6 %, layer 1 +8.2 %: the interpolant
//!   gives the top row about 0.6 of its due (the kernel is cut at the surface), and with ρ² in
//!   the pressure terms that pressure pushes about 1.56 times too hard
//!   (its SPH density is short by the same cut);
//! - this average with max(ρ, ρ0)²: the top row +0.9 %, layer 1 +5.7 %, layer 2 +1.8 %.
//!
//! Each half is needed: the Shepard average over every neighbour, Σ_j V_j p_j W / Σ_j V_j W,
//! without the density clamp reads layers 1 and 2 −3.5 % and −6.0 % against ρ0 g depth; this
//! average without the clamp, layer 1 −12.9 % by weight; the interpolant with the clamp, +10.5 %.
//! The bound is needed too: an unbounded
//! pressure hands a splash part of an impact's pressure: dambreak32k at its fixed dt of 1 ms
//! (three times the speed of sound's step, rolled back to 0.5 ms) had 12,973 guard corrections
//! with the unbounded interpolant, against 14. Bounded at ρ0 |g| Δx, 26 there and 1 in
//! `obstacles` (a jet's leading particle driven into the floor); at ρ0 |g| Δx/2, 15 and 0.
//! With this average, `obstacles` has 2 guard corrections (floor grazes) without the solids'
//! speculative contact ([`crate::boundary::speculative_contact`]), which stops such particles.

use crate::neighbor::Neighbors;
use crate::stage::StageContext;
use glam::Vec3;
use rayon::prelude::*;

/// The average of the pressures around `positions[i]` over the neighbours that have one:
/// Σ_j V_j p_j W_poly6 / Σ_{j: p_j > 0} V_j W_poly6 (V_j = m/ρ_j, within h; 0 where no
/// neighbour has pressure). A Shepard average that leaves out the air and the neighbours without
/// pressure, so a top-row particle over a full row takes the pressure of the water under it, not
/// a kernel-short share of it.
pub fn surrounding_pressure(
    ctx: &StageContext,
    neighbors: &Neighbors,
    positions: &[Vec3],
    density: &[f32],
    eos_pressure: &[f32],
    i: usize,
) -> f32 {
    let (mut weighted, mut weights) = (0.0, 0.0);
    neighbors.for_each_neighbor(positions, positions[i], |j, _, r2| {
        let p = eos_pressure[j];
        if p > 0.0 {
            let w = ctx.kernels.poly6(r2) / density[j];
            weighted += w * p;
            weights += w;
        }
    });
    if weights > 0.0 {
        weighted / weights
    } else {
        0.0
    }
}

/// Fills `pressure` for every (sorted) particle: its own equation-of-state pressure, or where
/// that is exactly 0 (the clamp's zero) the interpolant of the pressures around it
/// ([`surrounding_pressure`]), at most [`StageContext::max_surface_pressure`]. With the clamp
/// off (`SphParams::clamp_negative_pressure`), a negative pressure is the particle's own and is
/// kept.
pub fn extrapolate_free_surface_pressure(
    ctx: &StageContext,
    neighbors: &Neighbors,
    positions: &[Vec3],
    density: &[f32],
    eos_pressure: &[f32],
    pressure: &mut [f32],
) {
    pressure.par_iter_mut().enumerate().for_each(|(i, p)| {
        let own = eos_pressure[i];
        *p = if own != 0.0 {
            own
        } else {
            surrounding_pressure(ctx, neighbors, positions, density, eos_pressure, i)
                .min(ctx.max_surface_pressure)
        };
    });
}

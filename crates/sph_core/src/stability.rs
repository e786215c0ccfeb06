//! Adaptive time steps and instability detection, shared by the CPU solver and the GPU
//! `sph_time_step` pass (WGSL twin: `bevy_sph_fluid/src/render/stages/time_step.wgsl`).
//!
//! - The adaptive step is the smallest of the CFL (acoustic) limit λ h / (c0 + v_max)
//!   (Monaghan 1992; Becker & Teschner 2007 eq. 11), the viscous limit 0.125 h² / ν
//!   (Morris et al. 1997 eq. 20, ν = μ / ρ0), the force limit 0.25 √(h / a_max) (Monaghan 1992)
//!   and the user's `time_step`, which is the largest step allowed.
//! - A step is unstable when any speed or acceleration is not finite, or when the fastest particle
//!   crossed more than a support radius h in one step: the neighbour search then no longer sees
//!   the pairs it integrates, and weakly compressible SPH blows up from there.
//! - PBF is judged by finiteness alone ([`StepExtremes::is_unstable_for`]): its neighbour search
//!   runs on the predicted positions, so a particle that moved more than h still meets the
//!   pairs it is corrected against, and each correction is capped at a tenth of h, so a step
//!   cannot feed on itself. That is what lets it step at a frame's dt (1/30 s).

use crate::params::SphParams;
use crate::solvers::Solver;
use glam::Vec3;
use rayon::prelude::*;

/// The extremes of the particle state that the time-step rule and the stability check read.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepExtremes {
    /// Largest |v| [m/s]; infinite when any velocity is not finite.
    pub max_speed: f32,
    /// Largest |a| [m/s²]; infinite when any acceleration is not finite.
    pub max_acceleration: f32,
}

/// |x|, with every non-finite vector mapped to +∞ (so a NaN is never lost by `max`).
pub(crate) fn magnitude(x: Vec3) -> f32 {
    let length = x.length();
    if length.is_finite() {
        length
    } else {
        f32::INFINITY
    }
}

/// max_i |f(i)| over `0..n` in parallel, +∞ if any is not finite (0 for n = 0).
pub(crate) fn largest_magnitude(n: usize, f: impl Fn(usize) -> Vec3 + Sync) -> f32 {
    (0..n)
        .into_par_iter()
        .map(|i| magnitude(f(i)))
        .reduce(|| 0.0, f32::max)
}

impl StepExtremes {
    /// The extremes of velocities `v` and accelerations `a`.
    pub fn measure(v: &[Vec3], a: &[Vec3]) -> Self {
        let max = |x: &[Vec3]| x.par_iter().map(|&x| magnitude(x)).reduce(|| 0.0, f32::max);
        Self {
            max_speed: max(v),
            max_acceleration: max(a),
        }
    }

    /// Whether a step of `dt` that ended in this state went unstable (see the module docs).
    pub fn is_unstable(&self, dt: f32, smoothing_radius: f32) -> bool {
        !self.is_finite() || self.max_speed * dt > smoothing_radius
    }

    /// [`Self::is_unstable`] for WCSPH and DFSPH; finiteness alone for PBF (see the module
    /// docs).
    pub fn is_unstable_for(&self, solver: Solver, dt: f32, smoothing_radius: f32) -> bool {
        match solver {
            Solver::Pbf => !self.is_finite(),
            Solver::Wcsph | Solver::Dfsph => self.is_unstable(dt, smoothing_radius),
        }
    }

    /// Whether every speed and acceleration was finite.
    pub fn is_finite(&self) -> bool {
        self.max_speed.is_finite() && self.max_acceleration.is_finite()
    }
}

/// The viscous limit 0.125 h² ρ0 / μ [s], or +∞ without viscosity.
pub fn viscous_limit(params: &SphParams) -> f32 {
    if params.viscosity > 0.0 {
        0.125 * params.smoothing_radius * params.smoothing_radius * params.rest_density
            / params.viscosity
    } else {
        f32::INFINITY
    }
}

/// The time step of the next step: `params.time_step` when fixed; with
/// `params.adaptive_time_step`, min(time_step, λ h / (c0 + v_max), 0.125 h² / ν,
/// 0.25 √(h / a_max)).
pub fn adaptive_time_step(params: &SphParams, extremes: &StepExtremes) -> f32 {
    if !params.adaptive_time_step {
        return params.time_step;
    }
    let h = params.smoothing_radius;
    let cfl = params.cfl_factor * h / (params.speed_of_sound() + extremes.max_speed);
    let force = if extremes.max_acceleration > 0.0 {
        0.25 * (h / extremes.max_acceleration).sqrt()
    } else {
        f32::INFINITY
    };
    let dt = params
        .time_step
        .min(cfl)
        .min(viscous_limit(params))
        .min(force);
    // A non-finite state gives dt = 0; the stability check freezes such a state first.
    if dt.is_finite() {
        dt
    } else {
        params.time_step
    }
}

//! DFSPH's settings ([`DfsphSettings`], validated in [`crate::params`]) and its time-step rule's
//! largest step.

/// The fraction of a particle spacing gravity may move a particle in one DFSPH step from rest,
/// g dt² / Δx, that sets DFSPH's largest time step (see [`dfsph_max_time_step`]).
pub const DFSPH_GRAVITY_STEP_FRACTION: f32 = 0.005;

/// The largest time step of DFSPH's own rule [s] (the rule: dt = λ Δx / v_max, clamped to it):
/// √(0.005 Δx / |g|), the step in which gravity moves a particle from rest by half a percent of
/// its spacing. SPlisHSPlasH's dam break allows 5 ms at Δx = 5 cm, the same ratio; measured
/// here (docs/dfsph.md), a tank at Δx = 1 cm does not settle at 5 ms (0.17 % compression,
/// 0.2 m/s) and settles at this rule's 2.3 ms (0.01 %). Without gravity: 5 ms.
pub fn dfsph_max_time_step(spacing: f32, gravity: f32) -> f32 {
    if gravity > 0.0 && spacing > 0.0 {
        (DFSPH_GRAVITY_STEP_FRACTION * spacing / gravity)
            .sqrt()
            .clamp(1.0e-5, 0.01)
    } else {
        0.005
    }
}

/// Settings of [`Solver::Dfsph`](crate::Solver::Dfsph) (Bender & Koschier 2017, Algorithms 2 and 3).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub struct DfsphSettings {
    /// The constant-density solve stops once the mean predicted compression
    /// mean(max(ρ*_i/ρ0 - 1, 0)) is at most this (a fraction: 1e-4 is 0.01 %).
    pub max_density_error: f32,
    /// The divergence-free solve stops once the mean compression rate
    /// mean(max(Dρ_i/Dt, 0)) / ρ0 is at most this [1/s] (1e-3 is 0.1 % per second).
    pub max_divergence_error: f32,
    /// Iterations the constant-density solve always runs.
    pub min_density_iterations: u32,
    /// Iterations after which the constant-density solve stops even if not converged.
    pub max_density_iterations: u32,
    /// Iterations the divergence-free solve always runs.
    pub min_divergence_iterations: u32,
    /// Iterations after which the divergence-free solve stops even if not converged.
    pub max_divergence_iterations: u32,
    /// Start each solve from the previous step's stiffness (Bender & Koschier 2017, §4.3).
    pub warm_start: bool,
    /// Over-relaxation ω of the divergence-free solve's Jacobi iterations after its first: the
    /// stiffness applied is κ'_k = ω κ_k + (ω - 1) κ'_{k-1} (the stationary Chebyshev
    /// semi-iterative method, Wang 2015, as [`PbfSettings::over_relaxation`](crate::PbfSettings::over_relaxation)). 1 is plain
    /// Jacobi. Measured (docs/dfsph.md): at 1.4 dambreak32k's divergence iterations fall from
    /// 84 to 16 a step, and the tank at rest ends calmer. At 1.6 (with the constant-density
    /// solve at 1.3) the tank at rest does not settle (0.027 m/s) and a box held under water
    /// reads +29 % over ρ0 g V.
    pub divergence_over_relaxation: f32,
    /// Over-relaxation ω of the constant-density solve's Jacobi iterations after its first, as
    /// `divergence_over_relaxation`. 1 is plain Jacobi. Measured (docs/dfsph.md): at 1.3
    /// dambreak32k's constant-density iterations fall from 17 to 10 a step, the tank at rest
    /// keeps within 2.8 % and ends at 0.0022 m/s, and a box held under water reads its
    /// buoyancy within 0.01 %. (Before the mirrored boundary it kept the tank moving.)
    pub density_over_relaxation: f32,
}

impl Default for DfsphSettings {
    /// 0.01 % density error, 0.1 %/s divergence error, 2..=100 and 1..=100 iterations, warm
    /// starts on, the divergence-free solve over-relaxed by 1.4, the constant-density solve by
    /// 1.3.
    fn default() -> Self {
        Self {
            max_density_error: 1.0e-4,
            max_divergence_error: 1.0e-3,
            min_density_iterations: 2,
            max_density_iterations: 100,
            min_divergence_iterations: 1,
            max_divergence_iterations: 100,
            warm_start: true,
            divergence_over_relaxation: DEFAULT_DFSPH_OVER_RELAXATION,
            density_over_relaxation: DEFAULT_DFSPH_DENSITY_OVER_RELAXATION,
        }
    }
}

/// [`DfsphSettings::divergence_over_relaxation`]'s default.
pub const DEFAULT_DFSPH_OVER_RELAXATION: f32 = 1.4;

/// [`DfsphSettings::density_over_relaxation`]'s default.
pub const DEFAULT_DFSPH_DENSITY_OVER_RELAXATION: f32 = 1.3;

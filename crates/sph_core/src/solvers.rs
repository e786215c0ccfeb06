//! The pressure solvers a scene chooses between ([`Solver`]) and their settings (validated with
//! every other parameter in [`crate::params`]: the error names the field, the value and the
//! range).

/// How the fluid's pressure is found each step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub enum Solver {
    /// Weakly compressible SPH: pressure from the equation of state, explicit integration with
    /// the chosen integrator; dt bound by the speed of sound.
    #[default]
    Wcsph,
    /// Divergence-free SPH (Bender & Koschier 2015, 2017): two implicit solves per step, one
    /// for constant density, one for a divergence-free velocity; dt bound by the flow speed
    /// ([`DfsphSettings`]).
    Dfsph,
    /// Position-based fluids (Macklin & Müller 2013): a density constraint on predicted
    /// positions, solved by a few Jacobi iterations per step; dt bound by the support radius
    /// ([`PbfSettings`]).
    Pbf,
}

impl Solver {
    /// Every solver, in the order of the user interfaces.
    pub const ALL: [Solver; 3] = [Solver::Wcsph, Solver::Dfsph, Solver::Pbf];

    /// The short name used by the command line and the panels.
    pub fn name(self) -> &'static str {
        match self {
            Solver::Wcsph => "wcsph",
            Solver::Dfsph => "dfsph",
            Solver::Pbf => "pbf",
        }
    }
}

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

/// Settings of [`Solver::Dfsph`] (Bender & Koschier 2017, Algorithms 2 and 3).
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
    /// semi-iterative method, Wang 2015, as [`PbfSettings::over_relaxation`]). 1 is plain
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

/// Settings of [`Solver::Pbf`] (Macklin & Müller 2013).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub struct PbfSettings {
    /// Jacobi iterations of the density constraint per step.
    pub iterations: u32,
    /// The constraint's relaxation ε (constraint force mixing), as a fraction of the rest
    /// lattice's Σ |∇C|²: λ_i = -C_i / (Σ_k |∇_k C_i|² + ε).
    pub relaxation: f32,
    /// Artificial pressure s_corr = -k (W(r) / W(Δq))^n against tensile clumping: k.
    pub s_corr_k: f32,
    /// The exponent n of s_corr.
    pub s_corr_n: u32,
    /// Δq of s_corr as a fraction of h.
    pub s_corr_dq: f32,
    /// XSPH viscosity c: v_i += c Σ_j (m/ρ_j) (v_j - v_i) W_ij.
    pub xsph_c: f32,
    /// Vorticity confinement ε [m/s]: a_i = ε (N_i × ω_i) puts back the swirl that damping
    /// loses (Macklin & Müller 2013 §5 after Fedkiw et al. 2001). 0 (the default) skips the
    /// stage: it costs nothing.
    pub vorticity_epsilon: f32,
    /// Over-relaxation ω of the Jacobi iterations after the first:
    /// x_{k+1} = x_{k-1} + ω (x_k + Δp_k - x_{k-1}), the stationary form of the Chebyshev
    /// semi-iterative method (Wang 2015, "A Chebyshev semi-iterative approach for accelerating
    /// projective and position-based dynamics"; its ω_k tend to 2 / (1 + √(1 - ρ²)) for a
    /// spectral radius ρ). 1 is plain Jacobi. Measured on dambreak32k (docs/pbf.md): 1.4 cuts the
    /// mean compression from 1.05 % to 0.45 % at the same cost; from 1.5 the iterations put
    /// speed into the water.
    pub over_relaxation: f32,
}

impl Default for PbfSettings {
    /// 4 iterations, relaxation 0.01, s_corr k 0.1, n 4, Δq 0.2 h (the paper's), XSPH c 0.01,
    /// no vorticity confinement, over-relaxation 1.4.
    fn default() -> Self {
        Self {
            iterations: 4,
            relaxation: 0.01,
            s_corr_k: 0.1,
            s_corr_n: 4,
            s_corr_dq: 0.2,
            xsph_c: 0.01,
            vorticity_epsilon: 0.0,
            over_relaxation: DEFAULT_PBF_OVER_RELAXATION,
        }
    }
}

/// [`DfsphSettings::divergence_over_relaxation`]'s default.
pub const DEFAULT_DFSPH_OVER_RELAXATION: f32 = 1.4;

/// [`DfsphSettings::density_over_relaxation`]'s default.
pub const DEFAULT_DFSPH_DENSITY_OVER_RELAXATION: f32 = 1.3;

/// [`PbfSettings::over_relaxation`]'s default.
pub const DEFAULT_PBF_OVER_RELAXATION: f32 = 1.4;

/// The largest time step of PBF's own rule [s]: two steps per 60 Hz frame.
pub const PBF_MAX_TIME_STEP: f32 = 1.0 / 120.0;

/// The step factor λ of PBF's own rule (dt = λ h / v_max, a particle moves at most λ h = 2 λ Δx
/// in a step), set by [`crate::SphParams::use_solver`]. Measured on dambreak32k at the default
/// 4 iterations (docs/pbf.md): λ = 0.5 ran 1.23 times faster than 0.4 at a mean compression
/// over the run of 0.73 % against 0.50 % (peak 1.63 % both); 0.6 peaked at 13.8 %.
pub const PBF_CFL_FACTOR: f32 = 0.5;

/// What the pressure solves of the last step did (zero for WCSPH).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolverStats {
    /// Iterations of the constant-density solve.
    pub density_iterations: u32,
    /// Iterations of the divergence-free solve.
    pub divergence_iterations: u32,
    /// The constant-density solve's last mean predicted compression (fraction of ρ0).
    pub density_error: f32,
    /// The divergence-free solve's last mean compression rate [1/s].
    pub divergence_error: f32,
}

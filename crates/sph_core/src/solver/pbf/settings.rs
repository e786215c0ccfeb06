//! PBF's settings ([`PbfSettings`], validated in [`crate::params`]) and its time-step rule.

/// Settings of [`Solver::Pbf`](crate::Solver::Pbf) (Macklin & Müller 2013).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub struct PbfSettings {
    /// Jacobi iterations of the density constraint per step. The default, 6, is the fewest at
    /// which a 20-layer tank at rest comes to rest (mean speed ≤ 0.01 m/s) with the default
    /// [`Self::jacobi_weight`] (docs/pbf.md).
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
    /// The weight w of each Jacobi iteration's λ: λ_i = -w C_i / (Σ_k |∇_k C_i|² + ε), the
    /// weighted Jacobi method. Plain Jacobi (w = 1) does not damp the constraint's
    /// highest-frequency error, neighbours pushing against each other in turn: each particle
    /// solves its own constraint as if its neighbours stood still, while they move too, so the
    /// alternating mode is over-corrected and only the correction cap bounds it (plain Jacobi
    /// keeps a 20-layer tank at rest moving at 0.26 m/s mean). w = 2/3 is the textbook smoother
    /// weight of weighted Jacobi (Saad, "Iterative methods for sparse linear systems", §13.2.2;
    /// Briggs et al., "A multigrid tutorial", ch. 2), which damps every mode in the upper half of
    /// the spectrum by at least 1/3 per iteration (docs/pbf.md has the tank's figures).
    pub jacobi_weight: f32,
}

impl Default for PbfSettings {
    /// [`DEFAULT_PBF_ITERATIONS`] iterations, relaxation 0.01, s_corr k 0.1, n 4, Δq 0.2 h (the
    /// paper's), XSPH c 0.01, no vorticity confinement, over-relaxation 1.4, Jacobi weight 2/3.
    fn default() -> Self {
        Self {
            iterations: DEFAULT_PBF_ITERATIONS,
            relaxation: 0.01,
            s_corr_k: 0.1,
            s_corr_n: 4,
            s_corr_dq: 0.2,
            xsph_c: 0.01,
            vorticity_epsilon: 0.0,
            over_relaxation: DEFAULT_PBF_OVER_RELAXATION,
            jacobi_weight: DEFAULT_PBF_JACOBI_WEIGHT,
        }
    }
}

/// [`PbfSettings::iterations`]' default.
pub const DEFAULT_PBF_ITERATIONS: u32 = 6;

/// [`PbfSettings::jacobi_weight`]'s default: 2/3, weighted Jacobi's smoother weight.
pub const DEFAULT_PBF_JACOBI_WEIGHT: f32 = 2.0 / 3.0;

/// [`PbfSettings::over_relaxation`]'s default.
pub const DEFAULT_PBF_OVER_RELAXATION: f32 = 1.4;

/// The largest time step of PBF's own rule [s]: two steps per 60 Hz frame.
pub const PBF_MAX_TIME_STEP: f32 = 1.0 / 120.0;

/// The step factor λ of PBF's own rule (dt = λ h / v_max, a particle moves at most λ h = 2 λ Δx
/// in a step), set by [`crate::SphParams::use_solver`]. Measured on dambreak32k at the default
/// 4 iterations (docs/pbf.md): λ = 0.5 ran 1.23 times faster than 0.4 at a mean compression
/// over the run of 0.73 % against 0.50 % (peak 1.63 % both); 0.6 peaked at 13.8 %.
pub const PBF_CFL_FACTOR: f32 = 0.5;

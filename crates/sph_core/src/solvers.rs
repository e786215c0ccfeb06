//! The pressure solvers a scene chooses between ([`Solver`]) and what a step's solves did
//! ([`SolverStats`]). Each solver's settings are in its folder (`solver::dfsph::settings`,
//! `solver::pbf::settings`), validated with every other parameter in [`crate::params`] (the
//! error names the field, the value and the range); they are re-exported here.

pub use crate::solver::dfsph::settings::{
    dfsph_max_time_step, DfsphSettings, DEFAULT_DFSPH_DENSITY_OVER_RELAXATION,
    DEFAULT_DFSPH_OVER_RELAXATION, DFSPH_GRAVITY_STEP_FRACTION,
};
pub use crate::solver::pbf::settings::{
    PbfSettings, DEFAULT_PBF_OVER_RELAXATION, PBF_CFL_FACTOR, PBF_MAX_TIME_STEP,
};

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

//! PBF's own CPU stages, the twins of its GPU passes (the shared ones are
//! [`crate::stage::CpuStage`]'s own variants). A leaf module, so that `stage.rs` can list it.

/// A stage only PBF's step runs (Macklin & Müller 2013, Algorithm 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PbfStage {
    /// The constraint's λ_i at the predicted positions
    /// ([`crate::solver::pbf::macklin2013::compute_lambdas`]).
    Lambda,
    /// The particles within reach of each boundary sample over the step
    /// ([`crate::solver::pbf::wall_lambda::SampleNeighbors::rebuild`]).
    WallLists,
    /// The boundary samples' λ_b, the water's λ around each
    /// ([`crate::solver::pbf::wall_lambda::extrapolate_wall_lambda`]).
    WallLambda,
    /// The position corrections Δp_i and the bodies' reactions
    /// ([`crate::solver::pbf::macklin2013::compute_corrections`],
    /// [`crate::solver::pbf::macklin2013::apply_corrections`]).
    Correction,
    /// Velocities from the positions, the guard (step 4 of `CpuSolver`'s PBF step).
    Velocity,
    /// XSPH viscosity and the final densities
    /// ([`crate::solver::pbf::xsph_vorticity::xsph_and_densities`]), then the pumps.
    Xsph,
    /// The vorticity ω_i ([`crate::solver::pbf::xsph_vorticity::vorticity`]).
    Vorticity,
    /// Vorticity confinement ([`crate::solver::pbf::xsph_vorticity::confine_vorticity`]).
    Confinement,
}

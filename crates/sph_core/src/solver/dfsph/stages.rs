//! DFSPH's own CPU stages, the twins of its GPU passes (the shared ones are
//! [`crate::stage::CpuStage`]'s own variants). A leaf module, so that `stage.rs` can list it.

/// A stage only DFSPH's step runs (Bender & Koschier 2017, Algorithm 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DfsphStage {
    /// The cubic-spline densities and the factors 1/D_i
    /// ([`crate::neighbor::lists::NeighborLists::rebuild`]'s densities,
    /// [`crate::solver::dfsph::bender2017::compute_factors`]).
    Factors,
    /// The predicted velocities v* = v + dt a_np (step 3 of `CpuSolver`'s DFSPH step).
    Predict,
    /// v += dt a_p of the iteration's stiffness
    /// ([`crate::solver::dfsph::bender2017::apply_stiffness`]).
    Apply,
    /// The solve's source and the next stiffness
    /// ([`crate::solver::dfsph::bender2017::density_source`],
    /// [`crate::solver::dfsph::bender2017::divergence_source`],
    /// [`crate::solver::dfsph::bender2017::stiffness_from_source`]).
    Source,
    /// The bodies' reactions of a solve
    /// ([`crate::solver::dfsph::bender2017::boundary_reactions`]); after the divergence-free
    /// solve, the pressures and the pumps.
    Reactions,
}

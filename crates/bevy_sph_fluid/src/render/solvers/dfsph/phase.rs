//! Where a DFSPH step is ([`DfsphPhase`], [`DfsphSolve`]) and which error sum each pass
//! reads. A leaf module: `render::plan` holds the phase in its plans, the DFSPH stages read it.

/// One of DFSPH's two pressure solves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DfsphSolve {
    /// The constant-density solve on v* (before the move).
    Density,
    /// The divergence-free solve on v (after the move).
    Divergence,
}

/// Where a DFSPH step is (Bender & Koschier 2017, Algorithm 1; the CPU's `solver/dfsph/mod.rs`):
/// one pass over the stage list per phase, each running only its stages. A solve's Jacobi
/// iterations are two passes each, the stiffness applied to the velocities and the next
/// source; their indirect dispatches shrink to nothing once the device finds the solve
/// converged, so the CPU encodes the most iterations and never waits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DfsphPhase {
    /// Not DFSPH.
    #[default]
    None,
    /// Sort, lists, densities and factors at the current positions (the first step, or after
    /// spawns and parameter changes).
    Neighborhood,
    /// The non-pressure forces, the time step, v* = v + dt a_np, and the constant-density
    /// solve's first source (its warm start's, when `warm`).
    Predict {
        /// The solves warm-start.
        warm: bool,
    },
    /// The warm start's stiffness applied, then the solve's first source.
    WarmApply(DfsphSolve),
    /// Jacobi iteration k (from 0): the stiffness applied, then the next source.
    Iterate(DfsphSolve, u32),
    /// The constant-density solve's reactions and statistics.
    DensityEnd,
    /// x += v dt, the guard; sort, lists, densities and factors at the new positions; the
    /// divergence-free solve's first source (its warm start's, when `warm`).
    Move {
        /// The solves warm-start.
        warm: bool,
    },
    /// The divergence-free solve's reactions and statistics, the pressures, the pumps.
    Finish,
}

/// Where DFSPH's sources write their error sum and the applying pass reads it: source j of a
/// solve (0 the first) writes accumulator j % 2; iteration k reads accumulator k % 2.
pub fn dfsph_parity(j: u32) -> usize {
    (j % 2) as usize
}

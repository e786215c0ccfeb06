//! Where a PBF step is ([`PbfPhase`]) and which positions each Jacobi iteration reads. A leaf
//! module: `render::plan` holds the phase in its plans, the PBF stages read it.

/// Where a PBF step is: one pass over the stage list per phase, each running only its stages.
/// The Jacobi iterations ping-pong the positions between two scratch buffers, so that every
/// iteration reads the positions of the one before while the sorted positions stay for the
/// neighbour search.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PbfPhase {
    /// Not PBF.
    #[default]
    None,
    /// Time step, prediction, neighbour sort of the predicted positions.
    Predict,
    /// Jacobi iteration k (from 0): λ, then the corrections.
    Iterate(u32),
    /// After `iterations` iterations: velocities, XSPH, vorticity confinement; the last of
    /// them copies the final positions over the sorted ones.
    Finish {
        /// The step's iterations (which scratch buffer holds the final positions).
        iterations: u32,
        /// Vorticity confinement runs (its pass is the last).
        vorticity: bool,
    },
}

/// Where PBF's positions are read in iteration `k` (0: the sorted predicted positions,
/// 1: scratch A, 2: scratch B), and so the role of the λ and correction passes. Iteration k
/// writes the next iteration's source: 0 writes A, odd iterations write B, even ones A.
pub fn pbf_source(k: u32) -> usize {
    match k {
        0 => 0,
        k if k % 2 == 1 => 1,
        _ => 2,
    }
}

/// The roles of the passes that read PBF's positions, by [`pbf_source`]: the sorted positions,
/// scratch A, scratch B.
pub const PBF_SOURCE_ROLES: &[&[&str]] = &[&[], &["PBF_FROM_A"], &["PBF_FROM_B"]];

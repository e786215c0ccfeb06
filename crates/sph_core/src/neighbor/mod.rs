//! Neighbour search, laid out as the GPU passes: build a sort order (count/prefix-sum/scatter for
//! the dense grid, key sort for the spatial hash), reorder the particle arrays by it, then visit
//! the particles of the 27 cells around each particle with an exact distance check.

pub mod grid;
mod group_avx2;
pub mod hash;
pub mod lists;
pub mod pair_lanes;

pub use grid::DenseGrid;
pub use hash::SpatialHash;

use crate::container::BoxContainer;
use crate::params::{NeighborSearch, ParamError};
use glam::Vec3;

/// The neighbour-search structure of a solver: one of the two modes.
#[derive(Clone, Debug)]
pub enum Neighbors {
    /// Dense grid + counting sort (default).
    Grid(DenseGrid),
    /// The design's spatial hash + sort by hash.
    Hash(SpatialHash),
}

impl Neighbors {
    /// A structure of the given mode for `capacity` particles in `container` with cell size `h`.
    pub fn new(
        mode: NeighborSearch,
        container: &BoxContainer,
        h: f32,
        capacity: usize,
    ) -> Result<Self, ParamError> {
        Ok(match mode {
            NeighborSearch::Grid => Self::Grid(DenseGrid::new(container, h)?),
            NeighborSearch::Hash => Self::Hash(SpatialHash::new(h, capacity)),
        })
    }

    /// The mode of this structure.
    pub fn mode(&self) -> NeighborSearch {
        match self {
            Self::Grid(_) => NeighborSearch::Grid,
            Self::Hash(_) => NeighborSearch::Hash,
        }
    }

    /// Sorts the particles: returns `order`, where sorted slot `k` takes particle `order[k]`.
    /// After the particle arrays are gathered by `order`, [`Self::for_each_neighbor`] works on them.
    pub fn sort(&mut self, positions: &[Vec3]) -> &[u32] {
        match self {
            Self::Grid(g) => g.sort(positions),
            Self::Hash(s) => s.sort(positions),
        }
    }

    /// Calls `f(j, x_i - x_j, |x_i - x_j|²)` for every particle j (including i itself) closer than h
    /// to `x_i`, on the sorted `positions`.
    #[inline]
    pub fn for_each_neighbor(
        &self,
        positions: &[Vec3],
        x_i: Vec3,
        f: impl FnMut(usize, Vec3, f32),
    ) {
        match self {
            Self::Grid(g) => g.for_each_neighbor(positions, x_i, f),
            Self::Hash(s) => s.for_each_neighbor(positions, x_i, f),
        }
    }

    /// Σ_j w(r²) over every neighbour j (i included) for a weight `w` that is zero for r >= h.
    #[inline]
    pub fn sum_over_neighbors(&self, positions: &[Vec3], x_i: Vec3, w: impl Fn(f32) -> f32) -> f32 {
        match self {
            Self::Grid(g) => g.sum_over_candidates(positions, x_i, w),
            Self::Hash(s) => {
                let mut sum = 0.0;
                s.for_each_neighbor(positions, x_i, |_, _, r2| sum += w(r2));
                sum
            }
        }
    }

    /// How many candidate particles (before the distance check) particle `x_i` visits.
    pub fn candidate_count(&self, x_i: Vec3) -> usize {
        match self {
            Self::Grid(g) => g.candidate_count(x_i),
            Self::Hash(s) => s.candidate_count(x_i),
        }
    }
}

//! Sizes the GPU passes and their buffers share: the workgroup, the neighbour lists' tiles.

/// Workgroup size of every per-particle pass.
pub const WORKGROUP_SIZE: u32 = 64;

/// The most neighbours a particle keeps in the GPU's PBF neighbour lists (pairs within h at the
/// predicted positions). A particle has about 33 at rest density (h = 2 Δx); one with more than
/// this many (about twice the rest density) loses the rest for the step, and the clock counts them
/// ([`GpuClock::neighbor_list_overflows`](crate::gpu_layout::GpuClock::neighbor_list_overflows)).
pub const PBF_MAX_NEIGHBORS: u32 = 64;

/// The most fluid particles a boundary sample keeps in the GPU's PBF wall lists (particles
/// within h at the predicted positions; `sph_core::solver::pbf::wall_lambda`). A sample on a
/// flat wall has about half a particle's 33, one inside a wall a spacing thick up to about all
/// of them from both sides; past this many the sample loses the rest for the step and the clock
/// counts it with the particles' overflows. The CPU's lists have no limit.
pub const PBF_MAX_WALL_NEIGHBORS: u32 = 62;

/// u32 words of a boundary sample in the GPU's PBF wall lists: λ_b's bits, the particle count,
/// then [`PBF_MAX_WALL_NEIGHBORS`] particle indices.
pub const PBF_WALL_LIST_WORDS: u32 = PBF_MAX_WALL_NEIGHBORS + 2;

/// The GPU's neighbour lists (PBF's and DFSPH's) keep entry k of particle i in tiles of this
/// many particles, row by row: at `((i / LIST_TILE) * PBF_MAX_NEIGHBORS + k) * LIST_TILE +
/// i % LIST_TILE` (`list_slot` in the plugin's `shaders/neighbors.wgsl`), so that a pass over the
/// lists streams through memory on a SIMD machine such as lavapipe.
pub const LIST_TILE: u32 = 8;

/// Entries of a GPU neighbour list for `capacity` particles: whole tiles of [`LIST_TILE`]
/// particles, [`PBF_MAX_NEIGHBORS`] entries each.
pub fn list_entries(capacity: u32) -> u64 {
    capacity.next_multiple_of(LIST_TILE) as u64 * PBF_MAX_NEIGHBORS as u64
}

/// Threads of the single-workgroup prefix sum.
pub const PREFIX_SUM_THREADS: u32 = 256;

//! The storage buffers the passes bind: the logical buffers ([`Buf`]) packed into ten arenas,
//! so that no pass binds more than 8 storage buffers (WebGPU's default
//! `maxStorageBuffersPerShaderStage`). Each logical buffer is a region of its arena; WGSL reads
//! region `b` at `params.buffer_at` (its first element) through `sph::bindings`'s `*_at`
//! functions, and the pumps, probes, clock and body forces are the members of one structure
//! (`SphShared`).

use super::buf::Buf;
use sph_core::gpu_layout::{GpuCollider, GpuShared, BUFFER_AT_ROWS};

/// A storage buffer of group 0, holding one or more logical buffers. `binding()` is its WGSL
/// binding in `shaders/bindings.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Arena {
    /// `array<vec4<f32>>`, capacity each: position, velocity, predicted velocity,
    /// acceleration, start-of-step acceleration, normal.
    ParticleState = 1,
    /// `array<f32>`, capacity each: density, pressure, the equation of state's pressure.
    ParticleScalars,
    /// `array<vec4<f32>>`: the scatter's five sorted copies, the rollback checkpoint, DFSPH's
    /// mirrored factor shares.
    ParticleScratch,
    /// `array<u32>`: the grid's and the hash's arrays, the neighbour counts and lists, the
    /// boundary samples' cell offsets.
    Grid,
    /// `array<atomic<u32>>`: the grid's per-cell counts.
    CellCounts,
    /// `SphShared`: the pumps, the probes, the clock and the body forces.
    Shared,
    /// `array<vec4<f32>>`, sized by the upload: the boundary samples' positions and velocities,
    /// the mesh colliders' words.
    Boundary,
    /// `array<u32>`: each boundary sample's body.
    BoundaryBody,
    /// `array<GpuCollider>`: the colliders, for the guard.
    Colliders,
    /// `array<vec4<u32>>`: DFSPH's pairs.
    DfsphPairs,
}

impl Arena {
    /// Every arena, in binding order.
    pub const ALL: [Arena; 10] = [
        Arena::ParticleState,
        Arena::ParticleScalars,
        Arena::ParticleScratch,
        Arena::Grid,
        Arena::CellCounts,
        Arena::Shared,
        Arena::Boundary,
        Arena::BoundaryBody,
        Arena::Colliders,
        Arena::DfsphPairs,
    ];

    /// The WGSL binding in group 0 (the uniform block is binding 0).
    pub fn binding(self) -> u32 {
        self as u32
    }

    /// The buffer's label.
    pub fn label(self) -> &'static str {
        match self {
            Arena::ParticleState => "sph_particle_state",
            Arena::ParticleScalars => "sph_particle_scalars",
            Arena::ParticleScratch => "sph_particle_scratch",
            Arena::Grid => "sph_grid",
            Arena::CellCounts => "sph_cell_counts",
            Arena::Shared => "sph_shared",
            Arena::Boundary => "sph_boundary",
            Arena::BoundaryBody => "sph_boundary_body",
            Arena::Colliders => "sph_colliders",
            Arena::DfsphPairs => "sph_dfsph_pairs",
        }
    }

    /// The WGSL array's stride [bytes]: the unit of `params.buffer_at` (the shared structure's
    /// members are found by name, not by offset).
    pub fn element_bytes(self) -> u64 {
        match self {
            Arena::ParticleState | Arena::ParticleScratch | Arena::Boundary | Arena::DfsphPairs => {
                16
            }
            Arena::Colliders => std::mem::size_of::<GpuCollider>() as u64,
            Arena::ParticleScalars
            | Arena::Grid
            | Arena::CellCounts
            | Arena::Shared
            | Arena::BoundaryBody => 4,
        }
    }
}

impl Buf {
    /// The arena that holds this buffer.
    pub fn arena(self) -> Arena {
        match self {
            Buf::Position
            | Buf::Velocity
            | Buf::VelocityPredicted
            | Buf::Acceleration
            | Buf::AccelerationStart
            | Buf::Normal => Arena::ParticleState,
            Buf::Density | Buf::Pressure | Buf::PressureEos => Arena::ParticleScalars,
            Buf::SortedPosition
            | Buf::SortedVelocity
            | Buf::SortedVelocityPredicted
            | Buf::SortedAcceleration
            | Buf::SortedAccelerationStart
            | Buf::Checkpoint
            | Buf::DfsphMirror
            | Buf::DiffuseState
            | Buf::WhitewaterFluid => Arena::ParticleScratch,
            Buf::CellOf
            | Buf::RankInCell
            | Buf::CellStart
            | Buf::SortKeys
            | Buf::SortValues
            | Buf::BucketStart
            | Buf::BucketEnd
            | Buf::NeighborCount
            | Buf::NeighborLists
            | Buf::BoundaryCellStart
            | Buf::DiffuseFree
            | Buf::DiffuseOrder
            | Buf::BodyWords => Arena::Grid,
            Buf::CellCounts | Buf::DiffuseCounts | Buf::DiffuseBins | Buf::BodyContacts => {
                Arena::CellCounts
            }
            Buf::Clock | Buf::BodyForces | Buf::Pumps | Buf::Probes => Arena::Shared,
            Buf::BoundaryPosition | Buf::BoundaryVelocity | Buf::Meshes | Buf::BoundaryRest => {
                Arena::Boundary
            }
            Buf::BoundaryBody | Buf::BoundaryLambda => Arena::BoundaryBody,
            Buf::Colliders => Arena::Colliders,
            Buf::DfsphPairs => Arena::DfsphPairs,
        }
    }
}

/// Regions start on 256-byte boundaries (WebGPU's `minStorageBufferOffsetAlignment`), so any of
/// them could also be bound on its own.
const REGION_ALIGNMENT: u64 = 256;

/// Where every logical buffer lies in its arena, and each arena's size.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ArenaLayout {
    /// Each logical buffer's (offset, size) in its arena [bytes], at index `Buf as usize`.
    regions: [(u64, u64); Buf::ALL.len() + 1],
    /// Each arena's size [bytes], at index `Arena as usize`.
    arena_bytes: [u64; Arena::ALL.len() + 1],
}

impl ArenaLayout {
    /// The layout of logical buffers of `bytes(buf)` bytes each, packed in [`Buf::ALL`]'s order.
    /// The shared structure's members sit where `GpuShared` puts them.
    pub fn new(bytes: impl Fn(Buf) -> u64) -> Self {
        let mut layout = Self {
            regions: [(0, 0); Buf::ALL.len() + 1],
            arena_bytes: [0; Arena::ALL.len() + 1],
        };
        for buf in Buf::ALL {
            let arena = buf.arena();
            let region = match buf {
                Buf::Pumps => (GpuShared::PUMPS_OFFSET, size_of_member(buf)),
                Buf::Probes => (GpuShared::PROBES_OFFSET, size_of_member(buf)),
                Buf::Clock => (GpuShared::CLOCK_OFFSET, size_of_member(buf)),
                Buf::BodyForces => (GpuShared::BODY_FORCES_OFFSET, size_of_member(buf)),
                _ => {
                    let size = bytes(buf).next_multiple_of(arena.element_bytes());
                    let end = &mut layout.arena_bytes[arena as usize];
                    let offset = end.next_multiple_of(REGION_ALIGNMENT);
                    *end = offset + size;
                    (offset, size)
                }
            };
            layout.regions[buf as usize] = region;
        }
        layout.arena_bytes[Arena::Shared as usize] = GpuShared::BYTES;
        for end in &mut layout.arena_bytes {
            // A binding needs at least one element of the largest stride.
            *end = (*end).max(REGION_ALIGNMENT);
        }
        layout
    }

    /// The layout of buffers whose sizes are `sizes[buf as usize]` [bytes].
    pub fn of_sizes(sizes: &[u64]) -> Self {
        Self::new(|buf| sizes[buf as usize])
    }

    /// `buf`'s offset and size in its arena [bytes].
    pub fn region(&self, buf: Buf) -> (u64, u64) {
        self.regions[buf as usize]
    }

    /// `arena`'s size [bytes].
    pub fn arena_bytes(&self, arena: Arena) -> u64 {
        self.arena_bytes[arena as usize]
    }

    /// Every logical buffer's first element in its arena, for `GpuSphParams::buffer_at`.
    pub fn buffer_at(&self) -> [[u32; 4]; BUFFER_AT_ROWS] {
        let mut at = [[0u32; 4]; BUFFER_AT_ROWS];
        for buf in Buf::ALL {
            let element = self.regions[buf as usize].0 / buf.arena().element_bytes();
            at[buf as usize / 4][buf as usize % 4] = element as u32;
        }
        at
    }
}

/// The size of a member of the shared structure [bytes].
fn size_of_member(buf: Buf) -> u64 {
    use sph_core::gpu_layout::{GpuBodyForces, GpuClock, GpuProbes, GpuPumps};
    (match buf {
        Buf::Pumps => std::mem::size_of::<GpuPumps>(),
        Buf::Probes => std::mem::size_of::<GpuProbes>(),
        Buf::Clock => std::mem::size_of::<GpuClock>(),
        _ => std::mem::size_of::<GpuBodyForces>(),
    }) as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regions_of_one_arena_never_overlap_and_fit_it() {
        let layout = ArenaLayout::new(|buf| 100 + 16 * buf as u64);
        for arena in Arena::ALL {
            let mut regions: Vec<(u64, u64)> = Buf::ALL
                .iter()
                .filter(|b| b.arena() == arena)
                .map(|&b| layout.region(b))
                .collect();
            regions.sort();
            for pair in regions.windows(2) {
                assert!(pair[0].0 + pair[0].1 <= pair[1].0, "{arena:?}: {pair:?}");
            }
            let last = regions.last().expect("every arena holds a buffer");
            assert!(last.0 + last.1 <= layout.arena_bytes(arena), "{arena:?}");
        }
    }

    #[test]
    fn every_region_starts_on_an_element_of_its_arena_and_on_the_alignment() {
        let layout = ArenaLayout::new(|buf| 4 * buf as u64 + 4);
        for buf in Buf::ALL {
            let (offset, _) = layout.region(buf);
            assert_eq!(offset % buf.arena().element_bytes(), 0, "{buf:?}");
            if buf.arena() != Arena::Shared {
                assert_eq!(offset % REGION_ALIGNMENT, 0, "{buf:?}");
            }
            let at = layout.buffer_at()[buf as usize / 4][buf as usize % 4];
            assert_eq!(at as u64 * buf.arena().element_bytes(), offset, "{buf:?}");
        }
    }

    #[test]
    fn each_wgsl_region_reads_its_buffers_index() {
        // sph::bindings's `<name>_at` reads `params.buffer_at[row].<lane>` at the Buf's index.
        let wgsl = include_str!("shaders/bindings.wgsl");
        let mut found = 0;
        for line in wgsl.lines().filter(|l| l.starts_with("fn ")) {
            let name = line[3..line.find("_at(").expect("a region function")].to_string();
            let buf = Buf::ALL
                .into_iter()
                .find(|b| snake_case(&format!("{b:?}")) == name)
                .unwrap_or_else(|| panic!("{name} is no Buf"));
            let lane = ["x", "y", "z", "w"][buf as usize % 4];
            let expected = format!("params.buffer_at[{}].{lane} + i", buf as usize / 4);
            assert!(line.contains(&expected), "{line}: expected {expected}");
            found += 1;
        }
        // Every buffer that shares an arena of arrays has its function.
        let shares = |buf: &Buf| Buf::ALL.iter().filter(|b| b.arena() == buf.arena()).count() > 1;
        let regions = Buf::ALL
            .iter()
            .filter(|b| b.arena() != Arena::Shared && shares(b))
            .count();
        assert_eq!(found, regions);
    }

    fn snake_case(name: &str) -> String {
        let mut out = String::new();
        for (k, c) in name.chars().enumerate() {
            if c.is_uppercase() && k > 0 {
                out.push('_');
            }
            out.push(c.to_ascii_lowercase());
        }
        out
    }

    #[test]
    fn the_indices_fit_the_uniform_rows() {
        assert!(Buf::ALL.len() < 4 * BUFFER_AT_ROWS);
    }
}

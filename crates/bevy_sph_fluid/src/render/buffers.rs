//! GPU buffers: structure-of-arrays particle state sized by capacity, the sorted copies, the
//! grid and hash arrays, the rollback checkpoint, the uniform block, and their allocation (each
//! frame's writes are in `prepare`). Every logical storage buffer is a [`Buf`], a region of one
//! of the arenas of group 0 (`arenas`, `shaders/bindings.wgsl`); each stage binds the arenas of
//! the buffers it declares. The main world reads and draws its own copies of the state
//! ([`GpuBuffers::publish`]).

use super::arenas::{Arena, ArenaLayout};
pub use super::buf::Buf;
use super::plan::VariantKey;
use bevy::prelude::*;
use bevy::render::render_resource::{
    BindGroup, Buffer, BufferDescriptor, BufferUsages, CommandEncoder,
};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use sph_core::gpu_layout::{bitonic_steps, list_entries, sort_length, GpuCollider, GpuSphParams};
use sph_core::neighbor::hash::hash_table_size;
use sph_core::NeighborSearch;
use sph_core::Solver;

/// Byte stride of the bitonic steps in their uniform buffer (the dynamic-offset alignment).
pub const BITONIC_STRIDE: u64 = 256;

/// The buffers the main world reads back and draws ([`crate::api::SphGpuBuffers`]), in this
/// order, and the logical buffer each copies.
pub const READABLE: [Buf; 9] = [
    Buf::Position,
    Buf::Velocity,
    Buf::Acceleration,
    Buf::Density,
    Buf::Pressure,
    Buf::NeighborCount,
    Buf::Clock,
    Buf::BodyForces,
    Buf::Probes,
];

/// Every buffer of group 0.
#[derive(Clone, Debug)]
pub struct GpuBuffers {
    /// Particle slots.
    pub capacity: u32,
    /// Whitewater's diffuse particle slots (0 without whitewater).
    pub diffuse_capacity: u32,
    /// Grid cells per axis.
    pub grid_dims: UVec3,
    /// The variant the buffers were sized for.
    pub key: VariantKey,
    /// Bytes allocated on the GPU (all buffers).
    pub bytes: u64,
    /// Bitonic sort length.
    pub sort_length: u32,
    /// The uniform block.
    pub uniform: Buffer,
    /// The arenas, in [`Arena::ALL`] order.
    pub arenas: Vec<Buffer>,
    /// Where each logical buffer lies in its arena.
    pub layout: ArenaLayout,
    /// The size each logical buffer was given [bytes] (the boundary's grow with its samples).
    pub sizes: Vec<u64>,
    /// The main world's copies, in [`READABLE`] order.
    pub readable: [Buffer; 9],
    /// The bitonic steps (hash mode).
    pub bitonic_steps: Buffer,
    /// Number of bitonic steps.
    pub bitonic_step_count: u32,
    /// DFSPH: the indirect dispatch arguments of the solve's passes, copied from the clock
    /// ([`super::stage::copy_solve_arguments`]).
    pub dfsph_arguments: Buffer,
}

impl GpuBuffers {
    /// The arena `arena`.
    pub fn arena(&self, arena: Arena) -> &Buffer {
        &self.arenas[arena as usize - 1]
    }

    /// The arena that holds `buf`, and where `buf` starts in it [bytes].
    pub fn at(&self, buf: Buf) -> (&Buffer, u64) {
        (self.arena(buf.arena()), self.layout.region(buf).0)
    }

    /// `buf`'s size [bytes].
    pub fn size(&self, buf: Buf) -> u64 {
        self.layout.region(buf).1
    }

    /// Writes `bytes` into `buf` at `offset` [bytes].
    pub fn write(&self, queue: &RenderQueue, buf: Buf, offset: u64, bytes: &[u8]) {
        debug_assert!(
            offset + bytes.len() as u64 <= self.size(buf),
            "{buf:?} overrun"
        );
        let (arena, start) = self.at(buf);
        queue.write_buffer(arena, start + offset, bytes);
    }

    /// Copies the first `bytes` of `from` to `to`.
    pub fn copy(&self, encoder: &mut CommandEncoder, from: Buf, to: Buf, bytes: u64) {
        // WebGPU copies between two buffers only, within their regions here.
        debug_assert!(
            from.arena() != to.arena(),
            "{from:?} and {to:?} share an arena"
        );
        debug_assert!(
            bytes <= self.size(from).min(self.size(to)),
            "{from:?} overrun"
        );
        let ((source, at), (target, to_at)) = (self.at(from), self.at(to));
        encoder.copy_buffer_to_buffer(source, at, target, to_at, Some(bytes));
    }

    /// Zeroes `buf`.
    pub fn clear(&self, encoder: &mut CommandEncoder, buf: Buf) {
        let (arena, start) = self.at(buf);
        encoder.clear_buffer(arena, start, Some(self.size(buf)));
    }

    /// The bytes of `buf` the main world reads: the live particles' elements, or the whole
    /// structure.
    fn readable_bytes(&self, buf: Buf, particle_count: u32) -> u64 {
        let per_particle = match buf.arena() {
            Arena::ParticleState => 16,
            Arena::ParticleScalars | Arena::Grid => 4,
            _ => return self.size(buf),
        };
        (per_particle * particle_count as u64).min(self.size(buf))
    }

    /// Copies the state to the main world's buffers (after the frame's steps, so snapshots, the
    /// surface and the every-frame readbacks see it).
    pub fn publish(&self, encoder: &mut CommandEncoder, particle_count: u32) {
        for (buf, target) in READABLE.iter().zip(&self.readable) {
            let bytes = self.readable_bytes(*buf, particle_count).min(target.size());
            if bytes > 0 {
                let (arena, at) = self.at(*buf);
                encoder.copy_buffer_to_buffer(arena, at, target, 0, Some(bytes));
            }
        }
    }

    /// Copies the main world's buffers back into new arenas, so a reallocation (a new grid or
    /// variant) keeps the particles, the clock and the frame's sums.
    pub fn restore(&self, encoder: &mut CommandEncoder) {
        for (buf, source) in READABLE.iter().zip(&self.readable) {
            let bytes = self.size(*buf).min(source.size());
            let (arena, at) = self.at(*buf);
            encoder.copy_buffer_to_buffer(source, 0, arena, at, Some(bytes));
        }
    }

    /// Makes room for each `(buf, bytes)` (the boundary's buffers): the buffers that outgrow
    /// their regions get their new sizes, the others of their arenas move, and each arena that
    /// no longer holds them is reallocated once, its contents lost (the boundary's upload
    /// writes them all). Returns whether any region changed.
    pub fn grow(&mut self, device: &RenderDevice, needs: &[(Buf, u64)]) -> bool {
        let mut grown = Vec::new();
        for &(buf, bytes) in needs {
            if self.sizes[buf as usize] < bytes {
                // Room for growth, so a collider added at run time rarely reallocates; 16 bytes
                // keep vec4 arrays whole.
                self.sizes[buf as usize] = (bytes + bytes / 4).next_multiple_of(16);
                grown.push(buf.arena());
            }
        }
        if grown.is_empty() {
            return false;
        }
        self.layout = ArenaLayout::of_sizes(&self.sizes);
        grown.sort();
        grown.dedup();
        for arena in grown {
            let old = self.arena(arena).size();
            let new = self.layout.arena_bytes(arena);
            if new > old {
                self.arenas[arena as usize - 1] = storage_buffer(device, arena.label(), new);
                self.bytes += new - old;
            }
        }
        true
    }
}

/// Render-world simulation state.
#[derive(Resource, Default)]
pub struct SphGpuState {
    /// Buffers (once allocated).
    pub buffers: Option<GpuBuffers>,
    /// Live particles.
    pub particle_count: u32,
    /// The kick-drift-kick acceleration is stale (spawn, reset or parameter change).
    pub forces_stale: bool,
    /// Parameters of the last frame.
    pub last_params: Option<sph_core::SphParams>,
    /// Each stage's group 0 (by stage name), built from the buffers it declares.
    pub bind_groups: bevy::platform::collections::HashMap<&'static str, BindGroup>,
    /// Group 1 of the bitonic sort with each step's offset.
    pub bitonic_bind_group: Option<(BindGroup, Vec<u32>)>,
    /// Bumped when buffers are reallocated.
    pub generation: u64,
    /// The generation the bind groups were made for.
    pub bind_group_generation: u64,
    /// Why the buffers are not ready.
    pub status: Option<String>,
    /// Spawns that arrived before the buffers were ready.
    pub(super) pending_spawns: Vec<PendingSpawn>,
    /// The boundary generation last uploaded (0: none).
    pub(super) boundary_generation: u64,
    /// The membership of the boundary last uploaded (`Boundary::membership`).
    pub(super) boundary_membership: u64,
    /// Boundary samples on the GPU.
    pub boundary_samples: u32,
    /// Colliders in the guard's list on the GPU.
    pub boundary_colliders: u32,
    /// Whether some boundary sample on the GPU has friction (`GpuSphParams::boundary_friction`).
    pub boundary_friction: bool,
    /// Whether the boundary samples on the GPU do not mirror DFSPH's stiffness (a dynamic
    /// collider is among them; `GpuSphParams::unmirrored_samples`).
    pub boundary_unmirrored: bool,
    /// The whitewater pool's generation the buffers hold (`None`: not emptied yet).
    pub whitewater_generation: Option<u64>,
    /// The main world's buffers whitewater publishes to.
    pub whitewater_targets: Option<WhitewaterTargets>,
    /// The main world's copy of the moved bodies' states, while there are any.
    pub body_target: Option<Buffer>,
}

/// The main world's copies whitewater's buffers are published to: the slots for drawing, the
/// counters, the fluid's potentials.
#[derive(Clone, Debug)]
pub struct WhitewaterTargets {
    /// `capacity` vec4: (position, class or -1).
    pub draw: Buffer,
    /// `GpuDiffuseCounts`.
    pub counts: Buffer,
    /// Per fluid particle: (trapped air, wave crest, kinetic energy, rate).
    pub potentials: Buffer,
}

/// New particles waiting for upload: first slot, positions (w = id), velocities.
pub(super) type PendingSpawn = (u32, Vec<[f32; 4]>, Vec<[f32; 4]>);

/// A storage buffer of `bytes` (at least 16) that copies may read and write.
pub(super) fn storage_buffer(device: &RenderDevice, label: &'static str, bytes: u64) -> Buffer {
    device.create_buffer(&BufferDescriptor {
        label: Some(label),
        size: bytes.max(16),
        usage: BufferUsages::STORAGE | BufferUsages::COPY_DST | BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// Each logical buffer's size [bytes], at index `Buf as usize`: the normals, the hash arrays and
/// whitewater's `diffuse_capacity` diffuse particles only when the variant needs them (a 16-byte
/// placeholder keeps their region valid otherwise).
pub fn buffer_sizes(
    capacity: u32,
    grid_dims: UVec3,
    key: VariantKey,
    diffuse_capacity: u32,
) -> Vec<u64> {
    let n = capacity as u64;
    let diffuse = if key.whitewater {
        diffuse_capacity as u64
    } else {
        0
    };
    let cells = (grid_dims.x * grid_dims.y * grid_dims.z) as u64;
    let hash = key.search == NeighborSearch::Hash;
    let sort_len = if hash { sort_length(capacity) } else { 0 };
    let table = if hash {
        hash_table_size(capacity as usize) as u64
    } else {
        0
    };
    // The Akinci normals, or PBF's λ and densities.
    let normals = if key.surface_tension || key.solver == Solver::Pbf {
        16 * n
    } else {
        0
    };
    let size = |buf: Buf| -> u64 {
        match buf {
            Buf::Normal => normals,
            Buf::CellOf | Buf::RankInCell | Buf::Pressure | Buf::Density | Buf::NeighborCount => {
                4 * n
            }
            Buf::CellCounts => 4 * cells,
            Buf::CellStart => 4 * (cells + 1),
            Buf::SortKeys | Buf::SortValues => 4 * sort_len as u64,
            Buf::BucketStart | Buf::BucketEnd => 4 * table,
            Buf::Checkpoint => 3 * 16 * n,
            // Sized by the samples when they are uploaded (`upload_boundary`); an empty boundary
            // has no samples in any cell.
            Buf::BoundaryPosition
            | Buf::BoundaryVelocity
            | Buf::BoundaryBody
            | Buf::Meshes
            | Buf::BoundaryRest
            | Buf::BoundaryLambda => 16,
            Buf::BodyWords if key.bodies => sph_core::gpu_layout::GPU_BODY_BYTES as u64,
            Buf::BodyWords => 16,
            Buf::BodyContacts if key.bodies => {
                4 * sph_core::gpu_layout::GPU_BODY_CONTACT_WORDS as u64
                    * sph_core::gpu_layout::GPU_MOVED_BODIES as u64
            }
            Buf::BodyContacts => 16,
            Buf::Colliders => std::mem::size_of::<GpuCollider>() as u64,
            Buf::BoundaryCellStart => 4 * (cells + 1),
            Buf::NeighborLists if key.solver == Solver::Pbf || key.solver == Solver::Dfsph => {
                4 * list_entries(capacity)
            }
            Buf::NeighborLists => 16,
            // Two 8-byte pairs to a 16-byte entry (sph_core::gpu_dfsph_pairs).
            Buf::DfsphPairs if key.solver == Solver::Dfsph => 8 * list_entries(capacity),
            Buf::DfsphPairs => 16,
            Buf::PressureEos if key.solver != Solver::Pbf && key.solver != Solver::Dfsph => 4 * n,
            Buf::PressureEos => 16,
            Buf::DfsphMirror if key.solver == Solver::Dfsph => 16 * n,
            Buf::DfsphMirror => 16,
            Buf::DiffuseState => 2 * 16 * diffuse,
            Buf::WhitewaterFluid if key.whitewater => 2 * 16 * n,
            Buf::WhitewaterFluid => 16,
            Buf::DiffuseFree => 4 * diffuse,
            Buf::DiffuseCounts if key.whitewater => {
                std::mem::size_of::<sph_core::gpu_layout::GpuDiffuseCounts>() as u64
            }
            Buf::DiffuseCounts => 16,
            Buf::DiffuseBins if key.whitewater => 4 * (cells + 1),
            Buf::DiffuseBins => 16,
            Buf::DiffuseOrder => 3 * 4 * diffuse,
            // The shared structure's members have their own sizes.
            Buf::Clock | Buf::BodyForces | Buf::Pumps | Buf::Probes => 0,
            _ => 16 * n,
        }
    };
    let mut sizes = vec![0u64; Buf::ALL.len() + 1];
    for buf in Buf::ALL {
        sizes[buf as usize] = size(buf);
    }
    sizes
}

/// Allocates every buffer.
pub(super) fn allocate(
    device: &RenderDevice,
    capacity: u32,
    grid_dims: UVec3,
    key: VariantKey,
    diffuse_capacity: u32,
    readable: [Buffer; 9],
) -> GpuBuffers {
    let sizes = buffer_sizes(capacity, grid_dims, key, diffuse_capacity);
    let hash = key.search == NeighborSearch::Hash;
    let sort_len = if hash { sort_length(capacity) } else { 0 };
    let layout = ArenaLayout::of_sizes(&sizes);
    let arenas: Vec<Buffer> = Arena::ALL
        .iter()
        .map(|&arena| storage_buffer(device, arena.label(), layout.arena_bytes(arena)))
        .collect();
    let steps = if hash {
        bitonic_steps(sort_len)
    } else {
        Vec::new()
    };
    let mut bytes = vec![0u8; (steps.len().max(1) as u64 * BITONIC_STRIDE) as usize];
    for (k, step) in steps.iter().enumerate() {
        let at = k * BITONIC_STRIDE as usize;
        bytes[at..at + 16].copy_from_slice(bytemuck::bytes_of(step));
    }
    let bitonic =
        device.create_buffer_with_data(&bevy::render::render_resource::BufferInitDescriptor {
            label: Some("sph_bitonic_steps"),
            contents: &bytes,
            usage: BufferUsages::UNIFORM,
        });
    // The main world's copies count too: they are device buffers.
    let bytes = arenas
        .iter()
        .chain(&readable)
        .map(|b| b.size())
        .sum::<u64>()
        + (std::mem::size_of::<GpuSphParams>() as u64)
        + steps.len() as u64 * BITONIC_STRIDE;
    GpuBuffers {
        capacity,
        diffuse_capacity: if key.whitewater { diffuse_capacity } else { 0 },
        grid_dims,
        key,
        bytes,
        sort_length: sort_len,
        uniform: device.create_buffer(&BufferDescriptor {
            label: Some("sph_uniforms"),
            size: std::mem::size_of::<GpuSphParams>() as u64,
            usage: BufferUsages::UNIFORM | BufferUsages::COPY_DST,
            mapped_at_creation: false,
        }),
        arenas,
        layout,
        sizes,
        readable,
        bitonic_steps: bitonic,
        bitonic_step_count: steps.len() as u32,
        dfsph_arguments: device.create_buffer(&BufferDescriptor {
            label: Some("sph_dfsph_arguments"),
            size: 16,
            usage: BufferUsages::INDIRECT | BufferUsages::COPY_DST,
            mapped_at_creation: false,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sph_core::SphParams;

    /// Without whitewater its six buffers are 16-byte placeholders; with it, the pool's and the
    /// fluid's regions grow with their capacities.
    #[test]
    fn whitewater_buffers_exist_only_with_whitewater() {
        let whitewater = [
            Buf::DiffuseState,
            Buf::WhitewaterFluid,
            Buf::DiffuseFree,
            Buf::DiffuseCounts,
            Buf::DiffuseBins,
            Buf::DiffuseOrder,
        ];
        let off = VariantKey::of(&SphParams::water(), false);
        let on = VariantKey {
            whitewater: true,
            ..off
        };
        let dims = UVec3::splat(8);
        let sizes = buffer_sizes(1_000, dims, off, 65_536);
        for buf in whitewater {
            assert!(
                sizes[buf as usize] <= 16,
                "{buf:?}: {}",
                sizes[buf as usize]
            );
        }
        let sizes = buffer_sizes(1_000, dims, on, 4_096);
        assert_eq!(sizes[Buf::DiffuseState as usize], 2 * 16 * 4_096);
        assert_eq!(sizes[Buf::WhitewaterFluid as usize], 2 * 16 * 1_000);
        assert_eq!(sizes[Buf::DiffuseFree as usize], 4 * 4_096);
        assert_eq!(sizes[Buf::DiffuseCounts as usize], 32);
        assert_eq!(sizes[Buf::DiffuseBins as usize], 4 * (8 * 8 * 8 + 1));
        assert_eq!(sizes[Buf::DiffuseOrder as usize], 3 * 4 * 4_096);
        // The rest is the same either way.
        let (a, b) = (
            buffer_sizes(1_000, dims, off, 0),
            buffer_sizes(1_000, dims, on, 4_096),
        );
        for buf in Buf::ALL.into_iter().filter(|b| !whitewater.contains(b)) {
            assert_eq!(a[buf as usize], b[buf as usize], "{buf:?}");
        }
    }
}

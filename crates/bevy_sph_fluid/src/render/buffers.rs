//! GPU buffers: structure-of-arrays particle state sized by capacity, the sorted copies, the
//! grid and hash arrays, the rollback checkpoint, the uniform block, and their allocation (each
//! frame's writes are in `prepare`). Every storage buffer is a [`Buf`] with a fixed binding in group 0
//! (`shaders/bindings.wgsl`); each stage binds the ones it declares.

use super::plan::VariantKey;
use bevy::prelude::*;
use bevy::render::render_resource::{BindGroup, Buffer, BufferDescriptor, BufferUsages};
use bevy::render::renderer::RenderDevice;
use sph_core::gpu_layout::{bitonic_steps, list_entries, sort_length, GpuCollider, GpuSphParams};
use sph_core::neighbor::hash::hash_table_size;
use sph_core::NeighborSearch;
use sph_core::Solver;

/// Byte stride of the bitonic steps in their uniform buffer (the dynamic-offset alignment).
pub const BITONIC_STRIDE: u64 = 256;

/// The storage buffers of group 0; `binding()` is the WGSL binding in `shaders/bindings.wgsl`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Buf {
    /// Positions (w = id) [m].
    Position = 1,
    /// Velocities [m/s].
    Velocity,
    /// Predicted velocities (what viscosity sees).
    VelocityPredicted,
    /// Accelerations [m/s²].
    Acceleration,
    /// Start-of-step accelerations (the design's leapfrog).
    AccelerationStart,
    /// Densities [kg/m³].
    Density,
    /// Pressures [Pa].
    Pressure,
    /// Akinci normals (surface tension only).
    Normal,
    /// The scatter's sorted copies, in state order.
    SortedPosition,
    /// Sorted velocities.
    SortedVelocity,
    /// Sorted predicted velocities.
    SortedVelocityPredicted,
    /// Sorted accelerations.
    SortedAcceleration,
    /// Sorted start-of-step accelerations.
    SortedAccelerationStart,
    /// Grid: each particle's cell.
    CellOf,
    /// Grid: each particle's rank in its cell.
    RankInCell,
    /// Grid: per-cell counts.
    CellCounts,
    /// Grid: exclusive offsets.
    CellStart,
    /// Hash: sort keys.
    SortKeys,
    /// Hash: sort values (particle indices).
    SortValues,
    /// Hash: per-bucket start + 1.
    BucketStart,
    /// Hash: per-bucket end.
    BucketEnd,
    /// Debug: neighbours within h.
    NeighborCount,
    /// The clock (`GpuClock`).
    Clock,
    /// The rollback checkpoint: position, velocity, acceleration of every slot.
    Checkpoint,
    /// Boundary samples' positions (w = volume V_b), sorted by cell; sized by samples.
    BoundaryPosition,
    /// Boundary samples' velocities (w = friction factor).
    BoundaryVelocity,
    /// Boundary samples' exclusive cell offsets over the dense grid.
    BoundaryCellStart,
    /// The colliders (`GpuCollider`), for the guard.
    Colliders,
    /// Each boundary sample's body (0 the walls, k + 1 collider slot k).
    BoundaryBody,
    /// The fluid's force on each body over the frame (`GpuBodyForces`), read back.
    BodyForces,
    /// The frame's pumps (`GpuPumps`).
    Pumps,
    /// The frame's probes and their sums (`GpuProbes`), read back.
    Probes,
    /// The mesh colliders' hierarchies and triangles, for the guard.
    Meshes,
    /// PBF: each particle's neighbours of the step (pairs within h at the predicted positions),
    /// at most `PBF_MAX_NEIGHBORS`, neighbour k of particle i at `list_slot(i, k)`
    /// (`sph_core::gpu_layout::LIST_TILE`).
    NeighborLists,
    /// DFSPH: the same pairs with their weighted gradient, (m ∇W_ij, j as bits), written with
    /// the factors after each sort and read by every iteration of the solves.
    DfsphPairs,
    /// WCSPH: the equation of state's pressures, from which the free-surface pass writes
    /// [`Buf::Pressure`].
    PressureEos,
    /// DFSPH: the boundary's mirrored share of each particle's factor, (Σ_b g_ib over the
    /// samples that mirror κ_i, 1 when they do), written with the factors after each sort.
    DfsphMirror,
}

impl Buf {
    /// Every storage buffer, in binding order.
    pub const ALL: [Buf; 37] = [
        Buf::Position,
        Buf::Velocity,
        Buf::VelocityPredicted,
        Buf::Acceleration,
        Buf::AccelerationStart,
        Buf::Density,
        Buf::Pressure,
        Buf::Normal,
        Buf::SortedPosition,
        Buf::SortedVelocity,
        Buf::SortedVelocityPredicted,
        Buf::SortedAcceleration,
        Buf::SortedAccelerationStart,
        Buf::CellOf,
        Buf::RankInCell,
        Buf::CellCounts,
        Buf::CellStart,
        Buf::SortKeys,
        Buf::SortValues,
        Buf::BucketStart,
        Buf::BucketEnd,
        Buf::NeighborCount,
        Buf::Clock,
        Buf::Checkpoint,
        Buf::BoundaryPosition,
        Buf::BoundaryVelocity,
        Buf::BoundaryCellStart,
        Buf::Colliders,
        Buf::BoundaryBody,
        Buf::BodyForces,
        Buf::Pumps,
        Buf::Probes,
        Buf::Meshes,
        Buf::NeighborLists,
        Buf::DfsphPairs,
        Buf::PressureEos,
        Buf::DfsphMirror,
    ];

    /// The WGSL binding in group 0 (the uniform block is binding 0).
    pub fn binding(self) -> u32 {
        self as u32
    }

    /// The buffer's label.
    pub fn label(self) -> &'static str {
        match self {
            Buf::Position => "sph_position",
            Buf::Velocity => "sph_velocity",
            Buf::VelocityPredicted => "sph_velocity_predicted",
            Buf::Acceleration => "sph_acceleration",
            Buf::AccelerationStart => "sph_acceleration_start",
            Buf::Density => "sph_density",
            Buf::Pressure => "sph_pressure",
            Buf::Normal => "sph_normal",
            Buf::SortedPosition => "sph_sorted_position",
            Buf::SortedVelocity => "sph_sorted_velocity",
            Buf::SortedVelocityPredicted => "sph_sorted_velocity_predicted",
            Buf::SortedAcceleration => "sph_sorted_acceleration",
            Buf::SortedAccelerationStart => "sph_sorted_acceleration_start",
            Buf::CellOf => "sph_cell_of",
            Buf::RankInCell => "sph_rank_in_cell",
            Buf::CellCounts => "sph_cell_counts",
            Buf::CellStart => "sph_cell_start",
            Buf::SortKeys => "sph_sort_keys",
            Buf::SortValues => "sph_sort_values",
            Buf::BucketStart => "sph_bucket_start",
            Buf::BucketEnd => "sph_bucket_end",
            Buf::NeighborCount => "sph_neighbor_count",
            Buf::Clock => "sph_clock",
            Buf::Checkpoint => "sph_checkpoint",
            Buf::BoundaryPosition => "sph_boundary_position",
            Buf::BoundaryVelocity => "sph_boundary_velocity",
            Buf::BoundaryCellStart => "sph_boundary_cell_start",
            Buf::Colliders => "sph_colliders",
            Buf::BoundaryBody => "sph_boundary_body",
            Buf::BodyForces => "sph_body_forces",
            Buf::Pumps => "sph_pumps",
            Buf::Probes => "sph_probes",
            Buf::Meshes => "sph_meshes",
            Buf::NeighborLists => "sph_neighbor_lists",
            Buf::DfsphPairs => "sph_dfsph_pairs",
            Buf::PressureEos => "sph_pressure_eos",
            Buf::DfsphMirror => "sph_dfsph_mirror",
        }
    }
}

/// Every buffer of group 0.
#[derive(Clone, Debug)]
pub struct GpuBuffers {
    /// Particle slots.
    pub capacity: u32,
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
    /// The storage buffers, in [`Buf::ALL`] order.
    pub storage: Vec<Buffer>,
    /// The bitonic steps (hash mode).
    pub bitonic_steps: Buffer,
    /// Number of bitonic steps.
    pub bitonic_step_count: u32,
    /// DFSPH: the indirect dispatch arguments of the solve's passes, copied from the clock
    /// ([`super::stage::copy_solve_arguments`]).
    pub dfsph_arguments: Buffer,
}

impl GpuBuffers {
    /// The storage buffer `buf`.
    pub fn at(&self, buf: Buf) -> &Buffer {
        &self.storage[buf as usize - 1]
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

/// Allocates every buffer; the normals and the hash arrays only when the variant needs them (a
/// 16-byte placeholder keeps their binding valid otherwise).
pub(super) fn allocate(
    device: &RenderDevice,
    capacity: u32,
    grid_dims: UVec3,
    key: VariantKey,
    readable: [Buffer; 9],
) -> GpuBuffers {
    let n = capacity as u64;
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
    let [position, velocity, acceleration, density, pressure, neighbor_count, clock, body_forces, probes] =
        readable;
    let size = |buf: Buf| -> u64 {
        match buf {
            Buf::Normal => normals,
            Buf::CellOf | Buf::RankInCell | Buf::Pressure => 4 * n,
            Buf::CellCounts => 4 * cells,
            Buf::CellStart => 4 * (cells + 1),
            Buf::SortKeys | Buf::SortValues => 4 * sort_len as u64,
            Buf::BucketStart | Buf::BucketEnd => 4 * table,
            Buf::Checkpoint => 3 * 16 * n,
            // Sized by the samples when they are uploaded (`upload_boundary`); an empty boundary
            // has no samples in any cell.
            Buf::BoundaryPosition | Buf::BoundaryVelocity | Buf::BoundaryBody | Buf::Meshes => 16,
            Buf::Colliders => std::mem::size_of::<GpuCollider>() as u64,
            Buf::BoundaryCellStart => 4 * (cells + 1),
            Buf::Pumps => std::mem::size_of::<sph_core::gpu_layout::GpuPumps>() as u64,
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
            _ => 16 * n,
        }
    };
    let storage: Vec<Buffer> = Buf::ALL
        .iter()
        .map(|&buf| match buf {
            Buf::Position => position.clone(),
            Buf::Velocity => velocity.clone(),
            Buf::Acceleration => acceleration.clone(),
            Buf::Density => density.clone(),
            Buf::Pressure => pressure.clone(),
            Buf::NeighborCount => neighbor_count.clone(),
            Buf::Clock => clock.clone(),
            Buf::BodyForces => body_forces.clone(),
            Buf::Probes => probes.clone(),
            _ => storage_buffer(device, buf.label(), size(buf)),
        })
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
    let bytes = storage.iter().map(|b| b.size()).sum::<u64>()
        + (std::mem::size_of::<GpuSphParams>() as u64)
        + steps.len() as u64 * BITONIC_STRIDE;
    GpuBuffers {
        capacity,
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
        storage,
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

//! GPU buffers: structure-of-arrays particle state sized by capacity, the sorted copies, the
//! grid and hash arrays, the uniform block; spawns are uploaded at the end of the live range.

use super::pipelines::{SphPipelines, VariantKey, STORAGE_BINDINGS};
use super::{ExtractedSphFrame, SphRenderFeedback};
use bevy::prelude::*;
use bevy::render::render_asset::RenderAssets;
use bevy::render::render_resource::{
    BindGroup, BindGroupEntry, Buffer, BufferDescriptor, BufferUsages, PipelineCache,
};
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::storage::GpuShaderBuffer;
use sph_core::gpu_layout::{bitonic_steps, sort_length, GpuClock, GpuSphParams};
use sph_core::neighbor::grid::DenseGrid;
use sph_core::neighbor::hash::hash_table_size;
use sph_core::NeighborSearch;

/// Byte stride of the bitonic steps in their uniform buffer (the dynamic-offset alignment).
pub const BITONIC_STRIDE: u64 = 256;

/// Every buffer of group 0, in binding order after the uniform.
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
    /// Bindings 1 ..= 23 (see `shaders/bindings.wgsl`).
    pub storage: Vec<Buffer>,
    /// The bitonic steps (hash mode).
    pub bitonic_steps: Buffer,
    /// Number of bitonic steps.
    pub bitonic_step_count: u32,
}

/// Indices into [`GpuBuffers::storage`] (binding - 1).
pub mod slot {
    /// Positions (w = id).
    pub const POSITION: usize = 0;
    /// Velocities.
    pub const VELOCITY: usize = 1;
    /// Predicted velocities.
    pub const VELOCITY_PREDICTED: usize = 2;
    /// Accelerations.
    pub const ACCELERATION: usize = 3;
    /// Start-of-step accelerations (leapfrog).
    pub const ACCELERATION_START: usize = 4;
    /// Densities.
    pub const DENSITY: usize = 5;
    /// First sorted copy (sorted_position); the five sorted arrays follow in state order.
    pub const SORTED_POSITION: usize = 8;
    /// Per-cell counts.
    pub const CELL_COUNTS: usize = 15;
    /// Per-bucket start (+1).
    pub const BUCKET_START: usize = 19;
    /// The clock (`GpuClock`).
    pub const CLOCK: usize = 22;
}

impl GpuBuffers {
    /// The state buffer at `slot`.
    pub fn at(&self, slot: usize) -> &Buffer {
        &self.storage[slot]
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
    /// Group 0.
    pub bind_group: Option<BindGroup>,
    /// Group 1 of the bitonic sort with each step's offset.
    pub bitonic_bind_group: Option<(BindGroup, Vec<u32>)>,
    /// Bumped when buffers are reallocated.
    pub generation: u64,
    bind_group_generation: u64,
    /// Why the buffers are not ready.
    pub status: Option<String>,
    /// Spawns that arrived before the buffers were ready.
    pending_spawns: Vec<PendingSpawn>,
}

/// New particles waiting for upload: first slot, positions (w = id), velocities.
type PendingSpawn = (u32, Vec<[f32; 4]>, Vec<[f32; 4]>);

fn storage_buffer(device: &RenderDevice, label: &'static str, bytes: u64) -> Buffer {
    device.create_buffer(&BufferDescriptor {
        label: Some(label),
        size: bytes.max(16),
        usage: BufferUsages::STORAGE | BufferUsages::COPY_DST | BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// Allocates every buffer; the normals and the hash arrays only when the variant needs them (a
/// 16-byte placeholder keeps their binding valid otherwise).
fn allocate(
    device: &RenderDevice,
    capacity: u32,
    grid_dims: UVec3,
    key: VariantKey,
    readable: [Buffer; 6],
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
    let normals = if key.surface_tension { 16 * n } else { 0 };
    let [position, velocity, acceleration, density, neighbor_count, clock] = readable;
    let storage = vec![
        position,
        velocity,
        storage_buffer(device, "sph_velocity_predicted", 16 * n),
        acceleration,
        storage_buffer(device, "sph_acceleration_start", 16 * n),
        density,
        storage_buffer(device, "sph_pressure", 4 * n),
        storage_buffer(device, "sph_normal", normals),
        storage_buffer(device, "sph_sorted_position", 16 * n),
        storage_buffer(device, "sph_sorted_velocity", 16 * n),
        storage_buffer(device, "sph_sorted_velocity_predicted", 16 * n),
        storage_buffer(device, "sph_sorted_acceleration", 16 * n),
        storage_buffer(device, "sph_sorted_acceleration_start", 16 * n),
        storage_buffer(device, "sph_cell_of", 4 * n),
        storage_buffer(device, "sph_rank_in_cell", 4 * n),
        storage_buffer(device, "sph_cell_counts", 4 * cells),
        storage_buffer(device, "sph_cell_start", 4 * (cells + 1)),
        storage_buffer(device, "sph_sort_keys", 4 * sort_len as u64),
        storage_buffer(device, "sph_sort_values", 4 * sort_len as u64),
        storage_buffer(device, "sph_bucket_start", 4 * table),
        storage_buffer(device, "sph_bucket_end", 4 * table),
        neighbor_count,
        clock,
    ];
    debug_assert_eq!(storage.len(), STORAGE_BINDINGS as usize);
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
    }
}

/// Allocates buffers when the capacity, grid or readable buffers change, applies resets and
/// spawns, and writes the uniform block.
pub(crate) fn prepare_sph_buffers(
    frame: Res<ExtractedSphFrame>,
    assets: Res<RenderAssets<GpuShaderBuffer>>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    feedback: Res<SphRenderFeedback>,
    mut state: ResMut<SphGpuState>,
) {
    if !frame.active {
        return;
    }
    let Some(handles) = &frame.buffers else {
        return;
    };
    // Spawns and resets are queued first, so nothing is lost while the buffers get ready.
    if frame.reset {
        state.pending_spawns.clear();
        state.particle_count = 0;
        state.forces_stale = true;
        feedback.update(|f| f.step_count = 0);
    }
    if !frame.spawn_positions.is_empty() {
        state.pending_spawns.push((
            frame.spawn_offset,
            frame.spawn_positions.clone(),
            frame.spawn_velocities.clone(),
        ));
    }
    let readable = [
        &handles.position,
        &handles.velocity,
        &handles.acceleration,
        &handles.density,
        &handles.neighbor_count,
        &handles.clock,
    ]
    .map(|h| assets.get(h).map(|b| b.buffer.clone()));
    let [Some(position), Some(velocity), Some(acceleration), Some(density), Some(neighbor_count), Some(clock)] =
        readable
    else {
        state.status = Some("gpu: preparing buffers".into());
        return;
    };
    let grid = match DenseGrid::new(&frame.container, frame.params.smoothing_radius) {
        Ok(grid) => grid,
        Err(e) => {
            state.status = Some(format!("gpu: {e}"));
            state.bind_group = None;
            return;
        }
    };
    let key = VariantKey::of(&frame.params, frame.neighbor_counts);
    let needs_allocation = state.buffers.as_ref().is_none_or(|b| {
        b.capacity != frame.capacity
            || b.grid_dims != grid.dims
            || b.key.search != key.search
            || b.key.surface_tension != key.surface_tension
            || b.at(slot::POSITION).id() != position.id()
            || b.at(slot::DENSITY).id() != density.id()
    });
    if needs_allocation {
        // The readable state buffers are assets and survive a reallocation (a new container or
        // h keeps the particles); the rest is re-derived: forces are re-evaluated.
        let buffers = allocate(
            &device,
            frame.capacity,
            grid.dims,
            key,
            [
                position,
                velocity,
                acceleration,
                density,
                neighbor_count,
                clock,
            ],
        );
        let bytes_per_particle = (buffers.bytes / frame.capacity.max(1) as u64) as u32;
        feedback.update(|f| f.gpu_bytes_per_particle = bytes_per_particle);
        state.buffers = Some(buffers);
        state.generation += 1;
        state.forces_stale = true;
    }
    state.status = None;
    let Some(buffers) = state.buffers.clone() else {
        return;
    };
    if frame.reset {
        // Time, steps and the instability freeze start again.
        queue.write_buffer(
            buffers.at(slot::CLOCK),
            0,
            bytemuck::bytes_of(&GpuClock::default()),
        );
    }
    for (offset, positions, velocities) in std::mem::take(&mut state.pending_spawns) {
        let offset = offset as u64;
        let zeros = vec![[0.0f32; 4]; positions.len()];
        let write = |slot_index: usize, data: &[[f32; 4]]| {
            queue.write_buffer(
                buffers.at(slot_index),
                16 * offset,
                bytemuck::cast_slice(data),
            );
        };
        write(slot::POSITION, &positions);
        write(slot::VELOCITY, &velocities);
        write(slot::VELOCITY_PREDICTED, &velocities);
        write(slot::ACCELERATION, &zeros);
        write(slot::ACCELERATION_START, &zeros);
        state.forces_stale = true;
    }
    state.particle_count = frame.particle_count();
    if state.last_params != Some(frame.params) {
        state.forces_stale = true;
        state.last_params = Some(frame.params);
    }
    if state.forces_stale {
        // The re-evaluation records the acceleration the next kick uses; the one recorded with
        // the old state or parameters must not bound the adaptive step.
        queue.write_buffer(
            buffers.at(slot::CLOCK),
            std::mem::offset_of!(GpuClock, max_acceleration_bits) as u64,
            &[0; 4],
        );
    }
    let uniforms = GpuSphParams::with_grid(
        &frame.params,
        &frame.container,
        grid.dims,
        frame.capacity,
        state.particle_count,
    );
    queue.write_buffer(&buffers.uniform, 0, bytemuck::bytes_of(&uniforms));
}

/// (Re)creates the bind groups after a reallocation.
pub(crate) fn prepare_sph_bind_groups(
    pipelines: Option<Res<SphPipelines>>,
    cache: Res<PipelineCache>,
    device: Res<RenderDevice>,
    mut state: ResMut<SphGpuState>,
) {
    let Some(pipelines) = pipelines else {
        return;
    };
    if state.bind_group.is_some() && state.bind_group_generation == state.generation {
        return;
    }
    let Some(buffers) = state.buffers.clone() else {
        return;
    };
    let layout = cache.get_bind_group_layout(&pipelines.layout);
    let mut entries = vec![BindGroupEntry {
        binding: 0,
        resource: buffers.uniform.as_entire_binding(),
    }];
    for (k, buffer) in buffers.storage.iter().enumerate() {
        entries.push(BindGroupEntry {
            binding: k as u32 + 1,
            resource: buffer.as_entire_binding(),
        });
    }
    state.bind_group = Some(device.create_bind_group("sph_state", &layout, &entries));
    let bitonic_layout = cache.get_bind_group_layout(&pipelines.bitonic_layout);
    let step = bevy::render::render_resource::BufferBinding {
        buffer: &buffers.bitonic_steps,
        offset: 0,
        size: std::num::NonZeroU64::new(16),
    };
    let bitonic = device.create_bind_group(
        "sph_bitonic_step",
        &bitonic_layout,
        &[BindGroupEntry {
            binding: 0,
            resource: bevy::render::render_resource::BindingResource::Buffer(step),
        }],
    );
    let offsets = (0..buffers.bitonic_step_count)
        .map(|k| k * BITONIC_STRIDE as u32)
        .collect();
    state.bitonic_bind_group = Some((bitonic, offsets));
    state.bind_group_generation = state.generation;
}

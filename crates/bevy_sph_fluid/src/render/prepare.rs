//! Each frame's buffer work in the render world (`prepare_sph_buffers`): queue the spawns and
//! the reset, (re)allocate the buffers when the capacity, grid, variant or readable buffers
//! changed, write the frame's inputs (pumps, probes, the bodies' force sums), upload the spawns
//! and the boundary, mark the forces stale where the state changed, and write the uniform block.

use super::arenas::{Arena, ArenaLayout};
use super::buffers::{allocate, buffer_sizes, Buf, GpuBuffers, SphGpuState, WhitewaterTargets};
use super::extract::ExtractedSphFrame;
use super::plan::VariantKey;
use super::whitewater;
use crate::api::STATUS_PREPARING_BUFFERS;
use crate::shared::SphRenderFeedback;
use bevy::prelude::*;
use bevy::render::render_asset::RenderAssets;
use bevy::render::render_resource::Buffer;
use bevy::render::renderer::{RenderDevice, RenderQueue};
use bevy::render::storage::GpuShaderBuffer;
use sph_core::gpu_dfsph_pairs;
use sph_core::gpu_layout::{
    GpuBodyForces, GpuClock, GpuCollider, GpuProbes, GpuPumps, GpuSphParams, PBF_WALL_LIST_WORDS,
};
use sph_core::neighbor::grid::DenseGrid;
use sph_core::Solver;

/// The shedding's seed: the CPU solver's, so both backends name the same scene's stream.
const WHITEWATER_SEED: u32 = sph_core::solver::whitewater::WHITEWATER_SEED as u32;

/// The device and its queue.
struct Gpu<'a> {
    device: &'a RenderDevice,
    queue: &'a RenderQueue,
}

impl Gpu<'_> {
    /// Writes `bytes` into the clock at `offset`.
    fn write_clock(&self, buffers: &GpuBuffers, offset: u64, bytes: &[u8]) {
        buffers.write(self.queue, Buf::Clock, offset, bytes);
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
    let gpu = Gpu {
        device: &device,
        queue: &queue,
    };
    // Spawns and resets are queued first, so nothing is lost while the buffers get ready.
    queue_spawns(&frame, &feedback, &mut state);
    let Some(readable) = readable_buffers(handles, &assets) else {
        state.status = Some(STATUS_PREPARING_BUFFERS.into());
        return;
    };
    let grid = match DenseGrid::new(&frame.container, frame.params.smoothing_radius) {
        Ok(grid) => grid,
        Err(e) => {
            state.status = Some(format!("gpu: {e}"));
            state.bind_groups.clear();
            return;
        }
    };
    let key = VariantKey::of_frame(&frame);
    let diffuse = frame.whitewater.as_ref().map_or(0, |w| w.capacity);
    state.whitewater_targets = whitewater_targets(&frame, &assets);
    let reallocated = needs_allocation(&state, &frame, grid.dims, key, diffuse, &readable);
    if reallocated {
        // Buffers in place were checked when they were allocated.
        if let Err(reason) = fits_the_device(&device, &frame, grid.dims, key, diffuse) {
            state.status = Some(reason);
            state.bind_groups.clear();
            return;
        }
        reallocate(&gpu, &feedback, &mut state, &frame, grid.dims, readable);
    }
    state.status = None;
    let Some(buffers) = state.buffers.clone() else {
        return;
    };
    let pumps = write_frame_inputs(&gpu, &buffers, &frame);
    upload_spawns(&gpu, &buffers, &mut state, &frame);
    let white = frame.whitewater.as_ref().filter(|_| buffers.key.whitewater);
    if let Some(white) = white {
        // A new pool, new buffers or a reset: the pool starts empty.
        if state.whitewater_generation != Some(white.generation) || reallocated || frame.reset {
            whitewater::empty_the_pool(&buffers, &queue);
            state.whitewater_generation = Some(white.generation);
        }
    }
    note_changes(&gpu, &buffers, &mut state, &frame, reallocated);
    write_body_inputs(&gpu, &buffers, &mut state, &frame, &assets);
    let mut uniforms = GpuSphParams::with_grid(
        &frame.params,
        &frame.container,
        grid.dims,
        frame.capacity,
        state.particle_count,
    )
    .with_rollback(&frame.rollback)
    .with_boundary(
        state.boundary_colliders,
        state.boundary_friction,
        state.boundary_unmirrored,
    )
    .with_wall_force(frame.wall_force)
    .with_drains(frame.number, pumps.sink_count);
    if let Some(white) = white {
        uniforms = uniforms.with_whitewater(
            &white.settings,
            white.capacity,
            WHITEWATER_SEED,
            frame.steps,
        );
    }
    if let Some((duration, number)) = frame.budget {
        uniforms = uniforms.with_frame_budget(duration, frame.steps, number);
    }
    uniforms.boundary_sample_count = state.boundary_samples;
    // The boundary's upload may have moved its regions.
    let buffers = state.buffers.as_ref().unwrap_or(&buffers);
    uniforms.buffer_at = buffers.layout.buffer_at();
    queue.write_buffer(&buffers.uniform, 0, bytemuck::bytes_of(&uniforms));
}

/// A reset drops the queued spawns and starts the count again; the frame's spawns join the
/// queue.
fn queue_spawns(frame: &ExtractedSphFrame, feedback: &SphRenderFeedback, state: &mut SphGpuState) {
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
}

/// The buffers the main world reads back, once all of them exist on the device, in
/// [`super::buffers::READABLE`]'s order: position, velocity, acceleration, density, pressure,
/// neighbour count, clock, body forces, probes.
fn readable_buffers(
    handles: &crate::api::SphGpuBuffers,
    assets: &RenderAssets<GpuShaderBuffer>,
) -> Option<[Buffer; 9]> {
    let handles = [
        &handles.position,
        &handles.velocity,
        &handles.acceleration,
        &handles.density,
        &handles.pressure,
        &handles.neighbor_count,
        &handles.clock,
        &handles.body_forces,
        &handles.probes,
    ];
    let mut readable = Vec::with_capacity(handles.len());
    for handle in handles {
        readable.push(assets.get(handle)?.buffer.clone());
    }
    readable.try_into().ok()
}

/// The main world's whitewater buffers, once they exist on the device.
fn whitewater_targets(
    frame: &ExtractedSphFrame,
    assets: &RenderAssets<GpuShaderBuffer>,
) -> Option<WhitewaterTargets> {
    let white = frame.whitewater.as_ref()?;
    Some(WhitewaterTargets {
        draw: assets.get(&white.draw)?.buffer.clone(),
        counts: assets.get(&white.counts)?.buffer.clone(),
        potentials: assets.get(&white.potentials)?.buffer.clone(),
    })
}

/// Refuses, by name, a scene the device's buffers cannot hold.
fn fits_the_device(
    device: &RenderDevice,
    frame: &ExtractedSphFrame,
    grid_dims: UVec3,
    key: VariantKey,
    diffuse: u32,
) -> Result<(), String> {
    if key.solver == Solver::Dfsph && frame.capacity > gpu_dfsph_pairs::MAX_PARTICLES {
        return Err(format!(
            "gpu: DFSPH holds at most {} particles on the GPU (its pairs keep 18-bit indices); \
             the capacity is {}: use the CPU backend or another solver",
            gpu_dfsph_pairs::MAX_PARTICLES,
            frame.capacity
        ));
    }
    let sizes = buffer_sizes(frame.capacity, grid_dims, key, diffuse);
    let layout = ArenaLayout::of_sizes(&sizes);
    let limits = device.limits();
    let most = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    match Arena::ALL
        .into_iter()
        .find(|&arena| layout.arena_bytes(arena) > most)
    {
        Some(arena) => Err(format!(
            "gpu: the buffer {} needs {} bytes for a capacity of {}, the device binds at most \
             {most} (max_storage_buffer_binding_size, max_buffer_size): lower the capacity or \
             use the CPU backend",
            arena.label(),
            layout.arena_bytes(arena),
            frame.capacity
        )),
        None => Ok(()),
    }
}

/// Whether the buffers must be (re)allocated: none yet, or a new capacity, grid, variant,
/// whitewater pool or readable buffer.
fn needs_allocation(
    state: &SphGpuState,
    frame: &ExtractedSphFrame,
    grid_dims: UVec3,
    key: VariantKey,
    diffuse: u32,
    readable: &[Buffer; 9],
) -> bool {
    state.buffers.as_ref().is_none_or(|b| {
        b.capacity != frame.capacity
            || b.key.whitewater != key.whitewater
            || b.diffuse_capacity != diffuse
            || b.grid_dims != grid_dims
            || b.key.search != key.search
            || b.key.surface_tension != key.surface_tension
            || b.key.solver != key.solver
            || b.key.bodies != key.bodies
            || b.readable
                .iter()
                .zip(readable)
                .any(|(a, b)| a.id() != b.id())
    })
}

/// Allocates every buffer. The readable state buffers are assets and survive a reallocation (a
/// new container or h keeps the particles): the new arenas start from them, and the rest is
/// re-derived: forces are re-evaluated.
fn reallocate(
    gpu: &Gpu,
    feedback: &SphRenderFeedback,
    state: &mut SphGpuState,
    frame: &ExtractedSphFrame,
    grid_dims: UVec3,
    readable: [Buffer; 9],
) {
    let key = VariantKey::of_frame(frame);
    let diffuse = frame.whitewater.as_ref().map_or(0, |w| w.capacity);
    let buffers = allocate(
        gpu.device,
        frame.capacity,
        grid_dims,
        key,
        diffuse,
        readable,
    );
    // Submitted before this frame's writes, which the queue applies at its next submission.
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    buffers.restore(&mut encoder);
    gpu.queue.submit([encoder.finish()]);
    let bytes_per_particle = (buffers.bytes / frame.capacity.max(1) as u64) as u32;
    feedback.update(|f| f.gpu_bytes_per_particle = bytes_per_particle);
    // A new checkpoint buffer holds nothing yet.
    gpu.write_clock(
        &buffers,
        GpuClock::HAS_CHECKPOINT_OFFSET,
        &0u32.to_ne_bytes(),
    );
    state.buffers = Some(buffers);
    state.generation += 1;
    state.forces_stale = true;
}

/// The frame's inputs: the clock after a reset, the pumps and open drains, zeroed probe and
/// body-force sums and DFSPH's per-frame maxima when the frame steps, and the frame's number on
/// the force sums. Returns the pumps.
fn write_frame_inputs(gpu: &Gpu, buffers: &GpuBuffers, frame: &ExtractedSphFrame) -> GpuPumps {
    if frame.reset {
        // Time, steps and the instability freeze start again.
        gpu.write_clock(buffers, 0, bytemuck::bytes_of(&GpuClock::default()));
    }
    // The pumps, then the open drains in the slots left.
    let (pumps, _) = GpuPumps::with_sinks(&frame.pumps, &frame.sinks);
    let queue = gpu.queue;
    if frame.steps > 0 {
        buffers.write(queue, Buf::Pumps, 0, bytemuck::bytes_of(&pumps));
        // The probes with zero sums; the closing kicks sum the frame's steps.
        let probes = GpuProbes::of(
            &frame.probes,
            &frame.container,
            frame.params.spacing(),
            frame.number,
        );
        buffers.write(queue, Buf::Probes, 0, bytemuck::bytes_of(&probes));
        // This frame's sums of the fluid's force on each body start from zero; the readback
        // copies them after the frame's passes.
        buffers.write(
            queue,
            Buf::BodyForces,
            0,
            bytemuck::bytes_of(&GpuBodyForces::default()),
        );
        // DFSPH's most iterations per step are this frame's (src/dfsph_budget.rs reads them).
        gpu.write_clock(buffers, GpuClock::DFSPH_FRAME_MAX_OFFSET, &[0; 8]);
    }
    // Every frame, with steps or not, stamps the force sums with its number: the readback then
    // tells how many frames old the newest forces are (`sph_plan_frame` holds the water while
    // they are too old).
    buffers.write(
        queue,
        Buf::BodyForces,
        GpuBodyForces::FRAME_OFFSET,
        &frame.number.to_ne_bytes(),
    );
    pumps
}

/// Writes the queued spawns at the end of the live range, and counts the live particles.
fn upload_spawns(
    gpu: &Gpu,
    buffers: &GpuBuffers,
    state: &mut SphGpuState,
    frame: &ExtractedSphFrame,
) {
    for (offset, positions, velocities) in std::mem::take(&mut state.pending_spawns) {
        let offset = offset as u64;
        let zeros = vec![[0.0f32; 4]; positions.len()];
        let write = |buf: Buf, data: &[[f32; 4]]| {
            buffers.write(gpu.queue, buf, 16 * offset, bytemuck::cast_slice(data));
        };
        write(Buf::Position, &positions);
        write(Buf::Velocity, &velocities);
        // DFSPH keeps its solves' stiffness sums there (the warm starts): new particles have none.
        if buffers.key.solver == Solver::Dfsph {
            write(Buf::VelocityPredicted, &zeros);
        } else {
            write(Buf::VelocityPredicted, &velocities);
        }
        write(Buf::Acceleration, &zeros);
        write(Buf::AccelerationStart, &zeros);
        state.forces_stale = true;
        // The new particles join the rollback checkpoint at the next stable step.
        gpu.write_clock(
            buffers,
            GpuClock::SAVE_REQUESTED_OFFSET,
            &1u32.to_ne_bytes(),
        );
    }
    if !frame.reset && frame.spawn_offset < state.particle_count {
        // The main world dropped the drained particles from the tail (docs/scenes.md): a
        // checkpoint from before holds them among the live ones, so it cannot be restored.
        gpu.write_clock(
            buffers,
            GpuClock::HAS_CHECKPOINT_OFFSET,
            &0u32.to_ne_bytes(),
        );
    }
    state.particle_count = frame.particle_count();
}

/// Marks the forces stale where the parameters or the boundary's membership changed (and then
/// forgets the recorded acceleration), and uploads a new boundary.
fn note_changes(
    gpu: &Gpu,
    buffers: &GpuBuffers,
    state: &mut SphGpuState,
    frame: &ExtractedSphFrame,
    reallocated: bool,
) {
    if state.last_params != Some(frame.params) {
        state.forces_stale = true;
        state.last_params = Some(frame.params);
    }
    if let Some((_, samples)) = &frame.boundary {
        // A collider joined or left: the kick's forces are re-evaluated first, as on the CPU.
        if samples.membership != state.boundary_membership {
            state.forces_stale = true;
            state.boundary_membership = samples.membership;
        }
    }
    if state.forces_stale {
        // The re-evaluation records the acceleration the next kick uses; the one recorded with
        // the old state or parameters must not bound the adaptive step.
        gpu.write_clock(
            buffers,
            std::mem::offset_of!(GpuClock, max_acceleration_bits) as u64,
            &[0; 4],
        );
    }
    if let Some((generation, samples)) = &frame.boundary {
        if *generation != state.boundary_generation || reallocated {
            upload_boundary(gpu.device, gpu.queue, state, samples);
            state.boundary_generation = *generation;
            // DFSPH's factors hold the boundary samples near each particle (as the CPU, which
            // rebuilds its neighbourhood when the boundary moved): the frame's first step
            // starts from a new neighbourhood.
            if frame.params.solver == Solver::Dfsph {
                state.forces_stale = true;
            }
        }
    }
}

/// Writes the boundary samples; their buffers are reallocated (and the bind groups rebuilt) only
/// when the samples outgrow them, never the particle buffers.
fn upload_boundary(
    device: &RenderDevice,
    queue: &RenderQueue,
    state: &mut SphGpuState,
    samples: &sph_core::gpu_layout::GpuBoundarySamples,
) {
    let Some(buffers) = state.buffers.as_mut() else {
        return;
    };
    let need = (16 * samples.position.len() as u64).max(16);
    let collider_bytes =
        (std::mem::size_of::<GpuCollider>() * samples.colliders.len().max(1)) as u64;
    let body_bytes = (4 * samples.body.len() as u64).max(16);
    let mesh_bytes = (16 * samples.meshes.len() as u64).max(16);
    let starts = bytemuck::cast_slice(&samples.cell_start);
    if buffers.size(Buf::BoundaryCellStart) < starts.len() as u64 {
        // The grid and the samples disagree (a container change in flight): skip this frame.
        return;
    }
    // The samples as sorted, where the moved bodies' placement moves theirs from.
    let rest = if buffers.key.bodies { need } else { 16 };
    let lambda = if buffers.key.solver == Solver::Pbf {
        (4 * PBF_WALL_LIST_WORDS as u64 * samples.position.len() as u64).max(16)
    } else {
        16
    };
    let grown = buffers.grow(
        device,
        &[
            (Buf::BoundaryPosition, need),
            (Buf::BoundaryVelocity, need),
            (Buf::Colliders, collider_bytes),
            (Buf::BoundaryBody, body_bytes),
            (Buf::Meshes, mesh_bytes),
            (Buf::BoundaryRest, rest),
            (Buf::BoundaryLambda, lambda),
        ],
    );
    if !samples.position.is_empty() {
        let position = bytemuck::cast_slice(&samples.position);
        buffers.write(queue, Buf::BoundaryPosition, 0, position);
        if buffers.key.bodies {
            buffers.write(queue, Buf::BoundaryRest, 0, position);
        }
        let velocity = bytemuck::cast_slice(&samples.velocity);
        buffers.write(queue, Buf::BoundaryVelocity, 0, velocity);
        buffers.write(
            queue,
            Buf::BoundaryBody,
            0,
            bytemuck::cast_slice(&samples.body),
        );
    }
    buffers.write(queue, Buf::BoundaryCellStart, 0, starts);
    if !samples.colliders.is_empty() {
        let colliders = bytemuck::cast_slice(&samples.colliders);
        buffers.write(queue, Buf::Colliders, 0, colliders);
    }
    if !samples.meshes.is_empty() {
        buffers.write(queue, Buf::Meshes, 0, bytemuck::cast_slice(&samples.meshes));
    }
    state.boundary_samples = samples.position.len() as u32;
    state.boundary_colliders = samples.colliders.len() as u32;
    state.boundary_friction = samples.velocity.iter().any(|v| v[3] > 0.0);
    state.boundary_unmirrored = !samples.mirrors;
    if grown {
        state.generation += 1;
    }
}

/// The moved bodies' inputs, every frame while there are any (`render::bodies`); after a reset
/// their states start again empty, so each body starts from the engine's next state. Resolves
/// the main world's copy of the states.
fn write_body_inputs(
    gpu: &Gpu,
    buffers: &GpuBuffers,
    state: &mut SphGpuState,
    frame: &ExtractedSphFrame,
    assets: &RenderAssets<GpuShaderBuffer>,
) {
    use sph_core::gpu_layout::{GpuBodyState, GPU_BODY_STATES_OFFSET, GPU_MOVED_BODIES};
    state.body_target = None;
    let Some(bodies) = frame.bodies.as_ref().filter(|_| buffers.key.bodies) else {
        return;
    };
    let inputs = &bodies.inputs[..bodies.inputs.len().min(GPU_MOVED_BODIES)];
    buffers.write(gpu.queue, Buf::BodyWords, 0, bytemuck::cast_slice(inputs));
    if frame.reset {
        let empty = vec![GpuBodyState::default(); GPU_MOVED_BODIES];
        buffers.write(
            gpu.queue,
            Buf::BodyWords,
            GPU_BODY_STATES_OFFSET as u64,
            bytemuck::cast_slice(&empty),
        );
    }
    state.body_target = assets.get(&bodies.states).map(|b| b.buffer.clone());
}

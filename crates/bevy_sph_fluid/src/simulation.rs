//! Main-world simulation systems: the container, resets and spawners become this frame's plan
//! ([`SphFrame`](crate::shared::SphFrame), extracted to the render world), or are stepped directly on the CPU backend;
//! statistics are gathered from the solver or from the render world's feedback.

use crate::api::*;
use crate::colliders::{sph_sync_colliders, sph_write_collider_forces};
use crate::sets::SphSystems;
use crate::shared::{
    holds_for_body_forces, BodyForceReadback, ClockReadback, FramePlan, GpuIterations,
    SphRenderFeedback, SphSimulation,
};
use bevy::ecs::schedule::InternedScheduleLabel;
use bevy::prelude::*;
use bevy::render::render_resource::DownlevelFlags;
use bevy::render::renderer::{RenderAdapter, RenderAdapterInfo, RenderDevice};
use bevy::render::storage::ShaderBuffer;
use sph_core::CpuSolver;

/// [`SphStats::error`] while no entity holds an [`SphContainer`]; cleared when one comes.
const NO_CONTAINER: &str = "no entity with an SphContainer component";

pub(crate) fn add_systems(app: &mut App, schedule: InternedScheduleLabel) {
    app.add_systems(
        schedule,
        (
            (
                sph_plan_frame,
                sph_apply_capacity,
                sph_track_container,
                sph_sync_colliders,
                sph_reset,
                sph_spawn_blocks,
                sph_emit,
            )
                .chain()
                .in_set(SphSystems::Prepare),
            sph_plan_step.in_set(SphSystems::Step).in_set(StepSystem),
            (sph_update_stats, sph_write_collider_forces).in_set(SphSystems::Writeback),
        ),
    );
}

/// The system that steps (or plans the GPU's steps); drains run after it.
#[derive(SystemSet, Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct StepSystem;

/// Decides the backend: the GPU needs a render app on an adapter with compute shaders and the
/// limits the pipelines need ([`crate::render::limits`]); otherwise the CPU runs, and the reason
/// is kept for [`SphStats::fallback_reason`].
pub(crate) fn resolve_backend(app: &mut App) {
    let world = app.world_mut();
    let adapter_name = world
        .get_resource::<RenderAdapterInfo>()
        .map(|info| info.name.clone());
    let compute = world.get_resource::<RenderAdapter>().map(|adapter| {
        adapter
            .get_downlevel_capabilities()
            .flags
            .contains(DownlevelFlags::COMPUTE_SHADERS)
    });
    let shortfall = world.get_resource::<RenderDevice>().and_then(|device| {
        crate::render::limits::GpuNeeds::of_all_stages().shortfall(&device.limits())
    });
    let mut sim = world.resource_mut::<SphSimulation>();
    let adapter = adapter_name.as_deref().unwrap_or("?");
    let reason = match (sim.requested, compute) {
        (SphBackend::Cpu, _) => None,
        (SphBackend::Gpu, None) => {
            Some("no render device (rendering disabled or no GPU adapter)".to_string())
        }
        (SphBackend::Gpu, Some(false)) => Some(format!(
            "the adapter {adapter:?} has no compute shaders (e.g. WebGL2)"
        )),
        (SphBackend::Gpu, Some(true)) => shortfall.map(|short| {
            format!("the adapter {adapter:?} lacks a limit the pipelines need: {short}")
        }),
    };
    if let Some(reason) = &reason {
        warn!("SphFluidPlugin: {reason}; falling back to the sph_core CPU solver");
    }
    sim.backend = if reason.is_some() {
        SphBackend::Cpu
    } else {
        sim.requested
    };
    sim.fallback_reason = reason;
    sim.adapter = match sim.backend {
        SphBackend::Gpu => adapter_name.unwrap_or_default(),
        SphBackend::Cpu => "cpu".to_string(),
    };
    // The readable state buffers, once the backend is known to be the GPU.
    let (backend, capacity) = (sim.backend, sim.capacity);
    if backend != SphBackend::Gpu {
        return;
    }
    let Some(mut assets) = world.get_resource_mut::<Assets<ShaderBuffer>>() else {
        return;
    };
    let buffers = SphGpuBuffers::new(&mut assets, capacity);
    world.insert_resource(buffers.clone());
    world.resource_mut::<SphSimulation>().frame.buffers = Some(buffers);
}

pub(crate) fn clear_frame(mut sim: ResMut<SphSimulation>) {
    let count = sim.particle_count;
    let frame = &mut sim.frame;
    frame.reset = false;
    frame.spawn_positions.clear();
    frame.spawn_velocities.clear();
    frame.steps = 0;
    frame.spawn_offset = count;
}

/// Follows the container entity; a new container rebuilds the CPU solver (keeping particles);
/// a changed [`SphWallSlip`] resamples the walls on either backend.
fn sph_track_container(
    containers: Query<(&SphContainer, Option<&SphWallSlip>)>,
    params: Res<SphParams>,
    mut sim: ResMut<SphSimulation>,
    mut stats: ResMut<SphStats>,
) {
    let first = containers.iter().next();
    let container = first.map(|(c, _)| c.0);
    let slip = first
        .and_then(|(_, s)| s.map(|s| s.0))
        .unwrap_or(sph_core::Slip::Free);
    if slip != sim.wall_slip {
        if let Err(e) = slip.validate() {
            stats.error = Some(e.to_string());
        } else {
            sim.wall_slip = slip;
            if let Some(solver) = &mut sim.cpu {
                solver.set_wall_boundary(Some(slip));
            }
            if let Some(boundary) = &mut sim.gpu_boundary {
                boundary.set_walls(Some(slip));
            }
        }
    }
    if container == sim.container {
        return;
    }
    sim.container = container;
    let Some(container) = container else {
        return;
    };
    // The container has come (a scene file's a few frames after the app starts): the error its
    // absence set is over, on either backend.
    if stats.error.as_deref() == Some(NO_CONTAINER) {
        stats.error = None;
    }
    if sim.backend == SphBackend::Cpu {
        let mut p = params.0;
        if p.validate().is_err() {
            p = sph_core::SphParams::water();
        }
        match CpuSolver::new(p, container, sim.capacity as usize) {
            Ok(mut solver) => {
                solver.set_wall_boundary(Some(sim.wall_slip));
                if let Some(old) = &sim.cpu {
                    let particles = old.particles();
                    solver.spawn_with_velocities(&particles.position, &particles.velocity);
                }
                sim.cpu = Some(solver);
                sim.boundary_epoch += 1;
                stats.error = None;
            }
            Err(e) => stats.error = Some(e.to_string()),
        }
    }
}

/// Drops every particle; block spawners fire again and emitters start over.
fn reset_particles(
    sim: &mut SphSimulation,
    blocks: &mut Query<&mut SphBlockSpawn>,
    emitters: &mut Query<&mut SphEmitter>,
) {
    sim.particle_count = 0;
    sim.initial = 0;
    sim.emitted = 0;
    sim.drained = 0;
    sim.next_id = 0;
    sim.refused = 0;
    sim.inside_colliders = 0;
    sim.frame.reset = true;
    sim.frame.spawn_offset = 0;
    sim.frame.spawn_positions.clear();
    sim.frame.spawn_velocities.clear();
    sim.emission_steps_seen = None;
    if let Some(solver) = &mut sim.cpu {
        solver.clear();
    }
    for mut block in blocks.iter_mut() {
        block.set_changed();
    }
    for mut emitter in emitters.iter_mut() {
        emitter.0.emitted = 0;
    }
}

fn sph_reset(
    mut control: ResMut<SphControl>,
    mut sim: ResMut<SphSimulation>,
    mut blocks: Query<&mut SphBlockSpawn>,
    mut emitters: Query<&mut SphEmitter>,
) {
    if control.reset {
        control.reset = false;
        reset_particles(&mut sim, &mut blocks, &mut emitters);
    }
}

/// A changed [`SphCapacity`] reallocates every buffer (or rebuilds the CPU solver) and resets.
fn sph_apply_capacity(
    capacity: Res<SphCapacity>,
    mut sim: ResMut<SphSimulation>,
    mut stats: ResMut<SphStats>,
    buffers: Option<ResMut<Assets<ShaderBuffer>>>,
    mut commands: Commands,
    mut blocks: Query<&mut SphBlockSpawn>,
    mut emitters: Query<&mut SphEmitter>,
) {
    if capacity.0 == sim.capacity {
        return;
    }
    if let Err(e) = sph_core::solver::validate_capacity(capacity.0 as usize) {
        stats.error = Some(e.to_string());
        return;
    }
    sim.capacity = capacity.0;
    reset_particles(&mut sim, &mut blocks, &mut emitters);
    match sim.backend {
        SphBackend::Gpu => {
            if let Some(mut assets) = buffers {
                let buffers = SphGpuBuffers::new(&mut assets, capacity.0);
                commands.insert_resource(buffers.clone());
                sim.frame.buffers = Some(buffers);
            }
        }
        SphBackend::Cpu => {
            // Rebuilt for the new capacity by sph_track_container.
            sim.cpu = None;
            sim.container = None;
        }
    }
}

fn sph_spawn_blocks(
    blocks: Query<Ref<SphBlockSpawn>>,
    mut sim: ResMut<SphSimulation>,
    mut stats: ResMut<SphStats>,
) {
    if sim.container.is_none() {
        return;
    }
    for block in &blocks {
        if !block.is_changed() {
            continue;
        }
        if let Err(e) = block.block.validate() {
            stats.error = Some(e.to_string());
            continue;
        }
        sim.initial += sim.spawn(block.block.lattice(), block.velocity);
    }
}

fn sph_emit(
    mut emitters: Query<&mut SphEmitter>,
    mut sim: ResMut<SphSimulation>,
    mut stats: ResMut<SphStats>,
) {
    if sim.container.is_none() {
        return;
    }
    let steps_taken = match sim.backend {
        SphBackend::Cpu => true,
        SphBackend::Gpu => device_is_stepping(
            &mut sim.emission_steps_seen,
            stats.step_count,
            stats.gpu_warming_up(),
        ),
    };
    if sim.plan.steps == 0 || !steps_taken {
        return;
    }
    let duration = sim.plan.duration;
    for mut emitter in &mut emitters {
        if let Err(e) = emitter.0.validate() {
            stats.error = Some(e.to_string());
            continue;
        }
        let emission = emitter.0.emit(duration);
        sim.emitted += sim.spawn(emission.positions, emission.velocity);
    }
}

/// Whether the GPU backend's emitters may emit for this frame's plan: the device has been seen
/// stepping (its step count, as read back, `step_count`, advanced since the last frame's look,
/// `seen`) and is not compiling shaders or preparing buffers (`warming_up`).
///
/// An emitter places a frame's discs ahead of its mouth on the assumption that the frame's steps
/// move the water emitted before on. The device takes no step while its shaders compile, for
/// more than ten frames at a start on a software driver: discs emitted for those frames landed
/// on top of each other, and PBF threw them apart at 10-25 m/s. The readback is a frame or two
/// late, so a settings change that compiles new shaders mid-run may still stack that many.
fn device_is_stepping(seen: &mut Option<u64>, step_count: u64, warming_up: bool) -> bool {
    let advanced = seen.is_some_and(|last| step_count > last);
    *seen = Some(step_count);
    advanced && !warming_up
}

/// This frame's plan: its steps and the simulated time they cover, from [`SphControl`], the
/// frame's [`Time`] delta in real-time mode and the time-step rule's dt as last known.
fn sph_plan_frame(
    time: Res<Time>,
    params: Res<SphParams>,
    control: Res<SphControl>,
    mut stats: ResMut<SphStats>,
    mut sim: ResMut<SphSimulation>,
    colliders: Query<&SphCollider, Without<SphRigidBody>>,
    forces: Option<Res<BodyForceReadback>>,
) {
    let valid = control.real_time.is_none_or(|r| r.validate().is_ok())
        && control.validate_body_frame_time().is_ok();
    sim.plan = if valid {
        let plan = sim.plan(&control, &params, &stats, time.delta_secs());
        // The GPU's body forces arrive a frame or two late: a frame covers little water time
        // while a body the device does not move floats (`crate::moved_bodies`).
        let bodies = colliders
            .iter()
            .any(|c| c.motion == sph_core::ColliderMotion::Dynamic);
        match control.max_body_frame_time {
            Some(most) if bodies && sim.backend == SphBackend::Gpu => {
                // This frame's number once planned (`sph_plan_step` counts it).
                let planned = sim.frame_number.wrapping_add(1);
                let newest = forces.as_ref().and_then(|f| f.newest_frame);
                // (A frame with nothing to do, paused, holds nothing.)
                if plan.steps > 0
                    && holds_for_body_forces(planned, newest, sim.frames_held_in_a_row)
                {
                    sim.frames_held_in_a_row += 1;
                    stats.frames_held_for_body_forces += 1;
                    FramePlan::default()
                } else {
                    sim.frames_held_in_a_row = 0;
                    plan.capped(most, sim.expected_dt(&params, &stats))
                }
            }
            _ => plan,
        }
    } else {
        // Refused (and named) by sph_plan_step; nothing moves this frame.
        FramePlan::default()
    };
}

fn sph_plan_step(
    params: Res<SphParams>,
    mut control: ResMut<SphControl>,
    mut sim: ResMut<SphSimulation>,
    mut stats: ResMut<SphStats>,
    walls: Query<(), With<SphWallForce>>,
) {
    let plan = sim.plan;
    control.single_step = false;
    let Some(container) = sim.container else {
        stats.error = Some(NO_CONTAINER.into());
        sim.frame.active = false;
        return;
    };
    let real_time = control
        .real_time
        .map_or(Ok(()), |r| r.validate())
        .and(control.validate_body_frame_time());
    if let Err(e) = params
        .validate()
        .and(control.rollback.validate())
        .and(real_time)
    {
        stats.error = Some(e.to_string());
        sim.frame.steps = 0;
        return;
    }
    match sim.backend {
        SphBackend::Cpu => {
            let Some(solver) = &mut sim.cpu else {
                return;
            };
            if *solver.params() != params.0 {
                if let Err(e) = solver.set_params(params.0) {
                    stats.error = Some(e.to_string());
                    return;
                }
            }
            if solver.rollback() != control.rollback {
                if let Err(e) = solver.set_rollback(control.rollback) {
                    stats.error = Some(e.to_string());
                    return;
                }
            }
            solver.reset_timings();
            let (mut density, mut most, mut divergence) = (0u64, 0u32, 0u64);
            let mut steps = 0;
            let mut record = |solver: &CpuSolver| {
                let s = solver.solver_stats();
                density += s.density_iterations as u64;
                most = most.max(s.density_iterations);
                divergence += s.divergence_iterations as u64;
            };
            match plan.budget {
                // As many steps as the rule needs, each recorded.
                Some(budget) => {
                    let cap = control
                        .real_time
                        .map_or(plan.steps, |r| r.max_steps.clamp(1, MAX_SUBSTEPS));
                    let end = solver.time() + budget as f64;
                    while steps < cap {
                        let left = (end - solver.time()) as f32;
                        if solver.advance_by(left, 1).steps == 0 {
                            break;
                        }
                        steps += 1;
                        record(solver);
                    }
                }
                None => {
                    for _ in 0..plan.steps {
                        solver.step();
                        steps += 1;
                        record(solver);
                    }
                }
            }
            stats.frame_steps = steps;
            if steps > 0 {
                stats.pressure_iterations_mean = density as f32 / steps as f32;
                stats.pressure_iterations_max = most;
                stats.divergence_iterations_mean = divergence as f32 / steps as f32;
            }
            // A refused collider or scene file stays reported while it is refused.
            stats.error = stats
                .collider_errors
                .first()
                .map(ToString::to_string)
                .or_else(|| stats.scene_error.clone());
        }
        SphBackend::Gpu => {
            if let Err(e) = sim.prepare_gpu_boundary(&container, &params.0) {
                stats.error = Some(e.to_string());
                sim.frame.steps = 0;
                return;
            }
            let capacity = sim.capacity;
            let dfsph_iterations = sim.dfsph_budget.encoded(&params.dfsph);
            sim.frame_number = sim.frame_number.wrapping_add(1);
            let number = sim.frame_number;
            let frame = &mut sim.frame;
            frame.active = true;
            frame.params = params.0;
            frame.container = container;
            frame.capacity = capacity;
            frame.steps = plan.steps;
            frame.budget = plan.budget.map(|b| (b, number));
            frame.number = number;
            frame.dfsph_iterations = dfsph_iterations;
            stats.frame_steps = plan.steps;
            // PBF's Jacobi iterations are a fixed count per step on the device; DFSPH's come
            // back with the clock (`sph_update_stats`).
            if params.solver != sph_core::Solver::Dfsph {
                let pbf = params.solver == sph_core::Solver::Pbf;
                let iterations = if pbf { params.pbf.iterations } else { 0 };
                stats.pressure_iterations_mean = iterations as f32;
                stats.pressure_iterations_max = iterations;
                stats.divergence_iterations_mean = 0.0;
            }
            frame.neighbor_counts = control.record_neighbor_counts;
            frame.rollback = control.rollback;
            frame.wall_force = !walls.is_empty();
        }
    }
}

/// DFSPH's iterations on the GPU: the means per step between the last two clock readings, and
/// the most of one step since the reset. (WCSPH and PBF leave both sums at 0.)
fn record_gpu_iterations(
    last: &mut Option<GpuIterations>,
    clock: &sph_core::gpu_layout::GpuClock,
    stats: &mut SphStats,
) {
    let now = GpuIterations {
        step: clock.step,
        density: clock.density_iterations,
        divergence: clock.divergence_iterations,
    };
    if now.density == 0 && now.divergence == 0 {
        *last = Some(now);
        return;
    }
    match *last {
        // A reset or a rollback takes the sums or the step back: start again.
        Some(before)
            if before.step < now.step
                && before.density <= now.density
                && before.divergence <= now.divergence =>
        {
            let steps = (now.step - before.step) as f32;
            stats.pressure_iterations_mean = (now.density - before.density) as f32 / steps;
            stats.divergence_iterations_mean = (now.divergence - before.divergence) as f32 / steps;
            stats.pressure_iterations_max = clock.density_iterations_max;
            *last = Some(now);
        }
        Some(before) if before == now => {}
        _ => *last = Some(now),
    }
}

/// Real time and simulated time at the start of the real-time factor's window [s].
#[derive(Default)]
struct FactorWindow(Option<(f64, f64)>);

/// The shortest window the real-time factor is measured over [s of real time].
const FACTOR_WINDOW: f64 = 0.5;

impl FactorWindow {
    /// The factor when the window is complete (and a new one starts), `None` before. Simulated
    /// time going back (a reset, a rollback) restarts the window.
    fn update(&mut self, real: f64, sim: f64) -> Option<f32> {
        let Some((real0, sim0)) = self.0 else {
            self.0 = Some((real, sim));
            return None;
        };
        if sim < sim0 {
            self.0 = Some((real, sim));
            return None;
        }
        if real - real0 < FACTOR_WINDOW {
            return None;
        }
        self.0 = Some((real, sim));
        Some(((sim - sim0) / (real - real0)) as f32)
    }
}

fn sph_update_stats(
    mut sim: ResMut<SphSimulation>,
    clock: Res<ClockReadback>,
    feedback: Option<Res<SphRenderFeedback>>,
    diagnostics: Option<Res<bevy::diagnostic::DiagnosticsStore>>,
    real: Res<Time<Real>>,
    mut window: Local<FactorWindow>,
    mut stats: ResMut<SphStats>,
) {
    let sim = &mut *sim;
    stats.backend = sim.backend;
    stats.adapter = sim.adapter.clone();
    stats.fallback_reason = sim.fallback_reason.clone();
    stats.capacity = sim.capacity;
    stats.particle_count = sim.particle_count;
    stats.refused_spawns = sim.refused;
    stats.spawns_inside_colliders = sim.inside_colliders;
    stats.particles_initial = sim.initial;
    stats.particles_emitted = sim.emitted;
    stats.particles_drained = sim.drained;
    match (sim.backend, &sim.cpu) {
        (SphBackend::Cpu, Some(solver)) => {
            stats.step_count = solver.step_count();
            stats.sim_time = solver.time();
            stats.time_step = solver.last_time_step();
            stats.clock_steps = solver.step_count();
            stats.clock_steps_run = solver.step_count();
            stats.rollbacks = solver.rollbacks();
            stats.boundary_corrections = solver.boundary_corrections();
            stats.wall_corrections = solver.corrections().walls;
            stats.boundary_samples = solver.boundary().len() as u32;
            stats.dispatches_per_step = 0;
            let d = solver.diagnostics();
            stats.health = match solver.unstable_step() {
                Some(step) => SphHealth::Unstable { step },
                None => SphHealth::of(&d, solver.step_count()),
            };
            stats.density_error_mean_pct = d.density_error_mean_pct;
            stats.diagnostics = Some(d);
            sim.rule_dt = Some(solver.next_time_step() * solver.time_step_scale());
            stats.stage_ms = solver
                .timings()
                .stages()
                .iter()
                .map(|(name, t)| (name.to_string(), t.as_secs_f64() * 1e3))
                .collect();
        }
        (SphBackend::Gpu, _) => {
            stats.boundary_samples = sim.gpu_boundary.as_ref().map_or(0, |b| b.len() as u32);
            if let Some(feedback) = &feedback {
                let f = feedback.get();
                stats.step_count = f.step_count;
                stats.dispatches_per_step = f.dispatches_per_step;
                stats.gpu_bytes_per_particle = f.gpu_bytes_per_particle;
                if let Some(status) = f.status {
                    stats.error = Some(status);
                } else if stats
                    .error
                    .as_deref()
                    .is_some_and(|e| e.starts_with("gpu:"))
                {
                    stats.error = None;
                }
            }
            if sim.frame.reset {
                stats.health = SphHealth::Unknown;
            }
            // A clock read before a reset counts more steps than were taken since: stale.
            if let Some(clock) = clock.latest.filter(|c| c.step as u64 <= stats.step_count) {
                stats.sim_time = clock.time();
                stats.time_step = clock.dt;
                stats.rollbacks = clock.rollbacks as u64;
                stats.boundary_corrections = clock.boundary_corrections as u64;
                stats.wall_corrections = clock.wall_corrections as u64;
                stats.neighbor_list_overflows = clock.neighbor_list_overflows as u64;
                stats.clock_steps = clock.step as u64;
                stats.clock_steps_run = clock.steps_run as u64;
                record_gpu_iterations(&mut sim.gpu_iterations, &clock, &mut stats);
                sim.dfsph_budget.observe(&clock, sim.frame.dfsph_iterations);
                stats.dfsph_solves_cut_short = clock.solves_cut_short();
                let scale = (-(clock.halvings as f32)).exp2();
                sim.rule_dt = Some(clock.rule_dt * scale);
                if clock.unstable_step != 0 {
                    stats.health = SphHealth::Unstable {
                        step: clock.unstable_step as u64,
                    };
                } else if clock.step > 0 && stats.health == SphHealth::Unknown {
                    stats.health = SphHealth::Ok;
                }
            }
            if let Some(store) = diagnostics {
                let names = feedback.map(|f| f.get().stage_names).unwrap_or_default();
                stats.stage_ms = names
                    .iter()
                    .filter_map(|name| {
                        let path = bevy::diagnostic::DiagnosticPath::new(format!(
                            "render/{name}/elapsed_gpu"
                        ));
                        store
                            .get(&path)
                            .and_then(|d| d.value())
                            .map(|ms| (name.to_string(), ms))
                    })
                    .collect();
            }
        }
        _ => {}
    }
    if let Some(factor) = window.update(real.elapsed_secs_f64(), stats.sim_time) {
        stats.real_time_factor = factor;
    }
}

#[cfg(test)]
mod tests {
    use super::device_is_stepping;

    #[test]
    fn gpu_emitters_emit_once_the_device_is_seen_stepping() {
        let mut seen = None;
        // A start: nothing seen yet, then shaders compiling.
        assert!(!device_is_stepping(&mut seen, 0, false));
        assert!(!device_is_stepping(&mut seen, 0, true));
        // The first steps are read back, but the status still says compiling.
        assert!(!device_is_stepping(&mut seen, 2, true));
        assert!(device_is_stepping(&mut seen, 4, false));
        // Paused, or the steps skipped: the count stands still.
        assert!(!device_is_stepping(&mut seen, 4, false));
        assert!(device_is_stepping(&mut seen, 6, false));
        // A reset: the count starts again, and must advance from there.
        assert!(!device_is_stepping(&mut seen, 0, false));
        assert!(device_is_stepping(&mut seen, 2, false));
    }
}

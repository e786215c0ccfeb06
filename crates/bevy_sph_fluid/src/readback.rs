//! On-demand readback: a [`SphReadbackRequest`] becomes a [`SphSnapshot`]. On the GPU backend the
//! state buffers are copied by Bevy's asynchronous `Readback` (never stalling a frame); on the CPU
//! backend the solver's arrays are copied.

use crate::api::*;
use crate::sets::SphSystems;
use crate::shared::{BodyForceReadback, ClockReadback, ProbeReadback, SphSimulation};
use bevy::ecs::schedule::InternedScheduleLabel;
use bevy::prelude::*;
use bevy::render::gpu_readback::{Readback, ReadbackComplete};
use sph_core::gpu_layout::{w_to_id, GpuBodyForces, GpuClock, GpuProbes};

/// Which state buffer a readback entity copies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Part {
    Position = 0,
    Velocity = 1,
    Acceleration = 2,
    Density = 3,
    Pressure = 4,
    NeighborCount = 5,
}

/// Readbacks in flight: the bytes of each part as they arrive.
#[derive(Resource, Default)]
struct PendingReadback {
    parts: [Option<Vec<u8>>; 6],
    /// Whether the neighbour counts were asked for too.
    with_neighbor_counts: bool,
    in_flight: bool,
    step: u64,
}

pub(crate) fn add_systems(app: &mut App, schedule: InternedScheduleLabel) {
    app.init_resource::<PendingReadback>()
        .init_resource::<ClockReadback>()
        .init_resource::<BodyForceReadback>()
        .init_resource::<ProbeReadback>()
        .add_systems(
            schedule,
            (
                sph_request_readback,
                sph_deliver_snapshot,
                sph_read_every_frame::<ClockReadback>,
                sph_read_every_frame::<BodyForceReadback>,
                sph_read_every_frame::<ProbeReadback>,
            )
                .chain()
                .in_set(SphSystems::Writeback),
        );
}

/// The readback entity of a small GPU buffer that is read every frame, and its buffer.
type ReadbackSource = Option<(Handle<bevy::render::storage::ShaderBuffer>, Entity)>;

/// A small GPU buffer read back every frame into a resource: the clock, the body forces and the
/// probes.
trait EveryFrame: Resource<Mutability = bevy::ecs::component::Mutable> {
    /// The buffer's contents.
    type Value: bytemuck::Pod;
    /// The buffer among the state buffers.
    fn buffer(buffers: &SphGpuBuffers) -> &Handle<bevy::render::storage::ShaderBuffer>;
    /// The reader in place.
    fn source(&mut self) -> &mut ReadbackSource;
    /// Forgets the last value (a new buffer).
    fn clear(&mut self);
    /// Takes an arrived value.
    fn arrived(&mut self, value: Self::Value);
}

impl EveryFrame for ClockReadback {
    type Value = GpuClock;
    fn buffer(buffers: &SphGpuBuffers) -> &Handle<bevy::render::storage::ShaderBuffer> {
        &buffers.clock
    }
    fn source(&mut self) -> &mut ReadbackSource {
        &mut self.source
    }
    fn clear(&mut self) {
        self.latest = None;
    }
    fn arrived(&mut self, clock: GpuClock) {
        self.latest = Some(clock);
    }
}

impl EveryFrame for BodyForceReadback {
    type Value = GpuBodyForces;
    fn buffer(buffers: &SphGpuBuffers) -> &Handle<bevy::render::storage::ShaderBuffer> {
        &buffers.body_forces
    }
    fn source(&mut self) -> &mut ReadbackSource {
        &mut self.source
    }
    fn clear(&mut self) {
        self.latest = None;
        self.newest_frame = None;
    }
    fn arrived(&mut self, sums: GpuBodyForces) {
        // A frame without steps leaves the last forces in place, but its stamp says they are
        // still the newest (0: a buffer no frame has stamped yet).
        if sums.frame != 0
            && self
                .newest_frame
                .is_none_or(|newest| (sums.frame.wrapping_sub(newest) as i32) > 0)
        {
            self.newest_frame = Some(sums.frame);
        }
        if sums.evaluations > 0 {
            self.latest = Some(sums);
        }
    }
}

impl EveryFrame for ProbeReadback {
    type Value = GpuProbes;
    fn buffer(buffers: &SphGpuBuffers) -> &Handle<bevy::render::storage::ShaderBuffer> {
        &buffers.probes
    }
    fn source(&mut self) -> &mut ReadbackSource {
        &mut self.source
    }
    fn clear(&mut self) {
        self.latest = None;
    }
    fn arrived(&mut self, sums: GpuProbes) {
        // A frame without steps (or without probes) has nothing to report.
        if sums.samples > 0 && sums.count > 0 {
            self.latest = Some(sums);
        }
    }
}

/// Keeps one `Readback` of `R`'s current buffer alive (GPU backend): when the buffer changes,
/// the old reader goes and a new one delivers every arrival to `R`.
fn sph_read_every_frame<R: EveryFrame>(
    sim: Res<SphSimulation>,
    mut target: ResMut<R>,
    mut commands: Commands,
) {
    let Some(buffers) = sim
        .frame
        .buffers
        .as_ref()
        .filter(|_| sim.backend == SphBackend::Gpu)
    else {
        return;
    };
    let handle = R::buffer(buffers);
    let source = target.source();
    if source.as_ref().is_some_and(|(h, _)| h == handle) {
        return;
    }
    if let Some((_, entity)) = source.take() {
        commands.entity(entity).despawn();
    }
    let reader = commands
        .spawn(Readback::buffer(handle.clone()))
        .observe(|event: On<ReadbackComplete>, mut target: ResMut<R>| {
            let size = std::mem::size_of::<R::Value>();
            if event.data.len() >= size {
                target.arrived(bytemuck::pod_read_unaligned(&event.data[..size]));
            }
        })
        .id();
    *target.source() = Some((handle.clone(), reader));
    target.clear();
}

fn sph_request_readback(
    mut requests: MessageReader<SphReadbackRequest>,
    sim: Res<SphSimulation>,
    mut stats: ResMut<SphStats>,
    mut pending: ResMut<PendingReadback>,
    mut snapshots: MessageWriter<SphSnapshot>,
    mut commands: Commands,
) {
    if requests.read().count() == 0 {
        return;
    }
    match sim.backend {
        SphBackend::Cpu => {
            let snapshot = sim
                .cpu
                .as_ref()
                .map(|solver| {
                    let p = solver.particles();
                    SphSnapshot {
                        step: solver.step_count(),
                        ids: p.id.clone(),
                        positions: p.position.clone(),
                        velocities: p.velocity.clone(),
                        accelerations: p.acceleration.clone(),
                        densities: p.density.clone(),
                        pressures: p.pressure.clone(),
                        neighbor_counts: None,
                    }
                })
                .unwrap_or_default();
            snapshots.write(snapshot);
        }
        SphBackend::Gpu => {
            let count = sim.particle_count as u64;
            let buffers = sim.frame.buffers.as_ref();
            if count == 0 || buffers.is_none() {
                snapshots.write(SphSnapshot {
                    step: stats.step_count,
                    ..default()
                });
                return;
            }
            if pending.in_flight {
                stats.snapshot_requests_dropped += 1;
                return;
            }
            let Some(buffers) = buffers else { return };
            // The copy is taken after this frame's steps.
            let with_neighbor_counts = sim.frame.neighbor_counts;
            *pending = PendingReadback {
                in_flight: true,
                with_neighbor_counts,
                step: stats.step_count + sim.frame.steps as u64,
                ..default()
            };
            for (part, handle, stride) in [
                (Part::Position, &buffers.position, 16),
                (Part::Velocity, &buffers.velocity, 16),
                (Part::Acceleration, &buffers.acceleration, 16),
                (Part::Density, &buffers.density, 4),
                (Part::Pressure, &buffers.pressure, 4),
                (Part::NeighborCount, &buffers.neighbor_count, 4),
            ] {
                if part == Part::NeighborCount && !with_neighbor_counts {
                    continue;
                }
                commands
                    .spawn(Readback::buffer_range(handle.clone(), 0, count * stride))
                    .observe(
                        move |event: On<ReadbackComplete>,
                              mut pending: ResMut<PendingReadback>,
                              mut commands: Commands| {
                            pending.parts[part as usize] = Some(event.data.clone());
                            commands.entity(event.entity).despawn();
                        },
                    );
            }
        }
    }
}

fn sph_deliver_snapshot(
    mut pending: ResMut<PendingReadback>,
    mut snapshots: MessageWriter<SphSnapshot>,
    sim: Res<SphSimulation>,
    mut stats: ResMut<SphStats>,
) {
    let needed = if pending.with_neighbor_counts { 6 } else { 5 };
    if !pending.in_flight || pending.parts[..needed].iter().any(Option::is_none) {
        return;
    }
    let [Some(position), Some(velocity), Some(acceleration), Some(density), Some(pressure), neighbor_counts] =
        std::mem::take(&mut pending.parts)
    else {
        return;
    };
    pending.in_flight = false;
    let position: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&position);
    let velocity: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&velocity);
    let acceleration: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&acceleration);
    let xyz = |v: &[f32; 4]| Vec3::new(v[0], v[1], v[2]);
    let snapshot = SphSnapshot {
        step: pending.step,
        ids: position.iter().map(|p| w_to_id(p[3])).collect(),
        positions: position.iter().map(xyz).collect(),
        velocities: velocity.iter().map(xyz).collect(),
        accelerations: acceleration.iter().map(xyz).collect(),
        densities: bytemuck::pod_collect_to_vec(&density),
        pressures: bytemuck::pod_collect_to_vec(&pressure),
        neighbor_counts: neighbor_counts.map(|bytes| bytemuck::pod_collect_to_vec(&bytes)),
    };
    // The GPU backend measures health on readback. With rollback on, non-finite values are the
    // clock's to judge: a snapshot may catch an unstable step that the next step's time-step
    // pass rolls back.
    if let Some(container) = sim.container {
        let d = snapshot.diagnostics(&sim.frame.params, &container);
        let transient = sim.frame.rollback.enabled && d.non_finite_count > 0;
        if !stats.health.is_unstable() && !transient {
            stats.health = SphHealth::of(&d, pending.step);
        }
        stats.density_error_mean_pct = d.density_error_mean_pct;
        stats.diagnostics = Some(d);
    }
    snapshots.write(snapshot);
}

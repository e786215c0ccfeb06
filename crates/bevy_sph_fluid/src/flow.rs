//! Drains, pumps and probes as components, placed by the entity's [`GlobalTransform`]: what
//! moves water around an Aquaplay-style level and what game logic reads from it.
//!
//! - [`SphSink`]: removes the particles inside its box while open, and counts them
//!   ([`SphStats::particles_drained`]); the balance initial + emitted − drained = live holds at
//!   every frame ([`SphStats::particle_balance`]).
//! - [`SphPump`]: pushes the water inside its box along a direction toward a target speed
//!   ([`sph_core::flow::pump`]), every step.
//! - [`SphProbe`]: the water level, the flux through a rectangle or the particles in a box,
//!   sent as [`SphProbeReading`] messages every `every_steps` steps.
//!
//! Pumps and probes run on both backends. The GPU applies up to 16 pumps in its closing kicks,
//! and sums up to 16 probes there too, over each frame's steps (level: the highest; flux and
//! count: the mean), read back a frame or two later without a stall. Drains run on both: the
//! CPU removes the particles after the frame's steps; the GPU marks them at every step's sort
//! and sorts them to the tail of the live range, where nothing sees them, and the live count
//! drops by the tail read back a frame or two later (docs/scenes.md). Drains share the GPU's
//! 16 pump slots.

use crate::api::*;
use crate::sets::SphSystems;
use crate::shared::{ProbeReadback, SphSimulation};
use bevy::ecs::schedule::InternedScheduleLabel;
use bevy::prelude::*;
use sph_core::{Pose, ProbeKind, ProbeReading, Pump, Region, Sink};
use std::collections::{HashMap, VecDeque};

/// A drain: while `open`, every particle inside the box of `half_extents` (in the entity's
/// frame, scaled by its transform) is removed and counted.
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component)]
#[require(Transform)]
pub struct SphSink {
    /// Half extents of the box [m], > 0.
    pub half_extents: Vec3,
    /// Whether it drains.
    pub open: bool,
}

/// A pump: inside the box of `half_extents`, the water's velocity along `direction` (in the
/// entity's frame) relaxes toward `speed` at the rate `strength` (see [`sph_core::flow::pump`]).
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component)]
#[require(Transform)]
pub struct SphPump {
    /// Half extents of the box [m], > 0.
    pub half_extents: Vec3,
    /// The direction it pushes in, in the entity's frame (not zero).
    pub direction: Vec3,
    /// Target speed [m/s], 0 ..= 100.
    pub speed: f32,
    /// Relaxation rate [1/s], 0 (off) ..= 1000: the control a crank turns.
    pub strength: f32,
}

/// What a probe measures, in the entity's frame.
#[derive(Clone, Copy, Debug, PartialEq, Reflect)]
pub enum SphProbeKind {
    /// The water level [m, world y] of the vertical column through the entity's position: the
    /// free surface of the connected water under it, spray over an air gap left out
    /// ([`sph_core::flow::probe`] has the definition).
    Level {
        /// The column's radius [m] (> 0; about two spacings).
        radius: f32,
    },
    /// The flux [m³/s] through a rectangle centred on the entity, spanning ±`half_size` along
    /// its local x and y, counted along its local z.
    Flux {
        /// Half width and half height [m].
        half_size: Vec2,
    },
    /// The particles in the box of `half_extents`.
    Count {
        /// Half extents [m].
        half_extents: Vec3,
    },
}

/// A probe: measured every `every_steps` steps and sent as [`SphProbeReading`].
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component)]
#[require(Transform)]
pub struct SphProbe {
    /// What it measures.
    pub kind: SphProbeKind,
    /// Steps between readings (≥ 1); a frame sends at most one reading per probe.
    pub every_steps: u32,
}

/// A probe's measurement.
#[derive(Message, Clone, Copy, Debug, PartialEq)]
pub struct SphProbeReading {
    /// The entity carrying the [`SphProbe`].
    pub probe: Entity,
    /// The step the reading was taken after.
    pub step: u64,
    /// The simulated time [s].
    pub sim_time: f64,
    /// The measurement.
    pub reading: ProbeReading,
}

/// The transform that places a device at `pose`.
fn transform_of(pose: Pose) -> Transform {
    Transform::from_translation(pose.translation).with_rotation(pose.rotation)
}

fn pose_of(transform: &GlobalTransform) -> (Pose, Vec3) {
    let (scale, rotation, translation) = transform.to_scale_rotation_translation();
    (
        Pose {
            translation,
            rotation,
        },
        scale.abs(),
    )
}

impl SphSink {
    /// The component and the transform that place `sink` (the inverse of [`Self::placed`]).
    pub fn from_world(sink: &Sink) -> (Self, Transform) {
        (
            Self {
                half_extents: sink.region.half_extents,
                open: sink.open,
            },
            transform_of(sink.region.pose),
        )
    }

    /// The drain in the world.
    pub fn placed(&self, transform: &GlobalTransform) -> Sink {
        let (pose, scale) = pose_of(transform);
        Sink {
            region: Region {
                pose,
                half_extents: self.half_extents * scale,
            },
            open: self.open,
        }
    }
}

impl SphPump {
    /// The component and the transform that place `pump` (the inverse of [`Self::placed`]).
    pub fn from_world(pump: &Pump) -> (Self, Transform) {
        let pose = pump.region.pose;
        (
            Self {
                half_extents: pump.region.half_extents,
                direction: pose.rotation.inverse() * pump.direction,
                speed: pump.speed,
                strength: pump.strength,
            },
            transform_of(pose),
        )
    }

    /// The pump in the world.
    pub fn placed(&self, transform: &GlobalTransform) -> Pump {
        let (pose, scale) = pose_of(transform);
        Pump {
            region: Region {
                pose,
                half_extents: self.half_extents * scale,
            },
            direction: pose.rotation * self.direction,
            speed: self.speed,
            strength: self.strength,
        }
    }
}

impl SphProbe {
    /// The component and the transform that place a probe measuring `kind` every
    /// `every_steps` steps (the inverse of [`Self::placed`]).
    pub fn from_world(kind: &ProbeKind, every_steps: u32) -> (Self, Transform) {
        let (kind, pose) = match *kind {
            ProbeKind::Level { x, z, radius } => (
                SphProbeKind::Level { radius },
                Pose {
                    translation: Vec3::new(x, 0.0, z),
                    ..default()
                },
            ),
            ProbeKind::Flux { pose, half_size } => (
                SphProbeKind::Flux {
                    half_size: Vec2::from(half_size),
                },
                pose,
            ),
            ProbeKind::Count { region } => (
                SphProbeKind::Count {
                    half_extents: region.half_extents,
                },
                region.pose,
            ),
        };
        (Self { kind, every_steps }, transform_of(pose))
    }

    /// Checks `every_steps` (≥ 1).
    pub fn validate_every_steps(&self) -> Result<(), sph_core::ParamError> {
        if self.every_steps == 0 {
            return Err(sph_core::ParamError {
                field: "SphProbe::every_steps",
                value: "0".into(),
                allowed: ">= 1 step",
            });
        }
        Ok(())
    }

    /// What the probe measures, in the world.
    pub fn placed(&self, transform: &GlobalTransform) -> ProbeKind {
        let (pose, scale) = pose_of(transform);
        match self.kind {
            SphProbeKind::Level { radius } => ProbeKind::Level {
                x: pose.translation.x,
                z: pose.translation.z,
                radius,
            },
            SphProbeKind::Flux { half_size } => ProbeKind::Flux {
                pose,
                half_size: [half_size.x * scale.x, half_size.y * scale.y],
            },
            SphProbeKind::Count { half_extents } => ProbeKind::Count {
                region: Region {
                    pose,
                    half_extents: half_extents * scale,
                },
            },
        }
    }
}

pub(crate) fn add_systems(app: &mut App, schedule: InternedScheduleLabel) {
    app.register_type::<SphSink>()
        .register_type::<SphPump>()
        .register_type::<SphProbe>()
        .add_message::<SphProbeReading>()
        .init_resource::<GpuProbeFrames>()
        .add_systems(
            schedule,
            (
                sph_sync_pumps.in_set(SphSystems::Prepare),
                (sph_drain, sph_plan_gpu_probes)
                    .in_set(SphSystems::Step)
                    .after(crate::simulation::StepSystem),
                (sph_measure_probes, sph_deliver_gpu_probes).in_set(SphSystems::Writeback),
            ),
        );
}

/// Puts `message` in [`SphStats::flow_error`] and the log (once while it stays the same).
fn report(stats: &mut SphStats, message: String) {
    if stats.flow_error.as_deref() != Some(&message) {
        warn!("SphFluidPlugin: {message}");
    }
    stats.flow_error = Some(message);
}

/// Names a refused device.
fn refuse(stats: &mut SphStats, what: &str, entity: Entity, e: sph_core::ParamError) {
    report(stats, format!("{what} {entity}: {e}; it is left out"));
}

/// Hands the pumps to the CPU solver before the frame's steps.
fn sph_sync_pumps(
    pumps: Query<(Entity, &SphPump, &GlobalTransform)>,
    mut sim: ResMut<SphSimulation>,
    mut stats: ResMut<SphStats>,
) {
    let mut placed = Vec::new();
    let mut refused = None;
    for (entity, pump, transform) in &pumps {
        let p = pump.placed(transform);
        match p.validate() {
            Ok(()) => placed.push(p),
            Err(e) => refused = Some((entity, e)),
        }
    }
    if let Some((entity, e)) = refused {
        refuse(&mut stats, "SphPump", entity, e);
    }
    match (sim.backend, &mut sim.cpu) {
        // Validated above, so setting them cannot fail.
        (SphBackend::Cpu, Some(solver)) if solver.pumps() != placed.as_slice() => {
            let _ = solver.set_pumps(&placed);
        }
        (SphBackend::Gpu, _) => {
            let most = sph_core::gpu_layout::MAX_GPU_PUMPS;
            if placed.len() > most {
                report(
                    &mut stats,
                    format!(
                        "{} SphPump entities: the GPU applies the first {most}",
                        placed.len()
                    ),
                );
            }
            sim.frame.pumps = placed;
        }
        _ => {}
    }
}

/// Removes the particles inside open drains after the frame's steps, and counts them (a paused
/// frame drains nothing). On the GPU the device marks the particles inside open drains and
/// sorts them to the tail of the live range; the count drops by the tail's size read back
/// (`lower_gpu_count`).
fn sph_drain(
    sinks: Query<(Entity, &SphSink, &GlobalTransform)>,
    clock: Option<Res<crate::shared::ClockReadback>>,
    mut sim: ResMut<SphSimulation>,
    mut stats: ResMut<SphStats>,
) {
    let mut placed = Vec::new();
    for (entity, sink, transform) in &sinks {
        let s = sink.placed(transform);
        match s.validate() {
            Ok(()) => placed.push(s),
            Err(e) => refuse(&mut stats, "SphSink", entity, e),
        }
    }
    let sim = &mut *sim;
    match (sim.backend, &mut sim.cpu) {
        (SphBackend::Cpu, Some(solver)) => {
            if placed.is_empty() || sim.plan.steps == 0 {
                return;
            }
            let drained = solver.drain(&placed) as u32;
            sim.drained += drained as u64;
            sim.particle_count = sim.particle_count.saturating_sub(drained);
        }
        (SphBackend::Gpu, _) => {
            let (_, left_out) =
                sph_core::gpu_layout::GpuPumps::with_sinks(&sim.frame.pumps, &placed);
            if left_out > 0 {
                report(
                    &mut stats,
                    format!(
                        "SphSink: {left_out} open drains found no slot on the GPU (pumps and \
                         drains share {} slots); they are left out",
                        sph_core::gpu_layout::MAX_GPU_PUMPS
                    ),
                );
            }
            sim.frame.sinks = placed.into_iter().filter(|s| s.open).collect();
            lower_gpu_count(sim, clock.and_then(|c| c.latest));
        }
        _ => {}
    }
}

/// The GPU backend's drains, in the main world: the live count drops by the drained
/// particles the device sorted to the tail, from a clock read at a sort that came after the
/// last spawns were uploaded (they would follow the tail) and after the last drop (its tail is
/// gone). Marked particles only add up between sorts, so the last `tail_size` slots are all
/// drained; the next spawns overwrite them. A reset starts again.
fn lower_gpu_count(sim: &mut SphSimulation, clock: Option<sph_core::gpu_layout::GpuClock>) {
    let number = sim.frame.number;
    let sync = &mut sim.gpu_drains;
    if sim.frame.reset {
        sync.lowered_from = number;
    }
    if !sim.frame.spawn_positions.is_empty() {
        sync.last_spawn_frame = number;
    }
    let Some(clock) = clock else {
        return;
    };
    if clock.tail_size == 0
        || clock.tail_frame < sync.last_spawn_frame
        || clock.tail_frame < sync.lowered_from
    {
        return;
    }
    let dropped = clock.tail_size.min(sim.particle_count);
    sim.particle_count -= dropped;
    sim.drained += dropped as u64;
    // The drop takes effect with the next frame's spawn offset.
    sync.lowered_from = number.wrapping_add(1);
}

/// Measures the probes that are due and sends their readings.
fn sph_measure_probes(
    probes: Query<(Entity, &SphProbe, &GlobalTransform)>,
    sim: Res<SphSimulation>,
    mut stats: ResMut<SphStats>,
    mut last: Local<HashMap<Entity, u64>>,
    mut readings: MessageWriter<SphProbeReading>,
) {
    if probes.is_empty() {
        return;
    }
    let Some(solver) = sim.cpu.as_ref().filter(|_| sim.backend == SphBackend::Cpu) else {
        return;
    };
    let step = solver.step_count();
    last.retain(|entity, _| probes.contains(*entity));
    let p = solver.particles();
    for (entity, probe, transform) in &probes {
        let kind = probe.placed(transform);
        if let Err(e) = kind.validate() {
            refuse(&mut stats, "SphProbe", entity, e);
            continue;
        }
        if let Err(e) = probe.validate_every_steps() {
            refuse(&mut stats, "SphProbe", entity, e);
            continue;
        }
        if !due(last.get(&entity).copied(), probe.every_steps, step) {
            continue;
        }
        last.insert(entity, step);
        readings.write(SphProbeReading {
            probe: entity,
            step,
            sim_time: solver.time(),
            reading: kind.measure(
                solver.params(),
                solver.container(),
                &p.position,
                &p.velocity,
            ),
        });
    }
}

/// Whether a probe last read at step `last` is due at `step` (a reset or a rollback takes the
/// step count back: it is due again).
fn due(last: Option<u64>, every_steps: u32, step: u64) -> bool {
    match last {
        Some(at) => step < at || step >= at + every_steps as u64,
        None => true,
    }
}

/// The GPU backend's probe entities per frame number, for the readbacks that arrive a frame or
/// two later.
#[derive(Resource, Default)]
struct GpuProbeFrames(VecDeque<(u32, Vec<Entity>)>);

/// Frames of probe entities kept for late readbacks.
const PROBE_FRAMES_KEPT: usize = 8;

/// Puts the valid probes into the GPU frame's plan (at most
/// [`sph_core::gpu_layout::MAX_GPU_PROBES`]), remembering which entity each slot is.
fn sph_plan_gpu_probes(
    probes: Query<(Entity, &SphProbe, &GlobalTransform)>,
    mut sim: ResMut<SphSimulation>,
    mut frames: ResMut<GpuProbeFrames>,
    mut stats: ResMut<SphStats>,
) {
    if sim.backend != SphBackend::Gpu {
        return;
    }
    let mut kinds = Vec::new();
    let mut entities = Vec::new();
    let mut placed: Vec<_> = probes.iter().collect();
    placed.sort_by_key(|(entity, _, _)| *entity);
    for (entity, probe, transform) in placed {
        let kind = probe.placed(transform);
        match kind.validate().and(probe.validate_every_steps()) {
            Ok(()) => {
                kinds.push(kind);
                entities.push(entity);
            }
            Err(e) => refuse(&mut stats, "SphProbe", entity, e),
        }
    }
    let most = sph_core::gpu_layout::MAX_GPU_PROBES;
    if kinds.len() > most {
        report(
            &mut stats,
            format!(
                "{} SphProbe entities: the GPU measures the first {most}",
                kinds.len()
            ),
        );
        kinds.truncate(most);
        entities.truncate(most);
    }
    let number = sim.frame_number;
    sim.frame.probes = kinds;
    if frames.0.back().is_none_or(|(n, _)| *n != number) {
        frames.0.push_back((number, entities));
        while frames.0.len() > PROBE_FRAMES_KEPT {
            frames.0.pop_front();
        }
    }
}

/// Turns the probes' sums as read back (GPU backend) into readings of the probes that are due.
fn sph_deliver_gpu_probes(
    mut readback: ResMut<ProbeReadback>,
    frames: Res<GpuProbeFrames>,
    probes: Query<&SphProbe>,
    params: Res<SphParams>,
    mut last: Local<HashMap<Entity, u64>>,
    mut readings: MessageWriter<SphProbeReading>,
) {
    let Some(sums) = readback.latest.take() else {
        return;
    };
    let Some((_, entities)) = frames.0.iter().find(|(n, _)| *n == sums.frame) else {
        return;
    };
    let step = sums.step as u64;
    last.retain(|entity, _| probes.contains(*entity));
    for (k, &entity) in entities.iter().enumerate() {
        let Ok(probe) = probes.get(entity) else {
            continue;
        };
        if !due(last.get(&entity).copied(), probe.every_steps, step) {
            continue;
        }
        if let Some(reading) = sums.reading(k, &params) {
            last.insert(entity, step);
            readings.write(SphProbeReading {
                probe: entity,
                step,
                sim_time: sums.time(),
                reading,
            });
        }
    }
}

//! Drains, pumps and probes as components, placed by the entity's [`GlobalTransform`]: what
//! moves water around an Aquaplay-style level and what game logic reads from it.
//!
//! - [`SphSink`]: removes the particles inside its box while open, and counts them
//!   ([`SphStats::particles_drained`]); the balance initial + emitted − drained = live holds at
//!   every frame ([`SphStats::particle_balance`]).
//! - [`SphPump`]: pushes the water inside its box along a direction toward a target speed
//!   ([`sph_core::pump`]), every step.
//! - [`SphProbe`]: the water level, the flux through a rectangle or the particles in a box,
//!   sent as [`SphProbeReading`] messages every `every_steps` steps.
//!
//! Pumps run on both backends (the GPU applies up to 16 in its closing kicks). Drains and probes
//! run on the CPU backend; on the GPU backend their passes are not built yet, which is logged
//! once and reported in [`SphStats::flow_error`] (the simulation goes on without them).

use crate::api::*;
use crate::sets::SphSystems;
use crate::shared::SphSimulation;
use bevy::ecs::schedule::InternedScheduleLabel;
use bevy::prelude::*;
use sph_core::{Pose, ProbeKind, ProbeReading, Pump, Region, Sink};
use std::collections::HashMap;

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
/// entity's frame) relaxes toward `speed` at the rate `strength` (see [`sph_core::pump`]).
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
    /// The water level [m, world y] of the vertical column through the entity's position.
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
            Transform::from_translation(pose.translation).with_rotation(pose.rotation),
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
        .add_systems(
            schedule,
            (
                sph_sync_pumps.in_set(SphSystems::Prepare),
                sph_drain
                    .in_set(SphSystems::Step)
                    .after(crate::simulation::StepSystem),
                sph_measure_probes.in_set(SphSystems::Writeback),
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

/// Names a device whose GPU pass does not exist yet.
fn gpu_not_built(stats: &mut SphStats, what: &str) {
    report(
        stats,
        format!("{what} runs on the CPU backend only (SphBackend::Cpu): its GPU pass is not built yet; the simulation goes on without it"),
    );
}

/// Removes the particles inside open drains after the frame's steps, and counts them (a paused
/// frame drains nothing).
fn sph_drain(
    sinks: Query<(Entity, &SphSink, &GlobalTransform)>,
    mut sim: ResMut<SphSimulation>,
    mut stats: ResMut<SphStats>,
) {
    if sinks.is_empty() || sim.plan.steps == 0 {
        return;
    }
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
            let drained = solver.drain(&placed) as u32;
            sim.drained += drained as u64;
            sim.particle_count = sim.particle_count.saturating_sub(drained);
        }
        (SphBackend::Gpu, _) => gpu_not_built(&mut stats, "SphSink"),
        _ => {}
    }
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
        if sim.backend == SphBackend::Gpu {
            gpu_not_built(&mut stats, "SphProbe");
        }
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
        if probe.every_steps == 0 {
            let e = sph_core::ParamError {
                field: "SphProbe::every_steps",
                value: "0".into(),
                allowed: ">= 1 step",
            };
            refuse(&mut stats, "SphProbe", entity, e);
            continue;
        }
        let due = match last.get(&entity) {
            // A reset or a rollback takes the step count back: measure again.
            Some(&at) => step < at || step >= at + probe.every_steps as u64,
            None => true,
        };
        if !due {
            continue;
        }
        last.insert(entity, step);
        readings.write(SphProbeReading {
            probe: entity,
            step,
            sim_time: solver.time(),
            reading: kind.measure(solver.params(), &p.position, &p.velocity),
        });
    }
}

//! The bodies the device moves, main-world side (GPU backend; the device's side is
//! `render::bodies`, the rule `sph_core::bodies::engine_handoff`). A dynamic [`SphCollider`] with
//! an [`SphRigidBody`] in one of the first [`GPU_MOVED_BODIES`] collider slots is moved by the
//! device at every water step. Every frame this module
//! - hands the device each body's model and the engine's state at the frame the engine reached
//!   ([`SphMovedBodies::engine_frame`]), and the pose its boundary samples are sorted at: the
//!   newest record carried on to the frame at its velocity, so that the device moves them a
//!   small part of h from there;
//! - reads the device's records back and sets the engine's next window
//!   ([`SphMovedBodies::window`]): the frames read back since the engine's frame, their water
//!   time and each body's water impulse over them, with when in them it came. The engine steps
//!   its bodies over exactly that time with that impulse, closes the gap to the device's steps
//!   (`sph_core::bodies::engine_window`), then calls [`SphMovedBodies::engine_stepped`]
//!   (`crate::avian_coupling` does all three for avian bodies).
//!
//! Without such a body nothing here runs on the device and no buffer is made.

use crate::api::*;
use crate::colliders::SphColliderMap;
use crate::sets::SphSystems;
use crate::shared::{GpuBodiesFrame, SphSimulation};
use bevy::ecs::schedule::InternedScheduleLabel;
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use bevy::render::gpu_readback::{Readback, ReadbackComplete};
use bevy::render::storage::ShaderBuffer;
use sph_core::bodies::engine_handoff::{after, EngineState, FrameRecord, RECORDS};
use sph_core::bodies::engine_push::EnginePush;
use sph_core::bodies::engine_window::WindowImpulse;
use sph_core::bodies::rigid_step::{rotate, turned, Hinge, RigidBodyModel};
use sph_core::gpu_layout::{GpuBodyInput, GpuBodyStates, GPU_MOVED_BODIES};
use sph_core::{ColliderMotion, Pose};

/// What the engine steps its moved bodies over next: the frames the device recorded after the
/// engine's frame, up to `to_frame`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EngineWindow {
    /// The frame the engine's bodies reach.
    pub to_frame: u32,
    /// The water's time at that frame's end [ns].
    pub time_ns: u64,
    /// The water time the window covers [s]: what the engine steps.
    pub seconds: f64,
    /// Each moved body's water impulse and angular impulse (about its centre of mass) over the
    /// window, and when in it they came, by collider slot; `None` when some of its frames were
    /// no longer recorded: the engine then takes the body's newest record whole
    /// ([`Self::newest`]).
    pub impulses: HashMap<u32, Option<WindowImpulse>>,
    /// Each moved body's record of `to_frame`, by collider slot.
    pub newest: HashMap<u32, FrameRecord>,
}

impl EngineWindow {
    /// `slot`'s water impulse over the window when the device's steps cover the water time the
    /// engine steps (within 0.1 ms); `None` otherwise, or when some of its frames were lost.
    pub fn covered_impulse(&self, slot: u32) -> Option<WindowImpulse> {
        let impulse = (*self.impulses.get(&slot)?)?;
        ((impulse.duration as f64 - self.seconds).abs() <= 1e-4).then_some(impulse)
    }
}

/// The moved bodies' bookkeeping.
#[derive(Resource, Default)]
pub struct SphMovedBodies {
    /// The main world's copy of the device's states (made with the first moved body).
    pub states: Option<Handle<ShaderBuffer>>,
    /// The readback of `states`.
    reader: Option<Entity>,
    /// The states as last read back.
    pub latest: Option<Box<GpuBodyStates>>,
    /// The frame whose end the engine's bodies are at (`None` before the first moved body).
    pub engine_frame: Option<u32>,
    /// The water's time at that frame's end [ns] (`None` until known).
    pub engine_time_ns: Option<u64>,
    /// What the engine steps next (`None`: nothing new was read back; the engine waits).
    pub window: Option<EngineWindow>,
    /// The moved bodies of this frame: their collider slots by entity.
    pub slots: HashMap<Entity, u32>,
    /// The engine's push on each moved body that its state carries to the device
    /// ([`EngineState::push`]), by entity: set by the engine after each window (none: no push).
    pub engine_pushes: HashMap<Entity, EnginePush>,
}

impl SphMovedBodies {
    /// Whether the device moves some body.
    pub fn active(&self) -> bool {
        !self.slots.is_empty()
    }

    /// The engine stepped its bodies over `window`: their state is now at its frame.
    pub fn engine_stepped(&mut self, window: &EngineWindow) {
        self.engine_frame = Some(window.to_frame);
        self.engine_time_ns = Some(window.time_ns);
    }

    /// The newest record of collider slot `slot` as read back.
    pub fn newest_record(&self, slot: u32) -> Option<FrameRecord> {
        self.latest
            .as_ref()?
            .bodies
            .get(slot as usize)?
            .newest_record()
    }
}

pub(crate) fn add_systems(app: &mut App, schedule: InternedScheduleLabel) {
    app.init_resource::<SphMovedBodies>().add_systems(
        schedule,
        (
            sph_plan_moved_bodies
                .in_set(SphSystems::Step)
                .before(crate::simulation::StepSystem),
            (sph_read_moved_bodies, sph_moved_bodies_window)
                .chain()
                .in_set(SphSystems::Writeback),
        ),
    );
}

/// The pose to sort a body's boundary samples at and its origin's linear and angular velocity:
/// its `record` carried `ahead` seconds on at its velocity.
pub fn predicted(record: &FrameRecord, center_of_mass: Vec3, ahead: f32) -> (Pose, Vec3, Vec3) {
    let s = record.state;
    let position = s.position + ahead * s.linear_velocity;
    let rotation = turned(s.rotation, ahead * s.angular_velocity);
    let origin = position - rotate(rotation, center_of_mass);
    let velocity = s.linear_velocity + s.angular_velocity.cross(origin - position);
    let pose = Pose {
        translation: origin,
        rotation,
    };
    (pose, velocity, s.angular_velocity)
}

/// The model of a body from its [`SphRigidBody`] at `origin`, `None` when it cannot be moved.
pub fn body_model(body: &SphRigidBody, origin: Vec3, rotation: Quat) -> Option<RigidBodyModel> {
    if !(body.mass.is_finite() && body.mass > 0.0) {
        return None;
    }
    let hinge = body.hinge_axis.map(|axis| {
        let axis = axis.normalize_or(Vec3::Z);
        // I_a = a · (R I Rᵀ) a + M |a × (c − p)|², the pivot p the body's origin.
        let inertia = body.inverse_inertia.inverse();
        let local = rotation.inverse() * axis;
        let arm = axis.cross(rotation * body.center_of_mass);
        let about_axis = local.dot(inertia * local) + body.mass * arm.length_squared();
        Hinge {
            axis,
            pivot: origin,
            inverse_inertia: if about_axis.is_finite() && about_axis > 0.0 {
                1.0 / about_axis
            } else {
                0.0
            },
        }
    });
    Some(RigidBodyModel {
        mass: body.mass,
        free_translation: body.free_translation,
        free_rotation: body.free_rotation,
        center_of_mass: body.center_of_mass,
        inverse_inertia: body.inverse_inertia,
        hinge,
        gravity: body.gravity,
        linear_damping: body.linear_damping,
        angular_damping: body.angular_damping,
    })
}

/// A moved body's entity, collider, rigid body and pose.
type MovedBody<'a> = (Entity, &'a SphCollider, &'a SphRigidBody, &'a Transform);

/// This frame's inputs for the device (GPU backend): each moved body's model, the engine's
/// state at its frame and the pose its samples are sorted at, the newest record carried to the
/// middle of this frame (set on the boundary here, after `sph_sync_colliders` placed the
/// collider at the engine's pose).
fn sph_plan_moved_bodies(
    bodies: Query<MovedBody>,
    params: Res<SphParams>,
    mut map: ResMut<SphColliderMap>,
    mut moved: ResMut<SphMovedBodies>,
    mut sim: ResMut<SphSimulation>,
    mut stats: ResMut<SphStats>,
    mut assets: Option<ResMut<Assets<ShaderBuffer>>>,
) {
    moved.slots.clear();
    if sim.frame.reset {
        // The device's states start again empty; so does the bookkeeping.
        moved.engine_frame = None;
        moved.engine_time_ns = None;
        moved.latest = None;
        moved.window = None;
        moved.engine_pushes.clear();
    }
    let (Some(container), true) = (sim.container, sim.backend == SphBackend::Gpu) else {
        sim.frame.bodies = None;
        return;
    };
    let engine_frame = *moved.engine_frame.get_or_insert(sim.frame_number);
    let (last_frame, frame_time) = (sim.frame_number, sim.plan.duration);
    let mut inputs = vec![GpuBodyInput::default(); GPU_MOVED_BODIES];
    let mut boundary = sim.boundary_mut(&container, &params.0);
    for (entity, collider, body, transform) in &bodies {
        let Some(tracked) = map.tracked.get_mut(&entity) else {
            continue;
        };
        let slot = tracked.id.0;
        if collider.motion != ColliderMotion::Dynamic || slot as usize >= GPU_MOVED_BODIES {
            continue;
        }
        let Some(model) = body_model(body, transform.translation, transform.rotation) else {
            continue;
        };
        if let Some(record) = moved.newest_record(slot) {
            // From the record's end to the middle of this frame.
            let ahead = (last_frame.wrapping_sub(record.frame) as f32 + 0.5) * frame_time;
            let (pose, linear, angular) = predicted(&record, body.center_of_mass, ahead);
            if let Some(boundary) = boundary.as_deref_mut() {
                match boundary.set_motion(tracked.id, pose, linear, angular) {
                    Ok(()) => tracked.pose = pose,
                    Err(e) => stats.error = Some(format!("moved body {entity}: {e}")),
                }
            }
        }
        let engine = EngineState {
            frame: engine_frame,
            origin: transform.translation,
            rotation: transform.rotation,
            linear_velocity: body.linear_velocity,
            angular_velocity: body.angular_velocity,
            push: moved
                .engine_pushes
                .get(&entity)
                .copied()
                .unwrap_or_default(),
        };
        inputs[slot as usize] = GpuBodyInput::of(&model, Some(&engine), tracked.pose);
        moved.slots.insert(entity, slot);
    }
    if moved.slots.is_empty() {
        sim.frame.bodies = None;
        return;
    }
    if moved.states.is_none() {
        let Some(assets) = assets.as_mut() else {
            return;
        };
        moved.states = Some(assets.add(ShaderBuffer::with_size(
            std::mem::size_of::<GpuBodyStates>(),
            bevy::asset::RenderAssetUsages::RENDER_WORLD,
        )));
    }
    let Some(states) = moved.states.clone() else {
        return;
    };
    sim.frame.bodies = Some(GpuBodiesFrame { inputs, states });
}

/// Keeps a readback of the states alive while there are moved bodies, and none after.
fn sph_read_moved_bodies(mut moved: ResMut<SphMovedBodies>, mut commands: Commands) {
    if moved.slots.is_empty() {
        if let Some(reader) = moved.reader.take() {
            commands.entity(reader).despawn();
        }
        return;
    }
    if moved.reader.is_some() {
        return;
    }
    let Some(handle) = moved.states.clone() else {
        return;
    };
    let reader = commands
        .spawn(Readback::buffer(handle))
        .observe(
            |event: On<ReadbackComplete>, mut moved: ResMut<SphMovedBodies>| {
                let size = std::mem::size_of::<GpuBodyStates>();
                if event.data.len() >= size {
                    moved.latest =
                        Some(Box::new(bytemuck::pod_read_unaligned(&event.data[..size])));
                }
            },
        )
        .id();
    moved.reader = Some(reader);
}

/// The engine's next window: the frames recorded after its frame, up to the newest read back.
pub(crate) fn sph_moved_bodies_window(mut moved: ResMut<SphMovedBodies>) {
    moved.window = None;
    let Some(engine_frame) = moved.engine_frame else {
        return;
    };
    let slots: Vec<u32> = moved.slots.values().copied().collect();
    let Some(newest) = slots
        .iter()
        .filter_map(|&slot| moved.newest_record(slot))
        .map(|r| (r.frame, r.time_ns, r.duration))
        .reduce(|a, b| if after(b.0, a.0) { b } else { a })
    else {
        return;
    };
    let (to_frame, time_ns, duration) = newest;
    if !after(to_frame, engine_frame) {
        return;
    }
    let start_ns = *moved
        .engine_time_ns
        .get_or_insert(time_ns.saturating_sub((duration as f64 * 1e9) as u64));
    let mut window = EngineWindow {
        to_frame,
        time_ns,
        seconds: time_ns.saturating_sub(start_ns) as f64 * 1e-9,
        ..Default::default()
    };
    let Some(latest) = moved.latest.as_ref() else {
        return;
    };
    for slot in slots {
        let records: Vec<FrameRecord> = latest.bodies[slot as usize]
            .records
            .iter()
            .filter_map(|r| r.record())
            .filter(|r| after(r.frame, engine_frame) && !after(r.frame, to_frame))
            .collect();
        let Some(last) = records.iter().find(|r| r.frame == to_frame).copied() else {
            continue;
        };
        // Every record after the engine's frame, unless the ring is full of them and the frame
        // right after the engine's is gone: some were overwritten before they were read.
        let lost = records.len() == RECORDS
            && !records
                .iter()
                .any(|r| r.frame == engine_frame.wrapping_add(1));
        let impulse = (!lost).then(|| WindowImpulse::over(&records, time_ns));
        window.impulses.insert(slot, impulse);
        window.newest.insert(slot, last);
    }
    moved.window = Some(window);
}

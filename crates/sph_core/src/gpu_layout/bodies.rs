//! The bodies the device moves (`crate::bodies`): what the CPU hands it every frame
//! ([`GpuBodyInput`]) and what it keeps and records ([`GpuBodyState`]), one of each per collider
//! slot, as 32-bit words (WGSL reads them from a `u32` array, `render/bodies/bodies.wgsl`, so the
//! force sums' words and the frame numbers pass unchanged).

use crate::bodies::engine_handoff::{DeviceBody, EngineState, FrameRecord, RECORDS};
use crate::bodies::engine_push::EnginePush;
use crate::bodies::rigid_step::{Hinge, RigidBodyModel, RigidState};
use crate::boundary::collider::Pose;
use crate::gpu_layout::body_forces::GPU_BODY_SLOTS;
use bytemuck::{Pod, Zeroable};
use glam::{Mat3, Quat, Vec3};

/// Collider slots whose bodies the device can move: every slot the force sums cover.
pub const GPU_MOVED_BODIES: usize = GPU_BODY_SLOTS - 1;

/// One body as the CPU hands it to the device every frame (WGSL `body_input_*`): its model
/// ([`RigidBodyModel`]), the engine's state at a frame's end and its push ([`EngineState`]) and
/// the pose its boundary samples were sorted at.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuBodyInput {
    /// Mass [kg]; 0: the device does not move this slot's collider.
    pub mass: f32,
    /// 1 per free world axis of translation, 0 where locked.
    pub free_translation: [f32; 3],
    /// Linear damping [1/s].
    pub linear_damping: f32,
    /// 1 per free world axis of rotation.
    pub free_rotation: [f32; 3],
    /// Angular damping [1/s].
    pub angular_damping: f32,
    /// The centre of mass in the body's frame [m].
    pub center_of_mass: [f32; 3],
    /// 1 / I_a about the hinge's axis [1/(kg m²)] (a hinged body only).
    pub hinge_inverse_inertia: f32,
    /// The hinge's axis (world, unit).
    pub hinge_axis: [f32; 3],
    /// 1 when hinged, else 0.
    pub hinged: u32,
    /// The hinge's pivot (world) [m].
    pub hinge_pivot: [f32; 3],
    /// I⁻¹ about the centre of mass in the body's frame, column by column.
    pub inverse_inertia: [f32; 9],
    /// Gravity [m/s²].
    pub gravity: [f32; 3],
    /// The frame whose end the engine's state is at.
    pub engine_frame: u32,
    /// The engine's body origin (world) [m].
    pub engine_origin: [f32; 3],
    /// The engine's orientation (x, y, z, w).
    pub engine_rotation: [f32; 4],
    /// The engine's centre-of-mass velocity [m/s].
    pub engine_linear_velocity: [f32; 3],
    /// 1 when the engine's state is given, else 0.
    pub has_engine_state: u32,
    /// The engine's angular velocity [rad/s].
    pub engine_angular_velocity: [f32; 3],
    /// Padding.
    pub pad0: u32,
    /// The origin of the pose the body's boundary samples were sorted at (as uploaded) [m].
    pub sorted_origin: [f32; 3],
    /// Padding.
    pub pad1: u32,
    /// The orientation of that pose (x, y, z, w).
    pub sorted_rotation: [f32; 4],
    /// The engine's push, its force [N] ([`EngineState::push`]), applied at every step.
    pub engine_force: [f32; 3],
    /// Padding.
    pub pad2: u32,
    /// Its torque about the centre of mass [N m].
    pub engine_torque: [f32; 3],
    /// Padding.
    pub pad3: u32,
}

fn array(v: Vec3) -> [f32; 3] {
    v.to_array()
}

fn quat(q: Quat) -> [f32; 4] {
    q.to_array()
}

/// A rigid state from its words (a state's or a record's: the same order).
fn rigid(
    position: [f32; 3],
    rotation: [f32; 4],
    linear: [f32; 3],
    angular: [f32; 3],
) -> RigidState {
    RigidState {
        position: position.into(),
        rotation: Quat::from_array(rotation),
        linear_velocity: linear.into(),
        angular_velocity: angular.into(),
    }
}

impl GpuBodyInput {
    /// The input of a body of `model`, the engine's state `engine` when it has one, its samples
    /// sorted at `sorted`.
    pub fn of(model: &RigidBodyModel, engine: Option<&EngineState>, sorted: Pose) -> Self {
        let hinge = model.hinge.unwrap_or(Hinge {
            axis: Vec3::Z,
            pivot: Vec3::ZERO,
            inverse_inertia: 0.0,
        });
        let engine = engine.copied();
        let e = engine.unwrap_or(EngineState {
            frame: 0,
            origin: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            linear_velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
            push: EnginePush::default(),
        });
        Self {
            mass: model.mass,
            free_translation: array(model.free_translation),
            linear_damping: model.linear_damping,
            free_rotation: array(model.free_rotation),
            angular_damping: model.angular_damping,
            center_of_mass: array(model.center_of_mass),
            hinge_inverse_inertia: hinge.inverse_inertia,
            hinge_axis: array(hinge.axis),
            hinged: model.hinge.is_some() as u32,
            hinge_pivot: array(hinge.pivot),
            inverse_inertia: model.inverse_inertia.to_cols_array(),
            gravity: array(model.gravity),
            engine_frame: e.frame,
            engine_origin: array(e.origin),
            engine_rotation: quat(e.rotation),
            engine_linear_velocity: array(e.linear_velocity),
            has_engine_state: engine.is_some() as u32,
            engine_angular_velocity: array(e.angular_velocity),
            pad0: 0,
            sorted_origin: array(sorted.translation),
            pad1: 0,
            sorted_rotation: quat(sorted.rotation),
            engine_force: array(e.push.force),
            pad2: 0,
            engine_torque: array(e.push.torque),
            pad3: 0,
        }
    }

    /// The body's model, `None` for a slot the device does not move.
    pub fn model(&self) -> Option<RigidBodyModel> {
        (self.mass > 0.0).then(|| RigidBodyModel {
            mass: self.mass,
            free_translation: self.free_translation.into(),
            free_rotation: self.free_rotation.into(),
            center_of_mass: self.center_of_mass.into(),
            inverse_inertia: Mat3::from_cols_array(&self.inverse_inertia),
            hinge: (self.hinged != 0).then(|| Hinge {
                axis: self.hinge_axis.into(),
                pivot: self.hinge_pivot.into(),
                inverse_inertia: self.hinge_inverse_inertia,
            }),
            gravity: self.gravity.into(),
            linear_damping: self.linear_damping,
            angular_damping: self.angular_damping,
        })
    }

    /// The engine's state, when given.
    pub fn engine(&self) -> Option<EngineState> {
        (self.has_engine_state != 0).then(|| EngineState {
            frame: self.engine_frame,
            origin: self.engine_origin.into(),
            rotation: Quat::from_array(self.engine_rotation),
            linear_velocity: self.engine_linear_velocity.into(),
            angular_velocity: self.engine_angular_velocity.into(),
            push: EnginePush {
                force: self.engine_force.into(),
                torque: self.engine_torque.into(),
            },
        })
    }
}

/// A frame's end as the device recorded it (WGSL `body_record_*`; [`FrameRecord`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuBodyRecord {
    /// The frame's number.
    pub frame: u32,
    /// The water's time at the frame's end [ns], low word.
    pub time_ns_lo: u32,
    /// High word.
    pub time_ns_hi: u32,
    /// The water time the frame covered [s].
    pub duration: f32,
    /// The centre of mass [m].
    pub position: [f32; 3],
    /// 1 when the record holds a frame, else 0.
    pub valid: u32,
    /// The orientation (x, y, z, w).
    pub rotation: [f32; 4],
    /// The centre of mass's velocity [m/s].
    pub linear_velocity: [f32; 3],
    /// Padding.
    pub pad0: u32,
    /// The angular velocity [rad/s].
    pub angular_velocity: [f32; 3],
    /// Padding.
    pub pad1: u32,
    /// The water's impulse over the frame [N s].
    pub impulse: [f32; 3],
    /// Padding.
    pub pad2: u32,
    /// The water's angular impulse about the centre of mass [N m s].
    pub angular_impulse: [f32; 3],
    /// Padding.
    pub pad3: u32,
    /// Σ F dt (t − t₀) over the frame [N s²] ([`FrameRecord::impulse_moment`]).
    pub impulse_moment: [f32; 3],
    /// Σ dt (t − t₀) over the frame [s²].
    pub time_moment: f32,
    /// Σ τ_c dt (t − t₀) over the frame [N m s²].
    pub angular_impulse_moment: [f32; 3],
    /// Padding.
    pub pad4: u32,
}

impl GpuBodyRecord {
    /// The record, `None` for an empty one.
    pub fn record(&self) -> Option<FrameRecord> {
        (self.valid != 0).then(|| FrameRecord {
            frame: self.frame,
            time_ns: (self.time_ns_hi as u64) << 32 | self.time_ns_lo as u64,
            duration: self.duration,
            state: rigid(
                self.position,
                self.rotation,
                self.linear_velocity,
                self.angular_velocity,
            ),
            impulse: self.impulse.into(),
            angular_impulse: self.angular_impulse.into(),
            impulse_moment: self.impulse_moment.into(),
            angular_impulse_moment: self.angular_impulse_moment.into(),
            time_moment: self.time_moment,
        })
    }
}

/// One body as the device keeps it (WGSL `body_state_*`; CPU twin [`DeviceBody`]), read back.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuBodyState {
    /// 1 once the device holds the body (the engine's first state arrived), else 0.
    pub held: u32,
    /// The engine frame whose state was last taken.
    pub engine_frame: u32,
    /// 1 once an engine state was taken.
    pub has_engine_frame: u32,
    /// Engine states taken whole ([`DeviceBody::resyncs`]).
    pub resyncs: u32,
    /// The frame being summed.
    pub frame: u32,
    /// The force sums' evaluations when last read this frame.
    pub evaluations_seen: u32,
    /// The water time of the frame so far [s].
    pub duration: f32,
    /// Padding.
    pub pad0: u32,
    /// The body's six force sums (low, high words) when last read this frame.
    pub sums_seen: [u32; 12],
    /// The centre of mass [m].
    pub position: [f32; 3],
    /// Padding.
    pub pad1: u32,
    /// The orientation (x, y, z, w).
    pub rotation: [f32; 4],
    /// The centre of mass's velocity [m/s].
    pub linear_velocity: [f32; 3],
    /// Padding.
    pub pad2: u32,
    /// The angular velocity [rad/s].
    pub angular_velocity: [f32; 3],
    /// Padding.
    pub pad3: u32,
    /// The water's impulse over the frame so far [N s].
    pub impulse: [f32; 3],
    /// Padding.
    pub pad4: u32,
    /// The water's angular impulse over the frame so far [N m s].
    pub angular_impulse: [f32; 3],
    /// Padding.
    pub pad5: u32,
    /// Σ F dt (t − t₀) over the frame so far [N s²].
    pub impulse_moment: [f32; 3],
    /// Σ dt (t − t₀) over the frame so far [s²].
    pub time_moment: f32,
    /// Σ τ_c dt (t − t₀) over the frame so far [N m s²].
    pub angular_impulse_moment: [f32; 3],
    /// Padding.
    pub pad6: u32,
    /// The last frames' ends, frame k at `k % RECORDS`.
    pub records: [GpuBodyRecord; RECORDS],
}

impl GpuBodyState {
    /// The body as [`DeviceBody`] holds it.
    pub fn device_body(&self) -> DeviceBody {
        DeviceBody {
            state: (self.held != 0).then(|| {
                rigid(
                    self.position,
                    self.rotation,
                    self.linear_velocity,
                    self.angular_velocity,
                )
            }),
            engine_frame: (self.has_engine_frame != 0).then_some(self.engine_frame),
            resyncs: self.resyncs,
            frame: self.frame,
            impulse: self.impulse.into(),
            angular_impulse: self.angular_impulse.into(),
            duration: self.duration,
            impulse_moment: self.impulse_moment.into(),
            angular_impulse_moment: self.angular_impulse_moment.into(),
            time_moment: self.time_moment,
            records: self.records.map(|r| r.record()),
            // Not kept in the state: the device reads it from its input at every step.
            engine_push: EnginePush::default(),
        }
    }

    /// The newest record (the frame that ended last), if any.
    pub fn newest_record(&self) -> Option<FrameRecord> {
        self.records
            .iter()
            .filter_map(GpuBodyRecord::record)
            .reduce(|a, b| {
                if crate::bodies::engine_handoff::after(b.frame, a.frame) {
                    b
                } else {
                    a
                }
            })
    }
}

/// Every moved body's state, as read back ([`GPU_MOVED_BODIES`] of them, by collider slot).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuBodyStates {
    /// By collider slot.
    pub bodies: [GpuBodyState; GPU_MOVED_BODIES],
}

impl Default for GpuBodyStates {
    fn default() -> Self {
        Self::zeroed()
    }
}

/// The device's body words: the inputs of every slot, then their states.
pub const GPU_BODY_INPUT_WORDS: usize = std::mem::size_of::<GpuBodyInput>() / 4;
/// Words of one body's state.
pub const GPU_BODY_STATE_WORDS: usize = std::mem::size_of::<GpuBodyState>() / 4;
/// Words of one record.
pub const GPU_BODY_RECORD_WORDS: usize = std::mem::size_of::<GpuBodyRecord>() / 4;
/// Bytes of the device's body region: inputs, then states.
pub const GPU_BODY_BYTES: usize =
    GPU_MOVED_BODIES * (std::mem::size_of::<GpuBodyInput>() + std::mem::size_of::<GpuBodyState>());
/// Words of one body's contacts in a step (`sph_core::bodies::solid_contact`): the solids'
/// pushes along ±x, ±y, ±z and their velocity floors, the other bodies' pushes, the bodies that
/// pushed (a bit per slot), the friction's limit, and the directions the solids and walls
/// pushed the body along.
pub const GPU_BODY_CONTACT_WORDS: usize = 21;
/// Where the states start in the body region [bytes].
pub const GPU_BODY_STATES_OFFSET: usize = GPU_MOVED_BODIES * std::mem::size_of::<GpuBodyInput>();

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_layouts_are_whole_words_in_16_byte_rows() {
        assert_eq!(std::mem::size_of::<GpuBodyInput>(), 256);
        assert_eq!(std::mem::size_of::<GpuBodyRecord>(), 144);
        assert_eq!(std::mem::size_of::<GpuBodyState>(), 208 + 144 * RECORDS);
        assert_eq!(GPU_BODY_STATES_OFFSET % 16, 0);
    }

    #[test]
    fn an_input_gives_back_its_model_and_engine_state() {
        let model = RigidBodyModel {
            mass: 3.0,
            free_translation: Vec3::new(1.0, 1.0, 0.0),
            free_rotation: Vec3::ONE,
            center_of_mass: Vec3::new(0.0, 0.1, 0.0),
            inverse_inertia: Mat3::from_cols_array(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]),
            hinge: Some(Hinge {
                axis: Vec3::Z,
                pivot: Vec3::X,
                inverse_inertia: 2.5,
            }),
            gravity: Vec3::new(0.0, -9.81, 0.0),
            linear_damping: 0.1,
            angular_damping: 0.2,
        };
        let engine = EngineState {
            frame: 17,
            origin: Vec3::new(1.0, 2.0, 3.0),
            rotation: Quat::from_rotation_y(0.3),
            linear_velocity: Vec3::X,
            angular_velocity: Vec3::Y,
            push: EnginePush {
                force: Vec3::new(0.5, 20.0, -1.0),
                torque: Vec3::new(0.1, 0.2, 0.3),
            },
        };
        let input = GpuBodyInput::of(&model, Some(&engine), Pose::default());
        assert_eq!(input.model(), Some(model));
        assert_eq!(input.engine(), Some(engine));
        assert_eq!(GpuBodyInput::default().model(), None);
    }
}

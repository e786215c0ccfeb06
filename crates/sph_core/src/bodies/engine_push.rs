//! The engine's own push on a body the device moves: what the engine did to it over a window
//! beyond the water and gravity (its contacts with other bodies and the level, its joints, a
//! game's forces), as a mean force and torque ([`crate::bodies::engine_handoff`]).
//!
//! The engine's state reaches the device a few frames late, and until it does the device steps
//! the body with the water and gravity alone: a crate resting on a floating raft falls into it
//! on the device for those frames, and the raft floats as if the crate weighed nothing, so the
//! water under it pushes back too little and the handoff's correction comes as a jolt every
//! frame. Carrying the steady part of the engine's push on as a constant force (a predictor,
//! [`EnginePush::steadied`]) takes the contact's weight into the device's steps. The handoff's
//! difference between the engine's state and the device's record then holds only what the
//! prediction missed, so every impulse still counts once.
//!
//! The push over a window of T from the engine's velocities before (v₀, ω₀) and after (v₁, ω₁):
//! F = M (v₁ − v₀) / T − J / T − M g + M c_v v̄ and τ = (I₁ ω₁ − I₀ ω₀) / T − L / T + c_ω I₁ ω̄,
//! with J and L the water's impulse and angular impulse over the window, I the world inertia,
//! v̄ the window's mean velocity and the last terms the engine's own damping (which the device
//! applies itself).

use crate::bodies::rigid_step::{RigidBodyModel, RigidState};
use glam::{Mat3, Quat, Vec3};

/// The engine's push on a body, as a force at its centre of mass and a torque about it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnginePush {
    /// The force [N].
    pub force: Vec3,
    /// The torque about the centre of mass [N m].
    pub torque: Vec3,
}

/// The time constant of the push the device carries on [s] ([`EnginePush::steadied`]): its
/// steady part passes, a bob's does not. A floating raft with a crate on it bobs at about
/// 2.7 Hz (ω = √(ρ0 g A / M) ≈ 17 rad/s); carried on a readback late, that part of the contact
/// pushes the raft out of phase and feeds the bob, which grew until the crate was thrown off.
/// A first-order filter of 0.25 s lets a quarter of it through (1 / √(1 + (ω τ)²)), and still
/// takes up a crate set down on the raft within a second.
pub const ENGINE_PUSH_TIME_CONSTANT: f32 = 0.25;

/// The world inertia R I Rᵀ of a body of `model` at `rotation` (zero when its inverse cannot be
/// inverted).
fn world_inertia(model: &RigidBodyModel, rotation: Quat) -> Mat3 {
    if model.inverse_inertia.determinant().abs() <= f32::MIN_POSITIVE {
        return Mat3::ZERO;
    }
    let r = Mat3::from_quat(rotation);
    r * model.inverse_inertia.inverse() * r.transpose()
}

impl EnginePush {
    /// The engine's push over a window of `seconds` in which it took a body of `model` from
    /// `before` to `after` under the water's `impulse` [N s] and `angular_impulse` about the
    /// centre of mass [N m s]; zero along locked axes, and none for an empty window.
    pub fn measured(
        model: &RigidBodyModel,
        before: &RigidState,
        after: &RigidState,
        impulse: Vec3,
        angular_impulse: Vec3,
        seconds: f32,
    ) -> Self {
        if !(seconds.is_finite() && seconds > 0.0) {
            return Self::default();
        }
        let m = model.mass;
        let mean_v = 0.5 * (before.linear_velocity + after.linear_velocity);
        let force = m * (after.linear_velocity - before.linear_velocity) / seconds
            - impulse / seconds
            - m * model.gravity
            + m * model.linear_damping * mean_v;
        let (i0, i1) = (
            world_inertia(model, before.rotation),
            world_inertia(model, after.rotation),
        );
        let mean_w = 0.5 * (before.angular_velocity + after.angular_velocity);
        let torque = (i1 * after.angular_velocity - i0 * before.angular_velocity) / seconds
            - angular_impulse / seconds
            + model.angular_damping * (i1 * mean_w);
        let push = Self {
            force: force * model.free_translation,
            torque: torque * model.free_rotation,
        };
        if push.force.is_finite() && push.torque.is_finite() {
            push
        } else {
            Self::default()
        }
    }

    /// The steady push after a window of `seconds` in which the engine pushed with `self`,
    /// the steady push before it being `previous`: a first-order filter of time constant
    /// [`ENGINE_PUSH_TIME_CONSTANT`], p ← p + (1 − e^(−T/τ)) (push − p). A lasting contact (a
    /// crate resting on a raft, a boat against a wall) is carried on; a one-window blow (a
    /// landing, a collision) or a bob's share of a contact mostly is not, as the device would
    /// otherwise push the body with it a readback late until the engine's next state took it
    /// back.
    pub fn steadied(&self, previous: &Self, seconds: f32) -> Self {
        if !(seconds.is_finite() && seconds > 0.0) {
            return *previous;
        }
        let share = 1.0 - (-seconds / ENGINE_PUSH_TIME_CONSTANT).exp();
        Self {
            force: previous.force + share * (self.force - previous.force),
            torque: previous.torque + share * (self.torque - previous.torque),
        }
    }

    /// The push's moment about the world origin on a body whose centre of mass is at
    /// `position` [N m] (what [`crate::bodies::rigid_step::advance`] takes).
    pub fn moment_about_origin(&self, position: Vec3) -> Vec3 {
        self.torque + position.cross(self.force)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bodies::engine_handoff::tests::model;
    use crate::bodies::rigid_step::advance;

    fn at_rest() -> RigidState {
        RigidState {
            position: Vec3::new(0.0, 1.0, 0.0),
            rotation: Quat::from_rotation_z(0.4),
            linear_velocity: Vec3::new(0.2, 0.0, -0.1),
            angular_velocity: Vec3::new(0.0, 0.5, 0.3),
        }
    }

    /// A body stepped under the water's force, gravity and a contact's force and torque: the
    /// push measured from its velocities is the contact's (the water's and gravity's parts
    /// taken out), whatever the water did.
    #[test]
    fn the_measured_push_is_what_the_engine_added_to_the_water_and_gravity() {
        let mut m = model();
        m.linear_damping = 0.3;
        m.angular_damping = 0.2;
        let contact = EnginePush {
            force: Vec3::new(1.5, 30.0, -0.5),
            torque: Vec3::new(0.02, -0.01, 0.03),
        };
        let (mut state, dt) = (at_rest(), 0.002);
        let (mut impulse, mut angular) = (Vec3::ZERO, Vec3::ZERO);
        for k in 0..25 {
            let water = Vec3::new(0.0, 4.0 + 0.3 * k as f32, 0.2);
            let water_torque = Vec3::new(0.01, 0.0, -0.02 * k as f32);
            impulse += dt * water;
            angular += dt * water_torque;
            let force = water + contact.force;
            let moment = water_torque + contact.torque + state.position.cross(force);
            state = advance(&m, &state, force, moment, dt);
        }
        let push = EnginePush::measured(&m, &at_rest(), &state, impulse, angular, 25.0 * dt);
        // The damping is taken as acting on the window's mean velocity: first order in dt.
        assert!(
            (push.force - contact.force).length() < 0.01,
            "{:?}",
            push.force
        );
        assert!(
            (push.torque - contact.torque).length() < 2e-3,
            "{:?}",
            push.torque
        );
        let none = EnginePush::measured(&m, &at_rest(), &state, impulse, angular, 0.0);
        assert_eq!(none, EnginePush::default());
    }

    #[test]
    fn a_steady_push_follows_the_engines_over_its_time_constant() {
        let contact = EnginePush {
            force: Vec3::new(0.0, 20.0, -4.0),
            torque: Vec3::new(0.5, 0.0, 0.0),
        };
        let frame = 1.0 / 60.0;
        let mut steady = EnginePush::default();
        // One window's blow passes only its share.
        let once = contact.steadied(&steady, frame);
        let share = 1.0 - (-frame / ENGINE_PUSH_TIME_CONSTANT).exp();
        assert!((once.force - share * contact.force).length() < 1e-5);
        assert!(share < 0.1);
        // A lasting contact is taken up: after 1 s, all but e^(−4).
        for _ in 0..60 {
            steady = contact.steadied(&steady, frame);
        }
        let left = (steady.force - contact.force).length() / contact.force.length();
        assert!((left - (-4.0f32).exp()).abs() < 2e-3, "{left}");
        assert!((steady.torque - contact.torque).length() < 0.02 * 0.5);
        // A bob's push that changes sign every window averages out.
        let mut bob = EnginePush::default();
        for k in 0..60 {
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            let push = EnginePush {
                force: sign * contact.force,
                torque: Vec3::ZERO,
            };
            bob = push.steadied(&bob, frame);
        }
        assert!(
            bob.force.length() < 0.05 * contact.force.length(),
            "{bob:?}"
        );
        // An empty window keeps the push.
        assert_eq!(contact.steadied(&steady, 0.0), steady);
    }
}

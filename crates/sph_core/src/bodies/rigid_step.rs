//! One step of a rigid body the water carries: semi-implicit Euler at the water's own dt, as the
//! water's particles advance (Akinci et al. 2012, §4: the bodies are integrated with the forces
//! of the same step, so the water meets them where they are). WGSL twin: `body_motion.wgsl`.
//!
//! - A free body: v ← (v + dt (F/M + g)) / (1 + dt c_v), ω ← (ω + dt I_w⁻¹ τ_c) / (1 + dt c_ω),
//!   with I_w⁻¹ = R I⁻¹ Rᵀ and τ_c the water's torque about the centre of mass; then
//!   c ← c + dt v and q ← q + ½ dt [ω, 0] q, normalised. A locked axis keeps zero velocity.
//!   The damping is avian's (`LinearDamping`, `AngularDamping`: v / (1 + dt c)).
//! - A hinged body (a wheel on its axle) turns about a fixed axis through a fixed pivot:
//!   ω_a ← (ω_a + dt (a · τ_p) / I_a) / (1 + dt c_ω), with τ_p the torque of the water and of
//!   gravity about the pivot and I_a the moment of inertia about the axis; its centre of mass
//!   follows the turn.
//!
//! The gyroscopic term ω × I ω is left out: the bodies the water carries turn slowly, and the
//! engine's own solve, which has it, corrects the body every frame
//! ([`crate::bodies::engine_handoff`]).

use glam::{Mat3, Quat, Vec3};

/// A fixed axle: the body turns about `axis` through `pivot`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hinge {
    /// The axis (world, unit).
    pub axis: Vec3,
    /// The pivot (world) [m]: the body's origin, which stays on the axle.
    pub pivot: Vec3,
    /// 1 / I_a, the inverse of the body's moment of inertia about the axis through the pivot
    /// [1/(kg m²)].
    pub inverse_inertia: f32,
}

/// What moves a body besides its state: its mass and inertia, its locks and hinge, gravity and
/// damping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidBodyModel {
    /// Mass M [kg], > 0.
    pub mass: f32,
    /// 1 on each world axis the body may move along, 0 where it is locked.
    pub free_translation: Vec3,
    /// 1 on each world axis the body may turn about, 0 where it is locked.
    pub free_rotation: Vec3,
    /// The centre of mass in the body's frame [m].
    pub center_of_mass: Vec3,
    /// I⁻¹ about the centre of mass in the body's frame [1/(kg m²)].
    pub inverse_inertia: Mat3,
    /// The axle of a hinged body (`None`: free).
    pub hinge: Option<Hinge>,
    /// Gravity g [m/s²].
    pub gravity: Vec3,
    /// Linear damping c_v [1/s].
    pub linear_damping: f32,
    /// Angular damping c_ω [1/s].
    pub angular_damping: f32,
}

/// A rigid body's state: its centre of mass, orientation and velocities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidState {
    /// The centre of mass c (world) [m].
    pub position: Vec3,
    /// The orientation q (unit quaternion; the body's frame to the world).
    pub rotation: Quat,
    /// The centre of mass's velocity v [m/s].
    pub linear_velocity: Vec3,
    /// The angular velocity ω (world) [rad/s].
    pub angular_velocity: Vec3,
}

impl RigidState {
    /// The state of a body whose origin (the pose of its collider and transform) is at `origin`,
    /// its centre of mass at `center_of_mass` in its frame.
    pub fn at_origin(
        origin: Vec3,
        rotation: Quat,
        linear_velocity: Vec3,
        angular_velocity: Vec3,
        center_of_mass: Vec3,
    ) -> Self {
        Self {
            position: origin + rotate(rotation, center_of_mass),
            rotation,
            linear_velocity,
            angular_velocity,
        }
    }

    /// The body's origin (world) [m].
    pub fn origin(&self, center_of_mass: Vec3) -> Vec3 {
        self.position - rotate(self.rotation, center_of_mass)
    }

    /// The velocity of the body's point at `x` [m/s].
    pub fn point_velocity(&self, x: Vec3) -> Vec3 {
        self.linear_velocity + self.angular_velocity.cross(x - self.position)
    }
}

/// q v q⁻¹ for a unit quaternion, as the WGSL computes it: v + 2 u × (u × v + w v).
pub fn rotate(q: Quat, v: Vec3) -> Vec3 {
    let u = Vec3::new(q.x, q.y, q.z);
    let t = u.cross(v) + q.w * v;
    v + 2.0 * u.cross(t)
}

/// The product a b of two quaternions (b first, then a).
pub fn multiply(a: Quat, b: Quat) -> Quat {
    let (ua, ub) = (Vec3::new(a.x, a.y, a.z), Vec3::new(b.x, b.y, b.z));
    let u = a.w * ub + b.w * ua + ua.cross(ub);
    Quat::from_xyzw(u.x, u.y, u.z, a.w * b.w - ua.dot(ub))
}

/// q turned by the small rotation vector θ: q + ½ [θ, 0] q, normalised.
pub fn turned(q: Quat, theta: Vec3) -> Quat {
    let u = Vec3::new(q.x, q.y, q.z);
    let du = 0.5 * (q.w * theta + theta.cross(u));
    let dw = -0.5 * theta.dot(u);
    let sum = Quat::from_xyzw(u.x + du.x, u.y + du.y, u.z + du.z, q.w + dw);
    let length = (sum.x * sum.x + sum.y * sum.y + sum.z * sum.z + sum.w * sum.w).sqrt();
    Quat::from_xyzw(
        sum.x / length,
        sum.y / length,
        sum.z / length,
        sum.w / length,
    )
}

/// The conjugate (inverse) of a unit quaternion.
pub fn conjugate(q: Quat) -> Quat {
    Quat::from_xyzw(-q.x, -q.y, -q.z, q.w)
}

/// One step of `dt` [s] under the water's force `force` [N] and its moment about the world's
/// origin `moment` = Σ x_b × f_b [N m] (what the boundary's sums give).
pub fn advance(
    model: &RigidBodyModel,
    state: &RigidState,
    force: Vec3,
    moment: Vec3,
    dt: f32,
) -> RigidState {
    let angular_decay = 1.0 / (1.0 + dt * model.angular_damping);
    if let Some(hinge) = model.hinge {
        // τ_p = Σ x_b × f − p × F + (c − p) × M g.
        let weight = model.mass * model.gravity;
        let torque =
            moment - hinge.pivot.cross(force) + (state.position - hinge.pivot).cross(weight);
        let spin = (hinge.axis.dot(state.angular_velocity)
            + dt * hinge.inverse_inertia * hinge.axis.dot(torque))
            * angular_decay;
        let angular_velocity = spin * hinge.axis;
        let rotation = turned(state.rotation, dt * angular_velocity);
        let position = hinge.pivot + rotate(rotation, model.center_of_mass);
        return RigidState {
            position,
            rotation,
            linear_velocity: angular_velocity.cross(position - hinge.pivot),
            angular_velocity,
        };
    }
    let linear_decay = 1.0 / (1.0 + dt * model.linear_damping);
    let acceleration = force / model.mass + model.gravity;
    let linear_velocity =
        (state.linear_velocity + dt * acceleration) * model.free_translation * linear_decay;
    // τ_c = Σ x_b × f − c × F; I_w⁻¹ τ = R (I⁻¹ (Rᵀ τ)).
    let torque = moment - state.position.cross(force);
    let local = model.inverse_inertia * rotate(conjugate(state.rotation), torque);
    let angular_velocity = (state.angular_velocity + dt * rotate(state.rotation, local))
        * model.free_rotation
        * angular_decay;
    RigidState {
        position: state.position + dt * linear_velocity,
        rotation: turned(state.rotation, dt * angular_velocity),
        linear_velocity,
        angular_velocity,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn free_box() -> RigidBodyModel {
        RigidBodyModel {
            mass: 2.0,
            free_translation: Vec3::ONE,
            free_rotation: Vec3::ONE,
            center_of_mass: Vec3::new(0.0, 0.1, 0.0),
            inverse_inertia: Mat3::from_diagonal(Vec3::new(10.0, 20.0, 40.0)),
            hinge: None,
            gravity: Vec3::new(0.0, -9.81, 0.0),
            linear_damping: 0.0,
            angular_damping: 0.0,
        }
    }

    fn at_rest() -> RigidState {
        RigidState::at_origin(
            Vec3::ZERO,
            Quat::IDENTITY,
            Vec3::ZERO,
            Vec3::ZERO,
            Vec3::Y * 0.1,
        )
    }

    #[test]
    fn the_quaternion_helpers_agree_with_glam() {
        let q = Quat::from_axis_angle(Vec3::new(1.0, 2.0, -0.5).normalize(), 0.7);
        let p = Quat::from_axis_angle(Vec3::new(-0.3, 0.2, 1.0).normalize(), -1.2);
        let v = Vec3::new(0.3, -1.0, 2.0);
        assert!((rotate(q, v) - q * v).length() < 1e-6);
        let (ours, glams) = (multiply(q, p), q * p);
        assert!((ours.x - glams.x).abs() + (ours.w - glams.w).abs() < 1e-6);
        let theta = Vec3::new(0.0, 0.0, 1e-3);
        let small = turned(Quat::IDENTITY, theta);
        assert!((small * Vec3::X - Vec3::new(1.0, 1e-3, 0.0)).length() < 1e-6);
    }

    /// Falling freely, a body keeps its orientation and gains g dt a step; the water's weight
    /// of it (F = −M g) holds it still.
    #[test]
    fn a_body_falls_with_gravity_and_floats_when_the_water_carries_its_weight() {
        let model = free_box();
        let mut state = at_rest();
        for _ in 0..100 {
            state = advance(&model, &state, Vec3::ZERO, Vec3::ZERO, 0.01);
        }
        assert!((state.linear_velocity.y + 9.81).abs() < 1e-4, "{state:?}");
        // Semi-implicit Euler: Σ k g dt² = g dt² n(n + 1)/2.
        let fallen = 9.81 * 0.01 * 0.01 * 5050.0;
        assert!((state.position.y - 0.1 + fallen).abs() < 1e-3, "{state:?}");
        assert_eq!(state.rotation, Quat::IDENTITY);
        let mut held = at_rest();
        let weight = model.mass * model.gravity;
        for _ in 0..100 {
            // The water's force acts at the centre of mass: its moment about the origin is c × F.
            let moment = held.position.cross(-weight);
            held = advance(&model, &held, -weight, moment, 0.01);
        }
        assert!(held.linear_velocity.length() < 1e-5 && held.angular_velocity.length() < 1e-5);
    }

    /// A torque τ about the centre of mass turns the body at dt I⁻¹ τ a step; locked rotation
    /// and translation axes keep zero velocity; damping divides by 1 + dt c.
    #[test]
    fn torques_turn_locks_hold_and_damping_slows() {
        let mut model = free_box();
        model.gravity = Vec3::ZERO;
        let state = at_rest();
        // A force at the centre of mass plus a couple of 0.5 N m about z.
        let force = Vec3::new(1.0, 0.0, 0.0);
        let moment = state.position.cross(force) + Vec3::new(0.0, 0.0, 0.5);
        let next = advance(&model, &state, force, moment, 0.1);
        assert!((next.angular_velocity - Vec3::new(0.0, 0.0, 0.1 * 40.0 * 0.5)).length() < 1e-5);
        assert!((next.linear_velocity - Vec3::new(0.05, 0.0, 0.0)).length() < 1e-6);
        model.free_rotation = Vec3::ZERO;
        model.free_translation = Vec3::new(0.0, 1.0, 1.0);
        let locked = advance(&model, &state, force, moment, 0.1);
        assert_eq!(locked.angular_velocity, Vec3::ZERO);
        assert_eq!(locked.linear_velocity, Vec3::ZERO);
        model = free_box();
        model.gravity = Vec3::ZERO;
        model.linear_damping = 2.0;
        model.angular_damping = 3.0;
        let moving = RigidState {
            linear_velocity: Vec3::X,
            angular_velocity: Vec3::Y,
            ..at_rest()
        };
        let slowed = advance(&model, &moving, Vec3::ZERO, Vec3::ZERO, 0.1);
        assert!((slowed.linear_velocity.x - 1.0 / 1.2).abs() < 1e-6);
        assert!((slowed.angular_velocity.y - 1.0 / 1.3).abs() < 1e-6);
    }

    /// A hinged body turns about its axle by the water's torque about the pivot, keeps its
    /// pivot, and a centre of mass off the axle swings down under gravity.
    #[test]
    fn a_hinged_body_turns_about_its_axle_only() {
        let pivot = Vec3::new(1.0, 2.0, 0.0);
        let mut model = free_box();
        model.center_of_mass = Vec3::ZERO;
        model.hinge = Some(Hinge {
            axis: Vec3::Z,
            pivot,
            inverse_inertia: 4.0,
        });
        let state =
            RigidState::at_origin(pivot, Quat::IDENTITY, Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
        // A push along x below the axle: a torque of −(0.5 × 3) about z... and a force the axle takes.
        let at = pivot - Vec3::Y * 0.5;
        let force = Vec3::new(3.0, 0.0, 0.0);
        let next = advance(&model, &state, force, at.cross(force), 0.01);
        assert!((next.angular_velocity - Vec3::new(0.0, 0.0, 0.01 * 4.0 * 1.5)).length() < 1e-5);
        assert!((next.position - pivot).length() < 1e-6);
        assert_eq!(next.linear_velocity.length(), 0.0);
        // Off-axle mass: the centre of mass 0.2 m to the side of the axle swings down.
        model.center_of_mass = Vec3::new(0.2, 0.0, 0.0);
        let mut swing = RigidState::at_origin(
            pivot,
            Quat::IDENTITY,
            Vec3::ZERO,
            Vec3::ZERO,
            model.center_of_mass,
        );
        for _ in 0..10 {
            swing = advance(&model, &swing, Vec3::ZERO, Vec3::ZERO, 0.01);
        }
        assert!(swing.angular_velocity.z < 0.0, "{swing:?}");
        assert!(swing.position.y < pivot.y);
        assert!(((swing.position - pivot).length() - 0.2).abs() < 1e-5);
        assert!((swing.origin(model.center_of_mass) - pivot).length() < 1e-5);
    }
}

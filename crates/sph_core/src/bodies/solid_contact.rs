//! A body the device moves against the solids it does not move: the box's walls and floor, and
//! the static, kinematic and engine-held colliders. The device resolves these contacts itself,
//! at every step, because the engine's contacts reach it a readback late
//! ([`crate::bodies::engine_handoff`]): a boat pushed against a wall by a current went through
//! the wall for three frames, and the engine's late correction threw it up (0.45 m/s) and, in
//! aquaplay.ron, rolled it over. WGSL twin: `body_placement.wgsl` (the samples' pushes) and
//! `body_motion.wgsl` (the walls and the resolution).
//!
//! - **The walls**: the body's shape reaches `support(e)` from its origin along each world axis e
//!   (exact for a cuboid, a sphere, a capsule and a cylinder; a mesh is left to the engine), and
//!   what reaches past a face is pushed back.
//! - **The other solids**: each of the body's boundary samples inside a solid is pushed out along
//!   the solid's normal, n (−φ).
//! - **The resolution**: per world axis and sign the largest push of the step moves the body
//!   (a position projection, as the engine's contacts do), and the velocity into the pushes is
//!   taken away. The body does not turn: its rotation is the engine's to correct.

use crate::bodies::rigid_step::{conjugate, rotate, RigidState};
use crate::boundary::collider::{Collider, ColliderShape, Pose};
use crate::container::BoxContainer;
use glam::{Quat, Vec3};

/// The largest push along each world axis, in each direction, of one step's contacts [m].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AxisPush {
    /// Along +x, +y, +z (≥ 0).
    pub positive: Vec3,
    /// Along −x, −y, −z (≥ 0).
    pub negative: Vec3,
}

impl AxisPush {
    /// Adds a push: per axis and sign, the largest is kept.
    pub fn add(&mut self, push: Vec3) {
        for a in 0..3 {
            if push[a] > 0.0 {
                self.positive[a] = self.positive[a].max(push[a]);
            } else if push[a] < 0.0 {
                self.negative[a] = self.negative[a].max(-push[a]);
            }
        }
    }

    /// Whether nothing pushes.
    pub fn is_empty(&self) -> bool {
        self.positive == Vec3::ZERO && self.negative == Vec3::ZERO
    }

    /// `state` moved by the pushes, without its velocity into them.
    pub fn resolve(&self, state: &RigidState) -> RigidState {
        let mut v = state.linear_velocity;
        for a in 0..3 {
            if (self.positive[a] > 0.0 && v[a] < 0.0) || (self.negative[a] > 0.0 && v[a] > 0.0) {
                v[a] = 0.0;
            }
        }
        RigidState {
            position: state.position + self.positive - self.negative,
            linear_velocity: v,
            ..*state
        }
    }
}

/// How far `shape`, turned by `rotation`, reaches from its origin along the unit world
/// direction `e` [m]; `None` for a mesh.
pub fn support(shape: &ColliderShape, rotation: Quat, e: Vec3) -> Option<f32> {
    let d = rotate(conjugate(rotation), e);
    Some(match *shape {
        ColliderShape::Cuboid { half_extents } => d.abs().dot(half_extents),
        ColliderShape::Sphere { radius } => radius,
        ColliderShape::Capsule {
            radius,
            half_length,
        } => d.y.abs() * half_length + radius,
        ColliderShape::Cylinder {
            radius,
            half_length,
        } => d.y.abs() * half_length + radius * (1.0 - d.y * d.y).max(0.0).sqrt(),
        ColliderShape::TriMesh(_) => return None,
    })
}

/// The pushes that bring `shape` at `pose` back inside the box: per axis, what reaches past the
/// lower face (pushed along +axis) and past the upper one (along −axis).
pub fn box_push(shape: &ColliderShape, pose: Pose, container: &BoxContainer) -> AxisPush {
    let (lo, hi) = (container.min(), container.max());
    let mut push = AxisPush::default();
    for (a, e) in [Vec3::X, Vec3::Y, Vec3::Z].into_iter().enumerate() {
        let Some(reach) = support(shape, pose.rotation, e) else {
            return AxisPush::default();
        };
        let o = pose.translation[a];
        push.positive[a] = (lo[a] - (o - reach)).max(0.0);
        push.negative[a] = ((o + reach) - hi[a]).max(0.0);
    }
    push
}

/// The push of a boundary sample at `x` out of the solids it is inside: n (−φ) for each.
pub fn sample_push<'a>(x: Vec3, solids: impl IntoIterator<Item = &'a Collider>) -> Vec3 {
    solids
        .into_iter()
        .filter_map(|c| c.surface_within(x, 0.0))
        .filter(|&(phi, _)| phi < 0.0)
        .map(|(phi, n)| -phi * n)
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::collider::ColliderMotion;

    #[test]
    fn a_turned_box_reaches_its_corner_and_is_pushed_back_inside() {
        let shape = ColliderShape::Cuboid {
            half_extents: Vec3::new(0.1, 0.05, 0.02),
        };
        let turned = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
        // Turned a quarter about z, its 0.1 half length stands along y.
        assert!((support(&shape, turned, Vec3::Y).unwrap() - 0.1).abs() < 1e-6);
        let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::ONE);
        let pose = Pose {
            translation: Vec3::new(0.97, 0.08, 0.5),
            rotation: turned,
        };
        let push = box_push(&shape, pose, &container);
        // 0.02 past the floor (0.08 − 0.1): up; 0.02 past x = 1 (0.97 + 0.05): back along −x.
        assert!(
            (push.positive - Vec3::new(0.0, 0.02, 0.0)).length() < 1e-6,
            "{push:?}"
        );
        assert!(
            (push.negative - Vec3::new(0.02, 0.0, 0.0)).length() < 1e-6,
            "{push:?}"
        );
        let sphere = ColliderShape::Sphere { radius: 0.1 };
        let inside = Pose {
            translation: Vec3::splat(0.5),
            rotation: Quat::IDENTITY,
        };
        assert!(box_push(&sphere, inside, &container).is_empty());
    }

    #[test]
    fn pushes_keep_the_largest_per_axis_and_take_the_velocity_into_them() {
        let mut push = AxisPush::default();
        push.add(Vec3::new(0.01, -0.002, 0.0));
        push.add(Vec3::new(0.004, -0.005, 0.0));
        assert_eq!(push.positive, Vec3::new(0.01, 0.0, 0.0));
        assert_eq!(push.negative, Vec3::new(0.0, 0.005, 0.0));
        let state = RigidState {
            position: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            linear_velocity: Vec3::new(-0.3, -0.2, 0.1),
            angular_velocity: Vec3::Z,
        };
        let out = push.resolve(&state);
        assert_eq!(out.position, Vec3::new(0.01, -0.005, 0.0));
        // Against the +x push: taken away; along the −y push: kept.
        assert_eq!(out.linear_velocity, Vec3::new(0.0, -0.2, 0.1));
        assert_eq!(out.angular_velocity, Vec3::Z);
    }

    #[test]
    fn a_sample_inside_a_solid_is_pushed_out_along_its_normal() {
        let wall = Collider {
            shape: ColliderShape::Cuboid {
                half_extents: Vec3::new(0.1, 0.5, 0.5),
            },
            pose: Pose::default(),
            linear_velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
            motion: ColliderMotion::Static,
            slip: Default::default(),
        };
        let push = sample_push(Vec3::new(0.08, 0.0, 0.0), [&wall]);
        assert!((push - Vec3::new(0.02, 0.0, 0.0)).length() < 1e-3, "{push}");
        assert_eq!(sample_push(Vec3::new(0.2, 0.0, 0.0), [&wall]), Vec3::ZERO);
    }
}

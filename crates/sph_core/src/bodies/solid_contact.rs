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
//! - **The other solids**: each of the body's boundary samples nearer to a solid than its own
//!   depth inside its body (half a spacing, the outer layer's) is pushed back along the solid's
//!   normal to that distance, so the body's surface ends on the solid's.
//! - **The other bodies it moves**: the same, at the other body's pose of the step, back to a
//!   margin g dt² outside it ([`body_margin`]), for a share m_other / (m + m_other) of the push
//!   (the other body's samples push it back with the rest); a hinged body gives way only about
//!   its axle, so the body it meets takes the whole push.
//!   The engine's contact between two bodies comes a readback late, as with the solids: a box
//!   resting on a floating box sank into it for three frames on the device, and the engine's
//!   late correction threw both out of the tank.
//! - **Friction between bodies** ([`support_friction`]): where one body rests on another (a push
//!   within 45° of up or down), Coulomb's friction draws the pair's horizontal velocities
//!   together, by at most μ g dt a step for the upper body ([`friction_step`]: its weight is the
//!   load) and the same impulse for the lower one, so the pair's momentum is kept. The solids
//!   and the walls do not rub: the water's own slip at them is the scenes' to set.
//! - **The resolution**, in two rounds over all the bodies. First the solids and the walls
//!   ([`resolve_solids`]): per world axis and sign the largest push of the step moves the body
//!   (a position projection, as the engine's contacts do), the samples' pushes first and then
//!   the walls' ([`box_push`] at the moved pose), and along a push the body keeps at least the
//!   solid's velocity (zero for a solid at rest). Then the other bodies ([`resolve_bodies`]),
//!   from every body's velocity after the first round: along a push the body keeps at least
//!   the other's velocity where the other gives way to nothing along it (a solid or a wall
//!   pushed it that way), and the pair's common velocity (m v + m_other v_other) /
//!   (m + m_other) otherwise, a perfectly inelastic contact that keeps the pair's momentum;
//!   friction moves the horizontal velocity toward the same velocity; the walls come last
//!   again, as they give way to nothing (a box pressed onto one resting on the floor does not
//!   push it into the floor). The velocities must be those after the step's advance: from the
//!   step's start, the contact holds an upper body up against its fall of the step but takes
//!   nothing from the lower one, whose water force the advance has already added, so the upper
//!   body's weight never reaches it. The body does not turn: its rotation is the engine's to
//!   correct.

use crate::bodies::rigid_step::{conjugate, rotate, RigidState};
use crate::boundary::collider::{Collider, ColliderShape, Pose};
use crate::container::BoxContainer;
use glam::{Quat, Vec2, Vec3};

/// The largest push along each world axis, in each direction, of one step's contacts with the
/// solids and the walls [m], with the least velocity each direction's pushers leave the body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisPush {
    /// Along +x, +y, +z (≥ 0).
    pub positive: Vec3,
    /// Along −x, −y, −z (≥ 0).
    pub negative: Vec3,
    /// Where pushed along +axis, the body's velocity along it is at least this [m/s] (−∞: no
    /// push).
    pub positive_floor: Vec3,
    /// Where pushed along −axis, the body's velocity along −axis is at least this [m/s].
    pub negative_floor: Vec3,
}

impl Default for AxisPush {
    fn default() -> Self {
        Self {
            positive: Vec3::ZERO,
            negative: Vec3::ZERO,
            positive_floor: Vec3::NEG_INFINITY,
            negative_floor: Vec3::NEG_INFINITY,
        }
    }
}

/// The directions of the pushes `positive` and `negative` as bits: bit a for +axis a, bit 3 + a
/// for −axis a.
pub fn push_directions(positive: Vec3, negative: Vec3) -> u32 {
    (0..3).fold(0, |bits, a| {
        bits | (u32::from(positive[a] > 0.0) << a) | (u32::from(negative[a] > 0.0) << (a + 3))
    })
}

impl AxisPush {
    /// Adds a push by a solid moving at `velocity` (zero for one at rest): per axis and sign,
    /// the largest push and the largest floor are kept.
    pub fn add(&mut self, push: Vec3, velocity: Vec3) {
        for a in 0..3 {
            if push[a] > 0.0 {
                self.positive[a] = self.positive[a].max(push[a]);
                self.positive_floor[a] = self.positive_floor[a].max(velocity[a]);
            } else if push[a] < 0.0 {
                self.negative[a] = self.negative[a].max(-push[a]);
                self.negative_floor[a] = self.negative_floor[a].max(-velocity[a]);
            }
        }
    }

    /// Whether nothing pushes.
    pub fn is_empty(&self) -> bool {
        self.positive == Vec3::ZERO && self.negative == Vec3::ZERO
    }

    /// The directions it pushes along ([`push_directions`]).
    pub fn directions(&self) -> u32 {
        push_directions(self.positive, self.negative)
    }

    /// `state` moved by the pushes, with its velocity into them raised to the floors.
    pub fn resolve(&self, state: &RigidState) -> RigidState {
        let mut v = state.linear_velocity;
        for a in 0..3 {
            if self.positive[a] > 0.0 {
                v[a] = v[a].max(self.positive_floor[a]);
            }
            if self.negative[a] > 0.0 {
                v[a] = v[a].min(-self.negative_floor[a]);
            }
        }
        RigidState {
            position: state.position + self.positive - self.negative,
            linear_velocity: v,
            ..*state
        }
    }
}

/// One step's pushes out of the other bodies the device moves: per axis and sign the largest
/// [m], the bodies that pushed, and the friction's limit. Their velocity floors come from the
/// partners' velocities once every body has met its solids ([`resolve_bodies`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyPushes {
    /// Along +x, +y, +z (≥ 0).
    pub positive: Vec3,
    /// Along −x, −y, −z (≥ 0).
    pub negative: Vec3,
    /// The bodies that pushed, as bits of their index among the step's neighbours (the GPU:
    /// their collider slots).
    pub partners: u32,
    /// The most the friction of a resting contact changes the horizontal velocity in the step
    /// [m/s] (0: none).
    pub friction_limit: f32,
}

impl BodyPushes {
    /// Adds a push out of `partner` (its index, below 32), with its friction's limit where one
    /// body rests on the other ([`support_friction`]).
    pub fn add(&mut self, push: Vec3, partner: usize, friction: Option<f32>) {
        for a in 0..3 {
            self.positive[a] = self.positive[a].max(push[a]);
            self.negative[a] = self.negative[a].max(-push[a]);
        }
        if push != Vec3::ZERO && partner < 32 {
            self.partners |= 1 << partner;
        }
        if let Some(limit) = friction {
            self.friction_limit = self.friction_limit.max(limit);
        }
    }

    /// Whether nothing pushes.
    pub fn is_empty(&self) -> bool {
        self.positive == Vec3::ZERO && self.negative == Vec3::ZERO
    }
}

/// Another body the device moves, as a step's contacts between bodies see it: after its own
/// advance and its solids and walls ([`resolve_solids`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Partner {
    /// Its mass [kg].
    pub mass: f32,
    /// Its centre of mass's velocity [m/s].
    pub velocity: Vec3,
    /// The directions a solid or a wall pushed it along ([`push_directions`]): along those it
    /// gives way to nothing.
    pub supported: u32,
}

/// The velocity two bodies in contact share after a perfectly inelastic contact: mass `m` at
/// `v` and `m_other` at `v_other` (their momentum over their mass).
pub fn common_velocity(m: f32, v: Vec3, m_other: f32, v_other: Vec3) -> Vec3 {
    (v * m + v_other * m_other) / (m + m_other)
}

/// A body's share of the push out of another body it moves: m_other / (m + m_other).
pub fn push_share(m: f32, m_other: f32) -> f32 {
    m_other / (m + m_other)
}

/// Coulomb's friction coefficient between two bodies the device moves: avian's default
/// (`Friction::default()`, 0.5 static and dynamic), which the scenes keep.
pub const BODY_FRICTION: f32 = 0.5;

/// The most a step of `dt` changes the sliding velocity of a body resting on another under its
/// weight, gravity `g` [m/s²]: μ g dt ([`BODY_FRICTION`]).
pub fn friction_step(g: f32, dt: f32) -> f32 {
    BODY_FRICTION * g * dt
}

/// The most friction changes the horizontal velocity of a body of mass `m` in a step, pushed by
/// `push` out of another body of mass `m_other` ([`body_push`]), with `friction` its
/// [`friction_step`]: a push within 45° of up rests the body on the other, under its own
/// weight (`friction`); within 45° of down the other rests on it, and the same impulse is a
/// share m_other / m of that; a push from the side (bodies side by side) does not rub: its load
/// is not known here.
pub fn support_friction(push: Vec3, friction: f32, m: f32, m_other: f32) -> Option<f32> {
    if push.y * push.y < push.x * push.x + push.z * push.z || push.y == 0.0 {
        return None;
    }
    Some(if push.y > 0.0 {
        friction
    } else {
        friction * m_other / m
    })
}

/// The gap two bodies the device moves are pushed to at the start of a step of `dt` under
/// gravity `g` [m/s²]: g dt², what one of them, resting on the other and not held by the water,
/// falls onto it in the step. So the pair ends the step touching rather than one inside the
/// other, and the engine's own contact between them (a readback later) finds no overlap to
/// push apart; pushed only out of contact, the upper of two stacked boxes ended each step
/// 1.6 mm inside the lower.
pub fn body_margin(g: f32, dt: f32) -> f32 {
    g * dt * dt
}

/// The push of a boundary sample at `x` out of `other`, another body the device moves, at its
/// pose of the step: back to `margin` outside it (the sample's depth and [`body_margin`]), of
/// which the sample's body takes `share` ([`push_share`]).
pub fn body_push(x: Vec3, other: &Collider, share: f32, margin: f32) -> Vec3 {
    match other.surface_within(x, margin) {
        Some((phi, n)) if phi < margin => n * ((margin - phi) * share),
        _ => Vec3::ZERO,
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
        let along = |length: f32| {
            let mut push = Vec3::ZERO;
            push[a] = length;
            push
        };
        push.add(along((lo[a] - (o - reach)).max(0.0)), Vec3::ZERO);
        push.add(along(-((o + reach) - hi[a]).max(0.0)), Vec3::ZERO);
    }
    push
}

/// The push of a boundary sample at `x`, `depth` inside its own body's surface (the outer
/// layer's, half a spacing: [`crate::boundary::sampling::layer_depths`]), out of the solids it
/// is nearer to than `depth`: n (depth − φ) for each, so the body's surface ends on theirs.
pub fn sample_push<'a>(
    x: Vec3,
    depth: f32,
    solids: impl IntoIterator<Item = &'a Collider>,
) -> Vec3 {
    solids
        .into_iter()
        .filter_map(|c| c.surface_within(x, depth))
        .filter(|&(phi, _)| phi < depth)
        .map(|(phi, n)| (depth - phi) * n)
        .sum()
}

/// Another body the device moves, as one step's contacts see it: its collider at its pose of the
/// step, its mass, and whether a hinge holds it.
#[derive(Clone, Copy, Debug)]
pub struct MovedNeighbour<'a> {
    /// Its collider at its pose of the step.
    pub collider: &'a Collider,
    /// Its mass [kg].
    pub mass: f32,
    /// Whether it turns about an axle (it then gives way to nothing along the push).
    pub hinged: bool,
}

/// One step's pushes on a free body of mass `m` from its boundary samples `samples` (world, at
/// the body's pose of the step; twin of body_placement.wgsl): each sample out of the `solids` to
/// `depth`, its depth inside its body (half a spacing, the outer layer's: [`sample_push`]), and
/// out of each of the `others` to `margin` (the depth and [`body_margin`]) for its share
/// ([`body_push`]), with the friction's limit where one rests on the other
/// ([`support_friction`] with `friction`, the [`friction_step`]). A hinged body gives way to
/// nothing and does not rub: it pushes as a solid at rest.
pub fn sample_pushes(
    samples: impl IntoIterator<Item = Vec3>,
    (depth, margin, friction): (f32, f32, f32),
    m: f32,
    solids: &[Collider],
    others: &[MovedNeighbour],
) -> (AxisPush, BodyPushes) {
    let (mut solid, mut bodies) = (AxisPush::default(), BodyPushes::default());
    for x in samples {
        for (k, other) in others.iter().enumerate() {
            if other.hinged {
                solid.add(body_push(x, other.collider, 1.0, margin), Vec3::ZERO);
                continue;
            }
            let out = body_push(x, other.collider, push_share(m, other.mass), margin);
            bodies.add(out, k, support_friction(out, friction, m, other.mass));
        }
        solid.add(sample_push(x, depth, solids), Vec3::ZERO);
    }
    (solid, bodies)
}

/// A free body after a step's solids and walls (twin of body_motion.wgsl's `resolve_solids`):
/// `stepped` (the body after [`crate::bodies::rigid_step::advance`]) moved by its samples'
/// pushes out of the solids `push` ([`sample_pushes`]), then by the walls of `container` at the
/// pose that gives (`shape` with its centre of mass at `center_of_mass` in its frame); with the
/// directions they pushed it along, in which it gives way to nothing ([`Partner::supported`]).
pub fn resolve_solids(
    push: &AxisPush,
    stepped: &RigidState,
    shape: &ColliderShape,
    center_of_mass: Vec3,
    container: &BoxContainer,
) -> (RigidState, u32) {
    let pushed = push.resolve(stepped);
    let walls = box_push(shape, pose_of(&pushed, center_of_mass), container);
    (
        walls.resolve(&pushed),
        push.directions() | walls.directions(),
    )
}

fn pose_of(state: &RigidState, center_of_mass: Vec3) -> Pose {
    Pose {
        translation: state.origin(center_of_mass),
        rotation: state.rotation,
    }
}

/// A free body of mass `mass` after a step's contacts with the other bodies (twin of
/// body_motion.wgsl's `resolve_bodies`): `state` (after [`resolve_solids`]) moved by the pushes
/// `pushes` out of its `partners` (by index, each after its own solids), its velocity along
/// each push raised to the partner's where a solid pushed the partner the same way (it gives
/// way to nothing along it), and to the pair's common velocity (m v + m_p v_p) / (m + m_p)
/// otherwise (the partner's own resolution meets the same value from the other side, so the
/// pair's momentum is kept); where one rests on the other, friction moves the horizontal
/// velocity toward the common velocity, by at most the limit (the solids do not rub, so the
/// pair's momentum along them is kept too). The walls come last again: they give way to
/// nothing.
pub fn resolve_bodies(
    pushes: &BodyPushes,
    (state, mass, partners): (&RigidState, f32, &[Partner]),
    shape: &ColliderShape,
    center_of_mass: Vec3,
    container: &BoxContainer,
) -> RigidState {
    if pushes.is_empty() {
        return *state;
    }
    let mut floors = AxisPush {
        positive: pushes.positive,
        negative: pushes.negative,
        ..AxisPush::default()
    };
    let (mut low, mut high) = (Vec2::INFINITY, Vec2::NEG_INFINITY);
    for (k, partner) in partners.iter().enumerate().take(32) {
        if pushes.partners & (1 << k) == 0 {
            continue;
        }
        let common = common_velocity(mass, state.linear_velocity, partner.mass, partner.velocity);
        // Along a direction a solid pushed the partner, it gives way to nothing.
        let along = |bit: u32, a: usize| {
            if partner.supported & (1 << bit) != 0 {
                partner.velocity[a]
            } else {
                common[a]
            }
        };
        for a in 0..3 {
            floors.positive_floor[a] = floors.positive_floor[a].max(along(a as u32, a));
            floors.negative_floor[a] = floors.negative_floor[a].max(-along(a as u32 + 3, a));
        }
        low = low.min(Vec2::new(common.x, common.z));
        high = high.max(Vec2::new(common.x, common.z));
    }
    let mut out = floors.resolve(state);
    if pushes.friction_limit > 0.0 && low.x <= high.x {
        let horizontal = Vec2::new(out.linear_velocity.x, out.linear_velocity.z);
        let rub =
            (horizontal.clamp(low, high) - horizontal).clamp_length_max(pushes.friction_limit);
        out.linear_velocity.x += rub.x;
        out.linear_velocity.z += rub.y;
    }
    box_push(shape, pose_of(&out, center_of_mass), container).resolve(&out)
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
        push.add(Vec3::new(0.01, -0.002, 0.0), Vec3::ZERO);
        push.add(Vec3::new(0.004, -0.005, 0.0), Vec3::ZERO);
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

    /// A light box pushed up out of a heavier one: both end the step at the pair's common
    /// velocity from their velocities after the advance (the lower one's slowed by the water),
    /// so their momentum is kept; on a partner that gives way to nothing along the push, the
    /// box keeps the partner's velocity.
    #[test]
    fn a_push_by_a_body_leaves_the_pairs_common_velocity() {
        let (m, m_other) = (1.0, 3.0);
        let (v, v_other) = (Vec3::new(0.2, -0.5, 0.0), Vec3::new(0.0, -0.1, 0.0));
        let common = common_velocity(m, v, m_other, v_other);
        assert!((common.y - -0.2).abs() < 1e-6, "{common}");
        assert!((push_share(m, m_other) - 0.75).abs() < 1e-6);
        let shape = ColliderShape::Sphere { radius: 0.01 };
        let open = BoxContainer::from_min_max(Vec3::splat(-1.0), Vec3::splat(1.0));
        let mut up = BodyPushes::default();
        up.add(Vec3::new(0.0, 0.004, 0.0), 1, None);
        assert_eq!(up.partners, 0b10);
        let state = RigidState {
            position: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            linear_velocity: v,
            angular_velocity: Vec3::ZERO,
        };
        let partners = |supported| {
            [
                Partner {
                    mass: 99.0,
                    velocity: Vec3::splat(9.0),
                    supported: 0,
                },
                Partner {
                    mass: m_other,
                    velocity: v_other,
                    supported,
                },
            ]
        };
        let resolve = |pushes: &BodyPushes, state: &RigidState, m: f32, partners: &[Partner]| {
            resolve_bodies(pushes, (state, m, partners), &shape, Vec3::ZERO, &open)
        };
        let out = resolve(&up, &state, m, &partners(0));
        assert_eq!(out.linear_velocity, Vec3::new(0.2, common.y, 0.0));
        assert_eq!(out.position, Vec3::new(0.0, 0.004, 0.0));
        // Its partner, pushed down by the rest, meets the same velocity from above.
        let mut down = BodyPushes::default();
        down.add(Vec3::new(0.0, -0.001, 0.0), 0, None);
        let partner = RigidState {
            linear_velocity: v_other,
            ..state
        };
        let me = [Partner {
            mass: m,
            velocity: v,
            supported: 0,
        }];
        let out_other = resolve(&down, &partner, m_other, &me);
        assert!((out_other.linear_velocity.y - common.y).abs() < 1e-6);
        let momentum = m * out.linear_velocity.y + m_other * out_other.linear_velocity.y;
        assert!((momentum - (m * v.y + m_other * v_other.y)).abs() < 1e-6);
        // Held up by a solid under it, the partner gives way to nothing: its own velocity.
        let held = resolve(
            &up,
            &state,
            m,
            &partners(push_directions(Vec3::Y, Vec3::ZERO)),
        );
        assert_eq!(held.linear_velocity, Vec3::new(0.2, v_other.y, 0.0));
        // Parting already, the box is not held back.
        let parting = RigidState {
            linear_velocity: Vec3::new(0.2, 0.5, 0.0),
            ..state
        };
        assert_eq!(
            resolve(&up, &parting, m, &partners(0)).linear_velocity,
            parting.linear_velocity
        );
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
        let push = sample_push(Vec3::new(0.08, 0.0, 0.0), 0.005, [&wall]);
        assert!(
            (push - Vec3::new(0.025, 0.0, 0.0)).length() < 1e-3,
            "{push}"
        );
        assert_eq!(
            sample_push(Vec3::new(0.2, 0.0, 0.0), 0.005, [&wall]),
            Vec3::ZERO
        );
        // Half a spacing out: its body's surface touches the wall, no push.
        assert_eq!(
            sample_push(Vec3::new(0.106, 0.0, 0.0), 0.005, [&wall]),
            Vec3::ZERO
        );
        // Out of a body the device moves: back to the margin outside, for the body's share.
        let margin = body_margin(9.81, 1.0 / 120.0);
        let push = body_push(Vec3::new(0.08, 0.0, 0.0), &wall, 0.25, margin);
        let expected = 0.25 * (0.02 + margin);
        assert!(
            (push - Vec3::new(expected, 0.0, 0.0)).length() < 1e-4,
            "{push}"
        );
        let near = Vec3::new(0.1 + 0.5 * margin, 0.0, 0.0);
        assert!(body_push(near, &wall, 1.0, margin).x > 0.0);
        assert_eq!(
            body_push(Vec3::new(0.2, 0.0, 0.0), &wall, 1.0, margin),
            Vec3::ZERO
        );
    }

    /// A box on the floor (1 mm into it after its step) with a box of the same mass pressed
    /// 2 mm into its top: the floor holds it up, so it gives way to nothing downward; its top
    /// samples push it down by its half share, and the floor, resolved last again, puts it back
    /// with no velocity into it, while the upper box keeps the lower one's velocity (it rests);
    /// a hinged box above pushes as a solid and takes none of the push off it.
    #[test]
    fn the_walls_come_after_the_pushes_between_bodies() {
        let spacing = 0.01;
        let shape = ColliderShape::Cuboid {
            half_extents: Vec3::splat(0.04),
        };
        let lower = RigidState {
            position: Vec3::new(0.2, 0.039, 0.2),
            rotation: Quat::IDENTITY,
            linear_velocity: Vec3::new(0.0, -0.1, 0.0),
            angular_velocity: Vec3::ZERO,
        };
        let upper = RigidState {
            position: Vec3::new(0.2, 0.117, 0.2),
            linear_velocity: Vec3::new(0.0, -0.3, 0.0),
            ..lower
        };
        let collider =
            |state: &RigidState| Collider::new(shape.clone(), pose_of(state, Vec3::ZERO));
        let samples = crate::boundary::sampling::sample_shape(&shape, spacing).position;
        let (depth, margin) = (
            0.5 * spacing,
            0.5 * spacing + body_margin(9.81, 1.0 / 120.0),
        );
        let pushes = |own: &RigidState, other: &RigidState, hinged: bool| {
            let other = collider(other);
            let neighbour = MovedNeighbour {
                collider: &other,
                mass: 1.0,
                hinged,
            };
            sample_pushes(
                samples.iter().map(|&p| p + own.position),
                (depth, margin, friction_step(9.81, 1.0 / 120.0)),
                1.0,
                &[],
                &[neighbour],
            )
        };
        let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(0.4));
        let (lower_solids, lower_bodies) = pushes(&lower, &upper, false);
        let (upper_solids, upper_bodies) = pushes(&upper, &lower, false);
        // Half of the 2 mm overlap and the margin past the surface.
        let expected = 0.5 * (0.002 + body_margin(9.81, 1.0 / 120.0));
        assert!(
            (lower_bodies.negative.y - expected).abs() < 1e-5,
            "{lower_bodies:?}"
        );
        assert_eq!(lower_bodies.partners, 1);
        assert!(lower_solids.is_empty() && upper_solids.is_empty());
        let (lower_1, lower_supported) =
            resolve_solids(&lower_solids, &lower, &shape, Vec3::ZERO, &container);
        let (upper_1, upper_supported) =
            resolve_solids(&upper_solids, &upper, &shape, Vec3::ZERO, &container);
        assert_eq!((lower_supported, upper_supported), (1 << 1, 0));
        assert!((lower_1.position.y - 0.04).abs() < 1e-6, "{lower_1:?}");
        assert_eq!(lower_1.linear_velocity.y, 0.0);
        // Each box's second round among the other after its first.
        let second = |bodies: &BodyPushes, own: &RigidState, other: &RigidState, supported| {
            let partner = Partner {
                mass: 1.0,
                velocity: other.linear_velocity,
                supported,
            };
            resolve_bodies(
                bodies,
                (own, 1.0, &[partner]),
                &shape,
                Vec3::ZERO,
                &container,
            )
        };
        let lower_2 = second(&lower_bodies, &lower_1, &upper_1, upper_supported);
        assert!((lower_2.position.y - 0.04).abs() < 1e-6, "{lower_2:?}");
        assert_eq!(lower_2.linear_velocity.y, 0.0);
        let upper_2 = second(&upper_bodies, &upper_1, &lower_1, lower_supported);
        assert_eq!(upper_2.linear_velocity.y, 0.0, "{upper_2:?}");
        let (held, held_bodies) = pushes(&lower, &upper, true);
        assert!((held.negative.y - 2.0 * expected).abs() < 1e-5, "{held:?}");
        assert_eq!((held.negative_floor.y, held_bodies.partners), (0.0, 0));
    }

    /// A crate sliding at `slide` over a raft three times its mass, 2 mm into it, in open water:
    /// each box's pushes out of the other at the states given, resolved; the pair's new
    /// velocities.
    fn rub(slide: f32, side_by_side: bool) -> (Vec3, Vec3) {
        let (spacing, dt) = (0.01, 1.0 / 120.0);
        let shape = ColliderShape::Cuboid {
            half_extents: Vec3::splat(0.04),
        };
        let offset = if side_by_side {
            Vec3::new(0.078, 0.0, 0.0)
        } else {
            Vec3::new(0.0, 0.078, 0.0)
        };
        let raft = RigidState {
            position: Vec3::new(0.2, 0.1, 0.2),
            rotation: Quat::IDENTITY,
            linear_velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
        };
        let crate_ = RigidState {
            position: raft.position + offset,
            linear_velocity: Vec3::new(slide, 0.0, 0.0),
            ..raft
        };
        let (m_crate, m_raft) = (1.0, 3.0);
        let samples = crate::boundary::sampling::sample_shape(&shape, spacing).position;
        let settings = (
            0.5 * spacing,
            0.5 * spacing + body_margin(9.81, dt),
            friction_step(9.81, dt),
        );
        let open = BoxContainer::from_min_max(Vec3::splat(-1.0), Vec3::splat(1.0));
        let resolve = |own: &RigidState, m: f32, other: &RigidState, m_other: f32| {
            let collider = Collider::new(shape.clone(), pose_of(other, Vec3::ZERO));
            let neighbour = MovedNeighbour {
                collider: &collider,
                mass: m_other,
                hinged: false,
            };
            let world = samples.iter().map(|&p| p + own.position);
            let (solids, bodies) = sample_pushes(world, settings, m, &[], &[neighbour]);
            assert!(solids.is_empty() && !bodies.is_empty());
            let partner = Partner {
                mass: m_other,
                velocity: other.linear_velocity,
                supported: 0,
            };
            resolve_bodies(&bodies, (own, m, &[partner]), &shape, Vec3::ZERO, &open).linear_velocity
        };
        (
            resolve(&crate_, m_crate, &raft, m_raft),
            resolve(&raft, m_raft, &crate_, m_crate),
        )
    }

    #[test]
    fn friction_draws_a_resting_pair_together_and_keeps_their_momentum() {
        let limit = friction_step(9.81, 1.0 / 120.0);
        // Sliding fast: the crate loses μ g dt, the raft gains the same impulse.
        let (crate_, raft) = rub(0.5, false);
        assert!((crate_.x - (0.5 - limit)).abs() < 1e-6, "{crate_}");
        assert!((raft.x - limit / 3.0).abs() < 1e-6, "{raft}");
        assert!((crate_.x + 3.0 * raft.x - 0.5).abs() < 1e-6);
        assert_eq!((crate_.z, raft.z), (0.0, 0.0));
        // A slip within the limit is taken whole: both at the pair's common velocity.
        let (crate_, raft) = rub(0.02, false);
        assert!((crate_.x - 0.005).abs() < 1e-6, "{crate_}");
        assert!((raft.x - 0.005).abs() < 1e-6, "{raft}");
        // Side by side, they push apart and do not rub.
        let (crate_, raft) = rub(0.5, true);
        assert_eq!((crate_.x, raft.x), (0.5, 0.0));
        let down = support_friction(Vec3::new(0.0, -1.0, 0.0), limit, 3.0, 1.0);
        assert_eq!(down, Some(limit / 3.0));
        assert_eq!(
            support_friction(Vec3::new(1.0, 0.5, 0.0), limit, 3.0, 1.0),
            None
        );
    }
}

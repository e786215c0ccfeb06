//! Two-way coupling with avian rigid bodies (feature `avian`): a dynamic [`SphCollider`] on an
//! entity that is also an avian [`RigidBody`] receives the water's force and torque every frame
//! as avian's [`ConstantForce`] and [`ConstantTorque`] (the torque taken about the body's centre
//! of mass), avian moves it, and the plugin resamples nothing: it moves the collider's boundary
//! samples with the body's [`GlobalTransform`] and gives them the velocity of that move. The
//! fluid plugin stays engine-agnostic: it only writes [`SphColliderForce`], and this module turns
//! that into avian's forces (the split avian's maintainers ask for, avian issue #265).
//!
//! On the GPU with avian on the water's clock ([`SphWaterTime`]) each dynamic body also carries
//! an [`SphRigidBody`] equal to avian's, and the device moves it with the water at every step
//! (`crate::moved_bodies`): its force is read back a few frames late, and a late force does work
//! on a body that bobs. avian then steps over exactly the frames the device's records cover, in
//! steps of at most a game frame, with their water impulse, moves each body by the gap between
//! the device's steps and its own over them (`sph_core::bodies::engine_window`), and hands its
//! state back with the steady part of its own push on the body (its contacts and joints,
//! `sph_core::bodies::engine_push`), which the device applies at every step until the next; the
//! device adds what only avian saw (contacts, joints, a game's push). Any other
//! dynamic body on the GPU (avian on the game's clock) keeps the older rule: a frame covers at
//! most [`SphControl::max_body_frame_time`] of water while it is in the water.
//!
//! Mass: a free dynamic body (not on a scene's hinge, no locked translation axis) carries
//! [`SphColliderMass`], kept equal to avian's mass, so that DFSPH's solves on the CPU let it give
//! way to the water within a frame (`sph_core::boundary::free_bodies`): a heavy box resting on water no
//! longer rattles between frames.
//!
//! Time: by default avian steps in its fixed schedule by the game's time, the water by its own
//! frame plan; they agree only when the water runs in real-time mode ([`SphControl::real_time`])
//! and keeps up (real-time factor 1). Add avian with `PhysicsPlugins::new(SphWaterTime)`
//! instead, and the plugin runs avian once per frame, after the water's steps, for exactly the
//! simulated time the water gained ([`SphStats::sim_time`]): bodies and water then share one
//! clock at any real-time factor, and paused water pauses the bodies.
//!
//! A scene file's solids become avian bodies too: its container's
//! floor and walls and its static colliders static bodies, its kinematic colliders kinematic
//! ones, and its dynamic colliders dynamic bodies of the file's density or mass, so a boat meets
//! the channel's walls through avian's contacts. A hinged collider (`motion: Hinged(...)`, a
//! water wheel) is a dynamic body on a [`RevoluteJoint`] to a static anchor where it starts,
//! with the hinge's angular damping. A dynamic mesh is given to avian as the convex hulls of its
//! closed parts (a paddle wheel's paddles are exact).
//!
//! ```no_run
//! use avian3d::prelude::*;
//! use bevy::prelude::*;
//! use bevy_sph_fluid::prelude::*;
//! use sph_core::{ColliderMotion, ColliderShape};
//!
//! fn main() {
//!     App::new()
//!         .add_plugins((DefaultPlugins, SphFluidPlugin::default()))
//!         // avian on the water's clock.
//!         .add_plugins(PhysicsPlugins::new(SphWaterTime))
//!         .add_systems(Startup, spawn_boat)
//!         .run();
//! }
//!
//! fn spawn_boat(mut commands: Commands) {
//!     commands.spawn((
//!         RigidBody::Dynamic,
//!         Collider::cuboid(0.2, 0.08, 0.1),
//!         ColliderDensity(400.0),
//!         SphCollider::new(ColliderShape::Cuboid { half_extents: Vec3::new(0.1, 0.04, 0.05) })
//!             .with_motion(ColliderMotion::Dynamic),
//!         Transform::from_xyz(0.3, 0.2, 0.15),
//!     ));
//! }
//! ```

use crate::api::*;
use crate::moved_bodies::SphMovedBodies;
use crate::scene_asset::{SphDynamicBody, SphHinge, SphSceneMember as SceneMember};
use crate::sets::SphSystems;
use avian3d::prelude::*;
use bevy::ecs::schedule::{InternedScheduleLabel, ScheduleLabel};
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use sph_core::bodies::engine_push::EnginePush;
use sph_core::bodies::engine_window::WindowImpulse;
use sph_core::bodies::rigid_step::{RigidBodyModel, RigidState};
use std::time::Duration;

/// The schedule to run avian in (`PhysicsPlugins::new(SphWaterTime)`) so that rigid bodies
/// advance with the water: the plugin runs it once per frame, after the water's steps and the
/// force write-back, with the generic [`Time`] advanced by the simulated time the water gained
/// since the last run (at most [`MAX_WATER_TIME_STEP`] at once).
#[derive(ScheduleLabel, Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SphWaterTime;

/// The most simulated time one run of [`SphWaterTime`] covers [s]: a larger gain (a loaded
/// state, a long hitch) is cut, so bodies never take one huge step.
pub const MAX_WATER_TIME_STEP: f64 = 0.25;

/// The longest step avian takes over a readback's frames [s]: a game frame, near avian's own
/// fixed rate (64 Hz). avian finds its contacts once a step: stepped over the three frames of a
/// readback at once (50 ms), a raft resting on the floor fell 1.4 cm into it before its contact
/// caught it, and the handoff passed that on to the device.
pub const MAX_ENGINE_STEP: f64 = 1.0 / 60.0;

/// The water's simulated time when [`SphWaterTime`] last ran.
#[derive(Default)]
struct WaterTimeSeen(Option<f64>);

/// Runs [`SphWaterTime`] (when the app has it) for the simulated time the water gained: with
/// bodies the device moves (`crate::moved_bodies`), the water time of the frames their records
/// read back cover ([`SphMovedBodies::window`]), in runs of at most [`MAX_ENGINE_STEP`], after
/// which the bodies are at those frames' end.
fn sph_run_physics_on_water_time(world: &mut World, mut seen: Local<WaterTimeSeen>) {
    let now = world.resource::<SphStats>().sim_time;
    let moved = world
        .get_resource::<SphMovedBodies>()
        .filter(|m| m.active());
    if let Some(moved) = moved {
        seen.0 = Some(now);
        let Some(window) = moved.window.clone() else {
            return;
        };
        // Without avian on the water's clock nothing steps the bodies: their engine state
        // stays at its frame.
        let avian = world
            .get_resource::<Schedules>()
            .is_some_and(|s| s.contains(SphWaterTime));
        if avian {
            if window.seconds > 0.0 {
                let seconds = window.seconds.min(MAX_WATER_TIME_STEP);
                // (A window of exactly a game frame is one step, whatever its rounding.)
                let steps = (seconds / MAX_ENGINE_STEP - 1e-6).ceil().max(1.0) as u32;
                let before = engine_states(world);
                for _ in 0..steps {
                    run_on_water_time(world, seconds / steps as f64);
                }
                // A cut window (a long hitch) was not stepped whole: no gap to close, and no
                // push measured over it.
                let whole = seconds == window.seconds;
                if whole {
                    let substeps = world.get_resource::<SubstepCount>().map_or(1, |s| s.0);
                    close_step_gaps(world, &window, steps * substeps.max(1));
                }
                hand_engine_pushes(world, &window, &before, whole);
            }
            world
                .resource_mut::<SphMovedBodies>()
                .engine_stepped(&window);
        }
        return;
    }
    let Some(last) = seen.0.replace(now) else {
        return;
    };
    let gained = (now - last).min(MAX_WATER_TIME_STEP);
    // Paused water, or a reset (time went back): the bodies wait.
    if gained.is_nan() || gained <= 0.0 {
        return;
    }
    run_on_water_time(world, gained);
}

/// Moves each free body avian stepped over `window` in `substeps` substeps of its mean water
/// force by the gap between the device's steps and that free step
/// (`sph_core::bodies::engine_window`): avian then ends the window where the device's steps
/// took the body, and the handoff passes the device only what avian saw beyond the water.
/// Without it, a window of more than a game frame of water left avian centimetres from the
/// device, and the handoff handed the difference on as if it were a contact: a boat was thrown
/// out of the channel at 4 water steps a frame. Bodies that touch in avian's contacts are moved
/// as one ([`WindowImpulse::shared_shift`]), as the device's contact carries them together: each
/// moved by its own gap, a raft the water slapped was moved into the crate on it.
fn close_step_gaps(world: &mut World, window: &crate::moved_bodies::EngineWindow, substeps: u32) {
    let steps = free_steps(world, window);
    // A hinged body has no gap (its axle holds it): it joins no group.
    let free = steps.iter().filter(|(_, s)| s.model.hinge.is_none());
    let groups = touching_groups(world, free.map(|(&e, _)| e));
    for (&entity, step) in &steps {
        let (own, turn) = step
            .water
            .gap(&step.model, step.rotation, substeps, &step.push);
        let shift = match groups.get(&entity) {
            Some(members) if members.len() > 1 => {
                let parts: Vec<_> = members
                    .iter()
                    .map(|e| (&steps[e].water, &steps[e].model, &steps[e].push))
                    .collect();
                WindowImpulse::shared_shift(&parts, substeps)
            }
            _ => own,
        };
        if shift == Vec3::ZERO && turn == Vec3::ZERO {
            continue;
        }
        let Ok(mut body) = world.get_entity_mut(entity) else {
            continue;
        };
        // Turned about the centre of mass, which moves by the shift.
        let center = step.origin + step.rotation * step.model.center_of_mass;
        let turned = sph_core::bodies::rigid_step::turned(step.rotation, turn);
        let moved = center + shift - turned * step.model.center_of_mass;
        if let Some(mut p) = body.get_mut::<Position>() {
            p.0 = moved;
        }
        if let Some(mut r) = body.get_mut::<Rotation>() {
            r.0 = turned;
        }
        // The collider and the engine's state handed to the device are read from it.
        if let Some(mut t) = body.get_mut::<Transform>() {
            t.translation = moved;
            t.rotation = turned;
        }
    }
}

/// What closing a free body's gap over a window needs: its water over the window, its model and
/// pose in avian now, and the push the device applied with the water.
struct FreeStep {
    water: WindowImpulse,
    model: RigidBodyModel,
    origin: Vec3,
    rotation: Quat,
    push: EnginePush,
}

/// Each moved body whose device steps cover the window, by entity.
fn free_steps(
    world: &World,
    window: &crate::moved_bodies::EngineWindow,
) -> HashMap<Entity, FreeStep> {
    let moved = world.resource::<SphMovedBodies>();
    let mut steps = HashMap::new();
    for (&entity, &slot) in &moved.slots {
        // The device's steps and avian's must cover the same water time.
        let Some(water) = window.covered_impulse(slot) else {
            continue;
        };
        let Ok(body) = world.get_entity(entity) else {
            continue;
        };
        let (Some(rigid), Some(position), Some(rotation)) = (
            body.get::<SphRigidBody>(),
            body.get::<Position>(),
            body.get::<Rotation>(),
        ) else {
            continue;
        };
        let (origin, rotation) = (position.0, rotation.0);
        let Some(model) = crate::moved_bodies::body_model(rigid, origin, rotation) else {
            continue;
        };
        // The device stepped the window's frames under the push handed before it (the newest
        // one stands for the few it had then).
        let push = moved
            .engine_pushes
            .get(&entity)
            .copied()
            .unwrap_or_default();
        steps.insert(
            entity,
            FreeStep {
                water,
                model,
                origin,
                rotation,
                push,
            },
        );
    }
    steps
}

/// The `bodies` that touch one another in avian's contacts, directly or through others of
/// them, as groups: each body's group (itself alone when it touches none of them).
fn touching_groups(
    world: &World,
    bodies: impl Iterator<Item = Entity>,
) -> HashMap<Entity, Vec<Entity>> {
    let mut group: HashMap<Entity, Entity> = bodies.map(|e| (e, e)).collect();
    fn root(group: &HashMap<Entity, Entity>, mut e: Entity) -> Entity {
        while group[&e] != e {
            e = group[&e];
        }
        e
    }
    if let Some(contacts) = world.get_resource::<ContactGraph>() {
        let touching = contacts
            .iter_active_touching()
            .chain(contacts.iter_sleeping_touching());
        for pair in touching {
            let a = pair.body1.unwrap_or(pair.collider1);
            let b = pair.body2.unwrap_or(pair.collider2);
            if group.contains_key(&a) && group.contains_key(&b) {
                let (ra, rb) = (root(&group, a), root(&group, b));
                group.insert(ra, rb);
            }
        }
    }
    let mut members: HashMap<Entity, Vec<Entity>> = HashMap::new();
    for &e in group.keys() {
        members.entry(root(&group, e)).or_default().push(e);
    }
    group
        .keys()
        .map(|&e| (e, members[&root(&group, e)].clone()))
        .collect()
}

/// Each moved body's model and state (its centre of mass's) in avian now, by entity.
fn engine_states(world: &World) -> HashMap<Entity, (RigidBodyModel, RigidState)> {
    let mut states = HashMap::new();
    for &entity in world.resource::<SphMovedBodies>().slots.keys() {
        let Ok(body) = world.get_entity(entity) else {
            continue;
        };
        let (Some(rigid), Some(p), Some(r), Some(v), Some(w)) = (
            body.get::<SphRigidBody>(),
            body.get::<Position>(),
            body.get::<Rotation>(),
            body.get::<LinearVelocity>(),
            body.get::<AngularVelocity>(),
        ) else {
            continue;
        };
        let Some(model) = crate::moved_bodies::body_model(rigid, p.0, r.0) else {
            continue;
        };
        let state = RigidState::at_origin(p.0, r.0, v.0, w.0, model.center_of_mass);
        states.insert(entity, (model, state));
    }
    states
}

/// avian's push on each moved body over `window` (`sph_core::bodies::engine_push`: its
/// velocities `before` the window and now, less the water's impulse and gravity), steadied
/// with the one handed before, handed to the device with the body's state
/// ([`SphMovedBodies::engine_pushes`]). A window not stepped whole, or whose water was not all
/// read back, hands none (the steady push starts again).
fn hand_engine_pushes(
    world: &mut World,
    window: &crate::moved_bodies::EngineWindow,
    before: &HashMap<Entity, (RigidBodyModel, RigidState)>,
    whole: bool,
) {
    let after = engine_states(world);
    let moved = world.resource::<SphMovedBodies>();
    let mut pushes = HashMap::new();
    for (entity, slot) in &moved.slots {
        let (Some((model, start)), Some((_, end)), Some(water), true) = (
            before.get(entity),
            after.get(entity),
            window.covered_impulse(*slot),
            whole,
        ) else {
            continue;
        };
        let push = EnginePush::measured(
            model,
            start,
            end,
            water.impulse,
            water.angular_impulse,
            water.duration,
        );
        let handed = moved.engine_pushes.get(entity).copied().unwrap_or_default();
        pushes.insert(*entity, push.steadied(&handed, water.duration));
    }
    world.resource_mut::<SphMovedBodies>().engine_pushes = pushes;
}

/// Runs [`SphWaterTime`] once with the generic [`Time`] advanced by `seconds`.
fn run_on_water_time(world: &mut World, seconds: f64) {
    let saved = *world.resource::<Time>();
    let mut clock = Time::<()>::default();
    clock.advance_by(Duration::from_secs_f64(seconds));
    *world.resource_mut::<Time>() = clock;
    // An app that runs avian in another schedule has no `SphWaterTime`: nothing runs.
    let _ = world.try_run_schedule(SphWaterTime);
    *world.resource_mut::<Time>() = saved;
}

pub(crate) fn add_systems(app: &mut App, schedule: InternedScheduleLabel) {
    app.add_systems(
        schedule,
        (
            // Only in an app that runs avian (its plugins insert `Gravity`).
            sph_avian_scene_bodies
                .in_set(SphSystems::Prepare)
                .run_if(resource_exists::<Gravity>),
            sph_avian_body_masses
                .in_set(SphSystems::Prepare)
                .before(crate::colliders::sph_sync_colliders),
            // Before the frame is planned: a body the device moves does not cut the frame.
            sph_avian_rigid_bodies.before(SphSystems::Prepare),
            sph_drive_avian_bodies
                .in_set(SphSystems::Writeback)
                .after(crate::colliders::sph_write_collider_forces)
                .after(crate::moved_bodies::sph_moved_bodies_window),
            sph_run_physics_on_water_time
                .in_set(SphSystems::Writeback)
                .after(sph_drive_avian_bodies),
        ),
    );
}

/// avian's collider of the same shape (`None` when avian refuses a mesh).
fn avian_collider(shape: &sph_core::ColliderShape, dynamic: bool) -> Option<Collider> {
    use sph_core::ColliderShape as S;
    Some(match *shape {
        // A moving mesh needs volume and inertia: the convex hull of each of its closed parts
        // (exact for a paddle wheel's boxes).
        S::TriMesh(ref mesh) if dynamic => {
            let parts: Vec<_> = mesh
                .closed_parts()
                .into_iter()
                .filter_map(Collider::convex_hull)
                .map(|hull| (Vec3::ZERO, Quat::IDENTITY, hull))
                .collect();
            if parts.is_empty() {
                warn!("SphFluidPlugin: avian found no convex part in a dynamic mesh collider");
                return None;
            }
            Collider::compound(parts)
        }
        S::Cuboid { half_extents: h } => Collider::cuboid(2.0 * h.x, 2.0 * h.y, 2.0 * h.z),
        S::Sphere { radius } => Collider::sphere(radius),
        S::Capsule {
            radius,
            half_length,
        } => Collider::capsule(radius, 2.0 * half_length),
        S::Cylinder {
            radius,
            half_length,
        } => Collider::cylinder(radius, 2.0 * half_length),
        S::TriMesh(ref mesh) => {
            let (vertices, indices) = mesh.indexed();
            match Collider::try_trimesh(vertices, indices) {
                Ok(c) => c,
                Err(e) => {
                    warn!("SphFluidPlugin: avian refused a mesh collider: {e:?}");
                    return None;
                }
            }
        }
    })
}

/// A scene's solid as it appears, with its mass when dynamic and its hinge when hinged.
type NewSceneSolid<'a> = (
    Entity,
    &'a SphCollider,
    Option<&'a SphDynamicBody>,
    Option<&'a SphHinge>,
    &'a SceneMember,
    &'a Transform,
);

/// Wall thickness of a scene container's avian walls [m] (outside the box).
const WALL: f32 = 0.05;

/// A scene file's new solids as avian bodies (entities that already are avian bodies are left
/// alone).
fn sph_avian_scene_bodies(
    mut commands: Commands,
    colliders: Query<NewSceneSolid, (Added<SceneMember>, Without<RigidBody>)>,
    containers: Query<(Entity, &SphContainer), Added<SceneMember>>,
) {
    for (entity, collider, body, hinge, member, transform) in &colliders {
        let rigid = match collider.motion {
            sph_core::ColliderMotion::Static => RigidBody::Static,
            sph_core::ColliderMotion::Kinematic => RigidBody::Kinematic,
            sph_core::ColliderMotion::Dynamic => RigidBody::Dynamic,
        };
        let mut e = commands.entity(entity);
        e.insert(rigid);
        if let Some(shape) = avian_collider(&collider.shape, rigid == RigidBody::Dynamic) {
            e.insert(shape);
        }
        if let Some(SphHinge(hinge)) = hinge {
            e.insert(AngularDamping(hinge.damping));
            // The axle: a static body where the collider starts, turned like it, so the hinge's
            // axis is the same in both local frames; both belong to the scene.
            let anchor = commands
                .spawn((RigidBody::Static, *transform, *member))
                .id();
            let local_axis = transform.rotation.inverse() * hinge.axis;
            commands.spawn((
                RevoluteJoint::new(anchor, entity).with_hinge_axis(local_axis),
                *member,
            ));
        }
        let mut e = commands.entity(entity);
        match body.map(|b| b.0) {
            Some(sph_core::scene::BodyMass::Density(d)) => {
                e.insert(ColliderDensity(d));
            }
            Some(sph_core::scene::BodyMass::Mass(m)) => {
                e.insert(Mass(m));
            }
            None => {}
        }
    }
    for (entity, container) in &containers {
        // The walls are its children: it needs a (world-aligned) transform for theirs to
        // propagate (Bevy's B0004).
        commands
            .entity(entity)
            .insert_if_new((Transform::IDENTITY, GlobalTransform::IDENTITY));
        let (lo, hi) = (container.min(), container.max());
        let (size, center) = (hi - lo, 0.5 * (lo + hi));
        let slabs = [
            (
                Vec3::new(size.x + 2.0 * WALL, WALL, size.z + 2.0 * WALL),
                Vec3::new(center.x, lo.y - 0.5 * WALL, center.z),
            ),
            (
                Vec3::new(WALL, size.y, size.z),
                Vec3::new(lo.x - 0.5 * WALL, center.y, center.z),
            ),
            (
                Vec3::new(WALL, size.y, size.z),
                Vec3::new(hi.x + 0.5 * WALL, center.y, center.z),
            ),
            (
                Vec3::new(size.x, size.y, WALL),
                Vec3::new(center.x, center.y, lo.z - 0.5 * WALL),
            ),
            (
                Vec3::new(size.x, size.y, WALL),
                Vec3::new(center.x, center.y, hi.z + 0.5 * WALL),
            ),
        ];
        for (extent, at) in slabs {
            commands.spawn((
                RigidBody::Static,
                Collider::cuboid(extent.x, extent.y, extent.z),
                Transform::from_translation(at),
                // A child of the container: a reload despawns it with the container.
                ChildOf(entity),
            ));
        }
    }
}

/// A dynamic collider's avian mass, what stops it from giving way, and its [`SphColliderMass`].
type AvianMass<'a> = (
    Entity,
    &'a SphCollider,
    &'a ComputedMass,
    Option<&'a LockedAxes>,
    Option<&'a SphHinge>,
    Option<&'a mut SphColliderMass>,
);

/// Every free dynamic avian body's [`SphColliderMass`] follows avian's mass, so that DFSPH's
/// solves let it give way within a frame. A body on a scene's hinge, or with a locked
/// translation axis, gets none (the water would expect it to give way where avian holds it).
fn sph_avian_body_masses(mut commands: Commands, mut bodies: Query<AvianMass, With<RigidBody>>) {
    for (entity, collider, computed, locked, hinge, current) in &mut bodies {
        let held = hinge.is_some()
            || locked.is_some_and(|l| {
                l.is_translation_x_locked()
                    || l.is_translation_y_locked()
                    || l.is_translation_z_locked()
            });
        let mass = computed.value();
        let free = collider.motion == sph_core::ColliderMotion::Dynamic
            && !held
            && mass.is_finite()
            && mass > 0.0;
        match (free, current) {
            (true, Some(mut m)) if m.0 != mass => m.0 = mass,
            (true, None) => {
                commands.entity(entity).insert(SphColliderMass(mass));
            }
            (false, Some(_)) => {
                commands.entity(entity).remove::<SphColliderMass>();
            }
            _ => {}
        }
    }
}

/// A dynamic collider's avian body, as the device moves it.
type AvianRigid<'a> = (
    Entity,
    &'a SphCollider,
    (
        &'a ComputedMass,
        &'a ComputedCenterOfMass,
        &'a ComputedAngularInertia,
    ),
    (
        Option<&'a Collider>,
        Option<&'a ColliderDensity>,
        Option<&'a Mass>,
    ),
    (&'a LinearVelocity, &'a AngularVelocity),
    (
        Option<&'a LockedAxes>,
        Option<&'a SphHinge>,
        Option<&'a LinearDamping>,
        Option<&'a AngularDamping>,
        Option<&'a GravityScale>,
    ),
    Option<&'a mut SphRigidBody>,
);

/// A body's mass [kg], centre of mass and inverse inertia tensor (both in its frame): its own
/// collider's at its `ColliderDensity` (scaled to its `Mass` when it has one), as avian computes
/// them, or avian's computed ones for a body without a collider of its own. avian computes its
/// own only when it steps, and a body the device moves from its first frame on must not move
/// with the default density's mass until then (a wheel of 900 kg/m³ taken at 1 kg/m³ spun off).
fn mass_properties(
    computed: (
        &ComputedMass,
        &ComputedCenterOfMass,
        &ComputedAngularInertia,
    ),
    own: (Option<&Collider>, Option<&ColliderDensity>, Option<&Mass>),
) -> (f32, Vec3, Mat3) {
    use avian3d::dynamics::rigid_body::mass_properties::bevy_heavy::ComputeMassProperties3d;
    let (mass, center, inertia) = computed;
    let (Some(collider), density, given) = own else {
        return (mass.value(), center.0, inertia.inverse().to_mat3());
    };
    let props = collider.mass_properties(density.map_or(1.0, |d| d.0));
    let scale = match given {
        Some(m) if props.mass > 0.0 => m.0 / props.mass,
        _ => 1.0,
    };
    let principal = props.principal_angular_inertia * scale;
    let frame = Mat3::from_quat(props.local_inertial_frame);
    let inverse = Vec3::select(principal.cmpgt(Vec3::ZERO), principal.recip(), Vec3::ZERO);
    (
        props.mass * scale,
        props.center_of_mass,
        frame * Mat3::from_diagonal(inverse) * frame.transpose(),
    )
}

/// On the GPU backend with avian on the water's clock ([`SphWaterTime`]), every dynamic
/// collider's avian body carries an [`SphRigidBody`] equal to avian's, so that the device moves
/// it with the water at every step (`crate::moved_bodies`); otherwise none.
fn sph_avian_rigid_bodies(
    mut commands: Commands,
    mut bodies: Query<AvianRigid, With<RigidBody>>,
    gravity: Option<Res<Gravity>>,
    schedules: Res<Schedules>,
    sim: Res<crate::shared::SphSimulation>,
) {
    let device = sim.backend == SphBackend::Gpu && schedules.contains(SphWaterTime);
    let g = gravity.map_or(Vec3::new(0.0, -9.81, 0.0), |g| g.0);
    for (entity, collider, mass, own, velocity, extra, current) in &mut bodies {
        let (mass, center_of_mass, inverse_inertia) = mass_properties(mass, own);
        let (locked, hinge, linear_damping, angular_damping, scale) = extra;
        if !device || collider.motion != sph_core::ColliderMotion::Dynamic {
            if current.is_some() {
                commands.entity(entity).remove::<SphRigidBody>();
            }
            continue;
        }
        let free = |locked: bool| if locked { 0.0 } else { 1.0 };
        let l = locked.copied().unwrap_or_default();
        let body = SphRigidBody {
            mass,
            center_of_mass,
            inverse_inertia,
            free_translation: Vec3::new(
                free(l.is_translation_x_locked()),
                free(l.is_translation_y_locked()),
                free(l.is_translation_z_locked()),
            ),
            free_rotation: Vec3::new(
                free(l.is_rotation_x_locked()),
                free(l.is_rotation_y_locked()),
                free(l.is_rotation_z_locked()),
            ),
            hinge_axis: hinge.map(|h| h.0.axis),
            gravity: g * scale.map_or(1.0, |s| s.0),
            linear_damping: linear_damping.map_or(0.0, |d| d.0),
            angular_damping: angular_damping.map_or(0.0, |d| d.0),
            linear_velocity: velocity.0 .0,
            angular_velocity: velocity.1 .0,
        };
        match current {
            Some(mut c) if *c != body => *c = body,
            Some(_) => {}
            None => {
                commands.entity(entity).insert(body);
            }
        }
    }
}

/// A dynamic collider that avian moves.
type AvianBody<'a> = (
    Entity,
    &'a SphCollider,
    &'a SphColliderForce,
    &'a GlobalTransform,
    Option<&'a ComputedCenterOfMass>,
    Option<&'a mut ConstantForce>,
    Option<&'a mut ConstantTorque>,
);

/// An avian body the device moves, as the engine takes the device's newest record whole.
type TakenWhole<'a> = (
    &'a mut Position,
    &'a mut Rotation,
    &'a mut LinearVelocity,
    &'a mut AngularVelocity,
);

/// The water's force on each dynamic collider becomes its avian body's constant force and
/// torque (replaced every frame). A body the device moves takes its water impulse over the
/// engine's window instead ([`SphMovedBodies::window`]), spread over the window's time, or,
/// when some of its records were lost, the device's newest record whole.
fn sph_drive_avian_bodies(
    mut commands: Commands,
    mut bodies: Query<AvianBody, With<RigidBody>>,
    mut whole: Query<TakenWhole, With<RigidBody>>,
    moved: Res<SphMovedBodies>,
) {
    for (entity, collider, water, transform, com, force, torque) in &mut bodies {
        if collider.motion != sph_core::ColliderMotion::Dynamic {
            continue;
        }
        let origin = transform.translation();
        // The torque about the centre of mass: τ_c = τ_o − (c − o) × f.
        let center = com.map_or(origin, |c| transform.transform_point(c.0));
        let mut water = (
            water.force,
            water.torque - (center - origin).cross(water.force),
        );
        if let Some(&slot) = moved.slots.get(&entity) {
            let window = moved.window.as_ref();
            water = match window.map(|w| (w, w.impulses.get(&slot).copied().flatten())) {
                Some((w, Some(push))) if w.seconds > 0.0 => {
                    let per = (1.0 / w.seconds) as f32;
                    (push.impulse * per, push.angular_impulse * per)
                }
                Some((w, None)) => {
                    if let (Some(record), Ok(mut body)) =
                        (w.newest.get(&slot), whole.get_mut(entity))
                    {
                        let s = record.state;
                        let local = com.map_or(Vec3::ZERO, |c| c.0);
                        body.0 .0 = s.position - s.rotation * local;
                        body.1 .0 = s.rotation;
                        body.2 .0 = s.linear_velocity;
                        body.3 .0 = s.angular_velocity;
                    }
                    (Vec3::ZERO, Vec3::ZERO)
                }
                _ => (Vec3::ZERO, Vec3::ZERO),
            };
        }
        let (water_force, about_center) = water;
        match force {
            Some(mut f) => f.0 = water_force,
            None => {
                commands.entity(entity).insert(ConstantForce(water_force));
            }
        }
        match torque {
            Some(mut t) => t.0 = about_center,
            None => {
                commands.entity(entity).insert(ConstantTorque(about_center));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::moved_bodies::{body_model, EngineWindow};
    use sph_core::bodies::engine_handoff::DeviceBody;
    use sph_core::bodies::engine_window::WindowImpulse;
    use sph_core::bodies::rigid_step::RigidState;

    /// A free body of 2 kg as both sides hold it.
    fn rigid() -> SphRigidBody {
        SphRigidBody {
            mass: 2.0,
            center_of_mass: Vec3::ZERO,
            inverse_inertia: Mat3::from_diagonal(Vec3::splat(25.0)),
            free_translation: Vec3::ONE,
            free_rotation: Vec3::ONE,
            hinge_axis: None,
            gravity: Vec3::new(0.0, -9.81, 0.0),
            linear_damping: 0.0,
            angular_damping: 0.0,
            linear_velocity: Vec3::new(0.2, 0.0, 0.0),
            angular_velocity: Vec3::ZERO,
        }
    }

    /// The device's three frames of four steps of 1/240 s (a window of 0.05 s, three runs of
    /// avian): a wave's slap in the first steps, then the weight carried; the window read back
    /// and the device's body at its end.
    fn device_window(start: Vec3) -> (EngineWindow, RigidState) {
        let body = rigid();
        let model = body_model(&body, start, Quat::IDENTITY).unwrap();
        let mut device = DeviceBody {
            state: Some(RigidState {
                position: start,
                rotation: Quat::IDENTITY,
                linear_velocity: body.linear_velocity,
                angular_velocity: Vec3::ZERO,
            }),
            ..Default::default()
        };
        let dt = 1.0 / 240.0;
        let mut records = Vec::new();
        for frame in 1..=3u32 {
            device.begin_frame(frame);
            for step in 0..4 {
                let slap = if frame == 1 && step < 2 { 30.0 } else { 0.0 };
                let force = Vec3::new(slap, 19.62, 0.5 * slap);
                let torque = Vec3::new(0.0, 0.0, 0.1 * slap);
                let c = device.state.unwrap().position;
                device.step(&model, force, torque + c.cross(force), dt);
            }
            device.end_frame((frame as f64 * 4.0 * dt as f64 * 1e9).round() as u64);
            records.push(device.records[frame as usize % 8].unwrap());
        }
        let newest = *records.last().unwrap();
        let window = EngineWindow {
            to_frame: 3,
            time_ns: newest.time_ns,
            seconds: newest.time_ns as f64 * 1e-9,
            impulses: [(0, Some(WindowImpulse::over(&records, newest.time_ns)))].into(),
            newest: [(0, newest)].into(),
        };
        (window, device.state.unwrap())
    }

    /// An app with avian on the water's clock, under [`rigid`]'s gravity.
    fn avian_app() -> App {
        let mut app = App::new();
        app.add_plugins((
            MinimalPlugins,
            TransformPlugin,
            PhysicsPlugins::new(SphWaterTime),
        ));
        app.insert_resource(Gravity(rigid().gravity));
        app.init_resource::<SphStats>();
        app.finish();
        app
    }

    /// avian, stepped over a window with its mean water force and moved by the gap, ends it
    /// where the device's steps took the body: the handoff then has nothing to pass on.
    #[test]
    fn avian_ends_a_window_where_the_devices_steps_took_the_body() {
        let start = Vec3::new(0.3, 0.5, 0.2);
        let (window, device) = device_window(start);
        let mut app = avian_app();
        app.insert_resource(SubstepCount(6));
        let entity = app
            .world_mut()
            .spawn((
                RigidBody::Dynamic,
                Mass(2.0),
                AngularInertia::new(Vec3::splat(1.0 / 25.0)),
                LinearVelocity(rigid().linear_velocity),
                SphCollider::new(sph_core::ColliderShape::Sphere { radius: 0.05 })
                    .with_motion(sph_core::ColliderMotion::Dynamic),
                SphColliderForce::default(),
                rigid(),
                Transform::from_translation(start),
            ))
            .id();
        app.update();
        let mut moved = SphMovedBodies::default();
        moved.slots.insert(entity, 0);
        moved.window = Some(window.clone());
        app.insert_resource(moved);
        let world = app.world_mut();
        world.run_system_cached(sph_drive_avian_bodies).unwrap();
        world
            .run_system_cached(sph_run_physics_on_water_time)
            .unwrap();
        let position = world.get::<Position>(entity).unwrap().0;
        let rotation = world.get::<Rotation>(entity).unwrap().0;
        let velocity = world.get::<LinearVelocity>(entity).unwrap().0;
        let transform = world.get::<Transform>(entity).unwrap();
        assert_eq!(transform.translation, position);
        assert!(
            (position - device.position).length() < 2e-5,
            "avian {position}, device {}",
            device.position
        );
        assert!(
            (velocity - device.linear_velocity).length() < 1e-4,
            "{velocity}"
        );
        let left = (Vec4::from(rotation) - Vec4::from(device.rotation)).length();
        assert!(left < 1e-4, "avian {rotation}, device {}", device.rotation);
        // Without the gap avian would have ended the window millimetres short: the slap early
        // in the window carried the device's body further than its mean force carried avian's.
        let push = window.impulses[&0].unwrap();
        let model = body_model(&rigid(), position, rotation).unwrap();
        let (shift, _) = push.gap(&model, rotation, 3 * 6, &EnginePush::default());
        assert!(shift.length() > 1e-3, "{shift}");
        assert_eq!(world.resource::<SphMovedBodies>().engine_frame, Some(3));
    }

    /// A box resting on a static floor that only avian knows of, no water: avian hands the
    /// device the floor's push, the box's weight upward, taken up over the push's time constant
    /// (the device then holds the box up between avian's states); the first window's is a
    /// small share of it (a blow is not carried on whole).
    #[test]
    fn avian_hands_the_device_the_push_of_a_resting_contact() {
        let mut app = avian_app();
        app.world_mut().spawn((
            RigidBody::Static,
            Collider::cuboid(2.0, 0.2, 2.0),
            Transform::from_xyz(0.0, -0.1, 0.0),
        ));
        let resting = SphRigidBody {
            linear_velocity: Vec3::ZERO,
            ..rigid()
        };
        let entity = app
            .world_mut()
            .spawn((
                RigidBody::Dynamic,
                Collider::cuboid(0.2, 0.2, 0.2),
                Mass(2.0),
                AngularInertia::new(Vec3::splat(1.0 / 25.0)),
                SphCollider::new(sph_core::ColliderShape::Cuboid {
                    half_extents: Vec3::splat(0.1),
                })
                .with_motion(sph_core::ColliderMotion::Dynamic),
                SphColliderForce::default(),
                resting,
                Transform::from_xyz(0.0, 0.1, 0.0),
            ))
            .id();
        app.update();
        let mut moved = SphMovedBodies::default();
        moved.slots.insert(entity, 0);
        app.insert_resource(moved);
        let frame = 1.0 / 60.0;
        let mut handed = Vec::new();
        // 1.5 s of windows: six time constants.
        for window in 1..=90u32 {
            let world = app.world_mut();
            let dry = WindowImpulse {
                duration: frame as f32,
                ..Default::default()
            };
            world.resource_mut::<SphMovedBodies>().window = Some(EngineWindow {
                to_frame: window,
                time_ns: (window as f64 * frame * 1e9).round() as u64,
                seconds: frame,
                impulses: [(0, Some(dry))].into(),
                newest: Default::default(),
            });
            world.run_system_cached(sph_drive_avian_bodies).unwrap();
            world
                .run_system_cached(sph_run_physics_on_water_time)
                .unwrap();
            let pushes = &world.resource::<SphMovedBodies>().engine_pushes;
            handed.push(pushes.get(&entity).copied());
        }
        let weight = 2.0 * rigid().gravity;
        let first = handed[0].expect("a push after a window");
        assert!(first.force.length() < 0.1 * weight.length(), "{first:?}");
        let last = handed[89].expect("a push after the last window");
        assert!(
            (last.force + weight).length() < 0.02 * weight.length(),
            "{last:?}"
        );
        assert!(last.torque.length() < 1e-3, "{handed:?}");
        let y = app.world().get::<Position>(entity).unwrap().0.y;
        assert!((y - 0.1).abs() < 5e-3, "the box rests: {y}");
    }

    /// A crate resting on a raft in avian, the water slapping the raft early in the window:
    /// closing the gaps moves both by one shift, the pair's as one body, so avian's crate stays
    /// on avian's raft; a box apart from them takes its own gap.
    #[test]
    fn bodies_touching_in_avian_share_one_gap() {
        let mut app = avian_app();
        app.world_mut().spawn((
            RigidBody::Static,
            Collider::cuboid(4.0, 0.2, 4.0),
            Transform::from_xyz(0.0, -0.1, 0.0),
        ));
        let mut body = |mass: f32, half: Vec3, at: Vec3| {
            let rigid = SphRigidBody {
                mass,
                linear_velocity: Vec3::ZERO,
                ..rigid()
            };
            app.world_mut()
                .spawn((
                    RigidBody::Dynamic,
                    Collider::cuboid(2.0 * half.x, 2.0 * half.y, 2.0 * half.z),
                    Mass(mass),
                    AngularInertia::new(Vec3::splat(1.0 / 25.0)),
                    SphCollider::new(sph_core::ColliderShape::Cuboid { half_extents: half })
                        .with_motion(sph_core::ColliderMotion::Dynamic),
                    SphColliderForce::default(),
                    rigid,
                    Transform::from_translation(at),
                ))
                .id()
        };
        let raft = body(2.0, Vec3::new(0.2, 0.05, 0.2), Vec3::new(0.0, 0.05, 0.0));
        let krate = body(0.5, Vec3::splat(0.05), Vec3::new(0.0, 0.15, 0.0));
        let apart = body(2.0, Vec3::new(0.2, 0.05, 0.2), Vec3::new(1.0, 0.05, 0.0));
        app.update();
        // Settled for a few frames: avian's contacts hold the crate on the raft.
        for _ in 0..10 {
            run_on_water_time(app.world_mut(), 1.0 / 60.0);
        }
        let (mut window, _) = device_window(Vec3::ZERO);
        let slapped = window.impulses[&0].unwrap();
        let dry = WindowImpulse {
            duration: slapped.duration,
            time_lever: slapped.time_lever,
            ..Default::default()
        };
        window.impulses = [(0, Some(slapped)), (1, Some(dry)), (2, Some(slapped))].into();
        let mut moved = SphMovedBodies::default();
        moved.slots.extend([(raft, 0), (krate, 1), (apart, 2)]);
        app.insert_resource(moved);
        let world = app.world_mut();
        let at = |world: &World, e: Entity| world.get::<Position>(e).unwrap().0;
        let before = [raft, krate, apart].map(|e| at(world, e));
        close_step_gaps(world, &window, 18);
        let shifts: Vec<Vec3> = [raft, krate, apart]
            .iter()
            .zip(before)
            .map(|(&e, b)| at(world, e) - b)
            .collect();
        let model = |e: Entity| {
            let rigid = world.get::<SphRigidBody>(e).unwrap();
            body_model(rigid, Vec3::ZERO, Quat::IDENTITY).unwrap()
        };
        let none = EnginePush::default();
        let (raft_model, crate_model) = (model(raft), model(krate));
        let parts = [(&slapped, &raft_model, &none), (&dry, &crate_model, &none)];
        let shared = WindowImpulse::shared_shift(&parts, 18);
        let (own, _) = slapped.gap(&model(apart), Quat::IDENTITY, 18, &none);
        assert!(shared.length() > 1e-4, "{shared}");
        assert!((shifts[0] - shared).length() < 1e-6, "{shifts:?} {shared}");
        assert!((shifts[1] - shared).length() < 1e-6, "{shifts:?} {shared}");
        assert!((shifts[2] - own).length() < 1e-6, "{shifts:?} {own}");
        assert!((own - shared).length() > 1e-4, "{own} {shared}");
    }
}

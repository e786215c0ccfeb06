//! Two-way coupling with avian rigid bodies (feature `avian`): a dynamic [`SphCollider`] on an
//! entity that is also an avian [`RigidBody`] receives the water's force and torque every frame
//! as avian's [`ConstantForce`] and [`ConstantTorque`] (the torque taken about the body's centre
//! of mass), avian moves it, and the plugin resamples nothing: it moves the collider's boundary
//! samples with the body's [`GlobalTransform`] and gives them the velocity of that move. The
//! fluid plugin stays engine-agnostic: it only writes [`SphColliderForce`], and this module turns
//! that into avian's forces (the split avian's maintainers ask for, avian issue #265). On the
//! GPU the force is summed on the device and read back a frame or two late, without a stall.
//!
//! ```no_run
//! use avian3d::prelude::*;
//! use bevy::prelude::*;
//! use bevy_sph_fluid::prelude::*;
//! use sph_core::{ColliderMotion, ColliderShape};
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
use crate::sets::SphSystems;
use avian3d::prelude::*;
use bevy::ecs::schedule::InternedScheduleLabel;
use bevy::prelude::*;

pub(crate) fn add_systems(app: &mut App, schedule: InternedScheduleLabel) {
    app.add_systems(
        schedule,
        sph_drive_avian_bodies
            .in_set(SphSystems::Writeback)
            .after(crate::colliders::sph_write_collider_forces),
    );
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

/// The water's force on each dynamic collider becomes its avian body's constant force and
/// torque (replaced every frame).
fn sph_drive_avian_bodies(mut commands: Commands, mut bodies: Query<AvianBody, With<RigidBody>>) {
    for (entity, collider, water, transform, com, force, torque) in &mut bodies {
        if collider.motion != sph_core::ColliderMotion::Dynamic {
            continue;
        }
        let origin = transform.translation();
        // The torque about the centre of mass: τ_c = τ_o − (c − o) × f.
        let center = com.map_or(origin, |c| transform.transform_point(c.0));
        let about_center = water.torque - (center - origin).cross(water.force);
        match force {
            Some(mut f) => f.0 = water.force,
            None => {
                commands.entity(entity).insert(ConstantForce(water.force));
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

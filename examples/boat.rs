//! Bodies in water with avian: a crate (500 kg/m³) and a boat-shaped hull (350 kg/m³) float, a
//! stone ball (2,500 kg/m³) sinks to the floor. Each body is an avian `RigidBody` with a
//! `SphCollider` of the same shape moved as `ColliderMotion::Dynamic`: the water's force and
//! torque reach avian every frame, and avian runs on the water's clock (`SphWaterTime`).
//!
//! Run: `cargo run --release --example boat`. Needs `bevy_sph_fluid`'s `avian` feature.

use avian3d::prelude::*;
use bevy::prelude::*;
use bevy_sph_fluid::prelude::*;
use sph_core::{BlockSpawn, BoxContainer, ColliderMotion, ColliderShape};
use std::f32::consts::FRAC_PI_2;

/// The tank: 1.2 m long, 0.5 m high, 0.6 m deep, its floor at the origin.
const TANK: Vec3 = Vec3::new(1.2, 0.5, 0.6);

fn main() {
    App::new()
        .add_plugins((DefaultPlugins, SphFluidPlugin::default()))
        // avian steps once per frame for exactly the simulated time the water gained.
        .add_plugins(PhysicsPlugins::new(SphWaterTime))
        .add_systems(Startup, (spawn_tank, spawn_bodies, spawn_view))
        .run();
}

/// The water (0.2 m deep) and the tank's floor and walls for avian, which the water already
/// has as its container.
fn spawn_tank(mut commands: Commands) {
    commands.spawn(SphContainer(BoxContainer::from_min_max(Vec3::ZERO, TANK)));
    let water = BlockSpawn::new(Vec3::ZERO, Vec3::new(TANK.x, 0.2, TANK.z), 0.02);
    commands.spawn(SphBlockSpawn {
        block: water,
        velocity: Vec3::ZERO,
    });
    // Slabs 5 cm thick outside the container: the floor and the four walls.
    let t = 0.05;
    for (axis, far_side) in [(1, false), (0, false), (0, true), (2, false), (2, true)] {
        let (mut size, mut centre) = (TANK, 0.5 * TANK);
        size[axis] = t;
        centre[axis] = if far_side {
            TANK[axis] + 0.5 * t
        } else {
            -0.5 * t
        };
        commands.spawn((
            RigidBody::Static,
            Collider::cuboid(size.x, size.y, size.z),
            Transform::from_translation(centre),
        ));
    }
}

/// A body in the water: the same shape for avian and for the water, placed by `at`.
fn body(shape: ColliderShape, collider: Collider, density: f32, at: Transform) -> impl Bundle {
    (
        RigidBody::Dynamic,
        collider,
        ColliderDensity(density),
        SphCollider::new(shape).with_motion(ColliderMotion::Dynamic),
        at,
    )
}

fn spawn_bodies(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let half = Vec3::new(0.06, 0.06, 0.06);
    let crate_shape = ColliderShape::Cuboid { half_extents: half };
    commands.spawn((
        body(
            crate_shape,
            Collider::cuboid(0.12, 0.12, 0.12),
            500.0,
            Transform::from_xyz(0.3, 0.3, 0.3),
        ),
        Mesh3d(meshes.add(Cuboid::from_size(2.0 * half))),
        MeshMaterial3d(materials.add(Color::srgb(0.6, 0.4, 0.2))),
    ));
    // The hull: a capsule (along y in both engines) laid along x, 0.3 m long.
    let (radius, half_length) = (0.05, 0.1);
    let hull = ColliderShape::Capsule {
        radius,
        half_length,
    };
    let lying = Transform::from_xyz(0.8, 0.3, 0.3).with_rotation(Quat::from_rotation_z(FRAC_PI_2));
    commands.spawn((
        body(
            hull,
            Collider::capsule(radius, 2.0 * half_length),
            350.0,
            lying,
        ),
        Mesh3d(meshes.add(Capsule3d::new(radius, 2.0 * half_length))),
        MeshMaterial3d(materials.add(Color::srgb(0.85, 0.2, 0.15))),
    ));
    commands.spawn((
        body(
            ColliderShape::Sphere { radius: 0.05 },
            Collider::sphere(0.05),
            2_500.0,
            Transform::from_xyz(0.55, 0.35, 0.3),
        ),
        Mesh3d(meshes.add(Sphere::new(0.05))),
        MeshMaterial3d(materials.add(Color::srgb(0.35, 0.35, 0.38))),
    ));
}

fn spawn_view(mut commands: Commands) {
    commands.spawn((
        DirectionalLight {
            illuminance: 8_000.0,
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::from_xyz(1.0, 2.0, 1.5).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    commands.spawn((
        Camera3d::default(),
        SphSurface::default(),
        Transform::from_xyz(0.6, 0.9, 1.6).looking_at(Vec3::new(0.6, 0.1, 0.3), Vec3::Y),
    ));
}

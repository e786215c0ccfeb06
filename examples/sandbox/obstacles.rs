//! The obstacles the start panel offers (issue 11): a ball and a box turned 30° in the water's
//! path, and a gate that holds the block back until the runtime panel lifts it at 0.5 m/s of
//! simulated time. Each is an `SphCollider` with a flat-shaded mesh of the same shape.

use crate::config::{SandboxConfig, BLOCK_SIZE, WALL_HEIGHT};
use crate::flat_material::FlatMaterial;
use crate::{AppState, SandboxSet};
use bevy::prelude::*;
use bevy_sph_fluid::prelude::*;
use sph_core::{BoxContainer, ColliderMotion, ColliderShape};

/// The gate's lifting speed [m/s of simulated time].
pub const GATE_SPEED: f32 = 0.5;

/// Whether the gate is being lifted (the runtime panel's button).
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GateLift {
    /// Lifting now.
    pub lifting: bool,
}

/// The gate's entity.
#[derive(Component)]
pub struct Gate;

/// Spawns the chosen obstacles in `container`; returns their entities.
pub fn spawn_obstacles(
    commands: &mut Commands,
    config: &SandboxConfig,
    container: &BoxContainer,
    meshes: &mut Assets<Mesh>,
    materials: &mut Assets<FlatMaterial>,
) -> Vec<Entity> {
    let mut spawned = Vec::new();
    let lo = container.min();
    let depth = container.size().z;
    let solid = materials.add(FlatMaterial::new(Color::srgb(0.8, 0.45, 0.25)));
    if config.sphere_obstacle {
        let radius = 0.12;
        let entity = commands
            .spawn((
                SphCollider::new(ColliderShape::Sphere { radius }),
                Mesh3d(meshes.add(Sphere::new(radius))),
                MeshMaterial3d(solid.clone()),
                Transform::from_translation(lo + Vec3::new(1.1, radius, 0.3 * depth)),
            ))
            .id();
        spawned.push(entity);
    }
    if config.box_obstacle {
        let half = Vec3::new(0.1, 0.1, 0.1);
        let entity = commands
            .spawn((
                SphCollider::new(ColliderShape::Cuboid { half_extents: half }),
                Mesh3d(meshes.add(Cuboid::from_size(2.0 * half))),
                MeshMaterial3d(solid.clone()),
                Transform::from_translation(lo + Vec3::new(1.4, half.y, 0.65 * depth))
                    .with_rotation(Quat::from_rotation_y(30f32.to_radians())),
            ))
            .id();
        spawned.push(entity);
    }
    if config.gate {
        // Across the box, right of the block, from the floor to above the walls.
        let half = Vec3::new(0.02, 0.5 * WALL_HEIGHT, 0.5 * depth + 0.05);
        let entity = commands
            .spawn((
                SphCollider::new(ColliderShape::Cuboid { half_extents: half })
                    .with_motion(ColliderMotion::Kinematic),
                Mesh3d(meshes.add(Cuboid::from_size(2.0 * half))),
                MeshMaterial3d(materials.add(FlatMaterial::new(Color::srgb(0.35, 0.4, 0.5)))),
                Transform::from_translation(
                    lo + Vec3::new(BLOCK_SIZE.x + half.x + 0.02, half.y, 0.5 * depth),
                ),
                Gate,
            ))
            .id();
        spawned.push(entity);
    }
    commands.insert_resource(GateLift::default());
    spawned
}

/// Lifts the gate by its speed times the simulated time of this frame's steps, until it clears
/// the walls.
pub fn lift_gate(
    lift: Option<Res<GateLift>>,
    stats: Res<SphStats>,
    mut last_time: Local<f64>,
    mut gates: Query<&mut Transform, With<Gate>>,
) {
    // The simulated time since the last frame: the gate keeps pace with the water whatever the
    // substeps or the real-time mode (GPU: the clock as read back).
    let frame_time = (stats.sim_time - *last_time).max(0.0) as f32;
    *last_time = stats.sim_time;
    if !lift.is_some_and(|l| l.lifting) {
        return;
    }
    for mut t in &mut gates {
        if t.translation.y < 2.0 * WALL_HEIGHT {
            t.translation.y += GATE_SPEED * frame_time;
        }
    }
}

/// The built-in obstacles' gate, lifted from the runtime panel.
pub struct ObstaclesPlugin;

impl Plugin for ObstaclesPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(
            Update,
            lift_gate
                .in_set(SandboxSet::Read)
                .run_if(in_state(AppState::Running)),
        );
    }
}

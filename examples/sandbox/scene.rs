//! The scene: a floor plate, walls computed from it (semi-transparent), the pipe with its
//! emitter, the block spawn, and the particle mesh once the plugin's buffers exist.

use crate::config::{SandboxConfig, SpawnMode, BLOCK_SIZE, FLOOR_SIZE, WALL_HEIGHT};
use crate::flat_material::FlatMaterial;
use crate::particles::{spawn_particles, ParticleDrawing, ParticleMaterial};
use crate::{AppState, SandboxSet};
use bevy::prelude::*;
use bevy_sph_fluid::prelude::*;
use sph_core::{BlockSpawn, BoxContainer, PipeEmitter};

/// Everything spawned for the running scene (despawned on the way back to setup).
#[derive(Component)]
pub struct SceneEntity;

/// The particle mesh, with the buffers it was built for.
#[derive(Component)]
pub struct ParticleMesh(SphGpuBuffers);

/// Where the pipe's mouth is and where it points.
pub fn pipe(container: &BoxContainer) -> (Vec3, Vec3) {
    let max = container.max();
    let mouth = Vec3::new(max.x - 0.08, 0.75 * WALL_HEIGHT, container.floor_center.z);
    (mouth, Vec3::new(-1.0, -0.15, 0.0).normalize())
}

/// Builds the scene from the start screen's choices (the design's scene change).
pub fn enter_running(
    mut commands: Commands,
    config: Res<SandboxConfig>,
    assets: Res<AssetServer>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<FlatMaterial>>,
) {
    commands.insert_resource(SphCapacity(config.budget));
    commands.insert_resource(SphControl {
        running: true,
        substeps: 2,
        real_time: config.real_time.then(SphRealTime::default),
        ..default()
    });
    if let Some(path) = &config.scene {
        // The file brings its parameters, container, colliders and water.
        commands.spawn((SphScene(assets.load(path.clone())), SceneEntity));
        return;
    }
    let params = config.params();
    commands.insert_resource(SphParams(params));
    let container = BoxContainer::from_floor(Vec3::ZERO, FLOOR_SIZE, WALL_HEIGHT);
    commands.spawn((SphContainer(container), SceneEntity));
    spawn_tank(&mut commands, &container, &mut meshes, &mut materials);
    spawn_water(&mut commands, &config, &container, params.spacing());
    for entity in crate::obstacles::spawn_obstacles(
        &mut commands,
        &config,
        &container,
        &mut meshes,
        &mut materials,
    ) {
        commands.entity(entity).insert(SceneEntity);
    }
    // The pipe itself, a cylinder ending at the mouth.
    let (mouth, direction) = pipe(&container);
    let length = 0.3;
    commands.spawn((
        Mesh3d(meshes.add(Cylinder::new(PIPE_RADIUS + 0.01, length))),
        MeshMaterial3d(materials.add(FlatMaterial::new(Color::srgb(0.7, 0.7, 0.72)))),
        Transform::from_translation(mouth - direction * (length / 2.0 + 0.01))
            .with_rotation(Quat::from_rotation_arc(Vec3::Y, direction)),
        SceneEntity,
    ));
}

/// The pipe's inner radius [m].
const PIPE_RADIUS: f32 = 0.06;

/// The floor plate and the glass walls, computed from the container.
fn spawn_tank(
    commands: &mut Commands,
    container: &BoxContainer,
    meshes: &mut Assets<Mesh>,
    materials: &mut Assets<FlatMaterial>,
) {
    let (lo, hi) = (container.min(), container.max());
    let size = hi - lo;
    let t = 0.02;
    commands.spawn((
        Mesh3d(meshes.add(Cuboid::new(size.x + 2.0 * t, t, size.z + 2.0 * t))),
        MeshMaterial3d(materials.add(FlatMaterial::new(Color::srgb(0.55, 0.5, 0.45)))),
        Transform::from_translation(container.floor_center - Vec3::Y * (t / 2.0)),
        SceneEntity,
    ));
    // Back faces are culled, so each glass wall blends one layer over the water.
    let glass = materials.add(FlatMaterial::new(Color::srgba(0.8, 0.9, 1.0, 0.18)));
    let centre = (lo + hi) / 2.0;
    let (x_wall, z_wall) = (Vec3::new(t, size.y, size.z), Vec3::new(size.x, size.y, t));
    for (offset, dims) in [
        (Vec3::X * -(size.x + t) / 2.0, x_wall),
        (Vec3::X * (size.x + t) / 2.0, x_wall),
        (Vec3::Z * -(size.z + t) / 2.0, z_wall),
        (Vec3::Z * (size.z + t) / 2.0, z_wall),
    ] {
        commands.spawn((
            Mesh3d(meshes.add(Cuboid::from_size(dims))),
            MeshMaterial3d(glass.clone()),
            Transform::from_translation(centre + offset),
            SceneEntity,
        ));
    }
}

/// The block and the pipe's emitter, sharing the particle budget as the spawn mode says.
fn spawn_water(
    commands: &mut Commands,
    config: &SandboxConfig,
    container: &BoxContainer,
    spacing: f32,
) {
    let lo = container.min();
    let pipe_budget = match config.spawn {
        SpawnMode::Block => 0,
        SpawnMode::Pipe => config.budget,
        SpawnMode::Both => config.budget / 2,
    };
    if config.spawn != SpawnMode::Pipe {
        // The block's spacing fills its volume with (its share of) the budget.
        let share = (config.budget - pipe_budget) as f32 / config.budget as f32;
        let block_spacing = spacing / share.cbrt();
        let block = BlockSpawn::new(lo, lo + BLOCK_SIZE, block_spacing.max(spacing));
        commands.spawn((
            SphBlockSpawn {
                block,
                velocity: Vec3::ZERO,
            },
            SceneEntity,
        ));
    }
    if pipe_budget > 0 {
        let (mouth, direction) = pipe(container);
        let mut emitter = PipeEmitter::new(mouth, direction, PIPE_RADIUS, 2.0, spacing);
        emitter.total = Some(pipe_budget as u64);
        commands.spawn((SphEmitter(emitter), SceneEntity));
    }
}

/// (Re)builds the particle mesh whenever the plugin's buffers change (e.g. a new capacity).
pub fn sync_particle_mesh(
    mut commands: Commands,
    buffers: Option<Res<SphGpuBuffers>>,
    capacity: Res<SphCapacity>,
    params: Res<SphParams>,
    existing: Query<(Entity, &ParticleMesh)>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<ParticleMaterial>>,
) {
    let Some(buffers) = buffers else {
        return;
    };
    if existing.iter().any(|(_, m)| m.0 == *buffers) {
        return;
    }
    for (entity, _) in &existing {
        commands.entity(entity).despawn();
    }
    spawn_particles(
        &mut commands,
        &mut meshes,
        &mut materials,
        &buffers,
        capacity.0,
        0.6 * params.spacing(),
        (SceneEntity, ParticleMesh(buffers.clone())),
    );
}

/// Back to the start screen: the scene goes, the simulation is emptied.
pub fn exit_running(
    mut commands: Commands,
    entities: Query<Entity, With<SceneEntity>>,
    mut control: ResMut<SphControl>,
) {
    for entity in &entities {
        commands.entity(entity).despawn();
    }
    commands.remove_resource::<ParticleDrawing>();
    control.running = false;
    control.reset = true;
}

/// The running scene: built on entering [`AppState::Running`], torn down on leaving it, the
/// particle mesh kept in step with the plugin's buffers.
pub struct ScenePlugin;

impl Plugin for ScenePlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(OnEnter(AppState::Running), enter_running)
            .add_systems(OnExit(AppState::Running), exit_running)
            .add_systems(
                Update,
                sync_particle_mesh
                    .in_set(SandboxSet::Scene)
                    .run_if(in_state(AppState::Running)),
            );
    }
}

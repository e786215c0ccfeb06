//! `--scene FILE`: the sandbox runs a scene file (`assets/scenes/*.ron`) instead of the start
//! panel's scene, and dresses the scene's entities: a floor plate and glass walls for the
//! container, a flat-shaded mesh for each collider, a dark grate at the bottom of each drain and
//! a green plate at the bottom of each pump (thin, so the water over them stays visible). Editing the file while the sandbox runs
//! reloads the scene (Bevy's file watcher).

use crate::flat_material::FlatMaterial;
use crate::scene::SceneEntity;
use crate::{AppState, SandboxSet};
use bevy::prelude::*;
use bevy_sph_fluid::prelude::*;
use sph_core::ColliderShape;

/// A scene's entity as it appears: which scene, and what it is.
type NewMember<'a> = (
    Entity,
    &'a SphSceneMember,
    Option<&'a SphCollider>,
    Option<&'a SphContainer>,
    (Option<&'a SphSink>, Option<&'a SphPump>),
);

/// Meshes and tags every entity a scene file spawned, when it appears.
pub fn dress_scene_members(
    mut commands: Commands,
    added: Query<NewMember, Added<SphSceneMember>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<FlatMaterial>>,
) {
    // `try_insert`: a reload in the same frame may have despawned the entity already.
    for (entity, member, collider, container, (sink, pump)) in &added {
        commands.entity(entity).try_insert(SceneEntity);
        // A plate 5 mm thick at the bottom of the device's box, in the device's frame.
        let plate = |half: Vec3| (Cuboid::new(2.0 * half.x, 0.005, 2.0 * half.z), -half.y);
        let device = sink
            .map(|s| (plate(s.half_extents), Color::srgb(0.15, 0.15, 0.17)))
            .or(pump.map(|p| (plate(p.half_extents), Color::srgb(0.25, 0.7, 0.3))));
        if let Some(((cuboid, bottom), colour)) = device {
            // The plate is its child: the device needs visibility for the plate's (B0004).
            commands
                .entity(entity)
                .try_insert_if_new(Visibility::default());
            let colour = materials.add(FlatMaterial::new(colour));
            commands.spawn((
                Mesh3d(meshes.add(cuboid)),
                MeshMaterial3d(colour),
                Transform::from_translation(Vec3::Y * bottom),
                ChildOf(entity),
                *member,
            ));
        }
        if let Some(collider) = collider {
            let mesh = match collider.shape {
                ColliderShape::TriMesh(ref mesh) => {
                    meshes.add(bevy_sph_fluid::mesh_collider::render_mesh(mesh))
                }
                ColliderShape::Cuboid { half_extents } => {
                    meshes.add(Cuboid::from_size(2.0 * half_extents))
                }
                ColliderShape::Sphere { radius } => meshes.add(Sphere::new(radius)),
                ColliderShape::Capsule {
                    radius,
                    half_length,
                } => meshes.add(Capsule3d::new(radius, 2.0 * half_length)),
                ColliderShape::Cylinder {
                    radius,
                    half_length,
                } => meshes.add(Cylinder::new(radius, 2.0 * half_length)),
            };
            let colour = materials.add(FlatMaterial::new(Color::srgb(0.8, 0.45, 0.2)));
            commands
                .entity(entity)
                .try_insert((Mesh3d(mesh), MeshMaterial3d(colour)));
        }
        if let Some(container) = container {
            let (lo, hi) = (container.min(), container.max());
            let size = hi - lo;
            let t = 0.02;
            let floor = meshes.add(Cuboid::new(size.x + 2.0 * t, t, size.z + 2.0 * t));
            let plate = materials.add(FlatMaterial::new(Color::srgb(0.55, 0.5, 0.45)));
            // A member of the same scene: a reload removes it with the container.
            commands.spawn((
                Mesh3d(floor),
                MeshMaterial3d(plate),
                Transform::from_translation(container.floor_center - Vec3::Y * (t / 2.0)),
                *member,
            ));
        }
    }
}

/// The scene files the start panel offers: `scenes/*.ron` under the sandbox's asset folder, with
/// what of each runs on the CPU backend only (drains), or why it does not build.
#[derive(Resource, Default)]
pub struct SceneFiles(pub Vec<(String, Result<SceneFileKind, String>)>);

/// What the start panel tells of a scene file that builds.
pub struct SceneFileKind {
    /// Its solver.
    pub solver: sph_core::Solver,
    /// What of it runs on the CPU backend only (drains), if anything.
    pub cpu_only: Option<&'static str>,
}

impl SceneFiles {
    /// Reads the folder once (at start-up).
    pub fn find() -> Self {
        let dir = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes"));
        let mut files: Vec<(String, Result<SceneFileKind, String>)> = std::fs::read_dir(dir)
            .into_iter()
            .flatten()
            .flatten()
            .map(|entry| entry.path())
            .filter(|path| path.extension().is_some_and(|e| e == "ron"))
            .map(|path| {
                let name = format!(
                    "scenes/{}",
                    path.file_name().unwrap_or_default().to_string_lossy()
                );
                let cpu_only = std::fs::read_to_string(&path)
                    .map_err(|e| e.to_string())
                    .and_then(|text| {
                        sph_core::scene::SceneFile::parse(&text, &name)
                            .and_then(|scene| scene.build(&name, &text))
                            .map(|setup| SceneFileKind {
                                solver: setup.params.solver,
                                cpu_only: if !setup.sinks.is_empty() {
                                    Some("its drain")
                                } else {
                                    None
                                },
                            })
                            .map_err(|e| e.to_string())
                    });
                (name, cpu_only)
            })
            .collect();
        files.sort_by(|a, b| a.0.cmp(&b.0));
        Self(files)
    }
}

/// The shipped scene files offered on the start panel, and their members dressed in meshes.
pub struct SceneFilesPlugin;

impl Plugin for SceneFilesPlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(SceneFiles::find()).add_systems(
            Update,
            dress_scene_members
                .in_set(SandboxSet::Scene)
                .run_if(in_state(AppState::Running)),
        );
    }
}

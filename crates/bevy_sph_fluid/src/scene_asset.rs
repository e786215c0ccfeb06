//! Water scenes as assets: a RON file of `sph_core::scene::file` loaded through Bevy's asset
//! system becomes the parameters, the container, the colliders, the blocks, the emitters, the
//! drains, the pumps and the probes of the simulation. Spawn an entity with [`SphScene`]; when the file changes on disk (with Bevy's
//! `file_watcher` feature) the scene is rebuilt, and a file that fails to load or validate is
//! reported in [`SphStats::scene_error`], [`SphStats::error`] and the log while the running
//! scene stays.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_sph_fluid::prelude::*;
//!
//! fn setup(mut commands: Commands, assets: Res<AssetServer>) {
//!     commands.spawn(SphScene(assets.load("scenes/dam_break.ron")));
//! }
//! ```

use crate::api::*;
use crate::flow::{SphProbe, SphPump, SphSink};
use crate::whitewater::SphWhitewater;
use bevy::asset::io::Reader;
use bevy::asset::{AssetLoadError, AssetLoadFailedEvent, AssetLoader, LoadContext};
use bevy::prelude::*;
use sph_core::scene::controls::{ControlBinding, ControlTarget, SceneControl};
use sph_core::scene::{SceneError, SceneFile, SceneSetup};

/// A water scene read from a RON file (`assets/scenes/*.ron`), validated.
#[derive(Asset, TypePath, Clone, Debug, PartialEq)]
pub struct SphSceneAsset(pub SceneSetup);

/// Loads [`SphSceneAsset`]s from `.ron` files.
#[derive(Default, TypePath)]
pub struct SphSceneLoader;

impl AssetLoader for SphSceneLoader {
    type Asset = SphSceneAsset;
    type Settings = ();
    type Error = SceneError;

    async fn load(
        &self,
        reader: &mut dyn Reader,
        _settings: &(),
        load_context: &mut LoadContext<'_>,
    ) -> Result<SphSceneAsset, SceneError> {
        let file = load_context.path().to_string();
        let fail = |message: String| SceneError {
            file: file.clone(),
            line: 0,
            column: 0,
            field: "-".into(),
            message,
        };
        let mut bytes = Vec::new();
        reader
            .read_to_end(&mut bytes)
            .await
            .map_err(|e| fail(format!("cannot read the file: {e}")))?;
        let text = String::from_utf8(bytes).map_err(|e| fail(format!("not UTF-8: {e}")))?;
        let scene = SceneFile::parse(&text, &file)?;
        Ok(SphSceneAsset(scene.build(&file, &text)?))
    }

    fn extensions(&self) -> &[&str] {
        &["ron"]
    }
}

/// Put on an entity to run a scene file: the entities of the scene are spawned when it loads
/// and rebuilt when it changes (their particles are reset). Despawning this entity leaves the
/// scene's entities in place; despawn those carrying [`SphSceneMember`] to clear it.
#[derive(Component, Clone, Debug, PartialEq, Eq)]
pub struct SphScene(pub Handle<SphSceneAsset>);

/// On every entity a scene spawned: the [`SphScene`] entity it belongs to.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct SphSceneMember(pub Entity);

/// A dynamic collider's mass from a scene file. With the `avian` feature it becomes an avian
/// rigid body of that density or mass; without it, game code moves the collider (reading
/// [`SphColliderForce`]).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct SphDynamicBody(pub sph_core::scene::BodyMass);

/// A hinged collider's hinge from a scene file (`motion: Hinged(...)`): an axle through the
/// entity's position. With the `avian` feature it becomes an avian revolute joint to the world
/// with the hinge's angular damping; without it, game code turns the collider.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct SphHinge(pub sph_core::scene::Hinge);

/// The named controls of a scene file, on its [`SphScene`] entity: set a value (within its
/// range) and the colliders, pumps and drains bound to it follow on the next frame (see
/// [`sph_core::scene::controls`]).
#[derive(Component, Clone, Debug, PartialEq)]
pub struct SphSceneControls(pub Vec<SceneControl>);

impl SphSceneControls {
    /// The control named `name`.
    pub fn get_mut(&mut self, name: &str) -> Option<&mut SceneControl> {
        self.0.iter_mut().find(|c| c.name == name)
    }
}

/// On a scene member driven by a control: which control and what it drives.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct SphControlBinding(pub ControlBinding);

/// A kinematic collider's path from a scene file: `(time, position)` waypoints, followed by
/// simulated time ([`SphStats::sim_time`]).
#[derive(Component, Clone, Debug, PartialEq)]
pub struct SphColliderPath(pub sph_core::scene::SceneCollider);

pub(crate) fn add_systems(app: &mut App, schedule: bevy::ecs::schedule::InternedScheduleLabel) {
    app.init_asset::<SphSceneAsset>()
        .init_asset_loader::<SphSceneLoader>()
        .add_systems(
            schedule,
            (sph_apply_scenes, sph_follow_paths, sph_apply_scene_controls)
                .chain()
                .before(crate::sets::SphSystems::Prepare),
        );
}

/// The resources a scene file sets: the parameters, the reset it asks for, and its errors.
#[derive(bevy::ecs::system::SystemParam)]
struct SceneTargets<'w> {
    params: ResMut<'w, SphParams>,
    control: ResMut<'w, SphControl>,
    stats: ResMut<'w, SphStats>,
}

/// Builds a scene's entities when its asset loads or changes; reports files that fail.
fn sph_apply_scenes(
    mut commands: Commands,
    mut events: MessageReader<AssetEvent<SphSceneAsset>>,
    mut failures: MessageReader<AssetLoadFailedEvent<SphSceneAsset>>,
    scenes: Query<(Entity, &SphScene)>,
    members: Query<(Entity, &SphSceneMember)>,
    assets: Res<Assets<SphSceneAsset>>,
    mut targets: SceneTargets,
) {
    for failure in failures.read() {
        report_failure(failure, &mut targets.stats);
    }
    // A load or reload may send both events in one frame: each scene is rebuilt once.
    let mut changed: Vec<AssetId<SphSceneAsset>> = Vec::new();
    for event in events.read() {
        if let AssetEvent::LoadedWithDependencies { id } | AssetEvent::Modified { id } = event {
            if !changed.contains(id) {
                changed.push(*id);
            }
        }
    }
    for id in changed {
        let Some(asset) = assets.get(id) else {
            continue;
        };
        for (root, scene) in &scenes {
            if scene.0.id() != id {
                continue;
            }
            for (entity, member) in &members {
                if member.0 == root {
                    commands.entity(entity).despawn();
                }
            }
            spawn_scene(&mut commands, root, &asset.0, &mut targets);
        }
    }
}

/// A scene file that failed to load: the loader's own error (file, line, field, value, allowed)
/// in the stats and the log; the running scene stays.
fn report_failure(failure: &AssetLoadFailedEvent<SphSceneAsset>, stats: &mut SphStats) {
    let scene_error = match &failure.error {
        AssetLoadError::AssetLoaderError(e) => e.error().downcast_ref::<SceneError>(),
        _ => None,
    };
    let error = match scene_error {
        Some(e) => format!("scene {e}"),
        None => format!("scene {}: {}", failure.path, failure.error),
    };
    warn!("SphFluidPlugin: {error}; the running scene stays");
    stats.scene_error = Some(error.clone());
    stats.error = Some(error);
}

/// Spawns the entities of the scene `setup` under `root` and sets its parameters; a scene that
/// loads clears the error of one that did not.
fn spawn_scene(
    commands: &mut Commands,
    root: Entity,
    setup: &SceneSetup,
    targets: &mut SceneTargets,
) {
    targets.params.0 = setup.params;
    targets.control.reset = true;
    // The file decides whitewater, as it decides the parameters.
    match setup.whitewater {
        Some((settings, capacity)) => {
            commands.insert_resource(SphWhitewater { settings, capacity })
        }
        None => commands.remove_resource::<SphWhitewater>(),
    }
    let member = SphSceneMember(root);
    commands
        .entity(root)
        .insert(SphSceneControls(setup.controls.clone()));
    commands.spawn((SphContainer(setup.container), member));
    let collider_entities = spawn_colliders(commands, setup, member);
    for &(block, velocity) in &setup.blocks {
        commands.spawn((SphBlockSpawn { block, velocity }, member));
    }
    for emitter in &setup.emitters {
        commands.spawn((SphEmitter(emitter.clone()), member));
    }
    let (sinks, pumps) = spawn_flow_devices(commands, setup, member);
    for binding in &setup.bindings {
        let entities = match binding.target {
            ControlTarget::Position { .. } => &collider_entities,
            ControlTarget::PumpStrength { .. } => &pumps,
            ControlTarget::DrainOpen => &sinks,
        };
        if let Some(&entity) = entities.get(binding.index) {
            commands.entity(entity).insert(SphControlBinding(*binding));
        }
    }
    let stats = &mut targets.stats;
    if stats.scene_error.take().is_some()
        && stats
            .error
            .as_deref()
            .is_some_and(|e| e.starts_with("scene "))
    {
        stats.error = None;
    }
}

/// The scene's colliders, in place this frame, with their paths, bodies and hinges; returns
/// their entities in the file's order.
fn spawn_colliders(
    commands: &mut Commands,
    setup: &SceneSetup,
    member: SphSceneMember,
) -> Vec<Entity> {
    let mut collider_entities = Vec::with_capacity(setup.colliders.len());
    for c in &setup.colliders {
        let pose = c.collider.pose;
        let transform = Transform::from_translation(pose.translation).with_rotation(pose.rotation);
        let mut entity = commands.spawn((
            SphCollider {
                shape: c.collider.shape.clone(),
                motion: c.collider.motion,
                slip: c.collider.slip,
            },
            transform,
            // In place this frame, before transform propagation: the scene's blocks spawn
            // around it in the same frame.
            GlobalTransform::from(transform),
            Name::new(c.name.clone()),
            member,
        ));
        if !c.path.is_empty() {
            entity.insert(SphColliderPath(c.clone()));
        }
        if let Some(body) = c.body {
            entity.insert(SphDynamicBody(body));
        }
        if let Some(hinge) = c.hinge {
            entity.insert(SphHinge(hinge));
        }
        collider_entities.push(entity.id());
    }
    collider_entities
}

/// The scene's drains, pumps and probes, named as in the file; returns the drains' and the
/// pumps' entities.
fn spawn_flow_devices(
    commands: &mut Commands,
    setup: &SceneSetup,
    member: SphSceneMember,
) -> (Vec<Entity>, Vec<Entity>) {
    let sinks = setup
        .sinks
        .iter()
        .map(|(name, sink)| spawn_device(commands, SphSink::from_world(sink), name, member))
        .collect();
    let pumps = setup
        .pumps
        .iter()
        .map(|(name, pump)| spawn_device(commands, SphPump::from_world(pump), name, member))
        .collect();
    for probe in &setup.probes {
        let device = SphProbe::from_world(&probe.kind, probe.every_steps);
        spawn_device(commands, device, &probe.name, member);
    }
    (sinks, pumps)
}

/// A named scene member with its transform in place this frame, before transform propagation.
fn spawn_device(
    commands: &mut Commands,
    (device, transform): (impl Bundle, Transform),
    name: &str,
    member: SphSceneMember,
) -> Entity {
    commands
        .spawn((
            device,
            transform,
            GlobalTransform::from(transform),
            Name::new(name.to_owned()),
            member,
        ))
        .id()
}

/// Moves the scene's kinematic colliders along their paths by the simulated time.
fn sph_follow_paths(stats: Res<SphStats>, mut paths: Query<(&SphColliderPath, &mut Transform)>) {
    let t = stats.sim_time as f32;
    for (path, mut transform) in &mut paths {
        let at = path.0.position_at(t);
        if transform.translation != at {
            transform.translation = at;
        }
    }
}

/// A member bound to a control, with what a control can drive.
type BoundMember<'a> = (
    Ref<'a, SphControlBinding>,
    &'a SphSceneMember,
    Option<&'a mut Transform>,
    Option<&'a mut SphPump>,
    Option<&'a mut SphSink>,
);

/// Moves, scales and opens the members bound to a scene's controls when the controls change
/// (or the members appear).
fn sph_apply_scene_controls(scenes: Query<Ref<SphSceneControls>>, mut bound: Query<BoundMember>) {
    for (binding, member, transform, pump, sink) in &mut bound {
        let Ok(controls) = scenes.get(member.0) else {
            continue;
        };
        if !(controls.is_changed() || binding.is_added()) {
            continue;
        }
        let ControlBinding {
            control, target, ..
        } = binding.0;
        let Some(fraction) = controls.0.get(control).map(SceneControl::fraction) else {
            continue;
        };
        match target {
            ControlTarget::Position { from, to } => {
                if let Some(mut t) = transform {
                    let at = ControlTarget::position(from, to, fraction);
                    if t.translation != at {
                        t.translation = at;
                    }
                }
            }
            ControlTarget::PumpStrength { strength } => {
                if let Some(mut pump) = pump {
                    pump.strength = strength * fraction;
                }
            }
            ControlTarget::DrainOpen => {
                if let Some(mut sink) = sink {
                    sink.open = ControlTarget::drain_open(fraction);
                }
            }
        }
    }
}

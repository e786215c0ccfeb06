//! A water scene from a RON file: `SphScene` loads `assets/scenes/dam_break.ron` (or the file
//! given), spawns its container, water, colliders and probes, and rebuilds the scene whenever the
//! file is saved (Bevy's `file_watcher`). The probes' readings are printed as they arrive; a file
//! that does not parse is reported with its line and field, and the previous scene keeps running.
//!
//! Run: `cargo run --release --example scene_file [-- scenes/gate.ron]`, then edit the file.

use bevy::prelude::*;
use bevy_sph_fluid::prelude::*;

fn main() {
    let file = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "scenes/dam_break.ron".into());
    App::new()
        .add_plugins(DefaultPlugins.set(AssetPlugin {
            watch_for_changes_override: Some(true),
            ..default()
        }))
        .add_plugins(SphFluidPlugin::default())
        .insert_resource(SceneFileName(file))
        .add_systems(Startup, spawn_scene_and_view)
        .add_systems(Update, (print_probe_readings, report_scene_errors))
        .run();
}

/// The scene file, relative to `assets/`.
#[derive(Resource)]
struct SceneFileName(String);

fn spawn_scene_and_view(
    mut commands: Commands,
    assets: Res<AssetServer>,
    file: Res<SceneFileName>,
) {
    commands.spawn(SphScene(assets.load(file.0.clone())));
    commands.spawn((
        DirectionalLight::default(),
        Transform::from_xyz(1.0, 2.0, 1.5).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    commands.spawn((
        Camera3d::default(),
        SphSurface::default(),
        Transform::from_xyz(0.5, 0.8, 1.6).looking_at(Vec3::new(0.5, 0.15, 0.1), Vec3::Y),
    ));
}

/// One line per reading: the probe's name, the simulated time and the value.
fn print_probe_readings(mut readings: MessageReader<SphProbeReading>, names: Query<&Name>) {
    for r in readings.read() {
        let name = names.get(r.probe).map_or("unnamed", |n| n.as_str());
        match r.reading.value {
            Some(value) => println!(
                "t {:7.3} s  {name:>12}: {value:9.4} ({} particles)",
                r.sim_time, r.reading.particles
            ),
            None => println!("t {:7.3} s  {name:>12}: dry", r.sim_time),
        }
    }
}

/// A file that fails to load leaves the running scene as it is; say why.
fn report_scene_errors(
    mut events: MessageReader<bevy::asset::AssetLoadFailedEvent<SphSceneAsset>>,
) {
    for e in events.read() {
        eprintln!(
            "scene file refused, the previous scene keeps running: {}",
            e.error
        );
    }
}

//! The smallest game scene with water: a lit floor, a tank's back walls, a column of water that
//! falls and sloshes, drawn as a smooth surface by `SphSurface` on the camera. The plugin is one
//! line; the water is a container and a block of particles.
//!
//! Run: `cargo run --release --example minimal`. `-- --screenshot FILE.png` saves the 40th frame
//! and exits (tests/sandbox_screenshot.rs does this).

use bevy::prelude::*;
use bevy::render::view::screenshot::{save_to_disk, Screenshot, ScreenshotCaptured};
use bevy_sph_fluid::prelude::*;
use sph_core::{BlockSpawn, BoxContainer};

/// The tank: 1 m long, 0.6 m high, 0.4 m deep, its floor at the origin.
const TANK: Vec3 = Vec3::new(1.0, 0.6, 0.4);

fn main() {
    let screenshot = ScreenshotAt::from_args();
    App::new()
        // For a screenshot, every pipeline is compiled before the frame that first draws with
        // it, so the saved frame misses nothing on a loaded machine.
        .add_plugins(DefaultPlugins.set(bevy::render::RenderPlugin {
            synchronous_pipeline_compilation: screenshot.0.is_some(),
            ..default()
        }))
        .add_plugins(SphFluidPlugin::default())
        .insert_resource(screenshot)
        .add_systems(Startup, (spawn_water, spawn_level))
        .add_systems(Update, screenshot_and_exit)
        .run();
}

/// The water: a container and a column in its left end, at the default 2 cm spacing (4,800
/// particles).
fn spawn_water(mut commands: Commands) {
    commands.spawn(SphContainer(BoxContainer::from_min_max(Vec3::ZERO, TANK)));
    let column = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.3, 0.4, 0.4), 0.02);
    commands.spawn(SphBlockSpawn {
        block: column,
        velocity: Vec3::ZERO,
    });
}

/// What the water is seen against: a floor, the tank's back and left walls, a sun and the camera
/// with the surface.
fn spawn_level(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let stone = materials.add(Color::srgb(0.72, 0.70, 0.66));
    commands.spawn((
        Mesh3d(meshes.add(Plane3d::default().mesh().size(4.0, 4.0))),
        MeshMaterial3d(stone.clone()),
        Transform::from_translation(TANK * Vec3::new(0.5, 0.0, 0.5)),
    ));
    // (size, centre): the back wall behind the tank, the left wall beside it.
    let walls = [
        (
            Vec3::new(TANK.x, TANK.y, 0.02),
            Vec3::new(0.5 * TANK.x, 0.5 * TANK.y, -0.01),
        ),
        (
            Vec3::new(0.02, TANK.y, TANK.z),
            Vec3::new(-0.01, 0.5 * TANK.y, 0.5 * TANK.z),
        ),
    ];
    for (size, centre) in walls {
        commands.spawn((
            Mesh3d(meshes.add(Cuboid::from_size(size))),
            MeshMaterial3d(stone.clone()),
            Transform::from_translation(centre),
        ));
    }
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
        Transform::from_xyz(1.3, 0.9, 1.5).looking_at(Vec3::new(0.45, 0.15, 0.2), Vec3::Y),
    ));
}

/// `--screenshot FILE` from the command line: the frame to save after [`SCREENSHOT_FRAME`].
#[derive(Resource)]
struct ScreenshotAt(Option<String>);

/// Enough frames on a software renderer for the shaders to compile and the water to fall.
const SCREENSHOT_FRAME: u32 = 40;

impl ScreenshotAt {
    fn from_args() -> Self {
        let mut args = std::env::args().skip_while(|a| a != "--screenshot");
        Self(args.nth(1))
    }
}

/// Saves the frame and exits once it is written.
fn screenshot_and_exit(
    mut commands: Commands,
    mut at: ResMut<ScreenshotAt>,
    mut frame: Local<u32>,
) {
    *frame += 1;
    let Some(path) = at.0.take_if(|_| *frame == SCREENSHOT_FRAME) else {
        return;
    };
    commands
        .spawn(Screenshot::primary_window())
        .observe(save_to_disk(path))
        .observe(
            |_: On<ScreenshotCaptured>, mut exit: MessageWriter<AppExit>| {
                exit.write(AppExit::Success);
            },
        );
}

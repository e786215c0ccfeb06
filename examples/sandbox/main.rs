//! The Aquaplay-style sandbox: a start screen, then a water box with a pipe and a block spawn,
//! particles drawn straight from the GPU buffers, a runtime panel and an orbit camera. A scene
//! file's dynamic bodies are avian bodies on the water's clock (`SphWaterTime`).
//!
//! `cargo run --release --example sandbox -- --help` lists the options ([`cli::Cli`]).
//! `--render surface` draws the plugin's water surface (`SphSurface` on the camera) instead of
//! the particles; the runtime panel switches between them.
//! `--screenshot` starts the scene at once, renders N frames, saves a PNG, prints the median
//! frame time and exits; `--paused` and `--hide-particles` isolate the simulation's and the
//! particle drawing's share of the frame.

mod cli;
mod config;
mod debug;
mod flat_material;
mod obstacles;
mod particles;
mod ranges;
mod runtime_panel;
mod scene;
mod scene_file;
mod scene_panel;
mod surface;
mod ui;

use bevy::diagnostic::FrameTimeDiagnosticsPlugin;
use bevy::prelude::*;
use bevy::render::diagnostic::RenderDiagnosticsPlugin;
use bevy::render::view::screenshot::{save_to_disk, Screenshot, ScreenshotCaptured};
use bevy_egui::EguiPlugin;
use bevy_panorbit_camera::{EguiFocusIncludesHover, PanOrbitCamera, PanOrbitCameraPlugin};
use bevy_sph_fluid::prelude::*;
use clap::Parser;
use cli::Cli;

/// The sandbox's frame, in phases: what the frame reads (the command line's toggles, the panels'
/// inputs, readings and snapshots), then the scene brought in step with it, then what is drawn.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SandboxSet {
    /// Inputs, readings and snapshots.
    Read,
    /// The scene's entities in step with the settings and the plugin.
    Scene,
    /// The particles' draw data, the debug gizmos, the screenshot.
    Draw,
}

/// Setup screen, then the running scene.
#[derive(States, Default, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AppState {
    /// The start panel.
    #[default]
    Setup,
    /// The scene and the runtime panel.
    Running,
}

fn main() {
    let cli = Cli::parse();
    let no_gpu_timings = cli.no_gpu_timings;
    let render_view = surface::RenderView {
        mode: cli.render,
        hide_water: cli.hide_particles,
        surface_view: cli.surface_view,
    };
    let config = match cli.sandbox_config() {
        Ok(config) => config,
        Err(e) => {
            eprintln!("sandbox: {e}");
            std::process::exit(2);
        }
    };
    let backend = if cli.cpu {
        SphBackend::Cpu
    } else {
        SphBackend::Gpu
    };
    let mut app = App::new();
    app.add_plugins(default_plugins(cli.screenshot.is_some()));
    if !no_gpu_timings {
        // Per-stage GPU milliseconds in the panel (timestamp queries).
        app.add_plugins(RenderDiagnosticsPlugin);
    }
    app.add_plugins((
        FrameTimeDiagnosticsPlugin::default(),
        EguiPlugin::default(),
        PanOrbitCameraPlugin,
        MaterialPlugin::<flat_material::FlatMaterial>::default(),
        SphFluidPlugin::new(config.budget, backend),
        // Rigid bodies (a scene file's boats) on the water's clock: they float at any
        // real-time factor.
        avian3d::prelude::PhysicsPlugins::new(SphWaterTime),
    ))
    .add_plugins((
        scene::ScenePlugin,
        scene_file::SceneFilesPlugin,
        particles::ParticlesPlugin,
        surface::RenderModePlugin,
        obstacles::ObstaclesPlugin,
        debug::DebugPlugin,
        ui::PanelsPlugin,
        scene_panel::ScenePanelPlugin,
    ))
    .configure_sets(
        Update,
        (SandboxSet::Read, SandboxSet::Scene, SandboxSet::Draw).chain(),
    )
    .init_state::<AppState>()
    .insert_resource(config)
    .insert_resource(cli)
    .insert_resource(EguiFocusIncludesHover(true))
    .insert_resource(SphControl {
        running: false,
        ..default()
    })
    .insert_resource(render_view)
    .add_systems(Startup, (spawn_camera_and_light, auto_start))
    .add_systems(
        Update,
        (
            (apply_cli_toggles, apply_cli_whitewater).in_set(SandboxSet::Read),
            take_screenshot.in_set(SandboxSet::Draw),
        )
            .run_if(in_state(AppState::Running)),
    )
    .run();
}

/// Bevy's default plugins with the sandbox's 1280×720 window and its assets, hot-reloaded. With
/// `screenshot`, every pipeline is compiled before the frame that first draws with it: compiled
/// in the background, a pipeline can still be pending at the screenshot's frame on a loaded
/// machine, and the picture misses what it draws.
fn default_plugins(screenshot: bool) -> bevy::app::PluginGroupBuilder {
    DefaultPlugins
        .set(bevy::render::RenderPlugin {
            synchronous_pipeline_compilation: screenshot,
            ..default()
        })
        .set(WindowPlugin {
            primary_window: Some(Window {
                title: "Aquaplay SPH sandbox".into(),
                resolution: (1280, 720).into(),
                ..default()
            }),
            ..default()
        })
        // The example's own shader, found however the binary is started.
        .set(AssetPlugin {
            file_path: concat!(env!("CARGO_MANIFEST_DIR"), "/assets").into(),
            // Edit a scene file and the sandbox reloads it.
            watch_for_changes_override: Some(true),
            ..default()
        })
}

fn spawn_camera_and_light(mut commands: Commands, cli: Res<Cli>) {
    // `--camera` places the eye; the orbit's radius, yaw and pitch follow from it.
    let orbit = match cli.camera {
        Some(pose) => PanOrbitCamera {
            focus: pose.focus,
            ..default()
        },
        None => PanOrbitCamera {
            focus: Vec3::new(0.0, 0.3, 0.0),
            radius: Some(3.0),
            yaw: Some(0.35),
            pitch: Some(0.45),
            ..default()
        },
    };
    let (eye, focus) = cli.camera.map_or(
        (Vec3::new(0.8, 1.6, 2.6), Vec3::new(0.0, 0.3, 0.0)),
        |pose| (pose.eye, pose.focus),
    );
    commands.spawn((
        orbit,
        Transform::from_translation(eye).looking_at(focus, Vec3::Y),
        // Multisampling quadruples the rasterizer's work on a software driver.
        Msaa::Off,
        bevy::core_pipeline::tonemapping::Tonemapping::None,
    ));
    commands.spawn((
        DirectionalLight {
            illuminance: 8_000.0,
            ..default()
        },
        Transform::from_xyz(1.0, 3.0, 2.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
}

fn auto_start(cli: Res<Cli>, mut next: ResMut<NextState<AppState>>) {
    if cli.starts_at_once() {
        next.set(AppState::Running);
    }
}

/// `--whitewater`: whitewater on after the first step, once a scene file has decided its own.
fn apply_cli_whitewater(
    cli: Res<Cli>,
    stats: Res<SphStats>,
    mut applied: Local<bool>,
    mut commands: Commands,
) {
    if cli.whitewater && !*applied && stats.step_count > 0 {
        commands.insert_resource(SphWhitewater::default());
        *applied = true;
    }
}

/// `--paused` and `--debug`, applied once the scene runs (`--hide-particles` is
/// `surface::RenderView::hide_water`).
fn apply_cli_toggles(
    cli: Res<Cli>,
    mut control: ResMut<SphControl>,
    mut debug: ResMut<ui::DebugView>,
    drawing: Option<ResMut<particles::ParticleDrawing>>,
    mut render: ResMut<surface::RenderView>,
) {
    if cli.debug && !debug.0 {
        if let Some(mut drawing) = drawing {
            debug.0 = true;
            drawing.color_mode = particles::ColorMode::Neighbors;
            // The debug colours are the particles'.
            render.mode = surface::RenderMode::Particles;
        }
    }
    if cli.paused {
        control.running = false;
    }
}

/// With `--screenshot`, saves the window after `--frames` frames of the scene, prints the median
/// frame time and the real-time factor of the second half (with the surface passes' GPU times and
/// the whitewater's counts when there are), then exits. Frames while the GPU
/// backend still compiles its shaders or prepares its buffers (`SphStats::gpu_warming_up`) do not
/// count: on a slow machine a DFSPH scene can take more than 20 frames to compile, and the
/// picture would show no water.
fn take_screenshot(
    cli: Res<Cli>,
    time: Res<Time<Real>>,
    stats: Res<SphStats>,
    mut frames: Local<u32>,
    mut frame_ms: Local<Vec<f64>>,
    mut half_way: Local<(f64, f64)>,
    mut commands: Commands,
) {
    let Some(path) = cli.screenshot.clone() else {
        return;
    };
    if stats.gpu_warming_up() {
        return;
    }
    *frames += 1;
    if *frames == cli.frames / 2 {
        *half_way = (time.elapsed_secs_f64(), stats.sim_time);
    }
    if *frames > cli.frames / 2 {
        frame_ms.push(time.delta_secs_f64() * 1e3);
    }
    if *frames == cli.frames {
        frame_ms.sort_by(f64::total_cmp);
        let median = frame_ms.get(frame_ms.len() / 2).copied().unwrap_or(0.0);
        println!(
            "sandbox: median frame time {median:.1} ms ({:.1} FPS) over the last {} frames",
            1e3 / median.max(1e-9),
            frame_ms.len()
        );
        let (wall, simulated) = (
            time.elapsed_secs_f64() - half_way.0,
            stats.sim_time - half_way.1,
        );
        println!(
            "sandbox: {simulated:.4} s simulated in {wall:.2} s of wall clock over those frames \
             (real-time factor {:.4}), {} particles, {} steps in the last frame",
            simulated / wall.max(1e-9),
            stats.particle_count,
            stats.frame_steps
        );
        if !stats.surface_ms.is_empty() {
            let passes: Vec<String> = stats
                .surface_ms
                .iter()
                .map(|(pass, ms)| format!("{pass} {ms:.2}"))
                .collect();
            println!("sandbox: surface GPU ms: {}", passes.join(", "));
        }
        if let Some(c) = stats.whitewater {
            println!(
                "sandbox: whitewater: spray {}, foam {}, bubbles {}, born {}, dropped {}",
                c.spray, c.foam, c.bubbles, c.born, c.dropped
            );
        }
        commands
            .spawn(Screenshot::primary_window())
            .observe(save_to_disk(path))
            .observe(
                |_: On<ScreenshotCaptured>, mut exit: MessageWriter<AppExit>| {
                    exit.write(AppExit::Success);
                },
            );
    }
}

//! Shared by the plugin test binaries.
#![allow(dead_code)] // each test binary uses its own subset of the helpers

use bevy::prelude::*;
#[allow(unused_imports)]
pub use bevy_sph_fluid::headless::{by_id, require_gpu_adapter, steps_taken};
use bevy_sph_fluid::prelude::*;
use std::sync::Mutex;

/// GPU tests in one binary run one at a time (one lavapipe device at a time on 2 cores).
pub static GPU: Mutex<()> = Mutex::new(());

/// A paused headless app; GPU apps require a Vulkan adapter and fail naming the package.
pub fn headless_app(capacity: u32, backend: SphBackend) -> App {
    if backend == SphBackend::Gpu {
        require_gpu_adapter();
    }
    bevy_sph_fluid::headless::headless_app(
        DefaultPlugins.build().disable::<bevy::winit::WinitPlugin>(),
        capacity,
        backend,
        false,
    )
}

/// A paused GPU app holding `block` (at rest) in `container`, run with `params`, after its first
/// update (the spawn queued, no step taken).
pub fn gpu_app_with_block(
    params: sph_core::SphParams,
    container: sph_core::BoxContainer,
    block: sph_core::BlockSpawn,
) -> App {
    let mut app = headless_app(block.count() as u32, SphBackend::Gpu);
    app.insert_resource(SphParams(params));
    app.world_mut().spawn(SphContainer(container));
    app.world_mut().spawn(SphBlockSpawn {
        block,
        velocity: Vec3::ZERO,
    });
    app.update();
    app
}

/// Single-steps to `steps` steps.
pub fn step_to(app: &mut App, steps: u64) {
    bevy_sph_fluid::headless::step_to(app, steps).unwrap();
}

/// Reads the particle state back.
pub fn snapshot(app: &mut App) -> SphSnapshot {
    bevy_sph_fluid::headless::snapshot(app).unwrap()
}

/// A directory of its own (per process and `test`) holding `scene.ron` with `text`.
pub fn scene_dir(test: &str, text: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("sph_scenes_{}_{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("scene.ron"), text).unwrap();
    dir
}

/// A paused CPU app of `capacity` particles whose assets live in `dir`, with the scene
/// `scene.ron` spawned (it loads over the next updates).
pub fn app_with_scene(dir: &std::path::Path, capacity: u32) -> App {
    app_with_scene_on(dir, capacity, SphBackend::Cpu)
}

/// [`app_with_scene`] on `backend` (the GPU's requires a Vulkan adapter).
pub fn app_with_scene_on(dir: &std::path::Path, capacity: u32, backend: SphBackend) -> App {
    if backend == SphBackend::Gpu {
        require_gpu_adapter();
    }
    let plugins = DefaultPlugins
        .build()
        .disable::<bevy::winit::WinitPlugin>()
        .set(AssetPlugin {
            file_path: dir.to_string_lossy().into_owned(),
            ..default()
        });
    let mut app = bevy_sph_fluid::headless::headless_app(plugins, capacity, backend, false);
    let handle = app
        .world()
        .resource::<AssetServer>()
        .load::<SphSceneAsset>("scene.ron");
    app.world_mut().spawn(SphScene(handle));
    app
}

/// A headless app of 8,000 slots on `backend` with `physics` added and the shipped scene file
/// `path` (under `assets/`) loaded and spawned, paused.
pub fn shipped_scene_app(path: &str, backend: SphBackend, physics: impl FnOnce(&mut App)) -> App {
    if backend == SphBackend::Gpu {
        require_gpu_adapter();
    }
    let assets = concat!(env!("CARGO_MANIFEST_DIR"), "/assets");
    let plugins = DefaultPlugins
        .build()
        .disable::<bevy::winit::WinitPlugin>()
        .set(AssetPlugin {
            file_path: assets.into(),
            ..default()
        });
    let mut app =
        bevy_sph_fluid::headless::headless_app_with(plugins, 8_000, backend, false, physics);
    let handle = app
        .world()
        .resource::<AssetServer>()
        .load::<SphSceneAsset>(path.to_owned());
    app.world_mut().spawn(SphScene(handle));
    for _ in 0..500 {
        app.update();
        if app.world().resource::<SphStats>().particle_count > 0 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    app
}

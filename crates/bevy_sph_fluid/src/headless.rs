//! Headless apps: the plugin with no window, driven by a manual `app.update()` loop (tests, the
//! bench command). A missing GPU adapter is a clear error naming the package to install.

use crate::api::*;
use crate::plugin::SphFluidPlugin;
use crate::shared::{SphRenderFeedback, SphSimulation};
use bevy::app::PluginGroupBuilder;
use bevy::prelude::*;
use bevy::render::pipelined_rendering::PipelinedRenderingPlugin;
use bevy::render::settings::{RenderCreation, WgpuSettings};
use bevy::render::RenderPlugin;
use bevy::window::ExitCondition;

/// The message when no GPU adapter exists.
pub const NO_ADAPTER_HELP: &str = "The GPU backend needs a Vulkan, Metal or DX12 adapter; on \
Linux without a GPU, Mesa's software Vulkan driver works: install it with \
`sudo apt-get install mesa-vulkan-drivers` (scripts/test.sh does this)";

/// The name of the adapter Bevy's renderer would take, chosen as Bevy chooses it (its default
/// `WgpuSettings`: the backends Bevy is built with or those in `WGPU_BACKEND`, the power
/// preference in `WGPU_POWER_PREF`), or an error naming the package to install.
pub fn gpu_adapter() -> Result<String, String> {
    let settings = WgpuSettings::default();
    let Some(backends) = settings.backends else {
        return Err(format!("no backend is enabled. {NO_ADAPTER_HELP}"));
    };
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = backends;
    desc.flags = settings.instance_flags;
    let instance = wgpu::Instance::new(desc);
    let options = wgpu::RequestAdapterOptions {
        power_preference: settings.power_preference,
        force_fallback_adapter: settings.force_fallback_adapter,
        compatible_surface: None,
    };
    match bevy::tasks::block_on(instance.request_adapter(&options)) {
        Ok(adapter) => Ok(adapter.get_info().name),
        Err(e) => Err(format!(
            "no GPU adapter on {backends:?} ({e}). {NO_ADAPTER_HELP}"
        )),
    }
}

/// Panics with [`gpu_adapter`]'s error when no adapter exists (for tests).
pub fn require_gpu_adapter() -> String {
    gpu_adapter().unwrap_or_else(|e| panic!("{e}"))
}

/// Collects every snapshot the plugin delivers.
#[derive(Resource, Default)]
pub struct Snapshots(pub Vec<SphSnapshot>);

fn collect_snapshots(mut reader: MessageReader<SphSnapshot>, mut out: ResMut<Snapshots>) {
    out.0.extend(reader.read().cloned());
}

/// A headless app with the plugin on `backend`, paused, ready for `update()`. `default_plugins`
/// is `DefaultPlugins.build()` without the windowing backend (the caller names it, e.g.
/// `.disable::<bevy::winit::WinitPlugin>()`, since only apps enable Bevy's `bevy_winit`).
/// The GPU backend needs an adapter (see [`gpu_adapter`]); `timed` adds GPU timestamps
/// per stage.
pub fn headless_app(
    default_plugins: PluginGroupBuilder,
    capacity: u32,
    backend: SphBackend,
    timed: bool,
) -> App {
    headless_app_with(default_plugins, capacity, backend, timed, |_| {})
}

/// [`headless_app`] with more plugins, added by `more` before the app is finished (a physics
/// engine, say).
pub fn headless_app_with(
    default_plugins: PluginGroupBuilder,
    capacity: u32,
    backend: SphBackend,
    timed: bool,
    more: impl FnOnce(&mut App),
) -> App {
    let draws = backend == SphBackend::Gpu;
    app_on(default_plugins, capacity, backend, timed, draws, more)
}

/// [`headless_app`] with a renderer whatever the backend (the GPU backend always has one), so
/// that cameras draw the CPU backend's water too. Needs an adapter (see [`gpu_adapter`]).
pub fn headless_app_that_draws(
    default_plugins: PluginGroupBuilder,
    capacity: u32,
    backend: SphBackend,
) -> App {
    app_on(default_plugins, capacity, backend, false, true, |_| {})
}

/// The headless app, with Bevy's renderer on a device when `draws`, without one otherwise.
fn app_on(
    default_plugins: PluginGroupBuilder,
    capacity: u32,
    backend: SphBackend,
    timed: bool,
    draws: bool,
    more: impl FnOnce(&mut App),
) -> App {
    let mut app = App::new();
    let render = if draws {
        RenderPlugin {
            synchronous_pipeline_compilation: true,
            ..default()
        }
    } else {
        RenderPlugin {
            render_creation: RenderCreation::Automatic(Box::new(WgpuSettings {
                backends: None,
                ..default()
            })),
            ..default()
        }
    };
    app.add_plugins(
        default_plugins
            .set(WindowPlugin {
                primary_window: None,
                exit_condition: ExitCondition::DontExit,
                ..default()
            })
            .set(render)
            .disable::<PipelinedRenderingPlugin>()
            .disable::<bevy::log::LogPlugin>(),
    );
    if timed {
        app.add_plugins(bevy::render::diagnostic::RenderDiagnosticsPlugin);
    }
    app.add_plugins(SphFluidPlugin::new(capacity, backend));
    more(&mut app);
    app.init_resource::<Snapshots>()
        .add_systems(Last, collect_snapshots);
    app.insert_resource(SphControl {
        running: false,
        ..default()
    });
    while app.plugins_state() == bevy::app::PluginsState::Adding {
        bevy::tasks::tick_global_task_pools_on_main_thread();
    }
    app.finish();
    app.cleanup();
    app
}

/// Inserts a scene's parameters and spawns its container and its blocks at rest.
pub fn spawn_scene(app: &mut App, scene: &sph_core::scenario::Scene) {
    app.insert_resource(SphParams(scene.params));
    app.world_mut().spawn(SphContainer(scene.container));
    for block in &scene.blocks {
        app.world_mut().spawn(SphBlockSpawn {
            block: *block,
            velocity: Vec3::ZERO,
        });
    }
}

/// Steps taken so far, as the render world (GPU) or the solver (CPU) reports them.
pub fn steps_taken(app: &App) -> u64 {
    match app.world().resource::<SphStats>().backend {
        SphBackend::Gpu => app.world().resource::<SphRenderFeedback>().get().step_count,
        SphBackend::Cpu => app.world().resource::<SphStats>().step_count,
    }
}

/// Fails when the plugin runs another backend than the one the app asked for: a GPU test whose
/// adapter cannot run the passes falls back to the CPU, and would otherwise pass on the CPU's
/// figures. [`step_to`] and [`snapshot`] check it.
pub fn ran_as_requested(app: &App) -> Result<(), String> {
    let requested = app.world().resource::<SphSimulation>().requested;
    let stats = app.world().resource::<SphStats>();
    if stats.backend == requested {
        Ok(())
    } else {
        Err(format!(
            "the {requested:?} backend was requested but the plugin runs {:?} on adapter {:?}: {}",
            stats.backend,
            stats.adapter,
            stats
                .fallback_reason
                .as_deref()
                .unwrap_or("no reason recorded")
        ))
    }
}

/// Takes single steps until `steps` have been taken (pipelines may need frames to compile).
pub fn step_to(app: &mut App, steps: u64) -> Result<(), String> {
    for _ in 0..2000 {
        let done = steps_taken(app);
        if done >= steps {
            return if done == steps {
                ran_as_requested(app)
            } else {
                Err(format!("overshot: {done} steps taken, {steps} asked"))
            };
        }
        app.world_mut().resource_mut::<SphControl>().single_step = true;
        app.update();
    }
    Err(format!(
        "no progress after 2000 frames: {:?}",
        app.world().resource::<SphStats>().error
    ))
}

/// Requests a readback and updates until the snapshot arrives.
pub fn snapshot(app: &mut App) -> Result<SphSnapshot, String> {
    app.world_mut().resource_mut::<Snapshots>().0.clear();
    app.world_mut().write_message(SphReadbackRequest);
    for _ in 0..200 {
        app.update();
        if let Some(s) = app.world_mut().resource_mut::<Snapshots>().0.pop() {
            return ran_as_requested(app).map(|()| s);
        }
    }
    Err("no snapshot after 200 frames".into())
}

/// Blocks until the GPU has finished all submitted work (for timing; never in a game frame).
pub fn wait_for_gpu(app: &App) {
    if let Some(device) = app
        .world()
        .get_resource::<bevy::render::renderer::RenderDevice>()
    {
        let _ = device.poll(bevy::render::render_resource::PollType::Wait {
            submission_index: None,
            timeout: None,
        });
    }
}

/// Sorts a snapshot by particle id.
pub fn by_id(s: &SphSnapshot) -> Vec<usize> {
    let mut order: Vec<usize> = (0..s.ids.len()).collect();
    order.sort_by_key(|&k| s.ids[k]);
    order
}

//! WebGPU's default limits run the water on the GPU; a device short of a limit the pipelines
//! need runs the CPU solver and says why.

mod common;

use bevy::prelude::*;
use bevy::render::pipelined_rendering::PipelinedRenderingPlugin;
use bevy::render::settings::{RenderCreation, WgpuLimits, WgpuSettings};
use bevy::render::RenderPlugin;
use bevy::window::ExitCondition;
use bevy_sph_fluid::prelude::*;
use bevy_sph_fluid::render::limits::GpuNeeds;

/// An app on lavapipe's device held to `limits`, with a small block of water run by `solver`,
/// stepped until the water moves (at most 20 frames).
fn stepped_app(limits: WgpuLimits, solver: sph_core::Solver) -> App {
    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .build()
            .disable::<bevy::winit::WinitPlugin>()
            .set(WindowPlugin {
                primary_window: None,
                exit_condition: ExitCondition::DontExit,
                ..default()
            })
            .set(RenderPlugin {
                render_creation: RenderCreation::Automatic(Box::new(WgpuSettings {
                    constrained_limits: Some(limits),
                    ..default()
                })),
                synchronous_pipeline_compilation: true,
                ..default()
            })
            .disable::<PipelinedRenderingPlugin>()
            .disable::<bevy::log::LogPlugin>(),
    )
    .add_plugins(SphFluidPlugin::new(1024, SphBackend::Gpu));
    app.finish();
    app.cleanup();
    let mut params = sph_core::SphParams::water();
    params.use_solver(solver);
    app.insert_resource(SphParams(params));
    let block = sph_core::BlockSpawn::new(Vec3::ZERO, Vec3::splat(0.1), 0.02);
    app.world_mut()
        .spawn(SphContainer(sph_core::BoxContainer::from_min_max(
            Vec3::ZERO,
            Vec3::splat(0.3),
        )));
    app.world_mut().spawn(SphBlockSpawn {
        block,
        velocity: Vec3::ZERO,
    });
    app.update();
    for _ in 0..20 {
        app.world_mut().resource_mut::<SphControl>().single_step = true;
        app.update();
        if common::steps_taken(&app) > 0 {
            break;
        }
    }
    app
}

/// Lavapipe's device held to WebGPU's default limits (8 storage buffers a stage, 128 MiB a
/// binding): every solver's water steps on the GPU, with no fallback.
#[test]
fn a_device_held_to_webgpus_default_limits_runs_every_solver_on_the_gpu() {
    common::require_gpu_adapter();
    let _gpu = common::GPU.lock().unwrap_or_else(|e| e.into_inner());
    for solver in sph_core::Solver::ALL {
        let app = stepped_app(WgpuLimits::default(), solver);
        let stats = app.world().resource::<SphStats>();
        assert_eq!(stats.fallback_reason, None, "{solver:?}");
        assert_eq!(stats.backend, SphBackend::Gpu, "{solver:?}");
        assert!(
            stats.particle_count > 0,
            "{solver:?}: the block was spawned"
        );
        assert!(
            common::steps_taken(&app) > 0,
            "{solver:?}: the GPU solver steps"
        );
    }
}

/// A device with one storage buffer a stage fewer than the widest stage binds: the GPU request
/// falls back to the CPU, `SphStats::fallback_reason` names the limit, what is needed and what
/// the device has, and the water still steps.
#[test]
fn a_device_short_of_a_storage_buffer_runs_the_cpu_and_names_the_limit() {
    common::require_gpu_adapter();
    let _gpu = common::GPU.lock().unwrap_or_else(|e| e.into_inner());
    let widest = GpuNeeds::of_all_stages().storage_buffers_per_stage;
    let limits = WgpuLimits {
        max_storage_buffers_per_shader_stage: widest - 1,
        ..WgpuLimits::default()
    };
    let app = stepped_app(limits, sph_core::Solver::Pbf);
    let stats = app.world().resource::<SphStats>();
    assert_eq!(stats.backend, SphBackend::Cpu);
    let reason = stats.fallback_reason.as_deref().unwrap_or("");
    assert!(
        reason.contains(&format!(
            "max_storage_buffers_per_shader_stage: needs {widest}, the device has {}",
            widest - 1
        )),
        "{reason:?}"
    );
    assert!(stats.particle_count > 0, "the block was spawned");
    assert!(common::steps_taken(&app) > 0, "the CPU solver steps");
}

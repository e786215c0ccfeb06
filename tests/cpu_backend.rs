//! The same ECS API on the CPU backend: chosen on purpose, and as the fallback when there is no
//! render device (no compute shaders), without a GPU.

mod common;

use bevy::prelude::*;
use bevy_sph_fluid::prelude::*;
use common::*;
use sph_core::{BlockSpawn, BoxContainer};

fn water_app(backend: SphBackend) -> App {
    let mut app = headless_app(2_000, backend);
    app.world_mut()
        .spawn(SphContainer(BoxContainer::from_min_max(
            Vec3::ZERO,
            Vec3::new(0.4, 0.4, 0.2),
        )));
    let block = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.2, 0.2, 0.1), 0.02);
    app.world_mut().spawn(SphBlockSpawn {
        block,
        velocity: Vec3::ZERO,
    });
    app
}

#[test]
fn cpu_backend_steps_reads_back_and_resets() {
    let mut app = water_app(SphBackend::Cpu);
    app.update();
    step_to(&mut app, 3);
    let stats = app.world().resource::<SphStats>().clone();
    assert_eq!(stats.backend, SphBackend::Cpu);
    assert_eq!(stats.particle_count, 500);
    assert_eq!(stats.health, SphHealth::Ok);
    let s = snapshot(&mut app);
    assert_eq!(s.ids.len(), 500);
    assert_eq!(s.step, 3);
    app.world_mut().resource_mut::<SphControl>().reset = true;
    app.update();
    app.update();
    let stats = app.world().resource::<SphStats>();
    assert_eq!(stats.step_count, 0);
    assert_eq!(
        stats.particle_count, 500,
        "block spawners fire again after a reset"
    );
}

#[test]
fn gpu_request_without_a_render_device_falls_back_to_the_cpu() {
    // headless_app disables the render device for the CPU backend; request the GPU on such an app.
    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .set(bevy::render::RenderPlugin {
                render_creation: bevy::render::settings::RenderCreation::Automatic(Box::new(
                    bevy::render::settings::WgpuSettings {
                        backends: None,
                        ..default()
                    },
                )),
                ..default()
            })
            .set(WindowPlugin {
                primary_window: None,
                exit_condition: bevy::window::ExitCondition::DontExit,
                ..default()
            })
            .disable::<bevy::winit::WinitPlugin>()
            .disable::<bevy::log::LogPlugin>(),
    );
    app.add_plugins(SphFluidPlugin::new(100, SphBackend::Gpu));
    app.finish();
    app.cleanup();
    app.update();
    assert_eq!(app.world().resource::<SphStats>().backend, SphBackend::Cpu);
}

#[test]
fn dfsph_runs_on_the_cpu_backend_and_reports_its_iterations() {
    let mut app = water_app(SphBackend::Cpu);
    let mut params = *app.world().resource::<SphParams>();
    params.use_solver(sph_core::Solver::Dfsph);
    app.insert_resource(params);
    app.update();
    step_to(&mut app, 5);
    let stats = app.world().resource::<SphStats>().clone();
    assert_eq!(stats.error, None);
    assert_eq!(stats.health, SphHealth::Ok);
    assert_eq!(stats.particle_count, 500);
    assert!(
        stats.pressure_iterations_mean >= params.dfsph.min_density_iterations as f32,
        "{}",
        stats.pressure_iterations_mean
    );
    assert!(stats.pressure_iterations_max >= params.dfsph.min_density_iterations);
    assert!(
        stats.time_step > sph_core::SphParams::water().time_step,
        "DFSPH's own dt rule"
    );
}

//! The water without a window, as a test or a game server runs it: a headless app with the
//! plugin, a dam break of 4,000 particles stepped by hand, and a snapshot read back every 0.1 s
//! of simulated time (positions, velocities, densities), from which it prints the front of the
//! water, the fastest particle and the density error.
//!
//! Run: `cargo run --release --example headless [-- gpu]` (the CPU solver unless `gpu` is given;
//! the GPU backend needs a Vulkan adapter, Mesa's lavapipe works).

use bevy::prelude::*;
use bevy_sph_fluid::headless::{headless_app, snapshot, spawn_scene, step_to};
use bevy_sph_fluid::prelude::*;
use sph_core::scenario::dam_break_with_particles;

fn main() {
    let backend = match std::env::args().nth(1).as_deref() {
        Some("gpu") => SphBackend::Gpu,
        None | Some("cpu") => SphBackend::Cpu,
        Some(other) => {
            eprintln!("error: unknown backend {other:?}; allowed: cpu, gpu");
            std::process::exit(2);
        }
    };
    let scene = dam_break_with_particles(4_000);
    let plugins = DefaultPlugins.build().disable::<bevy::winit::WinitPlugin>();
    let mut app = headless_app(plugins, scene.particle_count() as u32, backend, false);
    spawn_scene(&mut app, &scene);

    // About 0.1 s of water between reports at the scene's time step (the solver may shorten it).
    let steps_per_report = (0.1 / scene.params.time_step).round().max(1.0) as u64;
    println!("    t [s]  front x [m]  max speed [m/s]  mean density error [%]");
    for report in 1..=5 {
        // Steps one at a time (the plugin's SphControl::single_step), then asks for the state.
        if let Err(e) = step_to(&mut app, report * steps_per_report) {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
        let state = match snapshot(&mut app) {
            Ok(state) => state,
            Err(e) => {
                eprintln!("error: {e}");
                std::process::exit(1);
            }
        };
        let front = state.positions.iter().map(|p| p.x).fold(0.0, f32::max);
        let fastest = state
            .velocities
            .iter()
            .map(|v| v.length())
            .fold(0.0, f32::max);
        let health = state.diagnostics(&scene.params, &scene.container);
        println!(
            "{:9.3} {front:12.3} {fastest:16.3} {:24.3}",
            app.world().resource::<SphStats>().sim_time,
            health.density_error_mean_pct
        );
    }
    let stats = app.world().resource::<SphStats>();
    println!(
        "{} particles on {} ({:?})",
        stats.particle_count, stats.adapter, stats.backend
    );
}

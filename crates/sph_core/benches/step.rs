//! `cargo bench -p sph_core`: one step of a 32,768-particle dam break (water preset,
//! kick-drift-kick), surface tension off and on. Prints the median, min and max of timed steps.

use sph_core::glam::Vec3;
use sph_core::scenario::dam_break;
use sph_core::CpuSolver;
use std::time::Instant;

fn bench(label: &str, surface_tension: f32) {
    // 32 x 64 x 16 = 32,768 particles on a 0.01 m lattice.
    let spacing = 0.01;
    let mut scene = dam_break(0.32, 0.16, spacing);
    scene.params.surface_tension = surface_tension;
    let n = scene.particle_count();
    let mut solver = CpuSolver::new(scene.params, scene.container, n).expect("valid scene");
    solver.spawn(&scene.positions(), Vec3::ZERO);
    for _ in 0..20 {
        solver.step();
    }
    solver.reset_timings();
    let mut times: Vec<f64> = (0..60)
        .map(|_| {
            let t = Instant::now();
            solver.step();
            t.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    let per_stage: Vec<String> = solver
        .timings()
        .stages()
        .iter()
        .map(|(name, t)| format!("{name} {:.2}", t.as_secs_f64() * 1e3 / times.len() as f64))
        .collect();
    println!(
        "step/{label}: {n} particles, {:.0} candidates/particle, {} threads: median {:.2} ms, min {:.2} ms, max {:.2} ms ({} steps)",
        solver.mean_candidates(),
        rayon::current_num_threads(),
        times[times.len() / 2],
        times[0],
        times[times.len() - 1],
        times.len()
    );
    println!("  mean ms per stage: {}", per_stage.join(", "));
}

fn main() {
    if std::env::args().any(|a| a == "--list") {
        println!("step/surface_tension_off: benchmark\nstep/surface_tension_on: benchmark");
        return;
    }
    bench("surface_tension_off", 0.0);
    bench(
        "surface_tension_on",
        sph_core::params::WATER_SURFACE_TENSION,
    );
}

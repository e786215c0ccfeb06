//! `cargo bench -p sph_core`: one step of a 32,768-particle dam break (water preset,
//! kick-drift-kick), surface tension off and on. Prints the median, min and max of timed steps.
//! Then PBF on dambreak32k (`cargo bench -p sph_core --bench step -- pbf` runs only that one).

use sph_core::glam::Vec3;
use sph_core::params::SpacingDerivation;
use sph_core::scenario::dam_break;
use sph_core::{BlockSpawn, BoxContainer, CpuSolver, Solver, SphParams};
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

/// The value after `flag` on the command line, if any.
fn arg<T: std::str::FromStr>(flag: &str) -> Option<T> {
    let args: Vec<String> = std::env::args().collect();
    let at = args.iter().position(|a| a == flag)?;
    args.get(at + 1)?.parse().ok()
}

/// PBF on sph-bench's dambreak32k (31,250 particles at 0.02 m, a 0.5 × 1 × 0.5 m column in a
/// 2 × 1.2 × 0.5 m tank) at its defaults, or with `--pbf-iterations N`, `--cfl λ`,
/// `--pbf-omega ω` (the over-relaxation), `--dt DT` (the largest step, 1/120 s by default) and
/// `--fixed-dt` (the largest step every step): the mean ms per step and per stage over the first
/// 0.5 s, the real-time factor of the steps, the mean compression over the steps (as
/// sph-bench's `density_error_mean_run_pct`) and the mean speed at the end.
fn bench_pbf() {
    let spacing = 0.02;
    let mut params = SphParams::from_spacing(SpacingDerivation {
        spacing,
        expected_peak_speed: (2.0 * 9.81f32).sqrt(),
        ..Default::default()
    });
    params.use_solver(Solver::Pbf);
    if let Some(n) = arg("--pbf-iterations") {
        params.pbf.iterations = n;
    }
    if std::env::args().any(|a| a == "--fixed-dt") {
        params.adaptive_time_step = false;
    }
    if let Some(w) = arg("--pbf-omega") {
        params.pbf.over_relaxation = w;
    }
    if let Some(dt) = arg("--dt") {
        params.time_step = dt;
    }
    if let Some(cfl) = arg("--cfl") {
        params.cfl_factor = cfl;
    }
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(2.0, 1.2, 0.5));
    let column = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.5, 1.0, 0.5), spacing).positions();
    let mut solver = CpuSolver::new(params, container, column.len()).expect("valid scene");
    solver.spawn(&column, Vec3::ZERO);
    let (mut wall, mut steps, mut compression) = (0.0, 0, 0.0);
    while solver.time() < 0.5 {
        let t = Instant::now();
        solver.step();
        wall += t.elapsed().as_secs_f64();
        steps += 1;
        compression += solver.diagnostics().density_error_mean_pct as f64;
    }
    let per_stage: Vec<String> = solver
        .timings()
        .stages()
        .iter()
        .map(|(name, t)| format!("{name} {:.2}", t.as_secs_f64() * 1e3 / steps as f64))
        .collect();
    println!(
        "step/pbf_dambreak32k: {} particles, {steps} steps to 0.5 s in {wall:.2} s: {:.2} ms per step, real-time factor {:.3}, mean compression {:.3} %",
        column.len(),
        wall * 1e3 / steps as f64,
        solver.time() / wall,
        compression / steps as f64
    );
    println!("  mean ms per stage: {}", per_stage.join(", "));
    let speeds = &solver.particles().velocity;
    println!(
        "  mean speed at the end {:.3} m/s (DFSPH: 1.96, WCSPH: 2.08; more is energy the solver put in)",
        speeds.iter().map(|v| v.length()).sum::<f32>() / speeds.len().max(1) as f32
    );
}

fn main() {
    if std::env::args().any(|a| a == "--list") {
        println!("step/surface_tension_off: benchmark\nstep/surface_tension_on: benchmark\nstep/pbf_dambreak32k: benchmark");
        return;
    }
    if std::env::args().any(|a| a == "pbf") {
        bench_pbf();
        return;
    }
    bench("surface_tension_off", 0.0);
    bench(
        "surface_tension_on",
        sph_core::params::WATER_SURFACE_TENSION,
    );
    bench_pbf();
}

//! Headless dam break on the CPU reference solver: prints one line of statistics per simulated
//! 0.1 s. Run: `cargo run --release --example dam_break -- [--particles N] [--time SECONDS]`.

use sph_core::scenario::dam_break_with_particles;
use sph_core::CpuSolver;
use std::time::Instant;

fn arg<T: std::str::FromStr>(name: &str, default: T) -> T {
    let args: Vec<String> = std::env::args().collect();
    match args.iter().position(|a| a == name) {
        Some(i) => match args.get(i + 1).and_then(|v| v.parse().ok()) {
            Some(v) => v,
            None => {
                eprintln!("error: {name} needs a value");
                std::process::exit(2);
            }
        },
        None => default,
    }
}

fn main() {
    let particles: usize = arg("--particles", 8_000);
    let duration: f64 = arg("--time", 1.0);
    let scene = dam_break_with_particles(particles);
    let mut solver = match CpuSolver::new(scene.params, scene.container, scene.particle_count()) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    };
    solver.spawn(&scene.positions(), sph_core::glam::Vec3::ZERO);
    let p = solver.params();
    println!(
        "dam break: {} particles, h {:.4} m, dt {:.2e} s, c0 {:.1} m/s, {:?}, {:?} search, {} threads",
        solver.len(),
        p.smoothing_radius,
        p.time_step,
        p.speed_of_sound(),
        p.integrator,
        p.neighbor_search,
        rayon::current_num_threads(),
    );
    println!("    t [s]   steps  particles  rho_err_mean%  rho_err_max%  v_max[m/s]  outside  nan  ms/step");
    let started = Instant::now();
    let mut next_report = 0.1;
    let mut last = (Instant::now(), 0u64);
    while solver.time() < duration - 1e-9 {
        solver.step();
        if solver.time() + 1e-9 >= next_report {
            let d = solver.diagnostics();
            let ms = last.0.elapsed().as_secs_f64() * 1e3 / (solver.step_count() - last.1) as f64;
            println!(
                "{:9.2} {:7} {:10} {:14.3} {:13.3} {:11.3} {:8} {:4} {:8.2}",
                solver.time(),
                solver.step_count(),
                d.particle_count,
                d.density_error_mean_pct,
                d.density_error_max_pct,
                d.max_speed,
                d.outside_count,
                d.non_finite_count,
                ms
            );
            last = (Instant::now(), solver.step_count());
            next_report += 0.1;
        }
    }
    println!(
        "done in {:.1} s wall clock",
        started.elapsed().as_secs_f64()
    );
}

//! Stability at the extremes: with rollback off, a time step beyond an integrator's limit is
//! detected, reported as unstable and rolled back (CPU) or frozen (GPU) (`tests/rollback.rs`
//! covers rollback on); the adaptive CFL step keeps the same runs
//! stable; every sandbox parameter at both ends of its slider's range, tiny and degenerate particle
//! sets and a quarter of a million particles stay sane. Every test asserts: no NaN, the particle
//! count conserved, nothing outside the container.

mod common;
#[path = "../examples/sandbox/ranges.rs"]
mod ranges;

use bevy::prelude::*;
use bevy_sph_fluid::prelude::*;
use common::*;
use sph_core::scenario::{dam_break_with_particles, Scene};
use sph_core::{BlockSpawn, BoxContainer, CpuSolver, Diagnostics, Integrator, NeighborSearch};

const INTEGRATORS: [Integrator; 3] = [
    Integrator::SymplecticEuler,
    Integrator::Leapfrog,
    Integrator::KickDriftKick,
];

fn assert_sane(d: &Diagnostics, particles: usize, what: &str) {
    assert_eq!(d.particle_count, particles, "{what}: particle count");
    assert_eq!(d.non_finite_count, 0, "{what}: NaN or infinite particles");
    assert_eq!(d.outside_count, 0, "{what}: particles outside the box");
}

fn solver_of(scene: &Scene) -> CpuSolver {
    let n = scene.particle_count();
    let mut solver = CpuSolver::new(scene.params, scene.container, n.max(1)).unwrap();
    solver.spawn(&scene.positions(), Vec3::ZERO);
    solver
}

/// A 1,000-particle dam break at the sandbox's largest dt, 0.01 s: about 20 times the derived
/// step (4.4e-4 s), beyond every integrator's limit.
fn too_large_a_step(integrator: Integrator, adaptive: bool) -> Scene {
    let mut scene = dam_break_with_particles(1_000);
    scene.params.integrator = integrator;
    scene.params.time_step = *ranges::TIME_STEP.end();
    scene.params.adaptive_time_step = adaptive;
    scene
}

#[test]
fn without_rollback_a_step_beyond_each_integrators_limit_is_detected_rolled_back_and_frozen() {
    for integrator in INTEGRATORS {
        let scene = too_large_a_step(integrator, false);
        let mut solver = solver_of(&scene);
        solver.set_rollback(sph_core::Rollback::off()).unwrap();
        for _ in 0..400 {
            solver.step();
        }
        let what = format!("{integrator:?} at dt 0.01 s");
        let step = solver
            .unstable_step()
            .unwrap_or_else(|| panic!("{what}: no instability detected"));
        assert_eq!(solver.step_count() + 1, step, "{what}: rolled back");
        assert_sane(&solver.diagnostics(), scene.particle_count(), &what);
        let (time, positions) = (solver.time(), solver.particles().position.clone());
        solver.step();
        assert_eq!(solver.time(), time, "{what}: frozen");
        assert_eq!(solver.particles().position, positions, "{what}: frozen");
        solver.clear();
        assert_eq!(
            solver.unstable_step(),
            None,
            "{what}: a reset clears the freeze"
        );
    }
}

#[test]
fn the_adaptive_step_keeps_the_same_runs_stable() {
    for integrator in INTEGRATORS {
        let scene = too_large_a_step(integrator, true);
        let mut solver = solver_of(&scene);
        while solver.time() < 0.3 {
            solver.step();
        }
        let what = format!("{integrator:?}, adaptive, largest dt 0.01 s");
        assert_eq!(solver.unstable_step(), None, "{what}");
        let d = solver.diagnostics();
        assert_sane(&d, scene.particle_count(), &what);
        assert!(d.density_error_mean_pct < 10.0, "{what}: {d:?}");
        let p = &scene.params;
        let dt = solver.last_time_step();
        assert!(dt < p.time_step, "{what}: the rule chose dt = {dt}");
        assert!(
            dt * p.speed_of_sound() / p.smoothing_radius <= p.cfl_factor * 1.0001,
            "{what}: dt = {dt}"
        );
    }
}

type Setter = fn(&mut sph_core::SphParams, f32);

/// Every runtime slider of the sandbox and its range.
fn sandbox_sliders() -> [(&'static str, std::ops::RangeInclusive<f32>, Setter); 8] {
    [
        ("viscosity α", ranges::VISCOSITY_ALPHA, |p, v| {
            p.set_artificial_viscosity_alpha(v)
        }),
        ("stiffness", ranges::STIFFNESS, |p, v| p.stiffness = v),
        ("rest_density", ranges::REST_DENSITY, |p, v| {
            ranges::set_rest_density(p, v)
        }),
        ("surface_tension", ranges::SURFACE_TENSION, |p, v| {
            p.surface_tension = v
        }),
        ("wall_damping", ranges::WALL_DAMPING, |p, v| {
            p.wall_damping = v
        }),
        ("gravity.y", ranges::GRAVITY_Y, |p, v| p.gravity.y = v),
        ("time_step", ranges::TIME_STEP, |p, v| p.time_step = v),
        ("cfl_factor", ranges::CFL_FACTOR, |p, v| p.cfl_factor = v),
    ]
}

/// A small block in a box, with the sandbox's two presets at a 0.02 m spacing.
fn preset_scenes() -> Vec<(&'static str, Scene)> {
    let water = sph_core::SphParams::water();
    let spacing = water.spacing();
    let design = sph_core::SphParams {
        particle_mass: sph_core::SphParams::seed().rest_density * spacing.powi(3),
        smoothing_radius: water.smoothing_radius,
        ..sph_core::SphParams::seed()
    };
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.3, 0.3, 0.16));
    let block = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.1, 0.2, 0.1), spacing);
    [("water", water), ("design", design)]
        .into_iter()
        .map(|(name, params)| {
            (
                name,
                Scene {
                    params,
                    container,
                    blocks: vec![block],
                },
            )
        })
        .collect()
}

#[test]
fn every_sandbox_parameter_at_both_ends_stays_stable_with_the_adaptive_step() {
    for (preset, base) in preset_scenes() {
        for (field, range, set) in sandbox_sliders() {
            for end in [*range.start(), *range.end()] {
                for integrator in INTEGRATORS {
                    let mut scene = base.clone();
                    scene.params.adaptive_time_step = true;
                    scene.params.integrator = integrator;
                    set(&mut scene.params, end);
                    let mut solver = solver_of(&scene);
                    for _ in 0..150 {
                        solver.step();
                    }
                    let what = format!("{preset}, {field} = {end}, {integrator:?}");
                    assert_eq!(solver.unstable_step(), None, "{what}");
                    assert_sane(&solver.diagnostics(), scene.particle_count(), &what);
                }
            }
        }
    }
}

/// DFSPH's settings at both ends of their ranges (and warm starts off).
fn dfsph_setting_ends() -> Vec<(&'static str, sph_core::DfsphSettings)> {
    let d = sph_core::DfsphSettings::default();
    vec![
        ("defaults", d),
        (
            "max_density_error 1e-6",
            sph_core::DfsphSettings {
                max_density_error: 1e-6,
                ..d
            },
        ),
        (
            "max_density_error 0.1",
            sph_core::DfsphSettings {
                max_density_error: 0.1,
                ..d
            },
        ),
        (
            "max_divergence_error 1e-6",
            sph_core::DfsphSettings {
                max_divergence_error: 1e-6,
                ..d
            },
        ),
        (
            "max_divergence_error 10",
            sph_core::DfsphSettings {
                max_divergence_error: 10.0,
                ..d
            },
        ),
        (
            "1 iteration each, none at least",
            sph_core::DfsphSettings {
                min_density_iterations: 0,
                max_density_iterations: 1,
                min_divergence_iterations: 0,
                max_divergence_iterations: 1,
                ..d
            },
        ),
        (
            "1000 iterations each, all at least",
            sph_core::DfsphSettings {
                min_density_iterations: 1000,
                max_density_iterations: 1000,
                min_divergence_iterations: 1000,
                max_divergence_iterations: 1000,
                ..d
            },
        ),
        (
            "warm starts off",
            sph_core::DfsphSettings {
                warm_start: false,
                ..d
            },
        ),
        (
            "over-relaxation 1",
            sph_core::DfsphSettings {
                divergence_over_relaxation: 1.0,
                ..d
            },
        ),
        (
            "over-relaxation 1.9",
            sph_core::DfsphSettings {
                divergence_over_relaxation: 1.9,
                ..d
            },
        ),
        (
            "density over-relaxation 1",
            sph_core::DfsphSettings {
                density_over_relaxation: 1.0,
                ..d
            },
        ),
        (
            "density over-relaxation 1.9",
            sph_core::DfsphSettings {
                density_over_relaxation: 1.9,
                ..d
            },
        ),
    ]
}

/// PBF's settings at both ends of their validated ranges (the sandbox's PBF sliders included).
fn pbf_setting_ends() -> Vec<(String, sph_core::PbfSettings)> {
    let d = sph_core::PbfSettings::default();
    let set = |f: &dyn Fn(&mut sph_core::PbfSettings)| {
        let mut s = d;
        f(&mut s);
        s
    };
    vec![
        ("iterations 1".into(), set(&|s| s.iterations = 1)),
        ("iterations 100".into(), set(&|s| s.iterations = 100)),
        ("relaxation 1e-6".into(), set(&|s| s.relaxation = 1e-6)),
        ("relaxation 10".into(), set(&|s| s.relaxation = 10.0)),
        ("s_corr_k 0".into(), set(&|s| s.s_corr_k = 0.0)),
        ("s_corr_k 1".into(), set(&|s| s.s_corr_k = 1.0)),
        ("s_corr_n 1".into(), set(&|s| s.s_corr_n = 1)),
        ("s_corr_n 8".into(), set(&|s| s.s_corr_n = 8)),
        ("s_corr_dq 1e-3".into(), set(&|s| s.s_corr_dq = 1e-3)),
        ("s_corr_dq 0.9".into(), set(&|s| s.s_corr_dq = 0.9)),
        ("xsph_c 0".into(), set(&|s| s.xsph_c = 0.0)),
        ("xsph_c 1".into(), set(&|s| s.xsph_c = 1.0)),
        (
            "vorticity_epsilon 1".into(),
            set(&|s| s.vorticity_epsilon = 1.0),
        ),
        (
            "over_relaxation 1".into(),
            set(&|s| s.over_relaxation = 1.0),
        ),
        (
            "over_relaxation 1.9".into(),
            set(&|s| s.over_relaxation = 1.9),
        ),
    ]
}

#[test]
fn dfsph_and_pbf_at_both_ends_of_every_slider_and_setting_stay_stable() {
    for (preset, base) in preset_scenes() {
        let mut runs: Vec<(String, sph_core::SphParams)> = Vec::new();
        for (field, range, set) in sandbox_sliders() {
            for end in [*range.start(), *range.end()] {
                let mut p = base.params;
                p.use_solver(sph_core::Solver::Dfsph);
                set(&mut p, end);
                runs.push((format!("DFSPH, {field} = {end}"), p));
            }
        }
        for (field, range, set) in sandbox_sliders() {
            for end in [*range.start(), *range.end()] {
                let mut p = base.params;
                p.use_solver(sph_core::Solver::Pbf);
                set(&mut p, end);
                runs.push((format!("PBF, {field} = {end}"), p));
            }
        }
        for (name, settings) in dfsph_setting_ends() {
            let mut p = base.params;
            p.use_solver(sph_core::Solver::Dfsph);
            p.dfsph = settings;
            runs.push((format!("DFSPH, {name}"), p));
        }
        for (name, settings) in pbf_setting_ends() {
            let mut p = base.params;
            p.use_solver(sph_core::Solver::Pbf);
            p.pbf = settings;
            assert_eq!(p.validate(), Ok(()), "{name} is in range");
            runs.push((format!("PBF, {name}"), p));
        }
        for (what, params) in runs {
            let scene = Scene {
                params,
                ..base.clone()
            };
            let mut solver = solver_of(&scene);
            for _ in 0..60 {
                solver.step();
            }
            let what = format!("{preset}, {what}");
            assert_eq!(solver.unstable_step(), None, "{what}");
            assert_sane(&solver.diagnostics(), scene.particle_count(), &what);
        }
    }
}

/// `positions` in a 0.3 m box of SI water, stepped 100 times by every integrator and search,
/// with the adaptive step on and off. With a fixed step, a squeezed start may go unstable (it is
/// then rolled back and frozen); with the adaptive step it must not.
fn run_degenerate(positions: &[Vec3], what: &str) {
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(0.3));
    for integrator in INTEGRATORS {
        for search in [NeighborSearch::Grid, NeighborSearch::Hash] {
            for adaptive in [false, true] {
                let mut params = sph_core::SphParams::water();
                params.integrator = integrator;
                params.neighbor_search = search;
                params.adaptive_time_step = adaptive;
                let mut solver = CpuSolver::new(params, container, positions.len().max(1)).unwrap();
                solver.spawn(positions, Vec3::ZERO);
                for _ in 0..100 {
                    solver.step();
                }
                let what = format!("{what}, {integrator:?}, {search:?}, adaptive {adaptive}");
                if adaptive {
                    assert_eq!(solver.unstable_step(), None, "{what}");
                }
                assert_sane(&solver.diagnostics(), positions.len(), &what);
            }
        }
    }
    for solver_kind in [sph_core::Solver::Dfsph, sph_core::Solver::Pbf] {
        for search in [NeighborSearch::Grid, NeighborSearch::Hash] {
            let mut params = sph_core::SphParams::water();
            params.use_solver(solver_kind);
            params.neighbor_search = search;
            let mut solver = CpuSolver::new(params, container, positions.len().max(1)).unwrap();
            solver.spawn(positions, Vec3::ZERO);
            for _ in 0..100 {
                solver.step();
            }
            let what = format!("{what}, {solver_kind:?}, {search:?}");
            assert_eq!(solver.unstable_step(), None, "{what}");
            assert_sane(&solver.diagnostics(), positions.len(), &what);
        }
    }
}

#[test]
fn zero_one_and_two_particles_stay_sane() {
    run_degenerate(&[], "0 particles");
    run_degenerate(&[Vec3::splat(0.15)], "1 particle");
    run_degenerate(
        &[Vec3::new(0.15, 0.15, 0.15), Vec3::new(0.16, 0.15, 0.15)],
        "2 particles",
    );
}

#[test]
fn all_particles_in_one_cell_and_on_top_of_each_other_stay_sane() {
    let h = sph_core::SphParams::water().smoothing_radius;
    let one_cell: Vec<Vec3> = (0..64)
        .map(|k| {
            let q = Vec3::new((k % 4) as f32, ((k / 4) % 4) as f32, (k / 16) as f32);
            Vec3::splat(0.1) + q * (0.24 * h)
        })
        .collect();
    run_degenerate(&one_cell, "64 particles in one cell");
    run_degenerate(&[Vec3::splat(0.15); 64], "64 coincident particles");
}

#[test]
fn a_quarter_million_particles_take_one_cpu_step() {
    let scene = dam_break_with_particles(262_144);
    let mut solver = solver_of(&scene);
    solver.step();
    assert_eq!(solver.unstable_step(), None);
    assert_sane(
        &solver.diagnostics(),
        scene.particle_count(),
        "262,144-particle dam break",
    );
    assert!(scene.particle_count() >= 250_000);
    for kind in [sph_core::Solver::Dfsph, sph_core::Solver::Pbf] {
        let mut other = scene.clone();
        other.params.use_solver(kind);
        let mut solver = solver_of(&other);
        solver.step();
        assert_eq!(solver.unstable_step(), None);
        assert_sane(
            &solver.diagnostics(),
            scene.particle_count(),
            &format!("262,144-particle dam break, {kind:?}"),
        );
    }
}

fn gpu_app(scene: &Scene) -> App {
    let mut app = headless_app(scene.particle_count() as u32, SphBackend::Gpu);
    bevy_sph_fluid::headless::spawn_scene(&mut app, scene);
    app
}

fn gpu_diagnostics(s: &SphSnapshot, scene: &Scene) -> Diagnostics {
    s.diagnostics(&scene.params, &scene.container)
}

#[test]
fn without_rollback_the_gpu_reports_a_step_beyond_the_limit_as_unstable_and_freezes() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let scene = too_large_a_step(Integrator::KickDriftKick, false);
    let mut cpu = solver_of(&scene);
    cpu.set_rollback(sph_core::Rollback::off()).unwrap();
    for _ in 0..400 {
        cpu.step();
    }
    let cpu_step = cpu.unstable_step().expect("the CPU detects it");
    let mut app = gpu_app(&scene);
    app.world_mut().resource_mut::<SphControl>().rollback = sph_core::Rollback::off();
    step_to(&mut app, cpu_step + 20);
    let first = snapshot(&mut app);
    let stats = app.world().resource::<SphStats>().clone();
    let SphHealth::Unstable { step } = stats.health else {
        panic!(
            "GPU health {:?} (the CPU went unstable at step {cpu_step})",
            stats.health
        );
    };
    assert!(step <= cpu_step + 20, "detected at step {step}");
    assert_sane(
        &gpu_diagnostics(&first, &scene),
        scene.particle_count(),
        "GPU, frozen",
    );
    step_to(&mut app, cpu_step + 30);
    let second = snapshot(&mut app);
    let (a, b) = (by_id(&first), by_id(&second));
    for (&i, &j) in a.iter().zip(&b) {
        assert_eq!(
            first.positions[i], second.positions[j],
            "frozen state moved"
        );
    }
}

#[test]
fn the_gpu_adaptive_step_follows_the_cpu_rule_and_stays_stable() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let scene = too_large_a_step(Integrator::KickDriftKick, true);
    let mut cpu = solver_of(&scene);
    for _ in 0..60 {
        cpu.step();
    }
    let mut app = gpu_app(&scene);
    step_to(&mut app, 60);
    let s = snapshot(&mut app);
    let stats = app.world().resource::<SphStats>().clone();
    assert_eq!(stats.health, SphHealth::Ok);
    assert_sane(
        &gpu_diagnostics(&s, &scene),
        scene.particle_count(),
        "GPU, adaptive",
    );
    let relative = (stats.sim_time - cpu.time()).abs() / cpu.time();
    assert!(
        relative < 1e-3,
        "60 adaptive steps: GPU {} s, CPU {} s",
        stats.sim_time,
        cpu.time()
    );
    assert!(
        stats.sim_time < 60.0 * scene.params.time_step as f64 * 0.5,
        "the CFL rule, not the largest dt, chose the steps: {} s",
        stats.sim_time
    );
}

/// DFSPH on the GPU at the degenerate ends: 1 and 2 particles and 64 in one cell take 60
/// steps of DFSPH's own rule and stay finite, inside and healthy, every particle kept. (A block
/// spawn cannot put particles exactly on top of each other; the CPU tests above do.)
#[test]
fn dfsph_on_the_gpu_keeps_degenerate_sets_sane() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let mut params = sph_core::SphParams::water();
    params.use_solver(sph_core::Solver::Dfsph);
    let h = params.smoothing_radius;
    let dx = params.spacing();
    let at = Vec3::splat(0.15);
    let cases = [
        (
            "1 particle",
            BlockSpawn::new(at, at + Vec3::splat(1.5 * dx), dx),
        ),
        (
            "2 particles",
            BlockSpawn::new(at, at + Vec3::new(2.5 * dx, 1.5 * dx, 1.5 * dx), dx),
        ),
        (
            "64 particles in one cell",
            BlockSpawn::new(at, at + Vec3::splat(1.08 * h), 0.24 * h),
        ),
    ];
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(0.3));
    for ((what, block), expected) in cases.into_iter().zip([1, 2, 64]) {
        let n = block.count();
        assert_eq!(n, expected, "{what}");
        let mut app = gpu_app_with_block(params, container, block);
        step_to(&mut app, 60);
        let stats = app.world().resource::<SphStats>();
        assert_eq!(stats.error, None, "{what}");
        assert!(!stats.health.is_unstable(), "{what}: {:?}", stats.health);
        let s = snapshot(&mut app);
        let d = s.diagnostics(&params, &container);
        eprintln!(
            "GPU DFSPH, {what}: {n} particles, max speed {:.3} m/s",
            d.max_speed
        );
        assert_sane(&d, n, &format!("GPU DFSPH, {what}"));
    }
}

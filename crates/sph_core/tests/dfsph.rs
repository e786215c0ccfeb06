//! DFSPH (Bender & Koschier 2017): the factor is the exact diagonal of the solve, the pressure
//! accelerations conserve momentum, the solves bring density errors down, the settings are
//! validated, and the solver survives the extremes.

use sph_core::glam::{Quat, Vec3};
use sph_core::kernel::CubicSpline;
use sph_core::neighbor::lists::{ListSource, NeighborLists};
use sph_core::solver::dfsph::bender2017::{
    apply_stiffness, compute_factors, density_rate, ParticleFactor,
};
use sph_core::{
    BlockSpawn, BoxContainer, Collider, ColliderShape, CpuSolver, DfsphSettings, Neighbors, Pose,
    Solver, SphParams,
};

/// A lattice block with a deterministic jitter of `jitter` Δx, sorted, with its lists built.
struct Block {
    params: SphParams,
    positions: Vec<Vec3>,
    lists: NeighborLists,
    factors: Vec<ParticleFactor>,
}

fn jittered(x: Vec3, k: usize, amount: f32) -> Vec3 {
    let h = |s: usize| ((s.wrapping_mul(2_654_435_761) >> 7) % 1000) as f32 / 1000.0 - 0.5;
    x + Vec3::new(h(3 * k), h(3 * k + 1), h(3 * k + 2)) * amount
}

fn block(jitter: f32) -> Block {
    let params = SphParams::water();
    let dx = params.spacing();
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(0.3));
    let spawn = BlockSpawn::new(Vec3::splat(0.1), Vec3::splat(0.1 + 6.0 * dx), dx);
    let raw: Vec<Vec3> = spawn
        .positions()
        .iter()
        .enumerate()
        .map(|(k, &x)| jittered(x, k, jitter * dx))
        .collect();
    let mut neighbors = Neighbors::new(
        params.neighbor_search,
        &container,
        params.smoothing_radius,
        raw.len(),
    )
    .unwrap();
    let order = neighbors.sort(&raw).to_vec();
    let positions: Vec<Vec3> = order.iter().map(|&i| raw[i as usize]).collect();
    let kernel = CubicSpline::new(params.smoothing_radius, dx);
    let mut lists = NeighborLists::default();
    let mut density = vec![0.0; positions.len()];
    lists.rebuild(
        ListSource {
            neighbors: &neighbors,
            positions: &positions,
            boundary: None,
            mass: params.particle_mass,
            rest_density: params.rest_density,
        },
        |r, r2| {
            let r_len = r2.sqrt();
            (kernel.value(r_len), kernel.gradient(r, r_len))
        },
        &mut density,
    );
    let mut factors = vec![ParticleFactor::default(); positions.len()];
    compute_factors(&lists, None, None, 1000.0, 1.0, &mut factors);
    Block {
        params,
        positions,
        lists,
        factors,
    }
}

#[test]
fn the_cubic_spline_gives_rest_density_on_the_lattice_and_its_gradient_matches_differences() {
    let params = SphParams::water();
    let dx = params.spacing();
    let kernel = CubicSpline::new(params.smoothing_radius, dx);
    let rho = params.particle_mass * kernel.lattice_sum(dx) / dx.powi(3);
    assert!((rho / params.rest_density - 1.0).abs() < 1e-4, "ρ = {rho}");
    for r_len in [0.1, 0.3, 0.45, 0.55, 0.7, 0.9].map(|q| q * params.smoothing_radius) {
        let e = 1e-3 * params.smoothing_radius;
        let numeric = (kernel.value(r_len + e) - kernel.value(r_len - e)) / (2.0 * e);
        let analytic = kernel.gradient(Vec3::X * r_len, r_len).x;
        assert!(
            (numeric - analytic).abs() <= 2e-3 * analytic.abs(),
            "r = {r_len}: {numeric} vs {analytic}"
        );
    }
}

#[test]
fn the_fused_cubic_spline_evaluation_equals_value_and_gradient() {
    let params = SphParams::water();
    let h = params.smoothing_radius;
    let kernel = CubicSpline::new(h, params.spacing());
    let direction = Vec3::new(0.36, -0.48, 0.8);
    for step in 0..=130 {
        let r_len = step as f32 / 120.0 * h;
        let r = direction * r_len;
        let (w, f) = kernel.value_and_gradient_factor(r.length_squared());
        let (w_ref, grad_ref) = (kernel.value(r_len), kernel.gradient(r, r_len));
        assert!(
            (w - w_ref).abs() <= 1e-5 * kernel.value(0.0),
            "W at r = {r_len}: {w} vs {w_ref}"
        );
        let scale = kernel.gradient(Vec3::X * 0.5 * h, 0.5 * h).length();
        assert!(
            (r * f - grad_ref).length() <= 1e-5 * scale,
            "∇W at r = {r_len}: {} vs {grad_ref}",
            r * f
        );
        assert!(f.is_finite());
    }
}

#[test]
fn a_unit_stiffness_changes_its_own_predicted_density_by_dt2_d() {
    let b = block(0.2);
    let n = b.positions.len();
    let i = n / 2;
    let dt = 1e-3;
    let mut stiffness = vec![0.0; n];
    stiffness[i] = 1.0;
    let mut v = vec![Vec3::ZERO; n];
    apply_stiffness(&b.lists, &stiffness, &b.factors, dt, &mut v);
    let mut rates = vec![0.0f32; n];
    b.lists.update(&mut rates, |k, pairs, r| {
        *r = density_rate(k, pairs, &v, &b.factors[k])
    });
    let rate = rates[i];
    let d = 1.0 / b.factors[i].inverse_factor;
    let expected = -dt * dt * d;
    assert!(
        (dt * rate - expected).abs() <= 1e-3 * expected.abs(),
        "Δρ* = {} against -dt² D = {expected}",
        dt * rate
    );
}

#[test]
fn pressure_accelerations_conserve_momentum() {
    let b = block(0.3);
    let n = b.positions.len();
    let stiffness: Vec<f32> = (0..n).map(|k| (k % 7) as f32 * 0.01).collect();
    let mut v = vec![Vec3::ZERO; n];
    apply_stiffness(&b.lists, &stiffness, &b.factors, 1e-3, &mut v);
    let momentum: Vec3 = v.iter().copied().sum::<Vec3>() * b.params.particle_mass;
    let scale: f32 = v.iter().map(|v| v.length()).sum::<f32>() * b.params.particle_mass;
    assert!(scale > 0.0);
    assert!(
        momentum.length() <= 1e-4 * scale,
        "Σ m Δv = {momentum} against Σ m |Δv| = {scale}"
    );
}

fn dfsph_params() -> SphParams {
    let mut p = SphParams::water();
    p.use_solver(Solver::Dfsph);
    p
}

#[test]
fn use_solver_switches_the_time_step_rule() {
    let mut p = SphParams::water();
    let wcsph_dt = p.time_step;
    p.use_solver(Solver::Dfsph);
    assert_eq!(p.solver, Solver::Dfsph);
    assert!(p.adaptive_time_step);
    let expected = sph_core::solvers::dfsph_max_time_step(p.spacing(), 9.81);
    assert!((p.time_step / expected - 1.0).abs() < 1e-3);
    // g dt² = Δx / 200.
    let moved = 9.81 * p.time_step * p.time_step / p.spacing();
    assert!((moved - 0.005).abs() < 1e-4, "{moved}");
    assert!(p.time_step > 5.0 * wcsph_dt);
    p.use_solver(Solver::Wcsph);
    assert!(!p.adaptive_time_step);
    assert!((p.time_step / wcsph_dt - 1.0).abs() < 1e-3);
    // PBF brings its own λ; leaving it restores the default, so WCSPH's dt is as before.
    p.use_solver(Solver::Pbf);
    assert!(p.adaptive_time_step);
    assert_eq!(p.cfl_factor, sph_core::solvers::PBF_CFL_FACTOR);
    assert_eq!(p.time_step, sph_core::solvers::PBF_MAX_TIME_STEP);
    p.use_solver(Solver::Wcsph);
    assert_eq!(p.cfl_factor, sph_core::params::DEFAULT_CFL_FACTOR);
    assert!((p.time_step / wcsph_dt - 1.0).abs() < 1e-3);
    // λ chosen after the switch stays.
    p.use_solver(Solver::Dfsph);
    p.cfl_factor = 0.3;
    p.use_solver(Solver::Dfsph);
    assert_eq!(p.cfl_factor, 0.3);
}

#[test]
fn use_solver_gives_dfsph_its_own_viscosity() {
    use sph_core::params::{DEFAULT_VISCOSITY_ALPHA, DFSPH_VISCOSITY_ALPHA};
    let alpha = |p: &SphParams| p.artificial_viscosity_alpha();
    let mut p = SphParams::water();
    assert!((alpha(&p) - DEFAULT_VISCOSITY_ALPHA).abs() < 1e-5);
    p.use_solver(Solver::Dfsph);
    assert!((alpha(&p) - DFSPH_VISCOSITY_ALPHA).abs() < 1e-5);
    // Leaving DFSPH, for either other solver, restores the derived viscosity.
    for other in [Solver::Wcsph, Solver::Pbf] {
        p.use_solver(other);
        assert!(
            (alpha(&p) - DEFAULT_VISCOSITY_ALPHA).abs() < 1e-5,
            "{other:?}"
        );
        p.use_solver(Solver::Dfsph);
    }
    // A viscosity chosen after the switch stays when DFSPH is chosen again.
    p.set_artificial_viscosity_alpha(0.4);
    p.use_solver(Solver::Dfsph);
    assert!((alpha(&p) - 0.4).abs() < 1e-5);
    // Switching between the other two leaves the viscosity alone.
    p.use_solver(Solver::Wcsph);
    p.set_artificial_viscosity_alpha(0.07);
    p.use_solver(Solver::Pbf);
    assert!((alpha(&p) - 0.07).abs() < 1e-5);
    // The design preset keeps its own viscosity's proportion, a round trip gives it back, and a
    // viscosity switched off stays off.
    let mut seed = SphParams::seed();
    let seed_viscosity = seed.viscosity;
    seed.use_solver(Solver::Dfsph);
    assert!(
        (seed.viscosity / seed_viscosity - DFSPH_VISCOSITY_ALPHA / DEFAULT_VISCOSITY_ALPHA).abs()
            < 1e-5
    );
    seed.use_solver(Solver::Wcsph);
    assert!((seed.viscosity / seed_viscosity - 1.0).abs() < 1e-6);
    seed.viscosity = 0.0;
    seed.use_solver(Solver::Dfsph);
    assert_eq!(seed.viscosity, 0.0);
}

#[test]
fn bad_settings_name_the_field_and_the_range() {
    let cases: [(DfsphSettings, &str); 8] = [
        (
            DfsphSettings {
                max_density_error: 0.0,
                ..Default::default()
            },
            "dfsph.max_density_error",
        ),
        (
            DfsphSettings {
                max_divergence_error: f32::NAN,
                ..Default::default()
            },
            "dfsph.max_divergence_error",
        ),
        (
            DfsphSettings {
                min_density_iterations: 5,
                max_density_iterations: 4,
                ..Default::default()
            },
            "dfsph.min_density_iterations",
        ),
        (
            DfsphSettings {
                max_divergence_iterations: 0,
                ..Default::default()
            },
            "dfsph.max_divergence_iterations",
        ),
        (
            DfsphSettings {
                divergence_over_relaxation: 0.5,
                ..Default::default()
            },
            "dfsph.divergence_over_relaxation",
        ),
        (
            DfsphSettings {
                divergence_over_relaxation: f32::NAN,
                ..Default::default()
            },
            "dfsph.divergence_over_relaxation",
        ),
        (
            DfsphSettings {
                density_over_relaxation: 0.99,
                ..Default::default()
            },
            "dfsph.density_over_relaxation",
        ),
        (
            DfsphSettings {
                density_over_relaxation: 2.0,
                ..Default::default()
            },
            "dfsph.density_over_relaxation",
        ),
    ];
    for (settings, field) in cases {
        let mut p = dfsph_params();
        p.dfsph = settings;
        let error = p.validate().unwrap_err();
        assert_eq!(error.field, field);
        assert!(!error.allowed.is_empty());
        let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::ONE);
        let mut solver = CpuSolver::new(dfsph_params(), container, 10).unwrap();
        assert!(solver.set_params(p).is_err());
        assert_eq!(solver.params().dfsph, DfsphSettings::default(), "kept");
    }
}

fn dam_break(particles_per_side: usize) -> CpuSolver {
    let params = dfsph_params();
    let dx = params.spacing();
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.6, 0.4, 0.2));
    let side = particles_per_side as f32 * dx;
    let spawn = BlockSpawn::new(Vec3::ZERO, Vec3::new(side, side, side.min(0.2)), dx);
    let positions = spawn.positions();
    let mut solver = CpuSolver::new(params, container, positions.len()).unwrap();
    solver.spawn(&positions, Vec3::ZERO);
    solver
}

/// Archimedes, in a tank like `sph-bench run --scenario buoyancy`'s (8,000 particles, Δx = 1 cm):
/// a 6 × 4 × 6 Δx box held at mid-depth feels ρ0 g V upward within 15 % over the last 0.4 s of
/// 1 s, through the solves' boundary reactions. It reads −11 % here (sph-bench's tank, at
/// Δx = 0.99 cm, −5.1 %; the issue's ±5 % is a figure of sph-bench, not of this test). With the
/// divergence solve's over-relaxation pushing on where a particle's compression was already
/// gone, it read +58.5 % (docs/dfsph.md).
#[test]
fn a_box_held_under_water_feels_its_buoyancy() {
    let scene = sph_core::scenario::hydrostatic(0.2, 0.2, 0.01);
    let mut params = scene.params;
    params.use_solver(Solver::Dfsph);
    let (rho0, g) = (params.rest_density, params.gravity.length());
    let mut solver = CpuSolver::new(params, scene.container, scene.particle_count()).unwrap();
    // Faces on the lattice's cell planes.
    let half = Vec3::new(0.03, 0.02, 0.03);
    let pose = Pose {
        translation: Vec3::splat(0.1),
        rotation: Quat::IDENTITY,
    };
    let cube = Collider::new(ColliderShape::Cuboid { half_extents: half }, pose);
    let id = solver.add_collider(cube).unwrap();
    solver.spawn(&scene.positions(), Vec3::ZERO);
    while solver.time() < 0.6 {
        solver.step();
    }
    solver.take_collider_forces();
    while solver.time() < 1.0 {
        solver.step();
    }
    let force = solver.collider_force(id).unwrap().force;
    let expected = rho0 * g * 8.0 * half.x * half.y * half.z;
    let error = force.y / expected - 1.0;
    assert!(
        error.abs() < 0.15,
        "{force} N against rho0 g V = {expected} N: {:+.1} %",
        error * 100.0
    );
}

#[test]
fn a_dam_break_keeps_its_particles_and_its_density() {
    let mut solver = dam_break(10);
    let n = solver.len();
    let mut iterations = 0;
    while solver.time() < 0.2 {
        solver.step();
        let stats = solver.solver_stats();
        let settings = solver.params().dfsph;
        assert!(stats.density_iterations >= settings.min_density_iterations);
        assert!(stats.density_iterations <= settings.max_density_iterations);
        assert!(stats.divergence_iterations <= settings.max_divergence_iterations);
        iterations += stats.density_iterations;
    }
    let d = solver.diagnostics();
    assert_eq!(d.particle_count, n);
    assert_eq!(d.non_finite_count, 0);
    assert_eq!(d.outside_count, 0);
    assert!(
        d.density_error_mean_pct < 0.2,
        "{}",
        d.density_error_mean_pct
    );
    assert!(iterations > 0);
    assert!(
        solver.last_time_step() > 5.0 * SphParams::water().time_step,
        "DFSPH steps far beyond the speed of sound's dt"
    );
    // The water ran: its front left the column.
    let front = solver
        .particles()
        .position
        .iter()
        .map(|x| x.x)
        .fold(0.0, f32::max);
    assert!(front > 0.3, "front at {front} m");
}

#[test]
fn a_jittered_block_relaxes_without_gravity() {
    let mut params = dfsph_params();
    params.gravity = Vec3::ZERO;
    let dx = params.spacing();
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(0.3));
    let spawn = BlockSpawn::new(Vec3::splat(0.05), Vec3::splat(0.05 + 8.0 * dx), dx);
    let positions: Vec<Vec3> = spawn
        .positions()
        .iter()
        .enumerate()
        .map(|(k, &x)| jittered(x, k, 0.3 * dx))
        .collect();
    let mut solver = CpuSolver::new(params, container, positions.len()).unwrap();
    solver.spawn(&positions, Vec3::ZERO);
    solver.step();
    let first = solver.solver_stats();
    for _ in 0..20 {
        solver.step();
    }
    let last = solver.solver_stats();
    assert!(
        last.density_error <= params.dfsph.max_density_error
            || last.density_iterations == params.dfsph.max_density_iterations
    );
    assert!(last.density_iterations <= first.density_iterations);
    assert!(solver.diagnostics().density_error_mean_pct < 0.05);
}

#[test]
fn the_extremes_stay_finite() {
    for n in [0usize, 1, 2] {
        let params = dfsph_params();
        let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(0.2));
        let mut solver = CpuSolver::new(params, container, 4).unwrap();
        let positions: Vec<Vec3> = (0..n)
            .map(|k| Vec3::new(0.1 + 0.01 * k as f32, 0.1, 0.1))
            .collect();
        solver.spawn(&positions, Vec3::ZERO);
        for _ in 0..20 {
            solver.step();
        }
        let d = solver.diagnostics();
        assert_eq!(
            (d.particle_count, d.non_finite_count, d.outside_count),
            (n, 0, 0)
        );
    }
    // Coincident particles.
    let params = dfsph_params();
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(0.2));
    let mut solver = CpuSolver::new(params, container, 64).unwrap();
    solver.spawn(&[Vec3::splat(0.1); 64], Vec3::ZERO);
    for _ in 0..20 {
        solver.step();
    }
    let d = solver.diagnostics();
    assert_eq!((d.particle_count, d.non_finite_count), (64, 0));
}

#[test]
fn wcsph_reports_no_pressure_iterations() {
    let mut solver = dam_break(6);
    let mut p = *solver.params();
    p.use_solver(Solver::Wcsph);
    solver.set_params(p).unwrap();
    solver.step();
    let stats = solver.solver_stats();
    assert_eq!(
        (stats.density_iterations, stats.divergence_iterations),
        (0, 0)
    );
}

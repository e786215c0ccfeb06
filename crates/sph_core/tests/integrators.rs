//! Integrators against closed-form motion, and the damped wall bounce.

use sph_core::glam::Vec3;
use sph_core::{BoxContainer, CpuSolver, Integrator, SphParams};

fn falling(integrator: Integrator, steps: usize) -> (f32, f32, SphParams) {
    let mut params = SphParams::water();
    params.integrator = integrator;
    params.time_step = 1e-3;
    let container = BoxContainer::from_min_max(Vec3::splat(-2.0), Vec3::splat(2.0));
    let mut solver = CpuSolver::new(params, container, 1).unwrap();
    solver.spawn(&[Vec3::ZERO], Vec3::new(1.0, 0.0, 0.0));
    for _ in 0..steps {
        solver.step();
    }
    let p = solver.particles();
    (p.position[0].y, p.velocity[0].y, params)
}

#[test]
fn leapfrogs_are_exact_for_constant_acceleration() {
    let steps = 500;
    let t = steps as f32 * 1e-3;
    let exact_y = -0.5 * 9.81 * t * t;
    for integrator in [Integrator::Leapfrog, Integrator::KickDriftKick] {
        let (y, vy, _) = falling(integrator, steps);
        assert!(
            (y - exact_y).abs() < 1e-4,
            "{integrator:?}: y {y} vs {exact_y}"
        );
        assert!((vy + 9.81 * t).abs() < 1e-4, "{integrator:?}: vy {vy}");
    }
}

#[test]
fn symplectic_euler_has_its_first_order_error() {
    let steps = 500;
    let dt = 1e-3f32;
    let (y, _, _) = falling(Integrator::SymplecticEuler, steps);
    // y_n = -g dt² n(n+1)/2 for v += a dt; x += v dt.
    let n = steps as f32;
    let expected = -9.81 * dt * dt * n * (n + 1.0) / 2.0;
    assert!((y - expected).abs() < 1e-4, "y {y} vs {expected}");
    let exact = -0.5 * 9.81 * (n * dt).powi(2);
    assert!(
        (y - exact).abs() > 1e-3,
        "Euler should differ from the exact parabola"
    );
}

#[test]
fn leapfrog_evaluates_forces_twice_per_step() {
    let mut params = SphParams::water();
    params.integrator = Integrator::Leapfrog;
    let solver = CpuSolver::new(params, BoxContainer::default(), 1).unwrap();
    assert_eq!(solver.evaluations_per_step(), 2);
    params.integrator = Integrator::KickDriftKick;
    let mut solver = CpuSolver::new(params, BoxContainer::default(), 1).unwrap();
    solver.spawn(&[Vec3::splat(0.1)], Vec3::ZERO);
    assert_eq!(
        solver.evaluations_per_step(),
        2,
        "stale forces after a spawn"
    );
    solver.step();
    assert_eq!(solver.evaluations_per_step(), 1);
}

#[test]
fn wall_bounce_reflects_and_damps_the_normal_velocity() {
    let container = BoxContainer::default();
    let walls = container.walls(0.5);
    let mut x = Vec3::new(0.6, 0.5, 0.0);
    let mut v = Vec3::new(2.0, 1.0, -1.0);
    walls.collide(&mut x, &mut v);
    assert_eq!(x.x, 0.5, "clamped onto the wall");
    assert_eq!(
        v,
        Vec3::new(-1.0, 1.0, -1.0),
        "normal reflected and halved, tangent kept"
    );
    // Moving away from the wall is left alone.
    let mut x2 = Vec3::new(0.5, 0.5, 0.0);
    let mut v2 = Vec3::new(-1.0, 0.0, 0.0);
    walls.collide(&mut x2, &mut v2);
    assert_eq!(v2, Vec3::new(-1.0, 0.0, 0.0));
}

#[test]
fn a_particle_thrown_at_a_wall_bounces_back_in_a_solver_step() {
    for integrator in [
        Integrator::SymplecticEuler,
        Integrator::Leapfrog,
        Integrator::KickDriftKick,
    ] {
        let mut params = SphParams::water();
        params.gravity = Vec3::ZERO;
        params.integrator = integrator;
        params.wall_damping = 0.5;
        let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::ONE);
        // The box alone, its walls not sampled: the guard clamps the particle onto the wall,
        // reflects its normal velocity and halves it.
        let mut solver = CpuSolver::new(params, container, 1).unwrap();
        solver.set_wall_boundary(None);
        solver.spawn(&[Vec3::new(0.999, 0.5, 0.5)], Vec3::new(10.0, 0.0, 0.0));
        solver.step();
        let p = solver.particles();
        assert!(p.position[0].x <= 1.0);
        assert!(
            (p.velocity[0].x + 5.0).abs() < 1e-3,
            "{integrator:?}: vx {}",
            p.velocity[0].x
        );
        assert_eq!(solver.corrections().walls, 1, "{integrator:?}");
        // With the walls sampled, the solids' speculative contact (the particle starts
        // 0.05 Δx from the wall, inside its margin of 0.1 Δx) stops it before the wall: the guard
        // corrects nothing.
        let mut solver = CpuSolver::new(params, container, 1).unwrap();
        solver.spawn(&[Vec3::new(0.999, 0.5, 0.5)], Vec3::new(10.0, 0.0, 0.0));
        solver.step();
        let p = solver.particles();
        assert!(
            p.position[0].x < 1.0,
            "{integrator:?}: x {}",
            p.position[0].x
        );
        assert!(
            p.velocity[0].x.abs() < 1e-3,
            "{integrator:?}: vx {}",
            p.velocity[0].x
        );
        assert_eq!(solver.corrections().total(), 0, "{integrator:?}");
    }
}

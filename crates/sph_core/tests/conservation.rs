//! Internal forces are pairwise antisymmetric: they sum to ~0 (momentum conservation).

use sph_core::glam::Vec3;
use sph_core::rng::SplitMix64;
use sph_core::{BoxContainer, CpuSolver, Integrator, NeighborSearch, SphParams};

fn random_blob(n: usize, seed: u64, spacing: f32) -> (Vec<Vec3>, Vec<Vec3>) {
    let mut rng = SplitMix64::new(seed);
    let half = 0.5 * spacing * (n as f32).cbrt();
    let positions = (0..n)
        .map(|_| {
            Vec3::new(
                rng.range(-half, half),
                rng.range(-half, half),
                rng.range(-half, half),
            )
        })
        .collect();
    let velocities = (0..n)
        .map(|_| {
            Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            )
        })
        .collect();
    (positions, velocities)
}

fn total_and_magnitude(a: &[Vec3]) -> (Vec3, f32) {
    (a.iter().copied().sum(), a.iter().map(|a| a.length()).sum())
}

#[test]
fn internal_forces_sum_to_zero_for_random_particles() {
    for (search, surface_tension, clamp, seed) in [
        (NeighborSearch::Grid, 0.0, true, 1),
        (NeighborSearch::Grid, 0.05, false, 2),
        (NeighborSearch::Hash, 0.05, true, 3),
    ] {
        let mut params = SphParams::water();
        params.gravity = Vec3::ZERO;
        params.surface_tension = surface_tension;
        params.clamp_negative_pressure = clamp;
        params.neighbor_search = search;
        params.integrator = Integrator::SymplecticEuler;
        // Random clumps push particles apart fast: a tiny step keeps the step stable (a step
        // that is not would be rolled back, leaving no accelerations to check).
        params.time_step = 1e-6;
        let container = BoxContainer::from_min_max(Vec3::splat(-1.0), Vec3::splat(1.0));
        let (positions, velocities) = random_blob(3000, seed, params.spacing());
        let mut solver = CpuSolver::new(params, container, 3000).unwrap();
        solver.spawn_with_velocities(&positions, &velocities);
        solver.step();
        assert_eq!(solver.unstable_step(), None);
        let (sum, magnitude) = total_and_magnitude(&solver.particles().acceleration);
        assert!(magnitude > 0.0);
        assert!(
            sum.length() <= 1e-4 * magnitude,
            "{search:?} st {surface_tension}: |Σa| = {} vs Σ|a| = {magnitude}",
            sum.length()
        );
    }
}

#[test]
fn momentum_is_conserved_over_many_steps_away_from_walls() {
    let mut params = SphParams::water();
    params.gravity = Vec3::ZERO;
    params.surface_tension = 0.05;
    let container = BoxContainer::from_min_max(Vec3::splat(-5.0), Vec3::splat(5.0));
    let (positions, velocities) = random_blob(1000, 4, params.spacing());
    let velocities: Vec<Vec3> = velocities.iter().map(|v| *v * 0.1).collect();
    let mut solver = CpuSolver::new(params, container, 1000).unwrap();
    solver.spawn_with_velocities(&positions, &velocities);
    let before: Vec3 = velocities.iter().copied().sum();
    for _ in 0..100 {
        solver.step();
    }
    let after: Vec3 = solver.particles().velocity.iter().copied().sum();
    let scale: f32 = solver.particles().velocity.iter().map(|v| v.length()).sum();
    assert!(
        (after - before).length() <= 1e-3 * scale,
        "momentum drift {} vs Σ|v| {scale}",
        (after - before).length()
    );
}

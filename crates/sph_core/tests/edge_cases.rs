//! Tiny and degenerate particle sets never produce NaN or errors.

use sph_core::glam::Vec3;
use sph_core::{BoxContainer, CpuSolver, Integrator, NeighborSearch, SphParams};

fn all_configurations() -> Vec<SphParams> {
    let mut out = Vec::new();
    for integrator in [
        Integrator::SymplecticEuler,
        Integrator::Leapfrog,
        Integrator::KickDriftKick,
    ] {
        for search in [NeighborSearch::Grid, NeighborSearch::Hash] {
            for surface_tension in [0.0, 0.05] {
                let mut p = SphParams::water();
                p.integrator = integrator;
                p.neighbor_search = search;
                p.surface_tension = surface_tension;
                out.push(p);
            }
        }
    }
    out
}

fn run(params: SphParams, positions: &[Vec3], steps: usize) -> CpuSolver {
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(0.5));
    let mut solver = CpuSolver::new(params, container, positions.len().max(1)).unwrap();
    solver.spawn(positions, Vec3::ZERO);
    for _ in 0..steps {
        solver.step();
    }
    solver
}

fn assert_sane(solver: &CpuSolver, n: usize, what: &str) {
    let d = solver.diagnostics();
    assert_eq!(d.particle_count, n, "{what}");
    assert_eq!(d.non_finite_count, 0, "{what}: NaN");
    assert_eq!(d.outside_count, 0, "{what}: escaped");
}

#[test]
fn zero_and_one_particle_step_without_error() {
    for params in all_configurations() {
        let s = run(params, &[], 10);
        assert_sane(&s, 0, "0 particles");
        let s = run(params, &[Vec3::splat(0.25)], 10);
        assert_sane(&s, 1, "1 particle");
    }
}

#[test]
fn two_particles_at_the_same_position_produce_no_nan() {
    for params in all_configurations() {
        let s = run(params, &[Vec3::splat(0.25), Vec3::splat(0.25)], 50);
        assert_sane(&s, 2, &format!("{params:?}"));
    }
}

#[test]
fn many_particles_on_top_of_each_other_in_one_cell() {
    for params in all_configurations() {
        let positions = vec![Vec3::new(0.1, 0.2, 0.3); 64];
        let s = run(params, &positions, 20);
        assert_sane(&s, 64, "64 coincident particles");
    }
}

#[test]
fn a_lone_particle_falls_and_rests_on_the_floor() {
    for params in all_configurations() {
        // It falls 0.4 m, bounces off the wall samples a few times (to 0.1 m first) and lies on
        // the floor from about 1.1 s at the defaults (0.8 s before the walls' hydrostatic rise,
        // which pushes a little longer near the floor).
        let mut s = run(params, &[Vec3::new(0.25, 0.4, 0.25)], 0);
        while s.time() < 1.5 {
            s.step();
        }
        let x = s.particles().position[0];
        assert!(x.y.abs() < 1e-6, "{:?}: y = {}", params.integrator, x.y);
        assert_sane(&s, 1, "lone particle");
    }
}

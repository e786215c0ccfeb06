//! Block and pipe spawners, and capacity refusal.

use sph_core::glam::Vec3;
use sph_core::{BlockSpawn, BoxContainer, CpuSolver, PipeEmitter, SphParams};

#[test]
fn block_fills_a_lattice_inside_its_cuboid() {
    let block = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.1, 0.2, 0.05), 0.01);
    assert_eq!(block.lattice_dims(), [10, 20, 5]);
    let positions = block.positions();
    assert_eq!(positions.len(), 1000);
    assert!(positions
        .iter()
        .all(|p| p.cmpgt(Vec3::ZERO).all() && p.cmplt(block.max).all()));
    assert!((positions[1] - positions[0] - Vec3::new(0.01, 0.0, 0.0)).length() < 1e-6);
}

#[test]
fn block_jitter_is_bounded_and_deterministic() {
    let mut block = BlockSpawn::new(Vec3::ZERO, Vec3::splat(0.1), 0.01);
    let lattice = block.positions();
    block.jitter = 0.2;
    block.seed = 7;
    let jittered = block.positions();
    assert_eq!(jittered, block.positions());
    let moved = lattice
        .iter()
        .zip(&jittered)
        .filter(|(a, b)| a != b)
        .count();
    assert!(moved > 900);
    assert!(lattice
        .iter()
        .zip(&jittered)
        .all(|(a, b)| (*a - *b).abs().max_element() <= 0.002 + 1e-6));
    block.jitter = 0.8;
    assert_eq!(block.validate().unwrap_err().field, "block.jitter");
}

#[test]
fn emitter_emits_exactly_its_total_over_many_uneven_steps() {
    let mut e = PipeEmitter::new(Vec3::new(0.0, 0.5, 0.0), Vec3::X, 0.03, 1.5, 0.01);
    e.total = Some(1000);
    let disc = e.disc().len();
    assert!(disc > 20, "disc of {disc}");
    let mut emitted = 0;
    for k in 0..2000 {
        let dt = if k % 3 == 0 { 0.004 } else { 0.0007 };
        let out = e.emit(dt);
        // Whole discs, except the last one.
        assert!(out.positions.len().is_multiple_of(disc) || e.finished());
        emitted += out.positions.len();
    }
    assert_eq!(emitted, 1000);
    assert!(e.finished());
}

#[test]
fn emitter_jet_is_continuous_at_the_matched_rate() {
    let spacing = 0.01;
    let mut e = PipeEmitter::new(Vec3::ZERO, Vec3::X, 0.02, 2.0, spacing);
    let disc = e.disc().len();
    // Steps shorter and longer than one disc period (spacing / speed = 5 ms).
    let mut xs: Vec<f32> = Vec::new();
    let mut t = 0.0f32;
    for dt in [0.003f32, 0.011, 0.002, 0.0065, 0.009] {
        // Move earlier particles downstream as the jet would.
        for x in &mut xs {
            *x += 2.0 * dt;
        }
        t += dt;
        let out = e.emit(dt);
        assert_eq!(out.velocity, Vec3::new(2.0, 0.0, 0.0));
        xs.extend(out.positions.chunks(disc).map(|c| c[0].x));
    }
    let mut layers: Vec<f32> = xs.clone();
    layers.sort_by(f32::total_cmp);
    assert_eq!(layers.len(), (t * 2.0 / spacing).floor() as usize);
    for w in layers.windows(2) {
        assert!(
            (w[1] - w[0] - spacing).abs() < 1e-4,
            "layers {} and {} apart",
            w[0],
            w[1]
        );
    }
}

#[test]
fn spawning_past_capacity_refuses_and_reports_the_excess() {
    let mut solver = CpuSolver::new(SphParams::water(), BoxContainer::default(), 100).unwrap();
    let block = BlockSpawn::new(Vec3::ZERO, Vec3::splat(0.1), 0.02);
    assert_eq!(block.count(), 125);
    let report = solver.spawn(&block.positions(), Vec3::ZERO);
    assert_eq!((report.spawned, report.refused), (100, 25));
    assert_eq!(solver.len(), 100);
    let report = solver.spawn(&[Vec3::ZERO], Vec3::ZERO);
    assert_eq!((report.spawned, report.refused), (0, 1));
    solver.step();
    assert_eq!(solver.len(), 100);
}

#[test]
fn particle_ids_survive_sorting() {
    let mut solver = CpuSolver::new(SphParams::water(), BoxContainer::default(), 1000).unwrap();
    let block = BlockSpawn {
        jitter: 0.3,
        seed: 1,
        ..BlockSpawn::new(Vec3::ZERO, Vec3::splat(0.2), 0.02)
    };
    solver.spawn(&block.positions(), Vec3::ZERO);
    solver.step();
    let mut ids = solver.particles().id.clone();
    ids.sort();
    assert!(ids.iter().copied().eq(0..1000));
}

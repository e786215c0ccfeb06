//! Sinks remove exactly the particles inside them, and nothing else: initial + emitted −
//! drained = live, also across a rollback; pumps drive the water toward their target speed.

use sph_core::glam::Vec3;
use sph_core::{BlockSpawn, BoxContainer, CpuSolver, PipeEmitter, Pump, Region, Sink, SphParams};

fn tank() -> CpuSolver {
    let params = SphParams::water();
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.6, 0.4, 0.2));
    CpuSolver::new(params, container, 20_000).unwrap()
}

#[test]
fn a_drain_removes_what_it_reports_and_the_balance_holds_every_step() {
    let mut solver = tank();
    let dx = solver.params().spacing();
    let block = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.2, 0.3, 0.2), dx);
    let initial = solver.spawn(&block.positions(), Vec3::ZERO).spawned;
    let mut pipe = PipeEmitter::new(Vec3::new(0.3, 0.3, 0.1), Vec3::X, 0.03, 1.0, dx);
    // A drain along the right wall, and a closed one that must remove nothing.
    let sinks = [
        Sink {
            region: Region::from_min_max(Vec3::new(0.5, 0.0, 0.0), Vec3::new(0.6, 0.4, 0.2)),
            open: true,
        },
        Sink {
            region: Region::from_min_max(Vec3::ZERO, Vec3::new(0.1, 0.1, 0.2)),
            open: false,
        },
    ];
    let (mut emitted, mut drained) = (0usize, 0usize);
    for frame in 0..150 {
        let emission = pipe.emit(4.0 * solver.params().time_step);
        emitted += solver.spawn(&emission.positions, emission.velocity).spawned;
        for _ in 0..4 {
            solver.step();
        }
        let inside_before = solver
            .particles()
            .position
            .iter()
            .filter(|&&x| sinks[0].drains(x))
            .count();
        let ids_before: Vec<u32> = solver.particles().id.clone();
        let removed = solver.drain(&sinks);
        assert_eq!(removed, inside_before, "frame {frame}");
        drained += removed;
        assert_eq!(initial + emitted - drained, solver.len(), "frame {frame}");
        // Nothing left inside an open drain, and the survivors are the ones outside it.
        assert!(solver
            .particles()
            .position
            .iter()
            .all(|&x| !sinks[0].drains(x)));
        let mut ids: Vec<u32> = solver.particles().id.clone();
        ids.sort_unstable();
        ids.dedup();
        assert_eq!(ids.len(), solver.len(), "no particle duplicated");
        assert_eq!(ids_before.len() - removed, solver.len());
    }
    assert!(drained > 100, "the water reached the drain: {drained}");
    assert!(solver.unstable_step().is_none());
}

#[test]
fn a_rollback_after_a_drain_does_not_bring_drained_particles_back() {
    let mut solver = tank();
    let dx = solver.params().spacing();
    let block = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.2, 0.2, 0.2), dx);
    solver.spawn(&block.positions(), Vec3::ZERO);
    solver.step();
    let sink = Sink {
        region: Region::from_min_max(Vec3::ZERO, Vec3::new(0.1, 0.1, 0.2)),
        open: true,
    };
    let before = solver.len();
    let removed = solver.drain(&[sink]);
    assert!(removed > 0);
    // Make the next step blow up: an absurd time step rolls back to the checkpoint.
    let mut params = *solver.params();
    params.time_step = 0.05;
    params.adaptive_time_step = false;
    solver.set_params(params).unwrap();
    solver.step();
    assert!(solver.rollbacks() > 0 || solver.unstable_step().is_some());
    assert_eq!(solver.len(), before - removed);
    assert!(solver.particles().position.iter().all(|&x| !sink.drains(x)));
}

#[test]
fn a_pump_drives_the_water_toward_its_speed() {
    let mut solver = tank();
    let dx = solver.params().spacing();
    let block = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.6, 0.1, 0.2), dx);
    solver.spawn(&block.positions(), Vec3::ZERO);
    let pump = Pump {
        region: Region::from_min_max(Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.6, 0.12, 0.2)),
        direction: Vec3::X,
        speed: 0.3,
        strength: 20.0,
    };
    solver.set_pumps(&[pump]).unwrap();
    let bad = Pump {
        strength: -1.0,
        ..pump
    };
    assert_eq!(solver.set_pumps(&[bad]).unwrap_err().field, "pump.strength");
    assert_eq!(solver.pumps(), &[pump], "the previous pumps stay");
    for _ in 0..200 {
        solver.step();
    }
    let v = &solver.particles().velocity;
    let mean_x = v.iter().map(|v| v.x).sum::<f32>() / v.len() as f32;
    // The water is pushed toward +x (the walls at either end turn it back, so the mean stays
    // below the pump's speed).
    assert!(mean_x > 0.03 && mean_x <= 0.3 + 1e-3, "mean vx {mean_x}");
    assert!(solver.unstable_step().is_none());
}

//! Every control of the sandbox's runtime panel goes through the plugin's ECS API; each one,
//! changed while running, changes the very next GPU step exactly as the CPU reference predicts.

mod common;

use bevy::prelude::*;
use bevy_sph_fluid::prelude::*;
use common::*;
use sph_core::{BlockSpawn, BoxContainer, CpuSolver, Integrator};

type Change = fn(&mut sph_core::SphParams);

/// The CPU solver's next step from a snapshot's state with `params`, ordered by id.
fn predict(s: &SphSnapshot, params: sph_core::SphParams, container: BoxContainer) -> Vec<Vec3> {
    let order = by_id(s);
    let positions: Vec<Vec3> = order.iter().map(|&k| s.positions[k]).collect();
    let velocities: Vec<Vec3> = order.iter().map(|&k| s.velocities[k]).collect();
    let mut cpu = CpuSolver::new(params, container, positions.len()).unwrap();
    cpu.spawn_with_velocities(&positions, &velocities);
    cpu.step();
    let p = cpu.particles();
    let mut ids: Vec<usize> = (0..p.id.len()).collect();
    ids.sort_by_key(|&k| p.id[k]);
    ids.iter().map(|&k| p.velocity[k]).collect()
}

fn velocities_by_id(s: &SphSnapshot) -> Vec<Vec3> {
    by_id(s).iter().map(|&k| s.velocities[k]).collect()
}

fn max_difference(a: &[Vec3], b: &[Vec3]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (*x - *y).length())
        .fold(0.0, f32::max)
}

#[test]
fn each_panel_parameter_changes_the_next_step() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let mut params = sph_core::SphParams::water();
    params.integrator = Integrator::SymplecticEuler;
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.3, 0.3, 0.2));
    let block = BlockSpawn {
        jitter: 0.2,
        seed: 5,
        // The bottom layer rests on the floor, so the wall response is exercised.
        ..BlockSpawn::new(
            Vec3::new(0.0, -0.5 * params.spacing(), 0.0),
            Vec3::new(0.16, 0.2, 0.1),
            params.spacing(),
        )
    };
    let mut app = headless_app(block.count() as u32, SphBackend::Gpu);
    app.insert_resource(SphParams(params));
    app.world_mut().spawn(SphContainer(container));
    app.world_mut().spawn(SphBlockSpawn {
        block,
        velocity: Vec3::new(0.3, 0.0, 0.1),
    });
    app.update();
    step_to(&mut app, 3);

    // Wall damping is not in the list: the walls' boundary samples keep the particles off the
    // box's clamp, whose bounce it damps (sph_core's guard tests cover the clamp).
    let changes: [(&str, Change); 10] = [
        ("viscosity", |p| p.viscosity *= 20.0),
        ("stiffness", |p| p.stiffness *= 3.0),
        ("rest density (the mass follows)", |p| {
            p.rest_density *= 1.05;
            p.particle_mass *= 1.05;
        }),
        ("surface tension", |p| p.surface_tension = 0.5),
        ("gravity", |p| p.gravity.y = -3.0),
        ("time step", |p| p.time_step *= 0.5),
        ("adaptive time step, CFL factor 0.1", |p| {
            p.adaptive_time_step = true;
            p.cfl_factor = 0.1;
        }),
        ("integrator: leapfrog", |p| {
            p.integrator = Integrator::Leapfrog
        }),
        // From a fresh evaluation the leapfrog's and kick-drift-kick's steps coincide, so each
        // switch starts from symplectic Euler.
        ("integrator: symplectic Euler", |p| {
            p.integrator = Integrator::SymplecticEuler
        }),
        ("integrator: kick-drift-kick", |p| {
            p.integrator = Integrator::KickDriftKick
        }),
    ];
    let mut steps = 3;
    for (what, change) in changes {
        let before = snapshot(&mut app);
        let old = app.world().resource::<SphParams>().0;
        let mut new = old;
        change(&mut new);
        app.insert_resource(SphParams(new));
        steps += 1;
        step_to(&mut app, steps);
        let after = velocities_by_id(&snapshot(&mut app));
        let expected = predict(&before, new, container);
        let unchanged = predict(&before, old, container);
        let scale = expected.iter().map(|v| v.length()).fold(1e-3, f32::max);
        let error = max_difference(&after, &expected);
        let effect = max_difference(&expected, &unchanged);
        assert!(
            error <= 1e-4 * scale,
            "{what}: GPU differs from the CPU by {error} (scale {scale})"
        );
        assert!(
            effect > 10.0 * error.max(1e-7),
            "{what}: no visible effect ({effect})"
        );
    }

    // Substeps per frame: one running frame takes that many steps.
    app.insert_resource(SphControl {
        running: true,
        substeps: 3,
        ..default()
    });
    let before = steps_taken(&app);
    app.update();
    assert_eq!(steps_taken(&app), before + 3);
}

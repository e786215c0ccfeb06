//! Diffuse particles after Ihmsen et al. 2012 (`sph_core::whitewater`): the potentials vanish
//! where they should and grow where water runs into water or breaks at a crest, the classes
//! follow the fluid around a particle, spray falls ballistically, foam dies with its lifetime,
//! and nothing is lost without being counted.

use sph_core::glam::Vec3;
use sph_core::whitewater::ihmsen2012::{classify, FluidView, Whitewater};
use sph_core::whitewater::pool::DiffuseKind;
use sph_core::whitewater::settings::{Limits, WhitewaterSettings};
use sph_core::BoxContainer;

const DX: f32 = 0.02;
const H: f32 = 2.0 * DX;

fn container() -> BoxContainer {
    BoxContainer::from_min_max(Vec3::splat(-1.0), Vec3::splat(1.0))
}

/// A lattice block of `n` particles a side from `min`.
fn block(min: Vec3, n: [usize; 3]) -> Vec<Vec3> {
    let mut out = Vec::new();
    for i in 0..n[0] {
        for j in 0..n[1] {
            for k in 0..n[2] {
                out.push(min + Vec3::new(i as f32, j as f32, k as f32) * DX);
            }
        }
    }
    out
}

/// Two slabs one spacing apart at 3 m/s towards each other: the view of their water.
fn colliding_slabs() -> FluidView {
    let left = block(Vec3::ZERO, [4, 6, 6]);
    let right = block(Vec3::new(4.0 * DX, 0.0, 0.0), [4, 6, 6]);
    let velocities: Vec<Vec3> = (0..left.len())
        .map(|_| Vec3::X * 3.0)
        .chain((0..right.len()).map(|_| Vec3::X * -3.0))
        .collect();
    let positions: Vec<Vec3> = left.into_iter().chain(right).collect();
    FluidView::new(&positions, &velocities, &container(), H).unwrap()
}

#[test]
fn limits_clamp_to_zero_and_one() {
    let limits = Limits { min: 1.0, max: 3.0 };
    assert_eq!(limits.clamp(0.5), 0.0);
    assert_eq!(limits.clamp(2.0), 0.5);
    assert_eq!(limits.clamp(10.0), 1.0);
    assert_eq!(limits.clamp(f32::NAN), 0.0);
}

#[test]
fn water_at_rest_sheds_nothing_and_water_moving_as_one_traps_no_air() {
    let positions = block(Vec3::ZERO, [8, 8, 8]);
    for velocity in [Vec3::ZERO, Vec3::new(1.5, 0.0, 0.5)] {
        let velocities = vec![velocity; positions.len()];
        let fluid = FluidView::new(&positions, &velocities, &container(), H).unwrap();
        for i in 0..fluid.len() {
            assert!(fluid.potentials(i).trapped_air.abs() < 1e-6);
        }
        if velocity == Vec3::ZERO {
            let mut white = Whitewater::new(WhitewaterSettings::default(), container(), 100, 1);
            let step = white.step(&fluid, Vec3::new(0.0, -9.81, 0.0), DX, 0.005);
            assert_eq!(step.born, 0, "water at rest sheds nothing");
            assert!(white.pool.is_empty());
        }
    }
}

#[test]
fn two_streams_running_into_each_other_trap_air_and_shed_spray() {
    let fluid = colliding_slabs();
    let most = (0..fluid.len())
        .map(|i| fluid.potentials(i).trapped_air)
        .fold(0.0, f32::max);
    assert!(most > 2.0, "the facing layers trap air: {most} m/s");
    let mut white = Whitewater::new(WhitewaterSettings::default(), container(), 10_000, 7);
    let mut born = 0;
    for _ in 0..10 {
        born += white
            .step(&fluid, Vec3::new(0.0, -9.81, 0.0), DX, 0.005)
            .born;
    }
    assert!(born > 10, "the collision sheds diffuse particles ({born})");
    assert_eq!(white.pool.born, born);
    assert_eq!(white.pool.len() as u64, born - white.pool.expired);
}

#[test]
fn a_ball_bursting_outwards_has_crests_and_a_flat_top_has_none() {
    let centre = Vec3::splat(0.1);
    let ball: Vec<Vec3> = block(Vec3::ZERO, [11, 11, 11])
        .into_iter()
        .filter(|x| (*x - centre).length() <= 5.0 * DX)
        .collect();
    let outwards: Vec<Vec3> = ball.iter().map(|x| (*x - centre) * 20.0).collect();
    let fluid = FluidView::new(&ball, &outwards, &container(), H).unwrap();
    let crest = (0..fluid.len())
        .map(|i| fluid.potentials(i).wave_crest)
        .fold(0.0, f32::max);
    assert!(crest > 0.2, "a bursting ball's surface is a crest: {crest}");

    // A layer rising as one: the middle of its flat top has parallel normals.
    let layer = block(Vec3::ZERO, [15, 4, 15]);
    let up = vec![Vec3::Y; layer.len()];
    let fluid = FluidView::new(&layer, &up, &container(), H).unwrap();
    let middle = Vec3::new(7.0 * DX, 3.0 * DX, 7.0 * DX);
    let top = fluid
        .positions()
        .iter()
        .position(|x| (*x - middle).length() < 1e-4)
        .unwrap();
    assert!(fluid.potentials(top).kinetic_energy > 0.0);
    let flat = fluid.potentials(top).wave_crest;
    assert!(flat < 0.01, "the flat top's middle reads a crest of {flat}");
}

#[test]
fn the_class_follows_the_water_around_a_diffuse_particle() {
    let settings = WhitewaterSettings::default();
    let positions = block(Vec3::ZERO, [10, 10, 10]);
    let velocities = vec![Vec3::ZERO; positions.len()];
    let fluid = FluidView::new(&positions, &velocities, &container(), H).unwrap();
    let inside = Vec3::splat(4.5 * DX);
    let surface = Vec3::new(4.5 * DX, 9.5 * DX, 4.5 * DX);
    let air = Vec3::new(4.5 * DX, 15.0 * DX, 4.5 * DX);
    assert_eq!(
        classify(&settings, fluid.around(inside).0),
        DiffuseKind::Bubble
    );
    assert_eq!(
        classify(&settings, fluid.around(surface).0),
        DiffuseKind::Foam
    );
    assert_eq!(classify(&settings, fluid.around(air).0), DiffuseKind::Spray);
}

#[test]
fn spray_falls_ballistically_and_foam_dies_with_its_lifetime() {
    let g = Vec3::new(0.0, -9.81, 0.0);
    let dt = 0.01;
    let no_water = FluidView::new(&[], &[], &container(), H).unwrap();
    let mut white = Whitewater::new(WhitewaterSettings::default(), container(), 4, 3);
    white.pool.spawn(Vec3::ZERO, Vec3::new(1.0, 2.0, 0.0), 1.0);
    for _ in 0..20 {
        white.step(&no_water, g, DX, dt);
    }
    // Symplectic Euler: y_n = v0 n dt + g dt² n (n + 1) / 2.
    let n = 20.0;
    let expected = Vec3::new(
        n * dt,
        2.0 * n * dt + g.y * dt * dt * n * (n + 1.0) / 2.0,
        0.0,
    );
    assert!((white.pool.position[0] - expected).length() < 1e-4);
    assert_eq!(white.pool.kind[0], DiffuseKind::Spray);

    // Foam on a resting pool lives out its lifetime, then is counted as expired.
    let positions = block(Vec3::ZERO, [10, 10, 10]);
    let velocities = vec![Vec3::ZERO; positions.len()];
    let pool = FluidView::new(&positions, &velocities, &container(), H).unwrap();
    let mut white = Whitewater::new(WhitewaterSettings::default(), container(), 4, 3);
    white
        .pool
        .spawn(Vec3::new(4.5 * DX, 9.5 * DX, 4.5 * DX), Vec3::ZERO, 0.05);
    let mut expired = 0;
    for _ in 0..4 {
        expired += white.step(&pool, g, DX, dt).expired;
    }
    assert_eq!((white.pool.len(), expired), (1, 0));
    assert_eq!(white.pool.kind[0], DiffuseKind::Foam);
    for _ in 0..2 {
        expired += white.step(&pool, g, DX, dt).expired;
    }
    assert_eq!((white.pool.len(), expired), (0, 1));
}

#[test]
fn a_full_pool_counts_every_particle_it_refuses() {
    let fluid = colliding_slabs();
    let mut white = Whitewater::new(WhitewaterSettings::default(), container(), 3, 7);
    let mut offered = 0;
    for _ in 0..10 {
        let step = white.step(&fluid, Vec3::new(0.0, -9.81, 0.0), DX, 0.005);
        offered += step.born + step.dropped;
    }
    assert!(white.pool.dropped > 0, "the pool filled up");
    assert!(white.pool.len() <= 3);
    assert_eq!(white.pool.born + white.pool.dropped, offered);
}

/// `CpuSolver` steps whitewater only when asked: off by default, refused by field name with the
/// previous state kept, shedding where two streams of its water collide, never moving the water,
/// and emptied by `clear`.
#[test]
fn the_solver_sheds_whitewater_when_asked_and_leaves_the_water_alone() {
    use sph_core::{CpuSolver, SphParams};
    let params = SphParams::water();
    let dx = params.spacing();
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.6, 0.3, 0.2));
    let slab = |x: f32| -> Vec<Vec3> {
        let mut out = Vec::new();
        for i in 0..5 {
            for j in 0..6 {
                for k in 0..6 {
                    out.push(Vec3::new(
                        x + i as f32 * dx,
                        (j as f32 + 0.5) * dx,
                        (k as f32 + 0.5) * dx,
                    ));
                }
            }
        }
        out
    };
    let (left, right) = (slab(0.1), slab(0.4));
    let velocities: Vec<Vec3> = (0..left.len())
        .map(|_| Vec3::X * 3.0)
        .chain((0..right.len()).map(|_| Vec3::X * -3.0))
        .collect();
    let positions: Vec<Vec3> = left.into_iter().chain(right).collect();
    let run = |whitewater: bool| {
        let mut solver = CpuSolver::new(params, container, positions.len()).unwrap();
        assert!(solver.whitewater().is_none(), "off by default");
        if whitewater {
            let bad = WhitewaterSettings {
                drag: 2.0,
                ..Default::default()
            };
            let e = solver.set_whitewater(Some((bad, 1_000))).unwrap_err();
            assert_eq!(e.field, "whitewater.drag");
            let e = solver
                .set_whitewater(Some((WhitewaterSettings::default(), 0)))
                .unwrap_err();
            assert_eq!(e.field, "whitewater.capacity");
            assert!(solver.whitewater().is_none(), "refusals change nothing");
            solver
                .set_whitewater(Some((WhitewaterSettings::default(), 1_000)))
                .unwrap();
        }
        solver.spawn_with_velocities(&positions, &velocities);
        while solver.time() < 0.08 {
            solver.step();
        }
        solver
    };
    let (with, without) = (run(true), run(false));
    let pool = &with.whitewater().unwrap().pool;
    println!(
        "born {}, alive {}, expired {}, dropped {}",
        pool.born,
        pool.len(),
        pool.expired,
        pool.dropped
    );
    assert!(pool.born > 0, "colliding streams shed");
    assert_eq!(pool.born, pool.len() as u64 + pool.expired);
    assert_eq!(
        with.particles().position,
        without.particles().position,
        "diffuse particles never act on the water"
    );
    let mut with = with;
    with.clear();
    let white = with.whitewater().expect("clear keeps it on");
    assert_eq!((white.pool.len(), white.pool.born), (0, 0));
}

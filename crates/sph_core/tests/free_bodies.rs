//! A dynamic body gives way in DFSPH's solves when its mass is known (`sph_core::boundary::free_bodies`): a
//! heavy box moved once per frame, as a physics engine moves it, rests on the water under it
//! instead of rattling; and the mass is validated.

use sph_core::glam::{Quat, Vec3};
use sph_core::{
    BlockSpawn, BoxContainer, Collider, ColliderId, ColliderMotion, ColliderShape, CpuSolver, Pose,
    Slip, Solver, SphParams,
};

const SIDE: f32 = 0.12;
const FRAME: f32 = 1.0 / 60.0;

/// A tank 0.2 m deep (spacing 0.02 m) with a box of 1,500 kg/m³ released at the surface.
fn tank_with_heavy_box() -> (CpuSolver, ColliderId, f32) {
    let mut params = SphParams::water();
    params.use_solver(Solver::Dfsph);
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.36, 0.4, 0.36));
    let mut solver = CpuSolver::new(params, container, 8_000).unwrap();
    solver.set_wall_boundary(Some(Slip::Free));
    let mut box_collider = Collider::new(
        ColliderShape::Cuboid {
            half_extents: Vec3::splat(0.5 * SIDE),
        },
        Pose {
            translation: Vec3::new(0.18, 0.2, 0.18),
            rotation: Quat::IDENTITY,
        },
    );
    box_collider.motion = ColliderMotion::Dynamic;
    let id = solver.add_collider(box_collider).unwrap();
    let block = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.36, 0.2, 0.36), params.spacing());
    solver.spawn(&block.positions(), Vec3::ZERO);
    (solver, id, 1500.0 * SIDE.powi(3))
}

/// Runs `frames` frames of 1/60 s: the water steps, then the box moves once with the frame's
/// mean force and gravity (symplectic Euler, no rotation) and stops on the floor, as an engine
/// would move it. Returns the box's vertical velocity and the water's vertical force per frame.
fn drop_box(mass_known: bool, frames: usize) -> Vec<(f32, f32)> {
    let (mut solver, id, mass) = tank_with_heavy_box();
    if mass_known {
        solver.set_collider_mass(id, Some(mass)).unwrap();
    }
    let mut pose = solver.colliders().next().unwrap().1.pose;
    let mut velocity = Vec3::ZERO;
    let mut frames_out = Vec::new();
    for _ in 0..frames {
        solver
            .set_collider_motion(id, pose, velocity, Vec3::ZERO)
            .unwrap();
        solver.advance_by(FRAME, 64);
        assert_eq!(solver.unstable_step(), None);
        let force = solver.take_collider_forces()[0].1.force;
        velocity += (force / mass + Vec3::new(0.0, -9.81, 0.0)) * FRAME;
        pose.translation += velocity * FRAME;
        if pose.translation.y < 0.5 * SIDE {
            pose.translation.y = 0.5 * SIDE;
            velocity = Vec3::ZERO;
        }
        frames_out.push((velocity.y, force.y));
    }
    frames_out
}

#[test]
fn a_heavy_box_moved_once_a_frame_rests_on_the_water_when_its_mass_is_known() {
    let frames = 100;
    // Settled on the last layer of water by frame 60; the last 40 frames are compared.
    let largest = |run: &[(f32, f32)]| {
        run[60..]
            .iter()
            .fold((0.0f32, 0.0f32), |(v, f), &(vy, fy)| {
                (
                    v.max(vy.abs()),
                    f.max((fy - 9.81 * 1500.0 * SIDE.powi(3)).abs()),
                )
            })
    };
    let (speed, force_off) = largest(&drop_box(true, frames));
    let (speed_blind, force_off_blind) = largest(&drop_box(false, frames));
    println!(
        "largest speed over frames 60-100: {speed:.3} m/s with the mass, {speed_blind:.3} \
         without; the water's force off the weight by at most {force_off:.1} and \
         {force_off_blind:.1} N"
    );
    // Without the mass the box rattles from frame to frame (measured: up to 0.101 m/s, the
    // water's force up to 30.4 N off the 25.4 N weight; no sample mirrors the stiffness then,
    // `sph_core::Boundary::mirrors`). With it every sample mirrors, and the box trembles on the
    // last layer of water, pinched between it and the floor (up to 0.074 m/s; 0.019 m/s before
    // DFSPH's boundary mirrored the stiffness, docs/dfsph.md), with the force within 7.0 N.
    assert!(speed_blind > 0.05, "{speed_blind}");
    assert!(speed < speed_blind, "{speed} {speed_blind}");
    assert!(
        force_off < 0.5 * force_off_blind,
        "{force_off} {force_off_blind}"
    );
}

#[test]
fn a_bodys_mass_is_refused_unless_finite_and_positive() {
    let (mut solver, id, mass) = tank_with_heavy_box();
    solver.set_collider_mass(id, Some(mass)).unwrap();
    for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        let e = solver.set_collider_mass(id, Some(bad)).unwrap_err();
        assert_eq!(e.field, "mass");
        assert_eq!(e.allowed, "finite and > 0 kg");
        assert_eq!(e.value, bad.to_string());
    }
    // The previous mass stays: body index = slot + 1.
    assert_eq!(solver.boundary().free_mass(id.0 as usize + 1), Some(mass));
    let e = solver
        .set_collider_mass(ColliderId(id.0 + 7), Some(1.0))
        .unwrap_err();
    assert_eq!(e.field, "id");
    solver.set_collider_mass(id, None).unwrap();
    assert_eq!(solver.boundary().free_mass(id.0 as usize + 1), None);
    // The walls and a static collider never give way, whatever mass they are told.
    let sphere = solver
        .add_collider(Collider::new(
            ColliderShape::Sphere { radius: 0.03 },
            Pose {
                translation: Vec3::new(0.05, 0.3, 0.05),
                rotation: Quat::IDENTITY,
            },
        ))
        .unwrap();
    solver.set_collider_mass(sphere, Some(1.0)).unwrap();
    assert_eq!(solver.boundary().free_mass(sphere.0 as usize + 1), None);
    assert_eq!(solver.boundary().free_mass(0), None);
}

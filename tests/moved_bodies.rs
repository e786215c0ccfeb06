//! The bodies the device moves (GPU backend, `sph_core::bodies`): a box with an `SphRigidBody`
//! dropped into a tank is moved by the device at every water step, and each frame's record
//! agrees with the CPU twin's step (`sph_core::bodies::rigid_step::advance`) from the record
//! before, under the water's force and torque the device recorded.

use bevy::prelude::*;
use bevy_sph_fluid::moved_bodies::SphMovedBodies;
use bevy_sph_fluid::prelude::*;
use sph_core::bodies::engine_handoff::FrameRecord;
use sph_core::bodies::rigid_step::advance;
use sph_core::{BlockSpawn, BoxContainer, ColliderMotion, ColliderShape};
use std::collections::BTreeMap;

mod common;

/// A 500 kg/m³ box of side 0.08 m, spinning, dropped at 0.2 m/s onto water 0.08 m deep (PBF,
/// one step a frame): 40 frames' records, each against the twin's step from the one before.
#[test]
fn the_devices_body_steps_match_the_cpu_twin() {
    let _alone = common::GPU.lock().unwrap_or_else(|e| e.into_inner());
    let mut app = common::headless_app(6_000, SphBackend::Gpu);
    let mut params = sph_core::SphParams::water();
    params.use_solver(sph_core::Solver::Pbf);
    app.insert_resource(SphParams(params));
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.3, 0.3, 0.3));
    app.world_mut().spawn(SphContainer(container));
    let side = 0.08;
    let mass = 500.0 * side * side * side;
    let inertia = mass * side * side / 6.0;
    let body = SphRigidBody {
        mass,
        center_of_mass: Vec3::new(0.0, 0.005, 0.0),
        inverse_inertia: Mat3::from_diagonal(Vec3::splat(1.0 / inertia)),
        free_translation: Vec3::ONE,
        free_rotation: Vec3::ONE,
        hinge_axis: None,
        gravity: params.gravity,
        linear_damping: 0.1,
        angular_damping: 0.2,
        linear_velocity: Vec3::new(0.05, -0.2, 0.0),
        angular_velocity: Vec3::new(0.0, 1.5, 0.5),
    };
    let entity = app
        .world_mut()
        .spawn((
            SphCollider::new(ColliderShape::Cuboid {
                half_extents: Vec3::splat(0.5 * side),
            })
            .with_motion(ColliderMotion::Dynamic),
            body,
            Transform::from_xyz(0.15, 0.14, 0.15).with_rotation(Quat::from_rotation_y(0.3)),
        ))
        .id();
    app.update();
    app.world_mut().spawn(SphBlockSpawn {
        block: BlockSpawn::new(Vec3::ZERO, Vec3::new(0.3, 0.08, 0.3), params.spacing()),
        velocity: Vec3::ZERO,
    });
    app.insert_resource(SphControl {
        running: true,
        substeps: 1,
        ..default()
    });
    // Every record read back, by frame.
    let mut records: BTreeMap<u32, FrameRecord> = BTreeMap::new();
    for _ in 0..400 {
        app.update();
        let moved = app.world().resource::<SphMovedBodies>();
        let slot = *moved.slots.get(&entity).expect("the box is a moved body");

        if let Some(latest) = &moved.latest {
            for r in latest.bodies[slot as usize]
                .records
                .iter()
                .filter_map(|r| r.record())
            {
                records.insert(r.frame, r);
            }
        }
        let stats = app.world().resource::<SphStats>();
        assert!(!stats.health.is_unstable(), "{:?}", stats.health);
        if records.len() >= 40 {
            break;
        }
    }
    assert!(records.len() >= 40, "{} records", records.len());
    let model = bevy_sph_fluid::moved_bodies::body_model(
        &body,
        Vec3::new(0.15, 0.14, 0.15),
        Quat::from_rotation_y(0.3),
    )
    .unwrap();
    let (mut pairs, mut wet, mut worst) = (0, 0, [0.0f32; 4]);
    for (frame, before) in &records {
        let Some(after) = records.get(&(frame + 1)) else {
            continue;
        };
        // One step a frame: the frame's force and its moment about the origin.
        let dt = after.duration;
        let force = after.impulse / dt;
        let moment = after.angular_impulse / dt + before.state.position.cross(force);
        let twin = advance(&model, &before.state, force, moment, dt);
        let s = after.state;
        let errors = [
            (twin.position - s.position).length(),
            (twin.linear_velocity - s.linear_velocity).length(),
            (twin.angular_velocity - s.angular_velocity).length(),
            (Vec4::from(twin.rotation) - Vec4::from(s.rotation)).length(),
        ];
        for (w, e) in worst.iter_mut().zip(errors) {
            *w = w.max(e);
        }
        pairs += 1;
        wet += (force.length() > 0.1 * mass * 9.81) as usize;
    }
    println!(
        "{pairs} frame pairs ({wet} in the water): largest |Δx| {:.2e} m, |Δv| {:.2e} m/s, \
         |Δω| {:.2e} rad/s, |Δq| {:.2e}",
        worst[0], worst[1], worst[2], worst[3]
    );
    assert!(
        pairs >= 30 && wet >= 10,
        "{pairs} pairs, {wet} in the water"
    );
    assert!(worst[0] < 1e-6, "position {}", worst[0]);
    assert!(worst[1] < 1e-5, "velocity {}", worst[1]);
    assert!(worst[2] < 1e-4, "angular velocity {}", worst[2]);
    assert!(worst[3] < 1e-5, "rotation {}", worst[3]);
    // It fell into the water and the water pushed back.
    let first = records.values().next().unwrap().state;
    let last = records.values().last().unwrap().state;
    assert!(
        last.position.y < first.position.y - 0.01,
        "{first:?} {last:?}"
    );
}

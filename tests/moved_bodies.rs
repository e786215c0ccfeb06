//! The bodies the device moves (GPU backend, `sph_core::bodies`): a box with an `SphRigidBody`
//! dropped into a tank is moved by the device at every water step, and each frame's record
//! agrees with the CPU twin's step (`sph_core::bodies::rigid_step::advance`, then the box's
//! contact with the tank, `solid_contact::box_push`) from the record before, under the water's
//! force and torque the device recorded.

use bevy::prelude::*;
use bevy_sph_fluid::moved_bodies::SphMovedBodies;
use bevy_sph_fluid::prelude::*;
use sph_core::bodies::engine_handoff::FrameRecord;
use sph_core::bodies::rigid_step::{advance, RigidState};
use sph_core::bodies::solid_contact::{box_push, support};
use sph_core::{BlockSpawn, BoxContainer, ColliderMotion, ColliderShape, Pose};
use std::collections::BTreeMap;

mod common;

/// The side of the dropped box [m].
const SIDE: f32 = 0.08;

/// What a drop showed: frame pairs compared, of those in the water and touching the floor, the
/// largest differences (position, velocity, angular velocity, quaternion) and the last state.
struct Drop {
    pairs: usize,
    wet: usize,
    on_the_floor: usize,
    worst: [f32; 4],
    last: RigidState,
}

/// A box of `density` [kg/m³], side 0.08 m, spinning, dropped at 0.2 m/s onto water 0.08 m deep
/// (PBF, one step a frame): `frames` records, each against the twin's step from the one before.
fn drop_box(density: f32, frames: usize) -> Drop {
    let mut app = common::headless_app(6_000, SphBackend::Gpu);
    let mut params = sph_core::SphParams::water();
    params.use_solver(sph_core::Solver::Pbf);
    app.insert_resource(SphParams(params));
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.3, 0.3, 0.3));
    app.world_mut().spawn(SphContainer(container));
    let mass = density * SIDE * SIDE * SIDE;
    let inertia = mass * SIDE * SIDE / 6.0;
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
    let shape = ColliderShape::Cuboid {
        half_extents: Vec3::splat(0.5 * SIDE),
    };
    let start = Transform::from_xyz(0.15, 0.14, 0.15).with_rotation(Quat::from_rotation_y(0.3));
    let entity = app
        .world_mut()
        .spawn((
            SphCollider::new(shape.clone()).with_motion(ColliderMotion::Dynamic),
            body,
            start,
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
    for _ in 0..40 * frames {
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
        if records.len() >= frames {
            break;
        }
    }
    assert!(records.len() >= frames, "{} records", records.len());
    let model =
        bevy_sph_fluid::moved_bodies::body_model(&body, start.translation, start.rotation).unwrap();
    let mut drop = Drop {
        pairs: 0,
        wet: 0,
        on_the_floor: 0,
        worst: [0.0; 4],
        last: records.values().last().unwrap().state,
    };
    for (frame, before) in &records {
        let Some(after) = records.get(&(frame + 1)) else {
            continue;
        };
        // One step a frame: the frame's force and its moment about the origin.
        let dt = after.duration;
        let force = after.impulse / dt;
        let moment = after.angular_impulse / dt + before.state.position.cross(force);
        let stepped = advance(&model, &before.state, force, moment, dt);
        let pose = Pose {
            translation: stepped.origin(model.center_of_mass),
            rotation: stepped.rotation,
        };
        let push = box_push(&shape, pose, &container);
        let twin = push.resolve(&stepped);
        let s = after.state;
        let errors = [
            (twin.position - s.position).length(),
            (twin.linear_velocity - s.linear_velocity).length(),
            (twin.angular_velocity - s.angular_velocity).length(),
            (Vec4::from(twin.rotation) - Vec4::from(s.rotation)).length(),
        ];
        for (w, e) in drop.worst.iter_mut().zip(errors) {
            *w = w.max(e);
        }
        drop.pairs += 1;
        drop.wet += (force.length() > 0.1 * mass * 9.81) as usize;
        drop.on_the_floor += (push.positive.y > 0.0) as usize;
    }
    println!(
        "{density} kg/m³: {} frame pairs ({} in the water, {} pushed off the floor): largest \
         |Δx| {:.2e} m, |Δv| {:.2e} m/s, |Δω| {:.2e} rad/s, |Δq| {:.2e}; last {:?}",
        drop.pairs,
        drop.wet,
        drop.on_the_floor,
        drop.worst[0],
        drop.worst[1],
        drop.worst[2],
        drop.worst[3],
        drop.last
    );
    drop
}

fn assert_twin(drop: &Drop) {
    assert!(drop.worst[0] < 1e-6, "position {}", drop.worst[0]);
    assert!(drop.worst[1] < 1e-5, "velocity {}", drop.worst[1]);
    assert!(drop.worst[2] < 1e-4, "angular velocity {}", drop.worst[2]);
    assert!(drop.worst[3] < 1e-5, "rotation {}", drop.worst[3]);
}

/// A 500 kg/m³ box: it falls into the water, which pushes it back up.
#[test]
fn the_devices_body_steps_match_the_cpu_twin() {
    let _alone = common::GPU.lock().unwrap_or_else(|e| e.into_inner());
    let drop = drop_box(500.0, 40);
    assert!(drop.pairs >= 30 && drop.wet >= 10, "{} pairs", drop.pairs);
    assert_twin(&drop);
}

/// A 3,000 kg/m³ box sinks to the tank's floor: the device stops it there (its contact with the
/// walls), as the twin does, and it rests with its lowest corner on the floor.
#[test]
fn a_sinking_body_rests_on_the_floor_as_the_twin_says() {
    let _alone = common::GPU.lock().unwrap_or_else(|e| e.into_inner());
    let drop = drop_box(3000.0, 90);
    assert!(
        drop.on_the_floor >= 5,
        "{} frames on the floor",
        drop.on_the_floor
    );
    assert_twin(&drop);
    // Its lowest point (the support along −y from its origin) is not below the floor.
    let shape = ColliderShape::Cuboid {
        half_extents: Vec3::splat(0.5 * SIDE),
    };
    let origin = drop.last.position - drop.last.rotation * Vec3::new(0.0, 0.005, 0.0);
    let reach = support(&shape, drop.last.rotation, Vec3::NEG_Y).unwrap();
    assert!(
        origin.y - reach > -1e-5,
        "{:?} below the floor",
        origin.y - reach
    );
}

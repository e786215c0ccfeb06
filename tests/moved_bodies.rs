//! The bodies the device moves (GPU backend, `sph_core::bodies`): a box with an `SphRigidBody`
//! dropped into a tank is moved by the device at every water step, and each frame's record
//! agrees with the CPU twin's step (`sph_core::bodies::rigid_step::advance`, then the box's
//! contact with the tank, `solid_contact::box_push`) from the record before, under the water's
//! force and torque the device recorded and the engine's push; at three steps a frame each record's moments in time
//! of the water's impulse give the body's end of frame from its start.

use bevy::prelude::*;
use bevy_sph_fluid::moved_bodies::SphMovedBodies;
use bevy_sph_fluid::prelude::*;
use sph_core::bodies::engine_handoff::FrameRecord;
use sph_core::bodies::engine_push::EnginePush;
use sph_core::bodies::rigid_step::{advance, RigidState};
use sph_core::bodies::solid_contact::{
    body_margin, box_push, friction_step, resolve_bodies, resolve_solids, sample_pushes, support,
    MovedNeighbour, Partner,
};
use sph_core::boundary::sampling::sample_shape;
use sph_core::{BlockSpawn, BoxContainer, Collider, ColliderMotion, ColliderShape, Pose};
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
/// (PBF, `substeps` steps a frame, the body damped by `damping` (linear, twice that angular),
/// the engine's `push` handed with its state): at least `frames` records read back, by frame;
/// the box and where it started.
fn dropped_records(
    density: f32,
    frames: usize,
    substeps: u32,
    damping: f32,
    push: EnginePush,
) -> (BTreeMap<u32, FrameRecord>, SphRigidBody, Transform) {
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
        linear_damping: damping,
        angular_damping: 2.0 * damping,
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
        substeps,
        ..default()
    });
    // Every record read back, by frame.
    let mut records: BTreeMap<u32, FrameRecord> = BTreeMap::new();
    for _ in 0..40 * frames {
        app.world_mut()
            .resource_mut::<SphMovedBodies>()
            .engine_pushes
            .insert(entity, push);
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
    (records, body, start)
}

/// A box of `density` [kg/m³] dropped as [`dropped_records`] says (one step a frame, damped,
/// under the engine's `push`): `frames` records, each against the twin's step from the one
/// before.
fn drop_box(density: f32, frames: usize, push: EnginePush) -> Drop {
    let (records, body, start) = dropped_records(density, frames, 1, 0.1, push);
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.3, 0.3, 0.3));
    let shape = ColliderShape::Cuboid {
        half_extents: Vec3::splat(0.5 * SIDE),
    };
    let mass = body.mass;
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
        // One step a frame: the frame's force and its moment about the origin, the water's and
        // the engine's push.
        let dt = after.duration;
        let force = after.impulse / dt;
        let c = before.state.position;
        let moment = after.angular_impulse / dt + c.cross(force) + push.moment_about_origin(c);
        let stepped = advance(&model, &before.state, force + push.force, moment, dt);
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

/// A 500 kg/m³ box: it falls into the water, which pushes it back up; the engine's push (a
/// contact holding a fifth of its weight, pressing it sideways and turning it) applies at
/// every step.
#[test]
fn the_devices_body_steps_match_the_cpu_twin() {
    let _alone = common::GPU.lock().unwrap_or_else(|e| e.into_inner());
    let weight = 500.0 * SIDE * SIDE * SIDE * 9.81;
    let push = EnginePush {
        force: Vec3::new(0.1, 0.2, -0.05) * weight,
        torque: Vec3::new(0.0, 1e-4, 2e-4),
    };
    let drop = drop_box(500.0, 40, push);
    assert!(drop.pairs >= 30 && drop.wet >= 10, "{} pairs", drop.pairs);
    assert_twin(&drop);
}

/// Three water steps a frame, no damping: each frame's record says when in the frame the water
/// pushed (the moments in time of its impulse, P = Σ F dt (t − t₀), and of its steps,
/// Q = Σ dt (t − t₀); `sph_core::bodies::engine_window`). With them the body's end follows from
/// its start, c₁ = c₀ + v₀ T + (J T − P) / M + g (T² − Q), in every frame of a 500 kg/m³ box
/// floating in the middle of the tank (no contact); taking the push as even over the frame
/// (P = Q J / T) misses it by far more.
#[test]
fn a_frames_moments_say_when_in_it_the_water_pushed() {
    let _alone = common::GPU.lock().unwrap_or_else(|e| e.into_inner());
    let (records, body, _) = dropped_records(500.0, 30, 3, 0.0, EnginePush::default());
    let (mut pairs, mut worst, mut worst_even) = (0, 0.0f32, 0.0f32);
    for (frame, before) in &records {
        let Some(after) = records.get(&(frame + 1)) else {
            continue;
        };
        let (t, j, p, q) = (
            after.duration,
            after.impulse,
            after.impulse_moment,
            after.time_moment,
        );
        // Three steps of the frame: 0 < Q < T² / 2.
        assert!(
            q > 0.0 && q < 0.5 * t * t,
            "frame {}: T {t}, Q {q}",
            after.frame
        );
        let s = before.state;
        let free = s.position + t * s.linear_velocity + (t * t - q) * body.gravity;
        let end = after.state.position;
        worst = worst.max((free + (t * j - p) / body.mass - end).length());
        worst_even = worst_even.max((free + (t * j - q * j / t) / body.mass - end).length());
        pairs += 1;
    }
    println!("{pairs} frame pairs: largest miss {worst:.2e} m, {worst_even:.2e} m taken even");
    assert!(pairs >= 25, "{pairs} pairs");
    assert!(worst < 1e-6, "missed by {worst} m");
    assert!(worst_even > 10.0 * worst.max(1e-7), "even: {worst_even} m");
}

/// A 3,000 kg/m³ box sinks to the tank's floor: the device stops it there (its contact with the
/// walls), as the twin does, and it rests with its lowest corner on the floor.
#[test]
fn a_sinking_body_rests_on_the_floor_as_the_twin_says() {
    let _alone = common::GPU.lock().unwrap_or_else(|e| e.into_inner());
    let drop = drop_box(3000.0, 90, EnginePush::default());
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

/// A 3,000 kg/m³ box dropped from 1 cm onto another resting on the floor, sliding at 6 cm/s,
/// both moved by the device (no engine): the device's contact between them
/// (`solid_contact::body_push`) stops the upper one on the lower one, within g dt² of touching,
/// and its friction (`solid_contact::support_friction`) makes the pair slide as one on the
/// frictionless floor with the upper box's momentum; without the contact the upper box sank
/// through the lower one.
#[test]
fn a_box_dropped_on_another_rests_on_it_on_the_device() {
    let _alone = common::GPU.lock().unwrap_or_else(|e| e.into_inner());
    let mut app = common::headless_app(2_000, SphBackend::Gpu);
    let mut params = sph_core::SphParams::water();
    params.use_solver(sph_core::Solver::Pbf);
    app.insert_resource(SphParams(params));
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.3, 0.3, 0.3));
    app.world_mut().spawn(SphContainer(container));
    let mass = 3000.0 * SIDE * SIDE * SIDE;
    let inertia = mass * SIDE * SIDE / 6.0;
    let shape = ColliderShape::Cuboid {
        half_extents: Vec3::splat(0.5 * SIDE),
    };
    let body = SphRigidBody {
        mass,
        center_of_mass: Vec3::ZERO,
        inverse_inertia: Mat3::from_diagonal(Vec3::splat(1.0 / inertia)),
        free_translation: Vec3::ONE,
        free_rotation: Vec3::ONE,
        hinge_axis: None,
        gravity: params.gravity,
        linear_damping: 0.0,
        angular_damping: 0.0,
        linear_velocity: Vec3::ZERO,
        angular_velocity: Vec3::ZERO,
    };
    let (lower_y, upper_y) = (0.5 * SIDE, 1.5 * SIDE + 0.01);
    let slide = Vec3::new(0.0, 0.0, 0.06);
    let mut entities = Vec::new();
    for (y, velocity) in [(lower_y, Vec3::ZERO), (upper_y, slide)] {
        entities.push(
            app.world_mut()
                .spawn((
                    SphCollider::new(shape.clone()).with_motion(ColliderMotion::Dynamic),
                    SphRigidBody {
                        linear_velocity: velocity,
                        ..body
                    },
                    Transform::from_xyz(0.2, y, 0.15),
                ))
                .id(),
        );
    }
    // A little water, walled off from the boxes.
    let divider = Collider::new(
        ColliderShape::Cuboid {
            half_extents: Vec3::new(0.01, 0.15, 0.15),
        },
        Pose {
            translation: Vec3::new(0.12, 0.15, 0.15),
            rotation: Quat::IDENTITY,
        },
    );
    app.world_mut().spawn((
        SphCollider::new(divider.shape.clone()),
        Transform::from_translation(divider.pose.translation),
    ));
    app.update();
    app.world_mut().spawn(SphBlockSpawn {
        block: BlockSpawn::new(Vec3::ZERO, Vec3::new(0.1, 0.04, 0.3), params.spacing()),
        velocity: Vec3::ZERO,
    });
    app.insert_resource(SphControl {
        running: true,
        substeps: 1,
        ..default()
    });
    // Each box's records by frame.
    let mut records: [BTreeMap<u32, FrameRecord>; 2] = Default::default();
    for _ in 0..400 {
        app.update();
        let moved = app.world().resource::<SphMovedBodies>();
        if let Some(latest) = &moved.latest {
            for (k, entity) in entities.iter().enumerate() {
                let slot = *moved.slots.get(entity).expect("a moved body");
                for r in latest.bodies[slot as usize]
                    .records
                    .iter()
                    .filter_map(|r| r.record())
                {
                    records[k].insert(r.frame, r);
                }
            }
        }
        if records[0].len() >= 60 && records[1].len() >= 60 {
            break;
        }
    }
    let [lower, upper] = &records;
    assert!(upper.len() >= 60, "{} records", upper.len());
    // Each box's frame against the twin's step from the frame before (one step a frame): its
    // samples' pushes at both boxes' states then (`sample_pushes`), its step under the water's
    // force, the solids and the walls (`resolve_solids`), then the other box after its own
    // first round (`resolve_bodies`).
    let model =
        bevy_sph_fluid::moved_bodies::body_model(&body, Vec3::ZERO, Quat::IDENTITY).unwrap();
    let local = sample_shape(&shape, params.spacing()).position;
    let collider_at = |state: &RigidState| {
        Collider::new(
            shape.clone(),
            Pose {
                translation: state.origin(model.center_of_mass),
                rotation: state.rotation,
            },
        )
    };
    let g = params.gravity.length();
    let (mut twin_pairs, mut pushed, mut rubbed, mut worst) = (0, 0, 0, [0.0f32; 2]);
    for (frame, lower_before) in lower {
        let (Some(lower_after), Some(upper_before), Some(upper_after)) = (
            lower.get(&(frame + 1)),
            upper.get(frame),
            upper.get(&(frame + 1)),
        ) else {
            continue;
        };
        let (before, after) = ([lower_before, upper_before], [lower_after, upper_after]);
        let dt = after[0].duration;
        // Each box's pushes, its step and its first round.
        let first: Vec<_> = (0..2)
            .map(|k| {
                let (b, o) = (before[k].state, before[1 - k].state);
                let pose = collider_at(&b).pose;
                let other_collider = collider_at(&o);
                let (solids, bodies) = sample_pushes(
                    local.iter().map(|&p| pose.to_world(p)),
                    (
                        0.5 * params.spacing(),
                        0.5 * params.spacing() + body_margin(g, dt),
                        friction_step(g, dt),
                    ),
                    mass,
                    std::slice::from_ref(&divider),
                    &[MovedNeighbour {
                        collider: &other_collider,
                        mass,
                        hinged: false,
                    }],
                );
                let force = after[k].impulse / dt;
                let moment = after[k].angular_impulse / dt + b.position.cross(force);
                let stepped = advance(&model, &b, force, moment, dt);
                let (state, supported) =
                    resolve_solids(&solids, &stepped, &shape, model.center_of_mass, &container);
                (bodies, state, supported)
            })
            .collect();
        for k in 0..2 {
            let (bodies, state, _) = &first[k];
            let (_, other, supported) = &first[1 - k];
            let partner = Partner {
                mass,
                velocity: other.linear_velocity,
                supported: *supported,
            };
            let twin = resolve_bodies(
                bodies,
                (state, mass, &[partner]),
                &shape,
                model.center_of_mass,
                &container,
            );
            worst[0] = worst[0].max((twin.position - after[k].state.position).length());
            worst[1] =
                worst[1].max((twin.linear_velocity - after[k].state.linear_velocity).length());
            twin_pairs += 1;
            pushed += (!bodies.is_empty()) as usize;
            let slip = before[k].state.linear_velocity.z - before[1 - k].state.linear_velocity.z;
            rubbed += (bodies.friction_limit > 0.0 && slip.abs() > 1e-3) as usize;
        }
    }
    println!(
        "stacked boxes against the twin: {twin_pairs} frame pairs, {pushed} with a push between \
         the boxes, {rubbed} sliding on each other: largest |Δx| {:.2e} m, |Δv| {:.2e} m/s",
        worst[0], worst[1]
    );
    assert!(
        twin_pairs >= 100 && pushed >= 20 && rubbed >= 1,
        "{twin_pairs} pairs, {pushed} pushed, {rubbed} rubbed"
    );
    assert!(worst[0] < 1e-6, "position {}", worst[0]);
    assert!(worst[1] < 1e-5, "velocity {}", worst[1]);
    let mut deepest = f32::INFINITY;
    let mut margin = 0.0f32;
    for (frame, up) in upper {
        let Some(low) = lower.get(frame) else {
            continue;
        };
        // Both stay upright: the gap between the upper box's bottom and the lower one's top.
        let gap = (up.state.position.y - 0.5 * SIDE) - (low.state.position.y + 0.5 * SIDE);
        deepest = deepest.min(gap);
        if std::env::var("TRACE").is_ok() {
            println!(
                "frame {frame}: lower {:?} upper {:?} v {:?} gap {gap}",
                low.state.position, up.state.position, up.state.linear_velocity
            );
        }
        margin = margin.max(body_margin(9.81, up.duration));
        assert!(
            low.state.position.y > lower_y - 1e-4,
            "frame {frame}: the lower box at {} m, pushed into the floor",
            low.state.position.y
        );
    }
    let (last_low, last_up) = (
        lower.values().last().unwrap().state,
        upper.values().last().unwrap().state,
    );
    println!(
        "stacked boxes: deepest gap {deepest:.5} m (margin g dt² {margin:.5} m); at the end the \
         upper box at {:.4} m moving {:.4} m/s, the lower at {:.4} m",
        last_up.position.y,
        last_up.linear_velocity.length(),
        last_low.position.y
    );
    // The pushes are found at the step's start, so the landing step's fall (0.49 m/s for a
    // step, 4 mm) goes in before the next step pushes it out.
    let landing = (2.0f32 * 9.81 * 0.01).sqrt() * 1.2 * (1.0 / 120.0);
    assert!(
        deepest > -margin - landing,
        "the upper box went {deepest} m into the lower one"
    );
    assert!(
        last_up.position.y > lower_y + SIDE - 1e-3 && last_up.position.y < upper_y,
        "the upper box ended at {} m",
        last_up.position.y
    );
    assert!(
        last_up.linear_velocity.y.abs() < 0.02 && last_low.linear_velocity.y.abs() < 0.02,
        "not at rest on the floor: {} and {} m/s",
        last_up.linear_velocity.y,
        last_low.linear_velocity.y
    );
    // The friction made them one: the same slide, the upper box's momentum shared.
    let (up_z, low_z) = (last_up.linear_velocity.z, last_low.linear_velocity.z);
    println!("sliding together: the upper box at {up_z:.5} m/s, the lower at {low_z:.5}");
    assert!((up_z - low_z).abs() < 1e-3, "{up_z} against {low_z} m/s");
    assert!(
        ((up_z + low_z) - slide.z).abs() < 2e-3,
        "the pair's momentum {} against {}",
        mass * (up_z + low_z),
        mass * slide.z
    );
}

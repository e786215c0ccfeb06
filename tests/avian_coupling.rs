//! Two-way coupling with avian (feature `avian`): a box of 500 kg/m³ settles floating with half
//! its height under water; a box of 1,500 kg/m³ sinks and rests on the floor (avian's contact
//! with a floor collider). The water pushes the bodies through `SphColliderForce` →
//! `ConstantForce`; avian moves them; the water sees their new pose. DFSPH, on the CPU backend
//! and on the GPU (its force summed on the device and read back a frame or two late). A
//! paddle wheel (one closed mesh of six boxes) on an avian revolute joint turns when a jet hits
//! its lower paddles, and not without it (WCSPH, CPU). On the GPU with avian on the water's
//! clock the device moves the bodies with the water at every step (`SphRigidBody`,
//! `bevy_sph_fluid::moved_bodies`): frames cover their full time of water and never wait for a
//! readback. In the shipped scenes, with avian on the
//! water's clock, on both backends: aquaplay.ron's pump carries its boat along the channel and
//! turns its water wheel (a scene file's `PaddleWheel` on a `Hinged` axle) with the current,
//! and lock.ron's boat, towed by the game, passes the lifted gate.

use avian3d::prelude::*;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_sph_fluid::prelude::*;
use sph_core::{BlockSpawn, BoxContainer, ColliderMotion, ColliderShape, PipeEmitter, TriMesh};
use std::time::Duration;

mod common;

const FRAME: f32 = 1.0 / 60.0;

// The GPU tests of this file run one at a time (`common::GPU`): lavapipe's readback comes more
// frames late when another app shares the 2 cores.
const SIDE: f32 = 0.12;
const DEPTH: f32 = 0.2;
/// Water steps per frame on the GPU backend in the tank (DFSPH, dt about 2.7 ms: 10.8 ms of
/// water a frame). Before the device moved the bodies, the force read back a frame or two late
/// held this at 2: with 4 the box of 1,500 kg/m³ overshot into the last layer of water on the
/// floor, the squeezed layer's pressure kicked it out (129 kN) and the water went unstable.
const GPU_SUBSTEPS: u32 = 4;

/// Water steps per frame in the shipped scenes (PBF, dt up to 1/120 s: up to a 60 FPS frame's
/// 1/60 s of water). Before the device moved the bodies a frame was cut to 6 ms of water while a
/// boat floated on the GPU (`SphControl::max_body_frame_time`): with 2 steps its heave grew
/// every bob until it left the channel.
const SCENE_SUBSTEPS: u32 = 2;

/// On the GPU the device moves every dynamic body (`SphMovedBodies`), so a frame takes all the
/// steps it asked for and none waits for the body forces' readback; on both backends no frame
/// is held.
fn assert_full_frames(app: &App, backend: SphBackend, substeps: u32) {
    use bevy_sph_fluid::moved_bodies::SphMovedBodies;
    use bevy_sph_fluid::shared::SphSimulation;
    let plan = app.world().resource::<SphSimulation>().plan;
    assert_eq!(plan.steps, substeps, "{plan:?}");
    assert_eq!(
        app.world()
            .resource::<SphStats>()
            .frames_held_for_body_forces,
        0
    );
    if backend == SphBackend::Gpu {
        assert!(app.world().resource::<SphMovedBodies>().active());
    }
}

/// Whose clock avian runs on.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Clock {
    /// avian in its fixed schedule on the game's time; the water in real-time mode.
    Game,
    /// avian in `SphWaterTime`; the water at `substeps` steps per frame, much slower than
    /// real time.
    Water { substeps: u32 },
}

/// A tank with water `DEPTH` deep and a box of `density` [kg/m³] held with its centre at the
/// surface, rotation locked; returns the app, the box and the level probe.
fn tank_with_box(density: f32) -> (App, Entity, Entity) {
    tank_with_box_on(density, Clock::Game, SphBackend::Cpu)
}

fn tank_with_box_on(density: f32, clock: Clock, backend: SphBackend) -> (App, Entity, Entity) {
    if backend == SphBackend::Gpu {
        bevy_sph_fluid::headless::require_gpu_adapter();
    }
    let plugins = DefaultPlugins.build().disable::<bevy::winit::WinitPlugin>();
    let mut app =
        bevy_sph_fluid::headless::headless_app_with(plugins, 8_000, backend, false, |app| {
            match clock {
                Clock::Game => {
                    app.add_plugins(PhysicsPlugins::default());
                }
                Clock::Water { .. } => {
                    app.add_plugins(PhysicsPlugins::new(SphWaterTime));
                }
            }
        });
    app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f32(
        FRAME,
    )));
    app.insert_resource(Time::<Fixed>::from_seconds(FRAME as f64));
    let mut params = sph_core::SphParams::water();
    params.use_solver(sph_core::Solver::Dfsph);
    app.insert_resource(SphParams(params));
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.36, 0.4, 0.36));
    app.world_mut().spawn(SphContainer(container));
    // avian's floor under the container's floor plate.
    app.world_mut().spawn((
        RigidBody::Static,
        Collider::cuboid(1.0, 0.1, 1.0),
        Transform::from_xyz(0.18, -0.05, 0.18),
    ));
    let body = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::cuboid(SIDE, SIDE, SIDE),
            ColliderDensity(density),
            LockedAxes::ROTATION_LOCKED,
            SphCollider::new(ColliderShape::Cuboid {
                half_extents: Vec3::splat(0.5 * SIDE),
            })
            .with_motion(ColliderMotion::Dynamic),
            Transform::from_xyz(0.18, DEPTH, 0.18),
        ))
        .id();
    // The level probe (the highest particle centre within its radius) reads the open water: its
    // disc (x, z in 0.04..0.10 m) keeps one smoothing length h = 0.04 m from the walls and clear
    // of the box (0.12..0.24 m). At (0.05, 0.05) with a radius of 0.04 m it reached into the
    // corner, where the water rides up the walls, and read 1.5 mm high on the CPU and 2–2.5 mm
    // high on the GPU: submerged 0.522 and 0.54–0.555 for the same box height (0.1936 m). Here:
    // 0.505 and 0.502.
    let probe = app
        .world_mut()
        .spawn((
            SphProbe {
                kind: SphProbeKind::Level { radius: 0.03 },
                every_steps: 1,
            },
            Transform::from_xyz(0.07, 0.0, 0.07),
        ))
        .id();
    app.update();
    app.world_mut().spawn(SphBlockSpawn {
        block: BlockSpawn::new(Vec3::ZERO, Vec3::new(0.36, DEPTH, 0.36), params.spacing()),
        velocity: Vec3::ZERO,
    });
    app.insert_resource(match clock {
        Clock::Game => SphControl {
            running: true,
            real_time: Some(SphRealTime {
                max_frame_time: FRAME,
                max_steps: 64,
            }),
            ..default()
        },
        Clock::Water { substeps } => SphControl {
            running: true,
            substeps,
            ..default()
        },
    });
    (app, body, probe)
}

#[derive(Resource, Default)]
struct Levels(Vec<f32>);

fn collect(mut reader: MessageReader<SphProbeReading>, mut levels: ResMut<Levels>) {
    levels
        .0
        .extend(reader.read().filter_map(|r| r.reading.value));
}

/// How far the box rose above its lowest centre so far once it came within 2 cm of resting on
/// the floor [m] (`settle`; 0 when it never did): a kick off the floor.
#[derive(Resource, Default)]
struct Rise(f32);

/// Runs `seconds` of the water's simulated time; returns the box's mean height and the mean
/// water level over the last half second.
fn settle(app: &mut App, body: Entity, seconds: f32) -> (f32, f32) {
    app.init_resource::<Levels>().add_systems(Last, collect);
    let (mut heights, mut tail) = (Vec::new(), false);
    let (mut lowest, mut rise): (Option<f32>, f32) = (None, 0.0);
    for frame in 0.. {
        app.update();
        let y = app.world().get::<Transform>(body).unwrap().translation.y;
        if lowest.is_some() || y <= 0.5 * SIDE + 0.02 {
            let low = lowest.map_or(y, |l| l.min(y));
            rise = rise.max(y - low);
            lowest = Some(low);
        }
        let stats = app.world().resource::<SphStats>();
        assert!(
            !stats.health.is_unstable(),
            "frame {frame}: {:?}",
            stats.health
        );
        let t = stats.sim_time as f32;
        if t >= seconds {
            break;
        }
        if t >= seconds - 0.5 {
            if !tail {
                // Only the last half second's levels count.
                app.world_mut().resource_mut::<Levels>().0.clear();
                tail = true;
            }
            heights.push(app.world().get::<Transform>(body).unwrap().translation.y);
        }
    }
    app.insert_resource(Rise(rise));
    let levels = &app.world().resource::<Levels>().0;
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len().max(1) as f32;
    (mean(&heights), mean(levels))
}

#[test]
fn a_box_of_half_the_waters_density_floats_half_submerged() {
    let (mut app, body, _) = tank_with_box(500.0);
    let (y, level) = settle(&mut app, body, 2.5);
    let bottom = y - 0.5 * SIDE;
    let submerged = (level - bottom) / SIDE;
    println!("500 kg/m³: box centre {y:.4} m, water level {level:.4} m, submerged {submerged:.3}");
    assert!(
        (submerged - 0.5).abs() <= 0.05,
        "submerged fraction {submerged}"
    );
    let stats = app.world().resource::<SphStats>();
    assert_eq!(stats.particle_balance(), 0);
}

/// avian on the water's clock (`SphWaterTime`) while the water runs far slower than real time
/// (two steps a frame): the box still floats half submerged. With avian on the game's clock in
/// the same run (measured once: 0.0049 simulated s per 1/60 s frame), the body moved 3.4 times
/// further per frame than the water could answer, and the box was thrown 30 km away.
#[test]
fn bodies_on_the_waters_clock_float_at_any_real_time_factor() {
    let (mut app, body, _) = tank_with_box_on(500.0, Clock::Water { substeps: 2 }, SphBackend::Cpu);
    let (y, level) = settle(&mut app, body, 2.5);
    let submerged = (level - (y - 0.5 * SIDE)) / SIDE;
    let stats = app.world().resource::<SphStats>();
    // Two steps per frame: the water's time per frame against the game's 1/60 s.
    let per_frame = 2.0 * stats.sim_time / stats.step_count.max(1) as f64;
    println!(
        "water clock, {per_frame:.4} simulated s per frame (game frame {FRAME:.4} s): box centre \
         {y:.4} m, level {level:.4} m, submerged {submerged:.3}"
    );
    assert!(per_frame < 0.5 * FRAME as f64, "slower than real time");
    assert!(
        (submerged - 0.5).abs() <= 0.05,
        "submerged fraction {submerged}"
    );
}

#[test]
fn a_box_of_one_and_a_half_times_the_waters_density_sinks_to_the_floor() {
    let (mut app, body, _) = tank_with_box(1500.0);
    let (y, _) = settle(&mut app, body, 2.0);
    println!("1500 kg/m³: box centre {y:.4} m");
    // Resting on the floor: its centre half a side up, within a particle spacing.
    assert!((y - 0.5 * SIDE).abs() <= 0.02, "box centre {y}");
}

/// The GPU backend, avian on the water's clock, four DFSPH steps a frame: the box of 500 kg/m³
/// floats half submerged and the box of 1,500 kg/m³ rests on the floor, without a kick. The
/// device moves each box with the water at every step; avian's floor reaches it once a frame.
#[test]
fn boxes_float_and_sink_by_their_density_on_the_gpu() {
    let _alone = common::GPU.lock().unwrap_or_else(|e| e.into_inner());
    let clock = Clock::Water {
        substeps: GPU_SUBSTEPS,
    };
    let (mut app, body, _) = tank_with_box_on(500.0, clock, SphBackend::Gpu);
    let (y, level) = settle(&mut app, body, 2.5);
    let submerged = (level - (y - 0.5 * SIDE)) / SIDE;
    let stats = app.world().resource::<SphStats>();
    println!(
        "GPU, 500 kg/m³: box centre {y:.4} m, water level {level:.4} m, submerged {submerged:.3} \
         ({} steps, {:.1} density and {:.1} divergence iterations per step, {} solves cut short)",
        stats.step_count,
        stats.pressure_iterations_mean,
        stats.divergence_iterations_mean,
        stats.dfsph_solves_cut_short
    );
    assert!(
        (submerged - 0.5).abs() <= 0.05,
        "submerged fraction {submerged}"
    );
    assert_eq!(stats.particle_balance(), 0);
    assert_full_frames(&app, SphBackend::Gpu, GPU_SUBSTEPS);
    let (mut app, body, _) = tank_with_box_on(1500.0, clock, SphBackend::Gpu);
    let (y, _) = settle(&mut app, body, 2.0);
    // No kick: near the floor the box never rose 5 mm above its lowest point.
    let rise = app.world().resource::<Rise>().0;
    println!("GPU, 1500 kg/m³: box centre {y:.4} m, rose {rise:.4} m near the floor");
    assert!((y - 0.5 * SIDE).abs() <= 0.02, "box centre {y}");
    assert!(rise < 0.005, "kicked up by {rise} m");
    assert_full_frames(&app, SphBackend::Gpu, GPU_SUBSTEPS);
}

/// A headless app on `backend` with `physics` added and the scene file `path` (under
/// `assets/`) loaded and spawned, paused.
fn scene_app(path: &str, backend: SphBackend, physics: impl FnOnce(&mut App)) -> App {
    common::shipped_scene_app(path, backend, physics)
}

/// The entity called `name`.
fn named(app: &mut App, name: &str) -> Entity {
    app.world_mut()
        .query::<(Entity, &Name)>()
        .iter(app.world())
        .find(|(_, n)| n.as_str() == name)
        .map(|(e, _)| e)
        .unwrap_or_else(|| panic!("no entity named {name}"))
}

/// lock.ron with avian: the boat becomes a dynamic avian body of the file's density, the
/// container's walls static bodies; the boat floats (neither sinks nor leaves the water) while
/// the gate opens and the basins even out.
#[test]
fn the_lock_scene_boat_is_an_avian_body_and_floats() {
    let mut app = scene_app("scenes/lock.ron", SphBackend::Cpu, |app| {
        app.add_plugins(PhysicsPlugins::default());
    });
    app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f32(
        FRAME,
    )));
    app.insert_resource(Time::<Fixed>::from_seconds(FRAME as f64));
    let boat = named(&mut app, "boat");
    assert_eq!(
        app.world().get::<RigidBody>(boat),
        Some(&RigidBody::Dynamic)
    );
    assert_eq!(
        app.world().get::<ColliderDensity>(boat).map(|d| d.0),
        Some(400.0)
    );
    app.insert_resource(SphControl {
        running: true,
        real_time: Some(SphRealTime {
            max_frame_time: FRAME,
            max_steps: 64,
        }),
        ..default()
    });
    let mut lowest = f32::MAX;
    let mut highest = f32::MIN;
    for frame in 0..(2.0 / FRAME) as usize {
        app.update();
        let stats = app.world().resource::<SphStats>();
        assert!(
            !stats.health.is_unstable(),
            "frame {frame}: {:?}",
            stats.health
        );
        assert_eq!(stats.particle_balance(), 0);
        let y = app.world().get::<Transform>(boat).unwrap().translation.y;
        lowest = lowest.min(y);
        highest = highest.max(y);
    }
    let at = app.world().get::<Transform>(boat).unwrap().translation;
    println!("boat: y in [{lowest:.3}, {highest:.3}] m, at {at}");
    // Afloat: above the floor by more than its half height, below the basin's brim.
    assert!(
        lowest > 0.06 && highest < 0.4,
        "boat y in [{lowest}, {highest}]"
    );
}

/// A paddle wheel about the z axis as one closed mesh: `paddles` boxes around the axle (apart
/// from each other, so the mesh is several closed parts), each reaching from `inner` to `outer`
/// [m] from the axle, `thickness` thick and `width` wide along the axle.
fn paddle_wheel(paddles: u32, inner: f32, outer: f32, thickness: f32, width: f32) -> TriMesh {
    let (mut vertices, mut indices) = (Vec::new(), Vec::new());
    for k in 0..paddles {
        let angle = std::f32::consts::TAU * k as f32 / paddles as f32;
        let rotation = Quat::from_rotation_z(angle);
        let centre = Vec3::new(0.5 * (inner + outer), 0.0, 0.0);
        let half = Vec3::new(0.5 * (outer - inner), 0.5 * thickness, 0.5 * width);
        let base = vertices.len() as u32;
        for z in [-1.0, 1.0] {
            for (x, y) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                vertices.push(rotation * (centre + Vec3::new(x, y, z) * half));
            }
        }
        // The six faces, counter-clockwise seen from outside.
        let quad = |a: u32, b: u32, c: u32, d: u32| [a, b, c, a, c, d].map(|i| base + i);
        for face in [
            quad(0, 3, 2, 1),
            quad(4, 5, 6, 7),
            quad(0, 1, 5, 4),
            quad(1, 2, 6, 5),
            quad(2, 3, 7, 6),
            quad(3, 0, 4, 7),
        ] {
            indices.extend(face);
        }
    }
    TriMesh::closed(&vertices, &indices).expect("each paddle is a closed box")
}

/// A water wheel on an avian revolute joint (axle along z) over a tank, its lower paddles in
/// the path of a pipe's jet when `jet` is on: the wheel's angle after `seconds`.
fn wheel_angle_after(seconds: f32, jet: bool) -> f32 {
    let plugins = DefaultPlugins.build().disable::<bevy::winit::WinitPlugin>();
    let mut app = bevy_sph_fluid::headless::headless_app_with(
        plugins,
        12_000,
        SphBackend::Cpu,
        false,
        |app| {
            app.add_plugins(PhysicsPlugins::default());
        },
    );
    app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f32(
        FRAME,
    )));
    app.insert_resource(Time::<Fixed>::from_seconds(FRAME as f64));
    let params = sph_core::SphParams::water();
    app.insert_resource(SphParams(params));
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.6, 0.4, 0.2));
    app.world_mut().spawn(SphContainer(container));
    let axle = Vec3::new(0.3, 0.15, 0.1);
    let anchor = app
        .world_mut()
        .spawn((RigidBody::Static, Transform::from_translation(axle)))
        .id();
    let (inner, outer, thickness, width) = (0.02, 0.1, 0.02, 0.14);
    let mesh = paddle_wheel(6, inner, outer, thickness, width);
    // avian's body: the same paddles as boxes, of oak, with some friction in the axle.
    let boxes = (0..6)
        .map(|k| {
            let rotation = Quat::from_rotation_z(std::f32::consts::TAU * k as f32 / 6.0);
            (
                rotation * Vec3::new(0.5 * (inner + outer), 0.0, 0.0),
                rotation,
                Collider::cuboid(outer - inner, thickness, width),
            )
        })
        .collect::<Vec<_>>();
    let wheel = app
        .world_mut()
        .spawn((
            RigidBody::Dynamic,
            Collider::compound(boxes),
            ColliderDensity(900.0),
            AngularDamping(3.0),
            SphCollider::new(ColliderShape::TriMesh(mesh.into()))
                .with_motion(ColliderMotion::Dynamic),
            Transform::from_translation(axle),
        ))
        .id();
    app.world_mut()
        .spawn(RevoluteJoint::new(anchor, wheel).with_hinge_axis(Vec3::Z));
    app.update();
    // Still water under the axle; the jet's pipe at the height of the lower paddles.
    app.world_mut().spawn(SphBlockSpawn {
        block: BlockSpawn::new(Vec3::ZERO, Vec3::new(0.6, 0.04, 0.2), params.spacing()),
        velocity: Vec3::ZERO,
    });
    if jet {
        app.world_mut().spawn(SphEmitter(PipeEmitter::new(
            Vec3::new(0.04, 0.09, 0.1),
            Vec3::X,
            0.03,
            1.5,
            params.spacing(),
        )));
    }
    app.insert_resource(SphControl {
        running: true,
        real_time: Some(SphRealTime {
            max_frame_time: FRAME,
            max_steps: 64,
        }),
        ..default()
    });
    let mut angle = 0.0;
    for frame in 0..(seconds / FRAME) as usize {
        app.update();
        let stats = app.world().resource::<SphStats>();
        assert!(
            !stats.health.is_unstable(),
            "frame {frame}: {:?}",
            stats.health
        );
        assert_eq!(stats.particle_balance(), 0, "frame {frame}");
        angle += app.world().get::<AngularVelocity>(wheel).unwrap().0.z * FRAME;
    }
    let at = app.world().get::<Transform>(wheel).unwrap().translation;
    assert!(at.distance(axle) < 0.01, "the joint holds the wheel: {at}");
    angle
}

/// The wheel turns when the jet hits its lower paddles (towards +x under the axle: +z), and
/// stays nearly still without the jet.
#[test]
fn a_water_wheel_on_a_revolute_joint_turns_with_the_flow() {
    let turned = wheel_angle_after(1.5, true);
    let still = wheel_angle_after(1.5, false);
    println!("wheel angle after 1.5 s: {turned:.3} rad with the jet, {still:.3} rad without");
    assert!(turned > 0.5, "the jet turns the wheel: {turned} rad");
    assert!(still.abs() < 0.2 * turned, "without the jet: {still} rad");
}

/// aquaplay.ron with avian on the water's clock: the pump's current carries the boat along
/// the front channel (+x), afloat, at the water's own pace (one or two steps a frame, far
/// slower than real time), and the water wheel (a `PaddleWheel` on a `Hinged` axle) turns with
/// the current in the back channel: its lower paddles move the way the water under them flows.
#[test]
fn the_pump_carries_aquaplays_boat_and_turns_its_wheel() {
    pump_carries_boat_and_turns_wheel(SphBackend::Cpu);
}

/// The same on the GPU backend: the device moves the boat and the wheel with the water.
#[test]
fn the_pump_carries_aquaplays_boat_and_turns_its_wheel_on_the_gpu() {
    let _alone = common::GPU.lock().unwrap_or_else(|e| e.into_inner());
    pump_carries_boat_and_turns_wheel(SphBackend::Gpu);
}

fn pump_carries_boat_and_turns_wheel(backend: SphBackend) {
    let mut app = scene_app("scenes/aquaplay.ron", backend, |app| {
        app.add_plugins(PhysicsPlugins::new(SphWaterTime));
    });
    let boat = named(&mut app, "boat");
    let wheel = named(&mut app, "water_wheel");
    let axle = app.world().get::<Transform>(wheel).unwrap().translation;
    let start = app.world().get::<Transform>(boat).unwrap().translation;
    app.insert_resource(SphControl {
        running: true,
        substeps: SCENE_SUBSTEPS,
        ..default()
    });
    let (mut lowest, mut highest) = (f32::MAX, f32::MIN);
    let mut angle = 0.0;
    let mut last = app.world().resource::<SphStats>().sim_time;
    while app.world().resource::<SphStats>().sim_time < 2.0 {
        app.update();
        let stats = app.world().resource::<SphStats>();
        assert!(!stats.health.is_unstable(), "{:?}", stats.health);
        assert_eq!(stats.particle_balance(), 0);
        let now = stats.sim_time;
        assert_full_frames(&app, backend, SCENE_SUBSTEPS);
        let y = app.world().get::<Transform>(boat).unwrap().translation.y;
        lowest = lowest.min(y);
        highest = highest.max(y);
        // avian ran for the time the water gained.
        angle += app.world().get::<AngularVelocity>(wheel).unwrap().0.z * (now - last) as f32;
        last = now;
    }
    // The water under the wheel: the back channel below its axle.
    let s = bevy_sph_fluid::headless::snapshot(&mut app).unwrap();
    let under: Vec<f32> = s
        .positions
        .iter()
        .zip(&s.velocities)
        .filter(|(x, _)| (x.x - axle.x).abs() < 0.1 && (x.z - axle.z).abs() < 0.06 && x.y < axle.y)
        .map(|(_, v)| v.x)
        .collect();
    let current = under.iter().sum::<f32>() / under.len().max(1) as f32;
    let at = app.world().get::<Transform>(wheel).unwrap().translation;
    println!(
        "{backend:?}: aquaplay wheel: {angle:.2} rad in 2 s, the current under it {current:.3} m/s ({} particles), axle moved {:.4} m",
        under.len(),
        at.distance(axle)
    );
    // A lower paddle moves at ω r along x (ω about +z): with the current when ω and it agree.
    assert!(
        current.abs() > 0.02,
        "a current under the wheel: {current} m/s"
    );
    assert!(
        angle * current.signum() > 0.3,
        "the wheel turns with the current: {angle} rad, current {current} m/s"
    );
    assert!(at.distance(axle) < 0.01, "the hinge holds the wheel: {at}");
    let end = app.world().get::<Transform>(boat).unwrap().translation;
    println!(
        "{backend:?}: aquaplay boat: {start} -> {end}, y in [{lowest:.3}, {highest:.3}] m; {} frames held for the body forces",
        app.world().resource::<SphStats>().frames_held_for_body_forces
    );
    assert!(
        end.x - start.x > 0.2,
        "carried along the channel: {start} -> {end}"
    );
    // Afloat: above the floor by more than its half height, not thrown out of the channel.
    assert!(
        lowest > 0.03 && highest < 0.2,
        "boat y in [{lowest}, {highest}]"
    );
}

/// lock.ron with avian on the water's clock: once the gate is up (t = 1.1 s), a game tows the
/// boat toward the lower basin at 0.3 m/s (it sets the boat's velocity along x every frame and
/// leaves the rest to the water and avian); the boat passes under the lifted gate into the lower
/// basin, afloat (measured: x = 0.63 m at t = 1.88 s). Without the tow the outflow alone had
/// carried it to x = 0.41 m by t = 3.5 s, short of the gate.
#[test]
fn the_lock_scene_boat_passes_the_open_gate_when_pushed() {
    boat_passes_the_open_gate(SphBackend::Cpu);
}

/// The same on the GPU backend.
#[test]
fn the_lock_scene_boat_passes_the_open_gate_when_pushed_on_the_gpu() {
    let _alone = common::GPU.lock().unwrap_or_else(|e| e.into_inner());
    boat_passes_the_open_gate(SphBackend::Gpu);
}

fn boat_passes_the_open_gate(backend: SphBackend) {
    let mut app = scene_app("scenes/lock.ron", backend, |app| {
        app.add_plugins(PhysicsPlugins::new(SphWaterTime));
    });
    let boat = named(&mut app, "boat");
    app.insert_resource(SphControl {
        running: true,
        substeps: SCENE_SUBSTEPS,
        ..default()
    });
    // The gate's far face (x = 0.52 m) plus the boat's half length (0.06 m).
    let beyond_gate = 0.58;
    let (mut lowest, mut highest) = (f32::MAX, f32::MIN);
    while app.world().resource::<SphStats>().sim_time < 3.5 {
        let t = app.world().resource::<SphStats>().sim_time;
        if t >= 1.1 {
            let mut v = app.world_mut().get_mut::<LinearVelocity>(boat).unwrap();
            v.0.x = 0.3;
        }
        app.update();
        let stats = app.world().resource::<SphStats>();
        assert!(!stats.health.is_unstable(), "{:?}", stats.health);
        assert_eq!(stats.particle_balance(), 0);
        assert_full_frames(&app, backend, SCENE_SUBSTEPS);
        let at = app.world().get::<Transform>(boat).unwrap().translation;
        lowest = lowest.min(at.y);
        highest = highest.max(at.y);
        if at.x > beyond_gate + 0.05 {
            break;
        }
    }
    let end = app.world().get::<Transform>(boat).unwrap().translation;
    let t = app.world().resource::<SphStats>().sim_time;
    println!("{backend:?}: lock boat at t = {t:.2} s: {end}, y in [{lowest:.3}, {highest:.3}] m");
    assert!(end.x > beyond_gate, "through the gate: {end}");
    // Afloat: above the floor by more than its half height, below the basin's brim.
    assert!(
        lowest > 0.03 && highest < 0.4,
        "boat y in [{lowest}, {highest}]"
    );
}

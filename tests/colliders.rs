//! `SphCollider` entities on both backends: one step from the same state agrees with the CPU
//! solver holding the same colliders (a rotated box, a sphere and a no-slip kinematic capsule in
//! a jittered block; with PBF also a rough box), a collider moved, added and removed at run time
//! changes the boundary without touching the particle buffers or losing a particle, no particle
//! ends inside a collider, both backends write the water's force into `SphColliderForce` and the
//! walls' into `SphWallForce` (the GPU's summed on the device and matching the CPU solver's, with
//! WCSPH and PBF), the walls carry the weight of water at rest, and a bad collider is refused by
//! entity and field while the simulation goes on.

mod common;

use bevy::prelude::*;
use bevy_sph_fluid::prelude::*;
use common::*;
use sph_core::boundary::collider::{Collider, ColliderMotion, ColliderShape, Pose, Slip};
use sph_core::{BlockSpawn, BoxContainer, CpuSolver, Solver};

/// The scene with `solver` at its own time-step rule.
fn scene_for(solver: Solver) -> (sph_core::SphParams, BoxContainer, BlockSpawn) {
    let mut params = sph_core::SphParams::water();
    if solver != Solver::Wcsph {
        params.use_solver(solver);
    }
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.5, 0.4, 0.3));
    let block = BlockSpawn {
        jitter: 0.1,
        seed: 7,
        ..BlockSpawn::new(Vec3::ZERO, Vec3::new(0.3, 0.24, 0.3), params.spacing())
    };
    (params, container, block)
}

/// The colliders as components (with their transforms) and as the CPU solver's colliders.
fn colliders() -> Vec<(SphCollider, Transform)> {
    colliders_with_sphere(ColliderMotion::Dynamic)
}

/// [`colliders`] with the sphere's motion `sphere`.
fn colliders_with_sphere(sphere: ColliderMotion) -> Vec<(SphCollider, Transform)> {
    vec![
        (
            SphCollider::new(ColliderShape::Cuboid {
                half_extents: Vec3::new(0.04, 0.03, 0.05),
            }),
            Transform::from_xyz(0.1, 0.08, 0.12).with_rotation(Quat::from_rotation_y(0.6)),
        ),
        // Dynamic (in `colliders`) and without a mass: then no sample mirrors DFSPH's stiffness
        // or holds the rise (sph_core::Boundary::mirrors), and every sample carries the GPU's
        // unmirrored bit (sph_core::gpu_layout::UNMIRRORED_BODY_BIT) through every pass's
        // reactions.
        (
            SphCollider::new(ColliderShape::Sphere { radius: 0.05 }).with_motion(sphere),
            Transform::from_xyz(0.22, 0.12, 0.2),
        ),
        (
            SphCollider::new(ColliderShape::Capsule {
                radius: 0.03,
                half_length: 0.05,
            })
            .with_motion(ColliderMotion::Kinematic)
            .with_slip(Slip::NoSlip { friction: 1.0 }),
            Transform::from_xyz(0.38, 0.1, 0.1).with_rotation(Quat::from_rotation_x(1.2)),
        ),
    ]
}

fn as_solver_collider(c: &SphCollider, t: &Transform) -> Collider {
    Collider {
        motion: c.motion,
        slip: c.slip,
        ..Collider::new(
            c.shape.clone(),
            Pose {
                translation: t.translation,
                rotation: t.rotation,
            },
        )
    }
}

fn app_with_colliders(backend: SphBackend) -> (App, Vec<Entity>, usize) {
    app_with_colliders_for(backend, Solver::Wcsph)
}

/// The block's velocity at spawn: PBF pushes only where the water is compressed, and WCSPH's
/// contact only while a particle approaches a sample, so their blocks fall onto the colliders
/// and the floor.
fn spawn_velocity(solver: Solver) -> Vec3 {
    match solver {
        Solver::Pbf | Solver::Wcsph => Vec3::new(0.0, -0.5, 0.0),
        Solver::Dfsph => Vec3::ZERO,
    }
}

fn app_with_colliders_for(backend: SphBackend, solver: Solver) -> (App, Vec<Entity>, usize) {
    app_with_colliders_moving(backend, solver, spawn_velocity(solver), colliders())
}

/// The scene's app with `colliders` and the block spawned at `velocity`.
fn app_with_colliders_moving(
    backend: SphBackend,
    solver: Solver,
    velocity: Vec3,
    colliders: Vec<(SphCollider, Transform)>,
) -> (App, Vec<Entity>, usize) {
    let (params, container, block) = scene_for(solver);
    let mut app = headless_app(block.count() as u32, backend);
    app.insert_resource(SphParams(params));
    // No frame-time limit for the dynamic sphere's sake: the steps are the CPU's.
    app.insert_resource(SphControl {
        running: false,
        max_body_frame_time: None,
        ..default()
    });
    app.world_mut()
        .spawn((SphContainer(container), SphWallForce::default()));
    let entities = colliders
        .into_iter()
        .map(|(c, t)| app.world_mut().spawn((c, t)).id())
        .collect();
    app.update();
    // The block is spawned after the colliders exist, so the solver skips what they cover.
    app.world_mut().spawn(SphBlockSpawn { block, velocity });
    app.update();
    let n = app.world().resource::<SphStats>().particle_count as usize;
    (app, entities, n)
}

#[test]
fn one_gpu_step_with_colliders_matches_the_cpu_solver() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    one_step_with_colliders_matches(Solver::Wcsph, spawn_velocity(Solver::Wcsph));
}

/// The block thrown down at 20 m/s: the floor's row and the particles over the colliders would
/// come closer than a tenth of a spacing to them within the step, and WCSPH's forces stop them
/// with the solids' speculative contact (`sph_core::boundary::speculative_contact`, on the GPU
/// `shaders/speculative_contact.wgsl`), whose reactions join the colliders' forces. Without the
/// contact in forces.wgsl (checked), the accelerations differ by 0.6 of the largest.
#[test]
fn one_gpu_step_with_the_speculative_contact_matches_the_cpu_solver() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    one_step_with_colliders_matches(Solver::Wcsph, Vec3::new(0.0, -20.0, 0.0));
}

/// PBF's boundary: the samples in λ and the corrections, and the reactions summed on the
/// device over the step's iterations, with the block falling onto the colliders.
#[test]
fn one_pbf_gpu_step_with_colliders_matches_the_cpu_solver() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    one_step_with_colliders_matches(Solver::Pbf, spawn_velocity(Solver::Pbf));
}

/// PBF's no-slip colliders (XSPH's wall term, `sph_core::solver::pbf::xsph_vorticity::
/// wall_friction`, in `pbf_xsph.wgsl`): with the box 50 times as rough as the water's XSPH (the
/// block falls past its sides), the GPU's two steps give the CPU solver's positions and forces,
/// the friction's reactions summed on the device with the others. On the CPU that roughness
/// moves the box's force by far more than the comparison's tolerance, so the friction is what
/// is compared.
#[test]
fn one_pbf_gpu_step_with_a_rough_box_matches_the_cpu_solver() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let velocity = spawn_velocity(Solver::Pbf);
    let with_box_friction = |friction: f32| {
        let mut colliders = colliders();
        colliders[0].0.slip = Slip::NoSlip { friction };
        colliders
    };
    // The box's force after two CPU steps.
    let box_force = |friction: f32| {
        let (params, container, block) = scene_for(Solver::Pbf);
        let mut cpu = CpuSolver::new(params, container, block.count()).unwrap();
        let ids: Vec<_> = with_box_friction(friction)
            .iter()
            .map(|(c, t)| cpu.add_collider(as_solver_collider(c, t)).unwrap())
            .collect();
        cpu.spawn(&block.positions(), velocity);
        cpu.step();
        cpu.take_collider_forces();
        cpu.step();
        cpu.collider_force(ids[0]).unwrap().force
    };
    let (smooth, rough) = (box_force(0.0), box_force(50.0));
    eprintln!("the box's force: smooth {smooth}, rough {rough}");
    assert!(
        (rough - smooth).length() > 0.05 * smooth.length().max(rough.length()),
        "the friction moves the box's force: {smooth} against {rough}"
    );
    one_step_with_these_colliders_matches(Solver::Pbf, velocity, with_box_friction(50.0));
}

/// DFSPH's boundary: the samples in the factors, the solves and the reactions summed on the
/// device by `dfsph_reactions`, over two steps (the second one's force compared).
#[test]
fn one_dfsph_gpu_step_with_colliders_matches_the_cpu_solver() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    one_step_with_colliders_matches(Solver::Dfsph, spawn_velocity(Solver::Dfsph));
}

/// DFSPH with every collider static or kinematic: every body's samples mirror κ_i and hold the
/// hydrostatic rise (`sph_core::Boundary::mirrors`), and their reactions are doubled.
#[test]
fn one_dfsph_gpu_step_with_mirroring_colliders_matches_the_cpu_solver() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    one_step_with_these_colliders_matches(
        Solver::Dfsph,
        spawn_velocity(Solver::Dfsph),
        colliders_with_sphere(ColliderMotion::Static),
    );
}

/// DFSPH with the block thrown down at 20 m/s: after the constant-density solve the speculative
/// contact bounds the velocity the move takes (on the GPU in `dfsph_reactions`), so the floor's
/// row and the water over the colliders stop a tenth of a spacing short of them, and its
/// reactions join the colliders' forces. Without it on the GPU (checked), the positions were
/// 3.3 mm and the densities 7 % apart.
#[test]
fn one_dfsph_gpu_step_with_the_speculative_contact_matches_the_cpu_solver() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    one_step_with_colliders_matches(Solver::Dfsph, Vec3::new(0.0, -20.0, 0.0));
}

fn one_step_with_colliders_matches(solver: Solver, velocity: Vec3) {
    one_step_with_these_colliders_matches(solver, velocity, colliders());
}

fn one_step_with_these_colliders_matches(
    solver: Solver,
    velocity: Vec3,
    colliders: Vec<(SphCollider, Transform)>,
) {
    let (params, container, block) = scene_for(solver);
    let mut cpu = CpuSolver::new(params, container, block.count()).unwrap();
    for (c, t) in &colliders {
        cpu.add_collider(as_solver_collider(c, t)).unwrap();
    }
    let mirrors = cpu.boundary().mirrors();
    let report = cpu.spawn(&block.positions(), velocity);
    assert!(report.inside_colliders > 0);
    // Some particles start closer than Δx to the floor's samples (Δx/2 under it) and move towards
    // them, where WCSPH's forces add the samples' contact (sph_core::stage::BoundaryContact).
    // Without it in forces.wgsl, the accelerations differ by 0.14 of the largest.
    let floor_contact = 0.5 * params.spacing();
    assert!(block.positions().iter().any(|x| x.y < floor_contact));
    // Two PBF or DFSPH steps, the second one's force compared (the GPU reports the last
    // frame's).
    let steps = if solver == Solver::Wcsph { 1 } else { 2 };
    for _ in 1..steps {
        cpu.step();
    }
    cpu.take_collider_forces();
    cpu.step();

    let dynamic = colliders
        .iter()
        .any(|(c, _)| c.motion == ColliderMotion::Dynamic);
    assert_eq!(
        mirrors, !dynamic,
        "a dynamic collider without a mass turns the mirror off"
    );
    let (mut app, entities, n) =
        app_with_colliders_moving(SphBackend::Gpu, solver, velocity, colliders);
    assert_eq!(n, report.spawned, "both backends skip the same particles");
    assert!(app.world().resource::<SphStats>().boundary_samples > 0);
    step_to(&mut app, steps);
    let s = snapshot(&mut app);
    let p = cpu.particles();
    let mut cpu_order: Vec<usize> = (0..n).collect();
    cpu_order.sort_by_key(|&k| p.id[k]);
    let gpu_order = by_id(&s);
    let a_max = p
        .acceleration
        .iter()
        .map(|a| a.length())
        .fold(0.0, f32::max);
    let mut worst = (0.0f32, 0.0f32, 0.0f32);
    for (&g, &c) in gpu_order.iter().zip(&cpu_order) {
        let rho = (s.densities[g] - p.density[c]).abs() / p.density[c];
        let a = (s.accelerations[g] - p.acceleration[c]).length() / a_max;
        let x = (s.positions[g] - p.position[c]).length();
        worst = (worst.0.max(rho), worst.1.max(a), worst.2.max(x));
    }
    eprintln!(
        "{solver:?}: worst density {:.2e}, acceleration {:.2e}, position {:.2e} m",
        worst.0, worst.1, worst.2
    );
    match solver {
        Solver::Pbf => assert!(worst.0 < 1e-4 && worst.2 < 1e-5, "{worst:?}"),
        _ => assert!(worst.0 < 1e-4 && worst.1 < 1e-3, "{worst:?}"),
    }
    // The water's force on each collider, summed on the device and read back (the snapshot's
    // frames gave the readback time to arrive).
    let cpu_forces: Vec<sph_core::BodyForce> = cpu
        .colliders()
        .map(|(id, _)| cpu.collider_force(id).unwrap())
        .collect();
    let scale = cpu_forces
        .iter()
        .map(|f| f.force.length())
        .fold(0.0, f32::max);
    assert!(
        scale > 0.1,
        "the water pushes the colliders: {cpu_forces:?}"
    );
    for (entity, expected) in entities.iter().zip(&cpu_forces) {
        let got = *app.world().get::<SphColliderForce>(*entity).unwrap();
        eprintln!("{solver:?}: collider force GPU {got:?}, CPU {expected:?}");
        assert!(
            (got.force - expected.force).length() < 2e-3 * scale,
            "force {} against {}",
            got.force,
            expected.force
        );
        assert!(
            (got.torque - expected.torque).length() < 2e-3 * scale * 0.5,
            "torque {} against {}",
            got.torque,
            expected.torque
        );
    }
    let walls = cpu.wall_force();
    let got = *app
        .world_mut()
        .query::<&SphWallForce>()
        .single(app.world())
        .unwrap();
    eprintln!("{solver:?}: walls' force GPU {got:?}, CPU {walls:?}");
    let scale = scale.max(walls.force.length());
    assert!(
        (got.force - walls.force).length() < 2e-3 * scale,
        "walls' force {} against {}",
        got.force,
        walls.force
    );
}

/// A small tank at rest (DFSPH) whose container carries `SphWallForce`: its mean over `frames`
/// frames after as many to settle, and the water's weight.
fn tank_at_rest(backend: SphBackend, frames: u32) -> (Vec3, Vec3) {
    let mut params = sph_core::SphParams::water();
    params.use_solver(Solver::Dfsph);
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.2, 0.2, 0.12));
    let block = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.2, 0.08, 0.12), params.spacing());
    let weight = block.count() as f32 * params.particle_mass * params.gravity;
    let mut app = headless_app(block.count() as u32, backend);
    app.insert_resource(SphParams(params));
    app.insert_resource(SphControl {
        running: true,
        substeps: 4,
        ..default()
    });
    app.world_mut()
        .spawn((SphContainer(container), SphWallForce::default()));
    app.world_mut().spawn(SphBlockSpawn {
        block,
        velocity: Vec3::ZERO,
    });
    for _ in 0..frames {
        app.update();
    }
    let mut sum = Vec3::ZERO;
    for _ in 0..frames {
        app.update();
        let walls = app
            .world_mut()
            .query::<&SphWallForce>()
            .single(app.world())
            .unwrap()
            .force;
        sum += walls;
    }
    let stats = app.world().resource::<SphStats>();
    assert_eq!(stats.backend, backend, "{:?}", stats.fallback_reason);
    (sum / frames as f32, weight)
}

/// With no collider in the water the GPU sums the walls' reactions for `SphWallForce` alone, and
/// on both backends the walls carry the water's weight within 2 % (the trade study's target).
#[test]
fn the_walls_carry_the_weight_of_water_at_rest_on_both_backends() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    for backend in [SphBackend::Cpu, SphBackend::Gpu] {
        let (walls, weight) = tank_at_rest(backend, 30);
        eprintln!("{backend:?}: the walls feel {walls} N; the water weighs {weight} N");
        assert!(
            (walls - weight).length() < 0.02 * weight.length(),
            "{backend:?}: the walls feel {walls} N; the water weighs {weight} N"
        );
    }
}

fn run_and_edit(backend: SphBackend) {
    let (mut app, entities, n) = app_with_colliders(backend);
    app.insert_resource(SphControl {
        running: true,
        substeps: 5,
        ..default()
    });
    let position_buffer = app
        .world()
        .get_resource::<SphGpuBuffers>()
        .map(|b| b.position.id());
    for frame in 0..40 {
        // The capsule rises at 0.2 m/s of simulated time (kinematic: the water sees it move).
        let dt = app.world().resource::<SphParams>().time_step * 5.0;
        let mut t = app.world_mut().get_mut::<Transform>(entities[2]).unwrap();
        t.translation.y += 0.2 * dt;
        if frame == 20 {
            app.world_mut()
                .entity_mut(entities[1])
                .remove::<SphCollider>();
            app.world_mut().spawn((
                SphCollider::new(ColliderShape::Cylinder {
                    radius: 0.03,
                    half_length: 0.05,
                }),
                Transform::from_xyz(0.45, 0.3, 0.15),
            ));
        }
        app.update();
    }
    let stats = app.world().resource::<SphStats>().clone();
    assert!(
        stats.collider_errors.is_empty(),
        "{:?}",
        stats.collider_errors
    );
    assert_eq!(stats.particle_count as usize, n);
    let s = snapshot(&mut app);
    assert_eq!(s.positions.len(), n, "{backend:?}: particles lost");
    let mut ids = s.ids.clone();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), n, "{backend:?}: duplicated ids");
    assert!(s.positions.iter().all(|x| x.is_finite()));
    // The moved capsule, and the box, hold the water out (the sphere was removed).
    let capsule = app.world().get::<Transform>(entities[2]).unwrap();
    let moved = as_solver_collider(&colliders()[2].0, capsule);
    // Deeper than the guard's tolerance (a particle resting on an edge rounds a few ulps in).
    let depth = -sph_core::boundary::guard::tolerance(sph_core::SphParams::water().spacing());
    let inside = s
        .positions
        .iter()
        .filter(|&&x| {
            moved.signed_distance(x) < depth
                || as_solver_collider(&colliders()[0].0, &colliders()[0].1).signed_distance(x)
                    < depth
        })
        .count();
    assert_eq!(inside, 0, "{backend:?}: particles inside a collider");
    if let Some(id) = position_buffer {
        let now = app.world().resource::<SphGpuBuffers>().position.id();
        assert_eq!(now, id, "the particle buffer was reallocated");
    }
    let f = app.world().get::<SphColliderForce>(entities[0]).unwrap();
    assert!(
        f.force.length() > 0.0,
        "{backend:?}: no force on the submerged box"
    );
}

#[test]
fn colliders_move_come_and_go_at_run_time_on_both_backends() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    run_and_edit(SphBackend::Cpu);
    run_and_edit(SphBackend::Gpu);
}

#[test]
fn a_bad_collider_is_refused_by_entity_and_field_and_the_rest_runs() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    for backend in [SphBackend::Cpu, SphBackend::Gpu] {
        let (mut app, _, n) = app_with_colliders(backend);
        let bad = app
            .world_mut()
            .spawn((
                SphCollider::new(ColliderShape::Sphere { radius: -0.1 }),
                Transform::from_xyz(0.2, 0.2, 0.2),
            ))
            .id();
        let squashed = app
            .world_mut()
            .spawn((
                SphCollider::new(ColliderShape::Sphere { radius: 0.05 }),
                Transform::from_xyz(0.2, 0.2, 0.2).with_scale(Vec3::new(1.0, 2.0, 1.0)),
            ))
            .id();
        app.insert_resource(SphControl {
            running: true,
            ..default()
        });
        // The transforms (and their scale) propagate at the end of the first frame.
        app.update();
        app.update();
        let stats = app.world().resource::<SphStats>().clone();
        let fields: Vec<(Entity, &str)> = stats
            .collider_errors
            .iter()
            .map(|e| (e.entity, e.field.as_str()))
            .collect();
        assert!(fields.contains(&(bad, "shape.radius")), "{fields:?}");
        assert!(
            fields.contains(&(squashed, "transform.scale")),
            "{fields:?}"
        );
        assert!(stats
            .error
            .as_deref()
            .is_some_and(|e| e.contains("shape.radius")));
        step_to(&mut app, 3);
        assert_eq!(snapshot(&mut app).positions.len(), n);
    }
}

/// Moves the marked collider to a new height every frame, in `Update` before the plugin's systems
/// (as a physics engine's fixed schedule does before `Update`).
#[derive(Component)]
struct MovedEarly;

fn move_early(mut moved: Query<&mut Transform, With<MovedEarly>>, mut frame: Local<u32>) {
    *frame += 1;
    for mut t in &mut moved {
        t.translation.y = 0.1 + 0.01 * *frame as f32;
    }
}

/// The water sees a root entity's collider where its `Transform` puts it in the same frame, not
/// where `GlobalTransform` said a frame earlier (it follows only in `PostUpdate`); and a dynamic
/// collider's `SphColliderMass` reaches the boundary, refused by field when not positive.
#[test]
fn colliders_are_where_this_frames_transform_puts_them_and_carry_their_mass() {
    let (params, container, _) = scene_for(Solver::Dfsph);
    let mut app = headless_app(1_000, SphBackend::Cpu);
    app.insert_resource(SphParams(params));
    app.world_mut().spawn(SphContainer(container));
    app.add_systems(Update, move_early.before(SphSystems::Prepare));
    let body = app
        .world_mut()
        .spawn((
            SphCollider::new(ColliderShape::Sphere { radius: 0.03 })
                .with_motion(ColliderMotion::Dynamic),
            SphColliderMass(2.0),
            Transform::from_xyz(0.2, 0.1, 0.2),
            MovedEarly,
        ))
        .id();
    let boundary_state = |app: &App| {
        let sim = app
            .world()
            .resource::<bevy_sph_fluid::shared::SphSimulation>();
        let boundary = sim.cpu.as_ref().expect("the CPU solver").boundary();
        let (id, c) = boundary.colliders().next().expect("the collider");
        (c.pose.translation.y, boundary.free_mass(id.0 as usize + 1))
    };
    for frame in 1..=3 {
        app.update();
        let (y, mass) = boundary_state(&app);
        let expected = app.world().get::<Transform>(body).unwrap().translation.y;
        assert!(
            (y - expected).abs() < 1e-6,
            "frame {frame}: {y} against {expected}"
        );
        assert_eq!(mass, Some(2.0));
    }
    app.world_mut()
        .entity_mut(body)
        .insert(SphColliderMass(-1.0));
    app.update();
    let stats = app.world().resource::<SphStats>();
    assert_eq!(
        stats.collider_errors.len(),
        1,
        "{:?}",
        stats.collider_errors
    );
    let e = &stats.collider_errors[0];
    assert_eq!((e.entity, e.field.as_str()), (body, "mass"));
    assert_eq!(e.value, "-1");
    // The previous mass stays.
    assert_eq!(boundary_state(&app).1, Some(2.0));
}

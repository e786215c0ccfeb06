//! Triangle-mesh colliders from Bevy meshes: a primitive's mesh becomes a closed collider with
//! the primitive's signed distance (a plane an open shell, a line list refused by field), and
//! water thrown at 60 m/s onto a closed torus and an open tilted sheet is stopped short of them
//! within a step by the solids' speculative contact, the GPU (which walks the mesh's hierarchy
//! on the device) agreeing with the CPU backend particle by particle, with nothing lost.

mod common;

use bevy::mesh::PrimitiveTopology;
use bevy::prelude::*;
use bevy_sph_fluid::mesh_collider::trimesh_from_mesh;
use bevy_sph_fluid::prelude::*;
use common::*;
use sph_core::boundary::collider::{Collider, ColliderShape, Pose};
use sph_core::{BlockSpawn, BoxContainer};

#[test]
fn bevy_meshes_become_closed_or_open_colliders() {
    let dx = sph_core::SphParams::water().spacing();
    let cuboid = trimesh_from_mesh(&Mesh::from(Cuboid::new(0.2, 0.1, 0.3)), dx).unwrap();
    assert_eq!(cuboid.thickness(), None, "a cuboid's 24 vertices weld shut");
    let exact = ColliderShape::Cuboid {
        half_extents: Vec3::new(0.1, 0.05, 0.15),
    };
    for p in [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.3, 0.1, -0.2),
        Vec3::new(0.05, 0.04, 0.1),
    ] {
        assert!((cuboid.signed_distance(p) - exact.signed_distance(p)).abs() < 1e-5);
    }
    let torus = trimesh_from_mesh(&Mesh::from(Torus::new(0.03, 0.07)), dx).unwrap();
    assert_eq!(torus.thickness(), None, "a torus's seams weld shut");
    // Inside the tube, outside in the hole.
    assert!(torus.signed_distance(Vec3::new(0.05, 0.0, 0.0)) < -0.015);
    assert!(torus.signed_distance(Vec3::ZERO) > 0.025);
    let plane =
        trimesh_from_mesh(&Mesh::from(Plane3d::new(Vec3::Y, Vec2::splat(0.1))), dx).unwrap();
    assert_eq!(plane.thickness(), Some(dx), "a plane is an open shell");
    let lines = Mesh::new(PrimitiveTopology::LineList, default()).with_inserted_attribute(
        Mesh::ATTRIBUTE_POSITION,
        vec![[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0]],
    );
    let e = trimesh_from_mesh(&lines, dx).unwrap_err();
    assert_eq!(e.field, "mesh.primitive_topology");
    let e = SphCollider::from_mesh(&Mesh::from(Cuboid::new(0.2, 0.1, 0.3)), -1.0);
    assert!(e.is_ok(), "the thickness is only for open meshes");
    let e = SphCollider::from_mesh(&Mesh::from(Plane3d::default()), -1.0).unwrap_err();
    assert_eq!(e.field, "shape.thickness");
}

fn mesh_colliders() -> Vec<(SphCollider, Transform)> {
    let dx = sph_core::SphParams::water().spacing();
    vec![
        (
            SphCollider::from_mesh(&Mesh::from(Torus::new(0.03, 0.07)), dx).unwrap(),
            Transform::from_xyz(0.12, 0.1, 0.15).with_rotation(Quat::from_rotation_x(0.4)),
        ),
        (
            SphCollider::from_mesh(&Mesh::from(Plane3d::new(Vec3::Y, Vec2::splat(0.06))), dx)
                .unwrap(),
            Transform::from_xyz(0.32, 0.12, 0.15).with_rotation(Quat::from_rotation_z(0.7)),
        ),
    ]
}

/// The mesh colliders as solids in the world.
fn solids() -> Vec<Collider> {
    mesh_colliders()
        .into_iter()
        .map(|(c, t)| {
            Collider::new(
                c.shape,
                Pose {
                    translation: t.translation,
                    rotation: t.rotation,
                },
            )
        })
        .collect()
}

/// Particles deeper inside a mesh than the guard's tolerance.
fn inside(s: &SphSnapshot) -> usize {
    let depth = -sph_core::boundary::guard::tolerance(sph_core::SphParams::water().spacing());
    let solids = solids();
    s.positions
        .iter()
        .filter(|&&x| solids.iter().any(|c| c.signed_distance(x) < depth))
        .count()
}

/// Water thrown down at 60 m/s onto the meshes: one step, in which the lowest layers would cross
/// into the meshes (before the speculative contact the guard pushed 52 of them back out) and the
/// contact stops them short. The collider corrections the step counted (CPU; the GPU's count
/// arrives frames later), the snapshot and the particle count.
fn throw_water_on_meshes(backend: SphBackend) -> (u64, SphSnapshot, usize) {
    let params = sph_core::SphParams::water();
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.45, 0.4, 0.3));
    let block = BlockSpawn {
        jitter: 0.1,
        seed: 11,
        ..BlockSpawn::new(
            Vec3::new(0.0, 0.12, 0.0),
            Vec3::new(0.45, 0.3, 0.3),
            params.spacing(),
        )
    };
    let mut app = headless_app(block.count() as u32, backend);
    app.insert_resource(SphParams(params));
    app.insert_resource(SphControl {
        running: false,
        ..default()
    });
    app.world_mut().spawn(SphContainer(container));
    for (c, t) in mesh_colliders() {
        app.world_mut().spawn((c, t));
    }
    app.update();
    // Spawned after the meshes exist: the solver skips what they cover.
    app.world_mut().spawn(SphBlockSpawn {
        block,
        velocity: Vec3::new(0.0, -60.0, 0.0),
    });
    app.update();
    let n = app.world().resource::<SphStats>().particle_count as usize;
    assert_eq!(
        inside(&snapshot(&mut app)),
        0,
        "{backend:?}: spawned inside"
    );
    step_to(&mut app, 1);
    let stats = app.world().resource::<SphStats>().clone();
    assert!(
        stats.collider_errors.is_empty(),
        "{:?}",
        stats.collider_errors
    );
    (stats.boundary_corrections, snapshot(&mut app), n)
}

#[test]
fn water_thrown_onto_meshes_stops_short_of_them_on_both_backends() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let (corrections, cpu, n) = throw_water_on_meshes(SphBackend::Cpu);
    let (_, gpu, m) = throw_water_on_meshes(SphBackend::Gpu);
    assert_eq!(n, m, "both backends skip the same particles");
    assert_eq!(
        (cpu.positions.len(), gpu.positions.len()),
        (n, n),
        "nothing lost"
    );
    eprintln!("{corrections} particles pushed out of the meshes (CPU)");
    assert_eq!(corrections, 0, "the water crossed into the meshes");
    // The step moved the lowest layers to the meshes' margin, a tenth of a spacing off.
    let dx = sph_core::SphParams::water().spacing();
    let solids = solids();
    let closest = cpu
        .positions
        .iter()
        .map(|&x| {
            solids
                .iter()
                .map(|c| c.signed_distance(x))
                .fold(f32::MAX, f32::min)
        })
        .fold(f32::MAX, f32::min);
    eprintln!("closest to a mesh: {closest:.2e} m");
    assert!(
        (0.05 * dx..0.5 * dx).contains(&closest),
        "closest to a mesh {closest} m"
    );
    assert_eq!(inside(&cpu), 0, "CPU: particles left inside a mesh");
    assert_eq!(inside(&gpu), 0, "GPU: particles left inside a mesh");
    let (c_order, g_order) = (by_id(&cpu), by_id(&gpu));
    let worst = c_order
        .iter()
        .zip(&g_order)
        .map(|(&c, &g)| cpu.positions[c].distance(gpu.positions[g]))
        .fold(0.0f32, f32::max);
    eprintln!("worst |Δx| {worst:.2e} m");
    assert!(worst < 1e-4, "worst position difference {worst} m");
}

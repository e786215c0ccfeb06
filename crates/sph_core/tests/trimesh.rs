//! Triangle-mesh colliders: exact signed distances (a mesh cube against the analytic box, a
//! mesh sphere's sign inside and out, an open sheet's shell), the hierarchy's closest point
//! against brute force, welding of a game mesh's duplicated vertices, inward winding turned
//! outward, refusals that name the field, and boundary samples at the layers' depths, about one
//! spacing apart.

use glam::Vec3;
use sph_core::boundary::collider::ColliderShape;
use sph_core::boundary::sampling::{layer_depths, sample_shape};
use sph_core::boundary::trimesh::{closest_on_triangle, icosphere};
use sph_core::rng::SplitMix64;
use sph_core::TriMesh;

const DX: f32 = 0.02;

/// A box of half extents `h` as a game mesh: four vertices per face, none shared.
fn cube(h: Vec3) -> (Vec<Vec3>, Vec<u32>) {
    let mut v = Vec::new();
    let mut i = Vec::new();
    for axis in 0..3 {
        for side in [-1.0f32, 1.0] {
            let n = Vec3::AXES[axis] * side;
            let (u, w) = (Vec3::AXES[(axis + 1) % 3], Vec3::AXES[(axis + 2) % 3]);
            let base = v.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                v.push((n + u * a + w * b) * h);
            }
            // Counter-clockwise seen from outside: u × w = n for side +1.
            if side > 0.0 {
                i.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
            } else {
                i.extend([base, base + 2, base + 1, base, base + 3, base + 2]);
            }
        }
    }
    (v, i)
}

/// A flat square sheet of side `2a` in the xz plane, `n` × `n` quads.
fn sheet(a: f32, n: u32) -> (Vec<Vec3>, Vec<u32>) {
    let mut v = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (i as f32 / n as f32, j as f32 / n as f32);
            v.push(Vec3::new(-a + 2.0 * a * x, 0.0, -a + 2.0 * a * z));
        }
    }
    let mut idx = Vec::new();
    let at = |i: u32, j: u32| j * (n + 1) + i;
    for j in 0..n {
        for i in 0..n {
            idx.extend([at(i, j), at(i, j + 1), at(i + 1, j)]);
            idx.extend([at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)]);
        }
    }
    (v, idx)
}

fn random_points(n: usize, extent: f32, seed: u64) -> Vec<Vec3> {
    let mut rng = SplitMix64::new(seed);
    (0..n)
        .map(|_| {
            Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            ) * extent
        })
        .collect()
}

#[test]
fn a_mesh_cube_has_the_boxs_exact_signed_distance() {
    let h = Vec3::new(0.2, 0.1, 0.15);
    let (v, i) = cube(h);
    let mesh = TriMesh::closed(&v, &i).expect("a game cube welds to a watertight mesh");
    assert_eq!(mesh.thickness(), None);
    let analytic = ColliderShape::Cuboid { half_extents: h };
    let mut worst = 0.0f32;
    for p in random_points(4000, 0.4, 1) {
        let (d, n) = mesh.distance_and_normal(p);
        worst = worst.max((d - analytic.signed_distance(p)).abs());
        assert!((n.length() - 1.0).abs() < 1e-4, "unit normal at {p}");
        // The normal is the distance's gradient: one step along it adds that step.
        let e = 1e-3;
        let ahead = mesh.signed_distance(p + n * e);
        assert!(
            (ahead - d - e).abs() < 2e-4,
            "gradient at {p}: {d} -> {ahead}"
        );
    }
    assert!(worst < 1e-5, "worst |Δφ| {worst}");

    // Inward winding is turned outward: the same distances.
    let flipped: Vec<u32> = i.chunks(3).flat_map(|t| [t[0], t[2], t[1]]).collect();
    let inward = TriMesh::closed(&v, &flipped).unwrap();
    for p in random_points(200, 0.4, 2) {
        assert!((inward.signed_distance(p) - mesh.signed_distance(p)).abs() < 1e-6);
    }
}

#[test]
fn a_mesh_sphere_is_negative_inside_and_positive_outside() {
    let r = 0.1;
    let (v, i) = icosphere(r, 3);
    let mesh = TriMesh::closed(&v, &i).unwrap();
    // The mesh lies inside the sphere, its faces at most r (1 − cos θ) under it, θ about
    // 0.1 rad at 3 levels: φ_mesh is at least the sphere's and at most that sag more.
    let sag = 0.01 * r;
    for p in random_points(3000, 0.2, 3) {
        let exact = p.length() - r;
        let d = mesh.signed_distance(p);
        assert!(
            d >= exact - 1e-5 && d <= exact + sag,
            "{p}: mesh {d}, sphere {exact}"
        );
    }
}

#[test]
fn the_hierarchy_finds_the_same_closest_point_as_brute_force() {
    let (v, i) = icosphere(0.3, 4);
    let mesh = TriMesh::closed(&v, &i).unwrap();
    assert_eq!(mesh.triangles().len(), 20 * 256);
    for p in random_points(500, 0.5, 4) {
        let (c, _, _) = mesh.closest(p).unwrap();
        let brute = mesh
            .triangles()
            .iter()
            .map(|t| closest_on_triangle(p, &t.corners).0.distance(p))
            .fold(f32::INFINITY, f32::min);
        assert!((c.distance(p) - brute).abs() < 1e-6, "{p}");
    }
}

#[test]
fn an_open_sheet_is_a_shell_of_its_thickness() {
    let (v, i) = sheet(0.2, 4);
    assert!(
        TriMesh::closed(&v, &i).is_err_and(|e| e.field == "shape.triangles"),
        "a sheet is not watertight"
    );
    let mesh = TriMesh::new(&v, &i, DX).unwrap();
    assert_eq!(mesh.thickness(), Some(DX));
    for (p, want) in [
        (Vec3::new(0.05, 0.05, 0.0), 0.05 - DX / 2.0),
        (Vec3::new(0.05, -0.05, 0.1), 0.05 - DX / 2.0),
        (Vec3::new(0.0, 0.0, 0.0), -DX / 2.0),
        (Vec3::new(0.3, 0.0, 0.0), 0.1 - DX / 2.0),
    ] {
        assert!((mesh.signed_distance(p) - want).abs() < 1e-6, "{p}");
    }
    // One layer on the mid surface when the shell is thinner than two half spacings.
    let samples = sample_shape(&ColliderShape::TriMesh(mesh.into()), DX);
    assert!(samples.position.iter().all(|p| p.y.abs() < 1e-6));
    let per_area = samples.len() as f32 / (0.4 * 0.4 / (DX * DX));
    assert!((0.8..1.4).contains(&per_area), "{per_area} samples per dx²");
}

#[test]
fn bad_meshes_are_refused_by_field() {
    let (v, i) = cube(Vec3::splat(0.1));
    let field =
        |r: Result<TriMesh, sph_core::boundary::collider::ColliderError>| r.unwrap_err().field;
    assert_eq!(field(TriMesh::closed(&v, &i[..4])), "shape.indices");
    assert_eq!(field(TriMesh::closed(&v, &[])), "shape.indices");
    let mut out_of_range = i.clone();
    out_of_range[5] = 99;
    assert_eq!(field(TriMesh::closed(&v, &out_of_range)), "shape.indices");
    let mut nan = v.clone();
    nan[3].y = f32::NAN;
    assert_eq!(field(TriMesh::closed(&nan, &i)), "shape.vertices");
    let far: Vec<Vec3> = v.iter().map(|p| *p * 1e5).collect();
    assert_eq!(field(TriMesh::closed(&far, &i)), "shape.vertices");
    assert_eq!(field(TriMesh::open(&v, &i, 0.0)), "shape.thickness");
    assert_eq!(field(TriMesh::open(&v, &i, f32::NAN)), "shape.thickness");
    // Only degenerate triangles.
    assert_eq!(field(TriMesh::closed(&v, &[0, 0, 1])), "shape.indices");
    // The open edge is named.
    let e = TriMesh::closed(&v, &i[..i.len() - 3]).unwrap_err();
    assert_eq!(e.field, "shape.triangles");
    assert!(e.value.contains("edge"), "{e}");
}

#[test]
fn mesh_samples_lie_at_the_layer_depths_about_a_spacing_apart() {
    let h = Vec3::new(0.2, 0.1, 0.15);
    let (v, i) = cube(h);
    let mesh = TriMesh::closed(&v, &i).unwrap();
    let shape = ColliderShape::TriMesh(mesh.clone().into());
    let samples = sample_shape(&shape, DX);
    let depths = layer_depths(DX);
    for (p, n) in samples.position.iter().zip(&samples.normal) {
        let d = -mesh.signed_distance(*p);
        assert!(
            depths.iter().any(|&want| (d - want).abs() <= 0.3 * DX),
            "sample {p} at depth {d}"
        );
        assert!((n.length() - 1.0).abs() < 1e-4);
    }
    // As many as the analytic box's lattice, within a third.
    let lattice = sample_shape(&ColliderShape::Cuboid { half_extents: h }, DX).len() as f32;
    let ratio = samples.len() as f32 / lattice;
    assert!(
        (0.75..1.35).contains(&ratio),
        "{} vs {lattice}",
        samples.len()
    );
    // No two samples of a layer closer than 0.9 dx.
    for (k, p) in samples.position.iter().enumerate() {
        let dp = mesh.signed_distance(*p);
        for q in &samples.position[k + 1..] {
            if (mesh.signed_distance(*q) - dp).abs() < 0.5 * DX {
                assert!(p.distance(*q) >= 0.9 * DX - 1e-6, "{p} {q}");
            }
        }
    }
}

/// Water dropped on a ball, the ball analytic or an icosphere mesh of the same radius: the
/// particles kept, where they end, the corrections the guard made and the ball's mean load.
fn drop_on_ball(shape: ColliderShape) -> (usize, f32, u64, f32) {
    use sph_core::{BlockSpawn, BoxContainer, Collider, CpuSolver, Pose, SphParams};
    let params = SphParams::water();
    let dx = params.spacing();
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.3, 0.4, 0.3));
    let block = BlockSpawn::new(Vec3::new(0.05, 0.16, 0.05), Vec3::new(0.25, 0.28, 0.25), dx);
    let mut solver = CpuSolver::new(params, container, block.count()).unwrap();
    let pose = Pose {
        translation: Vec3::new(0.15, 0.07, 0.15),
        ..Pose::default()
    };
    let id = solver.add_collider(Collider::new(shape, pose)).unwrap();
    solver.spawn(&block.positions(), Vec3::ZERO);
    let mut load = 0.0;
    let mut samples = 0;
    while solver.time() < 0.5 {
        solver.step();
        if solver.time() > 0.3 {
            load += solver.collider_force(id).unwrap().force.y;
            samples += 1;
        }
        solver.take_collider_forces();
    }
    let p = solver.particles();
    let mean_y = p.position.iter().map(|x| x.y).sum::<f32>() / p.position.len() as f32;
    (
        solver.len(),
        mean_y,
        solver.corrections().colliders,
        load / samples as f32,
    )
}

#[test]
fn water_meets_a_mesh_ball_as_it_meets_the_analytic_ball() {
    let r = 0.06;
    let (v, i) = icosphere(r, 3);
    let mesh = ColliderShape::TriMesh(TriMesh::closed(&v, &i).unwrap().into());
    let analytic = drop_on_ball(ColliderShape::Sphere { radius: r });
    let meshed = drop_on_ball(mesh);
    eprintln!("analytic {analytic:?}\nmesh     {meshed:?}");
    assert_eq!(analytic.0, meshed.0, "no particle lost");
    assert!((analytic.1 - meshed.1).abs() < 0.25 * DX, "mean heights");
    assert!(meshed.2 <= analytic.2 + 5, "guard corrections");
    assert!(
        (analytic.3 - meshed.3).abs() < 0.15 * analytic.3.abs(),
        "the ball's mean load"
    );
}

//! `cargo bench -p sph_core --bench mesh_sampling`: the cost of a triangle-mesh collider (issue
//! 11 asks under a second for 10k triangles): building the mesh (welding, watertight check,
//! pseudo-normals, hierarchy), sampling its boundary layers, and adding it to a boundary
//! (sampling plus Akinci's volumes), for icospheres of 5,120 to 81,920 triangles.

use sph_core::boundary::sampling::sample_shape;
use sph_core::boundary::trimesh::icosphere;
use sph_core::glam::Vec3;
use sph_core::{Boundary, BoxContainer, Collider, ColliderShape, Pose, Slip, SphParams, TriMesh};
use std::time::Instant;

fn main() {
    let params = SphParams::water();
    let spacing = params.spacing();
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(1.0));
    for levels in [4, 5, 6] {
        let (v, i) = icosphere(0.3, levels);
        let t = Instant::now();
        let mesh = TriMesh::closed(&v, &i).expect("an icosphere is watertight");
        let build = t.elapsed().as_secs_f64();
        let shape = ColliderShape::TriMesh(mesh.into());
        let t = Instant::now();
        let samples = sample_shape(&shape, spacing).len();
        let sample = t.elapsed().as_secs_f64();
        let mut boundary = Boundary::new(&container, &params, Slip::Free).expect("valid");
        let t = Instant::now();
        boundary
            .add(Collider::new(
                shape,
                Pose {
                    translation: Vec3::splat(0.5),
                    ..Pose::default()
                },
            ))
            .expect("valid collider");
        let add = t.elapsed().as_secs_f64();
        println!(
            "mesh_sampling/icosphere r 0.3 m, {} triangles, dx {spacing:.4} m: build {:.0} ms, \
             sample {:.0} ms ({samples} samples), add to a boundary {:.0} ms, total {:.0} ms",
            i.len() / 3,
            build * 1e3,
            sample * 1e3,
            add * 1e3,
            (build + add) * 1e3
        );
    }
}

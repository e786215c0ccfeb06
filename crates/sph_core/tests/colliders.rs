//! Collider shapes and their boundary samples (groundwork for the Akinci 2012 boundary model):
//! signed distances, validation, and samples at the two inset depths with about one spacing
//! between neighbours.

use glam::{Quat, Vec3};
use sph_core::boundary::collider::{ColliderShape, PlacedShape, Pose};
use sph_core::boundary::sampling::{layer_depths, sample_shape};

const DX: f32 = 0.02;

fn shapes() -> Vec<(&'static str, ColliderShape)> {
    vec![
        (
            "cuboid",
            ColliderShape::Cuboid {
                half_extents: Vec3::new(0.2, 0.1, 0.15),
            },
        ),
        ("sphere", ColliderShape::Sphere { radius: 0.12 }),
        (
            "capsule",
            ColliderShape::Capsule {
                radius: 0.08,
                half_length: 0.1,
            },
        ),
        (
            "cylinder",
            ColliderShape::Cylinder {
                radius: 0.1,
                half_length: 0.12,
            },
        ),
    ]
}

#[test]
fn signed_distances_are_exact_on_known_points() {
    let cuboid = ColliderShape::Cuboid {
        half_extents: Vec3::new(1.0, 2.0, 3.0),
    };
    assert_eq!(cuboid.signed_distance(Vec3::ZERO), -1.0);
    assert_eq!(cuboid.signed_distance(Vec3::new(2.0, 0.0, 0.0)), 1.0);
    assert!((cuboid.signed_distance(Vec3::new(2.0, 3.0, 0.0)) - 2f32.sqrt()).abs() < 1e-6);
    let capsule = ColliderShape::Capsule {
        radius: 0.5,
        half_length: 1.0,
    };
    assert_eq!(capsule.signed_distance(Vec3::new(0.0, 2.0, 0.0)), 0.5);
    assert_eq!(capsule.signed_distance(Vec3::new(1.0, 0.3, 0.0)), 0.5);
    let cylinder = ColliderShape::Cylinder {
        radius: 0.5,
        half_length: 1.0,
    };
    assert_eq!(cylinder.signed_distance(Vec3::new(0.0, 1.5, 0.0)), 0.5);
    assert_eq!(cylinder.signed_distance(Vec3::new(0.0, 0.0, 0.0)), -0.5);
    // A rotated box: 90° about z swaps x and y.
    let placed = PlacedShape {
        shape: cuboid,
        pose: Pose {
            translation: Vec3::new(10.0, 0.0, 0.0),
            rotation: Quat::from_rotation_z(std::f32::consts::FRAC_PI_2),
        },
    };
    assert!((placed.signed_distance(Vec3::new(12.5, 0.0, 0.0)) - 0.5).abs() < 1e-5);
}

#[test]
fn samples_lie_at_the_inset_depths_with_outward_normals() {
    let depths = layer_depths(DX);
    for (name, shape) in shapes() {
        let samples = sample_shape(&shape, DX);
        assert!(samples.len() > 100, "{name}: {} samples", samples.len());
        for (&p, &n) in samples.position.iter().zip(&samples.normal) {
            let d = -shape.signed_distance(p);
            assert!(
                depths.iter().any(|&depth| (d - depth).abs() < 1e-4),
                "{name}: sample {p} at depth {d}"
            );
            assert!((n.length() - 1.0).abs() < 1e-4, "{name}: normal {n}");
            // Moving along the normal goes towards the surface.
            assert!(
                shape.signed_distance(p + n * 0.1 * DX) > -d,
                "{name}: normal {n} at {p} points inward"
            );
        }
    }
}

#[test]
fn samples_are_about_one_spacing_apart() {
    for (name, shape) in shapes() {
        let samples = sample_shape(&shape, DX);
        let p = &samples.position;
        let nearest: Vec<f32> = p
            .iter()
            .enumerate()
            .map(|(i, &a)| {
                p.iter()
                    .enumerate()
                    .filter(|&(j, _)| j != i)
                    .map(|(_, &b)| a.distance(b))
                    .fold(f32::INFINITY, f32::min)
            })
            .collect();
        let min = nearest.iter().copied().fold(f32::INFINITY, f32::min);
        let mean = nearest.iter().sum::<f32>() / nearest.len() as f32;
        assert!(min > 0.3 * DX, "{name}: two samples {min} m apart");
        assert!(
            (0.6 * DX..=1.2 * DX).contains(&mean),
            "{name}: mean nearest-neighbour distance {mean} m"
        );
    }
}

/// Every point of a shape's surface has a sample within 0.95 Δx: Δx/2 under a face, 0.7 Δx under
/// an edge, up to 0.87 Δx at a box's corner and 0.92 Δx between a small capsule's rings (their
/// spacing is set on the inset layer, so it widens at the surface). The capsule of `sph-bench run
/// --scenario obstacles` is included: its caps' Fibonacci lattices once left the seams with the
/// side's rings holes where the nearest sample was 1.0 to 1.1 Δx away, and the water slid in.
#[test]
fn every_surface_point_has_a_sample_within_a_spacing() {
    let mut all = shapes();
    all.push((
        "obstacles' capsule",
        ColliderShape::Capsule {
            radius: 0.06,
            half_length: 0.12,
        },
    ));
    for (name, shape) in all {
        let samples = sample_shape(&shape, DX).position;
        let far = 2.0 * shape.bounding_radius();
        // Points on a sphere around the shape, projected onto its surface (the signed distance's
        // gradient leads a convex shape's outside point straight to its nearest surface point).
        let n = 20_000;
        let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
        let mut worst = (0.0f32, Vec3::ZERO);
        for k in 0..n {
            let y = 1.0 - 2.0 * (k as f32 + 0.5) / n as f32;
            let ring = (1.0 - y * y).sqrt();
            let phi = golden * k as f32;
            let mut p = Vec3::new(ring * phi.cos(), y, ring * phi.sin()) * far;
            for _ in 0..3 {
                p -= shape.normal(p, 1e-5) * shape.signed_distance(p);
            }
            assert!(
                shape.signed_distance(p).abs() < 1e-5,
                "{name}: {p} not on the surface"
            );
            let nearest = samples
                .iter()
                .map(|&b| b.distance(p))
                .fold(f32::INFINITY, f32::min);
            if nearest > worst.0 {
                worst = (nearest, p);
            }
        }
        eprintln!(
            "{name}: farthest sample {:.3} Δx from {}",
            worst.0 / DX,
            worst.1
        );
        assert!(
            worst.0 < 0.95 * DX,
            "{name}: the surface point {} has no sample within {:.3} Δx",
            worst.1,
            worst.0 / DX
        );
    }
}

#[test]
fn a_plate_thinner_than_the_spacing_gets_one_mid_layer() {
    let plate = ColliderShape::Cuboid {
        half_extents: Vec3::new(0.1, 0.004, 0.1),
    };
    let samples = sample_shape(&plate, DX);
    assert!(!samples.is_empty());
    assert!(samples.position.iter().all(|p| p.y.abs() < 1e-6));
}

#[test]
fn bad_sizes_and_poses_are_named() {
    let e = ColliderShape::Sphere { radius: 0.0 }
        .validate()
        .unwrap_err();
    assert_eq!(e.field, "shape.radius");
    let e = ColliderShape::Cuboid {
        half_extents: Vec3::new(1.0, -1.0, 1.0),
    }
    .validate()
    .unwrap_err();
    assert!(e.to_string().contains("shape.half_extents.y") && e.to_string().contains("-1"));
    let e = ColliderShape::Capsule {
        radius: 0.1,
        half_length: f32::NAN,
    }
    .validate()
    .unwrap_err();
    assert_eq!(e.field, "shape.half_length");
    let e = Pose {
        translation: Vec3::new(f32::INFINITY, 0.0, 0.0),
        ..Pose::default()
    }
    .validate()
    .unwrap_err();
    assert_eq!(e.field, "pose.translation");
    let e = Pose {
        rotation: Quat::from_xyzw(0.0, 0.0, 0.0, 2.0),
        ..Pose::default()
    }
    .validate()
    .unwrap_err();
    assert_eq!(e.field, "pose.rotation");
}

mod akinci2012 {
    use super::DX;
    use glam::Vec3;
    use sph_core::boundary::akinci2012::{
        boundary_density_ratio, boundary_volumes, calibrate_gamma, lattice_density_ratio,
    };
    use sph_core::boundary::collider::ColliderShape;
    use sph_core::boundary::sampling::sample_shape;
    use sph_core::Kernels;

    fn kernels() -> Kernels {
        Kernels::new(2.0 * DX)
    }

    #[test]
    fn volumes_of_a_regular_layer_are_even_and_about_a_particle_volume() {
        let slab = ColliderShape::Cuboid {
            half_extents: Vec3::new(0.2, 2.0 * DX, 0.2),
        };
        let samples = sample_shape(&slab, DX).position;
        let volumes = boundary_volumes(&samples, &kernels(), 1.0);
        // Samples of the outer layer's top face, away from edges: all alike.
        let middle: Vec<f32> = samples
            .iter()
            .zip(&volumes)
            .filter(|(p, _)| p.x.abs() < 0.05 && p.z.abs() < 0.05 && (p.y - 1.5 * DX).abs() < 1e-5)
            .map(|(_, &v)| v)
            .collect();
        assert!(!middle.is_empty());
        let (lo, hi) = middle
            .iter()
            .fold((f32::MAX, f32::MIN), |(a, b), &v| (a.min(v), b.max(v)));
        assert!(hi / lo < 1.01, "{lo} .. {hi}");
        // Two layers see fewer neighbours than a full lattice: more than dx³ each.
        let dx3 = DX.powi(3);
        assert!(lo > dx3 && lo < 2.0 * dx3, "V_b = {lo}, dx³ = {dx3}");
    }

    #[test]
    fn a_calibrated_wall_completes_the_second_fluid_row_too() {
        let k = kernels();
        let gamma = calibrate_gamma(DX, &k);
        println!("calibrated gamma = {gamma}");
        assert!((0.5..1.0).contains(&gamma), "gamma = {gamma}");
        // The second fluid row, 1.5 dx above the surface, is not what γ was fitted to.
        let thickness = 2.0 * DX;
        let half_width = 3.0 * k.h + 2.0 * DX;
        let slab = ColliderShape::Cuboid {
            half_extents: Vec3::new(half_width, thickness, half_width),
        };
        let samples = sample_shape(&slab, DX).position;
        let volumes = boundary_volumes(&samples, &k, gamma);
        let full = lattice_density_ratio(DX, &k, f32::NEG_INFINITY);
        let probe = Vec3::new(0.0, thickness + 1.5 * DX, 0.0);
        let fluid = lattice_density_ratio(DX, &k, -1.01 * DX);
        let total = fluid + boundary_density_ratio(probe, &samples, &volumes, &k);
        assert!(
            (total / full - 1.0).abs() < 0.02,
            "second row: {total} against a full lattice's {full}"
        );
    }
}

//! What the export tests share: loading scenes, comparing numbers, reading files back, and the
//! check that a written mesh lies on its collider's surface.

use super::super::common::{Export, ExportOptions, Loaded};
use super::super::mesh::Mesh;
use serde_json::Value;
use sph_core::glam::Vec3;
use sph_core::scene::{SceneCollider, SceneFile, ShapeSpec};
use std::collections::HashMap;
use std::path::Path;

/// DualSPHysics's point (z up) in the scene's frame (y up): the inverse of `to_dsph`.
pub fn from_dsph(p: Vec3) -> Vec3 {
    Vec3::new(p.x, p.z, -p.y)
}

/// The volume a closed mesh encloses (divergence theorem; positive when wound outward) [m³].
pub fn volume(mesh: &Mesh) -> f32 {
    let v = |k: u32| mesh.vertices[k as usize];
    mesh.triangles
        .iter()
        .map(|t| v(t[0]).dot(v(t[1]).cross(v(t[2]))) / 6.0)
        .sum()
}

pub fn load_file(stem: &str) -> Loaded {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../assets/scenes/{stem}.ron"));
    super::super::common::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

pub fn load_text(text: &str) -> Loaded {
    let spec = SceneFile::parse(text, "inline.ron").unwrap_or_else(|e| panic!("{e}"));
    let setup = spec
        .build("inline.ron", text)
        .unwrap_or_else(|e| panic!("{e}"));
    Loaded {
        file: "inline.ron".into(),
        spec,
        setup,
    }
}

pub fn options(drop_probes: bool) -> ExportOptions {
    ExportOptions {
        end_time: 3.0,
        drop_probes,
    }
}

pub fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= 2e-5 * (1.0 + a.abs().max(b.abs()))
}

pub fn close3(a: Vec3, b: Vec3) -> bool {
    (0..3).all(|i| close(a[i], b[i]))
}

pub fn num(v: &Value) -> f32 {
    v.as_f64().unwrap_or_else(|| panic!("{v} is not a number")) as f32
}

pub fn int(v: &Value) -> i64 {
    v.as_i64()
        .unwrap_or_else(|| panic!("{v} is not an integer"))
}

pub fn vec3(v: &Value) -> Vec3 {
    let a = v
        .as_array()
        .filter(|a| a.len() == 3)
        .unwrap_or_else(|| panic!("{v}: not [x, y, z]"));
    Vec3::new(num(&a[0]), num(&a[1]), num(&a[2]))
}

pub fn bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    points
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        })
}

/// The vertices of an OBJ (`v` lines) or an ASCII STL (`vertex` lines).
pub fn vertices(text: &str) -> Vec<Vec3> {
    text.lines()
        .filter_map(|l| {
            l.trim()
                .strip_prefix("v ")
                .or(l.trim().strip_prefix("vertex "))
        })
        .map(|l| {
            let c: Vec<f32> = l
                .split_whitespace()
                .map(|x| x.parse().expect("a number"))
                .collect();
            Vec3::new(c[0], c[1], c[2])
        })
        .collect()
}

/// Every vertex lies on the collider's surface, and the bounds are the shape's where they are
/// known exactly (boxes, balls, meshes: poles, corners and vertices are on the mesh).
pub fn check_surface(c: &SceneCollider, spec: &ShapeSpec, points: &[Vec3]) {
    assert!(!points.is_empty(), "{}: no vertices", c.name);
    for &x in points {
        let d = c.collider.signed_distance(x);
        assert!(
            d.abs() < 1e-4,
            "{}: vertex {x} is {d} m off the surface",
            c.name
        );
    }
    let pose = c.collider.pose;
    let expected: Option<Vec<Vec3>> = match spec {
        ShapeSpec::Cuboid { half_extents: h } => Some(
            (0..8)
                .map(|k| {
                    let s = |b: u32| if k & (1 << b) == 0 { -1.0 } else { 1.0 };
                    pose.to_world(Vec3::new(s(0) * h.0, s(1) * h.1, s(2) * h.2))
                })
                .collect(),
        ),
        ShapeSpec::Sphere { radius } => Some(
            [-1.0, 1.0]
                .iter()
                .map(|&s| pose.translation + Vec3::splat(s * radius))
                .collect(),
        ),
        ShapeSpec::Mesh {
            vertices: v,
            indices: i,
            thickness,
        } => {
            let v: Vec<Vec3> = v.iter().map(|p| Vec3::new(p.0, p.1, p.2)).collect();
            let offset = thickness.map_or(Vec3::ZERO, |t| {
                // The shipped open mesh is flat: its slab is the sheet ± t/2 along its normal.
                let (a, b, c) = (v[i[0] as usize], v[i[1] as usize], v[i[2] as usize]);
                (b - a).cross(c - a).normalize() * (0.5 * t)
            });
            Some(
                v.iter()
                    .flat_map(|&p| [p + offset, p - offset])
                    .map(|p| pose.to_world(p))
                    .collect(),
            )
        }
        _ => None,
    };
    let (lo, hi) = bounds(points);
    if let Some(corners) = expected {
        let (elo, ehi) = bounds(&corners);
        assert!(
            close3(lo, elo) && close3(hi, ehi),
            "{}: bounds {lo}..{hi}, shape {elo}..{ehi}",
            c.name
        );
    }
}

pub fn files(export: &Export) -> HashMap<&str, &str> {
    export
        .files
        .iter()
        .map(|(n, t)| (n.as_str(), t.as_str()))
        .collect()
}

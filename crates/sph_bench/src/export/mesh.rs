//! Closed triangle meshes for the exported geometry: every collider shape as a surface in world
//! coordinates (its pose applied), written as Wavefront OBJ (SPlisHSPlasH's `geometryFile`) or
//! ASCII STL (DualSPHysics's `drawfilestl`).
//!
//! Curved shapes are sampled with their extreme points on the surface (poles on the axis,
//! equators and rings of a multiple of four segments), so an unrotated sphere's mesh has the
//! sphere's bounds exactly. An open mesh collider (a shell of thickness t around a sheet) becomes
//! a closed slab: the sheet offset by ±t/2 along its vertex normals, with side walls along its
//! open edges.

use super::common::decimal;
use sph_core::boundary::collider::{ColliderShape, Pose};
use sph_core::boundary::trimesh::TriMesh;
use sph_core::glam::Vec3;
use std::collections::HashMap;
use std::f32::consts::{FRAC_PI_2, PI, TAU};
use std::fmt::Write as _;

/// An indexed triangle mesh, counter-clockwise seen from outside.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions [m].
    pub vertices: Vec<Vec3>,
    /// Three vertex indices per triangle.
    pub triangles: Vec<[u32; 3]>,
}

/// Segments around a curved shape of radius `radius` sampled for spacing `spacing`: chords of
/// at most half a spacing, a multiple of four, 16 ..= 256.
pub fn segments(radius: f32, spacing: f32) -> u32 {
    let n = (TAU * radius / (0.5 * spacing)).ceil().clamp(16.0, 256.0) as u32;
    n.div_ceil(4) * 4
}

impl Mesh {
    /// A box of half extents `half` centred on the origin.
    pub fn cuboid(half: Vec3) -> Self {
        // Corner k has x from bit 0, y from bit 1, z from bit 2.
        let vertices = (0..8)
            .map(|k| {
                let sign = |bit: u32| if k & (1 << bit) == 0 { -1.0 } else { 1.0 };
                half * Vec3::new(sign(0), sign(1), sign(2))
            })
            .collect();
        let triangles = vec![
            [0, 4, 6],
            [0, 6, 2],
            [1, 3, 7],
            [1, 7, 5],
            [0, 1, 5],
            [0, 5, 4],
            [2, 6, 7],
            [2, 7, 3],
            [0, 2, 3],
            [0, 3, 1],
            [4, 5, 7],
            [4, 7, 6],
        ];
        Self {
            vertices,
            triangles,
        }
    }

    /// The surface of revolution about y through `profile`: (radius, y) from the bottom pole
    /// (radius 0) to the top pole (radius 0), with `segments` around.
    fn revolve(profile: &[(f32, f32)], segments: u32) -> Self {
        let rings = &profile[1..profile.len() - 1];
        let mut vertices = vec![Vec3::new(0.0, profile[0].1, 0.0)];
        for &(r, y) in rings {
            vertices.extend((0..segments).map(|k| {
                let theta = TAU * k as f32 / segments as f32;
                Vec3::new(r * theta.cos(), y, r * theta.sin())
            }));
        }
        let top = vertices.len() as u32;
        vertices.push(Vec3::new(0.0, profile[profile.len() - 1].1, 0.0));
        let at = |ring: usize, k: u32| 1 + ring as u32 * segments + k % segments;
        let mut triangles = Vec::new();
        for k in 0..segments {
            triangles.push([0, at(0, k), at(0, k + 1)]);
            for ring in 0..rings.len() - 1 {
                let (a, b) = (at(ring, k), at(ring, k + 1));
                let (c, d) = (at(ring + 1, k + 1), at(ring + 1, k));
                triangles.push([a, d, c]);
                triangles.push([a, c, b]);
            }
            triangles.push([top, at(rings.len() - 1, k + 1), at(rings.len() - 1, k)]);
        }
        Self {
            vertices,
            triangles,
        }
    }

    /// A sphere of `radius` about the origin, poles on ±y.
    pub fn sphere(radius: f32, segments: u32) -> Self {
        Self::capsule(radius, 0.0, segments)
    }

    /// A capsule along y: hemispheres of `radius` on the ends of a segment of half length
    /// `half_length` (0: a sphere).
    pub fn capsule(radius: f32, half_length: f32, segments: u32) -> Self {
        let quarter = segments / 4;
        let mut profile = vec![(0.0, -half_length - radius)];
        let cap = |k: u32, centre: f32| {
            let phi = -FRAC_PI_2 + FRAC_PI_2 * k as f32 / quarter as f32;
            (radius * phi.cos(), centre + radius * phi.sin())
        };
        profile.extend((1..=quarter).map(|k| cap(k, -half_length)));
        if half_length > 0.0 {
            profile.push((radius, half_length));
        }
        profile.extend((1..quarter).map(|k| cap(quarter + k, half_length)));
        profile.push((0.0, half_length + radius));
        Self::revolve(&profile, segments)
    }

    /// A flat-capped cylinder along y.
    pub fn cylinder(radius: f32, half_length: f32, segments: u32) -> Self {
        let profile = [
            (0.0, -half_length),
            (radius, -half_length),
            (radius, half_length),
            (0.0, half_length),
        ];
        Self::revolve(&profile, segments)
    }

    /// A collider mesh with coincident corners welded (bit-equal positions share a vertex).
    pub fn welded(mesh: &TriMesh) -> Self {
        let (corners, _) = mesh.indexed();
        let mut index: HashMap<[u32; 3], u32> = HashMap::new();
        let mut out = Self::default();
        let ids: Vec<u32> = corners
            .iter()
            .map(|&p| {
                *index
                    .entry(p.to_array().map(f32::to_bits))
                    .or_insert_with(|| {
                        out.vertices.push(p);
                        out.vertices.len() as u32 - 1
                    })
            })
            .collect();
        out.triangles = ids.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        out
    }

    /// The closed slab of an open sheet: the sheet moved by ±`thickness`/2 along its vertex
    /// normals (angle-weighted), joined along the edges that only one triangle uses.
    pub fn slab(&self, thickness: f32) -> Self {
        let n = self.vertices.len();
        let mut normals = vec![Vec3::ZERO; n];
        for t in &self.triangles {
            let p = t.map(|k| self.vertices[k as usize]);
            let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            for k in 0..3 {
                let (u, w) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
                normals[t[k] as usize] += face * u.angle_between(w);
            }
        }
        let half = 0.5 * thickness;
        let mut out = Self::default();
        out.vertices
            .extend((0..n).map(|k| self.vertices[k] + normals[k].normalize_or_zero() * half));
        out.vertices
            .extend((0..n).map(|k| self.vertices[k] - normals[k].normalize_or_zero() * half));
        let below = |k: u32| k + n as u32;
        let mut uses: HashMap<(u32, u32), u32> = HashMap::new();
        for t in &self.triangles {
            out.triangles.push(*t);
            out.triangles.push([below(t[0]), below(t[2]), below(t[1])]);
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *uses.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if uses[&(a.min(b), a.max(b))] == 1 {
                    out.triangles.push([a, below(a), below(b)]);
                    out.triangles.push([a, below(b), b]);
                }
            }
        }
        out
    }

    /// The mesh of a collider shape at `pose`, curved shapes sampled for `spacing`. A sphere
    /// keeps its poles on the world's y axis (its rotation changes nothing).
    pub fn of_shape(shape: &ColliderShape, pose: &Pose, spacing: f32) -> Self {
        match shape {
            ColliderShape::Cuboid { half_extents } => Self::cuboid(*half_extents).placed(pose),
            ColliderShape::Sphere { radius } => {
                Self::sphere(*radius, segments(*radius, spacing)).map(|p| p + pose.translation)
            }
            ColliderShape::Capsule {
                radius,
                half_length,
            } => Self::capsule(*radius, *half_length, segments(*radius, spacing)).placed(pose),
            ColliderShape::Cylinder {
                radius,
                half_length,
            } => Self::cylinder(*radius, *half_length, segments(*radius, spacing)).placed(pose),
            ColliderShape::TriMesh(mesh) => {
                let welded = Self::welded(mesh);
                match mesh.thickness() {
                    Some(t) => welded.slab(t).placed(pose),
                    None => welded.placed(pose),
                }
            }
        }
    }

    /// The mesh with every vertex mapped by `f` (a rigid motion keeps it closed and outward).
    pub fn map(mut self, f: impl Fn(Vec3) -> Vec3) -> Self {
        self.vertices.iter_mut().for_each(|p| *p = f(*p));
        self
    }

    /// The mesh moved from its frame to the world by `pose`.
    pub fn placed(self, pose: &Pose) -> Self {
        self.map(|p| pose.to_world(p))
    }

    /// The smallest and largest vertex coordinates.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.vertices.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        )
    }

    /// Wavefront OBJ: `v x y z` lines, then 1-based `f a b c` lines.
    pub fn to_obj(&self, title: &str) -> String {
        let mut out = format!("# {title}\no {}\n", file_stem(title));
        for p in &self.vertices {
            let [x, y, z] = p.to_array().map(decimal);
            let _ = writeln!(out, "v {x} {y} {z}");
        }
        for t in &self.triangles {
            let _ = writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        out
    }

    /// ASCII STL: one facet per triangle with its unit normal.
    pub fn to_stl(&self, name: &str) -> String {
        let name = file_stem(name);
        let mut out = format!("solid {name}\n");
        for t in &self.triangles {
            let p = t.map(|k| self.vertices[k as usize]);
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            let _ = writeln!(
                out,
                "  facet normal {} {} {}\n    outer loop",
                n.x, n.y, n.z
            );
            for q in p {
                let _ = writeln!(out, "      vertex {} {} {}", q.x, q.y, q.z);
            }
            out.push_str("    endloop\n  endfacet\n");
        }
        out + &format!("endsolid {name}\n")
    }
}

/// `text` as a file name: ASCII letters, digits and `_`, everything else `_`.
pub fn file_stem(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect()
}

/// The axis and angle [rad] of the shortest rotation taking +x to `direction` (a rotation
/// about y by π when `direction` is −x).
pub fn rotation_from_x(direction: Vec3) -> (Vec3, f32) {
    let d = direction.normalize();
    let angle = d.x.clamp(-1.0, 1.0).acos();
    let axis = Vec3::X.cross(d);
    if axis.length() > 1e-6 {
        (axis.normalize(), angle)
    } else {
        (Vec3::Y, if d.x > 0.0 { 0.0 } else { PI })
    }
}

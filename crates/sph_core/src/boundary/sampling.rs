//! Boundary samples of collider shapes (groundwork for the Akinci 2012 boundary model, see
//! `docs/design_boundary_akinci2012.md` §4): points spaced about one particle spacing s on the
//! surfaces offset inward by dx/2 and 3dx/2, the depths of the fluid lattice mirrored into the
//! solid, so a fluid particle at the wall sees a full kernel support. A layer that would cross the
//! shape's medial axis is dropped; a shape too thin for any layer gets one layer on its mid
//! surface. Each sample carries its outward normal. Samples are in the shape's frame.

use crate::boundary::collider::ColliderShape;
use crate::container::BoxContainer;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Samples of one shape, in its frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShapeSamples {
    /// Positions [m].
    pub position: Vec<Vec3>,
    /// Outward unit normals of the surface each sample lies under.
    pub normal: Vec<Vec3>,
    /// For lattice samplings (cuboids): the volume of the lattice cell each sample stands for
    /// [m³], the exact boundary volume where the layers continue the fluid's lattice. Empty for
    /// curved shapes, whose volumes come from Akinci's Σ W.
    pub cell_volume: Vec<f32>,
}

impl ShapeSamples {
    fn push(&mut self, position: Vec3, normal: Vec3) {
        self.position.push(position);
        self.normal.push(normal.normalize_or(Vec3::Y));
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }
}

/// The inward depths of the sample layers for particle spacing `spacing`: dx/2 and 3dx/2.
pub fn layer_depths(spacing: f32) -> [f32; 2] {
    [0.5 * spacing, 1.5 * spacing]
}

/// Samples `shape` at spacing `spacing` (the fluid's particle spacing dx) in two inset layers.
pub fn sample_shape(shape: &ColliderShape, spacing: f32) -> ShapeSamples {
    let mut out = ShapeSamples::default();
    let depths = layer_depths(spacing);
    let thickness = match *shape {
        ColliderShape::Cuboid { half_extents } => half_extents.min_element(),
        ColliderShape::Sphere { radius }
        | ColliderShape::Capsule { radius, .. }
        | ColliderShape::Cylinder { radius, .. } => radius,
        ColliderShape::TriMesh(ref mesh) => {
            let m = crate::boundary::sampling_mesh::sample_mesh(mesh, spacing, depths);
            for (p, n) in m.position.into_iter().zip(m.normal) {
                out.push(p, n);
            }
            return out;
        }
    };
    let usable: Vec<f32> = depths.into_iter().filter(|&d| d < thickness).collect();
    if usable.is_empty() {
        // Thinner than dx: one layer on the mid surface (depth = the half thickness).
        sample_layer(shape, thickness, spacing, &mut out);
    }
    for depth in usable {
        sample_layer(shape, depth, spacing, &mut out);
    }
    out
}

fn sample_layer(shape: &ColliderShape, depth: f32, s: f32, out: &mut ShapeSamples) {
    match *shape {
        ColliderShape::Cuboid { half_extents } => cuboid(half_extents - Vec3::splat(depth), s, out),
        ColliderShape::Sphere { radius } => {
            cap_rings(radius - depth, 1.0, 0.0, true, s, out);
            cap_rings(radius - depth, -1.0, 0.0, false, s, out);
        }
        ColliderShape::Capsule {
            radius,
            half_length,
        } => {
            let r = radius - depth;
            cylinder_side(r, half_length, s, false, out);
            cap_rings(r, 1.0, half_length, true, s, out);
            cap_rings(r, -1.0, -half_length, true, s, out);
        }
        ColliderShape::Cylinder {
            radius,
            half_length,
        } => {
            let (r, h) = (radius - depth, (half_length - depth).max(0.0));
            cylinder_side(r, h, s, true, out);
            for y in [-h, h] {
                disc(r, y, s, out);
            }
        }
        ColliderShape::TriMesh(_) => {}
    }
}

/// Points on the surface of the box with half extents `a` (an axis of zero size collapses the
/// box to a plate): a lattice of about `s` over the box, keeping the points on its faces.
fn cuboid(a: Vec3, s: f32, out: &mut ShapeSamples) {
    let a = a.max(Vec3::ZERO);
    let n = (2.0 * a / s).ceil().as_uvec3();
    let step = |axis: usize| {
        if n[axis] == 0 {
            0.0
        } else {
            2.0 * a[axis] / n[axis] as f32
        }
    };
    let (dx, dy, dz) = (step(0), step(1), step(2));
    // A collapsed axis (a plate) stands for one spacing of thickness.
    let cell = [dx, dy, dz]
        .iter()
        .map(|&d| if d > 0.0 { d } else { s })
        .product::<f32>();
    for i in 0..=n.x {
        for j in 0..=n.y {
            for k in 0..=n.z {
                let on_face = [(i, n.x), (j, n.y), (k, n.z)]
                    .iter()
                    .any(|&(c, m)| c == 0 || c == m);
                if !on_face {
                    continue;
                }
                let p = Vec3::new(
                    -a.x + i as f32 * dx,
                    -a.y + j as f32 * dy,
                    -a.z + k as f32 * dz,
                );
                // The outward normal: towards the faces the point lies on.
                let face = |c: u32, m: u32| -> f32 {
                    if m == 0 {
                        0.0
                    } else if c == 0 {
                        -1.0
                    } else if c == m {
                        1.0
                    } else {
                        0.0
                    }
                };
                let normal = Vec3::new(face(i, n.x), face(j, n.y), face(k, n.z));
                out.push(
                    p,
                    if normal == Vec3::ZERO {
                        Vec3::Y
                    } else {
                        normal
                    },
                );
                out.cell_volume.push(cell);
            }
        }
    }
}

/// A hemisphere of radius `r` on the side `side` (+1 / -1) of y, its equator at height `y0`:
/// rings of latitude about `s` apart along the arc, from the equator (left out with
/// `equator` = false) to the pole. A capsule's cap (its equator continues the side's rings,
/// [`cylinder_side`] without ends) or half a sphere. A Fibonacci lattice there left holes a
/// spacing wide at the caps' seams and at a sphere's poles, where particles slid in.
fn cap_rings(r: f32, side: f32, y0: f32, equator: bool, s: f32, out: &mut ShapeSamples) {
    let center = Vec3::Y * y0;
    if r <= 0.0 {
        // A point; a sphere's second half (no equator) adds nothing.
        if equator {
            out.push(center, Vec3::Y * side);
        }
        return;
    }
    let steps = ((0.5 * PI * r / s).round() as u32).max(1);
    for k in (!equator) as u32..=steps {
        let latitude = 0.5 * PI * k as f32 / steps as f32;
        let (sin, cos) = latitude.sin_cos();
        let per_ring = if k == steps {
            1
        } else {
            ((2.0 * PI * r * cos / s).round() as u32).max(3)
        };
        let shift = if k % 2 == 0 { 0.0 } else { 0.5 };
        for m in 0..per_ring {
            let phi = 2.0 * PI * (m as f32 + shift) / per_ring as f32;
            let normal = Vec3::new(cos * phi.cos(), side * sin, cos * phi.sin());
            out.push(center + normal * r, normal);
        }
    }
}

/// Rings of radius `r` along y in [-h, h], about `s` apart, each shifted half a step from the
/// last; `ends` includes the rings at ±h (a flat-capped cylinder), otherwise they are left to the
/// caps (a capsule's hemispheres start there).
fn cylinder_side(r: f32, h: f32, s: f32, ends: bool, out: &mut ShapeSamples) {
    if r <= 0.0 {
        return;
    }
    let rings = ((2.0 * h / s).ceil() as u32).max(1);
    let per_ring = ((2.0 * PI * r / s).round() as u32).max(3);
    let (first, last) = if ends { (0, rings) } else { (1, rings - 1) };
    for j in first..=last {
        let y = -h + 2.0 * h * j as f32 / rings as f32;
        let shift = if j % 2 == 0 { 0.0 } else { 0.5 };
        for k in 0..per_ring {
            let phi = 2.0 * PI * (k as f32 + shift) / per_ring as f32;
            let normal = Vec3::new(phi.cos(), 0.0, phi.sin());
            out.push(normal * r + Vec3::Y * y, normal);
        }
    }
}

/// Concentric rings filling the disc of radius `r` at height `y` (without its rim, which the
/// side's end ring holds), plus its centre; normals point away from the middle plane.
fn disc(r: f32, y: f32, s: f32, out: &mut ShapeSamples) {
    let normal = if y >= 0.0 { Vec3::Y } else { Vec3::NEG_Y };
    out.push(Vec3::Y * y, normal);
    let rings = (r / s).round() as u32;
    for k in 1..rings {
        let radius = r * k as f32 / rings as f32;
        let per_ring = ((2.0 * PI * radius / s).round() as u32).max(3);
        for m in 0..per_ring {
            let phi = 2.0 * PI * m as f32 / per_ring as f32;
            let p = Vec2::from_angle(phi) * radius;
            out.push(Vec3::new(p.x, y, p.y), normal);
        }
    }
}

/// The container's walls as boundary samples, in the world frame: the fluid lattice mirrored
/// through the floor and the four side walls, two layers deep (dx/2 and 3dx/2 outside each
/// wall, with the edges and corners filled), up to the top of the walls; the top stays open.
/// Along each axis the spacing is the container's size divided into whole cells of about
/// `spacing`, so a block spawned from the container's corner lies on the same lattice. Normals
/// point into the container. Returns the samples and the volume of one lattice cell [m³].
pub fn container_shell(container: &BoxContainer, spacing: f32) -> (ShapeSamples, f32) {
    let (lo, size) = (container.min(), container.size());
    let cells = (size / spacing).round().max(Vec3::ONE);
    let step = size / cells;
    let n = cells.as_ivec3();
    let mut out = ShapeSamples::default();
    for k in -2..n.z + 2 {
        for j in -2..n.y {
            for i in -2..n.x + 2 {
                let outside = glam::IVec3::new(
                    (i < 0) as i32 - (i >= n.x) as i32,
                    (j < 0) as i32,
                    (k < 0) as i32 - (k >= n.z) as i32,
                );
                if outside == glam::IVec3::ZERO {
                    continue;
                }
                let cell = glam::Vec3::new(i as f32, j as f32, k as f32) + 0.5;
                out.push(lo + cell * step, outside.as_vec3());
            }
        }
    }
    (out, step.x * step.y * step.z)
}

//! Triangle-mesh colliders (issue 11): a game's level geometry as a solid the fluid meets. A
//! mesh is either **closed** (watertight once coincident vertices are welded; its inside is the
//! solid, and its exact signed distance takes its sign from the angle-weighted pseudo-normal of
//! the closest feature, Bærentzen & Aanæs 2005, "Signed distance computation using the angle
//! weighted pseudonormal") or **open** (a sheet, a channel's floor, a terrain: a shell of a
//! given thickness around the surface, φ = |x − c| − t/2). Closest points come from Ericson's
//! region test (Real-Time Collision Detection §5.1.5) over a bounding-volume hierarchy
//! ([`crate::boundary::trimesh_bvh`]); the GPU guard walks the same hierarchy in the same order
//! ([`TriMesh::gpu_words`]).

use crate::boundary::collider_error::{ColliderError, MAX_COLLIDER_SIZE};
pub use crate::boundary::triangle::{closest_on_triangle, Feature, MeshTriangle};
use crate::boundary::trimesh_bvh::{Bvh, BvhNode};
use glam::Vec3;
use std::collections::HashMap;
use std::sync::Arc;

/// Largest number of triangles a mesh collider takes.
pub const MAX_MESH_TRIANGLES: usize = 1 << 20;

/// A triangle mesh as a collider shape, in its own frame. Build it with [`TriMesh::closed`],
/// [`TriMesh::open`] or [`TriMesh::new`]; share it with [`SharedTriMesh`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    /// The triangles, in the hierarchy's leaf order (degenerate ones dropped).
    triangles: Vec<MeshTriangle>,
    /// The hierarchy over `triangles`.
    bvh: Bvh,
    /// `None`: closed; `Some(t)`: an open shell of thickness t [m].
    thickness: Option<f32>,
    /// Largest distance of a vertex from the origin [m].
    bounding_radius: f32,
}

fn mesh_error(field: &'static str, value: String, allowed: &'static str) -> ColliderError {
    ColliderError {
        field,
        value,
        allowed,
    }
}

/// Vertices welded by position: a vertex within `tolerance` [m] of an earlier kept vertex maps
/// to it (a grid of `tolerance` cells, the 27 around each vertex searched).
fn weld(vertices: &[Vec3], tolerance: f32) -> (Vec<Vec3>, Vec<u32>) {
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    let (mut welded, mut remap) = (Vec::<Vec3>::new(), Vec::with_capacity(vertices.len()));
    for v in vertices {
        let key = (*v / tolerance).floor().as_i64vec3();
        let mut found = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let k = (key + glam::I64Vec3::new(dx, dy, dz)).to_array();
                    for &w in grid.get(&k).into_iter().flatten() {
                        if welded[w as usize].distance(*v) <= tolerance {
                            found = Some(w);
                            break 'search;
                        }
                    }
                }
            }
        }
        let w = found.unwrap_or_else(|| {
            welded.push(*v);
            let w = (welded.len() - 1) as u32;
            grid.entry(key.to_array()).or_default().push(w);
            w
        });
        remap.push(w);
    }
    (welded, remap)
}

/// Whether every directed edge appears once and its reverse once (watertight, consistently
/// oriented); the first edge that fails otherwise.
fn watertight(triangles: &[[u32; 3]]) -> Result<(), (u32, u32)> {
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    for t in triangles {
        for k in 0..3 {
            *directed.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &directed {
        if n != 1 || directed.get(&(b, a)) != Some(&1) {
            return Err((a, b));
        }
    }
    Ok(())
}

/// The angle at corner `k` of triangle `t`.
fn corner_angle(v: &[Vec3], t: &[u32; 3], k: usize) -> f32 {
    let p = v[t[k] as usize];
    let (e1, e2) = (
        v[t[(k + 1) % 3] as usize] - p,
        v[t[(k + 2) % 3] as usize] - p,
    );
    e1.angle_between(e2)
}

impl TriMesh {
    /// A closed mesh from `vertices` [m] and `indices` (three per triangle, any winding that is
    /// consistent; a mesh whose normals point inward is turned outward). Vertices closer than
    /// 1e-5 of the mesh's extent are welded first (a game mesh duplicates them at hard edges
    /// and seams). Refused when an index is
    /// out of range, a coordinate is not finite, the mesh is empty or larger than
    /// [`MAX_COLLIDER_SIZE`], or it is not watertight (the error names an open edge).
    pub fn closed(vertices: &[Vec3], indices: &[u32]) -> Result<Self, ColliderError> {
        Self::build(vertices, indices, None)
    }

    /// An open mesh: a shell of `thickness` [m] around the surface (in (0, 1000] m; about one
    /// particle spacing for a wall that water meets from either side).
    pub fn open(vertices: &[Vec3], indices: &[u32], thickness: f32) -> Result<Self, ColliderError> {
        if !(thickness.is_finite() && thickness > 0.0 && thickness <= MAX_COLLIDER_SIZE) {
            return Err(mesh_error(
                "shape.thickness",
                thickness.to_string(),
                "(0, 1000] m",
            ));
        }
        Self::build(vertices, indices, Some(thickness))
    }

    /// Closed when the mesh is watertight, otherwise open with `open_thickness` [m].
    pub fn new(
        vertices: &[Vec3],
        indices: &[u32],
        open_thickness: f32,
    ) -> Result<Self, ColliderError> {
        match Self::closed(vertices, indices) {
            Err(e) if e.field == "shape.triangles" => Self::open(vertices, indices, open_thickness),
            other => other,
        }
    }

    fn build(
        vertices: &[Vec3],
        indices: &[u32],
        thickness: Option<f32>,
    ) -> Result<Self, ColliderError> {
        if indices.is_empty() || !indices.len().is_multiple_of(3) {
            return Err(mesh_error(
                "shape.indices",
                format!("{} indices", indices.len()),
                "a positive multiple of 3 (three per triangle)",
            ));
        }
        if indices.len() / 3 > MAX_MESH_TRIANGLES {
            return Err(mesh_error(
                "shape.indices",
                format!("{} triangles", indices.len() / 3),
                "at most 1,048,576 triangles",
            ));
        }
        if let Some(&i) = indices.iter().find(|&&i| i as usize >= vertices.len()) {
            return Err(mesh_error(
                "shape.indices",
                i.to_string(),
                "an index below the vertex count",
            ));
        }
        if let Some(v) = vertices.iter().find(|v| !v.is_finite()) {
            return Err(mesh_error(
                "shape.vertices",
                format!("{v:?}"),
                "finite coordinates [m]",
            ));
        }
        let radius = vertices.iter().map(|v| v.length()).fold(0.0, f32::max);
        if radius > MAX_COLLIDER_SIZE {
            return Err(mesh_error(
                "shape.vertices",
                format!("{radius} m from the origin"),
                "within 1000 m of the mesh's origin",
            ));
        }
        let extent = vertices
            .iter()
            .fold(Vec3::ZERO, |m, v| m.max(v.abs()))
            .max_element()
            .max(1e-6);
        let (v, remap) = weld(vertices, 1e-5 * extent);
        let mut tris: Vec<[u32; 3]> = indices
            .chunks_exact(3)
            .map(|t| {
                [
                    remap[t[0] as usize],
                    remap[t[1] as usize],
                    remap[t[2] as usize],
                ]
            })
            // Triangles that weld to a point or an edge (a UV sphere's poles) have no area.
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
            .collect();
        if tris.is_empty() {
            return Err(mesh_error(
                "shape.indices",
                "only degenerate triangles".into(),
                "at least one triangle with area",
            ));
        }
        if thickness.is_none() {
            if let Err((a, b)) = watertight(&tris) {
                return Err(mesh_error(
                    "shape.triangles",
                    format!(
                        "the edge from {} to {} is open or shared unevenly",
                        v[a as usize], v[b as usize]
                    ),
                    "a watertight mesh for a closed collider (TriMesh::open for a sheet)",
                ));
            }
            // Signed volume (divergence theorem): negative when the winding points inward.
            let volume: f32 = tris
                .iter()
                .map(|t| v[t[0] as usize].dot(v[t[1] as usize].cross(v[t[2] as usize])) / 6.0)
                .sum();
            if volume < 0.0 {
                for t in &mut tris {
                    t.swap(1, 2);
                }
            }
        }
        Ok(Self::with_normals(&v, &tris, thickness, radius))
    }

    /// Computes the pseudo-normals and the hierarchy.
    fn with_normals(v: &[Vec3], tris: &[[u32; 3]], thickness: Option<f32>, radius: f32) -> Self {
        let face: Vec<Vec3> = tris
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| v[i as usize]);
                (b - a).cross(c - a).normalize_or_zero()
            })
            .collect();
        let mut vertex = vec![Vec3::ZERO; v.len()];
        let mut edge: HashMap<(u32, u32), Vec3> = HashMap::new();
        for (t, n) in tris.iter().zip(&face) {
            for k in 0..3 {
                vertex[t[k] as usize] += corner_angle(v, t, k) * *n;
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *edge.entry((a.min(b), a.max(b))).or_default() += *n;
            }
        }
        let triangles: Vec<MeshTriangle> = tris
            .iter()
            .zip(&face)
            .filter(|(_, n)| **n != Vec3::ZERO)
            .map(|(t, n)| {
                let e = |k: usize| {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    edge[&(a.min(b), a.max(b))].normalize_or(*n)
                };
                let vn = |k: usize| vertex[t[k] as usize].normalize_or(*n);
                MeshTriangle {
                    corners: t.map(|i| v[i as usize]),
                    pseudo_normals: [vn(0), vn(1), vn(2), e(0), e(1), e(2), *n],
                }
            })
            .collect();
        let (bvh, triangles) = Bvh::build(triangles);
        Self {
            triangles,
            bvh,
            thickness,
            bounding_radius: radius,
        }
    }

    /// The triangles, in the hierarchy's leaf order.
    pub fn triangles(&self) -> &[MeshTriangle] {
        &self.triangles
    }

    /// The hierarchy's nodes.
    pub fn nodes(&self) -> &[BvhNode] {
        self.bvh.nodes()
    }

    /// `None` for a closed mesh; the shell's thickness [m] for an open one.
    pub fn thickness(&self) -> Option<f32> {
        self.thickness
    }

    /// Largest distance of a vertex from the origin [m].
    pub fn bounding_radius(&self) -> f32 {
        self.bounding_radius + self.thickness.unwrap_or(0.0) * 0.5
    }

    /// Whether the local point `p` lies farther than `reach` [m] (at least 0) outside the mesh's
    /// root box and the shell around it: no surface point is then within `reach` of it, and with
    /// a reach of 0 the point is certainly outside the solid (the guard's early out before a
    /// closest-point query).
    pub fn beyond(&self, p: Vec3, reach: f32) -> bool {
        let far = 0.5 * self.thickness.unwrap_or(0.0) + reach.max(0.0);
        self.nodes()
            .first()
            .is_none_or(|root| root.distance_squared(p) > far * far)
    }

    /// The closest surface point to the local point `p`, its triangle and feature.
    pub fn closest(&self, p: Vec3) -> Option<(Vec3, usize, Feature)> {
        self.bvh.closest(p, &self.triangles)
    }

    /// Signed distance of the local point `p` [m] (negative inside) and the outward unit
    /// normal there (the distance's gradient; the feature's pseudo-normal on the surface).
    pub fn distance_and_normal(&self, p: Vec3) -> (f32, Vec3) {
        let Some((c, tri, f)) = self.closest(p) else {
            return (f32::INFINITY, Vec3::Y);
        };
        let pseudo = self.triangles[tri].pseudo_normals[f];
        let offset = p - c;
        let d = offset.length();
        match self.thickness {
            None => {
                let sign = if offset.dot(pseudo) < 0.0 { -1.0 } else { 1.0 };
                let n = if d > 1e-7 { sign * offset / d } else { pseudo };
                (sign * d, n)
            }
            Some(thickness) => {
                // On the mid surface either side will do: the face's own normal.
                let n = if d > 1e-7 {
                    offset / d
                } else {
                    self.triangles[tri].pseudo_normals[6]
                };
                (d - 0.5 * thickness, n)
            }
        }
    }

    /// Signed distance of the local point `p` [m], negative inside.
    pub fn signed_distance(&self, p: Vec3) -> f32 {
        self.distance_and_normal(p).0
    }

    /// The triangles as an indexed list (three vertices per triangle, unshared), e.g. for a
    /// physics engine's collider.
    pub fn indexed(&self) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let vertices = self.triangles.iter().flat_map(|t| t.corners).collect();
        let indices = (0..self.triangles.len() as u32)
            .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
            .collect();
        (vertices, indices)
    }

    /// The corners of each connected part (triangles joined through shared welded vertices), for
    /// a physics engine that wants convex pieces: a mesh of disjoint boxes gives each box.
    pub fn closed_parts(&self) -> Vec<Vec<Vec3>> {
        let n = self.triangles.len();
        let mut parent: Vec<usize> = (0..n).collect();
        fn root(parent: &mut [usize], mut k: usize) -> usize {
            while parent[k] != k {
                parent[k] = parent[parent[k]];
                k = parent[k];
            }
            k
        }
        let key = |v: Vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
        let mut first_at: HashMap<[u32; 3], usize> = HashMap::new();
        for (t, triangle) in self.triangles.iter().enumerate() {
            for &corner in &triangle.corners {
                let other = *first_at.entry(key(corner)).or_insert(t);
                let (a, b) = (root(&mut parent, t), root(&mut parent, other));
                parent[a] = b;
            }
        }
        let mut parts: HashMap<usize, Vec<Vec3>> = HashMap::new();
        for t in 0..n {
            let r = root(&mut parent, t);
            parts
                .entry(r)
                .or_default()
                .extend(self.triangles[t].corners);
        }
        let mut parts: Vec<(usize, Vec<Vec3>)> = parts.into_iter().collect();
        parts.sort_by_key(|(r, _)| *r);
        parts.into_iter().map(|(_, corners)| corners).collect()
    }

    /// The same mesh scaled per axis by `scale` (an open shell keeps its thickness); refused
    /// like a new mesh when the result is too large.
    pub fn scaled(&self, scale: Vec3) -> Result<Self, ColliderError> {
        let (vertices, indices) = self.indexed();
        let vertices: Vec<Vec3> = vertices.iter().map(|v| *v * scale).collect();
        let indices: Vec<u32> = indices.into_iter().flatten().collect();
        // A mirroring scale turns the winding over; `build` turns a closed mesh outward again.
        Self::build(&vertices, &indices, self.thickness)
    }

    /// The mesh for the GPU guard (WGSL `mesh_distance`): the nodes, two words each (min with
    /// w = the first child or triangle bit-cast, max with w = the triangle count bit-cast, 0 for
    /// an inner node), then per triangle its three corners and seven pseudo-normals.
    pub fn gpu_words(&self) -> Vec<[f32; 4]> {
        let mut out = Vec::with_capacity(self.nodes().len() * 2 + self.triangles.len() * 10);
        for n in self.nodes() {
            out.push([n.min.x, n.min.y, n.min.z, f32::from_bits(n.first)]);
            out.push([n.max.x, n.max.y, n.max.z, f32::from_bits(n.count)]);
        }
        for t in &self.triangles {
            for p in t.corners.iter().chain(&t.pseudo_normals) {
                out.push([p.x, p.y, p.z, 0.0]);
            }
        }
        out
    }
}

/// An icosphere of radius `r` subdivided `levels` times (20 · 4^levels triangles): vertices
/// and indices, counter-clockwise seen from outside, for tests, benchmarks and examples.
pub fn icosphere(r: f32, levels: u32) -> (Vec<Vec3>, Vec<u32>) {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut v: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut half = |a: u32, b: u32, v: &mut Vec<Vec3>| -> u32 {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                v.push(((v[a as usize] + v[b as usize]) / 2.0).normalize());
                (v.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(f.len() * 4);
        for [a, b, c] in f {
            let (ab, bc, ca) = (half(a, b, &mut v), half(b, c, &mut v), half(c, a, &mut v));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = next;
    }
    (
        v.into_iter().map(|p| p * r).collect(),
        f.into_iter().flatten().collect(),
    )
}

/// A mesh shared between colliders and copies of a shape (cheap to clone; equal when it is the
/// same mesh).
#[derive(Clone, Debug)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
#[cfg_attr(feature = "bevy_reflect", reflect(opaque, Debug, PartialEq))]
pub struct SharedTriMesh(pub Arc<TriMesh>);

impl PartialEq for SharedTriMesh {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

impl From<TriMesh> for SharedTriMesh {
    fn from(mesh: TriMesh) -> Self {
        Self(Arc::new(mesh))
    }
}

impl std::ops::Deref for SharedTriMesh {
    type Target = TriMesh;
    fn deref(&self) -> &TriMesh {
        &self.0
    }
}

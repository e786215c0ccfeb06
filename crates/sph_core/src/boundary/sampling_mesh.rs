//! Boundary samples of a triangle mesh (the Akinci 2012 boundary model for any shape, see
//! `docs/design_boundary_akinci2012.md` §4), called by `sampling::sample_shape`. The layers
//! follow the primitives' rule (the `depths` given, dx/2 and 3dx/2): a closed mesh gets its surface offset inward by dx/2 and
//! 3dx/2, an open mesh (a shell of thickness t) the same depths under both of its faces, or one
//! layer on its mid surface when t/2 ≤ dx/2. Each triangle is covered by a barycentric grid of
//! candidates finer than dx, offset along the face's normal; a candidate is kept when its depth
//! under the whole mesh is the layer's (so layers neither cross at convex edges nor pass the
//! medial axis of a thin part) and no kept sample of its layer lies within 0.9 dx (a maximal
//! Poisson-disc set, about one sample per dx², shared edges sampled once). The samples'
//! volumes come from Akinci's Σ W as for curved primitives.

use crate::boundary::trimesh::TriMesh;
use glam::{IVec3, Vec3};
use std::collections::HashMap;

/// Closest two samples of one layer, in spacings.
const MIN_DISTANCE: f32 = 0.9;

/// How far a kept sample's depth may differ from its layer's, in spacings.
const DEPTH_TOLERANCE: f32 = 0.3;

/// A layer: the offset along the face normal [m] (negative: into a closed mesh), the signed
/// distance its samples must have [m], and the side its normals face (+1 or -1).
struct Layer {
    offset: f32,
    depth: f32,
    side: f32,
}

fn layers(mesh: &TriMesh, depths: [f32; 2]) -> Vec<Layer> {
    match mesh.thickness() {
        None => depths
            .iter()
            .map(|&d| Layer {
                offset: -d,
                depth: -d,
                side: 1.0,
            })
            .collect(),
        Some(t) => {
            let half = 0.5 * t;
            let usable: Vec<f32> = depths.into_iter().filter(|&d| d < half).collect();
            if usable.is_empty() {
                return vec![Layer {
                    offset: 0.0,
                    depth: -half,
                    side: 1.0,
                }];
            }
            usable
                .iter()
                .flat_map(|&d| {
                    [1.0, -1.0].map(|side| Layer {
                        offset: side * (half - d),
                        depth: -d,
                        side,
                    })
                })
                .collect()
        }
    }
}

/// Samples of a mesh in its frame: positions and outward unit normals.
#[derive(Clone, Debug, Default)]
pub struct MeshSamples {
    /// Positions [m].
    pub position: Vec<Vec3>,
    /// Outward unit normals.
    pub normal: Vec<Vec3>,
}

impl MeshSamples {
    fn push(&mut self, p: Vec3, n: Vec3) {
        self.position.push(p);
        self.normal.push(n);
    }

    fn is_empty(&self) -> bool {
        self.position.is_empty()
    }
}

/// Samples `mesh` at particle spacing `spacing` in layers at `depths` [m], in its frame.
pub fn sample_mesh(mesh: &TriMesh, spacing: f32, depths: [f32; 2]) -> MeshSamples {
    let mut out = MeshSamples::default();
    for layer in layers(mesh, depths) {
        sample_layer(mesh, &layer, spacing, &mut out);
    }
    if out.is_empty() {
        // A closed mesh thinner than dx everywhere: one layer on its surface.
        let surface = Layer {
            offset: 0.0,
            depth: 0.0,
            side: 1.0,
        };
        sample_layer(mesh, &surface, spacing, &mut out);
    }
    out
}

fn sample_layer(mesh: &TriMesh, layer: &Layer, s: f32, out: &mut MeshSamples) {
    let r = MIN_DISTANCE * s;
    let mut grid: HashMap<IVec3, Vec<Vec3>> = HashMap::new();
    let cell = |p: Vec3| (p / r).floor().as_ivec3();
    let crowded = |grid: &HashMap<IVec3, Vec<Vec3>>, p: Vec3| {
        let c = cell(p);
        (-1..=1).any(|i| {
            (-1..=1).any(|j| {
                (-1..=1).any(|k| {
                    grid.get(&(c + IVec3::new(i, j, k)))
                        .is_some_and(|v| v.iter().any(|q| q.distance_squared(p) < r * r))
                })
            })
        })
    };
    for tri in mesh.triangles() {
        let [a, b, c] = tri.corners;
        let normal = tri.pseudo_normals[6];
        let longest = (b - a).length().max((c - b).length()).max((a - c).length());
        // Candidates at most dx/3 apart.
        let m = ((3.0 * longest / s).ceil() as u32).max(1);
        for i in 0..=m {
            for j in 0..=m - i {
                let (u, v) = (i as f32 / m as f32, j as f32 / m as f32);
                let p = a + (b - a) * u + (c - a) * v + normal * layer.offset;
                if crowded(&grid, p) {
                    continue;
                }
                let depth = mesh.signed_distance(p);
                if (depth - layer.depth).abs() > DEPTH_TOLERANCE * s {
                    continue;
                }
                grid.entry(cell(p)).or_default().push(p);
                out.push(p, normal * layer.side);
            }
        }
    }
}

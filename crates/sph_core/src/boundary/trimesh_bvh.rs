//! A bounding-volume hierarchy over a mesh's triangles for closest-point queries (the guard's
//! signed distance, the sampler's depth check): axis-aligned boxes, split at the median
//! centroid along the longest axis down to leaves of at most [`LEAF_SIZE`] triangles, so the
//! depth stays below 2 + log2(n) and a fixed stack of [`MAX_DEPTH`] suffices (the GPU guard's
//! too). The query visits the nearer child first and skips a box farther than the best point.

use crate::boundary::triangle::{closest_on_triangle, Feature, MeshTriangle};
use glam::Vec3;

/// Most triangles in a leaf.
pub const LEAF_SIZE: usize = 4;

/// The traversal stack's size (enough for 2^30 triangles).
pub const MAX_DEPTH: usize = 32;

/// A node: its box; a leaf holds `count` triangles from `first`, an inner node (`count` = 0)
/// has its children at `first` and `first + 1`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BvhNode {
    /// The box's low corner [m].
    pub min: Vec3,
    /// The box's high corner [m].
    pub max: Vec3,
    /// First child (inner) or first triangle (leaf).
    pub first: u32,
    /// Triangles in a leaf; 0 for an inner node.
    pub count: u32,
}

impl BvhNode {
    /// Squared distance from `p` to the box (0 inside).
    pub fn distance_squared(&self, p: Vec3) -> f32 {
        let d = (self.min - p).max(p - self.max).max(Vec3::ZERO);
        d.length_squared()
    }
}

/// The hierarchy.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh {
    nodes: Vec<BvhNode>,
}

fn bounds(tris: &[MeshTriangle]) -> (Vec3, Vec3) {
    tris.iter().flat_map(|t| t.corners).fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    )
}

impl Bvh {
    /// Builds the hierarchy; returns it and the triangles reordered into leaf order.
    pub fn build(mut triangles: Vec<MeshTriangle>) -> (Self, Vec<MeshTriangle>) {
        let mut nodes = vec![BvhNode::default()];
        if !triangles.is_empty() {
            let n = triangles.len();
            split(&mut nodes, 0, &mut triangles, 0, n);
        }
        (Self { nodes }, triangles)
    }

    /// The nodes, root first.
    pub fn nodes(&self) -> &[BvhNode] {
        &self.nodes
    }

    /// The closest point to `p` on `triangles` (the leaf order this hierarchy was built with),
    /// with its triangle and feature; `None` for an empty mesh.
    pub fn closest(&self, p: Vec3, triangles: &[MeshTriangle]) -> Option<(Vec3, usize, Feature)> {
        if triangles.is_empty() {
            return None;
        }
        let mut best: Option<(Vec3, usize, Feature)> = None;
        let mut best_d2 = f32::INFINITY;
        let mut stack = [0u32; MAX_DEPTH];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = self.nodes[stack[top] as usize];
            if node.distance_squared(p) >= best_d2 {
                continue;
            }
            if node.count > 0 {
                for k in node.first..node.first + node.count {
                    let (c, f) = closest_on_triangle(p, &triangles[k as usize].corners);
                    let d2 = (p - c).length_squared();
                    if d2 < best_d2 {
                        best_d2 = d2;
                        best = Some((c, k as usize, f));
                    }
                }
                continue;
            }
            let (a, b) = (node.first, node.first + 1);
            let (da, db) = (
                self.nodes[a as usize].distance_squared(p),
                self.nodes[b as usize].distance_squared(p),
            );
            // The nearer child goes on top, to be visited first.
            let (near, far) = if da <= db { (a, b) } else { (b, a) };
            if top + 2 <= MAX_DEPTH {
                stack[top] = far;
                stack[top + 1] = near;
                top += 2;
            }
        }
        best
    }
}

/// Fills node `at` with triangles [lo, hi) and recurses.
fn split(nodes: &mut Vec<BvhNode>, at: usize, tris: &mut [MeshTriangle], lo: usize, hi: usize) {
    let (min, max) = bounds(&tris[lo..hi]);
    if hi - lo <= LEAF_SIZE {
        nodes[at] = BvhNode {
            min,
            max,
            first: lo as u32,
            count: (hi - lo) as u32,
        };
        return;
    }
    let centroid = |t: &MeshTriangle| (t.corners[0] + t.corners[1] + t.corners[2]) / 3.0;
    let (cmin, cmax) = tris[lo..hi].iter().map(centroid).fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(a, b), c| (a.min(c), b.max(c)),
    );
    let extent = cmax - cmin;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let mid = lo + (hi - lo) / 2;
    tris[lo..hi].select_nth_unstable_by(mid - lo, |a, b| {
        centroid(a)[axis].total_cmp(&centroid(b)[axis])
    });
    let first = nodes.len();
    nodes.push(BvhNode::default());
    nodes.push(BvhNode::default());
    nodes[at] = BvhNode {
        min,
        max,
        first: first as u32,
        count: 0,
    };
    split(nodes, first, tris, lo, mid);
    split(nodes, first + 1, tris, mid, hi);
}

//! One mesh triangle with the pseudo-normals a signed distance needs, and the closest point on
//! it (Ericson, Real-Time Collision Detection §5.1.5): shared by [`crate::boundary::trimesh`] and its
//! hierarchy [`crate::boundary::trimesh_bvh`].

use glam::Vec3;

/// Where on a triangle the closest point lies: a vertex (0–2), an edge (3 = ab, 4 = bc,
/// 5 = ca) or the face (6); indexes [`MeshTriangle::pseudo_normals`].
pub type Feature = usize;

/// One triangle with what a distance query needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshTriangle {
    /// Corners a, b, c (counter-clockwise seen from outside for a closed mesh) [m].
    pub corners: [Vec3; 3],
    /// Angle-weighted pseudo-normals of the corners, the edges ab, bc, ca and the face, in
    /// [`Feature`] order (unit length).
    pub pseudo_normals: [Vec3; 7],
}

/// The closest point to `p` on the triangle `t` and its feature (Ericson §5.1.5).
pub fn closest_on_triangle(p: Vec3, t: &[Vec3; 3]) -> (Vec3, Feature) {
    let [a, b, c] = *t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, 0);
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (b, 1);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (a + ab * (d1 / (d1 - d3)), 3);
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (c, 2);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (a + ac * (d2 / (d2 - d6)), 5);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (c - b) * w, 4);
    }
    let denom = 1.0 / (va + vb + vc);
    (a + ab * (vb * denom) + ac * (vc * denom), 6)
}

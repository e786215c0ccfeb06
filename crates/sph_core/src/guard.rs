//! The last-resort guard (`docs/design/boundary_akinci2012.md` §4): the boundary samples should
//! keep every particle out of the solids; a particle found inside a collider anyway is projected
//! back onto its surface along the outward normal and loses the velocity that points into the
//! solid (relative to the solid's own), and a particle beyond the container's box is clamped by
//! [`Walls::collide`]. Every such correction is counted: the count is the measure of whether the
//! boundary model holds.

use crate::collider::Collider;
use crate::container::Walls;
use glam::Vec3;

/// What a drift phase checks after moving a particle.
#[derive(Clone, Copy, Debug)]
pub struct Guard<'a> {
    /// The container's box (clamp and damped reflection).
    pub walls: Walls,
    /// The colliders, in the world.
    pub colliders: &'a [Collider],
}

impl<'a> Guard<'a> {
    /// A guard of the box only.
    pub fn walls_only(walls: Walls) -> Self {
        Self {
            walls,
            colliders: &[],
        }
    }

    /// Moves a particle at `x` found inside a collider onto its surface and removes its velocity
    /// into the solid; clamps it into the box. Returns whether anything was corrected.
    #[inline]
    pub fn apply(&self, x: &mut Vec3, v: &mut Vec3) -> bool {
        let mut corrected = false;
        for c in self.colliders {
            let local = c.pose.to_local(*x);
            if local.length_squared() > c.bounding_radius() * c.bounding_radius() {
                continue;
            }
            let phi = c.shape.signed_distance(local);
            if phi >= 0.0 {
                continue;
            }
            let eps = 1e-4 * c.bounding_radius().max(1e-3);
            let n = c.pose.rotation * c.shape.normal(local, eps);
            *x += n * -phi;
            let into = (*v - c.point_velocity(*x)).dot(n);
            if into < 0.0 {
                *v -= n * into;
            }
            corrected = true;
        }
        let outside = x.cmplt(self.walls.min).any() || x.cmpgt(self.walls.max).any();
        self.walls.collide(x, v);
        corrected || outside
    }

    /// Whether `x` lies inside any collider (signed distance below `-tolerance`).
    pub fn inside_any(&self, x: Vec3, tolerance: f32) -> bool {
        self.colliders
            .iter()
            .any(|c| c.signed_distance(x) < -tolerance)
    }
}

//! The last-resort guard (`docs/design_boundary_akinci2012.md` §4): the boundary samples should
//! keep every particle out of the solids; a particle found inside a collider anyway is projected
//! back onto its surface along the outward normal and loses the velocity that points into the
//! solid (relative to the solid's own), and a particle beyond the container's box is clamped by
//! [`Walls::collide`]. Every such correction is counted: the count is the measure of whether the
//! boundary model holds.

use crate::boundary::collider::Collider;
use crate::container::Walls;
use glam::Vec3;

/// Particles the guard corrected: moved out of a collider, or clamped back into the box.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Corrections {
    /// Particles found inside a collider.
    pub colliders: u64,
    /// Particles found beyond the box's walls.
    pub walls: u64,
}

impl Corrections {
    /// Whether anything was corrected.
    pub fn any(&self) -> bool {
        self.colliders + self.walls > 0
    }

    /// All corrections.
    pub fn total(&self) -> u64 {
        self.colliders + self.walls
    }
}

impl std::ops::Add for Corrections {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            colliders: self.colliders + o.colliders,
            walls: self.walls + o.walls,
        }
    }
}

impl std::ops::AddAssign for Corrections {
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl std::iter::Sum for Corrections {
    fn sum<I: Iterator<Item = Self>>(iter: I) -> Self {
        iter.fold(Self::default(), |a, b| a + b)
    }
}

/// What a drift phase checks after moving a particle.
#[derive(Clone, Copy, Debug)]
pub struct Guard<'a> {
    /// The container's box (clamp and damped reflection).
    pub walls: Walls,
    /// The colliders, in the world.
    pub colliders: &'a [Collider],
    /// How deep inside a collider a particle must be to count as inside [m]: a particle resting
    /// on a collider's edge sits at φ ≈ 0, and rounding puts it a few ulps inside.
    pub tolerance: f32,
}

/// The guard's tolerance for particle spacing `spacing`: a thousandth of it.
pub fn tolerance(spacing: f32) -> f32 {
    1e-3 * spacing
}

impl<'a> Guard<'a> {
    /// Moves a particle at `x` found inside a collider onto its surface and removes its velocity
    /// into the solid; clamps it into the box. Returns what was corrected.
    #[inline]
    pub fn apply(&self, x: &mut Vec3, v: &mut Vec3) -> Corrections {
        let mut corrected = false;
        for c in self.colliders {
            let Some((phi, n)) = c.surface_within(*x, -self.tolerance) else {
                continue;
            };
            *x += n * -phi;
            let into = (*v - c.point_velocity(*x)).dot(n);
            if into < 0.0 {
                *v -= n * into;
            }
            corrected = true;
        }
        let outside = x.cmplt(self.walls.min).any() || x.cmpgt(self.walls.max).any();
        self.walls.collide(x, v);
        Corrections {
            colliders: corrected as u64,
            walls: outside as u64,
        }
    }

    /// Whether `x` lies inside any collider (signed distance below `-tolerance`).
    pub fn inside_any(&self, x: Vec3, tolerance: f32) -> bool {
        self.colliders
            .iter()
            .any(|c| c.signed_distance(x) < -tolerance)
    }
}

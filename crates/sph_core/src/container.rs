//! The box container: a floor plate (centre, size) and a wall height, with the design's damped
//! wall collision.

use crate::params::{check_range, ParamError};
use glam::{Vec2, Vec3};

/// An axis-aligned box standing on a floor plate; y is up.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub struct BoxContainer {
    /// Centre of the floor plate [m]; the floor is at `floor_center.y`.
    pub floor_center: Vec3,
    /// Floor plate size along x and z [m].
    pub floor_size: Vec2,
    /// Height of the walls above the floor [m].
    pub wall_height: f32,
}

impl BoxContainer {
    /// A box whose walls are computed from the floor plate.
    pub fn from_floor(floor_center: Vec3, floor_size: Vec2, wall_height: f32) -> Self {
        Self {
            floor_center,
            floor_size,
            wall_height,
        }
    }

    /// A box spanning `min..max` (the floor is at `min.y`).
    pub fn from_min_max(min: Vec3, max: Vec3) -> Self {
        let size = max - min;
        Self {
            floor_center: Vec3::new(min.x + 0.5 * size.x, min.y, min.z + 0.5 * size.z),
            floor_size: Vec2::new(size.x, size.z),
            wall_height: size.y,
        }
    }

    /// Lower corner.
    pub fn min(&self) -> Vec3 {
        self.floor_center - Vec3::new(0.5 * self.floor_size.x, 0.0, 0.5 * self.floor_size.y)
    }

    /// Upper corner.
    pub fn max(&self) -> Vec3 {
        self.floor_center
            + Vec3::new(
                0.5 * self.floor_size.x,
                self.wall_height,
                0.5 * self.floor_size.y,
            )
    }

    /// Extent max - min.
    pub fn size(&self) -> Vec3 {
        Vec3::new(self.floor_size.x, self.wall_height, self.floor_size.y)
    }

    /// Whether `p` lies inside the box, allowing `tolerance` metres outside.
    pub fn contains(&self, p: Vec3, tolerance: f32) -> bool {
        let (lo, hi) = (self.min() - tolerance, self.max() + tolerance);
        p.cmpge(lo).all() && p.cmple(hi).all()
    }

    /// Checks the floor size and wall height (finite, > 0, <= 1e4 m) and the centre (finite).
    pub fn validate(&self) -> Result<(), ParamError> {
        if !self.floor_center.is_finite() {
            return Err(ParamError {
                field: "container.floor_center",
                value: format!("{}", self.floor_center),
                allowed: "finite",
            });
        }
        let allowed = "(0, 1e4] m";
        check_range(
            "container.floor_size.x",
            self.floor_size.x,
            0.0,
            false,
            1.0e4,
            allowed,
        )?;
        check_range(
            "container.floor_size.y",
            self.floor_size.y,
            0.0,
            false,
            1.0e4,
            allowed,
        )?;
        check_range(
            "container.wall_height",
            self.wall_height,
            0.0,
            false,
            1.0e4,
            allowed,
        )
    }

    /// The walls with their damping, ready for [`Walls::collide`].
    pub fn walls(&self, damping: f32) -> Walls {
        Walls {
            min: self.min(),
            max: self.max(),
            damping,
        }
    }
}

/// The six walls of a [`BoxContainer`] and the fraction of normal velocity kept on a bounce.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Walls {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
    /// Fraction of the normal velocity kept after a bounce, in [0, 1].
    pub damping: f32,
}

impl Walls {
    /// The design's wall collision: clamp the position into the box and, at a wall, reflect the
    /// velocity's outward normal component scaled by the damping (1 = elastic, 0 = stop).
    #[inline]
    pub fn collide(&self, x: &mut Vec3, v: &mut Vec3) {
        for axis in 0..3 {
            if x[axis] <= self.min[axis] {
                x[axis] = self.min[axis];
                if v[axis] < 0.0 {
                    v[axis] = -v[axis] * self.damping;
                }
            } else if x[axis] >= self.max[axis] {
                x[axis] = self.max[axis];
                if v[axis] > 0.0 {
                    v[axis] = -v[axis] * self.damping;
                }
            }
        }
    }
}

impl Default for BoxContainer {
    /// A 1 m x 1 m floor with 1 m walls, centred at the origin.
    fn default() -> Self {
        Self::from_floor(Vec3::ZERO, Vec2::ONE, 1.0)
    }
}

//! An oriented box in the world: the volume of a sink, a pump or a counting probe.

use crate::boundary::collider::Pose;
use crate::params::ParamError;
use glam::Vec3;

/// A box of half extents `half_extents` in the frame of `pose` (the box's centre and
/// orientation).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub struct Region {
    /// The box's centre and orientation.
    pub pose: Pose,
    /// Half extents along the box's own axes [m].
    pub half_extents: Vec3,
}

impl Region {
    /// An axis-aligned box from its corners.
    pub fn from_min_max(min: Vec3, max: Vec3) -> Self {
        Self {
            pose: Pose {
                translation: (min + max) * 0.5,
                ..Pose::default()
            },
            half_extents: (max - min) * 0.5,
        }
    }

    /// Checks the pose and that every half extent is positive and finite; `field` prefixes the
    /// field named in the error (e.g. `"SphSink"`).
    pub fn validate(&self, field: &'static str) -> Result<(), ParamError> {
        if let Err(e) = self.pose.validate() {
            return Err(ParamError {
                field,
                value: format!("{}: {}", e.field, e.value),
                allowed: e.allowed,
            });
        }
        let h = self.half_extents;
        if !(h.is_finite() && h.min_element() > 0.0) {
            return Err(ParamError {
                field,
                value: format!("half_extents {h:?}"),
                allowed: "half extents > 0 and finite [m]",
            });
        }
        Ok(())
    }

    /// Whether the world point `x` lies inside (or on) the box.
    #[inline]
    pub fn contains(&self, x: Vec3) -> bool {
        self.pose.to_local(x).abs().cmple(self.half_extents).all()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    #[test]
    fn a_rotated_box_contains_its_own_corners_only() {
        let region = Region {
            pose: Pose {
                translation: Vec3::new(1.0, 0.0, 0.0),
                rotation: Quat::from_rotation_y(std::f32::consts::FRAC_PI_2),
            },
            half_extents: Vec3::new(0.5, 0.1, 0.05),
        };
        // Local x is world -z after a quarter turn about y.
        assert!(region.contains(Vec3::new(1.0, 0.0, -0.49)));
        assert!(!region.contains(Vec3::new(1.49, 0.0, 0.0)));
        assert!(region.validate("r").is_ok());
        let flat = Region {
            half_extents: Vec3::new(0.5, 0.0, 0.1),
            ..region
        };
        let e = flat.validate("SphSink").unwrap_err();
        assert_eq!(e.field, "SphSink");
        assert!(e.value.contains("half_extents"), "{e}");
    }
}

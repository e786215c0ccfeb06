//! Solid shapes the fluid meets (groundwork for the Akinci 2012 boundary model, see
//! `docs/design/boundary_akinci2012.md`): primitive shapes in their own frame (y is the axis of
//! capsules and cylinders), a rigid pose, validation that names the field, the value and the
//! allowed range, and exact signed distances (negative inside) for the guard that projects
//! particles out of solids and for the sampling tests.

use glam::{Quat, Vec3};
use std::fmt;

/// Largest size of a collider along any axis [m].
pub const MAX_COLLIDER_SIZE: f32 = 1.0e3;

/// A primitive solid in its own frame, centred on the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub enum ColliderShape {
    /// A box with these half extents [m].
    Cuboid {
        /// Half extents along x, y, z [m].
        half_extents: Vec3,
    },
    /// A ball.
    Sphere {
        /// Radius [m].
        radius: f32,
    },
    /// A cylinder with hemispherical caps, along y.
    Capsule {
        /// Radius [m].
        radius: f32,
        /// Half the length of the cylindrical part [m].
        half_length: f32,
    },
    /// A flat-capped cylinder along y.
    Cylinder {
        /// Radius [m].
        radius: f32,
        /// Half the height [m].
        half_length: f32,
    },
}

/// A collider shape or pose outside its allowed range: names the field, the value and the range.
#[derive(Clone, Debug, PartialEq)]
pub struct ColliderError {
    /// The field, e.g. `shape.radius`.
    pub field: &'static str,
    /// The offending value, formatted.
    pub value: String,
    /// What is allowed.
    pub allowed: &'static str,
}

impl fmt::Display for ColliderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "invalid collider `{}` = {}: allowed {}",
            self.field, self.value, self.allowed
        )
    }
}

impl std::error::Error for ColliderError {}

fn size(field: &'static str, value: f32) -> Result<(), ColliderError> {
    if value.is_finite() && value > 0.0 && value <= MAX_COLLIDER_SIZE {
        Ok(())
    } else {
        Err(ColliderError {
            field,
            value: value.to_string(),
            allowed: "(0, 1000] m",
        })
    }
}

impl ColliderShape {
    /// Checks every size: finite, positive, at most [`MAX_COLLIDER_SIZE`].
    pub fn validate(&self) -> Result<(), ColliderError> {
        match *self {
            Self::Cuboid { half_extents: h } => {
                size("shape.half_extents.x", h.x)?;
                size("shape.half_extents.y", h.y)?;
                size("shape.half_extents.z", h.z)
            }
            Self::Sphere { radius } => size("shape.radius", radius),
            Self::Capsule {
                radius,
                half_length,
            }
            | Self::Cylinder {
                radius,
                half_length,
            } => {
                size("shape.radius", radius)?;
                size("shape.half_length", half_length)
            }
        }
    }

    /// Signed distance of the local point `p` to the surface [m]: negative inside, exact.
    pub fn signed_distance(&self, p: Vec3) -> f32 {
        match *self {
            Self::Cuboid { half_extents } => {
                let q = p.abs() - half_extents;
                q.max(Vec3::ZERO).length() + q.max_element().min(0.0)
            }
            Self::Sphere { radius } => p.length() - radius,
            Self::Capsule {
                radius,
                half_length,
            } => {
                let axis = Vec3::new(0.0, p.y.clamp(-half_length, half_length), 0.0);
                (p - axis).length() - radius
            }
            Self::Cylinder {
                radius,
                half_length,
            } => {
                let d = glam::Vec2::new(
                    glam::Vec2::new(p.x, p.z).length() - radius,
                    p.y.abs() - half_length,
                );
                d.max_element().min(0.0) + d.max(glam::Vec2::ZERO).length()
            }
        }
    }
}

/// Where a collider is: a rigid transform from its frame to the world.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub struct Pose {
    /// Position of the shape's origin [m].
    pub translation: Vec3,
    /// Orientation (unit quaternion).
    pub rotation: Quat,
}

impl Default for Pose {
    fn default() -> Self {
        Self {
            translation: Vec3::ZERO,
            rotation: Quat::IDENTITY,
        }
    }
}

impl Pose {
    /// Checks for non-finite values and a rotation that is not a unit quaternion.
    pub fn validate(&self) -> Result<(), ColliderError> {
        if !self.translation.is_finite() {
            return Err(ColliderError {
                field: "pose.translation",
                value: format!("{:?}", self.translation),
                allowed: "finite coordinates [m]",
            });
        }
        if !self.rotation.is_finite() || (self.rotation.length() - 1.0).abs() > 1e-3 {
            return Err(ColliderError {
                field: "pose.rotation",
                value: format!("{:?}", self.rotation),
                allowed: "a finite unit quaternion",
            });
        }
        Ok(())
    }

    /// The world position of the local point `p`.
    pub fn to_world(&self, p: Vec3) -> Vec3 {
        self.translation + self.rotation * p
    }

    /// The local position of the world point `x`.
    pub fn to_local(&self, x: Vec3) -> Vec3 {
        self.rotation.inverse() * (x - self.translation)
    }
}

/// A shape at a pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlacedShape {
    /// The shape in its frame.
    pub shape: ColliderShape,
    /// Its pose.
    pub pose: Pose,
}

impl PlacedShape {
    /// Checks the shape and the pose.
    pub fn validate(&self) -> Result<(), ColliderError> {
        self.shape.validate()?;
        self.pose.validate()
    }

    /// Signed distance of the world point `x` [m], negative inside.
    pub fn signed_distance(&self, x: Vec3) -> f32 {
        self.shape.signed_distance(self.pose.to_local(x))
    }
}

//! The error of a collider shape, pose or mesh outside its allowed range, and the largest size a
//! collider may have (shared by [`crate::boundary::collider`] and [`crate::boundary::trimesh`]).

use std::fmt;

/// Largest size of a collider along any axis [m].
pub const MAX_COLLIDER_SIZE: f32 = 1.0e3;

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

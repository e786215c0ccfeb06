//! A paddle wheel as a collider (issue 14's Aquaplay water wheel): flat paddles around an axle
//! along the local z axis, each a box apart from the others, given to the fluid as one closed
//! [`TriMesh`] of several closed parts (a physics engine can take each part as a convex box).

use crate::boundary::collider_error::{ColliderError, MAX_COLLIDER_SIZE};
use crate::boundary::trimesh::TriMesh;
use glam::{Quat, Vec3};

/// The most paddles a wheel may have.
pub const MAX_PADDLES: u32 = 32;

/// A paddle wheel about the local z axis: `paddles` boxes evenly around the axle, each reaching
/// from `inner` to `outer` [m] from it, `thickness` [m] thick and `width` [m] wide along it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaddleWheel {
    /// Number of paddles, 2 ..= [`MAX_PADDLES`].
    pub paddles: u32,
    /// Where the paddles start, from the axle [m], >= 0.
    pub inner: f32,
    /// Where they end [m], > inner.
    pub outer: f32,
    /// Paddle thickness [m], > 0.
    pub thickness: f32,
    /// Paddle width along the axle [m], > 0.
    pub width: f32,
}

impl PaddleWheel {
    /// Checks every field; the error names the first one out of range.
    pub fn validate(&self) -> Result<(), ColliderError> {
        let positive = |v: f32| v.is_finite() && v > 0.0 && v <= MAX_COLLIDER_SIZE;
        if !(2..=MAX_PADDLES).contains(&self.paddles) {
            return Err(ColliderError {
                field: "shape.paddles",
                value: self.paddles.to_string(),
                allowed: "2 ..= 32 paddles",
            });
        }
        if !(self.inner.is_finite() && self.inner >= 0.0 && self.inner < self.outer) {
            return Err(ColliderError {
                field: "shape.inner",
                value: self.inner.to_string(),
                allowed: ">= 0 m and below `outer`",
            });
        }
        for (field, value) in [
            ("shape.outer", self.outer),
            ("shape.thickness", self.thickness),
            ("shape.width", self.width),
        ] {
            if !positive(value) {
                return Err(ColliderError {
                    field,
                    value: value.to_string(),
                    allowed: "(0, 1000] m",
                });
            }
        }
        Ok(())
    }

    /// Each paddle as a box: its centre and rotation in the wheel's frame, and its half extents.
    pub fn boxes(&self) -> Vec<(Vec3, Quat, Vec3)> {
        let half = Vec3::new(
            0.5 * (self.outer - self.inner),
            0.5 * self.thickness,
            0.5 * self.width,
        );
        (0..self.paddles)
            .map(|k| {
                let rotation =
                    Quat::from_rotation_z(std::f32::consts::TAU * k as f32 / self.paddles as f32);
                let centre = rotation * Vec3::new(0.5 * (self.inner + self.outer), 0.0, 0.0);
                (centre, rotation, half)
            })
            .collect()
    }

    /// The wheel as one closed mesh (its paddles are its closed parts); refused like
    /// [`Self::validate`], or when paddles overlap (too thick for their number at `inner`).
    pub fn mesh(&self) -> Result<TriMesh, ColliderError> {
        self.validate()?;
        let (mut vertices, mut indices) = (Vec::new(), Vec::new());
        for (centre, rotation, half) in self.boxes() {
            let base = vertices.len() as u32;
            for z in [-1.0, 1.0] {
                for (x, y) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    vertices.push(centre + rotation * (Vec3::new(x, y, z) * half));
                }
            }
            // The six faces, counter-clockwise seen from outside.
            let quad = |a: u32, b: u32, c: u32, d: u32| [a, b, c, a, c, d].map(|i| base + i);
            for face in [
                quad(0, 3, 2, 1),
                quad(4, 5, 6, 7),
                quad(0, 1, 5, 4),
                quad(1, 2, 6, 5),
                quad(2, 3, 7, 6),
                quad(3, 0, 4, 7),
            ] {
                indices.extend(face);
            }
        }
        // Neighbouring paddles, 2π/n apart, must not overlap at their inner ends: the corner
        // (inner, t/2) of one lies outside the next while t < 2 inner tan(π/n).
        // Two paddles point opposite ways: they meet only at the axle.
        let room = match self.paddles {
            2 if self.inner > 0.0 => f32::INFINITY,
            2 => 0.0,
            n => 2.0 * self.inner * (std::f32::consts::PI / n as f32).tan(),
        };
        if self.thickness >= room {
            return Err(ColliderError {
                field: "shape.thickness",
                value: self.thickness.to_string(),
                allowed: "below 2 inner tan(π / paddles), where neighbouring paddles meet",
            });
        }
        TriMesh::closed(&vertices, &indices)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wheel() -> PaddleWheel {
        PaddleWheel {
            paddles: 6,
            inner: 0.02,
            outer: 0.1,
            thickness: 0.02,
            width: 0.14,
        }
    }

    #[test]
    fn the_mesh_is_the_paddles() {
        let mesh = wheel().mesh().unwrap();
        // Inside a paddle, outside between paddles and beyond the rim.
        let (d, _) = mesh.distance_and_normal(Vec3::new(0.06, 0.0, 0.0));
        assert!(d < -0.009, "{d}");
        let between =
            Quat::from_rotation_z(std::f32::consts::TAU / 12.0) * Vec3::new(0.06, 0.0, 0.0);
        assert!(mesh.distance_and_normal(between).0 > 0.0);
        assert!(mesh.distance_and_normal(Vec3::new(0.12, 0.0, 0.0)).0 > 0.019);
        assert_eq!(mesh.closed_parts().len(), 6);
        let two = PaddleWheel {
            paddles: 2,
            ..wheel()
        };
        assert_eq!(two.mesh().unwrap().closed_parts().len(), 2);
    }

    #[test]
    fn bad_wheels_are_named() {
        for (bad, field) in [
            (
                PaddleWheel {
                    paddles: 1,
                    ..wheel()
                },
                "shape.paddles",
            ),
            (
                PaddleWheel {
                    inner: 0.2,
                    ..wheel()
                },
                "shape.inner",
            ),
            (
                PaddleWheel {
                    thickness: f32::NAN,
                    ..wheel()
                },
                "shape.thickness",
            ),
            (
                PaddleWheel {
                    width: 0.0,
                    ..wheel()
                },
                "shape.width",
            ),
            // Six paddles 5 cm thick touch 2 cm from the axle.
            (
                PaddleWheel {
                    thickness: 0.05,
                    ..wheel()
                },
                "shape.thickness",
            ),
            (
                PaddleWheel {
                    paddles: 2,
                    inner: 0.0,
                    ..wheel()
                },
                "shape.thickness",
            ),
        ] {
            assert_eq!(bad.mesh().unwrap_err().field, field, "{bad:?}");
        }
    }
}

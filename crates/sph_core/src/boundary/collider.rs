//! Solid shapes the fluid meets (the Akinci 2012 boundary model, see
//! `docs/design_boundary_akinci2012.md`): primitive shapes in their own frame (y is the axis of
//! capsules and cylinders), a rigid pose, how a collider moves (static, kinematic, dynamic) and
//! how the fluid slides along it (free slip or no slip), validation that names the field, the
//! value and the allowed range, and exact signed distances (negative inside) for the guard that
//! projects particles out of solids. Triangle meshes live in [`crate::boundary::trimesh`].

pub use crate::boundary::collider_error::{ColliderError, MAX_COLLIDER_SIZE};
use crate::boundary::trimesh::SharedTriMesh;
use glam::{Quat, Vec3};

/// A solid in its own frame: a primitive centred on the origin, or a triangle mesh.
#[derive(Clone, Debug, PartialEq)]
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
    /// A triangle mesh, closed (a solid) or open (a shell of a thickness): [`crate::TriMesh`].
    TriMesh(SharedTriMesh),
}

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
            // Checked when the mesh was built.
            Self::TriMesh(_) => Ok(()),
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
            Self::TriMesh(ref mesh) => mesh.signed_distance(p),
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
#[derive(Clone, Debug, PartialEq)]
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

/// How a collider moves.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub enum ColliderMotion {
    /// Never moves; the fluid's force on it is still measured.
    #[default]
    Static,
    /// Moved by the game: its pose and velocity are set every step or frame, the fluid sees the
    /// velocity (Akinci 2012: v_b = v + ω × (x_b − x_c)), and it does not feel the fluid.
    Kinematic,
    /// Moved by the game or a physics engine that applies the fluid's force and torque on it
    /// (two-way coupling, Akinci 2012); the fluid sees its pose and velocity like a kinematic
    /// collider's.
    Dynamic,
}

/// How the fluid slides along a collider (Akinci 2012).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub enum Slip {
    /// Free slip: the boundary exerts pressure only, normal to the surface.
    Free,
    /// No slip: the fluid's viscosity term also acts between fluid and boundary samples, times
    /// `friction` (1 = the fluid's own viscosity). PBF's viscosity is XSPH: there the samples
    /// count as water moving with the body, with XSPH's c times `friction`
    /// (`sph_core::solver::pbf::xsph_vorticity::wall_friction`).
    NoSlip {
        /// Factor on the fluid's viscosity μ (PBF: on XSPH's c) for fluid-boundary pairs, in
        /// [0, 100].
        friction: f32,
    },
}

impl Default for Slip {
    /// Free slip: water's own friction at a wall is far below what the fluid's artificial
    /// viscosity would apply at a no-slip wall (a dam break's front then lags the experiment).
    fn default() -> Self {
        Self::Free
    }
}

impl Slip {
    /// The factor on μ for fluid-boundary pairs: 0 for free slip.
    pub fn friction(&self) -> f32 {
        match *self {
            Self::Free => 0.0,
            Self::NoSlip { friction } => friction,
        }
    }

    /// Checks the friction factor: finite, in [0, 100].
    pub fn validate(&self) -> Result<(), ColliderError> {
        let f = self.friction();
        if f.is_finite() && (0.0..=100.0).contains(&f) {
            Ok(())
        } else {
            Err(ColliderError {
                field: "slip.friction",
                value: f.to_string(),
                allowed: "[0, 100] (times the fluid's viscosity)",
            })
        }
    }
}

/// A solid the fluid meets: a shape at a pose, with its velocity, its motion kind and its slip.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub struct Collider {
    /// The shape in its own frame.
    pub shape: ColliderShape,
    /// Where it is.
    pub pose: Pose,
    /// Velocity of the shape's origin [m/s] (kinematic and dynamic colliders).
    pub linear_velocity: Vec3,
    /// Angular velocity about the shape's origin [rad/s] (kinematic and dynamic colliders).
    pub angular_velocity: Vec3,
    /// How it moves.
    pub motion: ColliderMotion,
    /// How the fluid slides along it.
    pub slip: Slip,
}

impl Collider {
    /// A static, free-slip collider.
    pub fn new(shape: ColliderShape, pose: Pose) -> Self {
        Self {
            shape,
            pose,
            linear_velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
            motion: ColliderMotion::Static,
            slip: Slip::default(),
        }
    }

    /// The same collider with motion kind `motion`.
    pub fn with_motion(mut self, motion: ColliderMotion) -> Self {
        self.motion = motion;
        self
    }

    /// The same collider with slip `slip`.
    pub fn with_slip(mut self, slip: Slip) -> Self {
        self.slip = slip;
        self
    }

    /// Checks the shape, the pose, the velocities (finite) and the slip.
    pub fn validate(&self) -> Result<(), ColliderError> {
        self.shape.validate()?;
        self.pose.validate()?;
        for (field, v) in [
            ("linear_velocity", self.linear_velocity),
            ("angular_velocity", self.angular_velocity),
        ] {
            if !v.is_finite() {
                return Err(ColliderError {
                    field,
                    value: format!("{v:?}"),
                    allowed: "finite components",
                });
            }
        }
        self.slip.validate()
    }

    /// Signed distance of the world point `x` [m], negative inside.
    pub fn signed_distance(&self, x: Vec3) -> f32 {
        self.shape.signed_distance(self.pose.to_local(x))
    }

    /// The signed distance [m] (negative inside) and the outward normal in the world of the
    /// surface seen from the world point `x`, when it is closer than `reach` [m]; `None` beyond,
    /// found without a distance where the bounding sphere or a mesh's root box is farther. The
    /// guard (reach: minus its tolerance, [`crate::boundary::guard`]) and the speculative contact
    /// ([`crate::boundary::speculative_contact`]) share it; WGSL twin `collider_surface` in guard.wgsl.
    pub fn surface_within(&self, x: Vec3, reach: f32) -> Option<(f32, Vec3)> {
        let local = self.pose.to_local(x);
        let bound = (self.bounding_radius() + reach).max(0.0);
        if local.length_squared() > bound * bound {
            return None;
        }
        let eps = 1e-4 * self.bounding_radius().max(1e-3);
        let (phi, n) = match &self.shape {
            ColliderShape::TriMesh(mesh) => {
                if mesh.beyond(local, reach) {
                    return None;
                }
                mesh.distance_and_normal(local)
            }
            shape => {
                // The normal only where the surface is within reach.
                let phi = shape.signed_distance(local);
                if phi >= reach {
                    return None;
                }
                (phi, shape.normal(local, eps))
            }
        };
        (phi < reach).then(|| (phi, self.pose.rotation * n))
    }

    /// The velocity of the solid at the world point `x`: v + ω × (x − x_c) (zero when static).
    pub fn point_velocity(&self, x: Vec3) -> Vec3 {
        match self.motion {
            ColliderMotion::Static => Vec3::ZERO,
            _ => self.linear_velocity + self.angular_velocity.cross(x - self.pose.translation),
        }
    }

    /// The radius of a sphere around the pose's origin that holds the shape [m].
    pub fn bounding_radius(&self) -> f32 {
        self.shape.bounding_radius()
    }
}

impl ColliderShape {
    /// The radius of a sphere around the origin that holds the shape [m].
    pub fn bounding_radius(&self) -> f32 {
        match *self {
            Self::Cuboid { half_extents } => half_extents.length(),
            Self::Sphere { radius } => radius,
            Self::Capsule {
                radius,
                half_length,
            } => radius + half_length,
            Self::Cylinder {
                radius,
                half_length,
            } => (radius * radius + half_length * half_length).sqrt(),
            Self::TriMesh(ref mesh) => mesh.bounding_radius(),
        }
    }

    /// The outward unit normal at the local point `p`, from the signed distance's central
    /// differences (step `eps` [m]); +y where the gradient vanishes.
    pub fn normal(&self, p: Vec3, eps: f32) -> Vec3 {
        if let Self::TriMesh(mesh) = self {
            // The exact gradient: no extra closest-point queries.
            return mesh.distance_and_normal(p).1;
        }
        let d = |e: Vec3| self.signed_distance(p + e) - self.signed_distance(p - e);
        Vec3::new(d(Vec3::X * eps), d(Vec3::Y * eps), d(Vec3::Z * eps)).normalize_or(Vec3::Y)
    }
}

//! Probes: what the water does at a place, for game logic and for `sph-bench`.
//!
//! - **Level** at an (x, z) point: the top of the water column, the highest particle centre
//!   within `radius` of the vertical line plus half a spacing (a particle's own thickness).
//! - **Flux** through a rectangle [m³/s]: the particles in a slab of thickness d = 2 Δx around
//!   the rectangle carry Q = (V / d) Σ v_i·n, V = m/ρ0 each. A uniform flow of speed u through
//!   a full rectangle of area A gives Q = u A: the slab holds A d / V particles.
//! - **Count** of the particles inside a box.

use crate::collider::Pose;
use crate::params::{ParamError, SphParams};
use crate::region::Region;
use glam::Vec3;

/// What a probe measures.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub enum ProbeKind {
    /// The water level at (x, z) [m, world y].
    Level {
        /// World x [m].
        x: f32,
        /// World z [m].
        z: f32,
        /// Horizontal radius of the column searched [m] (> 0; about two spacings is right).
        radius: f32,
    },
    /// The volume flux through a rectangle: centred on `pose`, spanning ±`half_size` along the
    /// pose's local x and y, with the normal along its local z [m³/s].
    Flux {
        /// Centre and orientation (normal = local z).
        pose: Pose,
        /// Half width (local x) and half height (local y) [m].
        half_size: [f32; 2],
    },
    /// The particles inside a box.
    Count {
        /// The box.
        region: Region,
    },
}

/// One measurement.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub struct ProbeReading {
    /// Level: the water's top [m, world y], `None` where the column is dry. Flux: Q [m³/s].
    /// Count: the particles.
    pub value: Option<f32>,
    /// The particles the reading is made of (the column's, the slab's, the box's).
    pub particles: u32,
    /// Flux: the mean speed along the normal of the particles in the slab [m/s] (`None` when
    /// the slab is empty); otherwise `None`.
    pub mean_speed: Option<f32>,
}

impl ProbeKind {
    /// Checks the kind's numbers; the error names the field.
    pub fn validate(&self) -> Result<(), ParamError> {
        match *self {
            ProbeKind::Level { x, z, radius } => {
                if !(x.is_finite() && z.is_finite()) {
                    return Err(ParamError {
                        field: "probe.level",
                        value: format!("x {x}, z {z}"),
                        allowed: "finite coordinates [m]",
                    });
                }
                if !(radius > 0.0 && radius.is_finite()) {
                    return Err(ParamError {
                        field: "probe.level.radius",
                        value: radius.to_string(),
                        allowed: "> 0 and finite [m]",
                    });
                }
            }
            ProbeKind::Flux { pose, half_size } => {
                Region {
                    pose,
                    half_extents: Vec3::new(half_size[0], half_size[1], 1.0),
                }
                .validate("probe.flux")?;
            }
            ProbeKind::Count { region } => region.validate("probe.count.region")?,
        }
        Ok(())
    }

    /// Measures the particles at `position` moving at `velocity` under `params`.
    pub fn measure(
        &self,
        params: &SphParams,
        position: &[Vec3],
        velocity: &[Vec3],
    ) -> ProbeReading {
        let spacing = params.spacing();
        match *self {
            ProbeKind::Level { x, z, radius } => {
                let (mut top, mut particles) = (f32::NEG_INFINITY, 0);
                for p in position {
                    let (dx, dz) = (p.x - x, p.z - z);
                    if dx * dx + dz * dz <= radius * radius {
                        top = top.max(p.y);
                        particles += 1;
                    }
                }
                ProbeReading {
                    value: (particles > 0).then_some(top + 0.5 * spacing),
                    particles,
                    mean_speed: None,
                }
            }
            ProbeKind::Flux { pose, half_size } => {
                let thickness = flux_slab_thickness(spacing);
                let normal = pose.rotation * Vec3::Z;
                let (mut sum, mut particles) = (0.0f64, 0u32);
                for (p, v) in position.iter().zip(velocity) {
                    let local = pose.to_local(*p);
                    if local.x.abs() <= half_size[0]
                        && local.y.abs() <= half_size[1]
                        && local.z.abs() <= 0.5 * thickness
                    {
                        sum += v.dot(normal) as f64;
                        particles += 1;
                    }
                }
                let volume = params.particle_mass / params.rest_density;
                ProbeReading {
                    value: Some((sum * volume as f64 / thickness as f64) as f32),
                    particles,
                    mean_speed: (particles > 0).then(|| (sum / particles as f64) as f32),
                }
            }
            ProbeKind::Count { region } => {
                let particles = position.iter().filter(|&&p| region.contains(p)).count() as u32;
                ProbeReading {
                    value: Some(particles as f32),
                    particles,
                    mean_speed: None,
                }
            }
        }
    }
}

/// The flux slab's thickness d = 2 Δx [m].
pub fn flux_slab_thickness(spacing: f32) -> f32 {
    2.0 * spacing
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spawn::BlockSpawn;

    #[test]
    fn a_uniform_flow_through_a_full_rectangle_gives_speed_times_area() {
        let params = SphParams::water();
        let dx = params.spacing();
        let block = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.4, 0.2, 0.2), dx);
        let position = block.positions();
        let velocity = vec![Vec3::new(0.3, 0.0, 0.0); position.len()];
        // A rectangle across the block at x = 0.2, normal +x (local z turned onto x).
        let kind = ProbeKind::Flux {
            pose: Pose {
                translation: Vec3::new(0.2, 0.1, 0.1),
                rotation: glam::Quat::from_rotation_y(std::f32::consts::FRAC_PI_2),
            },
            half_size: [0.2, 0.2],
        };
        let reading = kind.measure(&params, &position, &velocity);
        let q = reading.value.unwrap();
        let expected = 0.3 * 0.2 * 0.2;
        assert!((q - expected).abs() < 0.1 * expected, "Q {q} vs {expected}");
        assert!((reading.mean_speed.unwrap() - 0.3).abs() < 1e-5);
        // The level of the block's column is its top, the count its particles.
        let level = ProbeKind::Level {
            x: 0.1,
            z: 0.1,
            radius: 2.0 * dx,
        }
        .measure(&params, &position, &velocity);
        let top = position.iter().map(|p| p.y).fold(f32::MIN, f32::max) + 0.5 * dx;
        assert_eq!(level.value, Some(top));
        let dry = ProbeKind::Level {
            x: 3.0,
            z: 0.1,
            radius: dx,
        }
        .measure(&params, &position, &velocity);
        assert_eq!((dry.value, dry.particles), (None, 0));
        let count = ProbeKind::Count {
            region: Region::from_min_max(Vec3::splat(-1.0), Vec3::splat(1.0)),
        }
        .measure(&params, &position, &velocity);
        assert_eq!(count.particles as usize, position.len());
    }

    #[test]
    fn refuses_bad_probes_by_field() {
        let bad = ProbeKind::Level {
            x: 0.0,
            z: 0.0,
            radius: 0.0,
        };
        assert_eq!(bad.validate().unwrap_err().field, "probe.level.radius");
        let bad = ProbeKind::Flux {
            pose: Pose::default(),
            half_size: [0.1, -1.0],
        };
        assert_eq!(bad.validate().unwrap_err().field, "probe.flux");
    }
}

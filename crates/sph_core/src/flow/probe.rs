//! Probes: what the water does at a place, for game logic and for `sph-bench`.
//!
//! - **Level** at an (x, z) point: the free surface of the connected water column under it.
//!   The particles within `radius` of the vertical line are binned by height ([`LevelColumn`]:
//!   [`LEVEL_BINS`] bins from the container's floor, each at least a spacing tall), keeping
//!   each bin's highest particle. The column is the lowest run of occupied bins in which no two
//!   neighbouring bins are both empty: resting water fills every bin (about twelve particles a
//!   layer at the default radius of two spacings), so the run ends where at least two bins of
//!   air begin. Its level is the run's highest particle centre plus half a spacing (a
//!   particle's own thickness). Spray, a jet or a sheet above that air gap is not the level.
//! - **Flux** through a rectangle [m³/s]: the particles in a slab of thickness d = 2 Δx around
//!   the rectangle carry Q = (V / d) Σ v_i·n, V = m/ρ0 each. A uniform flow of speed u through
//!   a full rectangle of area A gives Q = u A: the slab holds A d / V particles.
//! - **Count** of the particles inside a box.

use crate::boundary::collider::Pose;
use crate::container::BoxContainer;
use crate::flow::region::Region;
use crate::params::{ParamError, SphParams};
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

    /// Measures the particles at `position` moving at `velocity` under `params`, in
    /// `container` (a level's bins start at its floor).
    pub fn measure(
        &self,
        params: &SphParams,
        container: &BoxContainer,
        position: &[Vec3],
        velocity: &[Vec3],
    ) -> ProbeReading {
        let spacing = params.spacing();
        match *self {
            ProbeKind::Level { x, z, radius } => {
                let column = LevelColumn::of(container, spacing);
                let mut tops = [None; LEVEL_BINS];
                let mut particles = 0;
                for p in position {
                    let (dx, dz) = (p.x - x, p.z - z);
                    if dx * dx + dz * dz <= radius * radius {
                        let top: &mut Option<f32> = &mut tops[column.bin_of(p.y)];
                        *top = Some(top.map_or(p.y, |t| t.max(p.y)));
                        particles += 1;
                    }
                }
                ProbeReading {
                    value: column_surface(&tops).map(|y| y + 0.5 * spacing),
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

/// The height bins of a Level probe's column.
pub const LEVEL_BINS: usize = 128;

/// How a Level probe bins its column by height: [`LEVEL_BINS`] bins from the container's floor,
/// each `max(Δx, wall height / LEVEL_BINS)` tall. Particles below the floor fall in the first
/// bin and those above the last bin in the last. The GPU bins the same way (`probes.wgsl`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelColumn {
    /// The first bin's bottom [m, world y].
    pub floor: f32,
    /// A bin's height [m].
    pub bin: f32,
}

impl LevelColumn {
    /// The bins in `container` for particles of spacing `spacing`.
    pub fn of(container: &BoxContainer, spacing: f32) -> Self {
        Self {
            floor: container.min().y,
            bin: spacing.max(container.size().y / LEVEL_BINS as f32),
        }
    }

    /// The bin of a particle at height `y` (the same f32 steps as the shader's).
    pub fn bin_of(&self, y: f32) -> usize {
        let k = ((y - self.floor) / self.bin).floor();
        if k >= 0.0 {
            (k as usize).min(LEVEL_BINS - 1)
        } else {
            0
        }
    }
}

/// The highest particle centre of the connected column: the lowest run of occupied bins
/// (`tops[k]` = bin k's highest particle centre) in which no two neighbouring bins are empty;
/// `None` when every bin is.
pub fn column_surface(tops: &[Option<f32>]) -> Option<f32> {
    let first = tops.iter().position(Option::is_some)?;
    let mut surface = tops[first]?;
    let mut empty = 0;
    for top in &tops[first + 1..] {
        match top {
            Some(y) => {
                surface = surface.max(*y);
                empty = 0;
            }
            None if empty == 1 => break,
            None => empty += 1,
        }
    }
    Some(surface)
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
        let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.4, 0.5, 0.2));
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
        let reading = kind.measure(&params, &container, &position, &velocity);
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
        .measure(&params, &container, &position, &velocity);
        let top = position.iter().map(|p| p.y).fold(f32::MIN, f32::max) + 0.5 * dx;
        assert_eq!(level.value, Some(top));
        let dry = ProbeKind::Level {
            x: 3.0,
            z: 0.1,
            radius: dx,
        }
        .measure(&params, &container, &position, &velocity);
        assert_eq!((dry.value, dry.particles), (None, 0));
        let count = ProbeKind::Count {
            region: Region::from_min_max(Vec3::splat(-1.0), Vec3::splat(1.0)),
        }
        .measure(&params, &container, &position, &velocity);
        assert_eq!(count.particles as usize, position.len());
    }

    #[test]
    fn a_level_reads_the_connected_column_not_the_spray_over_it() {
        let params = SphParams::water();
        let dx = params.spacing();
        let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.4, 1.0, 0.4));
        let block = BlockSpawn::new(Vec3::ZERO, Vec3::new(0.4, 0.42, 0.4), dx);
        let mut position = block.positions();
        let water_top = position.iter().map(|p| p.y).fold(f32::MIN, f32::max);
        let level = ProbeKind::Level {
            x: 0.2,
            z: 0.2,
            radius: 2.0 * dx,
        };
        let reading = |position: &[Vec3]| {
            let velocity = vec![Vec3::ZERO; position.len()];
            level
                .measure(&params, &container, position, &velocity)
                .value
                .unwrap()
        };
        assert_eq!(reading(&position), water_top + 0.5 * dx);
        // One droplet at 0.5 m over the 0.42 m surface, and a sheet of spray higher still:
        // neither is the level.
        position.push(Vec3::new(0.2, 0.5, 0.2));
        position.extend((0..5).map(|i| Vec3::new(0.18 + 0.01 * i as f32, 0.7, 0.2)));
        assert_eq!(reading(&position), water_top + 0.5 * dx);
        // A particle a spacing above the surface (one empty bin at most) is still the column's.
        position.push(Vec3::new(0.21, water_top + 2.0 * dx, 0.2));
        assert_eq!(reading(&position), water_top + 2.5 * dx);
    }

    #[test]
    fn level_bins_cover_the_container_from_its_floor() {
        let container =
            BoxContainer::from_min_max(Vec3::new(0.0, -2.0, 0.0), Vec3::new(1.0, 2.0, 1.0));
        let column = LevelColumn::of(&container, 0.02);
        assert_eq!(column.floor, -2.0);
        // 4 m over 128 bins is more than a spacing; 1 m would be less, and a bin is a spacing.
        assert_eq!(column.bin, 4.0 / LEVEL_BINS as f32);
        let short = BoxContainer::from_min_max(Vec3::ZERO, Vec3::ONE);
        assert_eq!(LevelColumn::of(&short, 0.02).bin, 0.02);
        assert_eq!(column.bin_of(-5.0), 0);
        assert_eq!(column.bin_of(-2.0), 0);
        assert_eq!(column.bin_of(-1.97), 0);
        assert_eq!(column.bin_of(-1.96), 1);
        assert_eq!(column.bin_of(1.99), LEVEL_BINS - 1);
        assert_eq!(column.bin_of(50.0), LEVEL_BINS - 1);
        assert_eq!(column.bin_of(f32::NAN), 0);
        assert_eq!(column_surface(&[None, None]), None);
        assert_eq!(
            column_surface(&[None, Some(1.0), None, Some(2.0), None, None, Some(9.0)]),
            Some(2.0)
        );
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

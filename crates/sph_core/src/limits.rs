//! The largest sizes a scene file, a component or an API call may imply, checked with checked
//! arithmetic before anything of that size is allocated.
//!
//! A scene file is user data that is hot-reloaded while a person types: a block a kilometre
//! wide, an emitter of radius `1e30` or a collider the size of the container must be refused
//! with the field, the value and the limit, not discovered by the allocator. Each bound here is
//! far above what a real-time scene holds and far below what exhausts a machine's memory.

use crate::boundary::collider::ColliderShape;
use crate::boundary::sampling::layer_depths;
use crate::container::BoxContainer;
use crate::params::ParamError;

/// The most cells a dense grid may have (64 Mi cells = 256 MiB of offsets); use the hash beyond.
pub const MAX_GRID_CELLS: u64 = 1 << 26;

/// The most particles one block, or a scene's blocks together, may hold: 2^22 = 4,194,304
/// (about 200 MB of CPU solver state).
pub const MAX_SPAWN_PARTICLES: u64 = 1 << 22;

/// The largest pipe radius in particle spacings: a disc of at most about 206,000 particles.
pub const MAX_DISC_RADIUS_SPACINGS: f32 = 256.0;

/// The most boundary samples one collider, or the container's walls, may take: 2^24.
pub const MAX_BOUNDARY_SAMPLES: u64 = 1 << 24;

/// Particles on a lattice of `dims` cells, or `None` when the product overflows.
pub fn lattice_count(dims: [u64; 3]) -> Option<u64> {
    dims[0].checked_mul(dims[1])?.checked_mul(dims[2])
}

/// Whole lattice steps along an extent, saturating: `extent / spacing` floored, 0 for a
/// negative or NaN ratio, `u64::MAX` for an infinite one.
pub fn steps_along(extent: f32, spacing: f32) -> u64 {
    // `as` saturates: NaN -> 0, +inf -> u64::MAX.
    (extent / spacing).floor().max(0.0) as u64
}

/// Checks that a count is at most `limit`; the error names `field`, the count and the limit.
pub fn check_count(
    field: &'static str,
    count: Option<u64>,
    limit: u64,
    allowed: &'static str,
) -> Result<u64, ParamError> {
    match count {
        Some(n) if n <= limit => Ok(n),
        Some(n) => Err(ParamError {
            field,
            value: format!("{n} particles"),
            allowed,
        }),
        None => Err(ParamError {
            field,
            value: "more than 2^64 particles".into(),
            allowed,
        }),
    }
}

/// Boundary samples the container's walls take at `spacing`: two layers over the floor and
/// the four side walls, edges and corners included (as `sampling::container_shell` lays them).
/// `None` when the count overflows.
pub fn container_shell_samples(container: &BoxContainer, spacing: f32) -> Option<u64> {
    let cells = (container.size() / spacing).round().max(glam::Vec3::ONE);
    // `as` saturates; a saturated axis overflows the products below.
    let [nx, ny, nz] = [cells.x as u64, cells.y as u64, cells.z as u64];
    let outer = lattice_count([nx.checked_add(4)?, ny.checked_add(2)?, nz.checked_add(4)?])?;
    outer.checked_sub(lattice_count([nx, ny, nz])?)
}

/// The cells of a dense grid of cell size `h` over `container`, checked: at most
/// [`MAX_GRID_CELLS`], so that a huge box over a small h is refused rather than wrapped.
pub fn grid_cells(container: &BoxContainer, h: f32) -> Result<u64, ParamError> {
    let size = container.size();
    let dims = (size / h).ceil().max(glam::Vec3::ONE);
    // `as` saturates; a saturated axis overflows the product.
    lattice_count([dims.x as u64, dims.y as u64, dims.z as u64])
        .filter(|&c| c <= MAX_GRID_CELLS)
        .ok_or_else(|| ParamError {
            field: "smoothing_radius",
            value: format!("{h} (a {dims} cell grid over a {size} m box)"),
            allowed: "at most 2^26 grid cells: a larger h, a smaller box, or the hash search",
        })
}

/// Checks that `container` can be searched with cells of `h` and sampled at `spacing`: at most
/// [`MAX_GRID_CELLS`] grid cells and [`MAX_BOUNDARY_SAMPLES`] wall samples.
pub fn check_container(container: &BoxContainer, h: f32, spacing: f32) -> Result<(), ParamError> {
    grid_cells(container, h)?;
    let size = container.size();
    let samples = container_shell_samples(container, spacing);
    if samples.is_none_or(|n| n > MAX_BOUNDARY_SAMPLES) {
        return Err(ParamError {
            field: "container",
            value: format!("a {size} m box sampled at {spacing} m"),
            allowed: "at most 2^24 wall samples: a smaller box or a larger spacing",
        });
    }
    Ok(())
}

/// An upper estimate of the boundary samples `shape` takes at `spacing`: its surface area over
/// spacing² for each of the two sample layers, with a margin for rounding on small shapes.
pub fn shape_samples_estimate(shape: &ColliderShape, spacing: f32) -> f64 {
    use std::f64::consts::PI;
    let area = match *shape {
        ColliderShape::Cuboid { half_extents: e } => {
            let e = e.as_dvec3() * 2.0;
            2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
        }
        ColliderShape::Sphere { radius } => 4.0 * PI * f64::from(radius).powi(2),
        ColliderShape::Capsule {
            radius,
            half_length,
        } => {
            let (r, l) = (f64::from(radius), 2.0 * f64::from(half_length));
            4.0 * PI * r * r + 2.0 * PI * r * l
        }
        ColliderShape::Cylinder {
            radius,
            half_length,
        } => {
            let (r, l) = (f64::from(radius), 2.0 * f64::from(half_length));
            2.0 * PI * r * r + 2.0 * PI * r * l
        }
        ColliderShape::TriMesh(ref mesh) => mesh
            .triangles()
            .iter()
            .map(|t| {
                let [a, b, c] = t.corners.map(|p| p.as_dvec3());
                0.5 * (b - a).cross(c - a).length()
            })
            .sum(),
    };
    let s = f64::from(spacing);
    let layers = layer_depths(spacing).len() as f64;
    // Each sample covers about s² of a layer; a layer is at least one sample.
    layers * (area / (s * s) * 2.0 + 1.0)
}

/// Checks that `shape` takes at most [`MAX_BOUNDARY_SAMPLES`] samples at `spacing`, before it
/// is sampled.
pub fn check_shape_samples(
    shape: &ColliderShape,
    spacing: f32,
) -> Result<(), crate::boundary::collider::ColliderError> {
    let estimate = shape_samples_estimate(shape, spacing);
    if estimate.is_nan() || estimate > MAX_BOUNDARY_SAMPLES as f64 {
        return Err(crate::boundary::collider::ColliderError {
            field: "shape",
            value: format!("about {estimate:.3e} boundary samples at a {spacing} m spacing"),
            allowed: "at most 2^24 boundary samples: a smaller shape or a larger spacing",
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn counts_that_overflow_are_refused_not_wrapped() {
        assert_eq!(lattice_count([u64::MAX, 2, 1]), None);
        assert_eq!(steps_along(f32::INFINITY, 0.02), u64::MAX);
        assert_eq!(steps_along(f32::NAN, 0.02), 0);
        assert_eq!(steps_along(-3.0, 0.02), 0);
        assert!(check_count("block", None, 10, "at most 10").is_err());
        assert_eq!(check_count("block", Some(10), 10, "at most 10"), Ok(10));
        assert!(check_count("block", Some(11), 10, "at most 10").is_err());
    }

    #[test]
    fn the_shell_estimate_counts_what_the_sampler_lays() {
        let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.4, 0.3, 0.2));
        let spacing = 0.02;
        let (laid, _) = crate::boundary::sampling::container_shell(&container, spacing);
        assert_eq!(
            container_shell_samples(&container, spacing),
            Some(laid.len() as u64)
        );
    }

    #[test]
    fn the_shape_estimate_is_not_below_what_the_sampler_lays() {
        let spacing = 0.02;
        for shape in [
            ColliderShape::Cuboid {
                half_extents: Vec3::new(0.2, 0.1, 0.05),
            },
            ColliderShape::Sphere { radius: 0.15 },
            ColliderShape::Capsule {
                radius: 0.1,
                half_length: 0.2,
            },
            ColliderShape::Cylinder {
                radius: 0.1,
                half_length: 0.2,
            },
        ] {
            let laid = crate::boundary::sampling::sample_shape(&shape, spacing).len() as f64;
            let estimate = shape_samples_estimate(&shape, spacing);
            assert!(
                laid <= estimate && estimate <= 8.0 * laid,
                "{shape:?}: laid {laid}, estimated {estimate}"
            );
        }
    }

    #[test]
    fn huge_shapes_and_boxes_are_refused_before_sampling() {
        let cube = ColliderShape::Cuboid {
            half_extents: Vec3::splat(500.0),
        };
        let e = check_shape_samples(&cube, 0.02).unwrap_err();
        assert_eq!(e.field, "shape");
        let big = BoxContainer::from_min_max(Vec3::ZERO, Vec3::splat(1.0e4));
        assert!(check_container(&big, 0.04, 0.02).is_err());
        let small = BoxContainer::from_min_max(Vec3::ZERO, Vec3::ONE);
        assert!(check_container(&small, 0.04, 0.02).is_ok());
    }
}

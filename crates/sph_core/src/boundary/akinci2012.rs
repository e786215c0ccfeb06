//! Boundary sample volumes after Akinci et al. 2012, "Versatile rigid-fluid coupling for
//! incompressible SPH" (§3.1): a boundary sample b stands for the volume
//! V_b = γ / Σ_k W(x_b − x_k), summed over the samples k of its own set (itself included), so
//! uneven sampling is compensated, and a fluid particle i gains ρ0 Σ_b V_b W(x_i − x_b) in its
//! density. γ corrects the over-count of a thin layout (two layers, `crate::boundary::sampling`), and is
//! calibrated on a flat wall so that the first fluid row sees the density of a full lattice
//! (`docs/design_boundary_akinci2012.md` §3). Groundwork: the solver does not use it yet.

use crate::boundary::collider::ColliderShape;
use crate::boundary::sampling::sample_shape;
use crate::kernel::Kernels;
use glam::{IVec3, Vec3};
use rayon::prelude::*;
use std::collections::HashMap;

/// Points bucketed in cells of size h, for sums over the neighbours within h.
struct CellIndex<'a> {
    points: &'a [Vec3],
    cells: HashMap<IVec3, Vec<u32>>,
    h: f32,
}

impl<'a> CellIndex<'a> {
    fn new(points: &'a [Vec3], h: f32) -> Self {
        let mut cells: HashMap<IVec3, Vec<u32>> = HashMap::new();
        for (k, &p) in points.iter().enumerate() {
            cells.entry(Self::cell(p, h)).or_default().push(k as u32);
        }
        Self { points, cells, h }
    }

    fn cell(p: Vec3, h: f32) -> IVec3 {
        (p / h).floor().as_ivec3()
    }

    /// Σ_k weight(k) W(x − x_k) over the points within h of `x`.
    fn kernel_sum(&self, x: Vec3, kernels: &Kernels, weight: impl Fn(usize) -> f32) -> f32 {
        let home = Self::cell(x, self.h);
        let mut sum = 0.0;
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let Some(list) = self.cells.get(&(home + IVec3::new(dx, dy, dz))) else {
                        continue;
                    };
                    for &k in list {
                        let r2 = (x - self.points[k as usize]).length_squared();
                        sum += weight(k as usize) * kernels.poly6(r2);
                    }
                }
            }
        }
        sum
    }
}

/// V_b = γ / Σ_k W(x_b − x_k) for every sample of one set (Akinci 2012 §3.1) [m³].
pub fn boundary_volumes(samples: &[Vec3], kernels: &Kernels, gamma: f32) -> Vec<f32> {
    let index = CellIndex::new(samples, kernels.h);
    samples
        .par_iter()
        .map(|&x| gamma / index.kernel_sum(x, kernels, |_| 1.0).max(f32::MIN_POSITIVE))
        .collect()
}

/// The boundary's density contribution at `x`, per unit rest density: Σ_b V_b W(x − x_b)
/// (multiply by ρ0). A plain sum over all samples, for calibration and tests.
pub fn boundary_density_ratio(
    x: Vec3,
    samples: &[Vec3],
    volumes: &[f32],
    kernels: &Kernels,
) -> f32 {
    samples
        .iter()
        .zip(volumes)
        .map(|(&b, &v)| v * kernels.poly6((x - b).length_squared()))
        .sum()
}

/// Σ W over a cubic lattice of spacing `spacing` through `x`, keeping the points whose height
/// above `x` is at least `min_dy` (−∞: the full lattice), times the particle volume dx³: the
/// density ratio ρ/ρ0 that lattice gives at `x`.
pub fn lattice_density_ratio(spacing: f32, kernels: &Kernels, min_dy: f32) -> f32 {
    let n = (kernels.h / spacing).ceil() as i32 + 1;
    let mut sum = 0.0;
    for i in -n..=n {
        for j in -n..=n {
            for k in -n..=n {
                let r = Vec3::new(i as f32, j as f32, k as f32) * spacing;
                if r.y >= min_dy {
                    sum += kernels.poly6(r.length_squared());
                }
            }
        }
    }
    sum * spacing.powi(3)
}

/// The layout factor γ of [`crate::boundary::sampling`]'s two-layer samples at `spacing` for smoothing
/// radius h: on a flat slab (wider than 6 h), the first fluid row (dx/2 above the surface) gets
/// the density of a full lattice from the fluid half-lattice plus the boundary.
pub fn calibrate_gamma(spacing: f32, kernels: &Kernels) -> f32 {
    let half_width = 3.0 * kernels.h + 2.0 * spacing;
    let thickness = 2.0 * spacing;
    let slab = ColliderShape::Cuboid {
        half_extents: Vec3::new(half_width, thickness, half_width),
    };
    let samples = sample_shape(&slab, spacing).position;
    let volumes = boundary_volumes(&samples, kernels, 1.0);
    let probe = Vec3::new(0.0, thickness + 0.5 * spacing, 0.0);
    let full = lattice_density_ratio(spacing, kernels, f32::NEG_INFINITY);
    let fluid = lattice_density_ratio(spacing, kernels, -0.01 * spacing);
    let boundary = boundary_density_ratio(probe, &samples, &volumes, kernels);
    (full - fluid) / boundary.max(f32::MIN_POSITIVE)
}

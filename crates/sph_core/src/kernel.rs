//! Smoothing kernels of Müller, Charypar & Gross 2003 ("Particle-based fluid simulation for
//! interactive applications") and the cohesion spline of Akinci, Akinci & Teschner 2013
//! ("Versatile surface tension and adhesion for SPH fluids").
//!
//! All kernels have compact support `h` and are zero for `r >= h`. The constants are the papers'
//! (the design document's text has typos in three of them; see docs/physics.md).

use glam::Vec3;
use std::f32::consts::PI;

/// The largest h / Δx a lattice sum walks: (2·64 + 1)³ ≈ 2.1 M lattice points. The presets use 2.
pub const MAX_LATTICE_REACH: f32 = 64.0;

/// The lattice points a sum walks along each axis either side of the origin, ⌈h / Δx⌉; `None`
/// when h / Δx is not finite, not positive or above [`MAX_LATTICE_REACH`] (a spacing of
/// `3.4e38` makes h infinite), so the sum returns NaN for validation to refuse instead of
/// walking 2^96 points.
fn lattice_reach(h: f32, spacing: f32) -> Option<i32> {
    let ratio = h / spacing;
    (ratio > 0.0 && ratio <= MAX_LATTICE_REACH).then(|| ratio.ceil() as i32)
}

/// Precomputed kernel constants for one smoothing radius `h` (metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kernels {
    /// Support radius h.
    pub h: f32,
    /// h².
    pub h2: f32,
    /// 315 / (64 π h⁹), Müller 2003 eq. 20 (poly6).
    pub poly6: f32,
    /// -945 / (32 π h⁹), the gradient of poly6.
    pub poly6_grad: f32,
    /// -45 / (π h⁶), Müller 2003 eq. 21 differentiated (spiky gradient).
    pub spiky_grad: f32,
    /// 45 / (π h⁶), Müller 2003 eq. 22 (viscosity Laplacian).
    pub viscosity_laplacian: f32,
    /// 32 / (π h⁹), Akinci 2013 eq. 2 (cohesion spline).
    pub cohesion: f32,
    /// h⁶ / 64, the constant term of the cohesion spline's inner branch.
    pub cohesion_offset: f32,
}

impl Kernels {
    /// Kernel constants for support radius `h` (> 0).
    pub fn new(h: f32) -> Self {
        let h3 = h * h * h;
        let h6 = h3 * h3;
        let h9 = h6 * h3;
        Self {
            h,
            h2: h * h,
            poly6: 315.0 / (64.0 * PI * h9),
            poly6_grad: -945.0 / (32.0 * PI * h9),
            spiky_grad: -45.0 / (PI * h6),
            viscosity_laplacian: 45.0 / (PI * h6),
            cohesion: 32.0 / (PI * h9),
            cohesion_offset: h6 / 64.0,
        }
    }

    /// Poly6 kernel W(r, h) = 315/(64 π h⁹) (h² - r²)³ for r < h (Müller 2003 eq. 20), from r².
    #[inline]
    pub fn poly6(&self, r2: f32) -> f32 {
        if r2 >= self.h2 {
            return 0.0;
        }
        let d = self.h2 - r2;
        self.poly6 * d * d * d
    }

    /// Poly6 written branch-free: max(h² - r², 0)³ scaled; equal to [`Self::poly6`].
    #[inline]
    pub fn poly6_unchecked(&self, r2: f32) -> f32 {
        let d = (self.h2 - r2).max(0.0);
        self.poly6 * d * d * d
    }

    /// ∇W_poly6 = -945/(32 π h⁹) (h² - r²)² r for r < h, with `r = x_i - x_j`.
    #[inline]
    pub fn poly6_grad(&self, r: Vec3, r2: f32) -> Vec3 {
        if r2 >= self.h2 {
            return Vec3::ZERO;
        }
        let d = self.h2 - r2;
        r * (self.poly6_grad * d * d)
    }

    /// Spiky kernel W(r, h) = 15/(π h⁶) (h - r)³ (Müller 2003 eq. 21); used by tests of its gradient.
    #[inline]
    pub fn spiky(&self, r_len: f32) -> f32 {
        if r_len >= self.h {
            return 0.0;
        }
        let d = self.h - r_len;
        15.0 / (PI * self.h.powi(6)) * d * d * d
    }

    /// ∇W_spiky = -45/(π h⁶) (h - r)² r/|r| for 0 < r < h, with `r = x_i - x_j`; zero at r = 0
    /// (coincident particles exert no pressure direction, never NaN).
    #[inline]
    pub fn spiky_grad(&self, r: Vec3, r_len: f32) -> Vec3 {
        if r_len >= self.h || r_len <= 0.0 {
            return Vec3::ZERO;
        }
        let d = self.h - r_len;
        r * (self.spiky_grad * d * d / r_len)
    }

    /// Viscosity kernel W(r, h) = 15/(2π h³) (-r³/(2h³) + r²/h² + h/(2r) - 1) (Müller 2003 eq. 22);
    /// used by tests of its Laplacian.
    #[inline]
    pub fn viscosity(&self, r_len: f32) -> f32 {
        if r_len >= self.h || r_len <= 0.0 {
            return 0.0;
        }
        let h = self.h;
        15.0 / (2.0 * PI * h * h * h)
            * (-r_len.powi(3) / (2.0 * h * h * h) + r_len * r_len / (h * h) + h / (2.0 * r_len)
                - 1.0)
    }

    /// ∇²W_viscosity = 45/(π h⁶) (h - r) for r < h (Müller 2003 eq. 22).
    #[inline]
    pub fn viscosity_laplacian(&self, r_len: f32) -> f32 {
        if r_len >= self.h {
            return 0.0;
        }
        self.viscosity_laplacian * (self.h - r_len)
    }

    /// Σ_j W_poly6(x_j) Δx³ over a cubic lattice of spacing Δx through the origin: the density
    /// ratio ρ/ρ0 that the rest lattice gives with m = ρ0 Δx³ (1.0098 at h = 2Δx). Summed in
    /// f64 in a fixed order, so the same inputs always give the same value.
    pub fn lattice_sum(&self, spacing: f32) -> f32 {
        let Some(n) = lattice_reach(self.h, spacing) else {
            return f32::NAN;
        };
        let (h2, dx) = (self.h as f64 * self.h as f64, spacing as f64);
        let mut sum = 0.0f64;
        for i in -n..=n {
            for j in -n..=n {
                for k in -n..=n {
                    let r2 = ((i * i + j * j + k * k) as f64) * dx * dx;
                    if r2 < h2 {
                        sum += (h2 - r2).powi(3);
                    }
                }
            }
        }
        (sum * self.poly6 as f64 * dx * dx * dx) as f32
    }

    /// Σ_j Δx³ (y_j - y_i)² |∇W_spiky(r_ij)| / r_ij over a cubic lattice of spacing Δx: the
    /// factor by which the SPH gradient Σ_j V_j (p_j - p_i) ∇W of a linear pressure field
    /// under-estimates it on the rest lattice (0.956 at h = 2Δx with V_j = Δx³). The forces pass
    /// divides the pressure gradient by it (times m / (ρ0 Δx³)), a first-order kernel-gradient
    /// correction of the rest configuration (Bonet & Lok 1999, evaluated once on the lattice
    /// instead of per particle), so hydrostatic water holds up with ρ0 g depth.
    pub fn lattice_gradient_moment(&self, spacing: f32) -> f32 {
        let Some(n) = lattice_reach(self.h, spacing) else {
            return f32::NAN;
        };
        let (h, dx) = (self.h as f64, spacing as f64);
        let mut sum = 0.0f64;
        for i in -n..=n {
            for j in -n..=n {
                for k in -n..=n {
                    let r = (((i * i + j * j + k * k) as f64).sqrt()) * dx;
                    if r > 0.0 && r < h {
                        let dy = j as f64 * dx;
                        sum += dy * dy * (h - r) * (h - r) / r;
                    }
                }
            }
        }
        (sum * (-self.spiky_grad as f64) * dx * dx * dx) as f32
    }

    /// Akinci 2013 eq. 2 cohesion spline C(r):
    /// 32/(π h⁹) × (h - r)³ r³ for h/2 < r <= h, 2 (h - r)³ r³ - h⁶/64 for 0 < r <= h/2, else 0.
    #[inline]
    pub fn cohesion(&self, r_len: f32) -> f32 {
        if r_len >= self.h || r_len <= 0.0 {
            return 0.0;
        }
        let d = self.h - r_len;
        let core = d * d * d * r_len * r_len * r_len;
        if 2.0 * r_len > self.h {
            self.cohesion * core
        } else {
            self.cohesion * (2.0 * core - self.cohesion_offset)
        }
    }
}

/// The cubic spline kernel (Monaghan 1992, the M4 B-spline) with support h, as DFSPH uses it
/// (Bender & Koschier 2017): with q = r/h and k = 8/(π h³), W = k (6q³ - 6q² + 1) for q <= 1/2,
/// 2k (1 - q)³ for 1/2 < q < 1. Its gradient peaks at r = h/3, inside the rest spacing h/2, so
/// pairs at the rest spacing push apart harder as they close in (poly6's peaks at 0.45 h, too
/// close to h/2 to stop the pairing of an implicit solve).
///
/// Scaled by `lattice_scale`, the ratio of poly6's lattice sum to its own, so that the particle
/// mass m = ρ0 Δx³ / L of [`crate::SphParams::from_spacing`] gives exactly ρ0 on the rest
/// lattice with this kernel too.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubicSpline {
    /// Support radius h.
    pub h: f32,
    /// lattice_scale × 8 / (π h³).
    pub k: f32,
    /// lattice_scale × 48 / (π h⁴), the gradient's constant.
    pub l: f32,
    /// 1 / h: the pair loops multiply by it (a division per pair is one of the slowest
    /// instructions in them).
    pub inverse_h: f32,
}

impl CubicSpline {
    /// The spline of support `h`, normalised on the lattice of spacing `spacing` (see the type).
    pub fn new(h: f32, spacing: f32) -> Self {
        let raw = Self {
            h,
            k: 8.0 / (PI * h * h * h),
            l: 48.0 / (PI * h * h * h * h),
            inverse_h: 1.0 / h,
        };
        let scale = Kernels::new(h).lattice_sum(spacing) / raw.lattice_sum(spacing);
        Self {
            k: raw.k * scale,
            l: raw.l * scale,
            ..raw
        }
    }

    /// W(r) for |r| = `r_len`.
    #[inline]
    pub fn value(&self, r_len: f32) -> f32 {
        let q = r_len / self.h;
        if q >= 1.0 {
            0.0
        } else if q <= 0.5 {
            self.k * (6.0 * q * q * (q - 1.0) + 1.0)
        } else {
            let d = 1.0 - q;
            self.k * 2.0 * d * d * d
        }
    }

    /// ∇W(r) with `r = x_i - x_j`, |r| = `r_len`; zero at r = 0 and beyond h.
    #[inline]
    pub fn gradient(&self, r: Vec3, r_len: f32) -> Vec3 {
        let q = r_len / self.h;
        if q >= 1.0 || r_len <= 1.0e-9 * self.h {
            return Vec3::ZERO;
        }
        let slope = if q <= 0.5 {
            self.l * q * (3.0 * q - 2.0)
        } else {
            let d = 1.0 - q;
            -self.l * d * d
        };
        r * (slope / r_len)
    }

    /// W(r) and the factor f with ∇W(r) = f r, from |r|² = `r2`, in one branch-free evaluation
    /// (one square root, selects instead of branches, so loops over pairs vectorise): the same
    /// values as [`Self::value`] and [`Self::gradient`] to rounding, zero beyond h and f finite
    /// at r = 0 (where the inner branch's slope vanishes with r).
    #[inline(always)]
    pub fn value_and_gradient_factor(&self, r2: f32) -> (f32, f32) {
        let r_len = r2.sqrt();
        let q = r_len * self.inverse_h;
        let d = (1.0 - q).max(0.0);
        let inner = q <= 0.5;
        let w = if inner {
            6.0 * q * q * (q - 1.0) + 1.0
        } else {
            2.0 * d * d * d
        };
        let slope = if inner {
            self.l * q * (3.0 * q - 2.0)
        } else {
            -self.l * d * d
        };
        (self.k * w, slope / r_len.max(f32::MIN_POSITIVE))
    }

    /// Σ_j W(x_j) Δx³ over the cubic lattice of spacing Δx (f64, fixed order).
    pub fn lattice_sum(&self, spacing: f32) -> f32 {
        let Some(n) = lattice_reach(self.h, spacing) else {
            return f32::NAN;
        };
        let mut sum = 0.0f64;
        for i in -n..=n {
            for j in -n..=n {
                for k in -n..=n {
                    let r = ((i * i + j * j + k * k) as f32).sqrt() * spacing;
                    sum += self.value(r) as f64;
                }
            }
        }
        (sum * (spacing as f64).powi(3)) as f32
    }
}

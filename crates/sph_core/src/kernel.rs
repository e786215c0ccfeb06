//! Smoothing kernels of Müller, Charypar & Gross 2003 ("Particle-based fluid simulation for
//! interactive applications") and the cohesion spline of Akinci, Akinci & Teschner 2013
//! ("Versatile surface tension and adhesion for SPH fluids").
//!
//! All kernels have compact support `h` and are zero for `r >= h`. The constants are the papers'
//! (the design document's text has typos in three of them; see the crate README).

use glam::Vec3;
use std::f32::consts::PI;

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

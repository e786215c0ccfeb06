//! The fluid's force and moment on each body, summed on the GPU in 64-bit fixed point.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// Bodies whose force the GPU sums: the walls and the first 31 collider slots. A body beyond
/// is left out of the sums (its [`GpuBodyForces::mean`] is `None`). While no collider is in
/// the boundary nothing is summed (no reader asks for the walls' force; `body_reactions.wgsl`).
pub const GPU_BODY_SLOTS: usize = 32;

/// Components summed per body: the force and Σ x_b × f (the moment about the world origin).
pub const GPU_BODY_COMPONENTS: usize = 6;

/// The fluid's force on each body summed on the device over one frame's force evaluations
/// (WGSL `SphBodyForces`): per body and component a 64-bit two's-complement fixed-point sum in
/// units of [`body_force_unit`] (the force) and [`body_moment_unit`] (the moment), as (low,
/// high) words, then the evaluations. Workgroups sum
/// their particles in 32-bit fixed point first; each adds its total with two 32-bit atomics and
/// the carry, so the sum is exact whatever the order.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
pub struct GpuBodyForces {
    /// (low, high) words of each body's six sums, body-major: sum k at `2k`, `2k + 1`.
    pub sums: [u32; 2 * GPU_BODY_SLOTS * GPU_BODY_COMPONENTS],
    /// Force evaluations summed (forces passes since the buffer was cleared).
    pub evaluations: u32,
    /// The number of the frame that wrote the buffer last (the plugin's frame counter, written
    /// by the CPU every frame, with steps or not): how old a reading is.
    pub frame: u32,
    /// Padding.
    pub pad: [u32; 2],
}

impl Default for GpuBodyForces {
    fn default() -> Self {
        Self::zeroed()
    }
}

/// The fixed-point unit of the body forces [N]: a thousandth of the weight of one particle of
/// mass `mass` under standard gravity, so a workgroup's 32-bit sum holds two million particle
/// weights and a body's rounding error stays a thousandth of a particle's weight per workgroup.
pub fn body_force_unit(mass: f32) -> f32 {
    (mass * 9.81e-3).max(f32::MIN_POSITIVE)
}

/// The fixed-point unit of the body moments Σ x_b × f [N m]: [`body_force_unit`] / 16. Each
/// thread's moment about the world origin is rounded to it before the sums, and the torque about
/// a body's origin is the small difference of two such moments: with the force's unit, a few
/// hundred particles next to a body left the GPU's torque 3e-4 to 6e-4 N m from the CPU's in
/// `tests/colliders.rs` (a tenth of a particle's weight times 1 m is 8e-4 N m there), as large as
/// the torques compared. A workgroup's 32-bit sum still holds over 100,000 particle weights times 1 m.
pub fn body_moment_unit(mass: f32) -> f32 {
    body_force_unit(mass) / 16.0
}

impl GpuBodyForces {
    /// Byte offset of [`Self::frame`].
    pub const FRAME_OFFSET: u64 = std::mem::offset_of!(GpuBodyForces, frame) as u64;

    /// The value of one sum in units.
    fn value(&self, body: usize, component: usize) -> i64 {
        let k = 2 * (body * GPU_BODY_COMPONENTS + component);
        ((self.sums[k + 1] as u64) << 32 | self.sums[k] as u64) as i64
    }

    /// Body `body`'s force [N] and torque about `origin` [N m], each the mean over the summed
    /// evaluations, for particles of mass `mass`; `None` beyond [`GPU_BODY_SLOTS`] or without
    /// evaluations.
    pub fn mean(&self, body: usize, mass: f32, origin: Vec3) -> Option<crate::BodyForce> {
        if body >= GPU_BODY_SLOTS || self.evaluations == 0 {
            return None;
        }
        let per_evaluation = 1.0 / self.evaluations as f64;
        let v = |k: usize, unit: f32| {
            glam::DVec3::new(
                self.value(body, k) as f64,
                self.value(body, k + 1) as f64,
                self.value(body, k + 2) as f64,
            ) * (unit as f64 * per_evaluation)
        };
        let (force, moment) = (v(0, body_force_unit(mass)), v(3, body_moment_unit(mass)));
        // Σ (x_b - o) × f = Σ x_b × f - o × Σ f.
        let torque = moment - origin.as_dvec3().cross(force);
        Some(crate::BodyForce {
            force: force.as_vec3(),
            torque: torque.as_vec3(),
        })
    }
}

#[cfg(test)]
mod body_force_tests {
    use super::*;

    /// Adds `units` to one sum the way the WGSL does: the low word with its carry, then the
    /// sign-extended high word.
    fn add(sums: &mut GpuBodyForces, at: usize, units: i32) {
        let (low, carry) = sums.sums[2 * at].overflowing_add(units as u32);
        sums.sums[2 * at] = low;
        sums.sums[2 * at + 1] = sums.sums[2 * at + 1]
            .wrapping_add(if units < 0 { u32::MAX } else { 0 })
            .wrapping_add(carry as u32);
    }

    #[test]
    fn fixed_point_sums_are_exact_and_give_the_torque_about_the_origin() {
        let mut sums = GpuBodyForces::default();
        // Body 1: 3 evaluations of a force (0, -2000, 0) units at x = (1, 0, 0) [m], added in
        // pieces of both signs that cross the 32-bit range of the low word many times.
        let moment_units = (body_force_unit(1.0) / body_moment_unit(1.0)).round() as usize;
        assert_eq!(moment_units, 16);
        for _ in 0..3 {
            for piece in [-1_000_000_000, 999_998_000, -1_000, -1_000] {
                add(&mut sums, GPU_BODY_COMPONENTS + 1, piece);
                // Σ x × f with x = (1, 0, 0): z component = x f_y, in 16 times finer units.
                for _ in 0..moment_units {
                    add(&mut sums, GPU_BODY_COMPONENTS + 5, piece);
                }
            }
        }
        sums.evaluations = 3;
        let mass = 0.008;
        let unit = body_force_unit(mass) as f64;
        let f = sums.mean(1, mass, Vec3::ZERO).unwrap();
        let expected = (-1_000_000_000.0 + 999_998_000.0 - 2_000.0) * unit;
        assert!((f.force.y as f64 - expected).abs() < 1e-6 * expected.abs());
        assert!((f.torque.z as f64 - expected).abs() < 1e-6 * expected.abs());
        // About the point of application the torque vanishes.
        let at_point = sums.mean(1, mass, Vec3::X).unwrap();
        assert!(at_point.torque.length() < 1e-6 * expected.abs() as f32);
        assert_eq!(sums.mean(0, mass, Vec3::ZERO).unwrap().force, Vec3::ZERO);
        assert!(sums.mean(GPU_BODY_SLOTS, mass, Vec3::ZERO).is_none());
        sums.evaluations = 0;
        assert!(sums.mean(1, mass, Vec3::ZERO).is_none());
    }
}

//! Time integration with the guard, one function per phase so the GPU integrate passes are
//! translations of these loops. The phases that move particles run the [`Guard`] and return how
//! many particles it corrected; the closing kicks only reflect velocities at the box's walls.

use crate::boundary::guard::{Corrections, Guard};
use glam::Vec3;
use rayon::prelude::*;

/// Symplectic Euler: v += a dt; x += v dt; guard. Returns the corrections.
pub fn euler(x: &mut [Vec3], v: &mut [Vec3], a: &[Vec3], dt: f32, guard: &Guard) -> Corrections {
    x.par_iter_mut()
        .zip(v.par_iter_mut())
        .zip(a.par_iter())
        .map(|((x, v), &a)| {
            *v += a * dt;
            *x += *v * dt;
            guard.apply(x, v)
        })
        .sum()
}

/// Kick-drift-kick, first half: v½ = v + a dt/2; x += v½ dt; guard; and the predicted velocity
/// the viscosity term will see, v* = v½ + a dt/2. Returns the corrections.
pub fn kick_drift(
    x: &mut [Vec3],
    v: &mut [Vec3],
    v_predicted: &mut [Vec3],
    a: &[Vec3],
    dt: f32,
    guard: &Guard,
) -> Corrections {
    x.par_iter_mut()
        .zip(v.par_iter_mut())
        .zip(v_predicted.par_iter_mut())
        .zip(a.par_iter())
        .map(|(((x, v), v_pred), &a)| {
            *v += a * (0.5 * dt);
            *x += *v * dt;
            let corrected = guard.apply(x, v);
            *v_pred = *v + a * (0.5 * dt);
            corrected
        })
        .sum()
}

/// Kick-drift-kick, closing kick with the new acceleration: v = v½ + a dt/2; wall response.
pub fn kick(x: &mut [Vec3], v: &mut [Vec3], a: &[Vec3], dt: f32, guard: &Guard) {
    x.par_iter_mut()
        .zip(v.par_iter_mut())
        .zip(a.par_iter())
        .for_each(|((x, v), &a)| {
            *v += a * (0.5 * dt);
            guard.walls.collide(x, v);
        });
}

/// The design's leapfrog, drift (design eqs. 18-19): x += v dt + a0 dt²/2, predicted velocity
/// v* = v + a0 dt for the second force evaluation; guard with v*. Returns the corrections.
pub fn leapfrog_drift(
    x: &mut [Vec3],
    v: &[Vec3],
    v_predicted: &mut [Vec3],
    a0: &[Vec3],
    dt: f32,
    guard: &Guard,
) -> Corrections {
    x.par_iter_mut()
        .zip(v.par_iter())
        .zip(v_predicted.par_iter_mut())
        .zip(a0.par_iter())
        .map(|(((x, &v), v_pred), &a0)| {
            *x += v * dt + a0 * (0.5 * dt * dt);
            *v_pred = v + a0 * dt;
            guard.apply(x, v_pred)
        })
        .sum()
}

/// The design's leapfrog, velocity update (design eqs. 20-21): v += (a0 + a1) dt/2; wall response.
pub fn leapfrog_kick(
    x: &mut [Vec3],
    v: &mut [Vec3],
    a0: &[Vec3],
    a1: &[Vec3],
    dt: f32,
    guard: &Guard,
) {
    x.par_iter_mut()
        .zip(v.par_iter_mut())
        .zip(a0.par_iter().zip(a1.par_iter()))
        .for_each(|((x, v), (&a0, &a1))| {
            *v += (a0 + a1) * (0.5 * dt);
            guard.walls.collide(x, v);
        });
}

//! Pumps: volumes that push the water along a direction toward a target speed (the Aquaplay
//! crank pump).
//!
//! Inside the pump's box, the velocity component u = v·d along the unit direction d relaxes
//! toward the target speed s at the rate k (the strength): du/dt = k (s − u) while u < s. The
//! pump only pushes: water already faster than s along d is left alone, and the other
//! components are never touched. Each step applies the exact solution of that equation over the
//! step's dt, u' = s − (s − u) e^(−k dt), so any strength is stable at any dt.

use crate::flow::region::Region;
use crate::params::ParamError;
use glam::Vec3;
use rayon::prelude::*;

/// The largest pump strength [1/s]: a relaxation time of one millisecond.
pub const MAX_PUMP_STRENGTH: f32 = 1000.0;
/// The largest target speed [m/s].
pub const MAX_PUMP_SPEED: f32 = 100.0;

/// A pump: a box, a direction, a target speed and a strength.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "bevy_reflect", derive(bevy_reflect::Reflect))]
pub struct Pump {
    /// Where the pump acts.
    pub region: Region,
    /// The direction it pushes in the world (normalized when applied; not zero).
    pub direction: Vec3,
    /// The target speed along `direction` [m/s], 0 ..= 100.
    pub speed: f32,
    /// The relaxation rate toward the target speed [1/s], 0 (off) ..= 1000.
    pub strength: f32,
}

impl Pump {
    /// Checks the box, the direction, the speed and the strength; the error names the field.
    pub fn validate(&self) -> Result<(), ParamError> {
        self.region.validate("pump.region")?;
        if !(self.direction.is_finite() && self.direction.length_squared() > 1e-12) {
            return Err(ParamError {
                field: "pump.direction",
                value: format!("{:?}", self.direction),
                allowed: "a finite, non-zero vector",
            });
        }
        if !(0.0..=MAX_PUMP_SPEED).contains(&self.speed) {
            return Err(ParamError {
                field: "pump.speed",
                value: self.speed.to_string(),
                allowed: "[0, 100] m/s",
            });
        }
        if !(0.0..=MAX_PUMP_STRENGTH).contains(&self.strength) {
            return Err(ParamError {
                field: "pump.strength",
                value: self.strength.to_string(),
                allowed: "[0, 1000] 1/s",
            });
        }
        Ok(())
    }

    /// The velocity of a particle at `x` moving at `v` after a step of `dt` in this pump.
    #[inline]
    pub fn velocity_after(&self, x: Vec3, v: Vec3, dt: f32) -> Vec3 {
        if self.strength <= 0.0 || !self.region.contains(x) {
            return v;
        }
        let d = self.direction.normalize();
        let u = v.dot(d);
        if u >= self.speed {
            return v;
        }
        let relaxed = self.speed - (self.speed - u) * (-self.strength * dt).exp();
        v + d * (relaxed - u)
    }
}

/// Applies every pump to every particle over a step of `dt` [s].
pub fn apply_pumps(pumps: &[Pump], position: &[Vec3], velocity: &mut [Vec3], dt: f32) {
    if pumps.is_empty() || dt.is_nan() || dt <= 0.0 {
        return;
    }
    velocity
        .par_iter_mut()
        .zip(position.par_iter())
        .for_each(|(v, &x)| {
            for pump in pumps {
                *v = pump.velocity_after(x, *v, dt);
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pump() -> Pump {
        Pump {
            region: Region::from_min_max(Vec3::ZERO, Vec3::ONE),
            direction: Vec3::new(2.0, 0.0, 0.0),
            speed: 0.5,
            strength: 4.0,
        }
    }

    #[test]
    fn pushes_toward_the_target_speed_exactly_and_never_past_it() {
        let p = pump();
        let x = Vec3::splat(0.5);
        // From rest, one step of 0.25 s: u = 0.5 (1 - e^-1).
        let v = p.velocity_after(x, Vec3::new(0.0, -1.0, 0.3), 0.25);
        assert!((v.x - 0.5 * (1.0 - (-1.0f32).exp())).abs() < 1e-6, "{v}");
        assert_eq!(
            (v.y, v.z),
            (-1.0, 0.3),
            "only the component along d changes"
        );
        // Many steps converge on s from below; a huge dt lands on s.
        assert!((p.velocity_after(x, Vec3::ZERO, 1e6).x - 0.5).abs() < 1e-6);
        // Faster water and water outside the box are left alone.
        assert_eq!(p.velocity_after(x, Vec3::X, 0.1), Vec3::X);
        assert_eq!(
            p.velocity_after(Vec3::splat(2.0), Vec3::ZERO, 0.1),
            Vec3::ZERO
        );
    }

    #[test]
    fn refuses_bad_settings_by_field() {
        for (bad, field) in [
            (
                Pump {
                    direction: Vec3::ZERO,
                    ..pump()
                },
                "pump.direction",
            ),
            (
                Pump {
                    speed: -1.0,
                    ..pump()
                },
                "pump.speed",
            ),
            (
                Pump {
                    speed: f32::NAN,
                    ..pump()
                },
                "pump.speed",
            ),
            (
                Pump {
                    strength: 1e4,
                    ..pump()
                },
                "pump.strength",
            ),
        ] {
            assert_eq!(bad.validate().unwrap_err().field, field);
        }
        assert!(pump().validate().is_ok());
    }
}

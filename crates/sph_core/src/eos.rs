//! Equations of state: density to pressure.

use crate::params::{EquationOfState, SphParams};

/// Constants of the equation of state, taken from [`SphParams`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eos {
    /// Which law.
    pub law: EquationOfState,
    /// Stiffness k (Tait's B).
    pub stiffness: f32,
    /// Rest density ρ0.
    pub rest_density: f32,
    /// Whether negative pressures are clamped to zero.
    pub clamp_negative: bool,
}

impl Eos {
    /// The equation of state of `params`.
    pub fn from_params(params: &SphParams) -> Self {
        Self {
            law: params.equation_of_state,
            stiffness: params.stiffness,
            rest_density: params.rest_density,
            clamp_negative: params.clamp_negative_pressure,
        }
    }

    /// Pressure [Pa] at density `rho`: linear p = k (ρ - ρ0) (Müller 2003 eq. 12) or
    /// Tait p = k ((ρ/ρ0)⁷ - 1), optionally clamped at zero.
    #[inline]
    pub fn pressure(&self, rho: f32) -> f32 {
        let p = match self.law {
            EquationOfState::Linear => self.stiffness * (rho - self.rest_density),
            EquationOfState::Tait => {
                let ratio = rho / self.rest_density;
                let r2 = ratio * ratio;
                let r3 = r2 * ratio;
                self.stiffness * (r3 * r3 * ratio - 1.0)
            }
        };
        if self.clamp_negative {
            p.max(0.0)
        } else {
            p
        }
    }
}

//! The settings of the diffuse particles ([`WhitewaterSettings`]), with Ihmsen et al. 2012's
//! names, and their validation.

use crate::params::{check_range, ParamError};

/// A potential's clamping range: below `min` it gives nothing, from `max` on it gives 1
/// (Ihmsen et al. 2012, eq. 1, Φ).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// τ_min.
    pub min: f32,
    /// τ_max.
    pub max: f32,
}

impl Limits {
    /// Φ(I) = (min(I, τ_max) - min(I, τ_min)) / (τ_max - τ_min), in [0, 1]; 0 for a non-finite I.
    pub fn clamp(&self, value: f32) -> f32 {
        if !value.is_finite() || self.max <= self.min {
            return 0.0;
        }
        (value.min(self.max) - value.min(self.min)) / (self.max - self.min)
    }
}

/// How much whitewater the water sheds, how the diffuse particles are told apart and how they
/// move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WhitewaterSettings {
    /// The trapped-air potential's limits: Σ_j |v_ij| (1 - v̂_ij·x̂_ij) W̃_ij [m/s].
    pub trapped_air: Limits,
    /// The wave-crest potential's limits: the surface curvature κ̃ of water moving along its
    /// normal [dimensionless].
    pub wave_crest: Limits,
    /// The kinetic-energy potential's limits, per unit mass: |v|²/2 [J/kg] (the paper's
    /// m |v|²/2 depends on the particle size; per unit mass the limits hold at any Δx).
    pub kinetic_energy: Limits,
    /// Diffuse particles per second a fluid particle sheds at full trapped-air and kinetic
    /// potentials, k_ta [1/s].
    pub trapped_air_rate: f32,
    /// The same at full wave-crest and kinetic potentials, k_wc [1/s].
    pub wave_crest_rate: f32,
    /// A diffuse particle with fewer fluid neighbours than this is spray.
    pub spray_below: u32,
    /// A diffuse particle with more fluid neighbours than this is a bubble; in between, foam.
    pub bubble_above: u32,
    /// A foam particle's lifetime [s], drawn in this range at birth.
    pub lifetime: (f32, f32),
    /// Bubbles' buoyancy k_b: a = -k_b g + k_d (ṽ - v) / dt.
    pub buoyancy: f32,
    /// Bubbles' drag k_d, the share of the velocity difference to the water taken in a step.
    pub drag: f32,
}

impl Default for WhitewaterSettings {
    /// The limits of SPlisHSPlasH's foam generator for trapped air (5 to 20, scaled to m/s of our
    /// unnormalised kernel sums: 0.5 to 2) and wave crests (2 to 8 over 10: 0.2 to 0.8), kinetic
    /// energy from |v| = 1 m/s to 3.2 m/s, the paper's buoyancy 2 and drag 0.8, neighbour
    /// bounds 6 and 20, foam living 2 to 5 s, and rates that shed a few particles a second from
    /// a breaking particle.
    fn default() -> Self {
        Self {
            trapped_air: Limits { min: 0.5, max: 2.0 },
            wave_crest: Limits { min: 0.2, max: 0.8 },
            kinetic_energy: Limits { min: 0.5, max: 5.0 },
            trapped_air_rate: 40.0,
            wave_crest_rate: 40.0,
            spray_below: 6,
            bubble_above: 20,
            lifetime: (2.0, 5.0),
            buoyancy: 2.0,
            drag: 0.8,
        }
    }
}

/// The largest rate a fluid particle may shed at [1/s].
pub const MAX_SHED_RATE: f32 = 10_000.0;
/// The longest foam lifetime [s].
pub const MAX_LIFETIME: f32 = 600.0;
/// The largest neighbour bound of the classes.
pub const MAX_NEIGHBOR_BOUND: u32 = 1_000;

/// The most diffuse particles a pool may hold.
pub const MAX_WHITEWATER_CAPACITY: usize = 1 << 24;

/// Refuses a pool of `capacity` diffuse particles outside 1 ..= [`MAX_WHITEWATER_CAPACITY`],
/// by the field `whitewater.capacity`.
pub fn check_capacity(capacity: usize) -> Result<(), ParamError> {
    if (1..=MAX_WHITEWATER_CAPACITY).contains(&capacity) {
        return Ok(());
    }
    Err(ParamError {
        field: "whitewater.capacity",
        value: capacity.to_string(),
        allowed: "[1, 2^24] diffuse particles",
    })
}

impl Limits {
    /// Checks that 0 ≤ min < max, both finite; the error names `min_field` or `max_field`.
    fn validate(&self, min_field: &'static str, max_field: &'static str) -> Result<(), ParamError> {
        check_range(
            min_field,
            self.min,
            0.0,
            true,
            f32::MAX,
            "[0, max) and finite",
        )?;
        if self.max.is_finite() && self.max > self.min {
            Ok(())
        } else {
            Err(ParamError {
                field: max_field,
                value: format!("{}", self.max),
                allowed: "(min, ∞) and finite",
            })
        }
    }
}

impl WhitewaterSettings {
    /// Checks every field; the error names the first field out of range.
    pub fn validate(&self) -> Result<(), ParamError> {
        self.trapped_air
            .validate("whitewater.trapped_air.min", "whitewater.trapped_air.max")?;
        self.wave_crest
            .validate("whitewater.wave_crest.min", "whitewater.wave_crest.max")?;
        self.kinetic_energy.validate(
            "whitewater.kinetic_energy.min",
            "whitewater.kinetic_energy.max",
        )?;
        check_range(
            "whitewater.trapped_air_rate",
            self.trapped_air_rate,
            0.0,
            true,
            MAX_SHED_RATE,
            "[0, 10000] 1/s",
        )?;
        check_range(
            "whitewater.wave_crest_rate",
            self.wave_crest_rate,
            0.0,
            true,
            MAX_SHED_RATE,
            "[0, 10000] 1/s",
        )?;
        if self.bubble_above > MAX_NEIGHBOR_BOUND {
            return Err(ParamError {
                field: "whitewater.bubble_above",
                value: self.bubble_above.to_string(),
                allowed: "[spray_below, 1000] neighbours",
            });
        }
        if self.spray_below > self.bubble_above {
            return Err(ParamError {
                field: "whitewater.spray_below",
                value: self.spray_below.to_string(),
                allowed: "[0, bubble_above] neighbours",
            });
        }
        let (low, high) = self.lifetime;
        check_range(
            "whitewater.lifetime.0",
            low,
            0.0,
            false,
            MAX_LIFETIME,
            "(0, 600] s",
        )?;
        check_range(
            "whitewater.lifetime.1",
            high,
            low,
            true,
            MAX_LIFETIME,
            "[lifetime.0, 600] s",
        )?;
        check_range(
            "whitewater.buoyancy",
            self.buoyancy,
            0.0,
            true,
            100.0,
            "[0, 100] (times -g)",
        )?;
        check_range(
            "whitewater.drag",
            self.drag,
            0.0,
            true,
            1.0,
            "[0, 1] (a share of the velocity difference per step)",
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_pass_and_each_bad_field_is_named() {
        assert_eq!(WhitewaterSettings::default().validate(), Ok(()));
        let field = |change: fn(&mut WhitewaterSettings)| {
            let mut s = WhitewaterSettings::default();
            change(&mut s);
            s.validate().unwrap_err().field
        };
        assert_eq!(
            field(|s| s.trapped_air.min = -1.0),
            "whitewater.trapped_air.min"
        );
        assert_eq!(
            field(|s| s.wave_crest.max = 0.1),
            "whitewater.wave_crest.max"
        );
        assert_eq!(
            field(|s| s.kinetic_energy.max = f32::INFINITY),
            "whitewater.kinetic_energy.max"
        );
        assert_eq!(
            field(|s| s.trapped_air_rate = f32::NAN),
            "whitewater.trapped_air_rate"
        );
        assert_eq!(
            field(|s| s.wave_crest_rate = 1e6),
            "whitewater.wave_crest_rate"
        );
        assert_eq!(field(|s| s.spray_below = 30), "whitewater.spray_below");
        assert_eq!(field(|s| s.bubble_above = 5_000), "whitewater.bubble_above");
        assert_eq!(field(|s| s.lifetime = (0.0, 1.0)), "whitewater.lifetime.0");
        assert_eq!(field(|s| s.lifetime = (3.0, 2.0)), "whitewater.lifetime.1");
        assert_eq!(field(|s| s.buoyancy = -1.0), "whitewater.buoyancy");
        assert_eq!(field(|s| s.drag = 1.5), "whitewater.drag");
    }
}

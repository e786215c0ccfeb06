//! A scene file's `whitewater: (...)`: the diffuse particles on, with the settings it changes
//! from [`WhitewaterSettings::default`].

use crate::params::ParamError;
use crate::whitewater::settings::{check_capacity, Limits, WhitewaterSettings};
use serde::Deserialize;

/// Whitewater as a scene file writes it; every field is optional.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WhitewaterSpec {
    /// The most diffuse particles at once; default 65,536.
    #[serde(default)]
    pub capacity: Option<u32>,
    /// The trapped-air potential's limits (min, max) [m/s].
    #[serde(default)]
    pub trapped_air: Option<(f32, f32)>,
    /// The wave-crest potential's limits (min, max).
    #[serde(default)]
    pub wave_crest: Option<(f32, f32)>,
    /// The kinetic-energy potential's limits (min, max) [J/kg].
    #[serde(default)]
    pub kinetic_energy: Option<(f32, f32)>,
    /// Diffuse particles a second a particle sheds at full trapped-air potential [1/s].
    #[serde(default)]
    pub trapped_air_rate: Option<f32>,
    /// The same at full wave-crest potential [1/s].
    #[serde(default)]
    pub wave_crest_rate: Option<f32>,
    /// Foam's lifetime range (shortest, longest) [s].
    #[serde(default)]
    pub lifetime: Option<(f32, f32)>,
}

/// The pool's capacity when the file gives none.
pub const DEFAULT_CAPACITY: u32 = 65_536;

impl WhitewaterSpec {
    /// The settings and the capacity, validated; the error names the first field refused.
    pub fn build(&self) -> Result<(WhitewaterSettings, u32), ParamError> {
        let base = WhitewaterSettings::default();
        let limits = |range: Option<(f32, f32)>, base: Limits| {
            range.map_or(base, |(min, max)| Limits { min, max })
        };
        let settings = WhitewaterSettings {
            trapped_air: limits(self.trapped_air, base.trapped_air),
            wave_crest: limits(self.wave_crest, base.wave_crest),
            kinetic_energy: limits(self.kinetic_energy, base.kinetic_energy),
            trapped_air_rate: self.trapped_air_rate.unwrap_or(base.trapped_air_rate),
            wave_crest_rate: self.wave_crest_rate.unwrap_or(base.wave_crest_rate),
            lifetime: self.lifetime.unwrap_or(base.lifetime),
            ..base
        };
        settings.validate()?;
        let capacity = self.capacity.unwrap_or(DEFAULT_CAPACITY);
        check_capacity(capacity as usize)?;
        Ok((settings, capacity))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_empty_spec_is_the_default_settings() {
        let (settings, capacity) = WhitewaterSpec::default().build().unwrap();
        assert_eq!(settings, WhitewaterSettings::default());
        assert_eq!(capacity, DEFAULT_CAPACITY);
    }

    #[test]
    fn a_field_out_of_range_is_refused_by_name() {
        let zero = WhitewaterSpec {
            capacity: Some(0),
            ..Default::default()
        };
        assert_eq!(zero.build().unwrap_err().field, "whitewater.capacity");
        let reversed = WhitewaterSpec {
            trapped_air: Some((2.0, 1.0)),
            ..Default::default()
        };
        assert!(reversed
            .build()
            .unwrap_err()
            .field
            .starts_with("whitewater.trapped_air"));
    }
}

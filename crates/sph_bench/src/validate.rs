//! `sph-bench validate`: the Martin & Moyce (1952) dam break against experiment (the RMS of the
//! front error Z for T <= 2.5, raw and with the best time shift in [0, 0.3]: see `martin_moyce`)
//! and the hydrostatic tank against ρ0 g depth.

use crate::args::{RunArgs, ValidateArgs};
use crate::progress::Bars;
use crate::report::Report;
use crate::scenarios::Scenario;
use serde::Serialize;

/// Both validations.
#[derive(Clone, Debug, Serialize)]
pub struct ValidateReport {
    /// The dam break against Martin & Moyce.
    pub dam_break: Report,
    /// The tank at rest against ρ0 g depth.
    pub hydrostatic: Report,
}

/// Runs the dam break and the hydrostatic tank.
pub fn run(args: &ValidateArgs, bars: &Bars) -> Result<ValidateReport, String> {
    let dam_break = crate::run::run(
        &RunArgs {
            scenario: Scenario::DamBreak,
            ..args.base()
        },
        bars,
    )?;
    let hydrostatic = crate::run::run(
        &RunArgs {
            scenario: Scenario::Hydrostatic,
            particles: args.hydrostatic_particles,
            ..args.base()
        },
        bars,
    )?;
    Ok(ValidateReport {
        dam_break,
        hydrostatic,
    })
}

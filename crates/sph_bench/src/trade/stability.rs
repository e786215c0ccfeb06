//! The largest stable time step of each integrator, found by bisection with rollback off.

use super::plan::SWEEP_PARTICLES;
use crate::args::{Backend, Duration, RunArgs};
use crate::progress::Bars;
use crate::report::Report;
use crate::run::{configured_setup, run_setup};
use sph_core::Integrator;

/// Simulated time of a stability probe [s].
pub(super) const STABILITY_TIME: f32 = 2.0;

/// Largest mean compression error a stable run may reach [%].
pub(super) const STABLE_DENSITY_ERROR_PCT: f32 = 10.0;

/// Whether a run is stable by the study's rule: no instability detected, no NaN, nothing outside,
/// and the mean compression error stayed below 10 %.
fn stable(r: &Report) -> bool {
    r.health == "ok" && r.density_error_mean_max_pct < STABLE_DENSITY_ERROR_PCT
}

/// The options of `integrator`'s stability probes (their dt aside): rollback off, since a
/// rolled-back step would hide the instability the search looks for.
pub(super) fn probe_args(integrator: Integrator) -> RunArgs {
    RunArgs {
        particles: SWEEP_PARTICLES,
        integrator,
        time: Some(STABILITY_TIME),
        rollback: false,
        ..Default::default()
    }
}

/// The largest stable dt of `integrator` on the dam break, by bisection in log(dt) between the
/// derived step (stable) and 0.01 s, with rollback off; returns (that dt, the derived dt, probes).
pub(super) fn largest_stable_dt(
    integrator: Integrator,
    bars: &Bars,
) -> Result<(f32, f32, u32), String> {
    let base = probe_args(integrator);
    let derived = configured_setup(&base).scene.params.time_step;
    let probe = |dt: f32| -> Result<bool, String> {
        let setup = configured_setup(&RunArgs {
            dt: Some(dt),
            ..base.clone()
        });
        let duration = Duration::Time(STABILITY_TIME.into());
        let r = run_setup(&setup, Backend::Cpu, 1, duration, bars)?;
        let ok = stable(&r);
        bars.note(format_args!(
            "  {integrator:?} dt {dt:.3e}: {} (mean density error peak {:.2} %)",
            if ok { "stable" } else { "unstable" },
            r.density_error_mean_max_pct
        ));
        Ok(ok)
    };
    let (mut lo, mut hi) = (derived, 0.01f32);
    let mut probes = 0;
    if !probe(lo)? {
        return Ok((0.0, derived, 1));
    }
    if probe(hi)? {
        return Ok((hi, derived, 2));
    }
    probes += 2;
    // 2 % resolution in dt.
    while hi / lo > 1.02 {
        let mid = (lo * hi).sqrt();
        if probe(mid)? {
            lo = mid;
        } else {
            hi = mid;
        }
        probes += 1;
    }
    Ok((lo, derived, probes))
}

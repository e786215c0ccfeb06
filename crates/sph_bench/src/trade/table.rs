//! The study's rows (a planned run with its report) and the Markdown tables made of them.

use super::plan::{Planned, WHITEWATER_GROUP};
use crate::args::{Backend, Duration};
use crate::progress::Bars;
use crate::report::Report;
use crate::run::{configured_setup, run_setup};
use std::fmt::Write as _;

/// One row of the table: what was varied, and the report.
pub(super) struct Row {
    pub(super) group: &'static str,
    pub(super) label: String,
    pub(super) report: Report,
}

/// Runs a planned run of the study.
pub(super) fn run_row(planned: Planned, bars: &Bars) -> Result<Row, String> {
    let Planned { group, label, args } = planned;
    let setup = configured_setup(&args);
    let duration = args.duration().unwrap_or(Duration::Time(setup.duration));
    let report = run_setup(&setup, args.backend, args.substeps, duration, bars)?;
    Ok(Row {
        group,
        label,
        report,
    })
}

fn fmt_opt(v: f64) -> String {
    if v.is_finite() && v > 0.0 {
        format!("{v:.3}")
    } else {
        "–".into()
    }
}

/// Simulated seconds per wall-clock second (the inverse of the cost), 3 significant digits.
pub(super) fn real_time_factor(r: &Report) -> String {
    let factor = 1.0 / r.cost_per_sim_second_s;
    if factor.is_finite() && factor > 0.0 {
        format!("{factor:.3}")
    } else {
        "–".into()
    }
}

/// The table of every run: what was varied, the settings, speed, accuracy and health.
pub(super) fn table(rows: &[Row]) -> String {
    let mut s = String::from(
        "| group | run | backend | particles | solver | integrator | search | surface tension | dt | mean dt [s] | iterations (density / divergence) | ms/step | cost per sim s [s] | real-time factor | density error end [%] | mean over run [%] | peak of mean [%] | RMS Z raw | RMS Z shifted | health |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for row in rows {
        let r = &row.report;
        let (raw, shifted) = r
            .dam_break
            .as_ref()
            .map_or((f64::NAN, f64::NAN), |d| (d.rms_z_raw, d.rms_z_shifted));
        let dt = if r.adaptive_time_step {
            format!("adaptive λ {} (≤ {:.1e})", r.cfl_factor, r.dt)
        } else {
            format!("{:.2e}", r.dt)
        };
        let mut health = match r.unstable_step {
            Some(step) => format!("unstable at step {step}"),
            None => r.health.clone(),
        };
        if r.rollbacks > 0 {
            let _ = write!(health, " ({} rollbacks)", r.rollbacks);
        }
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2e} | {} | {:.2} | {:.1} | {} | {:.4} | {:.4} | {:.3} | {} | {} | {} |",
            row.group,
            row.label,
            r.backend,
            r.particles,
            r.solver,
            if r.solver == "wcsph" { r.integrator.as_str() } else { "–" },
            r.search,
            if r.surface_tension { "on" } else { "off" },
            dt,
            r.dt_mean,
            if r.solver == "wcsph" {
                "–".to_string()
            } else {
                format!(
                    "{:.1} (max {}) / {:.1}",
                    r.pressure_iterations_mean,
                    r.pressure_iterations_max,
                    r.divergence_iterations_mean
                )
            },
            r.ms_per_step_median,
            r.cost_per_sim_second_s,
            real_time_factor(r),
            r.density_error_mean_pct,
            r.density_error_mean_run_pct,
            r.density_error_mean_max_pct,
            fmt_opt(raw),
            fmt_opt(shifted),
            health
        );
    }
    s
}

/// Milliseconds per step of the row matching `pred`.
fn ms_of(rows: &[Row], pred: impl Fn(&Row) -> bool) -> Option<f64> {
    rows.iter()
        .find(|r| pred(r))
        .map(|r| r.report.ms_per_step_median)
}

/// What whitewater adds to a simulated second of the row's water, in seconds of wall clock and
/// against the water's own cost: its cost over the run over the run's simulated time.
fn whitewater_cost(row: &Row) -> Option<String> {
    let (r, w) = (&row.report, row.report.whitewater.as_ref()?);
    let added = w.ms_total / 1e3 / r.sim_time.max(1e-9);
    Some(format!(
        "+{added:.2} s per sim s ({:+.0} %), {} diffuse at the end",
        added / r.cost_per_sim_second_s * 100.0,
        w.spray + w.foam + w.bubbles
    ))
}

/// What the optional stages cost on each backend, against the baseline at `particles`, and
/// what whitewater adds to the water's cost.
pub(super) fn stage_cost_table(rows: &[Row], backends: &[Backend], particles: usize) -> String {
    let mut s = String::from(
        "| backend | baseline (viscosity on, surface tension off) ms/step | surface tension on | viscosity off | whitewater on |\n|---|---|---|---|---|\n",
    );
    for &b in backends {
        let name = b.name();
        let at = |group: &str| {
            ms_of(rows, |r| {
                r.group == group && r.report.backend == name && r.report.particles >= particles / 2
            })
        };
        let base = ms_of(rows, |r| {
            r.group == "particles"
                && r.report.backend == name
                && r.label == format!("about {particles} particles")
        });
        let cell = |v: Option<f64>| match (v, base) {
            (Some(v), Some(b)) => format!("{v:.2} ({:+.0} %)", (v / b - 1.0) * 100.0),
            _ => "–".into(),
        };
        let whitewater = rows
            .iter()
            .find(|r| r.group == WHITEWATER_GROUP && r.report.backend == name)
            .and_then(whitewater_cost);
        let _ = writeln!(
            s,
            "| {name} | {} | {} | {} | {} |",
            base.map_or("–".into(), |b| format!("{b:.2}")),
            cell(at("surface tension")),
            cell(at("viscosity")),
            whitewater.unwrap_or_else(|| "–".into())
        );
    }
    s
}

//! `sph-bench`: runs SPH scenarios on the CPU solver or the GPU plugin and writes the figures
//! (speed, accuracy, stability) as JSON; validates against experiments; sweeps the speed-against-
//! accuracy trade into a table and a plot; soaks. See the README for the options.

mod args;
mod hydrostatic;
mod plot;
mod report;
mod run;
mod scenarios;
mod sim;
mod soak;
mod trade;
mod validate;

use args::USAGE;

/// Writes a report as pretty JSON to `path`, or to stdout without one.
fn write_json(report: &impl serde::Serialize, path: &Option<String>) -> Result<(), String> {
    let json = serde_json::to_string_pretty(report).map_err(|e| e.to_string())?;
    match path {
        Some(path) => {
            std::fs::write(path, json + "\n").map_err(|e| format!("cannot write {path}: {e}"))
        }
        None => {
            println!("{json}");
            Ok(())
        }
    }
}

fn health_text(r: &report::Report) -> String {
    match r.unstable_step {
        Some(step) => format!("unstable at step {step}"),
        None => r.health.clone(),
    }
}

fn main() {
    let argv: Vec<String> = std::env::args().skip(1).collect();
    let rest = argv.get(1..).unwrap_or_default();
    let result = match argv.first().map(String::as_str) {
        Some("run") => args::parse_run(rest).and_then(|args| {
            eprintln!(
                "sph-bench: {} on {:?}, about {} particles",
                args.scenario.name(),
                args.backend,
                args.particles
            );
            let report = run::run(&args)?;
            write_json(&report, &args.json)?;
            eprintln!(
                "sph-bench: {} particles, {} steps, {:.3} ms/step median, {:.1} s per simulated s, \
                 {} dispatches/step, density error {:.3} % mean; {}",
                report.particles,
                report.steps,
                report.ms_per_step_median,
                report.cost_per_sim_second_s,
                report.dispatches_per_step,
                report.density_error_mean_pct,
                health_text(&report)
            );
            if let Some(d) = report.dam_break.as_ref().filter(|d| d.rms_z_raw.is_finite()) {
                eprintln!(
                    "sph-bench: RMS Z error (T <= 2.5) {:.3} raw, {:.3} with the best shift {:.2}",
                    d.rms_z_raw, d.rms_z_shifted, d.best_shift
                );
            }
            if let Some(h) = &report.hydrostatic {
                eprintln!(
                    "sph-bench: pressure vs rho g depth below the top layer: max {:.2} %, mean {:.2} %; \
                     density error {:.3} %",
                    h.max_error_below_top_pct, h.mean_error_below_top_pct, h.density_error_mean_pct
                );
            }
            Ok(())
        }),
        Some("validate") => args::parse_validate(rest).and_then(|args| {
            eprintln!(
                "sph-bench: validation on {:?}: Martin & Moyce dam break (a = {} m, about {} \
                 particles), hydrostatic tank (about {} particles)",
                args.base.backend, args.base.a, args.base.particles, args.hydrostatic_particles
            );
            let report = validate::run(&args)?;
            write_json(&report, &args.base.json)?;
            if let Some(d) = &report.dam_break.dam_break {
                eprintln!(
                    "sph-bench: dam break: RMS Z error (T <= 2.5) {:.3} raw, {:.3} with the best \
                     shift {:.2} (target <= 0.1); {}",
                    d.rms_z_raw,
                    d.rms_z_shifted,
                    d.best_shift,
                    health_text(&report.dam_break)
                );
            }
            if let Some(h) = &report.hydrostatic.hydrostatic {
                eprintln!(
                    "sph-bench: hydrostatic: pressure vs rho g depth below the top layer: max {:.2} %, \
                     mean {:.2} % (target <= 5); mean density error {:.3} % (target <= 1); {}",
                    h.max_error_below_top_pct,
                    h.mean_error_below_top_pct,
                    h.density_error_mean_pct,
                    health_text(&report.hydrostatic)
                );
            }
            Ok(())
        }),
        Some("trade") => args::parse_trade(rest).and_then(|args| {
            let done = trade::run(&args)?;
            eprintln!("sph-bench: {done}");
            Ok(())
        }),
        Some("soak") => args::parse_soak(rest).and_then(|args| {
            eprintln!(
                "sph-bench: soak on {:?}: {} steps of a {}-particle dam break",
                args.backend, args.steps, args.particles
            );
            let report = soak::run(&args)?;
            write_json(&report, &args.json)?;
            eprintln!(
                "sph-bench: soak: {} steps, {:.2} s simulated in {:.0} s; {}; particles lost {}; \
                 density error {:.3} % early, {:.3} % late, peak {:.3} %",
                report.steps,
                report.sim_time,
                report.wall_seconds,
                match report.unstable_step {
                    Some(s) => format!("unstable at step {s}"),
                    None => report.health.clone(),
                },
                report.particles_lost,
                report.density_error_early_pct,
                report.density_error_late_pct,
                report.density_error_peak_pct
            );
            Ok(())
        }),
        _ => Err(USAGE.to_string()),
    };
    if let Err(e) = result {
        eprintln!("sph-bench: error: {e}");
        std::process::exit(2);
    }
}

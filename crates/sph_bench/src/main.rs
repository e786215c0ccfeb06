//! `sph-bench`: runs SPH scenarios on the CPU solver or the GPU plugin and writes the figures
//! (speed, accuracy, stability) as JSON. See the README for the options.

mod args;
mod report;
mod run;
mod validate;

use args::{parse_run, Backend, USAGE};

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

fn main() {
    let argv: Vec<String> = std::env::args().skip(1).collect();
    let result = match argv.first().map(String::as_str) {
        Some("run") => parse_run(&argv[1..]).and_then(|args| {
            eprintln!(
                "sph-bench: {} on {:?}, {} particles requested",
                args.scenario, args.backend, args.particles
            );
            let report = match args.backend {
                Backend::Cpu => run::run_cpu(&args),
                Backend::Gpu => run::run_gpu(&args),
            }?;
            write_json(&report, &args.json)?;
            eprintln!(
                "sph-bench: {} particles, {} steps, {:.3} ms/step median, {} dispatches/step, \
                 density error {:.3} % mean",
                report.particles,
                report.steps,
                report.ms_per_step_median,
                report.dispatches_per_step,
                report.density_error_mean_pct
            );
            Ok(())
        }),
        Some("validate") => args::parse_validate(&argv[1..]).and_then(|args| {
            eprintln!(
                "sph-bench: Martin & Moyce dam break, a = {} m, about {} particles, CPU",
                args.a, args.particles
            );
            let report = validate::run(&args)?;
            write_json(&report, &args.json)?;
            eprintln!(
                "sph-bench: RMS Z error (T <= 2.5) {:.3} raw, {:.3} with the best shift {:.2}; {}",
                report.rms_z_raw, report.rms_z_shifted, report.best_shift, report.health
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

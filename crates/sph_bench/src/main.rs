//! `sph-bench`: runs SPH scenarios on the CPU solver or the GPU plugin and writes the figures
//! (speed, accuracy, stability) as JSON; validates against experiments; sweeps the speed-against-
//! accuracy trade into a table and a plot; soaks. See the README, or `sph-bench --help`.
//!
//! The modules, top down (each imports only modules below it; `tests/module_imports.rs` fails on
//! any import cycle): export, fuzz, trade, soak, validate, run, hydrostatic, sim, plot, progress,
//! args, martin_moyce, report, scenarios, physical_checks.

mod args;
mod export;
mod fuzz;
mod hydrostatic;
mod martin_moyce;
mod physical_checks;
mod plot;
mod progress;
mod report;
mod run;
mod scenarios;
mod scene_run;
mod sim;
mod soak;
mod trade;
mod validate;
mod whitewater;

use args::{Cli, Command, ExportArgs, FuzzArgs, RunArgs, SoakArgs, TradeArgs, ValidateArgs};
use clap::Parser;
use progress::Bars;
use std::path::Path;

/// Writes a report as pretty JSON to `path`, or to stdout without one.
fn write_json(report: &impl serde::Serialize, path: Option<&Path>) -> Result<(), String> {
    let json = serde_json::to_string_pretty(report).map_err(|e| e.to_string())?;
    match path {
        Some(path) => std::fs::write(path, json + "\n")
            .map_err(|e| format!("cannot write {}: {e}", path.display())),
        None => {
            println!("{json}");
            Ok(())
        }
    }
}

fn health_text(r: &report::Report) -> String {
    let health = match r.unstable_step {
        Some(step) => format!("unstable at step {step}"),
        None => r.health.clone(),
    };
    if r.rollbacks == 0 {
        return health;
    }
    format!(
        "{health}; rollbacks {}, dt at the end {:.2e} s",
        r.rollbacks, r.dt_last
    )
}

/// `sph-bench run`.
fn run_command(args: &RunArgs, bars: &Bars) -> Result<(), String> {
    match &args.scene {
        Some(file) => eprintln!("sph-bench: {} on {:?}", file.display(), args.backend),
        None => eprintln!(
            "sph-bench: {} on {:?}, about {} particles",
            args.scenario.name(),
            args.backend,
            args.particles
        ),
    }
    let report = run::run(args, bars)?;
    write_json(&report, args.json.as_deref())?;
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
    if let Some(d) = report
        .dam_break
        .as_ref()
        .filter(|d| d.rms_z_raw.is_finite())
    {
        eprintln!(
            "sph-bench: RMS Z error (T <= 2.5) {:.3} raw, {:.3} with the best shift {:.2}",
            d.rms_z_raw, d.rms_z_shifted, d.best_shift
        );
    }
    if let Some(h) = &report.hydrostatic {
        eprintln!(
            "sph-bench: pressure vs rho g depth below the top layer: max {:.2} %, mean {:.2} % \
             (max {:.2} % against the depth below the initial surface); density error {:.3} %; \
             over the last 40 %: mean speed {:.4} m/s, largest speed {:.4} m/s on average, above \
             {} m/s in {:.0} % of the samples",
            h.max_error_below_top_pct,
            h.mean_error_below_top_pct,
            h.max_error_vs_initial_surface_pct,
            h.density_error_mean_pct,
            h.speed_mean_window_mean,
            h.speed_max_window_mean,
            hydrostatic::TANK_MAX_SPEED,
            h.speed_max_window_over_pct
        );
        if let (Some(f), Some(e)) = (h.walls_force_n, h.walls_weight_error_pct) {
            eprintln!(
                "sph-bench: the walls carry {f:.3} N over the last 40 %, {e:+.2} % against the \
                 water's weight"
            );
        }
    }
    if let Some(w) = &report.whitewater {
        eprintln!(
            "sph-bench: whitewater at the end: {} spray, {} foam, {} bubbles (most {} of {}); {} \
             born, {} expired, {} refused by the full pool; {:.2} ms a step over {} steps",
            w.spray,
            w.foam,
            w.bubbles,
            w.most_alive,
            w.capacity,
            w.born,
            w.expired,
            w.dropped,
            w.ms_per_step,
            w.steps
        );
        if let Some([low, high]) = w.foam_extent {
            eprintln!(
                "sph-bench: the foam lies in x {:.3} to {:.3}, y {:.3} to {:.3}, z {:.3} to {:.3} m \
                 (5th to 95th percentile)",
                low[0], high[0], low[1], high[1], low[2], high[2]
            );
        }
    }
    eprintln!(
        "sph-bench: end speed mean {:.4} m/s, max {:.4} m/s; boundary corrections {} ({} at \
         the box's walls), inside colliders {}, left out of the spawns {}",
        report.speed_mean_end,
        report.speed_max_end,
        report.boundary_corrections,
        report.wall_corrections,
        report.inside_collider_count,
        report.spawns_inside_colliders
    );
    if let Some(d) = report.level_difference_end {
        eprintln!("sph-bench: level difference at the end {d:.4} m");
    }
    for f in &report.collider_forces {
        eprintln!(
            "sph-bench: force on {}: ({:.3}, {:.3}, {:.3}) N",
            f.name, f.force[0], f.force[1], f.force[2]
        );
    }
    if let Some(b) = &report.buoyancy {
        eprintln!(
            "sph-bench: buoyancy {:.4} N against rho0 g V = {:.4} N ({:+.2} %)",
            b.measured_n, b.expected_n, b.error_pct
        );
    }
    Ok(())
}

/// `sph-bench validate`.
fn validate_command(args: &ValidateArgs, bars: &Bars) -> Result<(), String> {
    eprintln!(
        "sph-bench: validation on {:?}: Martin & Moyce dam break (a = {} m, about {} \
         particles), hydrostatic tank (about {} particles)",
        args.backend, args.a, args.particles, args.hydrostatic_particles
    );
    let report = validate::run(args, bars)?;
    write_json(&report, args.json.as_deref())?;
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
             mean {:.2} % (target <= 5; max {:.2} % against the depth below the initial \
             surface); mean density error {:.3} % (target <= 1); over the last 40 %: mean \
             speed {:.4} m/s, largest speed {:.4} m/s on average, above {} m/s in {:.0} % of the \
             samples; {}",
            h.max_error_below_top_pct,
            h.mean_error_below_top_pct,
            h.max_error_vs_initial_surface_pct,
            h.density_error_mean_pct,
            h.speed_mean_window_mean,
            h.speed_max_window_mean,
            hydrostatic::TANK_MAX_SPEED,
            h.speed_max_window_over_pct,
            health_text(&report.hydrostatic)
        );
    }
    Ok(())
}

/// `sph-bench trade`.
fn trade_command(args: &TradeArgs, bars: &Bars) -> Result<(), String> {
    let done = trade::run(args, bars)?;
    eprintln!("sph-bench: {done}");
    Ok(())
}

/// `sph-bench fuzz-scenes`: fails when any mutant panicked.
fn fuzz_command(args: &FuzzArgs, bars: &Bars) -> Result<(), String> {
    eprintln!(
        "sph-bench: fuzzing scene files, seed {}, {} mutants each",
        args.seed, args.count
    );
    let report = fuzz::run(args, bars)?;
    write_json(&report, args.json.as_deref())?;
    eprintln!(
        "sph-bench: {} loaded, {} refused, {} panicked; slowest load {:.2} ms ({}); {:.0} s",
        report.loaded,
        report.refused,
        report.panicked.len(),
        report.slowest_ms,
        report.slowest,
        report.wall_seconds
    );
    match report.panicked.first() {
        Some(first) => Err(format!("a mutant panicked: {first}")),
        None => Ok(()),
    }
}

/// `sph-bench soak`.
fn soak_command(args: &SoakArgs, bars: &Bars) -> Result<(), String> {
    match &args.scene {
        Some(file) => eprintln!(
            "sph-bench: soak on {:?}: {} for {} s of simulated time, bodies {}",
            args.backend,
            file.display(),
            args.time,
            args.bodies.name()
        ),
        None => eprintln!(
            "sph-bench: soak on {:?}: {} steps of a {}-particle dam break",
            args.backend, args.steps, args.particles
        ),
    }
    let report = soak::run(args, bars)?;
    write_json(&report, args.json.as_deref())?;
    eprintln!(
        "sph-bench: soak: {} steps, {:.2} s simulated in {:.0} s; {}; rollbacks {}; \
         particles lost {}; density error {:.3} % early, {:.3} % late, peak {:.3} %",
        report.steps,
        report.sim_time,
        report.wall_seconds,
        match report.unstable_step {
            Some(s) => format!("unstable at step {s}"),
            None => report.health.clone(),
        },
        report.rollbacks,
        report.particles_lost,
        report.density_error_early_pct,
        report.density_error_late_pct,
        report.density_error_peak_pct
    );
    if let Some(file) = &report.scene_file {
        eprintln!(
            "sph-bench: soak of {file}: {} particle checks, {} failed; resident memory {:?} MiB \
             at the start and the end, {:+.1} % after the first minute",
            report.balance_checks,
            report.balance_failures.len(),
            (
                report.resident_mib.first().map(|m| m[1]),
                report.resident_mib.last().map(|m| m[1])
            ),
            report.resident_growth_after_first_minute_pct.unwrap_or(0.0)
        );
        if let Some(first) = report.balance_failures.first() {
            return Err(format!("particles lost or duplicated: {first}"));
        }
    }
    Ok(())
}

/// `sph-bench export`: writes the scene for the engine, or refuses it and writes nothing.
fn export_command(args: &ExportArgs) -> Result<(), String> {
    let done = export::run(args)?;
    eprintln!(
        "sph-bench: {} for {}: wrote {} in {}",
        args.scene.display(),
        export::engine_name(args.to),
        export::count(done.written.len(), "file"),
        args.out.display()
    );
    for path in &done.written {
        println!("{}", path.display());
    }
    for note in &done.notes {
        eprintln!("sph-bench: note: {note}");
    }
    eprintln!("sph-bench: run it with:");
    for line in &done.commands {
        eprintln!("  {line}");
    }
    Ok(())
}

fn main() {
    // Wrong arguments: clap prints the error (option, value, what is allowed) and exits with 2.
    let cli = Cli::parse();
    let bars = Bars::new(cli.quiet);
    let result = match &cli.command {
        Command::Run(args) => run_command(args, &bars),
        Command::Validate(args) => validate_command(args, &bars),
        Command::Trade(args) => trade_command(args, &bars),
        Command::Soak(args) => soak_command(args, &bars),
        Command::FuzzScenes(args) => fuzz_command(args, &bars),
        Command::Export(args) => export_command(args),
    };
    if let Err(e) = result {
        eprintln!("sph-bench: error: {e}");
        std::process::exit(2);
    }
}

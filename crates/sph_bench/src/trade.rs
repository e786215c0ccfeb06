//! `sph-bench trade`: the speed-against-accuracy study. Sweeps integrator × time step on the Martin &
//! Moyce dam break, particle count × backend, neighbour search, the optional stages (surface
//! tension, viscosity), and the 31,250-particle peer scene; finds each integrator's largest stable
//! dt by bisection; writes `trade.md` (tables) and `trade.png` and `trade.svg` (cost per simulated
//! second against the density error and the dam break's front error) into the output directory.

use crate::args::{Backend, Duration, RunArgs, TradeArgs};
use crate::plot::{write_stacked_png, write_stacked_svg, Marker, ScatterPlot, Series, PALETTE};
use crate::progress::Bars;
use crate::report::Report;
use crate::run::{configured_setup, names, run_setup};
use crate::scenarios::Scenario;
use sph_core::{Integrator, NeighborSearch, Solver};
use std::fmt::Write as _;
use std::path::Path;

const INTEGRATORS: [Integrator; 3] = [
    Integrator::SymplecticEuler,
    Integrator::Leapfrog,
    Integrator::KickDriftKick,
];

/// Particles of the integrator × dt sweep and of the bisection (cheap on the CPU).
const SWEEP_PARTICLES: usize = 2_000;

/// Simulated time of a stability probe [s].
const STABILITY_TIME: f32 = 2.0;

/// Largest mean compression error a stable run may reach [%].
const STABLE_DENSITY_ERROR_PCT: f32 = 10.0;

/// One row of the table: what was varied, and the report.
struct Row {
    group: &'static str,
    label: String,
    report: Report,
}

/// One run of the study, before it runs.
struct Planned {
    group: &'static str,
    label: String,
    args: RunArgs,
}

impl Planned {
    fn new(group: &'static str, label: String, args: RunArgs) -> Self {
        Self { group, label, args }
    }
}

fn run_row(planned: Planned, bars: &Bars) -> Result<Row, String> {
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

/// Whether a run is stable by the study's rule: no instability detected, no NaN, nothing outside,
/// and the mean compression error stayed below 10 %.
fn stable(r: &Report) -> bool {
    r.health == "ok" && r.density_error_mean_max_pct < STABLE_DENSITY_ERROR_PCT
}

/// The options of `integrator`'s stability probes (their dt aside): rollback off, since a
/// rolled-back step would hide the instability the search looks for.
fn probe_args(integrator: Integrator) -> RunArgs {
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
fn largest_stable_dt(integrator: Integrator, bars: &Bars) -> Result<(f32, f32, u32), String> {
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

fn fmt_opt(v: f64) -> String {
    if v.is_finite() && v > 0.0 {
        format!("{v:.3}")
    } else {
        "–".into()
    }
}

/// Simulated seconds per wall-clock second (the inverse of the cost), 3 significant digits.
fn real_time_factor(r: &Report) -> String {
    let factor = 1.0 / r.cost_per_sim_second_s;
    if factor.is_finite() && factor > 0.0 {
        format!("{factor:.3}")
    } else {
        "–".into()
    }
}

fn table(rows: &[Row]) -> String {
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

/// Plots cost per simulated second against the density error and the front error, one series
/// per backend × integrator; writes `trade.png` and `trade.svg` into `dir`.
fn plot(rows: &[Row], dir: &Path) -> Result<(), String> {
    let mut keys: Vec<String> = Vec::new();
    for row in rows {
        let key = series_key(&row.report);
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    let series = |y: &dyn Fn(&Report) -> Option<f64>| -> Vec<Series> {
        keys.iter()
            .enumerate()
            .map(|(k, key)| Series {
                label: key.clone(),
                color: PALETTE[k % PALETTE.len()],
                marker: marker_of(key),
                points: rows
                    .iter()
                    .filter(|r| series_key(&r.report) == *key && r.report.health == "ok")
                    .filter_map(|r| Some((r.report.cost_per_sim_second_s, y(&r.report)?)))
                    .collect(),
            })
            .collect()
    };
    let density = ScatterPlot {
        title: "Mean compression error at the end (stable runs)".into(),
        x_label: "cost: wall-clock seconds per simulated second [s/s]".into(),
        y_label: "mean density error [%]".into(),
        series: series(&|r| Some(r.density_error_mean_pct as f64)),
    };
    let front = ScatterPlot {
        title: "Dam-break front vs Martin & Moyce: RMS Z error (shifted)".into(),
        x_label: "cost: wall-clock seconds per simulated second [s/s]".into(),
        y_label: "RMS error of Z = x/a [column widths a]".into(),
        series: series(&|r| r.dam_break.as_ref().map(|d| d.rms_z_shifted)),
    };
    let plots = [density, front];
    write_stacked_png(&plots, &dir.join("trade.png"), 1000, 640)?;
    write_stacked_svg(&plots, &dir.join("trade.svg"), 1000, 640)
}

/// One marker shape per solver: discs for WCSPH, triangles for DFSPH, squares for PBF.
fn marker_of(series_key: &str) -> Marker {
    if series_key.ends_with("dfsph") {
        Marker::Triangle
    } else if series_key.ends_with("pbf") {
        Marker::Square
    } else {
        Marker::Circle
    }
}

/// The plot series of a run: backend and integrator for WCSPH, backend and solver otherwise.
fn series_key(r: &Report) -> String {
    if r.solver == "wcsph" {
        format!("{} {}", r.backend, r.integrator)
    } else {
        format!("{} {}", r.backend, r.solver)
    }
}

/// The groups the advice compares: the same CPU dam break at the sweep's resolution.
const ADVICE_GROUPS: [&str; 2] = ["integrator × dt", "solver"];

/// The largest mean compression over the run a game's water may show [%].
const GAME_COMPRESSION_PCT: f32 = 1.0;

/// The largest raw RMS Z error of a front that looks right [column widths].
const FRONT_RMS_Z: f64 = 0.10;

/// One pick of the advice: the row, with the figures that decided it.
fn describe(row: &Row) -> String {
    let r = &row.report;
    let rms = r
        .dam_break
        .as_ref()
        .map_or("–".to_string(), |d| format!("{:.3}", d.rms_z_raw));
    format!(
        "**{}** (group `{}`: {} on the {} backend, {} particles): real-time factor {}, {:.2} % mean \
         compression over the run, RMS Z {}",
        row.label,
        row.group,
        r.solver.to_uppercase(),
        r.backend,
        r.particles,
        real_time_factor(r),
        r.density_error_mean_run_pct,
        rms
    )
}

/// Which solver and settings to pick, chosen from the measured rows by stated rules: for a game
/// the fastest stable run whose mean compression over the run stays within 1 %; for a visual
/// effect the cheapest whose dam-break front stays within RMS Z 0.10 of the experiment; for an
/// engineering answer the least compressed of those.
fn advice(rows: &[Row]) -> String {
    // One scene at one resolution: the CPU dam breaks of the integrator and solver sweeps.
    let stable_rows: Vec<&Row> = rows
        .iter()
        .filter(|r| ADVICE_GROUPS.contains(&r.group) && r.report.health == "ok")
        .collect();
    let rms = |r: &Row| {
        r.report
            .dam_break
            .as_ref()
            .map_or(f64::INFINITY, |d| d.rms_z_raw)
    };
    let cost = |r: &Row| r.report.cost_per_sim_second_s;
    let pick = |ok: &dyn Fn(&Row) -> bool, better: &dyn Fn(&Row, &Row) -> bool| {
        stable_rows
            .iter()
            .copied()
            .filter(|r| ok(r))
            .fold(None, |best: Option<&Row>, r| match best {
                Some(b) if !better(r, b) => Some(b),
                _ => Some(r),
            })
    };
    let game = pick(
        &|r| r.report.density_error_mean_run_pct <= GAME_COMPRESSION_PCT,
        &|a, b| cost(a) < cost(b),
    );
    let effect = pick(&|r| rms(r) <= FRONT_RMS_Z, &|a, b| cost(a) < cost(b));
    let engineering = pick(&|r| rms(r) <= FRONT_RMS_Z, &|a, b| {
        a.report.density_error_mean_run_pct < b.report.density_error_mean_run_pct
    });
    let line = |what: &str, rule: String, row: Option<&Row>| match row {
        Some(row) => format!("- **{what}** ({rule}): {}.\n", describe(row)),
        None => format!("- **{what}** ({rule}): no run of this study qualifies.\n"),
    };
    let mut s = String::from(
        "Picked by the rules in brackets from the stable runs of one scene at one resolution: \
         the CPU dam breaks of the groups `integrator × dt` and `solver` below. The rules are in \
         `trade.rs`.\n\n",
    );
    s += &line(
        "For a game",
        format!(
            "the highest real-time factor with at most {GAME_COMPRESSION_PCT} % mean compression over the run"
        ),
        game,
    );
    s += &line(
        "For a visual effect",
        format!("the lowest cost whose dam-break front stays within RMS Z {FRONT_RMS_Z} of the experiment"),
        effect,
    );
    s += &line(
        "For an engineering answer",
        format!(
            "the least compression among the runs whose front stays within RMS Z {FRONT_RMS_Z}"
        ),
        engineering,
    );
    s += "\nIn general:\n\
          - PBF takes the largest steps and is the cheapest per simulated second, at the price \
          of compression that depends on its iterations;\n\
          - DFSPH holds the density to its tolerance at any step the flow allows and is the \
          accurate end;\n\
          - WCSPH sits between them: it is cheap per step but its steps are bound by the speed \
          of sound.\n\
          With real-time stepping (`SphControl::real_time`, docs/real_time.md), a solver that \
          cannot keep pace runs slower than real time rather than taking unstable steps.\n";
    s
}

/// Milliseconds per step of the row matching `pred`.
fn ms_of(rows: &[Row], pred: impl Fn(&Row) -> bool) -> Option<f64> {
    rows.iter()
        .find(|r| pred(r))
        .map(|r| r.report.ms_per_step_median)
}

fn stage_cost_table(rows: &[Row], backends: &[Backend], particles: usize) -> String {
    let mut s = String::from(
        "| backend | baseline (viscosity on, surface tension off) ms/step | surface tension on | viscosity off |\n|---|---|---|---|\n",
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
        let _ = writeln!(
            s,
            "| {name} | {} | {} | {} |",
            base.map_or("–".into(), |b| format!("{b:.2}")),
            cell(at("surface tension")),
            cell(at("viscosity"))
        );
    }
    s
}

/// The runs of the study's table, in order.
fn plan(args: &TradeArgs) -> Vec<Planned> {
    let mut plan = Vec::new();
    let cpu = RunArgs {
        particles: SWEEP_PARTICLES,
        substeps: args.substeps,
        ..Default::default()
    };
    // Integrator × time step (CPU): the derived dt × 1, 2, 4, and the adaptive rule.
    for integrator in INTEGRATORS {
        let (name, _) = names(integrator, NeighborSearch::Grid);
        let base = RunArgs {
            integrator,
            ..cpu.clone()
        };
        let derived = configured_setup(&base).scene.params.time_step;
        for factor in [1.0f32, 2.0, 4.0] {
            plan.push(Planned::new(
                "integrator × dt",
                format!("{name}, {factor} × derived dt"),
                RunArgs {
                    dt: Some(derived * factor),
                    ..base.clone()
                },
            ));
        }
        plan.push(Planned::new(
            "integrator × dt",
            format!("{name}, adaptive λ 0.4"),
            RunArgs {
                adaptive: true,
                dt: Some(0.01),
                ..base.clone()
            },
        ));
    }
    // DFSPH and PBF on the CPU on the same dam break (DFSPH: its own dt rule, the WCSPH derived
    // dt, warm starts off, a looser divergence tolerance; PBF: its iterations, vorticity, a
    // frame's dt). PBF's GPU rows are in the backend sweep below.
    let dfsph = RunArgs {
        solver: Some(Solver::Dfsph),
        ..cpu.clone()
    };
    let derived = configured_setup(&cpu).scene.params.time_step;
    for (label, args) in [
        ("DFSPH, own dt rule", dfsph.clone()),
        (
            "DFSPH, the WCSPH derived dt",
            RunArgs {
                dt: Some(derived),
                ..dfsph.clone()
            },
        ),
        (
            "DFSPH, warm starts off",
            RunArgs {
                warm_start: false,
                ..dfsph.clone()
            },
        ),
        (
            "DFSPH, divergence error 20 %/s",
            RunArgs {
                divergence_error: Some(20.0),
                ..dfsph.clone()
            },
        ),
        (
            "PBF, own dt rule",
            RunArgs {
                solver: Some(Solver::Pbf),
                ..cpu.clone()
            },
        ),
        (
            "PBF, 2 iterations",
            RunArgs {
                solver: Some(Solver::Pbf),
                pbf_iterations: Some(2),
                ..cpu.clone()
            },
        ),
        (
            "PBF, 8 iterations",
            RunArgs {
                solver: Some(Solver::Pbf),
                pbf_iterations: Some(8),
                ..cpu.clone()
            },
        ),
        (
            "PBF, vorticity confinement 0.2 m/s",
            RunArgs {
                solver: Some(Solver::Pbf),
                pbf_vorticity: Some(0.2),
                ..cpu.clone()
            },
        ),
        (
            "PBF, a frame's dt: 1/60 s fixed",
            RunArgs {
                solver: Some(Solver::Pbf),
                dt: Some(1.0 / 60.0),
                ..cpu.clone()
            },
        ),
    ] {
        plan.push(Planned::new("solver", label.into(), args));
    }
    // Particle count × backend; search, surface tension and viscosity at the largest count.
    let largest = largest_count(args);
    for &backend in &args.backends {
        let b = RunArgs {
            backend,
            ..cpu.clone()
        };
        for &n in &args.particles {
            plan.push(Planned::new(
                "particles",
                format!("about {n} particles"),
                RunArgs {
                    particles: n,
                    ..b.clone()
                },
            ));
        }
        let at_largest = RunArgs {
            particles: largest,
            ..b.clone()
        };
        plan.push(Planned::new(
            "search",
            "spatial hash".into(),
            RunArgs {
                search: NeighborSearch::Hash,
                ..at_largest.clone()
            },
        ));
        plan.push(Planned::new(
            "surface tension",
            "surface tension on".into(),
            RunArgs {
                surface_tension: true,
                ..at_largest.clone()
            },
        ));
        plan.push(Planned::new(
            "viscosity",
            "viscosity off".into(),
            RunArgs {
                viscosity_alpha: Some(0.0),
                ..at_largest.clone()
            },
        ));
        plan.push(Planned::new(
            "hydrostatic",
            "tank at rest, 1 s".into(),
            RunArgs {
                scenario: Scenario::Hydrostatic,
                // The study's tank stays at 1 s, as in its earlier tables (`validate`'s runs 5 s).
                time: Some(1.0),
                ..at_largest.clone()
            },
        ));
        if backend == Backend::Gpu {
            // PBF's and DFSPH's GPU passes, at every count of the sweep.
            for &n in &args.particles {
                plan.push(Planned::new(
                    "particles",
                    format!("about {n} particles, PBF"),
                    RunArgs {
                        particles: n,
                        solver: Some(Solver::Pbf),
                        ..b.clone()
                    },
                ));
            }
        }
        // DFSPH at every count of the sweep, on both backends.
        {
            for &n in &args.particles {
                plan.push(Planned::new(
                    "particles",
                    format!("about {n} particles, DFSPH"),
                    RunArgs {
                        particles: n,
                        backend,
                        ..dfsph.clone()
                    },
                ));
            }
        }
        if backend == Backend::Cpu {
            plan.push(Planned::new(
                "hydrostatic",
                "tank at rest, 1 s, DFSPH".into(),
                RunArgs {
                    scenario: Scenario::Hydrostatic,
                    time: Some(1.0),
                    particles: largest,
                    ..dfsph.clone()
                },
            ));
            // Less artificial viscosity matches the front better, but a tank at rest no
            // longer calms down (see docs/physics.md).
            for alpha in [0.02f32, 0.03] {
                plan.push(Planned::new(
                    "viscosity α",
                    format!(
                        "α = {alpha} (default {})",
                        sph_core::params::DEFAULT_VISCOSITY_ALPHA
                    ),
                    RunArgs {
                        viscosity_alpha: Some(alpha),
                        ..at_largest.clone()
                    },
                ));
            }
        }
        if args.dambreak32k {
            for (label, adaptive) in [("dt 1e-3 as specified", false), ("adaptive λ 0.4", true)] {
                plan.push(Planned::new(
                    "dambreak32k",
                    label.into(),
                    RunArgs {
                        scenario: Scenario::DamBreak32k,
                        adaptive,
                        ..b.clone()
                    },
                ));
            }
            if backend == Backend::Gpu {
                plan.push(Planned::new(
                    "dambreak32k",
                    "PBF, own dt rule".into(),
                    RunArgs {
                        scenario: Scenario::DamBreak32k,
                        solver: Some(Solver::Pbf),
                        ..b.clone()
                    },
                ));
                plan.push(Planned::new(
                    "dambreak32k",
                    "DFSPH, own dt rule".into(),
                    RunArgs {
                        scenario: Scenario::DamBreak32k,
                        backend,
                        ..dfsph.clone()
                    },
                ));
            }
            if backend == Backend::Cpu {
                let d32 = RunArgs {
                    scenario: Scenario::DamBreak32k,
                    ..dfsph.clone()
                };
                for (label, args) in [
                    ("DFSPH, own dt rule", d32.clone()),
                    (
                        "DFSPH, dt 1e-3 as SPlisHSPlasH ran",
                        RunArgs {
                            dt: Some(1e-3),
                            ..d32.clone()
                        },
                    ),
                    (
                        "DFSPH, divergence error 20 %/s",
                        RunArgs {
                            divergence_error: Some(20.0),
                            ..d32.clone()
                        },
                    ),
                    (
                        "PBF, own dt rule",
                        RunArgs {
                            solver: Some(Solver::Pbf),
                            ..d32.clone()
                        },
                    ),
                ] {
                    plan.push(Planned::new("dambreak32k", label.into(), args));
                }
            }
        }
    }
    plan
}

/// The largest particle count of the sweep (where search and the optional stages are compared).
fn largest_count(args: &TradeArgs) -> usize {
    args.particles
        .iter()
        .copied()
        .max()
        .unwrap_or(SWEEP_PARTICLES)
}

/// Runs the study and writes `trade.md`, `trade.png` and `trade.svg` into `args.out_dir`.
pub fn run(args: &TradeArgs, bars: &Bars) -> Result<String, String> {
    let plan = plan(args);
    let largest = largest_count(args);
    let bars = bars.clearing_finished_runs();
    let runs = plan.len() + INTEGRATORS.len();
    let mut study = bars.study("trade", runs as u64);
    let mut rows = Vec::with_capacity(plan.len());
    for (k, planned) in plan.into_iter().enumerate() {
        let what = format!("{}: {}", planned.group, planned.label);
        study.set(k as u64, what.clone());
        bars.note(format_args!("sph-bench trade: {what}"));
        rows.push(run_row(planned, &bars)?);
    }
    // Largest stable dt per integrator (CPU, bisection).
    let mut limits = String::from(
        "| integrator | largest stable dt [s] | derived dt [s] | ratio | CFL number at c0 |\n|---|---|---|---|---|\n",
    );
    for (k, integrator) in INTEGRATORS.into_iter().enumerate() {
        let what = format!("largest stable dt of {integrator:?}");
        study.set((rows.len() + k) as u64, what.clone());
        bars.note(format_args!("sph-bench trade: {what}"));
        let (dt, derived, probes) = largest_stable_dt(integrator, &bars)?;
        let params = configured_setup(&RunArgs {
            particles: SWEEP_PARTICLES,
            ..Default::default()
        })
        .scene
        .params;
        let (name, _) = names(integrator, NeighborSearch::Grid);
        let _ = writeln!(
            limits,
            "| {name} | {dt:.3e} | {derived:.3e} | {:.2} | {:.2} ({probes} probes) |",
            dt / derived,
            dt * params.speed_of_sound() / params.smoothing_radius
        );
    }
    let dir = Path::new(&args.out_dir);
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    plot(&rows, dir)?;
    let markdown = format!(
        "# Speed against accuracy\n\n\
         Generated by `sph-bench trade` (see the README for the command). Scene: the Martin & Moyce \
         dam break (column a = 0.146 m wide, 2a high, tank 5a long, SI water, T up to 2.8) unless \
         the group says otherwise. Cost per simulated second = median wall-clock ms per step / mean dt. \
         Density error = mean compression max(0, ρ/ρ0 − 1) at the end; the mean over the run \
         averages it over samples every 0.01 s (CPU; the end value for GPU runs without samples) \
         and the peak of the mean is the largest sample. Iterations: DFSPH's constant-density \
         (mean, max) / divergence-free solves, PBF's constraint iterations. RMS Z: the front against the \
         experiment for T ≤ 2.5, raw and with the best lag in [0, 0.3] removed. Unstable steps are \
         rolled back and retried at half the dt (the health column counts the rollbacks). Hardware: 2 CPU \
         cores; the GPU backend runs on lavapipe (Mesa's software Vulkan) on the same 2 cores.\n\n\
         ![cost against accuracy](trade.png) ([SVG](trade.svg))\n\n\
         ## Which solver to pick\n\n{}\n\
         ## Runs\n\n{}\n\
         ## Largest stable time step\n\n\
         Bisection in log(dt) between the derived step and 0.01 s on the CPU, {SWEEP_PARTICLES} particles, \
         {STABILITY_TIME} s simulated, rollback off (a rollback would hide the instability). Stable: no \
         instability detected, no NaN, nothing outside, and \
         the mean compression error below {STABLE_DENSITY_ERROR_PCT} % throughout.\n\n{}\n\
         ## What the optional stages cost\n\n\
         At {largest} particles (ms per step; change against the baseline). A scene without surface \
         tension compiles no normals pass and no cohesion code; without viscosity, no viscosity term.\n\n{}\n\
         ## The peers on dambreak32k\n\n\
         Measured on an earlier 2-core machine (issue 5): SPlisHSPlasH 2.16 DFSPH 36.8 ms per step at \
         dt 1e-3 (18 s for 0.5 s: 36 s per simulated second); salva 0.11 DFSPH 192.6 ms per step (97 s: \
         194 s per simulated second); SPlisHSPlasH's WCSPH blew up at every dt down to 1e-4. Timed again \
         on the same 2-core machine (docs/peers/README.md): SPlisHSPlasH 2.16 DFSPH 54.9 ms per \
         step (27.5 s for 0.5 s: 55 s per simulated second). Our rows are in the `dambreak32k` group \
         above.\n",
        advice(&rows),
        table(&rows),
        limits,
        stage_cost_table(&rows, &args.backends, largest)
    );
    let md = dir.join("trade.md");
    std::fs::write(&md, &markdown).map_err(|e| format!("cannot write {}: {e}", md.display()))?;
    study.set(runs as u64, "done");
    study.finish();
    Ok(format!(
        "wrote {}, {} and {}",
        md.display(),
        dir.join("trade.png").display(),
        dir.join("trade.svg").display()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stability_search_runs_without_rollback_and_the_table_with_it() {
        for integrator in INTEGRATORS {
            let setup = configured_setup(&probe_args(integrator));
            assert!(!setup.rollback.enabled, "{integrator:?}");
        }
        let args = TradeArgs {
            backends: vec![Backend::Cpu, Backend::Gpu],
            particles: vec![2_000, 8_000],
            out_dir: "docs".into(),
            dambreak32k: true,
            substeps: 10,
        };
        let plan = plan(&args);
        // 12 integrator × dt, 4 DFSPH and 5 PBF variants; per backend 2 counts, search, surface
        // tension, viscosity, tank, 2 dambreak32k; the CPU adds 2 α, 2 DFSPH counts, a DFSPH
        // tank and 3 DFSPH and 1 PBF dambreak32k runs; the GPU 2 PBF counts, 2 DFSPH counts
        // and 1 PBF and 1 DFSPH dambreak32k run.
        assert_eq!(
            plan.len(),
            12 + 9 + 2 * (2 + 4 + 2) + 2 + 2 + 1 + 4 + 2 + 2 + 1 + 1
        );
        let on_the_gpu = |solver: Solver| {
            plan.iter()
                .filter(|p| {
                    p.args.backend == Backend::Gpu
                        && p.args.solver.unwrap_or(Solver::Wcsph) == solver
                })
                .count()
        };
        assert_eq!(on_the_gpu(Solver::Pbf), 3);
        assert_eq!(on_the_gpu(Solver::Dfsph), 3);
        assert!(plan
            .iter()
            .all(|p| configured_setup(&p.args).rollback.enabled));
    }

    fn row(label: &str, solver: &str, cost: f64, compression: f32, rms: f64, ok: bool) -> Row {
        Row {
            group: "solver",
            label: label.into(),
            report: Report {
                solver: solver.into(),
                backend: "cpu".into(),
                cost_per_sim_second_s: cost,
                density_error_mean_run_pct: compression,
                health: if ok { "ok" } else { "unstable" }.into(),
                dam_break: Some(crate::report::DamBreakFigures {
                    rms_z_raw: rms,
                    ..Default::default()
                }),
                ..Default::default()
            },
        }
    }

    #[test]
    fn the_advice_follows_its_rules_on_the_measured_rows() {
        let rows = vec![
            row("fast but unstable", "pbf", 0.5, 0.5, 0.05, false),
            row("pbf", "pbf", 3.0, 0.9, 0.22, true),
            row("pbf squeezed", "pbf", 2.0, 4.0, 0.30, true),
            row("wcsph", "wcsph", 20.0, 0.1, 0.08, true),
            row("dfsph", "dfsph", 40.0, 0.01, 0.09, true),
            // Another scene or resolution: never compared.
            Row {
                group: "dambreak32k",
                ..row("elsewhere", "pbf", 0.1, 0.001, 0.01, true)
            },
        ];
        let text = advice(&rows);
        let pick = |what: &str| {
            text.lines()
                .find(|l| l.starts_with(&format!("- **{what}**")))
                .unwrap()
                .to_string()
        };
        assert!(pick("For a game").contains("**pbf** ("), "{text}");
        assert!(pick("For a visual effect").contains("**wcsph**"), "{text}");
        assert!(
            pick("For an engineering answer").contains("**dfsph**"),
            "{text}"
        );
        let none = advice(&rows[..1]);
        assert!(none.contains("no run of this study qualifies"));
    }
}

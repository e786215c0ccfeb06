//! The physical checks of the study: every solver at its defaults on the CPU, in the scenarios
//! whose answers are known (a tank at rest, a held box, an oscillating column, an orifice, a jet
//! against a thin wall, the Martin & Moyce front), each against its target. The advice's game
//! rule asks a solver to pass the rest, contact and buoyancy ones.

use super::plan::Planned;
use super::table::Row;
use crate::args::RunArgs;
use crate::report::Report;
use crate::scenarios::Scenario;
use sph_core::Solver;
use std::fmt::Write as _;

/// The scenarios of the checks, in the table's order.
pub(super) const CHECKS: [Scenario; 6] = [
    Scenario::Hydrostatic,
    Scenario::Buoyancy,
    Scenario::ThinWall,
    Scenario::UTube,
    Scenario::Orifice,
    Scenario::DamBreak,
];

/// The group of the checks' rows.
pub(super) const CHECKS_GROUP: &str = "physical checks";

/// The targets a solver's defaults are held to.
mod target {
    /// A tank at rest: the mean particle speed at the end [m/s].
    pub const TANK_MEAN_SPEED: f32 = 0.01;
    /// A tank at rest: the largest particle speed at the end [m/s].
    pub const TANK_MAX_SPEED: f32 = 0.05;
    /// A tank at rest: the pressure against ρ0 g depth below the top layer, largest layer [%].
    pub const TANK_PRESSURE_PCT: f64 = 10.0;
    /// A tank at rest: the walls' force against the water's weight [%].
    pub const TANK_WALLS_PCT: f64 = 2.0;
    /// The held box's upward force against ρ0 g V [%].
    pub const HELD_BOX_PCT: f64 = 5.0;
    /// The oscillating column's period against 2π √(L / 2g) [%].
    pub const U_TUBE_PERIOD_PCT: f64 = 15.0;
    /// The orifice's discharge against Cd A √(2 g h), Cd 0.61 [%].
    pub const ORIFICE_PCT: f64 = 25.0;
    /// The Martin & Moyce front, raw RMS Z [column widths].
    pub const FRONT_RMS_Z: f64 = 0.10;
}

/// The runs of the checks: each solver at its defaults (the command lines
/// `sph-bench run --scenario S --solver X`), in the order of [`Solver::ALL`] and [`CHECKS`].
pub(super) fn plan_checks() -> Vec<Planned> {
    let mut plan = Vec::new();
    for solver in Solver::ALL {
        for scenario in CHECKS {
            plan.push(Planned::new(
                CHECKS_GROUP,
                format!("{}: {}", solver.name(), scenario.name()),
                RunArgs {
                    scenario,
                    solver: Some(solver),
                    ..Default::default()
                },
            ));
        }
    }
    plan
}

/// One solver's check reports, found among the study's rows.
struct SolverChecks<'a> {
    reports: [Option<&'a Report>; CHECKS.len()],
}

impl<'a> SolverChecks<'a> {
    fn of(rows: &'a [Row], solver: &str) -> Self {
        let mut reports = [None; CHECKS.len()];
        for row in rows.iter().filter(|r| r.group == CHECKS_GROUP) {
            if row.report.solver != solver {
                continue;
            }
            if let Some(k) = CHECKS.iter().position(|s| s.name() == row.report.scenario) {
                reports[k] = Some(&row.report);
            }
        }
        Self { reports }
    }

    fn get(&self, scenario: Scenario) -> Option<&'a Report> {
        CHECKS
            .iter()
            .position(|&s| s == scenario)
            .and_then(|k| self.reports[k])
    }

    /// The tank is calm with no guard correction and its walls carry its weight, the held box
    /// feels ρ0 g V, and the jet stays on its side of the thin wall with no guard correction.
    fn rests_and_meets_solids(&self) -> bool {
        let tank = self.get(Scenario::Hydrostatic).is_some_and(|r| {
            r.health == "ok" && tank_is_calm(r) && unguarded(r) && walls_carry_the_weight(r)
        });
        let held_box = self
            .get(Scenario::Buoyancy)
            .is_some_and(box_feels_its_weight);
        let wall = self.get(Scenario::ThinWall).is_some_and(jet_stays_out);
        tank && held_box && wall
    }
}

/// The tank's end speeds within the targets.
fn tank_is_calm(tank: &Report) -> bool {
    tank.speed_mean_end <= target::TANK_MEAN_SPEED && tank.speed_max_end <= target::TANK_MAX_SPEED
}

/// No particle needed the last-resort guard.
fn unguarded(run: &Report) -> bool {
    run.boundary_corrections == 0
}

/// The tank's walls carried the water's weight within the target.
fn walls_carry_the_weight(tank: &Report) -> bool {
    tank.hydrostatic
        .as_ref()
        .and_then(|h| h.walls_weight_error_pct)
        .is_some_and(|e| e.abs() <= target::TANK_WALLS_PCT)
}

/// The held box felt ρ0 g V within the target.
fn box_feels_its_weight(run: &Report) -> bool {
    run.buoyancy
        .as_ref()
        .is_some_and(|b| b.error_pct.abs() <= target::HELD_BOX_PCT)
}

/// No particle got behind the thin wall, and none needed the guard.
fn jet_stays_out(run: &Report) -> bool {
    unguarded(run)
        && run
            .thin_wall
            .as_ref()
            .is_some_and(|w| w.behind_wall_most == 0)
}

/// Whether `solver` (its report name) passed the rest, contact and buoyancy checks in `rows`
/// (false when they did not run).
pub(super) fn rests_and_meets_solids(rows: &[Row], solver: &str) -> bool {
    SolverChecks::of(rows, solver).rests_and_meets_solids()
}

/// A figure with its verdict: `✓` within the target, `✗` outside it.
fn judged(text: String, ok: bool) -> String {
    format!("{text} {}", if ok { "✓" } else { "✗" })
}

/// The table of the checks: one row per solver, "–" where a check did not run or measured
/// nothing.
pub(super) fn checks_table(rows: &[Row]) -> String {
    let mut s = format!(
        "| solver | tank at rest: end speed mean / max [m/s] (≤ {} / {}) | tank: guard corrections (0) | tank: pressure below the top layer, largest error [%] (≤ {}) | tank: walls' force against the water's weight [%] (±{}) | held box: force against ρ0 g V [%] (±{}) | thin wall: particles behind / guard corrections (0 / 0) | U-tube: period against 2π√(L/2g) [%] (±{}) | orifice: discharge against Cd A √(2gh) [%] (±{}) | dam break: RMS Z raw (≤ {}) |\n\
         |---|---|---|---|---|---|---|---|---|---|\n",
        target::TANK_MEAN_SPEED,
        target::TANK_MAX_SPEED,
        target::TANK_PRESSURE_PCT,
        target::TANK_WALLS_PCT,
        target::HELD_BOX_PCT,
        target::U_TUBE_PERIOD_PCT,
        target::ORIFICE_PCT,
        target::FRONT_RMS_Z,
    );
    let none = || "–".to_string();
    for solver in Solver::ALL {
        let checks = SolverChecks::of(rows, solver.name());
        let tank = checks.get(Scenario::Hydrostatic);
        let speeds = tank.map_or_else(none, |r| {
            judged(
                format!("{:.4} / {:.3}", r.speed_mean_end, r.speed_max_end),
                tank_is_calm(r),
            )
        });
        let tank_guard = tank.map_or_else(none, |r| {
            judged(r.boundary_corrections.to_string(), unguarded(r))
        });
        let pressure = tank
            .and_then(|r| r.hydrostatic.as_ref())
            .map_or_else(none, |h| {
                judged(
                    format!("{:.1}", h.max_error_below_top_pct),
                    h.max_error_below_top_pct <= target::TANK_PRESSURE_PCT,
                )
            });
        let walls = tank.map_or_else(none, |r| {
            match r
                .hydrostatic
                .as_ref()
                .and_then(|h| h.walls_weight_error_pct)
            {
                Some(e) => judged(format!("{e:+.2}"), walls_carry_the_weight(r)),
                None => none(),
            }
        });
        let held_box =
            checks
                .get(Scenario::Buoyancy)
                .map_or_else(none, |r| match r.buoyancy.as_ref() {
                    Some(b) => judged(format!("{:+.1}", b.error_pct), box_feels_its_weight(r)),
                    None => none(),
                });
        let wall = checks.get(Scenario::ThinWall).map_or_else(none, |r| {
            let behind = r
                .thin_wall
                .as_ref()
                .map_or(usize::MAX, |w| w.behind_wall_most);
            judged(
                format!("{behind} / {}", r.boundary_corrections),
                jet_stays_out(r),
            )
        });
        // A percentage error within ±`limit`, or `missing` when the run measured none.
        let within = |error: Option<f64>, limit: f64, missing: &str| match error {
            Some(e) => judged(format!("{e:+.1}"), e.abs() <= limit),
            None => judged(missing.into(), false),
        };
        let u_tube = checks.get(Scenario::UTube).map_or_else(none, |r| {
            within(
                r.u_tube.as_ref().and_then(|u| u.period_error_pct),
                target::U_TUBE_PERIOD_PCT,
                "no oscillation",
            )
        });
        let orifice = checks.get(Scenario::Orifice).map_or_else(none, |r| {
            within(
                r.orifice.as_ref().and_then(|o| o.discharge_error_pct),
                target::ORIFICE_PCT,
                "no discharge",
            )
        });
        let front = checks
            .get(Scenario::DamBreak)
            .and_then(|r| r.dam_break.as_ref())
            .map_or_else(none, |d| {
                judged(
                    format!("{:.3}", d.rms_z_raw),
                    d.rms_z_raw <= target::FRONT_RMS_Z,
                )
            });
        let _ = writeln!(
            s,
            "| {} | {speeds} | {tank_guard} | {pressure} | {walls} | {held_box} | {wall} | {u_tube} | {orifice} | {front} |",
            solver.name().to_uppercase()
        );
    }
    s
}

/// Check rows in which `solver` passes the rest, contact and buoyancy checks, for tests.
#[cfg(test)]
pub(super) fn passing_checks(solver: &str) -> Vec<Row> {
    tests::passing(solver)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physical_checks::thin_wall::ThinWallFigures;
    use crate::report::{BuoyancyFigures, HydrostaticFigures};

    fn row(solver: &str, scenario: Scenario, report: Report) -> Row {
        Row {
            group: CHECKS_GROUP,
            label: format!("{solver}: {}", scenario.name()),
            report: Report {
                solver: solver.into(),
                scenario: scenario.name().into(),
                health: "ok".into(),
                ..report
            },
        }
    }

    pub(super) fn passing(solver: &str) -> Vec<Row> {
        vec![
            row(
                solver,
                Scenario::Hydrostatic,
                Report {
                    speed_mean_end: 0.002,
                    speed_max_end: 0.03,
                    hydrostatic: Some(HydrostaticFigures {
                        walls_weight_error_pct: Some(0.004),
                        ..Default::default()
                    }),
                    ..Default::default()
                },
            ),
            row(
                solver,
                Scenario::Buoyancy,
                Report {
                    buoyancy: Some(BuoyancyFigures {
                        error_pct: -4.6,
                        ..Default::default()
                    }),
                    ..Default::default()
                },
            ),
            row(
                solver,
                Scenario::ThinWall,
                Report {
                    thin_wall: Some(ThinWallFigures::default()),
                    ..Default::default()
                },
            ),
        ]
    }

    #[test]
    fn a_solver_rests_and_meets_solids_only_when_every_such_check_passes() {
        let rows = passing("dfsph");
        assert!(rests_and_meets_solids(&rows, "dfsph"));
        assert!(!rests_and_meets_solids(&rows, "pbf"), "no checks ran");
        // Each failure on its own fails the solver.
        let fail = |k: usize, change: fn(&mut Report)| {
            let mut rows = passing("pbf");
            change(&mut rows[k].report);
            rests_and_meets_solids(&rows, "pbf")
        };
        assert!(!fail(0, |r| r.speed_max_end = 1.7));
        assert!(!fail(0, |r| r.boundary_corrections = 1));
        assert!(!fail(0, |r| {
            r.hydrostatic.as_mut().unwrap().walls_weight_error_pct = Some(11.6)
        }));
        assert!(!fail(0, |r| r.hydrostatic = None));
        assert!(!fail(1, |r| r.buoyancy.as_mut().unwrap().error_pct = 120.0));
        assert!(!fail(2, |r| r
            .thin_wall
            .as_mut()
            .unwrap()
            .behind_wall_most = 3));
        assert!(!fail(2, |r| r.boundary_corrections = 41_807));
        assert!(fail(1, |r| r.buoyancy.as_mut().unwrap().error_pct = 4.9));
    }

    #[test]
    fn the_checks_table_judges_each_figure_against_its_target() {
        let mut rows = passing("wcsph");
        rows[0].report.speed_max_end = 0.08;
        let table = checks_table(&rows);
        let wcsph = table.lines().find(|l| l.starts_with("| WCSPH")).unwrap();
        assert!(wcsph.contains("0.0020 / 0.080 ✗"), "{wcsph}");
        assert!(wcsph.contains("-4.6 ✓"), "{wcsph}");
        assert!(wcsph.contains("+0.00 ✓"), "{wcsph}");
        assert!(wcsph.contains("0 / 0 ✓"), "{wcsph}");
        let pbf = table.lines().find(|l| l.starts_with("| PBF")).unwrap();
        assert!(pbf.contains("| – | – |"), "nothing ran: {pbf}");
    }

    #[test]
    fn every_solver_runs_every_check_at_its_defaults() {
        let plan = plan_checks();
        assert_eq!(plan.len(), Solver::ALL.len() * CHECKS.len());
        assert!(plan.iter().all(|p| p.args.solver.is_some()
            && p.args.time.is_none()
            && p.args.particles == RunArgs::default().particles));
    }
}

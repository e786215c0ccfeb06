//! Which solver to pick: the advice of `trade.md`, chosen from the measured rows by stated rules.

use super::checks::rests_and_meets_solids;
use super::table::{real_time_factor, Row};

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
/// the fastest stable run whose mean compression over the run stays within 1 % and whose solver
/// passed the rest, contact and buoyancy checks in `checks` at its defaults (when they ran); for a visual
/// effect the cheapest whose dam-break front stays within RMS Z 0.10 of the experiment; for an
/// engineering answer the least compressed of those.
pub(super) fn advice(rows: &[Row], checks: &[Row]) -> String {
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
        &|r| {
            r.report.density_error_mean_run_pct <= GAME_COMPRESSION_PCT
                && (checks.is_empty() || rests_and_meets_solids(checks, &r.report.solver))
        },
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
         `trade/advice.rs`.\n\n",
    );
    s += &line(
        "For a game",
        format!(
            "the highest real-time factor with at most {GAME_COMPRESSION_PCT} % mean compression over \
             the run, {}",
            if checks.is_empty() {
                "the physical checks not run"
            } else {
                "of a solver whose water rests, stays out of thin walls and feels a held box's \
                 weight in the physical checks"
            }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::Report;
    use crate::trade::checks::passing_checks;

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
        let checks: Vec<Row> = [passing_checks("pbf"), passing_checks("wcsph")]
            .into_iter()
            .flatten()
            .collect();
        let text = advice(&rows, &checks);
        let pick = |text: &str, what: &str| {
            text.lines()
                .find(|l| l.starts_with(&format!("- **{what}**")))
                .unwrap()
                .to_string()
        };
        assert!(pick(&text, "For a game").contains("**pbf** ("), "{text}");
        // PBF's water that does not rest or meet solids is no game default.
        let text = advice(&rows, &passing_checks("wcsph"));
        assert!(pick(&text, "For a game").contains("**wcsph** ("), "{text}");
        let text = advice(&rows, &checks);
        assert!(
            pick(&text, "For a visual effect").contains("**wcsph**"),
            "{text}"
        );
        assert!(
            pick(&text, "For an engineering answer").contains("**dfsph**"),
            "{text}"
        );
        let none = advice(&rows[..1], &checks);
        assert!(none.contains("no run of this study qualifies"));
    }
}

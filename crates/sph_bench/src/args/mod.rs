//! Command-line arguments of `sph-bench` (clap): `--help` gives every option's unit and default,
//! and every error names the option, the value and what is allowed, e.g.
//! `invalid value '2' for '--dt <SECONDS>': 2 is not in (0, 1] s`.
//!
//! The options of each command are in their own module: `run` (`sph-bench run`), `studies`
//! (`validate`, `trade`, `soak`) and `scene_tools` (`fuzz-scenes`, `export`), over the values
//! and parsers they share in `values`.

mod run;
mod scene_tools;
mod studies;
mod values;

pub use run::{Duration, RunArgs};
pub use scene_tools::{ExportArgs, ExportTarget, FuzzArgs};
pub use studies::{SoakArgs, TradeArgs, ValidateArgs};
pub use values::{integrator_name, search_name, Backend};

use clap::{Parser, Subcommand};

/// Runs SPH scenarios on the CPU solver or the GPU plugin and reports speed, accuracy and
/// stability as JSON.
#[derive(Clone, Debug, Parser)]
#[command(name = "sph-bench", version, arg_required_else_help = true)]
pub struct Cli {
    /// No progress bars (they are also hidden when stderr is not a terminal).
    #[arg(long, short, global = true)]
    pub quiet: bool,
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The commands.
#[derive(Clone, Debug, PartialEq, Subcommand)]
pub enum Command {
    /// Runs one scenario and writes its report as JSON.
    Run(RunArgs),
    /// The Martin & Moyce dam break and the hydrostatic tank against their targets.
    Validate(ValidateArgs),
    /// The speed-against-accuracy study: writes trade.md, trade.png and trade.svg.
    Trade(TradeArgs),
    /// A long dam-break run: health, drift of the density error, particle loss.
    Soak(SoakArgs),
    /// Mutates scene files (truncations, flips, numeric extremes, deleted and duplicated keys)
    /// and loads each mutant: counts what loads, what is refused and what panics.
    FuzzScenes(FuzzArgs),
    /// Converts a scene file into a scene for a larger offline engine (SPlisHSPlasH or
    /// DualSPHysics) in the directory OUT; what the engine cannot express is refused by name and
    /// nothing is written (see docs/export.md).
    Export(ExportArgs),
}

#[cfg(test)]
mod tests {
    use super::run::{Duration, RunArgs};
    use super::values::Backend;
    use super::{Cli, Command};
    use crate::scenarios::Scenario;
    use clap::{CommandFactory, Parser};
    use sph_core::{Integrator, NeighborSearch, Solver};
    use std::path::PathBuf;

    fn parse(args: &[&str]) -> Result<Command, String> {
        let argv = std::iter::once("sph-bench").chain(args.iter().copied());
        Cli::try_parse_from(argv)
            .map(|cli| cli.command)
            .map_err(|e| e.to_string())
    }

    #[test]
    fn the_command_line_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn run_options_are_parsed() {
        let Ok(Command::Run(a)) = parse(&[
            "run",
            "--scenario",
            "hydrostatic",
            "--backend",
            "gpu",
            "--adaptive",
            "on",
            "--integrator",
            "leapfrog",
            "--search",
            "hash",
            "--cfl",
            "0.3",
            "--time",
            "0.5",
        ]) else {
            panic!("not a run");
        };
        assert_eq!(a.scenario, Scenario::Hydrostatic);
        assert_eq!(a.backend, Backend::Gpu);
        assert!(a.adaptive);
        assert_eq!(a.integrator, Integrator::Leapfrog);
        assert_eq!(a.search, NeighborSearch::Hash);
        assert_eq!(a.cfl, Some(0.3));
        assert_eq!(a.duration(), Some(Duration::Time(0.5)));
        assert!(a.rollback, "rollback is on by default");
        let Ok(Command::Soak(s)) = parse(&["soak", "--rollback", "off"]) else {
            panic!("not a soak");
        };
        assert!(!s.rollback);
    }

    #[test]
    fn defaults_are_the_documented_ones() {
        assert_eq!(parse(&["run"]).ok(), Some(Command::Run(RunArgs::default())));
        let Ok(Command::Validate(v)) = parse(&["validate"]) else {
            panic!("not a validation");
        };
        assert_eq!((v.particles, v.hydrostatic_particles), (8_000, 8_000));
        assert_eq!(
            v.base(),
            RunArgs {
                particles: 8_000,
                solver: Some(Solver::Wcsph),
                ..Default::default()
            }
        );
        let Ok(Command::Trade(t)) = parse(&["trade"]) else {
            panic!("not a trade study");
        };
        assert_eq!(t.backends, [Backend::Cpu, Backend::Gpu]);
        assert_eq!(t.particles, [2_000, 8_000]);
        assert_eq!(t.out_dir, PathBuf::from("docs"));
        assert!(t.dambreak32k);
        assert!(t.checks);
        assert_eq!(t.substeps, 10);
        let Ok(Command::Soak(s)) = parse(&["soak"]) else {
            panic!("not a soak");
        };
        assert_eq!(
            (s.backend, s.steps, s.particles),
            (Backend::Cpu, 100_000, 4_096)
        );
        assert_eq!((s.substeps, s.json, s.rollback), (20, None, true));
    }

    #[test]
    fn errors_name_the_option_the_value_and_the_range() {
        let cases: [(&[&str], &[&str]); 10] = [
            (
                &["run", "--dt", "2"],
                &["--dt", "'2'", "2 is not in (0, 1] s"],
            ),
            (&["run", "--dt", "fast"], &["--dt", "'fast'", "(0, 1] s"]),
            (&["run", "--a", "0"], &["--a", "'0'", "(0, 10] m"]),
            (
                &["run", "--scenario", "flood"],
                &["--scenario", "'flood'", "pipe-fill", "dambreak32k"],
            ),
            (
                &["run", "--surface-tension", "yes"],
                &["--surface-tension", "'yes'", "on", "off"],
            ),
            (
                &["run", "--integrator", "rk4"],
                &["--integrator", "'rk4'", "euler", "leapfrog", "kdk"],
            ),
            (
                &["trade", "--particles", "100,x"],
                &["--particles", "'x'", "1..=4194304 particles"],
            ),
            (
                &["validate", "--substeps", "65"],
                &["--substeps", "'65'", "1..=64 steps per frame"],
            ),
            (&["soak", "--steps"], &["--steps", "a value is required"]),
            (
                &["run", "--samples-every", "0"],
                &["--samples-every", "'0'", "[0.001, 10] s"],
            ),
        ];
        for (args, wanted) in cases {
            let e = parse(args).expect_err("an error");
            for w in wanted {
                assert!(e.contains(w), "{args:?}: {w:?} not in {e}");
            }
        }
    }

    #[test]
    fn steps_and_time_exclude_each_other() {
        let e = parse(&["run", "--steps", "5", "--time", "1"]).unwrap_err();
        assert!(e.contains("--steps") && e.contains("--time"), "{e}");
    }

    #[test]
    fn help_gives_every_option_a_unit_or_a_value_list() {
        let mut cli = Cli::command();
        for sub in ["run", "validate", "trade", "soak"] {
            let help = cli
                .find_subcommand_mut(sub)
                .expect("subcommand")
                .render_long_help()
                .to_string();
            for unit in ["[particles]", "[steps]"] {
                assert!(help.contains(unit), "{sub}: no {unit} in\n{help}");
            }
        }
        let run = cli
            .find_subcommand_mut("run")
            .expect("run")
            .render_long_help()
            .to_string();
        for text in ["[s]", "[m]", "dam-break", "kick-drift-kick", "on|off"] {
            assert!(run.contains(text), "no {text} in\n{run}");
        }
    }
}

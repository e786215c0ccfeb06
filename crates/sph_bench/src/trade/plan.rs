//! The study's plan: every run of its table, in order, before any of them runs.

use crate::args::{Backend, RunArgs, TradeArgs};
use crate::run::{configured_setup, names};
use crate::scenarios::Scenario;
use sph_core::{Integrator, NeighborSearch, Solver};

/// The integrators the study compares.
pub(super) const INTEGRATORS: [Integrator; 3] = [
    Integrator::SymplecticEuler,
    Integrator::Leapfrog,
    Integrator::KickDriftKick,
];

/// Particles of the integrator × dt sweep and of the bisection (cheap on the CPU).
pub(super) const SWEEP_PARTICLES: usize = 2_000;

/// One run of the study, before it runs.
pub(super) struct Planned {
    pub(super) group: &'static str,
    pub(super) label: String,
    pub(super) args: RunArgs,
}

impl Planned {
    pub(super) fn new(group: &'static str, label: String, args: RunArgs) -> Self {
        Self { group, label, args }
    }
}

/// The runs of the study's table, in order.
pub(super) fn plan(args: &TradeArgs) -> Vec<Planned> {
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
        // Whitewater on each backend: the CPU steps it over the state samples, the GPU's
        // stages run it once a frame.
        plan.push(Planned::new(
            WHITEWATER_GROUP,
            "whitewater on".into(),
            RunArgs {
                whitewater: true,
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

/// The group of the run with whitewater on (its cost is tabled with the optional stages').
pub(super) const WHITEWATER_GROUP: &str = "whitewater";

/// The largest particle count of the sweep (where search and the optional stages are compared).
pub(super) fn largest_count(args: &TradeArgs) -> usize {
    args.particles
        .iter()
        .copied()
        .max()
        .unwrap_or(SWEEP_PARTICLES)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trade::stability::probe_args;

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
            checks: true,
            substeps: 10,
        };
        let plan = plan(&args);
        // 12 integrator × dt, 4 DFSPH and 5 PBF variants; per backend 2 counts, search, surface
        // tension, viscosity, whitewater, tank, 2 dambreak32k; the CPU adds 2 α, 2 DFSPH counts,
        // a DFSPH tank and 3 DFSPH and 1 PBF dambreak32k runs; the GPU 2 PBF counts, 2 DFSPH
        // counts and 1 PBF and 1 DFSPH dambreak32k run.
        assert_eq!(
            plan.len(),
            12 + 9 + 2 * (2 + 5 + 2) + 2 + 2 + 1 + 4 + 2 + 2 + 1 + 1
        );
        let whitewater: Vec<_> = plan
            .iter()
            .filter(|p| p.args.whitewater)
            .map(|p| p.args.backend)
            .collect();
        assert_eq!(
            whitewater,
            [Backend::Cpu, Backend::Gpu],
            "one run with whitewater on each backend"
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
}

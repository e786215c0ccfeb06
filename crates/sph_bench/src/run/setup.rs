//! The setup of a run from the command line: the scenario with the solver, integrator, search,
//! time-step, viscosity, wall and rollback options applied, and the names the report gives the
//! integrator and the search.

use crate::args::{integrator_name, search_name, RunArgs};
use crate::scenarios::{setup, Setup};
use sph_core::{Integrator, NeighborSearch, Rollback, Solver};

/// The setup of the arguments: the scenario with the integrator, search, surface tension,
/// time-step and rollback overrides applied.
pub fn configured_setup(args: &RunArgs) -> Setup {
    let mut s = setup(args.scenario, args.particles, args.a);
    let p = &mut s.scene.params;
    p.integrator = args.integrator;
    p.neighbor_search = args.search;
    if args.surface_tension {
        p.surface_tension = sph_core::params::WATER_SURFACE_TENSION;
    }
    let solver = args.solver.unwrap_or(Solver::Wcsph);
    match solver {
        Solver::Wcsph => {
            if let Some(dt) = args.dt {
                p.time_step = dt;
            }
            p.adaptive_time_step = args.adaptive;
            if let Some(lambda) = args.cfl {
                p.cfl_factor = lambda;
                if !args.adaptive && args.dt.is_none() {
                    // A fixed step from the CFL factor: dt = λ h / (c0 + v_peak), v_peak = c0 / 10.
                    p.time_step = lambda * p.smoothing_radius / (1.1 * p.speed_of_sound());
                }
            }
        }
        Solver::Dfsph | Solver::Pbf => {
            // The solver's own rule, unless a dt is given (then fixed, or the largest with
            // --adaptive on), with --cfl's λ in place of the solver's.
            p.use_solver(solver);
            if let Some(lambda) = args.cfl {
                p.cfl_factor = lambda;
            }
            if let Some(dt) = args.dt {
                p.time_step = dt;
                p.adaptive_time_step = args.adaptive;
            }
            if let Some(pct) = args.density_error {
                p.dfsph.max_density_error = pct / 100.0;
            }
            if let Some(pct) = args.divergence_error {
                p.dfsph.max_divergence_error = pct / 100.0;
            }
            p.dfsph.warm_start = args.warm_start;
            if let Some(n) = args.max_iterations {
                p.dfsph.max_density_iterations = n;
                p.dfsph.max_divergence_iterations = n;
            }
            if let Some(omega) = args.divergence_over_relaxation {
                p.dfsph.divergence_over_relaxation = omega;
            }
            if let Some(omega) = args.density_over_relaxation {
                p.dfsph.density_over_relaxation = omega;
            }
            if let Some(n) = args.pbf_iterations {
                p.pbf.iterations = n;
            }
            if let Some(epsilon) = args.pbf_vorticity {
                p.pbf.vorticity_epsilon = epsilon;
            }
            if let Some(w) = args.pbf_jacobi_weight {
                p.pbf.jacobi_weight = w;
            }
            if let Some(omega) = args.pbf_over_relaxation {
                p.pbf.over_relaxation = omega;
            }
        }
    }
    if let Some(alpha) = args.viscosity_alpha {
        // ν = α h c0 / 10, as in the derivation; after use_solver, which sets DFSPH's own α.
        p.set_artificial_viscosity_alpha(alpha);
    }
    s.rollback = rollback(args.rollback);
    s.walls = args.walls;
    s.whitewater = args
        .whitewater
        .then(sph_core::whitewater::settings::WhitewaterSettings::default);
    if let Some(f) = args.wall_friction {
        s.wall_friction = (f > 0.0).then_some(f);
    }
    s
}

/// The rollback settings of `--rollback on|off`.
pub fn rollback(on: bool) -> Rollback {
    if on {
        Rollback::default()
    } else {
        Rollback::off()
    }
}

/// Names of the integrator and search, as on the command line.
pub fn names(integrator: Integrator, search: NeighborSearch) -> (&'static str, &'static str) {
    (integrator_name(integrator), search_name(search))
}

//! What to run: the scene's variant (search, features: the shader defs every stage shares) and
//! each force evaluation's plan (the integrator phases fused into the passes). No GPU types.

use bevy::shader::ShaderDefVal;
use sph_core::{Integrator, NeighborSearch, Solver, SphParams};

/// Which variant of the pipelines a parameter set needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct VariantKey {
    /// Neighbour-search mode.
    pub search: NeighborSearch,
    /// Surface tension on (normals pass, cohesion and curvature terms).
    pub surface_tension: bool,
    /// Viscosity term on.
    pub viscosity: bool,
    /// The density pass records neighbour counts (debug views).
    pub neighbor_counts: bool,
    /// The pressure solver, whose stage list runs: WCSPH, DFSPH (Bender & Koschier 2015, 2017)
    /// or PBF (Macklin & Müller 2013).
    pub solver: Solver,
    /// PBF's vorticity confinement stages (off: they are not in the list and cost nothing).
    pub vorticity: bool,
}

impl VariantKey {
    /// Every variant.
    pub fn all() -> impl Iterator<Item = VariantKey> {
        let flags = [false, true];
        [NeighborSearch::Grid, NeighborSearch::Hash]
            .into_iter()
            .flat_map(move |search| {
                flags.into_iter().flat_map(move |surface_tension| {
                    flags.into_iter().flat_map(move |viscosity| {
                        flags.into_iter().flat_map(move |neighbor_counts| {
                            // WCSPH, PBF, PBF with vorticity confinement, DFSPH.
                            [
                                (Solver::Wcsph, false),
                                (Solver::Pbf, false),
                                (Solver::Pbf, true),
                                (Solver::Dfsph, false),
                            ]
                            .into_iter()
                            .map(move |(solver, vorticity)| VariantKey {
                                search,
                                surface_tension,
                                viscosity,
                                neighbor_counts,
                                solver,
                                vorticity,
                            })
                        })
                    })
                })
            })
    }

    /// The variant `params` need.
    pub fn of(params: &SphParams, neighbor_counts: bool) -> Self {
        let pbf = params.solver == Solver::Pbf;
        Self {
            search: params.neighbor_search,
            // PBF has neither (XSPH stands for the viscosity).
            surface_tension: !pbf && params.has_surface_tension(),
            viscosity: !pbf && params.has_viscosity(),
            neighbor_counts,
            solver: params.solver,
            vorticity: pbf && params.pbf.vorticity_epsilon > 0.0,
        }
    }

    /// Shader defs common to every stage of this variant.
    pub fn shader_defs(&self) -> Vec<ShaderDefVal> {
        let mut defs = Vec::new();
        if self.search == NeighborSearch::Hash {
            defs.push("SEARCH_HASH".into());
        }
        if self.surface_tension {
            defs.push("SURFACE_TENSION".into());
        }
        if self.viscosity {
            defs.push("VISCOSITY".into());
        }
        if self.neighbor_counts {
            defs.push("NEIGHBOR_COUNT".into());
        }
        if self.solver == Solver::Pbf {
            defs.push("SOLVER_PBF".into());
        }
        if self.vorticity {
            defs.push("VORTICITY".into());
        }
        if self.solver == Solver::Dfsph {
            defs.push("SOLVER_DFSPH".into());
        }
        defs
    }
}

/// The integrator phase fused into the count pass, before the neighbour sort.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PrePhase {
    /// Nothing: forces at the current state.
    #[default]
    None,
    /// Kick-drift-kick: half kick, drift, collide, predicted velocity.
    KickDrift,
    /// The design's leapfrog: drift with a0, predicted velocity.
    LeapfrogDrift,
    /// PBF's prediction: keep x, v += g dt, x* = x + v dt, collide (Macklin & Müller 2013,
    /// Algorithm 1, lines 2-3).
    PbfPredict,
    /// DFSPH's move after the constant-density solve: x += v dt, collide (Bender & Koschier
    /// 2017, Algorithm 1).
    DfsphMove,
}

/// What the forces pass does besides computing accelerations.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ForcesRole {
    /// Accelerations from the current velocities, nothing else.
    #[default]
    Plain,
    /// Kick-drift-kick closing kick (viscosity sees predicted velocities).
    KickClose,
    /// The design's leapfrog, first evaluation: keep a0.
    LeapfrogFirst,
    /// The design's leapfrog, second evaluation: v += (a0 + a1) dt/2.
    LeapfrogSecond,
}

/// One force evaluation's plan.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EvaluationPlan {
    /// Phase fused into the count pass.
    pub pre: PrePhase,
    /// Role of the forces pass.
    pub forces: ForcesRole,
    /// Run the symplectic-Euler integrate pass after the forces.
    pub euler: bool,
    /// Where the time-step pass runs in this evaluation: right before the step's first
    /// integration phase.
    pub time_step: TimeStepPoint,
    /// The PBF phase of this pass over the list (`None` with WCSPH).
    pub pbf: PbfPhase,
    /// The DFSPH phase of this pass over the list (`None` with WCSPH and PBF).
    pub dfsph: DfsphPhase,
}

impl EvaluationPlan {
    /// Whether this evaluation sorts the particles (every WCSPH evaluation, PBF's prediction,
    /// DFSPH's neighbourhoods).
    pub fn sorts(&self) -> bool {
        match self.dfsph {
            DfsphPhase::None => matches!(self.pbf, PbfPhase::None | PbfPhase::Predict),
            DfsphPhase::Neighborhood | DfsphPhase::Move { .. } => true,
            _ => false,
        }
    }
}

/// One of DFSPH's two pressure solves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DfsphSolve {
    /// The constant-density solve on v* (before the move).
    Density,
    /// The divergence-free solve on v (after the move).
    Divergence,
}

/// Where a DFSPH step is (Bender & Koschier 2017, Algorithm 1; the CPU's `solver/dfsph/mod.rs`):
/// one pass over the stage list per phase, each running only its stages. A solve's Jacobi
/// iterations are two passes each, the stiffness applied to the velocities and the next
/// source; their indirect dispatches shrink to nothing once the device finds the solve
/// converged, so the CPU encodes the most iterations and never waits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DfsphPhase {
    /// Not DFSPH.
    #[default]
    None,
    /// Sort, lists, densities and factors at the current positions (the first step, or after
    /// spawns and parameter changes).
    Neighborhood,
    /// The non-pressure forces, the time step, v* = v + dt a_np, and the constant-density
    /// solve's first source (its warm start's, when `warm`).
    Predict {
        /// The solves warm-start.
        warm: bool,
    },
    /// The warm start's stiffness applied, then the solve's first source.
    WarmApply(DfsphSolve),
    /// Jacobi iteration k (from 0): the stiffness applied, then the next source.
    Iterate(DfsphSolve, u32),
    /// The constant-density solve's reactions and statistics.
    DensityEnd,
    /// x += v dt, the guard; sort, lists, densities and factors at the new positions; the
    /// divergence-free solve's first source (its warm start's, when `warm`).
    Move {
        /// The solves warm-start.
        warm: bool,
    },
    /// The divergence-free solve's reactions and statistics, the pressures, the pumps.
    Finish,
}

/// Where DFSPH's sources write their error sum and the applying pass reads it: source j of a
/// solve (0 the first) writes accumulator j % 2; iteration k reads accumulator k % 2.
pub fn dfsph_parity(j: u32) -> usize {
    (j % 2) as usize
}

/// The passes over the stage list of one DFSPH step: the neighbourhood first when it is stale,
/// then each solve with `warm` start or not and its `max_*` iterations.
pub fn dfsph_plans(
    stale: bool,
    warm: bool,
    max_density: u32,
    max_divergence: u32,
) -> Vec<EvaluationPlan> {
    let phase = |dfsph| EvaluationPlan {
        dfsph,
        ..EvaluationPlan::default()
    };
    let mut plans = Vec::new();
    if stale {
        plans.push(phase(DfsphPhase::Neighborhood));
    }
    plans.push(EvaluationPlan {
        time_step: TimeStepPoint::BeforeIntegrate,
        ..phase(DfsphPhase::Predict { warm })
    });
    for (solve, max) in [
        (DfsphSolve::Density, max_density),
        (DfsphSolve::Divergence, max_divergence),
    ] {
        if solve == DfsphSolve::Divergence {
            plans.push(phase(DfsphPhase::DensityEnd));
            plans.push(EvaluationPlan {
                pre: PrePhase::DfsphMove,
                ..phase(DfsphPhase::Move { warm })
            });
        }
        if warm {
            plans.push(phase(DfsphPhase::WarmApply(solve)));
        }
        plans.extend((0..max).map(|k| phase(DfsphPhase::Iterate(solve, k))));
    }
    plans.push(phase(DfsphPhase::Finish));
    plans
}

/// Where a PBF step is: one pass over the stage list per phase, each running only its stages.
/// The Jacobi iterations ping-pong the positions between two scratch buffers, so that every
/// iteration reads the positions of the one before while the sorted positions stay for the
/// neighbour search.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PbfPhase {
    /// Not PBF.
    #[default]
    None,
    /// Time step, prediction, neighbour sort of the predicted positions.
    Predict,
    /// Jacobi iteration k (from 0): λ, then the corrections.
    Iterate(u32),
    /// After `iterations` iterations: velocities, XSPH, vorticity confinement; the last of
    /// them copies the final positions over the sorted ones.
    Finish {
        /// The step's iterations (which scratch buffer holds the final positions).
        iterations: u32,
        /// Vorticity confinement runs (its pass is the last).
        vorticity: bool,
    },
}

/// Where PBF's positions are read in iteration `k` (0: the sorted predicted positions,
/// 1: scratch A, 2: scratch B), and so the role of the λ and correction passes. Iteration k
/// writes the next iteration's source: 0 writes A, odd iterations write B, even ones A.
pub fn pbf_source(k: u32) -> usize {
    match k {
        0 => 0,
        k if k % 2 == 1 => 1,
        _ => 2,
    }
}

/// The roles of the passes that read PBF's positions, by [`pbf_source`]: the sorted positions,
/// scratch A, scratch B.
pub const PBF_SOURCE_ROLES: &[&[&str]] = &[&[], &["PBF_FROM_A"], &["PBF_FROM_B"]];

/// Where an evaluation runs the time-step pass.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TimeStepPoint {
    /// Not in this evaluation.
    #[default]
    None,
    /// Before the count pass (its pre-phase drifts: kick-drift-kick, the leapfrog's second
    /// evaluation).
    Start,
    /// Between the forces and the integrate pass (symplectic Euler).
    BeforeIntegrate,
}

/// The passes over the stage list of one PBF step of `iterations` Jacobi iterations, with or
/// without vorticity confinement.
pub fn pbf_plans(iterations: u32, vorticity: bool) -> Vec<EvaluationPlan> {
    let mut plans = vec![EvaluationPlan {
        pre: PrePhase::PbfPredict,
        time_step: TimeStepPoint::Start,
        pbf: PbfPhase::Predict,
        ..EvaluationPlan::default()
    }];
    plans.extend((0..iterations).map(|k| EvaluationPlan {
        pbf: PbfPhase::Iterate(k),
        ..EvaluationPlan::default()
    }));
    plans.push(EvaluationPlan {
        pbf: PbfPhase::Finish {
            iterations,
            vorticity,
        },
        ..EvaluationPlan::default()
    });
    plans
}

/// The passes over the stage list of one step of `params`: PBF's phases ([`pbf_plans`]), DFSPH's
/// ([`dfsph_plans`], with `dfsph_iterations` encoded for each solve: see
/// `crate::dfsph_budget`), or the WCSPH integrator's evaluations ([`evaluation_plans`]).
pub fn step_plans(
    params: &SphParams,
    forces_stale: bool,
    dfsph_iterations: [u32; 2],
) -> Vec<EvaluationPlan> {
    match params.solver {
        Solver::Pbf => pbf_plans(params.pbf.iterations, params.pbf.vorticity_epsilon > 0.0),
        Solver::Dfsph => dfsph_plans(
            forces_stale,
            params.dfsph.warm_start,
            dfsph_iterations[0],
            dfsph_iterations[1],
        ),
        Solver::Wcsph => evaluation_plans(params.integrator, forces_stale),
    }
}

/// The evaluations of one step (kick-drift-kick with stale forces evaluates them first).
pub fn evaluation_plans(integrator: Integrator, forces_stale: bool) -> Vec<EvaluationPlan> {
    let plain = EvaluationPlan::default();
    match integrator {
        Integrator::SymplecticEuler => vec![EvaluationPlan {
            euler: true,
            time_step: TimeStepPoint::BeforeIntegrate,
            ..plain
        }],
        Integrator::KickDriftKick => {
            let step = EvaluationPlan {
                pre: PrePhase::KickDrift,
                forces: ForcesRole::KickClose,
                time_step: TimeStepPoint::Start,
                ..plain
            };
            if forces_stale {
                vec![plain, step]
            } else {
                vec![step]
            }
        }
        Integrator::Leapfrog => vec![
            EvaluationPlan {
                forces: ForcesRole::LeapfrogFirst,
                ..plain
            },
            EvaluationPlan {
                pre: PrePhase::LeapfrogDrift,
                forces: ForcesRole::LeapfrogSecond,
                time_step: TimeStepPoint::Start,
                ..plain
            },
        ],
    }
}

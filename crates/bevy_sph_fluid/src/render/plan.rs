//! What to run: the scene's variant (search, features: the shader defs every stage shares) and
//! each force evaluation's plan (the integrator phases fused into the passes). No GPU types.

use bevy::shader::ShaderDefVal;
use sph_core::{Integrator, NeighborSearch, SphParams};

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
                        flags.into_iter().map(move |neighbor_counts| VariantKey {
                            search,
                            surface_tension,
                            viscosity,
                            neighbor_counts,
                        })
                    })
                })
            })
    }

    /// The variant `params` need.
    pub fn of(params: &SphParams, neighbor_counts: bool) -> Self {
        Self {
            search: params.neighbor_search,
            surface_tension: params.has_surface_tension(),
            viscosity: params.has_viscosity(),
            neighbor_counts,
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
}

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

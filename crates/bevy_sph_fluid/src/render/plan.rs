//! What to run: the scene's variant (search, features: the shader defs every stage shares) and
//! each pass over the stage list's plan (the integrator phases fused into the passes, the
//! solver's phase). Each solver builds its step's plans in `render::solvers`. No GPU types.

use super::solvers::dfsph::phase::DfsphPhase;
use super::solvers::pbf::phase::PbfPhase;
use bevy::shader::ShaderDefVal;
use sph_core::{NeighborSearch, Solver, SphParams};

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
    /// Whitewater's stages (`render::whitewater`; off: not in the list, no buffers).
    pub whitewater: bool,
    /// The moved bodies' stages (`render::bodies`; off: not in the list, no buffers).
    pub bodies: bool,
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
                            .flat_map(move |(solver, vorticity)| {
                                flags.into_iter().flat_map(move |whitewater| {
                                    flags.into_iter().map(move |bodies| VariantKey {
                                        search,
                                        surface_tension,
                                        viscosity,
                                        neighbor_counts,
                                        solver,
                                        vorticity,
                                        whitewater,
                                        bodies,
                                    })
                                })
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
            whitewater: false,
            bodies: false,
        }
    }

    /// The variant a frame of the GPU backend runs: its parameters', with whitewater's stages
    /// while it is on and the bodies' while the device moves some.
    pub fn of_frame(frame: &crate::shared::SphFrame) -> Self {
        Self {
            whitewater: frame.whitewater.is_some(),
            bodies: frame.bodies.is_some(),
            ..Self::of(&frame.params, frame.neighbor_counts)
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
    /// The first pass that sorts of the frame's last step: whitewater's stages run after its
    /// sort, where the grid and the state agree, once a frame
    /// ([`super::solvers::frame_step_plans`]).
    pub step_first_sort: bool,
    /// The step's first pass: the moved bodies are placed before its other stages
    /// (`render::bodies`).
    pub place_bodies: bool,
    /// The step's last pass: the moved bodies move after its other stages, and record the
    /// frame's end when `Some(true)` (the frame's last step).
    pub move_bodies: Option<bool>,
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

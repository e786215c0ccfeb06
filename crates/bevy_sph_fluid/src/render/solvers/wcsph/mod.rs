//! WCSPH on the GPU: its stages (one `.rs` + `.wgsl` pair each), the force evaluations of one
//! step for each integrator ([`plans`]) and its part of the stage list ([`stage_list`]). CPU
//! twin: `sph_core::solver::wcsph`.

pub mod density;
pub mod free_surface_pressure;
pub mod integrate;

use crate::render::plan::{EvaluationPlan, ForcesRole, PrePhase, TimeStepPoint, VariantKey};
use crate::render::stage::GpuStage;
use crate::render::stages::{forces, normals, time_step};
use sph_core::Integrator;

/// WCSPH's stages after the sort, in each force evaluation: density and the equation of state,
/// the free surface's pressure, normals (with surface tension), forces, then the time step and
/// the symplectic-Euler integration where the plan asks for them.
pub fn stage_list(key: &VariantKey) -> Vec<&'static GpuStage> {
    let mut list: Vec<&'static GpuStage> = vec![&density::STAGE, &free_surface_pressure::STAGE];
    if key.surface_tension {
        list.push(&normals::STAGE);
    }
    list.extend([
        &forces::STAGE,
        &time_step::BEFORE_INTEGRATE,
        &integrate::STAGE,
    ]);
    list
}

/// The evaluations of one step (kick-drift-kick with stale forces evaluates them first).
pub fn plans(integrator: Integrator, forces_stale: bool) -> Vec<EvaluationPlan> {
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

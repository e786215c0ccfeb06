//! PBF on the GPU (Macklin & Müller 2013): its stages (one `.rs` + `.wgsl` pair each, the
//! shared arrays in `pbf.wgsl`), the phases of its step ([`phase`]), the passes of one step
//! ([`plans`]) and its part of the stage list ([`stage_list`]). CPU twin:
//! `sph_core::solver::pbf`.

pub mod pbf_confine;
pub mod pbf_correct;
pub mod pbf_lambda;
pub mod pbf_velocity;
pub mod pbf_vorticity;
pub mod pbf_wall_lambda;
pub mod pbf_wall_lists;
pub mod pbf_xsph;
pub mod phase;

use crate::render::plan::{EvaluationPlan, PrePhase, TimeStepPoint, VariantKey};
use crate::render::stage::GpuStage;
use crate::render::stages::neighbor_lists;
use phase::PbfPhase;

/// PBF's stages after the sort of the predicted positions: the step's neighbour lists and the
/// samples' wall lists, then each Jacobi iteration runs λ, the samples' λ and the corrections
/// (the plans' phases pick them), then the finish (velocities, XSPH, with vorticity
/// confinement its two passes).
pub fn stage_list(key: &VariantKey) -> Vec<&'static GpuStage> {
    let mut list: Vec<&'static GpuStage> = vec![
        &neighbor_lists::STAGE,
        &pbf_wall_lists::STAGE,
        &pbf_lambda::STAGE,
        &pbf_wall_lambda::STAGE,
        &pbf_correct::STAGE,
        &pbf_velocity::STAGE,
        &pbf_xsph::STAGE,
    ];
    if key.vorticity {
        list.extend([&pbf_vorticity::STAGE, &pbf_confine::STAGE]);
    }
    list
}

/// The passes over the stage list of one PBF step of `iterations` Jacobi iterations, with or
/// without vorticity confinement.
pub fn plans(iterations: u32, vorticity: bool) -> Vec<EvaluationPlan> {
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

//! DFSPH on the GPU (Bender & Koschier 2015, 2017): its stages (one `.rs` + `.wgsl` pair each,
//! the solves' shared sums in `dfsph.wgsl`), the phases of its step ([`phase`]), the passes of
//! one step ([`plans`]) and its part of the stage list ([`stage_list`]). CPU twin:
//! `sph_core::solver::dfsph`.

pub mod dfsph_apply;
pub mod dfsph_density;
pub mod dfsph_predict;
pub mod dfsph_reactions;
pub mod dfsph_source;
pub mod phase;

use crate::render::plan::{EvaluationPlan, PrePhase, TimeStepPoint, VariantKey};
use crate::render::stage::GpuStage;
use crate::render::stages::{forces, neighbor_lists, normals, time_step};
use phase::{DfsphPhase, DfsphSolve};

/// DFSPH's stages after the sort: the neighbourhood (lists, densities, factors, normals), the
/// non-pressure forces, the time step and v*, then each solve's iterations (apply, source) and
/// its end. The plans' phases pick them.
pub fn stage_list(key: &VariantKey) -> Vec<&'static GpuStage> {
    let mut list: Vec<&'static GpuStage> = vec![&neighbor_lists::STAGE, &dfsph_density::STAGE];
    if key.surface_tension {
        list.push(&normals::STAGE);
    }
    list.extend([
        &forces::STAGE,
        &time_step::BEFORE_INTEGRATE,
        &dfsph_predict::STAGE,
        &dfsph_apply::STAGE,
        &dfsph_source::STAGE,
        &dfsph_reactions::STAGE,
    ]);
    list
}

/// The passes over the stage list of one DFSPH step: the neighbourhood first when it is stale,
/// then each solve with `warm` start or not and its `max_*` iterations.
pub fn plans(
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

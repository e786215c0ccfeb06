//! A folder per pressure solver, each with its GPU stages, the phases and plans of its step and
//! its part of the stage list: WCSPH, DFSPH (Bender & Koschier 2015, 2017), PBF (Macklin &
//! Müller 2013). The shared stages (sort, neighbour lists, normals, forces, time step) are in
//! `render::stages`, whose registry puts the lists together. A new solver is a new folder here
//! plus one line in [`step_plans`] and in `render::stages::stage_list`.

pub mod dfsph;
pub mod pbf;
pub mod wcsph;

use super::plan::EvaluationPlan;
use sph_core::{Solver, SphParams};

/// The passes over the stage list of one step of `params`: PBF's phases ([`pbf::plans`]), DFSPH's
/// ([`dfsph::plans`], with `dfsph_iterations` encoded for each solve: see
/// `crate::dfsph_budget`), or the WCSPH integrator's evaluations ([`wcsph::plans`]).
pub fn step_plans(
    params: &SphParams,
    forces_stale: bool,
    dfsph_iterations: [u32; 2],
) -> Vec<EvaluationPlan> {
    match params.solver {
        Solver::Pbf => pbf::plans(params.pbf.iterations, params.pbf.vorticity_epsilon > 0.0),
        Solver::Dfsph => dfsph::plans(
            forces_stale,
            params.dfsph.warm_start,
            dfsph_iterations[0],
            dfsph_iterations[1],
        ),
        Solver::Wcsph => wcsph::plans(params.integrator, forces_stale),
    }
}

/// [`step_plans`] for a frame's step, with whitewater's pass marked
/// ([`EvaluationPlan::step_first_sort`]): the first pass that sorts of the frame's last step
/// (`last_of_frame`), so that whitewater runs once a frame; and the moved bodies' places: their
/// placement in the step's first pass, their motion in its last ([`EvaluationPlan::place_bodies`],
/// [`EvaluationPlan::move_bodies`]).
pub fn frame_step_plans(
    params: &SphParams,
    forces_stale: bool,
    dfsph_iterations: [u32; 2],
    last_of_frame: bool,
) -> Vec<EvaluationPlan> {
    let mut plans = step_plans(params, forces_stale, dfsph_iterations);
    if let Some(first) = plans.first_mut() {
        first.place_bodies = true;
    }
    if let Some(last) = plans.last_mut() {
        last.move_bodies = Some(last_of_frame);
    }
    if last_of_frame {
        if let Some(first_sort) = plans.iter_mut().find(|plan| plan.sorts()) {
            first_sort.step_first_sort = true;
        }
    }
    plans
}

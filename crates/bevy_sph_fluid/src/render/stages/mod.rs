//! The stage registry: one `name.rs` + `name.wgsl` pair per GPU stage, each declaring a
//! [`GpuStage`] `const`, and [`stage_list`], the ordered list of stages a scene runs, chosen from
//! its settings. The stages every solver shares (the sort, the neighbour lists, normals, forces,
//! the time step) are here; each solver's own stages and its part of the list are in its folder
//! under `render::solvers`. Adding a stage is adding its pair and one line in its list;
//! [`all_stages`] (embedded shaders, layouts, bind groups, the shader tests) follows from it.

pub mod bitonic_sort;
pub mod count_cells;
pub mod forces;
pub mod hash_offsets;
pub mod neighbor_lists;
pub mod normals;
pub mod prefix_sum;
pub mod scatter;
pub mod time_step;

use super::bodies;
use super::plan::VariantKey;
use super::solvers::{dfsph, pbf, wcsph};
use super::stage::GpuStage;
use super::whitewater;
use sph_core::{NeighborSearch, Solver};

/// The stages of one force evaluation of a scene of `key` (with PBF and DFSPH, of one step), in
/// order: the moved bodies' placement, the time step where a drift comes first, the sort, the
/// solver's own list, then the moved bodies' motion. Each
/// stage's `role` then picks its pipeline for the plan's integrator phase or solver phase, or
/// skips it (the time step runs in one of its two places, integrate only for symplectic Euler,
/// PBF's and DFSPH's stages each in their phase).
pub fn stage_list(key: &VariantKey) -> Vec<&'static GpuStage> {
    let mut list = bodies::first_stages(key);
    list.extend([&time_step::AT_START, &count_cells::STAGE]);
    match key.search {
        NeighborSearch::Grid => list.push(&prefix_sum::STAGE),
        NeighborSearch::Hash => list.extend([&bitonic_sort::STAGE, &hash_offsets::STAGE]),
    }
    list.push(&scatter::STAGE);
    // Once a step, where the sort left the grid and the state in agreement.
    list.extend(whitewater::stage_list(key));
    list.extend(match key.solver {
        Solver::Wcsph => wcsph::stage_list(key),
        Solver::Dfsph => dfsph::stage_list(key),
        Solver::Pbf => pbf::stage_list(key),
    });
    list.extend(bodies::last_stages(key));
    list
}

/// Every stage of every scene's list, each once: their shaders are embedded and their layouts
/// and bind groups made up front.
pub fn all_stages() -> Vec<&'static GpuStage> {
    let mut all: Vec<&'static GpuStage> = Vec::new();
    for key in VariantKey::all() {
        for stage in stage_list(&key) {
            if !all
                .iter()
                .any(|s| s.name == stage.name && s.roles == stage.roles)
            {
                all.push(stage);
            }
        }
    }
    all
}

#[cfg(test)]
mod tests {
    use super::*;
    use sph_core::solver::dfsph::step_stages as dfsph_step_stages;
    use sph_core::solver::pbf::step_stages as pbf_step_stages;
    use sph_core::solver::wcsph::step_stages as evaluation_stages;
    use sph_core::{CpuStage, SphParams};

    /// The CPU solver's evaluation mirrors the GPU list: mapping each GPU stage to its CPU twin
    /// (the integrator's time step and phases aside) gives the CPU stages in the same order.
    #[test]
    fn every_stage_list_mirrors_the_cpu_solver() {
        for search in [NeighborSearch::Grid, NeighborSearch::Hash] {
            for surface_tension in [0.0, 0.5] {
                let mut params = SphParams::water();
                params.neighbor_search = search;
                params.surface_tension = surface_tension;
                let key = VariantKey::of(&params, false);
                let mut twins: Vec<CpuStage> = stage_list(&key)
                    .iter()
                    .map(|stage| stage.cpu_twin)
                    .filter(|twin| !matches!(twin, CpuStage::TimeStep | CpuStage::Integrate))
                    .collect();
                twins.dedup();
                assert_eq!(twins, evaluation_stages(&params), "{key:?}");
            }
        }
    }

    /// PBF's list mirrors the CPU's PBF step: the GPU stages' twins (the time step aside),
    /// each once, are `pbf_step_stages`.
    #[test]
    fn the_pbf_stage_list_mirrors_the_cpu_step() {
        for search in [NeighborSearch::Grid, NeighborSearch::Hash] {
            for vorticity in [0.0, 0.1] {
                let mut params = SphParams::water();
                params.solver = sph_core::Solver::Pbf;
                params.neighbor_search = search;
                params.pbf.vorticity_epsilon = vorticity;
                let key = VariantKey::of(&params, false);
                assert!(key.solver == Solver::Pbf && key.vorticity == (vorticity > 0.0));
                let mut twins: Vec<CpuStage> = stage_list(&key)
                    .iter()
                    .map(|stage| stage.cpu_twin)
                    .filter(|twin| *twin != CpuStage::TimeStep)
                    .collect();
                twins.dedup();
                assert_eq!(twins, pbf_step_stages(&params), "{key:?}");
            }
        }
    }

    /// A PBF step runs each stage in its own phases only: the sort once (in the prediction),
    /// λ and the corrections once per iteration reading where the last one wrote, the finish
    /// once from where the last iteration wrote.
    #[test]
    fn pbf_phases_run_each_stage_where_it_belongs() {
        use crate::render::solvers::pbf::phase::PbfPhase;
        use crate::render::solvers::pbf::plans as pbf_plans;
        for iterations in 1..=5 {
            for vorticity in [false, true] {
                let key = VariantKey {
                    search: NeighborSearch::Grid,
                    surface_tension: false,
                    viscosity: false,
                    neighbor_counts: false,
                    solver: Solver::Pbf,
                    vorticity,
                    whitewater: false,
                    bodies: false,
                };
                let list = stage_list(&key);
                let mut runs: Vec<(&str, usize)> = Vec::new();
                for plan in pbf_plans(iterations, vorticity) {
                    for stage in &list {
                        if let Some(role) = (stage.role)(&plan) {
                            runs.push((stage.name, role));
                        }
                    }
                    if let PbfPhase::Iterate(k) = plan.pbf {
                        // Iteration k reads what k - 1 wrote: 0 the sorted positions, then
                        // A, B, A, ...
                        let expected = if k == 0 { 0 } else { 1 + (k as usize + 1) % 2 };
                        assert_eq!(runs.last(), Some(&("sph_pbf_correct", expected)));
                    }
                }
                let count = |name: &str| runs.iter().filter(|r| r.0 == name).count();
                assert_eq!(count("sph_count_cells"), 1);
                assert_eq!(count("sph_scatter"), 1);
                assert_eq!(count("sph_neighbor_lists"), 1);
                assert_eq!(count("sph_time_step"), 1);
                assert_eq!(count("sph_pbf_lambda"), iterations as usize);
                assert_eq!(count("sph_pbf_correct"), iterations as usize);
                assert_eq!(count("sph_pbf_velocity"), 1);
                assert_eq!(count("sph_pbf_confine"), vorticity as usize);
                // The finish reads where the last iteration wrote: A after odd counts.
                let finish = runs.iter().find(|r| r.0 == "sph_pbf_velocity").unwrap();
                assert_eq!(finish.1, if iterations % 2 == 1 { 1 } else { 2 });
            }
        }
    }

    /// DFSPH's list mirrors the CPU's DFSPH step: the GPU stages' twins (the time step aside),
    /// each once, are `dfsph_step_stages`.
    #[test]
    fn the_dfsph_stage_list_mirrors_the_cpu_step() {
        for search in [NeighborSearch::Grid, NeighborSearch::Hash] {
            for surface_tension in [0.0, 0.5] {
                let mut params = SphParams::water();
                params.use_solver(sph_core::Solver::Dfsph);
                params.neighbor_search = search;
                params.surface_tension = surface_tension;
                let key = VariantKey::of(&params, false);
                assert_eq!(key.solver, Solver::Dfsph);
                let mut twins: Vec<CpuStage> = stage_list(&key)
                    .iter()
                    .map(|stage| stage.cpu_twin)
                    .filter(|twin| *twin != CpuStage::TimeStep)
                    .collect();
                twins.dedup();
                assert_eq!(twins, dfsph_step_stages(&params), "{key:?}");
            }
        }
    }

    /// A DFSPH step runs each stage where it belongs: two sorts (one without a stale
    /// neighbourhood), the forces, time step and v* once, per solve one first source (after the
    /// warm start's apply when on), then per iteration one apply reading the sum the source
    /// before wrote and one source writing the other, and one end.
    #[test]
    fn dfsph_phases_run_each_stage_where_it_belongs() {
        use crate::render::solvers::dfsph::phase::DfsphPhase;
        use crate::render::solvers::dfsph::plans as dfsph_plans;
        let mut params = SphParams::water();
        params.use_solver(sph_core::Solver::Dfsph);
        let list = stage_list(&VariantKey::of(&params, false));
        for stale in [false, true] {
            for warm in [false, true] {
                for (most_density, most_divergence) in [(1, 1), (2, 5), (100, 100)] {
                    let plans = dfsph_plans(stale, warm, most_density, most_divergence);
                    let mut runs: Vec<(&str, usize, DfsphPhase)> = Vec::new();
                    for plan in &plans {
                        for stage in &list {
                            if let Some(role) = (stage.role)(plan) {
                                runs.push((stage.name, role, plan.dfsph));
                            }
                        }
                    }
                    let count = |name: &str| runs.iter().filter(|r| r.0 == name).count();
                    let sorts = 1 + stale as usize;
                    assert_eq!(count("sph_count_cells"), sorts);
                    assert_eq!(count("sph_neighbor_lists"), sorts);
                    assert_eq!(count("sph_dfsph_density"), sorts);
                    assert_eq!(count("sph_forces"), 1);
                    assert_eq!(count("sph_time_step"), 1);
                    assert_eq!(count("sph_dfsph_predict"), 1);
                    assert_eq!(count("sph_dfsph_reactions"), 2);
                    let warm_passes = 2 * warm as usize;
                    assert_eq!(
                        count("sph_dfsph_apply"),
                        (most_density + most_divergence) as usize + warm_passes
                    );
                    assert_eq!(
                        count("sph_dfsph_source"),
                        (most_density + most_divergence) as usize + 2 + warm_passes
                    );
                    // Iteration k reads sum k % 2 (roles 1, 2 and 4, 5), which source k wrote:
                    // the first source (role 1 or 5) writes a, source j > 0 writes j % 2.
                    let mut last_written = None;
                    for (name, role, _) in &runs {
                        match *name {
                            "sph_dfsph_source" if role % 4 == 1 => last_written = Some(0),
                            "sph_dfsph_source" if role % 4 >= 2 => {
                                last_written = Some(role % 4 - 2)
                            }
                            "sph_dfsph_apply" if role % 3 != 0 => {
                                assert_eq!(Some(role % 3 - 1), last_written, "{runs:?}");
                            }
                            _ => {}
                        }
                    }
                    // The move comes after the density solve's end and before the divergence
                    // solve's first source.
                    let at = |name: &str, role: usize| {
                        runs.iter()
                            .position(|r| r.0 == name && r.1 == role)
                            .unwrap()
                    };
                    assert!(at("sph_dfsph_reactions", 0) < at("sph_count_cells", 4));
                    assert!(at("sph_count_cells", 4) < at("sph_dfsph_source", 5 - warm as usize));
                    assert_eq!(runs.last().unwrap().0, "sph_dfsph_reactions");
                }
            }
        }
    }

    /// With whitewater, its six stages follow the scatter and run once a frame, after the first
    /// sort of the frame's last step, in every solver's plans (DFSPH's without a stale
    /// neighbourhood sorts first in its move); without it, none is in the list.
    #[test]
    fn whitewater_runs_once_a_frame_after_its_last_steps_first_sort_in_every_solver() {
        use crate::render::solvers::frame_step_plans;
        let whitewater_stages = |list: &[&GpuStage]| {
            list.iter()
                .filter(|s| s.name.starts_with("sph_whitewater"))
                .count()
        };
        for solver in [Solver::Wcsph, Solver::Pbf, Solver::Dfsph] {
            for integrator in [
                sph_core::Integrator::SymplecticEuler,
                sph_core::Integrator::KickDriftKick,
                sph_core::Integrator::Leapfrog,
            ] {
                for stale in [false, true] {
                    let mut params = SphParams::water();
                    params.use_solver(solver);
                    params.integrator = integrator;
                    let off = VariantKey::of(&params, false);
                    assert_eq!(whitewater_stages(&stage_list(&off)), 0);
                    let key = VariantKey {
                        whitewater: true,
                        ..off
                    };
                    let list = stage_list(&key);
                    let scatter = list.iter().position(|s| s.name == "sph_scatter").unwrap();
                    let names: Vec<&str> = list[scatter + 1..scatter + 7]
                        .iter()
                        .map(|s| s.name)
                        .collect();
                    assert_eq!(
                        names,
                        [
                            "sph_whitewater_normals",
                            "sph_whitewater_bin",
                            "sph_whitewater_bin_offsets",
                            "sph_whitewater_order",
                            "sph_whitewater_advect",
                            "sph_whitewater_shed"
                        ]
                    );
                    // A frame of three steps, planned as `sph_simulate` plans them.
                    let mut runs = [0; 3];
                    for (step, runs) in runs.iter_mut().enumerate() {
                        let plans = frame_step_plans(&params, stale, [3, 3], step == 2);
                        for plan in plans {
                            for stage in &list[scatter + 1..scatter + 7] {
                                if (stage.role)(&plan).is_some() {
                                    assert!(plan.sorts());
                                    *runs += 1;
                                }
                            }
                        }
                    }
                    assert_eq!(runs, [0, 0, 6], "{solver:?} {integrator:?} stale {stale}");
                }
            }
        }
    }

    #[test]
    fn names_are_unique_except_the_two_places_of_the_time_step() {
        let all = all_stages();
        assert_eq!(all.len(), 34, "every stage file, the time step twice");
        let mut names: Vec<&str> = all.iter().map(|s| s.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), all.len() - 1);
    }
}

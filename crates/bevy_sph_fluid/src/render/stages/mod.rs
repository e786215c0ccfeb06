//! The stage registry: one `name.rs` + `name.wgsl` pair per GPU stage, each declaring a
//! [`GpuStage`] `const`, and [`stage_list`], the ordered list of stages a scene runs, chosen from
//! its settings. Adding a stage is adding its pair and one line in [`stage_list`]; [`all_stages`]
//! (embedded shaders, layouts, bind groups, the shader tests) follows from it.

pub mod bitonic_sort;
pub mod count_cells;
pub mod density;
pub mod forces;
pub mod hash_offsets;
pub mod integrate;
pub mod normals;
pub mod prefix_sum;
pub mod scatter;
pub mod time_step;

use super::plan::VariantKey;
use super::stage::GpuStage;
use sph_core::NeighborSearch;

/// The stages of one force evaluation of a scene of `key`, in order. Each stage's `role` then
/// picks its pipeline for the evaluation's integrator phase, or skips it (the time step runs in
/// one of its two places, integrate only for symplectic Euler).
pub fn stage_list(key: &VariantKey) -> Vec<&'static GpuStage> {
    let mut list = vec![&time_step::AT_START, &count_cells::STAGE];
    match key.search {
        NeighborSearch::Grid => list.push(&prefix_sum::STAGE),
        NeighborSearch::Hash => list.extend([&bitonic_sort::STAGE, &hash_offsets::STAGE]),
    }
    list.extend([&scatter::STAGE, &density::STAGE]);
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
    use sph_core::stage::evaluation_stages;
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

    #[test]
    fn names_are_unique_except_the_two_places_of_the_time_step() {
        let all = all_stages();
        assert_eq!(all.len(), 11, "every stage file, the time step twice");
        let mut names: Vec<&str> = all.iter().map(|s| s.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), all.len() - 1);
    }
}

//! Composes every WGSL entry point with the shared library, in every variant the plugin queues,
//! and validates it with naga: no GPU needed.

use naga_oil::compose::{
    ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderDefValue,
};
use std::collections::HashMap;

const LIBRARY: [(&str, &str); 5] = [
    (
        "types.wgsl",
        include_str!("../src/render/shaders/types.wgsl"),
    ),
    (
        "bindings.wgsl",
        include_str!("../src/render/shaders/bindings.wgsl"),
    ),
    (
        "kernels.wgsl",
        include_str!("../src/render/shaders/kernels.wgsl"),
    ),
    (
        "neighbors.wgsl",
        include_str!("../src/render/shaders/neighbors.wgsl"),
    ),
    (
        "clock.wgsl",
        include_str!("../src/render/shaders/clock.wgsl"),
    ),
];

/// Each stage with the role defs the plugin queues it with.
const STAGES: [(&str, &str, &[&[&str]]); 10] = [
    (
        "time_step.wgsl",
        include_str!("../src/render/stages/time_step.wgsl"),
        &[&[]],
    ),
    (
        "count_cells.wgsl",
        include_str!("../src/render/stages/count_cells.wgsl"),
        &[&[], &["PRE_KDK"], &["PRE_LEAPFROG"]],
    ),
    (
        "prefix_sum.wgsl",
        include_str!("../src/render/stages/prefix_sum.wgsl"),
        &[&[]],
    ),
    (
        "bitonic_sort.wgsl",
        include_str!("../src/render/stages/bitonic_sort.wgsl"),
        &[&[]],
    ),
    (
        "hash_offsets.wgsl",
        include_str!("../src/render/stages/hash_offsets.wgsl"),
        &[&[]],
    ),
    (
        "scatter.wgsl",
        include_str!("../src/render/stages/scatter.wgsl"),
        &[&[]],
    ),
    (
        "density.wgsl",
        include_str!("../src/render/stages/density.wgsl"),
        &[&[], &["NEIGHBOR_COUNT"]],
    ),
    (
        "normals.wgsl",
        include_str!("../src/render/stages/normals.wgsl"),
        &[&[]],
    ),
    (
        "forces.wgsl",
        include_str!("../src/render/stages/forces.wgsl"),
        &[
            &[],
            &["USE_PREDICTED_VELOCITY", "POST_KDK"],
            &["POST_LEAPFROG_SAVE"],
            &["USE_PREDICTED_VELOCITY", "POST_LEAPFROG_KICK"],
        ],
    ),
    (
        "integrate.wgsl",
        include_str!("../src/render/stages/integrate.wgsl"),
        &[&[]],
    ),
];

fn composer() -> Composer {
    let mut composer = Composer::default();
    for (path, source) in LIBRARY {
        let result = composer
            .add_composable_module(ComposableModuleDescriptor {
                source,
                file_path: path,
                ..Default::default()
            })
            .map(|_| ());
        if let Err(e) = result {
            panic!("{path}: {}", e.emit_to_string(&composer));
        }
    }
    composer
}

fn compose(composer: &mut Composer, path: &str, source: &str, defs: &[&str]) -> naga::Module {
    let shader_defs: HashMap<String, ShaderDefValue> = defs
        .iter()
        .map(|d| (d.to_string(), ShaderDefValue::Bool(true)))
        .collect();
    match composer.make_naga_module(NagaModuleDescriptor {
        source,
        file_path: path,
        shader_defs,
        ..Default::default()
    }) {
        Ok(module) => module,
        Err(e) => panic!("{path} {defs:?}: {}", e.emit_to_string(composer)),
    }
}

#[test]
fn every_stage_and_variant_composes_and_validates() {
    let mut composer = composer();
    let mut validated = 0;
    for (path, source, roles) in STAGES {
        for search in [None, Some("SEARCH_HASH")] {
            for surface_tension in [None, Some("SURFACE_TENSION")] {
                for viscosity in [None, Some("VISCOSITY")] {
                    for role in roles.iter() {
                        let mut defs: Vec<&str> = role.to_vec();
                        defs.extend(search);
                        defs.extend(surface_tension);
                        defs.extend(viscosity);
                        let module = compose(&mut composer, path, source, &defs);
                        let mut validator = naga::valid::Validator::new(
                            naga::valid::ValidationFlags::all(),
                            naga::valid::Capabilities::default(),
                        );
                        if let Err(e) = validator.validate(&module) {
                            panic!("{path} {defs:?}: {e:?}");
                        }
                        assert_eq!(module.entry_points.len(), 1, "{path}");
                        assert_eq!(module.entry_points[0].stage, naga::ShaderStage::Compute);
                        validated += 1;
                    }
                }
            }
        }
    }
    // 10 stages, 8 common variants, roles: count 3, density 2, forces 4, the others 1.
    assert_eq!(validated, 8 * (1 + 3 + 1 + 1 + 1 + 1 + 2 + 1 + 4 + 1));
}

#[test]
fn variant_defs_change_the_code() {
    let mut composer = composer();
    let (_, forces, _) = STAGES[8];
    let plain = compose(&mut composer, "forces.wgsl", forces, &[]);
    let full = compose(
        &mut composer,
        "forces.wgsl",
        forces,
        &["VISCOSITY", "SURFACE_TENSION"],
    );
    let size = |m: &naga::Module| m.entry_points[0].function.expressions.len();
    assert!(
        size(&full) > size(&plain),
        "surface tension and viscosity add code"
    );
}

/// The size naga lays out for the WGSL struct named `name` in `stage`.
fn wgsl_struct_size(stage: usize, name: &str) -> usize {
    let mut composer = composer();
    let (path, source, _) = STAGES[stage];
    let module = compose(&mut composer, path, source, &[]);
    let ty = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref().is_some_and(|n| n.contains(name)))
        .unwrap_or_else(|| panic!("{name} in {path}"));
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).unwrap();
    layouter[ty.0].size as usize
}

#[test]
fn uniform_block_matches_the_rust_layout() {
    assert_eq!(
        wgsl_struct_size(6, "SphUniforms"),
        std::mem::size_of::<sph_core::gpu_layout::GpuSphParams>()
    );
}

#[test]
fn clock_matches_the_rust_layout() {
    assert_eq!(
        wgsl_struct_size(0, "SphClock"),
        std::mem::size_of::<sph_core::gpu_layout::GpuClock>()
    );
}

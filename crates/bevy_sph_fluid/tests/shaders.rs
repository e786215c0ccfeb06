//! Composes every WGSL entry point with the shared library, in every variant the plugin queues,
//! and validates it with naga: no GPU needed.

use bevy_sph_fluid::render::stage::GpuStage;
use bevy_sph_fluid::render::stages::all_stages;
use naga_oil::compose::{
    ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderDefValue,
};
use std::collections::HashMap;

mod translate;

const LIBRARY: [(&str, &str); 16] = [
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
    ("scan.wgsl", include_str!("../src/render/shaders/scan.wgsl")),
    (
        "neighbors.wgsl",
        include_str!("../src/render/shaders/neighbors.wgsl"),
    ),
    (
        "clock.wgsl",
        include_str!("../src/render/shaders/clock.wgsl"),
    ),
    (
        "checkpoint.wgsl",
        include_str!("../src/render/shaders/checkpoint.wgsl"),
    ),
    (
        "guard.wgsl",
        include_str!("../src/render/shaders/guard.wgsl"),
    ),
    (
        "pumps.wgsl",
        include_str!("../src/render/shaders/pumps.wgsl"),
    ),
    (
        "probes.wgsl",
        include_str!("../src/render/shaders/probes.wgsl"),
    ),
    (
        "body_reactions.wgsl",
        include_str!("../src/render/shaders/body_reactions.wgsl"),
    ),
    (
        "speculative_contact.wgsl",
        include_str!("../src/render/shaders/speculative_contact.wgsl"),
    ),
    (
        "pbf.wgsl",
        include_str!("../src/render/solvers/pbf/pbf.wgsl"),
    ),
    (
        "dfsph.wgsl",
        include_str!("../src/render/solvers/dfsph/dfsph.wgsl"),
    ),
    (
        "whitewater.wgsl",
        include_str!("../src/render/whitewater/whitewater.wgsl"),
    ),
    (
        "bodies.wgsl",
        include_str!("../src/render/bodies/bodies.wgsl"),
    ),
];

/// The WGSL of a registered stage: `sph_<stem>` lives in `stages/<stem>.wgsl` (the shared
/// stages), in its solver's folder, `solvers/<solver>/<stem>.wgsl`, or in its feature's
/// (`whitewater/<stem>.wgsl`, `bodies/<stem>.wgsl`).
fn stage_source(stage: &GpuStage) -> (String, String) {
    let stem = stage
        .name
        .strip_prefix("sph_")
        .unwrap_or_else(|| panic!("{}: stage names start with sph_", stage.name));
    let render = format!("{}/src/render", env!("CARGO_MANIFEST_DIR"));
    let source = [
        "stages",
        "solvers/wcsph",
        "solvers/dfsph",
        "solvers/pbf",
        "whitewater",
        "bodies",
    ]
    .iter()
    .find_map(|folder| std::fs::read_to_string(format!("{render}/{folder}/{stem}.wgsl")).ok())
    .unwrap_or_else(|| panic!("{stem}.wgsl is in no stage folder under {render}"));
    (format!("{stem}.wgsl"), source)
}

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

fn compose(
    composer: &mut Composer,
    path: &str,
    source: &str,
    defs: &[&str],
    workgroup_size: u32,
) -> naga::Module {
    let mut shader_defs: HashMap<String, ShaderDefValue> = defs
        .iter()
        .map(|d| (d.to_string(), ShaderDefValue::Bool(true)))
        .collect();
    shader_defs.insert(
        "WORKGROUP_SIZE".into(),
        ShaderDefValue::UInt(workgroup_size),
    );
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

/// Calls `each(path, defs, module)` with every registered stage composed in every variant it can
/// run in (its roles, the solvers, the searches, surface tension, viscosity, neighbour counts);
/// returns how many.
fn for_each_stage_variant(mut each: impl FnMut(&str, &[&str], &GpuStage, naga::Module)) -> usize {
    let mut composer = composer();
    let mut count = 0;
    for stage in all_stages() {
        let (path, source) = stage_source(stage);
        for solver in [&[][..], &["SOLVER_PBF"], &["SOLVER_PBF", "VORTICITY"]] {
            for search in [None, Some("SEARCH_HASH")] {
                for surface_tension in [None, Some("SURFACE_TENSION")] {
                    for viscosity in [None, Some("VISCOSITY")] {
                        for (role, neighbor_count) in stage
                            .roles
                            .iter()
                            .flat_map(|r| [(r, None), (r, Some("NEIGHBOR_COUNT"))])
                        {
                            let mut defs: Vec<&str> = role.to_vec();
                            defs.extend(solver);
                            defs.extend(search);
                            defs.extend(surface_tension);
                            defs.extend(viscosity);
                            defs.extend(neighbor_count);
                            let module =
                                compose(&mut composer, &path, &source, &defs, stage.workgroup_size);
                            each(&path, &defs, stage, module);
                            count += 1;
                        }
                    }
                }
            }
        }
    }
    count
}

#[test]
fn every_stage_and_variant_composes_and_validates() {
    let expected: usize = all_stages().iter().map(|s| 48 * s.roles.len()).sum();
    let validated = for_each_stage_variant(|path, defs, stage, module| {
        let mut validator = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        );
        if let Err(e) = validator.validate(&module) {
            panic!("{path} {defs:?}: {e:?}");
        }
        assert_eq!(module.entry_points.len(), 1, "{path}");
        let entry = &module.entry_points[0];
        assert_eq!(entry.stage, naga::ShaderStage::Compute);
        assert_eq!(
            entry.workgroup_size,
            [stage.workgroup_size, 1, 1],
            "{path}: the declared workgroup size reaches the shader"
        );
    });
    assert_eq!(validated, expected);
    assert!(validated >= 48 * 22, "{validated}");
}

/// Every stage variant, validated with the capabilities of each backend Bevy runs on and
/// translated by naga as wgpu does: to Metal Shading Language (macOS, iOS), HLSL (DX12) and
/// SPIR-V (Vulkan). WebGPU reads the WGSL itself, validated with the default capabilities above.
#[test]
fn every_stage_variant_translates_to_metal_hlsl_and_spirv() {
    let translated = for_each_stage_variant(|path, defs, _, module| {
        if let Err(e) = translate::translate_for_every_backend(&module) {
            panic!("{path} {defs:?}: {e}");
        }
    });
    assert!(translated >= 48 * 22, "{translated}");
}

#[test]
fn variant_defs_change_the_code() {
    let mut composer = composer();
    let all = all_stages();
    let forces = all.iter().find(|s| s.name == "sph_forces").unwrap();
    let (path, source) = stage_source(forces);
    let plain = compose(&mut composer, &path, &source, &[], 64);
    let full = compose(
        &mut composer,
        &path,
        &source,
        &["VISCOSITY", "SURFACE_TENSION"],
        64,
    );
    // Every function's code: the entry point and the functions it calls.
    let size = |m: &naga::Module| {
        m.entry_points[0].function.expressions.len()
            + m.functions
                .iter()
                .map(|(_, f)| f.expressions.len())
                .sum::<usize>()
    };
    assert!(
        size(&full) > size(&plain),
        "surface tension and viscosity add code"
    );
}

/// The registered stage `name` composed without variant definitions: its path and module.
fn composed_stage(name: &str) -> (String, naga::Module) {
    let mut composer = composer();
    let all = all_stages();
    let stage = all.iter().find(|s| s.name == name).unwrap();
    let (path, source) = stage_source(stage);
    let module = compose(&mut composer, &path, &source, &[], stage.workgroup_size);
    (path, module)
}

/// The WGSL struct named `name` in `stage`: the composed module, the struct's type and naga's
/// layout of the module's types.
fn wgsl_struct(
    stage: &str,
    name: &str,
) -> (naga::Module, naga::Handle<naga::Type>, naga::proc::Layouter) {
    let (path, module) = composed_stage(stage);
    let ty = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref().is_some_and(|n| n.contains(name)))
        .map(|(handle, _)| handle)
        .unwrap_or_else(|| panic!("{name} in {path}"));
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).unwrap();
    (module, ty, layouter)
}

/// The size naga lays out for the WGSL struct named `name` in `stage`.
fn wgsl_struct_size(stage: &str, name: &str) -> usize {
    let (_, ty, layouter) = wgsl_struct(stage, name);
    layouter[ty].size as usize
}

#[test]
fn uniform_block_matches_the_rust_layout() {
    assert_eq!(
        wgsl_struct_size("sph_density", "SphUniforms"),
        std::mem::size_of::<sph_core::gpu_layout::GpuSphParams>()
    );
}

/// A member of a struct as both languages see it: name, byte offset, byte size and the kind of
/// its scalars (a `vec3<f32>` and a `[f32; 3]` are both 12 bytes of floats).
type Member = (String, usize, usize, naga::ScalarKind);

/// Each member of the WGSL struct `name` in a composed stage (an `atomic<u32>` is a `u32`).
fn wgsl_members(stage: &str, name: &str) -> Vec<Member> {
    let (module, ty, layouter) = wgsl_struct(stage, name);
    // An array's kind is its elements'.
    fn kind(module: &naga::Module, name: &str, ty: naga::Handle<naga::Type>) -> naga::ScalarKind {
        match module.types[ty].inner {
            naga::TypeInner::Scalar(scalar)
            | naga::TypeInner::Vector { scalar, .. }
            | naga::TypeInner::Atomic(scalar) => scalar.kind,
            naga::TypeInner::Array { base, .. } => kind(module, name, base),
            ref other => {
                panic!("a member of {name} is neither a scalar, a vector nor an array: {other:?}")
            }
        }
    }
    match &module.types[ty].inner {
        naga::TypeInner::Struct { members, .. } => members
            .iter()
            .map(|m| {
                let name = m.name.clone().unwrap_or_default();
                let size = layouter[m.ty].size as usize;
                (
                    name.clone(),
                    m.offset as usize,
                    size,
                    kind(&module, &name, m.ty),
                )
            })
            .collect(),
        other => panic!("{name} in {stage} is not a struct: {other:?}"),
    }
}

/// The kind of a Rust field's scalars.
trait Scalars {
    const KIND: naga::ScalarKind;
}

impl Scalars for f32 {
    const KIND: naga::ScalarKind = naga::ScalarKind::Float;
}

impl Scalars for u32 {
    const KIND: naga::ScalarKind = naga::ScalarKind::Uint;
}

impl<T: Scalars, const N: usize> Scalars for [T; N] {
    const KIND: naga::ScalarKind = T::KIND;
}

fn scalars_of<T: Scalars>(_: &T) -> naga::ScalarKind {
    T::KIND
}

/// Each listed field of a Rust value's type, in the order given.
macro_rules! rust_fields {
    ($value:expr; $t:ty; $($field:ident),+ $(,)?) => {
        vec![$((
            stringify!($field).to_string(),
            std::mem::offset_of!($t, $field),
            std::mem::size_of_val(&$value.$field),
            scalars_of(&$value.$field),
        )),+]
    };
}

#[test]
fn every_uniform_field_sits_where_the_rust_layout_puts_it() {
    // The same names in the same order at the same offsets, with the same sizes and scalar
    // kinds: a field added, moved, renamed or retyped on one side only fails here (a field
    // missing from this list fails the size check above).
    let params = sph_core::gpu_layout::GpuSphParams::default();
    let rust = rust_fields!(params; sph_core::gpu_layout::GpuSphParams;
        particle_count, capacity, cell_count, table_size, grid_dims, sort_length, grid_origin,
        cell_size, box_min, wall_damping, box_max, fixed_dt, gravity, particle_mass, h, h_squared,
        poly6_scale, poly6_grad, spiky_grad, viscosity_laplacian, cohesion, cohesion_offset,
        rest_density, stiffness, viscosity, surface_tension, tait, clamp_negative_pressure,
        adaptive_time_step, guard_colliders, max_dt, cfl_factor, viscous_limit, speed_of_sound,
        rollback_enabled, checkpoint_interval, max_retries, recovery_steps, budget_time_bits,
        budget_steps, budget_frame, sum_reactions, pbf_cubic_k, pbf_cubic_l, pbf_relaxation,
        pbf_s_corr_k, pbf_inverse_w_dq, pbf_xsph_c, pbf_vorticity_epsilon, pbf_max_correction,
        pbf_s_corr_n, pbf_iterations, pbf_max_neighbors, pbf_over_relaxation_bits,
        dfsph_max_density_error, dfsph_max_divergence_error, dfsph_factor_epsilon,
        dfsph_warm_start, dfsph_min_density_iterations, dfsph_max_density_iterations,
        dfsph_min_divergence_iterations, dfsph_max_divergence_iterations, spacing,
        dfsph_density_warm_start, dfsph_divergence_warm_start, dfsph_max_correction, drain_frame,
        open_drains, pbf_jacobi_weight, drains_unused_w, dfsph_divergence_over_relaxation,
        dfsph_density_over_relaxation, boundary_friction, unmirrored_samples, contact_radius,
        contact_modulus, max_surface_pressure, surface_margin, whitewater_trapped_air_min,
        whitewater_trapped_air_max, whitewater_wave_crest_min, whitewater_wave_crest_max,
        whitewater_kinetic_min, whitewater_kinetic_max, whitewater_trapped_air_rate,
        whitewater_wave_crest_rate, whitewater_spray_below, whitewater_bubble_above,
        whitewater_lifetime_min, whitewater_lifetime_max, whitewater_buoyancy, whitewater_drag,
        whitewater_capacity, whitewater_seed, whitewater_steps, boundary_sample_count,
        whitewater_unused_z, whitewater_unused_w, buffer_at,
    );

    assert_eq!(wgsl_members("sph_density", "SphUniforms"), rust);
}

#[test]
fn clock_matches_the_rust_layout() {
    assert_eq!(
        wgsl_struct_size("sph_time_step", "SphClock"),
        std::mem::size_of::<sph_core::gpu_layout::GpuClock>()
    );
}

#[test]
fn every_clock_field_sits_where_the_rust_layout_puts_it() {
    let clock = sph_core::gpu_layout::GpuClock::default();
    let rust = rust_fields!(clock; sph_core::gpu_layout::GpuClock;
        dt, step, time_ns_lo, time_ns_hi, max_speed_bits, max_acceleration_bits, unstable_step,
        checkpoint_action, rollbacks, retries, halvings, stable_steps, has_checkpoint,
        checkpoint_step, checkpoint_time_lo, checkpoint_time_hi, checkpoint_count, restore_count,
        save_requested, rule_dt, checkpoint_rule_dt, boundary_corrections, wall_corrections,
        budget_frame, budget_remaining, budget_steps_left, neighbor_list_overflows, dfsph_args_x,
        dfsph_args_y, dfsph_args_z, dfsph_done, dfsph_applied, dfsph_error_a_lo, dfsph_error_a_hi,
        dfsph_error_b_lo, dfsph_error_b_hi, density_iterations, density_iterations_max,
        divergence_iterations, density_error, divergence_error, marked, tail_size, tail_frame,
        pbf_iteration, density_frame_max, divergence_frame_max, density_cut_short,
        divergence_cut_short, steps_run,
    );
    assert_eq!(wgsl_members("sph_time_step", "SphClock"), rust);
}

#[test]
fn the_shared_structures_sit_where_the_rust_layout_puts_them() {
    use sph_core::gpu_layout::GpuShared;
    let (module, ty, _) = wgsl_struct("sph_forces", "SphShared");
    let naga::TypeInner::Struct { members, .. } = &module.types[ty].inner else {
        panic!("SphShared is not a struct");
    };
    let offsets: Vec<(String, usize)> = members
        .iter()
        .map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize))
        .collect();
    let rust = [
        ("pumps", GpuShared::PUMPS_OFFSET),
        ("probes", GpuShared::PROBES_OFFSET),
        ("clock", GpuShared::CLOCK_OFFSET),
        ("body_forces", GpuShared::BODY_FORCES_OFFSET),
    ]
    .map(|(name, offset)| (name.to_string(), offset as usize));
    assert_eq!(offsets, rust);
    assert_eq!(
        wgsl_struct_size("sph_forces", "SphShared") as u64,
        GpuShared::BYTES
    );
}

#[test]
fn pumps_match_the_rust_layout() {
    assert_eq!(
        wgsl_struct_size("sph_integrate", "SphPumps"),
        std::mem::size_of::<sph_core::gpu_layout::GpuPumps>()
    );
}

#[test]
fn probes_match_the_rust_layout() {
    assert_eq!(
        wgsl_struct_size("sph_integrate", "SphProbes"),
        std::mem::size_of::<sph_core::gpu_layout::GpuProbes>()
    );
}

/// The value of the u32 constant `name` in a composed stage (naga_oil decorates the names).
fn u32_constant(stage: &str, name: &str) -> u32 {
    let (_, module) = composed_stage(stage);
    let (_, constant) = module
        .constants
        .iter()
        .find(|(_, c)| c.name.as_deref().is_some_and(|n| n.contains(name)))
        .unwrap_or_else(|| panic!("{name} in {stage}"));
    match module.global_expressions[constant.init] {
        naga::Expression::Literal(naga::Literal::U32(v)) => v,
        ref other => panic!("{name} is {other:?}"),
    }
}

/// The whitewater counters' word indices are `GpuDiffuseCounts`'s fields, in its order.
#[test]
fn the_whitewater_counters_sit_where_the_rust_layout_puts_them() {
    use sph_core::gpu_layout::GpuDiffuseCounts;
    // Each constant from a stage that uses it (naga keeps only what a module uses).
    let (shed, advect, normals) = (
        "sph_whitewater_shed",
        "sph_whitewater_advect",
        "sph_whitewater_normals",
    );
    let expected = [
        (
            "DIFFUSE_FREE",
            shed,
            std::mem::offset_of!(GpuDiffuseCounts, free),
        ),
        (
            "DIFFUSE_BORN",
            shed,
            std::mem::offset_of!(GpuDiffuseCounts, born),
        ),
        (
            "DIFFUSE_DROPPED",
            shed,
            std::mem::offset_of!(GpuDiffuseCounts, dropped),
        ),
        (
            "DIFFUSE_EXPIRED",
            advect,
            std::mem::offset_of!(GpuDiffuseCounts, expired),
        ),
        (
            "DIFFUSE_SPRAY",
            shed,
            std::mem::offset_of!(GpuDiffuseCounts, spray),
        ),
        (
            "DIFFUSE_FOAM",
            normals,
            std::mem::offset_of!(GpuDiffuseCounts, foam),
        ),
        (
            "DIFFUSE_BUBBLES",
            normals,
            std::mem::offset_of!(GpuDiffuseCounts, bubbles),
        ),
        (
            "DIFFUSE_HIGH_WATER",
            shed,
            std::mem::offset_of!(GpuDiffuseCounts, high_water),
        ),
    ];
    for (name, stage, offset) in expected {
        assert_eq!(u32_constant(stage, name), (offset / 4) as u32, "{name}");
    }
    // The classes count at DIFFUSE_SPRAY + class (0 spray, 1 foam, 2 bubble).
    assert_eq!(
        u32_constant(normals, "DIFFUSE_BUBBLES"),
        u32_constant(normals, "DIFFUSE_SPRAY") + 2
    );
}

#[test]
fn the_packed_pairs_have_the_rust_twins_bits() {
    use sph_core::gpu_dfsph_pairs::{GRAD_BITS, INDEX_BITS};
    assert_eq!(
        u32_constant("sph_dfsph_apply", "PAIR_INDEX_BITS"),
        INDEX_BITS
    );
    assert_eq!(u32_constant("sph_dfsph_apply", "PAIR_GRAD_BITS"), GRAD_BITS);
}

#[test]
fn the_lists_tile_as_the_rust_layout_sizes_them() {
    let value = u32_constant("sph_neighbor_lists", "LIST_TILE");
    assert_eq!(value, sph_core::gpu_layout::LIST_TILE);
    // Whole tiles: the last particle's last entry fits, for a capacity that is not a multiple.
    let capacity = 8 * 5 + 3;
    let last = ((capacity - 1) / value * sph_core::gpu_layout::PBF_MAX_NEIGHBORS
        + sph_core::gpu_layout::PBF_MAX_NEIGHBORS
        - 1)
        * value
        + (capacity - 1) % value;
    assert!((last as u64) < sph_core::gpu_layout::list_entries(capacity));
}

/// The wall lists' length in the shaders is the Rust layout's, which sizes their buffer.
#[test]
fn the_wall_lists_hold_what_the_rust_layout_sizes() {
    let value = u32_constant("sph_pbf_wall_lists", "PBF_MAX_WALL_NEIGHBORS");
    assert_eq!(value, sph_core::gpu_layout::PBF_MAX_WALL_NEIGHBORS);
    assert_eq!(sph_core::gpu_layout::PBF_WALL_LIST_WORDS, value + 2);
}

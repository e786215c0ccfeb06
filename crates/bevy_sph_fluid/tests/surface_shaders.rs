//! The water surface's shaders (`src/surface/*.wgsl`): every entry shader composes with the
//! surface library in every variant the plugin queues and validates with naga, and the uniform
//! block's WGSL layout matches the Rust one; each variant translates to MSL, HLSL and SPIR-V.
//! No GPU needed.

use bevy::render::render_resource::ShaderType;
use bevy_sph_fluid::surface::view::GpuSurfaceUniform;
use naga_oil::compose::{
    ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderDefValue,
};
use std::collections::HashMap;

mod translate;

const LIBRARY: [(&str, &str); 2] = [
    (
        "surface_types.wgsl",
        include_str!("../src/surface/surface_types.wgsl"),
    ),
    (
        "surface_impostor.wgsl",
        include_str!("../src/surface/surface_impostor.wgsl"),
    ),
];

/// An entry shader, the shader-def sets the plugin queues it with, and its entry points.
type Entry = (
    &'static str,
    &'static [&'static [&'static str]],
    &'static [naga::ShaderStage],
);

/// Every entry shader.
const ENTRIES: [Entry; 6] = [
    (
        "surface_depth.wgsl",
        &[&[]],
        &[naga::ShaderStage::Vertex, naga::ShaderStage::Fragment],
    ),
    (
        "surface_thickness.wgsl",
        &[&[]],
        &[naga::ShaderStage::Vertex, naga::ShaderStage::Fragment],
    ),
    (
        "surface_whitewater.wgsl",
        &[&[]],
        &[naga::ShaderStage::Vertex, naga::ShaderStage::Fragment],
    ),
    (
        "surface_filter.wgsl",
        &[&[], &["FILTER_VERTICAL"]],
        &[naga::ShaderStage::Fragment],
    ),
    (
        "surface_normals.wgsl",
        &[&[]],
        &[naga::ShaderStage::Fragment],
    ),
    (
        "surface_composite.wgsl",
        &[
            &[],
            &["MULTISAMPLED_DEPTH"],
            &["WHITEWATER"],
            &["MULTISAMPLED_DEPTH", "WHITEWATER"],
        ],
        &[naga::ShaderStage::Fragment],
    ),
];

fn composer() -> Composer {
    let mut composer = Composer::default();
    for (path, source) in LIBRARY {
        if let Err(e) = composer.add_composable_module(ComposableModuleDescriptor {
            source,
            file_path: path,
            ..Default::default()
        }) {
            panic!("{path}: {}", e.emit_to_string(&composer));
        }
    }
    composer
}

fn compose(composer: &mut Composer, path: &str, defs: &[&str]) -> naga::Module {
    let file = format!("{}/src/surface/{path}", env!("CARGO_MANIFEST_DIR"));
    let source = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{file}: {e}"));
    let shader_defs: HashMap<String, ShaderDefValue> = defs
        .iter()
        .map(|d| (d.to_string(), ShaderDefValue::Bool(true)))
        .collect();
    composer
        .make_naga_module(NagaModuleDescriptor {
            source: &source,
            file_path: path,
            shader_defs,
            ..Default::default()
        })
        .unwrap_or_else(|e| panic!("{path} {defs:?}: {}", e.emit_to_string(composer)))
}

#[test]
fn every_surface_shader_and_variant_composes_and_validates() {
    let mut composer = composer();
    let mut validated = 0;
    for (path, variants, stages) in ENTRIES {
        for defs in variants {
            let module = compose(&mut composer, path, defs);
            let mut validator = naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::default(),
            );
            if let Err(e) = validator.validate(&module) {
                panic!("{path} {defs:?}: {e:?}");
            }
            let found: Vec<naga::ShaderStage> =
                module.entry_points.iter().map(|e| e.stage).collect();
            assert_eq!(found, stages.to_vec(), "{path}: entry points");
            validated += 1;
        }
    }
    assert_eq!(validated, 10);
}

#[test]
fn every_surface_shader_variant_translates_to_metal_hlsl_and_spirv() {
    let mut composer = composer();
    let mut translated = 0;
    for (path, variants, _) in ENTRIES {
        for defs in variants {
            let module = compose(&mut composer, path, defs);
            if let Err(e) = translate::translate_for_every_backend(&module) {
                panic!("{path} {defs:?}: {e}");
            }
            translated += 1;
        }
    }
    assert_eq!(translated, 10);
}

#[test]
fn every_surface_wgsl_file_is_checked() {
    let dir = format!("{}/src/surface", env!("CARGO_MANIFEST_DIR"));
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{dir}: {e}"))
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".wgsl"))
        .collect();
    files.sort();
    let mut checked: Vec<String> = LIBRARY
        .iter()
        .map(|(path, _)| path.to_string())
        .chain(ENTRIES.iter().map(|(path, _, _)| path.to_string()))
        .collect();
    checked.sort();
    assert_eq!(files, checked);
}

#[test]
fn surface_uniform_matches_the_rust_layout() {
    let mut composer = composer();
    let module = compose(&mut composer, "surface_filter.wgsl", &[]);
    let (handle, _) = module
        .types
        .iter()
        .find(|(_, t)| {
            t.name.as_deref() == Some("SurfaceUniform")
                || t.name
                    .as_deref()
                    .is_some_and(|n| n.contains("SurfaceUniform"))
        })
        .expect("SurfaceUniform in surface_filter.wgsl");
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).unwrap();
    assert_eq!(
        layouter[handle].size as u64,
        GpuSurfaceUniform::min_size().get()
    );
}

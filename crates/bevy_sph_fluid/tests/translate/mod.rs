//! Translates a composed WGSL module for each backend Bevy runs on: validated with the
//! backend's own capabilities, then written as MSL 2.4 (Metal), HLSL shader model 6.0 (DX12) and
//! SPIR-V (Vulkan), every entry point on its own. Shared by `shaders.rs` and
//! `surface_shaders.rs`.

use naga::back::{hlsl, msl, spv};
use naga::valid::{Capabilities, ValidationFlags, Validator};

/// The backends and the capabilities their writers support.
pub fn backends() -> [(&'static str, Capabilities); 3] {
    [
        ("Metal", msl::supported_capabilities()),
        ("DX12", hlsl::supported_capabilities()),
        ("Vulkan", spv::supported_capabilities()),
    ]
}

/// Validates `module` for every backend and writes each of its entry points; the error names
/// the backend and the entry point.
pub fn translate_for_every_backend(module: &naga::Module) -> Result<(), String> {
    for (backend, capabilities) in backends() {
        let info = Validator::new(ValidationFlags::all(), capabilities)
            .validate(module)
            .map_err(|e| format!("{backend}: {e:?}"))?;
        for entry in &module.entry_points {
            let (stage, name) = (entry.stage, entry.name.clone());
            let written = match backend {
                "Metal" => msl::write_string(
                    module,
                    &info,
                    &msl::Options {
                        lang_version: (2, 4),
                        ..Default::default()
                    },
                    &msl::PipelineOptions {
                        entry_point: Some((stage, name.clone())),
                        ..Default::default()
                    },
                )
                .map(|(text, _)| text.len())
                .map_err(|e| format!("{e:?}")),
                "DX12" => {
                    let mut text = String::new();
                    let options = hlsl::Options {
                        shader_model: hlsl::ShaderModel::V6_0,
                        ..Default::default()
                    };
                    let pipeline = hlsl::PipelineOptions {
                        entry_point: Some((stage, name.clone())),
                    };
                    hlsl::Writer::new(&mut text, &options, &pipeline)
                        .write(module, &info, None)
                        .map(|_| text.len())
                        .map_err(|e| format!("{e:?}"))
                }
                _ => spv::write_vec(
                    module,
                    &info,
                    &spv::Options::default(),
                    Some(&spv::PipelineOptions {
                        shader_stage: stage,
                        entry_point: name.clone(),
                    }),
                )
                .map(|words| 4 * words.len())
                .map_err(|e| format!("{e:?}")),
            };
            match written {
                Ok(0) => return Err(format!("{backend} {name}: empty output")),
                Ok(_) => {}
                Err(e) => return Err(format!("{backend} {name}: {e}")),
            }
        }
    }
    Ok(())
}

//! The device limits the GPU backend's pipelines need, from the registered stages. Bevy asks
//! the adapter for its own limits on native backends, so the check is against what the device
//! was created with; a device short of a limit runs the CPU solver instead, with the reason in
//! [`crate::SphStats::fallback_reason`]. Every stage fits WebGPU's defaults
//! (`wgpu::Limits::default()`: 8 storage buffers per shader stage), because the logical buffers
//! are packed into arenas (`render::arenas`).
//!
//! The plugin asks for no limit in `WgpuSettings` itself: under Bevy's default priority
//! (`WgpuSettingsPriority::Functionality`) the device already gets all the adapter has, and a
//! request beyond the adapter would fail the device's creation, where the check here falls back.

use crate::render::stages::all_stages;
use bevy::render::render_resource::WgpuLimits;

/// What the stages need of the device.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GpuNeeds {
    /// The most storage buffers one stage binds (group 0, besides its uniform block).
    pub storage_buffers_per_stage: u32,
    /// The largest workgroup (x; y and z are 1).
    pub workgroup_size: u32,
    /// The stage that binds the most storage buffers.
    pub widest_stage: &'static str,
}

impl GpuNeeds {
    /// The needs of every registered stage.
    pub fn of_all_stages() -> Self {
        let mut needs = Self {
            storage_buffers_per_stage: 0,
            workgroup_size: 0,
            widest_stage: "",
        };
        for stage in all_stages() {
            let storage = stage.arenas().len() as u32;
            if storage > needs.storage_buffers_per_stage {
                needs.storage_buffers_per_stage = storage;
                needs.widest_stage = stage.name;
            }
            needs.workgroup_size = needs.workgroup_size.max(stage.workgroup_size);
        }
        needs
    }

    /// `None` when `limits` cover the needs, else each limit that falls short: its name, what
    /// is needed and what the device has.
    pub fn shortfall(&self, limits: &WgpuLimits) -> Option<String> {
        let checks = [
            (
                "max_storage_buffers_per_shader_stage",
                self.storage_buffers_per_stage,
                limits.max_storage_buffers_per_shader_stage,
            ),
            (
                "max_compute_workgroup_size_x",
                self.workgroup_size,
                limits.max_compute_workgroup_size_x,
            ),
            (
                "max_compute_invocations_per_workgroup",
                self.workgroup_size,
                limits.max_compute_invocations_per_workgroup,
            ),
        ];
        let short: Vec<String> = checks
            .iter()
            .filter(|(_, needed, has)| needed > has)
            .map(|(name, needed, has)| format!("{name}: needs {needed}, the device has {has}"))
            .collect();
        (!short.is_empty()).then(|| {
            format!(
                "{} (the widest stage, {}, binds {} storage buffers)",
                short.join("; "),
                self.widest_stage,
                self.storage_buffers_per_stage
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_stage_fits_webgpus_defaults_and_a_smaller_device_falls_short_by_name() {
        let needs = GpuNeeds::of_all_stages();
        let widest = all_stages()
            .iter()
            .map(|s| s.arenas().len() as u32)
            .max()
            .unwrap_or(0);
        assert_eq!(needs.storage_buffers_per_stage, widest);
        // WebGPU's defaults (8 storage buffers per stage, 256 invocations) hold every stage.
        assert_eq!(needs.shortfall(&WgpuLimits::default()), None);
        // A device with one storage buffer fewer than the widest stage binds falls short, by name.
        let short = WgpuLimits {
            max_storage_buffers_per_shader_stage: widest - 1,
            ..WgpuLimits::default()
        };
        let reason = needs.shortfall(&short).expect("one buffer too few");
        assert!(
            reason.contains("max_storage_buffers_per_shader_stage: needs")
                && reason.contains(&format!("the device has {}", widest - 1)),
            "{reason}"
        );
    }

    /// Per shader stage: (storage buffers, uniform buffers, dynamic uniform buffers, sampled
    /// textures, samplers) of `layout`.
    fn bindings_of(layout: &bevy::render::render_resource::BindGroupLayoutDescriptor) -> [u32; 5] {
        use bevy::render::render_resource::{BindingType, BufferBindingType};
        let mut counts = [0; 5];
        for entry in &layout.entries {
            match entry.ty {
                BindingType::Buffer {
                    ty: BufferBindingType::Storage { .. },
                    ..
                } => counts[0] += 1,
                BindingType::Buffer {
                    has_dynamic_offset, ..
                } => {
                    counts[1] += 1;
                    counts[2] += has_dynamic_offset as u32;
                }
                BindingType::Texture { .. } => counts[3] += 1,
                BindingType::Sampler(_) => counts[4] += 1,
                _ => {}
            }
        }
        counts
    }

    #[test]
    fn every_pipelines_bind_groups_fit_webgpus_defaults() {
        use crate::surface::{composite, filter, impostor, normals};
        let webgpu = WgpuLimits::default();
        let most = [
            webgpu.max_storage_buffers_per_shader_stage,
            webgpu.max_uniform_buffers_per_shader_stage,
            webgpu.max_dynamic_uniform_buffers_per_pipeline_layout,
            webgpu.max_sampled_textures_per_shader_stage,
            webgpu.max_samplers_per_shader_stage,
        ];
        let mut layouts: Vec<_> = all_stages()
            .iter()
            .map(|stage| crate::render::pipelines::stage_layout(stage))
            .collect();
        layouts.extend([
            impostor::impostor_layout(),
            filter::filter_layout(),
            normals::normals_layout(),
        ]);
        for whitewater in [false, true] {
            for multisampled in [false, true] {
                layouts.push(composite::composite_layout(multisampled, whitewater));
            }
        }
        for layout in &layouts {
            let counts = bindings_of(layout);
            for (k, (count, most)) in counts.iter().zip(most).enumerate() {
                assert!(
                    count <= &most,
                    "{}: binding kind {k}: {count} > {most}",
                    layout.label
                );
            }
        }
        // Every pipeline has this one group, besides the bitonic sort's group 1: one more
        // uniform block, at a dynamic offset (2 and 1 of WebGPU's 12 and 8).
    }

    #[test]
    fn bevy_creates_its_device_with_the_adapters_own_limits_by_default() {
        // What the module relies on instead of requesting limits (see the module docs).
        let settings = bevy::render::settings::WgpuSettings::default();
        assert!(matches!(
            settings.priority,
            bevy::render::settings::WgpuSettingsPriority::Functionality
        ));
    }
}

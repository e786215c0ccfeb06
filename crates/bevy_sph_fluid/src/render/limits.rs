//! The device limits the GPU backend's pipelines need, from the registered stages. Bevy asks
//! the adapter for its own limits on native backends, so the check is against what the device
//! was created with; a device short of a limit runs the CPU solver instead, with the reason in
//! [`crate::SphStats::fallback_reason`]. WebGPU's defaults (`wgpu::Limits::default()`) allow 8
//! storage buffers per shader stage, fewer than the solvers' largest passes bind.
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
            let storage = stage.bindings.len() as u32;
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
    fn the_needs_are_the_stages_and_webgpus_defaults_fall_short_by_name() {
        let needs = GpuNeeds::of_all_stages();
        let widest = all_stages()
            .iter()
            .map(|s| s.bindings.len() as u32)
            .max()
            .unwrap_or(0);
        assert_eq!(needs.storage_buffers_per_stage, widest);
        // WebGPU's default of 8 storage buffers per stage is short, and the reason names it.
        let webgpu = WgpuLimits::default();
        let reason = needs
            .shortfall(&webgpu)
            .expect("8 storage buffers are too few");
        assert!(
            reason.contains("max_storage_buffers_per_shader_stage: needs")
                && reason.contains("the device has 8"),
            "{reason}"
        );
        // A device that has what the stages bind passes.
        let enough = WgpuLimits {
            max_storage_buffers_per_shader_stage: widest,
            ..WgpuLimits::default()
        };
        assert_eq!(needs.shortfall(&enough), None);
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

//! Whitewater on the GPU backend, the main world's side: `apply` validates [`SphWhitewater`]
//! and hands it to the render world in the frame plan (`SphFrame::whitewater`) with the buffers
//! it copies into: the slots for drawing, the counters, the fluid's potentials. The diffuse
//! particles stay on the device; only the counters are read back every frame
//! (`sph_read_gpu_whitewater`), into [`SphStats::whitewater`] and the slots worth drawing.

use super::resources::{SphDiffuseParticles, SphWhitewater};
use crate::api::{SphStats, SphWhitewaterCounts};
use crate::shared::{GpuWhitewaterFrame, SphSimulation};
use bevy::asset::RenderAssetUsages;
use bevy::prelude::*;
use bevy::render::gpu_readback::{Readback, ReadbackComplete};
use bevy::render::storage::ShaderBuffer;
use sph_core::gpu_layout::GpuDiffuseCounts;
use sph_core::whitewater::settings::check_capacity;

/// The counters as last read back, and the reader of the current buffer.
#[derive(Resource, Default)]
pub struct DiffuseCountsReadback {
    source: Option<(Handle<ShaderBuffer>, Entity)>,
    /// The latest counters that arrived.
    pub latest: Option<GpuDiffuseCounts>,
}

/// A device buffer of `bytes` the render world copies into and the main world may read back.
fn device_buffer(assets: &mut Assets<ShaderBuffer>, bytes: usize) -> Handle<ShaderBuffer> {
    assets.add(ShaderBuffer::with_size(
        bytes.max(16),
        RenderAssetUsages::RENDER_WORLD,
    ))
}

/// Hands `wanted` to the render world when it differs from what runs there: a new pool (its
/// buffers made, its generation bumped), or none. A refused setting is named in
/// [`SphStats::whitewater_error`] and what ran before stays.
pub(super) fn apply(
    wanted: Option<SphWhitewater>,
    sim: &mut SphSimulation,
    stats: &mut SphStats,
    assets: &mut Assets<ShaderBuffer>,
    refused: &mut Option<SphWhitewater>,
) {
    let Some(wanted) = wanted else {
        if sim.frame.whitewater.is_some() {
            sim.frame.whitewater = None;
        }
        stats.whitewater_error = None;
        *refused = None;
        return;
    };
    let running = sim.frame.whitewater.as_ref();
    let same = running.is_some_and(|w| {
        w.settings == wanted.settings
            && w.capacity == wanted.capacity
            && w.fluid_capacity == sim.capacity
    });
    if same || Some(wanted) == *refused {
        return;
    }
    if let Err(e) = wanted
        .settings
        .validate()
        .and_then(|()| check_capacity(wanted.capacity as usize))
    {
        *refused = Some(wanted);
        stats.whitewater_error = Some(e.to_string());
        return;
    }
    *refused = None;
    stats.whitewater_error = None;
    let generation = running.map_or(1, |w| w.generation + 1);
    let counts_bytes = std::mem::size_of::<GpuDiffuseCounts>();
    sim.frame.whitewater = Some(GpuWhitewaterFrame {
        settings: wanted.settings,
        capacity: wanted.capacity,
        fluid_capacity: sim.capacity,
        generation,
        draw: device_buffer(assets, 16 * wanted.capacity as usize),
        counts: device_buffer(assets, counts_bytes),
        potentials: device_buffer(assets, 16 * sim.capacity as usize),
    });
}

/// Keeps a `Readback` of the counters alive while the GPU backend runs whitewater, and turns
/// the latest into [`SphStats::whitewater`] and the slots the surface draws.
pub(super) fn sph_read_gpu_whitewater(
    sim: Res<SphSimulation>,
    mut readback: ResMut<DiffuseCountsReadback>,
    mut particles: ResMut<SphDiffuseParticles>,
    mut stats: ResMut<SphStats>,
    mut commands: Commands,
) {
    let running = sim
        .frame
        .whitewater
        .as_ref()
        .filter(|_| sim.backend == crate::api::SphBackend::Gpu);
    let Some(white) = running else {
        if let Some((_, entity)) = readback.source.take() {
            commands.entity(entity).despawn();
            readback.latest = None;
            if sim.backend == crate::api::SphBackend::Gpu {
                *particles = SphDiffuseParticles::default();
                stats.whitewater = None;
            }
        }
        return;
    };
    if readback.source.as_ref().map(|(h, _)| h) != Some(&white.counts) {
        if let Some((_, entity)) = readback.source.take() {
            commands.entity(entity).despawn();
        }
        let reader = commands
            .spawn(Readback::buffer(white.counts.clone()))
            .observe(
                |event: On<ReadbackComplete>, mut target: ResMut<DiffuseCountsReadback>| {
                    let size = std::mem::size_of::<GpuDiffuseCounts>();
                    if event.data.len() >= size {
                        target.latest = Some(bytemuck::pod_read_unaligned(&event.data[..size]));
                    }
                },
            )
            .id();
        readback.source = Some((white.counts.clone(), reader));
        readback.latest = None;
    }
    let counts = readback
        .latest
        .unwrap_or_else(|| GpuDiffuseCounts::empty(white.capacity));
    if particles.buffer.as_ref() != Some(&white.draw) {
        *particles = SphDiffuseParticles {
            buffer: Some(white.draw.clone()),
            ..default()
        };
    }
    particles.slots = counts.high_water.min(white.capacity);
    stats.whitewater = Some(SphWhitewaterCounts {
        spray: counts.spray,
        foam: counts.foam,
        bubbles: counts.bubbles,
        born: counts.born as u64,
        dropped: counts.dropped as u64,
        expired: counts.expired as u64,
    });
}

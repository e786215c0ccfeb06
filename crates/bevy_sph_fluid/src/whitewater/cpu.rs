//! Whitewater on the CPU backend, the main world's side: the solver steps the diffuse particles
//! after every stable step; `sph_read_whitewater` copies them out for drawing and counting.

use super::resources::{diffuse_class_w, SphDiffuseParticles};
use crate::api::{SphBackend, SphStats, SphWhitewaterCounts};
use crate::shared::SphSimulation;
use bevy::asset::RenderAssetUsages;
use bevy::prelude::*;
use bevy::render::storage::ShaderBuffer;

/// What the drawing buffer holds: the pool's capacity, and the step, births, deaths and length
/// it was written at (the same again: nothing moved, nothing to upload).
type WrittenPool = (usize, Handle<ShaderBuffer>, (u64, u64, u64, usize));

/// Copies the diffuse particles and their counts out of the CPU solver, and into the drawing
/// buffer (made once per capacity), when the pool changed.
pub(super) fn sph_read_whitewater(
    sim: Res<SphSimulation>,
    mut particles: ResMut<SphDiffuseParticles>,
    mut stats: ResMut<SphStats>,
    mut assets: ResMut<Assets<ShaderBuffer>>,
    mut written: Local<Option<WrittenPool>>,
) {
    if sim.backend == SphBackend::Gpu {
        // The GPU backend's are read in `gpu::sph_read_gpu_whitewater`.
        *written = None;
        return;
    }
    let white = sim.cpu.as_ref().and_then(|solver| solver.whitewater());
    let Some(white) = white else {
        if !particles.position.is_empty() || particles.buffer.is_some() {
            *particles = SphDiffuseParticles::default();
        }
        *written = None;
        stats.whitewater = None;
        return;
    };
    let pool = &white.pool;
    let state = (stats.step_count, pool.born, pool.expired, pool.len());
    let capacity = pool.capacity().max(1);
    if written.as_ref().map(|w| (w.0, w.2)) == Some((capacity, state)) {
        return;
    }
    particles.position.clone_from(&pool.position);
    particles.kind.clone_from(&pool.kind);
    particles.slots = pool.len() as u32;
    if written.as_ref().map(|w| w.0) != Some(capacity) {
        let usage = RenderAssetUsages::MAIN_WORLD | RenderAssetUsages::RENDER_WORLD;
        let handle = assets.add(ShaderBuffer::new(&vec![0u8; 16 * capacity], usage));
        *written = Some((capacity, handle, state));
    }
    if let Some((_, handle, at)) = written.as_mut() {
        *at = state;
        let handle = handle.clone();
        if let Some(mut buffer) = assets.get_mut(&handle) {
            if let Some(data) = buffer.data.as_mut() {
                let live = pool.position.iter().zip(&pool.kind);
                for (slot, (x, kind)) in data.chunks_exact_mut(16).zip(live) {
                    for (k, c) in [x.x, x.y, x.z, diffuse_class_w(*kind)].iter().enumerate() {
                        slot[4 * k..4 * k + 4].copy_from_slice(&c.to_le_bytes());
                    }
                }
            }
        }
        particles.buffer = Some(handle);
    }
    let [spray, foam, bubbles] = pool.counts().map(|n| n as u32);
    stats.whitewater = Some(SphWhitewaterCounts {
        spray,
        foam,
        bubbles,
        born: pool.born,
        dropped: pool.dropped,
        expired: pool.expired,
    });
}

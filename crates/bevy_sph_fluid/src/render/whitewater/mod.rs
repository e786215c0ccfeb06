//! Whitewater on the GPU (Ihmsen et al. 2012; CPU twin `sph_core::whitewater`): its stages run
//! once a step, right after the step's first sort, where the grid and the state agree:
//! [`whitewater_normals`] (the surface normals), a counting sort of the live diffuse particles
//! by cell ([`whitewater_bin`], [`whitewater_bin_offsets`], [`whitewater_order`]: the order in
//! which the advection visits them, so that neighbouring threads search the same cells),
//! [`whitewater_advect`] (classify, move and retire the diffuse particles) and
//! [`whitewater_shed`] (the potentials, and the particles they shed). The pool is a fixed set of
//! slots with a free list and atomic counters (`sph_core::gpu_layout::GpuDiffuseCounts`);
//! nothing is compacted, so a slot keeps its particle for life and the drawing skips empty
//! slots. Without whitewater none of this is in the stage list and none of its buffers is
//! allocated (`VariantKey::whitewater`).

pub mod whitewater_advect;
pub mod whitewater_bin;
pub mod whitewater_bin_offsets;
pub mod whitewater_normals;
pub mod whitewater_order;
pub mod whitewater_shed;

use super::buffers::{Buf, GpuBuffers, WhitewaterTargets};
use super::plan::VariantKey;
use super::stage::GpuStage;
use bevy::render::render_resource::{Buffer, CommandEncoder};
use bevy::render::renderer::RenderQueue;
use sph_core::gpu_layout::GpuDiffuseCounts;

/// Whitewater's stages, in order, when the variant has them.
pub fn stage_list(key: &VariantKey) -> Vec<&'static GpuStage> {
    if key.whitewater {
        vec![
            &whitewater_normals::STAGE,
            &whitewater_bin::STAGE,
            &whitewater_bin_offsets::STAGE,
            &whitewater_order::STAGE,
            &whitewater_advect::STAGE,
            &whitewater_shed::STAGE,
        ]
    } else {
        Vec::new()
    }
}

/// Empties the pool: every slot empty (w = -1), every slot on the free list, the counters zero.
pub fn empty_the_pool(buffers: &GpuBuffers, queue: &RenderQueue) {
    let capacity = buffers.diffuse_capacity;
    if capacity == 0 {
        return;
    }
    let empty = vec![[0.0f32, 0.0, 0.0, -1.0]; capacity as usize];
    buffers.write(queue, Buf::DiffuseState, 0, bytemuck::cast_slice(&empty));
    let free = GpuDiffuseCounts::free_list(capacity);
    buffers.write(queue, Buf::DiffuseFree, 0, bytemuck::cast_slice(&free));
    let counts = GpuDiffuseCounts::empty(capacity);
    buffers.write(queue, Buf::DiffuseCounts, 0, bytemuck::bytes_of(&counts));
}

/// Copies the pool's slots, its counters and the live fluid particles' potentials to the main
/// world's buffers.
pub fn publish(
    buffers: &GpuBuffers,
    encoder: &mut CommandEncoder,
    targets: &WhitewaterTargets,
    particle_count: u32,
) {
    if !buffers.key.whitewater || buffers.diffuse_capacity == 0 {
        return;
    }
    let mut copy = |buf: Buf, offset: u64, bytes: u64, target: &Buffer| {
        let bytes = bytes.min(target.size()).min(buffers.size(buf) - offset);
        if bytes > 0 {
            let (arena, at) = buffers.at(buf);
            encoder.copy_buffer_to_buffer(arena, at + offset, target, 0, Some(bytes));
        }
    };
    let slots = 16 * buffers.diffuse_capacity as u64;
    copy(Buf::DiffuseState, 0, slots, &targets.draw);
    let counts = std::mem::size_of::<GpuDiffuseCounts>() as u64;
    copy(Buf::DiffuseCounts, 0, counts, &targets.counts);
    let fluid = 16 * buffers.capacity as u64;
    copy(
        Buf::WhitewaterFluid,
        fluid,
        16 * particle_count as u64,
        &targets.potentials,
    );
}

//! Drawing the CPU backend's particles. The particle material reads the plugin's storage
//! buffers, which only the GPU backend has; on the CPU backend (`--solver dfsph`) the sandbox
//! makes buffers of the same layout and fills them every frame from a snapshot of the solver.

use bevy::asset::RenderAssetUsages;
use bevy::prelude::*;
use bevy::render::storage::ShaderBuffer;
use bevy_sph_fluid::prelude::*;
use sph_core::gpu_layout::id_to_w;

/// Makes the buffers the particle mesh draws from, once per capacity, on the CPU backend.
pub fn make_cpu_draw_buffers(
    stats: Res<SphStats>,
    capacity: Res<SphCapacity>,
    existing: Option<Res<SphGpuBuffers>>,
    mut assets: ResMut<Assets<ShaderBuffer>>,
    mut made_for: Local<Option<u32>>,
    mut commands: Commands,
) {
    if stats.backend != SphBackend::Cpu || (existing.is_some() && *made_for == Some(capacity.0)) {
        return;
    }
    let n = capacity.0.max(1) as usize;
    let usage = RenderAssetUsages::MAIN_WORLD | RenderAssetUsages::RENDER_WORLD;
    let mut make = |bytes: usize| assets.add(ShaderBuffer::new(&vec![0u8; bytes], usage));
    commands.insert_resource(SphGpuBuffers {
        position: make(16 * n),
        velocity: make(16 * n),
        acceleration: make(16 * n),
        density: make(4 * n),
        neighbor_count: make(4 * n),
        clock: make(64),
    });
    *made_for = Some(capacity.0);
}

/// Asks for a snapshot every frame on the CPU backend (a copy of the solver's arrays).
pub fn request_cpu_snapshot(stats: Res<SphStats>, mut requests: MessageWriter<SphReadbackRequest>) {
    if stats.backend == SphBackend::Cpu {
        requests.write(SphReadbackRequest);
    }
}

/// Writes the newest snapshot into the draw buffers (positions with the id in w, velocities,
/// densities), as the GPU passes would have left them.
pub fn upload_cpu_snapshot(
    stats: Res<SphStats>,
    mut snapshots: MessageReader<SphSnapshot>,
    buffers: Option<Res<SphGpuBuffers>>,
    mut assets: ResMut<Assets<ShaderBuffer>>,
) {
    let Some(snapshot) = snapshots.read().last() else {
        return;
    };
    let Some(buffers) = buffers.filter(|_| stats.backend == SphBackend::Cpu) else {
        return;
    };
    let vec4s = |v: &[Vec3], w: &dyn Fn(usize) -> f32| -> Vec<u8> {
        let mut bytes = Vec::with_capacity(16 * v.len());
        for (k, x) in v.iter().enumerate() {
            for c in [x.x, x.y, x.z, w(k)] {
                bytes.extend_from_slice(&c.to_le_bytes());
            }
        }
        bytes
    };
    let ids = &snapshot.ids;
    let parts = [
        (
            &buffers.position,
            vec4s(&snapshot.positions, &|k| {
                id_to_w(ids.get(k).copied().unwrap_or(0))
            }),
        ),
        (&buffers.velocity, vec4s(&snapshot.velocities, &|_| 0.0)),
        (
            &buffers.density,
            snapshot
                .densities
                .iter()
                .flat_map(|d| d.to_le_bytes())
                .collect(),
        ),
    ];
    for (handle, bytes) in parts {
        if let Some(mut buffer) = assets.get_mut(handle) {
            if let Some(data) = buffer.data.as_mut() {
                let k = bytes.len().min(data.len());
                data[..k].copy_from_slice(&bytes[..k]);
            }
        }
    }
}

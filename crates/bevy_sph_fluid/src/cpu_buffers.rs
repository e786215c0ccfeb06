//! The CPU backend's state in buffers of the GPU layout ([`SphGpuBuffers`]), so that whatever
//! draws the particles straight from the GPU buffers draws the CPU backend's too: positions
//! (particle id in w), velocities and densities, written from the solver every frame.

use crate::api::*;
use crate::sets::SphSystems;
use crate::shared::SphSimulation;
use bevy::asset::RenderAssetUsages;
use bevy::ecs::schedule::InternedScheduleLabel;
use bevy::prelude::*;
use bevy::render::storage::ShaderBuffer;
use sph_core::gpu_layout::id_to_w;

pub(crate) fn add_systems(app: &mut App, schedule: InternedScheduleLabel) {
    app.add_systems(
        schedule,
        sph_write_cpu_buffers.in_set(SphSystems::Writeback),
    );
}

/// Makes the buffers once per capacity on the CPU backend, and writes the solver's state into
/// them every frame.
fn sph_write_cpu_buffers(
    sim: Res<SphSimulation>,
    existing: Option<Res<SphGpuBuffers>>,
    mut assets: ResMut<Assets<ShaderBuffer>>,
    mut made_for: Local<Option<(u32, SphGpuBuffers)>>,
    mut commands: Commands,
) {
    if sim.backend != SphBackend::Cpu {
        return;
    }
    let current = made_for
        .as_ref()
        .filter(|(capacity, buffers)| {
            *capacity == sim.capacity && existing.as_deref() == Some(buffers)
        })
        .map(|(_, buffers)| buffers.clone());
    let buffers = match current {
        Some(buffers) => buffers,
        None => {
            let n = sim.capacity.max(1) as usize;
            let usage = RenderAssetUsages::MAIN_WORLD | RenderAssetUsages::RENDER_WORLD;
            let mut make = |bytes: usize| assets.add(ShaderBuffer::new(&vec![0u8; bytes], usage));
            let buffers = SphGpuBuffers {
                position: make(16 * n),
                velocity: make(16 * n),
                acceleration: make(16 * n),
                density: make(4 * n),
                pressure: make(4 * n),
                neighbor_count: make(4 * n),
                clock: make(std::mem::size_of::<sph_core::gpu_layout::GpuClock>()),
                body_forces: make(16),
                probes: make(16),
            };
            commands.insert_resource(buffers.clone());
            *made_for = Some((sim.capacity, buffers.clone()));
            buffers
        }
    };
    let Some(solver) = &sim.cpu else {
        return;
    };
    let p = solver.particles();
    let vec4s = |v: &[Vec3], w: &dyn Fn(usize) -> f32| -> Vec<u8> {
        let mut bytes = Vec::with_capacity(16 * v.len());
        for (k, x) in v.iter().enumerate() {
            for c in [x.x, x.y, x.z, w(k)] {
                bytes.extend_from_slice(&c.to_le_bytes());
            }
        }
        bytes
    };
    let parts = [
        (&buffers.position, vec4s(&p.position, &|k| id_to_w(p.id[k]))),
        (&buffers.velocity, vec4s(&p.velocity, &|_| 0.0)),
        (
            &buffers.density,
            p.density.iter().flat_map(|d| d.to_le_bytes()).collect(),
        ),
        (
            &buffers.pressure,
            p.pressure.iter().flat_map(|d| d.to_le_bytes()).collect(),
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

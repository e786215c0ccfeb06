//! Whitewater in the plugin: the [`SphWhitewater`] resource turns on the diffuse particles of
//! Ihmsen et al. 2012 (`sph_core::whitewater`: spray, foam and bubbles shed where the water
//! breaks), [`SphDiffuseParticles`] holds them after every frame for drawing (the surface draws
//! them from its buffer as billboards), and [`SphStats::whitewater`] counts them. The CPU
//! backend steps them after every stable step ([`cpu`]); the GPU backend runs its whitewater
//! stages (`render::whitewater`) once a step, and only their counters come back ([`gpu`]).

pub mod cpu;
pub mod gpu;
mod resources;

pub use resources::{diffuse_class_w, SphDiffuseParticles, SphWhitewater, EMPTY_SLOT_W};

use crate::api::{SphBackend, SphStats};
use crate::sets::SphSystems;
use crate::shared::SphSimulation;
use bevy::ecs::schedule::InternedScheduleLabel;
use bevy::prelude::*;
use bevy::render::storage::ShaderBuffer;

pub(crate) fn add_systems(app: &mut App, schedule: InternedScheduleLabel) {
    app.init_resource::<SphDiffuseParticles>()
        .init_resource::<gpu::DiffuseCountsReadback>()
        .add_systems(
            schedule,
            (
                sph_apply_whitewater.in_set(SphSystems::Prepare),
                (cpu::sph_read_whitewater, gpu::sph_read_gpu_whitewater)
                    .chain()
                    .in_set(SphSystems::Writeback),
            ),
        );
}

/// Hands [`SphWhitewater`] to the CPU solver when it differs from what the solver runs (a new
/// solver after a container change starts without), or turns it off.
fn sph_apply_whitewater(
    wanted: Option<Res<SphWhitewater>>,
    mut sim: ResMut<SphSimulation>,
    mut stats: ResMut<SphStats>,
    mut assets: ResMut<Assets<ShaderBuffer>>,
    mut refused: Local<Option<SphWhitewater>>,
) {
    let wanted = wanted.map(|w| *w);
    if sim.backend == SphBackend::Gpu {
        gpu::apply(wanted, &mut sim, &mut stats, &mut assets, &mut refused);
        return;
    }
    if sim.frame.whitewater.is_some() {
        sim.frame.whitewater = None;
    }
    let Some(solver) = sim.cpu.as_mut() else {
        return;
    };
    let running = solver.whitewater().map(|w| (w.settings, w.pool.capacity()));
    let request = wanted.map(|w| (w.settings, w.capacity as usize));
    if running == request || (wanted.is_some() && wanted == *refused) {
        return;
    }
    match solver.set_whitewater(request) {
        Ok(()) => {
            *refused = None;
            stats.whitewater_error = None;
        }
        Err(e) => {
            *refused = wanted;
            stats.whitewater_error = Some(e.to_string());
        }
    }
}

//! Whitewater in the plugin: the [`SphWhitewater`] resource turns on the diffuse particles of
//! Ihmsen et al. 2012 (`sph_core::whitewater`: spray, foam and bubbles shed where the water
//! breaks), [`SphDiffuseParticles`] holds them after every frame for drawing (the surface draws
//! them from its buffer as billboards), and
//! [`SphStats::whitewater`] counts them. The CPU backend steps them after every stable step; the
//! GPU backend has no whitewater stages, and [`SphStats::whitewater_error`] says so.

use crate::api::{SphBackend, SphStats, SphWhitewaterCounts};
use crate::sets::SphSystems;
use crate::shared::SphSimulation;
use bevy::asset::RenderAssetUsages;
use bevy::ecs::schedule::InternedScheduleLabel;
use bevy::prelude::*;
use bevy::render::storage::ShaderBuffer;
use sph_core::whitewater::pool::DiffuseKind;
use sph_core::whitewater::settings::WhitewaterSettings;

/// Whitewater on, with these settings and a pool of `capacity` diffuse particles. Insert the
/// resource to turn it on, change it to restart the pool with new settings, remove it to turn it
/// off. A setting out of range is refused by name in [`SphStats::whitewater_error`], and the
/// whitewater running before (or none) stays.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct SphWhitewater {
    /// Potentials' limits, rates, classes and motion.
    pub settings: WhitewaterSettings,
    /// The most diffuse particles at once (1 ..= 2^24); the ones shed beyond are counted in
    /// [`SphWhitewaterCounts::dropped`](crate::api::SphWhitewaterCounts::dropped).
    pub capacity: u32,
}

impl Default for SphWhitewater {
    /// The default settings and room for 65,536 diffuse particles.
    fn default() -> Self {
        Self {
            settings: WhitewaterSettings::default(),
            capacity: 65_536,
        }
    }
}

/// The diffuse particles as of the last frame, for drawing (empty while whitewater is off).
#[derive(Resource, Clone, Debug, Default)]
pub struct SphDiffuseParticles {
    /// Positions [m].
    pub position: Vec<Vec3>,
    /// Each one's class: spray, foam or bubble.
    pub kind: Vec<DiffuseKind>,
    /// The same particles in a buffer of the pool's capacity, what the surface draws: one
    /// `vec4<f32>` a particle, xyz the position and w the class ([`diffuse_class_w`]), slots
    /// `0..position.len()` live. `None` while whitewater is off.
    pub buffer: Option<Handle<ShaderBuffer>>,
}

/// The class of a diffuse particle as the drawing buffer's w: 0 spray, 1 foam, 2 bubble.
pub fn diffuse_class_w(kind: DiffuseKind) -> f32 {
    match kind {
        DiffuseKind::Spray => 0.0,
        DiffuseKind::Foam => 1.0,
        DiffuseKind::Bubble => 2.0,
    }
}

pub(crate) fn add_systems(app: &mut App, schedule: InternedScheduleLabel) {
    app.init_resource::<SphDiffuseParticles>().add_systems(
        schedule,
        (
            sph_apply_whitewater.in_set(SphSystems::Prepare),
            sph_read_whitewater.in_set(SphSystems::Writeback),
        ),
    );
}

/// Hands [`SphWhitewater`] to the CPU solver when it differs from what the solver runs (a new
/// solver after a container change starts without), or turns it off.
fn sph_apply_whitewater(
    wanted: Option<Res<SphWhitewater>>,
    mut sim: ResMut<SphSimulation>,
    mut stats: ResMut<SphStats>,
    mut refused: Local<Option<SphWhitewater>>,
) {
    let wanted = wanted.map(|w| *w);
    if sim.backend == SphBackend::Gpu {
        stats.whitewater_error = wanted.map(|_| {
            "whitewater runs on the CPU backend only: the GPU backend has no whitewater stages"
                .to_string()
        });
        return;
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

/// What the drawing buffer holds: the pool's capacity, and the step, births, deaths and length
/// it was written at (the same again: nothing moved, nothing to upload).
type WrittenPool = (usize, Handle<ShaderBuffer>, (u64, u64, u64, usize));

/// Copies the diffuse particles and their counts out of the CPU solver, and into the drawing
/// buffer (made once per capacity), when the pool changed.
fn sph_read_whitewater(
    sim: Res<SphSimulation>,
    mut particles: ResMut<SphDiffuseParticles>,
    mut stats: ResMut<SphStats>,
    mut assets: ResMut<Assets<ShaderBuffer>>,
    mut written: Local<Option<WrittenPool>>,
) {
    let white = sim.cpu.as_ref().and_then(|solver| solver.whitewater());
    let Some(white) = white.filter(|_| sim.backend == SphBackend::Cpu) else {
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

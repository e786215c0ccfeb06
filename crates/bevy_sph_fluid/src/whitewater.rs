//! Whitewater in the plugin: the [`SphWhitewater`] resource turns on the diffuse particles of
//! Ihmsen et al. 2012 (`sph_core::whitewater`: spray, foam and bubbles shed where the water
//! breaks), [`SphDiffuseParticles`] holds them after every frame for drawing, and
//! [`SphStats::whitewater`] counts them. The CPU backend steps them after every stable step; the
//! GPU backend has no whitewater stages, and [`SphStats::whitewater_error`] says so.

use crate::api::{SphBackend, SphStats, SphWhitewaterCounts};
use crate::sets::SphSystems;
use crate::shared::SphSimulation;
use bevy::ecs::schedule::InternedScheduleLabel;
use bevy::prelude::*;
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

/// Copies the diffuse particles and their counts out of the CPU solver.
fn sph_read_whitewater(
    sim: Res<SphSimulation>,
    mut particles: ResMut<SphDiffuseParticles>,
    mut stats: ResMut<SphStats>,
) {
    let white = sim.cpu.as_ref().and_then(|solver| solver.whitewater());
    let Some(white) = white.filter(|_| sim.backend == SphBackend::Cpu) else {
        if !particles.position.is_empty() {
            *particles = SphDiffuseParticles::default();
        }
        stats.whitewater = None;
        return;
    };
    let pool = &white.pool;
    particles.position.clone_from(&pool.position);
    particles.kind.clone_from(&pool.kind);
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

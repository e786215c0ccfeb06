//! The design's debug mode: grid cells drawn with gizmos and velocity arrows for a sample of
//! particles (from the periodic readback).

use crate::ui::DebugView;
use crate::{AppState, SandboxSet};
use bevy::prelude::*;
use bevy_sph_fluid::prelude::*;

/// The last snapshot, for arrows and statistics.
#[derive(Resource, Default)]
pub struct LastSnapshot(pub Option<SphSnapshot>);

/// Asks for a snapshot twice a second (density error, health, arrows).
pub fn request_readback(
    time: Res<Time>,
    mut timer: Local<f32>,
    mut requests: MessageWriter<SphReadbackRequest>,
) {
    *timer += time.delta_secs();
    if *timer >= 0.5 {
        *timer = 0.0;
        requests.write(SphReadbackRequest);
    }
}

/// Keeps the newest snapshot.
pub fn keep_snapshot(mut snapshots: MessageReader<SphSnapshot>, mut last: ResMut<LastSnapshot>) {
    if let Some(s) = snapshots.read().last() {
        last.0 = Some(s.clone());
    }
}

/// Grid cells on the floor and the back wall, and velocity arrows.
pub fn draw_debug(
    debug: Res<DebugView>,
    containers: Query<&SphContainer>,
    params: Res<SphParams>,
    last: Res<LastSnapshot>,
    mut gizmos: Gizmos,
) {
    if !debug.0 {
        return;
    }
    let Some(container) = containers.iter().next() else {
        return;
    };
    let (lo, hi) = (container.min(), container.max());
    let h = params.smoothing_radius;
    let grey = Color::srgba(1.0, 1.0, 1.0, 0.15);
    let mut x = lo.x;
    while x <= hi.x + 1e-6 {
        gizmos.line(Vec3::new(x, lo.y, lo.z), Vec3::new(x, lo.y, hi.z), grey);
        gizmos.line(Vec3::new(x, lo.y, lo.z), Vec3::new(x, hi.y, lo.z), grey);
        x += h;
    }
    let mut z = lo.z;
    while z <= hi.z + 1e-6 {
        gizmos.line(Vec3::new(lo.x, lo.y, z), Vec3::new(hi.x, lo.y, z), grey);
        z += h;
    }
    let mut y = lo.y;
    while y <= hi.y + 1e-6 {
        gizmos.line(Vec3::new(lo.x, y, lo.z), Vec3::new(hi.x, y, lo.z), grey);
        y += h;
    }
    if let Some(s) = &last.0 {
        let step = (s.positions.len() / 400).max(1);
        for k in (0..s.positions.len()).step_by(step) {
            let p = s.positions[k];
            gizmos.arrow(p, p + s.velocities[k] * 0.05, Color::srgb(1.0, 0.5, 0.1));
        }
    }
}

/// The debug view: a snapshot read back every few frames, drawn as gizmos.
pub struct DebugPlugin;

impl Plugin for DebugPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<LastSnapshot>().add_systems(
            Update,
            (
                (request_readback, keep_snapshot).in_set(SandboxSet::Read),
                draw_debug.in_set(SandboxSet::Draw),
            )
                .run_if(in_state(AppState::Running)),
        );
    }
}

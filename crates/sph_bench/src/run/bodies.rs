//! What a run measures on its colliders and bodies: the water's force on each collider averaged
//! over the last 40 % of the run, the motion of a scene file's dynamic and hinged colliders, and
//! the held box's buoyancy.

use crate::report::{BodyMotion, BodySample, BuoyancyFigures, ColliderForceReport};
use crate::scenarios::Setup;
use crate::sim::Simulation;
use sph_core::glam::Vec3;

/// Averages the water's force on each collider, and on the walls where the simulation measures
/// it, over the window from `start` on.
pub(super) struct ForceWindow {
    start: f64,
    sums: Vec<(sph_core::glam::DVec3, sph_core::glam::DVec3)>,
    /// The walls' force summed like the colliders' (`None`: not measured).
    walls: Option<sph_core::glam::DVec3>,
    evaluations: u64,
    /// The force on each collider as last taken, in or before the window [N].
    pub(super) last: Vec<Vec3>,
}

impl ForceWindow {
    pub(super) fn new(start: f64, colliders: usize) -> Self {
        Self {
            start,
            sums: vec![Default::default(); colliders],
            walls: None,
            evaluations: 0,
            last: vec![Vec3::ZERO; colliders],
        }
    }

    pub(super) fn record(&mut self, sim: &mut dyn Simulation) {
        let in_window = sim.time() >= self.start;
        // Read before the take, which starts the next average.
        let walls = sim.wall_force();
        let Some((forces, n)) = sim.take_collider_forces() else {
            return;
        };
        if n > 0 {
            for (last, f) in self.last.iter_mut().zip(&forces) {
                *last = f.force;
            }
        }
        if !in_window || n == 0 {
            return;
        }
        for (sum, f) in self.sums.iter_mut().zip(&forces) {
            sum.0 += f.force.as_dvec3() * n as f64;
            sum.1 += f.torque.as_dvec3() * n as f64;
        }
        if let Some(w) = walls {
            *self.walls.get_or_insert_default() += w.as_dvec3() * n as f64;
        }
        self.evaluations += n;
    }

    /// The walls' mean force over the window [N] (`None`: not measured, or no evaluation).
    pub(super) fn walls(&self) -> Option<sph_core::glam::DVec3> {
        let walls = self.walls?;
        (self.evaluations > 0).then(|| walls / self.evaluations as f64)
    }

    pub(super) fn report(
        &self,
        colliders: &[crate::scenarios::ScenarioCollider],
    ) -> Vec<ColliderForceReport> {
        if self.evaluations == 0 {
            return Vec::new();
        }
        let n = self.evaluations as f64;
        colliders
            .iter()
            .zip(&self.sums)
            .map(|(c, (f, t))| ColliderForceReport {
                name: c.name.clone(),
                force: (*f / n).as_vec3().to_array(),
                torque: (*t / n).as_vec3().to_array(),
                evaluations: self.evaluations,
            })
            .collect()
    }
}

/// How often a scene file's dynamic and hinged colliders are sampled [s of simulated time].
pub const BODY_SAMPLE_INTERVAL: f64 = 0.05;
/// A body slower than this [m/s] over the last quarter of a run has settled.
pub const SETTLED_SPEED: f32 = 0.02;
/// A body turning slower than this [rad/s] over the last quarter of a run has settled.
pub const SETTLED_TURN_RATE: f32 = 0.05;

/// The poses of a scene file's dynamic and hinged colliders every `interval` of simulated time
/// ([`BODY_SAMPLE_INTERVAL`] unless the run asks for another).
pub(super) struct BodyTrack {
    /// The tracked colliders' indices in `Setup::colliders`.
    pub(super) bodies: Vec<usize>,
    series: Vec<Vec<BodySample>>,
    pub(super) next: f64,
    interval: f64,
}

impl BodyTrack {
    pub(super) fn new(setup: &Setup, interval: f64) -> Self {
        let bodies: Vec<usize> = setup.extras.as_ref().map_or(Vec::new(), |extras| {
            extras
                .colliders
                .iter()
                .enumerate()
                .filter(|(_, written)| written.body.is_some() || written.hinge.is_some())
                .map(|(k, _)| k)
                .collect()
        });
        Self {
            series: vec![Vec::new(); bodies.len()],
            bodies,
            next: 0.0,
            interval,
        }
    }

    /// Samples the bodies when the next sample is due, or at the end of the run (`last`) when
    /// the latest sample is older.
    pub(super) fn record(
        &mut self,
        setup: &Setup,
        sim: &dyn Simulation,
        forces: &[Vec3],
        last: bool,
    ) {
        let t = sim.time();
        let newest = self.series.first().and_then(|s| s.last()).map(|s| s.t);
        let due = t + 1e-9 >= self.next || (last && newest.is_some_and(|n| n < t));
        if self.bodies.is_empty() || !due {
            return;
        }
        self.next = t + self.interval;
        let now = sim.colliders_now(&setup.colliders);
        for (series, &k) in self.series.iter_mut().zip(&self.bodies) {
            let pose = now[k].pose;
            let (velocity, turn_rate) = match series.last() {
                Some(last) if t > last.t => {
                    let dt = (t - last.t) as f32;
                    let before = sph_core::glam::Quat::from_array(last.rotation);
                    (
                        (pose.translation - Vec3::from(last.position)) / dt,
                        before.angle_between(pose.rotation) / dt,
                    )
                }
                _ => (Vec3::ZERO, 0.0),
            };
            series.push(BodySample {
                t,
                position: pose.translation.to_array(),
                rotation: pose.rotation.to_array(),
                velocity: velocity.to_array(),
                turn_rate,
                force: forces.get(k).copied().unwrap_or_default().to_array(),
            });
        }
    }
}

/// Where each of a scene file's dynamic and hinged colliders started and where it is now, with
/// its samples and whether it settled.
pub(super) fn body_motion(
    setup: &Setup,
    now: &[sph_core::Collider],
    track: BodyTrack,
) -> Vec<BodyMotion> {
    track
        .bodies
        .iter()
        .zip(track.series)
        .map(|(&k, series)| {
            let c = &setup.colliders[k];
            let start = c.at(0.0).pose;
            let end = series.last().map_or(0.0, |s| s.t);
            let last_quarter: Vec<&BodySample> =
                series.iter().filter(|s| s.t >= 0.75 * end).collect();
            let settled = last_quarter.len() >= 2
                && last_quarter.iter().all(|s| {
                    Vec3::from(s.velocity).length() < SETTLED_SPEED
                        && s.turn_rate < SETTLED_TURN_RATE
                });
            BodyMotion {
                name: c.name.clone(),
                start: start.translation.to_array(),
                end: now[k].pose.translation.to_array(),
                turned_rad: start.rotation.angle_between(now[k].pose.rotation),
                settled,
                series,
            }
        })
        .collect()
}

/// The held box's upward force against ρ0 |g| V.
pub(super) fn buoyancy(setup: &Setup, forces: &[ColliderForceReport]) -> Option<BuoyancyFigures> {
    let c = setup.colliders.first()?;
    let f = forces.first()?;
    let sph_core::boundary::collider::ColliderShape::Cuboid { half_extents } = c.collider.shape
    else {
        return None;
    };
    let p = &setup.scene.params;
    let volume = 8.0 * (half_extents.x * half_extents.y * half_extents.z) as f64;
    let expected = p.rest_density as f64 * p.gravity.length() as f64 * volume;
    let measured = f.force[1] as f64;
    Some(BuoyancyFigures {
        expected_n: expected,
        measured_n: measured,
        error_pct: (measured - expected) / expected * 100.0,
    })
}

//! Ihmsen, Akinci, Akinci & Teschner 2012, "Unified spray, foam and bubbles for particle-based
//! fluids" (The Visual Computer 28), on the CPU: the potentials of the water (§4.1), the
//! particles they shed (§4.2), their classes (§4.3) and how each class moves (§5).
//!
//! With W̃_ij = 1 - |x_ij|/h within h (eq. 2; unnormalised, so the potentials count neighbours),
//! v_ij = v_i - v_j and x̂_ij = x_ij / |x_ij|:
//! - trapped air: Σ_j |v_ij| (1 - v̂_ij·x̂_ij) W̃_ij, large where water runs into water (eq. 3);
//! - wave crest: κ̃_i = Σ_j (1 - n̂_i·n̂_j) W̃_ij over the surface neighbours behind the surface
//!   (x̂_ji·n̂_i < 0), counted only while the water moves out along its normal (v̂_i·n̂_i ≥ 0.6;
//!   eqs. 4-6), n̂ the surface normal (none in the bulk, so a flat top reads no crest);
//! - kinetic energy: |v_i|²/2 per unit mass.
//!
//! Each is clamped to [0, 1] by its limits (Φ, eq. 1); a particle sheds
//! n_d = I_k (k_ta I_ta + k_wc I_wc) dt diffuse particles in a step (eq. 7), placed at random in
//! the cylinder its velocity sweeps over the step, of radius Δx/2, with the particle's velocity
//! plus their offset from its axis (eqs. 8-9).

use super::pool::{DiffuseKind, DiffusePool};
use super::settings::WhitewaterSettings;
use crate::container::BoxContainer;
use crate::neighbor::Neighbors;
use crate::params::{NeighborSearch, ParamError};
use crate::rng::SplitMix64;
use glam::Vec3;

/// W̃(r) = 1 - r/h within h, else 0 (eq. 2).
#[inline]
pub fn scaled_weight(r: f32, h: f32) -> f32 {
    if r < h {
        1.0 - r / h
    } else {
        0.0
    }
}

/// Below this share of h, a particle's normal sum is the bulk's (no surface).
const SURFACE_THRESHOLD: f32 = 0.2;

/// The water's three potentials at one particle, unclamped.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Potentials {
    /// Σ_j |v_ij| (1 - v̂_ij·x̂_ij) W̃_ij [m/s].
    pub trapped_air: f32,
    /// κ̃_i when the particle moves out along its normal, else 0.
    pub wave_crest: f32,
    /// |v_i|²/2 [J/kg].
    pub kinetic_energy: f32,
}

/// The water as the potentials see it: a sorted copy of its positions and velocities, with the
/// surface normals.
#[derive(Clone, Debug)]
pub struct FluidView {
    positions: Vec<Vec3>,
    velocities: Vec<Vec3>,
    normals: Vec<Vec3>,
    neighbors: Neighbors,
    h: f32,
}

impl FluidView {
    /// The view of the water at `positions` moving at `velocities`, in `container`, with the
    /// support radius `h`. Fails like [`Neighbors::new`] for a grid too large.
    pub fn new(
        positions: &[Vec3],
        velocities: &[Vec3],
        container: &BoxContainer,
        h: f32,
    ) -> Result<Self, ParamError> {
        let n = positions.len().min(velocities.len());
        let mut neighbors = Neighbors::new(NeighborSearch::Grid, container, h, n)?;
        let order = neighbors.sort(&positions[..n]).to_vec();
        let positions: Vec<Vec3> = order.iter().map(|&k| positions[k as usize]).collect();
        let velocities: Vec<Vec3> = order.iter().map(|&k| velocities[k as usize]).collect();
        let mut view = Self {
            normals: vec![Vec3::ZERO; n],
            positions,
            velocities,
            neighbors,
            h,
        };
        view.normals = (0..n).map(|i| view.normal(i)).collect();
        Ok(view)
    }

    /// Particles in the view.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// The water's positions, in the view's (sorted) order.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Whether the view holds no water.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// n̂_i: the unit vector away from the neighbours' weighted centre, Σ_j x_ij W̃_ij, or zero
    /// in the bulk (the sum shorter than [`SURFACE_THRESHOLD`] h).
    fn normal(&self, i: usize) -> Vec3 {
        let x_i = self.positions[i];
        let mut sum = Vec3::ZERO;
        self.neighbors
            .for_each_neighbor(&self.positions, x_i, |_, r, r2| {
                sum += r * scaled_weight(r2.sqrt(), self.h);
            });
        if sum.length() < SURFACE_THRESHOLD * self.h {
            Vec3::ZERO
        } else {
            sum.normalize()
        }
    }

    /// The potentials of particle `i` of the view (Ihmsen et al. 2012, eqs. 3-6).
    pub fn potentials(&self, i: usize) -> Potentials {
        let (x_i, v_i, n_i) = (self.positions[i], self.velocities[i], self.normals[i]);
        let mut trapped_air = 0.0;
        let mut curvature = 0.0;
        self.neighbors
            .for_each_neighbor(&self.positions, x_i, |j, x_ij, r2| {
                if j == i || r2 <= 0.0 {
                    return;
                }
                let r = r2.sqrt();
                let w = scaled_weight(r, self.h);
                let x_hat = x_ij / r;
                let v_ij = v_i - self.velocities[j];
                let speed = v_ij.length();
                if speed > 0.0 {
                    trapped_air += speed * (1.0 - (v_ij / speed).dot(x_hat)) * w;
                }
                // x̂_ji·n̂_i < 0: j lies behind i's surface; only surface neighbours bend it
                // (the bulk has no normal).
                let n_j = self.normals[j];
                if n_i != Vec3::ZERO && n_j != Vec3::ZERO && (-x_hat).dot(n_i) < 0.0 {
                    curvature += (1.0 - n_i.dot(n_j)) * w;
                }
            });
        let moving_out = v_i.length() > 0.0 && v_i.normalize().dot(n_i) >= 0.6;
        Potentials {
            trapped_air,
            wave_crest: if moving_out { curvature } else { 0.0 },
            kinetic_energy: 0.5 * v_i.length_squared(),
        }
    }

    /// The fluid neighbours within h of `x` and their W̃-weighted mean velocity ṽ (zero without
    /// neighbours).
    pub fn around(&self, x: Vec3) -> (u32, Vec3) {
        let (mut count, mut weight, mut sum) = (0u32, 0.0f32, Vec3::ZERO);
        self.neighbors
            .for_each_neighbor(&self.positions, x, |j, _, r2| {
                let w = scaled_weight(r2.sqrt(), self.h);
                count += 1;
                weight += w;
                sum += self.velocities[j] * w;
            });
        let mean = if weight > 0.0 {
            sum / weight
        } else {
            Vec3::ZERO
        };
        (count, mean)
    }
}

/// The expected number of diffuse particles a fluid particle with `potentials` sheds in a step
/// of `dt`: I_k (k_ta I_ta + k_wc I_wc) dt (eq. 7).
pub fn shed_count(settings: &WhitewaterSettings, potentials: &Potentials, dt: f32) -> f32 {
    let s = settings;
    let kinetic = s.kinetic_energy.clamp(potentials.kinetic_energy);
    let trapped = s.trapped_air.clamp(potentials.trapped_air);
    let crest = s.wave_crest.clamp(potentials.wave_crest);
    kinetic * (s.trapped_air_rate * trapped + s.wave_crest_rate * crest) * dt
}

/// The class of a diffuse particle with `fluid_neighbors` fluid particles within h (§4.3).
pub fn classify(settings: &WhitewaterSettings, fluid_neighbors: u32) -> DiffuseKind {
    if fluid_neighbors < settings.spray_below {
        DiffuseKind::Spray
    } else if fluid_neighbors > settings.bubble_above {
        DiffuseKind::Bubble
    } else {
        DiffuseKind::Foam
    }
}

/// What one whitewater step did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WhitewaterStep {
    /// Diffuse particles born.
    pub born: u64,
    /// Diffuse particles refused by a full pool.
    pub dropped: u64,
    /// Diffuse particles that died (foam at the end of its lifetime, any outside the container).
    pub expired: u64,
}

/// The diffuse particles of a scene and the generator that sheds them.
#[derive(Clone, Debug)]
pub struct Whitewater {
    /// The settings.
    pub settings: WhitewaterSettings,
    /// The diffuse particles.
    pub pool: DiffusePool,
    container: BoxContainer,
    rng: SplitMix64,
}

impl Whitewater {
    /// No diffuse particles yet, at most `capacity` of them in `container`; `seed` makes the
    /// random placement repeatable.
    pub fn new(
        settings: WhitewaterSettings,
        container: BoxContainer,
        capacity: usize,
        seed: u64,
    ) -> Self {
        Self {
            settings,
            pool: DiffusePool::new(capacity),
            container,
            rng: SplitMix64::new(seed),
        }
    }

    /// One step of `dt` under `gravity` over the water of `fluid` (spacing `spacing`): the
    /// diffuse particles are classified and moved (§5), the dead ones removed, then the water
    /// sheds new ones (§4.2).
    pub fn step(
        &mut self,
        fluid: &FluidView,
        gravity: Vec3,
        spacing: f32,
        dt: f32,
    ) -> WhitewaterStep {
        let before = (self.pool.born, self.pool.dropped, self.pool.expired);
        self.advect(fluid, gravity, dt);
        let container = self.container;
        let pool = &self.pool;
        let dead: Vec<bool> = (0..pool.len())
            .map(|i| {
                let foam_gone = pool.kind[i] == DiffuseKind::Foam && pool.lifetime[i] <= 0.0;
                foam_gone || !container.contains(pool.position[i], 0.0)
            })
            .collect();
        self.pool.remove_where(|i| dead[i]);
        for i in 0..fluid.len() {
            // Φ_k = 0 multiplies the other potentials: a slow particle sheds nothing, and its
            // neighbour loop is skipped (its draw is still taken, so that the particles after
            // it see the same random numbers either way).
            let kinetic = 0.5 * fluid.velocities[i].length_squared();
            if self.settings.kinetic_energy.clamp(kinetic) <= 0.0 {
                self.rng.next_f32();
                continue;
            }
            let expected = shed_count(&self.settings, &fluid.potentials(i), dt);
            let whole = expected.floor();
            let count = whole as u32 + u32::from(self.rng.next_f32() < expected - whole);
            for _ in 0..count {
                self.shed(fluid.positions[i], fluid.velocities[i], spacing, dt);
            }
        }
        WhitewaterStep {
            born: self.pool.born - before.0,
            dropped: self.pool.dropped - before.1,
            expired: self.pool.expired - before.2,
        }
    }

    /// Classifies and moves every diffuse particle: spray falls, foam rides the water and ages,
    /// bubbles rise and are dragged towards the water's velocity (§5).
    fn advect(&mut self, fluid: &FluidView, gravity: Vec3, dt: f32) {
        let s = self.settings;
        for i in 0..self.pool.len() {
            let x = self.pool.position[i];
            let (count, water) = fluid.around(x);
            let kind = classify(&s, count);
            let v = &mut self.pool.velocity[i];
            match kind {
                DiffuseKind::Spray => *v += gravity * dt,
                DiffuseKind::Foam => {
                    *v = water;
                    self.pool.lifetime[i] -= dt;
                }
                DiffuseKind::Bubble => *v += -s.buoyancy * gravity * dt + s.drag * (water - *v),
            }
            self.pool.kind[i] = kind;
            self.pool.position[i] = x + *v * dt;
        }
    }

    /// One diffuse particle from the water at `x` moving at `v`: at random in the cylinder of
    /// radius Δx/2 along v over the step, with v plus its offset from the axis (eqs. 8-9).
    fn shed(&mut self, x: Vec3, v: Vec3, spacing: f32, dt: f32) {
        let axis = v.normalize_or_zero();
        let (e1, e2) = if axis == Vec3::ZERO {
            (Vec3::X, Vec3::Z)
        } else {
            axis.any_orthonormal_pair()
        };
        let rng = &mut self.rng;
        let radius = 0.5 * spacing * rng.next_f32().sqrt();
        let angle = std::f32::consts::TAU * rng.next_f32();
        let along = rng.next_f32() * (v * dt).length();
        let offset = radius * (angle.cos() * e1 + angle.sin() * e2);
        let (low, high) = self.settings.lifetime;
        let lifetime = low + (high - low) * rng.next_f32();
        self.pool
            .spawn(x + offset + along * axis, v + offset, lifetime);
    }
}

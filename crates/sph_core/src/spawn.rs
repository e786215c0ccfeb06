//! Spawners: a block of particles on a lattice, and the design's water jet from a pipe.

use crate::limits;
use crate::params::{check_range, ParamError};
use crate::rng::SplitMix64;
use glam::Vec3;

/// A cuboid filled with particles on a cubic lattice (first particle half a spacing inside `min`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlockSpawn {
    /// Lower corner [m].
    pub min: Vec3,
    /// Upper corner [m].
    pub max: Vec3,
    /// Lattice spacing [m].
    pub spacing: f32,
    /// Random displacement of each particle, as a fraction of the spacing, in [0, 0.5].
    pub jitter: f32,
    /// Seed of the jitter.
    pub seed: u64,
}

impl BlockSpawn {
    /// A block without jitter.
    pub fn new(min: Vec3, max: Vec3, spacing: f32) -> Self {
        Self {
            min,
            max,
            spacing,
            jitter: 0.0,
            seed: 0,
        }
    }

    /// Particles along each axis (saturating: an infinite extent gives `usize::MAX`).
    pub fn lattice_dims(&self) -> [usize; 3] {
        let e = self.max - self.min;
        [e.x, e.y, e.z].map(|x| limits::steps_along(x, self.spacing) as usize)
    }

    /// Number of particles the block holds, or `None` when it overflows.
    pub fn checked_count(&self) -> Option<u64> {
        limits::lattice_count(self.lattice_dims().map(|n| n as u64))
    }

    /// Number of particles the block holds (saturating at `usize::MAX`; a validated block holds
    /// at most [`limits::MAX_SPAWN_PARTICLES`]).
    pub fn count(&self) -> usize {
        self.checked_count()
            .and_then(|n| usize::try_from(n).ok())
            .unwrap_or(usize::MAX)
    }

    /// Checks spacing (> 0, finite), jitter ([0, 0.5]), corners (finite, min <= max) and the
    /// particle count (at most [`limits::MAX_SPAWN_PARTICLES`]).
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range(
            "block.spacing",
            self.spacing,
            0.0,
            false,
            1.0e3,
            "(0, 1e3] m",
        )?;
        check_range(
            "block.jitter",
            self.jitter,
            0.0,
            true,
            0.5,
            "[0, 0.5] spacings",
        )?;
        if !(self.min.is_finite() && self.max.is_finite() && self.min.cmple(self.max).all()) {
            return Err(ParamError {
                field: "block.max",
                value: format!("{} (min {})", self.max, self.min),
                allowed: "finite corners with min <= max on every axis",
            });
        }
        limits::check_count(
            "block.max",
            self.checked_count(),
            limits::MAX_SPAWN_PARTICLES,
            "at most 4194304 particles (2^22) in a block",
        )?;
        Ok(())
    }

    /// The particle positions, x fastest, one at a time: a caller with room for fewer takes
    /// what fits without building the rest.
    pub fn lattice(&self) -> impl Iterator<Item = Vec3> + '_ {
        let [nx, ny, nz] = self.lattice_dims();
        let mut rng = SplitMix64::new(self.seed);
        let amplitude = self.jitter * self.spacing;
        (0..nz)
            .flat_map(move |k| (0..ny).flat_map(move |j| (0..nx).map(move |i| (i, j, k))))
            .map(move |(i, j, k)| {
                let lattice = Vec3::new(i as f32 + 0.5, j as f32 + 0.5, k as f32 + 0.5);
                let mut p = self.min + lattice * self.spacing;
                if amplitude > 0.0 {
                    p += Vec3::new(
                        rng.range(-amplitude, amplitude),
                        rng.range(-amplitude, amplitude),
                        rng.range(-amplitude, amplitude),
                    );
                }
                p
            })
    }

    /// The particle positions, x fastest. Validate first: an unvalidated block may hold more
    /// than memory does.
    pub fn positions(&self) -> Vec<Vec3> {
        self.lattice().collect()
    }
}

/// The design's water jet: a pipe mouth that emits whole discs of particles (a square lattice
/// inside the pipe radius) so that the jet is continuous at any frame rate.
#[derive(Clone, Debug, PartialEq)]
pub struct PipeEmitter {
    /// Centre of the pipe mouth [m].
    pub position: Vec3,
    /// Jet direction (normalised on use).
    pub direction: Vec3,
    /// Pipe radius [m].
    pub radius: f32,
    /// Exit speed [m/s].
    pub speed: f32,
    /// Emission rate [particles/s]; [`PipeEmitter::matched_rate`] gives the rate whose discs lie
    /// exactly one spacing apart.
    pub rate: f32,
    /// Lattice spacing inside a disc [m].
    pub spacing: f32,
    /// Stop after this many particles (the last disc is partial); `None` emits forever.
    pub total: Option<u64>,
    /// Particles emitted so far (including any the solver refused).
    pub emitted: u64,
    budget: f32,
}

/// One emission: positions and the common exit velocity.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Emission {
    /// New particle positions.
    pub positions: Vec<Vec3>,
    /// Velocity of every new particle.
    pub velocity: Vec3,
}

impl PipeEmitter {
    /// An emitter at `position` pointing along `direction` with the continuous-jet rate.
    pub fn new(position: Vec3, direction: Vec3, radius: f32, speed: f32, spacing: f32) -> Self {
        let mut emitter = Self {
            position,
            direction,
            radius,
            speed,
            rate: 0.0,
            spacing,
            total: None,
            emitted: 0,
            budget: 0.0,
        };
        emitter.rate = emitter.matched_rate();
        emitter
    }

    /// Checks radius, speed, rate, spacing and direction, and that the disc holds at most
    /// [`limits::MAX_DISC_RADIUS_SPACINGS`] spacings of radius.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range(
            "emitter.radius",
            self.radius,
            0.0,
            false,
            1.0e3,
            "(0, 1e3] m",
        )?;
        check_range(
            "emitter.spacing",
            self.spacing,
            0.0,
            false,
            1.0e3,
            "(0, 1e3] m",
        )?;
        if !self.disc_fits() {
            return Err(ParamError {
                field: "emitter.radius",
                value: format!(
                    "{} m ({} spacings of {} m)",
                    self.radius,
                    self.radius / self.spacing,
                    self.spacing
                ),
                allowed: "at most 256 spacings",
            });
        }
        check_range(
            "emitter.speed",
            self.speed,
            0.0,
            true,
            1.0e3,
            "[0, 1e3] m/s",
        )?;
        check_range(
            "emitter.rate",
            self.rate,
            0.0,
            true,
            1.0e9,
            "[0, 1e9] particles/s",
        )?;
        if !(self.direction.is_finite() && self.direction.length() > 1e-6) {
            return Err(ParamError {
                field: "emitter.direction",
                value: format!("{}", self.direction),
                allowed: "a finite non-zero vector",
            });
        }
        if !self.position.is_finite() {
            return Err(ParamError {
                field: "emitter.position",
                value: format!("{}", self.position),
                allowed: "finite",
            });
        }
        Ok(())
    }

    /// Whether the radius is at most [`limits::MAX_DISC_RADIUS_SPACINGS`] spacings (false for a
    /// negative, infinite or NaN ratio).
    fn disc_fits(&self) -> bool {
        let ratio = self.radius / self.spacing;
        (0.0..=limits::MAX_DISC_RADIUS_SPACINGS).contains(&ratio)
    }

    /// Disc offsets in the pipe's cross-section: a square lattice of the spacing inside the
    /// radius; empty when the radius is not a valid number of spacings, so that an emitter
    /// built from bad input allocates nothing before it is validated.
    pub fn disc(&self) -> Vec<Vec3> {
        if !self.disc_fits() {
            return Vec::new();
        }
        let axis = self.direction.normalize_or(Vec3::Y);
        let (u, w) = axis.any_orthonormal_pair();
        let n = (self.radius / self.spacing).floor() as i32;
        let mut out = Vec::new();
        for b in -n..=n {
            for a in -n..=n {
                let offset = u * (a as f32 * self.spacing) + w * (b as f32 * self.spacing);
                if offset.length() <= self.radius {
                    out.push(offset);
                }
            }
        }
        out
    }

    /// The rate whose discs are one spacing apart along the jet: disc size × speed / spacing.
    pub fn matched_rate(&self) -> f32 {
        self.disc().len() as f32 * self.speed / self.spacing
    }

    /// Whether the emitter has emitted its `total`.
    pub fn finished(&self) -> bool {
        self.total.is_some_and(|t| self.emitted >= t)
    }

    /// Advances the emitter by `dt` and returns the discs that became due. Each disc is placed
    /// downstream by `speed × (time since it was due)`, so successive discs form a continuous jet.
    pub fn emit(&mut self, dt: f32) -> Emission {
        let axis = self.direction.normalize_or(Vec3::Y);
        let velocity = axis * self.speed;
        let mut positions = Vec::new();
        if self.rate <= 0.0 || self.finished() {
            return Emission {
                positions,
                velocity,
            };
        }
        let disc = self.disc();
        if disc.is_empty() {
            return Emission {
                positions,
                velocity,
            };
        }
        self.budget += self.rate * dt;
        while !self.finished() {
            let remaining = self.total.map_or(u64::MAX, |t| t - self.emitted);
            let take = (disc.len() as u64).min(remaining) as usize;
            if self.budget < take as f32 {
                break;
            }
            self.budget -= take as f32;
            // Time since this disc was due: the budget left over, converted back to seconds.
            let age = self.budget / self.rate;
            let centre = self.position + velocity * age;
            positions.extend(disc[..take].iter().map(|&o| centre + o));
            self.emitted += take as u64;
        }
        Emission {
            positions,
            velocity,
        }
    }
}

//! A jet against a wall one spacing thick: a pipe ([`JET_RADIUS`], [`JET_SPEED`]) shoots water
//! at a wall [`WALL_THICKNESS`] = Δx thick that splits the container, until [`JET_TOTAL`]
//! particles have left it. Water must not pass the wall: the check counts the particles beyond
//! its far face while the run goes (the guard's corrections are in the report beside it).

use serde::Serialize;
use sph_core::glam::Vec3;

/// The lattice spacing Δx [m].
pub const SPACING: f32 = 0.01;
/// The container's size [m].
pub const SIZE: Vec3 = Vec3::new(0.5, 0.4, 0.1);
/// The wall's near face [m] (x).
pub const WALL_X: f32 = 0.3;
/// The wall's thickness: one spacing [m].
pub const WALL_THICKNESS: f32 = SPACING;
/// Where the pipe's mouth is [m].
pub const JET_AT: Vec3 = Vec3::new(0.05, 0.15, 0.05);
/// The pipe's radius [m].
pub const JET_RADIUS: f32 = 0.03;
/// The jet's speed [m/s].
pub const JET_SPEED: f32 = 3.0;
/// Particles the pipe emits (about 0.95 s of jet).
pub const JET_TOTAL: u64 = 8_000;
/// Simulated time of a run [s].
pub const DURATION: f64 = 1.2;

/// Particles beyond the wall's far face.
pub fn behind_wall(positions: &[Vec3]) -> usize {
    positions
        .iter()
        .filter(|x| x.x > WALL_X + WALL_THICKNESS)
        .count()
}

/// The particles behind the wall over time.
#[derive(Clone, Debug, Default)]
pub struct ThinWallSampler {
    most: usize,
    last: usize,
}

impl ThinWallSampler {
    /// Counts the particles behind the wall.
    pub fn record(&mut self, positions: &[Vec3]) {
        self.last = behind_wall(positions);
        self.most = self.most.max(self.last);
    }

    /// The figures of the run.
    pub fn finish(self) -> ThinWallFigures {
        ThinWallFigures {
            wall_thickness_m: WALL_THICKNESS,
            jet_speed_m_s: JET_SPEED,
            behind_wall_most: self.most,
            behind_wall_end: self.last,
        }
    }
}

/// What the thin wall let through.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ThinWallFigures {
    /// The wall's thickness [m].
    pub wall_thickness_m: f32,
    /// The jet's speed [m/s].
    pub jet_speed_m_s: f32,
    /// The most particles beyond the wall's far face in any sample.
    pub behind_wall_most: usize,
    /// Particles beyond the wall's far face at the end.
    pub behind_wall_end: usize,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_water_past_the_far_face_counts() {
        let far = WALL_X + WALL_THICKNESS;
        let positions = [
            Vec3::new(0.1, 0.1, 0.05),
            Vec3::new(WALL_X + 0.5 * WALL_THICKNESS, 0.1, 0.05),
            Vec3::new(far + 0.001, 0.1, 0.05),
            Vec3::new(0.45, 0.02, 0.05),
        ];
        let mut sampler = ThinWallSampler::default();
        sampler.record(&positions);
        sampler.record(&positions[..2]);
        let figures = sampler.finish();
        assert_eq!((figures.behind_wall_most, figures.behind_wall_end), (2, 0));
    }
}

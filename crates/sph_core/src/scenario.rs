//! Ready-made scenes shared by the tests, the benchmark and the examples.

use crate::container::BoxContainer;
use crate::params::{SpacingDerivation, SphParams};
use crate::spawn::BlockSpawn;
use glam::Vec3;

/// A scene: parameters, container and the blocks to spawn at rest.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Parameters.
    pub params: SphParams,
    /// Container.
    pub container: BoxContainer,
    /// Blocks of particles spawned at rest.
    pub blocks: Vec<BlockSpawn>,
}

impl Scene {
    /// Particles the blocks hold.
    pub fn particle_count(&self) -> usize {
        self.blocks.iter().map(BlockSpawn::count).sum()
    }

    /// All block positions.
    pub fn positions(&self) -> Vec<Vec3> {
        self.blocks.iter().flat_map(BlockSpawn::positions).collect()
    }
}

/// A Martin & Moyce (1952) dam break: a column of width `a` and height 2a against the wall x = 0
/// of a tank 5a long and 3a high, `depth` deep along z, filled on a lattice of `spacing` (SI water).
pub fn dam_break(a: f32, depth: f32, spacing: f32) -> Scene {
    let g = 9.81;
    let params = SphParams::from_spacing(SpacingDerivation {
        spacing,
        expected_peak_speed: (2.0 * g * 2.0 * a).sqrt(),
        ..Default::default()
    });
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(5.0 * a, 3.0 * a, depth));
    let column = BlockSpawn::new(Vec3::ZERO, Vec3::new(a, 2.0 * a, depth), spacing);
    Scene {
        params,
        container,
        blocks: vec![column],
    }
}

/// A dam break of about `particles` particles (column a × 2a × a/2, spacing chosen to match).
pub fn dam_break_with_particles(particles: usize) -> Scene {
    let a = 0.146;
    // a/s × 2a/s × (a/2)/s = a³/s³ particles.
    let spacing = a / (particles.max(1) as f32).cbrt();
    let depth = 0.5 * a;
    // Keep whole lattice rows: the column spans integer multiples of the spacing.
    let a = (a / spacing).round().max(1.0) * spacing;
    let depth = (depth / spacing).round().max(1.0) * spacing;
    dam_break(a, depth, spacing)
}

/// A tank at rest: water of height `depth` in a box `width` × 1.5 depth × `width`.
pub fn hydrostatic(width: f32, depth: f32, spacing: f32) -> Scene {
    let params = SphParams::from_spacing(SpacingDerivation {
        spacing,
        expected_peak_speed: (2.0 * 9.81 * depth).sqrt(),
        ..Default::default()
    });
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(width, 1.5 * depth, width));
    let block = BlockSpawn::new(Vec3::ZERO, Vec3::new(width, depth, width), spacing);
    Scene {
        params,
        container,
        blocks: vec![block],
    }
}

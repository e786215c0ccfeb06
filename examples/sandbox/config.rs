//! The start screen's choices and how they become simulation parameters.

use bevy::prelude::*;
use sph_core::{Integrator, NeighborSearch, Solver, SpacingDerivation, SphParams};

/// How particles enter the box.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SpawnMode {
    /// A block of water against the left wall.
    #[default]
    Block,
    /// The pipe's jet fills the box.
    Pipe,
    /// Half the budget in the block, half through the pipe.
    Both,
}

/// Which parameter table.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Preset {
    /// SI water (ρ0 1000 kg/m³, Tait with c0 = 10 v_peak).
    #[default]
    Water,
    /// The design's table (μ 0.02, k 1, ρ0 1, γ 1, damping 0.5, dt 0.005 s, leapfrog).
    Design,
}

/// Smallest and largest particle budget.
pub const BUDGET_RANGE: std::ops::RangeInclusive<u32> = 1_024..=262_144;

/// The start screen's choices.
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct SandboxConfig {
    /// Particle budget (the plugin's capacity).
    pub budget: u32,
    /// Block, pipe or both.
    pub spawn: SpawnMode,
    /// Parameter table.
    pub preset: Preset,
    /// Pressure solver (DFSPH brings its own time-step rule).
    pub solver: Solver,
    /// Integrator (WCSPH).
    pub integrator: Integrator,
    /// Time step [s] (the largest step with the adaptive rule).
    pub time_step: f32,
    /// Choose dt every step by the CFL rule.
    pub adaptive_time_step: bool,
    /// Neighbour search.
    pub search: NeighborSearch,
    /// Surface tension on.
    pub surface_tension: bool,
    /// A ball in the water's path.
    pub sphere_obstacle: bool,
    /// A box turned 30° in the water's path.
    pub box_obstacle: bool,
    /// A gate holding the block back, lifted from the runtime panel.
    pub gate: bool,
    /// Real-time mode: each frame advances the water by the frame's own time.
    pub real_time: bool,
    /// A scene file under `assets/` to run instead of the panel's scene.
    pub scene: Option<String>,
}

impl Default for SandboxConfig {
    fn default() -> Self {
        let mut config = Self {
            budget: 32_768,
            spawn: SpawnMode::Block,
            preset: Preset::Water,
            // PBF at two steps per frame: on lavapipe at 32k particles its water moves 4.6 times
            // faster than WCSPH's at half the frame rate (docs/real_time.md).
            solver: Solver::Pbf,
            integrator: Integrator::KickDriftKick,
            time_step: 0.0,
            adaptive_time_step: false,
            search: NeighborSearch::Grid,
            surface_tension: false,
            sphere_obstacle: false,
            box_obstacle: false,
            gate: false,
            real_time: false,
            scene: None,
        };
        config.apply_preset_defaults();
        config
    }
}

/// The box: floor plate centre and size, wall height [m].
pub const FLOOR_SIZE: Vec2 = Vec2::new(2.0, 0.8);
/// Wall height [m].
pub const WALL_HEIGHT: f32 = 1.0;
/// The block's share of the box: x from the left wall, full depth, up to this height.
pub const BLOCK_SIZE: Vec3 = Vec3::new(0.6, 0.8, 0.8);

impl SandboxConfig {
    /// Resets integrator and time step to the preset's own.
    pub fn apply_preset_defaults(&mut self) {
        let p = self.params_with_defaults();
        self.integrator = p.integrator;
        self.time_step = p.time_step;
    }

    /// Lattice spacing so the budget fills the block volume.
    pub fn spacing(&self) -> f32 {
        (BLOCK_SIZE.x * BLOCK_SIZE.y * BLOCK_SIZE.z / self.budget.max(1) as f32).cbrt()
    }

    fn params_with_defaults(&self) -> SphParams {
        let spacing = self.spacing();
        let water = SphParams::from_spacing(SpacingDerivation {
            spacing,
            expected_peak_speed: (2.0 * 9.81 * BLOCK_SIZE.y).sqrt(),
            ..Default::default()
        });
        match self.preset {
            Preset::Water => water,
            Preset::Design => {
                let seed = SphParams::seed();
                SphParams {
                    particle_mass: seed.rest_density * spacing.powi(3),
                    smoothing_radius: water.smoothing_radius,
                    ..seed
                }
            }
        }
    }

    /// The parameters the start screen's choices give.
    pub fn params(&self) -> SphParams {
        let mut p = self.params_with_defaults();
        p.integrator = self.integrator;
        p.time_step = self.time_step;
        p.adaptive_time_step = self.adaptive_time_step;
        p.neighbor_search = self.search;
        p.surface_tension = match (self.surface_tension, self.preset) {
            (false, _) => 0.0,
            (true, Preset::Water) => sph_core::params::WATER_SURFACE_TENSION,
            (true, Preset::Design) => SphParams::seed().surface_tension,
        };
        if self.solver != Solver::Wcsph {
            p.use_solver(self.solver);
        }
        p
    }
}

//! The scenarios of `sph-bench`: their scenes, emitters and default durations.

use sph_core::glam::Vec3;
use sph_core::scenario::{dam_break, hydrostatic, Scene};
use sph_core::{BoxContainer, PipeEmitter, Rollback, SpacingDerivation, SphParams};

/// Gravity [m/s²] of every scenario (T = t sqrt(2g/a)).
pub const G: f64 = 9.81;

/// A scenario name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scenario {
    /// Martin & Moyce (1952): a column a wide and 2a high against the wall of a tank 5a long.
    DamBreak,
    /// A tank of water at rest.
    Hydrostatic,
    /// The pipe fills a box.
    PipeFill,
    /// The scene our peers were measured on: 31,250 particles, dt 1e-3, 0.5 s.
    DamBreak32k,
}

impl Scenario {
    /// Every scenario.
    pub const ALL: [Scenario; 4] = [
        Scenario::DamBreak,
        Scenario::Hydrostatic,
        Scenario::PipeFill,
        Scenario::DamBreak32k,
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Scenario::DamBreak => "dam-break",
            Scenario::Hydrostatic => "hydrostatic",
            Scenario::PipeFill => "pipe-fill",
            Scenario::DamBreak32k => "dambreak32k",
        }
    }

    /// One line for the command's help.
    pub fn description(self) -> &'static str {
        match self {
            Scenario::DamBreak => "Martin & Moyce (1952): a column a wide, 2a high, to T = 2.8",
            Scenario::Hydrostatic => "a 0.2 m cube of water at rest for 1 s",
            Scenario::PipeFill => "a pipe fills a 0.6 x 0.4 x 0.3 m box, then 0.5 s settling",
            Scenario::DamBreak32k => "the peers' scene: 31,250 particles, dt 1e-3 s, 0.5 s",
        }
    }
}

/// A scenario ready to run.
#[derive(Clone, Debug)]
pub struct Setup {
    /// Which scenario.
    pub scenario: Scenario,
    /// Parameters, container and blocks.
    pub scene: Scene,
    /// The pipe (pipe-fill).
    pub emitter: Option<PipeEmitter>,
    /// Particle slots.
    pub capacity: usize,
    /// Simulated time of a full run [s].
    pub duration: f64,
    /// The dam break's column width a [m].
    pub column_width_a: Option<f32>,
    /// The water height of the hydrostatic tank [m].
    pub water_depth: Option<f32>,
    /// How unstable steps are handled (rollback on unless the command turns it off).
    pub rollback: Rollback,
}

/// Rounds `length` to whole lattice cells of `spacing`.
fn cells(length: f32, spacing: f32) -> f32 {
    (length / spacing).round().max(1.0) * spacing
}

/// The scenario with about `particles` particles (ignored by `dambreak32k`); `a` is the dam
/// break's column width.
pub fn setup(scenario: Scenario, particles: usize, a: f32) -> Setup {
    let n = particles.max(1) as f32;
    match scenario {
        Scenario::DamBreak => {
            // a × 2a × a/2 holds a³/s³ particles.
            let spacing = a / n.cbrt();
            let (a, depth) = (cells(a, spacing), cells(0.5 * a, spacing));
            let scene = dam_break(a, depth, spacing);
            Setup {
                scenario,
                capacity: scene.particle_count(),
                // T = 2.8 covers the experiment's T <= 2.5 with room for a shift.
                duration: 2.8 / (2.0 * G / a as f64).sqrt(),
                column_width_a: Some(a),
                water_depth: None,
                rollback: Rollback::default(),
                emitter: None,
                scene,
            }
        }
        Scenario::Hydrostatic => {
            // A cube of water: width = depth = n^(1/3) spacings, 0.2 m deep.
            let depth = 0.2;
            let spacing = depth / n.cbrt();
            let depth = cells(depth, spacing);
            let scene = hydrostatic(depth, depth, spacing);
            Setup {
                scenario,
                capacity: scene.particle_count(),
                duration: 1.0,
                column_width_a: None,
                water_depth: Some(depth),
                rollback: Rollback::default(),
                emitter: None,
                scene,
            }
        }
        Scenario::PipeFill => pipe_fill(particles.max(1)),
        Scenario::DamBreak32k => dam_break_32k(),
    }
}

/// A 0.6 × 0.4 × 0.3 m box filled by a horizontal pipe (radius 0.04 m, 1.5 m/s) near its top
/// left; `particles` in all, at the spacing that fills a third of the box.
fn pipe_fill(particles: usize) -> Setup {
    let size = Vec3::new(0.6, 0.4, 0.3);
    let spacing = (size.x * size.y * size.z / 3.0 / particles as f32).cbrt();
    let speed = 1.5;
    let params = SphParams::from_spacing(SpacingDerivation {
        spacing,
        expected_peak_speed: (speed * speed + 2.0 * 9.81 * size.y).sqrt(),
        ..Default::default()
    });
    let container = BoxContainer::from_min_max(Vec3::ZERO, size);
    let mut pipe = PipeEmitter::new(Vec3::new(0.04, 0.3, 0.15), Vec3::X, 0.04, speed, spacing);
    pipe.total = Some(particles as u64);
    let fill_time = particles as f64 / pipe.matched_rate().max(1.0) as f64;
    Setup {
        scenario: Scenario::PipeFill,
        scene: Scene {
            params,
            container,
            blocks: Vec::new(),
        },
        emitter: Some(pipe),
        capacity: particles,
        // Fill, then let it settle for half a second.
        duration: fill_time + 0.5,
        column_width_a: None,
        water_depth: None,
        rollback: Rollback::default(),
    }
}

/// Tank x 0..2.0, y 0..1.2, z 0..0.5 m; column x 0..0.5, y 0..1.0, z 0..0.5 m on a 0.02 m lattice
/// (31,250 particles), support radius 0.04 m, ρ0 = 1000, dt = 1e-3 s, 0.5 s, no surface tension.
fn dam_break_32k() -> Setup {
    let spacing = 0.02;
    let mut params = SphParams::from_spacing(SpacingDerivation {
        spacing,
        expected_peak_speed: (2.0 * 9.81 * 1.0f32).sqrt(),
        ..Default::default()
    });
    params.time_step = 1e-3;
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(2.0, 1.2, 0.5));
    let column = sph_core::BlockSpawn::new(Vec3::ZERO, Vec3::new(0.5, 1.0, 0.5), spacing);
    let scene = Scene {
        params,
        container,
        blocks: vec![column],
    };
    Setup {
        scenario: Scenario::DamBreak32k,
        capacity: scene.particle_count(),
        duration: 0.5,
        column_width_a: None,
        water_depth: None,
        rollback: Rollback::default(),
        emitter: None,
        scene,
    }
}

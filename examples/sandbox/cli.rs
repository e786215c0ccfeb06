//! The sandbox's command line (clap; `--help` lists it).

use crate::config::{SandboxConfig, BUDGET_RANGE};
use crate::surface::{RenderMode, SurfaceView};
use bevy::prelude::Resource;
use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::Parser;
use std::path::PathBuf;

/// The Aquaplay-style sandbox: a start screen, then a water box with a pipe and a block spawn.
#[derive(Parser, Resource, Clone, Debug)]
#[command(name = "sandbox")]
pub struct Cli {
    /// The particle budget (1024 ..= 262144).
    #[arg(long, value_name = "N", value_parser = particles)]
    pub particles: Option<u32>,
    /// Skip the start screen.
    #[arg(long)]
    pub start: bool,
    /// Start at once, render `--frames` frames, save a PNG here, print the median frame time
    /// and exit.
    #[arg(long, value_name = "FILE")]
    pub screenshot: Option<PathBuf>,
    /// Frames rendered before `--screenshot` saves.
    #[arg(long, value_name = "N", default_value_t = 60)]
    pub frames: u32,
    /// Start with the simulation paused (times the drawing alone).
    #[arg(long)]
    pub paused: bool,
    /// Draw no water (times the simulation alone).
    #[arg(long)]
    pub hide_particles: bool,
    /// Leave out the GPU's per-pass timings.
    #[arg(long)]
    pub no_gpu_timings: bool,
    /// Start with the debug view on.
    #[arg(long)]
    pub debug: bool,
    /// The adaptive time step.
    #[arg(long)]
    pub adaptive: bool,
    /// Colliders of every shape in the box.
    #[arg(long)]
    pub obstacles: bool,
    /// Each frame advances the water by the frame's own time.
    #[arg(long)]
    pub real_time: bool,
    /// A scene file under `assets/` (`scenes/dam_break.ron`, `assets/scenes/dam_break.ron` or its
    /// absolute path), reloaded when it changes; starts at once.
    #[arg(long, value_name = "FILE", value_parser = asset_path)]
    pub scene: Option<String>,
    /// That solver instead of the default PBF (each runs on either backend).
    #[arg(long, value_name = "NAME", value_parser = solver())]
    pub solver: Option<sph_core::Solver>,
    /// The CPU backend instead of the GPU.
    #[arg(long)]
    pub cpu: bool,
    /// How the water is drawn.
    #[arg(long, value_enum, default_value_t = RenderMode::Surface)]
    pub render: RenderMode,
    /// Whitewater (spray, foam and bubbles) on with its default settings, once the scene runs
    /// (a scene file that loads later decides again). The CPU backend's only, for now.
    #[arg(long)]
    pub whitewater: bool,
    /// What the surface shows first: lit, or one of its passes raw.
    #[arg(long, value_enum, default_value_t = SurfaceView::Lit)]
    pub surface_view: SurfaceView,
    /// The camera's eye and the point it orbits, `EX,EY,EZ,FX,FY,FZ` in metres (a close view:
    /// `--camera 0.45,0.30,-0.15,0.6,0.12,0.18`).
    #[arg(long, value_name = "EYE,FOCUS", value_parser = camera_pose, allow_hyphen_values = true)]
    pub camera: Option<CameraPose>,
}

/// Where the camera starts: its eye and the point it orbits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraPose {
    /// The eye [m].
    pub eye: bevy::math::Vec3,
    /// The point the camera looks at and orbits [m].
    pub focus: bevy::math::Vec3,
}

fn camera_pose(text: &str) -> Result<CameraPose, String> {
    let numbers: Vec<f32> = text
        .split(',')
        .map(|n| n.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{text:?}: {e}; expected six numbers EX,EY,EZ,FX,FY,FZ"))?;
    let [ex, ey, ez, fx, fy, fz] = numbers[..] else {
        return Err(format!(
            "{text:?}: {} numbers; expected six, EX,EY,EZ,FX,FY,FZ",
            numbers.len()
        ));
    };
    let pose = CameraPose {
        eye: bevy::math::Vec3::new(ex, ey, ez),
        focus: bevy::math::Vec3::new(fx, fy, fz),
    };
    if !pose.eye.is_finite() || !pose.focus.is_finite() || pose.eye.distance(pose.focus) < 1e-3 {
        return Err(format!(
            "{text:?}: the eye and the focus must be finite and at least 1 mm apart"
        ));
    }
    Ok(pose)
}

impl Cli {
    /// The sandbox's settings as the options set them. A `--scene` file is read and built once
    /// here, so that a broken one is refused before the window opens (the asset system loads
    /// and watches it afterwards), and its solver is the sandbox's.
    pub fn sandbox_config(&self) -> Result<SandboxConfig, String> {
        let mut config = SandboxConfig::default();
        if let Some(n) = self.particles {
            config.budget = n;
            config.apply_preset_defaults();
        }
        config.adaptive_time_step = self.adaptive;
        config.real_time = self.real_time;
        config.scene = self.scene.clone();
        if let Some(solver) = self.solver {
            config.solver = solver;
        }
        if let Some(path) = &self.scene {
            let file = format!("{}/assets/{path}", env!("CARGO_MANIFEST_DIR"));
            let text =
                std::fs::read_to_string(&file).map_err(|e| format!("--scene: {file}: {e}"))?;
            let setup = sph_core::scene::SceneFile::parse(&text, path)
                .and_then(|scene| scene.build(path, &text))
                .map_err(|e| format!("--scene: {e}"))?;
            config.solver = setup.params.solver;
        }
        if self.obstacles {
            config.sphere_obstacle = true;
            config.box_obstacle = true;
            config.gate = true;
        }
        Ok(config)
    }

    /// Whether the scene starts without the start screen (`--start`, `--scene`, `--screenshot`).
    pub fn starts_at_once(&self) -> bool {
        self.start || self.scene.is_some() || self.screenshot.is_some()
    }
}

fn particles(text: &str) -> Result<u32, String> {
    let allowed = format!("{} ..= {}", BUDGET_RANGE.start(), BUDGET_RANGE.end());
    match text.parse::<u32>() {
        Ok(n) if BUDGET_RANGE.contains(&n) => Ok(n),
        _ => Err(format!("{text:?}: allowed {allowed}")),
    }
}

/// One of `Solver::ALL` by its name.
fn solver() -> impl TypedValueParser<Value = sph_core::Solver> {
    PossibleValuesParser::new(sph_core::Solver::ALL.map(|s| s.name())).map(|name| {
        sph_core::Solver::ALL
            .into_iter()
            .find(|s| s.name() == name)
            .unwrap_or_default()
    })
}

/// The path of `file` inside the sandbox's `assets/` folder (where Bevy's asset system loads
/// and watches it): `scenes/x.ron`, `assets/scenes/x.ron` and the absolute path all give
/// `scenes/x.ron`; a file outside the folder is refused.
fn asset_path(file: &str) -> Result<String, String> {
    let assets = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/assets"));
    let path = std::path::Path::new(file);
    let inside = if path.is_absolute() {
        path.strip_prefix(assets).ok()
    } else {
        Some(path.strip_prefix("assets").unwrap_or(path))
    };
    inside
        .map(|p| p.to_string_lossy().into_owned())
        .ok_or_else(|| {
            format!(
                "{file:?}: allowed a file under {} (the asset folder Bevy loads and watches)",
                assets.display()
            )
        })
}

//! The scene file's format: every section and field of `assets/scenes/*.ron` as serde types,
//! read by [`SceneFile::parse`](crate::scene::SceneFile::parse).

use crate::scene::controls::ControlSpec;
use glam::Vec3;
use serde::Deserialize;

/// The most angular damping a hinge may have [1/s].
pub const MAX_HINGE_DAMPING: f32 = 100.0;

/// A vector written as a tuple `(x, y, z)`.
pub type Vector = (f32, f32, f32);

/// A tuple as a vector.
pub(crate) fn v(x: Vector) -> Vec3 {
    Vec3::new(x.0, x.1, x.2)
}

/// The parameter table a scene starts from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
pub enum Preset {
    /// SI water derived from the spacing ([`SphParams::from_spacing`](crate::params::SphParams::from_spacing)).
    #[default]
    Water,
    /// The design's seed table ([`SphParams::seed`](crate::params::SphParams::seed)).
    Design,
}

/// Changes to the preset's parameters; every field is optional.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Overrides {
    /// Artificial viscosity α (sets μ).
    pub viscosity_alpha: Option<f32>,
    /// Surface tension γ.
    pub surface_tension: Option<f32>,
    /// Gravity [m/s²].
    pub gravity: Option<Vector>,
    /// The time step, or the largest one with the adaptive rule [s].
    pub time_step: Option<f32>,
    /// The adaptive (CFL) time step.
    pub adaptive_time_step: Option<bool>,
    /// CFL factor λ.
    pub cfl_factor: Option<f32>,
}

/// The pressure solver with its settings (omitted settings keep their defaults).
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum SolverSpec {
    /// Weakly compressible SPH.
    #[default]
    Wcsph,
    /// Divergence-free SPH.
    Dfsph {
        /// Largest mean density error [%].
        max_density_error_pct: Option<f32>,
        /// Largest mean divergence error [%/s].
        max_divergence_error_pct: Option<f32>,
        /// Warm starts.
        warm_start: Option<bool>,
        /// Over-relaxation ω of the divergence-free solve (1: plain Jacobi).
        divergence_over_relaxation: Option<f32>,
        /// Over-relaxation ω of the constant-density solve (1: plain Jacobi).
        density_over_relaxation: Option<f32>,
    },
    /// Position-based fluids.
    Pbf {
        /// Constraint iterations per step.
        iterations: Option<u32>,
        /// XSPH viscosity c.
        xsph_c: Option<f32>,
        /// Vorticity confinement ε [m/s].
        vorticity_epsilon: Option<f32>,
        /// Over-relaxation ω of the iterations after the first (1: plain Jacobi).
        over_relaxation: Option<f32>,
        /// The weight of each iteration's λ, (0, 1] (1: plain Jacobi).
        jacobi_weight: Option<f32>,
    },
}

/// The container: an axis-aligned box standing on its floor.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContainerSpec {
    /// Minimum corner [m].
    pub min: Vector,
    /// Maximum corner [m].
    pub max: Vector,
}

/// A collider's shape (y is the axis of capsules and cylinders).
#[derive(Clone, Debug, PartialEq, Deserialize)]
pub enum ShapeSpec {
    /// A box with half extents [m].
    Cuboid {
        /// Half extents [m].
        half_extents: Vector,
    },
    /// A ball.
    Sphere {
        /// Radius [m].
        radius: f32,
    },
    /// A capsule along y.
    Capsule {
        /// Radius [m].
        radius: f32,
        /// Half length of the axis segment [m].
        half_length: f32,
    },
    /// A cylinder along y.
    Cylinder {
        /// Radius [m].
        radius: f32,
        /// Half length [m].
        half_length: f32,
    },
    /// A triangle mesh ([`crate::TriMesh`]): closed (watertight) without `thickness`, an open
    /// shell of `thickness` [m] with it.
    Mesh {
        /// Vertices in the collider's frame [m].
        vertices: Vec<Vector>,
        /// Three vertex indices per triangle.
        indices: Vec<u32>,
        /// The shell's thickness [m] for an open mesh (a sheet, a chute).
        #[serde(default)]
        thickness: Option<f32>,
    },
    /// A paddle wheel about the collider's local z axis ([`crate::boundary::paddle_wheel::PaddleWheel`]):
    /// `paddles` boxes from `inner` to `outer` [m] from the axle, `thickness` [m] thick and
    /// `width` [m] wide along it; a closed mesh for the water.
    PaddleWheel {
        /// Number of paddles, 2 ..= 32.
        paddles: u32,
        /// Where the paddles start, from the axle [m].
        inner: f32,
        /// Where they end [m].
        outer: f32,
        /// Paddle thickness [m].
        thickness: f32,
        /// Paddle width along the axle [m].
        width: f32,
    },
}

/// How a collider moves.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
pub enum MotionSpec {
    /// Never moves.
    #[default]
    Static,
    /// Moves along a path: `(time [s], position)` waypoints, linear in between, held before the
    /// first and after the last.
    Kinematic {
        /// The waypoints, in time order.
        path: Vec<(f32, Vector)>,
    },
    /// A rigid body the water pushes (moved by a physics engine: with the plugin's `avian`
    /// feature, avian): give its `density` [kg/m³] or its `mass` [kg], not both.
    Dynamic {
        /// Density [kg/m³], > 0.
        #[serde(default)]
        density: Option<f32>,
        /// Mass [kg], > 0.
        #[serde(default)]
        mass: Option<f32>,
    },
    /// A dynamic body (as `Dynamic`) that turns on a hinge through its `position` along `axis`
    /// (world frame): with the plugin's `avian` feature, a revolute joint to the world.
    /// `damping` [1/s] is its angular damping (the axle's friction), 0 ..= 100.
    Hinged {
        /// The hinge's direction (world frame; normalised), not zero.
        axis: Vector,
        /// Density [kg/m³], > 0.
        #[serde(default)]
        density: Option<f32>,
        /// Mass [kg], > 0.
        #[serde(default)]
        mass: Option<f32>,
        /// Angular damping [1/s].
        #[serde(default)]
        damping: f32,
    },
    /// Moved by a named control (see [`crate::scene::controls`]): at `position` at the start of
    /// the control's range, at `to` at its end, linear between.
    Controlled {
        /// The control's name.
        control: String,
        /// The position at the range's end [m].
        to: Vector,
    },
}

/// A collider of a scene file.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColliderSpec {
    /// A name for errors, logs and game code.
    pub name: String,
    /// The shape.
    pub shape: ShapeSpec,
    /// The centre [m].
    pub position: Vector,
    /// Rotation as XYZ Euler angles [degrees].
    #[serde(default)]
    pub rotation_degrees: Vector,
    /// Static or kinematic.
    #[serde(default)]
    pub motion: MotionSpec,
    /// No-slip friction factor; omitted: free slip.
    #[serde(default)]
    pub no_slip_friction: Option<f32>,
}

/// A block of water on the lattice.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BlockSpec {
    /// Minimum corner [m].
    pub min: Vector,
    /// Maximum corner [m].
    pub max: Vector,
    /// Initial velocity [m/s].
    #[serde(default)]
    pub velocity: Vector,
}

/// A pipe emitter.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EmitterSpec {
    /// Centre of the pipe mouth [m].
    pub position: Vector,
    /// Jet direction.
    pub direction: Vector,
    /// Pipe radius [m].
    pub radius: f32,
    /// Exit speed [m/s].
    pub speed: f32,
    /// Stop after this many particles; omitted: forever.
    #[serde(default)]
    pub total: Option<u64>,
}

/// A drain: removes the water inside its box while open.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SinkSpec {
    /// A name for errors, logs and game code.
    pub name: String,
    /// Minimum corner [m].
    pub min: Vector,
    /// Maximum corner [m].
    pub max: Vector,
    /// Open at the start; default true.
    #[serde(default)]
    pub open: Option<bool>,
    /// A control that opens it (while its value is past the range's middle) instead of `open`.
    #[serde(default)]
    pub open_control: Option<String>,
}

/// A pump: pushes the water inside its box along `direction` toward `speed`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PumpSpec {
    /// A name for errors, logs and game code.
    pub name: String,
    /// Minimum corner [m].
    pub min: Vector,
    /// Maximum corner [m].
    pub max: Vector,
    /// The direction it pushes in.
    pub direction: Vector,
    /// Target speed [m/s], 0 ..= 100.
    pub speed: f32,
    /// Relaxation rate toward the target speed [1/s], 0 ..= 1000.
    pub strength: f32,
    /// A control whose fraction of its range multiplies the strength (a crank).
    #[serde(default)]
    pub strength_control: Option<String>,
}

/// What a probe measures.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
pub enum ProbeSpec {
    /// The water level at (x, z) [m].
    Level {
        /// World x [m].
        x: f32,
        /// World z [m].
        z: f32,
        /// Column radius [m]; default two spacings.
        #[serde(default)]
        radius: Option<f32>,
    },
    /// The flux through a rectangle [m³/s].
    Flux {
        /// Centre [m].
        position: Vector,
        /// The normal the flux is counted along.
        normal: Vector,
        /// Half width and half height [m].
        half_size: (f32, f32),
    },
    /// The particles in a box.
    Count {
        /// Minimum corner [m].
        min: Vector,
        /// Maximum corner [m].
        max: Vector,
    },
}

/// A probe of a scene file.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeEntry {
    /// A name for readings, plots and JSON.
    pub name: String,
    /// What it measures.
    pub kind: ProbeSpec,
    /// Steps between readings; default 1 (every frame that steps).
    #[serde(default)]
    pub every_steps: Option<u32>,
}

/// A scene file as written.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// The parameter table.
    #[serde(default)]
    pub preset: Preset,
    /// Particle spacing Δx [m] (the water preset derives h, m, c0 and dt from it); default 0.02.
    #[serde(default)]
    pub spacing: Option<f32>,
    /// Changes to the preset.
    #[serde(default)]
    pub overrides: Overrides,
    /// The pressure solver.
    #[serde(default)]
    pub solver: SolverSpec,
    /// The container.
    pub container: ContainerSpec,
    /// Solids in the water.
    #[serde(default)]
    pub colliders: Vec<ColliderSpec>,
    /// Water at the start.
    #[serde(default)]
    pub blocks: Vec<BlockSpec>,
    /// Pipes.
    #[serde(default)]
    pub emitters: Vec<EmitterSpec>,
    /// Drains.
    #[serde(default)]
    pub sinks: Vec<SinkSpec>,
    /// Pumps.
    #[serde(default)]
    pub pumps: Vec<PumpSpec>,
    /// Probes.
    #[serde(default)]
    pub probes: Vec<ProbeEntry>,
    /// Named controls (see [`crate::scene::controls`]).
    #[serde(default)]
    pub controls: Vec<ControlSpec>,
    /// Spray, foam and bubbles where the water breaks (off when absent).
    #[serde(default)]
    pub whitewater: Option<crate::scene::whitewater::WhitewaterSpec>,
}

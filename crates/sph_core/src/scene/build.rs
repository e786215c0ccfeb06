//! Water scenes as data: the RON format of `assets/scenes/*.ron`, read by the Bevy plugin's
//! asset loader and by `sph-bench run --scene FILE`.
//!
//! A file names a parameter preset with overrides, the solver, the container, colliders (static,
//! or kinematic along a path of timed waypoints), fluid blocks, pipe emitters, drains (`sinks`),
//! pumps and probes:
//!
//! ```
//! let text = r#"(
//!     spacing: 0.02,
//!     solver: Pbf(iterations: 4),
//!     container: (min: (0.0, 0.0, 0.0), max: (0.8, 0.5, 0.3)),
//!     colliders: [(name: "ball", shape: Sphere(radius: 0.06), position: (0.5, 0.06, 0.15))],
//!     blocks: [(min: (0.0, 0.0, 0.0), max: (0.2, 0.3, 0.3))],
//! )"#;
//! let scene = sph_core::scene::SceneFile::parse(text, "doc.ron").unwrap();
//! let setup = scene.build("doc.ron", text).unwrap();
//! assert_eq!(setup.colliders.len(), 1);
//! ```
//!
//! Every error names the file, the line and column, the field, the value and what is allowed
//! ([`SceneError`]); the parser refuses unknown fields, so a misspelt key is an error too.
//! Optional values are written bare (RON's `implicit_some`): `spacing: 0.02`, `total: 8000`.

use crate::boundary::collider::{Collider, ColliderMotion, ColliderShape, Pose, Slip};
use crate::boundary::paddle_wheel::PaddleWheel;
use crate::boundary::trimesh::TriMesh;
use crate::container::BoxContainer;
use crate::flow::probe::ProbeKind;
use crate::flow::pump::Pump;
use crate::flow::region::Region;
use crate::flow::sink::Sink;
use crate::params::{ParamError, SpacingDerivation, SphParams};
use crate::scene::controls::{ControlBinding, ControlTarget, SceneControl};
use crate::scene::error::{end_of, locate_after, locate_in_entry, SceneError};
use crate::scene::setup::{BodyMass, Hinge, SceneCollider, SceneProbe, SceneSetup};
use crate::scene::spec::*;
use crate::solver::dfsph::settings::DfsphSettings;
use crate::solver::pbf::settings::PbfSettings;
use crate::solvers::Solver;
use crate::spawn::{BlockSpawn, PipeEmitter};
use glam::{EulerRot, Quat, Vec3};

impl SceneFile {
    /// Parses `text` (the contents of `file`); a syntax error or an unknown, missing or
    /// mistyped field is refused with its line and column.
    pub fn parse(text: &str, file: &str) -> Result<Self, SceneError> {
        // Optional values are written bare (`spacing: 0.02`, not `Some(0.02)`).
        let options = ron::Options::default()
            .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
        options
            .from_str(text)
            .map_err(|e: ron::error::SpannedError| {
                use ron::error::Error as E;
                let field = match &e.code {
                    E::NoSuchStructField { found, .. } => found.clone(),
                    E::MissingStructField { field, .. } => field.to_string(),
                    E::DuplicateStructField { field, .. } => field.to_string(),
                    E::NoSuchEnumVariant { found, .. } => found.clone(),
                    _ => "-".into(),
                };
                // A file cut short (a truncated save, a hot reload mid-write) fails at its last
                // character with whatever token the parser expected next: name the real cause.
                let reaches = (e.span.end.line, e.span.end.col);
                let message = if matches!(e.code, E::Eof) || reaches >= end_of(text) {
                    format!("unexpected end of file ({})", e.code)
                } else {
                    e.code.to_string()
                };
                SceneError {
                    file: file.into(),
                    line: e.span.start.line,
                    column: e.span.start.col,
                    field,
                    message,
                }
            })
    }

    /// Builds and validates the scene; `text` (the file's contents) locates a refused value.
    pub fn build(&self, file: &str, text: &str) -> Result<SceneSetup, SceneError> {
        // A refused value: the field's key on its line, the nth time the key appears.
        let refuse =
            |field: String, (section, key): (Option<&str>, &str), nth: usize, e: ParamError| {
                let (line, column) = locate_after(text, section, key, nth);
                SceneError {
                    file: file.into(),
                    line,
                    column,
                    field,
                    message: format!("{} is not allowed: {}", e.value, e.allowed),
                }
            };
        let mut params = match self.preset {
            Preset::Water => SphParams::from_spacing(SpacingDerivation {
                spacing: self.spacing.unwrap_or(SpacingDerivation::default().spacing),
                ..SpacingDerivation::default()
            }),
            Preset::Design => SphParams::seed(),
        };
        let solver = match self.solver {
            SolverSpec::Wcsph => Solver::Wcsph,
            SolverSpec::Dfsph { .. } => Solver::Dfsph,
            SolverSpec::Pbf { .. } => Solver::Pbf,
        };
        params.use_solver(solver);
        match self.solver {
            SolverSpec::Wcsph => {}
            SolverSpec::Dfsph {
                max_density_error_pct,
                max_divergence_error_pct,
                warm_start,
                divergence_over_relaxation,
                density_over_relaxation,
            } => {
                let base = DfsphSettings::default();
                params.dfsph = DfsphSettings {
                    max_density_error: max_density_error_pct
                        .map_or(base.max_density_error, |p| p / 100.0),
                    max_divergence_error: max_divergence_error_pct
                        .map_or(base.max_divergence_error, |p| p / 100.0),
                    warm_start: warm_start.unwrap_or(base.warm_start),
                    divergence_over_relaxation: divergence_over_relaxation
                        .unwrap_or(base.divergence_over_relaxation),
                    density_over_relaxation: density_over_relaxation
                        .unwrap_or(base.density_over_relaxation),
                    ..base
                };
            }
            SolverSpec::Pbf {
                iterations,
                xsph_c,
                vorticity_epsilon,
                over_relaxation,
                jacobi_weight,
            } => {
                let base = PbfSettings::default();
                params.pbf = PbfSettings {
                    iterations: iterations.unwrap_or(base.iterations),
                    xsph_c: xsph_c.unwrap_or(base.xsph_c),
                    vorticity_epsilon: vorticity_epsilon.unwrap_or(base.vorticity_epsilon),
                    over_relaxation: over_relaxation.unwrap_or(base.over_relaxation),
                    jacobi_weight: jacobi_weight.unwrap_or(base.jacobi_weight),
                    ..base
                };
            }
        }
        let o = &self.overrides;
        if let Some(alpha) = o.viscosity_alpha {
            params.set_artificial_viscosity_alpha(alpha);
        }
        if let Some(gamma) = o.surface_tension {
            params.surface_tension = gamma;
        }
        if let Some(g) = o.gravity {
            params.gravity = v(g);
        }
        if let Some(dt) = o.time_step {
            params.time_step = dt;
        }
        if let Some(adaptive) = o.adaptive_time_step {
            params.adaptive_time_step = adaptive;
        }
        if let Some(cfl) = o.cfl_factor {
            params.cfl_factor = cfl;
        }
        params.validate().map_err(|e| {
            let key = e.field.rsplit('.').next().unwrap_or(e.field);
            refuse(e.field.to_string(), (None, key), 0, e)
        })?;
        let container = BoxContainer::from_min_max(v(self.container.min), v(self.container.max));
        container
            .validate()
            .map_err(|e| refuse(format!("container.{}", e.field), (None, "container"), 0, e))?;
        // The walls' samples and the search grid, counted before anything is allocated.
        crate::limits::check_container(&container, params.smoothing_radius, params.spacing())
            .map_err(|e| refuse(e.field.to_string(), (None, "container"), 0, e))?;
        let in_entry = |section: &str, k: usize, key: &str, field: String, message: String| {
            let (line, column) = locate_in_entry(text, section, k, key);
            SceneError {
                file: file.into(),
                line,
                column,
                field,
                message,
            }
        };
        let mut controls: Vec<SceneControl> = Vec::with_capacity(self.controls.len());
        for (k, spec) in self.controls.iter().enumerate() {
            let control = SceneControl::of(spec).map_err(|(key, message)| {
                in_entry(
                    "controls",
                    k,
                    key,
                    format!("controls[{k}] ({:?}).{key}", spec.name),
                    message,
                )
            })?;
            if controls.iter().any(|c| c.name == spec.name) {
                return Err(in_entry(
                    "controls",
                    k,
                    "name",
                    format!("controls[{k}].name"),
                    format!(
                        "{:?} is not allowed: control names must be unique",
                        spec.name
                    ),
                ));
            }
            controls.push(control);
        }
        // The index of the control `name` that entry k of `section` names under `key`.
        let control_of = |section: &str, k: usize, entry: &str, key: &str, name: &str| {
            controls.iter().position(|c| c.name == name).ok_or_else(|| {
                let names: Vec<&str> = controls.iter().map(|c| c.name.as_str()).collect();
                in_entry(
                    section,
                    k,
                    key,
                    format!("{section}[{k}] ({entry:?}).{key}"),
                    format!("{name:?} is not allowed: one of the controls {names:?}"),
                )
            })
        };
        let mut bindings = Vec::new();
        let mut colliders = Vec::with_capacity(self.colliders.len());
        for (k, c) in self.colliders.iter().enumerate() {
            let mut collider = self.collider(k, c, file, text)?;
            crate::limits::check_shape_samples(&collider.collider.shape, params.spacing())
                .map_err(|e| {
                    in_entry(
                        "colliders",
                        k,
                        "shape",
                        format!("colliders[{k}] ({:?}).{}", c.name, e.field),
                        format!("{} is not allowed: {}", e.value, e.allowed),
                    )
                })?;
            if let MotionSpec::Controlled { control, to } = &c.motion {
                let index = control_of("colliders", k, &c.name, "control", control)?;
                let (from, to) = (v(c.position), v(*to));
                if !to.is_finite() {
                    return Err(in_entry(
                        "colliders",
                        k,
                        "to",
                        format!("colliders[{k}] ({:?}).motion.to", c.name),
                        format!("{to:?} is not allowed: finite coordinates [m]"),
                    ));
                }
                collider.collider.pose.translation =
                    ControlTarget::position(from, to, controls[index].fraction());
                bindings.push(ControlBinding {
                    control: index,
                    index: k,
                    target: ControlTarget::Position { from, to },
                });
            }
            colliders.push(collider);
        }
        let spacing = params.spacing();
        let mut blocks = Vec::with_capacity(self.blocks.len());
        let mut block_particles: u64 = 0;
        for (k, b) in self.blocks.iter().enumerate() {
            let block = BlockSpawn::new(v(b.min), v(b.max), spacing);
            let refuse_block = |e: ParamError| {
                refuse(
                    format!("blocks[{k}].{}", e.field),
                    (Some("blocks"), "min"),
                    k,
                    e,
                )
            };
            block.validate().map_err(refuse_block)?;
            // Each block is within the bound; so must all of them be together.
            block_particles = crate::limits::check_count(
                "block.max",
                block.checked_count().map(|n| n + block_particles),
                crate::limits::MAX_SPAWN_PARTICLES,
                "at most 4194304 particles (2^22) in all blocks together",
            )
            .map_err(refuse_block)?;
            blocks.push((block, v(b.velocity)));
        }
        let mut emitters = Vec::with_capacity(self.emitters.len());
        for (k, e) in self.emitters.iter().enumerate() {
            let mut pipe =
                PipeEmitter::new(v(e.position), v(e.direction), e.radius, e.speed, spacing);
            pipe.total = e.total;
            pipe.validate().map_err(|err| {
                refuse(
                    format!("emitters[{k}].{}", err.field),
                    (Some("emitters"), "radius"),
                    k,
                    err,
                )
            })?;
            emitters.push(pipe);
        }
        let refuse_named = |section: &str, k: usize, name: &str, e: ParamError| {
            let (line, column) = locate_after(text, Some(section), "name", k);
            SceneError {
                file: file.into(),
                line,
                column,
                field: format!("{section}[{k}] ({name:?}).{}", e.field),
                message: format!("{} is not allowed: {}", e.value, e.allowed),
            }
        };
        let mut sinks = Vec::with_capacity(self.sinks.len());
        for (k, s) in self.sinks.iter().enumerate() {
            let mut sink = Sink {
                region: Region::from_min_max(v(s.min), v(s.max)),
                open: s.open.unwrap_or(true),
            };
            if let Some(name) = &s.open_control {
                let index = control_of("sinks", k, &s.name, "open_control", name)?;
                sink.open = ControlTarget::drain_open(controls[index].fraction());
                bindings.push(ControlBinding {
                    control: index,
                    index: k,
                    target: ControlTarget::DrainOpen,
                });
            }
            sink.validate()
                .map_err(|e| refuse_named("sinks", k, &s.name, e))?;
            sinks.push((s.name.clone(), sink));
        }
        let mut pumps = Vec::with_capacity(self.pumps.len());
        for (k, p) in self.pumps.iter().enumerate() {
            let pump = Pump {
                region: Region::from_min_max(v(p.min), v(p.max)),
                direction: v(p.direction),
                speed: p.speed,
                strength: p.strength,
            };
            pump.validate()
                .map_err(|e| refuse_named("pumps", k, &p.name, e))?;
            let mut pump = pump;
            if let Some(name) = &p.strength_control {
                let index = control_of("pumps", k, &p.name, "strength_control", name)?;
                pump.strength = p.strength * controls[index].fraction();
                bindings.push(ControlBinding {
                    control: index,
                    index: k,
                    target: ControlTarget::PumpStrength {
                        strength: p.strength,
                    },
                });
            }
            pumps.push((p.name.clone(), pump));
        }
        let mut probes = Vec::with_capacity(self.probes.len());
        for (k, p) in self.probes.iter().enumerate() {
            let kind = match p.kind {
                ProbeSpec::Level { x, z, radius } => ProbeKind::Level {
                    x,
                    z,
                    radius: radius.unwrap_or(2.0 * spacing),
                },
                ProbeSpec::Flux {
                    position,
                    normal,
                    half_size,
                } => {
                    let n = v(normal);
                    if !(n.is_finite() && n.length_squared() > 1e-12) {
                        return Err(refuse_named(
                            "probes",
                            k,
                            &p.name,
                            ParamError {
                                field: "kind.normal",
                                value: format!("{normal:?}"),
                                allowed: "a finite, non-zero vector",
                            },
                        ));
                    }
                    ProbeKind::Flux {
                        pose: Pose {
                            translation: v(position),
                            rotation: Quat::from_rotation_arc(Vec3::Z, n.normalize()),
                        },
                        half_size: [half_size.0, half_size.1],
                    }
                }
                ProbeSpec::Count { min, max } => ProbeKind::Count {
                    region: Region::from_min_max(v(min), v(max)),
                },
            };
            kind.validate()
                .map_err(|e| refuse_named("probes", k, &p.name, e))?;
            let every_steps = p.every_steps.unwrap_or(1);
            if every_steps == 0 {
                return Err(refuse_named(
                    "probes",
                    k,
                    &p.name,
                    ParamError {
                        field: "every_steps",
                        value: "0".into(),
                        allowed: ">= 1 step",
                    },
                ));
            }
            probes.push(SceneProbe {
                name: p.name.clone(),
                kind,
                every_steps,
            });
        }
        // A refused whitewater field is located by its key after `whitewater:`.
        let whitewater = self
            .whitewater
            .map(|spec| spec.build())
            .transpose()
            .map_err(|e| {
                let key = e.field.split('.').nth(1).unwrap_or("whitewater");
                refuse(e.field.to_string(), (Some("whitewater"), key), 0, e)
            })?;
        Ok(SceneSetup {
            params,
            container,
            colliders,
            blocks,
            emitters,
            sinks,
            pumps,
            probes,
            controls,
            bindings,
            whitewater,
        })
    }

    fn collider(
        &self,
        k: usize,
        c: &ColliderSpec,
        file: &str,
        text: &str,
    ) -> Result<SceneCollider, SceneError> {
        // The collider's own line for its key.
        let at = |key: &str| locate_in_entry(text, "colliders", k, key);
        let error = |key: &str, field: String, message: String| {
            let (line, column) = at(key);
            SceneError {
                file: file.into(),
                line,
                column,
                field: format!("colliders[{k}] ({:?}).{field}", c.name),
                message,
            }
        };
        let shape = match c.shape {
            ShapeSpec::Mesh {
                ref vertices,
                ref indices,
                thickness,
            } => {
                let vertices: Vec<Vec3> = vertices.iter().map(|&p| v(p)).collect();
                let mesh = match thickness {
                    None => TriMesh::closed(&vertices, indices),
                    Some(t) => TriMesh::open(&vertices, indices, t),
                };
                let mesh = mesh.map_err(|e| {
                    let key = e.field.trim_start_matches("shape.");
                    error(
                        key,
                        e.field.to_string(),
                        format!("{} is not allowed: {}", e.value, e.allowed),
                    )
                })?;
                ColliderShape::TriMesh(mesh.into())
            }
            ShapeSpec::PaddleWheel {
                paddles,
                inner,
                outer,
                thickness,
                width,
            } => {
                let wheel = PaddleWheel {
                    paddles,
                    inner,
                    outer,
                    thickness,
                    width,
                };
                let mesh = wheel.mesh().map_err(|e| {
                    let key = e.field.trim_start_matches("shape.");
                    error(
                        key,
                        e.field.to_string(),
                        format!("{} is not allowed: {}", e.value, e.allowed),
                    )
                })?;
                ColliderShape::TriMesh(mesh.into())
            }
            ShapeSpec::Cuboid { half_extents } => ColliderShape::Cuboid {
                half_extents: v(half_extents),
            },
            ShapeSpec::Sphere { radius } => ColliderShape::Sphere { radius },
            ShapeSpec::Capsule {
                radius,
                half_length,
            } => ColliderShape::Capsule {
                radius,
                half_length,
            },
            ShapeSpec::Cylinder {
                radius,
                half_length,
            } => ColliderShape::Cylinder {
                radius,
                half_length,
            },
        };
        let r = c.rotation_degrees;
        let rotation = Quat::from_euler(
            EulerRot::XYZ,
            r.0.to_radians(),
            r.1.to_radians(),
            r.2.to_radians(),
        );
        let path: Vec<(f32, Vec3)> = match &c.motion {
            MotionSpec::Static
            | MotionSpec::Controlled { .. }
            | MotionSpec::Dynamic { .. }
            | MotionSpec::Hinged { .. } => Vec::new(),
            MotionSpec::Kinematic { path } => path.iter().map(|&(t, p)| (t, v(p))).collect(),
        };
        if let MotionSpec::Kinematic { .. } = c.motion {
            if path.is_empty() {
                return Err(error(
                    "path",
                    "motion.path".into(),
                    "an empty path is not allowed: at least one (time, position) waypoint".into(),
                ));
            }
            for (n, pair) in path.windows(2).enumerate() {
                // NaN times are refused too.
                let ordered = pair[1].0.partial_cmp(&pair[0].0);
                if !matches!(
                    ordered,
                    Some(std::cmp::Ordering::Greater | std::cmp::Ordering::Equal)
                ) {
                    return Err(error(
                        "path",
                        format!("motion.path[{}].time", n + 1),
                        format!(
                            "{} is not allowed: waypoint times must not decrease (the previous is {})",
                            pair[1].0, pair[0].0
                        ),
                    ));
                }
            }
        }
        let mut collider = Collider::new(
            shape,
            Pose {
                translation: v(c.position),
                rotation,
            },
        );
        collider.motion = match c.motion {
            MotionSpec::Static => ColliderMotion::Static,
            MotionSpec::Dynamic { .. } | MotionSpec::Hinged { .. } => ColliderMotion::Dynamic,
            _ => ColliderMotion::Kinematic,
        };
        let body = match c.motion {
            MotionSpec::Dynamic { density, mass } | MotionSpec::Hinged { density, mass, .. } => {
                let (key, value, body) = match (density, mass) {
                    (Some(d), None) => ("density", d, BodyMass::Density(d)),
                    (None, Some(m)) => ("mass", m, BodyMass::Mass(m)),
                    _ => return Err(error(
                        "motion",
                        "motion".into(),
                        "Dynamic and Hinged need exactly one of `density` [kg/m³] and `mass` [kg]"
                            .into(),
                    )),
                };
                if !(value.is_finite() && value > 0.0) {
                    return Err(error(
                        key,
                        format!("motion.{key}"),
                        format!("{value} is not allowed: > 0 and finite"),
                    ));
                }
                Some(body)
            }
            _ => None,
        };
        let hinge = match c.motion {
            MotionSpec::Hinged { axis, damping, .. } => {
                let axis = v(axis);
                let unit = axis.normalize_or_zero();
                if !axis.is_finite() || unit == Vec3::ZERO {
                    return Err(error(
                        "axis",
                        "motion.axis".into(),
                        format!("{axis} is not allowed: a finite, non-zero direction"),
                    ));
                }
                if !(damping.is_finite() && (0.0..=MAX_HINGE_DAMPING).contains(&damping)) {
                    return Err(error(
                        "damping",
                        "motion.damping".into(),
                        format!("{damping} is not allowed: [0, {MAX_HINGE_DAMPING}] 1/s"),
                    ));
                }
                Some(Hinge {
                    axis: unit,
                    damping,
                })
            }
            _ => None,
        };
        collider.slip = match c.no_slip_friction {
            Some(friction) => Slip::NoSlip { friction },
            None => Slip::Free,
        };
        collider.validate().map_err(|e| {
            error(
                "shape",
                e.field.to_string(),
                format!("{} is not allowed: {}", e.value, e.allowed),
            )
        })?;
        let mut scene_collider = SceneCollider {
            name: c.name.clone(),
            collider,
            path,
            body,
            hinge,
        };
        scene_collider.collider.pose.translation = scene_collider.position_at(0.0);
        Ok(scene_collider)
    }
}

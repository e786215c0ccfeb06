//! What every engine's export shares: the loaded scene, the options, refusals (the field, its
//! value and what the engine lacks), the export held in memory, and the refusals and notes that
//! apply to every engine.

use sph_core::scene::{MotionSpec, SceneFile, SceneSetup};
use std::fmt;
use std::path::Path;

/// Frames per second of the engines' particle output (SPlisHSPlasH's default `dataExportFPS`).
pub const DATA_FPS: f32 = 25.0;

/// `x` to 6 significant digits (a micrometre on a metre, far below any spacing) as an f64, so
/// that files say 0.04 where f32 arithmetic gives 0.03999999; −0 becomes 0.
pub fn decimal(x: f32) -> f64 {
    let rounded: f64 = format!("{x:.5e}").parse().unwrap_or(f64::from(x));
    if rounded == 0.0 {
        0.0
    } else {
        rounded
    }
}

/// A scene file as written and as built.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The file's name, for messages.
    pub file: String,
    /// The file's fields.
    pub spec: SceneFile,
    /// The validated scene.
    pub setup: SceneSetup,
}

/// Reads, parses and builds `path`; the error names the file, the line and the field.
pub fn load(path: &Path) -> Result<Loaded, String> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{file}: cannot read: {e}"))?;
    let spec = SceneFile::parse(&text, &file).map_err(|e| e.to_string())?;
    let setup = spec.build(&file, &text).map_err(|e| e.to_string())?;
    Ok(Loaded { file, spec, setup })
}

/// How to export.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExportOptions {
    /// Simulated time the exported scene runs for [s].
    pub end_time: f32,
    /// Leave the probes out instead of refusing the scene.
    pub drop_probes: bool,
}

/// Something of the scene an engine cannot express: the field, its value and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Refusal {
    /// The field, e.g. `pumps[0] ("crank_pump")`.
    pub field: String,
    /// Its value, shortened.
    pub value: String,
    /// What the engine lacks.
    pub why: String,
}

impl Refusal {
    /// A refusal of `field` = `value` because `why`.
    pub fn new(field: impl Into<String>, value: impl Into<String>, why: impl Into<String>) -> Self {
        Self {
            field: field.into(),
            value: value.into(),
            why: why.into(),
        }
    }
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "`{}` = {}: {}", self.field, self.value, self.why)
    }
}

/// An export held in memory: file names (relative to OUT) with their contents, and notes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Export {
    /// `(name, contents)`, the scene file first.
    pub files: Vec<(String, String)>,
    /// What was mapped approximately, one sentence each.
    pub notes: Vec<String>,
}

/// The field name of collider `k`, as the scene file's errors write it.
pub fn collider_field(k: usize, name: &str) -> String {
    format!("colliders[{k}] ({name:?})")
}

/// The refusals every engine shares: drains, pumps, probes (unless dropped), colliders moved by
/// a control or turning on a hinge, and no-slip colliders.
pub fn common_refusals(scene: &Loaded, options: &ExportOptions, engine: &str) -> Vec<Refusal> {
    let mut out = Vec::new();
    for (k, c) in scene.spec.colliders.iter().enumerate() {
        let field = collider_field(k, &c.name);
        match &c.motion {
            MotionSpec::Controlled { control, .. } => out.push(Refusal::new(
                format!("{field}.motion"),
                format!("Controlled(control: {control:?})"),
                format!("{engine} runs offline: nothing moves a body by a control at run time"),
            )),
            MotionSpec::Hinged { axis, damping, .. } => out.push(Refusal::new(
                format!("{field}.motion"),
                format!("Hinged(axis: {axis:?}, damping: {damping})"),
                format!(
                    "{engine}'s scene file has no hinge to the world with an axle's angular \
                     damping"
                ),
            )),
            _ => {}
        }
        if let Some(f) = c.no_slip_friction.filter(|&f| f != 0.0) {
            out.push(Refusal::new(
                format!("{field}.no_slip_friction"),
                f.to_string(),
                format!(
                    "{engine} has one boundary friction for every solid, and the container's \
                     walls are free slip"
                ),
            ));
        }
    }
    for (k, s) in scene.spec.sinks.iter().enumerate() {
        out.push(Refusal::new(
            format!("sinks[{k}] ({:?})", s.name),
            format!("a drain from {:?} to {:?}", s.min, s.max),
            format!("{engine}'s scene file has no region that removes water"),
        ));
    }
    for (k, p) in scene.spec.pumps.iter().enumerate() {
        out.push(Refusal::new(
            format!("pumps[{k}] ({:?})", p.name),
            format!("a pump at {} m/s from {:?} to {:?}", p.speed, p.min, p.max),
            format!("{engine}'s scene file has no region that drives the water toward a speed"),
        ));
    }
    if !options.drop_probes {
        for (k, p) in scene.spec.probes.iter().enumerate() {
            out.push(Refusal::new(
                format!("probes[{k}] ({:?})", p.name),
                format!("{:?}", p.kind),
                format!(
                    "{engine}'s scene file has no probes (measure its output instead); \
                     --drop-probes leaves them out"
                ),
            ));
        }
    }
    out
}

/// The notes every engine shares.
pub fn common_notes(scene: &Loaded, options: &ExportOptions) -> Vec<String> {
    let mut notes = Vec::new();
    if options.drop_probes && !scene.spec.probes.is_empty() {
        let names: Vec<&str> = scene.spec.probes.iter().map(|p| p.name.as_str()).collect();
        notes.push(format!("probes left out (--drop-probes): {names:?}"));
    }
    if !scene.spec.controls.is_empty() && scene.setup.bindings.is_empty() {
        notes.push("the scene's controls drive nothing and are left out".into());
    }
    notes
}

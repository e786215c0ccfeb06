//! Named controls of a scene file: a value in a range that game code or the sandbox's panel sets
//! at run time, and that drives a collider along a line (a gate's lift), a pump's strength (a
//! crank) or a drain's valve.
//!
//! ```ron
//! controls: [(name: "gate_lift", value: 0.0), (name: "crank", value: 1.0, max: 2.0)],
//! colliders: [(name: "gate", ..., motion: Controlled(control: "gate_lift", to: (0.4, 0.6, 0.05)))],
//! pumps: [(name: "pump", ..., strength_control: "crank")],   // strength × value
//! sinks: [(name: "drain", ..., open_control: "drain_valve")], // open while value > 0.5
//! ```

use serde::Deserialize;

/// A control as written: a name, its starting value and its range (default 0 ..= 1).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControlSpec {
    /// The name colliders, pumps and drains refer to.
    pub name: String,
    /// The starting value, in the range.
    pub value: f32,
    /// The smallest value; default 0.
    #[serde(default)]
    pub min: Option<f32>,
    /// The largest value; default 1.
    #[serde(default)]
    pub max: Option<f32>,
}

/// A control of a built scene.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneControl {
    /// Its name.
    pub name: String,
    /// Its value.
    pub value: f32,
    /// The smallest value.
    pub min: f32,
    /// The largest value.
    pub max: f32,
}

impl SceneControl {
    /// The control as written, checked: finite, min < max, value in the range.
    pub fn of(spec: &ControlSpec) -> Result<Self, (&'static str, String)> {
        let (min, max) = (spec.min.unwrap_or(0.0), spec.max.unwrap_or(1.0));
        if !(min.is_finite() && max.is_finite() && min < max) {
            return Err((
                "max",
                format!("min {min}, max {max} is not allowed: finite, min < max"),
            ));
        }
        if !(min..=max).contains(&spec.value) {
            return Err((
                "value",
                format!("{} is not allowed: [{min}, {max}]", spec.value),
            ));
        }
        Ok(Self {
            name: spec.name.clone(),
            value: spec.value,
            min,
            max,
        })
    }

    /// How far the value is through the range, 0 ..= 1 (a value set outside it is clamped).
    pub fn fraction(&self) -> f32 {
        ((self.value - self.min) / (self.max - self.min)).clamp(0.0, 1.0)
    }
}

/// What a control drives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ControlTarget {
    /// A collider's position: `from` at the range's start, `to` at its end, linear between.
    Position {
        /// The position at the range's start [m].
        from: glam::Vec3,
        /// The position at its end [m].
        to: glam::Vec3,
    },
    /// A pump's strength: `strength` × the fraction.
    PumpStrength {
        /// The strength at the range's end [1/s].
        strength: f32,
    },
    /// A drain's valve: open while the fraction is above one half.
    DrainOpen,
}

impl ControlTarget {
    /// The position a [`ControlTarget::Position`] takes at `fraction`.
    pub fn position(from: glam::Vec3, to: glam::Vec3, fraction: f32) -> glam::Vec3 {
        from.lerp(to, fraction)
    }

    /// Whether a drain is open at `fraction`.
    pub fn drain_open(fraction: f32) -> bool {
        fraction > 0.5
    }
}

/// A binding of a built scene: control `control` drives `target` of the `index`-th collider,
/// pump or drain (by the target's kind).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ControlBinding {
    /// The control's index in [`crate::scene::SceneSetup::controls`].
    pub control: usize,
    /// The collider's, pump's or drain's index in its section.
    pub index: usize,
    /// What it drives.
    pub target: ControlTarget,
}

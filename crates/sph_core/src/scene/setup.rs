//! A scene built from its file ([`SceneFile::build`](crate::scene::SceneFile::build)): the
//! validated parameters and the colliders, water and devices to spawn.

use crate::boundary::collider::Collider;
use crate::container::BoxContainer;
use crate::flow::probe::ProbeKind;
use crate::flow::pump::Pump;
use crate::flow::sink::Sink;
use crate::params::SphParams;
use crate::scene::controls::{ControlBinding, SceneControl};
use crate::spawn::{BlockSpawn, PipeEmitter};
use glam::Vec3;

/// A probe of a built scene.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneProbe {
    /// The file's name for it.
    pub name: String,
    /// What it measures.
    pub kind: ProbeKind,
    /// Steps between readings (≥ 1).
    pub every_steps: u32,
}

/// A collider of a built scene, with its name and path.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneCollider {
    /// The file's name for it.
    pub name: String,
    /// The collider at time 0.
    pub collider: Collider,
    /// Kinematic waypoints `(time, position)`; empty for a static collider.
    pub path: Vec<(f32, Vec3)>,
    /// A dynamic collider's mass.
    pub body: Option<BodyMass>,
    /// A hinged collider's hinge.
    pub hinge: Option<Hinge>,
}

/// The hinge of a [`MotionSpec::Hinged`](crate::scene::spec::MotionSpec::Hinged) collider.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hinge {
    /// Unit direction of the axle, world frame.
    pub axis: Vec3,
    /// Angular damping [1/s].
    pub damping: f32,
}

/// How heavy a dynamic collider is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BodyMass {
    /// Density [kg/m³] (the mass follows from the shape's volume).
    Density(f32),
    /// Mass [kg].
    Mass(f32),
}

impl SceneCollider {
    /// The position at simulated time `t` [s]: linear between waypoints, held outside them.
    pub fn position_at(&self, t: f32) -> Vec3 {
        let Some(&(t0, first)) = self.path.first() else {
            return self.collider.pose.translation;
        };
        if t <= t0 {
            return first;
        }
        for pair in self.path.windows(2) {
            let ((ta, a), (tb, b)) = (pair[0], pair[1]);
            if t <= tb {
                let s = if tb > ta { (t - ta) / (tb - ta) } else { 1.0 };
                return a.lerp(b, s);
            }
        }
        self.path.last().map_or(first, |p| p.1)
    }
}

/// A scene ready to run: validated parameters and the things to spawn.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSetup {
    /// Validated parameters (the solver's own time-step rule unless overridden).
    pub params: SphParams,
    /// The container.
    pub container: BoxContainer,
    /// The colliders.
    pub colliders: Vec<SceneCollider>,
    /// The blocks with their initial velocities.
    pub blocks: Vec<(BlockSpawn, Vec3)>,
    /// The emitters.
    pub emitters: Vec<PipeEmitter>,
    /// The drains with their names.
    pub sinks: Vec<(String, Sink)>,
    /// The pumps with their names.
    pub pumps: Vec<(String, Pump)>,
    /// The probes.
    pub probes: Vec<SceneProbe>,
    /// The named controls at their starting values (the colliders, pumps and drains above are
    /// placed for them).
    pub controls: Vec<SceneControl>,
    /// What each control drives.
    pub bindings: Vec<ControlBinding>,
    /// Whitewater's settings and pool capacity, when the file turns it on.
    pub whitewater: Option<(crate::whitewater::settings::WhitewaterSettings, u32)>,
}

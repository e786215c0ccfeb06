//! The water's push on a body over an engine window (the frames the engine steps at once,
//! [`crate::bodies::engine_handoff`]), and the gap between the device's steps and the engine's.
//!
//! The device moves a body at every water step with that step's force; the engine steps the
//! same window with the window's mean force, J / T. Both end it at the same velocity (the same
//! impulse), but not at the same place: an impulse early in the window moves the body on the
//! device for longer than the same impulse spread over the window. Semi-implicit Euler on both
//! sides, with no contact and no damping, from the same state:
//!
//! - the device, steps k of dt_k starting at t_k: Δc = v₀ T + Σ_k (F_k / M + g) dt_k (E − t_k),
//!   E the window's end (a step's velocity change moves the body over the rest of the window);
//! - the engine, N substeps of h = T / N under a = J / (M T) + g: Δc = v₀ T + a T² (N + 1) / (2N).
//!
//! Their difference, the gap, is (Λ − J κ) / M + g (Λ_t − T κ) with κ = T (N + 1) / (2N),
//! Λ = Σ F dt (E − t) the impulse's lever to the window's end and Λ_t = Σ dt (E − t). The
//! device's own contact pushes are not in it, nor the engine's: closing the gap in the engine
//! leaves the handoff only what the engine saw beyond the water (avian's contacts and joints).
//! The turn's gap is the same with the angular impulse, I_w⁻¹ (Λ_τ − L κ), to first order (the
//! world inertia taken at the window's end, the gyroscopic term left out as in
//! [`crate::bodies::rigid_step`]); damping is left out of both. The engine's push the device
//! applied at every step ([`crate::bodies::engine_push`]) is a constant force, as gravity:
//! (F_e / M) (Λ_t − T κ) and I_w⁻¹ τ_e (Λ_t − T κ); the engine's contacts that it stands for
//! act in the engine itself.

use crate::bodies::engine_handoff::FrameRecord;
use crate::bodies::engine_push::EnginePush;
use crate::bodies::rigid_step::{conjugate, rotate, RigidBodyModel};
use glam::{Quat, Vec3};

/// The water's push on a body over consecutive frames, and when in them it came.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WindowImpulse {
    /// The water time the frames cover, T [s].
    pub duration: f32,
    /// The water's impulse, J = Σ F dt [N s].
    pub impulse: Vec3,
    /// The water's angular impulse about the centre of mass, L = Σ τ_c dt [N m s].
    pub angular_impulse: Vec3,
    /// Λ = Σ F dt (E − t) [N s²]: each step's impulse times the time from the step's start t to
    /// the window's end E.
    pub impulse_lever: Vec3,
    /// Λ_τ = Σ τ_c dt (E − t) [N m s²].
    pub angular_impulse_lever: Vec3,
    /// Λ_t = Σ dt (E − t) [s²].
    pub time_lever: f32,
}

impl WindowImpulse {
    /// The push over `records` (consecutive frames of one body) in a window that ends at water
    /// time `end_ns`.
    pub fn over<'a>(records: impl IntoIterator<Item = &'a FrameRecord>, end_ns: u64) -> Self {
        let mut sum = Self::default();
        for r in records {
            // From the frame's start to the window's end: E − t = (E − t₀) − (t − t₀).
            let to_end = (end_ns.saturating_sub(r.time_ns) as f64 * 1e-9) as f32;
            let from_start = to_end + r.duration;
            sum.duration += r.duration;
            sum.impulse += r.impulse;
            sum.angular_impulse += r.angular_impulse;
            sum.impulse_lever += from_start * r.impulse - r.impulse_moment;
            sum.angular_impulse_lever += from_start * r.angular_impulse - r.angular_impulse_moment;
            sum.time_lever += from_start * r.duration - r.time_moment;
        }
        sum
    }

    /// How much further the device's steps moved and turned a body of `model` over the window
    /// than an engine stepping it in `engine_substeps` substeps of the mean force: the centre of
    /// mass's gap [m] and the turn's [rad] (world), the body at `rotation` at the window's end,
    /// the device's steps under the engine's `push` besides the water.
    /// None for a hinged body (its axle's reaction and gravity's lever change with its angle
    /// within the window; the handoff passes its difference on) and none along locked axes.
    pub fn gap(
        &self,
        model: &RigidBodyModel,
        rotation: Quat,
        engine_substeps: u32,
        push: &EnginePush,
    ) -> (Vec3, Vec3) {
        let t = self.duration;
        if model.hinge.is_some() || !(t.is_finite() && t > 0.0 && model.mass > 0.0) {
            return (Vec3::ZERO, Vec3::ZERO);
        }
        let n = engine_substeps.max(1) as f32;
        let kappa = t * (n + 1.0) / (2.0 * n);
        let steady = self.time_lever - kappa * t;
        let translation = Self::shared_shift(&[(self, model, push)], engine_substeps);
        let angular =
            self.angular_impulse_lever - kappa * self.angular_impulse + steady * push.torque;
        let local = model.inverse_inertia * rotate(conjugate(rotation), angular);
        let gap = (translation, rotate(rotation, local) * model.free_rotation);
        if gap.0.is_finite() && gap.1.is_finite() {
            gap
        } else {
            (Vec3::ZERO, Vec3::ZERO)
        }
    }

    /// The centre of mass's gap [m] of bodies that rest on one another in the engine, moved as
    /// one body: their impulses, levers, weights and the engine's pushes summed over their
    /// summed mass, (ΣΛ − κ ΣJ + (Λ_t − T κ) Σ (m g + F_e)) / Σ m. On the device a crate
    /// resting on a raft goes with the raft (their contact keeps their common velocity,
    /// `crate::bodies::solid_contact`), so the water's slap on the raft early in a window
    /// carries both; closed apart, the raft's gap alone would move it into the crate in the
    /// engine. The engine's pushes between them are equal and opposite and drop out. One part
    /// is [`Self::gap`]'s shift. Zero with a hinged part, windows of other durations or no mass;
    /// zero along an axis any part locks.
    pub fn shared_shift(
        parts: &[(&WindowImpulse, &RigidBodyModel, &EnginePush)],
        engine_substeps: u32,
    ) -> Vec3 {
        let Some((first, ..)) = parts.first() else {
            return Vec3::ZERO;
        };
        let (t, time_lever) = (first.duration, first.time_lever);
        let apart = |(w, m, _): &(&WindowImpulse, &RigidBodyModel, &EnginePush)| {
            m.hinge.is_some() || (w.duration - t).abs() > 1e-6 * t.max(1.0)
        };
        if !(t.is_finite() && t > 0.0) || parts.iter().any(apart) {
            return Vec3::ZERO;
        }
        let (mut mass, mut lever, mut impulse, mut weight, mut free) =
            (0.0, Vec3::ZERO, Vec3::ZERO, Vec3::ZERO, Vec3::ONE);
        for (w, m, push) in parts {
            mass += m.mass;
            lever += w.impulse_lever;
            impulse += w.impulse;
            weight += m.mass * m.gravity + push.force;
            free *= m.free_translation;
        }
        if !(mass.is_finite() && mass > 0.0) {
            return Vec3::ZERO;
        }
        let n = engine_substeps.max(1) as f32;
        let kappa = t * (n + 1.0) / (2.0 * n);
        let shift = (lever - kappa * impulse + (time_lever - kappa * t) * weight) / mass * free;
        if shift.is_finite() {
            shift
        } else {
            Vec3::ZERO
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bodies::engine_handoff::tests::model;
    use crate::bodies::engine_handoff::DeviceBody;
    use crate::bodies::rigid_step::{turned, RigidState};

    fn start() -> RigidState {
        RigidState {
            position: Vec3::new(0.0, 1.0, 0.0),
            rotation: Quat::IDENTITY,
            linear_velocity: Vec3::new(0.3, -0.1, 0.0),
            angular_velocity: Vec3::ZERO,
        }
    }

    /// The engine's push the device applies in [`device_frames`] (a contact pressing the body
    /// sideways and holding part of its weight).
    const PUSH: EnginePush = EnginePush {
        force: Vec3::new(-4.0, 10.0, 2.0),
        torque: Vec3::new(0.1, 0.0, 0.3),
    };

    /// Three frames of four water steps of 4 ms, the water's force and torque changing from step
    /// to step (a slap in the first steps, then the weight carried), the engine's push [`PUSH`]
    /// applied too: the device's records.
    fn device_frames() -> (DeviceBody, Vec<FrameRecord>) {
        let m = model();
        let mut device = DeviceBody {
            state: Some(start()),
            engine_push: PUSH,
            ..Default::default()
        };
        let mut records = Vec::new();
        let mut time_ns = 0;
        for frame in 1..=3u32 {
            device.begin_frame(frame);
            for step in 0..4 {
                let k = (frame - 1) * 4 + step;
                let slap = if k < 2 { 60.0 } else { 0.0 };
                let force = Vec3::new(slap, 39.0 + 2.0 * k as f32, -5.0 + k as f32);
                let torque = Vec3::new(0.0, 0.0, if k == 5 { 3.0 } else { 0.2 });
                let c = device.state.unwrap().position;
                device.step(&m, force, torque + c.cross(force), 0.004);
                time_ns += 4_000_000;
            }
            device.end_frame(time_ns);
            records.push(device.records[frame as usize % 8].unwrap());
        }
        (device, records)
    }

    /// The engine's free step: `substeps` semi-implicit substeps of the mean force and torque,
    /// and of the contact [`PUSH`] stands for (a steady one).
    fn engine_step(window: &WindowImpulse, substeps: u32) -> RigidState {
        let m = model();
        let h = window.duration / substeps as f32;
        let mut s = start();
        for _ in 0..substeps {
            let water = window.impulse / (m.mass * window.duration);
            s.linear_velocity += h * (water + PUSH.force / m.mass + m.gravity);
            let torque = window.angular_impulse / window.duration + PUSH.torque;
            s.angular_velocity += h * 5.0 * torque;
            s.position += h * s.linear_velocity;
            s.rotation = turned(s.rotation, h * s.angular_velocity);
        }
        s
    }

    /// For any number of engine substeps, the engine's free step plus the gap is where the
    /// device's steps took the body (the engine's push on the device counted as the engine's
    /// steady contact); the engine ends at the device's velocity without it.
    #[test]
    fn the_gap_closes_the_engines_free_step_on_the_devices_steps() {
        let (device, records) = device_frames();
        let window = WindowImpulse::over(&records, records[2].time_ns);
        assert!((window.duration - 0.048).abs() < 1e-6);
        let moved = device.state.unwrap();
        for substeps in [1, 6, 18, 100] {
            let engine = engine_step(&window, substeps);
            let (shift, turn) = window.gap(&model(), engine.rotation, substeps, &PUSH);
            assert!(
                (engine.linear_velocity - moved.linear_velocity).length() < 1e-5,
                "{substeps}: {engine:?} {moved:?}"
            );
            let closed = engine.position + shift;
            assert!(
                (closed - moved.position).length() < 2e-6,
                "{substeps}: {closed} against {}, gap {shift}",
                moved.position
            );
            // The slap early in the window moved the device's body further along x than the
            // engine's substeps (one substep takes it all at once).
            assert!(substeps == 1 || shift.x > 1e-4, "{substeps}: {shift}");
            let closed = turned(engine.rotation, turn);
            let left = (glam::Vec4::from(moved.rotation) - glam::Vec4::from(closed)).length();
            assert!(left < 1e-6, "{substeps}: turn {turn}, left {left}");
            assert!(turn.z.abs() > 1e-6, "{turn}");
        }
    }

    /// A window counted frame by frame is the window counted at once: the levers of its earlier
    /// frames grow by their impulses times the time to the window's end.
    #[test]
    fn a_windows_levers_add_up_over_its_frames() {
        let (_, records) = device_frames();
        let end = records[2].time_ns;
        let whole = WindowImpulse::over(&records, end);
        let last = WindowImpulse::over(&records[2..], end);
        let first = WindowImpulse::over(&records[..2], records[1].time_ns);
        let later = 0.016;
        let lever = first.impulse_lever + later * first.impulse + last.impulse_lever;
        assert!((whole.impulse_lever - lever).length() < 1e-6);
        let time = first.time_lever + later * first.duration + last.time_lever;
        assert!((whole.time_lever - time).abs() < 1e-7);
        // Even steps: Λ_t = (T² + Σ dt²) / 2.
        let t = whole.duration;
        assert!((whole.time_lever - 0.5 * (t * t + 12.0 * 0.004 * 0.004)).abs() < 1e-7);
    }

    /// A crate resting on a raft that the water slapped early in the window shares one gap
    /// with it: that of one body of both masses under the raft's water and the pushes' sum (the
    /// contact's push between them, equal and opposite in the two, drops out). Each alone, the
    /// raft's gap would carry it into the crate.
    #[test]
    fn bodies_resting_on_one_another_share_one_gap() {
        let (_, records) = device_frames();
        let raft_water = WindowImpulse::over(&records, records[2].time_ns);
        let crate_water = WindowImpulse {
            duration: raft_water.duration,
            time_lever: raft_water.time_lever,
            ..Default::default()
        };
        let raft = model();
        let mut krate = model();
        krate.mass = 1.5;
        let held = -krate.mass * krate.gravity;
        let crate_push = EnginePush {
            force: held,
            torque: Vec3::ZERO,
        };
        let raft_push = EnginePush {
            force: PUSH.force - held,
            torque: PUSH.torque,
        };
        let parts = [
            (&raft_water, &raft, &raft_push),
            (&crate_water, &krate, &crate_push),
        ];
        let mut both = model();
        both.mass = raft.mass + krate.mass;
        for substeps in [1, 6, 18] {
            let shared = WindowImpulse::shared_shift(&parts, substeps);
            let (one, _) = raft_water.gap(&both, Quat::IDENTITY, substeps, &PUSH);
            assert!(
                (shared - one).length() < 1e-7,
                "{substeps}: {shared} against {one}"
            );
            let (raft_alone, _) = raft_water.gap(&raft, Quat::IDENTITY, substeps, &raft_push);
            let (crate_alone, _) = crate_water.gap(&krate, Quat::IDENTITY, substeps, &crate_push);
            assert!(crate_alone.length() < 1e-7, "{crate_alone}");
            // The slap's lever shared by mass: the raft alone would move 5.5 / 4 as far.
            if substeps > 1 {
                let ratio = raft_alone.x / shared.x;
                assert!((ratio - 5.5 / 4.0).abs() < 0.1, "{substeps}: {ratio}");
            }
        }
        let mut locked = krate;
        locked.free_translation = Vec3::new(1.0, 0.0, 1.0);
        let parts = [
            (&raft_water, &raft, &raft_push),
            (&crate_water, &locked, &crate_push),
        ];
        assert_eq!(WindowImpulse::shared_shift(&parts, 6).y, 0.0);
        assert_eq!(WindowImpulse::shared_shift(&[], 6), Vec3::ZERO);
    }

    /// A hinged body, a locked axis and an empty window have no gap there.
    #[test]
    fn a_hinge_a_locked_axis_and_an_empty_window_have_no_gap() {
        let (_, records) = device_frames();
        let window = WindowImpulse::over(&records, records[2].time_ns);
        let mut locked = model();
        locked.free_translation = Vec3::new(0.0, 1.0, 1.0);
        assert_eq!(window.gap(&locked, Quat::IDENTITY, 6, &PUSH).0.x, 0.0);
        let mut hinged = model();
        hinged.hinge = Some(crate::bodies::rigid_step::Hinge {
            axis: Vec3::Z,
            pivot: Vec3::ZERO,
            inverse_inertia: 1.0,
        });
        assert_eq!(
            window.gap(&hinged, Quat::IDENTITY, 6, &PUSH),
            (Vec3::ZERO, Vec3::ZERO)
        );
        assert_eq!(
            WindowImpulse::default().gap(&model(), Quat::IDENTITY, 6, &PUSH),
            (Vec3::ZERO, Vec3::ZERO)
        );
    }
}

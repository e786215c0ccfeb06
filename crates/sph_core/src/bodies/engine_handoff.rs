//! A body the water carries, as the device holds it between the physics engine's frames: the
//! water and the body advance together at the water's steps ([`crate::bodies::rigid_step`]),
//! and the engine, which sees the contacts and joints between bodies and with the level (the
//! device resolves only plain contacts on its own, [`crate::bodies::solid_contact`]), stays the
//! authority. WGSL twin: `body_motion.wgsl`.
//!
//! The rule, at every frame's end, for each body:
//! 1. The device records the body's state and the water's impulse on it over the frame
//!    (J = Σ F dt, and Σ τ_c dt about the centre of mass, with their moments in time) with the
//!    frame's number and time.
//! 2. The engine receives those records as they are read back (a few frames late on a GPU),
//!    steps the body over exactly the frames they cover, in steps of at most a game frame, with
//!    the force J / T (J and T, their water time, over those frames), moves it by the gap
//!    between the device's steps and that free step ([`crate::bodies::engine_window`]), and
//!    hands its state at the newest of them back to the device.
//! 3. The device compares the engine's state at that frame with its own record of it: the
//!    difference is what only the engine saw (a contact, a joint, a game's push). It adds the
//!    difference to its state now, the velocity difference carried over the time since that
//!    frame, and to its newer records, so that the next difference counts only what is new.
//!
//! Between the engine's states the device also applies the engine's steady push (its contacts
//! and joints as a mean force, [`crate::bodies::engine_push`]) at every step: the record then
//! holds it, and step 3's difference only what it missed.
//!
//! Every impulse is applied once on each side: the water's on the device at once and in the
//! engine when read back, the engine's in the engine at once and on the device when handed over.
//! Momentum is conserved, and the lag of the readback never enters the loop between the water
//! and the body, which is what threw floating bodies out of the water when the engine alone
//! moved them with forces three frames late.

use crate::bodies::engine_push::EnginePush;
use crate::bodies::rigid_step::{advance, conjugate, multiply, turned, RigidBodyModel, RigidState};
use glam::{Quat, Vec3};

/// The frame ends a device keeps per body: the engine's state may come back this many frames
/// late and still be compared with the device's record of its frame.
pub const RECORDS: usize = 8;

/// A frame's end as the device recorded it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameRecord {
    /// The frame's number.
    pub frame: u32,
    /// The water's time at the frame's end [ns].
    pub time_ns: u64,
    /// The water time the frame covered [s].
    pub duration: f32,
    /// The body at the frame's end.
    pub state: RigidState,
    /// The water's impulse over the frame, Σ F dt [N s].
    pub impulse: Vec3,
    /// The water's angular impulse about the centre of mass, Σ τ_c dt [N m s].
    pub angular_impulse: Vec3,
    /// When in the frame the water pushed: Σ F dt (t − t₀) [N s²], t a step's start and t₀ the
    /// frame's ([`crate::bodies::engine_window`]).
    pub impulse_moment: Vec3,
    /// The same of the angular impulse, Σ τ_c dt (t − t₀) [N m s²].
    pub angular_impulse_moment: Vec3,
    /// The same of the steps themselves, Σ dt (t − t₀) [s²] (gravity's).
    pub time_moment: f32,
}

/// The engine's body at the end of a frame the device recorded: its origin's pose (the
/// collider's) and its centre of mass's velocities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EngineState {
    /// The frame whose end the state is at.
    pub frame: u32,
    /// The body's origin (world) [m].
    pub origin: Vec3,
    /// Its orientation.
    pub rotation: Quat,
    /// Its centre of mass's velocity [m/s].
    pub linear_velocity: Vec3,
    /// Its angular velocity [rad/s].
    pub angular_velocity: Vec3,
    /// The steady part of the engine's push on the body over its last windows
    /// ([`EnginePush::steadied`]), which the device applies at every step from now on.
    pub push: EnginePush,
}

impl EngineState {
    /// The state of a body of `model`.
    pub fn rigid(&self, model: &RigidBodyModel) -> RigidState {
        RigidState::at_origin(
            self.origin,
            self.rotation,
            self.linear_velocity,
            self.angular_velocity,
            model.center_of_mass,
        )
    }
}

/// Whether frame `a` comes after frame `b` (frame numbers wrap).
pub fn after(a: u32, b: u32) -> bool {
    (a.wrapping_sub(b) as i32) > 0
}

/// `state` with the engine's difference from `record` added, `since` [s] after the record:
/// Δv and Δω at once, Δc + Δv since and the turn Δq, then Δω since.
pub fn corrected(
    state: &RigidState,
    engine: &RigidState,
    record: &RigidState,
    since: f32,
) -> RigidState {
    let dv = engine.linear_velocity - record.linear_velocity;
    let dw = engine.angular_velocity - record.angular_velocity;
    let dq = multiply(engine.rotation, conjugate(record.rotation));
    RigidState {
        position: state.position + (engine.position - record.position) + since * dv,
        rotation: turned(multiply(dq, state.rotation), since * dw),
        linear_velocity: state.linear_velocity + dv,
        angular_velocity: state.angular_velocity + dw,
    }
}

/// A body as the device holds it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DeviceBody {
    /// The body now (`None` until the engine's first state arrives).
    pub state: Option<RigidState>,
    /// The engine frame whose state was last taken.
    pub engine_frame: Option<u32>,
    /// Times the engine's state was taken whole because its frame was no longer (or never) among
    /// the records.
    pub resyncs: u32,
    /// The frame being summed.
    pub frame: u32,
    /// The water's impulse over the frame so far [N s].
    pub impulse: Vec3,
    /// The water's angular impulse over the frame so far [N m s].
    pub angular_impulse: Vec3,
    /// The water time of the frame so far [s].
    pub duration: f32,
    /// Σ F dt (t − t₀) over the frame so far [N s²] ([`FrameRecord::impulse_moment`]).
    pub impulse_moment: Vec3,
    /// Σ τ_c dt (t − t₀) over the frame so far [N m s²].
    pub angular_impulse_moment: Vec3,
    /// Σ dt (t − t₀) over the frame so far [s²].
    pub time_moment: f32,
    /// The last frames' ends, frame k at `k % RECORDS`.
    pub records: [Option<FrameRecord>; RECORDS],
    /// The engine's push applied at every step (the newest engine state's; the device reads it
    /// from its input at every step).
    pub engine_push: EnginePush,
}

impl DeviceBody {
    /// Starts summing frame `frame` (nothing changes while it is the frame being summed).
    pub fn begin_frame(&mut self, frame: u32) {
        if frame != self.frame {
            self.frame = frame;
            self.impulse = Vec3::ZERO;
            self.angular_impulse = Vec3::ZERO;
            self.duration = 0.0;
            self.impulse_moment = Vec3::ZERO;
            self.angular_impulse_moment = Vec3::ZERO;
            self.time_moment = 0.0;
        }
    }

    /// One water step of `dt` [s] under the water's force [N] and moment about the origin
    /// Σ x_b × f_b [N m], and the engine's push; a body without a state yet waits for the
    /// engine's. The impulses and their moments are the water's alone.
    pub fn step(&mut self, model: &RigidBodyModel, force: Vec3, moment: Vec3, dt: f32) {
        let Some(state) = self.state else {
            return;
        };
        let push = self.engine_push;
        let (impulse, angular) = (dt * force, dt * (moment - state.position.cross(force)));
        // The step starts `duration` into the frame.
        self.impulse_moment += self.duration * impulse;
        self.angular_impulse_moment += self.duration * angular;
        self.time_moment += self.duration * dt;
        self.impulse += impulse;
        self.angular_impulse += angular;
        self.duration += dt;
        let moment_with_push = moment + push.moment_about_origin(state.position);
        self.state = Some(advance(
            model,
            &state,
            force + push.force,
            moment_with_push,
            dt,
        ));
    }

    /// Takes the engine's state (when newer than the last taken) at water time `time_ns`: the
    /// first one as it is, later ones as the difference from the record of their frame
    /// ([`corrected`]), also added to the newer records. An engine frame no longer among the
    /// records is taken whole (a resync) and the records are dropped. Its push applies from
    /// now on, newer or not (the device reads it from its input at every step).
    pub fn take_engine_state(
        &mut self,
        model: &RigidBodyModel,
        engine: &EngineState,
        time_ns: u64,
    ) {
        self.engine_push = engine.push;
        if self
            .engine_frame
            .is_some_and(|taken| !after(engine.frame, taken))
        {
            return;
        }
        self.engine_frame = Some(engine.frame);
        let arrived = engine.rigid(model);
        let Some(state) = self.state else {
            self.state = Some(arrived);
            return;
        };
        let slot = engine.frame as usize % RECORDS;
        let Some(record) = self.records[slot].filter(|r| r.frame == engine.frame) else {
            self.state = Some(arrived);
            self.records = [None; RECORDS];
            self.resyncs += 1;
            return;
        };
        let seconds = |from: u64, to: u64| (to.saturating_sub(from) as f64 * 1e-9) as f32;
        self.state = Some(corrected(
            &state,
            &arrived,
            &record.state,
            seconds(record.time_ns, time_ns),
        ));
        for newer in self.records.iter_mut().flatten() {
            if after(newer.frame, engine.frame) {
                newer.state = corrected(
                    &newer.state,
                    &arrived,
                    &record.state,
                    seconds(record.time_ns, newer.time_ns),
                );
            }
        }
    }

    /// Records the frame's end at water time `time_ns`.
    pub fn end_frame(&mut self, time_ns: u64) {
        if let Some(state) = self.state {
            self.records[self.frame as usize % RECORDS] = Some(FrameRecord {
                frame: self.frame,
                time_ns,
                duration: self.duration,
                state,
                impulse: self.impulse,
                angular_impulse: self.angular_impulse,
                impulse_moment: self.impulse_moment,
                angular_impulse_moment: self.angular_impulse_moment,
                time_moment: self.time_moment,
            });
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::bodies::engine_window::WindowImpulse;
    use glam::Mat3;

    /// A free body of 4 kg under gravity, undamped (also `engine_window`'s tests' body).
    pub(crate) fn model() -> RigidBodyModel {
        RigidBodyModel {
            mass: 4.0,
            free_translation: Vec3::ONE,
            free_rotation: Vec3::ONE,
            center_of_mass: Vec3::ZERO,
            inverse_inertia: Mat3::from_diagonal(Vec3::splat(5.0)),
            hinge: None,
            gravity: Vec3::new(0.0, -9.81, 0.0),
            linear_damping: 0.0,
            angular_damping: 0.0,
        }
    }

    /// A body in the water of frames of `steps` steps of `dt`, the water pushing up with
    /// `lift` [N]: the engine's body is stepped from the device's records over the same frames.
    struct Run {
        device: DeviceBody,
        engine: RigidState,
        engine_frame: u32,
        time_ns: u64,
        /// The engine's push handed over with its state.
        push: EnginePush,
    }

    impl Run {
        fn new(start: RigidState) -> Self {
            let mut device = DeviceBody::default();
            let first = EngineState {
                frame: 0,
                origin: start.position,
                rotation: start.rotation,
                linear_velocity: start.linear_velocity,
                angular_velocity: start.angular_velocity,
                push: EnginePush::default(),
            };
            device.take_engine_state(&model(), &first, 0);
            Self {
                device,
                engine: start,
                engine_frame: 0,
                time_ns: 0,
                push: EnginePush::default(),
            }
        }

        fn frame(&mut self, frame: u32, lift: Vec3) {
            self.frame_varying(frame, [lift; 4]);
        }

        /// A frame of four steps under the lifts `lifts`, one per step.
        fn frame_varying(&mut self, frame: u32, lifts: [Vec3; 4]) {
            self.device.begin_frame(frame);
            for lift in lifts {
                let c = self.device.state.unwrap().position;
                self.device.step(&model(), lift, c.cross(lift), 0.004);
                self.time_ns += 4_000_000;
            }
            self.device.end_frame(self.time_ns);
        }

        /// The engine's body, at frame `upto`, handed to the device.
        fn hand_over(&mut self, upto: u32) {
            self.engine_frame = upto;
            let handed = EngineState {
                frame: upto,
                origin: self.engine.position,
                rotation: self.engine.rotation,
                linear_velocity: self.engine.linear_velocity,
                angular_velocity: self.engine.angular_velocity,
                push: self.push,
            };
            self.device
                .take_engine_state(&model(), &handed, self.time_ns);
        }

        /// The engine steps over the device's records after its frame up to `upto` with the
        /// mean force, adds `push` to its velocity (a contact), and hands its state back.
        fn engine_catches_up(&mut self, upto: u32, push: Vec3) {
            let m = model();
            let (mut impulse, mut time) = (Vec3::ZERO, 0.0);
            for frame in self.engine_frame + 1..=upto {
                let r = self.device.records[frame as usize % RECORDS].unwrap();
                assert_eq!(r.frame, frame);
                impulse += r.impulse;
                time += r.duration;
            }
            let v0 = self.engine.linear_velocity;
            let v1 = v0 + impulse / m.mass + time * m.gravity;
            self.engine.position += 0.5 * (v0 + v1) * time;
            self.engine.linear_velocity = v1 + push;
            self.hand_over(upto);
        }

        /// The engine steps over the records after its frame up to `upto` in `substeps`
        /// semi-implicit substeps of the mean force, moves its body by the gap to the device's
        /// steps when `close`, and hands its state back.
        fn engine_substeps(&mut self, upto: u32, substeps: u32, close: bool) {
            let m = model();
            let records: Vec<FrameRecord> = (self.engine_frame + 1..=upto)
                .map(|f| self.device.records[f as usize % RECORDS].unwrap())
                .collect();
            let push = WindowImpulse::over(&records, records.last().unwrap().time_ns);
            let h = push.duration / substeps as f32;
            let a = push.impulse / (m.mass * push.duration) + m.gravity;
            for _ in 0..substeps {
                self.engine.linear_velocity += h * a;
                self.engine.position += h * self.engine.linear_velocity;
            }
            if close {
                self.engine.position += push.gap(&m, self.engine.rotation, substeps, &self.push).0;
            }
            self.hand_over(upto);
        }

        /// The engine holds the body where it is (it rests on something the device does not
        /// know of) over the records after its frame up to `upto`, and hands its state back
        /// with its steady push when `carry`.
        fn engine_holds(&mut self, upto: u32, carry: bool) {
            let m = model();
            let records: Vec<FrameRecord> = (self.engine_frame + 1..=upto)
                .map(|f| self.device.records[f as usize % RECORDS].unwrap())
                .collect();
            let water = WindowImpulse::over(&records, records.last().unwrap().time_ns);
            let before = self.engine;
            self.engine.linear_velocity = Vec3::ZERO;
            self.engine.angular_velocity = Vec3::ZERO;
            let push = EnginePush::measured(
                &m,
                &before,
                &self.engine,
                water.impulse,
                water.angular_impulse,
                water.duration,
            );
            if carry {
                self.push = push.steadied(&self.push, water.duration);
            }
            self.hand_over(upto);
        }
    }

    fn start() -> RigidState {
        RigidState {
            position: Vec3::new(0.0, 1.0, 0.0),
            rotation: Quat::IDENTITY,
            linear_velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
        }
    }

    /// Water that carries the body's weight: the engine, three frames behind, agrees with the
    /// device, so the device is not moved; the body stays still on both sides.
    #[test]
    fn a_floating_body_needs_no_correction() {
        let mut run = Run::new(start());
        let weight = model().mass * model().gravity;
        for frame in 1..=20u32 {
            run.frame(frame, -weight);
            if frame > 3 {
                run.engine_catches_up(frame - 3, Vec3::ZERO);
            }
        }
        let s = run.device.state.unwrap();
        assert!(s.linear_velocity.length() < 1e-5 && (s.position.y - 1.0).abs() < 1e-5);
        assert!(run.engine.linear_velocity.length() < 1e-5);
        assert_eq!(run.device.resyncs, 0);
    }

    /// A contact the engine saw three frames ago (a push of 0.5 m/s) reaches the device once:
    /// its velocity gains exactly the push, its position the push times the time since, and a
    /// later handover of the same engine does not add it again.
    #[test]
    fn an_engine_push_is_added_once_with_the_time_since() {
        let mut run = Run::new(start());
        let weight = model().mass * model().gravity;
        for frame in 1..=6u32 {
            run.frame(frame, -weight);
        }
        let before = run.device.state.unwrap();
        run.engine_catches_up(3, Vec3::X * 0.5);
        let after = run.device.state.unwrap();
        assert!((after.linear_velocity - before.linear_velocity - Vec3::X * 0.5).length() < 1e-6);
        // Frames 4-6 ended 3 × 16 ms after frame 3.
        assert!((after.position.x - before.position.x - 0.5 * 0.048).abs() < 1e-6);
        for frame in 7..=12u32 {
            run.frame(frame, -weight);
            run.engine_catches_up(frame - 3, Vec3::ZERO);
        }
        let s = run.device.state.unwrap();
        assert!((s.linear_velocity.x - 0.5).abs() < 1e-5, "{s:?}");
        assert!((s.position.x - run.engine.position.x - 0.5 * 0.048).abs() < 1e-5);
        // The same handover again changes nothing.
        let again = run.device;
        run.engine_catches_up(9, Vec3::ZERO);
        assert_eq!(run.device.state, again.state);
    }

    /// Water that carries the body's weight over a frame but unevenly within it (a wave's slap
    /// then nothing): once the engine, three frames behind in six substeps a window, closes the
    /// gap to the device's steps, the handoff leaves the device's body as the water alone moved
    /// it; without closing it the handoff moves the body as if the engine had seen a contact.
    #[test]
    fn an_uneven_push_moves_the_device_only_by_the_water_once_the_gap_is_closed() {
        let weight = model().mass * model().gravity;
        let lifts = [-3.0 * weight, -weight, Vec3::ZERO, Vec3::ZERO];
        let mut alone = Run::new(start());
        for frame in 1..=20u32 {
            alone.frame_varying(frame, lifts);
        }
        let reference = alone.device.state.unwrap();
        for close in [true, false] {
            let mut run = Run::new(start());
            for frame in 1..=20u32 {
                run.frame_varying(frame, lifts);
                if frame > 3 {
                    run.engine_substeps(frame - 3, 6, close);
                }
            }
            let s = run.device.state.unwrap();
            let off = (s.position - reference.position).length();
            if close {
                assert!(off < 1e-5, "closed: {off}");
            } else {
                assert!(off > 1e-3, "not closed: {off}");
            }
            assert!((s.linear_velocity - reference.linear_velocity).length() < 1e-4);
        }
    }

    /// A body resting on something only the engine knows of (a crate on a raft), no water:
    /// with the engine's steady push carried on, the device's body comes to stay where the
    /// engine holds it between the handovers; without it, it falls for the frames the engine's
    /// state takes to come back and is pulled up at every handover.
    #[test]
    fn a_body_resting_in_the_engine_stays_at_rest_on_the_device_with_the_engines_push() {
        for carry in [true, false] {
            let mut run = Run::new(start());
            let mut worst = 0.0f32;
            // 2 s of frames of 16 ms: eight of the push's time constants.
            for frame in 1..=125u32 {
                run.frame(frame, Vec3::ZERO);
                if frame > 3 {
                    run.engine_holds(frame - 3, carry);
                }
                if frame > 100 {
                    let s = run.device.state.unwrap();
                    worst = worst.max((s.position - start().position).length());
                }
            }
            let weight = model().mass * model().gravity;
            if carry {
                // All but e^(−7.8) of the weight taken up.
                assert!((run.push.force + weight).length() < 0.05, "{:?}", run.push);
                assert!(worst < 1e-4, "carried: {worst}");
            } else {
                assert!(worst > 1e-3, "not carried: {worst}");
            }
        }
    }

    /// An engine frame older than the records is taken whole, and counted.
    #[test]
    fn an_engine_state_older_than_the_records_is_taken_whole() {
        let mut run = Run::new(start());
        for frame in 1..=(RECORDS as u32 + 4) {
            run.frame(frame, Vec3::ZERO);
        }
        let handed = EngineState {
            frame: 2,
            origin: Vec3::new(5.0, 0.0, 0.0),
            rotation: Quat::IDENTITY,
            linear_velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
            push: EnginePush::default(),
        };
        run.device.take_engine_state(&model(), &handed, run.time_ns);
        assert_eq!(run.device.resyncs, 1);
        assert_eq!(run.device.state.unwrap().position, Vec3::new(5.0, 0.0, 0.0));
        assert!(run.device.records.iter().all(Option::is_none));
    }
}

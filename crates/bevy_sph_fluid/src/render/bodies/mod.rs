//! The bodies the device moves (`sph_core::bodies`): a dynamic collider with a rigid body
//! ([`crate::api::SphRigidBody`]) advances with the water at every step on the device, and the
//! physics engine's state joins it once a frame. Two stages, one `.rs` + `.wgsl` pair each (the
//! shared words and math in `bodies.wgsl`): [`body_placement`] first in every step, puts each
//! body's collider and boundary samples where the device holds the body; [`body_motion`] last in
//! every step, moves the bodies by the step's force sums and records each frame's end. Without
//! such a body neither is in the list and their buffers are not allocated.

pub mod body_motion;
pub mod body_placement;

use super::plan::VariantKey;
use super::stage::GpuStage;

/// The stages that run before a step's others (the placement), when the scene has moved bodies.
pub fn first_stages(key: &VariantKey) -> Vec<&'static GpuStage> {
    if key.bodies {
        vec![&body_placement::STAGE]
    } else {
        Vec::new()
    }
}

/// The stages that run after a step's others (the motion), when the scene has moved bodies.
pub fn last_stages(key: &VariantKey) -> Vec<&'static GpuStage> {
    if key.bodies {
        vec![&body_motion::STAGE]
    } else {
        Vec::new()
    }
}

#[cfg(test)]
mod tests {
    use sph_core::gpu_layout::{
        GpuBodyInput, GpuBodyRecord, GpuBodyState, GPU_BODY_CONTACT_WORDS, GPU_MOVED_BODIES,
    };
    use std::mem::{offset_of, size_of};

    /// The value of `const NAME: u32 = Nu;` in bodies.wgsl.
    fn word(name: &str) -> usize {
        let wgsl = include_str!("bodies.wgsl");
        let line = wgsl
            .lines()
            .find(|l| l.starts_with(&format!("const {name}: u32 = ")))
            .unwrap_or_else(|| panic!("bodies.wgsl has no {name}"));
        let value = line.rsplit("= ").next().unwrap().trim_end_matches("u;");
        value.parse().unwrap()
    }

    /// bodies.wgsl reads the words where `sph_core::gpu_layout::bodies` puts them.
    #[test]
    fn the_wgsl_words_are_the_rust_layouts() {
        assert_eq!(word("MOVED_BODIES"), GPU_MOVED_BODIES);
        assert_eq!(word("CONTACT_WORDS"), GPU_BODY_CONTACT_WORDS);
        assert_eq!(word("INPUT_WORDS") * 4, size_of::<GpuBodyInput>());
        assert_eq!(word("STATE_WORDS") * 4, size_of::<GpuBodyState>());
        assert_eq!(word("RECORD_WORDS") * 4, size_of::<GpuBodyRecord>());
        assert_eq!(word("RECORDS"), sph_core::bodies::engine_handoff::RECORDS);
        let friction = include_str!("bodies.wgsl")
            .lines()
            .find_map(|l| l.strip_prefix("const BODY_FRICTION: f32 = "))
            .expect("bodies.wgsl has BODY_FRICTION");
        assert_eq!(
            friction.trim_end_matches(';').parse::<f32>().unwrap(),
            sph_core::bodies::solid_contact::BODY_FRICTION
        );
        let inputs = [
            ("IN_MASS", offset_of!(GpuBodyInput, mass)),
            (
                "IN_FREE_TRANSLATION",
                offset_of!(GpuBodyInput, free_translation),
            ),
            (
                "IN_LINEAR_DAMPING",
                offset_of!(GpuBodyInput, linear_damping),
            ),
            ("IN_FREE_ROTATION", offset_of!(GpuBodyInput, free_rotation)),
            (
                "IN_ANGULAR_DAMPING",
                offset_of!(GpuBodyInput, angular_damping),
            ),
            (
                "IN_CENTER_OF_MASS",
                offset_of!(GpuBodyInput, center_of_mass),
            ),
            (
                "IN_HINGE_INVERSE_INERTIA",
                offset_of!(GpuBodyInput, hinge_inverse_inertia),
            ),
            ("IN_HINGE_AXIS", offset_of!(GpuBodyInput, hinge_axis)),
            ("IN_HINGED", offset_of!(GpuBodyInput, hinged)),
            ("IN_HINGE_PIVOT", offset_of!(GpuBodyInput, hinge_pivot)),
            (
                "IN_INVERSE_INERTIA",
                offset_of!(GpuBodyInput, inverse_inertia),
            ),
            ("IN_GRAVITY", offset_of!(GpuBodyInput, gravity)),
            ("IN_ENGINE_FRAME", offset_of!(GpuBodyInput, engine_frame)),
            ("IN_ENGINE_ORIGIN", offset_of!(GpuBodyInput, engine_origin)),
            (
                "IN_ENGINE_ROTATION",
                offset_of!(GpuBodyInput, engine_rotation),
            ),
            (
                "IN_ENGINE_LINEAR_VELOCITY",
                offset_of!(GpuBodyInput, engine_linear_velocity),
            ),
            (
                "IN_HAS_ENGINE_STATE",
                offset_of!(GpuBodyInput, has_engine_state),
            ),
            (
                "IN_ENGINE_ANGULAR_VELOCITY",
                offset_of!(GpuBodyInput, engine_angular_velocity),
            ),
            ("IN_SORTED_ORIGIN", offset_of!(GpuBodyInput, sorted_origin)),
            (
                "IN_SORTED_ROTATION",
                offset_of!(GpuBodyInput, sorted_rotation),
            ),
            ("IN_ENGINE_FORCE", offset_of!(GpuBodyInput, engine_force)),
            ("IN_ENGINE_TORQUE", offset_of!(GpuBodyInput, engine_torque)),
        ];
        let states = [
            ("ST_HELD", offset_of!(GpuBodyState, held)),
            ("ST_ENGINE_FRAME", offset_of!(GpuBodyState, engine_frame)),
            (
                "ST_HAS_ENGINE_FRAME",
                offset_of!(GpuBodyState, has_engine_frame),
            ),
            ("ST_RESYNCS", offset_of!(GpuBodyState, resyncs)),
            ("ST_FRAME", offset_of!(GpuBodyState, frame)),
            (
                "ST_EVALUATIONS_SEEN",
                offset_of!(GpuBodyState, evaluations_seen),
            ),
            ("ST_DURATION", offset_of!(GpuBodyState, duration)),
            ("ST_SUMS_SEEN", offset_of!(GpuBodyState, sums_seen)),
            ("ST_POSITION", offset_of!(GpuBodyState, position)),
            ("ST_ROTATION", offset_of!(GpuBodyState, rotation)),
            (
                "ST_LINEAR_VELOCITY",
                offset_of!(GpuBodyState, linear_velocity),
            ),
            (
                "ST_ANGULAR_VELOCITY",
                offset_of!(GpuBodyState, angular_velocity),
            ),
            ("ST_IMPULSE", offset_of!(GpuBodyState, impulse)),
            (
                "ST_ANGULAR_IMPULSE",
                offset_of!(GpuBodyState, angular_impulse),
            ),
            (
                "ST_IMPULSE_MOMENT",
                offset_of!(GpuBodyState, impulse_moment),
            ),
            ("ST_TIME_MOMENT", offset_of!(GpuBodyState, time_moment)),
            (
                "ST_ANGULAR_IMPULSE_MOMENT",
                offset_of!(GpuBodyState, angular_impulse_moment),
            ),
            ("ST_RECORDS", offset_of!(GpuBodyState, records)),
        ];
        let records = [
            ("REC_FRAME", offset_of!(GpuBodyRecord, frame)),
            ("REC_TIME_LO", offset_of!(GpuBodyRecord, time_ns_lo)),
            ("REC_TIME_HI", offset_of!(GpuBodyRecord, time_ns_hi)),
            ("REC_DURATION", offset_of!(GpuBodyRecord, duration)),
            ("REC_POSITION", offset_of!(GpuBodyRecord, position)),
            ("REC_VALID", offset_of!(GpuBodyRecord, valid)),
            ("REC_ROTATION", offset_of!(GpuBodyRecord, rotation)),
            (
                "REC_LINEAR_VELOCITY",
                offset_of!(GpuBodyRecord, linear_velocity),
            ),
            (
                "REC_ANGULAR_VELOCITY",
                offset_of!(GpuBodyRecord, angular_velocity),
            ),
            ("REC_IMPULSE", offset_of!(GpuBodyRecord, impulse)),
            (
                "REC_ANGULAR_IMPULSE",
                offset_of!(GpuBodyRecord, angular_impulse),
            ),
            (
                "REC_IMPULSE_MOMENT",
                offset_of!(GpuBodyRecord, impulse_moment),
            ),
            ("REC_TIME_MOMENT", offset_of!(GpuBodyRecord, time_moment)),
            (
                "REC_ANGULAR_IMPULSE_MOMENT",
                offset_of!(GpuBodyRecord, angular_impulse_moment),
            ),
        ];
        for (name, bytes) in inputs.into_iter().chain(states).chain(records) {
            assert_eq!(word(name) * 4, bytes, "{name}");
        }
    }
}

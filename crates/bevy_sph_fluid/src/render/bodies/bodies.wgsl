// The bodies the device moves (Rust twins: sph_core::bodies::rigid_step and engine_handoff; the
// words: sph_core::gpu_layout::bodies). Each collider slot has its input (written by the CPU
// every frame) and its state (kept by the device, read back), as 32-bit words in the grid
// arena's `body_words` region: inputs of every slot first, then the states.
#define_import_path sph::bodies

#import sph::bindings::{grid, cell_counts, body_words_at, body_contacts_at}

const MOVED_BODIES: u32 = 31u;
const RECORDS: u32 = 8u;
const INPUT_WORDS: u32 = 64u;
const STATE_WORDS: u32 = 340u;
const RECORD_WORDS: u32 = 36u;
// Coulomb's coefficient between two bodies the device moves (solid_contact::BODY_FRICTION).
const BODY_FRICTION: f32 = 0.5;

// GpuBodyInput's words.
const IN_MASS: u32 = 0u;
const IN_FREE_TRANSLATION: u32 = 1u;
const IN_LINEAR_DAMPING: u32 = 4u;
const IN_FREE_ROTATION: u32 = 5u;
const IN_ANGULAR_DAMPING: u32 = 8u;
const IN_CENTER_OF_MASS: u32 = 9u;
const IN_HINGE_INVERSE_INERTIA: u32 = 12u;
const IN_HINGE_AXIS: u32 = 13u;
const IN_HINGED: u32 = 16u;
const IN_HINGE_PIVOT: u32 = 17u;
const IN_INVERSE_INERTIA: u32 = 20u;
const IN_GRAVITY: u32 = 29u;
const IN_ENGINE_FRAME: u32 = 32u;
const IN_ENGINE_ORIGIN: u32 = 33u;
const IN_ENGINE_ROTATION: u32 = 36u;
const IN_ENGINE_LINEAR_VELOCITY: u32 = 40u;
const IN_HAS_ENGINE_STATE: u32 = 43u;
const IN_ENGINE_ANGULAR_VELOCITY: u32 = 44u;
const IN_SORTED_ORIGIN: u32 = 48u;
const IN_SORTED_ROTATION: u32 = 52u;
const IN_ENGINE_FORCE: u32 = 56u;
const IN_ENGINE_TORQUE: u32 = 60u;

// GpuBodyState's words.
const ST_HELD: u32 = 0u;
const ST_ENGINE_FRAME: u32 = 1u;
const ST_HAS_ENGINE_FRAME: u32 = 2u;
const ST_RESYNCS: u32 = 3u;
const ST_FRAME: u32 = 4u;
const ST_EVALUATIONS_SEEN: u32 = 5u;
const ST_DURATION: u32 = 6u;
const ST_SUMS_SEEN: u32 = 8u;
const ST_POSITION: u32 = 20u;
const ST_ROTATION: u32 = 24u;
const ST_LINEAR_VELOCITY: u32 = 28u;
const ST_ANGULAR_VELOCITY: u32 = 32u;
const ST_IMPULSE: u32 = 36u;
const ST_ANGULAR_IMPULSE: u32 = 40u;
const ST_IMPULSE_MOMENT: u32 = 44u;
const ST_TIME_MOMENT: u32 = 47u;
const ST_ANGULAR_IMPULSE_MOMENT: u32 = 48u;
const ST_RECORDS: u32 = 52u;

// GpuBodyRecord's words.
const REC_FRAME: u32 = 0u;
const REC_TIME_LO: u32 = 1u;
const REC_TIME_HI: u32 = 2u;
const REC_DURATION: u32 = 3u;
const REC_POSITION: u32 = 4u;
const REC_VALID: u32 = 7u;
const REC_ROTATION: u32 = 8u;
const REC_LINEAR_VELOCITY: u32 = 12u;
const REC_ANGULAR_VELOCITY: u32 = 16u;
const REC_IMPULSE: u32 = 20u;
const REC_ANGULAR_IMPULSE: u32 = 24u;
const REC_IMPULSE_MOMENT: u32 = 28u;
const REC_TIME_MOMENT: u32 = 31u;
const REC_ANGULAR_IMPULSE_MOMENT: u32 = 32u;

// Word k of slot's input, of its state, of its record r.
fn input_word(slot: u32, k: u32) -> u32 {
    return body_words_at(slot * INPUT_WORDS + k);
}

fn state_word(slot: u32, k: u32) -> u32 {
    return body_words_at(MOVED_BODIES * INPUT_WORDS + slot * STATE_WORDS + k);
}

fn record_word(slot: u32, r: u32, k: u32) -> u32 {
    return state_word(slot, ST_RECORDS + r * RECORD_WORDS + k);
}

fn word_f32(at: u32) -> f32 {
    return bitcast<f32>(grid[at]);
}

fn word_vec3(at: u32) -> vec3<f32> {
    return vec3<f32>(word_f32(at), word_f32(at + 1u), word_f32(at + 2u));
}

fn word_vec4(at: u32) -> vec4<f32> {
    return vec4<f32>(word_vec3(at), word_f32(at + 3u));
}

fn set_f32(at: u32, v: f32) {
    grid[at] = bitcast<u32>(v);
}

fn set_vec3(at: u32, v: vec3<f32>) {
    set_f32(at, v.x);
    set_f32(at + 1u, v.y);
    set_f32(at + 2u, v.z);
}

fn set_vec4(at: u32, v: vec4<f32>) {
    set_vec3(at, v.xyz);
    set_f32(at + 3u, v.w);
}

// sph_core::bodies::rigid_step::RigidBodyModel.
struct Model {
    mass: f32,
    free_translation: vec3<f32>,
    free_rotation: vec3<f32>,
    center_of_mass: vec3<f32>,
    inverse_inertia: mat3x3<f32>,
    hinged: bool,
    hinge_axis: vec3<f32>,
    hinge_pivot: vec3<f32>,
    hinge_inverse_inertia: f32,
    gravity: vec3<f32>,
    linear_damping: f32,
    angular_damping: f32,
}

// sph_core::bodies::rigid_step::RigidState: centre of mass, orientation (x, y, z, w), velocities.
struct Rigid {
    position: vec3<f32>,
    rotation: vec4<f32>,
    linear_velocity: vec3<f32>,
    angular_velocity: vec3<f32>,
}

// Whether the device moves slot's collider (the CPU gave it a mass).
fn moved(slot: u32) -> bool {
    return word_f32(input_word(slot, IN_MASS)) > 0.0;
}

// Whether the device holds slot's body (the engine's first state arrived).
fn held(slot: u32) -> bool {
    return moved(slot) && grid[state_word(slot, ST_HELD)] != 0u;
}

fn load_model(slot: u32) -> Model {
    let i = input_word(slot, IN_INVERSE_INERTIA);
    return Model(
        word_f32(input_word(slot, IN_MASS)),
        word_vec3(input_word(slot, IN_FREE_TRANSLATION)),
        word_vec3(input_word(slot, IN_FREE_ROTATION)),
        word_vec3(input_word(slot, IN_CENTER_OF_MASS)),
        mat3x3<f32>(word_vec3(i), word_vec3(i + 3u), word_vec3(i + 6u)),
        grid[input_word(slot, IN_HINGED)] != 0u,
        word_vec3(input_word(slot, IN_HINGE_AXIS)),
        word_vec3(input_word(slot, IN_HINGE_PIVOT)),
        word_f32(input_word(slot, IN_HINGE_INVERSE_INERTIA)),
        word_vec3(input_word(slot, IN_GRAVITY)),
        word_f32(input_word(slot, IN_LINEAR_DAMPING)),
        word_f32(input_word(slot, IN_ANGULAR_DAMPING)),
    );
}

// The rigid state whose words start at `at` (the state's or a record's: the same order).
fn load_rigid(position: u32, rotation: u32, linear: u32, angular: u32) -> Rigid {
    return Rigid(word_vec3(position), word_vec4(rotation), word_vec3(linear), word_vec3(angular));
}

fn load_state(slot: u32) -> Rigid {
    return load_rigid(
        state_word(slot, ST_POSITION),
        state_word(slot, ST_ROTATION),
        state_word(slot, ST_LINEAR_VELOCITY),
        state_word(slot, ST_ANGULAR_VELOCITY),
    );
}

fn store_state(slot: u32, s: Rigid) {
    set_vec3(state_word(slot, ST_POSITION), s.position);
    set_vec4(state_word(slot, ST_ROTATION), s.rotation);
    set_vec3(state_word(slot, ST_LINEAR_VELOCITY), s.linear_velocity);
    set_vec3(state_word(slot, ST_ANGULAR_VELOCITY), s.angular_velocity);
}

fn load_record(slot: u32, r: u32) -> Rigid {
    return load_rigid(
        record_word(slot, r, REC_POSITION),
        record_word(slot, r, REC_ROTATION),
        record_word(slot, r, REC_LINEAR_VELOCITY),
        record_word(slot, r, REC_ANGULAR_VELOCITY),
    );
}

fn store_record_state(slot: u32, r: u32, s: Rigid) {
    set_vec3(record_word(slot, r, REC_POSITION), s.position);
    set_vec4(record_word(slot, r, REC_ROTATION), s.rotation);
    set_vec3(record_word(slot, r, REC_LINEAR_VELOCITY), s.linear_velocity);
    set_vec3(record_word(slot, r, REC_ANGULAR_VELOCITY), s.angular_velocity);
}

// q v q⁻¹: v + 2 u × (u × v + w v).
fn rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let t = cross(q.xyz, v) + q.w * v;
    return v + 2.0 * cross(q.xyz, t);
}

fn multiply(a: vec4<f32>, b: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}

fn conjugate(q: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(-q.xyz, q.w);
}

// q + ½ [θ, 0] q, normalised.
fn turned(q: vec4<f32>, theta: vec3<f32>) -> vec4<f32> {
    let du = 0.5 * (q.w * theta + cross(theta, q.xyz));
    let dw = -0.5 * dot(theta, q.xyz);
    let sum = vec4<f32>(q.xyz + du, q.w + dw);
    return sum / sqrt(dot(sum, sum));
}

// The body's origin (the collider's pose).
fn origin(s: Rigid, center_of_mass: vec3<f32>) -> vec3<f32> {
    return s.position - rotate(s.rotation, center_of_mass);
}

// One step of dt under the water's force and moment about the world origin (rigid_step::advance).
fn advance(m: Model, s: Rigid, force: vec3<f32>, moment: vec3<f32>, dt: f32) -> Rigid {
    let angular_decay = 1.0 / (1.0 + dt * m.angular_damping);
    if m.hinged {
        let weight = m.mass * m.gravity;
        let torque = moment - cross(m.hinge_pivot, force) + cross(s.position - m.hinge_pivot, weight);
        let spin = (dot(m.hinge_axis, s.angular_velocity) + dt * m.hinge_inverse_inertia * dot(m.hinge_axis, torque)) * angular_decay;
        let w = spin * m.hinge_axis;
        let q = turned(s.rotation, dt * w);
        let c = m.hinge_pivot + rotate(q, m.center_of_mass);
        return Rigid(c, q, cross(w, c - m.hinge_pivot), w);
    }
    let linear_decay = 1.0 / (1.0 + dt * m.linear_damping);
    let acceleration = force / m.mass + m.gravity;
    let v = (s.linear_velocity + dt * acceleration) * m.free_translation * linear_decay;
    let torque = moment - cross(s.position, force);
    let local = m.inverse_inertia * rotate(conjugate(s.rotation), torque);
    let w = (s.angular_velocity + dt * rotate(s.rotation, local)) * m.free_rotation * angular_decay;
    return Rigid(s.position + dt * v, turned(s.rotation, dt * w), v, w);
}

// `s` with the engine's difference from `record` added, `since` [s] after the record
// (engine_handoff::corrected).
fn corrected(s: Rigid, engine: Rigid, record: Rigid, since: f32) -> Rigid {
    let dv = engine.linear_velocity - record.linear_velocity;
    let dw = engine.angular_velocity - record.angular_velocity;
    let dq = multiply(engine.rotation, conjugate(record.rotation));
    return Rigid(
        s.position + (engine.position - record.position) + since * dv,
        turned(multiply(dq, s.rotation), since * dw),
        s.linear_velocity + dv,
        s.angular_velocity + dw,
    );
}

// The words of slot's contacts in a step (solid_contact::AxisPush).
const CONTACT_WORDS: u32 = 21u;
// Words 0..6: the solids' pushes +x, +y, +z, -x, -y, -z, f32 bits of non-negative values, so
// they order as u32. Words 6..12: their floors of the velocity along +x, +y, +z and along -x,
// -y, -z, as ordered_bits (0: no floor). Words 12..18: the other bodies' pushes, as words 0..6.
// Word 18: the bodies that pushed, a bit per slot. Word 19: the friction's limit, f32 bits (0:
// none). Word 20: the directions the solids and the walls pushed the body along in this step's
// first round (push_directions), for the other bodies' second round.
fn contact_word(slot: u32, k: u32) -> u32 {
    return body_contacts_at(slot * CONTACT_WORDS + k);
}

// The bits of v, ordered as u32 as the values are (negative values' bits reversed, positive
// values' sign set), so an atomicMax keeps the largest value; never 0.
fn ordered_bits(v: f32) -> u32 {
    let b = bitcast<u32>(v);
    if (b & 0x80000000u) != 0u {
        return ~b;
    }
    return b | 0x80000000u;
}

// The value of ordered_bits u; -3.4e38 for 0 (no floor).
fn from_ordered_bits(u: u32) -> f32 {
    if u == 0u {
        return -3.4e38;
    }
    if (u & 0x80000000u) != 0u {
        return bitcast<f32>(u & 0x7fffffffu);
    }
    return bitcast<f32>(~u);
}

// Adds a push by a solid moving at `velocity` (zero for one at rest) to slot's step: the
// largest push and the largest floor per axis and sign.
fn add_push(slot: u32, push: vec3<f32>, velocity: vec3<f32>) {
    for (var a = 0u; a < 3u; a += 1u) {
        if push[a] > 0.0 {
            atomicMax(&cell_counts[contact_word(slot, a)], bitcast<u32>(push[a]));
            atomicMax(&cell_counts[contact_word(slot, a + 6u)], ordered_bits(velocity[a]));
        } else if push[a] < 0.0 {
            atomicMax(&cell_counts[contact_word(slot, a + 3u)], bitcast<u32>(-push[a]));
            atomicMax(&cell_counts[contact_word(slot, a + 9u)], ordered_bits(-velocity[a]));
        }
    }
}

// Adds a push out of `partner`, another body the device moves (its slot), to slot's step
// (solid_contact::BodyPushes::add): the largest push per axis and sign, the partner, and the
// friction's largest limit. Its floor is found once every body has met its solids.
fn add_body_push(slot: u32, push: vec3<f32>, partner: u32, friction_limit: f32) {
    var pushed = false;
    for (var a = 0u; a < 3u; a += 1u) {
        if push[a] > 0.0 {
            atomicMax(&cell_counts[contact_word(slot, 12u + a)], bitcast<u32>(push[a]));
            pushed = true;
        } else if push[a] < 0.0 {
            atomicMax(&cell_counts[contact_word(slot, 15u + a)], bitcast<u32>(-push[a]));
            pushed = true;
        }
    }
    if pushed {
        atomicOr(&cell_counts[contact_word(slot, 18u)], 1u << partner);
    }
    if friction_limit > 0.0 {
        atomicMax(&cell_counts[contact_word(slot, 19u)], bitcast<u32>(friction_limit));
    }
}

// The directions of the pushes as bits: bit a for +axis a, bit 3 + a for -axis a
// (solid_contact::push_directions).
fn push_directions(positive: vec3<f32>, negative: vec3<f32>) -> u32 {
    var bits = 0u;
    for (var a = 0u; a < 3u; a += 1u) {
        bits |= select(0u, 1u << a, positive[a] > 0.0) | select(0u, 1u << (a + 3u), negative[a] > 0.0);
    }
    return bits;
}

// The most friction changes the horizontal velocity of a body of mass m in a step, pushed by
// `push` out of a body of mass m_other (solid_contact::support_friction): `friction` (μ g dt)
// where it rests on the other (a push within 45° of up), the same impulse's share
// m_other / m where the other rests on it (within 45° of down), 0 from the side.
fn support_friction(push: vec3<f32>, friction: f32, m: f32, m_other: f32) -> f32 {
    if push.y * push.y < push.x * push.x + push.z * push.z || push.y == 0.0 {
        return 0.0;
    }
    if push.y > 0.0 {
        return friction;
    }
    return friction * m_other / m;
}

// How far a shape of `kind` and `size` (GpuCollider), turned by q, reaches from its origin along
// the unit world direction e; -1 for a mesh (solid_contact::support).
fn support(kind: u32, size: vec3<f32>, q: vec4<f32>, e: vec3<f32>) -> f32 {
    let d = rotate(conjugate(q), e);
    switch kind {
        case 0u: {
            return dot(abs(d), size);
        }
        case 1u: {
            return size.x;
        }
        case 2u: {
            return abs(d.y) * size.y + size.x;
        }
        case 3u: {
            return abs(d.y) * size.y + size.x * sqrt(max(1.0 - d.y * d.y, 0.0));
        }
        default: {
            return -1.0;
        }
    }
}

// Whether frame a comes after frame b (frame numbers wrap).
fn after(a: u32, b: u32) -> bool {
    return bitcast<i32>(a - b) > 0;
}

// The bodies the device moves, at the end of every step, one thread per collider slot (Rust
// twin: sph_core::bodies::engine_handoff::DeviceBody):
// 1. a new frame (the force sums' stamp) starts its impulse sums and its reading of the sums;
// 2. this step's force and moment: the sums' growth since they were last read, over the force
//    evaluations it spans (the sums are exact 64-bit fixed point, so the difference is too);
// 3. the step: impulse J += F dt, angular impulse += τ_c dt, their moments in time over the
//    frame (engine_window), then rigid_step::advance under the water's force and the engine's
//    push (engine_push: its contacts and joints carried on between its states);
// 4. the engine's state, when newer than the last taken: the first as it is, later ones as
//    their difference from this device's record of their frame (engine_handoff), also added
//    to the newer records; a frame no longer recorded is taken whole and counted;
// 5. after every body's steps 1 to 4 (the barriers of the one workgroup that holds all the
//    slots order the rounds across the bodies), the contacts (sph_core::bodies::solid_contact):
//    first the solids' pushes the placement gathered and the shape's reach past the box's
//    faces, the largest push per axis and sign moving the body and its velocity into a push
//    raised to the solid's; then the other bodies' pushes, from every body's velocity after the
//    first round: the velocity into a push raised to the other body's where that one gives way
//    to nothing, to the pair's common velocity otherwise, friction where one rests on the
//    other, and the faces again (a hinged body's axle holds it); the pushes are cleared for
//    the next step, and the states stored after a last barrier;
// 6. FRAME_END (the frame's last step): the frame's record.
#import sph::bindings::{params, shared_state, grid, colliders, cell_counts}
#import sph::body_reactions::{body_force_unit, body_moment_unit}
#import sph::clock::{step_dt, frozen}
#import sph::bodies::{MOVED_BODIES, RECORDS, Rigid, moved, held, load_model, load_state, store_state, load_record, store_record_state, state_word, input_word, record_word, word_f32, word_vec3, word_vec4, set_f32, set_vec3, advance, corrected, after, rotate, ST_HELD, ST_ENGINE_FRAME, ST_HAS_ENGINE_FRAME, ST_RESYNCS, ST_FRAME, ST_EVALUATIONS_SEEN, ST_DURATION, ST_SUMS_SEEN, ST_IMPULSE, ST_ANGULAR_IMPULSE, ST_IMPULSE_MOMENT, ST_TIME_MOMENT, ST_ANGULAR_IMPULSE_MOMENT, IN_CENTER_OF_MASS, IN_ENGINE_FRAME, IN_ENGINE_ORIGIN, IN_ENGINE_ROTATION, IN_ENGINE_LINEAR_VELOCITY, IN_ENGINE_ANGULAR_VELOCITY, IN_HAS_ENGINE_STATE, REC_FRAME, REC_TIME_LO, REC_TIME_HI, REC_DURATION, REC_VALID, REC_IMPULSE, REC_ANGULAR_IMPULSE, REC_IMPULSE_MOMENT, REC_TIME_MOMENT, REC_ANGULAR_IMPULSE_MOMENT, IN_HINGED, IN_MASS, IN_ENGINE_FORCE, IN_ENGINE_TORQUE, contact_word, from_ordered_bits, support, origin, push_directions}

// A 64-bit two's-complement difference (low, high words) as f32.
fn difference(lo: u32, hi: u32, seen_lo: u32, seen_hi: u32) -> f32 {
    let d_lo = lo - seen_lo;
    let d_hi = hi - seen_hi - select(0u, 1u, lo < seen_lo);
    // Small differences of either sign are one 32-bit word: no cancellation.
    if (d_hi == 0u && d_lo < 0x80000000u) || (d_hi == 0xffffffffu && d_lo >= 0x80000000u) {
        return f32(bitcast<i32>(d_lo));
    }
    return f32(bitcast<i32>(d_hi)) * 4294967296.0 + f32(d_lo);
}

// Seconds from the time (lo, hi) [ns] to now's clock.
fn seconds_since(lo: u32, hi: u32) -> f32 {
    let now_lo = shared_state.clock.time_ns_lo;
    let now_hi = shared_state.clock.time_ns_hi;
    let d_lo = now_lo - lo;
    let d_hi = now_hi - hi - select(0u, 1u, now_lo < lo);
    return f32(d_hi) * 4.294967296 + f32(d_lo) * 1.0e-9;
}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    // One workgroup holds every slot (MOVED_BODIES < WORKGROUP_SIZE), so its barriers order the
    // rounds across the bodies.
    let slot = id.x;
    let moving = slot < MOVED_BODIES && moved(slot);
    if moving {
        advance_body(slot);
    }
    storageBarrier();
    workgroupBarrier();
    // 5. The contacts: the solids and the walls, then the other bodies.
    if moving {
        resolve_solids(slot);
    }
    storageBarrier();
    workgroupBarrier();
    var resolved = Resolved(false, Rigid(vec3<f32>(0.0), vec4<f32>(0.0, 0.0, 0.0, 1.0), vec3<f32>(0.0), vec3<f32>(0.0)));
    if moving {
        resolved = resolve_bodies(slot);
    }
    storageBarrier();
    workgroupBarrier();
    if moving {
        if resolved.changed {
            store_state(slot, resolved.state);
        }
        record_frame(slot);
    }
}

// Steps 1 to 4 of slot's body.
fn advance_body(slot: u32) {
    let model = load_model(slot);
    // 1. The frame being summed.
    let frame = shared_state.body_forces.frame;
    if grid[state_word(slot, ST_FRAME)] != frame {
        grid[state_word(slot, ST_FRAME)] = frame;
        grid[state_word(slot, ST_EVALUATIONS_SEEN)] = 0u;
        set_f32(state_word(slot, ST_DURATION), 0.0);
        set_vec3(state_word(slot, ST_IMPULSE), vec3<f32>(0.0));
        set_vec3(state_word(slot, ST_ANGULAR_IMPULSE), vec3<f32>(0.0));
        set_vec3(state_word(slot, ST_IMPULSE_MOMENT), vec3<f32>(0.0));
        set_f32(state_word(slot, ST_TIME_MOMENT), 0.0);
        set_vec3(state_word(slot, ST_ANGULAR_IMPULSE_MOMENT), vec3<f32>(0.0));
        for (var k = 0u; k < 12u; k += 1u) {
            grid[state_word(slot, ST_SUMS_SEEN + k)] = 0u;
        }
    }
    // 2. The step's force and moment (the body's sums are at body slot + 1).
    let evaluations = atomicLoad(&shared_state.body_forces.evaluations);
    let fresh = evaluations - grid[state_word(slot, ST_EVALUATIONS_SEEN)];
    var sums: array<f32, 6>;
    for (var c = 0u; c < 6u; c += 1u) {
        let k = 2u * ((slot + 1u) * 6u + c);
        let lo = atomicLoad(&shared_state.body_forces.sums[k]);
        let hi = atomicLoad(&shared_state.body_forces.sums[k + 1u]);
        let seen = state_word(slot, ST_SUMS_SEEN + 2u * c);
        sums[c] = difference(lo, hi, grid[seen], grid[seen + 1u]);
        grid[seen] = lo;
        grid[seen + 1u] = hi;
    }
    grid[state_word(slot, ST_EVALUATIONS_SEEN)] = evaluations;
    // 3. The step.
    if held(slot) && fresh > 0u && !frozen() {
        let per = 1.0 / f32(fresh);
        let force = vec3<f32>(sums[0], sums[1], sums[2]) * (body_force_unit() * per);
        let moment = vec3<f32>(sums[3], sums[4], sums[5]) * (body_moment_unit() * per);
        let dt = step_dt();
        let s = load_state(slot);
        let impulse = dt * force;
        let angular = dt * (moment - cross(s.position, force));
        // The step starts `before` into the frame (engine_window's moments).
        let before = word_f32(state_word(slot, ST_DURATION));
        let impulse_at = state_word(slot, ST_IMPULSE);
        let angular_at = state_word(slot, ST_ANGULAR_IMPULSE);
        let moment_at = state_word(slot, ST_IMPULSE_MOMENT);
        let angular_moment_at = state_word(slot, ST_ANGULAR_IMPULSE_MOMENT);
        let time_moment_at = state_word(slot, ST_TIME_MOMENT);
        set_vec3(moment_at, word_vec3(moment_at) + before * impulse);
        set_vec3(angular_moment_at, word_vec3(angular_moment_at) + before * angular);
        set_f32(time_moment_at, word_f32(time_moment_at) + before * dt);
        set_vec3(impulse_at, word_vec3(impulse_at) + impulse);
        set_vec3(angular_at, word_vec3(angular_at) + angular);
        set_f32(state_word(slot, ST_DURATION), before + dt);
        // The engine's push: a force at the centre of mass and a torque about it.
        let push = word_vec3(input_word(slot, IN_ENGINE_FORCE));
        let push_moment = word_vec3(input_word(slot, IN_ENGINE_TORQUE)) + cross(s.position, push);
        store_state(slot, advance(model, s, force + push, moment + push_moment, dt));
    }
    // 4. The engine's state.
    take_engine_state(slot, model.center_of_mass);
}

// 6. The frame's record (FRAME_END).
fn record_frame(slot: u32) {
#ifdef FRAME_END
    if held(slot) {
        let frame = shared_state.body_forces.frame;
        let r = frame % RECORDS;
        grid[record_word(slot, r, REC_FRAME)] = frame;
        grid[record_word(slot, r, REC_TIME_LO)] = shared_state.clock.time_ns_lo;
        grid[record_word(slot, r, REC_TIME_HI)] = shared_state.clock.time_ns_hi;
        set_f32(record_word(slot, r, REC_DURATION), word_f32(state_word(slot, ST_DURATION)));
        grid[record_word(slot, r, REC_VALID)] = 1u;
        store_record_state(slot, r, load_state(slot));
        set_vec3(record_word(slot, r, REC_IMPULSE), word_vec3(state_word(slot, ST_IMPULSE)));
        set_vec3(record_word(slot, r, REC_ANGULAR_IMPULSE), word_vec3(state_word(slot, ST_ANGULAR_IMPULSE)));
        let moment = word_vec3(state_word(slot, ST_IMPULSE_MOMENT));
        let angular_moment = word_vec3(state_word(slot, ST_ANGULAR_IMPULSE_MOMENT));
        set_vec3(record_word(slot, r, REC_IMPULSE_MOMENT), moment);
        set_vec3(record_word(slot, r, REC_ANGULAR_IMPULSE_MOMENT), angular_moment);
        set_f32(record_word(slot, r, REC_TIME_MOMENT), word_f32(state_word(slot, ST_TIME_MOMENT)));
    }
#endif
}

fn take_engine_state(slot: u32, center_of_mass: vec3<f32>) {
    if grid[input_word(slot, IN_HAS_ENGINE_STATE)] == 0u {
        return;
    }
    let engine_frame = grid[input_word(slot, IN_ENGINE_FRAME)];
    let taken = grid[state_word(slot, ST_HAS_ENGINE_FRAME)] != 0u;
    if taken && !after(engine_frame, grid[state_word(slot, ST_ENGINE_FRAME)]) {
        return;
    }
    grid[state_word(slot, ST_ENGINE_FRAME)] = engine_frame;
    grid[state_word(slot, ST_HAS_ENGINE_FRAME)] = 1u;
    let q = word_vec4(input_word(slot, IN_ENGINE_ROTATION));
    let arrived = Rigid(
        word_vec3(input_word(slot, IN_ENGINE_ORIGIN)) + rotate(q, center_of_mass),
        q,
        word_vec3(input_word(slot, IN_ENGINE_LINEAR_VELOCITY)),
        word_vec3(input_word(slot, IN_ENGINE_ANGULAR_VELOCITY)),
    );
    if grid[state_word(slot, ST_HELD)] == 0u {
        store_state(slot, arrived);
        grid[state_word(slot, ST_HELD)] = 1u;
        return;
    }
    let r = engine_frame % RECORDS;
    let recorded = grid[record_word(slot, r, REC_VALID)] != 0u && grid[record_word(slot, r, REC_FRAME)] == engine_frame;
    if !recorded {
        store_state(slot, arrived);
        for (var k = 0u; k < RECORDS; k += 1u) {
            grid[record_word(slot, k, REC_VALID)] = 0u;
        }
        grid[state_word(slot, ST_RESYNCS)] += 1u;
        return;
    }
    let record = load_record(slot, r);
    let lo = grid[record_word(slot, r, REC_TIME_LO)];
    let hi = grid[record_word(slot, r, REC_TIME_HI)];
    store_state(slot, corrected(load_state(slot), arrived, record, seconds_since(lo, hi)));
    for (var k = 0u; k < RECORDS; k += 1u) {
        if grid[record_word(slot, k, REC_VALID)] != 0u && after(grid[record_word(slot, k, REC_FRAME)], engine_frame) {
            // The time from the engine's frame to this newer record's end.
            let since = seconds_since(lo, hi) - seconds_since(grid[record_word(slot, k, REC_TIME_LO)], grid[record_word(slot, k, REC_TIME_HI)]);
            store_record_state(slot, k, corrected(load_record(slot, k), arrived, record, since));
        }
    }
}

// Slot's pushes out of the box's faces at state s: the shape's reach from its origin along
// each axis past the lower faces (up) and the upper ones (down) (solid_contact::box_push).
struct Faces {
    up: vec3<f32>,
    down: vec3<f32>,
}

fn face_pushes(slot: u32, s: Rigid, center_of_mass: vec3<f32>) -> Faces {
    let o = origin(s, center_of_mass);
    var faces = Faces(vec3<f32>(0.0), vec3<f32>(0.0));
    for (var k = 0u; k < params.guard_colliders; k++) {
        if bitcast<u32>(colliders[k].linear_velocity.w) != slot + 1u {
            continue;
        }
        let kind = u32(colliders[k].translation.w);
        let size = colliders[k].size.xyz;
        for (var a = 0u; a < 3u; a += 1u) {
            var e = vec3<f32>(0.0);
            e[a] = 1.0;
            let reach = support(kind, size, s.rotation, e);
            if reach < 0.0 {
                break;
            }
            faces.up[a] = max(faces.up[a], params.box_min[a] - (o[a] - reach));
            faces.down[a] = max(faces.down[a], (o[a] + reach) - params.box_max[a]);
        }
    }
    return faces;
}

// s moved by the faces' pushes, with no velocity into them.
fn moved_by_faces(s: Rigid, faces: Faces) -> Rigid {
    let v = pushed_velocity(s.linear_velocity, faces.up, faces.down, vec3<f32>(0.0), vec3<f32>(0.0));
    return Rigid(s.position + faces.up - faces.down, s.rotation, v, s.angular_velocity);
}

// s moved by the box's faces, with no velocity into them.
fn within_faces(slot: u32, s: Rigid, center_of_mass: vec3<f32>) -> Rigid {
    return moved_by_faces(s, face_pushes(slot, s, center_of_mass));
}

// The first round of slot's contacts (solid_contact::resolve_solids): the solids' pushes the
// placement gathered, then the box's faces (they give way to nothing, so they come last); along
// a push the velocity is raised to the solid's floor (zero for the faces). The directions they
// pushed along are kept for the other bodies' second round; the words are cleared for the
// next step.
fn resolve_solids(slot: u32) {
    var positive = vec3<f32>(0.0);
    var negative = vec3<f32>(0.0);
    var positive_floor = vec3<f32>(0.0);
    var negative_floor = vec3<f32>(0.0);
    for (var a = 0u; a < 3u; a += 1u) {
        positive[a] = bitcast<f32>(atomicExchange(&cell_counts[contact_word(slot, a)], 0u));
        negative[a] = bitcast<f32>(atomicExchange(&cell_counts[contact_word(slot, a + 3u)], 0u));
        positive_floor[a] = from_ordered_bits(atomicExchange(&cell_counts[contact_word(slot, a + 6u)], 0u));
        negative_floor[a] = from_ordered_bits(atomicExchange(&cell_counts[contact_word(slot, a + 9u)], 0u));
    }
    atomicStore(&cell_counts[contact_word(slot, 20u)], 0u);
    if !held(slot) || frozen() || grid[input_word(slot, IN_HINGED)] != 0u {
        return;
    }
    let center_of_mass = word_vec3(input_word(slot, IN_CENTER_OF_MASS));
    let s = load_state(slot);
    let v = pushed_velocity(s.linear_velocity, positive, negative, positive_floor, negative_floor);
    let pushed = Rigid(s.position + positive - negative, s.rotation, v, s.angular_velocity);
    let faces = face_pushes(slot, pushed, center_of_mass);
    let out = moved_by_faces(pushed, faces);
    atomicStore(&cell_counts[contact_word(slot, 20u)], push_directions(positive, negative) | push_directions(faces.up, faces.down));
    if any(out.position != s.position) || any(out.linear_velocity != s.linear_velocity) {
        store_state(slot, out);
    }
}

// A body's state after its contacts, and whether they changed it.
struct Resolved {
    changed: bool,
    state: Rigid,
}

// The second round of slot's contacts (solid_contact::resolve_bodies): the pushes out of the
// other bodies, each partner read after its first round (its state is stored only after the
// barrier that ends this round). Along a push the velocity is raised to the partner's where a
// solid or a face pushed the partner that way (it gives way to nothing), to the pair's common
// velocity otherwise, so the pair's momentum is kept; friction moves the horizontal velocity
// toward the common velocity; the faces come last again. The words are cleared for the next
// step.
fn resolve_bodies(slot: u32) -> Resolved {
    var positive = vec3<f32>(0.0);
    var negative = vec3<f32>(0.0);
    for (var a = 0u; a < 3u; a += 1u) {
        positive[a] = bitcast<f32>(atomicExchange(&cell_counts[contact_word(slot, 12u + a)], 0u));
        negative[a] = bitcast<f32>(atomicExchange(&cell_counts[contact_word(slot, 15u + a)], 0u));
    }
    let partners = atomicExchange(&cell_counts[contact_word(slot, 18u)], 0u);
    let friction_limit = bitcast<f32>(atomicExchange(&cell_counts[contact_word(slot, 19u)], 0u));
    let s = load_state(slot);
    var out = Resolved(false, s);
    if partners == 0u || !held(slot) || frozen() || grid[input_word(slot, IN_HINGED)] != 0u {
        return out;
    }
    let m = word_f32(input_word(slot, IN_MASS));
    var positive_floor = vec3<f32>(-3.4e38);
    var negative_floor = vec3<f32>(-3.4e38);
    var low = vec2<f32>(3.4e38);
    var high = vec2<f32>(-3.4e38);
    for (var p = 0u; p < MOVED_BODIES; p += 1u) {
        if (partners & (1u << p)) == 0u {
            continue;
        }
        let v_p = load_state(p).linear_velocity;
        let m_p = word_f32(input_word(p, IN_MASS));
        let pair_velocity = (s.linear_velocity * m + v_p * m_p) / (m + m_p);
        // Along a direction a solid pushed the partner, it gives way to nothing.
        let supported = atomicLoad(&cell_counts[contact_word(p, 20u)]);
        for (var a = 0u; a < 3u; a += 1u) {
            let up = select(pair_velocity[a], v_p[a], (supported & (1u << a)) != 0u);
            let down = select(pair_velocity[a], v_p[a], (supported & (1u << (a + 3u))) != 0u);
            positive_floor[a] = max(positive_floor[a], up);
            negative_floor[a] = max(negative_floor[a], -down);
        }
        low = min(low, pair_velocity.xz);
        high = max(high, pair_velocity.xz);
    }
    var v = pushed_velocity(s.linear_velocity, positive, negative, positive_floor, negative_floor);
    if friction_limit > 0.0 && low.x <= high.x {
        let horizontal = vec2<f32>(v.x, v.z);
        var rub = clamp(horizontal, low, high) - horizontal;
        let length_rub = length(rub);
        if length_rub > friction_limit {
            rub *= friction_limit / length_rub;
        }
        v.x += rub.x;
        v.z += rub.y;
    }
    let center_of_mass = word_vec3(input_word(slot, IN_CENTER_OF_MASS));
    out.state = within_faces(slot, Rigid(s.position + positive - negative, s.rotation, v, s.angular_velocity), center_of_mass);
    out.changed = any(out.state.position != s.position) || any(out.state.linear_velocity != s.linear_velocity);
    return out;
}

// v raised along each push to its floor (solid_contact::AxisPush::resolve).
fn pushed_velocity(v_in: vec3<f32>, positive: vec3<f32>, negative: vec3<f32>, positive_floor: vec3<f32>, negative_floor: vec3<f32>) -> vec3<f32> {
    var v = v_in;
    for (var a = 0u; a < 3u; a += 1u) {
        if positive[a] > 0.0 {
            v[a] = max(v[a], positive_floor[a]);
        }
        if negative[a] > 0.0 {
            v[a] = min(v[a], -negative_floor[a]);
        }
    }
    return v;
}

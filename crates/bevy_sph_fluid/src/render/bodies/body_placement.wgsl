// The bodies the device moves, placed at the start of every step (Rust twin:
// sph_core::bodies::rigid_step, RigidState's origin and point velocity): each such collider
// takes the device's pose and velocities (for the guard and the contact), and each of its
// boundary samples moves rigidly from where the CPU sorted it (`boundary_rest`, at the pose
// the input names) to the body's pose now, with the body's velocity at that point. The samples
// stay in their sorted cells: the CPU sorts them at the pose it predicts for the frame, so they
// move a small part of h from it (docs/scenes.md, "Bodies on the GPU"). A sample nearer than
// half a spacing (its depth inside its own surface) to a solid the device does not move
// (sph_core::bodies::solid_contact::sample_push) adds its push back to that distance to its
// body's contacts of the step, which the motion pass resolves; a sample nearer than half a
// spacing and g dt² to another body the device moves, at that body's pose of the step (its
// state: this pass moves the colliders' entries), adds its share m_other / (m + m_other) of the
// push back to that distance and names the other body (the motion pass finds the push's floor
// once every body has met its solids) and, where one rests on the other, the friction's limit:
// mu g dt for the upper body, the same impulse for the lower (solid_contact::support_friction).
// A hinged body pushes as a solid at rest. CPU twin: solid_contact::sample_pushes.
#import sph::bindings::{params, grid, boundary_samples, boundary_body, boundary_body_at, colliders, boundary_position_at, boundary_velocity_at, boundary_rest_at}
#import sph::bodies::{MOVED_BODIES, held, load_state, input_word, word_f32, word_vec3, word_vec4, origin, rotate, conjugate, add_push, add_body_push, support_friction, BODY_FRICTION, IN_MASS, IN_CENTER_OF_MASS, IN_SORTED_ORIGIN, IN_SORTED_ROTATION, IN_HINGED}
#import sph::guard::{collider_surface, surface_of}
#import sph::clock::step_dt

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i < params.guard_colliders {
        // The colliders are listed without the empty slots; each names its body (slot + 1).
        let body = bitcast<u32>(colliders[i].linear_velocity.w);
        if body >= 1u && body <= MOVED_BODIES && held(body - 1u) {
            let s = load_state(body - 1u);
            let o = origin(s, word_vec3(input_word(body - 1u, IN_CENTER_OF_MASS)));
            // Only the components: w holds the shape's kind and the body's index as bits.
            colliders[i].translation.x = o.x;
            colliders[i].translation.y = o.y;
            colliders[i].translation.z = o.z;
            colliders[i].rotation = s.rotation;
            let v = s.linear_velocity + cross(s.angular_velocity, o - s.position);
            colliders[i].linear_velocity.x = v.x;
            colliders[i].linear_velocity.y = v.y;
            colliders[i].linear_velocity.z = v.z;
            colliders[i].angular_velocity = vec4<f32>(s.angular_velocity, 0.0);
        }
    }
    if i >= params.boundary_sample_count {
        return;
    }
    let body = boundary_body[boundary_body_at(i)];
    if body == 0u || body > MOVED_BODIES || !held(body - 1u) {
        return;
    }
    let slot = body - 1u;
    let s = load_state(slot);
    let o = origin(s, word_vec3(input_word(slot, IN_CENTER_OF_MASS)));
    let sorted_origin = word_vec3(input_word(slot, IN_SORTED_ORIGIN));
    let sorted_rotation = word_vec4(input_word(slot, IN_SORTED_ROTATION));
    let local = rotate(conjugate(sorted_rotation), boundary_samples[boundary_rest_at(i)].xyz - sorted_origin);
    let x = o + rotate(s.rotation, local);
    let at = boundary_position_at(i);
    boundary_samples[at] = vec4<f32>(x, boundary_samples[at].w);
    let v = s.linear_velocity + cross(s.angular_velocity, x - s.position);
    let v_at = boundary_velocity_at(i);
    boundary_samples[v_at] = vec4<f32>(v, boundary_samples[v_at].w);
    // A hinged body's axle holds it.
    if grid[input_word(slot, IN_HINGED)] != 0u {
        return;
    }
    let m = word_f32(input_word(slot, IN_MASS));
    var push = vec3<f32>(0.0);
    for (var k = 0u; k < params.guard_colliders; k++) {
        let other = bitcast<u32>(colliders[k].linear_velocity.w);
        if other == body {
            continue;
        }
        if other >= 1u && other <= MOVED_BODIES && held(other - 1u) {
            // Another body the device moves, at its pose of the step; a hinged one gives way only
            // about its axle, so it takes none of the push.
            let so = load_state(other - 1u);
            var c = colliders[k];
            let o_other = origin(so, word_vec3(input_word(other - 1u, IN_CENTER_OF_MASS)));
            c.translation = vec4<f32>(o_other, c.translation.w);
            c.rotation = so.rotation;
            // The sample lies half a spacing inside its own surface (the outer layer).
            let margin = 0.5 * params.spacing + length(params.gravity) * step_dt() * step_dt();
            let surface = surface_of(c, x, margin);
            if surface.w < margin {
                let m_other = word_f32(input_word(other - 1u, IN_MASS));
                if grid[input_word(other - 1u, IN_HINGED)] != 0u {
                    add_push(slot, (margin - surface.w) * surface.xyz, vec3<f32>(0.0));
                    continue;
                }
                let out = (margin - surface.w) * m_other / (m + m_other) * surface.xyz;
                let friction = BODY_FRICTION * length(params.gravity) * step_dt();
                add_body_push(slot, out, other - 1u, support_friction(out, friction, m, m_other));
            }
            continue;
        }
        let surface = collider_surface(k, x, 0.5 * params.spacing);
        if surface.w < 0.5 * params.spacing {
            push += (0.5 * params.spacing - surface.w) * surface.xyz;
        }
    }
    if any(push != vec3<f32>(0.0)) {
        add_push(slot, push, vec3<f32>(0.0));
    }
}

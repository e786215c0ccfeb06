// The solids' speculative contact (Rust twin: sph_core::boundary::speculative_contact): the next drift may
// bring a particle no closer than the margin (params.surface_margin, a tenth of a spacing) to
// the exact surface of a collider or of the box. For each surface within reach, taken one after
// another, the velocity the drift starts from, v' = v_c + (a + a_s) dt, may approach it at most
// at (φ - margin)/dt, plus the solid's own speed toward it when it comes on:
// v'·n - max(v_s·n, 0) >= -max(φ - margin, 0)/dt (the Rust twin says why). The excess approach
// is taken away along n (never a push away), and its reaction -m n Δv/dt goes to the surface's
// body at the particle.
#define_import_path sph::speculative_contact

#import sph::bindings::{params, colliders}
#import sph::guard::collider_surface
#import sph::body_reactions::add_reaction

// The acceleration that takes away the approach of v_next to a surface at distance phi with
// outward normal n beyond (phi - margin)/dt, with a solid that comes on at v_solid·n > 0 taken
// along; the drift's velocity takes it times step = κ dt.
fn stopping(phi: f32, n: vec3<f32>, v_solid: vec3<f32>, v_next: vec3<f32>, dt: f32, step: f32) -> vec3<f32> {
    let approach = dot(v_next, n) - max(dot(v_solid, n), 0.0);
    let allowed = -max(phi - params.surface_margin, 0.0) / dt;
    if approach < allowed {
        return n * ((allowed - approach) / step);
    }
    return vec3<f32>(0.0);
}

// The contact's acceleration a_s of a particle at x: v_c the velocity the next drift starts from
// before this evaluation's acceleration a, dt the drift's step, kick the share κ of the
// acceleration the drift's velocity takes (v_c + κ a dt; sph_core::stage::BoundaryContact::
// drift_kick); the reactions go to the bodies when `react` (not for a drained particle).
fn speculative_contact(x: vec3<f32>, v_c: vec3<f32>, a: vec3<f32>, dt: f32, kick: f32, react: bool) -> vec3<f32> {
    let step = kick * dt;
    if !(step > 0.0) {
        return vec3<f32>(0.0);
    }
    let m = params.particle_mass;
    // Farther surfaces cannot be reached by the next drift (twice the reach covers a wedge).
    let reach = params.surface_margin + 2.0 * length(v_c + a * step) * dt;
    var extra = vec3<f32>(0.0);
    // The box's six faces (body 0, the walls).
    let lo = x - params.box_min;
    let hi = params.box_max - x;
    let phis = array<f32, 6>(lo.x, hi.x, lo.y, hi.y, lo.z, hi.z);
    let normals = array<vec3<f32>, 6>(
        vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(-1.0, 0.0, 0.0),
        vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, -1.0, 0.0),
        vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0, 0.0, -1.0),
    );
    for (var f = 0u; f < 6u; f++) {
        if phis[f] < reach {
            let s = stopping(phis[f], normals[f], vec3<f32>(0.0), v_c + (a + extra) * step, dt, step);
            extra += s;
            // Only a stop adds a reaction (each change of body flushes the thread's sum).
            if react && any(s != vec3<f32>(0.0)) {
                add_reaction(0u, s * -m, x);
            }
        }
    }
    for (var k = 0u; k < params.guard_colliders; k++) {
        let surface = collider_surface(k, x, reach);
        if surface.w >= reach {
            continue;
        }
        let c = colliders[k];
        let phi = surface.w;
        let n = surface.xyz;
        let solid = c.linear_velocity.xyz + cross(c.angular_velocity.xyz, x - c.translation.xyz);
        let s = stopping(phi, n, solid, v_c + (a + extra) * step, dt, step);
        extra += s;
        if react && any(s != vec3<f32>(0.0)) {
            add_reaction(bitcast<u32>(c.linear_velocity.w), s * -m, x);
        }
    }
    return extra;
}

// PBF's contact inside its iterations (Rust twin: sph_core::solver::pbf::solid_contact): a
// particle at x nearer than the margin to a face of the box is clamped back to the margin (all
// faces at once: their projections are independent for a box wider than two margins), then one
// nearer to a collider's surface is projected back onto it, x += n (margin - φ), collider after
// collider; each projection δ gives its body `reaction` δ at the particle (the caller's
// -m c / dt², c the projection's share of the step's moves) when `react`.
fn contact_projection(x_in: vec3<f32>, reaction: f32, react: bool) -> vec3<f32> {
    let margin = params.surface_margin;
    var x = clamp(x_in, params.box_min + vec3<f32>(margin), params.box_max - vec3<f32>(margin));
    if react && any(x != x_in) {
        add_reaction(0u, (x - x_in) * reaction, x);
    }
    for (var k = 0u; k < params.guard_colliders; k++) {
        let surface = collider_surface(k, x, margin);
        if surface.w >= margin {
            continue;
        }
        let delta = surface.xyz * (margin - surface.w);
        x += delta;
        if react {
            add_reaction(bitcast<u32>(colliders[k].linear_velocity.w), delta * reaction, x);
        }
    }
    return x;
}

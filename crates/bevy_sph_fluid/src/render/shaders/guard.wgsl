// The last-resort guard (Rust twin: sph_core::guard): a particle found inside a collider after a
// drift is projected onto its surface along the outward normal (central differences of the
// exact signed distance) and loses its velocity into the solid, relative to the solid's; a
// particle beyond the box is clamped by the wall collision. Every correction is counted in the
// clock.
#define_import_path sph::guard

#import sph::bindings::{params, colliders}
#import sph::kernels::{collide, outside_box, PositionVelocity}
#import sph::clock::record_correction

// v rotated by the unit quaternion q.
fn rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

// Signed distance of the local point p to collider shape `kind` of size `s` (negative inside).
fn shape_distance(kind: u32, s: vec3<f32>, p: vec3<f32>) -> f32 {
    switch kind {
        case 0u: {
            let q = abs(p) - s;
            return length(max(q, vec3<f32>(0.0))) + min(max(q.x, max(q.y, q.z)), 0.0);
        }
        case 1u: {
            return length(p) - s.x;
        }
        case 2u: {
            let axis = vec3<f32>(0.0, clamp(p.y, -s.y, s.y), 0.0);
            return length(p - axis) - s.x;
        }
        default: {
            let d = vec2<f32>(length(p.xz) - s.x, abs(p.y) - s.y);
            return min(max(d.x, d.y), 0.0) + length(max(d, vec2<f32>(0.0)));
        }
    }
}

// The guard after a drift to x with velocity v.
fn guard(x_in: vec3<f32>, v_in: vec3<f32>) -> PositionVelocity {
    var x = x_in;
    var v = v_in;
    var corrected = false;
    for (var k = 0u; k < params.flags.w; k++) {
        let c = colliders[k];
        let inverse = vec4<f32>(-c.rotation.xyz, c.rotation.w);
        let local = rotate(inverse, x - c.translation.xyz);
        if dot(local, local) > c.size.w * c.size.w {
            continue;
        }
        let kind = u32(c.translation.w);
        let phi = shape_distance(kind, c.size.xyz, local);
        // A thousandth of the spacing (h / 2) deep before it counts (sph_core::guard::tolerance).
        if phi >= -5e-4 * params.kernel_a.x {
            continue;
        }
        let e = 1e-4 * max(c.size.w, 1e-3);
        let g = vec3<f32>(
            shape_distance(kind, c.size.xyz, local + vec3<f32>(e, 0.0, 0.0)) - shape_distance(kind, c.size.xyz, local - vec3<f32>(e, 0.0, 0.0)),
            shape_distance(kind, c.size.xyz, local + vec3<f32>(0.0, e, 0.0)) - shape_distance(kind, c.size.xyz, local - vec3<f32>(0.0, e, 0.0)),
            shape_distance(kind, c.size.xyz, local + vec3<f32>(0.0, 0.0, e)) - shape_distance(kind, c.size.xyz, local - vec3<f32>(0.0, 0.0, e)),
        );
        var n_local = vec3<f32>(0.0, 1.0, 0.0);
        if dot(g, g) > 0.0 {
            n_local = normalize(g);
        }
        let n = rotate(c.rotation, n_local);
        x += n * -phi;
        let solid = c.linear_velocity.xyz + cross(c.angular_velocity.xyz, x - c.translation.xyz);
        let into = dot(v - solid, n);
        if into < 0.0 {
            v -= n * into;
        }
        corrected = true;
    }
    let outside = outside_box(x);
    if corrected || outside {
        record_correction(outside);
    }
    return collide(x, v);
}

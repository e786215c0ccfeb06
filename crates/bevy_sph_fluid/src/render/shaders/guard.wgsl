// The last-resort guard (Rust twin: sph_core::boundary::guard): a particle found inside a collider after a
// drift is projected onto its surface along the outward normal (central differences of the
// exact signed distance; for a mesh the exact gradient, see `mesh_distance`) and loses its
// velocity into the solid, relative to the solid's; a
// particle beyond the box is clamped by the wall collision. Every correction is counted in the
// clock.
#define_import_path sph::guard

#import sph::bindings::{params, colliders, boundary_samples, meshes_at}
#import sph::kernels::{collide, outside_box, PositionVelocity}
#import sph::clock::record_correction
#import sph::types::GpuCollider

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

// The closest point to p on the triangle (a, b, c), w = its feature: corners 0-2, edges ab, bc,
// ca 3-5, the face 6 (Ericson's region test; Rust twin: sph_core::boundary::trimesh::closest_on_triangle).
fn closest_on_triangle(p: vec3<f32>, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> vec4<f32> {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return vec4<f32>(a, 0.0);
    }
    let bp = p - b;
    let d3 = dot(ab, bp);
    let d4 = dot(ac, bp);
    if d3 >= 0.0 && d4 <= d3 {
        return vec4<f32>(b, 1.0);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return vec4<f32>(a + ab * (d1 / (d1 - d3)), 3.0);
    }
    let cp = p - c;
    let d5 = dot(ab, cp);
    let d6 = dot(ac, cp);
    if d6 >= 0.0 && d5 <= d6 {
        return vec4<f32>(c, 2.0);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return vec4<f32>(a + ac * (d2 / (d2 - d6)), 5.0);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return vec4<f32>(b + (c - b) * w, 4.0);
    }
    let denom = 1.0 / (va + vb + vc);
    return vec4<f32>(a + ab * (vb * denom) + ac * (vc * denom), 6.0);
}

// Squared distance from p to the box of hierarchy node `node` (words from `nodes`).
fn node_distance2(nodes: u32, node: u32, p: vec3<f32>) -> f32 {
    let lo = boundary_samples[meshes_at(nodes + 2u * node)].xyz;
    let hi = boundary_samples[meshes_at(nodes + 2u * node + 1u)].xyz;
    let d = max(max(lo - p, p - hi), vec3<f32>(0.0));
    return dot(d, d);
}

// Signed distance of the local point p to a mesh collider (negative inside) and the outward
// normal there, as (normal, distance): the hierarchy walked nearer child first with a fixed
// stack, the sign from the closest feature's angle-weighted pseudo-normal when closed
// (half_thickness < 0), |x - c| - t/2 for an open shell. Rust twin:
// sph_core::boundary::trimesh::TriMesh::distance_and_normal.
fn mesh_distance(nodes: u32, tris: u32, half_thickness: f32, p: vec3<f32>) -> vec4<f32> {
    var stack: array<u32, 32>;
    var top = 1u;
    stack[0] = 0u;
    var best_d2 = 3.4e38;
    var best_point = vec3<f32>(0.0);
    var best_tri = 0u;
    var best_feature = 6u;
    while top > 0u {
        top -= 1u;
        let node = stack[top];
        if node_distance2(nodes, node, p) >= best_d2 {
            continue;
        }
        let first = bitcast<u32>(boundary_samples[meshes_at(nodes + 2u * node)].w);
        let count = bitcast<u32>(boundary_samples[meshes_at(nodes + 2u * node + 1u)].w);
        if count > 0u {
            for (var k = first; k < first + count; k++) {
                let t = tris + 10u * k;
                let c = closest_on_triangle(p, boundary_samples[meshes_at(t)].xyz, boundary_samples[meshes_at(t + 1u)].xyz, boundary_samples[meshes_at(t + 2u)].xyz);
                let d2 = dot(p - c.xyz, p - c.xyz);
                if d2 < best_d2 {
                    best_d2 = d2;
                    best_point = c.xyz;
                    best_tri = k;
                    best_feature = u32(c.w);
                }
            }
            continue;
        }
        let da = node_distance2(nodes, first, p);
        let db = node_distance2(nodes, first + 1u, p);
        var near = first;
        var far = first + 1u;
        if da > db {
            near = first + 1u;
            far = first;
        }
        if top + 2u <= 32u {
            stack[top] = far;
            stack[top + 1u] = near;
            top += 2u;
        }
    }
    let t = tris + 10u * best_tri;
    let pseudo = boundary_samples[meshes_at(t + 3u + best_feature)].xyz;
    let offset = p - best_point;
    let d = length(offset);
    if half_thickness < 0.0 {
        var sign = 1.0;
        if dot(offset, pseudo) < 0.0 {
            sign = -1.0;
        }
        var n = pseudo;
        if d > 1e-7 {
            n = sign * offset / d;
        }
        return vec4<f32>(n, sign * d);
    }
    var n = boundary_samples[meshes_at(t + 9u)].xyz;
    if d > 1e-7 {
        n = offset / d;
    }
    return vec4<f32>(n, d - half_thickness);
}

// Collider k's surface seen from the world point x when it is closer than `reach`: (outward
// normal in the world, signed distance, negative inside); beyond, (0, 1, 0, 3.4e38), found
// without a distance where the bounding sphere or a mesh's root box is farther. The normal: a
// mesh's exact gradient, central differences of a primitive's exact distance. Used by the guard
// (reach: minus its tolerance) and the speculative contact (shaders/speculative_contact.wgsl).
fn collider_surface(k: u32, x: vec3<f32>, reach: f32) -> vec4<f32> {
    return surface_of(colliders[k], x, reach);
}

// collider_surface of the collider c, at whatever pose it holds (the bodies' placement asks at a
// moved body's pose of the step, bodies/body_placement.wgsl).
fn surface_of(c: GpuCollider, x: vec3<f32>, reach: f32) -> vec4<f32> {
    let far = vec4<f32>(0.0, 1.0, 0.0, 3.4e38);
    let inverse = vec4<f32>(-c.rotation.xyz, c.rotation.w);
    let local = rotate(inverse, x - c.translation.xyz);
    let bound = max(c.size.w + reach, 0.0);
    if dot(local, local) > bound * bound {
        return far;
    }
    let kind = u32(c.translation.w);
    var phi: f32;
    var n_local = vec3<f32>(0.0, 1.0, 0.0);
    if kind == 4u {
        // Beyond the root box by more than the reach (and an open shell's half thickness).
        let box_reach = max(max(c.size.z, 0.0) + reach, 0.0);
        if node_distance2(bitcast<u32>(c.size.x), 0u, local) > box_reach * box_reach {
            return far;
        }
        let m = mesh_distance(bitcast<u32>(c.size.x), bitcast<u32>(c.size.y), c.size.z, local);
        phi = m.w;
        n_local = m.xyz;
    } else {
        phi = shape_distance(kind, c.size.xyz, local);
        if phi >= reach {
            return far;
        }
        let e = 1e-4 * max(c.size.w, 1e-3);
        let g = vec3<f32>(
            shape_distance(kind, c.size.xyz, local + vec3<f32>(e, 0.0, 0.0)) - shape_distance(kind, c.size.xyz, local - vec3<f32>(e, 0.0, 0.0)),
            shape_distance(kind, c.size.xyz, local + vec3<f32>(0.0, e, 0.0)) - shape_distance(kind, c.size.xyz, local - vec3<f32>(0.0, e, 0.0)),
            shape_distance(kind, c.size.xyz, local + vec3<f32>(0.0, 0.0, e)) - shape_distance(kind, c.size.xyz, local - vec3<f32>(0.0, 0.0, e)),
        );
        if dot(g, g) > 0.0 {
            n_local = normalize(g);
        }
    }
    if phi >= reach {
        return far;
    }
    return vec4<f32>(rotate(c.rotation, n_local), phi);
}

// The guard after a drift to x with velocity v.
fn guard(x_in: vec3<f32>, v_in: vec3<f32>) -> PositionVelocity {
    var x = x_in;
    var v = v_in;
    var corrected = false;
    // A thousandth of the spacing (h / 2) deep before it counts (sph_core::boundary::guard::tolerance).
    let tolerance = 5e-4 * params.h;
    for (var k = 0u; k < params.guard_colliders; k++) {
        let surface = collider_surface(k, x, -tolerance);
        if surface.w >= -tolerance {
            continue;
        }
        let c = colliders[k];
        let n = surface.xyz;
        let phi = surface.w;
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

// Sphere impostors, one camera-facing quad per live particle slot drawn straight from the
// simulation's position buffer, and the exact ray-sphere intersection each fragment needs.
#define_import_path bevy_sph_fluid::surface_impostor

#import bevy_sph_fluid::surface_types::SurfaceUniform

@group(0) @binding(0) var<uniform> surface: SurfaceUniform;
@group(0) @binding(1) var<storage, read> positions: array<vec4<f32>>;

struct ImpostorVarying {
    @builtin(position) clip: vec4<f32>,
    // The quad's point, view space.
    @location(0) on_quad: vec3<f32>,
    // The sphere's centre, view space.
    @location(1) @interpolate(flat) center: vec3<f32>,
}

// The quad of `slot`'s sphere: square, perpendicular to the line of sight to the centre and
// moved toward the eye by one radius, so that it covers the sphere's outline (whose radius in
// that plane is r (d - r) / sqrt(d^2 - r^2) < r). Slots past the live count are culled.
fn impostor_vertex(vertex: u32, slot: u32) -> ImpostorVarying {
    return billboard_vertex(vertex, slot, surface.particle_count, surface.sphere_radius);
}

// The same quad for a sphere of radius `r` at `positions[slot]`, of `count` live slots.
fn billboard_vertex(vertex: u32, slot: u32, count: u32, r: f32) -> ImpostorVarying {
    var out: ImpostorVarying;
    if slot >= count {
        out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
        return out;
    }
    let corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let center = (surface.view_from_world * vec4<f32>(positions[slot].xyz, 1.0)).xyz;
    var toward_eye = vec3<f32>(0.0, 0.0, 1.0);
    if surface.orthographic == 0u {
        toward_eye = -normalize(center);
    }
    var across = cross(toward_eye, vec3<f32>(0.0, 1.0, 0.0));
    if dot(across, across) < 1e-8 {
        across = vec3<f32>(1.0, 0.0, 0.0);
    }
    across = normalize(across);
    let up = cross(across, toward_eye);
    let corner = corners[vertex % 6u];
    let on_quad = center + r * (toward_eye + corner.x * across + corner.y * up);
    out.clip = surface.clip_from_view * vec4<f32>(on_quad, 1.0);
    out.on_quad = on_quad;
    out.center = center;
    return out;
}

// The ray from the eye through a quad point: origin and unit direction, view space.
struct Ray {
    origin: vec3<f32>,
    direction: vec3<f32>,
}

fn eye_ray(on_quad: vec3<f32>) -> Ray {
    if surface.orthographic == 1u {
        return Ray(vec3<f32>(on_quad.xy, 0.0), vec3<f32>(0.0, 0.0, -1.0));
    }
    return Ray(vec3<f32>(0.0), normalize(on_quad));
}

// Where the ray enters the sphere (t of the nearer root) and the chord's length inside it;
// the chord is negative when the ray misses.
struct Hit {
    t: f32,
    chord: f32,
}

fn hit_sphere(ray: Ray, center: vec3<f32>) -> Hit {
    let to_origin = ray.origin - center;
    let b = dot(ray.direction, to_origin);
    let c = dot(to_origin, to_origin) - surface.sphere_radius * surface.sphere_radius;
    let discriminant = b * b - c;
    if discriminant < 0.0 {
        return Hit(0.0, -1.0);
    }
    let half_chord = sqrt(discriminant);
    return Hit(-b - half_chord, 2.0 * half_chord);
}

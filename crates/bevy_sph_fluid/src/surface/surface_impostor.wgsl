// Sphere impostors, one camera-facing triangle per live particle slot drawn straight from the
// simulation's position buffer, and the exact ray-sphere intersection each fragment needs. A
// pass draws 3 vertices per slot in one instance: vertex v is corner v % 3 of slot v / 3. Not
// one instance per slot: a software rasteriser (lavapipe) runs its vertex pipeline once per
// instance, which cost about 1 us per particle whatever the vertices.
#define_import_path bevy_sph_fluid::surface_impostor

#import bevy_sph_fluid::surface_types::SurfaceUniform

@group(0) @binding(0) var<uniform> surface: SurfaceUniform;
@group(0) @binding(1) var<storage, read> positions: array<vec4<f32>>;

const SQRT_3: f32 = 1.7320508;

struct ImpostorVarying {
    @builtin(position) clip: vec4<f32>,
    // The billboard's point, view space.
    @location(0) on_billboard: vec3<f32>,
    // The sphere's centre, view space.
    @location(1) @interpolate(flat) center: vec3<f32>,
}

// The billboard of `slot`'s sphere: an equilateral triangle, perpendicular to the line of sight
// to the centre and moved toward the eye by one radius, whose inscribed circle of radius r covers
// the sphere's outline in that plane (of radius r (d - r) / sqrt(d^2 - r^2) < r). One triangle,
// not a quad's two: half the vertices and triangles to set up, for a larger area (3 sqrt(3) r^2
// against 4 r^2) whose fragments outside the outline are discarded. Slots past the live count
// are culled.
fn impostor_vertex(vertex: u32) -> ImpostorVarying {
    return billboard_vertex(vertex, surface.particle_count, surface.sphere_radius);
}

// The slot whose billboard vertex `vertex` is a corner of.
fn billboard_slot(vertex: u32) -> u32 {
    return vertex / 3u;
}

// The same billboard for a sphere of radius `r` at `positions[billboard_slot(vertex)]`, of
// `count` live slots.
fn billboard_vertex(vertex: u32, count: u32, r: f32) -> ImpostorVarying {
    var out: ImpostorVarying;
    let slot = billboard_slot(vertex);
    if slot >= count {
        out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
        return out;
    }
    // At twice the inradius from the centre, 120 degrees apart.
    let corners = array<vec2<f32>, 3>(
        vec2<f32>(0.0, 2.0), vec2<f32>(-SQRT_3, -1.0), vec2<f32>(SQRT_3, -1.0),
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
    let corner = corners[vertex % 3u];
    let on_billboard = center + r * (toward_eye + corner.x * across + corner.y * up);
    out.clip = surface.clip_from_view * vec4<f32>(on_billboard, 1.0);
    out.on_billboard = on_billboard;
    out.center = center;
    return out;
}

// The ray from the eye through a billboard's point: origin and unit direction, view space.
struct Ray {
    origin: vec3<f32>,
    direction: vec3<f32>,
}

fn eye_ray(on_billboard: vec3<f32>) -> Ray {
    if surface.orthographic == 1u {
        return Ray(vec3<f32>(on_billboard.xy, 0.0), vec3<f32>(0.0, 0.0, -1.0));
    }
    return Ray(vec3<f32>(0.0), normalize(on_billboard));
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

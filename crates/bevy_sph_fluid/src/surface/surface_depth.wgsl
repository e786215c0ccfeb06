// Depth pass: the nearest sphere's view-space distance at every pixel of the scaled target
// (depth-tested, reverse z like Bevy's views), 0 where no water is.

#import bevy_sph_fluid::surface_impostor::{impostor_vertex, eye_ray, hit_sphere, surface, ImpostorVarying}

@vertex
fn vertex(@builtin(vertex_index) vertex: u32) -> ImpostorVarying {
    return impostor_vertex(vertex);
}

struct DepthOutput {
    @location(0) distance: f32,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn fragment(in: ImpostorVarying) -> DepthOutput {
    let ray = eye_ray(in.on_billboard);
    let hit = hit_sphere(ray, in.center);
    if hit.chord < 0.0 {
        discard;
    }
    let point = ray.origin + hit.t * ray.direction;
    let clip = surface.clip_from_view * vec4<f32>(point, 1.0);
    var out: DepthOutput;
    out.distance = -point.z;
    out.depth = clamp(clip.z / clip.w, 0.0, 1.0);
    return out;
}

// Whitewater pass: every diffuse particle (Ihmsen et al. 2012) a soft, view-facing disc, its
// weight added to its class's channel (spray r, foam g, bubbles b) and, for spray and foam, its
// weight times its distance along the view axis to a (their mean depth is a / (r + g)). The
// composite lays foam and spray over the lit water and bubbles under it.

#import bevy_sph_fluid::surface_impostor::{billboard_slot, billboard_vertex, eye_ray, surface, positions, ImpostorVarying}

struct WhitewaterVarying {
    @builtin(position) clip: vec4<f32>,
    @location(0) on_billboard: vec3<f32>,
    @location(1) @interpolate(flat) center: vec3<f32>,
    // 0 spray, 1 foam, 2 bubble.
    @location(2) @interpolate(flat) kind: u32,
}

@vertex
fn vertex(@builtin(vertex_index) vertex: u32) -> WhitewaterVarying {
    var out: WhitewaterVarying;
    let slot = billboard_slot(vertex);
    // An empty slot of the GPU's pool (w < 0) draws nothing.
    if slot < surface.diffuse_count && positions[slot].w < 0.0 {
        out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
        return out;
    }
    let billboard = billboard_vertex(vertex, surface.diffuse_count, surface.diffuse_radius);
    out.clip = billboard.clip;
    out.on_billboard = billboard.on_billboard;
    out.center = billboard.center;
    out.kind = 0u;
    if slot < surface.diffuse_count {
        out.kind = min(u32(positions[slot].w + 0.5), 2u);
    }
    return out;
}

@fragment
fn fragment(in: WhitewaterVarying) -> @location(0) vec4<f32> {
    // The ray's closest approach to the centre, over the radius: 0 at the centre, 1 at the rim.
    let ray = eye_ray(in.on_billboard);
    let to_center = in.center - ray.origin;
    let along = dot(to_center, ray.direction);
    let off_axis = length(to_center - along * ray.direction) / surface.diffuse_radius;
    if off_axis >= 1.0 {
        discard;
    }
    // A smooth disc, 1 at the centre falling to 0 at the rim.
    let weight = (1.0 - off_axis * off_axis) * (1.0 - off_axis * off_axis);
    let depth = -in.center.z;
    switch in.kind {
        case 0u: {
            return vec4<f32>(weight, 0.0, 0.0, weight * depth);
        }
        case 1u: {
            return vec4<f32>(0.0, weight, 0.0, weight * depth);
        }
        default: {
            return vec4<f32>(0.0, 0.0, weight, 0.0);
        }
    }
}

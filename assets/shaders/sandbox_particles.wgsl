// Sphere impostors drawn straight from the simulation's GPU buffers: one camera-facing quad per
// particle slot, positioned from `positions[index]` (the mesh carries only the corner and the
// index), shaded as a sphere and coloured by density, speed, pressure or neighbour count, or
// (the whitewater's diffuse particles) by class.
#import bevy_pbr::mesh_view_bindings::view
#import bevy_pbr::view_transformations::position_world_to_clip

struct ParticleDraw {
    count: u32,
    color_mode: u32,
    radius: f32,
    rest_density: f32,
    max_speed: f32,
    pad_a: f32,
    pad_b: f32,
    pad_c: f32,
}

@group(#{MATERIAL_BIND_GROUP}) @binding(0) var<storage, read> positions: array<vec4<f32>>;
@group(#{MATERIAL_BIND_GROUP}) @binding(1) var<storage, read> velocities: array<vec4<f32>>;
@group(#{MATERIAL_BIND_GROUP}) @binding(2) var<storage, read> densities: array<f32>;
@group(#{MATERIAL_BIND_GROUP}) @binding(3) var<uniform> draw: ParticleDraw;
@group(#{MATERIAL_BIND_GROUP}) @binding(4) var<storage, read> neighbor_counts: array<u32>;

struct Vertex {
    // xy: quad corner in [-1, 1]
    @location(0) corner: vec3<f32>,
    // x: particle slot
    @location(2) slot: vec2<f32>,
}

struct VertexOutput {
    @builtin(position) clip: vec4<f32>,
    @location(0) corner: vec2<f32>,
    @location(1) color: vec3<f32>,
}

const PALE: vec3<f32> = vec3<f32>(0.72, 0.86, 1.0);
const STRONG: vec3<f32> = vec3<f32>(0.02, 0.2, 0.85);

@vertex
fn vertex(v: Vertex) -> VertexOutput {
    var out: VertexOutput;
    let i = u32(v.slot.x + 0.5);
    // Unused slot, or an empty one of the GPU's whitewater pool (w < 0).
    if i >= draw.count || (draw.color_mode == 4u && positions[i].w < 0.0) {
        // A degenerate triangle outside the clip volume.
        out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
        return out;
    }
    let center = positions[i].xyz;
    let right = view.world_from_view[0].xyz;
    let up = view.world_from_view[1].xyz;
    let world = center + (right * v.corner.x + up * v.corner.y) * draw.radius;
    out.clip = position_world_to_clip(world);
    out.corner = v.corner.xy;
    if draw.color_mode == 4u {
        // The whitewater's diffuse particles, by class in w: spray, foam, bubbles.
        let classes = array<vec3<f32>, 3>(
            vec3<f32>(1.0, 1.0, 1.0), vec3<f32>(0.9, 0.95, 1.0), vec3<f32>(0.55, 0.8, 1.0),
        );
        out.color = classes[min(u32(positions[i].w + 0.5), 2u)];
        return out;
    }
    var t: f32;
    if draw.color_mode == 1u {
        t = length(velocities[i].xyz) / draw.max_speed;
    } else if draw.color_mode == 3u {
        // About 32 neighbours in the bulk at h = 2 spacings.
        t = f32(neighbor_counts[i]) / 40.0;
    } else if draw.color_mode == 2u {
        let ratio = densities[i] / draw.rest_density;
        let r2 = ratio * ratio;
        t = (r2 * r2 * r2 * ratio - 1.0) * 2.0;
    } else {
        // Free-surface particles have about half the rest density; the bulk is near rest.
        t = (densities[i] / draw.rest_density - 0.5) / 0.52;
    }
    out.color = mix(PALE, STRONG, clamp(t, 0.0, 1.0));
    return out;
}

@fragment
fn fragment(in: VertexOutput) -> @location(0) vec4<f32> {
    let r2 = dot(in.corner, in.corner);
    if r2 > 1.0 {
        discard;
    }
    let normal = vec3<f32>(in.corner, sqrt(1.0 - r2));
    let light = normalize(vec3<f32>(0.4, 0.6, 0.7));
    let shade = 0.45 + 0.55 * max(dot(normal, light), 0.0);
    return vec4<f32>(in.color * shade, 1.0);
}

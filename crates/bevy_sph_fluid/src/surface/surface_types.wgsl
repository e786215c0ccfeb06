// The surface's uniform block (`GpuSurfaceUniform` in view.rs) and the geometry every surface
// pass shares: view-space positions from the fluid depth, rays through a pixel.
#define_import_path bevy_sph_fluid::surface_types

struct SurfaceUniform {
    clip_from_view: mat4x4<f32>,
    view_from_clip: mat4x4<f32>,
    view_from_world: mat4x4<f32>,
    // Absorption per metre (rgb).
    absorption: vec4<f32>,
    // Sky colour (linear rgb).
    sky_color: vec4<f32>,
    // Colour of deep water, what the absorbed light tends to (linear rgb).
    deep_color: vec4<f32>,
    // Toward the sun in view space (xyz), w = specular strength.
    sun_direction: vec4<f32>,
    // View to world space.
    world_from_view: mat4x4<f32>,
    // The container's lower corner (xyz), w = 1 when there is one.
    container_min: vec4<f32>,
    // Its upper corner (xyz), w = how near a wall the water touches it [m].
    container_max: vec4<f32>,
    // Scaled depth/thickness targets [pixels].
    target_size: vec2<f32>,
    // The view [pixels], and its top-left corner in the render target.
    view_size: vec2<f32>,
    view_origin: vec2<f32>,
    // Live diffuse particles (whitewater) and their billboards' radius [m].
    diffuse_count: u32,
    diffuse_radius: f32,
    particle_count: u32,
    sphere_radius: f32,
    filter_radius: f32,
    filter_max_pixels: f32,
    depth_range: f32,
    refraction_strength: f32,
    orthographic: u32,
    // Water volume per sphere volume: summed chords times this is the water's thickness.
    chord_weight: f32,
    // 0 = the lit surface, 1 depth, 2 thickness, 3 normals, 4 whitewater (SphSurfaceDebugView).
    debug_view: u32,
}

// The view-space point of normalized device coordinates `ndc` at clip depth `z`.
fn unproject(surface: SurfaceUniform, ndc: vec2<f32>, z: f32) -> vec3<f32> {
    let p = surface.view_from_clip * vec4<f32>(ndc, z, 1.0);
    return p.xyz / p.w;
}

// Normalized device coordinates of the centre of `pixel` in a target of `size` pixels.
fn pixel_ndc(pixel: vec2<f32>, size: vec2<f32>) -> vec2<f32> {
    let uv = pixel / size;
    return vec2<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0);
}

// The view-space point at distance `depth` along the view axis (-z) on the ray through `ndc`:
// two points of the ray from the inverse projection (reverse z: 1 is the near plane), then the
// one at z = -depth. Perspective and orthographic alike.
fn view_position(surface: SurfaceUniform, ndc: vec2<f32>, depth: f32) -> vec3<f32> {
    let near = unproject(surface, ndc, 1.0);
    let farther = unproject(surface, ndc, 0.5);
    let t = (-depth - near.z) / (farther.z - near.z);
    return near + t * (farther - near);
}

// Pixels of the scaled target per metre, across the view, at distance `depth`.
fn pixels_per_metre(surface: SurfaceUniform, depth: f32) -> f32 {
    let scale = surface.clip_from_view[1][1] * 0.5 * surface.target_size.y;
    if surface.orthographic == 1u {
        return scale;
    }
    return scale / max(depth, 1e-6);
}

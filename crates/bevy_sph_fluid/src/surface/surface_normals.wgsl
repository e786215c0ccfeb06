// Normals pass: the smoothed fluid depth's view-space normal at every pixel of the scaled
// target, from screen-space differences of the reconstructed positions, taking on each axis the
// smaller one-sided difference (van der Laan et al. 2009 sec. 4) so that silhouettes do not
// bend it. Written as xyz = normal (facing the eye), w = 1 where there is water and 0 elsewhere,
// for the composite to sample bilinearly.

#import bevy_sph_fluid::surface_types::{SurfaceUniform, pixel_ndc, view_position}

@group(0) @binding(0) var<uniform> surface: SurfaceUniform;
@group(0) @binding(1) var fluid_depth: texture_2d<f32>;

fn depth_at(pixel: vec2<i32>) -> f32 {
    let last = vec2<i32>(surface.target_size) - vec2<i32>(1);
    return textureLoad(fluid_depth, clamp(pixel, vec2<i32>(0), last), 0).r;
}

fn position_at(pixel: vec2<i32>, depth: f32) -> vec3<f32> {
    return view_position(surface, pixel_ndc(vec2<f32>(pixel) + 0.5, surface.target_size), depth);
}

// The difference toward the neighbour on the side whose depth is closer to this pixel's; a
// side without water is not used, and with none on either side there is no difference (a
// one-pixel strand then faces the eye).
fn difference(pixel: vec2<i32>, here: vec3<f32>, step: vec2<i32>) -> vec3<f32> {
    let ahead_depth = depth_at(pixel + step);
    let behind_depth = depth_at(pixel - step);
    let ahead = position_at(pixel + step, ahead_depth) - here;
    let behind = here - position_at(pixel - step, behind_depth);
    if ahead_depth <= 0.0 && behind_depth <= 0.0 {
        return vec3<f32>(0.0);
    }
    if ahead_depth <= 0.0 {
        return behind;
    }
    if behind_depth <= 0.0 || abs(ahead.z) < abs(behind.z) {
        return ahead;
    }
    return behind;
}

@fragment
fn fragment(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(position.xy);
    let depth = depth_at(pixel);
    if depth <= 0.0 {
        return vec4<f32>(0.0);
    }
    let here = position_at(pixel, depth);
    var normal = cross(difference(pixel, here, vec2<i32>(1, 0)), difference(pixel, here, vec2<i32>(0, 1)));
    if dot(normal, normal) < 1e-20 {
        // A lone pixel: face the eye.
        normal = -here;
    }
    normal = normalize(normal);
    // Toward the eye: the view axis for orthographic views, the pixel's ray otherwise.
    var to_eye = vec3<f32>(0.0, 0.0, 1.0);
    if surface.orthographic == 0u {
        to_eye = -here;
    }
    if dot(normal, to_eye) < 0.0 {
        normal = -normal;
    }
    return vec4<f32>(normal, 1.0);
}

// Composite: the water surface over the view's colour, before tonemapping. Per pixel of the
// view: the scaled targets' normal (bilinear: its w is the water's coverage) and thickness; the
// scene behind refracted along the normal by the thickness; Beer-Lambert absorption toward the
// deep-water colour over the thickness; Fresnel (Schlick, F0 = 0.02) reflection of the sky; a
// Blinn-Phong highlight of the sun (van der Laan, Green & Sainz 2009). Opaque geometry nearer
// than the water (the view's depth) hides it.

#import bevy_sph_fluid::surface_types::{SurfaceUniform, unproject, pixel_ndc}

@group(0) @binding(0) var<uniform> surface: SurfaceUniform;
@group(0) @binding(1) var scene_color: texture_2d<f32>;
@group(0) @binding(2) var linear_sampler: sampler;
@group(0) @binding(3) var fluid_depth: texture_2d<f32>;
@group(0) @binding(4) var normals: texture_2d<f32>;
@group(0) @binding(5) var thickness: texture_2d<f32>;
#ifdef MULTISAMPLED_DEPTH
@group(0) @binding(6) var scene_depth: texture_depth_multisampled_2d;
#else
@group(0) @binding(6) var scene_depth: texture_depth_2d;
#endif

// Water reflects about 2 % of the light at normal incidence.
const WATER_F0: f32 = 0.02;
const SHININESS: f32 = 256.0;

@fragment
fn fragment(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    // Exact texel loads where there is no water: most of the view, so the cheapest path.
    let behind_water = textureLoad(scene_color, vec2<i32>(position.xy), 0);
    // Pixels outside this camera's viewport (another camera's) stay as they are.
    let in_view = position.xy - surface.view_origin;
    if any(in_view < vec2<f32>(0.0)) || any(in_view >= surface.view_size) {
        return behind_water;
    }
    let uv = in_view / surface.view_size;
    let last = vec2<i32>(surface.target_size) - vec2<i32>(1);
    let scaled = uv * surface.target_size;
    if surface.debug_view != 0u {
        // One pass's output, raw, from the texel under the pixel.
        let texel = clamp(vec2<i32>(scaled), vec2<i32>(0), last);
        switch surface.debug_view {
            case 1u: {
                return vec4<f32>(vec3<f32>(textureLoad(fluid_depth, texel, 0).r), 1.0);
            }
            case 2u: {
                return vec4<f32>(vec3<f32>(textureLoad(thickness, texel, 0).r), 1.0);
            }
            default: {
                let n = textureLoad(normals, texel, 0);
                return vec4<f32>(select(vec3<f32>(0.0), 0.5 + 0.5 * n.xyz, n.w > 0.5), 1.0);
            }
        }
    }
    // Depth-aware upsampling: of the four scaled texels around the pixel, weighted bilinearly,
    // only those whose water lies in front of the opaque geometry at this full-resolution pixel
    // and on the nearest such surface (within the filter's depth range) count, so the water's
    // edges against geometry follow the full resolution, and neither hidden water nor another
    // surface's normal blends in.
    let ndc = pixel_ndc(in_view, surface.view_size);
    let opaque = textureLoad(scene_depth, vec2<i32>(position.xy), 0);
    var opaque_depth = 3.4e38;
    if opaque > 0.0 {
        opaque_depth = -unproject(surface, ndc, opaque).z;
    }
    let below = scaled - 0.5;
    let corner = clamp(vec2<i32>(floor(below)), vec2<i32>(0), last);
    let f = clamp(below - floor(below), vec2<f32>(0.0), vec2<f32>(1.0));
    let corners = array<vec2<i32>, 4>(corner, min(corner + vec2<i32>(1, 0), last), min(corner + vec2<i32>(0, 1), last), min(corner + vec2<i32>(1, 1), last));
    let weights = array<f32, 4>((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
    var depths = array<f32, 4>(0.0, 0.0, 0.0, 0.0);
    var nearest = 0.0;
    for (var k = 0; k < 4; k++) {
        let d = textureLoad(fluid_depth, corners[k], 0).r;
        if d > 0.0 && d < opaque_depth {
            depths[k] = d;
            if nearest == 0.0 || d < nearest {
                nearest = d;
            }
        }
    }
    if nearest == 0.0 {
        return behind_water;
    }
    var coverage = 0.0;
    var sum_normal = vec3<f32>(0.0);
    var sum_water = 0.0;
    for (var k = 0; k < 4; k++) {
        if depths[k] > 0.0 && depths[k] <= nearest + surface.depth_range {
            let n = textureLoad(normals, corners[k], 0);
            coverage += weights[k] * n.w;
            sum_normal += weights[k] * n.xyz;
            sum_water += weights[k] * textureLoad(thickness, corners[k], 0).r;
        }
    }
    if coverage < 0.5 || dot(sum_normal, sum_normal) < 1e-12 {
        return behind_water;
    }
    let normal = normalize(sum_normal);
    var to_eye = vec3<f32>(0.0, 0.0, 1.0);
    if surface.orthographic == 0u {
        to_eye = -normalize(unproject(surface, ndc, 1.0));
    }
    let water = sum_water / coverage;
    // Refraction: the scene behind, moved along the normal's screen direction by the thickness.
    let offset = vec2<f32>(normal.x, -normal.y) * surface.refraction_strength * water;
    let refracted = textureSampleLevel(scene_color, linear_sampler, clamp(uv - offset, vec2<f32>(0.0), vec2<f32>(1.0)), 0.0).rgb;
    let transmittance = exp(-surface.absorption.rgb * water);
    let transmitted = refracted * transmittance + surface.deep_color.rgb * (1.0 - transmittance);
    let cos_view = clamp(dot(normal, to_eye), 0.0, 1.0);
    let fresnel = WATER_F0 + (1.0 - WATER_F0) * pow(1.0 - cos_view, 5.0);
    let sun = normalize(surface.sun_direction.xyz);
    let half_way = normalize(sun + to_eye);
    let highlight = surface.sun_direction.w * pow(max(dot(normal, half_way), 0.0), SHININESS);
    let color = mix(transmitted, surface.sky_color.rgb, fresnel) + vec3<f32>(highlight);
    return vec4<f32>(color, behind_water.a);
}

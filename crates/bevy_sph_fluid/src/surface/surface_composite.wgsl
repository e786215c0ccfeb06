// Composite: the water surface over the view's colour, before tonemapping. Per pixel of the
// view: the scaled targets' normal and thickness, upsampled depth-aware (see below); the
// scene behind refracted along the normal by the thickness; Beer-Lambert absorption toward the
// deep-water colour over the thickness; Fresnel (Schlick, F0 = 0.02) reflection of the sky; a
// Blinn-Phong highlight of the sun (van der Laan, Green & Sainz 2009). Opaque geometry nearer
// than the water (the view's depth) hides it. With whitewater (Ihmsen et al. 2012's diffuse
// particles, drawn by the whitewater pass), bubbles cloud the light seen through the water, and
// foam and spray lie over everything that is not nearer than their mean depth.

#import bevy_sph_fluid::surface_types::{SurfaceUniform, unproject, pixel_ndc, view_position}

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
#ifdef WHITEWATER
@group(0) @binding(7) var whitewater: texture_2d<f32>;
#endif

// Water reflects about 2 % of the light at normal incidence.
const WATER_F0: f32 = 0.02;
const SHININESS: f32 = 256.0;
// Whitewater's colour, its opacity per unit of summed billboard weight (a disc's centre alone
// covers 1 - e^-1.5 = 78 %), and its unlit share (lit from the sun by the rest).
const WHITEWATER_COLOR: vec3<f32> = vec3<f32>(0.92, 0.95, 1.0);
const WHITEWATER_OPACITY: f32 = 1.5;
const WHITEWATER_AMBIENT: f32 = 0.6;

// The view-space distance along the view axis of the opaque geometry at `pixel` (the largest
// float where there is none).
fn opaque_depth_at(pixel: vec2<f32>, ndc: vec2<f32>) -> f32 {
    let opaque = textureLoad(scene_depth, vec2<i32>(pixel), 0);
    if opaque > 0.0 {
        return -unproject(surface, ndc, opaque).z;
    }
    return 3.4e38;
}

// The direction to the eye through `ndc`, view space.
fn toward_eye(ndc: vec2<f32>) -> vec3<f32> {
    if surface.orthographic == 0u {
        return -normalize(unproject(surface, ndc, 1.0));
    }
    return vec3<f32>(0.0, 0.0, 1.0);
}

// Whether the surface at view-space `point` is the water's face against a container wall (within
// the contact distance of one): seen through the wall, it meets no air and catches no sun.
fn against_a_wall(point: vec3<f32>) -> bool {
    if surface.container_min.w == 0.0 {
        return false;
    }
    let world = (surface.world_from_view * vec4<f32>(point, 1.0)).xyz;
    let near = surface.container_max.w;
    return any(world < surface.container_min.xyz + near) || any(world > surface.container_max.xyz - near);
}

// Whitewater's colour lit by the sun, its billboards facing the eye along `to_eye`.
fn whitewater_color(to_eye: vec3<f32>) -> vec3<f32> {
    let sun = max(dot(normalize(surface.sun_direction.xyz), to_eye), 0.0);
    return WHITEWATER_COLOR * (WHITEWATER_AMBIENT + (1.0 - WHITEWATER_AMBIENT) * sun);
}

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
    // Spray r, foam g, bubbles b, spray's and foam's weighted depth a.
    var white = vec4<f32>(0.0);
#ifdef WHITEWATER
    white = textureSampleLevel(whitewater, linear_sampler, uv, 0.0);
#endif
    // A debug view: one pass's output, raw.
    if surface.debug_view == 4u {
        return vec4<f32>(1.0 - exp(-WHITEWATER_OPACITY * white.rgb), 1.0);
    }
    if surface.debug_view != 0u {
        return vec4<f32>(water(position.xy, in_view, uv, behind_water.rgb, 0.0), 1.0);
    }
    var color = water(position.xy, in_view, uv, behind_water.rgb, white.b);
    let over = white.r + white.g;
    if over > 1e-4 {
        let ndc = pixel_ndc(in_view, surface.view_size);
        if white.a / over < opaque_depth_at(position.xy, ndc) {
            let opacity = 1.0 - exp(-WHITEWATER_OPACITY * over);
            color = mix(color, whitewater_color(toward_eye(ndc)), opacity);
        }
    }
    return vec4<f32>(color, behind_water.a);
}

// Refraction: the scene behind the water at the view pixel `pixel` (`in_view` within the view),
// moved along the normal's screen direction by the thickness `water`. Where the moved sample
// lands on opaque geometry nearer than the water's surface (`nearest`), it is not behind the
// water (thick water seen at a grazing angle beside the island drew it in vertical bands): the
// scene straight behind is taken instead.
fn refracted_scene(pixel: vec2<f32>, in_view: vec2<f32>, normal: vec3<f32>, water: f32, nearest: f32) -> vec3<f32> {
    let offset = vec2<f32>(normal.x, -normal.y) * surface.refraction_strength * water * surface.view_size;
    let moved = clamp(in_view - offset, vec2<f32>(0.5), surface.view_size - vec2<f32>(0.5));
    var source = surface.view_origin + moved;
    if opaque_depth_at(source, pixel_ndc(moved, surface.view_size)) < nearest {
        source = pixel;
    }
    // The view's texture spans the whole target; the view may be a viewport of it.
    let size = vec2<f32>(textureDimensions(scene_color));
    return textureSampleLevel(scene_color, linear_sampler, source / size, 0.0).rgb;
}

// The lit water at the view pixel `pixel` (`in_view` within the view, `uv` its share), over
// `behind` (the scene's colour there), with `bubbles` of summed bubble weight clouding the light
// it lets through; `behind` where no water is drawn.
fn water(pixel: vec2<f32>, in_view: vec2<f32>, uv: vec2<f32>, behind: vec3<f32>, bubbles: f32) -> vec3<f32> {
    let last = vec2<i32>(surface.target_size) - vec2<i32>(1);
    let scaled = uv * surface.target_size;
    if surface.debug_view != 0u {
        // One pass's output, raw, from the texel under the pixel.
        let texel = clamp(vec2<i32>(scaled), vec2<i32>(0), last);
        switch surface.debug_view {
            case 1u: {
                return vec3<f32>(textureLoad(fluid_depth, texel, 0).r);
            }
            case 2u: {
                return vec3<f32>(textureLoad(thickness, texel, 0).r);
            }
            default: {
                let n = textureLoad(normals, texel, 0);
                return select(vec3<f32>(0.0), 0.5 + 0.5 * n.xyz, n.w > 0.5);
            }
        }
    }
    // Depth-aware upsampling: of the four scaled texels around the pixel, weighted bilinearly,
    // only those whose water lies in front of the opaque geometry at this full-resolution pixel
    // count toward the coverage, so the water's edges against geometry follow the full
    // resolution. The normal and the thickness are those of the nearest such surface (the
    // texels within the filter's depth range of the nearest), so neither hidden water nor a
    // surface behind blends in.
    let below = scaled - 0.5;
    let base = vec2<i32>(floor(below));
    let f = below - floor(below);
    let low = clamp(base, vec2<i32>(0), last);
    let high = clamp(base + vec2<i32>(1), vec2<i32>(0), last);
    let corners = array<vec2<i32>, 4>(low, vec2<i32>(high.x, low.y), vec2<i32>(low.x, high.y), high);
    let weights = array<f32, 4>((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
    var depths = array<f32, 4>(0.0, 0.0, 0.0, 0.0);
    var any_water = false;
    for (var k = 0; k < 4; k++) {
        depths[k] = textureLoad(fluid_depth, corners[k], 0).r;
        any_water = any_water || depths[k] > 0.0;
    }
    if !any_water {
        return behind;
    }
    let ndc = pixel_ndc(in_view, surface.view_size);
    let opaque_depth = opaque_depth_at(pixel, ndc);
    var coverage = 0.0;
    var nearest = 0.0;
    for (var k = 0; k < 4; k++) {
        if depths[k] > 0.0 && depths[k] < opaque_depth {
            coverage += weights[k];
            if nearest == 0.0 || depths[k] < nearest {
                nearest = depths[k];
            }
        }
    }
    if coverage < 0.5 {
        return behind;
    }
    var front = 0.0;
    var sum_normal = vec3<f32>(0.0);
    var sum_water = 0.0;
    for (var k = 0; k < 4; k++) {
        if depths[k] > 0.0 && depths[k] < opaque_depth && depths[k] <= nearest + surface.depth_range {
            front += weights[k];
            sum_normal += weights[k] * textureLoad(normals, corners[k], 0).xyz;
            sum_water += weights[k] * textureLoad(thickness, corners[k], 0).r;
        }
    }
    if dot(sum_normal, sum_normal) < 1e-12 {
        return behind;
    }
    let normal = normalize(sum_normal);
    let to_eye = toward_eye(ndc);
    let water = sum_water / front;
    let refracted = refracted_scene(pixel, in_view, normal, water, nearest);
    let transmittance = exp(-surface.absorption.rgb * water);
    var transmitted = refracted * transmittance + surface.deep_color.rgb * (1.0 - transmittance);
    transmitted = mix(transmitted, whitewater_color(to_eye), 1.0 - exp(-WHITEWATER_OPACITY * bubbles));
    let cos_view = clamp(dot(normal, to_eye), 0.0, 1.0);
    let fresnel = WATER_F0 + (1.0 - WATER_F0) * pow(1.0 - cos_view, 5.0);
    let sun = normalize(surface.sun_direction.xyz);
    let half_way = normalize(sun + to_eye);
    var highlight = surface.sun_direction.w * pow(max(dot(normal, half_way), 0.0), SHININESS);
    if against_a_wall(view_position(surface, ndc, nearest)) {
        highlight = 0.0;
    }
    return mix(transmitted, surface.sky_color.rgb, fresnel) + vec3<f32>(highlight);
}

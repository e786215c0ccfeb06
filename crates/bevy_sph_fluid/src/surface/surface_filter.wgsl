// One direction of the separable depth filter (FILTER_VERTICAL: down the columns, otherwise
// along the rows), a narrow-range filter after Truong & Yuksel 2018: a Gaussian over the
// neighbours within the filter radius (world metres, projected at the pixel's depth, capped in
// pixels), where a neighbour farther than the depth range behind counts at the range's edge and
// one farther than the range in front (another surface) is left out, so silhouettes stay sharp.

#import bevy_sph_fluid::surface_types::{SurfaceUniform, pixels_per_metre}

@group(0) @binding(0) var<uniform> surface: SurfaceUniform;
@group(0) @binding(1) var depth_in: texture_2d<f32>;

@fragment
fn fragment(@builtin(position) position: vec4<f32>) -> @location(0) f32 {
    let pixel = vec2<i32>(position.xy);
    let depth = textureLoad(depth_in, pixel, 0).r;
    if depth <= 0.0 {
        return 0.0;
    }
    let radius = min(surface.filter_radius * pixels_per_metre(surface, depth), surface.filter_max_pixels);
    let taps = i32(ceil(radius));
    if taps < 1 {
        return depth;
    }
#ifdef FILTER_VERTICAL
    let step = vec2<i32>(0, 1);
#else
    let step = vec2<i32>(1, 0);
#endif
    let last = vec2<i32>(surface.target_size) - vec2<i32>(1);
    let sigma = max(0.5 * radius, 0.5);
    let range = surface.depth_range;
    var sum = 0.0;
    var weights = 0.0;
    for (var k = -taps; k <= taps; k += 1) {
        let q = clamp(pixel + k * step, vec2<i32>(0), last);
        var sample = textureLoad(depth_in, q, 0).r;
        if sample <= 0.0 || sample < depth - range {
            continue;
        }
        sample = min(sample, depth + range);
        let x = f32(k);
        let w = exp(-x * x / (2.0 * sigma * sigma));
        sum += w * sample;
        weights += w;
    }
    return sum / max(weights, 1e-12);
}

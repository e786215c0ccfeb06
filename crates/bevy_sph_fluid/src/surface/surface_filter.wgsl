// One direction of the separable depth filter (FILTER_VERTICAL: down the columns, otherwise
// along the rows), a narrow-range filter after Truong & Yuksel 2018: a Gaussian over the
// neighbours within the filter radius (world metres, projected at the pixel's depth, capped in
// pixels), where a neighbour farther than the depth range behind counts at the range's edge and
// one farther than the range in front (another surface) or without water is left out with its
// mirror neighbour, so silhouettes stay sharp and the window symmetric.

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
    // The centre, then the pairs at k and -k. A pair counts only when neither of its samples is
    // empty or more than the range in front (a sample more than the range behind counts,
    // clamped), so the window stays symmetric at a silhouette: a surface seen at a grazing
    // angle, whose depth is linear across the window, keeps its depth. A one-sided window there
    // moves each column by how far its edge is, and the normals show vertical strands along the
    // water's edges.
    var sum = depth;
    var weights = 1.0;
    for (var k = 1; k <= taps; k += 1) {
        let ahead = textureLoad(depth_in, clamp(pixel + k * step, vec2<i32>(0), last), 0).r;
        let behind = textureLoad(depth_in, clamp(pixel - k * step, vec2<i32>(0), last), 0).r;
        if ahead <= 0.0 || ahead < depth - range || behind <= 0.0 || behind < depth - range {
            continue;
        }
        let x = f32(k);
        let w = exp(-x * x / (2.0 * sigma * sigma));
        sum += w * (min(ahead, depth + range) + min(behind, depth + range));
        weights += 2.0 * w;
    }
    return sum / weights;
}

// Pumps (Rust twin: sph_core::flow::pump): inside a pump's box the velocity component u along its
// direction d relaxes toward the target speed s at the rate k, du/dt = k (s - u), integrated
// exactly over the step, u' = s - (s - u) e^(-k dt); faster water and the other components are
// left alone. Applied to the step's final velocity by the closing kicks and by integrate.
#define_import_path sph::pumps

#import sph::bindings::shared_state
#import sph::guard::rotate

fn pumped(x: vec3<f32>, v: vec3<f32>, dt: f32) -> vec3<f32> {
    var out = v;
    let count = min(shared_state.pumps.count, 16u);
    for (var k = 0u; k < count; k++) {
        let p = shared_state.pumps.pumps[k];
        let local = rotate(p.to_local, x - p.center_speed.xyz);
        let strength = p.half_extents_strength.w;
        if strength <= 0.0 || any(abs(local) > p.half_extents_strength.xyz) {
            continue;
        }
        let d = p.direction.xyz;
        let u = dot(out, d);
        let speed = p.center_speed.w;
        if u >= speed {
            continue;
        }
        let relaxed = speed - (speed - u) * exp(-strength * dt);
        out += d * (relaxed - u);
    }
    return out;
}

// Whether x lies inside an open drain (the boxes after the pumps; Rust twin:
// sph_core::flow::sink::drained_by_any).
fn in_open_sink(x: vec3<f32>) -> bool {
    let first = min(shared_state.pumps.count, 16u);
    let end = min(first + shared_state.pumps.sink_count, 16u);
    for (var k = first; k < end; k++) {
        let p = shared_state.pumps.pumps[k];
        let local = rotate(p.to_local, x - p.center_speed.xyz);
        if all(abs(local) <= p.half_extents_strength.xyz) {
            return true;
        }
    }
    return false;
}

// One compare-exchange step (k, j) of the design's bitonic sort of (hash key, particle) pairs.
// Ties break on the particle index, so the result equals a stable sort by key.
#import sph::bindings::{params, sort_keys, sort_values}
#import sph::types::BitonicStep

@group(1) @binding(0) var<uniform> step: BitonicStep;

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= params.sort_length {
        return;
    }
    let l = i ^ step.j;
    if l <= i {
        return;
    }
    let ascending = (i & step.k) == 0u;
    let key_i = sort_keys[i];
    let key_l = sort_keys[l];
    let value_i = sort_values[i];
    let value_l = sort_values[l];
    let greater = key_i > key_l || (key_i == key_l && value_i > value_l);
    if greater == ascending {
        sort_keys[i] = key_l;
        sort_keys[l] = key_i;
        sort_values[i] = value_l;
        sort_values[l] = value_i;
    }
}

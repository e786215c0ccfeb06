// One compare-exchange step (k, j) of the design's bitonic sort of (hash key, particle) pairs.
// Ties break on the particle index, so the result equals a stable sort by key.
#import sph::bindings::{params, grid, sort_keys_at, sort_values_at}
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
    let key_i = grid[sort_keys_at(i)];
    let key_l = grid[sort_keys_at(l)];
    let value_i = grid[sort_values_at(i)];
    let value_l = grid[sort_values_at(l)];
    let greater = key_i > key_l || (key_i == key_l && value_i > value_l);
    if greater == ascending {
        grid[sort_keys_at(i)] = key_l;
        grid[sort_keys_at(l)] = key_i;
        grid[sort_values_at(i)] = value_l;
        grid[sort_values_at(l)] = value_i;
    }
}

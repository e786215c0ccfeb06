// The design's cell offsets: where each hash bucket starts (+1, 0 = empty) and ends in the
// sorted key array (a drained particle's key, past the table, has none).
#import sph::bindings::{params, sort_keys, bucket_start, bucket_end, clock}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    let n = params.particle_count;
    if k >= n {
        return;
    }
    if k == 0u {
        // The drained particles' keys sort last: record how many (as the grid's prefix sum).
        clock.tail_size = atomicExchange(&clock.marked, 0u);
        clock.tail_frame = params.drain_frame;
    }
    let key = sort_keys[k];
    if key >= params.table_size {
        return;
    }
    if k == 0u || sort_keys[k - 1u] != key {
        bucket_start[key] = k + 1u;
    }
    if k + 1u == n || sort_keys[k + 1u] != key {
        bucket_end[key] = k + 1u;
    }
}

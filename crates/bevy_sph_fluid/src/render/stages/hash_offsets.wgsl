// The design's cell offsets: where each hash bucket starts (+1, 0 = empty) and ends in the
// sorted key array (a drained particle's key, past the table, has none).
#import sph::bindings::{params, grid, sort_keys_at, bucket_start_at, bucket_end_at, shared_state}

@compute @workgroup_size(#{WORKGROUP_SIZE})
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    let n = params.particle_count;
    if k >= n {
        return;
    }
    if k == 0u {
        // The drained particles' keys sort last: record how many (as the grid's prefix sum).
        shared_state.clock.tail_size = atomicExchange(&shared_state.clock.marked, 0u);
        shared_state.clock.tail_frame = params.drain_frame;
    }
    let key = grid[sort_keys_at(k)];
    if key >= params.table_size {
        return;
    }
    if k == 0u || grid[sort_keys_at(k - 1u)] != key {
        grid[bucket_start_at(key)] = k + 1u;
    }
    if k + 1u == n || grid[sort_keys_at(k + 1u)] != key {
        grid[bucket_end_at(key)] = k + 1u;
    }
}

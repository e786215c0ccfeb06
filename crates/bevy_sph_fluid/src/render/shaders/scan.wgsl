// An exclusive prefix sum across one workgroup (Hillis & Steele 1986): each thread brings the
// sum of its chunk and gets the sum of the chunks before it; scan_total() then holds all of
// them. Shared by the grid sort's cell offsets (stages/prefix_sum.wgsl) and whitewater's
// (whitewater/whitewater_bin_offsets.wgsl). Every thread of the workgroup must call it.
#define_import_path sph::scan

var<workgroup> partial: array<u32, #{WORKGROUP_SIZE}>;

// Thread t's chunk of n items, [begin, end): the items split evenly over the workgroup.
fn scan_chunk(t: u32, n: u32) -> vec2<u32> {
    let chunk = (n + #{WORKGROUP_SIZE}u - 1u) / #{WORKGROUP_SIZE}u;
    let begin = min(t * chunk, n);
    return vec2<u32>(begin, min(begin + chunk, n));
}

fn workgroup_exclusive_scan(t: u32, sum: u32) -> u32 {
    partial[t] = sum;
    workgroupBarrier();
    for (var offset = 1u; offset < #{WORKGROUP_SIZE}u; offset *= 2u) {
        var add = 0u;
        if t >= offset {
            add = partial[t - offset];
        }
        workgroupBarrier();
        partial[t] += add;
        workgroupBarrier();
    }
    return partial[t] - sum;
}

// The sum of every thread's chunk, after workgroup_exclusive_scan.
fn scan_total() -> u32 {
    return partial[#{WORKGROUP_SIZE}u - 1u];
}

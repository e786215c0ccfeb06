// Probes (Rust twin: sph_core::flow::probe, summed as sph_core::gpu_layout::GpuProbes): each closing
// kick adds its particle to every probe it lies in. Level: the particles within the radius of
// the vertical line, binned by height (sph_core::flow::probe::LevelColumn: floor and bin height in
// the probe's normal.xy), each bin keeping its highest y (atomicMax on an order-keeping key);
// the CPU finds the connected column in the bins (sph_core::flow::probe::column_surface); flux: the
// particles in the slab and their Σ v·n in fixed point (sph_core::gpu_layout::PROBE_SPEED_UNIT);
// count: the particles in the box. Particle 0 counts the steps summed (the CPU averages over
// them) and stamps the last one's step and time. Particles a drain took are left out.
#define_import_path sph::probes

#import sph::bindings::{params, shared_state, particle_state, position_at}
#import sph::types::drained
#import sph::guard::rotate

const PROBE_SPEED_UNIT: f32 = 1e-4;
// sph_core::flow::probe::LEVEL_BINS.
const LEVEL_BINS: u32 = 128u;

// sph_core::gpu_layout::float_key.
fn float_key(x: f32) -> u32 {
    let b = bitcast<u32>(x);
    if (b & 0x80000000u) != 0u {
        return ~b;
    }
    return b | 0x80000000u;
}

fn record_probes(i: u32, x: vec3<f32>, v: vec3<f32>) {
    let count = min(shared_state.probes.count, 16u);
    if count == 0u {
        return;
    }
    if i == 0u {
        atomicAdd(&shared_state.probes.samples, 1u);
        shared_state.probes.step = shared_state.clock.step;
        shared_state.probes.time_ns_lo = shared_state.clock.time_ns_lo;
        shared_state.probes.time_ns_hi = shared_state.clock.time_ns_hi;
    }
    // A particle a drain took is no longer water.
    if drained(particle_state[position_at(i)].w) {
        return;
    }
    for (var k = 0u; k < count; k++) {
        let p = shared_state.probes.probes[k];
        let kind = u32(p.center_kind.w);
        let d = x - p.center_kind.xyz;
        if kind == 0u {
            if dot(d.xz, d.xz) <= p.half.x * p.half.x {
                // sph_core::flow::probe::LevelColumn::bin_of: below the floor (or NaN) is bin 0.
                let b = floor((x.y - p.normal.x) / p.normal.y);
                var bin = 0u;
                if b >= 0.0 {
                    bin = u32(min(b, f32(LEVEL_BINS - 1u)));
                }
                atomicMax(&shared_state.probes.level_tops[LEVEL_BINS * k + bin], float_key(x.y));
                atomicAdd(&shared_state.probes.sums[4u * k + 1u], 1u);
            }
            continue;
        }
        if any(abs(rotate(p.to_local, d)) > p.half.xyz) {
            continue;
        }
        atomicAdd(&shared_state.probes.sums[4u * k + 1u], 1u);
        if kind == 1u {
            let flux = i32(round(dot(v, p.normal.xyz) / PROBE_SPEED_UNIT));
            atomicAdd(&shared_state.probes.sums[4u * k + 2u], bitcast<u32>(flux));
        }
    }
}

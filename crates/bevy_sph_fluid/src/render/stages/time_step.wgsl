// Right before each step's first integration phase, one thread (CPU twin: sph_core::stability
// and CpuSolver::step); the extremes are the last step's final |v| and the |a| about to be used:
// 1. the previous step is unstable when a recorded |v| or |a| is not finite or v_max dt > h:
//    then the clock freezes integration until reset;
// 2. dt = time_step, or with the adaptive rule
//    min(time_step, λ h / (c0 + v_max), 0.125 h² ρ0/μ, 0.25 sqrt(h / a_max));
// 3. step += 1, time += dt (in whole nanoseconds, exact), the extremes are cleared.
#import sph::bindings::{params, clock}

const NON_FINITE: u32 = 0x7f800000u;

@compute @workgroup_size(1)
fn main() {
    if clock.unstable_step != 0u {
        return;
    }
    let speed_bits = atomicLoad(&clock.max_speed_bits);
    let acceleration_bits = atomicLoad(&clock.max_acceleration_bits);
    let v_max = bitcast<f32>(speed_bits);
    let a_max = bitcast<f32>(acceleration_bits);
    let h = params.grid_origin.w;
    if clock.step > 0u && (speed_bits >= NON_FINITE || acceleration_bits >= NON_FINITE || v_max * clock.dt > h) {
        clock.unstable_step = clock.step;
        return;
    }
    var dt = params.time_step.x;
    if params.flags.z != 0u {
        dt = min(dt, params.time_step.y * h / (params.time_step.w + v_max));
        dt = min(dt, params.time_step.z);
        if a_max > 0.0 {
            dt = min(dt, 0.25 * sqrt(h / a_max));
        }
    }
    clock.dt = dt;
    clock.step += 1u;
    let ticks = u32(round(dt * 1.0e9));
    let low = clock.time_ns_lo + ticks;
    clock.time_ns_hi += select(0u, 1u, low < ticks);
    clock.time_ns_lo = low;
    atomicStore(&clock.max_speed_bits, 0u);
    atomicStore(&clock.max_acceleration_bits, 0u);
}

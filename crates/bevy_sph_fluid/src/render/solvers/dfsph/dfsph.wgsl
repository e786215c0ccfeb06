// Divergence-free SPH (Bender & Koschier 2015, 2017) on the GPU: where each DFSPH pass finds
// its arrays, and the solves' shared sums. Rust twin: sph_core::solver::dfsph::bender2017 and
// sph_core::solver::dfsph.
//
// Notation as in the Rust twin: g_ij = m ∇W(x_i - x_j) (W the cubic spline normalised on the
// rest lattice), g_ib = Ψ_b ∇W(x_i - x_b) with Ψ_b = ρ0 V_b; the stiffness κ_i = p_i/ρ_i²;
// a_i = -Σ_j (κ_i + κ_j) g_ij - κ_i Σ_b g_ib - κ_i Σ_b' g_ib', b' the samples that mirror κ_i
// (those of the walls and of static and kinematic colliders, unless the particle is pinched;
// see dfsph_density.wgsl), and once a step the hydrostatic rise at the same samples,
// a_i^rise = -Σ_b' (p_b'^rise/ρ0²) g_ib', p_b'^rise = max(ρ0 g·(x_b' - x_i), -p̂_i);
// Dρ_i/Dt = Σ_j (v_i - v_j)·g_ij + Σ_b (v_i - v_b)·g_ib.
//
// The arrays a DFSPH step borrows (none of them is used otherwise by its stage list):
// - `density`: ρ_i, the cubic-spline density of the lists;
// - `acceleration_start`: (Σ_b g_ib, 1/D_i), the factor (0 for an isolated particle);
// - `sorted_acceleration_start`: (Σ_b v_b·g_ib, fluid and boundary neighbours, boundary
//   neighbours, p̂_i the rise's floor) (the sort's scratch, free after the scatter);
// - `dfsph_mirror`: (Σ_b' g_ib', 1 if the samples b' mirror κ_i else 0), its own;
// - `pressure`: κ_i of the iteration, during the solves (the last pass writes the pressures);
// - `velocity_predicted`: (κ summed by the constant-density solve, κ summed by the
//   divergence-free solve, 0, 0), carried by the sort: the next step's warm starts;
// - `neighbor_count`, `neighbor_lists`: the pairs within h after each sort (the lists pass),
//   and `dfsph_pairs`: the same pairs with g_ij, packed (the factors pass; see `pairs` below),
//   read by every iteration.
// The solve in progress keeps its state in the clock (dfsph_*): the applied iterations, the
// converged flag, two error sums, and the indirect dispatch arguments of its passes.
#define_import_path sph::dfsph

#import sph::bindings::{params, shared_state, particle_scalars, pressure_at, particle_state, acceleration_start_at, particle_scratch, sorted_acceleration_start_at, velocity_predicted_at, dfsph_pairs, dfsph_mirror_at}
#import sph::neighbors::tiled_slot

// Isolated particles: fewer neighbours than this is a free surface, left out of the
// divergence-free solve (sph_core::solver::dfsph::bender2017::INTERIOR_NEIGHBORS).
const INTERIOR_NEIGHBORS: f32 = 20.0;

// 2^32 in units of the error sums' fixed point (sph_core::gpu_layout::DFSPH_ERROR_UNIT = 1e-9).
const HIGH_WORD: f32 = 4.294967296;
const UNITS_PER_ONE: f32 = 1.0e9;

fn mass() -> f32 {
    return params.particle_mass;
}

fn rest_density() -> f32 {
    return params.rest_density;
}

// The particle spacing Δx (the CFL rule's length).
fn spacing() -> f32 {
    return params.spacing;
}

struct Factor {
    boundary_grad: vec3<f32>,
    inverse: f32,
    boundary_flux: f32,
    // Fluid and boundary neighbours within h.
    neighbors: f32,
}

fn factor(i: u32) -> Factor {
    let a = particle_state[acceleration_start_at(i)];
    let b = particle_scratch[sorted_acceleration_start_at(i)];
    return Factor(a.xyz, a.w, b.x, b.y);
}

// The boundary samples within h of particle i when the factors pass ran (0: no boundary pair).
fn boundary_neighbors(i: u32) -> f32 {
    return particle_scratch[sorted_acceleration_start_at(i)].z;
}

// Σ_b' g_ib' over the samples that mirror κ_i (0 when the particle is pinched).
fn mirrored_grad(i: u32) -> vec3<f32> {
    return particle_scratch[dfsph_mirror_at(i)].xyz;
}

// Whether the samples of static bodies mirror κ_i (the particle is not pinched).
fn mirrors(i: u32) -> bool {
    return particle_scratch[dfsph_mirror_at(i)].w != 0.0;
}

// Whether the boundary samples mirror κ_i and hold the rise: unless a dynamic collider is in the
// water, and then none does (params.unmirrored_samples; sph_core::gpu_layout::GpuBoundarySamples::mirrors).
fn samples_mirror() -> bool {
    return params.unmirrored_samples == 0.0;
}

// p̂_i = max((κ_i^ρ + κ_i^v) ρ0², 0) of the solves' totals when the factors pass ran: the
// lowest the boundary's hydrostatic rise goes below the particle's pressure.
fn rise_floor(i: u32) -> f32 {
    return particle_scratch[sorted_acceleration_start_at(i)].w;
}

// p_b^rise/ρ0² of a particle at x_i with floor p̂ and a sample at x_b: the hydrostatic rise
// ρ0 g·(x_b - x_i), no lower than -p̂ (Rust twin: sph_core::solver::dfsph::bender2017::BoundaryRise).
fn rise_over_rho0_squared(x_i: vec3<f32>, x_b: vec3<f32>, p_floor: f32) -> f32 {
    let rho0 = rest_density();
    let rise = max(rho0 * dot(params.gravity, x_b - x_i), -p_floor);
    return rise / (rho0 * rho0);
}

// κ_j of the iteration (in `pressure`, free during the solves: the step's last pass writes
// the pressures).
fn stiffness(j: u32) -> f32 {
    return particle_scalars[pressure_at(j)];
}

fn set_stiffness(i: u32, k: f32) {
    particle_scalars[pressure_at(i)] = k;
}

// The stiffness to apply from a Jacobi iteration's κ and the one applied before it (a solve's
// iterations after its first): ω κ + (ω - 1) κ', with the solve's ω. Rust twin: the
// over-relaxation of sph_core::solver::dfsph::bender2017::stiffness_from_source.
fn over_relaxed(k: f32, previous: f32) -> f32 {
#ifdef DIVERGENCE_SOLVE
    let omega = params.dfsph_divergence_over_relaxation;
#else
    let omega = params.dfsph_density_over_relaxation;
#endif
    return omega * k + (omega - 1.0) * previous;
}

// The stiffness the solve in progress summed for particle i.
fn total(i: u32) -> f32 {
#ifdef DIVERGENCE_SOLVE
    return particle_state[velocity_predicted_at(i)].y;
#else
    return particle_state[velocity_predicted_at(i)].x;
#endif
}

fn set_total(i: u32, k: f32) {
#ifdef DIVERGENCE_SOLVE
    particle_state[velocity_predicted_at(i)].y = k;
#else
    particle_state[velocity_predicted_at(i)].x = k;
#endif
}

// Neighbour k of particle i and g_ij, as the factors pass stored them.
struct Pair {
    j: u32,
    grad: vec3<f32>,
}

// Pairs are packed to 8 bytes, two to an entry, so that a pair loop issues one load for two
// pairs and one for each neighbour's value: lavapipe runs every load whose address varies
// across the SIMD lanes as a loop over the lanes, and the iterations' passes cost what their
// loads issue (docs/dfsph.md, "Packed pairs"). As one 64-bit field (x the low word): j in bits
// 0-17, then g_ij's x, y and z in 15 bits each, fixed point of the largest |g_ij| (pair_scale)
// with PAIR_STEPS steps each way, offset by PAIR_ZERO. So GPU DFSPH holds at most 2^18
// particles. Rust twin: sph_core::gpu_dfsph_pairs::{pack, unpack}.
const PAIR_INDEX_BITS: u32 = 18u;
const PAIR_GRAD_BITS: u32 = 15u;
const PAIR_STEPS: f32 = 16383.0;
const PAIR_ZERO: f32 = 16384.0;

// The largest |g_ij| = m |∇W|: the cubic spline's slope l q (3q - 2) peaks at q = 1/3 (l/3,
// sph::kernels::cubic_grad), above its l (1 - q)² beyond q = 1/2. Rust twin:
// sph_core::gpu_dfsph_pairs::scale.
fn pair_scale() -> f32 {
    return mass() * params.pbf_cubic_l / 3.0;
}

// g_ij in steps of scale / PAIR_STEPS, clamped to ±PAIR_STEPS (ties to even): what a packed pair
// keeps of it. Rust twin: sph_core::gpu_dfsph_pairs::round, with which the CPU solver rounds its
// pairs as well, so both backends solve with the same g_ij.
fn pair_steps(grad: vec3<f32>, scale: f32) -> vec3<f32> {
    return round(clamp(grad / scale, vec3<f32>(-1.0), vec3<f32>(1.0)) * PAIR_STEPS);
}

// g_ij back from its pair_steps.
fn steps_grad(steps: vec3<f32>, scale: f32) -> vec3<f32> {
    return steps * (scale / PAIR_STEPS);
}

// Pair (j, g_ij) packed, g_ij given by its pair_steps.
fn pack_pair(j: u32, steps: vec3<f32>) -> vec2<u32> {
    let c = vec3<u32>(steps + PAIR_ZERO);
    let low = j | (c.x << PAIR_INDEX_BITS);
    let high = (c.x >> (32u - PAIR_INDEX_BITS)) | (c.y << 1u) | (c.z << (1u + PAIR_GRAD_BITS));
    return vec2<u32>(low, high);
}

fn unpack_pair(e: vec2<u32>, scale: f32) -> Pair {
    let j = extractBits(e.x, 0u, PAIR_INDEX_BITS);
    let low_bits = 32u - PAIR_INDEX_BITS;
    let x = extractBits(e.x, PAIR_INDEX_BITS, low_bits) | (extractBits(e.y, 0u, 1u) << low_bits);
    let y = extractBits(e.y, 1u, PAIR_GRAD_BITS);
    let z = extractBits(e.y, 1u + PAIR_GRAD_BITS, PAIR_GRAD_BITS);
    let steps = vec3<f32>(vec3<u32>(x, y, z)) - PAIR_ZERO;
    return Pair(j, steps_grad(steps, scale));
}

// The entry of pairs k and k + 1 (k even): tiles of LIST_TILE particles as the lists, half as
// many rows.
fn pairs_slot(i: u32, k: u32) -> u32 {
    return tiled_slot(i, k / 2u, params.pbf_max_neighbors / 2u);
}

// Pairs k and k + 1 of particle i (k even; `second` means nothing when k + 1 is past the list).
struct TwoPairs {
    first: Pair,
    second: Pair,
}

fn pairs(i: u32, k: u32) -> TwoPairs {
    let e = dfsph_pairs[pairs_slot(i, k)];
    let scale = pair_scale();
    return TwoPairs(unpack_pair(e.xy, scale), unpack_pair(e.zw, scale));
}

// Stores pairs k and k + 1 of particle i (k even), packed by pack_pair.
fn set_pairs(i: u32, k: u32, first: vec2<u32>, second: vec2<u32>) {
    dfsph_pairs[pairs_slot(i, k)] = vec4<u32>(first, second);
}

// A solve starts: nothing applied, no error summed, its passes dispatched over every particle
// (workgroups of `threads`).
fn open_solve(threads: u32) {
    shared_state.clock.dfsph_done = 0u;
    shared_state.clock.dfsph_applied = 0u;
    shared_state.clock.dfsph_error_a_lo = 0u;
    shared_state.clock.dfsph_error_a_hi = 0u;
    shared_state.clock.dfsph_error_b_lo = 0u;
    shared_state.clock.dfsph_error_b_hi = 0u;
    shared_state.clock.dfsph_args_x = (params.particle_count + threads - 1u) / threads;
    shared_state.clock.dfsph_args_y = 1u;
    shared_state.clock.dfsph_args_z = 1u;
}

// Whether a solve with `applied` iterations done and mean error `error` goes on: while
// (applied < least or error > η) and applied < most (Rust twin: the loop of
// sph_core::solver::dfsph).
fn goes_on(applied: u32, error: f32, least: u32, most: u32, eta: f32) -> bool {
    return (applied < least || error > eta) && applied < most;
}

// The solve's tolerance η: the constant-density solve's largest mean compression
// (params.dfsph_max_density_error), the divergence-free solve's largest mean compression rate [1/s] (.y).
fn tolerance() -> f32 {
#ifdef DIVERGENCE_SOLVE
    return params.dfsph_max_divergence_error;
#else
    return params.dfsph_max_density_error;
#endif
}

// goes_on with the solve's least and most iterations (params.dfsph_min_* and
// params.dfsph_max_*_iterations) and its tolerance.
fn solve_goes_on(applied: u32, error: f32) -> bool {
#ifdef DIVERGENCE_SOLVE
    let counts = vec2(params.dfsph_min_divergence_iterations, params.dfsph_max_divergence_iterations);
#else
    let counts = vec2(params.dfsph_min_density_iterations, params.dfsph_max_density_iterations);
#endif
    return goes_on(applied, error, counts.x, counts.y, tolerance());
}

// The solve converged: its remaining passes dispatch no workgroup.
fn close_solve() {
    shared_state.clock.dfsph_done = 1u;
    shared_state.clock.dfsph_args_x = 0u;
}

// Adds a sum (of s_i/ρ0 terms, non-negative) to error sum `b` (0: a, 1: b) in 64-bit
// fixed point.
fn add_error(b: u32, sum: f32) {
    let units = max(sum, 0.0) * UNITS_PER_ONE;
    let high = floor(units / 4294967296.0);
    let low = u32(units - high * 4294967296.0);
    var old: u32;
    if b == 0u {
        old = atomicAdd(&shared_state.clock.dfsph_error_a_lo, low);
    } else {
        old = atomicAdd(&shared_state.clock.dfsph_error_b_lo, low);
    }
    let carry = select(0u, 1u, old + low < old);
    let add_high = u32(high) + carry;
    if add_high != 0u {
        if b == 0u {
            atomicAdd(&shared_state.clock.dfsph_error_a_hi, add_high);
        } else {
            atomicAdd(&shared_state.clock.dfsph_error_b_hi, add_high);
        }
    }
}

// The mean error of sum `b`: Σ s_i / (n ρ0).
fn mean_error(b: u32) -> f32 {
    var lo: u32;
    var hi: u32;
    if b == 0u {
        lo = atomicLoad(&shared_state.clock.dfsph_error_a_lo);
        hi = atomicLoad(&shared_state.clock.dfsph_error_a_hi);
    } else {
        lo = atomicLoad(&shared_state.clock.dfsph_error_b_lo);
        hi = atomicLoad(&shared_state.clock.dfsph_error_b_hi);
    }
    let sum = f32(hi) * HIGH_WORD + f32(lo) / UNITS_PER_ONE;
    return sum / f32(max(params.particle_count, 1u));
}

fn clear_error(b: u32) {
    if b == 0u {
        atomicStore(&shared_state.clock.dfsph_error_a_lo, 0u);
        atomicStore(&shared_state.clock.dfsph_error_a_hi, 0u);
    } else {
        atomicStore(&shared_state.clock.dfsph_error_b_lo, 0u);
        atomicStore(&shared_state.clock.dfsph_error_b_hi, 0u);
    }
}

//! One step on the GPU (lavapipe) from the same state as `sph_core`'s CPU solver: densities,
//! pressures (the free surface's extrapolated ones too), accelerations (forces) and positions agree within 1e-4 relative, for both neighbour-search
//! modes and all three integrators; three PBF and three DFSPH steps agree with the CPU's (DFSPH
//! with the CPU's iteration counts).

mod common;

use bevy::prelude::*;
use bevy_sph_fluid::prelude::*;
use common::*;
use sph_core::{BlockSpawn, BoxContainer, CpuSolver, Integrator, NeighborSearch};

fn scene() -> (sph_core::SphParams, BoxContainer, BlockSpawn) {
    let mut params = sph_core::SphParams::water();
    params.surface_tension = sph_core::params::WATER_SURFACE_TENSION;
    let container = BoxContainer::from_min_max(Vec3::ZERO, Vec3::new(0.4, 0.4, 0.2));
    // 12 x 15 x 8 = 1440 jittered particles against a wall and the floor.
    let block = BlockSpawn {
        jitter: 0.2,
        seed: 3,
        ..BlockSpawn::new(Vec3::ZERO, Vec3::new(0.24, 0.3, 0.16), params.spacing())
    };
    (params, container, block)
}

/// The CPU solver after `steps` DFSPH steps of `block` at rest, with the constant-density and
/// divergence-free iterations it summed.
fn cpu_dfsph_steps(
    params: sph_core::SphParams,
    container: BoxContainer,
    block: &BlockSpawn,
    steps: u64,
) -> (CpuSolver, u32, u32) {
    let mut cpu = CpuSolver::new(params, container, block.count()).unwrap();
    cpu.spawn(&block.positions(), Vec3::ZERO);
    let (mut density, mut divergence) = (0, 0);
    for _ in 0..steps {
        cpu.step();
        density += cpu.solver_stats().density_iterations;
        divergence += cpu.solver_stats().divergence_iterations;
    }
    (cpu, density, divergence)
}

/// |gpu - cpu| <= 1e-4 max(|cpu|, floor) for every particle, matched by id.
fn assert_close(what: &str, gpu: &[Vec3], cpu: &[Vec3], floor: f32) {
    let mut worst = 0.0f32;
    for (g, c) in gpu.iter().zip(cpu) {
        let err = (*g - *c).length() / c.length().max(floor);
        worst = worst.max(err);
    }
    eprintln!("{what}: worst relative error {worst:.2e}");
    assert!(worst <= 1e-4, "{what}: worst relative error {worst:e}");
}

#[test]
fn one_gpu_step_matches_the_cpu_solver() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let (base, container, block) = scene();
    for search in [NeighborSearch::Grid, NeighborSearch::Hash] {
        for integrator in [
            Integrator::KickDriftKick,
            Integrator::SymplecticEuler,
            Integrator::Leapfrog,
        ] {
            let mut params = base;
            params.neighbor_search = search;
            params.integrator = integrator;
            let n = block.count();

            let mut cpu = CpuSolver::new(params, container, n).unwrap();
            cpu.spawn(&block.positions(), Vec3::ZERO);
            cpu.step();
            let cpu_p = cpu.particles();
            let mut cpu_order: Vec<usize> = (0..n).collect();
            cpu_order.sort_by_key(|&k| cpu_p.id[k]);

            let mut app = gpu_app_with_block(params, container, block);
            step_to(&mut app, 1);
            let s = snapshot(&mut app);
            assert_eq!(s.ids.len(), n, "{search:?} {integrator:?}");
            let gpu_order = by_id(&s);
            let what = format!("{search:?} {integrator:?}");
            let pick =
                |v: &[Vec3], order: &[usize]| order.iter().map(|&k| v[k]).collect::<Vec<_>>();
            let gpu_ids: Vec<u32> = gpu_order.iter().map(|&k| s.ids[k]).collect();
            assert!(gpu_ids.iter().copied().eq(0..n as u32), "{what}: ids");
            let rho_gpu: Vec<Vec3> = gpu_order
                .iter()
                .map(|&k| Vec3::splat(s.densities[k]))
                .collect();
            let rho_cpu: Vec<Vec3> = cpu_order
                .iter()
                .map(|&k| Vec3::splat(cpu_p.density[k]))
                .collect();
            assert_close(&format!("{what} density"), &rho_gpu, &rho_cpu, 1.0);
            // The pressures, the free surface's extrapolated ones included, within 1e-4 of the
            // largest (the equation of state turns the densities' rounding into pressure).
            let splat = |p: &[f32], order: &[usize]| -> Vec<Vec3> {
                order.iter().map(|&k| Vec3::splat(p[k])).collect()
            };
            let p_max = cpu_p.pressure.iter().fold(0.0, |m: f32, &p| m.max(p));
            let surface = cpu_order
                .iter()
                .filter(|&&k| cpu_p.pressure[k] > 0.0 && cpu_p.density[k] < params.rest_density)
                .count();
            assert!(
                surface > 0,
                "{what}: no free-surface particle carries a pressure"
            );
            assert_close(
                &format!("{what} pressure"),
                &splat(&s.pressures, &gpu_order),
                &splat(&cpu_p.pressure, &cpu_order),
                p_max,
            );
            let a_max = cpu_p
                .acceleration
                .iter()
                .map(|a| a.length())
                .fold(0.0, f32::max);
            assert_close(
                &format!("{what} acceleration"),
                &pick(&s.accelerations, &gpu_order),
                &pick(&cpu_p.acceleration, &cpu_order),
                1e-2 * a_max,
            );
            assert_close(
                &format!("{what} position"),
                &pick(&s.positions, &gpu_order),
                &pick(&cpu_p.position, &cpu_order),
                0.01,
            );
            let v_max = cpu_p
                .velocity
                .iter()
                .map(|v| v.length())
                .fold(0.0, f32::max);
            assert_close(
                &format!("{what} velocity"),
                &pick(&s.velocities, &gpu_order),
                &pick(&cpu_p.velocity, &cpu_order),
                1e-2 * v_max,
            );
        }
    }
}

/// The largest |gpu - cpu| over particles matched by id.
fn worst_difference(gpu: &[Vec3], gpu_order: &[usize], cpu: &[Vec3], cpu_order: &[usize]) -> f32 {
    gpu_order
        .iter()
        .zip(cpu_order)
        .map(|(&g, &c)| (gpu[g] - cpu[c]).length())
        .fold(0.0, f32::max)
}

/// The worst differences between the GPU's snapshot and the CPU solver's state, particles
/// matched by id (every id present once on the GPU), with the scale they are judged against.
struct Differences {
    /// Largest |Δx| [m].
    dx: f32,
    /// Largest |Δv| [m/s].
    dv: f32,
    /// Largest relative density difference.
    drho: f32,
    /// Largest |Δp| of the pressures read back [Pa].
    dp: f32,
    /// The CPU's largest pressure [Pa].
    p_max: f32,
    /// The CPU's largest speed [m/s].
    v_max: f32,
    /// The farthest a CPU particle moved from its spawn position [m].
    moved: f32,
}

fn differences(s: &SphSnapshot, cpu: &CpuSolver, block: &BlockSpawn, what: &str) -> Differences {
    let cpu_p = cpu.particles();
    let n = cpu_p.len();
    let mut cpu_order: Vec<usize> = (0..n).collect();
    cpu_order.sort_by_key(|&k| cpu_p.id[k]);
    assert_eq!(s.ids.len(), n, "{what}");
    let gpu_order = by_id(s);
    let gpu_ids: Vec<u32> = gpu_order.iter().map(|&k| s.ids[k]).collect();
    assert!(gpu_ids.iter().copied().eq(0..n as u32), "{what}: ids");
    let dx = worst_difference(&s.positions, &gpu_order, &cpu_p.position, &cpu_order);
    let dv = worst_difference(&s.velocities, &gpu_order, &cpu_p.velocity, &cpu_order);
    let drho = gpu_order
        .iter()
        .zip(&cpu_order)
        .map(|(&g, &c)| (s.densities[g] - cpu_p.density[c]).abs() / cpu_p.density[c])
        .fold(0.0, f32::max);
    let dp = gpu_order
        .iter()
        .zip(&cpu_order)
        .map(|(&g, &c)| (s.pressures[g] - cpu_p.pressure[c]).abs())
        .fold(0.0, f32::max);
    let p_max = cpu_p.pressure.iter().copied().fold(0.0, f32::max);
    let v_max = cpu_p
        .velocity
        .iter()
        .map(|v| v.length())
        .fold(0.0, f32::max);
    let start = block.positions();
    let moved = cpu_order
        .iter()
        .map(|&c| (cpu_p.position[c] - start[cpu_p.id[c] as usize]).length())
        .fold(0.0, f32::max);
    eprintln!(
        "{what}: worst |Δx| {dx:.2e} m (moved up to {moved:.2e} m), |Δv| {dv:.2e} m/s \
         (v_max {v_max:.3} m/s), density {drho:.2e} relative, pressure {dp:.2e} Pa \
         (p_max {p_max:.1} Pa)"
    );
    Differences {
        dx,
        dv,
        drho,
        dp,
        p_max,
        v_max,
        moved,
    }
}

/// PBF (Macklin & Müller 2013) on the GPU: three steps at PBF's own dt (1/120 s) from the same
/// jittered block give the CPU solver's positions, velocities, densities and the pressures the
/// step's λ stand for, in both search
/// modes, with and without vorticity confinement. Both take the pairs within h at the predicted
/// positions for the whole step and evaluate the kernel at the iteration's positions.
#[test]
fn pbf_steps_on_the_gpu_match_the_cpu_solver() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let (mut base, container, block) = scene();
    base.use_solver(sph_core::Solver::Pbf);
    base.surface_tension = 0.0;
    let steps = 3;
    for search in [NeighborSearch::Grid, NeighborSearch::Hash] {
        for vorticity in [0.0, 0.2] {
            let mut params = base;
            params.neighbor_search = search;
            params.pbf.vorticity_epsilon = vorticity;
            let what = format!("PBF {search:?} vorticity {vorticity}");
            let n = block.count();
            let mut cpu = CpuSolver::new(params, container, n).unwrap();
            cpu.spawn(&block.positions(), Vec3::ZERO);
            for _ in 0..steps {
                cpu.step();
            }

            let mut app = gpu_app_with_block(params, container, block);
            step_to(&mut app, steps);
            let stats = app.world().resource::<SphStats>();
            assert_eq!(stats.error, None, "{what}");
            assert_eq!(stats.pressure_iterations_max, params.pbf.iterations);
            assert_eq!(stats.neighbor_list_overflows, 0, "{what}");
            let s = snapshot(&mut app);
            let Differences {
                dx,
                dv,
                drho,
                dp,
                p_max,
                v_max,
                moved,
            } = differences(&s, &cpu, &block, &what);
            assert!(moved > 1e-3, "{what}: the water moves");
            assert!(dx <= 1e-6, "{what}: positions differ by {dx} m");
            assert!(dv <= 1e-4 * v_max, "{what}: velocities differ by {dv} m/s");
            // f32 sums in another order, over three steps of six iterations each (measured
            // at most 2.0e-5).
            assert!(drho <= 4e-5, "{what}: densities differ by {drho}");
            // The pressure the step's λ stand for (Λ summed over the iterations).
            assert!(p_max > 10.0, "{what}: the block is compressed ({p_max} Pa)");
            assert!(
                dp <= 1e-3 * p_max,
                "{what}: pressures differ by {dp} Pa of {p_max}"
            );
        }
    }
}

/// DFSPH (Bender & Koschier 2015, 2017) on the GPU: three steps at DFSPH's own dt rule from
/// the same jittered block give the CPU solver's positions, velocities and densities, in both
/// search modes, with and without warm starts; the device's solves take the CPU's iteration
/// counts (their convergence tests are on-device sums, read back with the clock).
#[test]
fn dfsph_steps_on_the_gpu_match_the_cpu_solver() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let (mut base, container, block) = scene();
    base.use_solver(sph_core::Solver::Dfsph);
    let steps = 3;
    for search in [NeighborSearch::Grid, NeighborSearch::Hash] {
        for warm_start in [true, false] {
            let mut params = base;
            params.neighbor_search = search;
            params.dfsph.warm_start = warm_start;
            let what = format!("DFSPH {search:?} warm start {warm_start}");
            let (cpu, density_iterations, divergence_iterations) =
                cpu_dfsph_steps(params, container, &block, steps);

            let mut app = gpu_app_with_block(params, container, block);
            step_to(&mut app, steps);
            let stats = app.world().resource::<SphStats>();
            assert_eq!(stats.error, None, "{what}");
            assert!(!stats.health.is_unstable(), "{what}: {:?}", stats.health);
            // The snapshot's frames (no steps) bring the clock of the last step back too.
            let s = snapshot(&mut app);
            let clock = app
                .world()
                .resource::<bevy_sph_fluid::shared::ClockReadback>()
                .latest
                .expect("a clock reading");
            eprintln!(
                "{what}: iterations on the GPU {} + {} (most {}), on the CPU {} + {}; dt {:.2e} s",
                clock.density_iterations,
                clock.divergence_iterations,
                clock.density_iterations_max,
                density_iterations,
                divergence_iterations,
                clock.dt
            );
            let Differences {
                dx,
                dv,
                drho,
                dp,
                p_max,
                v_max,
                moved,
            } = differences(&s, &cpu, &block, &what);
            assert_eq!(clock.step as u64, steps, "{what}");
            assert_eq!(
                (clock.density_iterations, clock.divergence_iterations),
                (density_iterations, divergence_iterations),
                "{what}: iterations"
            );
            assert!(moved > 1e-4, "{what}: the water moves");
            // The pressures read back, (κ^ρ + κ^v) ρ² of the solves, are the CPU's.
            assert!(p_max > 1.0, "{what}: the water has pressure ({p_max} Pa)");
            assert!(
                dp <= 1e-3 * p_max,
                "{what}: pressures differ by {dp} Pa of {p_max}"
            );
            assert!(dx <= 1e-6, "{what}: positions differ by {dx} m");
            assert!(dv <= 1e-3 * v_max, "{what}: velocities differ by {dv} m/s");
            assert!(drho <= 2e-5, "{what}: densities differ by {drho}");
        }
    }
}

/// DFSPH's iteration budget on the GPU (`bevy_sph_fluid::dfsph_budget`): once the first clock
/// readings are back, a step encodes far fewer passes than the settings' 100 + 100 iterations,
/// and still takes exactly the CPU's iterations (none cut short). Pinned below what the solves
/// need, the device cuts them short, counts them, and the water stays healthy.
#[test]
fn dfsph_on_the_gpu_encodes_what_recent_steps_needed_and_counts_solves_cut_short() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let (mut params, container, block) = scene();
    params.use_solver(sph_core::Solver::Dfsph);
    let steps = 6;
    let n = block.count();
    let (_, density_iterations, divergence_iterations) =
        cpu_dfsph_steps(params, container, &block, steps);

    let mut app = gpu_app_with_block(params, container, block);
    step_to(&mut app, steps);
    snapshot(&mut app);
    let clock = |app: &App| {
        app.world()
            .resource::<bevy_sph_fluid::shared::ClockReadback>()
            .latest
            .expect("a clock reading")
    };
    let adapted = clock(&app);
    let stats = app.world().resource::<SphStats>().clone();
    let encoded = app
        .world()
        .resource::<bevy_sph_fluid::shared::SphSimulation>()
        .frame
        .dfsph_iterations;
    println!(
        "budget {encoded:?}: {} dispatches a step; iterations on the GPU {} + {}, on the CPU \
         {density_iterations} + {divergence_iterations}; cut short {}",
        stats.dispatches_per_step,
        adapted.density_iterations,
        adapted.divergence_iterations,
        stats.dfsph_solves_cut_short
    );
    assert!(
        stats.dispatches_per_step < 200,
        "the budget follows the steps: {} dispatches a step (416 at the most)",
        stats.dispatches_per_step
    );
    assert_eq!(stats.dfsph_solves_cut_short, 0);
    assert_eq!(
        (adapted.density_iterations, adapted.divergence_iterations),
        (density_iterations, divergence_iterations),
        "the budget changes no step"
    );

    // Below what the solves need: 2 constant-density iterations (their least; 1 is raised to
    // it) and 1 divergence-free.
    app.world_mut()
        .resource_mut::<bevy_sph_fluid::shared::SphSimulation>()
        .dfsph_budget = bevy_sph_fluid::dfsph_budget::DfsphIterationBudget::pinned([1, 1]);
    let more = 4;
    step_to(&mut app, steps + more);
    let s = snapshot(&mut app);
    let pinned = clock(&app);
    let stats = app.world().resource::<SphStats>().clone();
    println!(
        "pinned: {} dispatches a step; iterations {} + {} in {more} steps; cut short {}",
        stats.dispatches_per_step,
        pinned.density_iterations - adapted.density_iterations,
        pinned.divergence_iterations - adapted.divergence_iterations,
        stats.dfsph_solves_cut_short
    );
    assert_eq!(
        pinned.density_iterations - adapted.density_iterations,
        2 * more as u32
    );
    assert_eq!(
        pinned.divergence_iterations - adapted.divergence_iterations,
        more as u32
    );
    assert!(stats.dfsph_solves_cut_short > 0);
    assert_eq!(stats.dfsph_solves_cut_short, pinned.solves_cut_short());
    assert!(!stats.health.is_unstable(), "{:?}", stats.health);
    assert_eq!(s.positions.len(), n);
    assert!(s.positions.iter().all(|x| x.is_finite()));
}

//! Whitewater on the GPU backend (lavapipe): the potentials of every fluid particle agree with
//! the CPU twin (`sph_core::whitewater::ihmsen2012::FluidView`) on the same state, the particles
//! born in a step agree with the count the twin expects within Poisson noise, every particle
//! born is alive or counted dead, still water sheds nothing, the classes' counts agree with the
//! CPU backend's on the same scene within a stated tolerance (a thrown block with WCSPH, the
//! pipe's jet into a basin with PBF), and removing the resource turns it off.

mod common;

use bevy::prelude::*;
use bevy::render::gpu_readback::{Readback, ReadbackComplete};
use bevy_sph_fluid::prelude::*;
use bevy_sph_fluid::shared::SphSimulation;
use common::*;
use sph_core::whitewater::ihmsen2012::{shed_count, FluidView};
use sph_core::whitewater::settings::{Limits, WhitewaterSettings};
use sph_core::{BlockSpawn, BoxContainer, Integrator, Solver};
use std::collections::HashMap;

/// The container of the thrown block.
const EXTENT: Vec3 = Vec3::new(0.4, 0.3, 0.2);

/// WCSPH with symplectic Euler: its step's first sort sees the state as the last step left it
/// (no drift before it), so a snapshot between two steps is what the whitewater stages read.
fn params() -> sph_core::SphParams {
    let mut params = sph_core::SphParams::water();
    params.use_solver(Solver::Wcsph);
    params.integrator = Integrator::SymplecticEuler;
    params
}

/// The default settings shedding `times` as many diffuse particles.
fn shedding_times(times: f32) -> WhitewaterSettings {
    let defaults = WhitewaterSettings::default();
    WhitewaterSettings {
        trapped_air_rate: times * defaults.trapped_air_rate,
        wave_crest_rate: times * defaults.wave_crest_rate,
        ..defaults
    }
}

/// An app on `backend` with whitewater on with `settings`: a block of `size` at the container's
/// floor corner, moving at `velocity`.
fn app_with_whitewater(
    backend: SphBackend,
    settings: WhitewaterSettings,
    size: Vec3,
    velocity: Vec3,
    extent: Vec3,
) -> App {
    let mut app = headless_app(4_000, backend);
    app.insert_resource(SphParams(params()));
    app.insert_resource(SphWhitewater {
        settings,
        ..default()
    });
    app.world_mut()
        .spawn(SphContainer(BoxContainer::from_min_max(Vec3::ZERO, extent)));
    let block = BlockSpawn::new(Vec3::ZERO, size, params().spacing());
    app.world_mut().spawn(SphBlockSpawn { block, velocity });
    app.update();
    app
}

/// A block thrown at 3 m/s against the far wall, with `settings`.
fn thrown_block(backend: SphBackend, settings: WhitewaterSettings) -> App {
    app_with_whitewater(
        backend,
        settings,
        Vec3::new(0.1, 0.1, 0.2),
        Vec3::new(3.0, 0.0, 0.0),
        EXTENT,
    )
}

fn counts(app: &App) -> SphWhitewaterCounts {
    let stats = app.world().resource::<SphStats>();
    assert_eq!(stats.whitewater_error, None);
    stats.whitewater.expect("whitewater runs")
}

/// Runs paused frames until the counters read back are those of the step taken (the readback
/// arrives a few frames late).
fn settled_counts(app: &mut App) -> SphWhitewaterCounts {
    let mut last = None;
    for _ in 0..20 {
        app.update();
        let now = counts(app);
        if last == Some(now) {
            return now;
        }
        last = Some(now);
    }
    last.unwrap()
}

/// The bytes of `handle` read back from the device.
#[derive(Resource, Default)]
struct Arrived(Option<Vec<u8>>);

fn read_buffer(app: &mut App, handle: Handle<bevy::render::storage::ShaderBuffer>) -> Vec<u8> {
    app.insert_resource(Arrived(None));
    let reader = app
        .world_mut()
        .spawn(Readback::buffer(handle))
        .observe(
            |event: On<ReadbackComplete>, mut arrived: ResMut<Arrived>| {
                arrived.0 = Some(event.data.clone());
            },
        )
        .id();
    for _ in 0..50 {
        app.update();
        if let Some(bytes) = app.world_mut().resource_mut::<Arrived>().0.take() {
            app.world_mut().despawn(reader);
            return bytes;
        }
    }
    panic!("no readback after 50 frames");
}

#[test]
fn the_gpu_potentials_and_births_match_the_cpu_twin() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    // A hundred times the default rates, so that one step sheds a count to test, and from
    // 2.8 m/s on, so that the particles the wall slowed are too slow to shed.
    let settings = WhitewaterSettings {
        kinetic_energy: Limits { min: 4.0, max: 8.0 },
        ..shedding_times(100.0)
    };
    let mut app = thrown_block(SphBackend::Gpu, settings);
    // The block has hit the wall and splashes.
    step_to(&mut app, 120);
    let before = snapshot(&mut app);
    let dt = app.world().resource::<SphStats>().time_step;
    let born_before = settled_counts(&mut app).born;
    step_to(&mut app, 121);
    let after = snapshot(&mut app);
    let born = settled_counts(&mut app).born - born_before;
    let handle = app
        .world()
        .resource::<SphSimulation>()
        .frame
        .whitewater
        .as_ref()
        .expect("the GPU runs whitewater")
        .potentials
        .clone();
    let bytes = read_buffer(&mut app, handle);
    let gpu: Vec<[f32; 4]> = bytes[..16 * after.ids.len()]
        .chunks_exact(16)
        .map(|c| {
            std::array::from_fn(|k| f32::from_le_bytes(c[4 * k..4 * k + 4].try_into().unwrap()))
        })
        .collect();

    // The twin on the state the stages read: the one the step before left.
    let container = BoxContainer::from_min_max(Vec3::ZERO, EXTENT);
    let h = params().smoothing_radius;
    let view = FluidView::new(&before.positions, &before.velocities, &container, h).unwrap();
    let view_index: HashMap<[u32; 3], usize> = view
        .positions()
        .iter()
        .enumerate()
        .map(|(k, p)| (p.to_array().map(f32::to_bits), k))
        .collect();
    let by_id: HashMap<u32, usize> = before
        .ids
        .iter()
        .enumerate()
        .map(|(k, &id)| (id, k))
        .collect();
    let (mut agree, mut worst, mut expected, mut variance) = (0, 0.0f32, 0.0f64, 0.0f64);
    let mut skipped = 0;
    let (mut gpu_rate, mut cpu_rate) = (0.0f64, 0.0f64);
    for (slot, id) in after.ids.iter().enumerate() {
        let k = by_id[id];
        let cpu = view.potentials(view_index[&before.positions[k].to_array().map(f32::to_bits)]);
        let g = gpu[slot];
        if g[0] < 0.0 {
            // Too slow to shed: the stage skipped the other potentials.
            assert_eq!(
                settings.kinetic_energy.clamp(cpu.kinetic_energy),
                0.0,
                "{cpu:?}"
            );
            assert!((g[2] - cpu.kinetic_energy).abs() <= 1e-6 + 1e-3 * cpu.kinetic_energy);
            assert_eq!(g[3], 0.0);
            skipped += 1;
            continue;
        }
        let close = |gpu: f32, cpu: f32| (gpu - cpu).abs() <= 1e-3 * cpu.abs().max(0.1);
        let error = [
            (g[0] - cpu.trapped_air).abs() / cpu.trapped_air.abs().max(0.1),
            (g[1] - cpu.wave_crest).abs() / cpu.wave_crest.abs().max(0.1),
            (g[2] - cpu.kinetic_energy).abs() / cpu.kinetic_energy.abs().max(0.1),
        ]
        .into_iter()
        .fold(0.0f32, f32::max);
        if close(g[0], cpu.trapped_air)
            && close(g[1], cpu.wave_crest)
            && close(g[2], cpu.kinetic_energy)
        {
            agree += 1;
        } else {
            worst = worst.max(error);
        }
        let n = shed_count(&settings, &cpu, dt) as f64;
        let p = n.fract();
        expected += n;
        variance += p * (1.0 - p);
        gpu_rate += g[3] as f64;
        cpu_rate += (shed_count(&settings, &cpu, 1.0)) as f64;
    }
    let total = after.ids.len();
    println!(
        "potentials: {agree} of {total} particles within 1e-3 (worst of the others {worst:.2e}), \
         {skipped} too slow to shed; \
         rate sum GPU {gpu_rate:.1}/s, CPU {cpu_rate:.1}/s; born {born}, the twin expects \
         {expected:.1} ± {:.1}",
        variance.sqrt()
    );
    // A particle whose normal sum or v̂·n̂ sits on a threshold may fall either side of it with
    // a different summation order: at most 1 % of them.
    assert!(
        (agree + skipped) * 100 >= total * 99 && agree > 0,
        "{agree} and {skipped} of {total}"
    );
    assert!(cpu_rate > 100.0, "the splash sheds: {cpu_rate}");
    assert!(
        (gpu_rate - cpu_rate).abs() <= 0.02 * cpu_rate,
        "{gpu_rate} against {cpu_rate}"
    );
    // The births are Bernoulli draws around the expectation: within 4 standard deviations.
    assert!(
        (born as f64 - expected).abs() <= 4.0 * variance.sqrt() + 2.0,
        "born {born}, expected {expected} ± {}",
        variance.sqrt()
    );
}

#[test]
fn the_gpu_pool_keeps_every_particle_and_its_classes_match_the_cpu_backend() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let steps = 150;
    // Ten times the default rates: a thousand particles to count.
    let settings = shedding_times(10.0);
    let mut cpu = thrown_block(SphBackend::Cpu, settings);
    step_to(&mut cpu, steps);
    let cpu_counts = counts(&cpu);
    let mut gpu = thrown_block(SphBackend::Gpu, settings);
    step_to(&mut gpu, steps);
    let gpu_counts = settled_counts(&mut gpu);
    println!("after {steps} steps: CPU {cpu_counts:?}\n GPU {gpu_counts:?}");
    let live = gpu_counts.spray + gpu_counts.foam + gpu_counts.bubbles;
    assert!(gpu_counts.born > 0);
    assert_eq!(
        gpu_counts.born,
        live as u64 + gpu_counts.expired,
        "every diffuse particle born is alive or counted dead"
    );
    assert_eq!(gpu_counts.dropped, 0, "the default pool holds them all");
    let particles = gpu.world().resource::<SphDiffuseParticles>();
    assert!(particles.buffer.is_some());
    assert!(
        particles.slots >= live,
        "{} slots for {live}",
        particles.slots
    );
    // Two runs of a splash, on two backends, drift apart particle by particle: the counts agree
    // as a whole, each class and the births within 20 % (of the larger, or of 20 particles).
    let pairs = [
        ("born", cpu_counts.born as f64, gpu_counts.born as f64),
        ("spray", cpu_counts.spray as f64, gpu_counts.spray as f64),
        ("foam", cpu_counts.foam as f64, gpu_counts.foam as f64),
        (
            "bubbles",
            cpu_counts.bubbles as f64,
            gpu_counts.bubbles as f64,
        ),
    ];
    for (name, c, g) in pairs {
        assert!(
            (c - g).abs() <= 0.2 * c.max(g).max(20.0),
            "{name}: CPU {c}, GPU {g}"
        );
    }
    // Removing the resource turns it off.
    gpu.world_mut().remove_resource::<SphWhitewater>();
    gpu.update();
    gpu.update();
    let stats = gpu.world().resource::<SphStats>();
    assert_eq!(stats.whitewater, None);
    assert!(gpu
        .world()
        .resource::<SphDiffuseParticles>()
        .buffer
        .is_none());
}

#[test]
fn still_water_on_the_gpu_sheds_nothing_and_a_bad_setting_is_named() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let extent = Vec3::new(0.2, 0.3, 0.2);
    let mut app = app_with_whitewater(
        SphBackend::Gpu,
        WhitewaterSettings::default(),
        Vec3::new(0.2, 0.1, 0.2),
        Vec3::ZERO,
        extent,
    );
    step_to(&mut app, 200);
    let still = settled_counts(&mut app);
    assert_eq!(still.born, 0, "{still:?}");
    app.insert_resource(SphWhitewater {
        capacity: 0,
        ..default()
    });
    app.update();
    let stats = app.world().resource::<SphStats>().clone();
    let error = stats.whitewater_error.unwrap_or_default();
    assert!(error.contains("whitewater.capacity"), "{error:?}");
    assert!(stats.whitewater.is_some(), "the whitewater before runs on");
}

/// The diffuse particles' (position, class) of a GPU app's pool, empty slots left out.
fn gpu_diffuse_particles(app: &mut App) -> Vec<(Vec3, u32)> {
    let handle = app.world().resource::<SphDiffuseParticles>().buffer.clone();
    let bytes = read_buffer(app, handle.expect("the drawing buffer"));
    bytes
        .chunks_exact(16)
        .filter_map(|c| {
            let f: [f32; 4] = std::array::from_fn(|k| {
                f32::from_le_bytes(c[4 * k..4 * k + 4].try_into().unwrap())
            });
            (f[3] >= 0.0).then(|| (Vec3::new(f[0], f[1], f[2]), f[3] as u32))
        })
        .collect()
}

/// The median of `values`.
fn median(mut values: Vec<f32>) -> f32 {
    values.sort_by(f32::total_cmp);
    values[values.len() / 2]
}

/// PBF's prediction is fused into the sort the stages follow: they take its g dt back, or foam
/// on still water would sink (and turn to bubbles) at g dt.
///
/// The jet is chaotic, and the GPU's atomics order its births differently from run to run, so a
/// single snapshot of the pool swings by a quarter between runs: the counts compared are the
/// means of `SAMPLES` snapshots 40 steps apart, and the foam's place is the median over them all.
/// Even so the GPU's bubbles run under the CPU's, by 12 to 21 % in repeated runs with PBF's
/// samples pushing by λ_i alone (CPU 604, GPU 479 to 534) and by 22 to 28 % since they push
/// with the water's λ (CPU 659, GPU 474 to 514): the counts may differ by 30 %.
#[test]
fn the_pipes_foam_on_the_gpu_matches_the_cpu_backends_in_count_and_place() {
    let _gpu = GPU.lock().unwrap_or_else(|e| e.into_inner());
    const SAMPLES: [u64; 4] = [180, 220, 260, 300];
    let mut figures = Vec::new();
    for backend in [SphBackend::Cpu, SphBackend::Gpu] {
        let mut app = shipped_scene_app("scenes/basin_jet.ron", backend, |_| {});
        app.insert_resource(SphWhitewater::default());
        let mut mean = [0.0f64; 3];
        let mut foam_x = Vec::new();
        for steps in SAMPLES {
            step_to(&mut app, steps);
            let counts = settled_counts(&mut app);
            let particles: Vec<(Vec3, u32)> = if backend == SphBackend::Cpu {
                let d = app.world().resource::<SphDiffuseParticles>();
                d.position
                    .iter()
                    .zip(&d.kind)
                    .map(|(p, k)| (*p, *k as u32))
                    .collect()
            } else {
                gpu_diffuse_particles(&mut app)
            };
            println!("{backend:?} at step {steps}: {counts:?}");
            let live = counts.spray + counts.foam + counts.bubbles;
            assert_eq!(
                particles.len(),
                live as usize,
                "{backend:?}: the pool holds the live ones"
            );
            for (m, c) in mean.iter_mut().zip([
                counts.born as f64,
                counts.foam as f64,
                counts.bubbles as f64,
            ]) {
                *m += c / SAMPLES.len() as f64;
            }
            foam_x.extend(particles.iter().filter(|p| p.1 == 1).map(|p| p.0.x));
        }
        let x = median(foam_x);
        println!("{backend:?}: mean born, foam, bubbles {mean:?}; foam's median x {x:.3} m");
        figures.push((mean, x));
    }
    let ((cpu, cpu_x), (gpu, gpu_x)) = (figures[0], figures[1]);
    for (k, name) in ["born", "foam", "bubbles"].iter().enumerate() {
        let (c, g) = (cpu[k], gpu[k]);
        assert!(
            (c - g).abs() <= 0.3 * c.max(g).max(20.0),
            "{name}: CPU {c}, GPU {g}"
        );
    }
    assert!(
        (cpu_x - gpu_x).abs() <= 0.05,
        "foam's median x: CPU {cpu_x}, GPU {gpu_x}"
    );
}

//! `SphWhitewater` on the CPU backend: still water sheds nothing, water thrown against a wall
//! sheds diffuse particles counted by class, a refused setting is named and the whitewater
//! running before stays, and removing the resource turns it off. The GPU backend's are in
//! `gpu_whitewater.rs`.

mod common;

use bevy::prelude::*;
use bevy_sph_fluid::prelude::*;
use common::*;
use sph_core::{BlockSpawn, BoxContainer};

/// A CPU app with whitewater on: a block of `size` at the container's floor corner, moving at
/// `velocity`, in a container of `extent`.
fn app_with_whitewater(extent: Vec3, size: Vec3, velocity: Vec3) -> App {
    let mut app = headless_app(4_000, SphBackend::Cpu);
    app.insert_resource(SphWhitewater::default());
    app.world_mut()
        .spawn(SphContainer(BoxContainer::from_min_max(Vec3::ZERO, extent)));
    let block = BlockSpawn::new(Vec3::ZERO, size, 0.02);
    app.world_mut().spawn(SphBlockSpawn { block, velocity });
    app.update();
    app
}

/// The container of [`thrown_block_app`].
const THROWN_EXTENT: Vec3 = Vec3::new(0.4, 0.3, 0.2);

/// A block thrown at 3 m/s against the far wall of a [`THROWN_EXTENT`] container.
fn thrown_block_app() -> App {
    app_with_whitewater(
        THROWN_EXTENT,
        Vec3::new(0.1, 0.1, 0.2),
        Vec3::new(3.0, 0.0, 0.0),
    )
}

fn assert_no_diffuse_particles(app: &App) {
    let particles = app.world().resource::<SphDiffuseParticles>();
    assert!(particles.position.is_empty() && particles.kind.is_empty());
}

fn counts(app: &App) -> SphWhitewaterCounts {
    let stats = app.world().resource::<SphStats>();
    assert_eq!(stats.whitewater_error, None);
    stats.whitewater.expect("whitewater runs")
}

#[test]
fn still_water_sheds_nothing() {
    // The block fills the floor: a tank at rest.
    let extent = Vec3::new(0.2, 0.3, 0.2);
    let mut app = app_with_whitewater(extent, Vec3::new(0.2, 0.1, 0.2), Vec3::ZERO);
    step_to(&mut app, 200);
    let counts = counts(&app);
    assert_eq!(counts.born, 0, "{counts:?}");
    assert_no_diffuse_particles(&app);
}

#[test]
fn water_thrown_at_a_wall_sheds_diffuse_particles_counted_by_class() {
    let mut app = thrown_block_app();
    step_to(&mut app, 150);
    let counts = counts(&app);
    println!("{counts:?}");
    let live = counts.spray + counts.foam + counts.bubbles;
    assert!(counts.born > 0, "{counts:?}");
    assert_eq!(
        counts.born,
        live as u64 + counts.expired,
        "every diffuse particle born is alive or counted dead: {counts:?}"
    );
    let particles = app.world().resource::<SphDiffuseParticles>();
    assert_eq!(particles.position.len(), live as usize);
    assert_eq!(particles.kind.len(), live as usize);
    let container = BoxContainer::from_min_max(Vec3::ZERO, THROWN_EXTENT);
    assert!(
        particles
            .position
            .iter()
            .all(|p| p.cmpge(container.min() - 1e-4).all() && p.cmple(container.max() + 1e-4).all()),
        "diffuse particles stay in the container"
    );
}

#[test]
fn a_refused_setting_is_named_the_running_whitewater_stays_and_removal_turns_it_off() {
    let mut app = thrown_block_app();
    step_to(&mut app, 100);
    let before = counts(&app);
    app.insert_resource(SphWhitewater {
        capacity: 0,
        ..default()
    });
    app.update();
    let stats = app.world().resource::<SphStats>().clone();
    let error = stats.whitewater_error.unwrap_or_default();
    assert!(error.contains("whitewater.capacity"), "{error:?}");
    let running = stats.whitewater.expect("the whitewater before runs on");
    assert!(running.born >= before.born, "{running:?} after {before:?}");
    app.world_mut().remove_resource::<SphWhitewater>();
    app.update();
    let stats = app.world().resource::<SphStats>();
    assert_eq!(stats.whitewater, None);
    assert_eq!(stats.whitewater_error, None);
    assert_no_diffuse_particles(&app);
}

#[test]
fn a_scene_file_turns_whitewater_on_with_its_settings() {
    let text = r#"(
    container: (min: (0.0, 0.0, 0.0), max: (0.4, 0.3, 0.2)),
    blocks: [(min: (0.0, 0.0, 0.0), max: (0.1, 0.1, 0.2), velocity: (3.0, 0.0, 0.0))],
    whitewater: (capacity: 500, lifetime: (1.0, 2.0)),
)"#;
    let dir = scene_dir("whitewater", text);
    let mut app = app_with_scene(&dir, 4_000);
    for _ in 0..500 {
        app.update();
        if app.world().contains_resource::<SphWhitewater>()
            && app.world().resource::<SphStats>().particle_count > 0
        {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    let whitewater = *app.world().resource::<SphWhitewater>();
    assert_eq!(whitewater.capacity, 500);
    assert_eq!(whitewater.settings.lifetime, (1.0, 2.0));
    step_to(&mut app, 100);
    let counts = counts(&app);
    assert!(counts.born > 0, "{counts:?}");
    assert!(counts.spray + counts.foam + counts.bubbles <= 500);
}

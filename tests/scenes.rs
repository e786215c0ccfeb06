//! Scene files through Bevy's asset system (`SphScene`): a file's container, colliders, blocks
//! and parameters are spawned; editing the file and reloading it rebuilds the scene; a broken
//! edit is reported by file, line and field while the running scene stays; a kinematic collider
//! follows its path by simulated time.

mod common;

use bevy::prelude::*;
use bevy_sph_fluid::prelude::*;
use bevy_sph_fluid::scene_asset::SphColliderPath;
use sph_core::Solver;

const GOOD: &str = r#"(
    solver: Pbf(),
    container: (min: (0.0, 0.0, 0.0), max: (0.6, 0.4, 0.3)),
    colliders: [
        (name: "ball", shape: Sphere(radius: 0.05), position: (0.45, 0.05, 0.15)),
        (
            name: "gate",
            shape: Cuboid(half_extents: (0.02, 0.2, 0.14)),
            position: (0.3, 0.2, 0.15),
            motion: Kinematic(path: [(0.0, (0.3, 0.2, 0.15)), (1.0, (0.3, 1.2, 0.15))]),
        ),
    ],
    blocks: [(min: (0.0, 0.0, 0.0), max: (0.2, 0.2, 0.2))],
)"#;

fn update_until(app: &mut App, what: &str, done: impl Fn(&mut App) -> bool) {
    for _ in 0..500 {
        app.update();
        if done(app) {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    panic!(
        "{what}: not after 500 frames ({:?})",
        app.world().resource::<SphStats>().error
    );
}

fn members(app: &mut App) -> usize {
    app.world_mut()
        .query::<&SphSceneMember>()
        .iter(app.world())
        .count()
}

#[test]
fn a_scene_file_spawns_reloads_and_survives_a_broken_edit() {
    let dir = common::scene_dir("reload", GOOD);
    let mut app = common::app_with_scene(&dir, 4_000);
    // Container, two colliders, one block.
    update_until(&mut app, "the scene spawns", |app| members(app) == 4);
    update_until(&mut app, "the block spawns", |app| {
        app.world().resource::<SphStats>().particle_count > 0
    });
    let stats = app.world().resource::<SphStats>().clone();
    assert_eq!(stats.particle_count, 10 * 10 * 10);
    assert_eq!(app.world().resource::<SphParams>().solver, Solver::Pbf);
    let names: Vec<String> = app
        .world_mut()
        .query_filtered::<&Name, With<SphCollider>>()
        .iter(app.world())
        .map(|n| n.to_string())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");

    // An edit: a second block and WCSPH. Reloading rebuilds the scene and resets the water.
    let edited = GOOD.replace("solver: Pbf(),", "solver: Wcsph,").replace(
        "blocks: [(min: (0.0, 0.0, 0.0), max: (0.2, 0.2, 0.2))],",
        "blocks: [(min: (0.0, 0.0, 0.0), max: (0.2, 0.2, 0.2)), \
             (min: (0.4, 0.2, 0.0), max: (0.6, 0.3, 0.1))],",
    );
    std::fs::write(dir.join("scene.ron"), edited).unwrap();
    app.world().resource::<AssetServer>().reload("scene.ron");
    update_until(&mut app, "the edit reloads", |app| {
        app.world().resource::<SphParams>().solver == Solver::Wcsph
            && app.world().resource::<SphStats>().particle_count == 1000 + 10 * 5 * 5
    });
    assert_eq!(
        members(&mut app),
        5,
        "the old entities are gone, the new ones there"
    );

    // A broken edit: refused by file, line and field; the running scene stays.
    let broken = GOOD.replace("radius: 0.05", "radius: -0.05");
    std::fs::write(dir.join("scene.ron"), broken).unwrap();
    app.world().resource::<AssetServer>().reload("scene.ron");
    update_until(&mut app, "the broken edit is reported", |app| {
        app.world().resource::<SphStats>().scene_error.is_some()
    });
    let error = app
        .world()
        .resource::<SphStats>()
        .scene_error
        .clone()
        .unwrap();
    assert_eq!(
        app.world().resource::<SphStats>().error.as_ref(),
        Some(&error),
        "the panel's error line shows it"
    );
    assert!(
        error.starts_with("scene scene.ron:5:")
            && error.contains("radius")
            && error.contains("-0.05"),
        "{error}"
    );
    for _ in 0..5 {
        app.update();
    }
    assert_eq!(members(&mut app), 5, "the running scene stays");
    assert_eq!(app.world().resource::<SphParams>().solver, Solver::Wcsph);
    assert_eq!(
        app.world().resource::<SphStats>().particle_count,
        1000 + 10 * 5 * 5
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_kinematic_collider_follows_its_path_by_simulated_time() {
    let dir = common::scene_dir("path", GOOD);
    let mut app = common::app_with_scene(&dir, 4_000);
    app.insert_resource(SphControl {
        running: true,
        substeps: 4,
        ..default()
    });
    update_until(&mut app, "the water has run 0.2 s", |app| {
        app.world().resource::<SphStats>().sim_time > 0.2
    });
    app.update();
    let t = app.world().resource::<SphStats>().sim_time as f32;
    let (path, transform) = app
        .world_mut()
        .query::<(&SphColliderPath, &Transform)>()
        .single(app.world())
        .unwrap();
    assert_eq!(path.0.name, "gate");
    // The transform was placed before this frame's steps: at most a frame behind.
    let expected = 0.2 + t;
    assert!(
        (transform.translation.y - expected).abs() < 0.05,
        "gate at y = {} at t = {t}",
        transform.translation.y
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// An app that starts without a container (a scene file's comes a few frames later) names the
/// missing container, and the error goes when the container comes, on both backends.
#[test]
fn the_missing_containers_error_goes_when_the_container_comes() {
    let _gpu = common::GPU.lock().unwrap_or_else(|e| e.into_inner());
    for backend in [SphBackend::Cpu, SphBackend::Gpu] {
        let mut app = common::headless_app(64, backend);
        app.insert_resource(SphControl {
            running: true,
            ..default()
        });
        let names_it = |app: &mut App| {
            app.world()
                .resource::<SphStats>()
                .error
                .as_deref()
                .is_some_and(|e| e.contains("SphContainer"))
        };
        update_until(&mut app, &format!("{backend:?}: the error named"), names_it);
        app.world_mut()
            .spawn(SphContainer(sph_core::BoxContainer::from_min_max(
                Vec3::ZERO,
                Vec3::splat(0.2),
            )));
        update_until(&mut app, &format!("{backend:?}: the error gone"), |app| {
            !names_it(app)
        });
    }
}

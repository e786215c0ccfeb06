//! Scene files (`assets/scenes/*.ron`): the shipped scenes parse and build, and bad files are
//! refused with the file, the line, the field, the value and what is allowed.

use sph_core::glam::Vec3;
use sph_core::scene::{SceneError, SceneFile, SceneSetup};
use sph_core::{ColliderShape, Solver};

fn load(name: &str) -> (String, Result<SceneSetup, SceneError>) {
    let path = format!("{}/../../assets/scenes/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    let built = SceneFile::parse(&text, name).and_then(|s| s.build(name, &text));
    (text, built)
}

fn build(text: &str) -> Result<SceneSetup, SceneError> {
    SceneFile::parse(text, "test.ron").and_then(|s| s.build("test.ron", text))
}

#[test]
fn the_shipped_scenes_build() {
    let (_, dam) = load("dam_break.ron");
    let dam = dam.unwrap();
    assert_eq!(dam.params.solver, Solver::Wcsph);
    assert_eq!(dam.colliders.len(), 2);
    assert_eq!(dam.blocks[0].0.count(), 10 * 20 * 15);
    let (_, pipe) = load("pipe_fill.ron");
    let pipe = pipe.unwrap();
    assert_eq!(pipe.params.solver, Solver::Pbf);
    assert_eq!(pipe.emitters[0].total, Some(8000));
    let (_, gate) = load("gate.ron");
    let gate = gate.unwrap();
    assert_eq!(gate.params.solver, Solver::Dfsph);
    let lift = &gate.colliders[0];
    assert_eq!(lift.position_at(0.0), Vec3::new(0.4, 0.25, 0.05));
    assert!((lift.position_at(0.7) - Vec3::new(0.4, 0.5, 0.05)).length() < 1e-6);
    assert_eq!(lift.position_at(5.0), Vec3::new(0.4, 0.75, 0.05));
    let (_, lock) = load("lock.ron");
    let lock = lock.unwrap();
    assert_eq!((lock.colliders.len(), lock.probes.len()), (2, 3));
    assert!(lock.colliders[1].body.is_some(), "the boat");
    let (_, aquaplay) = load("aquaplay.ron");
    let aquaplay = aquaplay.unwrap();
    assert_eq!(aquaplay.sinks.len(), 1);
    assert_eq!(aquaplay.pumps.len(), 1);
    assert_eq!(aquaplay.probes.len(), 4);
    assert_eq!(aquaplay.emitters.len(), 1);
    let wheel = &aquaplay.colliders[3];
    assert_eq!(wheel.name, "water_wheel");
    assert_eq!(wheel.hinge.map(|h| h.axis), Some(Vec3::Z));
    assert!(matches!(wheel.collider.shape, ColliderShape::TriMesh(_)));
    let (_, ramp) = load("ramp.ron");
    let ramp = ramp.unwrap();
    let shapes: Vec<_> = ramp.colliders.iter().map(|c| &c.collider.shape).collect();
    match shapes[..] {
        [ColliderShape::TriMesh(wedge), ColliderShape::TriMesh(chute)] => {
            assert_eq!(wedge.thickness(), None, "the wedge is closed");
            assert_eq!(wedge.triangles().len(), 8);
            assert_eq!(chute.thickness(), Some(0.02), "the chute is an open shell");
            // The wedge's slope: under it inside, above it outside (local frame).
            assert!(wedge.signed_distance(Vec3::new(0.1, 0.02, 0.0)) < 0.0);
            assert!(wedge.signed_distance(Vec3::new(-0.1, 0.06, 0.0)) > 0.0);
        }
        _ => panic!("ramp.ron's colliders are two meshes: {shapes:?}"),
    }
    // Every block of every shipped scene lies inside its container.
    for scene in [&dam, &pipe, &gate, &lock, &aquaplay, &ramp] {
        for (block, _) in &scene.blocks {
            assert!(
                scene.container.contains(block.min, 1e-6)
                    && scene.container.contains(block.max, 1e-6)
            );
        }
    }
}

#[test]
fn overrides_and_settings_reach_the_parameters() {
    let s = build(
        "(spacing: 0.01, solver: Pbf(iterations: 7, vorticity_epsilon: 0.1), \
         overrides: (gravity: (0.0, -5.0, 0.0), surface_tension: 0.5), \
         container: (min: (0.0, 0.0, 0.0), max: (0.3, 0.3, 0.3)))",
    )
    .unwrap();
    assert!((s.params.spacing() - 0.01).abs() < 1e-7);
    assert_eq!(s.params.pbf.iterations, 7);
    assert_eq!(s.params.pbf.vorticity_epsilon, 0.1);
    assert_eq!(s.params.gravity, Vec3::new(0.0, -5.0, 0.0));
    assert_eq!(s.params.surface_tension, 0.5);
    let d = build(
        "(solver: Dfsph(max_density_error_pct: 0.05), container: (min: (0.0, 0.0, 0.0), max: (0.3, 0.3, 0.3)))",
    )
    .unwrap();
    assert!((d.params.dfsph.max_density_error - 5e-4).abs() < 1e-9);
}

#[test]
fn bad_files_name_the_line_the_field_and_what_is_allowed() {
    // A misspelt key.
    let e =
        build("(\n  container: (min: (0.0, 0.0, 0.0), max: (1.0, 1.0, 1.0)),\n  colider: [],\n)")
            .unwrap_err();
    assert_eq!((e.line, e.field.as_str()), (3, "colider"), "{e}");
    assert!(
        e.message.contains("colliders"),
        "the allowed fields are listed: {e}"
    );
    // A missing container.
    let e = build("(spacing: 0.02)").unwrap_err();
    assert_eq!(e.field, "container", "{e}");
    // A mistyped value.
    let e = build("(container: (min: (0.0, 0.0, 0.0), max: \"big\"))").unwrap_err();
    assert_eq!(e.line, 1, "{e}");
    // Values out of range, with the field, the value and the range, on their line.
    let e = build(
        "(\n  container: (min: (0.0, 0.0, 0.0), max: (1.0, 1.0, 1.0)),\n  colliders: [\n    (name: \"a\", shape: Sphere(radius: 0.1), position: (0.5, 0.5, 0.5)),\n    (name: \"b\", shape: Sphere(radius: -0.1), position: (0.5, 0.5, 0.5)),\n  ],\n)",
    )
    .unwrap_err();
    assert_eq!(e.line, 5, "{e}");
    assert!(
        e.field.contains("colliders[1]") && e.field.contains("radius"),
        "{e}"
    );
    assert!(e.message.contains("-0.1"), "{e}");
    let e = build(
        "(\n  solver: Pbf(iterations: 0),\n  container: (min: (0.0, 0.0, 0.0), max: (1.0, 1.0, 1.0)),\n)",
    )
    .unwrap_err();
    assert_eq!((e.line, e.field.as_str()), (2, "pbf.iterations"), "{e}");
    assert!(e.message.contains("[1, 100]"), "{e}");
    let e = build(
        "(container: (min: (0.0, 0.0, 0.0), max: (1.0, 1.0, 1.0)), colliders: [(name: \"gate\", \
         shape: Sphere(radius: 0.1), position: (0.5, 0.5, 0.5), \
         motion: Kinematic(path: [(1.0, (0.0, 0.0, 0.0)), (0.5, (0.0, 1.0, 0.0))]))])",
    )
    .unwrap_err();
    assert!(e.field.contains("motion.path[1].time"), "{e}");
    // Blocks and emitters are located in their own sections, past the container's `min` and a
    // collider's `radius`.
    let e = build(
        "(\n  container: (min: (0.0, 0.0, 0.0), max: (1.0, 1.0, 1.0)),\n  colliders: [(name: \"a\", shape: Sphere(radius: 0.1), position: (0.5, 0.5, 0.5))],\n  blocks: [\n    (min: (0.0, 0.0, 0.0), max: (0.1, 0.1, 0.1)),\n    (min: (0.0, 0.0, 0.0), max: (0.1, NaN, 0.1)),\n  ],\n  emitters: [(position: (0.5, 0.9, 0.5), direction: (1.0, 0.0, 0.0), radius: -1.0, speed: 1.0)],\n)",
    )
    .unwrap_err();
    assert!(e.field.starts_with("blocks[1]"), "{e}");
    assert_eq!(e.line, 6, "{e}");
    let e = build(
        "(\n  container: (min: (0.0, 0.0, 0.0), max: (1.0, 1.0, 1.0)),\n  colliders: [(name: \"a\", shape: Sphere(radius: 0.1), position: (0.5, 0.5, 0.5))],\n  emitters: [(position: (0.5, 0.9, 0.5), direction: (1.0, 0.0, 0.0), radius: -1.0, speed: 1.0)],\n)",
    )
    .unwrap_err();
    assert_eq!(
        (e.line, e.field.as_str()),
        (4, "emitters[0].emitter.radius"),
        "{e}"
    );
    // The display names the file.
    assert!(e.to_string().starts_with("test.ron:4:"), "{e}");
    // A mesh that is not watertight, without a thickness, is refused on its line, naming an
    // open edge.
    let e = build(
        "(\n  container: (min: (0.0, 0.0, 0.0), max: (1.0, 1.0, 1.0)),\n  colliders: [(\n    name: \"sheet\",\n    shape: Mesh(vertices: [(0.0, 0.0, 0.0), (0.1, 0.0, 0.0), (0.0, 0.0, 0.1)], indices: [0, 1, 2]),\n    position: (0.5, 0.5, 0.5),\n  )],\n)",
    )
    .unwrap_err();
    assert_eq!(e.field, "colliders[0] (\"sheet\").shape.triangles", "{e}");
    assert!(e.message.contains("watertight"), "{e}");
    let e = build(
        "(container: (min: (0.0, 0.0, 0.0), max: (1.0, 1.0, 1.0)), colliders: [(name: \"m\", \
         shape: Mesh(vertices: [(0.0, 0.0, 0.0)], indices: [0, 1, 2], thickness: Some(0.02)), \
         position: (0.5, 0.5, 0.5))])",
    )
    .unwrap_err();
    assert!(e.field.ends_with("shape.indices"), "{e}");
    assert!(e.message.contains("below the vertex count"), "{e}");
}

#[test]
fn the_readme_example_builds() {
    let readme =
        std::fs::read_to_string(format!("{}/../../README.md", env!("CARGO_MANIFEST_DIR"))).unwrap();
    let start = readme
        .find("```ron\n")
        .expect("a RON example in the README")
        + 7;
    let end = start + readme[start..].find("```").unwrap();
    let s = build(&readme[start..end]).unwrap();
    assert_eq!(s.params.solver, Solver::Dfsph);
    assert_eq!(s.colliders[0].name, "gate");
    assert_eq!(s.emitters[0].total, Some(2000));
}

#[test]
fn sinks_pumps_and_probes_are_built_and_bad_ones_refused_by_name() {
    let s = build(
        r#"(
    container: (min: (0.0, 0.0, 0.0), max: (1.0, 0.5, 0.3)),
    sinks: [(name: "drain", min: (0.9, 0.0, 0.0), max: (1.0, 0.1, 0.3), open: false)],
    pumps: [(name: "crank", min: (0.1, 0.0, 0.0), max: (0.3, 0.2, 0.3),
             direction: (1.0, 0.0, 0.0), speed: 0.4, strength: 5.0)],
    probes: [
        (name: "level", kind: Level(x: 0.5, z: 0.15)),
        (name: "channel", kind: Flux(position: (0.5, 0.1, 0.15), normal: (1.0, 0.0, 0.0),
                                     half_size: (0.15, 0.1)), every_steps: 10),
        (name: "basin", kind: Count(min: (0.0, 0.0, 0.0), max: (0.5, 0.5, 0.3))),
    ],
)"#,
    )
    .unwrap();
    assert_eq!(s.sinks[0].0, "drain");
    assert!(!s.sinks[0].1.open);
    assert!(s.sinks[0].1.region.contains(Vec3::new(0.95, 0.05, 0.1)));
    assert_eq!(s.pumps[0].1.speed, 0.4);
    assert_eq!(s.probes.len(), 3);
    assert_eq!(s.probes[1].every_steps, 10);
    match s.probes[0].kind {
        sph_core::ProbeKind::Level { radius, .. } => {
            assert!((radius - 2.0 * s.params.spacing()).abs() < 1e-7)
        }
        other => panic!("{other:?}"),
    }
    // A flux rectangle with normal +x turns local z onto x.
    match s.probes[1].kind {
        sph_core::ProbeKind::Flux { pose, .. } => {
            assert!((pose.rotation * Vec3::Z - Vec3::X).length() < 1e-6)
        }
        other => panic!("{other:?}"),
    }
    let bad = |section: &str| {
        format!("(\n    container: (min: (0.0, 0.0, 0.0), max: (1.0, 0.5, 0.3)),\n    {section}\n)")
    };
    let e = build(&bad(
        r#"pumps: [(name: "p", min: (0.0, 0.0, 0.0), max: (0.1, 0.1, 0.1), direction: (1.0, 0.0, 0.0), speed: -2.0, strength: 1.0)],"#,
    ))
    .unwrap_err();
    assert_eq!(
        (e.line, e.field.as_str()),
        (3, "pumps[0] (\"p\").pump.speed"),
        "{e}"
    );
    assert!(
        e.message.contains("-2") && e.message.contains("[0, 100]"),
        "{e}"
    );
    let e = build(&bad(
        r#"sinks: [(name: "d", min: (0.5, 0.0, 0.0), max: (0.1, 0.1, 0.1))],"#,
    ))
    .unwrap_err();
    assert!(e.field.starts_with("sinks[0] (\"d\")"), "{e}");
    let e = build(&bad(
        r#"probes: [(name: "q", kind: Level(x: 0.5, z: 0.1), every_steps: 0)],"#,
    ))
    .unwrap_err();
    assert_eq!(e.field, "probes[0] (\"q\").every_steps", "{e}");
    let e = build(&bad(r#"probes: [(name: "q", kind: Volume(x: 0.5))],"#)).unwrap_err();
    assert_eq!((e.line, e.field.as_str()), (3, "Volume"), "{e}");
}

#[test]
fn controls_drive_colliders_pumps_and_drains_and_unknown_names_are_refused() {
    let text = r#"(
    container: (min: (0.0, 0.0, 0.0), max: (1.0, 0.5, 0.3)),
    controls: [
        (name: "gate_lift", value: 0.25),
        (name: "crank", value: 1.0, max: 2.0),
        (name: "valve", value: 0.0),
    ],
    colliders: [(
        name: "gate",
        shape: Cuboid(half_extents: (0.02, 0.1, 0.1)),
        position: (0.5, 0.1, 0.15),
        motion: Controlled(control: "gate_lift", to: (0.5, 0.5, 0.15)),
    )],
    pumps: [(name: "pump", min: (0.0, 0.0, 0.0), max: (0.2, 0.1, 0.3),
             direction: (1.0, 0.0, 0.0), speed: 0.5, strength: 8.0, strength_control: "crank")],
    sinks: [(name: "drain", min: (0.9, 0.0, 0.0), max: (1.0, 0.1, 0.3), open_control: "valve")],
)"#;
    let s = build(text).unwrap();
    assert_eq!(s.controls.len(), 3);
    // A quarter of the way up, half the crank's range, the valve shut.
    assert!((s.colliders[0].collider.pose.translation.y - 0.2).abs() < 1e-6);
    assert_eq!(
        s.colliders[0].collider.motion,
        sph_core::ColliderMotion::Kinematic
    );
    assert!((s.pumps[0].1.strength - 4.0).abs() < 1e-6);
    assert!(!s.sinks[0].1.open);
    assert_eq!(s.bindings.len(), 3);

    let e = build(&text.replace("strength_control: \"crank\"", "strength_control: \"crnk\""))
        .unwrap_err();
    assert_eq!(
        (e.line, e.field.as_str()),
        (15, "pumps[0] (\"pump\").strength_control"),
        "{e}"
    );
    assert!(
        e.message.contains("\"crnk\"") && e.message.contains("gate_lift"),
        "{e}"
    );
    let e = build(&text.replace("control: \"gate_lift\"", "control: \"lift\"")).unwrap_err();
    assert_eq!(
        (e.line, e.field.as_str()),
        (12, "colliders[0] (\"gate\").control"),
        "{e}"
    );
    let e = build(&text.replace("value: 0.25", "value: 1.5")).unwrap_err();
    assert_eq!(
        (e.line, e.field.as_str()),
        (4, "controls[0] (\"gate_lift\").value"),
        "{e}"
    );
    let e = build(&text.replace(
        "(name: \"valve\", value: 0.0)",
        "(name: \"crank\", value: 0.0)",
    ))
    .unwrap_err();
    assert_eq!(e.field, "controls[2].name", "{e}");
}

#[test]
fn a_dynamic_body_needs_one_positive_density_or_mass() {
    let with = |motion: &str| {
        build(&format!(
            "(\n    container: (min: (0.0, 0.0, 0.0), max: (1.0, 0.5, 0.3)),\n    colliders: [(\n        name: \"boat\",\n        shape: Cuboid(half_extents: (0.05, 0.03, 0.04)),\n        position: (0.3, 0.2, 0.15),\n        motion: {motion},\n    )],\n)"
        ))
    };
    let boat = with("Dynamic(density: 400.0)").unwrap();
    assert_eq!(
        boat.colliders[0].collider.motion,
        sph_core::ColliderMotion::Dynamic
    );
    assert_eq!(
        boat.colliders[0].body,
        Some(sph_core::scene::BodyMass::Density(400.0))
    );
    for (motion, field) in [
        ("Dynamic(mass: 0.0)", "motion.mass"),
        ("Dynamic(mass: -1.0)", "motion.mass"),
        ("Dynamic(density: -400.0)", "motion.density"),
        ("Dynamic()", "motion"),
        ("Dynamic(mass: 1.0, density: 400.0)", "motion"),
    ] {
        let e = with(motion).unwrap_err();
        assert_eq!(e.line, 7, "{motion}: {e}");
        assert_eq!(
            e.field,
            format!("colliders[0] (\"boat\").{field}"),
            "{motion}: {e}"
        );
    }
}

#[test]
fn a_hinged_paddle_wheel_is_built_and_bad_ones_are_refused_by_field() {
    let with = |shape: &str, motion: &str| {
        build(&format!(
            "(\n    container: (min: (0.0, 0.0, 0.0), max: (1.0, 0.5, 0.3)),\n    colliders: [(\n        name: \"wheel\",\n        shape: {shape},\n        position: (0.3, 0.2, 0.15),\n        motion: {motion},\n    )],\n)"
        ))
    };
    let good_shape =
        "PaddleWheel(paddles: 6, inner: 0.02, outer: 0.08, thickness: 0.015, width: 0.1)";
    let good_motion = "Hinged(axis: (0.0, 0.0, 2.0), density: 900.0, damping: 1.0)";
    let wheel = with(good_shape, good_motion).unwrap();
    let c = &wheel.colliders[0];
    assert_eq!(c.collider.motion, sph_core::ColliderMotion::Dynamic);
    assert_eq!(c.body, Some(sph_core::scene::BodyMass::Density(900.0)));
    let hinge = c.hinge.unwrap();
    assert_eq!(
        (hinge.axis, hinge.damping),
        (Vec3::Z, 1.0),
        "the axis is normalised"
    );
    match &c.collider.shape {
        ColliderShape::TriMesh(mesh) => {
            assert_eq!(mesh.closed_parts().len(), 6);
            // Inside the paddle along +x, 5 cm from the axle (local frame).
            assert!(mesh.signed_distance(Vec3::new(0.05, 0.0, 0.0)) < 0.0);
        }
        other => panic!("a paddle wheel is a mesh: {other:?}"),
    }
    for (shape, motion, line, field) in [
        (
            "PaddleWheel(paddles: 1, inner: 0.02, outer: 0.08, thickness: 0.015, width: 0.1)",
            good_motion,
            5,
            "shape.paddles",
        ),
        (
            "PaddleWheel(paddles: 6, inner: 0.09, outer: 0.08, thickness: 0.015, width: 0.1)",
            good_motion,
            5,
            "shape.inner",
        ),
        (
            "PaddleWheel(paddles: 6, inner: 0.02, outer: 0.08, thickness: 0.05, width: 0.1)",
            good_motion,
            5,
            "shape.thickness",
        ),
        (
            good_shape,
            "Hinged(axis: (0.0, 0.0, 0.0), density: 900.0)",
            7,
            "motion.axis",
        ),
        (
            good_shape,
            "Hinged(axis: (0.0, 0.0, 1.0), density: 900.0, damping: -1.0)",
            7,
            "motion.damping",
        ),
        (good_shape, "Hinged(axis: (0.0, 0.0, 1.0))", 7, "motion"),
    ] {
        let e = with(shape, motion).unwrap_err();
        assert_eq!(e.line, line, "{shape} {motion}: {e}");
        assert_eq!(e.field, format!("colliders[0] (\"wheel\").{field}"), "{e}");
    }
}

#[test]
fn sizes_a_file_implies_are_refused_before_anything_is_allocated() {
    let scene = |body: &str| {
        format!("(\n  container: (min: (0.0, 0.0, 0.0), max: (1.0, 1.0, 1.0)),\n{body}\n)")
    };
    // Emitter radii that would lay 1e19 disc points, or overflow the lattice's bounds.
    for radius in ["inf", "1e30", "-1e30", "NaN", "999.0"] {
        let e = build(&scene(&format!(
            "  emitters: [(position: (0.5, 0.9, 0.5), direction: (1.0, 0.0, 0.0), radius: {radius}, speed: 1.0)],"
        )))
        .unwrap_err();
        assert_eq!(
            (e.line, e.field.as_str()),
            (3, "emitters[0].emitter.radius"),
            "{radius}: {e}"
        );
    }
    // A block of 8e12 particles, and blocks each within the bound but not together.
    let e = build(&scene(
        "  blocks: [(min: (0.0, 0.0, 0.0), max: (400.0, 400.0, 400.0))],",
    ))
    .unwrap_err();
    assert_eq!(e.field, "blocks[0].block.max", "{e}");
    assert!(e.message.contains("4194304"), "{e}");
    let e = build(
        "(\n  container: (min: (0.0, 0.0, 0.0), max: (10.0, 10.0, 10.0)),\n  blocks: [\n    (min: (0.0, 0.0, 0.0), max: (3.0, 3.0, 2.4)),\n    (min: (0.0, 0.0, 0.0), max: (3.0, 3.0, 2.4)),\n  ],\n)",
    )
    .unwrap_err();
    assert_eq!(
        (e.line, e.field.as_str()),
        (5, "blocks[1].block.max"),
        "{e}"
    );
    assert!(e.message.contains("together"), "{e}");
    // A container whose walls alone would take 1.5e11 samples at the default spacing.
    let e = build("(container: (min: (0.0, 0.0, 0.0), max: (5000.0, 10.0, 5000.0)))").unwrap_err();
    assert!(
        e.field.contains("smoothing_radius") || e.field == "container",
        "{e}"
    );
    // A collider that samples to more than 2^24 points.
    let e = build(
        "(\n  container: (min: (0.0, 0.0, 0.0), max: (10.0, 10.0, 10.0)),\n  spacing: 0.05,\n  colliders: [(name: \"slab\", shape: Cuboid(half_extents: (60.0, 1.0, 60.0)), position: (5.0, 5.0, 5.0))],\n)",
    )
    .unwrap_err();
    assert_eq!(e.field, "colliders[0] (\"slab\").shape", "{e}");
    assert!(e.message.contains("2^24"), "{e}");
}

#[test]
fn a_file_cut_short_says_so() {
    let (text, built) = load("dam_break.ron");
    built.unwrap();
    for cut in [text.len() / 3, text.len() / 2, text.len() - 3] {
        let mut at = cut;
        while !text.is_char_boundary(at) {
            at -= 1;
        }
        let e = build(&text[..at]).unwrap_err();
        assert!(
            e.message.starts_with("unexpected end of file"),
            "cut at {at}: {e}"
        );
    }
    // An error inside the file is not called the end of it.
    let e = build("(container: (min: (0.0, 0.0, 0.0), max: \"big\"))").unwrap_err();
    assert!(!e.message.contains("end of file"), "{e}");
}

#[test]
fn whitewater_is_off_unless_the_file_turns_it_on_and_bad_fields_are_named() {
    let box_only = "(container: (min: (0.0, 0.0, 0.0), max: (0.3, 0.3, 0.3)))";
    assert_eq!(build(box_only).unwrap().whitewater, None);
    let on = build(
        "(\n  container: (min: (0.0, 0.0, 0.0), max: (0.3, 0.3, 0.3)),\n  whitewater: (capacity: 1000, lifetime: (1.0, 3.0)),\n)",
    )
    .unwrap();
    let (settings, capacity) = on.whitewater.expect("whitewater on");
    assert_eq!(capacity, 1000);
    assert_eq!(settings.lifetime, (1.0, 3.0));
    let e = build(
        "(\n  container: (min: (0.0, 0.0, 0.0), max: (0.3, 0.3, 0.3)),\n  whitewater: (\n    capacity: 0,\n  ),\n)",
    )
    .unwrap_err();
    assert_eq!(e.field, "whitewater.capacity");
    assert_eq!(e.line, 4, "{e}");
    assert!(e.message.contains("[1, 2^24]"), "{e}");
}

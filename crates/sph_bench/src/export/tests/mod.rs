//! `sph-bench export`: every shipped scene through both engines (which export, which are refused,
//! and that a refusal names each field), the written files read back against each engine's
//! documented schema ([`schema_splishsplash`], [`schema_dualsphysics`]), geometry that
//! round-trips, and the all-or-nothing write.

mod schema_dualsphysics;
mod schema_splishsplash;
mod support;

use super::common::{Export, ExportOptions, Loaded};
use super::mesh::Mesh;
use super::{convert, write};
use crate::args::ExportTarget::{self, Dualsphysics as Dsph, Splishsplash as Sph};
use schema_dualsphysics::check_dualsphysics;
use schema_splishsplash::check_splishsplash;
use sph_core::glam::Vec3;
use std::collections::HashMap;
use std::path::Path;
use support::{close3, load_file, load_text, options, volume};

fn check(target: ExportTarget, scene: &Loaded, export: &Export, opts: &ExportOptions) {
    match target {
        Sph => check_splishsplash(scene, export, opts),
        Dsph => check_dualsphysics(scene, export, opts),
    }
}

/// Each shipped scene, engine and --drop-probes: the fields refused (none: it exports).
fn shipped() -> Vec<(&'static str, ExportTarget, bool, Vec<&'static str>)> {
    let aquaplay_common = [
        r#"colliders[1] ("lock_gate").motion"#,
        r#"colliders[3] ("water_wheel").motion"#,
        r#"sinks[0] ("overflow_drain")"#,
        r#"pumps[0] ("crank_pump")"#,
    ];
    let with = |base: &[&'static str], more: &[&'static str]| [base, more].concat();
    let aquaplay_probes = [
        r#"probes[0] ("front_channel_flow")"#,
        r#"probes[1] ("left_basin_level")"#,
        r#"probes[2] ("right_basin_level")"#,
        r#"probes[3] ("back_channel_water")"#,
    ];
    let dam = vec![
        r#"probes[0] ("column_level")"#,
        r#"probes[1] ("front_flow")"#,
    ];
    let lock = vec![
        r#"probes[0] ("upper_level")"#,
        r#"probes[1] ("lower_level")"#,
        r#"probes[2] ("gate_flux")"#,
    ];
    let ramp = vec![
        r#"probes[0] ("over_the_crest")"#,
        r#"probes[1] ("far_level")"#,
    ];
    let gate = r#"colliders[0] ("gate").motion"#;
    let boat = r#"colliders[1] ("boat").motion"#;
    let aquaplay_sph = with(&aquaplay_common, &[r#"colliders[2] ("boat").motion"#]);
    let aquaplay_dsph = with(&aquaplay_common, &["emitters[0]"]);
    vec![
        (
            "aquaplay",
            Sph,
            false,
            with(&aquaplay_sph, &aquaplay_probes),
        ),
        ("aquaplay", Sph, true, aquaplay_sph),
        (
            "aquaplay",
            Dsph,
            false,
            with(&aquaplay_dsph, &aquaplay_probes),
        ),
        ("aquaplay", Dsph, true, aquaplay_dsph),
        ("basin_jet", Sph, false, vec![]),
        ("basin_jet", Sph, true, vec![]),
        ("basin_jet", Dsph, false, vec!["emitters[0]"]),
        ("basin_jet", Dsph, true, vec!["emitters[0]"]),
        ("dam_break", Sph, false, dam.clone()),
        ("dam_break", Sph, true, vec![]),
        ("dam_break", Dsph, false, dam),
        ("dam_break", Dsph, true, vec![]),
        ("gate", Sph, false, vec![gate]),
        ("gate", Sph, true, vec![gate]),
        ("gate", Dsph, false, vec![]),
        ("gate", Dsph, true, vec![]),
        ("lock", Sph, false, with(&[gate, boat], &lock)),
        ("lock", Sph, true, vec![gate, boat]),
        ("lock", Dsph, false, lock),
        ("lock", Dsph, true, vec![]),
        ("pipe_fill", Sph, false, vec![]),
        ("pipe_fill", Sph, true, vec![]),
        ("pipe_fill", Dsph, false, vec!["emitters[0]"]),
        ("pipe_fill", Dsph, true, vec!["emitters[0]"]),
        ("ramp", Sph, false, ramp.clone()),
        ("ramp", Sph, true, vec![]),
        ("ramp", Dsph, false, with(&ramp, &["emitters[0]"])),
        ("ramp", Dsph, true, vec!["emitters[0]"]),
    ]
}

#[test]
fn export_every_shipped_scene_or_refuse_it_by_field() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes");
    let mut stems: Vec<String> = std::fs::read_dir(&dir)
        .expect("assets/scenes")
        .filter_map(|e| {
            e.ok()?
                .path()
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
        })
        .collect();
    stems.sort();
    let table = shipped();
    let mut listed: Vec<&str> = table.iter().map(|e| e.0).collect();
    listed.dedup();
    assert_eq!(stems, listed, "a shipped scene without an expectation");
    for (stem, target, drop_probes, refused) in table {
        let scene = load_file(stem);
        let opts = options(drop_probes);
        let case = format!("{stem} to {target:?}, drop_probes {drop_probes}");
        match (convert(target, &scene, &opts), refused.is_empty()) {
            (Ok(export), true) => check(target, &scene, &export, &opts),
            (Err(e), false) => {
                let count = format!(
                    "(nothing written): {} it cannot express",
                    super::count(refused.len(), "field")
                );
                assert!(e.contains(&count), "{case}: not {count}:\n{e}");
                for field in refused {
                    assert!(
                        e.contains(&format!("`{field}`")),
                        "{case}: {field} not named:\n{e}"
                    );
                }
            }
            (Ok(_), false) => panic!("{case}: exported, expected refusals {refused:?}"),
            (Err(e), true) => panic!("{case}: refused:\n{e}"),
        }
    }
}

#[test]
fn export_other_shapes_round_trip_in_both_engines() {
    let scene = load_text(
        r#"(
            spacing: 0.02,
            solver: Dfsph(),
            container: (min: (0.0, 0.0, 0.0), max: (1.0, 0.6, 0.5)),
            colliders: [
                (name: "pill", shape: Capsule(radius: 0.04, half_length: 0.06), position: (0.3, 0.2, 0.25), rotation_degrees: (0.0, 0.0, 90.0)),
                (name: "post", shape: Cylinder(radius: 0.05, half_length: 0.1), position: (0.6, 0.12, 0.25), rotation_degrees: (20.0, 0.0, 0.0)),
                (name: "tilted box", shape: Cuboid(half_extents: (0.05, 0.03, 0.04)), position: (0.8, 0.1, 0.1), rotation_degrees: (0.0, 45.0, 10.0)),
                (name: "sheet", shape: Mesh(vertices: [(-0.1, 0.0, -0.1), (0.1, 0.0, -0.1), (0.1, 0.0, 0.1), (-0.1, 0.0, 0.1)], indices: [0, 2, 1, 0, 3, 2], thickness: Some(0.02)), position: (0.5, 0.4, 0.25), rotation_degrees: (0.0, 0.0, 30.0)),
                (name: "float", shape: Cuboid(half_extents: (0.04, 0.02, 0.04)), position: (0.85, 0.4, 0.35), motion: Dynamic(mass: 0.5)),
            ],
            blocks: [(min: (0.0, 0.0, 0.0), max: (0.2, 0.3, 0.5), velocity: (0.5, 0.0, 0.0))],
        )"#,
    );
    let opts = options(false);
    let export = convert(Dsph, &scene, &opts).unwrap_or_else(|e| panic!("{e}"));
    check_dualsphysics(&scene, &export, &opts);
    let xml = &export.files[0].1;
    assert!(
        xml.contains("<massbody value=\"0.5\" />")
            && xml.contains("<velocity mkfluid=\"0\" x=\"0.5\"")
    );
    let e = convert(Sph, &scene, &opts).expect_err("the float is dynamic");
    assert!(e.contains(r#"`colliders[4] ("float").motion`"#), "{e}");
    let mut still = scene.clone();
    still.spec.colliders.pop();
    still.setup.colliders.pop();
    let export = convert(Sph, &still, &opts).unwrap_or_else(|e| panic!("{e}"));
    check_splishsplash(&still, &export, &opts);
}

#[test]
fn export_refusals_name_the_field_the_value_and_why() {
    let base = |extra: &str| {
        format!("(spacing: 0.02, container: (min: (0.0, 0.0, 0.0), max: (0.6, 0.4, 0.3)), {extra})")
    };
    let cases: [(&str, ExportTarget, &str, &str); 5] = [
        ("emitters: [(position: (0.1, 0.3, 0.15), direction: (1.0, 0.0, 0.0), radius: 0.04, speed: 1.0)]", Sph, "emitters[0].total", "omitted (endless)"),
        ("blocks: [(min: (0.0, 0.0, 0.0), max: (0.2, 0.02, 0.2))]", Sph, "blocks[0]", "0.02 m along y"),
        ("overrides: (surface_tension: 0.05)", Dsph, "overrides.surface_tension", "0.05"),
        (r#"colliders: [(name: "g", shape: Sphere(radius: 0.05), position: (0.3, 0.1, 0.15), motion: Kinematic(path: [(0.5, (0.3, 0.1, 0.15)), (0.5, (0.3, 0.2, 0.15))]))]"#, Dsph, r#"colliders[0] ("g").motion.path"#, "a jump at 0.5 s"),
        (r#"colliders: [(name: "c", shape: Sphere(radius: 0.05), position: (0.3, 0.1, 0.15), no_slip_friction: 1.0)]"#, Dsph, r#"colliders[0] ("c").no_slip_friction"#, "= 1:"),
    ];
    for (extra, target, field, value) in cases {
        let e = convert(target, &load_text(&base(extra)), &options(false)).expect_err(field);
        assert!(e.starts_with("inline.ron: cannot export to"), "{e}");
        assert!(
            e.contains(&format!("`{field}`")) && e.contains(value),
            "{field}: {e}"
        );
    }
}

#[test]
fn export_meshes_are_closed_and_outward() {
    let quad = Mesh {
        vertices: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, 1.0), Vec3::Z],
        triangles: vec![[0, 2, 1], [0, 3, 2]],
    };
    let r: f32 = 0.05;
    let cases = [
        (Mesh::cuboid(Vec3::new(0.1, 0.2, 0.3)), 0.048, 1e-6),
        (
            Mesh::sphere(r, 32),
            4.0 / 3.0 * std::f32::consts::PI * r.powi(3),
            0.03,
        ),
        (
            Mesh::capsule(r, 0.1, 32),
            std::f32::consts::PI * r * r * (0.2 + 4.0 / 3.0 * r),
            0.03,
        ),
        (
            Mesh::cylinder(r, 0.1, 32),
            std::f32::consts::PI * r * r * 0.2,
            0.03,
        ),
        (quad.slab(0.02), 0.02, 1e-5),
    ];
    for (mesh, expected, tolerance) in cases {
        let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
        for t in &mesh.triangles {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
            }
        }
        // Watertight and consistently wound: every directed edge once, its reverse once.
        assert!(edges
            .iter()
            .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1)));
        let v = volume(&mesh);
        assert!(
            (v - expected).abs() <= tolerance * expected,
            "volume {v}, expected {expected}"
        );
    }
    let (lo, hi) = Mesh::sphere(r, 32).bounds();
    assert!(close3(lo, Vec3::splat(-r)) && close3(hi, Vec3::splat(r)));
}

#[test]
fn export_writes_all_or_nothing() {
    let parent = std::env::temp_dir().join(format!("sph_bench_export_{}", std::process::id()));
    let out = parent.join("pipe_fill");
    let export =
        convert(Sph, &load_file("pipe_fill"), &options(false)).unwrap_or_else(|e| panic!("{e}"));
    let written = write(&out, &export).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(written.len(), export.files.len());
    for (name, text) in &export.files {
        assert_eq!(
            &std::fs::read_to_string(out.join(name)).expect("written"),
            text
        );
    }
    let e = write(&out, &Export::default()).expect_err("OUT is not empty");
    assert!(e.contains("exists and is not an empty directory"), "{e}");
    assert!(
        out.join("scene.json").exists(),
        "a refused write leaves OUT as it was"
    );
    let left: Vec<_> = std::fs::read_dir(&parent)
        .expect("parent")
        .filter_map(|e| e.ok())
        .collect();
    assert_eq!(left.len(), 1, "no staging directory is left behind");
    std::fs::remove_dir_all(&parent).expect("clean up");
}

#[test]
fn export_arguments_are_parsed() {
    use clap::Parser;
    let cli = crate::args::Cli::try_parse_from([
        "sph-bench",
        "export",
        "--to",
        "dualsphysics",
        "a.ron",
        "out",
    ]);
    let Ok(crate::args::Cli {
        command: crate::args::Command::Export(a),
        ..
    }) = cli
    else {
        panic!("not an export");
    };
    assert_eq!(
        (a.to, a.time, a.drop_probes),
        (Dsph, crate::scene_run::SCENE_DURATION as f32, false)
    );
    let e =
        crate::args::Cli::try_parse_from(["sph-bench", "export", "--to", "flip", "a.ron", "out"])
            .expect_err("no such engine");
    assert!(
        e.to_string().contains("splishsplash") && e.to_string().contains("dualsphysics"),
        "{e}"
    );
}

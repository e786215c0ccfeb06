//! A scene file as a DualSPHysics case: `Case_Def.xml` for GenCase, with an STL file per
//! collider that has no GenCase primitive, run by `GenCase Case_Def out/Case` then
//! `DualSPHysics5.4CPU_linux64 out/Case out`.
//!
//! Format: DualSPHysics's `doc/xml_format/GenCase_CaseTemplate.xml` (v5.4; `constantsdef`,
//! `mkconfig`, `geometry` with `definition` and the `mainlist` commands `setmkfluid`,
//! `setmkbound`, `drawbox`, `drawsphere`, `drawcylinder`, `drawfilestl`; `initials`,
//! `floatings`, `motion` with `objreal`/`begin`/`mvrect`), `doc/xml_format/_FmtXML__Parameters.xml`
//! (the `execution` parameters) and `examples/main/01_DamBreak/CaseDambreak_Def.xml`
//! (DualSPHysics/DualSPHysics). Conventions:
//!
//! - DualSPHysics's vertical is z: the scene's point (x, y, z) is (x, −z, y) there (a rotation
//!   about x, so meshes keep their winding), gravity included.
//! - `dp` is our spacing Δx; `speedsound` is our c0 (`auto="false"`), `rhop0` our ρ0, `gamma` 7
//!   (1 for the linear law), so its B = c0² ρ0 / γ is ours. Its smoothing length keeps the
//!   template's `coefh` (h = 1.5 Δx) and its time step its own CFL rule (`cflnumber` 0.2) unless
//!   the scene fixes dt (`DtFixed`).
//! - Viscosity is `ViscoTreatment` 3 (laminar) with `Visco` our kinematic ν = μ/ρ0 [m²/s], and
//!   `ViscoBoundFactor` 0 for our free-slip walls.
//! - Later commands overwrite earlier particles, so the fluid is drawn first, then the container
//!   (`drawbox` with every face), then each collider as mk 1, 2, ... with `setdrawmode full`
//!   (solid); an STL collider uses `autofill`. A kinematic path becomes `mvrect` segments of
//!   constant velocity, a dynamic body a `floating` with `rhopbody` or `massbody`.

use super::common::{
    collider_field, common_refusals, Export, ExportOptions, Loaded, Refusal, DATA_FPS,
};
use super::mesh::{file_stem, Mesh};
use super::xml::{num, value, xyz, Xml};
use sph_core::boundary::collider::ColliderShape;
use sph_core::glam::{Quat, Vec3};
use sph_core::params::EquationOfState;
use sph_core::scene::{BodyMass, SceneCollider};
use sph_core::Solver;
use std::path::Path;

/// The engine's name.
pub const ENGINE: &str = "DualSPHysics";

/// The case definition's file name in OUT.
pub const CASE_FILE: &str = "Case_Def.xml";

/// The template's smoothing-length coefficient: h = coefh √(3 dp²) = 1.5 dp.
const COEFH: f32 = 0.866025;

/// The template's CFL number of DualSPHysics's own time step.
const CFL_NUMBER: f32 = 0.2;

/// The execution parameters that do not depend on the scene: DBC walls (`Boundary` 1), the
/// symplectic step, the Wendland kernel, laminar viscosity without wall friction (our free slip),
/// Fourtakas's density diffusion 0.1 (the dam-break example's), no shifting, SPH contact for
/// floating bodies, and DualSPHysics's own step limits.
const FIXED_PARAMETERS: &str = "Boundary=1 StepAlgorithm=2 Kernel=2 ViscoTreatment=3 \
    ViscoBoundFactor=0 DensityDT=2 DensityDTvalue=0.1 Shifting=0 RigidAlgorithm=1 FtPause=0 \
    CoefDtMin=0.05 DtIni=0 DtMin=0 DtAllParticles=0";

/// The scene's point `p` in DualSPHysics's frame (z up).
pub fn to_dsph(p: Vec3) -> Vec3 {
    Vec3::new(p.x, -p.z, p.y)
}

/// The scene's axis-aligned box `min..max` as DualSPHysics's (min, max).
pub fn box_to_dsph(min: Vec3, max: Vec3) -> (Vec3, Vec3) {
    let (a, b) = (to_dsph(min), to_dsph(max));
    (a.min(b), a.max(b))
}

/// Draws collider `k` (mk `mk`) in the scene's frame; a shape without a GenCase primitive goes
/// to an STL file.
fn draw(
    xml: &mut Xml,
    c: &SceneCollider,
    k: usize,
    mk: u32,
    spacing: f32,
) -> Option<(String, String)> {
    let pose = &c.collider.pose;
    xml.comment(&format!("colliders[{k}] {:?}", c.name));
    xml.empty("setmkbound", &[("mk", mk.to_string())]);
    let axis_end = |s: f32, half: f32| to_dsph(pose.to_world(Vec3::Y * (s * half)));
    match c.collider.shape {
        ColliderShape::Cuboid { half_extents }
            if pose.rotation.angle_between(Quat::IDENTITY) < 1e-6 =>
        {
            let t = pose.translation;
            let (lo, hi) = box_to_dsph(t - half_extents, t + half_extents);
            xml.draw_box("solid", lo, hi);
            None
        }
        ColliderShape::Sphere { radius } => {
            xml.draw_sphere(radius, to_dsph(pose.translation));
            None
        }
        ColliderShape::Cylinder {
            radius,
            half_length,
        }
        | ColliderShape::Capsule {
            radius,
            half_length,
        } => {
            let ends = [axis_end(-1.0, half_length), axis_end(1.0, half_length)];
            xml.open("drawcylinder", &[("radius", num(radius))]);
            ends.iter().for_each(|&p| xml.point("point", p));
            xml.close("drawcylinder");
            if matches!(c.collider.shape, ColliderShape::Capsule { .. }) {
                ends.iter().for_each(|&p| xml.draw_sphere(radius, p));
            }
            None
        }
        _ => {
            let mesh = Mesh::of_shape(&c.collider.shape, pose, spacing).map(to_dsph);
            let file = format!("collider_{k}_{}.stl", file_stem(&c.name));
            xml.empty(
                "drawfilestl",
                &[("file", file.clone()), ("autofill", "true".into())],
            );
            Some((file.clone(), mesh.to_stl(&file)))
        }
    }
}

/// The `objreal` of a kinematic path: constant-velocity `mvrect` segments from its first move.
fn motion(xml: &mut Xml, c: &SceneCollider, field: &str, mk: u32, refusals: &mut Vec<Refusal>) {
    let mut knots = vec![(0.0, c.position_at(0.0))];
    knots.extend(c.path.iter().copied().filter(|&(t, _)| t > 0.0));
    let mut segments = Vec::new();
    for (i, pair) in knots.windows(2).enumerate() {
        let ((t0, a), (t1, b)) = (pair[0], pair[1]);
        if t1 > t0 {
            segments.push((t0, t1 - t0, (b - a) / (t1 - t0)));
        } else if a != b {
            refusals.push(Refusal::new(
                format!("{field}.motion.path"),
                format!("a jump at {t1} s from {a} to {b} (waypoint {i})"),
                "DualSPHysics moves a body by velocities over durations; it cannot jump",
            ));
        }
    }
    let Some(first) = segments.iter().position(|s| s.2 != Vec3::ZERO) else {
        return;
    };
    xml.open("objreal", &[("ref", mk.to_string())]);
    xml.empty(
        "begin",
        &[("mov", "1".into()), ("start", num(segments[first].0))],
    );
    let moves = &segments[first..];
    for (i, &(_, duration, velocity)) in moves.iter().enumerate() {
        let mut attrs = vec![("id", (i + 1).to_string()), ("duration", num(duration))];
        if i + 1 < moves.len() {
            attrs.push(("next", (i + 2).to_string()));
        }
        xml.open("mvrect", &attrs);
        xml.point("vel", to_dsph(velocity));
        xml.close("mvrect");
    }
    xml.close("objreal");
}

/// Converts `scene`; every field DualSPHysics cannot express is refused.
pub fn convert(scene: &Loaded, options: &ExportOptions) -> Result<Export, Vec<Refusal>> {
    let mut refusals = common_refusals(scene, options, ENGINE);
    let mut export = Export::default();
    let setup = &scene.setup;
    let p = &setup.params;
    let dp = p.spacing();
    if p.has_surface_tension() && p.solver != Solver::Pbf {
        refusals.push(Refusal::new(
            "overrides.surface_tension",
            num(p.surface_tension),
            "DualSPHysics's single-phase solver has no surface tension",
        ));
    }
    for (k, e) in setup.emitters.iter().enumerate() {
        refusals.push(Refusal::new(
            format!("emitters[{k}]"),
            format!("a pipe of radius {} m at {}", e.radius, e.position),
            "DualSPHysics's inlets (inout zones) are buffer layers on the domain's edge with a \
             velocity, not a free jet of a number of particles",
        ));
    }
    let mut geometry = Xml::at(5);
    let mut initials = Xml::at(3);
    geometry.text("setshapemode", "dp | bound");
    geometry.empty("setdrawmode", &[("mode", "full".into())]);
    for (k, (block, velocity)) in setup.blocks.iter().enumerate() {
        if block.lattice_dims().contains(&0) {
            export
                .notes
                .push(format!("blocks[{k}] holds no particle and is left out"));
            continue;
        }
        let (lo, hi) = box_to_dsph(block.min, block.max);
        geometry.comment(&format!("blocks[{k}]"));
        geometry.empty("setmkfluid", &[("mk", k.to_string())]);
        geometry.draw_box("solid", lo, hi);
        if *velocity != Vec3::ZERO {
            let mut attrs = vec![("mkfluid", k.to_string())];
            attrs.extend(xyz(to_dsph(*velocity)));
            initials.empty("velocity", &attrs);
        }
    }
    let (min, max) = (setup.container.min(), setup.container.max());
    let (wall_lo, wall_hi) = box_to_dsph(min, max);
    geometry.comment("the container");
    geometry.empty("setmkbound", &[("mk", "0".into())]);
    geometry.draw_box("all", wall_lo, wall_hi);
    let (mut lo, mut hi) = (wall_lo, wall_hi);
    let mut floatings = Xml::at(3);
    let mut moving = Xml::at(3);
    for (k, c) in setup.colliders.iter().enumerate() {
        let mk = k as u32 + 1;
        let field = collider_field(k, &c.name);
        if let Some(file) = draw(&mut geometry, c, k, mk, dp) {
            export.files.push(file);
        }
        let (a, b) = Mesh::of_shape(&c.collider.shape, &c.collider.pose, dp).bounds();
        for q in c
            .path
            .iter()
            .map(|w| w.1)
            .chain([c.collider.pose.translation])
        {
            let shift = q - c.collider.pose.translation;
            let (sa, sb) = box_to_dsph(a + shift, b + shift);
            (lo, hi) = (lo.min(sa), hi.max(sb));
        }
        if !c.path.is_empty() {
            motion(&mut moving, c, &field, mk, &mut refusals);
        }
        match c.body {
            Some(BodyMass::Density(d)) if c.hinge.is_none() => floatings.empty(
                "floating",
                &[("mkbound", mk.to_string()), ("rhopbody", num(d))],
            ),
            Some(BodyMass::Mass(m)) if c.hinge.is_none() => {
                floatings.open("floating", &[("mkbound", mk.to_string())]);
                floatings.empty("massbody", &value(m));
                floatings.close("floating");
            }
            _ => {}
        }
    }
    if !refusals.is_empty() {
        return Err(refusals);
    }
    if p.solver != Solver::Wcsph {
        export.notes.push(format!(
            "{:?} runs as DualSPHysics's weakly compressible SPH (its only solver) with the \
             scene's speed of sound",
            p.solver
        ));
    }
    let margin = Vec3::splat(3.0 * dp);
    let domain = (lo - margin, hi + margin);
    let fixed_dt = scene.spec.overrides.time_step.is_some() && !p.adaptive_time_step;
    if !fixed_dt {
        export.notes.push(format!(
            "time step: DualSPHysics's own rule (cflnumber {CFL_NUMBER}), not sph-bench's"
        ));
    }
    let case = case_xml(
        scene,
        options,
        domain,
        wall_lo,
        fixed_dt,
        [geometry, initials, floatings, moving],
    );
    export.files.insert(0, (CASE_FILE.into(), case));
    Ok(export)
}

/// The whole case definition around the geometry commands and the initials, floatings and
/// motion sections.
fn case_xml(
    scene: &Loaded,
    options: &ExportOptions,
    (lo, hi): (Vec3, Vec3),
    lattice_origin: Vec3,
    fixed_dt: bool,
    [geometry, initials, floatings, moving]: [Xml; 4],
) -> String {
    let p = &scene.setup.params;
    let gamma = match p.equation_of_state {
        EquationOfState::Tait => 7.0,
        EquationOfState::Linear => 1.0,
    };
    let mut x = Xml::default();
    x.line("<?xml version=\"1.0\" encoding=\"UTF-8\" ?>");
    x.comment(&format!(
        "{} exported by sph-bench. DualSPHysics's z is the scene's y: (x, y, z) -> (x, -z, y).",
        scene.file
    ));
    x.open("case", &[]);
    x.open("casedef", &[]);
    x.open("constantsdef", &[]);
    x.empty("lattice", &[("bound", "1".into()), ("fluid", "1".into())]);
    x.point("gravity", to_dsph(p.gravity));
    x.empty("rhop0", &value(p.rest_density));
    x.empty("rhopgradient", &value(2.0));
    x.empty("hswl", &[("value", "0".into()), ("auto", "true".into())]);
    x.empty("gamma", &value(gamma));
    x.empty(
        "speedsystem",
        &[("value", "0".into()), ("auto", "true".into())],
    );
    x.empty("coefsound", &value(20.0));
    let c0 = num(p.speed_of_sound());
    x.empty("speedsound", &[("value", c0), ("auto", "false".into())]);
    x.empty("coefh", &value(COEFH));
    x.empty("cflnumber", &value(CFL_NUMBER));
    x.close("constantsdef");
    let bound_count = (scene.setup.colliders.len() + 1).max(240);
    let fluid_count = scene.setup.blocks.len().max(9);
    x.empty(
        "mkconfig",
        &[
            ("boundcount", bound_count.to_string()),
            ("fluidcount", fluid_count.to_string()),
        ],
    );
    x.open("geometry", &[]);
    x.open("definition", &[("dp", num(p.spacing()))]);
    x.point("pointref", lattice_origin);
    x.point("pointmin", lo);
    x.point("pointmax", hi);
    x.close("definition");
    x.open("commands", &[]);
    x.open("mainlist", &[]);
    x.out += &geometry.out;
    x.close("mainlist");
    x.close("commands");
    x.close("geometry");
    for (name, section) in [
        ("initials", initials),
        ("floatings", floatings),
        ("motion", moving),
    ] {
        if !section.out.is_empty() {
            x.open(name, &[]);
            x.out += &section.out;
            x.close(name);
        }
    }
    x.close("casedef");
    x.open("execution", &[]);
    x.open("parameters", &[]);
    let dt_fixed = if fixed_dt { p.time_step } else { 0.0 };
    let fixed = FIXED_PARAMETERS
        .split_whitespace()
        .filter_map(|kv| kv.split_once('='));
    let scene_parameters = [
        ("Visco", num(p.kinematic_viscosity())),
        ("DtFixed", num(dt_fixed)),
        ("TimeMax", num(options.end_time)),
        ("TimeOut", num(1.0 / DATA_FPS)),
        ("RhopOutMin", num(0.7 * p.rest_density)),
        ("RhopOutMax", num(1.3 * p.rest_density)),
    ];
    let all = fixed
        .map(|(k, v)| (k, v.to_string()))
        .chain(scene_parameters);
    for (key, v) in all {
        x.empty("parameter", &[("key", key.into()), ("value", v)]);
    }
    x.open("simulationdomain", &[]);
    x.point("posmin", lo);
    x.point("posmax", hi);
    x.close("simulationdomain");
    x.close("parameters");
    x.close("execution");
    x.close("case");
    x.out
}

/// The command lines that run the export in `out`, from inside it (GenCase reads the STL files
/// from there): the Linux binaries of the DualSPHysics 5.4 package, `DualSPHysics5.4_linux64 -gpu`
/// on a GPU.
pub fn run_lines(out: &Path) -> Vec<String> {
    vec![
        format!("cd {}", out.display()),
        "GenCase_linux64 Case_Def out/Case -save:all".into(),
        "DualSPHysics5.4CPU_linux64 out/Case out -svres".into(),
    ]
}

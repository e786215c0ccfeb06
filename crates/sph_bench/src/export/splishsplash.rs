//! A scene file as a SPlisHSPlasH scene: `scene.json` with `container.obj` and one OBJ per
//! collider, run by `SPHSimulator scene.json`.
//!
//! Format: SPlisHSPlasH's `doc/file_format.md` (the `Configuration`, `Materials`, `RigidBodies`,
//! `FluidBlocks` and `Emitters` blocks, and a block per pressure solver and per non-pressure
//! method) and its example scenes `data/Scenes/DamBreakModel.json` and `Emitter.json`
//! (InteractiveComputerGraphics/SPlisHSPlasH). Conventions taken from its sources:
//!
//! - `particleRadius` is half our spacing Δx; its support radius 4 r is our h = 2 Δx. A fluid
//!   block's `start`/`end` are the scene's min/max; SPlisHSPlasH fills it from one diameter
//!   inside its faces with `round((end − start) / 2r) − 1` particles per axis (fewer than our
//!   lattice's, which starts half a spacing inside), so that its first layer keeps a diameter
//!   from the walls' boundary particles. A block under 2.5 diameters thick is skipped there, so
//!   it is refused here.
//! - `simulationMethod` 0 WCSPH (`stiffness` B [Pa] and `exponent` 7 of p = B((ρ/ρ0)^7 − 1)),
//!   2 PBF, 4 DFSPH (`maxError` in %, `maxErrorV` in %/s); `kernel`/`gradKernel` 2/3 (poly6 and
//!   spiky, our WCSPH's) or 0 (the cubic spline of our DFSPH and PBF).
//! - The adaptive step is dt = `cflFactor` · 0.4 · 2r / v_max, at most `cflMaxTimeStepSize`:
//!   our DFSPH's λ Δx / v_max is `cflFactor` = λ / 0.4, our PBF's λ h / v_max is 2 λ / 0.4.
//! - "Standard viscosity" takes the kinematic viscosity ν = μ/ρ0 [m²/s]; "XSPH" our PBF's c;
//!   "Vorticity confinement" our ε; "Akinci et al. 2013" our γ.
//! - `boundaryHandlingMethod`: 0 (Akinci et al. 2012 boundary particles, our boundary model)
//!   for WCSPH, 2 (Bender et al. 2019 volume maps, SPlisHSPlasH's default) for DFSPH and PBF.
//!   Run in SPlisHSPlasH 2.16, WCSPH at our fixed step blows up against volume maps within
//!   0.03 s, and PBF at our step (a particle moves up to a spacing; our guard projects it out of
//!   solids, SPlisHSPlasH has no guard) tunnels through the one layer of wall particles. A map
//!   needs a closed mesh: the container is a wall with `mapInvert` (the fluid is inside), an
//!   open mesh collider a closed slab ([`super::mesh`]); map cells are half a spacing.
//! - An emitter of `type` 1 is a disc `width` particles across emitting along its local +x
//!   (`rotationAxis`, `rotationAngle` [rad]), one disc per diameter travelled; the engine puts a
//!   nozzle body around it. `Materials.maxEmitterParticles` caps all emitters of the fluid.

use super::common::{
    collider_field, common_refusals, decimal, Export, ExportOptions, Loaded, Refusal, DATA_FPS,
};
use super::mesh::{file_stem, rotation_from_x, Mesh};
use serde_json::{json, Map, Value};
use sph_core::glam::Vec3;
use sph_core::params::EquationOfState;
use sph_core::scene::MotionSpec;
use sph_core::Solver;
use std::path::Path;

/// The engine's name.
pub const ENGINE: &str = "SPlisHSPlasH";

/// The scene's file name in OUT.
pub const SCENE_FILE: &str = "scene.json";

/// SPlisHSPlasH's adaptive step factor: dt = cflFactor · 0.4 · particle diameter / v_max.
const CFL_BASE: f32 = 0.4;

/// A number as written ([`decimal`]).
fn n(x: f32) -> Value {
    serde_json::Number::from_f64(decimal(x)).map_or(Value::Null, Value::Number)
}

/// A vector as a JSON array.
fn v3(p: Vec3) -> Value {
    Value::Array(vec![n(p.x), n(p.y), n(p.z)])
}

/// The particles SPlisHSPlasH places in the fluid block `min..max` of dense mode 0
/// (`createFluidBlocks`): `round((max − min) / d) − 1` per axis, a diameter d apart, the first
/// one diameter inside `min`. Returns the counts per axis and the positions.
fn block_particles(min: Vec3, max: Vec3, d: f32) -> ([i64; 3], Vec<Vec3>) {
    let steps =
        |a: usize| ((f64::from(max[a]) - f64::from(min[a])) / f64::from(d)).round() as i64 - 1;
    let n = [steps(0), steps(1), steps(2)];
    let at = |i: i64, j: i64, k: i64| {
        min + Vec3::new(i as f32 + 1.0, j as f32 + 1.0, k as f32 + 1.0) * d
    };
    let positions = (0..n[0].max(0))
        .flat_map(|i| {
            (0..n[1].max(0)).flat_map(move |j| (0..n[2].max(0)).map(move |k| at(i, j, k)))
        })
        .collect();
    (n, positions)
}

/// A static rigid body of the OBJ `file`.
fn body(file: &str, mesh: &Mesh, spacing: f32, wall: bool) -> Value {
    let (lo, hi) = mesh.bounds();
    // Map cells of half a spacing, so that a slab a spacing thick is resolved.
    let resolution = ((hi - lo) / (0.5 * spacing))
        .ceil()
        .clamp(Vec3::splat(10.0), Vec3::splat(256.0));
    json!({
        "geometryFile": file,
        "translation": [0, 0, 0],
        "rotationAxis": [1, 0, 0],
        "rotationAngle": 0,
        "scale": [1, 1, 1],
        "color": if wall { [0.1, 0.4, 0.6, 1.0] } else { [0.6, 0.5, 0.4, 1.0] },
        "isDynamic": false,
        "isWall": wall,
        "mapInvert": wall,
        "mapThickness": 0.0,
        "mapResolution": resolution.to_array().map(|r| r as u32),
    })
}

/// Converts `scene`; every field SPlisHSPlasH cannot express is refused.
pub fn convert(scene: &Loaded, options: &ExportOptions) -> Result<Export, Vec<Refusal>> {
    let mut refusals = common_refusals(scene, options, ENGINE);
    let mut export = Export::default();
    let setup = &scene.setup;
    let p = &setup.params;
    let spacing = p.spacing();
    let (min, max) = (setup.container.min(), setup.container.max());
    let container = Mesh::cuboid(0.5 * (max - min)).map(|q| q + 0.5 * (min + max));
    let mut bodies = vec![body("container.obj", &container, spacing, true)];
    let mut files = vec![(
        "container.obj".to_string(),
        container.to_obj("the container's walls"),
    )];
    for (k, (spec, built)) in scene
        .spec
        .colliders
        .iter()
        .zip(&setup.colliders)
        .enumerate()
    {
        let field = collider_field(k, &spec.name);
        match &spec.motion {
            MotionSpec::Kinematic { path } => refusals.push(Refusal::new(
                format!("{field}.motion"),
                format!("Kinematic(path: {} waypoints)", path.len()),
                "SPlisHSPlasH moves a body along a path only from a Python script \
                 (`isAnimated`); its scene file has no path",
            )),
            MotionSpec::Dynamic { density, mass } => refusals.push(Refusal::new(
                format!("{field}.motion"),
                format!("Dynamic(density: {density:?}, mass: {mass:?})"),
                "SPlisHSPlasH moves dynamic bodies with PositionBasedDynamics, whose collision \
                 shapes and contact settings this export does not write",
            )),
            _ => {}
        }
        let mesh = Mesh::of_shape(&built.collider.shape, &built.collider.pose, spacing);
        let file = format!("collider_{k}_{}.obj", file_stem(&spec.name));
        bodies.push(body(&file, &mesh, spacing, false));
        files.push((file, mesh.to_obj(&format!("collider {k}: {}", spec.name))));
    }
    let mut blocks = Vec::new();
    for (k, (block, velocity)) in setup.blocks.iter().enumerate() {
        let ours = block.count();
        if ours == 0 {
            let note = format!("blocks[{k}] holds no particle and is left out");
            export.notes.push(note);
            continue;
        }
        let (steps, positions) = block_particles(block.min, block.max, spacing);
        if let Some(axis) = (0..3).find(|&a| steps[a] <= 1) {
            refusals.push(Refusal::new(
                format!("blocks[{k}]"),
                format!(
                    "{} m along {}",
                    (block.max - block.min)[axis],
                    ["x", "y", "z"][axis]
                ),
                "SPlisHSPlasH fills a block from one particle diameter inside its faces and \
                 skips one under 2.5 diameters thick",
            ));
            continue;
        }
        let solid = |x: Vec3| {
            setup
                .colliders
                .iter()
                .any(|c| c.collider.signed_distance(x) < 0.0)
        };
        let inside = positions.iter().filter(|&&x| solid(x)).count();
        export.notes.push(format!(
            "blocks[{k}]: SPlisHSPlasH places {} particles (from one diameter inside the block's \
             faces, {inside} of them inside colliders), sph-bench {ours}",
            positions.len()
        ));
        blocks.push(json!({
            "denseMode": 0,
            "start": v3(block.min),
            "end": v3(block.max),
            "translation": [0, 0, 0],
            "scale": [1, 1, 1],
            "initialVelocity": v3(*velocity),
        }));
    }
    let mut emitters = Vec::new();
    let mut emitted: u64 = 0;
    for (k, e) in setup.emitters.iter().enumerate() {
        let Some(total) = e.total else {
            refusals.push(Refusal::new(
                format!("emitters[{k}].total"),
                "omitted (endless)",
                "SPlisHSPlasH reserves every emitted particle up front \
                 (`Materials.maxEmitterParticles`): give the emitter a total",
            ));
            continue;
        };
        emitted = emitted.saturating_add(total);
        let width = (2.0 * e.radius / spacing).round().max(1.0);
        // SPlisHSPlasH's disc: a width × width grid a diameter apart, within width/2 diameters
        // of the centre; one disc per diameter travelled.
        let offset = |i: u32| (i as f32 - 0.5 * (width - 1.0)) * spacing;
        let within = |i: u32, j: u32| offset(i).hypot(offset(j)) <= 0.5 * width * spacing;
        let cells = (0..width as u32).flat_map(|i| (0..width as u32).map(move |j| (i, j)));
        let disc = cells.filter(|&(i, j)| within(i, j)).count();
        export.notes.push(format!(
            "emitters[{k}]: a disc {width} particles across (radius {} m), {disc} particles, \
             {} particles/s; sph-bench's {} m pipe emits {} particles/s",
            decimal(0.5 * width * spacing),
            decimal(disc as f32 * e.speed / spacing),
            e.radius,
            decimal(e.rate)
        ));
        let (axis, angle) = rotation_from_x(e.direction);
        let mut emitter = json!({
            "type": 1,
            "width": width as u32,
            "translation": v3(e.position),
            "rotationAxis": v3(axis),
            "rotationAngle": n(angle),
            "velocity": n(e.speed),
            "emitStartTime": 0,
        });
        if setup.emitters.len() > 1 && e.rate > 0.0 {
            // The cap is shared: each emitter stops when it has emitted its total at our rate.
            emitter["emitEndTime"] = n(total as f32 / e.rate);
        }
        emitters.push(emitter);
    }
    if !refusals.is_empty() {
        return Err(refusals);
    }
    let mut configuration = configuration(scene, &mut export.notes);
    if p.solver == Solver::Pbf && p.has_surface_tension() {
        export
            .notes
            .push("surface tension left out: sph-bench's PBF does not apply it".into());
    }
    let mut root = Map::new();
    configuration.insert("stopAt".into(), n(options.end_time));
    root.insert("Configuration".into(), Value::Object(configuration));
    root.insert("Materials".into(), json!([material(scene, emitted)]));
    root.insert("RigidBodies".into(), Value::Array(bodies));
    root.insert("FluidBlocks".into(), Value::Array(blocks));
    if !emitters.is_empty() {
        root.insert("Emitters".into(), Value::Array(emitters));
    }
    let text = serde_json::to_string_pretty(&Value::Object(root)).unwrap_or_default() + "\n";
    export.files.push((SCENE_FILE.into(), text));
    export.files.append(&mut files);
    Ok(export)
}

/// The `Configuration` block: particle size, solver, time step, gravity, boundary model, output.
fn configuration(scene: &Loaded, notes: &mut Vec<String>) -> Map<String, Value> {
    let p = &scene.setup.params;
    let (method, kernel, block_name, block) = match p.solver {
        Solver::Wcsph => {
            let (stiffness, exponent) = match p.equation_of_state {
                EquationOfState::Tait => (p.stiffness, 7.0),
                EquationOfState::Linear => (p.stiffness * p.rest_density, 1.0),
            };
            let block = json!({"stiffness": n(stiffness), "exponent": n(exponent)});
            (0, 2, "WCSPH", block)
        }
        Solver::Dfsph => {
            let d = &p.dfsph;
            let block = json!({
                "minIterations": d.min_density_iterations,
                "maxIterations": d.max_density_iterations,
                "maxError": n(100.0 * d.max_density_error),
                "maxIterationsV": d.max_divergence_iterations,
                "maxErrorV": n(100.0 * d.max_divergence_error),
                "enableDivergenceSolver": true,
            });
            notes
                .push("DFSPH: SPlisHSPlasH always warm-starts and has no over-relaxation ω".into());
            (4, 0, "DFSPH", block)
        }
        Solver::Pbf => {
            let block = json!({
                "minIterations": p.pbf.iterations,
                "maxIterations": p.pbf.iterations,
                "maxError": 0.01,
                "velocityUpdateMethod": 0,
            });
            notes.push(
                "PBF: SPlisHSPlasH's has no artificial pressure s_corr and no over-relaxation ω"
                    .into(),
            );
            (2, 0, "PBF", block)
        }
    };
    let mut c = Map::new();
    c.insert("particleRadius".into(), n(0.5 * p.spacing()));
    c.insert("sim2D".into(), json!(false));
    c.insert("simulationMethod".into(), json!(method));
    c.insert("kernel".into(), json!(kernel));
    c.insert("gradKernel".into(), json!(if kernel == 2 { 3 } else { 0 }));
    c.insert("gravitation".into(), v3(p.gravity));
    c.insert("timeStepSize".into(), n(p.time_step));
    if p.adaptive_time_step {
        // Our rules: DFSPH λ Δx / v_max, PBF λ h / v_max = 2 λ Δx / v_max.
        let per_spacing = match p.solver {
            Solver::Dfsph => 1.0,
            Solver::Wcsph | Solver::Pbf => 2.0,
        };
        if p.solver == Solver::Wcsph {
            notes.push(
                "WCSPH's adaptive step: SPlisHSPlasH's rule has no speed of sound, so dt is \
                 held to the scene's largest step"
                    .into(),
            );
        }
        c.insert("cflMethod".into(), json!(1));
        c.insert("cflFactor".into(), n(per_spacing * p.cfl_factor / CFL_BASE));
        c.insert("cflMaxTimeStepSize".into(), n(p.time_step));
    } else {
        c.insert("cflMethod".into(), json!(0));
    }
    // Akinci 2012 particles for WCSPH (volume maps blow up at its fixed step), volume maps for
    // DFSPH and PBF (water tunnels through one layer of particles at PBF's step).
    let boundary = if p.solver == Solver::Wcsph { 0 } else { 2 };
    c.insert("boundaryHandlingMethod".into(), json!(boundary));
    c.insert("enablePartioExport".into(), json!(true));
    c.insert("dataExportFPS".into(), n(DATA_FPS));
    c.insert("particleAttributes".into(), json!("velocity;density"));
    c.insert(block_name.into(), block);
    c
}

/// The fluid's material: rest density, viscosity, XSPH, vorticity, surface tension, emitters.
fn material(scene: &Loaded, emitted: u64) -> Value {
    let p = &scene.setup.params;
    let mut m = json!({"id": "Fluid", "density0": n(p.rest_density), "colorMapType": 1});
    if p.solver == Solver::Pbf {
        // Our PBF's viscosity is XSPH alone.
        m["viscosityMethod"] = json!(0);
        m["XSPH"] = json!({"xsph": n(p.pbf.xsph_c), "xsphBoundary": 0.0});
        if p.pbf.vorticity_epsilon > 0.0 {
            m["vorticityMethod"] = json!(2);
            m["Vorticity confinement"] = json!({"vorticity": n(p.pbf.vorticity_epsilon)});
        }
    } else {
        let method = if p.has_viscosity() { 1 } else { 0 };
        m["viscosityMethod"] = json!(method);
        m["Standard viscosity"] =
            json!({"viscosity": n(p.kinematic_viscosity()), "viscosityBoundary": 0.0});
        if p.has_surface_tension() {
            m["surfaceTensionMethod"] = json!(2);
            m["Akinci et al. 2013"] =
                json!({"surfaceTension": n(p.surface_tension), "surfaceTensionBoundary": 0.0});
        }
    }
    if emitted > 0 {
        m["maxEmitterParticles"] = json!(emitted);
        m["emitterReuseParticles"] = json!(false);
    }
    m
}

/// The command lines that run the export in `out`.
pub fn run_lines(out: &Path) -> Vec<String> {
    let scene = out.join(SCENE_FILE);
    vec![format!(
        "SPHSimulator {} --no-gui --output-dir {}",
        scene.display(),
        out.join("output").display()
    )]
}

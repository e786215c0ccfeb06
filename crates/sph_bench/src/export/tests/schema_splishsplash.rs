//! scene.json read back against SPlisHSPlasH's doc/file_format.md.

use super::super::common::{Export, ExportOptions, Loaded};
use super::support::{bounds, check_surface, close, close3, files, int, num, vec3, vertices};
use serde_json::Value;
use sph_core::glam::Vec3;
use sph_core::Solver;

/// The lattice SPlisHSPlasH builds from a fluid block (`createFluidBlocks` in its
/// `Simulator/SimulatorBase.cpp`, dense mode 0).
fn splishsplash_lattice(start: Vec3, end: Vec3, radius: f32) -> Vec<Vec3> {
    let diam = 2.0 * f64::from(radius);
    let steps = |a: f32, b: f32| ((f64::from(b) - f64::from(a)) / diam).round() as i64 - 1;
    let (sx, sy, sz) = (
        steps(start.x, end.x),
        steps(start.y, end.y),
        steps(start.z, end.z),
    );
    let mut out = Vec::new();
    for j in 0..sx {
        for k in 0..sy {
            for l in 0..sz {
                let q = |s: f32, i: i64| (f64::from(s) + diam + i as f64 * diam) as f32;
                out.push(Vec3::new(q(start.x, j), q(start.y, k), q(start.z, l)));
            }
        }
    }
    out
}

/// scene.json against SPlisHSPlasH's doc/file_format.md: required fields, their types and units,
/// particleRadius = Δx/2, blocks and bodies that round-trip.
pub fn check_splishsplash(scene: &Loaded, export: &Export, opts: &ExportOptions) {
    let files = files(export);
    let json: Value = serde_json::from_str(files["scene.json"]).expect("scene.json parses");
    let (p, setup) = (&scene.setup.params, &scene.setup);
    let c = &json["Configuration"];
    assert!(close(num(&c["particleRadius"]), 0.5 * p.spacing()));
    let (method, block) = match p.solver {
        Solver::Wcsph => (0, "WCSPH"),
        Solver::Pbf => (2, "PBF"),
        Solver::Dfsph => (4, "DFSPH"),
    };
    assert_eq!(int(&c["simulationMethod"]), method);
    assert!(c[block].is_object(), "no {block} block");
    assert!(close(num(&c["timeStepSize"]), p.time_step));
    assert!(close3(vec3(&c["gravitation"]), p.gravity));
    assert!(close(num(&c["stopAt"]), opts.end_time));
    let boundary = if p.solver == Solver::Wcsph { 0 } else { 2 };
    assert_eq!(int(&c["boundaryHandlingMethod"]), boundary);
    assert_eq!(int(&c["cflMethod"]), i64::from(p.adaptive_time_step));
    if p.adaptive_time_step {
        assert!(num(&c["cflFactor"]) > 0.0);
        assert!(close(num(&c["cflMaxTimeStepSize"]), p.time_step));
    }
    let materials = json["Materials"].as_array().expect("Materials");
    assert_eq!(materials[0]["id"], "Fluid");
    assert!(close(num(&materials[0]["density0"]), p.rest_density));
    let bodies = json["RigidBodies"].as_array().expect("RigidBodies");
    assert_eq!(bodies.len(), setup.colliders.len() + 1);
    for b in bodies {
        let file = b["geometryFile"].as_str().expect("geometryFile");
        assert!(files.contains_key(file), "{file} not written");
        assert_eq!(
            (vec3(&b["translation"]), vec3(&b["scale"])),
            (Vec3::ZERO, Vec3::ONE)
        );
        assert!(vec3(&b["rotationAxis"]).length() > 0.0 && num(&b["rotationAngle"]) == 0.0);
        assert_eq!(b["isDynamic"], false);
    }
    assert_eq!(
        (&bodies[0]["isWall"], &bodies[0]["mapInvert"]),
        (&Value::Bool(true), &Value::Bool(true))
    );
    let walls = bounds(&vertices(
        files[bodies[0]["geometryFile"].as_str().unwrap_or("")],
    ));
    assert!(close3(walls.0, setup.container.min()) && close3(walls.1, setup.container.max()));
    for (k, (c, spec)) in setup
        .colliders
        .iter()
        .zip(&scene.spec.colliders)
        .enumerate()
    {
        let obj = files[bodies[k + 1]["geometryFile"].as_str().unwrap_or("")];
        check_surface(c, &spec.shape, &vertices(obj));
    }
    let blocks = json["FluidBlocks"].as_array().expect("FluidBlocks");
    assert_eq!(blocks.len(), setup.blocks.len());
    let r = num(&c["particleRadius"]);
    for (written, (block, velocity)) in blocks.iter().zip(&setup.blocks) {
        assert_eq!(int(&written["denseMode"]), 0);
        let (start, end) = (vec3(&written["start"]), vec3(&written["end"]));
        assert!(
            close3(start, block.min) && close3(end, block.max),
            "{start}..{end}"
        );
        assert!(close3(vec3(&written["initialVelocity"]), *velocity));
        // SPlisHSPlasH's particles: a diameter 2r = Δx apart, the first one diameter inside the
        // block's faces, the last at least a radius inside, as many as the export's note says.
        let theirs = splishsplash_lattice(start, end, r);
        let (lo, hi) = bounds(&theirs);
        assert!(
            close3(lo, block.min + Vec3::splat(2.0 * r)),
            "first particle {lo}"
        );
        assert!(
            (block.max - hi).cmpge(Vec3::splat(r - 1e-5)).all(),
            "last particle {hi}"
        );
        let said = format!("SPlisHSPlasH places {} particles", theirs.len());
        assert!(
            export.notes.iter().any(|n| n.contains(&said)),
            "{said}: {:?}",
            export.notes
        );
        assert!(theirs.len() <= block.count() && theirs.len() * 2 > block.count());
    }
    let emitters = json["Emitters"]
        .as_array()
        .map_or(&[][..], |e| e.as_slice());
    assert_eq!(emitters.len(), setup.emitters.len());
    for (e, ours) in emitters.iter().zip(&setup.emitters) {
        assert_eq!(int(&e["type"]), 1);
        assert!(
            close(int(&e["width"]) as f32 * r, ours.radius),
            "width {}",
            e["width"]
        );
        assert!(close3(vec3(&e["translation"]), ours.position));
        let turn = sph_core::glam::Quat::from_axis_angle(
            vec3(&e["rotationAxis"]),
            num(&e["rotationAngle"]),
        );
        assert!(close3(turn * Vec3::X, ours.direction.normalize()));
        assert!(close(num(&e["velocity"]), ours.speed));
    }
    let total: u64 = setup.emitters.iter().filter_map(|e| e.total).sum();
    if total > 0 {
        assert_eq!(materials[0]["maxEmitterParticles"].as_u64(), Some(total));
    }
}

//! Case_Def.xml read back against DualSPHysics's GenCase_CaseTemplate.xml.

use super::super::common::{Export, ExportOptions, Loaded, DATA_FPS};
use super::super::dualsphysics::to_dsph;
use super::support::{check_surface, close, close3, files, from_dsph, vertices};
use sph_core::glam::Vec3;
use sph_core::scene::ShapeSpec;
use std::collections::HashMap;

fn child<'a>(node: roxmltree::Node<'a, 'a>, name: &str) -> roxmltree::Node<'a, 'a> {
    node.children()
        .find(|n| n.has_tag_name(name))
        .unwrap_or_else(|| panic!("no <{name}>"))
}

fn attr(node: roxmltree::Node, name: &str) -> f32 {
    let text = node
        .attribute(name)
        .unwrap_or_else(|| panic!("<{}> has no {name}", node.tag_name().name()));
    text.parse()
        .unwrap_or_else(|_| panic!("{name}={text:?} is not a number"))
}

fn point(node: roxmltree::Node) -> Vec3 {
    Vec3::new(attr(node, "x"), attr(node, "y"), attr(node, "z"))
}

/// The scene-frame box of a `drawbox`.
fn drawn_box(node: roxmltree::Node) -> (Vec3, Vec3) {
    let (a, b) = (child(node, "point"), child(node, "size"));
    let (lo, hi) = (from_dsph(point(a)), from_dsph(point(a) + point(b)));
    (lo.min(hi), lo.max(hi))
}

/// Case_Def.xml against DualSPHysics's GenCase_CaseTemplate.xml: required constants and
/// parameters with numeric values in SI units, and geometry that round-trips to the scene.
pub fn check_dualsphysics(scene: &Loaded, export: &Export, opts: &ExportOptions) {
    let files = files(export);
    let doc = roxmltree::Document::parse(files["Case_Def.xml"]).expect("Case_Def.xml parses");
    let (p, setup) = (&scene.setup.params, &scene.setup);
    let case = doc.root_element();
    assert!(case.has_tag_name("case"));
    let casedef = child(case, "casedef");
    let constants = child(casedef, "constantsdef");
    assert!(close3(
        from_dsph(point(child(constants, "gravity"))),
        p.gravity
    ));
    assert!(close(
        attr(child(constants, "rhop0"), "value"),
        p.rest_density
    ));
    let sound = child(constants, "speedsound");
    assert!(
        close(attr(sound, "value"), p.speed_of_sound()) && sound.attribute("auto") == Some("false")
    );
    for name in ["gamma", "coefh", "cflnumber", "coefsound"] {
        assert!(attr(child(constants, name), "value") > 0.0);
    }
    let geometry = child(casedef, "geometry");
    let definition = child(geometry, "definition");
    assert!(close(attr(definition, "dp"), p.spacing()));
    let (pmin, pmax) = (
        point(child(definition, "pointmin")),
        point(child(definition, "pointmax")),
    );
    let mut mk = ("", -1);
    let mut drawn: HashMap<(&str, i32), Vec<roxmltree::Node>> = HashMap::new();
    for n in child(child(geometry, "commands"), "mainlist")
        .children()
        .filter(|n| n.is_element())
    {
        match n.tag_name().name() {
            "setmkfluid" => mk = ("fluid", attr(n, "mk") as i32),
            "setmkbound" => mk = ("bound", attr(n, "mk") as i32),
            name if name.starts_with("draw") => drawn.entry(mk).or_default().push(n),
            _ => {}
        }
    }
    for (k, (block, _)) in setup.blocks.iter().enumerate() {
        let (lo, hi) = drawn_box(drawn[&("fluid", k as i32)][0]);
        assert!(
            close3(lo, block.min) && close3(hi, block.max),
            "blocks[{k}]: {lo}..{hi}"
        );
    }
    let walls = drawn[&("bound", 0)][0];
    assert_eq!(child(walls, "boxfill").text(), Some("all"));
    let (lo, hi) = drawn_box(walls);
    assert!(close3(lo, setup.container.min()) && close3(hi, setup.container.max()));
    let (dlo, dhi) = (to_dsph(lo).min(to_dsph(hi)), to_dsph(lo).max(to_dsph(hi)));
    assert!(
        pmin.cmplt(dlo).all() && pmax.cmpgt(dhi).all(),
        "the definition holds the tank"
    );
    for (k, (c, spec)) in setup
        .colliders
        .iter()
        .zip(&scene.spec.colliders)
        .enumerate()
    {
        let nodes = &drawn[&("bound", k as i32 + 1)];
        let pose = c.collider.pose;
        let end = |s: f32, hl: f32| pose.to_world(Vec3::Y * (s * hl));
        match (&spec.shape, nodes[0].tag_name().name()) {
            (ShapeSpec::Sphere { radius }, "drawsphere") => {
                assert!(close(attr(nodes[0], "radius"), *radius));
                assert!(close3(
                    from_dsph(point(child(nodes[0], "point"))),
                    pose.translation
                ));
            }
            (ShapeSpec::Cuboid { .. }, "drawbox") => {
                let (lo, hi) = drawn_box(nodes[0]);
                check_surface(c, &spec.shape, &[lo, hi]);
            }
            (
                ShapeSpec::Capsule {
                    radius,
                    half_length,
                }
                | ShapeSpec::Cylinder {
                    radius,
                    half_length,
                },
                "drawcylinder",
            ) => {
                let ends: Vec<Vec3> = nodes[0]
                    .children()
                    .filter(|n| n.has_tag_name("point"))
                    .map(|n| from_dsph(point(n)))
                    .collect();
                assert!(close(attr(nodes[0], "radius"), *radius));
                assert!(
                    close3(ends[0], end(-1.0, *half_length))
                        && close3(ends[1], end(1.0, *half_length))
                );
                let capped = matches!(spec.shape, ShapeSpec::Capsule { .. });
                assert_eq!(nodes.len(), if capped { 3 } else { 1 });
            }
            (_, "drawfilestl") => {
                let stl = files[nodes[0].attribute("file").unwrap_or("")];
                let points: Vec<Vec3> = vertices(stl).into_iter().map(from_dsph).collect();
                check_surface(c, &spec.shape, &points);
            }
            (shape, tag) => panic!("colliders[{k}]: {shape:?} drawn as <{tag}>"),
        }
        if let (Some((&(t0, _), &(_, last))), false) =
            (c.path.first().zip(c.path.last()), c.path.is_empty())
        {
            let motion = child(casedef, "motion");
            let obj = motion
                .children()
                .find(|n| n.attribute("ref") == Some(&(k + 1).to_string()))
                .expect("objreal");
            assert!(close(attr(child(obj, "begin"), "start"), t0.max(0.0)));
            let moved: Vec3 = obj
                .children()
                .filter(|n| n.has_tag_name("mvrect"))
                .map(|m| from_dsph(point(child(m, "vel"))) * attr(m, "duration"))
                .sum();
            assert!(
                close3(pose.translation + moved, last),
                "the path ends at {last}"
            );
        }
        if let Some(sph_core::scene::BodyMass::Density(d)) = c.body {
            let f = child(casedef, "floatings")
                .children()
                .find(|n| n.attribute("mkbound") == Some(&(k + 1).to_string()))
                .expect("floating");
            assert!(close(attr(f, "rhopbody"), d));
        }
    }
    let parameters = child(child(case, "execution"), "parameters");
    let value = |key: &str| {
        let node = parameters
            .children()
            .find(|n| n.attribute("key") == Some(key))
            .unwrap_or_else(|| panic!("no {key}"));
        attr(node, "value")
    };
    for key in [
        "StepAlgorithm",
        "Kernel",
        "ViscoTreatment",
        "DtFixed",
        "RhopOutMin",
        "RhopOutMax",
    ] {
        assert!(value(key) >= 0.0);
    }
    assert!(close(value("TimeMax"), opts.end_time) && close(value("TimeOut"), 1.0 / DATA_FPS));
    assert!(close(value("Visco"), p.kinematic_viscosity()));
    let domain = child(parameters, "simulationdomain");
    assert!(
        point(child(domain, "posmin")).cmple(pmin).all()
            && point(child(domain, "posmax")).cmpge(pmax).all()
    );
}

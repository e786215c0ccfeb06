//! `sph-bench export --to ENGINE SCENE.ron OUT`: a scene file (`sph_core::scene`) as a scene
//! for a larger offline engine, one module per engine:
//!
//! - [`splishsplash`]: SPlisHSPlasH's JSON scene (`scene.json`) with OBJ geometry;
//! - [`dualsphysics`]: DualSPHysics's GenCase case definition (`Case_Def.xml`) with STL geometry.
//!
//! over what they share: [`common`] (the loaded scene, the options, refusals, notes), [`mesh`]
//! (collider shapes as closed meshes, OBJ and STL) and [`xml`] (the case definition's writer).
//!
//! What an engine cannot express is refused by name: every refusal names the scene's field, its
//! value and what the engine lacks, all of them at once, and nothing is written. The files are
//! written to a staging directory beside OUT and moved to OUT only when all of them are written,
//! so OUT never holds a partial export. Approximations that keep the scene's physics (a solver
//! the engine has under another name, a boundary model's own settings) are listed as notes.
//! See `docs/export.md` for the mappings and the command lines that run the results.

pub mod common;
pub mod dualsphysics;
pub mod mesh;
pub mod splishsplash;
#[cfg(test)]
mod tests;
pub mod xml;

use crate::args::{ExportArgs, ExportTarget};
use common::{common_notes, load, Export, ExportOptions, Loaded};
use std::path::{Path, PathBuf};

/// The name the engine goes by.
pub fn engine_name(target: ExportTarget) -> &'static str {
    match target {
        ExportTarget::Splishsplash => splishsplash::ENGINE,
        ExportTarget::Dualsphysics => dualsphysics::ENGINE,
    }
}

/// Converts `scene` for `target`; the error lists every refusal, naming the file.
pub fn convert(
    target: ExportTarget,
    scene: &Loaded,
    options: &ExportOptions,
) -> Result<Export, String> {
    let converted = match target {
        ExportTarget::Splishsplash => splishsplash::convert(scene, options),
        ExportTarget::Dualsphysics => dualsphysics::convert(scene, options),
    };
    match converted {
        Ok(mut export) => {
            let mut notes = common_notes(scene, options);
            notes.append(&mut export.notes);
            export.notes = notes;
            Ok(export)
        }
        Err(mut refusals) => {
            refusals.sort_by_key(|r| field_order(&r.field));
            let list: Vec<String> = refusals.iter().map(|r| format!("  {r}")).collect();
            Err(format!(
                "{}: cannot export to {} (nothing written): {} it cannot express:\n{}",
                scene.file,
                engine_name(target),
                count(refusals.len(), "field"),
                list.join("\n")
            ))
        }
    }
}

/// `n` `thing`s, in words.
pub fn count(n: usize, thing: &str) -> String {
    match n {
        1 => format!("1 {thing}"),
        _ => format!("{n} {thing}s"),
    }
}

/// Where a field comes in a scene file: its section in the file's order, then its index.
fn field_order(field: &str) -> (usize, usize) {
    const SECTIONS: [&str; 8] = [
        "overrides",
        "controls",
        "colliders",
        "blocks",
        "emitters",
        "sinks",
        "pumps",
        "probes",
    ];
    let section = SECTIONS.iter().position(|s| field.starts_with(s));
    let index = field
        .split_once('[')
        .and_then(|(_, rest)| rest.split_once(']'))
        .and_then(|(k, _)| k.parse().ok());
    (section.unwrap_or(SECTIONS.len()), index.unwrap_or(0))
}

/// Writes `export` into the new directory `out` (which may exist empty): into a staging
/// directory beside it first, then moved into place. Returns the paths written.
pub fn write(out: &Path, export: &Export) -> Result<Vec<PathBuf>, String> {
    if out.exists() {
        let empty = std::fs::read_dir(out).is_ok_and(|mut d| d.next().is_none());
        if !empty {
            return Err(format!(
                "OUT {} exists and is not an empty directory: give a new directory",
                out.display()
            ));
        }
    }
    let name = out
        .file_name()
        .ok_or_else(|| format!("OUT {} names no directory", out.display()))?;
    let parent = out.parent().filter(|p| !p.as_os_str().is_empty());
    let parent = parent.unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent)
        .map_err(|e| format!("cannot create {}: {e}", parent.display()))?;
    let staging = parent.join(format!(
        ".{}.partial-{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    let written = (|| {
        std::fs::create_dir(&staging)?;
        for (file, contents) in &export.files {
            std::fs::write(staging.join(file), contents)?;
        }
        if out.exists() {
            std::fs::remove_dir(out)?;
        }
        std::fs::rename(&staging, out)
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_dir_all(&staging);
        return Err(format!("cannot write {}: {e}", out.display()));
    }
    Ok(export.files.iter().map(|(f, _)| out.join(f)).collect())
}

/// What `sph-bench export` did.
#[derive(Clone, Debug, PartialEq)]
pub struct Exported {
    /// The files written.
    pub written: Vec<PathBuf>,
    /// What was mapped approximately.
    pub notes: Vec<String>,
    /// The command lines that run the result.
    pub commands: Vec<String>,
}

/// `sph-bench export`: loads, converts and writes.
pub fn run(args: &ExportArgs) -> Result<Exported, String> {
    let scene = load(&args.scene)?;
    let options = ExportOptions {
        end_time: args.time,
        drop_probes: args.drop_probes,
    };
    let export = convert(args.to, &scene, &options)?;
    let written = write(&args.out, &export)?;
    let commands = match args.to {
        ExportTarget::Splishsplash => splishsplash::run_lines(&args.out),
        ExportTarget::Dualsphysics => dualsphysics::run_lines(&args.out),
    };
    Ok(Exported {
        written,
        notes: export.notes,
        commands,
    })
}

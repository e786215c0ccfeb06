//! `sph-bench export` from the command line: a refused scene exits with status 2, names the
//! field and leaves OUT absent; an exportable one writes OUT, lists the files on stdout and
//! prints the command lines; an OUT that is not empty is refused and left as it was.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn scene(stem: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../assets/scenes/{stem}.ron"))
}

/// A fresh scratch directory for `name` (not created).
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "sph_bench_export_cli_{}_{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn export(engine: &str, stem: &str, out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sph-bench"))
        .args(["export", "--to", engine])
        .arg(scene(stem))
        .arg(out)
        .output()
        .expect("sph-bench runs")
}

#[test]
fn export_cli_refuses_by_field_and_writes_nothing() {
    let dir = scratch("refused");
    let out = dir.join("aquaplay");
    let run = export("splishsplash", "aquaplay", &out);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    for field in [
        r#"`pumps[0] ("crank_pump")`"#,
        r#"`sinks[0] ("overflow_drain")`"#,
        r#"`colliders[3] ("water_wheel").motion`"#,
    ] {
        assert!(stderr.contains(field), "{field} not named:\n{stderr}");
    }
    assert!(stderr.contains("nothing written"), "{stderr}");
    assert!(!dir.exists(), "a refused export creates nothing");
}

#[test]
fn export_cli_writes_the_case_and_keeps_a_full_out() {
    let dir = scratch("written");
    let out = dir.join("gate");
    let run = export("dualsphysics", "gate", &out);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    let case = out.join("Case_Def.xml");
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(stdout.contains(&case.display().to_string()), "{stdout}");
    assert!(
        stderr.contains("GenCase_linux64 Case_Def out/Case"),
        "{stderr}"
    );
    let text = std::fs::read_to_string(&case).expect("Case_Def.xml written");
    assert!(text.starts_with("<?xml"));
    let again = export("dualsphysics", "gate", &out);
    let stderr = String::from_utf8_lossy(&again.stderr);
    assert_eq!(again.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("exists and is not an empty directory"),
        "{stderr}"
    );
    assert_eq!(std::fs::read_to_string(&case).ok(), Some(text));
    std::fs::remove_dir_all(&dir).expect("clean up");
}

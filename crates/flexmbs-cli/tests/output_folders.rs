//! `reduce -o` and `export-inp -o` into a folder that does not exist yet create it (as `run -o`
//! does); `export-inp` refuses an output path that is a symbolic link instead of writing through
//! it.

use std::path::{Path, PathBuf};
use std::process::Command;

const FE_BODY: &str = r#"
[body]
name = "beam"
[body.mesh]
type = "box"
size = [0.2, 0.02, 0.02]
divisions = [4, 2, 2]
element = "hex8"
material = { e = 210e9, nu = 0.3, rho = 7850.0 }
[body.boundary]
fixed = ["xmin"]
[body.reduction]
modes = 2
"#;

fn scratch(name: &str) -> PathBuf {
    flexmbs_io::test_tools::scratch_dir(&format!("out_folders_{name}"))
}

/// Runs `flexmbs -q args`; returns (success, stderr).
fn flexmbs(args: &[&Path]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_flexmbs"))
        .arg("-q")
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn reduce_and_export_create_the_output_folder() {
    let d = scratch("create");
    let model = d.join("beam.toml");
    std::fs::write(&model, FE_BODY).unwrap();
    let body = d.join("new/deeper/beam.fmb.h5");
    let (ok, err) = flexmbs(&[Path::new("reduce"), &model, Path::new("-o"), &body]);
    assert!(ok, "{err}");
    assert!(body.is_file());
    let deck = d.join("decks/beam.inp");
    let (ok, err) = flexmbs(&[Path::new("export-inp"), &model, Path::new("-o"), &deck]);
    assert!(ok, "{err}");
    let text = std::fs::read_to_string(&deck).unwrap();
    assert!(text.contains("*NODE"), "{text}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[cfg(unix)]
#[test]
fn export_inp_refuses_a_symbolic_link() {
    let d = scratch("symlink");
    let model = d.join("beam.toml");
    std::fs::write(&model, FE_BODY).unwrap();
    let target = d.join("precious.txt");
    std::fs::write(&target, "keep me").unwrap();
    let link = d.join("deck.inp");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let (ok, err) = flexmbs(&[Path::new("export-inp"), &model, Path::new("-o"), &link]);
    assert!(!ok);
    assert!(err.contains("a symbolic link"), "{err}");
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "keep me");
    std::fs::remove_dir_all(&d).unwrap();
}

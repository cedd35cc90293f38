//! The wrong kind of file gets a message saying what the file is and what the command expects:
//! an FE body file given to `run`, an HDF5 file given to `check`, a model file given to `plot`.

use std::path::{Path, PathBuf};
use std::process::Command;

const FE_BODY: &str = r#"
[body]
name = "beam"
[body.mesh]
type = "beam"
start = [0.0, 0.0, 0.0]
end = [1.0, 0.0, 0.0]
elements = 4
section = { shape = "rectangle", width = 0.02, height = 0.01 }
material = { e = 210e9, nu = 0.3, rho = 7850.0 }
"#;

/// A fresh scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    flexmbs_io::test_tools::scratch_dir(&format!("wrong_kind_{name}"))
}

/// Runs `flexmbs args`; returns (success, stderr).
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
fn run_on_an_fe_body_file_says_what_it_is() {
    let d = scratch("run");
    let f = d.join("beam.toml");
    std::fs::write(&f, FE_BODY).unwrap();
    let (ok, err) = flexmbs(&[Path::new("run"), &f]);
    assert!(!ok);
    assert!(
        err.contains("is an FE body file (no [model] table): use `flexmbs modal`"),
        "{err}"
    );
    assert!(err.contains("as a body's `source`"), "{err}");
    // The same file is fine for `check`.
    let (ok, err) = flexmbs(&[Path::new("check"), &f]);
    assert!(ok, "{err}");
}

#[test]
fn check_on_an_hdf5_file_says_what_it_is() {
    let d = scratch("check");
    let f = d.join("thing.h5");
    let mut bytes = b"\x89HDF\r\n\x1a\n".to_vec();
    bytes.extend_from_slice(&[0, 0, 0, 0, 200, 201, 202]);
    std::fs::write(&f, bytes).unwrap();
    let (ok, err) = flexmbs(&[Path::new("check"), &f]);
    assert!(!ok);
    assert!(err.contains("thing.h5 is an HDF5 file"), "{err}");
    assert!(
        err.contains("`flexmbs check` expects a TOML model file"),
        "{err}"
    );
    assert!(!err.contains("UTF-8"), "{err}");
    let (ok, err) = flexmbs(&[Path::new("modal"), &f]);
    assert!(!ok);
    assert!(err.contains("thing.h5 is an HDF5 file"), "{err}");
}

#[test]
fn plot_on_a_model_file_says_it_is_not_a_results_file() {
    let d = scratch("plot");
    let f = d.join("beam.toml");
    std::fs::write(&f, FE_BODY).unwrap();
    let (ok, err) = flexmbs(&[Path::new("plot"), &f, Path::new("--list")]);
    assert!(!ok);
    assert!(
        err.contains("beam.toml is not a flexmbs results file: it is a text file"),
        "{err}"
    );
    assert!(!err.contains("HDF5 signature not found"), "{err}");
}

//! `flexmbs reduce` stores the centrifugal geometric stiffness of a body with fixed nodes in the
//! reduced-body file (bitwise what a multibody model computes from the FE model), none for a
//! free-free body, and none with `--no-geometric`.

use flexmbs_io::body_file::read_body_file;
use flexmbs_sim::bodies::load_reduced_with_fe;
use flexmbs_sim::stiffening::centrifugal_stiffness;
use std::path::{Path, PathBuf};
use std::process::Command;

fn part(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../examples/mbs/parts/{name}.toml"))
}

/// Runs `flexmbs -q reduce model -o out extra...`; returns stdout (panics on failure).
fn reduce(model: &Path, out: &Path, extra: &[&str]) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_flexmbs"))
        .arg("-q")
        .arg("reduce")
        .arg(model)
        .arg("-o")
        .arg(out)
        .args(extra)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn reduce_stores_geometric_stiffness_of_supported_bodies() {
    let dir = std::env::temp_dir().join(format!("flexmbs_reduce_kg_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();

    // clamped tube: six centrifugal K_G over its 4 modes, identical to the model compiler's
    let tube = dir.join("tube.fmb.h5");
    let msg = reduce(&part("rotor_tube"), &tube, &[]);
    assert!(
        msg.contains("geometric stiffness of 6 load patterns"),
        "{msg}"
    );
    let f = read_body_file(&tube).unwrap();
    let (body, fe) =
        load_reduced_with_fe(&part("rotor_tube"), Path::new("."), "b", Default::default()).unwrap();
    assert_eq!(f.body.k_red, body.k_red);
    let expected = centrifugal_stiffness(fe.as_ref().unwrap(), &body).unwrap();
    assert_eq!(f.geometric.as_ref(), Some(&expected));
    // spin about z puts the tube (along x) in tension: K_G,zz stiffens every bending mode, its
    // diagonal is >= 0 and not all zero
    let kzz = &expected.matrices[5];
    assert!((0..4).all(|i| kzz[(i, i)] >= 0.0) && (0..4).any(|i| kzz[(i, i)] > 0.0));

    // opt-out
    let plain = dir.join("tube_plain.fmb.h5");
    let msg = reduce(&part("rotor_tube"), &plain, &["--no-geometric"]);
    assert!(!msg.contains("geometric"), "{msg}");
    let p = read_body_file(&plain).unwrap();
    assert_eq!(p.geometric, None);
    assert_eq!(p.body, f.body);

    // free-free rod: no supports, no K_G, said so
    let rod = dir.join("rod.fmb.h5");
    let msg = reduce(&part("rod"), &rod, &[]);
    assert!(
        msg.contains("no geometric stiffness (no fixed nodes)"),
        "{msg}"
    );
    assert_eq!(read_body_file(&rod).unwrap().geometric, None);
    let _ = std::fs::remove_dir_all(&dir);
}

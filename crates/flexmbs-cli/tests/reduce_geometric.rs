//! `flexmbs reduce` stores the centrifugal geometric stiffness of a body with fixed nodes in the
//! reduced-body file (bitwise what a multibody model computes from the FE model), none for a
//! free-free body, and none with `--no-geometric`; beam meshes get their node rotary inertias.

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
    let dir = flexmbs_io::test_tools::scratch_dir("reduce_kg");

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

/// `flexmbs reduce` stores the lumped node rotary inertias of a beam mesh (bitwise the ones a
/// multibody model computes from the FE model file; the tube's torsion sum `rho (I_y + I_z) L`
/// to 1e-12) and says so; a solid mesh gets none.
#[test]
fn reduce_stores_rotary_inertias_of_beam_meshes() {
    let dir = flexmbs_io::test_tools::scratch_dir("reduce_rot");
    let tube = dir.join("tube.fmb.h5");
    let msg = reduce(&part("rotor_tube"), &tube, &["--no-geometric"]);
    assert!(msg.contains("beam node rotary inertias"), "{msg}");
    let f = read_body_file(&tube).unwrap();
    let (body, fe) =
        load_reduced_with_fe(&part("rotor_tube"), Path::new("."), "b", Default::default()).unwrap();
    let expected = flexmbs_sim::mass_model::beam_rotary_inertias(fe.as_ref().unwrap(), &body)
        .unwrap()
        .expect("beam mesh");
    let stored = f.rotary_inertia.expect("no rotary inertias stored");
    assert_eq!(stored, expected);
    // tube r_o = 10 mm, wall 1 mm: I_y + I_z = pi (r_o^4 - r_i^4) / 2, rho = 2700, L = 1 m
    let ip = std::f64::consts::PI * (0.01f64.powi(4) - 0.009f64.powi(4)) / 2.0;
    let sum: f64 = stored.iter().map(|m| m[(0, 0)]).sum();
    let rel = (sum - 2700.0 * ip) / (2700.0 * ip);
    eprintln!("tube torsion inertia sum {sum:e} kg m^2, rel. dev {rel:e}");
    assert!(rel.abs() < 1e-12, "{sum} vs {}", 2700.0 * ip);

    let solid = dir.join("solid.fmb.h5");
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cantilever_modal.toml");
    let msg = reduce(&model, &solid, &["--no-geometric"]);
    assert!(!msg.contains("rotary"), "{msg}");
    assert_eq!(read_body_file(&solid).unwrap().rotary_inertia, None);
    let _ = std::fs::remove_dir_all(&dir);
}

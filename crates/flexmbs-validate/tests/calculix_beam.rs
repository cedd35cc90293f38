//! The 40 x 2 x 2 C3D20R reference cantilever (`../shared/reference/calculix/`, copied to
//! `examples/calculix/`): flexmbs's modal analysis of the matrices exported by CalculiX equals
//! CalculiX's own frequencies to 1e-6, flexmbs's Hex20R on the same mesh is within 0.1 %, and the
//! Guyan tip stiffness of the CalculiX matrices matches the recipe's sanity value.
//! Skipped, with the reason printed, when `ccx` is not installed (CI installs it).

use flexmbs_fe::constraint::BoundaryConditions;
use flexmbs_fe::eigen::EigenOptions;
use flexmbs_fe::reduction::{craig_bampton, modal_analysis, CraigBamptonOptions, Provenance};
use flexmbs_fe::system::FeSystem;
use flexmbs_fe::UnitSystem;
use flexmbs_io::calculix::{import_matrices, read_dat_frequencies, read_inp, run_ccx};
use flexmbs_io::model::read_fe_model;
use flexmbs_reduce::pipeline::{prepare, run_modal};
use std::path::{Path, PathBuf};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

fn ccx_frequencies() -> Option<Vec<f64>> {
    flexmbs_io::test_tools::ccx_or_skip("ccx_frequencies")?;
    let dir = flexmbs_io::test_tools::scratch_dir("test-ccx-freq");
    let run = run_ccx(&examples().join("calculix/beam_freq.inp"), &dir).expect("ccx frequency run");
    let f: Vec<f64> = read_dat_frequencies(&run.file("dat"))
        .unwrap()
        .iter()
        .map(|m| m.frequency_hz)
        .collect();
    let _ = std::fs::remove_dir_all(&dir);
    Some(f)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn imported_calculix_matrices_reproduce_calculix_frequencies() {
    let Some(reference) = ccx_frequencies() else {
        return;
    };
    assert_eq!(reference.len(), 6);
    // regression values of the recipe
    for (f, r) in reference
        .iter()
        .zip([16.73174, 16.73174, 104.6634, 104.6634, 292.1994, 292.1994])
    {
        assert!(rel(*f, r) < 1e-6, "ccx gives {f}, recipe says {r}");
    }
    let model = examples().join("calculix_beam.toml");
    let spec = read_fe_model(&model).unwrap().body;
    let body = prepare(&spec, model.parent().unwrap(), &mut |_| {}).unwrap();
    assert_eq!(body.system.len(), 3600);
    let modal = run_modal(&spec, &body, 6, &mut |_| {}).unwrap();
    for (k, (label, r)) in modal.labels.iter().zip(&reference).enumerate() {
        let f = label.frequency_hz;
        // the .dat table prints 7 significant digits: 1e-6 relative is its resolution
        assert!(rel(f, *r) < 1e-6, "mode {}: flexmbs {f} vs ccx {r}", k + 1);
    }
    // flexmbs's own element on the same deck
    let model = examples().join("calculix_beam_flexmbs.toml");
    let spec = read_fe_model(&model).unwrap().body;
    let body = prepare(&spec, model.parent().unwrap(), &mut |_| {}).unwrap();
    let modal = run_modal(&spec, &body, 6, &mut |_| {}).unwrap();
    for (k, (label, r)) in modal.labels.iter().zip(&reference).enumerate() {
        let f = label.frequency_hz;
        assert!(
            rel(f, *r) < 1e-3,
            "mode {}: flexmbs Hex20R {f} vs ccx {r}",
            k + 1
        );
    }
}

#[test]
fn guyan_tip_stiffness_of_calculix_matrices() {
    if flexmbs_io::test_tools::ccx_or_skip("guyan_tip_stiffness_of_calculix_matrices").is_none() {
        return;
    }
    let deck = examples().join("calculix/beam_mat_free.inp");
    let inp = read_inp(&deck, UnitSystem::Si).unwrap();
    let mesh = inp.mesh;
    let assembled = import_matrices(&deck, &mesh).unwrap();
    let fixed = mesh.nodes_on_plane(0, 0.0, 1e-9);
    assert_eq!(fixed.len(), 21);
    let bc = BoundaryConditions {
        fixed,
        rigid: vec![],
    };
    let sys = FeSystem::from_assembled(&mesh, &assembled, &bc).unwrap();
    // the free-free export clamped in flexmbs gives CalculiX's clamped frequencies
    let modal = modal_analysis(&sys, 2, &EigenOptions::default(), &mut |_| {}).unwrap();
    assert!(rel(modal.labels[0].frequency_hz, 16.73174) < 1e-6);
    let tip = mesh.nearest_node([1.0, 0.01, 0.01]).unwrap();
    let body = craig_bampton(
        &mesh,
        &sys,
        &CraigBamptonOptions {
            interface: &[tip],
            internal_modes: 0,
            eigen: &EigenOptions::default(),
        },
        "guyan",
        Provenance::default(),
        &mut |_| {},
    )
    .unwrap();
    // tip stiffness for a y force with the node otherwise free: 1 / (K_red^-1)_yy
    let k = &body.k_red;
    let det = k[(0, 0)] * (k[(1, 1)] * k[(2, 2)] - k[(1, 2)] * k[(2, 1)])
        - k[(0, 1)] * (k[(1, 0)] * k[(2, 2)] - k[(1, 2)] * k[(2, 0)])
        + k[(0, 2)] * (k[(1, 0)] * k[(2, 1)] - k[(1, 1)] * k[(2, 0)]);
    let flex_yy = (k[(0, 0)] * k[(2, 2)] - k[(0, 2)] * k[(2, 0)]) / det;
    let k_yy = 1.0 / flex_yy;
    // recipe sanity value (CalculiX's K condensed onto the tip-centre node): 8417.5 N/m; flexmbs
    // measures 8413.2 (-0.05 %), see the case notes.
    assert!(rel(k_yy, 8417.5) < 1e-3, "k_yy = {k_yy}");
    let k_beam = 3.0 * 210e9 * 0.02f64.powi(4) / 12.0;
    assert!(
        rel(k_yy, k_beam) < 0.01,
        "k_yy = {k_yy} vs 3EI/L^3 = {k_beam}"
    );
}

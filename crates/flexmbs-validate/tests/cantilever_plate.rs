//! `cantilever_plate`: the chain of 10 four-interface superelements from an FE body file meets
//! the stored geometrically nonlinear CalculiX reference (C3D20R 80 x 8 x 2) within the case's
//! tolerances at every load; with `ccx` installed, the coarse deck stored with the case is run
//! again and reproduces its stored table.

use flexmbs_validate::cantilever_plate::{
    case_dir, read_reference, reference_from_dat, superelement_path, TOLERANCE_U, TOLERANCE_W,
};

/// `w/L` at every 5 % of the load within [`TOLERANCE_W`] (3 %) and `−u/L` where it is at least 0.1
/// within [`TOLERANCE_U`] (5 %) of the fine CalculiX run.
#[test]
fn superelement_plate_meets_calculix_reference() {
    let fine = read_reference(&case_dir().join("reference_c3d20r_80x8x2.csv")).unwrap();
    let (path, iterations) = superelement_path().unwrap();
    assert_eq!(fine.len(), 20);
    let (mut worst_w, mut worst_u) = (0.0_f64, 0.0_f64);
    for &(p, w_ref, u_ref) in &fine {
        let &(_, w, u) = path
            .iter()
            .find(|r| (r.0 - p).abs() < 1e-3)
            .unwrap_or_else(|| panic!("load {p} not on the path"));
        worst_w = worst_w.max(((w - w_ref) / w_ref).abs());
        if u_ref >= 0.1 {
            worst_u = worst_u.max(((u - u_ref) / u_ref).abs());
        }
    }
    eprintln!("largest error: w/L {worst_w:e}, -u/L {worst_u:e}; {iterations} Newton iterations");
    assert!(worst_w <= TOLERANCE_W && worst_u <= TOLERANCE_U);
}

/// The stored coarse table is what CalculiX computes from the stored coarse deck (to the 7
/// printed digits). Skipped, with the reason printed, when `ccx` is not installed.
#[test]
fn stored_coarse_reference_is_reproduced_by_calculix() {
    if flexmbs_io::test_tools::ccx_or_skip("stored_coarse_reference_is_reproduced_by_calculix")
        .is_none()
    {
        return;
    }
    let dir = flexmbs_io::test_tools::scratch_dir("plate-ccx");
    let run = flexmbs_io::calculix::run_ccx(&case_dir().join("ccx_c3d20r_40x4x2.inp"), &dir)
        .expect("ccx run");
    let dat = std::fs::read_to_string(run.job.with_extension("dat")).unwrap();
    let rerun = reference_from_dat(&dat).unwrap();
    let stored = read_reference(&case_dir().join("reference_c3d20r_40x4x2.csv")).unwrap();
    assert_eq!(rerun.len(), stored.len());
    for (a, b) in rerun.iter().zip(&stored) {
        assert!((a.0 - b.0).abs() < 1e-6 * b.0);
        assert!(
            (a.1 - b.1).abs() <= 1e-6 * b.1.abs().max(1e-3),
            "{a:?} vs {b:?}"
        );
        assert!(
            (a.2 - b.2).abs() <= 1e-6 * b.2.abs().max(1e-3),
            "{a:?} vs {b:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

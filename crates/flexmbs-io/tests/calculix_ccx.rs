//! End-to-end checks against a real CalculiX run (`ccx`, Debian calculix-ccx 2.20) of the
//! reference beam (1 m x 20 mm x 20 mm steel, 40 x 2 x 2 C3D20R). Each test prints a reason and
//! returns early (skips) when ccx is not installed.

use crate::common;

use common::data;
use faer::Mat;
use flexmbs_fe::{SparseMatrix, UnitSystem};
use flexmbs_io::calculix::matrices::sparse_times_dense;
use flexmbs_io::calculix::{
    matrix_export_deck, read_ccx_matrices, read_dat_frequencies, read_frd, read_inp, run_ccx,
    CcxMatrices,
};
use flexmbs_io::IoError;
use std::collections::{HashMap, HashSet};
use std::path::PathBuf;

fn workdir(name: &str) -> PathBuf {
    flexmbs_io::test_tools::scratch_dir(&format!("ccx_{name}"))
}

/// True (after printing why) if ccx is missing; fails instead under `FLEXMBS_REQUIRE_TOOLS=1`.
fn skip_without_ccx(test: &str) -> bool {
    flexmbs_io::test_tools::ccx_or_skip(test).is_none()
}

fn fro(a: &SparseMatrix) -> f64 {
    a.val().iter().map(|v| v * v).sum::<f64>().sqrt()
}

fn fro_dense(a: &Mat<f64>) -> f64 {
    let mut s = 0.0;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            s += a[(i, j)] * a[(i, j)];
        }
    }
    s.sqrt()
}

/// Clamped export of beam_mat.inp (K, M without the DOFs of set FIX).
fn clamped_export(dir: &std::path::Path) -> CcxMatrices {
    let run = run_ccx(&data("ccx/beam_mat.inp"), dir).expect("ccx clamped export");
    read_ccx_matrices(&run.job).unwrap()
}

#[test]
fn matrix_export_rigid_body_checks_and_clamping() {
    if skip_without_ccx("matrix_export_rigid_body_checks_and_clamping") {
        return;
    }
    let dir = workdir("mat");
    std::fs::create_dir_all(&dir).unwrap();
    let deck = dir.join("free_src").join("beam_free.inp");
    std::fs::create_dir_all(deck.parent().unwrap()).unwrap();
    std::fs::write(&deck, matrix_export_deck(&data("ccx/beam_mesh.inp"))).unwrap();
    let run = run_ccx(&deck, &dir.join("run")).unwrap();
    assert!(
        run.files
            .iter()
            .any(|f| f.extension().is_some_and(|e| e == "sti")),
        "{:?}",
        run.files
    );
    let free = read_ccx_matrices(&run.job).unwrap();
    let mesh = read_inp(&data("ccx/beam_mesh.inp"), UnitSystem::Si)
        .unwrap()
        .mesh;
    assert_eq!(free.len(), 3 * 1221);

    // Rigid-body matrix from node coordinates (rotations about the origin on the beam axis).
    let r = free.rigid_body_matrix(&mesh, [0.0, 0.0, 0.0]);
    let kr = sparse_times_dense(&free.k, &r);
    let rel = fro_dense(&kr) / (fro(&free.k) * fro_dense(&r));
    println!("||K R|| / (||K|| ||R||) = {rel:.3e}");
    assert!(rel < 1e-12, "K R relative {rel:e}");

    let mr = r.transpose() * sparse_times_dense(&free.m, &r);
    let rho_v = 7850.0 * 1.0 * 0.02 * 0.02; // 3.14 kg
    let jxx = rho_v * (0.02f64.powi(2) + 0.02f64.powi(2)) / 12.0; // 2.0933e-4 kg m^2
    let jyy = rho_v * (1.0 / 3.0 + 0.02f64.powi(2) / 12.0); // about the clamped end
    println!(
        "mass {:.12} {:.12} {:.12}, J_xx {:.6e}, J_yy {:.6}",
        mr[(0, 0)],
        mr[(1, 1)],
        mr[(2, 2)],
        mr[(3, 3)],
        mr[(4, 4)]
    );
    for k in 0..3 {
        assert!(
            (mr[(k, k)] / rho_v - 1.0).abs() < 1e-6,
            "mass {}",
            mr[(k, k)]
        );
    }
    assert!((mr[(3, 3)] / jxx - 1.0).abs() < 1e-4, "J_xx {}", mr[(3, 3)]);
    assert!((mr[(4, 4)] / jyy - 1.0).abs() < 1e-6, "J_yy {}", mr[(4, 4)]);
    // Static moment: z translation couples with rotation about y by -m x_c, x_c = 0.5 m.
    assert!(
        (mr[(2, 4)] / (-rho_v * 0.5) - 1.0).abs() < 1e-6,
        "S {}",
        mr[(2, 4)]
    );

    // Deleting the clamped DOFs from the free-free export gives the clamped export bit for bit.
    let fix: HashSet<u64> = mesh
        .node_set("FIX")
        .unwrap()
        .iter()
        .map(|&n| mesh.node_ids[n])
        .collect();
    let reduced = free.remove_dofs(|n, _| !fix.contains(&n));
    let clamped = clamped_export(&dir.join("clamped"));
    assert_eq!(reduced.dofs, clamped.dofs);
    for (a, b) in [(&reduced.k, &clamped.k), (&reduced.m, &clamped.m)] {
        assert_eq!(a.col_ptr(), b.col_ptr());
        assert_eq!(a.row_idx(), b.row_idx());
        let bits = |m: &SparseMatrix| m.val().iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(a), bits(b));
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn frequency_run_dat_frd_and_matrices_agree() {
    if skip_without_ccx("frequency_run_dat_frd_and_matrices_agree") {
        return;
    }
    let dir = workdir("freq");
    let run = run_ccx(&data("ccx/beam_freq.inp"), &dir).unwrap();
    let dat = read_dat_frequencies(&run.file("dat")).unwrap();
    let expect = [16.73174, 16.73174, 104.6634, 104.6634, 292.1994, 292.1994];
    assert_eq!(dat.len(), 6);
    for (m, f) in dat.iter().zip(expect) {
        assert!(
            (m.frequency_hz / f - 1.0).abs() < 1e-6,
            "{} vs {f}",
            m.frequency_hz
        );
    }
    let frd = read_frd(&run.file("frd")).unwrap();
    assert_eq!(frd.nodes.len(), 1221);
    assert_eq!(frd.modes.len(), 6);
    // Element connectivity of the frd (converted to Abaqus order) equals the deck's.
    let model = read_inp(&data("ccx/beam_mesh.inp"), UnitSystem::Si).unwrap();
    let mesh = &model.mesh;
    assert_eq!(frd.elements.len(), mesh.elements.len());
    for (fe, (e, label)) in frd
        .elements
        .iter()
        .zip(mesh.elements.iter().zip(&model.element_labels))
    {
        assert_eq!(fe.label, *label);
        let nodes: Vec<u64> = e.nodes.iter().map(|&n| mesh.node_ids[n]).collect();
        assert_eq!(fe.nodes, nodes);
    }
    // Coordinates agree to the 6 printed digits.
    for (label, x) in &frd.nodes {
        let i = mesh.node_ids.iter().position(|l| l == label).unwrap();
        for (a, b) in x.iter().zip(&mesh.nodes[i]) {
            assert!((a - b).abs() < 1e-6 * 1.0f64.max(b.abs()));
        }
    }
    // Mass normalisation and Rayleigh quotient of the frd modes with the exported K, M.
    let mats = clamped_export(&dir.join("clamped"));
    for (mode, d) in frd.modes.iter().zip(&dat) {
        assert!((mode.frequency_hz / d.frequency_hz - 1.0).abs() < 1e-6);
        let u: HashMap<u64, [f64; 3]> = mode.disp.iter().copied().collect();
        let phi = Mat::from_fn(mats.len(), 1, |i, _| {
            let (n, dir) = mats.dofs[i];
            u[&n][(dir - 1) as usize]
        });
        let mphi = phi.transpose() * sparse_times_dense(&mats.m, &phi);
        let kphi = phi.transpose() * sparse_times_dense(&mats.k, &phi);
        let omega2 = (2.0 * std::f64::consts::PI * mode.frequency_hz).powi(2);
        println!(
            "mode {:?}: phi^T M phi = {:.7}, phi^T K phi / omega^2 = {:.7}",
            mode.mode,
            mphi[(0, 0)],
            kphi[(0, 0)] / omega2
        );
        // Modes are mass-normalised; the frd prints 6 digits, which K (weighting the short
        // wavelengths of the rounding error) turns into ~6.5e-5 on mode 1.
        assert!((mphi[(0, 0)] - 1.0).abs() < 1e-5);
        assert!((kphi[(0, 0)] / omega2 - 1.0).abs() < 2e-4);
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn failing_deck_is_reported() {
    if skip_without_ccx("failing_deck_is_reported") {
        return;
    }
    let dir = workdir("fail");
    std::fs::create_dir_all(&dir).unwrap();
    let deck = dir.join("broken.inp");
    std::fs::write(&deck, "*NODE\n1, 0, 0, 0\n*ELEMENT, TYPE=C3D8, ELSET=E\n1, 1, 2, 3, 4, 5, 6, 7, 8\n*STEP\n*STATIC\n*END STEP\n")
        .unwrap();
    match run_ccx(&deck, &dir.join("run")) {
        Err(IoError::CcxFailed {
            message, status, ..
        }) => {
            println!("ccx failed as expected: status {status:?}: {message}");
            assert!(!message.is_empty());
        }
        other => panic!("expected CcxFailed, got {other:?}"),
    }
    std::fs::remove_dir_all(&dir).ok();
}

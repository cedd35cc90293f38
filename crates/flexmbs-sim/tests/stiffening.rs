//! Model-file keys `geometric_stiffening` and `[solver.newton] modified`: the rotating-beam
//! example against `validation/rotating_beam` (same data), its linear (spin-softened) variant,
//! modified against full Newton, and the SI(mm) conversion of the geometric stiffness.

use flexmbs_core::ffr::reduced_body_to_si;
use flexmbs_fe::geometric::GeometricStiffness;
use flexmbs_fe::reduction::ReducedBody;
use flexmbs_io::results::{read_results, RunStatus};
use flexmbs_sim::bodies::load_reduced_with_fe;
use flexmbs_sim::run::{run_model, RunOptions};
use flexmbs_sim::stiffening::{centrifugal_stiffness, geometric_to_si, select_geometric_modes};
use flexmbs_sim::{compile_model, SolverConfig};
use flexmbs_validate::rotating_beam::{first_peak, omega_after_pulse};
use std::path::{Path, PathBuf};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mbs")
}

fn out_dir(name: &str) -> PathBuf {
    let d = flexmbs_io::test_tools::scratch_dir(&format!("sim-stiff-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Runs the rotating-beam example text with `edit` applied; returns `(t, w_tip)` of the tip
/// deformation along the body y axis (rotating frame, direction of rotation) and the number of
/// Newton iterations.
fn run_rotating_beam(name: &str, edit: &dyn Fn(&str) -> String) -> (Vec<f64>, Vec<f64>, usize) {
    let file = examples().join("rotating_beam.toml");
    let text = edit(&std::fs::read_to_string(&file).unwrap());
    let cm = compile_model(&text, &file).unwrap();
    let out = out_dir(name);
    let summary = run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    assert_eq!(summary.status, RunStatus::Completed);
    let r = read_results(&out.join("results.h5")).unwrap();
    let w = r.series("tip.deformation.y").unwrap().to_vec();
    let _ = std::fs::remove_dir_all(&out);
    (r.time.clone(), w, summary.newton_iterations)
}

/// The example has the data of `validation/rotating_beam` (aluminium tube, 20 beam elements,
/// 4 cantilever modes, 100 rad/s, 50 N for 10 ms). Its post-pulse chordwise frequency with
/// geometric stiffening must match the validation's nonlinear reference (finite-segment chain,
/// n = 60: 127.728 rad/s) to 0.5 % and its FFR result (127.756 rad/s, h = 2e-5 s) to 0.1 %,
/// the first peak the reference's 0.090666 m to 1 %;
/// without stiffening the linear FFR body shows spin softening: sqrt(120.259^2 - 100^2) =
/// 66.801 rad/s (0.5 %). Modified and full Newton give the same history to 1e-8 relative.
#[test]
fn rotating_beam_example_stiffened_linear_and_modified_newton() {
    let (t, w_mod, it_mod) = run_rotating_beam("stiff", &|s| s.to_string());
    let omega = omega_after_pulse(&t, &w_mod).expect("no oscillation");
    let peak = first_peak(&w_mod);
    eprintln!("stiffened: omega after pulse {omega:.4} rad/s, first peak {peak:.6} m");
    assert!(
        ((omega - 127.728) / 127.728).abs() < 5e-3,
        "omega {omega} vs reference 127.728"
    );
    assert!(
        ((omega - 127.756) / 127.756).abs() < 1e-3,
        "omega {omega} vs validation FFR 127.756"
    );
    // first peak: validation FFR 0.090304 m, reference 0.090666 m; the example's tip force
    // follows the tip slope (node frame with rotations), which changes the peak slightly
    assert!(
        ((peak - 0.090666) / 0.090666).abs() < 0.01,
        "peak {peak} vs reference 0.090666"
    );

    // full Newton: same history to 1e-8 relative to the peak deflection
    let (t_full, w_full, it_full) = run_rotating_beam("full", &|s| {
        s.replace("modified = true", "modified = false")
    });
    assert_eq!(t_full.len(), t.len());
    let dw = w_full
        .iter()
        .zip(&w_mod)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let wmax = w_full.iter().map(|x| x.abs()).fold(0.0, f64::max);
    eprintln!(
        "modified vs full Newton: max |dw| = {dw:e} m (max |w| = {wmax:e} m), \
         {it_mod} vs {it_full} iterations"
    );
    assert!(dw < 1e-8 * wmax, "max |dw| = {dw:e}, max |w| = {wmax:e}");

    // linear FFR body: spin softening
    let (t_lin, w_lin, _) = run_rotating_beam("linear", &|s| {
        s.replace(
            "geometric_stiffening = true",
            "geometric_stiffening = false",
        )
    });
    let omega_lin = omega_after_pulse(&t_lin, &w_lin).expect("no oscillation (linear)");
    let peak_lin = first_peak(&w_lin);
    eprintln!("linear: omega after pulse {omega_lin:.4} rad/s, first peak {peak_lin:.6} m");
    assert!(
        ((omega_lin - 66.801) / 66.801).abs() < 5e-3,
        "linear omega {omega_lin} vs 66.801"
    );
    assert!(omega > 1.9 * omega_lin);
}

/// `modified = true` reaches the Newton settings of the solver configuration.
#[test]
fn newton_modified_key_sets_the_solver() {
    let file = examples().join("rotating_beam.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    for (edit, expected) in [("modified = true", true), ("modified = false", false)] {
        let cm = compile_model(&text.replace("modified = true", edit), &file).unwrap();
        let SolverConfig::GenAlpha { settings, .. } = cm.solver else {
            panic!("not generalized-alpha");
        };
        assert_eq!(settings.newton.modified, expected);
    }
}

/// The basis-independent form `Φ A Φᵀ` (translations, SI) of a modal matrix `A` (modes of a
/// degenerate pair, as the tube's y/z bending pairs, are defined only up to a rotation).
fn nodal(phi: &faer::Mat<f64>, a: &faer::Mat<f64>) -> faer::Mat<f64> {
    phi * a * phi.transpose()
}

fn max_rel_diff(a: &faer::Mat<f64>, b: &faer::Mat<f64>) -> f64 {
    let mut d: f64 = 0.0;
    let mut m: f64 = 0.0;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            d = d.max((a[(i, j)] - b[(i, j)]).abs());
            m = m.max(a[(i, j)].abs());
        }
    }
    d / m
}

/// Reduced body and K_G in SI, as the model compiler builds them, modes 1..=nf.
fn si_body_and_stiffness(path: &Path, nf: usize) -> (ReducedBody, GeometricStiffness) {
    let (body, fe) = load_reduced_with_fe(path, Path::new("."), "b", Default::default()).unwrap();
    let g = centrifugal_stiffness(fe.as_ref().unwrap(), &body).unwrap();
    let cols: Vec<usize> = (0..nf).collect();
    let g = geometric_to_si(&select_geometric_modes(&g, &cols), body.units);
    (reduced_body_to_si(&body), g)
}

/// The rotor tube in SI(mm) (mm, t, N/mm^2) gives the same SI geometric stiffness as in SI, to
/// 1e-9 relative (compared as `Φ K_G,ab Φᵀ` over the translations; also `Φ k_ff Φᵀ`), and the
/// stiffened example run with either part the same tip history to 1e-9 relative.
#[test]
fn geometric_stiffness_si_mm_equals_si() {
    let dir = out_dir("mm");
    std::fs::create_dir_all(&dir).unwrap();
    let mm = dir.join("rotor_tube_mm.toml");
    std::fs::write(
        &mm,
        r#"[body]
name = "rotor_tube"
units = "SI(mm)"

[body.mesh]
type = "beam"
start = [0.0, 0.0, 0.0]
end = [1000.0, 0.0, 0.0]
elements = 20
section = { shape = "tube", outer_radius = 10.0, wall = 1.0 }
material = { e = 70000.0, nu = 0.3, rho = 2.7e-9 }

[body.boundary]
fixed = [{ nearest = [0.0, 0.0, 0.0] }]

[body.reduction]
method = "modal"
modes = 4
"#,
    )
    .unwrap();
    let (b_si, g_si) = si_body_and_stiffness(&examples().join("parts/rotor_tube.toml"), 4);
    let (b_mm, g_mm) = si_body_and_stiffness(&mm, 4);
    assert_eq!(b_mm.units, flexmbs_fe::UnitSystem::Si);
    let d_k = max_rel_diff(
        &nodal(&b_si.modes_t, &b_si.k_red),
        &nodal(&b_mm.modes_t, &b_mm.k_red),
    );
    eprintln!("Phi k_ff Phi^T: max rel diff {d_k:e}");
    assert!(d_k < 1e-9);
    assert_eq!(g_si.matrices.len(), 6);
    for (k, (a, b)) in g_si.matrices.iter().zip(&g_mm.matrices).enumerate() {
        let d = max_rel_diff(&nodal(&b_si.modes_t, a), &nodal(&b_mm.modes_t, b));
        eprintln!("pattern {:?}: max rel diff {d:e}", g_si.load_patterns[k]);
        // the xx pattern (a = e_x x_x - x) loads nothing on the x axis: K_G,xx = 0 in both
        let scale = a.norm_max();
        if scale > 1e-12 * g_si.matrices[0].norm_max() {
            assert!(d < 1e-9, "pattern {k}: {d:e}");
        }
    }
    // end to end: the example with the SI(mm) part gives the same tip history (20 ms, through
    // the pulse) as with the SI part
    let shorten = |s: &str| s.replace("t_end = \"0.3 s\"", "t_end = \"20 ms\"");
    let (_, w_si, _) = run_rotating_beam("si", &|s| shorten(s));
    let mm_source = format!("source = {:?}", mm.display().to_string());
    let (_, w_mm, _) = run_rotating_beam("si_mm", &|s| {
        shorten(s).replace("source = \"parts/rotor_tube.toml\"", &mm_source)
    });
    let dw = w_si
        .iter()
        .zip(&w_mm)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let wmax = w_si.iter().map(|x| x.abs()).fold(0.0, f64::max);
    eprintln!("SI(mm) vs SI run: max |dw| = {dw:e} m (max |w| = {wmax:e} m)");
    assert!(w_si.len() > 200 && wmax > 0.05);
    assert!(dw < 1e-9 * wmax, "max |dw| = {dw:e}");
    let _ = std::fs::remove_dir_all(&dir);
}

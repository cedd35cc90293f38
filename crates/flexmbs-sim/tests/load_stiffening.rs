//! Model-file key `load_stiffening`: the slider-crank example (free-free FFR rod from an FE model
//! file) with its rod stiffened by its joint reactions: patterns at the nodes of its node frames
//! with inertia relief, a smaller midpoint deflection, the energy balance with the stiffening
//! power, and the solver restriction.

use flexmbs_io::results::{read_results, RunStatus};
use flexmbs_sim::compile_model;
use flexmbs_sim::run::{run_model, RunOptions};
use std::path::{Path, PathBuf};

fn example() -> (PathBuf, String) {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mbs/slider_crank.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    (file, text)
}

/// One crank revolution; `stiffen` adds `load_stiffening = true` (and centrifugal stiffening) to
/// the rod. Returns the largest `|rod_mid.deformation.y|`, the energy drift and the run's energy.
fn run(stiffen: bool, name: &str) -> (f64, f64, f64) {
    let (file, text) = example();
    let mut text = text.replace(
        "t_end = 0.16755160819145562",
        "t_end = 0.041887902047863905",
    );
    if stiffen {
        text = text.replace(
            "modes = 4\n",
            "modes = 4\nload_stiffening = true\ngeometric_stiffening = true\n",
        );
    }
    let cm = compile_model(&text, &file).unwrap();
    let rod = cm.model.body_id("rod").unwrap();
    let b = cm.model.bodies[rod.0].element.load_stiffened_ffr();
    assert_eq!(b.is_some(), stiffen);
    if let Some(b) = b {
        let ls = b.load_stiffening().unwrap();
        // the three node frames rod_a, rod_mid, rod_b: nodes 0, 10, 20 of the 20-element rod
        let nodes: Vec<usize> = ls.interfaces.iter().map(|i| i.node).collect();
        assert_eq!(nodes, vec![0, 10, 20]);
        assert!(ls.inertia_relief && ls.acceleration.is_none());
        assert!(b.geometric_stiffening().is_some());
    }
    let out = flexmbs_io::test_tools::scratch_dir(&format!("load-stiff-{name}"));
    let _ = std::fs::remove_dir_all(&out);
    let summary = run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    assert_eq!(summary.status, RunStatus::Completed);
    let r = read_results(&out.join("results.h5")).unwrap();
    let w = r.series("rod_mid.deformation.y").unwrap();
    let w_max = w.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let _ = std::fs::remove_dir_all(&out);
    (
        w_max,
        summary.energy_drift,
        summary
            .energy_initial
            .abs()
            .max(summary.external_work.abs()),
    )
}

/// The stiffened rod deflects at least 10 % less at midspan in the first revolution; the energy
/// balance (drive work plus stiffening power) closes as well as without stiffening (drift below
/// 1e-3 of the drive work).
#[test]
fn slider_crank_example_with_load_stiffening() {
    let (w0, drift0, scale0) = run(false, "plain");
    let (w1, drift1, scale1) = run(true, "stiff");
    eprintln!(
        "max |rod_mid.deformation.y|: {w0:.4e} m unstiffened, {w1:.4e} m with load stiffening ({:+.1} %); energy drift {drift0:.2e} / {drift1:.2e} J of {scale0:.3e} / {scale1:.3e} J",
        100.0 * (w1 / w0 - 1.0)
    );
    assert!(w1 < 0.9 * w0, "{w1} vs {w0}");
    assert!(drift1 < 1e-3 * scale1, "{drift1} of {scale1}");
}

/// `load_stiffening` with another solver than generalized-alpha is an error at the key.
#[test]
fn load_stiffening_needs_generalized_alpha() {
    let (file, text) = example();
    let text = text
        .replace("modes = 4\n", "modes = 4\nload_stiffening = true\n")
        .replace("type = \"generalized-alpha\"", "type = \"moreau\"")
        .replace("rho_inf = 0.8\n", "");
    let e = compile_model(&text, &file).unwrap_err().to_string();
    assert!(
        e.contains("body[1].load_stiffening") && e.contains("generalized-alpha"),
        "{e}"
    );
}

/// `load_stiffening` with `initial = "static"` compiles: the static start is a statics solve,
/// which includes the stiffening ([`statics_with_load_stiffening_is_a_beam_column`]).
#[test]
fn load_stiffening_accepts_a_static_start() {
    let (file, text) = example();
    let text = text
        .replace("modes = 4\n", "modes = 4\nload_stiffening = true\n")
        .replace(
            "type = \"generalized-alpha\"",
            "type = \"generalized-alpha\"\ninitial = \"static\"",
        );
    // a static start is at rest: the bodies' initial velocities go
    let text: String = text
        .lines()
        .filter(|l| !l.starts_with("velocity = ") && !l.starts_with("angular_velocity = ["))
        .map(|l| format!("{l}\n"))
        .collect();
    assert!(text.contains("initial = \"static\""));
    let cm = compile_model(&text, &file).unwrap();
    assert!(cm.initial_static);
}

/// Exact midspan deflection over its value without axial force of a pinned-pinned beam-column
/// under a central lateral force and an axial force `p` (compression positive) with
/// `P_cr = π² EI / L²` (Timoshenko & Gere, Theory of Elastic Stability, 2nd ed., §1.5):
/// `u = (π/2) sqrt(|p|/P_cr)`, `3 (tan u − u) / u³` in compression, `3 (u − tanh u) / u³` in
/// tension.
fn beam_column_amplification(p_over_pcr: f64) -> f64 {
    let u = 0.5 * std::f64::consts::PI * p_over_pcr.abs().sqrt();
    if p_over_pcr > 0.0 {
        3.0 * (u.tan() - u) / u.powi(3)
    } else {
        3.0 * (u - u.tanh()) / u.powi(3)
    }
}

/// `type = "statics"` with `load_stiffening` (issue 9 item 6 in statics): the slider-crank
/// example held at crank angle 0 is a pinned-pinned column (crank pin revolute, slider on its
/// guide). The rod is on 8 free-free modes (two symmetric in-plane modes; the FE file is the
/// example's with `modes = 8`). An axial force on the slider, `P = ±0.5 P_cr` (compression,
/// tension), and 1 N laterally at the rod midpoint. The midpoint's deflection over the one
/// without axial force equals the exact beam-column amplification within 0.5 % (1.986 and
/// 0.671; the 8-mode basis gives −0.33 % and +0.06 %, `flexmbs-core/tests/ffr_load_stiffening.rs`).
/// Without `load_stiffening` the axial force leaves it at 1 within 1e-3.
#[test]
fn statics_with_load_stiffening_is_a_beam_column() {
    let (file, text) = example();
    let dir = flexmbs_io::test_tools::scratch_dir("load-stiff-statics");
    let rod = std::fs::read_to_string(file.parent().unwrap().join("parts/rod.toml")).unwrap();
    let rod_file = dir.join("rod8.toml");
    std::fs::write(&rod_file, rod.replace("modes = 4", "modes = 8")).unwrap();
    let (e, d) = (200e9, 0.006_f64);
    let pcr = std::f64::consts::PI.powi(3) * e * d.powi(4) / 64.0 / 0.09;
    let deflection = |p_over_pcr: f64, stiffen: bool| -> f64 {
        let solver_start = text.find("[solver]").unwrap();
        let solver_end = text.find("[[body]]").unwrap();
        let mut t = format!(
            "{}[solver]\ntype = \"statics\"\n\n{}",
            &text[..solver_start],
            &text[solver_end..]
        );
        t = t
            .replace(
                "source = \"parts/rod.toml\"",
                &format!("source = {:?}", rod_file.to_str().unwrap()),
            )
            .replace(
                "modes = 4\n",
                if stiffen {
                    "modes = 8\nload_stiffening = true\n"
                } else {
                    "modes = 8\n"
                },
            )
            .replace("every = 10\n", "every = 1\n");
        t.push_str(&format!(
            "\n[[frame]]\nname = \"slider_c\"\nbody = \"slider\"\n\n[[load]]\ntype = \"force\"\nframe = \"slider_c\"\nvector = [{}, 0, 0]\n\n[[load]]\ntype = \"force\"\nframe = \"rod_mid\"\nvector = [0, 1.0, 0]\n",
            -p_over_pcr * pcr
        ));
        let cm = compile_model(&t, &file).unwrap();
        let out = dir.join(format!("run-{p_over_pcr}-{stiffen}"));
        let summary = run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
        assert_eq!(summary.status, RunStatus::Completed);
        let r = read_results(&out.join("results.h5")).unwrap();
        *r.series("rod_mid.position.y").unwrap().last().unwrap()
    };
    let w0 = deflection(0.0, true);
    for ratio in [0.5, -0.5] {
        let amp = deflection(ratio, true) / w0;
        let plain = deflection(ratio, false) / w0;
        let exact = beam_column_amplification(ratio);
        eprintln!(
            "P/P_cr = {ratio:+.1}: amplification {amp:.5} (exact {exact:.5}, {:+.2e}); without load_stiffening {plain:.5}",
            amp / exact - 1.0
        );
        assert!((amp / exact - 1.0).abs() < 5e-3, "{amp} vs {exact}");
        assert!((plain - 1.0).abs() < 1e-3, "{plain}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

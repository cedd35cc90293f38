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
    let out =
        std::env::temp_dir().join(format!("flexmbs-load-stiff-{}-{name}", std::process::id()));
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

/// `load_stiffening` with `initial = "static"` is an error at the key: the static start would be
/// computed without it.
#[test]
fn load_stiffening_refuses_a_static_start() {
    let (file, text) = example();
    let text = text
        .replace("modes = 4\n", "modes = 4\nload_stiffening = true\n")
        .replace(
            "type = \"generalized-alpha\"",
            "type = \"generalized-alpha\"\ninitial = \"static\"",
        );
    assert!(text.contains("initial = \"static\""));
    let e = compile_model(&text, &file).unwrap_err().to_string();
    assert!(
        e.contains("body[1].load_stiffening") && e.contains("initial = \"static\""),
        "{e}"
    );
}

//! `solver.linear_solver` in a model file: parsed, checked, and the sparse backend reproduces
//! the dense run of the slider-crank example (flexible rod, joints) to 1e-10.

use flexmbs_core::algebra::LinearSolver;
use flexmbs_io::results::{read_results, RunStatus};
use flexmbs_sim::run::{run_model, RunOptions};
use std::path::{Path, PathBuf};

fn example_text(name: &str) -> (String, PathBuf) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/mbs")
        .join(name);
    (std::fs::read_to_string(&path).unwrap(), path)
}

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "flexmbs-sim-linsolve-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// The example text with `linear_solver = value` added to `[solver]`.
fn with_linear_solver(text: &str, value: &str) -> String {
    text.replacen(
        "[solver]\n",
        &format!("[solver]\nlinear_solver = {value}\n"),
        1,
    )
}

#[test]
fn linear_solver_key_selects_the_backend() {
    let (text, path) = example_text("slider_crank.toml");
    let cm = flexmbs_sim::compile_model(&text, &path).unwrap();
    assert_eq!(cm.linear_solver, LinearSolver::Auto);
    for (value, expect) in [
        ("\"dense\"", LinearSolver::Dense),
        ("\"sparse\"", LinearSolver::Sparse),
        ("\"auto\"", LinearSolver::Auto),
    ] {
        let cm = flexmbs_sim::compile_model(&with_linear_solver(&text, value), &path).unwrap();
        assert_eq!(cm.linear_solver, expect, "{value}");
    }
    let err = flexmbs_sim::compile_model(&with_linear_solver(&text, "\"lu\""), &path)
        .unwrap_err()
        .to_string();
    assert!(err.contains("linear_solver") || err.contains("lu"), "{err}");
}

/// Every output series of the slider-crank example with the sparse backend equals the dense
/// run to 1e-10 relative to the series' largest value.
#[test]
fn sparse_run_equals_dense_run() {
    let (text, path) = example_text("slider_crank.toml");
    let mut series = Vec::new();
    for value in ["\"dense\"", "\"sparse\""] {
        let cm = flexmbs_sim::compile_model(&with_linear_solver(&text, value), &path).unwrap();
        let out = out_dir(value.trim_matches('"'));
        let summary = run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
        assert_eq!(summary.status, RunStatus::Completed);
        series.push(read_results(&out.join("results.h5")).unwrap());
    }
    let (d, s) = (&series[0], &series[1]);
    assert_eq!(d.time, s.time);
    let mut worst = (0.0_f64, String::new());
    for name in d.series_names() {
        let (a, b) = (d.series(&name).unwrap(), s.series(&name).unwrap());
        let scale = a.iter().fold(1e-300_f64, |m, x| m.max(x.abs()));
        let e = a
            .iter()
            .zip(&b)
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
            / scale;
        if e > worst.0 {
            worst = (e, name.to_string());
        }
    }
    println!("worst series difference {:e} ({})", worst.0, worst.1);
    assert!(worst.0 < 1e-10, "{worst:?}");
}

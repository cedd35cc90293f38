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
    let d = flexmbs_io::test_tools::scratch_dir(&format!("sim-linsolve-{name}"));
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
/// run to 1e-10 relative to `max(1, the series' largest magnitude)` (SI units: a series that is
/// zero up to round-off, like the out-of-plane position, is compared absolutely), the joint
/// multipliers and the reactions and drive torque computed from them to 1e-6 (measured 8e-8);
/// the drift monitors are round-off and not compared.
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
    // (worst difference, series) for the multipliers and for everything else
    let mut worst = [(0.0_f64, String::new()), (0.0_f64, String::new())];
    for name in d.series_names() {
        let (a, b) = (d.series(&name).unwrap(), s.series(&name).unwrap());
        let scale = a.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
        let e = a
            .iter()
            .zip(&b)
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
            / scale;
        if name.starts_with("drift/") {
            continue; // round-off monitors (|g|, |G u|), not results
        }
        let from_multipliers = name.starts_with("lambda/")
            || name.contains(".reaction.")
            || name.contains(".torque.")
            || name.contains(".force.");
        let k = usize::from(from_multipliers);
        if e > worst[k].0 {
            worst[k] = (e, name.to_string());
        }
    }
    println!(
        "worst state/output difference {:e} ({})",
        worst[0].0, worst[0].1
    );
    println!(
        "worst multiplier/reaction difference {:e} ({})",
        worst[1].0, worst[1].1
    );
    assert!(worst[0].0 < 1e-10, "{:?}", worst[0]);
    // Newton's convergence test checks the acceleration increment (1e-10) and the constraint
    // error, not the multipliers: two converged runs agree in lambda to the multiplier update
    // left at convergence, a few orders above the state's agreement
    assert!(worst[1].0 < 1e-6, "{:?}", worst[1]);
}

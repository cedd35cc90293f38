//! Failure hints chosen by the cause (issue 11 item 7): the double-pendulum example without
//! numerical damping (`rho_inf = 1`) run to 10 s fails by a growing step-frequency oscillation of
//! its joint reactions, which a smaller step does not remove (it fails with a quarter of the step
//! too): the hint must name `rho_inf < 1`, not a smaller `h`. A failure of another cause keeps the
//! general hint.

use crate::common;

use flexmbs_sim::run::{run_model, RunError, RunOptions};
use std::path::Path;

/// The double-pendulum example with `[solver]` lines replaced (`key = value` by key).
fn double_pendulum_with(
    test: &str,
    solver: &[(&str, &str)],
) -> (flexmbs_sim::compile::CompiledModel, std::path::PathBuf) {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mbs/double_pendulum.toml");
    let mut text = std::fs::read_to_string(&src).unwrap();
    for (key, value) in solver {
        let start = text
            .find(&format!("\n{key} = "))
            .unwrap_or_else(|| panic!("no `{key}`"))
            + 1;
        let end = start + text[start..].find('\n').unwrap();
        text.replace_range(start..end, &format!("{key} = {value}"));
    }
    let dir = common::work_dir("failure-hints", test);
    let file = dir.join("double_pendulum.toml");
    std::fs::write(&file, text).unwrap();
    (flexmbs_sim::load_model(&file).unwrap(), dir)
}

/// The hint of a failed run of `cm` (panics if the run does not fail in the solver).
fn failure_hint(cm: &flexmbs_sim::compile::CompiledModel, dir: &Path) -> (f64, String) {
    let err = run_model(cm, &RunOptions::new(dir.join("out")), &mut |_| {}).unwrap_err();
    let _ = std::fs::remove_dir_all(dir);
    match err {
        RunError::Solver { t, cause, .. } => (t, cause.hint(&cm.solver)),
        e => panic!("expected a solver failure, got {e}"),
    }
}

#[test]
fn undamped_step_frequency_growth_suggests_rho_inf_below_one() {
    for (name, h) in [("h1", "\"1 ms\""), ("h025", "\"0.25 ms\"")] {
        let (cm, dir) = double_pendulum_with(name, &[("t_end", "\"10 s\""), ("h", h)]);
        let (t, hint) = failure_hint(&cm, &dir);
        eprintln!("h = {h}: failed at t = {t}: {hint}");
        assert!(t > 3.0 && t < 10.0, "{t}");
        assert!(hint.contains("step frequency"), "{hint}");
        assert!(hint.contains("`rho_inf = 0.9`"), "{hint}");
        assert!(!hint.contains("adaptive"), "{hint}");
    }
    // and the suggested fix works: rho_inf = 0.9 runs the 10 s
    let (cm, dir) = double_pendulum_with("fixed", &[("t_end", "\"10 s\""), ("rho_inf", "0.9")]);
    run_model(&cm, &RunOptions::new(dir.join("out")), &mut |_| {}).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn other_failures_keep_the_general_hint() {
    // one Newton iteration cannot converge the first step: no oscillation has grown
    let (cm, dir) = double_pendulum_with("newton", &[("rho_inf", "0.9"), ("h", "\"1 ms\"")]);
    let mut cm = cm;
    if let flexmbs_sim::config::SolverConfig::GenAlpha { settings, .. } = &mut cm.solver {
        settings.newton.max_iterations = 1;
    }
    let (_, hint) = failure_hint(&cm, &dir);
    assert!(hint.starts_with("a smaller step `h`"), "{hint}");
    assert!(!hint.contains("rho_inf"), "{hint}");
}

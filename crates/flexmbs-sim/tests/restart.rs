//! `solver.restart`: a run restarted from an output row of an earlier run continues it. With
//! `rho_inf = 1` the generalized-alpha acceleration variable equals the consistent acceleration
//! the restarted run computes, so half a run plus its restart reproduce the whole run to the
//! Newton tolerance (measured: 1.6e-19 m on a 3.2e-4 m tip deflection).

use crate::common;

use flexmbs_io::results::read_results;
use flexmbs_sim::run::{run_model, RunOptions};
use flexmbs_sim::{compile_model, SimError};
use std::path::{Path, PathBuf};

fn part(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../examples/mbs/parts/{name}"))
}

/// A clamped cantilever released from its bent first mode, loaded at the tip from t = 2 ms.
fn model(solver_extra: &str, t_end: f64, body_extra: &str) -> String {
    format!(
        r#"
[model]
name = "restarted_cantilever"
[solver]
type = "generalized-alpha"
rho_inf = 1.0
h = 1e-4
t_end = {t_end}
{solver_extra}
[[body]]
name = "beam"
type = "ffr"
source = "{}"
{body_extra}
[[frame]]
name = "wall"
body = "ground"
[[frame]]
name = "tip"
body = "beam"
nearest = [1.0, 0.0, 0.0]
[[joint]]
name = "clamp"
type = "fixed"
a = "wall"
b = "beam"
[[load]]
type = "force"
frame = "tip"
vector = [0, 0, -20.0]
time = {{ type = "step", t0 = 2e-3, after = 1 }}
[output]
signals = ["tip.deformation"]
"#,
        part("cantilever_beam.toml").display()
    )
}

const START: &str = "modal_coordinates = [1e-3, 0, 0, 0, 0, 0, 0, 0]";

fn run(text: &str, tag: &str) -> flexmbs_io::results::Results {
    let dir = common::work_dir("restart", tag);
    let cm = compile_model(text, &dir.join("m.toml")).unwrap();
    run_model(&cm, &RunOptions::new(&dir), &mut |_| {}).unwrap();
    read_results(&dir.join("results.h5")).unwrap()
}

fn restart_key(results: &Path, time: Option<&str>) -> String {
    let t = time.map_or(String::new(), |t| format!(", time = {t}"));
    format!("restart = {{ results = \"{}\"{t} }}", results.display())
}

#[test]
fn half_run_plus_restart_equals_the_whole_run() {
    let whole = run(&model("", 6e-3, START), "whole");
    let first = run(&model("", 3e-3, START), "first");
    let path = first.path().to_path_buf();
    // from the row at 2 ms (before the end of the first run) and from the last row (3 ms)
    for (time, tag) in [(Some("\"2 ms\""), "second-2ms"), (None, "second-last")] {
        let second = run(&model(&restart_key(&path, time), 6e-3, ""), tag);
        let t0 = second.time[0];
        assert!(
            (t0 - if time.is_some() { 2e-3 } else { 3e-3 }).abs() < 1e-12,
            "{t0}"
        );
        let (a, b) = (
            whole.series("tip.deformation.z").unwrap(),
            second.series("tip.deformation.z").unwrap(),
        );
        let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let offset = whole
            .time
            .iter()
            .position(|&t| (t - t0).abs() < 1e-12)
            .unwrap();
        assert_eq!(second.rows() + offset, whole.rows());
        let worst = b
            .iter()
            .zip(&a[offset..])
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(
            worst < 1e-8 * scale,
            "max difference {worst:e} (scale {scale:e})"
        );
    }
}

fn error_of(text: &str) -> String {
    match compile_model(text, &common::work_dir("restart", "bad").join("m.toml")) {
        Err(e @ SimError::Model { .. }) => e.to_string(),
        Err(e) => panic!("expected a located model error, got {e}"),
        Ok(_) => panic!("accepted"),
    }
}

#[test]
fn bad_restarts_are_located() {
    let first = run(&model("", 1e-3, START), "bad-first");
    let path = first.path().to_path_buf();
    let e = error_of(&model(&restart_key(&path, Some("\"0.55 ms\"")), 2e-3, ""));
    assert!(
        e.contains("solver.restart.time") && e.contains("nearest rows are at"),
        "{e}"
    );
    let e = error_of(&model(&restart_key(&path, None), 1e-3, ""));
    assert!(
        e.contains("solver.t_end") && e.contains("not before"),
        "{e}"
    );
    let e = error_of(&model(&restart_key(&path, None), 2e-3, START));
    assert!(
        e.contains("body[0].modal_coordinates") && e.contains("results file"),
        "{e}"
    );
    let e = error_of(&model(
        &restart_key(Path::new("nowhere/results.h5"), None),
        2e-3,
        "",
    ));
    assert!(e.contains("solver.restart.results"), "{e}");
    // another body (a different part: other modes) has other coordinates
    let other = model(&restart_key(&path, None), 2e-3, "modes = 4");
    let e = error_of(&other);
    assert!(
        e.contains("solver.restart.results") && e.contains("same bodies"),
        "{e}"
    );
    let statics = model(&restart_key(&path, None), 2e-3, "").replace(
        "type = \"generalized-alpha\"\nrho_inf = 1.0\nh = 1e-4\nt_end = 0.002",
        "type = \"statics\"",
    );
    assert!(statics.contains("statics"));
    let e = error_of(&statics);
    assert!(e.contains("solver.restart") && e.contains("statics"), "{e}");
}

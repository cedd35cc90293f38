//! Run-time plausibility warnings: a statically overloaded cantilever (elastic deflection beyond
//! 10 % of its size) and a drive whose velocity jumps (velocity-constraint drift) are reported in
//! the run summary; the shipped static cantilever (2.4 mm on 1 m) is not.

use crate::common;

use flexmbs_sim::compile_model;
use flexmbs_sim::run::{run_model, RunOptions, RunSummary};
use std::path::Path;

fn run(text: &str, tag: &str) -> RunSummary {
    let dir = common::work_dir("plausibility", tag);
    let cm = compile_model(text, &dir.join("m.toml")).unwrap();
    run_model(&cm, &RunOptions::new(&dir), &mut |_| {}).unwrap()
}

fn static_cantilever(force: &str) -> String {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mbs/static_cantilever.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let part = path.parent().unwrap().join("parts/cantilever_beam.toml");
    text.replace(
        "\"parts/cantilever_beam.toml\"",
        &format!("\"{}\"", part.display()),
    )
    .replace("\"-20 N\"", force)
}

#[test]
fn overloaded_cantilever_warns_about_large_deformation() {
    let ok = run(&static_cantilever("\"-20 N\""), "small");
    assert!(ok.warnings.is_empty(), "{:?}", ok.warnings);
    // 1 kN: P L^3 / (3 E I) = 0.119 m on a 1 m beam (size 1.0004 m): 12 %
    let big = run(&static_cantilever("\"-1 kN\""), "large");
    assert_eq!(big.warnings.len(), 1, "{:?}", big.warnings);
    let w = &big.warnings[0];
    assert!(
        w.contains("body `beam`") && w.contains("elastic deformation reached 1.19"),
        "{w}"
    );
}

#[test]
fn velocity_jump_of_a_drive_warns_about_velocity_drift() {
    let text = r#"
[model]
name = "kink"
[solver]
type = "generalized-alpha"
h = 1e-3
t_end = 0.1
[[body]]
name = "arm"
type = "rigid"
mass = 1.0
inertia = [0.01, 0.01, 0.01]
position = [0.5, 0, 0]
[[frame]]
name = "o"
body = "ground"
[[frame]]
name = "pin"
body = "arm"
position = [-0.5, 0, 0]
[[joint]]
name = "drive"
type = "revolute"
a = "o"
b = "pin"
angle = { type = "ramp", t0 = 0.05, t1 = 0.06, v0 = 0, v1 = "90 deg" }
"#;
    let s = run(text, "kink");
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("velocity constraints") && w.contains("t = 5.0")),
        "{:?}",
        s.warnings
    );
    // a smooth law over 80 steps: no warning
    let smooth = text
        .replace(
            "type = \"ramp\", t0 = 0.05, t1 = 0.06",
            "type = \"step5\", t0 = 0.02, t1 = 0.1",
        )
        .replace("t_end = 0.1", "t_end = 0.12");
    let s = run(&smooth, "smooth");
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

/// A 2 kg ball dropped on a penalty floor (k = 1e6 N/m) with Moreau's fixed steps: at h = 3 ms
/// the explicit penalty step `h sqrt(k / m)` is 2.12 (above 2, the bounces gain energy) and the
/// run warns with the ratio and the factor to shrink the step by; at 1 ms (0.71) it does not.
#[test]
fn unstable_penalty_step_of_moreau_warns() {
    let model = |h: &str| {
        format!(
            r#"
[model]
name = "drop"
gravity = [0, 0, -9.81]
[solver]
type = "moreau"
h = {h}
t_end = 0.5
[[body]]
name = "ball"
type = "rigid"
mass = 2.0
inertia = [8e-3, 8e-3, 8e-3]
position = [0, 0, 0.101]
[[frame]]
name = "floor"
body = "ground"
[[contact]]
name = "floor_contact"
a = {{ type = "sphere", frame = "ball", radius = 0.1 }}
b = {{ type = "plane", frame = "floor" }}
normal = "regularized"
stiffness = 1e6
"#
        )
    };
    let ok = run(&model("1e-3"), "penalty-stable");
    assert!(ok.warnings.is_empty(), "{:?}", ok.warnings);
    let bad = run(&model("3e-3"), "penalty-unstable");
    assert_eq!(bad.warnings.len(), 1, "{:?}", bad.warnings);
    let w = &bad.warnings[0];
    assert!(
        w.contains("contact `floor_contact`") && w.contains("reached 2.121") && w.contains("0.94"),
        "{w}"
    );
}

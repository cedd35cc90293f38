//! `flexmbs check` and `flexmbs run` refuse a revolute joint at a solid-mesh node with the same
//! located message naming the rigid interface to use, and print drive warnings alike.

use std::path::Path;
use std::process::Command;

/// A solid strip clamped at its root, hinged to a rigid crank at a corner node of its end face.
const MODEL: &str = r#"
[model]
name = "solid_hinge"

[solver]
type = "generalized-alpha"
h = "1 ms"
t_end = "0.01 s"

[[body]]
name = "strip"
type = "ffr"
source = "strip.toml"

[[body]]
name = "crank"
type = "rigid"
mass = "0.1 kg"
inertia = [1e-5, 1e-5, 1e-5]
position = [0.2, 0, 0]

[[frame]]
name = "wall"
body = "ground"

[[frame]]
name = "end"
body = "strip"
NODE

[[joint]]
name = "clamp"
type = "fixed"
a = "wall"
b = "strip"

[[joint]]
name = "pin"
type = "revolute"
a = "end"
b = "crank"
"#;

const STRIP: &str = r#"
[body]
name = "strip"
[body.mesh]
type = "box"
size = [0.2, 0.02, 0.01]
divisions = [4, 1, 1]
element = "hex8"
material = { e = 70e9, nu = 0.3, rho = 2700.0 }
[body.boundary]
fixed = ["xmin"]
[[body.boundary.rigid]]
name = "tip"
nodes = "xmax"
[body.reduction]
modes = 2
"#;

fn stderr_of(command: &str, model: &Path, out: &Path) -> (bool, String) {
    let mut c = Command::new(env!("CARGO_BIN_EXE_flexmbs"));
    c.arg("-q").arg(command).arg(model);
    if command == "run" {
        c.arg("-o").arg(out);
    }
    let o = c.output().unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn check_and_run_refuse_a_hinge_at_a_solid_node_alike() {
    let d = flexmbs_io::test_tools::scratch_dir("solid_node");
    let model = d.join("model.toml");
    std::fs::write(d.join("strip.toml"), STRIP).unwrap();
    std::fs::write(&model, MODEL.replace("NODE", "nearest = [0.2, 0, 0]")).unwrap();
    let (ok_check, check) = stderr_of("check", &model, &d.join("out"));
    let (ok_run, run) = stderr_of("run", &model, &d.join("out"));
    assert!(!ok_check && !ok_run);
    assert!(check.contains("model.toml:40: at `joint[1].a`: joint `pin` locks rotations at frame `end`, which sits on FE node"), "{check}");
    assert!(
        check.contains("`interface = \"tip\"` (at [0.2, 0.01, 0.005] m, "),
        "{check}"
    );
    assert!(!check.contains("::"), "no Rust item names: {check}");
    assert_eq!(check, run);
    // on the interface, with a ramp drive starting after t = 0: accepted, with the warning
    let text = MODEL
        .replace("NODE", "interface = \"tip\"")
        .replace("position = [0.2, 0, 0]", "position = [0.2, 0.01, 0.005]")
        + "angle = { type = \"ramp\", t0 = \"2 ms\", t1 = \"1 s\", v1 = \"1 deg\" }\n";
    std::fs::write(&model, text).unwrap();
    let (ok_check, check) = stderr_of("check", &model, &d.join("out"));
    let (ok_run, run) = stderr_of("run", &model, &d.join("out"));
    assert!(ok_check && ok_run, "{check}\n{run}");
    let warning = "warning: ";
    assert!(check.starts_with(warning), "{check}");
    assert!(
        check.contains("model.toml:42: at `joint[1].angle`: the prescribed motion of joint `pin` has a kink at t = 0.002 s"),
        "{check}"
    );
    assert_eq!(check.lines().count(), 1, "{check}");
    assert_eq!(check, run);
    let _ = std::fs::remove_dir_all(&d);
}

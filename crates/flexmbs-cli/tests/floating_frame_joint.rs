//! `flexmbs check` and `flexmbs run` refuse a joint at the floating frame of a free-free ffr body
//! with the same located message (both compile the model the same way).

use std::path::Path;
use std::process::Command;

/// A free-free beam (no supports) hinged to ground at its body frame.
const MODEL: &str = r#"
[model]
name = "free_free_hinge"

[solver]
type = "generalized-alpha"
h = "1 ms"
t_end = "0.01 s"

[[body]]
name = "bar"
type = "ffr"
source = "bar.toml"

[[frame]]
name = "pivot"
body = "ground"

[[joint]]
name = "hinge"
type = "revolute"
a = "pivot"
b = "bar"
"#;

const BAR: &str = r#"
[body]
name = "bar"
[body.mesh]
type = "beam"
start = [0.0, 0.0, 0.0]
end = [1.0, 0.0, 0.0]
elements = 6
section = { shape = "rectangle", width = 0.02, height = 0.01 }
material = { e = 210e9, nu = 0.3, rho = 7850.0 }
[body.reduction]
method = "modal"
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
fn check_and_run_refuse_a_joint_at_a_free_floating_frame_alike() {
    let d = flexmbs_io::test_tools::scratch_dir("floating");
    let model = d.join("model.toml");
    std::fs::write(&model, MODEL).unwrap();
    std::fs::write(d.join("bar.toml"), BAR).unwrap();
    let (ok_check, check) = stderr_of("check", &model, &d.join("out"));
    let (ok_run, run) = stderr_of("run", &model, &d.join("out"));
    assert!(!ok_check && !ok_run);
    let expected =
        "at `joint[0].b`: frame `bar` is fixed in the floating frame of ffr body `bar`, \
                    whose modes do not clamp it";
    assert!(check.contains(expected), "{check}");
    assert!(check.contains("model.toml:23:"), "{check}");
    assert_eq!(check, run);
}

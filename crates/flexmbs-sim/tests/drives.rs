//! Smooth drives in model files (issue 11 item 2): `step3`, `step5`, `cycloidal` and `move`
//! follow their closed forms end to end (parsing, units, the joint's drive row); non-smooth
//! position drives after t = 0 are warned about (kinks) or refused (jumps) with the jump named.

use crate::common;

use flexmbs_io::results::read_results;
use flexmbs_sim::run::{run_model, RunOptions};
use std::f64::consts::PI;

/// A rigid link (1 m, 1 kg) hinged at its end to ground, its angle about z prescribed.
const MODEL: &str = r#"
[model]
name = "driven_link"

[solver]
type = "generalized-alpha"
h = "1 ms"
t_end = "0.5 s"

[[body]]
name = "link"
type = "rigid"
mass = "1 kg"
inertia = [1e-4, 0.0834, 0.0834]
position = ["0.5 m", 0, 0]

[[frame]]
name = "hinge"
body = "ground"

[[frame]]
name = "top"
body = "link"
position = ["-0.5 m", 0, 0]

[[joint]]
name = "shoulder"
type = "revolute"
a = "hinge"
b = "top"
DRIVE

[output]
signals = ["link.orientation"]
animation = false
"#;

fn model(dir: &std::path::Path, drive: &str) -> std::path::PathBuf {
    let file = dir.join("model.toml");
    std::fs::write(&file, MODEL.replace("DRIVE", drive)).unwrap();
    file
}

/// The link's angle follows each smooth move from 0 at 0.1 s to 90 deg at 0.4 s (closed forms of
/// the normalized laws in `tau = (t - 0.1 s) / 0.3 s`, written out here), and none of them warns.
#[test]
fn smooth_angle_drives_follow_their_closed_forms() {
    let dir = common::work_dir("drives", "smooth");
    let cycloid = |x: f64| x - (2.0 * PI * x).sin() / (2.0 * PI);
    let laws: [(&str, &dyn Fn(f64) -> f64); 4] = [
        ("type = \"step3\"", &|x| 3.0 * x * x - 2.0 * x.powi(3)),
        ("type = \"step5\"", &|x| {
            6.0 * x.powi(5) - 15.0 * x.powi(4) + 10.0 * x.powi(3)
        }),
        ("type = \"cycloidal\"", &cycloid),
        // ramp 1/2: velocity rises along a cycloid to 2 (per unit move and time) at tau = 1/2
        ("type = \"move\", ramp = 0.5", &|x| {
            let p = |y: f64| y * y / 2.0 + ((2.0 * PI * y).cos() - 1.0) / (4.0 * PI * PI);
            if x <= 0.5 {
                2.0 * 0.5 * p(x / 0.5)
            } else {
                1.0 - 2.0 * 0.5 * p((1.0 - x) / 0.5)
            }
        }),
    ];
    for (kind, s) in laws {
        let file = model(
            &dir,
            &format!("angle = {{ {kind}, t0 = \"0.1 s\", t1 = \"400 ms\", v1 = \"90 deg\" }}"),
        );
        let cm = flexmbs_sim::load_model(&file).unwrap();
        assert_eq!(cm.warnings, Vec::<String>::new(), "{kind}");
        let out = dir.join("run");
        run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
        let r = read_results(&out.join("results.h5")).unwrap();
        let t = r.time.clone();
        let phi = r.series("link.orientation.z").unwrap();
        let mut worst: f64 = 0.0;
        for (t, phi) in t.iter().zip(phi) {
            let tau = ((t - 0.1) / 0.3).clamp(0.0, 1.0);
            worst = worst.max((phi - PI / 2.0 * s(tau)).abs());
        }
        eprintln!("{kind}: largest angle error {worst:e} rad");
        assert!(worst < 1e-9, "{kind}: {worst:e}");
    }
}

#[test]
fn ramp_angle_after_t0_is_warned_with_the_rate_jump() {
    let dir = common::work_dir("drives", "ramp");
    let file = model(
        &dir,
        "angle = { type = \"ramp\", t0 = \"0.1 s\", t1 = \"0.3 s\", v1 = \"90 deg\" }",
    );
    let cm = flexmbs_sim::load_model(&file).unwrap();
    assert_eq!(cm.warnings.len(), 2, "{:?}", cm.warnings);
    // the rate jumps by (pi/2) / 0.2 s = 7.853982 rad/s at 0.1 s, back at 0.3 s
    let expect = |t: &str, jump: &str| {
        format!(
            "model.toml:31: at `joint[0].angle`: the prescribed motion of joint `shoulder` has a \
             kink at t = {t} s: its rate jumps by {jump} rad/s, so its acceleration is infinite \
             there (an impulse: the joint's reaction spikes and the bodies' velocities jump); use a \
             smooth move instead: `type = \"step5\"` (quintic), `\"cycloidal\"` or `\"move\"`"
        )
    };
    assert!(
        cm.warnings[0].contains(&expect("0.1", "7.853982e0")),
        "{}",
        cm.warnings[0]
    );
    assert!(
        cm.warnings[1].contains(&expect("0.3", "-7.853982e0")),
        "{}",
        cm.warnings[1]
    );
    // kinks after t_end are not warned about (at t = 0 the initial-velocity check applies)
    let file = model(
        &dir,
        "angle = { type = \"ramp\", t0 = \"0.6 s\", t1 = \"2 s\", v1 = \"90 deg\" }",
    );
    let cm = flexmbs_sim::load_model(&file).unwrap();
    assert_eq!(cm.warnings, Vec::<String>::new());
}

#[test]
fn angle_step_is_refused_and_rate_step_is_warned() {
    let dir = common::work_dir("drives", "step");
    let file = model(
        &dir,
        "angle = { type = \"step\", t0 = \"0.2 s\", after = \"10 deg\" }",
    );
    let e = flexmbs_sim::load_model(&file).unwrap_err().to_string();
    assert!(
        e.contains(
            "model.toml:31: at `joint[0].angle`: the prescribed motion of joint `shoulder` jumps \
             by 1.745329e-1 rad at t = 0.2 s: a position cannot jump (infinite velocity); use a \
             smooth move instead"
        ),
        "{e}"
    );
    let file = model(
        &dir,
        "angular_velocity = { type = \"step\", t0 = \"0.2 s\", after = \"1 rad/s\" }",
    );
    let cm = flexmbs_sim::load_model(&file).unwrap();
    assert_eq!(cm.warnings.len(), 1);
    assert!(
        cm.warnings[0].contains(
            "at `joint[0].angular_velocity`: the prescribed angular velocity of joint `shoulder` \
             jumps by 1.000000e0 rad/s at t = 0.2 s, so its angular acceleration is infinite there"
        ),
        "{}",
        cm.warnings[0]
    );
    // a bad ramp fraction is an error at its key
    let file = model(
        &dir,
        "angle = { type = \"move\", t1 = \"0.3 s\", v1 = 1, ramp = 0.7 }",
    );
    let e = flexmbs_sim::load_model(&file).unwrap_err().to_string();
    assert!(
        e.contains("at `joint[0].angle.ramp`: the ramp fraction must be in (0, 0.5], got 0.7"),
        "{e}"
    );
}

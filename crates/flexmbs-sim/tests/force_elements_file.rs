//! `[[force]]` in the model file: `examples/mbs/servo_arm.toml` (PID servo, joint spring,
//! friction, bushing) settles where the hand calculation of its header says, and bad values are
//! refused with the key path and line.

use flexmbs_io::results::{read_results, RunStatus};
use flexmbs_sim::run::{run_model, RunOptions};
use flexmbs_sim::{compile_model, SimError};
use std::path::{Path, PathBuf};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/mbs")
        .join(name)
}

/// At 6 s the arm stands at 45 deg (PI servo: no steady error) to 1e-5 rad, and the servo's
/// drive torque (signal `servo.output`) is the static torque of gravity on arm and payload plus
/// the spring, (1.5 x 0.4 + 0.2 x 0.8) 9.81 cos(45 deg) + 2 pi/4 = 6.843 N m, to 1e-4 relative
/// (the bushing's sag moves the payload by 2e-5 m, 2.5e-5 of its lever arm).
#[test]
fn servo_arm_example_settles_at_the_reference_with_the_static_torque() {
    let cm = flexmbs_sim::load_model(&example("servo_arm.toml")).unwrap();
    let out = flexmbs_io::test_tools::scratch_dir("force");
    let _ = std::fs::remove_dir_all(&out);
    let summary = run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    assert_eq!(summary.status, RunStatus::Completed);
    let r = read_results(&out.join("results.h5")).unwrap();
    let torque = *r.series("servo.output.value").unwrap().last().unwrap();
    let angle = *r.series("arm.orientation.z").unwrap().last().unwrap();
    let quarter = std::f64::consts::FRAC_PI_4;
    let expected = (1.5 * 0.4 + 0.2 * 0.8) * 9.81 * quarter.cos() + 2.0 * quarter;
    println!("angle {angle}, torque {torque} (expected {expected})");
    assert!((angle - quarter).abs() < 1e-5, "angle {angle}");
    assert!(
        (torque - expected).abs() < 1e-4 * expected,
        "torque {torque}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// Bad `[[force]]` entries: the error names the key path and its line.
#[test]
fn bad_force_entries_are_located() {
    let base = std::fs::read_to_string(example("servo_arm.toml")).unwrap();
    let cases = [
        (
            "kp = \"300 N*m/rad\"",
            "kp = -3",
            "force[0].kp",
            "must be >= 0",
        ),
        (
            "joint = \"shoulder\"\nreference",
            "joint = \"elbow\"\nreference",
            "force[0].joint",
            "unknown joint `elbow`",
        ),
        (
            "stiffness = \"2 N*m/rad\"",
            "stiffness = \"2 N/m\"",
            "force[1].stiffness",
            "rotational stiffness",
        ),
        (
            "slip_velocity = \"0.01 rad/s\"",
            "slip_velocity = 0",
            "force[2].slip_velocity",
            "must be > 0",
        ),
        (
            "rotational_stiffness = [50, 50, 50]",
            "rotational_stiffness = [50, -50, 50]",
            "force[3].rotational_stiffness",
            "must be >= 0",
        ),
        (
            "name = \"bearing\"\ntype = \"friction\"",
            "name = \"bearing\"\ntype = \"friction\"\nkp = 3",
            "force[2].kp",
            "not used by a friction",
        ),
        (
            "kd = \"10 N*m*s/rad\"",
            "kd = \"10 N*m*s/rad\"\nintegral_lag = 0",
            "force[0].integral_lag",
            "must be > 0",
        ),
    ];
    for (from, to, path, message) in cases {
        assert!(base.contains(from), "{from}");
        let text = base.replacen(from, to, 1);
        let err = compile_model(&text, &example("servo_arm.toml")).unwrap_err();
        let SimError::Model {
            line,
            path: p,
            message: m,
            ..
        } = &err
        else {
            panic!("{err}")
        };
        println!("{err}");
        assert_eq!(p, path, "{err}");
        assert!(m.contains(message), "{err}");
        // the line of the key in the edited text
        let key = format!("{} =", path.rsplit('.').next().unwrap());
        let start = text.find(to).unwrap();
        let offset = to.lines().position(|l| l.starts_with(&key)).unwrap();
        let expected_line = text[..start].lines().count() + offset + 1;
        assert_eq!(*line, expected_line, "{err}");
    }
}

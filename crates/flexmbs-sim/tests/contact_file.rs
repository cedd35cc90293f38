//! Contacts in model files: the bouncing-ball example runs with the `moreau` solver and meets
//! the analytic rebound height; bad contact tables give located errors.

use flexmbs_core::integrator::{drive, MoreauSscStepper, Stepper};
use flexmbs_core::Workspace;
use flexmbs_sim::{compile_model, SimError, SolverConfig};
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

fn example() -> (PathBuf, String) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mbs/bouncing_ball.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    (path, text)
}

/// First rebound apex of the ball centre: `C_R^2 h0 + r = 0.64 + 0.1 m` (the floor is
/// horizontal, so friction does not change the normal motion).
#[test]
fn bouncing_ball_example_rebounds_to_cr_squared() {
    let (path, text) = example();
    let cm = compile_model(&text, &path).unwrap();
    assert_eq!(cm.model.contacts.len(), 1);
    let SolverConfig::Moreau {
        adaptive: Some(settings),
        ..
    } = cm.solver
    else {
        panic!("{:?}", cm.solver)
    };
    let mut s = cm.initial.clone();
    let mut ws = Workspace::new(&cm.model);
    let mut st = MoreauSscStepper::new(settings);
    st.initialize(&cm.model, &mut s, &mut ws).unwrap();
    let (mut apex, mut bounced, mut spin) = (f64::NEG_INFINITY, false, 0.0);
    let control = st.control();
    drive(&mut st, &cm.model, &mut s, &mut ws, control, 1.0, |s, _| {
        let (z, vz) = (s.q[2], s.u[2]);
        bounced |= vz > 0.0;
        if bounced && vz <= 0.0 && apex == f64::NEG_INFINITY {
            apex = z + vz * vz / (2.0 * 9.81);
            spin = s.u[4]; // body-frame angular velocity about y
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    })
    .unwrap();
    assert!((apex - 0.74).abs() < 1e-5, "apex {apex}");
    // rolling forward (+x velocity) spins the ball about +y
    assert!(spin > 0.0, "spin {spin}");
}

/// (replace this, by this, expected key path, message fragment)
const CASES: &[(&str, &str, &str, &str)] = &[
    (
        "frame = \"floor\" }",
        "frame = \"flor\" }",
        "contact[0].b.frame",
        "unknown frame `flor`",
    ),
    (
        ", radius = \"0.1 m\" }",
        " }",
        "contact[0].a",
        "a sphere contour needs `radius`",
    ),
    (
        "restitution = 0.8",
        "restitution = 1.8",
        "contact[0].restitution",
        "must be in [0, 1]",
    ),
    (
        "restitution = 0.8",
        "restitution = 0.8\nstiffness = \"1e5 N/m\"",
        "contact[0].stiffness",
        "`stiffness` is not used by",
    ),
    ("\nmu = 0.3\n", "\n", "contact[0]", "friction needs `mu`"),
    (
        "type = \"plane\", frame = \"floor\"",
        "type = \"circle\", frame = \"floor\", radius = \"1 m\"",
        "contact[0]",
        "no contact kinematics for a Sphere and a Circle",
    ),
    (
        "type = \"moreau\"",
        "type = \"generalized-alpha\"",
        "contact[0].normal",
        "a set-valued law (`unilateral`, `bilateral`) needs `solver.type = \"moreau\"`",
    ),
];

#[test]
fn contact_errors_are_located() {
    let (path, text) = example();
    for (from, to, key, fragment) in CASES {
        assert!(text.contains(from), "{from}");
        let mut bad = text.replacen(from, to, 1);
        if *to == "type = \"generalized-alpha\"" {
            bad = bad.replacen("adaptive = {", "rho_inf = 0.9\nadaptive = {", 1);
        }
        let err = match compile_model(&bad, &path) {
            Ok(_) => panic!("case `{to}` compiled"),
            Err(e) => e,
        };
        let msg = err.to_string();
        let SimError::Model { path: p, line, .. } = &err else {
            panic!("case `{to}`: not a model error: {msg}");
        };
        assert_eq!(p, key, "case `{to}`: {msg}");
        assert!(*line > 0, "case `{to}`: no line: {msg}");
        assert!(msg.contains(fragment), "case `{to}`: {msg}");
    }
}

/// The penalty-ball example (adaptive `generalized-alpha`, regularized contact with damping
/// ratio 0.1 and regularized friction): the first rebound apex is `e^2 h0` above the floor with
/// the restitution `e = 0.74408` of the damped linear oscillator that cannot pull (within 1 %:
/// gravity during the 3 ms contact lowers the exact apex by 0.29 %; the adaptive run's own
/// error is 5e-4), and friction spins the ball up.
#[test]
fn penalty_ball_example_runs_in_generalized_alpha() {
    use flexmbs_core::integrator::{GenAlpha, GenAlphaStepper};
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mbs/penalty_ball.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let cm = compile_model(&text, &path).unwrap();
    let SolverConfig::GenAlpha {
        settings,
        h,
        adaptive: adaptive @ Some(_),
        ..
    } = cm.solver
    else {
        panic!("{:?}", cm.solver)
    };
    let mut s = cm.initial.clone();
    let mut ws = Workspace::new(&cm.model);
    let mut st = GenAlphaStepper::new(GenAlpha::new(settings).unwrap(), adaptive);
    st.initialize(&cm.model, &mut s, &mut ws).unwrap();
    let (mut apex, mut bounced, mut spin) = (f64::NEG_INFINITY, false, 0.0);
    let control = st.control(h);
    drive(&mut st, &cm.model, &mut s, &mut ws, control, 1.0, |s, _| {
        let (z, vz) = (s.q[2], s.u[2]);
        bounced |= vz > 0.0 && s.contacts[0].gap > 0.0;
        if bounced && vz <= 0.0 && apex == f64::NEG_INFINITY {
            apex = z + vz * vz / (2.0 * 9.81);
            spin = s.u[4];
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    })
    .unwrap();
    let e: f64 = 0.744_079_397_721_78;
    let expected = 0.1 + e * e * 0.5;
    println!("penalty ball: apex {apex:.5} m, expected {expected:.5} m");
    assert!(
        (apex - expected).abs() < 0.01 * (expected - 0.1),
        "apex {apex}"
    );
    assert!(spin > 0.0, "spin {spin}");
}

/// Contacts need `moreau` or (regularized laws) `generalized-alpha` or `statics`: DOPRI5 is
/// refused at the solver type; a static start of the penalty ball (at rest) compiles.
#[test]
fn penalty_contact_solver_errors_are_located() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mbs/penalty_ball.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let dopri5 = text
        .replacen("type = \"generalized-alpha\"", "type = \"dopri5\"", 1)
        .replacen(
            "adaptive = { rtol = 1e-8, atol = 1e-8, h_max = \"5 ms\" }\n",
            "",
            1,
        );
    assert!(!dopri5.contains("adaptive = "));
    let err = compile_model(&dopri5, &path).unwrap_err();
    let msg = err.to_string();
    let SimError::Model { path: p, .. } = &err else {
        panic!("not a model error: {msg}");
    };
    assert_eq!(p, "solver.type", "{msg}");
    let static_start = text
        .replacen(
            "t_end = \"1 s\"",
            "t_end = \"1 s\"\ninitial = \"static\"",
            1,
        )
        .replacen("velocity = [\"1 m/s\", 0, 0]\n", "", 1);
    assert!(static_start.contains("initial = \"static\""));
    let cm = compile_model(&static_start, &path).unwrap();
    assert!(cm.initial_static);
}

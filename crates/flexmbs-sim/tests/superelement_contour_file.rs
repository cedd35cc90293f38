//! Neutral contours on beam superelements in model files: a ball kept on the axis of one
//! superelement of a clamped `superelement_beam` (`body = "arm.s1"`, its FE nodes `1 ... 5`)
//! slides along it with the guide rows at round-off, and bad contours are refused with located
//! errors.

use flexmbs_core::integrator::{drive, MoreauSscSettings, MoreauSscStepper, Stepper};
use flexmbs_core::Workspace;
use flexmbs_sim::{compile_model, SimError};
use std::ops::ControlFlow;
use std::path::PathBuf;

const MODEL: &str = r#"
[model]
name = "se_guided_ball"
[solver]
type = "moreau"
t_end = "0.01 s"
h = "1e-4 s"
adaptive = { h_max = "1 ms" }
[[body]]
name = "arm"
type = "superelement_beam"
material = { e = 70e7, nu = 0.3, rho = 2700.0 }
section = { shape = "tube", outer_radius = 0.01, wall = 0.001 }
direction = [1, 0, 0]
length = "0.6 m"
segments = 3
elements = 4
fixed = ["i0"]
[[body]]
name = "ball"
type = "rigid"
mass = "0.2 kg"
inertia = [1e-4, 1e-4, 1e-4]
position = ["300 mm", 0, 0]
velocity = ["0.2 m/s", "-0.05 m/s", 0]
[[contact]]
name = "guide"
a = { type = "curve", body = "arm.s1", nodes = [1, 2, 3, 4, 5], normal = [0, 1, 0] }
b = { type = "point", frame = "ball" }
normal = "bilateral"
"#;

fn path() -> PathBuf {
    let dir = flexmbs_io::test_tools::scratch_dir("se-contour");
    dir.join("model.toml")
}

#[test]
fn ball_slides_on_a_superelement_axis_from_a_model_file() {
    let cm = compile_model(MODEL, &path()).unwrap();
    let model = &cm.model;
    assert_eq!(model.guides.len(), 1);
    let mut s = cm.initial.clone();
    let mut ws = Workspace::new(model);
    let mut st = MoreauSscStepper::new(MoreauSscSettings {
        h_max: 1e-3,
        ..Default::default()
    });
    let control = st.control();
    st.initialize(model, &mut s, &mut ws).unwrap();
    let mut g_max: f64 = 0.0;
    let mut steps = 0;
    drive(
        &mut st,
        model,
        &mut s,
        &mut ws,
        control,
        0.01,
        |_, stats| {
            steps += 1;
            g_max = g_max.max(stats.g_max);
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    let ball = cm.bodies.iter().position(|b| b.name == "ball").unwrap();
    let q = model.body_q(cm.bodies[ball].id, &s.q);
    println!(
        "ball at ({:.6}, {:.3e}, {:.3e}), g_max {g_max:.2e}, {steps} steps",
        q[0], q[1], q[2]
    );
    // 0.2 m/s for 0.01 s along the axis; across it the ball shares its momentum with the arm
    assert!((q[0] - 0.302).abs() < 2e-4, "x = {}", q[0]);
    assert!(q[2].abs() < 1e-9, "z = {}", q[2]);
    assert!(g_max < 1e-10, "constraint drift {g_max}");
    assert!(s.lambda.iter().any(|l| *l != 0.0));
}

/// (replace, with, expected key path, message fragment)
const CASES: &[(&str, &str, &str, &str)] = &[
    (
        r#"body = "arm.s1""#,
        r#"body = "ball""#,
        "contact[0].a.body",
        "no neutral contours",
    ),
    (
        r#"body = "arm.s1""#,
        r#"body = "arm""#,
        "contact[0].a.body",
        "unknown body `arm`",
    ),
    (
        r#"nodes = [1, 2, 3, 4, 5]"#,
        r#"nodes = [1, 2, 3, 4, 9]"#,
        "contact[0].a.nodes",
        "not a node of the body (ids 1 ... 5)",
    ),
];

#[test]
fn bad_superelement_contours_are_refused_with_their_key_path() {
    for (from, to, key, fragment) in CASES {
        assert!(MODEL.contains(from), "{from}");
        let bad = MODEL.replacen(from, to, 1);
        let err = match compile_model(&bad, &path()) {
            Ok(_) => panic!("case `{to}` compiled"),
            Err(e) => e,
        };
        let msg = err.to_string();
        let SimError::Model { path: p, .. } = &err else {
            panic!("case `{to}`: not a model error: {msg}");
        };
        assert_eq!(p, key, "case `{to}`: {msg}");
        assert!(msg.contains(fragment), "case `{to}`: {msg}");
    }
}

/// An FE-file superelement (the free hex20 bar of `tests/data/superelement_fe/bar_free.toml`,
/// 1 m x 20 mm x 20 mm from the FE origin, Craig-Bampton to its end faces with 4 internal modes)
/// carries a `curve` along the middle of its top face (`through` in FE coordinates; 11 hex20
/// corner nodes): at t = 0 a point 30 mm above the face's centre has gap 0.03 m along +y
/// (1e-12), the contact point under it. (The face itself has 3 node stations across: too few
/// for a cubic surface.)
#[test]
fn fe_superelement_carries_a_curve_contour() {
    let text = r#"
[model]
name = "fe_se_surface"
[solver]
type = "moreau"
t_end = "1 ms"
h = "1e-4 s"
[[body]]
name = "bar"
type = "superelement"
source = "bar_free.toml"
[[body]]
name = "ball"
type = "rigid"
mass = "0.1 kg"
inertia = [1e-5, 1e-5, 1e-5]
position = [0.5, 0.05, 0.01]
[[contact]]
name = "touch"
a = { type = "curve", body = "bar", through = [[0, 0.02, 0.01], [1, 0.02, 0.01]] }
b = { type = "point", frame = "ball" }
normal = "unilateral"
"#;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/superelement_fe");
    let cm = compile_model(text, &dir.join("model.toml")).unwrap_or_else(|e| panic!("{e}"));
    let model = &cm.model;
    let s = cm.initial.clone();
    let mut ws = Workspace::new(model);
    flexmbs_core::system::evaluate(model, &s.q, &s.u, &mut ws.sys).unwrap();
    let mut work = flexmbs_core::contact::ContactWork::new(model);
    let geo = model.contacts[0].geometry(model, &ws.sys.frames, &ws.sys.eval, &mut work.sides[0]);
    println!(
        "gap {:.15}, normal {:?}, point {:?}",
        geo.gap,
        geo.normal.as_slice(),
        geo.point_a.as_slice()
    );
    assert!((geo.gap - 0.03).abs() < 1e-12, "gap {}", geo.gap);
    assert!((geo.normal - nalgebra::Vector3::y()).norm() < 1e-12);
    let want = nalgebra::Vector3::new(0.5, 0.02, 0.01);
    assert!((geo.point_a - want).norm() < 1e-12, "{}", geo.point_a);
}

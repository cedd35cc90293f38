//! A point kept on a curve in model files (`[[contact]] normal = "bilateral"` on a `curve`): the
//! contact becomes a guide with 2 (or, with `rotations = true`, 5) constraint rows, the ball stays
//! on the beam's axis found by `through`, its multipliers are named, and bad combinations are
//! refused at compile time with located errors.

use crate::common::CONTACT_BEAM as BEAM;
use flexmbs_core::integrator::{drive, MoreauSscSettings, MoreauSscStepper, Stepper};
use flexmbs_core::Workspace;
use flexmbs_sim::{compile_model, SimError};
use std::ops::ControlFlow;
use std::path::PathBuf;

const MODEL: &str = r#"
[model]
name = "guided_ball"
[solver]
type = "moreau"
t_end = "0.05 s"
h = "1e-4 s"
adaptive = { h_max = "1 ms" }
[[body]]
name = "beam"
type = "ffr"
source = "beam.toml"
inertia = "consistent"
[[body]]
name = "ball"
type = "rigid"
mass = "0.2 kg"
inertia = [1e-4, 1e-4, 1e-4]
position = ["100 mm", "20 mm", "20 mm"]
velocity = ["0.5 m/s", "-0.05 m/s", 0]
[[frame]]
name = "wall"
body = "ground"
[[joint]]
name = "clamp"
type = "fixed"
a = "wall"
b = "beam"
[[contact]]
name = "guide"
a = { type = "curve", body = "beam", through = [[0, 0.02, 0.02], [0.2, 0.02, 0.02]], normal = [0, 1, 0] }
b = { type = "point", frame = "ball" }
normal = "bilateral"
rotations = true
"#;

fn files() -> PathBuf {
    let dir = flexmbs_io::test_tools::scratch_dir("guide-file");
    std::fs::write(dir.join("beam.toml"), BEAM).unwrap();
    dir.join("model.toml")
}

#[test]
fn ball_slides_on_the_beam_axis_from_a_model_file() {
    let path = files();
    let cm = compile_model(MODEL, &path).unwrap();
    let model = &cm.model;
    assert_eq!(model.guides.len(), 1);
    assert_eq!(model.nc, 6 + 5, "clamp and guide rows");
    let (_, _, lambda) = flexmbs_sim::signals::coordinate_names(model, &cm.bodies);
    assert_eq!(
        &lambda[6..],
        ["guide.n1", "guide.n2", "guide.rt", "guide.rn1", "guide.rn2"]
    );
    let mut s = cm.initial.clone();
    let mut ws = Workspace::new(model);
    let mut st = MoreauSscStepper::new(MoreauSscSettings {
        h_max: 1e-3,
        ..Default::default()
    });
    let control = st.control();
    st.initialize(model, &mut s, &mut ws).unwrap();
    let mut g_max: f64 = 0.0;
    drive(
        &mut st,
        model,
        &mut s,
        &mut ws,
        control,
        0.05,
        |_, stats| {
            g_max = g_max.max(stats.g_max);
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    let ball = model.body_q(flexmbs_core::BodyId(1), &s.q);
    // 0.5 m/s for 0.05 s along the axis; the axis moved by the beam's deflection only
    assert!((ball[0] - 0.125).abs() < 1e-3, "x = {}", ball[0]);
    assert!((ball[2] - 0.02).abs() < 1e-3, "z = {}", ball[2]);
    assert!(g_max < 1e-10, "constraint drift {g_max}");
    // the ball's transverse velocity was shared with the beam: the guide pushed (n1 row)
    assert!(s.lambda[6].is_finite() && s.lambda[6] != 0.0);
}

/// (replace, with, expected key path, message fragment)
const CASES: &[(&str, &str, &str, &str)] = &[
    (
        r#"type = "curve", body = "beam", through"#,
        r#"type = "band", width = 0.01, body = "beam", through"#,
        "contact[0].a.type",
        "needs a `curve`",
    ),
    (
        r#"normal = [0, 1, 0] }"#,
        r#"normal = [0, 1, 0], radius = 0.01 }"#,
        "contact[0].a.radius",
        "no radius",
    ),
    (
        r#"normal = [0, 1, 0] }"#,
        r#"normal = [1, 0, 0] }"#,
        "contact[0]",
        "along the curve",
    ),
    (
        r#"b = { type = "point", frame = "ball" }"#,
        r#"b = { type = "plane", frame = "ball" }"#,
        "contact[0].b.type",
        "`point` or the centre of a `sphere`",
    ),
    (
        r#"rotations = true"#,
        r#"rotations = true
restitution = 0.5"#,
        "contact[0].restitution",
        "not used",
    ),
    (
        r#"body = "beam", through"#,
        r#"body = "ball", through"#,
        "contact[0].a.body",
        "rigid body",
    ),
    (
        r#"[0.2, 0.02, 0.02]]"#,
        r#"[0.2, 0.021, 0.02]]"#,
        "contact[0].a.through",
        "at least 4",
    ),
];

#[test]
fn bad_guides_are_refused_with_their_key_path() {
    let path = files();
    for (from, to, key, fragment) in CASES {
        assert!(MODEL.contains(from), "{from}");
        let bad = MODEL.replacen(from, to, 1);
        let err = match compile_model(&bad, &path) {
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
    // `rotations` on another contact
    let bad = MODEL.replacen(
        r#"a = { type = "curve", body = "beam", through = [[0, 0.02, 0.02], [0.2, 0.02, 0.02]], normal = [0, 1, 0] }"#,
        r#"a = { type = "sphere", frame = "wall", radius = 0.01 }"#,
        1,
    );
    let err = compile_model(&bad, &path).unwrap_err().to_string();
    assert!(err.contains("rotations"), "{err}");
}

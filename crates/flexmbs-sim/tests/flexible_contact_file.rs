//! Flexible contours in model files (`type = "surface"`, `"curve"`, `"band"`): a point mass
//! dropped with `C_R = 1` on the top face of a small clamped solid beam bounces off it without
//! gaining energy, the face's node grid is found from `face = "ymax"` and equals the explicit node
//! index matrix, and bad flexible contours are refused at compile time with located errors.

use crate::common::CONTACT_BEAM as BEAM;
use flexmbs_core::integrator::{drive, MoreauStepper, Stepper};
use flexmbs_core::Workspace;
use flexmbs_sim::{compile_model, SimError};
use std::ops::ControlFlow;
use std::path::PathBuf;

const MODEL: &str = r#"
[model]
name = "ball_on_beam"
[solver]
type = "moreau"
t_end = "0.04 s"
h = "1e-5 s"
[[body]]
name = "beam"
type = "ffr"
source = "beam.toml"
inertia = "consistent"
[[body]]
name = "mass"
type = "rigid"
mass = "0.2 kg"
inertia = [1e-6, 1e-6, 1e-6]
position = ["180 mm", "41 mm", "20 mm"]
velocity = [0, "-0.2 m/s", 0]
[[frame]]
name = "wall"
body = "ground"
[[joint]]
name = "clamp"
type = "fixed"
a = "wall"
b = "beam"
[[contact]]
name = "impact"
a = { type = "surface", body = "beam", face = "ymax" }
b = { type = "point", frame = "mass" }
normal = "unilateral"
restitution = 1.0
"#;

fn files() -> PathBuf {
    let dir = flexmbs_io::test_tools::scratch_dir("flexible-contact");
    std::fs::write(dir.join("beam.toml"), BEAM).unwrap();
    dir.join("model.toml")
}

#[test]
fn point_mass_bounces_off_a_flexible_surface_from_a_model_file() {
    let path = files();
    let cm = compile_model(MODEL, &path).unwrap();
    let model = &cm.model;
    let mut s = cm.initial.clone();
    let mut ws = Workspace::new(model);
    let mut st = MoreauStepper::new(Default::default());
    st.initialize(model, &mut s, &mut ws).unwrap();
    let mut ws_e = Workspace::new(model);
    let e0 = flexmbs_core::integrator::monitor(model, &s, &mut ws_e)
        .0
        .total();
    let (mut gain, mut impacts, mut y_min) = (f64::NEG_INFINITY, 0, f64::INFINITY);
    let mass = model.body_id("mass").unwrap();
    let control = st.control(1e-5);
    drive(&mut st, model, &mut s, &mut ws, control, 0.04, |s, _| {
        let e = flexmbs_core::integrator::monitor(model, s, &mut ws_e)
            .0
            .total();
        gain = gain.max((e - e0) / e0);
        impacts += usize::from(s.contacts[0].impulse[0] > 0.0);
        y_min = y_min.min(model.body_q(mass, &s.q)[1]);
        ControlFlow::Continue(())
    })
    .unwrap();
    let vy = model.body_u(mass, &s.u)[1];
    eprintln!("impacts {impacts}, y_min {y_min}, v_y end {vy}, energy gain {gain:e}");
    assert!(impacts > 0, "no impact");
    // the mass went below the undeformed face (the beam deflected) and came back up
    assert!(y_min < 0.04 && vy > 0.0, "y_min {y_min}, v_y {vy}");
    // Moreau with C_R = 1: no energy gain beyond 0.1 % (seed §4.2)
    assert!(gain <= 1e-3, "energy gain {gain}");
}

/// `(replace, by, key path, message fragment)` applied to [`MODEL`].
const CASES: &[(&str, &str, &str, &str)] = &[
    (
        "face = \"ymax\"",
        "face = \"top\"",
        "contact[0].a.face",
        "unknown face `top`",
    ),
    (
        "body = \"beam\", face",
        "body = \"mass\", face",
        "contact[0].a.body",
        "rigid body",
    ),
    (
        "body = \"beam\", face",
        "body = \"wheel\", face",
        "contact[0].a.body",
        "unknown body `wheel`",
    ),
    (
        "face = \"ymax\"",
        "nodes = [[1, 2], [3, 99999]]",
        "contact[0].a.nodes",
        "node 99999 is not a node of the body",
    ),
    (
        "face = \"ymax\"",
        "nodes = [[1, 2, 3], [4, 5]]",
        "contact[0].a.nodes",
        "row 1 has 2 nodes",
    ),
    (
        "face = \"ymax\"",
        "nodes = [[1, 2], [3, 1]]",
        "contact[0].a.nodes",
        "appears twice",
    ),
    (
        "face = \"ymax\"",
        "face = \"ymax\", radius = \"1 mm\"",
        "contact[0].a.radius",
        "not used by a surface contour",
    ),
    (
        "face = \"ymax\"",
        "face = \"ymax\", frame = \"wall\"",
        "contact[0].a.frame",
        "give `body`, not `frame`",
    ),
    (
        "type = \"surface\", body = \"beam\", face = \"ymax\"",
        "type = \"curve\", body = \"beam\", nodes = [1, 2]",
        "contact[0].a.nodes",
        "degree",
    ),
    (
        "type = \"surface\", body = \"beam\", face = \"ymax\"",
        "type = \"band\", body = \"beam\", nodes = [1, 2, 3, 4, 5]",
        "contact[0].a",
        "width",
    ),
    (
        "b = { type = \"point\", frame = \"mass\" }",
        "b = { type = \"plane\", frame = \"wall\" }",
        "contact[0]",
        "no contact kinematics",
    ),
];

#[test]
fn bad_flexible_contours_are_refused_with_their_key_path() {
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
}

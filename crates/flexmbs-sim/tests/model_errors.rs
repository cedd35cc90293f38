//! Every kind of model-file error names the key path and the line (table-driven over small bad
//! variants of one valid model).

use flexmbs_sim::{compile_model, SimError};
use std::path::{Path, PathBuf};

const BASE: &str = r#"
[model]
name = "pendulum"
gravity = [0, 0, "-9.81 m/s^2"]

[solver]
type = "generalized-alpha"
h = "1 ms"
t_end = "0.01 s"

[[body]]
name = "arm"
type = "rigid"
mass = "1 kg"
inertia = [0.01, 0.01, 0.001]
position = [0, 0, -0.5]

[[body]]
name = "rod"
type = "ffr"
source = "parts/rod.toml"
modes = [1, 2]
position = [0, 0, -1.0]

[[frame]]
name = "hinge"
body = "ground"

[[frame]]
name = "top"
body = "arm"
position = [0, 0, "500 mm"]

[[joint]]
name = "pin"
type = "revolute"
a = "hinge"
b = "top"

[[load]]
type = "force"
frame = "arm"
vector = ["1 N", 0, 0]
time = { type = "ramp", t1 = "5 ms", v1 = 1 }

[output]
signals = ["arm.position", "pin.reaction"]
"#;

/// The model file path: next to the example FE parts so that `parts/rod.toml` resolves.
fn model_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mbs/test_model.toml")
}

#[test]
fn base_model_compiles() {
    let cm = compile_model(BASE, &model_path()).unwrap();
    assert_eq!(cm.bodies.len(), 2);
    // rigid body: 6 coordinates; FFR rod with 2 modes and Cardan angles: 3 + 3 + 2
    assert_eq!(cm.model.nq, 6 + 8);
    assert_eq!(cm.model.nc, 5);
    assert_eq!(cm.signals.len(), 2);
    assert_eq!(cm.initial.q[2], -0.5);
}

/// (replace this, by this, expected key path, text on the expected line, message fragment)
const CASES: &[(&str, &str, &str, &str, &str)] = &[
    (
        "t_end = \"0.01 s\"",
        "t_end = \"1e9 s\"",
        "output.every",
        "[output]",
        "output rows (",
    ),
    (
        "t_end = \"0.01 s\"",
        "t_end = \"100 s\"",
        "output.animation_every",
        "[output]",
        "animation frames (one .vtu file each",
    ),
    (
        "[[joint]]",
        "[[frame]]\nname = \"far\"\nbody = \"rod\"\nnearest = [\"100 m\", 0, 0]\n\n[[joint]]",
        "frame[2].nearest",
        "nearest = [\"100 m\", 0, 0]",
        "more than 0.05 of the body size",
    ),
    // a joint at a frame fixed in the floating frame of the free-free rod (its body frame, or a
    // `position` frame) constrains a mean-axis frame, not material: refused
    (
        "b = \"top\"",
        "b = \"rod\"",
        "joint[0].b",
        "b = \"rod\"",
        "frame `rod` is fixed in the floating frame of ffr body `rod`, whose modes do not clamp it",
    ),
    (
        "[[joint]]",
        "[[frame]]\nname = \"rod_end\"\nbody = \"rod\"\nposition = [\"0.3 m\", 0, 0]\n\n[[joint]]\nname = \"pin2\"\ntype = \"spherical\"\na = \"rod_end\"\nb = \"top\"\n\n[[joint]]",
        "joint[0].a",
        "a = \"rod_end\"",
        "a mean-axis frame, not a material point",
    ),
    (
        "b = \"top\"",
        "b = \"hinge\"",
        "joint[0].b",
        "b = \"hinge\"",
        "frames `a` and `b` belong to the same body (or both to ground)",
    ),
    (
        "position = [0, 0, \"500 mm\"]",
        "position = [0, 0, \"510 mm\"]",
        "joint[0]",
        "[[joint]]",
        "joint `pin` is not assembled in the initial state: row tz is off by",
    ),
    (
        "position = [0, 0, -0.5]",
        "position = [0, 0, -0.5]\nvelocity = [0, \"1 m/s\", 0]",
        "joint[0]",
        "[[joint]]",
        "joint `pin`: the initial velocities violate row ty by",
    ),
    (
        "inertia = [0.01, 0.01, 0.001]",
        "inertia = [0.01, 0.001, 0.02]",
        "body[0].inertia",
        "inertia = [0.01, 0.001, 0.02]",
        "triangle inequality",
    ),
    (
        "modes = [1, 2]",
        "modes = [1, 2]\ngeometric_stiffening = true",
        "body[1].geometric_stiffening",
        "geometric_stiffening = true",
        "geometric stiffening needs supports (fixed nodes in the FE model)",
    ),
    // `.fmb.h5` source with geometric_stiffening: the file's stored K_G is used; a file without
    // it is a located error (tests/stiffening_file.rs)
    (
        "source = \"parts/rod.toml\"",
        "source = \"parts\"\ngeometric_stiffening = true",
        "body[1].geometric_stiffening",
        "geometric_stiffening = true",
        "seed folder has no FE",
    ),
    (
        "source = \"parts/rod.toml\"",
        "source = \"parts\"\ninertia = \"consistent\"",
        "body[1].inertia",
        "inertia = \"consistent\"",
        "seed folder has no FE mass matrix",
    ),
    (
        "modes = [1, 2]",
        "modes = [1, 2]\ninertia = \"consistent\"",
        "body[1].inertia",
        "inertia = \"consistent\"",
        "needs a solid mesh",
    ),
    (
        "modes = [1, 2]",
        "modes = [1, 2]\ninertia = [1, 1, 1]",
        "body[1].inertia",
        "inertia = [1, 1, 1]",
        "principal moments are for rigid bodies",
    ),
    (
        "modes = [1, 2]",
        "modes = [1, 2]\ninertia = \"exact\"",
        "body[1].inertia",
        "inertia = \"exact\"",
        "unknown mass model",
    ),
    // `.fmb.h5` source with rotary_inertia = true: the file's stored inertias are used; a file
    // without them is a located error (tests/rotary_file.rs)
    (
        "source = \"parts/rod.toml\"",
        "source = \"parts\"\nrotary_inertia = true",
        "body[1].rotary_inertia",
        "rotary_inertia = true",
        "need an FE model file (.toml) with a beam mesh",
    ),
    (
        "inertia = [0.01, 0.01, 0.001]",
        "inertia = \"lumped\"",
        "body[0].inertia",
        "inertia = \"lumped\"",
        "mass models of ffr bodies",
    ),
    (
        "mass = \"1 kg\"",
        "mass = \"1 kg\"\ngeometric_stiffening = false",
        "body[0].geometric_stiffening",
        "geometric_stiffening = false",
        "not used by a rigid body",
    ),
    (
        "t_end = \"0.01 s\"",
        "t_end = \"0.01 s\"\nnewton = { modified = \"yes\" }",
        "solver.newton.modified",
        "modified = \"yes\"",
        "invalid type",
    ),
    (
        "mass = \"1 kg\"",
        "masss = \"1 kg\"",
        "body[0].masss",
        "masss",
        "unknown field",
    ),
    (
        "mass = \"1 kg\"",
        "mass = \"1 mm\"",
        "body[0].mass",
        "mass = \"1 mm\"",
        "length unit",
    ),
    (
        "mass = \"1 kg\"",
        "mass = \"1 furlong\"",
        "body[0].mass",
        "furlong",
        "unknown unit",
    ),
    (
        "mass = \"1 kg\"",
        "mass = 0",
        "body[0].mass",
        "mass = 0",
        "must be > 0",
    ),
    (
        "inertia = [0.01, 0.01, 0.001]",
        "inertia = [0.01, -0.01, 0.001]",
        "body[0].inertia",
        "inertia = [0.01, -0.01",
        "positive definite",
    ),
    (
        "b = \"top\"",
        "b = \"tpo\"",
        "joint[0].b",
        "b = \"tpo\"",
        "unknown frame `tpo` (frames: arm, hinge, rod, top)",
    ),
    (
        "frame = \"arm\"",
        "frame = \"leg\"",
        "load[0].frame",
        "frame = \"leg\"",
        "unknown frame `leg`",
    ),
    (
        "name = \"top\"",
        "name = \"arm\" # dup",
        "frame[1].name",
        "# dup",
        "duplicate name `arm`",
    ),
    (
        "modes = [1, 2]",
        "modes = [1, 9]",
        "body[1].modes[1]",
        "modes = [1, 9]",
        "mode 9 out of range: the body has modes 1..=4",
    ),
    (
        "modes = [1, 2]",
        "modes = 7",
        "body[1].modes",
        "modes = 7",
        "7 modes requested but the body has 4",
    ),
    (
        "type = \"generalized-alpha\"",
        "type = \"dopri5\"",
        "solver.type",
        "type = \"dopri5\"",
        "unconstrained models only",
    ),
    (
        "t_end = \"0.01 s\"",
        "t_end = \"0.01 s\"\nrho_inf = 1.0\nadaptive = { rtol = 1e-6 }",
        "solver.rho_inf",
        "rho_inf = 1.0",
        "needs numerical damping (rho_inf < 1)",
    ),
    (
        "type = \"generalized-alpha\"",
        "type = \"rk4\"",
        "solver.type",
        "type = \"rk4\"",
        "unknown variant",
    ),
    (
        "t_end = \"0.01 s\"",
        "t_end = \"-1 s\"",
        "solver.t_end",
        "t_end = \"-1 s\"",
        "must be > 0",
    ),
    (
        "t_end = \"0.01 s\"",
        "t_end = \"10 N\"",
        "solver.t_end",
        "t_end = \"10 N\"",
        "force unit",
    ),
    ("h = \"1 ms\"", "h = 0", "solver.h", "h = 0", "must be > 0"),
    (
        "t_end = \"0.01 s\"",
        "t_end = \"0.01 s\"\nnewton = { constraint_tol = 2.0 }",
        "solver.newton.constraint_tol",
        "constraint_tol = 2.0",
        "must be in (0, 1)",
    ),
    (
        "t1 = \"5 ms\"",
        "t1 = \"5 ms\", t3 = 2",
        "load[0].time.t3",
        "t3 = 2",
        "unknown field",
    ),
    (
        "t1 = \"5 ms\", v1 = 1",
        "t1 = \"5 ms\"",
        "load[0].time",
        "type = \"ramp\"",
        "needs `v1`",
    ),
    (
        "signals = [\"arm.position\"",
        "signals = [\"hand.position\"",
        "output.signals[0]",
        "hand.position",
        "unknown frame `hand`",
    ),
    (
        "signals = [\"arm.position\"",
        "signals = [\"arm.deformation\"",
        "output.signals[0]",
        "arm.deformation",
        "not a node frame",
    ),
    (
        "source = \"parts/rod.toml\"",
        "source = \"parts/nothing.toml\"",
        "body[1].source",
        "nothing.toml",
        "nothing.toml",
    ),
    (
        "type = \"rigid\"",
        "type = \"rigid\"\nsource = \"x.toml\"",
        "body[0].source",
        "source = \"x.toml\"",
        "not used by a rigid body",
    ),
    (
        "name = \"pendulum\"",
        "name = \"pendulum\"\ncolour = \"red\"",
        "model.colour",
        "colour",
        "unknown field",
    ),
    (
        "position = [0, 0, \"500 mm\"]",
        "position = [0, 0, \"500 mm\"]\nnode = 3",
        "frame[1].node",
        "node = 3",
        "is rigid",
    ),
];

/// A joint at the floating frame of a body whose modes are clamped there (the cantilever part,
/// clamped at its origin node) is valid: the frame is a rigid extension of the clamped node.
#[test]
fn joint_at_clamped_floating_frame_compiles() {
    let text = BASE
        .replacen("parts/rod.toml", "parts/cantilever_beam.toml", 1)
        .replacen("position = [0, 0, -1.0]", "position = [0, 0, 0]", 1)
        .replacen("b = \"top\"", "b = \"rod\"", 1);
    let cm = compile_model(&text, &model_path()).unwrap();
    assert_eq!(cm.model.nc, 5);
}

#[test]
fn every_error_names_key_path_and_line() {
    let file = model_path();
    for (from, to, path, line_text, fragment) in CASES {
        assert!(BASE.contains(from), "case {from}");
        let text = BASE.replacen(from, to, 1);
        let err = match compile_model(&text, &file) {
            Ok(_) => panic!("case `{to}` compiled"),
            Err(e) => e,
        };
        let msg = err.to_string();
        let SimError::Model { path: p, line, .. } = &err else {
            panic!("case `{to}`: not a model error: {msg}");
        };
        assert_eq!(p, path, "case `{to}`: {msg}");
        let expected_line = text
            .lines()
            .position(|l| l.contains(line_text))
            .map(|i| i + 1)
            .unwrap();
        // a table header line is accepted for errors on the table itself
        assert!(
            *line == expected_line,
            "case `{to}`: line {line}, expected {expected_line}: {msg}"
        );
        assert!(msg.contains(fragment), "case `{to}`: {msg}");
        assert!(msg.contains("test_model.toml:"), "{msg}");
    }
}

/// An error inside an FE body file used as `source` names both places: the model file's line
/// and key, and the FE file's line and key.
#[test]
fn fe_source_errors_are_located_in_both_files() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mbs");
    let dir = flexmbs_io::test_tools::scratch_dir("fe-source");
    std::fs::create_dir_all(dir.join("parts")).unwrap();
    let rod = std::fs::read_to_string(root.join("parts/rod.toml")).unwrap()
        + "\n[body.boundary]\nfixed = [\"xmin_typo\"]\n";
    std::fs::write(dir.join("parts/rod.toml"), &rod).unwrap();
    let model = dir.join("slider_crank.toml");
    std::fs::copy(root.join("slider_crank.toml"), &model).unwrap();
    let err = flexmbs_sim::load_model(&model).unwrap_err().to_string();
    let rod_line = rod.lines().position(|l| l.starts_with("fixed")).unwrap() + 1;
    let text = std::fs::read_to_string(&model).unwrap();
    let source_line = text
        .lines()
        .position(|l| l.starts_with("source = \"parts/rod.toml\""))
        .unwrap()
        + 1;
    assert!(
        err.contains(&format!(
            "slider_crank.toml:{source_line}: at `body[1].source`"
        )),
        "{err}"
    );
    assert!(
        err.contains(&format!(
            "rod.toml:{rod_line}: at `body.boundary.fixed[0]`: no node set 'xmin_typo'"
        )),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

//! `type = "point_mass"` bodies: free fall (exact for the constant acceleration), a tip mass on a
//! flexible cantilever through a spherical joint equal to a rigid body with inertia on the same
//! joint (its rotation is decoupled: an independent code path; measured equal to the last bit), and refusals of rotational
//! couplings with their key paths.

use crate::common;

use flexmbs_io::results::read_results;
use flexmbs_sim::run::{run_model, RunOptions};
use flexmbs_sim::{compile_model, SimError};
use std::path::Path;

fn run(text: &str, tag: &str) -> flexmbs_io::results::Results {
    let dir = common::work_dir("point-mass", tag);
    let cm = compile_model(text, &dir.join("m.toml")).unwrap();
    run_model(&cm, &RunOptions::new(&dir), &mut |_| {}).unwrap();
    read_results(&dir.join("results.h5")).unwrap()
}

#[test]
fn free_fall_is_exact() {
    let text = r#"
[model]
name = "fall"
gravity = [0, 0, -9.81]
[solver]
type = "generalized-alpha"
h = 0.01
t_end = 1.0
[[body]]
name = "p"
type = "point_mass"
mass = "2 kg"
position = [1, 2, 3]
velocity = [0.5, 0, 4]
[output]
signals = ["p.position", "p.velocity"]
"#;
    let r = run(text, "fall");
    let t = *r.time.last().unwrap();
    let z = *r.series("p.position.z").unwrap().last().unwrap();
    let x = *r.series("p.position.x").unwrap().last().unwrap();
    assert!((t - 1.0).abs() < 1e-12);
    assert!(
        (z - (3.0 + 4.0 * t - 0.5 * 9.81 * t * t)).abs() < 1e-12,
        "{z}"
    );
    assert!((x - (1.0 + 0.5 * t)).abs() < 1e-12, "{x}");
    let names = r.series_names();
    assert!(names.iter().any(|n| n == "q/p.R_z"), "{names:?}");
}

fn tip_mass_model(body: &str) -> String {
    let part =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mbs/parts/cantilever_beam.toml");
    format!(
        r#"
[model]
name = "tip_mass"
gravity = [0, 0, -9.81]
[solver]
type = "generalized-alpha"
rho_inf = 0.9
h = 2e-4
t_end = 0.05
[[body]]
name = "beam"
type = "ffr"
source = "{}"
[[body]]
name = "payload"
{body}
position = [1, 0, 0]
[[frame]]
name = "wall"
body = "ground"
[[frame]]
name = "tip"
body = "beam"
nearest = [1.0, 0.0, 0.0]
[[joint]]
name = "clamp"
type = "fixed"
a = "wall"
b = "beam"
[[joint]]
name = "hold"
type = "spherical"
a = "tip"
b = "payload"
[output]
signals = ["tip.deformation", "payload.position"]
"#,
        part.display()
    )
}

#[test]
fn tip_point_mass_equals_a_rigid_body_on_a_spherical_joint() {
    let point = run(
        &tip_mass_model("type = \"point_mass\"\nmass = 0.5"),
        "tip-point",
    );
    let rigid = run(
        &tip_mass_model("type = \"rigid\"\nmass = 0.5\ninertia = [1e-4, 2e-4, 3e-4]"),
        "tip-rigid",
    );
    let (a, b) = (
        point.series("tip.deformation.z").unwrap(),
        rigid.series("tip.deformation.z").unwrap(),
    );
    assert_eq!(a.len(), b.len());
    // two different models: the rigid body has three rotation coordinates more
    let nq = |r: &flexmbs_io::results::Results| r.layout.coordinates.len();
    assert_eq!(nq(&point) + 3, nq(&rigid));
    let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(scale > 1e-3, "the payload bends the beam: {scale}");
    assert!(worst < 1e-8 * scale, "{worst:e} vs {scale:e}");
}

fn error_of(text: &str) -> String {
    match compile_model(text, Path::new("/tmp/point_mass_bad.toml")) {
        Err(e @ SimError::Model { .. }) => e.to_string(),
        Err(e) => panic!("expected a located model error, got {e}"),
        Ok(_) => panic!("accepted:\n{text}"),
    }
}

const BASE: &str = r#"
[model]
name = "m"
[solver]
type = "generalized-alpha"
h = 1e-3
t_end = 1e-2
[[body]]
name = "p"
type = "point_mass"
mass = 1.0
[[body]]
name = "arm"
type = "rigid"
mass = 1.0
inertia = [1, 1, 1]
[[frame]]
name = "o"
body = "ground"
"#;

#[test]
fn rotational_couplings_on_a_point_mass_are_refused() {
    let joint = |kind: &str| {
        format!("{BASE}[[joint]]\nname = \"j\"\ntype = \"{kind}\"\na = \"arm\"\nb = \"p\"\n")
    };
    for kind in ["revolute", "fixed", "prismatic", "cylindrical"] {
        let e = error_of(&joint(kind));
        assert!(
            e.contains("joint[0].b") && e.contains("no rotations"),
            "{e}"
        );
    }
    let generic = format!(
        "{BASE}[[joint]]\nname = \"j\"\ntype = \"generic\"\nlocked = [\"ty\", \"rz\"]\na = \"o\"\nb = \"p\"\n"
    );
    assert!(error_of(&generic).contains("joint[0].b"));
    let torque = format!("{BASE}[[load]]\ntype = \"torque\"\nframe = \"p\"\nvector = [0, 0, 1]\n");
    let e = error_of(&torque);
    assert!(e.contains("load[0].frame") && e.contains("torque"), "{e}");
    let bushing = format!(
        "{BASE}[[force]]\nname = \"bush\"\ntype = \"bushing\"\na = \"o\"\nb = \"p\"\n\
         translational_stiffness = [1, 1, 1]\nrotational_stiffness = [1, 1, 1]\n"
    );
    let e = error_of(&bushing);
    assert!(e.contains("force[0].b") && e.contains("bush"), "{e}");
    let e = error_of(&BASE.replace("mass = 1.0\n[[body]]", "inertia = [1, 1, 1]\n[[body]]"));
    assert!(e.contains("body[0]"), "{e}");
}

#[test]
fn translational_couplings_on_a_point_mass_are_accepted() {
    let ok = format!(
        "{BASE}[[joint]]\nname = \"j\"\ntype = \"spherical\"\na = \"o\"\nb = \"p\"\n\
         [[load]]\ntype = \"force\"\nframe = \"p\"\nvector = [0, 0, 1]\n"
    );
    compile_model(&ok, Path::new("/tmp/point_mass_ok.toml")).unwrap();
    let slider = format!(
        "{BASE}[[joint]]\nname = \"j\"\ntype = \"generic\"\nlocked = [\"ty\", \"tz\"]\na = \"o\"\nb = \"p\"\n"
    );
    compile_model(&slider, Path::new("/tmp/point_mass_ok.toml")).unwrap();
}

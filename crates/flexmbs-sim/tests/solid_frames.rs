//! Frames on solid FE bodies (issue 11 item 1): a solid-mesh node has no rotational DOFs, so a
//! joint that locks rotations there is refused with a message naming the rigid interface to use;
//! a frame on that interface (`interface = "tip"`) carries the body's slope, checked against
//! Euler-Bernoulli beam theory for a tip moment (exact for hex20r with nu = 0: measured 3e-8).

use crate::common;

use flexmbs_io::results::read_results;
use flexmbs_sim::run::{run_model, RunOptions};

/// Aluminium-like strip 0.5 m x 20 mm x 5 mm, hex20r, clamped at x = 0, a rigid interface `tip`
/// on the end face x = 0.5 (its node at the face centroid [0.5, 0.01, 0.0025]), Craig-Bampton with
/// that interface (exact static response to loads there). `nu = 0`: no anticlastic or clamp
/// Poisson effects, so the slope under a pure end moment is the beam theory's `M L / (E I)`.
const LINK: &str = r#"
[body]
name = "link"
[body.mesh]
type = "box"
size = [0.5, 0.02, 0.005]
divisions = [20, 2, 1]
element = "hex20r"
material = { e = 70e9, nu = 0.0, rho = 2700.0 }
[body.boundary]
fixed = ["xmin"]
[[body.boundary.rigid]]
name = "tip"
nodes = "xmax"
[body.reduction]
method = "craig-bampton"
interface = ["tip"]
modes = 4
"#;

/// The link clamped to ground, a payload welded at frame `elbow`, a torque about y on the
/// payload (statics).
const MODEL: &str = r#"
[model]
name = "solid_link"

[solver]
type = "statics"
load_steps = 1

[[body]]
name = "link"
type = "ffr"
source = "link.toml"

[[body]]
name = "payload"
type = "rigid"
mass = "0.2 kg"
inertia = [1e-5, 1e-5, 1e-5]
position = [0.5, 0.01, 0.0025]

[[frame]]
name = "wall"
body = "ground"

[[frame]]
name = "elbow"
body = "link"
ELBOW

[[joint]]
name = "clamp"
type = "fixed"
a = "wall"
b = "link"

[[joint]]
name = "weld"
type = "fixed"
a = "elbow"
b = "payload"

[[load]]
type = "torque"
frame = "payload"
vector = [0, "1 N*m", 0]

[output]
signals = ["payload.orientation"]
"#;

fn model_with(dir: &std::path::Path, elbow: &str) -> std::path::PathBuf {
    std::fs::write(dir.join("link.toml"), LINK).unwrap();
    let file = dir.join("model.toml");
    std::fs::write(&file, MODEL.replace("ELBOW", elbow)).unwrap();
    file
}

#[test]
fn joint_locking_rotations_at_a_solid_node_is_refused_naming_the_interface() {
    let dir = common::work_dir("solid-frames", "refused");
    // a corner node of the end face: a solid-mesh node, translations only
    let file = model_with(&dir, "nearest = [0.5, 0.0, 0.0]");
    let e = flexmbs_sim::load_model(&file).unwrap_err().to_string();
    assert!(e.contains("model.toml:39: at `joint[1].a`"), "{e}");
    assert!(
        e.contains("joint `weld` locks rotations at frame `elbow`, which sits on FE node"),
        "{e}"
    );
    assert!(
        e.contains(
            "of body `link`: a node without rotational degrees of freedom (a solid-mesh node)"
        ),
        "{e}"
    );
    assert!(e.contains("is tied to the rigid interface `tip`"), "{e}");
    assert!(
        e.contains("Attach the frame to a rigid interface of `link` instead (in place of `node`/`nearest`): `interface = \"tip\"` (at [0.5, 0.01, 0.0025] m, "),
        "{e}"
    );
    // a spherical joint locks no rotation: accepted there
    let text = std::fs::read_to_string(&file).unwrap().replacen(
        "name = \"weld\"\ntype = \"fixed\"",
        "name = \"weld\"\ntype = \"spherical\"",
        1,
    );
    std::fs::write(&file, text).unwrap();
    // (statics assembles the rough start, so the payload may sit off the node)
    flexmbs_sim::load_model(&file).unwrap();
    // a torque there is refused alike
    let text = std::fs::read_to_string(&file).unwrap().replacen(
        "frame = \"payload\"",
        "frame = \"elbow\"",
        1,
    );
    std::fs::write(&file, text).unwrap();
    let e = flexmbs_sim::load_model(&file).unwrap_err().to_string();
    assert!(
        e.contains("at `load[0].frame`: a torque acts at frame `elbow`, which sits on FE node"),
        "{e}"
    );
    assert!(
        e.contains("so the torque would turn the body as a whole instead of bending it there"),
        "{e}"
    );
    assert!(e.contains("`interface = \"tip\"`"), "{e}");
}

#[test]
fn frame_on_rigid_interface_transmits_the_slope() {
    let dir = common::work_dir("solid-frames", "interface");
    let ei = 70e9 * 0.02 * 0.005f64.powi(3) / 12.0;
    let slope = 1.0 * 0.5 / ei;
    for elbow in [
        "interface = \"tip\"",
        // the face centroid is also a mid-edge node of the mesh: `nearest` prefers the interface
        "nearest = [0.5, 0.01, 0.0025]",
    ] {
        let file = model_with(&dir, elbow);
        let cm = flexmbs_sim::load_model(&file).unwrap();
        let out = dir.join("run");
        run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
        let r = read_results(&out.join("results.h5")).unwrap();
        let oy = *r.series("payload.orientation.y").unwrap().last().unwrap();
        let rel = (oy - slope).abs() / slope;
        eprintln!("{elbow}: payload rotation {oy:e} rad, beam theory M L / (E I) = {slope:e} rad, rel. {rel:e}");
        assert!(rel < 1e-6, "{elbow}: {oy} vs {slope} (rel. {rel:e})");
    }
}

#[test]
fn unknown_node_and_interface_errors_list_the_interfaces() {
    let dir = common::work_dir("solid-frames", "unknown");
    let e = flexmbs_sim::load_model(&model_with(&dir, "node = 99999"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("at `frame[1].node`: body `link` has no FE node 99999 ("),
        "{e}"
    );
    assert!(e.contains("; rigid interfaces `tip` (node "), "{e}");
    let e = flexmbs_sim::load_model(&model_with(&dir, "interface = \"root\""))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(
            "at `frame[1].interface`: body `link` has no rigid interface `root` (interfaces: tip)"
        ),
        "{e}"
    );
}

/// Without a rigid interface the message explains how to define one.
#[test]
fn refusal_without_interfaces_explains_how_to_define_one() {
    let dir = common::work_dir("solid-frames", "no-interface");
    let file = model_with(&dir, "nearest = [0.5, 0.0, 0.0]");
    let plain = LINK
        .replace(
            "[[body.boundary.rigid]]\nname = \"tip\"\nnodes = \"xmax\"\n",
            "",
        )
        .replace("method = \"craig-bampton\"\ninterface = [\"tip\"]\n", "");
    assert!(
        !plain.contains("tip") && !plain.contains("craig"),
        "{plain}"
    );
    std::fs::write(dir.join("link.toml"), plain).unwrap();
    let e = flexmbs_sim::load_model(&file).unwrap_err().to_string();
    assert!(
        e.contains("at `joint[1].a`: joint `weld` locks rotations"),
        "{e}"
    );
    assert!(
        e.contains(
            "Body `link` has no rigid interface. Define one in the body's FE model file: a \
             `[[body.boundary.rigid]]` table with a `name` and the `nodes` the joint grips"
        ),
        "{e}"
    );
    assert!(
        e.contains("then name it on the frame with `interface = \"<name>\"`"),
        "{e}"
    );
}

/// A reduced-body file keeps the interface node (with rotations) but not its name: the refusal
/// lists it by id, and `interface = "tip"` is an error that says so.
#[test]
fn refusal_on_a_reduced_body_file_lists_nodes_with_rotations() {
    let dir = common::work_dir("solid-frames", "body-file");
    let file = model_with(&dir, "nearest = [0.5, 0.0, 0.0]");
    let (body, _) = flexmbs_sim::bodies::load_reduced_with_fe(
        &dir.join("link.toml"),
        &dir,
        "link",
        Default::default(),
    )
    .unwrap();
    // the interface node follows the mesh nodes
    let iface = body.num_nodes() - 1;
    let id = body.node_ids[iface];
    assert_eq!(body.nodes[iface], [0.5, 0.01, 0.0025]);
    flexmbs_io::body_file::write_body(&dir.join("link.fmb.h5"), &body).unwrap();
    let text = std::fs::read_to_string(&file)
        .unwrap()
        .replace("source = \"link.toml\"", "source = \"link.fmb.h5\"");
    std::fs::write(&file, &text).unwrap();
    let e = flexmbs_sim::load_model(&file).unwrap_err().to_string();
    assert!(
        e.contains(&format!(
            "Attach the frame to a node with rotations (a rigid interface node) instead: \
             `node = {id}` (at [0.5, 0.01, 0.0025] m, "
        )),
        "{e}"
    );
    std::fs::write(
        &file,
        text.replace("nearest = [0.5, 0.0, 0.0]", "interface = \"tip\""),
    )
    .unwrap();
    let e = flexmbs_sim::load_model(&file).unwrap_err().to_string();
    assert!(
        e.contains("at `frame[1].interface`: body `link` has no rigid interface `tip`: its source names none"),
        "{e}"
    );
    assert!(e.contains("a reduced-body file keeps the interface node, without its name: use `node = <id>` there"), "{e}");
    // and with `node = <id>` it runs and transmits the slope as the FE model file does
    std::fs::write(
        &file,
        text.replace("nearest = [0.5, 0.0, 0.0]", &format!("node = {id}")),
    )
    .unwrap();
    let cm = flexmbs_sim::load_model(&file).unwrap();
    let out = dir.join("run");
    run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    let r = read_results(&out.join("results.h5")).unwrap();
    let oy = *r.series("payload.orientation.y").unwrap().last().unwrap();
    let slope = 0.5 / (70e9 * 0.02 * 0.005f64.powi(3) / 12.0);
    assert!((oy - slope).abs() < 1e-6 * slope, "{oy} vs {slope}");
}

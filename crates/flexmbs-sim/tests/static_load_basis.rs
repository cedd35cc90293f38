//! Static load responses in a modal basis (`[body.reduction] static_loads`): a clamped steel
//! cantilever 1 m x 20 mm x 20 mm (20 Euler-Bernoulli beam elements) loaded by 20 N at
//! mid-span. Reference: beam theory, `w(a) = P a^3 / (3 E I)` under the load at `a = 0.5 m`
//! (Euler-Bernoulli beam elements are nodally exact for nodal loads). One mode misses it by
//! percents; one mode plus the static response to a load at that node reproduces it to
//! round-off (the response is in the basis). Also: a mode count keeps the static response,
//! modal damping is refused with the reason, the body file keeps the basis and passes its
//! consistency checks on write and read.

use crate::common;

use flexmbs_io::results::read_results;
use flexmbs_sim::compile_model;
use flexmbs_sim::run::{run_model, RunOptions};

const BODY: &str = r#"
[body]
name = "cantilever"
[body.mesh]
type = "beam"
start = [0.0, 0.0, 0.0]
end = [1.0, 0.0, 0.0]
elements = 20
section = { shape = "rectangle", width = 0.02, height = 0.02 }
material = { e = 210e9, nu = 0.3, rho = 7850.0 }
[body.boundary]
fixed = [{ nearest = [0.0, 0.0, 0.0] }]
[body.reduction]
method = "modal"
modes = 4
"#;

const MID_LOAD: &str =
    "static_loads = [{ nodes = { nearest = [0.5, 0.0, 0.0] }, direction = [0.0, 0.0, -1.0] }]\n";

fn model(extra_body: &str) -> String {
    format!(
        r#"
[model]
name = "mid_loaded_cantilever"
[solver]
type = "statics"
load_steps = 1
[[body]]
name = "beam"
type = "ffr"
source = "body.toml"
{extra_body}
[[frame]]
name = "wall"
body = "ground"
[[frame]]
name = "mid"
body = "beam"
nearest = [0.5, 0.0, 0.0]
[[joint]]
name = "clamp"
type = "fixed"
a = "wall"
b = "beam"
[[load]]
type = "force"
frame = "mid"
vector = [0, 0, "-20 N"]
[output]
signals = ["mid.deformation"]
"#
    )
}

/// Mid-span deflection of the statics run (m, along z).
fn mid_deflection(body: &str, extra: &str, tag: &str) -> f64 {
    let dir = common::work_dir("static-load-basis", tag);
    std::fs::write(dir.join("body.toml"), body).unwrap();
    let path = dir.join("m.toml");
    std::fs::write(&path, model(extra)).unwrap();
    let cm = compile_model(&model(extra), &path).unwrap();
    let out = dir.join("out");
    run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    let r = read_results(&out.join("results.h5")).unwrap();
    *r.series("mid.deformation.z").unwrap().last().unwrap()
}

fn beam_theory() -> f64 {
    let ei = 210e9 * 0.02f64.powi(4) / 12.0;
    -20.0 * 0.5f64.powi(3) / (3.0 * ei)
}

#[test]
fn static_response_makes_the_statics_exact() {
    let exact = beam_theory();
    let with = mid_deflection(&format!("{BODY}{MID_LOAD}"), "modes = 1", "with");
    let without = mid_deflection(BODY, "modes = 1", "without");
    let e_with = (with - exact).abs() / exact.abs();
    let e_without = (without - exact).abs() / exact.abs();
    eprintln!("mid deflection {exact:e}: 1 mode {without:e} ({e_without:.2e}), 1 mode + static response {with:e} ({e_with:.2e})");
    assert!(e_with < 1e-8, "with the static response: {e_with:e}");
    assert!(e_without > 1e-3, "one mode alone: {e_without:e}");
}

#[test]
fn count_keeps_the_static_response_and_modal_damping_is_refused() {
    let dir = common::work_dir("static-load-basis", "count");
    std::fs::write(dir.join("body.toml"), format!("{BODY}{MID_LOAD}")).unwrap();
    let path = dir.join("m.toml");
    // 4 modes + 1 static response: 5 modes asked is one too many, with the reason
    let text = model("modes = 5");
    let msg = match compile_model(&text, &path) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("5 modes of 4 accepted"),
    };
    assert!(
        msg.contains("body[0].modes") && msg.contains("1 static load responses"),
        "{msg}"
    );
    let text = model("modes = 2\ndamping = { modal = [0.01] }");
    let msg = match compile_model(&text, &path) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("modal damping accepted on a coupled basis"),
    };
    assert!(
        msg.contains("body[0].damping.modal") && msg.contains("rayleigh"),
        "{msg}"
    );
    compile_model(
        &model("modes = 2\ndamping = { rayleigh = [0.0, 1e-4] }"),
        &path,
    )
    .unwrap();
}

#[test]
fn body_file_keeps_the_basis() {
    let spec = flexmbs_io::model::parse_fe_model(
        &format!("{BODY}{MID_LOAD}"),
        std::path::Path::new("body.toml"),
    )
    .unwrap()
    .body;
    let prepared =
        flexmbs_reduce::pipeline::prepare(&spec, std::path::Path::new("."), &mut |_| {}).unwrap();
    let body = flexmbs_reduce::pipeline::run_reduction(&spec, &prepared, &mut |_| {}).unwrap();
    assert_eq!(body.num_modes(), 5);
    assert_eq!(body.labels[4].dominant, "static load 1");
    // the static vector's frequency lies above the four modes
    assert!(body.frequencies_hz[4] > body.frequencies_hz[3]);
    let dir = common::work_dir("static-load-basis", "file");
    let f = dir.join("b.fmb.h5");
    flexmbs_io::body_file::write_body(&f, &body).unwrap();
    let back = flexmbs_io::body_file::read_body(&f).unwrap();
    assert_eq!(back.labels, body.labels);
    assert_eq!(back.k_red, body.k_red);
    assert_eq!(back.modes_t, body.modes_t);
}

#[test]
fn refusals_are_located() {
    let dir = common::work_dir("static-load-basis", "refusals");
    let path = dir.join("m.toml");
    for (load, key, words) in [
        (
            "static_loads = [{ nodes = { nearest = [0.0, 0.0, 0.0] }, direction = [0.0, 0.0, 1.0] }]\n",
            "static_loads[0].nodes",
            "no effect",
        ),
        (
            "static_loads = [{ nodes = \"end\", direction = [0.0, 0.0, 0.0] }]\n",
            "static_loads[0].direction",
            "nonzero",
        ),
        (
            "static_loads = [{ nodes = \"end\", direction = [0.0, 0.0, 1.0] }, { nodes = \"end\", direction = [0.0, 0.0, 2.0] }]\n",
            "static_loads",
            "adds nothing",
        ),
        (
            "static_loads = [{ point = [0.5, 0.0, 0.0], direction = [0.0, 0.0, 1.0] }]\n",
            "static_loads[0].point",
            "solid elements",
        ),
        (
            "static_loads = [{ direction = [0.0, 0.0, 1.0] }]\n",
            "static_loads[0]",
            "exactly one",
        ),
        (
            "static_loads = [{ nodes = \"end\", point = [1.0, 0.0, 0.0], direction = [0.0, 0.0, 1.0] }]\n",
            "static_loads[0]",
            "exactly one",
        ),
        (
            "static_loads = [{ face = \"top\", point = [1.0, 0.0, 0.0], direction = [0.0, 0.0, 1.0] }]\n",
            "static_loads[0].face",
            "unknown face",
        ),
        (
            "static_loads = [{ face = \"ymax\", nodes = \"end\", direction = [0.0, 0.0, 1.0] }]\n",
            "static_loads[0]",
            "needs `point`",
        ),
    ] {
        std::fs::write(dir.join("body.toml"), format!("{BODY}{load}")).unwrap();
        let msg = match compile_model(&model("modes = 1"), &path) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("accepted: {load}"),
        };
        assert!(msg.contains(key) && msg.contains(words), "{load}: {msg}");
    }
}

/// A point load at a node of a solid mesh is the same pattern as a load on that node alone: the
/// same basis vector (to round-off); a point between nodes loads the element's nodes.
#[test]
fn point_load_at_a_node_equals_the_node_load() {
    let solid = |load: &str| {
        format!(
            r#"
[body]
name = "block"
[body.mesh]
type = "box"
size = [0.2, 0.04, 0.04]
divisions = [5, 2, 2]
element = "hex20"
material = {{ e = 210e9, nu = 0.3, rho = 7850.0 }}
[body.boundary]
fixed = ["xmin"]
[body.reduction]
modes = 3
mass = "consistent"
static_loads = [{load}]
"#
        )
    };
    let reduce = |text: &str| {
        let spec = flexmbs_io::model::parse_fe_model(text, std::path::Path::new("b.toml"))
            .unwrap()
            .body;
        let prepared =
            flexmbs_reduce::pipeline::prepare(&spec, std::path::Path::new("."), &mut |_| {})
                .unwrap();
        flexmbs_reduce::pipeline::run_reduction(&spec, &prepared, &mut |_| {}).unwrap()
    };
    let at_point = reduce(&solid(
        "{ point = [0.2, 0.04, 0.02], direction = [0.0, -1.0, 0.0] }",
    ));
    let at_node = reduce(&solid(
        "{ nodes = { nearest = [0.2, 0.04, 0.02] }, direction = [0.0, -1.0, 0.0] }",
    ));
    assert_eq!(at_point.num_modes(), 4);
    let d = (0..at_point.modes_t.nrows())
        .map(|i| (at_point.modes_t[(i, 3)] - at_node.modes_t[(i, 3)]).abs())
        .fold(0.0, f64::max);
    let scale = (0..at_node.modes_t.nrows())
        .map(|i| at_node.modes_t[(i, 3)].abs())
        .fold(0.0, f64::max);
    assert!(d < 1e-9 * scale, "point vs node load: {d:e} of {scale:e}");
    // the same point on the top face's NURBS surface: at a grid node its weights load that
    // node alone (interpolation), so the vector is again the node load's
    let at_face = reduce(&solid(
        "{ face = \"ymax\", point = [0.2, 0.04, 0.02], direction = [0.0, -1.0, 0.0] }",
    ));
    let d = (0..at_face.modes_t.nrows())
        .map(|i| (at_face.modes_t[(i, 3)] - at_node.modes_t[(i, 3)]).abs())
        .fold(0.0, f64::max);
    assert!(
        d < 1e-9 * scale,
        "face point vs node load: {d:e} of {scale:e}"
    );
    // between nodes the face weights spread over the whole top face (a global interpolation):
    // another vector than the element's shape functions give
    let face_between = reduce(&solid(
        "{ face = \"ymax\", point = [0.19, 0.04, 0.013], direction = [0.0, -1.0, 0.0] }",
    ));
    assert_eq!(face_between.num_modes(), 4);
    // between nodes: a different vector, still a valid basis
    let between = reduce(&solid(
        "{ point = [0.19, 0.04, 0.013], direction = [0.0, -1.0, 0.0] }",
    ));
    assert_eq!(between.num_modes(), 4);
    assert!(between.frequencies_hz[3] > between.frequencies_hz[2]);
}

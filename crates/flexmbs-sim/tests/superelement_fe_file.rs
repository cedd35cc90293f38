//! Superelements from FE body files (`type = "superelement"`): a chain of superelements made
//! from an FE beam file equals the `superelement_beam` of the same beam (same data, same static
//! path); a superelement of a solid bar clamped at one interface vibrates like the FFR body of
//! the same FE model and Craig-Bampton modes; bad input is refused at the keys.

use crate::common;

use flexmbs_io::results::{read_results, RunStatus};
use flexmbs_sim::compile_model;
use flexmbs_sim::run::{run_model, RunOptions};
use flexmbs_sim::superelement_fe::{superelement_from_reduced, FeFrame, FrameCondition};
use std::path::{Path, PathBuf};

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/superelement_fe")
}

/// Compiles `text` as a model file in the test data folder (FE files resolve there).
fn compiled(text: &str) -> Result<flexmbs_sim::CompiledModel, String> {
    compile_model(text, &data_dir().join("model.toml")).map_err(|e| e.to_string())
}

/// Runs `text` and returns the series `names` of the results.
fn run_series(text: &str, tag: &str, names: &[&str]) -> Vec<Vec<f64>> {
    let cm = compiled(text).unwrap_or_else(|e| panic!("{e}"));
    let out = common::work_dir("sefe", tag);
    let summary = run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    assert_eq!(summary.status, RunStatus::Completed);
    let r = read_results(&out.join("results.h5")).unwrap();
    let series = names
        .iter()
        .map(|n| r.series(n).unwrap_or_else(|e| panic!("{n}: {e}")).to_vec())
        .collect();
    let _ = std::fs::remove_dir_all(&out);
    series
}

const BEAM_HEADER: &str = r#"
[model]
name = "cantilever"

[solver]
type = "statics"
load_steps = 20

[output]
signals = ["tip.position"]
animation = false

[[load]]
type = "force"
frame = "tip"
vector = [0, "-1 kN", 0]
"#;

/// The 10-superelement cantilever of `validation/cantilever_static` as a `superelement_beam`.
fn beam_component() -> String {
    format!(
        "{BEAM_HEADER}
[[body]]
name = \"beam\"
type = \"superelement_beam\"
material = {{ e = 70e9, nu = 0.3, rho = 2700.0 }}
section = {{ shape = \"tube\", outer_radius = 0.01, wall = 0.001 }}
length = \"1 m\"
segments = 10
fixed = [\"i0\"]
interfaces = [\"n0\", \"n1\", \"n2\", \"n3\", \"n4\", \"n5\", \"n6\", \"n7\", \"n8\", \"n9\", \"tip\"]
"
    )
}

/// The same cantilever as 10 `superelement` bodies made from the FE beam file of one segment.
fn fe_chain() -> String {
    let mut text = BEAM_HEADER.to_string();
    for k in 0..10 {
        let b = if k == 9 {
            "tip".to_string()
        } else {
            format!("n{}", k + 1)
        };
        let fixed = if k == 0 { "fixed = [\"n0\"]\n" } else { "" };
        text.push_str(&format!(
            "
[[body]]
name = \"s{k}\"
type = \"superelement\"
source = \"beam_segment.toml\"
position = [{}, 0, 0]
interfaces = [\"n{k}\", \"{b}\"]
{fixed}",
            0.1 * k as f64
        ));
    }
    text
}

/// A superelement from an FE beam file has the data of `superelement_beam` (the node at the
/// centre of mass gives `[Φ_CB]`), to round-off, and a chain of ten of them follows the same
/// static path as the `superelement_beam` cantilever to 1e-9 of the tip deflection.
#[test]
fn fe_beam_chain_equals_superelement_beam() {
    use flexmbs_core::superelement::{beam_segment, BeamSegmentSpec, FrameLocation};
    use flexmbs_fe::mesh::{BeamSection, BeamTheory};
    let path = data_dir().join("beam_segment.toml");
    let src = flexmbs_io::model_check::FeModelSource::read(&path).unwrap();
    let spec = src.model.body.clone();
    let prepared = flexmbs_reduce::pipeline::prepare(&spec, &data_dir(), &mut |_| {}).unwrap();
    let reduced = flexmbs_reduce::pipeline::run_reduction(&spec, &prepared, &mut |_| {}).unwrap();
    let names = ["start".to_string(), "end".to_string()];
    let fe = superelement_from_reduced(&prepared.system, &reduced, &names, FeFrame::CentreOfMass)
        .unwrap();
    assert!(matches!(fe.condition, FrameCondition::Node(_)));
    assert!((fe.origin - nalgebra::Vector3::new(0.05, 0.0, 0.0)).norm() < 1e-15);
    let beam = beam_segment(&BeamSegmentSpec {
        length: 0.1,
        material: flexmbs_fe::Material {
            e: 70e9,
            nu: 0.3,
            rho: 2700.0,
        },
        section: BeamSection::tube(0.01, 0.001),
        theory: BeamTheory::EulerBernoulli,
        elements: 2,
        internal_modes: 0,
        frame: FrameLocation::CentreOfMass,
    })
    .unwrap();
    let rel = |a: &nalgebra::DMatrix<f64>, b: &nalgebra::DMatrix<f64>| (a - b).amax() / b.amax();
    let (dm, dk, dp) = (
        rel(&fe.data.m_cb, &beam.m_cb),
        rel(&fe.data.k_cb, &beam.k_cb),
        rel(&fe.data.phi_cb, &beam.phi_cb),
    );
    eprintln!("FE file vs superelement_beam data: M {dm:e}, K {dk:e}, Phi_CB {dp:e}");
    assert!(dm < 1e-12 && dk < 1e-12 && dp < 1e-12);
    for (a, b) in fe.data.interfaces.iter().zip(&beam.interfaces) {
        assert!((a.position - b.position).norm() < 1e-15);
    }
    let names = ["tip.position.x", "tip.position.y"];
    let reference = run_series(&beam_component(), "beam", &names);
    let chain = run_series(&fe_chain(), "chain", &names);
    let scale = reference[1].last().unwrap().abs();
    assert!(scale > 0.1, "tip deflection {scale}");
    let mut diff: f64 = 0.0;
    for (a, b) in chain.iter().zip(&reference) {
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(b) {
            diff = diff.max((x - y).abs() / scale);
        }
    }
    eprintln!("FE-file chain vs superelement_beam: static path {diff:e} of the tip deflection");
    assert!(diff < 1e-9, "{diff:e}");
}

const VIBRATION_HEADER: &str = r#"
[model]
name = "bar"
gravity = [0, -9.81, 0]

[solver]
type = "generalized-alpha"
h = "0.1 ms"
t_end = "0.3 s"
rho_inf = 1.0
"#;

/// The bar as a superelement clamped at its root interface.
fn superelement_bar() -> String {
    format!(
        "{VIBRATION_HEADER}
[[body]]
name = \"bar\"
type = \"superelement\"
source = \"bar_free.toml\"
interfaces = [\"root\", \"tip\"]
fixed = [\"root\"]

[output]
signals = [\"tip.position\", \"bar.deformation\", \"bar.frame_iterations\"]
animation = false
"
    )
}

/// The bar as an FFR body of the clamped FE model (same Craig-Bampton modes), its frame fixed.
fn ffr_bar() -> String {
    format!(
        "{VIBRATION_HEADER}
[[body]]
name = \"bar\"
type = \"ffr\"
source = \"bar_clamped.toml\"

[[frame]]
name = \"tip\"
body = \"bar\"
interface = \"tip\"

[[frame]]
name = \"wall\"
body = \"ground\"

[[joint]]
name = \"clamp\"
type = \"fixed\"
a = \"wall\"
b = \"bar\"

[output]
signals = [\"tip.position\"]
animation = false
"
    )
}

/// Peak deflection (most negative y) and the mean period of the oscillation of `y` about its
/// mean (upward crossings, linearly interpolated), `h` the output step.
fn peak_and_period(y: &[f64], h: f64) -> (f64, f64) {
    let y0 = y[0];
    let d: Vec<f64> = y.iter().map(|v| v - y0).collect();
    let peak = d.iter().copied().fold(0.0, f64::min);
    let mean = d.iter().sum::<f64>() / d.len() as f64;
    let mut crossings = Vec::new();
    for i in 1..d.len() {
        let (a, b) = (d[i - 1] - mean, d[i] - mean);
        if a < 0.0 && b >= 0.0 {
            crossings.push(h * ((i - 1) as f64 + a / (a - b)));
        }
    }
    assert!(crossings.len() >= 3, "{} crossings", crossings.len());
    let n = crossings.len() - 1;
    (peak, (crossings[n] - crossings[0]) / n as f64)
}

/// Free vibration under gravity switched on at t = 0 (tip deflection about 2 x 1.4 mm, 1.4e-3 of
/// the length): the superelement of the free bar held at its root interface and the FFR body of
/// the bar clamped there, both from the same hex20 mesh and the same Craig-Bampton basis (rigid
/// tip face, 4 fixed-interface modes), agree in peak tip deflection and period to 1e-3 and in
/// the whole tip history to 1e-3 of the peak.
#[test]
fn solid_superelement_vibrates_like_ffr_body() {
    let names = [
        "tip.position.y",
        "bar.deformation.u1_y",
        "bar.deformation.eta4",
        "bar.frame_iterations.value",
    ];
    let mut se_signals = run_series(&superelement_bar(), "se_bar", &names);
    // the signals of superelement_beam: the tip's local deflection in the floating frame,
    // internal modes, recovery iterations
    let its = se_signals.pop().unwrap();
    let steps = &its[1..]; // the initial row is 0
    assert!(
        steps.iter().all(|&k| (1.0..=30.0).contains(&k)),
        "recovery iterations out of 1..=30"
    );
    assert!(se_signals[2].iter().any(|&v| v != 0.0));
    let local = se_signals[1].iter().copied().fold(0.0, f64::min);
    let se = se_signals.remove(0);
    let names = ["tip.position.y"];
    let ffr = run_series(&ffr_bar(), "ffr_bar", &names).remove(0);
    assert_eq!(se.len(), ffr.len());
    let h = 1e-4;
    let (peak_se, period_se) = peak_and_period(&se, h);
    let (peak_ffr, period_ffr) = peak_and_period(&ffr, h);
    let history = se
        .iter()
        .zip(&ffr)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
        / peak_ffr.abs();
    eprintln!(
        "superelement: peak {peak_se:e} m, period {period_se:e} s; FFR: peak {peak_ffr:e} m, \
         period {period_ffr:e} s; history {history:e} of the peak"
    );
    assert!(peak_ffr < -1e-3, "peak {peak_ffr}");
    // the mean-axes frame turns with the bar: the tip's deflection relative to it (8 % of the
    // global one here) is a fraction of the global deflection, of the same sign
    assert!(
        local < 0.01 * peak_se && local > 0.5 * peak_se,
        "local {local} vs {peak_se}"
    );
    assert!(((peak_se - peak_ffr) / peak_ffr).abs() < 1e-3);
    assert!(((period_se - period_ffr) / period_ffr).abs() < 1e-3);
    assert!(history < 1e-3, "{history:e}");
}

/// The error of compiling a superelement made from `bar_free.toml` with `from` replaced by `to`
/// (written to a work folder).
fn fe_error(tag: &str, from: &str, to: &str) -> String {
    let fe = std::fs::read_to_string(data_dir().join("bar_free.toml")).unwrap();
    assert!(fe.contains(from), "{from}");
    let dir = common::work_dir("sefe_err", tag);
    std::fs::write(dir.join("bar.toml"), fe.replace(from, to)).unwrap();
    let model = "[model]\nname = \"m\"\n[solver]\ntype = \"statics\"\n[[body]]\nname = \"bar\"\n\
                 type = \"superelement\"\nsource = \"bar.toml\"\n";
    let e = compile_model(model, &dir.join("model.toml"))
        .err()
        .unwrap_or_else(|| panic!("{tag}: accepted"))
        .to_string();
    let _ = std::fs::remove_dir_all(&dir);
    eprintln!("{tag}: {e}");
    e
}

/// Bad input is refused at check time with the model file's key and the FE file's line and key:
/// an interface node set not in the mesh, an empty selection, no interface, a selection of
/// several nodes or of a node without rotations, a modal reduction, two bodies sharing an
/// interface that is not at the same place.
#[test]
fn bad_fe_superelements_are_refused_at_keys() {
    let iface = "interface = [\"root\", \"tip\"]";
    let e = fe_error("unknown", iface, "interface = [\"root\", \"nope\"]");
    assert!(e.contains("body[0].source") && e.contains("body.reduction.interface[1]"));
    assert!(e.contains("no node set 'nope'"), "{e}");
    let empty =
        "interface = [\"root\", { within = { min = [5.0, 5.0, 5.0], max = [6.0, 6.0, 6.0] } }]";
    let e = fe_error("empty", iface, empty);
    assert!(e.contains("body.reduction.interface[1]") && e.contains("matches no node"));
    let e = fe_error("none", iface, "interface = []");
    assert!(e.contains("body.reduction.interface") && e.contains("at least one interface"));
    let e = fe_error("several", iface, "interface = [\"root\", \"xmax\"]");
    assert!(
        e.contains("body.reduction.interface[1]") && e.contains("selects 8 nodes"),
        "{e}"
    );
    let e = fe_error(
        "solid_node",
        iface,
        "interface = [\"root\", { nearest = [0.5, 0.0, 0.0] }]",
    );
    assert!(
        e.contains("interface 1 (`i1`") && e.contains("3 independent DOFs"),
        "{e}"
    );
    let e = fe_error("modal", "method = \"craig-bampton\"", "method = \"modal\"");
    assert!(
        e.contains("body.reduction.method") && e.contains("craig-bampton"),
        "{e}"
    );
    // two bodies naming the same interface at different places
    let text = fe_chain().replace("position = [0.1, 0, 0]", "position = [0.15, 0, 0]");
    let e = compiled(&text).expect_err("incompatible shared interface accepted");
    assert!(
        e.contains("body[1].interfaces[0]") && e.contains("must coincide"),
        "{e}"
    );
}

/// The solid bar has no node at its centre of mass: the frame condition is the mass-weighted
/// rigid motion, at the centroid (0.5, 0.01, 0.01) m, with `[Φ_CB][Φ_rig,0] = 1` to round-off;
/// a `[Φ_CB]` that does not describe a rigid motion is refused by the superelement.
#[test]
fn mean_axes_frame_condition_of_a_solid() {
    use flexmbs_core::superelement::{Superelement, SuperelementError};
    let path = data_dir().join("bar_free.toml");
    let spec = flexmbs_io::model_check::FeModelSource::read(&path)
        .unwrap()
        .model
        .body;
    let prepared = flexmbs_reduce::pipeline::prepare(&spec, &data_dir(), &mut |_| {}).unwrap();
    let reduced = flexmbs_reduce::pipeline::run_reduction(&spec, &prepared, &mut |_| {}).unwrap();
    let names = ["root".to_string(), "tip".to_string()];
    let fe = superelement_from_reduced(&prepared.system, &reduced, &names, FeFrame::CentreOfMass)
        .unwrap();
    assert_eq!(fe.condition, FrameCondition::MeanAxes);
    assert!((fe.origin - nalgebra::Vector3::new(0.5, 0.01, 0.01)).norm() < 1e-9);
    let b = &fe.data.phi_cb * fe.data.rigid_modes();
    let dev = (b - nalgebra::DMatrix::<f64>::identity(6, 6)).amax();
    assert!(dev < 1e-8, "{dev:e}");
    // the internal modes move no rigid motion of the frame in the mass-weighted sense
    let mut bad = fe.data.clone();
    bad.phi_cb.column_mut(1).scale_mut(0.5);
    let e = Superelement::new(bad).err().unwrap();
    assert!(
        matches!(e, SuperelementError::SingularFrameCondition { .. }),
        "{e}"
    );
    let interface =
        superelement_from_reduced(&prepared.system, &reduced, &names, FeFrame::FirstInterface)
            .unwrap();
    assert!(interface.origin.norm() < 0.02 && interface.data.interfaces[0].position.norm() == 0.0);
}

//! Stress recovery in a run (issue 11 item 5): `<frame>.stress` signals and the animation's
//! `stress` / `von_mises` point fields of a clamped beam cantilever under a static tip force,
//! against beam theory sigma = M c / I; the same numbers from the FE model file and from its
//! `.fmb.h5` file; the errors of a reduced-body file without stress fields and of a frame that
//! is not on a mesh node.

use crate::common;

use flexmbs_io::body_file::BodyFile;
use flexmbs_io::model_check::FeModelSource;
use flexmbs_io::results::{read_results, RunStatus};
use flexmbs_reduce::pipeline::{prepare, run_reduction};
use flexmbs_reduce::stress::modal_stress_fields;
use flexmbs_sim::compile_model;
use flexmbs_sim::run::{run_model, RunOptions};
use std::path::Path;

/// Aluminium cantilever 1 m, 20 mm (y) x 10 mm (z), 20 beam elements, clamped at x = 0,
/// Craig-Bampton with the tip node as interface: the static response to a tip force is exact.
const PART: &str = r#"
[body]
name = "beam"
[body.mesh]
type = "beam"
start = [0.0, 0.0, 0.0]
end = [1.0, 0.0, 0.0]
elements = 20
section = { shape = "rectangle", width = 0.02, height = 0.01 }
material = { e = 70e9, nu = 0.33, rho = 2700.0 }
[body.boundary]
fixed = [{ nearest = [0.0, 0.0, 0.0] }]
[body.reduction]
method = "craig-bampton"
interface = [{ nearest = [1.0, 0.0, 0.0] }]
modes = 4
"#;

const P: f64 = 20.0; // tip force in -z, N

fn model(source: &Path, output: &str) -> String {
    format!(
        r#"[model]
name = "stress_cantilever"
[solver]
type = "statics"
load_steps = 2
[[body]]
name = "beam"
type = "ffr"
source = {source:?}
[[frame]]
name = "wall"
body = "ground"
[[frame]]
name = "root"
body = "beam"
nearest = [0.0, 0.0, 0.0]
[[frame]]
name = "quarter"
body = "beam"
nearest = [0.25, 0.0, 0.0]
[[frame]]
name = "tip"
body = "beam"
nearest = [1.0, 0.0, 0.0]
[[joint]]
name = "clamp"
type = "fixed"
a = "wall"
b = "beam"
[[load]]
type = "force"
frame = "tip"
vector = [0, 0, "-{P} N"]
[output]
{output}
"#,
        source = source.display().to_string(),
    )
}

const SIGNALS: &str = r#"signals = ["root.stress", "quarter.stress"]"#;

/// Runs `text` in `dir`; the last row of every stress signal component.
fn run(dir: &Path, text: &str) -> Result<Vec<(String, f64)>, String> {
    let file = dir.join("model.toml");
    std::fs::write(&file, text).unwrap();
    let cm = compile_model(text, &file).map_err(|e| e.to_string())?;
    let out = dir.join("out");
    let summary = run_model(&cm, &RunOptions::new(&out), &mut |_| {}).map_err(|e| e.to_string())?;
    assert_eq!(summary.status, RunStatus::Completed);
    let r = read_results(&out.join("results.h5")).unwrap();
    Ok(r.series_names()
        .into_iter()
        .filter(|n| n.contains(".stress."))
        .map(|n| {
            let v = *r.series(&n).unwrap().last().unwrap();
            (n, v)
        })
        .collect())
}

fn value(rows: &[(String, f64)], name: &str) -> f64 {
    rows.iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no series {name} in {rows:?}"))
        .1
}

/// The steps of `flexmbs reduce part.toml -o out`: the body with its modal stress fields.
fn reduce_to_file(part: &Path, out: &Path, with_stress: bool) {
    let src = FeModelSource::read(part).unwrap();
    let spec = &src.model.body;
    let prepared = prepare(spec, part.parent().unwrap(), &mut |_| {}).unwrap();
    let body = run_reduction(spec, &prepared, &mut |_| {}).unwrap();
    let stress = with_stress.then(|| modal_stress_fields(spec, &prepared, &body).unwrap());
    BodyFile {
        stress,
        ..BodyFile::plain(body)
    }
    .write(out)
    .unwrap();
}

/// Beam theory at the clamp and at x = L/4: bending stress at the top fibre
/// sigma = M c / I = P (L - x) (h/2) / (b h^3 / 12) (tension on top: the tip is pushed down),
/// axial and torsion zero, shear P / A; von Mises = |sigma|. The Euler-Bernoulli elements and
/// the Craig-Bampton basis are exact for this load, so the run matches to the statics solver's
/// tolerance (1e-6 relative required); so does the body restricted to its six static modes. The
/// `.fmb.h5` source gives the same numbers (1e-12).
#[test]
fn clamp_stress_signal_matches_beam_theory_from_fe_and_body_file() {
    let dir = common::work_dir("stress", "signals");
    let part = dir.join("beam.toml");
    std::fs::write(&part, PART).unwrap();
    let fe = run(&dir, &model(&part, SIGNALS)).unwrap();
    let (l, b, h) = (1.0, 0.02, 0.01);
    let mc_i = |x: f64| P * (l - x) * (h / 2.0) / (b * h * h * h / 12.0);
    for (frame, x) in [("root", 0.0), ("quarter", 0.25)] {
        let s = |c: &str| value(&fe, &format!("{frame}.stress.{c}"));
        let want = mc_i(x);
        eprintln!(
            "{frame}: von Mises {:e} Pa, M c / I {want:e} Pa",
            s("von_mises")
        );
        assert!(
            (s("bending_y") / want - 1.0).abs() < 1e-6,
            "{}",
            s("bending_y")
        );
        assert!((s("von_mises") / want - 1.0).abs() < 1e-6);
        assert!(s("axial").abs() < 1e-9 * want && s("torsion").abs() < 1e-9 * want);
        assert!(s("bending_z").abs() < 1e-9 * want);
        assert!((s("shear_z") / (-P / (b * h)) - 1.0).abs() < 1e-6);
    }
    // the six static (constraint) modes of the tip node alone span the static response, so the
    // selection `modes = [1..6]` recovers the same stresses (fields restricted with the modes)
    let statics_only = model(&part, SIGNALS).replace(
        "type = \"ffr\"\n",
        "type = \"ffr\"\nmodes = [1, 2, 3, 4, 5, 6]\n",
    );
    assert!(statics_only.contains("modes = [1, 2"));
    let sel = run(&dir, &statics_only).unwrap();
    for ((n, a), (_, c)) in fe.iter().zip(&sel) {
        assert!((a - c).abs() <= 1e-6 * mc_i(0.0), "{n}: {a} vs {c}");
    }
    let h5 = dir.join("beam.fmb.h5");
    reduce_to_file(&part, &h5, true);
    let file = run(&dir, &model(&h5, SIGNALS)).unwrap();
    assert_eq!(fe.len(), file.len());
    for ((n, a), (m, c)) in fe.iter().zip(&file) {
        assert_eq!(n, m);
        assert!((a - c).abs() <= 1e-12 * mc_i(0.0), "{n}: {a} vs {c}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The same part in SI(mm) (mm, t, s; stresses in MPa in the FE model and the body file) gives
/// the same signals in Pa (1e-9 relative), from the FE model file and from its `.fmb.h5`.
#[test]
fn stress_signals_are_si_for_a_millimetre_body() {
    let dir = common::work_dir("stress", "mm");
    let part = dir.join("beam.toml");
    std::fs::write(&part, PART).unwrap();
    let si = run(&dir, &model(&part, SIGNALS)).unwrap();
    let mm = PART
        .replace("name = \"beam\"", "name = \"beam\"\nunits = \"SI(mm)\"")
        .replace("[1.0, 0.0, 0.0]", "[1000.0, 0.0, 0.0]")
        .replace("width = 0.02, height = 0.01", "width = 20.0, height = 10.0")
        .replace(
            "e = 70e9, nu = 0.33, rho = 2700.0",
            "e = 70000.0, nu = 0.33, rho = 2.7e-9",
        );
    assert_eq!(mm.matches("1000.0").count(), 2);
    let part_mm = dir.join("beam_mm.toml");
    std::fs::write(&part_mm, &mm).unwrap();
    let h5 = dir.join("beam_mm.fmb.h5");
    reduce_to_file(&part_mm, &h5, true);
    let scale = si.iter().map(|(_, v)| v.abs()).fold(0.0, f64::max);
    for src in [&part_mm, &h5] {
        let got = run(&dir, &model(src, SIGNALS)).unwrap();
        assert_eq!(got.len(), si.len());
        for ((n, a), (_, b)) in si.iter().zip(&got) {
            assert!((a - b).abs() <= 1e-9 * scale, "{n}: {a} vs {b}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `output.stress = true` writes the point fields `stress` (6 components) and `von_mises` into
/// every animation frame.
#[test]
fn animation_has_stress_point_fields() {
    let dir = common::work_dir("stress", "anim");
    let part = dir.join("beam.toml");
    std::fs::write(&part, PART).unwrap();
    run(&dir, &model(&part, "stress = true")).unwrap();
    let frames = dir.join("out/stress_cantilever_frames");
    let last = std::fs::read_dir(&frames)
        .unwrap()
        .map(|e| e.unwrap().path())
        .max()
        .unwrap();
    let vtu = std::fs::read_to_string(&last).unwrap();
    assert!(
        vtu.contains(r#"Name="stress" NumberOfComponents="6""#),
        "{}",
        &vtu[..vtu.len().min(2000)]
    );
    assert!(vtu.contains(r#"Name="von_mises""#));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A `.fmb.h5` without stress fields (written before they existed) is refused where stress is
/// asked for, naming the fix; a frame that is not on a mesh node and `stress = true` without the
/// animation are refused with the reason.
#[test]
fn stress_requests_without_fields_are_refused_with_the_fix() {
    let dir = common::work_dir("stress", "errors");
    let part = dir.join("beam.toml");
    std::fs::write(&part, PART).unwrap();
    let h5 = dir.join("old.fmb.h5");
    reduce_to_file(&part, &h5, false);
    for output in [SIGNALS, "stress = true"] {
        let e = run(&dir, &model(&h5, output)).unwrap_err();
        assert!(
            e.contains("no modal stress fields") && e.contains("re-run `flexmbs reduce`"),
            "{e}"
        );
        let key = if output == SIGNALS {
            "output.signals[0]"
        } else {
            "output.stress"
        };
        assert!(e.contains(key), "{e}");
    }
    let e = run(&dir, &model(&part, r#"signals = ["beam.stress"]"#)).unwrap_err();
    assert!(
        e.contains("not a node frame") && e.contains("output.signals[0]"),
        "{e}"
    );
    let e = run(&dir, &model(&part, "stress = true\nanimation = false")).unwrap_err();
    assert!(
        e.contains("output.stress") && e.contains("animation"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

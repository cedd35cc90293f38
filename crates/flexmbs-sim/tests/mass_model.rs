//! FFR body key `inertia = "lumped" | "consistent"` and the automatic lumped node rotary inertias
//! of beam meshes: clamped bodies (reference frame fixed to ground) hit by a short pulse vibrate
//! freely afterwards at the FE modal frequency of the selected mode.

use crate::common;

use flexmbs_core::ffr::{reduced_body_to_si, FfrBody, RotaryInertia, RotationParam};
use flexmbs_io::results::{read_results, RunStatus};
use flexmbs_sim::bodies::load_reduced_with_fe;
use flexmbs_sim::compile_model;
use flexmbs_sim::mass_model::beam_rotary_inertias;
use flexmbs_sim::run::{run_model, RunOptions};
use flexmbs_validate::complex_beam_frequencies::zero_crossing_frequency;
use std::path::Path;

/// Clamped FFR body `source` with `extra` body keys, a load `load_vector` (type `load`) at the
/// frame nearest `tip` for `pulse`, step `h`, end `t_end`; returns `(t, series)` of `signals`.
#[allow(clippy::too_many_arguments)]
fn run_clamped(
    dir: &Path,
    source: &Path,
    extra: &str,
    tip: &str,
    load: &str,
    load_vector: &str,
    pulse: &str,
    h: &str,
    t_end: &str,
    signals: &[&str],
) -> (Vec<f64>, Vec<Vec<f64>>) {
    let list: Vec<String> = signals
        .iter()
        .map(|s| format!("\"{}\"", s.rsplit_once('.').unwrap().0))
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    let text = format!(
        r#"
[model]
name = "clamped"
[solver]
type = "generalized-alpha"
h = "{h}"
t_end = "{t_end}"
[[body]]
name = "body"
type = "ffr"
source = "{source}"
{extra}
[[frame]]
name = "wall"
body = "ground"
[[frame]]
name = "tip"
body = "body"
nearest = {tip}
[[joint]]
name = "clamp"
type = "fixed"
a = "wall"
b = "body"
[[load]]
type = "{load}"
frame = "tip"
vector = {load_vector}
time = {{ type = "pulse", t0 = 0, t1 = "{pulse}", value = 1 }}
[output]
signals = [{}]
animation = false
"#,
        list.join(", "),
        source = source.display(),
    );
    let file = dir.join("model.toml");
    std::fs::write(&file, &text).unwrap();
    let cm = compile_model(&text, &file).unwrap();
    let out = dir.join("out");
    let summary = run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    assert_eq!(summary.status, RunStatus::Completed);
    let r = read_results(&out.join("results.h5")).unwrap();
    let series = signals
        .iter()
        .map(|s| r.series(s).unwrap().to_vec())
        .collect();
    (r.time.clone(), series)
}

/// Zero-crossing frequency (Hz) of the larger of `series` for `t > t_after`.
fn free_frequency(t: &[f64], series: &[Vec<f64>], t_after: f64) -> f64 {
    let amp = |x: &Vec<f64>| x.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let x = series
        .iter()
        .max_by(|a, b| amp(a).total_cmp(&amp(b)))
        .unwrap();
    let keep: Vec<usize> = (0..t.len()).filter(|&i| t[i] > t_after).collect();
    let ta: Vec<f64> = keep.iter().map(|&i| t[i]).collect();
    let xa: Vec<f64> = keep.iter().map(|&i| x[i]).collect();
    zero_crossing_frequency(&ta, &xa).expect("no oscillation")
}

/// A beam body with its torsion mode selected. Without node rotary inertia the torsion mode
/// moves no node mass: its translational modal mass is < 1e-12 (the model-file run failed with
/// "singular augmented mass matrix at t = 0" before rotary inertias were added). With the lumped
/// beam rotary inertias, `m_ff + D = Phi^T M_lumped Phi = I` (1e-10, mass-normalised modes), and
/// the tip twist after a 0.1 ms torque pulse oscillates at the FE torsion frequency (0.5 %).
#[test]
fn beam_torsion_mode_runs_with_lumped_rotary_inertia() {
    let dir = common::work_dir("mass", "torsion");
    let part = dir.join("part.toml");
    std::fs::write(&part, common::SHAFT).unwrap();
    let (reduced, fe) =
        load_reduced_with_fe(&part, &dir, "shaft", flexmbs_fe::UnitSystem::Si).unwrap();
    let fe = fe.unwrap();
    let si = reduced_body_to_si(&reduced);
    let nf = si.num_modes();
    let mr = si
        .modes_r
        .as_ref()
        .expect("beam body without rotational modes");
    let col_norm = |m: &faer::Mat<f64>, k: usize| {
        (0..m.nrows())
            .map(|i| m[(i, k)] * m[(i, k)])
            .sum::<f64>()
            .sqrt()
    };
    let torsion = (0..nf)
        .find(|&k| col_norm(&si.modes_t, k) < 1e-8 * col_norm(mr, k))
        .expect("no torsion mode among the 12");
    let f_torsion = si.frequencies_hz[torsion];
    eprintln!("torsion: mode {} at {f_torsion} Hz", torsion + 1);

    let plain = FfrBody::from_reduced(&si, RotationParam::Cardan).unwrap();
    let m_tt = plain.invariants.m_ff[(torsion, torsion)];
    assert!(
        m_tt.abs() < 1e-12,
        "translational torsion modal mass {m_tt}"
    );
    let inertias = beam_rotary_inertias(&fe, &reduced).unwrap().unwrap();
    let rot = RotaryInertia::new(&plain, &inertias).unwrap();
    let mut dev = 0.0f64;
    for i in 0..nf {
        for j in 0..nf {
            let m = plain.invariants.m_ff[(i, j)] + rot.d[(i, j)];
            dev = dev.max((m - if i == j { 1.0 } else { 0.0 }).abs());
        }
    }
    eprintln!("max |m_ff + D - I| = {dev:e}");
    assert!(dev < 1e-10, "m_ff + D deviates from I by {dev:e}");

    let extra = format!("modes = [1, {}]", torsion + 1);
    let (t, s) = run_clamped(
        &dir,
        &part,
        &extra,
        "[1.0, 0.0, 0.0]",
        "torque",
        "[\"1 N m\", 0, 0]",
        "0.1 ms",
        "0.01 ms",
        "10 ms",
        &["tip.orientation.x"],
    );
    let f = free_frequency(&t, &s, 0.11e-3);
    let err = (f - f_torsion) / f_torsion;
    eprintln!(
        "simulated torsion {f} Hz vs FE {f_torsion} Hz ({:.4} %)",
        100.0 * err
    );
    assert!(err.abs() < 5e-3, "torsion {f} Hz vs FE {f_torsion} Hz");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Steel cantilever 200 x 20 x 10 mm of 10 x 1 x 1 Hex20, clamped at x = 0, FE mass `{mass}`.
const SOLID_PART: &str = r#"
[body]
name = "plate"
[body.mesh]
type = "box"
size = [0.2, 0.02, 0.01]
divisions = [10, 1, 1]
element = "hex20"
material = { e = 210e9, nu = 0.3, rho = 7850.0 }
[body.boundary]
fixed = ["xmin"]
[body.reduction]
method = "modal"
modes = 4
mass = "{mass}"
"#;

/// The same small solid body (first mode only) as `inertia = "consistent"` (FE mass consistent)
/// and `inertia = "lumped"` (FE mass lumped): both run, and since the invariants come from the
/// mass the modes are normalised with (`m_ff = 1`), the free vibration after a 0.2 ms tip pulse
/// has the FE frequency of the respective discretisation (0.5 %). The lumped model on the
/// consistent FE mass (no lumped node masses) and the consistent model on the lumped FE mass are
/// rejected at `body[0].inertia` / `body[0].source` with a hint to the other choice; consistent
/// invariants compile together with `geometric_stiffening` and a mode list.
#[test]
fn consistent_and_lumped_solid_body_both_run() {
    let dir = common::work_dir("mass", "solid");
    let mut f_fe = Vec::new();
    for model in ["consistent", "lumped"] {
        let part = dir.join(format!("{model}.toml"));
        std::fs::write(&part, SOLID_PART.replace("{mass}", model)).unwrap();
        let (reduced, _) =
            load_reduced_with_fe(&part, &dir, "plate", flexmbs_fe::UnitSystem::Si).unwrap();
        let f1 = reduced.frequencies_hz[0];
        let (t, s) = run_clamped(
            &dir,
            &part,
            &format!("modes = 1\ninertia = \"{model}\""),
            "[0.2, 0.01, 0.005]",
            "force",
            "[0, \"10 N\", \"10 N\"]",
            "0.2 ms",
            "0.02 ms",
            "20 ms",
            &["tip.deformation.y", "tip.deformation.z"],
        );
        let f = free_frequency(&t, &s, 0.22e-3);
        let err = (f - f1) / f1;
        eprintln!("{model}: {f} Hz vs FE {f1} Hz ({:.4} %)", 100.0 * err);
        assert!(err.abs() < 5e-3, "{model}: {f} Hz vs FE {f1} Hz");
        f_fe.push(f1);
    }
    eprintln!("FE f1: consistent {} Hz, lumped {} Hz", f_fe[0], f_fe[1]);
    // consistent invariants with geometric stiffening and a reordered mode selection: compiles
    // with the two selected modes (3 + 3 + 2 coordinates)
    let part = dir.join("consistent.toml");
    let text = format!(
        "[model]\nname = \"x\"\n[solver]\ntype = \"generalized-alpha\"\nh = \"1 ms\"\n\
         t_end = \"1 ms\"\n[[body]]\nname = \"b\"\ntype = \"ffr\"\nsource = \"{}\"\n\
         inertia = \"consistent\"\ngeometric_stiffening = true\nmodes = [3, 1]\n",
        part.display()
    );
    let cm = compile_model(&text, &dir.join("model.toml")).unwrap();
    assert_eq!(cm.bodies[0].geometry.modes, 2);
    assert_eq!(cm.model.nq, 8);
    // crossed choices are rejected with a hint
    for (fe_mass, model, path, fragment) in [
        (
            "lumped",
            "consistent",
            "body[0].inertia",
            "set `mass = \"consistent\"`",
        ),
        (
            "consistent",
            "lumped",
            "body[0].source",
            "set `inertia = \"consistent\"`",
        ),
    ] {
        let part = dir.join(format!("{fe_mass}.toml"));
        let text = format!(
            "[model]\nname = \"x\"\n[solver]\ntype = \"generalized-alpha\"\nh = \"1 ms\"\n\
             t_end = \"1 ms\"\n[[body]]\nname = \"b\"\ntype = \"ffr\"\nsource = \"{}\"\n\
             inertia = \"{model}\"\n",
            part.display()
        );
        let err = compile_model(&text, &dir.join("model.toml")).unwrap_err();
        let msg = err.to_string();
        let flexmbs_sim::SimError::Model { path: p, .. } = &err else {
            panic!("not a model error: {msg}");
        };
        assert_eq!(p, path, "{msg}");
        assert!(msg.contains(fragment), "{msg}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `inertia = "consistent"` on the CalculiX cantilever (`examples/calculix_beam.toml`,
/// `matrices = "ccx"`, first mode 16.73174 Hz): the free vibration after a 1 ms tip pulse has the
/// FE frequency (0.5 %). Skipped, with the reason printed, without `ccx`.
#[test]
fn consistent_ccx_body_matches_modal_frequency() {
    if flexmbs_io::test_tools::ccx_or_skip("consistent_ccx_body_matches_modal_frequency").is_none()
    {
        return;
    }
    let dir = common::work_dir("mass", "ccx");
    let part = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/calculix_beam.toml")
        .canonicalize()
        .unwrap();
    let (t, s) = run_clamped(
        &dir,
        &part,
        "modes = 1\ninertia = \"consistent\"",
        "[1.0, 0.01, 0.01]",
        "force",
        "[0, \"10 N\", \"10 N\"]",
        "1 ms",
        "0.5 ms",
        "0.3 s",
        &["tip.deformation.y", "tip.deformation.z"],
    );
    let f = free_frequency(&t, &s, 1.1e-3);
    let f1 = 16.73174;
    eprintln!(
        "ccx consistent: {f} Hz vs FE {f1} Hz ({:.4} %)",
        100.0 * (f - f1) / f1
    );
    assert!(((f - f1) / f1).abs() < 5e-3, "{f} Hz vs {f1} Hz");
    let _ = std::fs::remove_dir_all(&dir);
}

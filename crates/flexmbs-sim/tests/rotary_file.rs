//! Beam node rotary inertias stored in a reduced-body file (`nodes/rotary_inertia`): a beam body
//! reduced like `flexmbs reduce` does gives the same trajectory from the `.fmb.h5` file as from
//! its FE model file, with the default `rotary_inertia` (on), in SI and SI(mm); the key's
//! opt-out and its errors work on `.fmb.h5` sources as on FE sources.

use crate::common;

use flexmbs_io::body_file::{write_body, BodyFile};
use flexmbs_io::model_check::FeModelSource;
use flexmbs_io::results::{read_results, RunStatus};
use flexmbs_reduce::full_mass::beam_node_rotary_inertias;
use flexmbs_reduce::pipeline::{prepare, run_reduction};
use flexmbs_sim::run::{run_model, RunOptions};
use flexmbs_sim::{compile_model, SimError};
use std::path::Path;

/// The shaft in SI(mm) (mm, t, s): the same body, numbers scaled.
fn shaft_mm() -> String {
    let s = common::SHAFT
        .replace("name = \"shaft\"", "name = \"shaft\"\nunits = \"SI(mm)\"")
        .replace("end = [1.0, 0.0, 0.0]", "end = [1000.0, 0.0, 0.0]")
        .replace("width = 0.02, height = 0.02", "width = 20.0, height = 20.0")
        .replace(
            "e = 210e9, nu = 0.3, rho = 7850.0",
            "e = 210000.0, nu = 0.3, rho = 7.85e-9",
        );
    assert!(s.contains("SI(mm)") && s.contains("1000.0") && s.contains("7.85e-9"));
    s
}

/// The steps of `flexmbs reduce part.toml -o out --no-geometric`: prepare, reduce, store the
/// body with the node rotary inertias of the beam mesh (body units).
fn reduce_to_file(part: &Path, out: &Path) -> BodyFile {
    let src = FeModelSource::read(part).unwrap();
    let spec = &src.model.body;
    let prepared = prepare(spec, part.parent().unwrap(), &mut |_| {}).unwrap();
    let body = run_reduction(spec, &prepared, &mut |_| {}).unwrap();
    let rotary_inertia = beam_node_rotary_inertias(&prepared.mesh, body.num_nodes()).unwrap();
    let f = BodyFile {
        body,
        geometric: None,
        rotary_inertia,
        stress: None,
        inertia_gram: None,
    };
    f.write(out).unwrap();
    f
}

/// Clamped shaft (`source`, extra body keys `extra`) hit at the tip for 0.1 ms by a torque about
/// x and a transverse force, 2 ms with h = 0.01 ms.
fn model_text(source: &Path, extra: &str) -> String {
    format!(
        r#"[model]
name = "clamped_shaft"
[solver]
type = "generalized-alpha"
h = "0.01 ms"
t_end = "2 ms"
[[body]]
name = "shaft"
type = "ffr"
source = {source:?}
{extra}
[[frame]]
name = "wall"
body = "ground"
[[frame]]
name = "tip"
body = "shaft"
nearest = [1.0, 0.0, 0.0]
[[joint]]
name = "clamp"
type = "fixed"
a = "wall"
b = "shaft"
[[load]]
type = "torque"
frame = "tip"
vector = ["1 N m", 0, 0]
time = {{ type = "pulse", t0 = 0, t1 = "0.1 ms", value = 1 }}
[[load]]
type = "force"
frame = "tip"
vector = [0, "20 N", "10 N"]
time = {{ type = "pulse", t0 = 0, t1 = "0.1 ms", value = 1 }}
[output]
signals = ["tip.orientation", "tip.deformation"]
animation = false
"#,
        source = source.display().to_string(),
    )
}

/// Runs the model text (written to `dir/model.toml`); the tip twist and the tip deflections
/// `[orientation.x, deformation.y, deformation.z]`, or the compile/run error.
fn run(dir: &Path, text: &str) -> Result<Vec<Vec<f64>>, String> {
    let file = dir.join("model.toml");
    std::fs::write(&file, text).unwrap();
    let cm = compile_model(text, &file).map_err(|e| e.to_string())?;
    let out = dir.join("out");
    let summary = run_model(&cm, &RunOptions::new(&out), &mut |_| {}).map_err(|e| e.to_string())?;
    if summary.status != RunStatus::Completed {
        return Err(format!("run ended with {:?}", summary.status));
    }
    let r = read_results(&out.join("results.h5")).unwrap();
    let s = [
        "tip.orientation.x",
        "tip.deformation.y",
        "tip.deformation.z",
    ]
    .iter()
    .map(|s| r.series(s).unwrap().to_vec())
    .collect();
    let _ = std::fs::remove_dir_all(&out);
    Ok(s)
}

/// Largest `max |a - b| / max |a|` over the series.
fn max_rel_diff(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            assert_eq!(x.len(), y.len());
            let amax = x.iter().map(|v| v.abs()).fold(0.0, f64::max);
            assert!(amax > 0.0);
            let d = x
                .iter()
                .zip(y)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max);
            d / amax
        })
        .fold(0.0, f64::max)
}

/// The stored node inertias match the lumped beam mass independently: summed over the nodes,
/// `I_xx = rho (I_y + I_z) L` (torsion, `rho I_p l/2` per element end) and
/// `I_yy = I_zz = rho A L l^2/39 + rho I L` (`rho A l^3/78 + rho I l/2` per end, l = L/10),
/// off-diagonals zero (beam along x); 1e-12 relative, in SI and, scaled by kg m² -> t mm² =
/// 1e3, in SI(mm). Then the FE-model source and the `.fmb.h5` source give the same tip twist and
/// deflections to 1e-12 relative, with the default rotary inertias, all 12 modes and the
/// selection `modes = [1, 9]` (first bending and torsion, which needs the rotary inertias).
#[test]
fn body_file_source_matches_fe_source_with_rotary_inertia() {
    let dir = common::work_dir("rotfile", "traj");
    let (rho, a, i, l) = (7850.0, 4e-4, 0.02f64.powi(4) / 12.0, 1.0);
    let ixx = rho * 2.0 * i * l;
    let iyy = rho * a * l * (l / 10.0).powi(2) / 39.0 + rho * i * l;
    for (tag, text, scale) in [
        ("si", common::SHAFT.to_string(), 1.0),
        ("mm", shaft_mm(), 1e3),
    ] {
        let part = dir.join(format!("shaft_{tag}.toml"));
        std::fs::write(&part, text).unwrap();
        let h5 = dir.join(format!("shaft_{tag}.fmb.h5"));
        let written = reduce_to_file(&part, &h5);
        let r = written
            .rotary_inertia
            .as_ref()
            .expect("beam mesh: inertias");
        assert_eq!(r.len(), 11);
        let sum: nalgebra::Matrix3<f64> = r.iter().sum();
        let expected = nalgebra::Matrix3::from_diagonal(&nalgebra::Vector3::new(ixx, iyy, iyy));
        let dev = (sum / scale - expected).abs().max() / ixx.max(iyy);
        eprintln!(
            "{tag}: sum of node inertias {:?}, rel. dev {dev:e}",
            sum.diagonal()
        );
        assert!(dev < 1e-12, "{tag}: {sum} vs {expected}");

        for modes in ["", "modes = [1, 9]"] {
            let fe = run(&dir, &model_text(&part, modes)).unwrap();
            let file = run(&dir, &model_text(&h5, modes)).unwrap();
            let d = max_rel_diff(&fe, &file);
            let twist = fe[0].iter().map(|v| v.abs()).fold(0.0, f64::max);
            eprintln!(
                "{tag} [{modes}]: FE vs .fmb.h5: max rel diff {d:e} ({} samples, max twist {twist:e} rad)",
                fe[0].len()
            );
            assert!(fe[0].len() > 150 && twist > 1e-5, "{twist}");
            assert!(d <= 1e-12, "{tag} [{modes}]: {d:e}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `rotary_inertia = false` drops the stored inertias: with the torsion mode selected the run
/// fails as for the FE source (the torsion mode moves no node mass: singular mass matrix), and
/// with bending modes only both sources agree to 1e-12 and differ from the default (inertias on)
/// by more than 1e-6 relative, so the stored inertias are really applied.
#[test]
fn rotary_inertia_false_opts_out_for_body_files() {
    let dir = common::work_dir("rotfile", "off");
    let part = dir.join("shaft.toml");
    std::fs::write(&part, common::SHAFT).unwrap();
    let h5 = dir.join("shaft.fmb.h5");
    reduce_to_file(&part, &h5);
    for src in [&part, &h5] {
        let e = run(
            &dir,
            &model_text(src, "modes = [1, 9]\nrotary_inertia = false"),
        )
        .unwrap_err();
        eprintln!("{}: {e}", src.display());
        assert!(e.contains("singular"), "{e}");
    }
    let off = "modes = [1, 2, 3]\nrotary_inertia = false";
    let fe_off = run(&dir, &model_text(&part, off)).unwrap();
    let h5_off = run(&dir, &model_text(&h5, off)).unwrap();
    let h5_on = run(&dir, &model_text(&h5, "modes = [1, 2, 3]")).unwrap();
    let same = max_rel_diff(&fe_off[1..], &h5_off[1..]);
    let effect = max_rel_diff(&h5_on[1..], &h5_off[1..]);
    eprintln!("bending only, off: FE vs file {same:e}; file on vs off {effect:e}");
    assert!(same <= 1e-12, "{same:e}");
    assert!(effect > 1e-6, "{effect:e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `rotary_inertia = true` on a `.fmb.h5` file without stored inertias (written without them,
/// as by older versions, or from a solid mesh) is an error at `body[0].rotary_inertia` and its
/// line that says how to re-export; without the key such a file compiles (no inertias).
#[test]
fn rotary_inertia_true_on_file_without_them_is_located() {
    let dir = common::work_dir("rotfile", "errs");
    let part = dir.join("shaft.toml");
    std::fs::write(&part, common::SHAFT).unwrap();
    let f = reduce_to_file(&part, &dir.join("full.fmb.h5"));
    let plain = dir.join("plain.fmb.h5");
    write_body(&plain, &f.body).unwrap();
    let text = model_text(&plain, "modes = [1, 2]\nrotary_inertia = true");
    let file = dir.join("model.toml");
    let err: SimError = compile_model(&text, &file).unwrap_err();
    let msg = err.to_string();
    let line = text
        .lines()
        .position(|l| l == "rotary_inertia = true")
        .unwrap()
        + 1;
    assert_eq!(err.path(), Some("body[0].rotary_inertia"), "{msg}");
    assert_eq!(err.line(), Some(line), "{msg}");
    assert!(
        msg.contains("has no node rotary inertias")
            && msg.contains("re-export it with `flexmbs reduce` from the FE model file"),
        "{msg}"
    );
    assert!(compile_model(&model_text(&plain, "modes = [1, 2]"), &file).is_ok());
    assert!(compile_model(
        &model_text(&dir.join("full.fmb.h5"), "rotary_inertia = true"),
        &file
    )
    .is_ok());
    let _ = std::fs::remove_dir_all(&dir);
}

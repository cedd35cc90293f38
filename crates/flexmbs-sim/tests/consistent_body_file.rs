//! The consistent inertia kept in a reduced-body file (dataset `inertia/gram`): a solid body with
//! consistent FE mass, reduced as `flexmbs reduce` does, runs from its `.fmb.h5` file exactly as
//! from the FE model file, also with a subset of its modes; files without the dataset read as
//! before.

use crate::common;

use flexmbs_core::ffr::{
    consistent_mass_to_si, gram_to_si, reduced_body_to_si, restrict_gram, FfrInvariants,
};
use flexmbs_io::body_file::{read_body_file, BodyFile};
use flexmbs_io::results::read_results;
use flexmbs_reduce::body_file::{body_file_of, prepare_for_body_file};
use flexmbs_reduce::pipeline::run_reduction;
use flexmbs_sim::bodies::load_fe_body;
use flexmbs_sim::compile_model;
use flexmbs_sim::run::{run_model, RunOptions};
use std::path::Path;

/// Steel bar 200 x 20 x 10 mm of 10 x 1 x 1 Hex20 in SI(mm) (so that the stored matrix is
/// converted to SI), supports at x = 0 (for the modes only), FE mass `{mass}`, 4 modes.
const PART: &str = r#"
[body]
name = "bar"
units = "SI(mm)"
[body.mesh]
type = "box"
size = [200.0, 20.0, 10.0]
divisions = [10, 1, 1]
element = "hex20"
material = { e = 210000.0, nu = 0.3, rho = 7.85e-9 }
[body.boundary]
fixed = ["xmin"]
[body.reduction]
method = "modal"
modes = 4
mass = "{mass}"
"#;

/// Reduces the FE model file `part` as `flexmbs reduce` does and writes `out`.
fn reduce_to_file(part: &Path, out: &Path) -> BodyFile {
    let src = flexmbs_io::model_check::FeModelSource::read(part).unwrap();
    let spec = &src.model.body;
    let base = part.parent().unwrap();
    let (prepared, m) = prepare_for_body_file(spec, base, &mut |_| {}).unwrap();
    let body = run_reduction(spec, &prepared, &mut |_| {}).unwrap();
    let (f, _) = body_file_of(spec, &prepared, m.as_ref(), body, false, &mut |_| {}).unwrap();
    f.write(out).unwrap();
    f
}

/// A pendulum: the bar hinged to ground about z at its root corner node, under gravity along -y, starting at
/// rest horizontal; `source` and `extra` body keys; returns every `q/` series.
fn run_pendulum(dir: &Path, tag: &str, source: &Path, extra: &str) -> Vec<(String, Vec<f64>)> {
    let text = format!(
        r#"
[model]
name = "pendulum"
gravity = [0, -9.81, 0]
[solver]
type = "generalized-alpha"
h = "0.1 ms"
t_end = "20 ms"
[[body]]
name = "bar"
type = "ffr"
source = "{}"
{extra}
[[frame]]
name = "pivot"
body = "ground"
[[frame]]
name = "root"
body = "bar"
nearest = [0.0, 0.0, 0.0]
[[joint]]
name = "hinge"
type = "revolute"
a = "pivot"
b = "root"
[output]
animation = false
"#,
        source.display()
    );
    let file = dir.join(format!("{tag}.toml"));
    std::fs::write(&file, &text).unwrap();
    let cm = compile_model(&text, &file).unwrap();
    let out = dir.join(tag);
    run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    let r = read_results(&out.join("results.h5")).unwrap();
    r.series_names()
        .into_iter()
        .filter(|n| n.starts_with("q/"))
        .map(|n| {
            let s = r.series(&n).unwrap();
            (n, s)
        })
        .collect()
}

/// Largest difference of two runs' series, relative to the largest value of each series, at
/// least 1e-10 (the out-of-plane modes stay at round-off level, 1e-18, and are compared
/// absolutely).
fn max_relative_difference(a: &[(String, Vec<f64>)], b: &[(String, Vec<f64>)]) -> f64 {
    assert_eq!(a.len(), b.len());
    let mut d = 0.0f64;
    for ((na, xa), (nb, xb)) in a.iter().zip(b) {
        assert_eq!(na, nb);
        assert_eq!(xa.len(), xb.len(), "{na}");
        let scale = xa.iter().map(|v| v.abs()).fold(1e-10, f64::max);
        for (u, v) in xa.iter().zip(xb) {
            d = d.max((u - v).abs() / scale);
        }
    }
    d
}

/// The stored Gram matrix gives the invariants of the FE mass matrix (SI(mm) file, converted to
/// SI) to 1e-12 relative, for all modes and for the modes `[3, 1]` (restricted matrix vs the
/// projection of the restricted modes); the pendulum run from the `.fmb.h5` file equals the run
/// from the FE model file to 1e-12 relative in every coordinate, for both mode sets.
#[test]
fn consistent_inertia_from_body_file_equals_fe_model() {
    let dir = common::work_dir("gram", "solid");
    let part = dir.join("bar.toml");
    std::fs::write(&part, PART.replace("{mass}", "consistent")).unwrap();
    let file = dir.join("bar.fmb.h5");
    let written = reduce_to_file(&part, &file);
    let back = read_body_file(&file).unwrap();
    assert_eq!(back, written, "round trip");
    let g = back.inertia_gram.expect("no inertia/gram in the body file");
    assert_eq!(g.nrows(), 4 + 3 * 4);

    // invariants: FE mass matrix (SI) vs stored matrix (converted)
    let loaded = load_fe_body(&part, &dir, "bar", flexmbs_fe::UnitSystem::Si, true).unwrap();
    let m_si = consistent_mass_to_si(loaded.full_mass.as_ref().unwrap(), loaded.reduced.units);
    for cols in [vec![0, 1, 2, 3], vec![2, 0]] {
        let si = reduced_body_to_si(&loaded.reduced.restricted_to(&cols));
        let fe = FfrInvariants::from_consistent(&si.nodes, &m_si, si.modes_t.as_ref()).unwrap();
        let sub = restrict_gram(&g, 4, &cols).unwrap();
        let stored =
            FfrInvariants::from_gram(&gram_to_si(&sub, cols.len(), back.body.units), cols.len())
                .unwrap();
        let scale = fe.i_kl.abs().max().max(fe.m_ff.abs().max()).max(fe.i1);
        let d = fe.max_abs_difference(&stored);
        eprintln!("modes {cols:?}: max |invariant difference| = {d:e} (scale {scale:e})");
        assert!(d <= 1e-12 * scale, "modes {cols:?}: {d:e}");
        // the modal mass of mass-normalised modes is the identity (independent of G)
        for i in 0..cols.len() {
            assert!(
                (stored.m_ff[(i, i)] - 1.0).abs() < 1e-9,
                "m_ff {}",
                stored.m_ff
            );
        }
        // total mass = rho V = 7850 * 0.2 * 0.02 * 0.01
        assert!((stored.i1 - 0.314).abs() < 1e-12, "mass {}", stored.i1);
    }

    // trajectories: FE model file vs body file
    for (tag, modes) in [("all", "modes = 4"), ("sub", "modes = [3, 1]")] {
        let extra = format!("{modes}\ninertia = \"consistent\"");
        let a = run_pendulum(&dir, &format!("fe-{tag}"), &part, &extra);
        let b = run_pendulum(&dir, &format!("file-{tag}"), &file, &extra);
        let d = max_relative_difference(&a, &b);
        let swing = a.iter().find(|(n, _)| n == "q/bar.theta_z").unwrap();
        eprintln!(
            "{modes}: max relative difference {d:e} over {} coordinates ({} rows, theta_z end {:.6})",
            a.len(),
            swing.1.len(),
            swing.1.last().unwrap()
        );
        assert!(
            swing.1.last().unwrap().abs() > 1e-3,
            "the pendulum did not swing"
        );
        assert!(d <= 1e-12, "{modes}: {d:e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Files without `inertia/gram`: a lumped-mass body is reduced without it and runs with its node
/// masses as before; a consistent-mass body file with the dataset removed (as written before it
/// existed) reads, and `inertia = "consistent"` is refused at `body[0].inertia` naming the
/// dataset and the fix; a file with the dataset and the default (lumped) inertia is refused at
/// `body[0].source` with the hint to set `inertia = "consistent"`.
#[test]
fn body_files_without_consistent_inertia_read_as_before() {
    let dir = common::work_dir("gram", "old");
    let lumped = dir.join("lumped.toml");
    std::fs::write(&lumped, PART.replace("{mass}", "lumped")).unwrap();
    let lumped_file = dir.join("lumped.fmb.h5");
    let f = reduce_to_file(&lumped, &lumped_file);
    assert!(f.inertia_gram.is_none() && f.body.node_masses.is_some());
    let q = run_pendulum(&dir, "lumped", &lumped_file, "");
    assert!(q.iter().all(|(_, s)| s.iter().all(|v| v.is_finite())));

    let part = dir.join("bar.toml");
    std::fs::write(&part, PART.replace("{mass}", "consistent")).unwrap();
    let with = dir.join("with.fmb.h5");
    let f = reduce_to_file(&part, &with);
    let old = dir.join("old.fmb.h5");
    BodyFile {
        inertia_gram: None,
        ..f
    }
    .write(&old)
    .unwrap();
    assert!(read_body_file(&old).unwrap().inertia_gram.is_none());
    let model = |source: &Path, extra: &str| {
        format!(
            "[model]\nname = \"x\"\n[solver]\ntype = \"generalized-alpha\"\nh = \"1 ms\"\n\
             t_end = \"1 ms\"\n[[body]]\nname = \"b\"\ntype = \"ffr\"\nsource = \"{}\"\n{extra}\n",
            source.display()
        )
    };
    for (source, extra, path, fragment) in [
        (
            &old,
            "inertia = \"consistent\"",
            "body[0].inertia",
            "stores no consistent inertia (dataset `inertia/gram`): re-export it with `flexmbs reduce`",
        ),
        (
            &with,
            "",
            "body[0].source",
            "the file stores the consistent inertia: set `inertia = \"consistent\"`",
        ),
    ] {
        let err = compile_model(&model(source, extra), &dir.join("m.toml")).unwrap_err();
        let msg = err.to_string();
        let flexmbs_sim::SimError::Model { path: p, .. } = &err else {
            panic!("not a model error: {msg}");
        };
        assert_eq!(p, path, "{msg}");
        assert!(msg.contains(fragment), "{msg}");
        assert!(!msg.contains("FfrInvariants"), "{msg}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The CalculiX cantilever (`examples/calculix_beam.toml`, `matrices = "ccx"`, 6 modes): reduced
/// as `flexmbs reduce` does, the file stores the consistent inertia, and its invariants equal those
/// of the full mass matrix the model compiler exports (1e-12 relative); skipped without `ccx`.
#[test]
fn calculix_body_file_keeps_the_consistent_inertia() {
    if flexmbs_io::test_tools::ccx_or_skip("calculix_body_file_keeps_the_consistent_inertia")
        .is_none()
    {
        return;
    }
    let dir = common::work_dir("gram", "ccx");
    let part = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/calculix_beam.toml")
        .canonicalize()
        .unwrap();
    let file = dir.join("beam.fmb.h5");
    reduce_to_file(&part, &file);
    let back = read_body_file(&file).unwrap();
    let g = back
        .inertia_gram
        .expect("no inertia/gram in the CalculiX body file");
    let base = part.parent().unwrap();
    let loaded = load_fe_body(&part, base, "beam", flexmbs_fe::UnitSystem::Si, true).unwrap();
    let si = reduced_body_to_si(&loaded.reduced);
    let m_si = consistent_mass_to_si(loaded.full_mass.as_ref().unwrap(), loaded.reduced.units);
    let fe = FfrInvariants::from_consistent(&si.nodes, &m_si, si.modes_t.as_ref()).unwrap();
    let nf = si.num_modes();
    let stored = FfrInvariants::from_gram(&gram_to_si(&g, nf, back.body.units), nf).unwrap();
    let scale = fe.i_kl.abs().max().max(fe.m_ff.abs().max()).max(fe.i1);
    let d = fe.max_abs_difference(&stored);
    eprintln!(
        "ccx: {nf} modes, mass {}, max |invariant difference| = {d:e}",
        stored.i1
    );
    assert!(d <= 1e-12 * scale, "{d:e}");
    let _ = std::fs::remove_dir_all(&dir);
}

//! `geometric_stiffening = true` with a reduced-body file (`.fmb.h5`) as `source`: the file
//! written like `flexmbs reduce` does (body + stored centrifugal `K_G`) gives the same trajectory
//! as the FE model file it came from; files without `K_G` and unusable `K_G` give located errors.

use flexmbs_fe::geometric::InertialLoad;
use flexmbs_io::body_file::{read_body_file, write_body, write_body_file, BodyFile};
use flexmbs_io::model_check::FeModelSource;
use flexmbs_io::results::{read_results, RunStatus};
use flexmbs_reduce::full_mass::beam_node_rotary_inertias;
use flexmbs_reduce::geometric::{centrifugal_geometric_stiffness, system_mass_kind};
use flexmbs_reduce::pipeline::{prepare, run_reduction};
use flexmbs_sim::bodies::load_reduced_with_fe;
use flexmbs_sim::run::{run_model, RunOptions};
use flexmbs_sim::stiffening::centrifugal_stiffness;
use flexmbs_sim::{compile_model, SimError};
use std::path::{Path, PathBuf};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/mbs")
}

fn temp(name: &str) -> PathBuf {
    flexmbs_io::test_tools::scratch_dir(&format!("sim-kgfile-{name}"))
}

/// The steps of `flexmbs reduce model.toml -o out.fmb.h5`: prepare, reduce, for a body with
/// fixed nodes the centrifugal `K_G` (all modes, body units) and for a beam mesh the node rotary
/// inertias, written to `out`.
fn reduce_to_file(model: &Path, out: &Path) -> BodyFile {
    let src = FeModelSource::read(model).unwrap();
    let spec = &src.model.body;
    let base = model.parent().unwrap();
    let prepared = prepare(spec, base, &mut |_| {}).unwrap();
    let body = run_reduction(spec, &prepared, &mut |_| {}).unwrap();
    let mass = system_mass_kind(&spec.mesh, spec.reduction.mass);
    let geometric = centrifugal_geometric_stiffness(&prepared, mass, &body).unwrap();
    let rotary_inertia = beam_node_rotary_inertias(&prepared.mesh, body.num_nodes()).unwrap();
    let f = BodyFile {
        body,
        geometric,
        rotary_inertia,
        stress: None,
        inertia_gram: None,
    };
    f.write(out).unwrap();
    f
}

/// The rotating-beam example, 20 ms (through the 10 ms pulse), with `edit` applied to its text;
/// returns the tip deformation along the body y axis.
fn tip_signal(name: &str, edit: &dyn Fn(&str) -> String) -> Vec<f64> {
    let file = examples().join("rotating_beam.toml");
    let text = std::fs::read_to_string(&file)
        .unwrap()
        .replace("t_end = \"0.3 s\"", "t_end = \"20 ms\"");
    let text = edit(&text);
    let cm = compile_model(&text, &file).unwrap();
    let out = temp(name);
    let summary = run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    assert_eq!(summary.status, RunStatus::Completed);
    let r = read_results(&out.join("results.h5")).unwrap();
    let w = r.series("tip.deformation.y").unwrap().to_vec();
    let _ = std::fs::remove_dir_all(&out);
    w
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The stored `K_G` of the rotor tube is bitwise the one the model compiler computes from the FE
/// model, and the rotating-beam example gives the same tip history (to 1e-12 relative to the
/// peak deflection) with the `.fmb.h5` source as with the FE source, for all modes and for the
/// selection `modes = [2, 1, 4]`, both with the default node rotary inertias (computed from the
/// beam mesh, stored in the file). Without stiffening the history differs by > 10 %, so the
/// stored `K_G` is really in use.
#[test]
fn body_file_source_matches_fe_source_with_stiffening() {
    let dir = temp("traj");
    let part = examples().join("parts/rotor_tube.toml");
    let h5 = dir.join("rotor_tube.fmb.h5");
    let written = reduce_to_file(&part, &h5);
    let g = written
        .geometric
        .as_ref()
        .expect("the tube is clamped: K_G expected");
    assert_eq!(g.load_patterns, InertialLoad::centrifugal());
    let back = read_body_file(&h5).unwrap();
    assert_eq!(back, written);
    // the model compiler's K_G from the FE model: identical
    let (body, fe) = load_reduced_with_fe(&part, Path::new("."), "b", Default::default()).unwrap();
    assert_eq!(
        &centrifugal_stiffness(fe.as_ref().unwrap(), &body).unwrap(),
        g
    );

    assert!(
        written.rotary_inertia.is_some(),
        "beam mesh: rotary inertias expected"
    );
    let fe_src = |s: &str| s.to_string();
    let h5_source = format!("source = {:?}", h5.display().to_string());
    let file_src = |s: &str| s.replace("source = \"parts/rotor_tube.toml\"", &h5_source);
    for (tag, modes) in [("all", ""), ("sel", "\nmodes = [2, 1, 4]")] {
        let with_modes = |s: &str| {
            s.replace(
                "geometric_stiffening = true",
                &format!("geometric_stiffening = true{modes}"),
            )
        };
        let w_fe = tip_signal(&format!("fe-{tag}"), &|s| fe_src(&with_modes(s)));
        let w_h5 = tip_signal(&format!("h5-{tag}"), &|s| file_src(&with_modes(s)));
        let wmax = w_fe.iter().map(|x| x.abs()).fold(0.0, f64::max);
        let dw = max_abs_diff(&w_fe, &w_h5);
        eprintln!(
            "{tag}: FE vs .fmb.h5 source: max |dw| = {dw:e} m, max |w| = {wmax:e} m, {} samples",
            w_fe.len()
        );
        assert!(
            w_fe.len() > 200 && wmax > 0.01,
            "{} samples, {wmax}",
            w_fe.len()
        );
        assert!(dw <= 1e-12 * wmax, "max |dw| = {dw:e} (max |w| = {wmax:e})");
        if tag == "all" {
            let w_lin = tip_signal("h5-lin", &|s| {
                file_src(s).replace(
                    "geometric_stiffening = true",
                    "geometric_stiffening = false",
                )
            });
            let d = max_abs_diff(&w_lin, &w_h5);
            eprintln!("stiffened vs linear (.fmb.h5): max |dw| = {d:e} m");
            assert!(d > 0.1 * wmax, "{d:e}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The rotor tube in SI(mm): the file stores `K_G` and the node rotary inertias in the file's
/// units (mm, t, s), converted to SI at model compile time like the FE-computed ones; the two
/// sources give the same tip history to 1e-12 relative.
#[test]
fn body_file_in_si_mm_matches_fe_source() {
    let dir = temp("mm");
    let part = std::fs::read_to_string(examples().join("parts/rotor_tube.toml"))
        .unwrap()
        .replace(
            "name = \"rotor_tube\"",
            "name = \"rotor_tube\"\nunits = \"SI(mm)\"",
        )
        .replace("end = [1.0, 0.0, 0.0]", "end = [1000.0, 0.0, 0.0]")
        .replace(
            "outer_radius = 0.01, wall = 0.001",
            "outer_radius = 10.0, wall = 1.0",
        )
        .replace(
            "e = 70e9, nu = 0.3, rho = 2700.0",
            "e = 70000.0, nu = 0.3, rho = 2.7e-9",
        );
    assert!(part.contains("SI(mm)") && part.contains("rho = 2.7e-9") && part.contains("1000.0"));
    let mm = dir.join("rotor_tube_mm.toml");
    std::fs::write(&mm, &part).unwrap();
    let h5 = dir.join("rotor_tube_mm.fmb.h5");
    let written = reduce_to_file(&mm, &h5);
    assert_eq!(written.body.units, flexmbs_fe::UnitSystem::SiMm);
    assert!(written.geometric.is_some());
    let with = |src: &Path, extra: &'static str| {
        let src = format!("source = {:?}{extra}", src.display().to_string());
        move |s: &str| s.replace("source = \"parts/rotor_tube.toml\"", &src)
    };
    assert!(written.rotary_inertia.is_some());
    let w_fe = tip_signal("mm-fe", &with(&mm, ""));
    let w_h5 = tip_signal("mm-h5", &with(&h5, ""));
    let wmax = w_fe.iter().map(|x| x.abs()).fold(0.0, f64::max);
    let dw = max_abs_diff(&w_fe, &w_h5);
    eprintln!("SI(mm): FE vs .fmb.h5 source: max |dw| = {dw:e} m, max |w| = {wmax:e} m");
    assert!(w_fe.len() > 200 && wmax > 0.01);
    assert!(dw <= 1e-12 * wmax, "max |dw| = {dw:e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Compiles the rotating-beam example with the beam's source replaced by `h5`; the error.
fn compile_error_with_source(h5: &Path) -> (SimError, String) {
    let file = examples().join("rotating_beam.toml");
    let text = std::fs::read_to_string(&file).unwrap().replace(
        "source = \"parts/rotor_tube.toml\"",
        &format!("source = {:?}", h5.display().to_string()),
    );
    let err = compile_model(&text, &file).unwrap_err();
    (err, text)
}

/// Errors: a body file without `K_G` (written without it, or from a free-free FE model) and a
/// body file whose `K_G` has a pattern the engine cannot use are located at
/// `body[0].geometric_stiffening` and its line; the first tells how to fix it.
#[test]
fn body_file_without_usable_geometric_stiffness_is_a_located_error() {
    let dir = temp("errs");
    // the free-free rod: no fixed nodes, hence no K_G in the file
    let rod = dir.join("rod.fmb.h5");
    assert!(reduce_to_file(&examples().join("parts/rod.toml"), &rod)
        .geometric
        .is_none());
    assert!(read_body_file(&rod).unwrap().geometric.is_none());
    // the tube written without K_G
    let plain = dir.join("tube_plain.fmb.h5");
    let tube = reduce_to_file(
        &examples().join("parts/rotor_tube.toml"),
        &dir.join("t.fmb.h5"),
    );
    write_body(&plain, &tube.body).unwrap();
    for path in [&rod, &plain] {
        let (err, text) = compile_error_with_source(path);
        let msg = err.to_string();
        let line = text
            .lines()
            .position(|l| l.starts_with("geometric_stiffening = true"))
            .unwrap()
            + 1;
        assert_eq!(err.path(), Some("body[0].geometric_stiffening"), "{msg}");
        assert_eq!(err.line(), Some(line), "{msg}");
        assert!(
            msg.contains("has no geometric stiffness")
                && msg
                    .contains("re-export it with `flexmbs reduce` from an FE model with supports"),
            "{msg}"
        );
    }
    // a stored translational pattern: the engine takes centrifugal patterns only
    let mut g = tube.geometric.clone().unwrap();
    g.load_patterns[2] = InertialLoad::Translation(1);
    let odd = dir.join("tube_odd.fmb.h5");
    write_body_file(&odd, &tube.body, Some(&g)).unwrap();
    let (err, _) = compile_error_with_source(&odd);
    assert_eq!(err.path(), Some("body[0].geometric_stiffening"), "{err}");
    assert!(err.to_string().contains("Translation(1)"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

//! `cantilever_plate` (seed 001 §8.4; `benchmarks.md`): a plate 10 m x 1 m x 0.1 m (E = 12 GPa,
//! nu = 0.3) clamped at x = 0 under two equal vertical tip forces (fixed direction), as a chain
//! of 10 superelements with 4 interface points each (24 Craig-Bampton modes per body), each made
//! from the FE body file `validation/cantilever_plate/plate_segment.toml` (hex20, each cut face
//! tied rigidly in two halves), solved by load stepping. Reference: a geometrically nonlinear
//! CalculiX run of the continuous plate (C3D20R, NLGEOM, two meshes), stored in
//! `validation/cantilever_plate/reference_*.csv` with the decks that produced them.

use crate::ValidationResult;
use anyhow::{bail, Context, Result};
use flexmbs_core::integrator::{Statics, StaticsSettings};
use flexmbs_core::superelement::Superelement;
use flexmbs_core::{Joint, Load, LoadCoordinates, ModelSpec, NodeKind, TimeFunction, Workspace};
use flexmbs_io::plot::{LinePlot, Series, Style};
use flexmbs_reduce::superelement::{superelement_from_reduced, FeFrame};
use nalgebra::{Matrix3, Vector3};
use std::path::{Path, PathBuf};

/// Plate length (m).
const L: f64 = 10.0;
/// Total load of the two forces (N): `P L² / EI = 10` with `EI = E b t³ / 12 = 1e6 N m²`.
const P_MAX: f64 = 1e5;
/// Bending stiffness of the plate as a beam, `E b t³ / 12` (N m²).
const EI: f64 = 12e9 * 1.0 * 1e-3 / 12.0;
/// Load increments of the statics (the reference prints every 5 %).
const STEPS: usize = 40;
/// Superelements along the plate.
const BODIES: usize = 10;
/// Tolerance on `w/L` relative to the fine reference (measured: 2.65 % at the smallest load, the
/// superelements being stiffer there; README).
pub const TOLERANCE_W: f64 = 0.03;
/// Tolerance on `−u/L` where it is at least 0.1 (measured: 4.2 %; README).
pub const TOLERANCE_U: f64 = 0.05;

/// The case folder in the source tree (FE body file, reference tables, decks).
pub fn case_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../validation/cantilever_plate")
}

/// One point of a load-displacement path: `(P, w/L, −u/L)`.
pub type PathPoint = (f64, f64, f64);

/// Reference rows `(P, w/L, −u/L)` of a stored CalculiX table.
pub fn read_reference(path: &Path) -> Result<Vec<(f64, f64, f64)>> {
    let text = std::fs::read_to_string(path).with_context(|| path.display().to_string())?;
    let mut rows = Vec::new();
    for line in text.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let v: Vec<f64> = line
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .with_context(|| format!("{}: bad row `{line}`", path.display()))?;
        if v.len() != 3 {
            bail!("{}: bad row `{line}`", path.display());
        }
        rows.push((v[0], v[1], v[2]));
    }
    Ok(rows)
}

/// Reference rows `(P, w/L, −u/L)` from the `.dat` file of a CalculiX run of the stored decks
/// (the mean of the two reference nodes printed at every time point; as
/// `reference_from_dat.py`).
pub fn reference_from_dat(text: &str) -> Result<Vec<(f64, f64, f64)>> {
    let lines: Vec<&str> = text.lines().collect();
    let mut rows = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let Some(t) = line.split("for set REFS and time").nth(1) else {
            continue;
        };
        let t: f64 = t.trim().parse()?;
        let (mut ux, mut uz) = (0.0, 0.0);
        for k in [2, 3] {
            let v: Vec<f64> = lines
                .get(i + k)
                .context("truncated .dat")?
                .split_whitespace()
                .skip(1)
                .map(str::parse)
                .collect::<Result<_, _>>()?;
            if v.len() != 3 {
                bail!("bad displacement row after `{line}`");
            }
            ux += 0.5 * v[0];
            uz += 0.5 * v[2];
        }
        rows.push((t * P_MAX, -uz / L, -ux / L));
    }
    Ok(rows)
}

/// The equilibrium path of the superelement plate: `(P, w/L, −u/L)` of the mean of the two tip
/// interface points at every load increment, and the Newton iterations.
pub fn superelement_path() -> Result<(Vec<PathPoint>, usize)> {
    let file = case_dir().join("plate_segment.toml");
    let src = flexmbs_io::model_check::FeModelSource::read(&file)?;
    let spec = src.model.body.clone();
    let base = file.parent().context("no folder")?;
    let prepared = flexmbs_reduce::pipeline::prepare(&spec, base, &mut |_| {})?;
    let reduced = flexmbs_reduce::pipeline::run_reduction(&spec, &prepared, &mut |_| {})?;
    let names: Vec<String> = ["a0", "b0", "a1", "b1"].map(String::from).into();
    let fe = superelement_from_reduced(&prepared.system, &reduced, &names, FeFrame::CentreOfMass)?;
    let mut model_spec = ModelSpec::new();
    // nodes a0, b0, a1, b1, ...: body k lives on the consecutive nodes 2k .. 2k + 3
    let nodes: Vec<_> = (0..=BODIES)
        .flat_map(|k| [format!("a{k}"), format!("b{k}")])
        .map(|n| model_spec.add_node(&n, NodeKind::Pose))
        .collect();
    let mut bodies = Vec::new();
    for k in 0..BODIES {
        let se = Superelement::new(fe.data.clone())?;
        bodies.push(model_spec.add_body_on(&format!("s{k}"), se, &nodes[2 * k..2 * k + 4]));
    }
    let frame = |s: &mut ModelSpec, i: usize| {
        s.add_node_owned_frame(
            &format!("f{i}"),
            nodes[i],
            Vector3::zeros(),
            Matrix3::identity(),
        )
    };
    let frames: Vec<_> = (0..nodes.len())
        .map(|i| frame(&mut model_spec, i))
        .collect();
    for (i, y) in [(0, 0.25), (1, 0.75)] {
        let g = model_spec.add_ground_frame(
            &format!("clamp{i}"),
            Vector3::new(0.0, y, 0.05),
            Matrix3::identity(),
        );
        model_spec.add_joint(Joint::fixed(&format!("clamp{i}"), g, frames[i]));
    }
    let tips = [frames[2 * BODIES], frames[2 * BODIES + 1]];
    for tip in tips {
        model_spec.add_load(Load::Force {
            frame: tip,
            vector: Vector3::new(0.0, 0.0, -0.5 * P_MAX),
            time: TimeFunction::Constant(1.0),
            coordinates: LoadCoordinates::Global,
        });
    }
    let model = model_spec.compile()?;
    let mut s = model.initial_state();
    for (k, b) in bodies.iter().enumerate() {
        let origin = Vector3::new(k as f64, 0.0, 0.0) + fe.origin;
        model.set_body_pose(&mut s, *b, origin, Matrix3::identity());
    }
    let mut ws = Workspace::new(&model);
    let statics = Statics::new(StaticsSettings {
        load_steps: STEPS,
        ..Default::default()
    });
    let mut path = Vec::new();
    let stats = statics.solve_with(&model, &mut s, &mut ws, |st, mu, _| {
        let x: Vector3<f64> = tips
            .iter()
            .filter_map(|&f| model.frame_kinematics(st, f))
            .map(|k| k.position)
            .sum::<Vector3<f64>>()
            / 2.0;
        path.push((mu * P_MAX, -(x.z - 0.05) / L, -(x.x - L) / L));
    })?;
    Ok((path, stats.iterations))
}

/// The superelement value at load `p` (a load increment of the path).
fn at(path: &[(f64, f64, f64)], p: f64) -> Result<(f64, f64)> {
    path.iter()
        .find(|(q, _, _)| (q - p).abs() < 1e-6 * P_MAX)
        .map(|&(_, w, u)| (w, u))
        .with_context(|| format!("load {p} N not on the path"))
}

/// Runs the case.
pub fn run(out: &Path, quiet: bool) -> Result<ValidationResult> {
    let coarse = read_reference(&case_dir().join("reference_c3d20r_40x4x2.csv"))?;
    let fine = read_reference(&case_dir().join("reference_c3d20r_80x8x2.csv"))?;
    let (path, iterations) = superelement_path()?;
    let mut res = ValidationResult::new("cantilever_plate");
    res.record("newton_iterations", iterations as f64);
    res.record("load_steps", STEPS as f64);
    let (mut worst_w, mut worst_u, mut mesh_change) = (0.0_f64, 0.0_f64, 0.0_f64);
    for (&(p, w_ref, u_ref), &(pc, w_c, u_c)) in fine.iter().zip(&coarse) {
        if (p - pc).abs() > 1e-6 * P_MAX {
            bail!("the two reference tables have different loads");
        }
        let (w, u) = at(&path, p)?;
        let key = |q: &str| format!("{q}_{p:.0}");
        let (ew, eu) = ((w - w_ref) / w_ref, (u - u_ref) / u_ref);
        mesh_change = mesh_change.max(((w_c - w_ref) / w_ref).abs());
        res.check(&key("w_over_L"), w, w_ref, TOLERANCE_W);
        worst_w = worst_w.max(ew.abs());
        // -u/L is checked where it is at least 0.1 (from 15 kN): below, a relative error of a
        // quantity near zero says little
        if u_ref >= 0.1 {
            res.check(&key("minus_u_over_L"), u, u_ref, TOLERANCE_U);
            worst_u = worst_u.max(eu.abs());
        } else {
            res.record(&key("minus_u_over_L"), u);
        }
        // context: the inextensible elastica of a beam with EI = E b t³ / 12 (no plate effect)
        let (ue, ve) = crate::elastica::elastica_elliptic(p, L, EI);
        res.record(&key("elastica_w_over_L"), ve / L);
        res.record(&key("elastica_minus_u_over_L"), ue / L);
        res.record(&key("coarse_reference_w_over_L"), w_c);
        res.record(&key("coarse_reference_minus_u_over_L"), u_c);
        if !quiet {
            println!(
                "P {p:7.0} N: w/L {w:.5} (ref {w_ref:.5}, {:+.2} %), -u/L {u:.5} (ref {u_ref:.5}, {:+.2} %)",
                100.0 * ew,
                100.0 * eu
            );
        }
    }
    res.record("largest_error_w", worst_w);
    res.record("largest_error_minus_u", worst_u);
    res.record("reference_mesh_change_w", mesh_change);
    plot(out, &path, &coarse, &fine)?;
    Ok(res)
}

fn plot(
    out: &Path,
    path: &[(f64, f64, f64)],
    coarse: &[(f64, f64, f64)],
    fine: &[(f64, f64, f64)],
) -> Result<()> {
    let mut series = Vec::new();
    let mut add = |name: &str, rows: &[(f64, f64, f64)], style: Style| {
        for (q, pick) in [("w/L", 1), ("-u/L", 2)] {
            series.push(Series {
                name: format!("{name} {q}"),
                points: rows
                    .iter()
                    .map(|r| (r.0, if pick == 1 { r.1 } else { r.2 }))
                    .collect(),
                style,
            });
        }
    };
    add("CalculiX C3D20R 80x8x2", fine, Style::Line);
    add("CalculiX C3D20R 40x4x2", coarse, Style::Line);
    add("10 superelements", path, Style::Points);
    let elastica: Vec<(f64, f64, f64)> = fine
        .iter()
        .map(|&(p, _, _)| {
            let (u, v) = crate::elastica::elastica_elliptic(p, L, EI);
            (p, v / L, u / L)
        })
        .collect();
    add("elastica (beam, E b t^3/12)", &elastica, Style::Line);
    let plot = LinePlot {
        title: "Cantilever plate, two vertical tip forces: tip displacements".into(),
        x_label: "P (sum of both forces) [N]".into(),
        y_label: "w/L, -u/L".into(),
        series,
        log_x: false,
        log_y: false,
    };
    plot.write(&out.join("tip.png"))?;
    plot.write(&out.join("tip.svg"))?;
    Ok(())
}

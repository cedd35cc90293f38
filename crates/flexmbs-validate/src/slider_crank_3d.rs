//! `slider_crank_3d` (seed 001 §5.1, Fig. 5.4-5.5): the flexible slider-crank of
//! `slider_crank_2d` made spatial: the crank's rotation axis along the slider guide, offset
//! horizontally by d = 0.1 m, the crank vertical at the start; revolute crank, spherical joint
//! crank-rod, universal joint rod-slider, prismatic slider ([`crate::slider_crank_3d_model`]).
//! Output: the rod midpoint deflection along the rod's local y (and z) vs crank angle.
//! Reference: a spatial discrete elastic rod of its own ([`crate::slider_crank_3d_reference`]),
//! converged in segments and step. Checks: the rigid mechanism's slider position against the
//! closed form; the 3D model in the planar geometry (d = 0, crank axis along z) against
//! `slider_crank_2d`'s model; the spatial reference in the planar geometry against
//! `slider_crank_2d`'s corotational reference.

use crate::slider_crank_3d_model::{
    planar_crank, rod_mass, simulate, spatial_crank, Rod, CRANK, OMEGA, ROD,
};
use crate::slider_crank_3d_reference::{self as reference, Crank, DiscreteRod};
use crate::slider_crank_reference::SliderCrank;
use crate::{slider_crank_superelement, ValidationResult};
use anyhow::Result;
use flexmbs_io::plot::{LinePlot, Series, Style};
use std::f64::consts::PI;
use std::path::Path;

/// Horizontal offset of the crank axis (m).
pub const OFFSET: f64 = 0.1;
/// Largest deviation of the 3D model in the planar geometry from `slider_crank_2d`'s model,
/// relative to the largest deflection.
pub const PLANAR_MODEL_TOL: f64 = 1e-3;
/// Largest deviation of the discrete-rod reference in the planar geometry from the planar
/// corotational reference over one revolution, relative to the largest deflection.
pub const PLANAR_REFERENCE_TOL: f64 = 0.005;
/// Sample interval and step of the flexmbs models (s).
const SAMPLE_DT: f64 = 1e-5;
/// Segment counts of the reference's convergence study (the last is the reference).
pub const REFERENCE_SEGMENTS: [usize; 3] = [16, 32, 64];

/// Crank revolutions of the run: `SLIDER_CRANK_3D_REVOLUTIONS` (default 1, so that CI runs it;
/// 4 for the full run).
pub fn revolutions() -> f64 {
    std::env::var("SLIDER_CRANK_3D_REVOLUTIONS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1.0)
}

/// First-revolution extremes and the RMS over all samples (every [`SAMPLE_DT`] from `t = 0`):
/// `(max, min, rms)`.
pub fn extremes_and_rms(w: &[f64]) -> (f64, f64, f64) {
    let rev1 = (2.0 * PI / OMEGA / SAMPLE_DT).round() as usize + 1;
    let first = &w[..rev1.min(w.len())];
    let max = first.iter().copied().fold(f64::MIN, f64::max);
    let min = first.iter().copied().fold(f64::MAX, f64::min);
    let rms = (w.iter().map(|x| x * x).sum::<f64>() / w.len() as f64).sqrt();
    (max, min, rms)
}

/// RMS of `w - reference` over their common samples relative to the RMS of `reference`.
pub fn rms_deviation(w: &[f64], reference: &[f64]) -> f64 {
    let n = w.len().min(reference.len());
    let d: f64 = (0..n).map(|i| (w[i] - reference[i]).powi(2)).sum();
    let r: f64 = reference[..n].iter().map(|x| x * x).sum();
    (d / r).sqrt()
}

/// Largest |a_i - b_i| over the common samples relative to the largest |b_i|.
fn max_deviation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let d = (0..n).fold(0.0f64, |m, i| m.max((a[i] - b[i]).abs()));
    d / b[..n].iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// The discrete-rod reference run on `crank` with `n` segments at half the stable step
/// (`halve`: a quarter), sampled every [`SAMPLE_DT`].
fn reference_run(crank: &Crank, n: usize, halve: bool, revs: f64) -> Result<reference::RodRun> {
    let rod = DiscreteRod::slider_crank_rod(n);
    let h_crit = reference::critical_step(&rod, 0.5 * rod_mass());
    let sub = (SAMPLE_DT / (0.5 * h_crit)).ceil() as usize * if halve { 2 } else { 1 };
    reference::simulate(&rod, crank, 0.5 * rod_mass(), revs, SAMPLE_DT, sub)
        .map_err(|e| anyhow::anyhow!("reference, {n} segments: {e}"))
}

/// The reference on the spatial crank: [`REFERENCE_SEGMENTS`] at the step and (finest count) half
/// of it; records the table and the Richardson estimate; returns the finest `(w_y, w_z)`.
fn reference(res: &mut ValidationResult, revs: f64, log: &dyn Fn(&str)) -> Result<[Vec<f64>; 2]> {
    let crank = spatial_crank(OFFSET);
    let mut previous: Option<(usize, [f64; 3])> = None;
    let mut finest = None;
    for (k, &n) in REFERENCE_SEGMENTS.iter().enumerate() {
        let last = k + 1 == REFERENCE_SEGMENTS.len();
        for halve in [false, true] {
            if halve && !last {
                continue;
            }
            let run = reference_run(&crank, n, halve, revs)?;
            let (max, min, rms) = extremes_and_rms(&run.w_y);
            let tag = format!("n{n}{}", if halve { "_half_step" } else { "" });
            log(&format!(
                "reference {n:2} segments, h = {:.3e} s: w_y in revolution 1 in [{min:.5e}, {max:.5e}] m, rms {rms:.5e} m, max compression {:.0} N",
                run.h, run.compression_max
            ));
            res.record(&format!("reference_w_y_max_rev1_{tag}"), max);
            res.record(&format!("reference_w_y_min_rev1_{tag}"), min);
            res.record(&format!("reference_w_y_rms_{tag}"), rms);
            if halve {
                continue;
            }
            res.record(&format!("reference_step_{tag}"), run.h);
            res.record(
                &format!("reference_compression_max_{tag}"),
                run.compression_max,
            );
            if let (true, Some((n0, [mx0, mn0, r0]))) = (last, previous) {
                // Richardson with the previous count, O(1/n^2): an error estimate, recorded
                let f = (n0 * n0) as f64 / ((n * n - n0 * n0) as f64);
                res.record("reference_w_y_max_rev1_extrapolated", max + f * (max - mx0));
                res.record("reference_w_y_min_rev1_extrapolated", min + f * (min - mn0));
                res.record("reference_w_y_rms_extrapolated", rms + f * (rms - r0));
            }
            previous = Some((n, [max, min, rms]));
            if last {
                finest = Some([run.w_y, run.w_z]);
            }
        }
    }
    finest.ok_or_else(|| anyhow::anyhow!("no reference run"))
}

/// Compares a history with the reference (extremes of revolution 1, RMS over the run): checked
/// within `tol`, or recorded with the deviation if `None`.
fn compare(
    res: &mut ValidationResult,
    key: &str,
    suffix: &str,
    w: &[f64],
    reference: &[f64],
    tol: Option<f64>,
) {
    let (max, min, rms) = extremes_and_rms(w);
    let (rmax, rmin, rrms) = extremes_and_rms(reference);
    for (name, v, r) in [
        ("max_rev1", max, rmax),
        ("min_rev1", min, rmin),
        ("rms", rms, rrms),
    ] {
        let q = format!("{key}_{name}{suffix}");
        match tol {
            Some(t) => res.check(&q, v, r, t),
            None => {
                res.record(&q, v);
                res.record(&format!("{q}_deviation"), v / r - 1.0);
            }
        }
    }
    res.record(
        &format!("{key}_rms_of_difference{suffix}"),
        rms_deviation(w, reference),
    );
}

/// Rigid mechanism: the slider position of the flexmbs model with a rigid rod against the
/// closed form over one revolution (largest error, m), on `crank`.
fn rigid_kinematics_error(crank: &Crank) -> Result<f64> {
    let run = simulate(crank, Rod::Rigid, 1e-4, 1.0)?;
    Ok(run
        .theta
        .iter()
        .zip(&run.slider_x)
        .fold(0.0f64, |m, (&th, &x)| {
            m.max((x - crank.rigid_slider(ROD, th).0).abs())
        }))
}

/// The planar checks over one revolution: the 3D model (2 superelements) in the planar geometry
/// against `slider_crank_2d`'s superelement model, and the discrete-rod reference (64 segments)
/// in the planar geometry against the planar corotational beam (32 elements).
fn planar_checks(res: &mut ValidationResult, log: &dyn Fn(&str)) -> Result<()> {
    let w3 = simulate(&planar_crank(), Rod::Superelements(2), SAMPLE_DT, 1.0)?;
    let w2 = slider_crank_superelement::simulate(2, SAMPLE_DT, 1.0)?;
    let d_model = max_deviation(&w3.w_y, &w2);
    let out_of_plane = w3.w_z.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    log(&format!(
        "planar geometry, 2 superelements: 3D model vs slider_crank_2d model: max |dw| / max |w| = {d_model:.2e}, max |w_z| = {out_of_plane:.2e} m"
    ));
    res.record("planar_model_max_deviation", d_model);
    if d_model.is_nan() || d_model > PLANAR_MODEL_TOL {
        res.pass = false;
    }
    res.record("planar_model_w_z_max", out_of_plane);
    let r3 = reference_run(&planar_crank(), 64, false, 1.0)?;
    let planar = SliderCrank::seed(32);
    let sub = (SAMPLE_DT / (0.5 * planar.critical_step())).ceil() as usize;
    let r2 = planar
        .simulate(1.0, SAMPLE_DT, sub)
        .map_err(|e| anyhow::anyhow!("planar corotational reference: {e}"))?;
    let d_ref = max_deviation(&r3.w_y, &r2.w);
    log(&format!(
        "planar geometry, references: discrete rod (64 segments) vs corotational beam (32 elements): max |dw| / max |w| = {d_ref:.2e}"
    ));
    res.record("planar_reference_max_deviation", d_ref);
    if d_ref.is_nan() || d_ref > PLANAR_REFERENCE_TOL {
        res.pass = false;
    }
    let ((max3, min3, _), (max2, min2, _)) = (extremes_and_rms(&r3.w_y), extremes_and_rms(&r2.w));
    res.record("planar_reference_w_max_deviation", max3 / max2 - 1.0);
    res.record("planar_reference_w_min_deviation", min3 / min2 - 1.0);
    Ok(())
}

/// Runs the case.
pub fn run(out: &Path, quiet: bool) -> Result<ValidationResult> {
    let log = |m: &str| {
        if !quiet {
            eprintln!("  {m}");
        }
    };
    let revs = revolutions();
    let mut res = ValidationResult::new("slider_crank_3d");
    res.record("revolutions", revs);
    res.record("offset", OFFSET);
    for (name, crank) in [("", spatial_crank(OFFSET)), ("_planar", planar_crank())] {
        let e = rigid_kinematics_error(&crank)?;
        log(&format!(
            "rigid rod{name}: slider position vs closed form, max error {e:.2e} m"
        ));
        res.record(&format!("rigid_slider_error_max{name}"), e);
        if e.is_nan() || e > 1e-6 {
            res.pass = false;
        }
    }
    planar_checks(&mut res, &log)?;
    let [ref_y, ref_z] = reference(&mut res, revs, &log)?;
    let n_ref = REFERENCE_SEGMENTS[REFERENCE_SEGMENTS.len() - 1];
    let plot_points = |w: &[f64]| -> Vec<(f64, f64)> {
        w.iter()
            .enumerate()
            .step_by(10)
            .map(|(i, x)| (i as f64 * SAMPLE_DT * OMEGA, x * 1e3))
            .collect()
    };
    let (mut series_y, mut series_z) = (Vec::new(), Vec::new());
    let crank = spatial_crank(OFFSET);
    let models = [
        (
            Rod::Superelements(10),
            "",
            Some(0.02),
            "10 superelements".to_string(),
        ),
        (
            Rod::Superelements(2),
            "_n2",
            Some(0.05),
            "2 superelements".to_string(),
        ),
        (
            Rod::Ffr {
                modes: 8,
                stiffened: false,
            },
            "_ffr",
            None,
            "FFR rod, 8 free-free modes".to_string(),
        ),
        (
            Rod::Ffr {
                modes: 8,
                stiffened: true,
            },
            "_ffr_stiffened",
            Some(0.05),
            "FFR rod, 8 modes, geometric stiffening under end loads".to_string(),
        ),
    ];
    for (rod, suffix, tol, label) in models {
        let clock = std::time::Instant::now();
        let r = simulate(&crank, rod, SAMPLE_DT, revs)?;
        let cpu = clock.elapsed().as_secs_f64();
        compare(&mut res, "w_y", suffix, &r.w_y, &ref_y, tol);
        compare(&mut res, "w_z", suffix, &r.w_z, &ref_z, tol);
        res.record(&format!("constraint_violation_max{suffix}"), r.g_max);
        if r.g_max.is_nan() || r.g_max > 1e-8 {
            res.pass = false;
        }
        let (max, min, rms) = extremes_and_rms(&r.w_y);
        log(&format!(
            "{label}: w_y in revolution 1 in [{min:.5e}, {max:.5e}] m, rms {rms:.5e} m, max |g| {:.1e} ({cpu:.1} s)",
            r.g_max
        ));
        series_y.push(Series {
            name: label.clone(),
            points: plot_points(&r.w_y),
            style: Style::Line,
        });
        series_z.push(Series {
            name: label,
            points: plot_points(&r.w_z),
            style: Style::Line,
        });
    }
    for (series, w) in [(&mut series_y, &ref_y), (&mut series_z, &ref_z)] {
        series.push(Series {
            name: format!("reference: discrete elastic rod, {n_ref} segments"),
            points: plot_points(w),
            style: Style::Line,
        });
    }
    for (series, axis, file) in [(series_y, "y", "w_y"), (series_z, "z", "w_z")] {
        let plot = LinePlot {
            title: format!(
                "3D slider-crank (d = {OFFSET} m, crank {CRANK} m): rod midpoint deflection along local {axis}"
            ),
            x_label: "crank angle [rad]".into(),
            y_label: format!("w_{axis} [mm]"),
            series,
            log_x: false,
            log_y: false,
        };
        plot.write(&out.join(format!("{file}.png")))?;
        plot.write(&out.join(format!("{file}.svg")))?;
    }
    Ok(res)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs the case into a temporary folder, prints its summary and asserts that it passes.
    #[test]
    #[ignore = "the whole case, which `flexmbs validate --all` already runs in CI: run with --ignored"]
    fn whole_case() {
        let dir = std::env::temp_dir().join("sc3d_case");
        std::fs::create_dir_all(&dir).unwrap();
        let t = std::time::Instant::now();
        let r = run(&dir, false).unwrap();
        eprintln!("{}\n{:.1} s", r.summary(), t.elapsed().as_secs_f64());
        assert!(r.pass, "{}", r.summary());
    }
}

//! `point_mass_on_beam`: the FFR body's convergence with the number of modes towards the
//! unreduced FE reference ([`crate::point_mass_on_beam_full_fe`]), penalty law (S4, k = 1e7 N/m,
//! no damping), setup A, fixed steps.
//!
//! Compared: the mass's lowest point `y_min`, the contact span (first and last step with a
//! contact force) and time in contact, the mass's final velocity, and the y displacement of the
//! node (250, 50, 25) mm over time (RMS of the difference to the reference over the reference's
//! RMS). Besides the FFR runs (Moreau time-stepping, the NURBS contour and its contact search),
//! the reference's own integrator is run on the modal basis (`Phi^T K Phi`, `Phi^T M Phi`,
//! `Phi^T w`): that isolates the modal truncation from the FFR body's integrator and contact
//! kinematics.
//!
//! The validation run ([`full_fe_check`]) compares 100 modes with the reference over 0.05 s (the
//! contact phase); the step and mode studies behind the README's tables are
//! [`step_study`] and [`mode_study`] (ignored tests, minutes).

use crate::point_mass_on_beam::{simulate, Beam, Config, Run, BEAM};
use crate::point_mass_on_beam_full_fe::{
    assemble_full_fe, contact_times, contact_weights, simulate_penalty_impact, static_response,
    y_dof_at, FullFeBeam, Interpolation, PenaltyImpact, ReferenceRun,
};
use crate::ValidationResult;
use anyhow::{bail, Result};
use faer::sparse::Triplet;
use flexmbs_fe::SparseMatrix;
use flexmbs_io::plot::{LinePlot, Series, Style};
use std::path::Path;

/// Tolerance of the 100-mode FFR body's largest deflection `0.05 - y_min` relative to the full-FE
/// reference's (fixed before the comparison was run; `docs/decisions.md`).
pub const TOL_DEFLECTION: f64 = 0.03;
/// Tolerance of the RMS difference of the node (250, 50, 25) mm y displacement, relative to the
/// reference's RMS (fixed before the comparison was run).
pub const TOL_NODE_RMS: f64 = 0.05;

/// The node-trajectory check against the full FE.
const NODE_CHECK: &str = "full_fe_node_rms_diff_modes100";

/// The node-trajectory check of the basis with the static response of the contact region.
const NODE_CHECK_STATIC: &str = "full_fe_node_rms_diff_modes100_static";

/// Why [`NODE_CHECK_STATIC`] fails (declared after its first run, 2026-11-29: 17.2 % against the
/// 5 % fixed before it; the README has the numbers).
const NODE_CHECK_STATIC_DISAGREEMENT: &str = "the static response to a uniform load on the 16 \
nodes around the impact point brings the deflection closer (-1.65 % instead of -2.87 %) but not \
the node trajectory (17-19 % RMS, with round-off of the build): the impact train on the surface stays sensitive to the basis; \
see validation/point_mass_on_beam/README.md";

/// Why [`NODE_CHECK`] fails (measured 10.2 % with the tolerance of 5 % fixed before the first
/// comparison; the README's section "Full-FE reference" has the mode and step studies).
const NODE_CHECK_DISAGREEMENT: &str = "a lowest-mode basis (10 to 200 modes) lacks the local \
deformation under the load and changes the impact train, so the node 15 mm from the load stays \
10-26 % RMS from the unreduced model; see validation/point_mass_on_beam/README.md";

/// The full-FE beam with the contact weights and the probe node.
pub struct FullFeSetup {
    /// The beam with all its DOFs.
    pub beam: FullFeBeam,
    /// Contact weights of the NURBS contour (the benchmark's 2D neutral contour).
    pub w_nurbs: Vec<f64>,
    /// Contact weights of the hex20 face shape functions.
    pub w_hex20: Vec<f64>,
    /// Unit vector of the probe node's y DOF.
    pub probe: Vec<f64>,
}

/// Assembles the beam and the weights at the setup-A contact point (235, 25) mm.
pub fn full_fe_setup() -> Result<FullFeSetup> {
    let beam = assemble_full_fe(BEAM)?;
    let n = beam.k.nrows();
    let weights = |how| {
        contact_weights(&beam, how, [0.235, 0.025], 0.05, [0.01, 0.01], [25, 5]).map(|w| w.dense(n))
    };
    let (w_nurbs, w_hex20) = (
        weights(Interpolation::Nurbs)?,
        weights(Interpolation::Hex20Face)?,
    );
    let mut probe = vec![0.0; n];
    probe[y_dof_at(&beam, [0.25, 0.05, 0.025])?] = 1.0;
    Ok(FullFeSetup {
        beam,
        w_nurbs,
        w_hex20,
        probe,
    })
}

/// The benchmark's mass and penalty law (setup A) with step `h` to `t_end`.
pub fn penalty_setup(h: f64, t_end: f64) -> PenaltyImpact {
    PenaltyImpact {
        mass: 0.5,
        y0: 0.052,
        v0: -0.2,
        y_top: 0.05,
        stiffness: 1e7,
        h,
        t_end,
    }
}

/// Runs the full-FE reference.
pub fn run_reference(
    s: &FullFeSetup,
    how: Interpolation,
    h: f64,
    t_end: f64,
) -> Result<ReferenceRun> {
    let w = match how {
        Interpolation::Nurbs => &s.w_nurbs,
        Interpolation::Hex20Face => &s.w_hex20,
    };
    simulate_penalty_impact(&s.beam.k, &s.beam.m, w, &s.probe, &penalty_setup(h, t_end))
}

/// One row of a comparison with the reference.
#[derive(Debug, Clone, Copy)]
pub struct Row {
    /// Lowest point of the mass (m).
    pub y_min: f64,
    /// First and last time in contact (s).
    pub contact_span: (f64, f64),
    /// Time in contact (s).
    pub contact_time: f64,
    /// Final vertical velocity of the mass (m/s).
    pub v_y_final: f64,
    /// Smallest y displacement of the probe node (m).
    pub node_min: f64,
    /// RMS of the probe node's difference to the reference over the reference's RMS.
    pub node_rms_rel: f64,
    /// Wall time of the integration (s).
    pub cpu: f64,
}

/// The reference's probe displacement at time `t` (linear between steps).
fn probe_at(r: &ReferenceRun, t: f64) -> f64 {
    let h = r.t[1] - r.t[0];
    let x = (t / h).clamp(0.0, (r.t.len() - 1) as f64);
    let i = (x.floor() as usize).min(r.t.len() - 2);
    let s = x - i as f64;
    (1.0 - s) * r.probe[i] + s * r.probe[i + 1]
}

/// RMS of `samples - reference` over the RMS of the reference, at the sample times.
fn rms_rel(samples: &[(f64, f64)], r: &ReferenceRun) -> f64 {
    let (mut d2, mut r2) = (0.0, 0.0);
    for &(t, v) in samples {
        let p = probe_at(r, t);
        d2 += (v - p).powi(2);
        r2 += p * p;
    }
    (d2 / r2).sqrt()
}

/// Compares an FFR run with the reference.
pub fn compare_ffr(run: &Run, r: &ReferenceRun) -> Row {
    Row {
        y_min: run.y_min,
        contact_span: run.contact_span,
        contact_time: run.contact_time,
        v_y_final: run.v_y_final,
        node_min: run.node.iter().map(|p| p.1).fold(f64::INFINITY, f64::min),
        node_rms_rel: rms_rel(&run.node, r),
        cpu: run.cpu,
    }
}

/// Compares a run of the reference's integrator (another step, basis or interpolation) with
/// the reference, sampled every 2.5e-4 s like the FFR runs.
pub fn compare_reference(run: &ReferenceRun, r: &ReferenceRun) -> Row {
    let h = run.t[1] - run.t[0];
    let every = ((2.5e-4 / h).round() as usize).max(1);
    let samples: Vec<(f64, f64)> = (0..run.t.len())
        .step_by(every)
        .map(|i| (run.t[i], run.probe[i]))
        .collect();
    let (a, b, total) = contact_times(&run.t, &run.force);
    Row {
        y_min: run.y_min,
        contact_span: (a, b),
        contact_time: total,
        v_y_final: run.v_y_final,
        node_min: run.probe.iter().copied().fold(f64::INFINITY, f64::min),
        node_rms_rel: rms_rel(&samples, r),
        cpu: run.cpu,
    }
}

/// The modal system of the first `n` modes of `beam` over the full FE model's free DOFs:
/// `(Phi^T K Phi, Phi^T M Phi, Phi^T w, Phi^T probe)`; with `static_correction`, `Phi` gets
/// one more column: the static response `K^-1 w` to the contact force, made M-orthogonal to
/// the modes (two Gram-Schmidt passes) and M-normalized (the benchmark's "basis that contains
/// the static response to a load at the contact region").
pub fn modal_system(
    beam: &Beam,
    s: &FullFeSetup,
    n: usize,
    w: &[f64],
    static_correction: bool,
) -> Result<(SparseMatrix, SparseMatrix, Vec<f64>, Vec<f64>)> {
    let red = &beam.reduced;
    if red.nodes.len() < s.beam.nodes.len() || n > red.num_modes() {
        bail!("the reduced body does not match the full FE model");
    }
    let nf = s.beam.k.nrows();
    let cols = n + usize::from(static_correction);
    let mut phi = faer::Mat::<f64>::zeros(nf, cols);
    for (node, dofs) in s.beam.dofs.iter().enumerate() {
        if (0..3).any(|k| (red.nodes[node][k] - s.beam.nodes[node][k]).abs() > 1e-12) {
            bail!("node {node} differs between the reduced body and the full FE model");
        }
        for (dir, d) in dofs.iter().enumerate() {
            if let Some(d) = d {
                for k in 0..n {
                    phi[(*d, k)] = red.modes_t[(3 * node + dir, k)];
                }
            }
        }
    }
    if static_correction {
        let mut x = static_response(&s.beam.k, w)?;
        let m_phi = flexmbs_fe::system::sparse_times(&s.beam.m, phi.as_ref());
        let col_dot = |a: &faer::Mat<f64>, k: usize, v: &[f64]| -> f64 {
            (0..nf).map(|i| a[(i, k)] * v[i]).sum()
        };
        for _ in 0..2 {
            for k in 0..n {
                let norm_k: f64 = (0..nf).map(|i| phi[(i, k)] * m_phi[(i, k)]).sum();
                let c = col_dot(&m_phi, k, &x) / norm_k;
                for (i, xi) in x.iter_mut().enumerate() {
                    *xi -= c * phi[(i, k)];
                }
            }
        }
        let xm = flexmbs_fe::system::sparse_times(
            &s.beam.m,
            faer::Mat::<f64>::from_fn(nf, 1, |i, _| x[i]).as_ref(),
        );
        let norm = (0..nf).map(|i| x[i] * xm[(i, 0)]).sum::<f64>().sqrt();
        for (i, xi) in x.iter().enumerate() {
            phi[(i, n)] = xi / norm;
        }
    }
    let n = cols;
    let project = |a: &SparseMatrix| -> Result<SparseMatrix> {
        let ap = flexmbs_fe::system::sparse_times(a, phi.as_ref());
        let r = phi.transpose() * &ap;
        let t: Vec<Triplet<usize, usize, f64>> = (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .map(|(i, j)| Triplet::new(i, j, 0.5 * (r[(i, j)] + r[(j, i)])))
            .collect();
        Ok(SparseMatrix::try_new_from_triplets(n, n, &t)?)
    };
    let reduce_vec = |v: &[f64]| -> Vec<f64> {
        (0..n)
            .map(|k| (0..nf).map(|i| phi[(i, k)] * v[i]).sum())
            .collect()
    };
    Ok((
        project(&s.beam.k)?,
        project(&s.beam.m)?,
        reduce_vec(w),
        reduce_vec(&s.probe),
    ))
}

/// The validation run's check: 100 modes (S4, h = 1e-5 s, 0.05 s) against the full-FE reference
/// in the largest deflection and the node displacement; records the CPU times.
pub fn full_fe_check(
    beam: &Beam,
    base: &Config,
    res: &mut ValidationResult,
    log: &dyn Fn(&str),
) -> Result<()> {
    let (h, t_end) = (1e-5, 0.05);
    res.declare_known_disagreement(NODE_CHECK, NODE_CHECK_DISAGREEMENT);
    let s = full_fe_setup()?;
    let r = run_reference(&s, Interpolation::Nurbs, h, t_end)?;
    let (a, b, total) = r.contact();
    log(&format!(
        "full FE (9900 DOFs, S4, h {h:e}, {t_end} s): y_min {:.6} m, contact {a:.5} .. {b:.5} s ({total:.5} s), node min {:.4e} m, {:.1} s (+{:.1} s factorization)",
        r.y_min,
        r.probe.iter().copied().fold(f64::INFINITY, f64::min),
        r.cpu - r.cpu_factor,
        r.cpu_factor
    ));
    let c = Config {
        modes: 100,
        restitution: None,
        step: Some(h),
        t_end,
        ..*base
    };
    let ffr_run = simulate(beam, &c)?;
    let ffr_penalty_step = ffr_run.penalty_step;
    let ffr = compare_ffr(&ffr_run, &r);
    log(&format!(
        "FFR 100 modes (S4): y_min {:.6} m, node RMS difference {:.2} %, {:.1} s",
        ffr.y_min,
        100.0 * ffr.node_rms_rel,
        ffr.cpu
    ));
    res.record("full_fe_y_min", r.y_min);
    res.record("full_fe_cpu_s", r.cpu);
    res.record("full_fe_contact_first", a);
    res.record("full_fe_contact_last", b);
    res.record("full_fe_contact_time", total);
    res.record("full_fe_y_min_modes100", ffr.y_min);
    res.record("full_fe_cpu_s_modes100", ffr.cpu);
    res.check(
        "full_fe_deflection_max_modes100",
        0.05 - ffr.y_min,
        0.05 - r.y_min,
        TOL_DEFLECTION,
    );
    res.tolerance.insert(NODE_CHECK.into(), TOL_NODE_RMS);
    res.limit(NODE_CHECK, ffr.node_rms_rel, TOL_NODE_RMS);
    // the same 100 modes and the static response to a load on the contact region (the
    // benchmark's "basis that contains the static response"), same tolerances
    res.declare_known_disagreement(NODE_CHECK_STATIC, NODE_CHECK_STATIC_DISAGREEMENT);
    let augmented = crate::point_mass_on_beam::reduce_beam_augmented(100)?;
    let aug = compare_ffr(&simulate(&augmented, &c)?, &r);
    log(&format!(
        "FFR 100 modes + static response (S4): y_min {:.6} m, node RMS difference {:.2} %, {:.1} s",
        aug.y_min,
        100.0 * aug.node_rms_rel,
        aug.cpu
    ));
    res.record("full_fe_y_min_modes100_static", aug.y_min);
    res.record("full_fe_cpu_s_modes100_static", aug.cpu);
    res.check(
        "full_fe_deflection_max_modes100_static",
        0.05 - aug.y_min,
        0.05 - r.y_min,
        TOL_DEFLECTION,
    );
    res.tolerance.insert(NODE_CHECK_STATIC.into(), TOL_NODE_RMS);
    res.limit(NODE_CHECK_STATIC, aug.node_rms_rel, TOL_NODE_RMS);
    // recorded, not checked (added after the two checks above had run): the static response to
    // a force at the impact point itself (consistent nodal loads of its element)
    let at_point = crate::point_mass_on_beam::reduce_beam_with_load(
        100,
        crate::point_mass_on_beam::CONTACT_POINT_LOAD,
    )?;
    let pt = compare_ffr(&simulate(&at_point, &c)?, &r);
    log(&format!(
        "FFR 100 modes + static response at the point (S4): y_min {:.6} m, node RMS difference {:.2} %, {:.1} s",
        pt.y_min,
        100.0 * pt.node_rms_rel,
        pt.cpu
    ));
    res.record("full_fe_y_min_modes100_point", pt.y_min);
    res.record(
        "full_fe_deflection_error_modes100_point",
        (r.y_min - pt.y_min) / (0.05 - r.y_min),
    );
    res.record("full_fe_node_rms_diff_modes100_point", pt.node_rms_rel);
    // recorded, not checked (added after the checks above had run): the static response to the
    // contour's own interpolation weights at the impact point (`static_loads` with `face`)
    let at_face = crate::point_mass_on_beam::reduce_beam_with_load(
        100,
        crate::point_mass_on_beam::CONTACT_FACE_LOAD,
    )?;
    // this vector lowers the effective mass of the contour point under the load from 16.6 g
    // (modes alone) to 0.23 g: the explicit penalty step needs `h sqrt(k / m_eff) < 2`, 2.07 at
    // h = 1e-5 s (the run diverges), 1.03 at h = 5e-6 s; the reference moves by 0.13 % of the
    // deflection between these steps (README, step study)
    let half = Config {
        step: Some(0.5 * h),
        ..c
    };
    let face_run = simulate(&at_face, &half)?;
    let fc_penalty_step = face_run.penalty_step;
    let fc = compare_ffr(&face_run, &r);
    log(&format!(
        "FFR 100 modes + static response to the contour's weights (S4, h = {:e}): y_min {:.6} \
         m, deflection {:+.2} %, node RMS difference {:.2} %, {:.1} s",
        0.5 * h,
        fc.y_min,
        100.0 * (r.y_min - fc.y_min) / (0.05 - r.y_min),
        100.0 * fc.node_rms_rel,
        fc.cpu
    ));
    res.record("full_fe_y_min_modes100_face", fc.y_min);
    res.record(
        "full_fe_deflection_error_modes100_face",
        (r.y_min - fc.y_min) / (0.05 - r.y_min),
    );
    res.record("full_fe_node_rms_diff_modes100_face", fc.node_rms_rel);
    res.record("full_fe_penalty_step_modes100", ffr_penalty_step);
    res.record("full_fe_penalty_step_modes100_face", fc_penalty_step);
    if fc_penalty_step > 2.0 {
        res.fail("full_fe_penalty_step_modes100_face");
    }
    Ok(())
}

/// A table row as text (mm, m/s, %, s).
pub fn format_row(label: &str, r: &Row) -> String {
    format!(
        "| {label} | {:.4} | {:.5} .. {:.5} | {:.5} | {:.4} | {:.4} | {:.2} | {:.1} |",
        1e3 * r.y_min,
        r.contact_span.0,
        r.contact_span.1,
        r.contact_time,
        r.v_y_final,
        1e3 * r.node_min,
        100.0 * r.node_rms_rel,
        r.cpu
    )
}

/// The mode study behind the README's table: the reference (NURBS weights, `h`, 0.1 s) against
/// the FFR body (S4, `h`) and the reference's integrator on the modal basis, for each mode
/// count; writes `node_full_fe` and `mass_full_fe` (png, svg) into `out`; returns the rows.
pub fn mode_study(
    beam: &Beam,
    counts: &[usize],
    h: f64,
    out: &Path,
    log: &dyn Fn(&str),
) -> Result<Vec<String>> {
    let s = full_fe_setup()?;
    let r = run_reference(&s, Interpolation::Nurbs, h, 0.1)?;
    log(&format!(
        "reference energy error {:.3e}, factorization {:.1} s",
        r.energy_error, r.cpu_factor
    ));
    mode_rows(beam, &s, &r, counts, out, log)
}

/// The step study of the reference: NURBS weights at `h`, `h/2`, `h/4` and the hex20 face
/// weights at `h`, over `t_end` (the contact phase), each against the run at `h/4`; returns the
/// rows.
pub fn step_study(h: f64, t_end: f64, log: &dyn Fn(&str)) -> Result<Vec<String>> {
    let s = full_fe_setup()?;
    let mut runs = vec![];
    for (how, hh) in [
        (Interpolation::Nurbs, h),
        (Interpolation::Nurbs, h / 2.0),
        (Interpolation::Nurbs, h / 4.0),
        (Interpolation::Hex20Face, h),
    ] {
        let label = match how {
            Interpolation::Nurbs => format!("NURBS, h = {hh:e} s"),
            Interpolation::Hex20Face => format!("hex20 face, h = {hh:e} s"),
        };
        let r = run_reference(&s, how, hh, t_end)?;
        log(&format!("{label}: energy error {:.3e}", r.energy_error));
        runs.push((label, r));
    }
    let finest = &runs[2].1;
    Ok(runs
        .iter()
        .map(|(label, r)| {
            let row = format_row(label, &compare_reference(r, finest));
            let row = format!("{row} {:.2e} |", r.energy_error);
            log(&row);
            row
        })
        .collect())
}

/// The rows and plots of [`mode_study`].
fn mode_rows(
    beam: &Beam,
    s: &FullFeSetup,
    r: &ReferenceRun,
    counts: &[usize],
    out: &Path,
    log: &dyn Fn(&str),
) -> Result<Vec<String>> {
    let h = r.t[1] - r.t[0];
    let t_end = r.t[r.t.len() - 1];
    let mut rows = vec![format_row("full FE (9900 DOFs)", &compare_reference(r, r))];
    log(&rows[0]);
    let every = ((2.5e-4 / h).round() as usize).max(1);
    let sampled = |v: &[f64]| -> Vec<(f64, f64)> {
        (0..r.t.len())
            .step_by(every)
            .map(|i| (r.t[i], 1e3 * v[i]))
            .collect()
    };
    let mut node = vec![Series {
        name: "full FE".into(),
        points: sampled(&r.probe),
        style: Style::Line,
    }];
    let mut mass = vec![Series {
        name: "full FE".into(),
        points: sampled(&r.y),
        style: Style::Line,
    }];
    let base = Config {
        modes: 10,
        z0: 0.025,
        restitution: None,
        step: Some(h),
        band: false,
        t_end,
    };
    for &n in counts {
        let run = simulate(beam, &Config { modes: n, ..base })?;
        rows.push(format_row(
            &format!("FFR, {n} modes"),
            &compare_ffr(&run, r),
        ));
        log(rows.last().map_or("", |s| s.as_str()));
        for correction in [false, true] {
            let (k, m, w, p) = modal_system(beam, s, n, &s.w_nurbs, correction)?;
            let modal = simulate_penalty_impact(&k, &m, &w, &p, &penalty_setup(h, t_end))?;
            let label = match correction {
                false => format!("reference integrator, {n} modes"),
                true => format!("reference integrator, {n} modes + static response"),
            };
            rows.push(format_row(&label, &compare_reference(&modal, r)));
            log(rows.last().map_or("", |s| s.as_str()));
        }
        if [10, 40, 100, 200].contains(&n) {
            let scale = |v: &[(f64, f64)]| v.iter().map(|&(t, y)| (t, 1e3 * y)).collect();
            node.push(Series {
                name: format!("FFR, {n} modes"),
                points: scale(&run.node),
                style: Style::Line,
            });
            mass.push(Series {
                name: format!("FFR, {n} modes"),
                points: scale(&run.y),
                style: Style::Line,
            });
        }
    }
    write_full_fe_plots(out, h, node, mass)?;
    Ok(rows)
}

/// `node_full_fe` and `mass_full_fe` (png, svg).
fn write_full_fe_plots(out: &Path, h: f64, node: Vec<Series>, mass: Vec<Series>) -> Result<()> {
    for (series, file, what, unit) in [
        (
            node,
            "node_full_fe",
            "y displacement of node (250, 50, 25) mm",
            "u_y [mm]",
        ),
        (mass, "mass_full_fe", "height of the mass", "y [mm]"),
    ] {
        let plot = LinePlot {
            title: format!("Point mass on beam, setup A, S4 (h = {h:e} s): {what}, FFR vs full FE"),
            x_label: "t [s]".into(),
            y_label: unit.into(),
            series,
            log_x: false,
            log_y: false,
        };
        plot.write(&out.join(format!("{file}.png")))?;
        plot.write(&out.join(format!("{file}.svg")))?;
    }
    Ok(())
}

//! `complex_beam_frequencies` (seed 000 §5.1, Table 5.2 protocol): the FFR body of the complex beam
//! with its reference frame fixed to the ground, excited by initial modal velocities
//! `u_f(0:4) = [0.2, 0.17, 0.14, 0.1, 0.05]`; the frequency of each `q_f(k)` measured from the
//! simulated time series (zero crossings, linear interpolation) is compared with the modal analysis.

use crate::ValidationResult;
use anyhow::{bail, Context, Result};
use flexmbs_core::ffr::{reduced_body_to_si, FfrBody, FfrElement, RotationParam};
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
use flexmbs_core::{Joint, ModelSpec, Workspace};
use flexmbs_fe::reduction::ReducedBody;
use flexmbs_io::model::parse_fe_model;
use flexmbs_io::plot::{LinePlot, Series, Style};
use flexmbs_reduce::pipeline::{prepare, run_reduction};
use nalgebra::{Matrix3, Vector3};
use std::path::Path;

/// The model file of the body (also `examples/complex_beam.toml`).
pub const MODEL: &str = include_str!("../../../examples/complex_beam.toml");

/// Initial modal velocities of the seed's protocol.
pub const U_F0: [f64; 5] = [0.2, 0.17, 0.14, 0.1, 0.05];

/// Frequency of a sampled signal from its zero crossings (linear interpolation between samples):
/// `(n - 1) / (2 (t_last - t_first))` for `n` crossings.
pub fn zero_crossing_frequency(t: &[f64], x: &[f64]) -> Option<f64> {
    let mut crossings = Vec::new();
    for i in 1..x.len() {
        if (x[i - 1] < 0.0 && x[i] >= 0.0) || (x[i - 1] > 0.0 && x[i] <= 0.0) {
            let s = x[i - 1] / (x[i - 1] - x[i]);
            crossings.push(t[i - 1] + s * (t[i] - t[i - 1]));
        }
    }
    if crossings.len() < 3 {
        return None;
    }
    let n = crossings.len();
    Some((n - 1) as f64 / (2.0 * (crossings[n - 1] - crossings[0])))
}

/// The reduced body (30 lumped-mass modes) of the complex beam, in SI.
pub fn reduced_body() -> Result<ReducedBody> {
    let spec = parse_fe_model(MODEL, Path::new("examples/complex_beam.toml"))?.body;
    let prepared = prepare(&spec, Path::new("."), &mut |_| {})?;
    let body = run_reduction(&spec, &prepared, &mut |_| {})?;
    Ok(reduced_body_to_si(&body))
}

/// Simulates the protocol with step `h` to `t_end` for the lumped-mass FFR body of `body`;
/// returns time and the first five `q_f`.
pub fn simulate(body: &ReducedBody, h: f64, t_end: f64) -> Result<(Vec<f64>, Vec<[f64; 5]>)> {
    simulate_ffr(
        FfrBody::from_reduced(body, RotationParam::Cardan)?,
        h,
        t_end,
    )
}

/// Simulates the protocol with step `h` to `t_end` for an FFR body (reference frame clamped to the
/// ground, initial modal velocities [`U_F0`]); returns time and the first five `q_f`.
pub fn simulate_ffr(ffr: FfrBody, h: f64, t_end: f64) -> Result<(Vec<f64>, Vec<[f64; 5]>)> {
    let mut spec = ModelSpec::new();
    let b = spec.add_body("complex_beam", FfrElement::new(ffr));
    let fb = spec.add_frame("origin", b, Vector3::zeros(), Matrix3::identity());
    let fg = spec.add_ground_frame("ground", Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::fixed("clamp", fg, fb));
    let model = spec.compile()?;
    let mut state = model.initial_state();
    model.body_u_mut(b, &mut state.u)[6..6 + U_F0.len()].copy_from_slice(&U_F0);
    let mut ws = Workspace::new(&model);
    let integrator = GenAlpha::new(GenAlphaSettings {
        rho_inf: 1.0,
        ..GenAlphaSettings::default()
    })?;
    integrator.initialize(&model, &mut state, &mut ws)?;
    let mut t = vec![0.0];
    let mut q = vec![[0.0; 5]];
    integrator
        .integrate(&model, &mut state, &mut ws, h, t_end, |s, _| {
            t.push(s.t);
            let mut row = [0.0; 5];
            row.copy_from_slice(&model.body_q(b, &s.q)[6..11]);
            q.push(row);
        })
        .context("time integration")?;
    Ok((t, q))
}

/// Time step of the simulations: generalized-alpha with `rho_inf = 1` (trapezoidal rule) lowers a
/// frequency by `(omega h)^2 / 12`, 6.1e-5 for the fifth mode (8.6 kHz) at this step.
pub const STEP: f64 = 5e-7;

/// Simulated time in periods of the first mode (the `q_f` are single-frequency oscillations:
/// with the frame clamped the modal equations are linear and decoupled, so few periods suffice).
pub const PERIODS: f64 = 4.0;

/// Relative tolerance of the simulated frequencies (the 0.02 %).
pub const TOLERANCE: f64 = 2e-4;

/// The first five frequencies of the simulated `q_f` (zero crossings).
fn measured_frequencies(t: &[f64], q: &[[f64; 5]]) -> Result<[f64; 5]> {
    let mut f = [0.0; 5];
    for (k, fk) in f.iter_mut().enumerate() {
        let x: Vec<f64> = q.iter().map(|r| r[k]).collect();
        let Some(v) = zero_crossing_frequency(t, &x) else {
            bail!("q_f({k}) does not oscillate")
        };
        *fk = v;
    }
    Ok(f)
}

/// Time series of one variant for the plot.
struct Run {
    name: &'static str,
    t: Vec<f64>,
    q: Vec<[f64; 5]>,
}

/// Records the five frequencies of a variant (`suffix` "" or "_ccx") and adds table rows.
fn check_variant(
    res: &mut ValidationResult,
    table: &mut String,
    variant: &str,
    suffix: &str,
    simulated: &[f64; 5],
    reference: &[f64],
    quiet: bool,
) {
    for k in 0..5 {
        let (f, r) = (simulated[k], reference[k]);
        res.check(&format!("f{}_hz{suffix}", k + 1), f, r, TOLERANCE);
        *table += &format!(
            "| {variant} | {} | {:.3} | {:.3} | {:+.5} % |\n",
            k + 1,
            r,
            f,
            100.0 * (f - r) / r
        );
        if !quiet {
            eprintln!(
                "  {variant} mode {}: reference {r:.3} Hz, simulated {f:.3} Hz",
                k + 1
            );
        }
    }
}

/// The CalculiX variant: quantities `f1_hz_ccx` ... (simulated vs CalculiX's `.dat`),
/// `f1_hz_ccx_eig` ... (flexmbs's eigenvalues of the imported matrices vs the `.dat`, 1e-6:
/// the `.dat` has 7 digits), `mff_deviation_ccx` (largest |m_ff - Phi^T M Phi|, must be < 1e-10)
/// and `mass_isotropy_ccx` (relative deviation of the ccx mass from block isotropy).
fn run_ccx_variant(
    res: &mut ValidationResult,
    table: &mut String,
    quiet: bool,
    log: &mut dyn FnMut(&str),
) -> Result<Run> {
    let c = crate::complex_beam_ccx::ccx_body(5, log)?;
    let (ffr, mff_dev) = crate::complex_beam_ccx::ffr_body(&c)?;
    res.record("mass_isotropy_ccx", c.isotropy_deviation);
    res.record("mff_deviation_ccx", mff_dev);
    if mff_dev.is_nan() || mff_dev >= 1e-10 {
        res.pass = false;
        eprintln!(
            "  FAIL: m_ff of the consistent invariants deviates from Phi^T M Phi by {mff_dev:e}"
        );
    }
    for k in 0..5 {
        res.check(
            &format!("f{}_hz_ccx_eig", k + 1),
            c.body.frequencies_hz[k],
            c.dat_hz[k],
            1e-6,
        );
    }
    let (t, q) = simulate_ffr(ffr, STEP, PERIODS / c.dat_hz[0])?;
    log("ccx variant simulated");
    let f = measured_frequencies(&t, &q)?;
    check_variant(res, table, "CalculiX", "_ccx", &f, &c.dat_hz, quiet);
    Ok(Run { name: "ccx", t, q })
}

/// Runs the case: the built-in variant always, the CalculiX variant when `ccx` is installed
/// (otherwise `details.skipped_ccx` says why and no `_ccx` quantity is written).
pub fn run(out: &Path, quiet: bool) -> Result<ValidationResult> {
    let clock = std::time::Instant::now();
    let mut log = |m: &str| {
        if !quiet {
            eprintln!("  [{:6.1} s] {m}", clock.elapsed().as_secs_f64());
        }
    };
    let body = reduced_body()?;
    let modal: Vec<f64> = body.frequencies_hz[..5].to_vec();
    log("built-in body reduced");
    let (t, q) = simulate(&body, STEP, PERIODS / modal[0])?;
    log("built-in variant simulated");
    let mut res = ValidationResult::new("complex_beam_frequencies");
    let mut table = String::from(
        "| variant | mode | reference [Hz] | simulated [Hz] | error |\n|---|---|---|---|---|\n",
    );
    let f = measured_frequencies(&t, &q)?;
    check_variant(&mut res, &mut table, "built-in", "", &f, &modal, quiet);
    let mut runs = vec![Run {
        name: "built-in",
        t,
        q,
    }];
    if flexmbs_io::calculix::ccx_available().is_none() {
        let reason = "ccx (CalculiX) not found in PATH or $FLEXMBS_CCX: the CalculiX variant was not run (apt-get install calculix-ccx)";
        eprintln!("  SKIPPED: {reason}");
        res.details
            .insert("skipped_ccx".into(), serde_json::Value::from(reason));
    } else {
        runs.push(run_ccx_variant(&mut res, &mut table, quiet, &mut log)?);
    }
    std::fs::write(out.join("frequencies.md"), &table)?;
    write_plot(out, &runs)?;
    Ok(res)
}

/// Plot of the five `q_f`: built-in lines, CalculiX markers.
fn write_plot(out: &Path, runs: &[Run]) -> Result<()> {
    let mut series = Vec::new();
    for r in runs {
        let n_plot = r.t.len();
        let ccx = r.name == "ccx";
        for k in 0..5 {
            series.push(Series {
                name: format!("q_f({k}) {}", r.name),
                points: (0..n_plot)
                    .step_by(if ccx { 25 } else { 2 })
                    .map(|i| (r.t[i] * 1e3, r.q[i][k]))
                    .collect(),
                style: if ccx { Style::Points } else { Style::Line },
            });
        }
    }
    let plot = LinePlot {
        title: "Complex beam: modal coordinates after initial modal velocities".into(),
        x_label: "t [ms]".into(),
        y_label: "q_f [SI]".into(),
        series,
        log_x: false,
        log_y: false,
    };
    plot.write(&out.join("q_f.png"))?;
    plot.write(&out.join("q_f.svg"))?;
    Ok(())
}

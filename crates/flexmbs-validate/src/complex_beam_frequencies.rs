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
use flexmbs_io::pipeline::{prepare, run_reduction};
use flexmbs_io::plot::{LinePlot, Series, Style};
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

/// Simulates the protocol with step `h` to `t_end`; returns time and the first five `q_f`.
pub fn simulate(body: &ReducedBody, h: f64, t_end: f64) -> Result<(Vec<f64>, Vec<[f64; 5]>)> {
    let ffr = FfrBody::from_reduced(body, RotationParam::Cardan)?;
    let mut spec = ModelSpec::new();
    let b = spec.add_body("complex_beam", FfrElement::new(ffr));
    let fb = spec.add_frame("origin", b, Vector3::zeros(), Matrix3::identity());
    let fg = spec.add_ground_frame("ground", Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::fixed("clamp", fg, fb));
    let model = spec.compile()?;
    let mut state = model.initial_state();
    let u0 = model.bodies[b.0].u_offset;
    for (k, v) in U_F0.iter().enumerate() {
        state.u[u0 + 6 + k] = *v;
    }
    let mut ws = Workspace::new(&model);
    let integrator = GenAlpha::new(GenAlphaSettings {
        rho_inf: 1.0,
        ..GenAlphaSettings::default()
    })?;
    integrator.initialize(&model, &mut state, &mut ws)?;
    let q0 = model.bodies[b.0].q_offset;
    let mut t = vec![0.0];
    let mut q = vec![[0.0; 5]];
    integrator
        .integrate(&model, &mut state, &mut ws, h, t_end, |s, _| {
            t.push(s.t);
            let mut row = [0.0; 5];
            for (k, r) in row.iter_mut().enumerate() {
                *r = s.q[q0 + 6 + k];
            }
            q.push(row);
        })
        .context("time integration")?;
    Ok((t, q))
}

/// Runs the case.
pub fn run(out: &Path, quiet: bool) -> Result<ValidationResult> {
    let body = reduced_body()?;
    let modal: Vec<f64> = body.frequencies_hz[..5].to_vec();
    // generalized-alpha with rho_inf = 1 (trapezoidal rule) lowers a frequency by (omega h)^2 / 12:
    // h = 2e-7 s keeps that below 1e-5 for the fifth mode
    let h = 2e-7;
    let t_end = 12.0 / modal[0];
    let (t, q) = simulate(&body, h, t_end)?;
    let mut res = ValidationResult::new("complex_beam_frequencies");
    let mut table =
        String::from("| mode | modal [Hz] | simulated [Hz] | error |\n|---|---|---|---|\n");
    for k in 0..5 {
        let x: Vec<f64> = q.iter().map(|r| r[k]).collect();
        let Some(f) = zero_crossing_frequency(&t, &x) else {
            bail!("q_f({k}) does not oscillate")
        };
        res.check(&format!("f{}_hz", k + 1), f, modal[k], 2e-4);
        table += &format!(
            "| {} | {:.3} | {:.3} | {:+.4} % |\n",
            k + 1,
            modal[k],
            f,
            100.0 * (f - modal[k]) / modal[k]
        );
        if !quiet {
            eprintln!(
                "  mode {}: modal {:.3} Hz, simulated {:.3} Hz",
                k + 1,
                modal[k],
                f
            );
        }
    }
    std::fs::write(out.join("frequencies.md"), &table)?;
    let n_plot = t.len().min((5.0 / modal[0] / h) as usize);
    let series = (0..5)
        .map(|k| Series {
            name: format!("q_f({k})"),
            points: (0..n_plot)
                .step_by(10)
                .map(|i| (t[i] * 1e3, q[i][k]))
                .collect(),
            style: Style::Line,
        })
        .collect();
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
    Ok(res)
}

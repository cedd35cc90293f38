//! `sliding_balls` (seed 000 §5.3, `benchmarks.md`): a 1 kg ball (inertia 1e-3 kg m^2) whose
//! centre is bilaterally kept on the neutral axis of a soft cantilever (1.5 x 0.05 x 0.05 m,
//! E = 50 MPa, nu = 0.3, 920 kg/m^3, clamped at x = 0, no gravity; 30 x 2 x 2 20-node hexahedra,
//! consistent mass) and whose rotations follow the beam's contour frame
//! ([`flexmbs_core::contact::CurveGuide`]). The ball starts with (0.01, -0.002, 0) m/s; setup A
//! reduces the beam to 20 clamped modes, setup B to 100; Moreau time-stepping with step-size
//! control, 5 s.
//!
//! The seed does not give the ball's start; here it starts at mid-span, x = 0.75 m (assumed).
//! At 0.01 m/s it slides 5 cm in 5 s, so a second run ("traverse", 20 modes) sends it along the
//! whole beam: from x = 0.05 m at 0.3 m/s to x = 1.45 m, over every knot span of the axis curve.
//!
//! No published trajectory exists; the checks are laws and trends: after the first step (which
//! takes up the ball's transverse velocity, an impact) no work is done, so the total energy of
//! beam and ball stays constant up to the stepper's error; the ball's velocity has no jumps
//! (its discrete acceleration has no spikes: the C^2 requirement of sliding contact); the
//! constraint holds; the response converges with the number of modes (10/20/40/100). The
//! geometrically nonlinear reference ([`crate::sliding_balls_reference`], a corotational beam)
//! gives the comparison: ball x, ball height, tip deflection.

use crate::ValidationResult;
use anyhow::{Context, Result};
use flexmbs_core::contact::{CurveGuide, NeutralCurve};
use flexmbs_core::ffr::contour::{ContourSettings, FfrCurveContour};
use flexmbs_core::ffr::{FfrBody, FfrElement, RotationParam};
use flexmbs_core::integrator::{drive, MoreauSscSettings, MoreauSscStepper, Stepper};
use flexmbs_core::{BodyId, Joint, Model, ModelSpec, RigidBody, State, Workspace};
use flexmbs_io::plot::{LinePlot, Series, Style};
use nalgebra::{Matrix3, Vector3};
use std::ops::ControlFlow;
use std::path::Path;
use std::time::Instant;

/// The FE beam: SI units, modes clamped on the x = 0 face.
const BEAM: &str = r#"
[body]
name = "beam"
units = "SI"

[body.mesh]
type = "box"
size = [1.5, 0.05, 0.05]
divisions = [30, 2, 2]
element = "hex20"
material = { e = 50e6, nu = 0.3, rho = 920.0 }

[body.boundary]
fixed = ["xmin"]

[body.reduction]
method = "modal"
modes = 100
mass = "consistent"
"#;

/// The reduced beam (100 clamped modes) and its consistent mass matrix: the same pair as the
/// point-mass case's beam.
pub use crate::point_mass_on_beam::Beam;

/// Meshes and reduces the beam.
pub fn reduce_beam() -> Result<Beam> {
    let spec = flexmbs_io::model::parse_fe_model(BEAM, Path::new("sliding_balls.toml"))?.body;
    let (prepared, mass) =
        flexmbs_reduce::full_mass::prepare_with_mass(&spec, Path::new("."), &mut |_| {})?;
    let reduced = flexmbs_reduce::pipeline::run_reduction(&spec, &prepared, &mut |_| {})?;
    Ok(Beam { reduced, mass })
}

/// One run.
#[derive(Debug, Clone, Copy)]
pub struct Config {
    /// Modes of the beam.
    pub modes: usize,
    /// Initial x of the ball (m).
    pub x0: f64,
    /// Initial velocity of the ball along x (m/s).
    pub vx0: f64,
    /// End time (s).
    pub t_end: f64,
    /// Degree of the axis curve (3: C^2).
    pub degree: usize,
}

/// What a run gives.
#[derive(Debug, Clone, Default)]
pub struct Run {
    /// (t, x, y of the ball), every 10 ms.
    pub ball: Vec<(f64, f64, f64)>,
    /// (t, y displacement of the beam's tip on the axis), every 10 ms.
    pub tip: Vec<(f64, f64)>,
    /// (t, (E - E_1) / E_1), E_1 the energy after the first step.
    pub energy: Vec<(f64, f64)>,
    /// Largest |E - E_1| / E_1.
    pub energy_deviation: f64,
    /// Largest |g| of the constraint rows (clamp and guide) after a step.
    pub drift: f64,
    /// Largest discrete acceleration of the ball |Δv| / h over the steps after the first.
    pub acc_max: f64,
    /// RMS of the discrete acceleration.
    pub acc_rms: f64,
    /// Largest velocity change of the ball in one step (after the first).
    pub dv_max: f64,
    /// The ball left the curve's ends.
    pub beyond_end: bool,
    /// Final x of the ball.
    pub x_end: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Gauss-Seidel sweeps of the accepted steps' last half steps.
    pub sweeps: usize,
    /// Wall time of the integration (s).
    pub cpu: f64,
    /// Time the integrating thread ran on a CPU (s; Linux `/proc/thread-self/schedstat`, NaN
    /// elsewhere): unlike the wall time, it does not grow with other jobs on the machine.
    pub cpu_thread: f64,
    /// Largest out-of-plane displacement of the ball, |z - 25 mm| (m): the motion is planar.
    pub z_dev: f64,
}

fn nearest_node(nodes: &[[f64; 3]], p: [f64; 3]) -> usize {
    let d = |i: usize| (0..3).map(|k| (nodes[i][k] - p[k]).powi(2)).sum::<f64>();
    (0..nodes.len())
        .min_by(|&a, &b| d(a).total_cmp(&d(b)))
        .unwrap_or(0)
}

/// The model: (model, tip node index).
fn model(beam: &Beam, c: &Config) -> Result<(Model, usize)> {
    let cols: Vec<usize> = (0..c.modes).collect();
    let reduced = beam.reduced.restricted_to(&cols);
    let ffr = FfrBody::from_reduced_consistent(&reduced, &beam.mass, RotationParam::Cardan)?;
    let nodes = &reduced.nodes;
    let on_axis = |p: &[f64; 3]| (p[1] - 0.025).abs() < 1e-9 && (p[2] - 0.025).abs() < 1e-9;
    let mut line: Vec<usize> = (0..nodes.len()).filter(|&i| on_axis(&nodes[i])).collect();
    line.sort_by(|&a, &b| nodes[a][0].total_cmp(&nodes[b][0]));
    let tip = nearest_node(nodes, [1.5, 0.025, 0.025]);
    let settings = ContourSettings {
        degree: c.degree,
        ..ContourSettings::default()
    };
    let curve = FfrCurveContour::new(&ffr, &line, settings).context("axis curve")?;
    let mut spec = ModelSpec::new();
    let b = spec.add_body("beam", FfrElement::new(ffr));
    let fb = spec.add_frame("beam", b, Vector3::zeros(), Matrix3::identity());
    let fg = spec.add_ground_frame("ground", Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::fixed("clamp", fg, fb));
    let m = spec.add_body("ball", RigidBody::new(1.0, Matrix3::identity() * 1e-3));
    let fm = spec.add_frame("ball", m, Vector3::zeros(), Matrix3::identity());
    let axis = NeutralCurve::new(fb, curve, 0.0)?;
    spec.add_guide(CurveGuide::new("guide", axis, fm, Vector3::y(), true));
    Ok((spec.compile()?, tip))
}

/// Time the calling thread has run on a CPU so far (s), NaN where the kernel does not say.
fn thread_cpu_seconds() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .map_or(f64::NAN, |ns| 1e-9 * ns)
}

/// Runs configuration `c`.
pub fn simulate(beam: &Beam, c: &Config) -> Result<Run> {
    let (model, tip) = model(beam, c)?;
    let (b, m) = (BodyId(0), BodyId(1));
    let mut s = model.initial_state();
    let p0 = Vector3::new(c.x0, 0.025, 0.025);
    model.set_body_pose(&mut s, m, p0, Matrix3::identity());
    let v0 = Vector3::new(c.vx0, -0.002, 0.0);
    model.set_body_velocity(&mut s, m, v0, Vector3::zeros());
    let mut ws = Workspace::new(&model);
    let mut ws_out = Workspace::new(&model);
    let mut stepper = MoreauSscStepper::new(MoreauSscSettings {
        h_max: 2e-3,
        ..MoreauSscSettings::default()
    });
    let control = stepper.control();
    stepper.initialize(&model, &mut s, &mut ws)?;
    // the guide's projection at the accepted state, for `beyond_end` (kinematics and the rows'
    // values only; the energy is the stepper's own end-of-step monitor's, `stats.energy`)
    let guide_at = |s: &State, ws: &mut Workspace| {
        let sys = &mut ws.sys;
        let ok = flexmbs_core::system::evaluate_kinematics(&model, &s.q, &s.u, &mut sys.eval);
        flexmbs_core::system::update_frames(&model, &s.q, &s.u, &mut sys.eval, &mut sys.frames);
        flexmbs_core::system::update_constraint_values(&model, s.t, sys);
        ok.is_ok() && !sys.guides[0].beyond_end
    };
    let nf = c.modes;
    let tip_y = |s: &State| {
        let qf = &model.body_q(b, &s.q)[6..6 + nf];
        (0..nf)
            .map(|k| beam.reduced.modes_t[(3 * tip + 1, k)] * qf[k])
            .sum::<f64>()
    };
    let mut run = Run::default();
    let (mut e1, mut v_prev, mut t_prev) = (f64::NAN, v0, 0.0);
    let (mut acc_sq, mut n_acc) = (0.0, 0usize);
    let mut next_out = 0.0;
    let start = Instant::now();
    let start_thread = thread_cpu_seconds();
    drive(
        &mut stepper,
        &model,
        &mut s,
        &mut ws,
        control,
        c.t_end,
        |s, stats| {
            run.steps += 1;
            run.sweeps += stats.iterations;
            let v = Vector3::from_column_slice(&model.body_u(m, &s.u)[..3]);
            let e = stats.energy.total();
            if run.steps == 1 {
                e1 = e;
            } else {
                let dv = (v - v_prev).norm();
                let a = dv / (s.t - t_prev);
                run.dv_max = run.dv_max.max(dv);
                run.acc_max = run.acc_max.max(a);
                acc_sq += a * a;
                n_acc += 1;
            }
            (v_prev, t_prev) = (v, s.t);
            let de = (e - e1) / e1;
            run.energy_deviation = run.energy_deviation.max(de.abs());
            run.drift = run.drift.max(stats.g_max);
            run.beyond_end |= !guide_at(s, &mut ws_out);
            run.z_dev = run.z_dev.max((model.body_q(m, &s.q)[2] - 0.025).abs());
            if s.t >= next_out {
                let q = model.body_q(m, &s.q);
                run.ball.push((s.t, q[0], q[1]));
                run.tip.push((s.t, tip_y(s)));
                run.energy.push((s.t, de));
                next_out += 0.01;
            }
            ControlFlow::Continue(())
        },
    )?;
    run.cpu = start.elapsed().as_secs_f64();
    run.cpu_thread = thread_cpu_seconds() - start_thread;
    run.acc_rms = (acc_sq / n_acc.max(1) as f64).sqrt();
    run.x_end = model.body_q(m, &s.q)[0];
    Ok(run)
}

/// Writes the sampled series of a run as CSV: t, ball x, ball y, tip y (m), (E - E_1) / E_1.
pub fn write_series(path: &Path, r: &Run) -> Result<()> {
    let mut text = String::from("t,x,y,tip_y,energy_dev\n");
    for ((b, tip), e) in r.ball.iter().zip(&r.tip).zip(&r.energy) {
        text += &format!("{},{},{},{},{}\n", b.0, b.1, b.2, tip.1, e.1);
    }
    std::fs::write(path, text)?;
    Ok(())
}

/// Root-mean-square difference of two equally sampled series (the shorter length).
fn rms_difference(a: &[(f64, f64)], b: &[(f64, f64)]) -> f64 {
    let n = a.len().min(b.len()).max(1);
    let s: f64 = a.iter().zip(b).map(|(x, y)| (x.1 - y.1).powi(2)).sum();
    (s / n as f64).sqrt()
}

/// Root-mean-square of a series.
fn rms(a: &[(f64, f64)]) -> f64 {
    (a.iter().map(|x| x.1 * x.1).sum::<f64>() / a.len().max(1) as f64).sqrt()
}

/// Records the laws of one run under `key`; returns whether they hold: energy constant to
/// `5e-3` relative (the first-order stepper's error; measured values in the README), constraint
/// rows at round-off (`1e-9` m), no acceleration spike above 20 times the RMS acceleration (a
/// velocity jump), the ball on the curve.
fn record_run(res: &mut ValidationResult, key: &str, r: &Run) -> bool {
    res.record(&format!("energy_deviation_{key}"), r.energy_deviation);
    res.record(&format!("drift_{key}"), r.drift);
    res.record(&format!("acc_max_{key}"), r.acc_max);
    res.record(&format!("acc_rms_{key}"), r.acc_rms);
    res.record(&format!("dv_max_{key}"), r.dv_max);
    res.record(&format!("x_end_{key}"), r.x_end);
    res.record(&format!("steps_{key}"), r.steps as f64);
    res.record(&format!("cpu_s_{key}"), r.cpu);
    res.record(&format!("z_dev_{key}"), r.z_dev);
    r.energy_deviation < 5e-3
        && r.drift < 1e-9
        && r.acc_max < 20.0 * r.acc_rms
        && !r.beyond_end
        && r.x_end.is_finite()
}

/// Runs the case (module documentation). `SLIDING_BALLS_T_END` (s, default 0.5 so that CI runs it;
/// the seed's 5 s with `SLIDING_BALLS_T_END=5`) sets the end of the runs from
/// mid-span (the traverse always runs its 4.6 s); `SLIDING_BALLS_MODES` (e.g. `10,20`) selects
/// the mode counts (the last is the convergence reference).
pub fn run(out: &Path, quiet: bool) -> Result<ValidationResult> {
    let log = |m: &str| {
        if !quiet {
            println!("  {m}");
        }
    };
    let t_end: f64 = std::env::var("SLIDING_BALLS_T_END")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0.5);
    let beam = reduce_beam().context("reducing the beam")?;
    let f = &beam.reduced.frequencies_hz;
    log(&format!(
        "beam reduced: {} nodes, 100 modes, f1 = {:.3} Hz, f100 = {:.1} Hz",
        beam.reduced.num_nodes(),
        f.first().copied().unwrap_or(f64::NAN),
        f.last().copied().unwrap_or(f64::NAN)
    ));
    let mut res = ValidationResult::new("sliding_balls");
    res.record("t_end", t_end);
    res.record("f1_hz", f.first().copied().unwrap_or(f64::NAN));
    let base = Config {
        modes: 20,
        x0: 0.75,
        vx0: 0.01,
        t_end,
        degree: 3,
    };
    let mut ok = true;
    let mut runs = Vec::new();
    let counts: Vec<usize> = std::env::var("SLIDING_BALLS_MODES")
        .ok()
        .map(|v| v.split(',').filter_map(|x| x.parse().ok()).collect())
        .unwrap_or_else(|| vec![10, 20, 40, 100]);
    std::fs::create_dir_all(out)?;
    let write_csv = std::env::var_os("SLIDING_BALLS_SERIES").is_some();
    for n in counts {
        let r = simulate(&beam, &Config { modes: n, ..base })?;
        if write_csv {
            write_series(&out.join(format!("series_modes{n}.csv")), &r)?;
        }
        log(&format!(
            "{n} modes: x_end {:.5} m, tip y min {:.4e} m, energy dev {:.2e}, drift {:.1e}, \
             acc max/rms {:.2e}/{:.2e}, z dev {:.1e}, {} steps, {} sweeps, {:.2} s",
            r.x_end,
            r.tip.iter().map(|p| p.1).fold(f64::INFINITY, f64::min),
            r.energy_deviation,
            r.drift,
            r.acc_max,
            r.acc_rms,
            r.z_dev,
            r.steps,
            r.sweeps,
            r.cpu
        ));
        let key = match n {
            20 => "A".to_string(),
            100 => "B".to_string(),
            n => format!("modes{n}"),
        };
        ok &= record_run(&mut res, &key, &r);
        runs.push((n, r));
    }
    // mode convergence: ball y and tip y vs 100 modes (RMS difference over the run)
    let Some((_, reference)) = runs.last() else {
        anyhow::bail!("SLIDING_BALLS_MODES selects no mode count");
    };
    let ball_y = |r: &Run| r.ball.iter().map(|p| (p.0, p.2)).collect::<Vec<_>>();
    let y_ref = ball_y(reference);
    let y_ref0: Vec<(f64, f64)> = y_ref.iter().map(|p| (p.0, p.1 - 0.025)).collect();
    let mut previous = f64::INFINITY;
    for (n, r) in &runs[..runs.len() - 1] {
        let dy = rms_difference(&ball_y(r), &y_ref) / rms(&y_ref0);
        let dtip = rms_difference(&r.tip, &reference.tip) / rms(&reference.tip);
        log(&format!(
            "{n} modes vs 100: ball y RMS difference {dy:.3e}, tip y {dtip:.3e} (relative)"
        ));
        res.record(&format!("ball_y_rms_diff_modes{n}_vs_100"), dy);
        res.record(&format!("tip_y_rms_diff_modes{n}_vs_100"), dtip);
        ok &= dy <= previous * 1.05;
        previous = dy;
    }
    let reference = compare_with_reference(&mut res, &runs, &base, &log)?;
    ok &= reference.0;
    if write_csv {
        write_reference_series(&out.join("series_reference.csv"), &reference.1)?;
    }
    // the traverse: along the whole beam, over every knot span of the axis curve
    let traverse = Config {
        x0: 0.05,
        vx0: 0.3,
        t_end: 4.6,
        ..base
    };
    let r = simulate(&beam, &traverse)?;
    log(&format!(
        "traverse: x_end {:.4} m, energy dev {:.2e}, acc max/rms {:.2e}/{:.2e}, dv max {:.2e}, {} steps, {:.2} s",
        r.x_end, r.energy_deviation, r.acc_max, r.acc_rms, r.dv_max, r.steps, r.cpu
    ));
    ok &= record_run(&mut res, "traverse", &r);
    // the C^2 check on a curved contour (the straight beam cannot show it)
    let ring_dir = std::env::temp_dir().join(format!("flexmbs_ring_{}", std::process::id()));
    let arc = crate::sliding_balls_arc::check_arc(&mut res, &ring_dir, &log);
    let _ = std::fs::remove_dir_all(&ring_dir);
    let arc = arc?;
    res.pass = res.pass && ok;
    std::fs::create_dir_all(out)?;
    plots(out, &runs, &reference.1, &r)?;
    arc_plot(out, &arc)?;
    Ok(res)
}

/// The reference runs (elements, step): the finest is the comparison reference, the others
/// show its convergence in elements and step.
const REFERENCE_RUNS: [(usize, f64); 4] = [(10, 2.5e-4), (20, 2.5e-4), (40, 2.5e-4), (40, 1.25e-4)];

/// Relative tolerance of the 100-mode run against the nonlinear reference: RMS differences of
/// the ball's height and the tip deflection over 0.5 s, relative to the reference's RMS. It bounds
/// the difference of the two beam models (hex20 solid, loaded at an interior axis node, vs an
/// Euler-Bernoulli line), not nonlinearity (rotations stay below 3.2e-4 rad, nonlinear terms
/// O(1e-7)); chosen before the 100-mode comparison was run (measured 2.85e-2 / 2.78e-2, README).
const REFERENCE_TOLERANCE: f64 = 0.03;

/// Runs the nonlinear reference ([`crate::sliding_balls_reference`]) and compares the FFR runs
/// with it: ball x, ball height, tip deflection; returns whether setup B is within
/// [`REFERENCE_TOLERANCE`], and the finest reference run.
fn compare_with_reference(
    res: &mut ValidationResult,
    runs: &[(usize, Run)],
    base: &Config,
    log: &dyn Fn(&str),
) -> Result<(bool, crate::sliding_balls_reference::ReferenceRun)> {
    use crate::sliding_balls_reference as reference;
    let mut refs = Vec::new();
    for (n, h) in REFERENCE_RUNS {
        let start = Instant::now();
        let r = reference::simulate(n, 1.0, h, base.t_end, h, base.x0, base.vx0, -0.002)
            .map_err(|e| anyhow::anyhow!("reference ({n} elements, h = {h}): {e}"))?;
        let cpu = start.elapsed().as_secs_f64();
        let key = format!("ref_n{n}_h{:.0}us", h * 1e6);
        let tip_min = r.samples.iter().map(|s| s[3]).fold(f64::INFINITY, f64::min);
        log(&format!(
            "reference {n} elements, h = {h}: x_end {:.6} m, tip y min {tip_min:.4e} m, largest \
             rotation {:.2e} rad, energy dev {:.2e}, {:.1} Newton iterations per step, {cpu:.1} s",
            r.samples.last().map_or(f64::NAN, |s| s[1]),
            r.rotation_max,
            r.energy_deviation,
            r.iterations as f64 / r.steps.max(1) as f64
        ));
        res.record(&format!("energy_deviation_{key}"), r.energy_deviation);
        res.record(&format!("tip_y_min_{key}"), tip_min);
        res.record(&format!("rotation_max_{key}"), r.rotation_max);
        res.record(&format!("cpu_s_{key}"), cpu);
        refs.push((key, r));
    }
    let Some((_, best)) = refs.last() else {
        anyhow::bail!("no reference run");
    };
    let series = |r: &reference::ReferenceRun, col: usize| -> Vec<(f64, f64)> {
        r.samples.iter().map(|s| (s[0], s[col])).collect()
    };
    let (ref_y, ref_tip) = (series(best, 2), series(best, 3));
    let (rms_y, rms_tip) = (rms(&ref_y), rms(&ref_tip));
    // convergence of the reference: coarser runs vs the finest
    for (key, r) in &refs[..refs.len() - 1] {
        let at = |col: usize| -> Vec<(f64, f64)> {
            r.samples
                .iter()
                .map(|s| (s[0], reference::interpolate(&best.samples, col, s[0])))
                .collect()
        };
        let dy = rms_difference(&series(r, 2), &at(2)) / rms_y;
        let dtip = rms_difference(&series(r, 3), &at(3)) / rms_tip;
        log(&format!(
            "{key} vs finest: ball y RMS difference {dy:.2e}, tip y {dtip:.2e} (relative)"
        ));
        res.record(&format!("ball_y_rms_diff_{key}_vs_finest"), dy);
        res.record(&format!("tip_y_rms_diff_{key}_vs_finest"), dtip);
    }
    let mut ok = true;
    for (n, r) in runs {
        let [dy, dtip, dx] = differences_to_reference(r, best);
        log(&format!(
            "{n} modes vs reference: ball y RMS difference {dy:.2e}, tip y {dtip:.2e} \
             (relative), ball x largest difference {dx:.2e} m"
        ));
        res.record(&format!("ball_y_rms_diff_modes{n}_vs_ref"), dy);
        res.record(&format!("tip_y_rms_diff_modes{n}_vs_ref"), dtip);
        res.record(&format!("ball_x_diff_modes{n}_vs_ref"), dx);
        if *n == 100 {
            // a bound on a relative difference (no reference value): a quantity, not `check`
            res.record("rms_diff_vs_ref_bound_B", REFERENCE_TOLERANCE);
            ok &= dy < REFERENCE_TOLERANCE && dtip < REFERENCE_TOLERANCE;
        }
    }
    // diagnostic, not the reference: the same reference with E scaled so that its first clamped
    // frequency equals the FE solid's (it shows whether the first frequency's difference explains
    // the deviation; measured: it does not)
    let f_fe = res.quantities.get("f1_hz").copied().unwrap_or(f64::NAN);
    let f_eb = reference::clamped_frequencies(&reference::BallOnBeam::sliding_balls(40, 1.0), 1);
    let factor = (f_fe / f_eb.first().copied().unwrap_or(f64::NAN)).powi(2);
    res.record(
        "f1_hz_reference_40",
        f_eb.first().copied().unwrap_or(f64::NAN),
    );
    res.record("stiffness_factor_f1_matched", factor);
    let (nm, hm) = REFERENCE_RUNS[REFERENCE_RUNS.len() - 2];
    let matched = reference::simulate(nm, factor, hm, base.t_end, hm, base.x0, base.vx0, -0.002)
        .map_err(|e| anyhow::anyhow!("f1-matched reference: {e}"))?;
    for (n, r) in runs {
        let [dy, dtip, _] = differences_to_reference(r, &matched);
        log(&format!(
            "{n} modes vs f1-matched reference (E x {factor:.5}): ball y RMS difference \
             {dy:.2e}, tip y {dtip:.2e} (relative)"
        ));
        res.record(&format!("ball_y_rms_diff_modes{n}_vs_ref_f1matched"), dy);
        res.record(&format!("tip_y_rms_diff_modes{n}_vs_ref_f1matched"), dtip);
    }
    res.record("ref_energy_after_impact", best.e0);
    res.record("ref_tip_y_max_abs", best.tip_max);
    Ok((ok, best.clone()))
}

/// Differences of an FFR run to a reference run: `[RMS difference of the ball's height, RMS
/// difference of the tip deflection]`, each relative to the reference's RMS (the reference
/// interpolated linearly at the FFR sample times), and the largest difference of the ball's x (m).
pub fn differences_to_reference(
    r: &Run,
    reference: &crate::sliding_balls_reference::ReferenceRun,
) -> [f64; 3] {
    use crate::sliding_balls_reference::interpolate;
    let at = |col: usize, t: f64| interpolate(&reference.samples, col, t);
    let series = |col: usize| -> Vec<(f64, f64)> {
        reference.samples.iter().map(|s| (s[0], s[col])).collect()
    };
    let y: Vec<(f64, f64)> = r.ball.iter().map(|p| (p.0, p.2 - 0.025)).collect();
    let y_ref: Vec<(f64, f64)> = r.ball.iter().map(|p| (p.0, at(2, p.0))).collect();
    let tip_ref: Vec<(f64, f64)> = r.tip.iter().map(|p| (p.0, at(3, p.0))).collect();
    let dy = rms_difference(&y, &y_ref) / rms(&series(2));
    let dtip = rms_difference(&r.tip, &tip_ref) / rms(&series(3));
    let dx = r
        .ball
        .iter()
        .map(|p| (p.1 - at(1, p.0)).abs())
        .fold(0.0, f64::max);
    [dy, dtip, dx]
}

/// Writes the reference's samples (every 1 ms) as CSV: t, ball x, ball y, tip y (m), energy (J).
pub fn write_reference_series(
    path: &Path,
    r: &crate::sliding_balls_reference::ReferenceRun,
) -> Result<()> {
    let mut text = String::from("t,x,y,tip_y,energy\n");
    let mut next = 0.0;
    for s in &r.samples {
        if s[0] >= next - 1e-9 {
            text += &format!("{},{},{},{},{}\n", s[0], s[1], s[2], s[3], s[4]);
            next += 1e-3;
        }
    }
    std::fs::write(path, text)?;
    Ok(())
}

/// The ring's acceleration along the contour for the quadratic and the cubic contour.
fn arc_plot(out: &Path, runs: &[crate::sliding_balls_arc::ArcRun]) -> Result<()> {
    let series = runs
        .iter()
        .filter(|r| r.degree > 1)
        .map(|r| Series {
            name: format!("contour degree {} (C^{})", r.degree, r.degree - 1),
            points: r.acceleration.clone(),
            style: Style::Line,
        })
        .collect();
    let plot = LinePlot {
        title: "Ball guided on a quarter ring: |a| / (v0^2 / R) (degree 1: spikes of 490)".into(),
        x_label: "angle along the ring [deg]".into(),
        y_label: "|a| / (v0^2 / R)".into(),
        series,
        log_x: false,
        log_y: false,
    };
    plot.write(&out.join("ring_acceleration.png"))?;
    plot.write(&out.join("ring_acceleration.svg"))?;
    Ok(())
}

fn plots(
    out: &Path,
    runs: &[(usize, Run)],
    reference: &crate::sliding_balls_reference::ReferenceRun,
    traverse: &Run,
) -> Result<()> {
    let line = |name: String, points: Vec<(f64, f64)>| Series {
        name,
        points,
        style: Style::Line,
    };
    let write = |name: &str, title: &str, y_label: &str, series: Vec<Series>| -> Result<()> {
        let plot = LinePlot {
            title: title.into(),
            x_label: "t [s]".into(),
            y_label: y_label.into(),
            series,
            log_x: false,
            log_y: false,
        };
        plot.write(&out.join(format!("{name}.png")))?;
        plot.write(&out.join(format!("{name}.svg")))?;
        Ok(())
    };
    let per_mode = |f: &dyn Fn(&Run) -> Vec<(f64, f64)>| {
        runs.iter()
            .map(|(n, r)| line(format!("{n} modes"), f(r)))
            .collect::<Vec<_>>()
    };
    let with_reference = |mut series: Vec<Series>, col: usize| {
        let step = (reference.samples.len() / 2000).max(1);
        series.push(line(
            "nonlinear reference (40 el.)".into(),
            reference
                .samples
                .iter()
                .step_by(step)
                .map(|s| (s[0], 1e3 * s[col]))
                .collect(),
        ));
        series
    };
    write(
        "ball_y",
        "Sliding ball from x = 0.75 m: height of the ball's centre",
        "y - 25 mm [mm]",
        with_reference(
            per_mode(&|r| r.ball.iter().map(|p| (p.0, 1e3 * (p.2 - 0.025))).collect()),
            2,
        ),
    )?;
    write(
        "tip_y",
        "Sliding ball from x = 0.75 m: tip deflection of the beam's axis",
        "u_y(tip) [mm]",
        with_reference(
            per_mode(&|r| r.tip.iter().map(|p| (p.0, 1e3 * p.1)).collect()),
            3,
        ),
    )?;
    write(
        "energy",
        "Sliding ball: relative energy change after the first step",
        "(E - E1) / E1",
        per_mode(&|r| r.energy.clone()),
    )?;
    write(
        "traverse",
        "Ball along the whole beam (0.3 m/s, 20 modes): x [m] and y - 25 mm [mm]",
        "x [m], y [mm]",
        vec![
            line(
                "x [m]".into(),
                traverse.ball.iter().map(|p| (p.0, p.1)).collect(),
            ),
            line(
                "y - 25 mm [mm]".into(),
                traverse
                    .ball
                    .iter()
                    .map(|p| (p.0, 1e3 * (p.2 - 0.025)))
                    .collect(),
            ),
        ],
    )?;
    Ok(())
}

//! `spinning_beam` (seed 001 §5.1, after Cardona & Geradin 1991), a **consistent variant**
//! (the published torque would spin this beam at ~1e4 rad/s): a steel beam (L = 141.42 mm,
//! 3 x 3 mm square, E = 210 GPa, rho = 7800 kg/m³) on a spherical joint at its base, horizontal
//! along x at the start, at rest, gravity 0. A torque about the vertical axis on the base,
//! triangular over `0..10.2 s` with the impulse that spins the rigid beam up to 0.1 rad/s; a
//! vertical tip force pulse at `t = 25.2 s` (1 mN for 50 ms: short against the spin, long against
//! the beam's 551 Hz first flexible mode); run to 50 s. The beam as 2 superelements (seed
//! 001), generalized-alpha `rho_inf = 1` (no numerical dissipation), fixed step.
//!
//! Checks (physics, no reference from flexmbs): the angular momentum about the vertical axis
//! through the joint equals the torque impulse at every sample after the torque ends (the joint
//! reaction passes through the pivot, the vertical tip force has no moment about the vertical
//! axis); the energy is constant after the pulse; the kinetic energy at the end of the torque
//! equals the rigid beam's `J² / (2 I_zz)`; the angular velocity about the vertical axis at the
//! base at 50 s equals the rigid value `J / I_zz` (for a rigid slender beam on a spherical joint
//! the vertical impulse tilts the rotation axis but leaves `omega_z = H_z / I_1` unchanged); the
//! highest tip position after the pulse equals the rigid beam's `L omega_t / |omega|`.

use crate::ValidationResult;
use anyhow::{Context, Result};
use flexmbs_core::integrator::{monitor, GenAlpha, GenAlphaSettings};
use flexmbs_core::superelement::{beam_segment, BeamSegmentSpec, FrameLocation, Superelement};
use flexmbs_core::{
    FrameId, Joint, Load, LoadCoordinates, Model, ModelSpec, NodeKind, State, TimeFunction,
    Workspace,
};
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::Material;
use flexmbs_io::plot::{LinePlot, Series, Style};
use nalgebra::{Matrix3, Vector3};
use std::path::Path;

/// Beam length (m).
pub const LENGTH: f64 = 0.14142;
/// Side of the square section (m).
pub const SIDE: f64 = 0.003;
/// Density (kg/m³).
pub const RHO: f64 = 7800.0;
/// End of the torque (s).
pub const T_TORQUE: f64 = 10.2;
/// Start of the tip force pulse (s).
pub const T_PULSE: f64 = 25.2;
/// Duration of the tip force pulse (s).
pub const PULSE: f64 = 0.05;
/// Peak tip force of the triangular pulse (N).
pub const TIP_FORCE: f64 = 2e-3;
/// Target angular velocity of the rigid beam after the torque (rad/s).
pub const OMEGA_TARGET: f64 = 0.1;
/// End of the run (s).
pub const T_END: f64 = 50.0;

/// Moment of inertia of the uniform beam about the vertical axis through its end:
/// `rho A L³ / 3 + rho I_z L` (translation plus the cross-section's rotary inertia).
pub fn inertia_about_pivot() -> f64 {
    let a = SIDE * SIDE;
    let iz = SIDE.powi(4) / 12.0;
    RHO * a * LENGTH.powi(3) / 3.0 + RHO * iz * LENGTH
}

/// Torque impulse `J = I_zz omega_target` (N m s).
pub fn torque_impulse() -> f64 {
    inertia_about_pivot() * OMEGA_TARGET
}

/// The triangular torque profile (peak at `T_TORQUE / 2`, impulse [`torque_impulse`]).
fn torque_profile() -> TimeFunction {
    let peak = 2.0 * torque_impulse() / T_TORQUE;
    TimeFunction::Table {
        times: vec![0.0, 0.5 * T_TORQUE, T_TORQUE],
        values: vec![0.0, peak, 0.0],
    }
}

/// The tip force pulse: a triangle over `T_PULSE..T_PULSE + PULSE` with peak 1 (impulse
/// `PULSE / 2` times [`TIP_FORCE`]).
fn pulse_profile() -> TimeFunction {
    TimeFunction::Table {
        times: vec![T_PULSE, T_PULSE + 0.5 * PULSE, T_PULSE + PULSE],
        values: vec![0.0, 1.0, 0.0],
    }
}

/// The beam as `bodies` superelements on a spherical joint; the frames at the base and the tip.
fn build(bodies: usize) -> Result<(Model, State, [FrameId; 2])> {
    let material = Material {
        e: 210e9,
        nu: 0.3,
        rho: RHO,
    };
    let l = LENGTH / bodies as f64;
    let mut spec = ModelSpec::new();
    let i3 = Matrix3::identity();
    let nodes: Vec<_> = (0..=bodies)
        .map(|i| spec.add_node(&format!("n{i}"), NodeKind::Pose))
        .collect();
    let mut segs = Vec::new();
    for i in 0..bodies {
        let data = beam_segment(&BeamSegmentSpec {
            length: l,
            material,
            section: BeamSection::rectangle(SIDE, SIDE),
            theory: BeamTheory::EulerBernoulli,
            elements: 2,
            internal_modes: 0,
            frame: FrameLocation::CentreOfMass,
        })?;
        segs.push(spec.add_body_on(
            &format!("beam{i}"),
            Superelement::new(data)?,
            &nodes[i..i + 2],
        ));
    }
    let ground = spec.add_ground_frame("pivot", Vector3::zeros(), i3);
    let base = spec.add_node_owned_frame("base", nodes[0], Vector3::zeros(), i3);
    let tip = spec.add_node_owned_frame("tip", nodes[bodies], Vector3::zeros(), i3);
    spec.add_joint(Joint::spherical("pivot", ground, base));
    spec.add_load(Load::Torque {
        frame: base,
        vector: Vector3::z(),
        time: torque_profile(),
        coordinates: LoadCoordinates::Global,
    });
    spec.add_load(Load::Force {
        frame: tip,
        vector: Vector3::z() * TIP_FORCE,
        time: pulse_profile(),
        coordinates: LoadCoordinates::Global,
    });
    let model = spec.compile()?;
    let mut s = model.initial_state();
    for (i, b) in segs.iter().enumerate() {
        model.set_body_pose(&mut s, *b, Vector3::new((i as f64 + 0.5) * l, 0.0, 0.0), i3);
    }
    Ok((model, s, [base, tip]))
}

/// Angular momentum about the vertical axis through the origin: `u_r^T M u` with `u_r` the
/// generalized velocity of a unit rigid rotation about z, by polarization of the kinetic energy
/// (`T(u + u_r) - T(u) - T(u_r)`; `T` is exactly quadratic in `u`).
fn angular_momentum_z(model: &Model, s: &State, ws: &mut Workspace) -> f64 {
    let mut r = s.clone();
    r.u.iter_mut().for_each(|x| *x = 0.0);
    for n in model.node_ids() {
        let q = model.node_q(n, &s.q);
        let x = Vector3::from_column_slice(&q[..3]);
        model.nodes[n.index()].kind.set_velocity(
            q,
            model.node_u_mut(n, &mut r.u),
            &Vector3::z().cross(&x),
            &Vector3::z(),
        );
    }
    let kinetic = |st: &State, ws: &mut Workspace| monitor(model, st, ws).0.kinetic;
    let t_r = kinetic(&r, ws);
    let t_u = kinetic(s, ws);
    let mut sum = s.clone();
    sum.u.iter_mut().zip(&r.u).for_each(|(a, b)| *a += b);
    kinetic(&sum, ws) - t_u - t_r
}

/// Samples of a run.
#[derive(Debug, Clone, Default)]
pub struct Run {
    /// Sample times (s).
    pub t: Vec<f64>,
    /// Angular velocity about z of the base cross-section (rad/s).
    pub omega_z: Vec<f64>,
    /// Angular momentum about the vertical axis through the pivot (N m s).
    pub h_z: Vec<f64>,
    /// Total energy (J).
    pub energy: Vec<f64>,
    /// Vertical tip position (m).
    pub tip_z: Vec<f64>,
}

/// Simulates the spinning beam with `bodies` superelements, step `h`, `rho_inf`, sampling every
/// `every` steps.
pub fn simulate(bodies: usize, h: f64, rho_inf: f64, every: usize) -> Result<Run> {
    let (model, mut s, [base, tip]) = build(bodies)?;
    let mut ws = Workspace::new(&model);
    let mut ws_out = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings {
        rho_inf,
        ..GenAlphaSettings::default()
    })?;
    ga.initialize(&model, &mut s, &mut ws)?;
    let mut run = Run::default();
    let mut failed = false;
    let mut sample = |st: &State, run: &mut Run| {
        let (Some(kb), Some(kt)) = (
            model.frame_kinematics(st, base),
            model.frame_kinematics(st, tip),
        ) else {
            failed = true;
            return;
        };
        run.t.push(st.t);
        run.omega_z.push(kb.angular_velocity[2]);
        run.tip_z.push(kt.position[2]);
        run.energy.push(monitor(&model, st, &mut ws_out).0.total());
        run.h_z.push(angular_momentum_z(&model, st, &mut ws_out));
    };
    sample(&s, &mut run);
    let mut k = 0usize;
    ga.integrate(&model, &mut s, &mut ws, h, T_END, |st, _| {
        k += 1;
        if k.is_multiple_of(every) {
            sample(st, &mut run);
        }
    })
    .context("time integration of the spinning beam")?;
    anyhow::ensure!(!failed, "frame kinematics failed");
    Ok(run)
}

/// Largest `|x_i - x_ref| / |x_ref|` over the samples with `t > t0`.
fn max_rel_deviation(t: &[f64], x: &[f64], t0: f64, x_ref: f64) -> f64 {
    t.iter()
        .zip(x)
        .filter(|(t, _)| **t > t0)
        .fold(0.0f64, |m, (_, x)| m.max(((x - x_ref) / x_ref).abs()))
}

/// The value at the first sample at or after `t0`.
fn at(t: &[f64], x: &[f64], t0: f64) -> f64 {
    t.iter()
        .position(|s| *s >= t0 - 1e-9)
        .map_or(f64::NAN, |i| x[i])
}

/// Tolerances of one run: angular momentum and energy drift (relative, largest over the
/// samples), angular velocity at the end (relative to the rigid value).
struct Tolerances {
    momentum: f64,
    energy: f64,
    omega_end: f64,
}

/// Records and checks one run (quantities with `suffix`).
fn check_run(res: &mut ValidationResult, r: &Run, suffix: &str, tol: &Tolerances) -> String {
    let (j, izz) = (torque_impulse(), inertia_about_pivot());
    let omega_rigid = j / izz;
    let mut limit = |name: &str, v: f64, max: f64| {
        res.record(&format!("{name}{suffix}"), v);
        res.record(&format!("{name}{suffix}_limit"), max);
        if v.is_nan() || v > max {
            res.pass = false;
        }
    };
    // angular momentum about the vertical axis after the torque: the torque impulse
    let dh = max_rel_deviation(&r.t, &r.h_z, T_TORQUE + 1e-9, j);
    limit("h_z_max_rel_deviation_after_torque", dh, tol.momentum);
    // energy constant after the pulse
    let t_after = T_PULSE + PULSE + 0.1;
    let e_after = at(&r.t, &r.energy, t_after);
    let de = max_rel_deviation(&r.t, &r.energy, t_after, e_after);
    limit("energy_max_rel_drift_after_pulse", de, tol.energy);
    res.record(&format!("energy_after_pulse{suffix}"), e_after);
    // rigid spin-up: kinetic energy and angular velocity before the pulse
    let e_spin = at(&r.t, &r.energy, T_TORQUE);
    res.check(
        &format!("energy_after_torque{suffix}"),
        e_spin,
        0.5 * j * j / izz,
        1e-3,
    );
    let w_before = at(&r.t, &r.omega_z, T_PULSE - 0.1);
    res.check(
        &format!("omega_z_before_pulse{suffix}"),
        w_before,
        omega_rigid,
        1e-3,
    );
    let omega_end = *r.omega_z.last().unwrap_or(&f64::NAN);
    res.check(
        &format!("omega_z_end{suffix}"),
        omega_end,
        omega_rigid,
        tol.omega_end,
    );
    // the vertical impulse P = F_peak PULSE / 2 at the tip tilts the rigid rotation axis: tilt
    // rate omega_t = P L / I_1; the beam turns about the fixed axis omega = H / I_1, so the tip
    // rises to L omega_t / |omega|
    let omega_t = TIP_FORCE * PULSE / 2.0 * LENGTH / izz;
    let z_rigid = LENGTH * omega_t / omega_t.hypot(omega_rigid);
    let z_max = r.tip_z.iter().copied().fold(f64::MIN, f64::max);
    res.check(&format!("tip_z_max{suffix}"), z_max, z_rigid, 1e-3);
    let after: Vec<f64> =
        r.t.iter()
            .zip(&r.omega_z)
            .filter(|(t, _)| **t > t_after)
            .map(|(_, w)| *w)
            .collect();
    let mean = after.iter().sum::<f64>() / after.len() as f64;
    res.record(&format!("omega_z_mean_after_pulse{suffix}"), mean);
    format!(
        "omega_z(50 s) {omega_end:.6} rad/s (rigid {omega_rigid:.6}), mean after the pulse {mean:.6}, max |dH_z|/J {dh:.2e}, energy drift after the pulse {de:.2e}"
    )
}

/// Runs the case: 2 superelements, h = 5 ms, `rho_inf` = 1 (no suffix) and 0.9 (`_rho09`).
pub fn run(out: &Path, quiet: bool) -> Result<ValidationResult> {
    let log = |m: &str| {
        if !quiet {
            eprintln!("  {m}");
        }
    };
    let mut res = ValidationResult::new("spinning_beam");
    let (h, every) = (5e-3, 10);
    res.record("torque_impulse", torque_impulse());
    res.record("inertia_about_pivot", inertia_about_pivot());
    res.record("step", h);
    let runs = [
        (
            1.0,
            "",
            Tolerances {
                momentum: 1e-3,
                energy: 1e-3,
                omega_end: 0.01,
            },
        ),
        (
            0.9,
            "_rho09",
            Tolerances {
                momentum: 1e-5,
                energy: 1e-5,
                omega_end: 1e-4,
            },
        ),
    ];
    let mut results = Vec::new();
    for (rho, suffix, tol) in runs {
        let clock = std::time::Instant::now();
        let r = simulate(2, h, rho, every)?;
        let cpu = clock.elapsed().as_secs_f64();
        let line = check_run(&mut res, &r, suffix, &tol);
        log(&format!(
            "2 superelements, h = {h} s, rho_inf = {rho}: {line} ({cpu:.1} s)"
        ));
        results.push((rho, r));
    }
    write_plots(out, &results)?;
    Ok(res)
}

fn write_plots(out: &Path, runs: &[(f64, Run)]) -> Result<()> {
    let series = |rho: f64, r: &Run, x: &[f64], scale: f64| Series {
        name: format!("2 superelements, rho_inf = {rho}"),
        points: r.t.iter().zip(x).map(|(t, v)| (*t, v * scale)).collect(),
        style: Style::Line,
    };
    let plots = [
        (
            "omega_z",
            "Spinning beam: angular velocity about the vertical axis at the base",
            "omega_z [rad/s]",
        ),
        (
            "tip_z",
            "Spinning beam: vertical tip position",
            "z_tip [mm]",
        ),
    ];
    for (file, title, y_label) in plots {
        let plot = LinePlot {
            title: title.into(),
            x_label: "t [s]".into(),
            y_label: y_label.into(),
            series: runs
                .iter()
                .map(|(rho, r)| match file {
                    "omega_z" => series(*rho, r, &r.omega_z, 1.0),
                    _ => series(*rho, r, &r.tip_z, 1e3),
                })
                .collect(),
            log_x: false,
            log_y: false,
        };
        plot.write(&out.join(format!("{file}.png")))?;
        plot.write(&out.join(format!("{file}.svg")))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs the case into a temporary folder, prints its summary and asserts that it passes.
    #[test]
    #[ignore = "the whole case, which `flexmbs validate --all` already runs in CI: run with --ignored"]
    fn whole_case() {
        let dir = std::env::temp_dir().join("spinning_beam_case");
        std::fs::create_dir_all(&dir).unwrap();
        let r = run(&dir, false).unwrap();
        eprintln!("{}", r.summary());
        eprintln!("{:?}", r.quantities);
        assert!(r.pass, "{}", r.summary());
    }
}

#[cfg(test)]
mod step_convergence {
    use super::*;

    /// With `rho_inf = 1` the beam's unresolved flexible vibrations (first mode 551 Hz against
    /// h = 5 ms) are kept undamped and alias through the geometric nonlinearity: the angular
    /// momentum and energy errors after the pulse fall fast with the step (measured 2.9e-4,
    /// 2.0e-5, 8.9e-7 for H_z and 4.3e-4, 2.4e-5, 1.5e-6 for the energy at h = 5, 2.5, 1 ms),
    /// while before the pulse H_z holds to 6e-8. About 40 s (dev profile).
    #[test]
    #[ignore = "about 40 s (dev profile): run with --ignored"]
    fn rho_one_conserves_as_the_step_falls() {
        let j = torque_impulse();
        let mut previous = f64::INFINITY;
        for (h, every) in [(2.5e-3, 20), (1e-3, 50)] {
            let r = simulate(2, h, 1.0, every).unwrap();
            let dh = max_rel_deviation(&r.t, &r.h_z, T_TORQUE + 1e-9, j);
            let t_after = T_PULSE + PULSE + 0.1;
            let de = max_rel_deviation(&r.t, &r.energy, t_after, at(&r.t, &r.energy, t_after));
            eprintln!("h = {h}: max |dH_z|/J {dh:.2e}, energy drift {de:.2e}");
            assert!(dh < 0.2 * previous, "h = {h}: {dh:e} after {previous:e}");
            assert!(dh < 5e-5 && de < 5e-5, "h = {h}: {dh:e}, {de:e}");
            previous = dh;
        }
    }
}

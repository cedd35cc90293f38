//! `rotating_beam` (seed 001 §5.2) with the tube as a chain of `n` equal superelements
//! (Craig-Bampton static modes of 2 FE beam elements each, exact matrices) sharing interface pose
//! nodes, hinged at the first interface node to the ground by a revolute joint with the
//! prescribed rate 100 rad/s; the floating frame of every segment at its centre of mass or at its
//! first interface point (seed 001 Figs. 5.10-5.14). The 50 N tip force acts at the last
//! interface node during the first 0.01 s along the hub's y axis `(-sin Omega t, cos Omega t, 0)`
//! (two global force components with [`HubAxis`] time functions), as in the reference
//! ([`crate::rotating_beam_reference`]). Output: the tip deflection in the rotating frame,
//! `w = -x sin Omega t + y cos Omega t` of the tip node.

use crate::rotating_beam::{first_peak, omega_after_pulse};
use crate::ValidationResult;
use anyhow::{Context, Result};
use flexmbs_core::algebra::LinearSolver;
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
use flexmbs_core::superelement::{beam_segment, BeamSegmentSpec, FrameLocation, Superelement};
use flexmbs_core::user_function::{UserFunctionRef, UserTimeFunction};
use flexmbs_core::{
    Joint, Load, LoadCoordinates, Model, ModelSpec, NodeKind, PrescribedMotion, State,
    TimeFunction, Workspace,
};
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::Material;
use flexmbs_io::plot::{LinePlot, Series, Style};
use nalgebra::{Matrix3, Vector3};
use std::path::Path;

const L: f64 = 1.0;
const OMEGA: f64 = 100.0;
const FORCE: f64 = 50.0;
const PULSE: f64 = 0.01;

/// A component of the hub's y axis `(-sin Omega t, cos Omega t)` during `[0, PULSE)`, zero after.
#[derive(Debug, Clone, Copy)]
pub struct HubAxis {
    /// 0: x component, 1: y component.
    pub component: usize,
}

impl UserTimeFunction for HubAxis {
    fn value(&self, t: f64) -> f64 {
        if !(0.0..PULSE).contains(&t) {
            return 0.0;
        }
        match self.component {
            0 => -(OMEGA * t).sin(),
            _ => (OMEGA * t).cos(),
        }
    }
}

/// The rotating tube as a chain of superelements, ready to integrate.
pub struct RotatingChain {
    /// The compiled model.
    pub model: Model,
    /// Initial state: straight, in steady rigid rotation, consistent accelerations.
    pub state: State,
    /// Workspace (sparse backend).
    pub workspace: Workspace,
    /// The generalized-alpha stepper.
    pub stepper: GenAlpha,
    /// The tip node's frame.
    pub tip: flexmbs_core::FrameId,
}

/// Builds the chain of `n` superelements with the floating frames at `frame`, with the linear
/// solver `solver` (generalized-alpha, `rho_inf = 0.9` as the FFR model of the case).
pub fn rotating_chain(
    n: usize,
    frame: FrameLocation,
    solver: LinearSolver,
) -> Result<RotatingChain> {
    let mut spec = ModelSpec::new();
    let i3 = Matrix3::identity();
    let nodes: Vec<_> = (0..=n)
        .map(|i| spec.add_node(&format!("n{i}"), NodeKind::Pose))
        .collect();
    let l = L / n as f64;
    let mut bodies = Vec::new();
    for i in 0..n {
        let data = beam_segment(&BeamSegmentSpec {
            length: l,
            material: Material {
                e: 70e9,
                nu: 0.3,
                rho: 2700.0,
            },
            section: BeamSection::tube(0.01, 0.001),
            theory: BeamTheory::EulerBernoulli,
            elements: 2,
            internal_modes: 0,
            frame,
        })?;
        let se = Superelement::new(data)?;
        bodies.push(spec.add_body_on(&format!("b{i}"), se, &nodes[i..i + 2]));
    }
    let hinge_g = spec.add_ground_frame("hinge", Vector3::zeros(), i3);
    let hinge = spec.add_node_owned_frame("hinge node", nodes[0], Vector3::zeros(), i3);
    let tip = spec.add_node_owned_frame("tip", nodes[n], Vector3::zeros(), i3);
    spec.add_joint(Joint::revolute("drive", hinge_g, hinge).with_prescribed(
        PrescribedMotion::RevoluteRate {
            initial_angle: 0.0,
            rate: TimeFunction::Constant(OMEGA),
        },
    ));
    for component in 0..2 {
        let mut vector = Vector3::zeros();
        vector[component] = FORCE;
        spec.add_load(Load::Force {
            frame: tip,
            vector,
            time: TimeFunction::User(UserFunctionRef::new(HubAxis { component })),
            coordinates: LoadCoordinates::Global,
        });
    }
    let model = spec.compile()?;
    let mut state = model.initial_state();
    let w = Vector3::new(0.0, 0.0, OMEGA);
    for (i, b) in bodies.iter().enumerate() {
        let x = match frame {
            FrameLocation::CentreOfMass => (i as f64 + 0.5) * l,
            FrameLocation::FirstInterface => i as f64 * l,
        };
        let origin = Vector3::new(x, 0.0, 0.0);
        model.set_body_pose(&mut state, *b, origin, i3);
        model.set_body_velocity(&mut state, *b, w.cross(&origin), w);
    }
    let mut workspace = Workspace::with_linear_solver(&model, solver);
    let stepper = GenAlpha::new(GenAlphaSettings {
        rho_inf: 0.9,
        ..GenAlphaSettings::default()
    })?;
    stepper.initialize(&model, &mut state, &mut workspace)?;
    Ok(RotatingChain {
        model,
        state,
        workspace,
        stepper,
        tip,
    })
}

/// Tip deflection history `(t, w)` in the rotating frame of the chain of `n` superelements
/// over `[0, t_end]` with step `h`.
pub fn simulate(
    n: usize,
    frame: FrameLocation,
    h: f64,
    t_end: f64,
) -> Result<(Vec<f64>, Vec<f64>)> {
    let mut c = rotating_chain(n, frame, LinearSolver::Sparse)?;
    let (mut t, mut w) = (vec![0.0], vec![0.0]);
    let mut failed = false;
    let model = &c.model;
    let tip = c.tip;
    c.stepper
        .integrate(
            model,
            &mut c.state,
            &mut c.workspace,
            h,
            t_end,
            |st, _| match model.frame_kinematics(st, tip) {
                Some(k) => {
                    let (s, co) = ((OMEGA * st.t).sin(), (OMEGA * st.t).cos());
                    t.push(st.t);
                    w.push(-k.position.x * s + k.position.y * co);
                }
                None => failed = true,
            },
        )
        .with_context(|| format!("rotating beam, {n} superelements ({frame:?})"))?;
    anyhow::ensure!(!failed, "tip frame kinematics failed");
    Ok((t, w))
}

/// Chains of 1, 2, 3 and 10 superelements, floating frames at the centres of mass and at the first
/// interface points, step `h`: records `tip_w_peak` and `omega_after_pulse` (suffixes `_n1`,
/// `_n2`, `_n3`, `_frame_at_interface`), checks the 10-body chain with frames at the centres of
/// mass against the reference `(ref_peak, ref_omega)` within 3 % and 1 %, and plots both frame
/// locations with the reference `(ref_t, ref_w)` like seed 001 Figs. 5.10-5.14.
pub fn run_chains(
    res: &mut ValidationResult,
    reference: (&[f64], &[f64], f64, f64),
    h: f64,
    t_end: f64,
    out: &Path,
    quiet: bool,
) -> Result<()> {
    let (ref_t, ref_w, ref_peak, ref_omega) = reference;
    let pts = |t: &[f64], w: &[f64]| -> Vec<(f64, f64)> {
        let every = ((5e-4 / (t[1] - t[0]).max(1e-12)).round() as usize).max(1);
        t.iter()
            .zip(w)
            .step_by(every)
            .map(|(a, b)| (*a, b * 1e3))
            .collect()
    };
    for (frame, file, label) in [
        (
            FrameLocation::CentreOfMass,
            "w_tip_superelements_com",
            "at the centres of mass",
        ),
        (
            FrameLocation::FirstInterface,
            "w_tip_superelements_interface",
            "at the first interface points",
        ),
    ] {
        let mut series = Vec::new();
        for n in [1usize, 2, 3, 10] {
            let checked =
                (n == 10 && frame == FrameLocation::CentreOfMass).then_some((ref_peak, ref_omega));
            if let Some((t, w)) = one_chain(res, n, frame, (h, t_end), checked, quiet)? {
                series.push(Series {
                    name: format!("{n} superelements"),
                    points: pts(&t, &w),
                    style: Style::Line,
                });
            }
        }
        series.push(Series {
            name: "reference: nonlinear finite-segment chain".into(),
            points: pts(ref_t, ref_w),
            style: Style::Line,
        });
        let plot = LinePlot {
            title: format!(
                "Rotating tube: tip deflection, superelement chains, floating frames {label}"
            ),
            x_label: "t [s]".into(),
            y_label: "w_tip [mm]".into(),
            series,
            log_x: false,
            log_y: false,
        };
        plot.write(&out.join(format!("{file}.png")))?;
        plot.write(&out.join(format!("{file}.svg")))?;
    }
    Ok(())
}

/// One chain of [`run_chains`]: simulates `n` bodies with frames at `frame` over `(h, t_end)` and
/// records (or, with `checked = Some((peak, omega))`, checks) its first peak and frequency; a
/// failed unchecked run is recorded in the details and gives `None`.
fn one_chain(
    res: &mut ValidationResult,
    n: usize,
    frame: FrameLocation,
    (h, t_end): (f64, f64),
    checked: Option<(f64, f64)>,
    quiet: bool,
) -> Result<Option<(Vec<f64>, Vec<f64>)>> {
    let suffix = format!(
        "{}{}",
        if n == 10 {
            String::new()
        } else {
            format!("_n{n}")
        },
        match frame {
            FrameLocation::CentreOfMass => "",
            FrameLocation::FirstInterface => "_frame_at_interface",
        }
    );
    let (t, w) = match simulate(n, frame, h, t_end) {
        Ok(r) => r,
        Err(e) if checked.is_none() => {
            res.details.insert(
                format!("failed{suffix}"),
                serde_json::Value::String(format!("{e:#}")),
            );
            return Ok(None);
        }
        Err(e) => return Err(e),
    };
    let peak = first_peak(&w);
    let omega = omega_after_pulse(&t, &w).unwrap_or(f64::NAN);
    if !quiet {
        eprintln!(
            "  {n:2} superelements, frame {frame:?}: peak {peak:.6} m, omega {omega:.3} rad/s"
        );
    }
    match checked {
        Some((ref_peak, ref_omega)) => {
            res.check("tip_w_peak", peak, ref_peak, 0.03);
            res.check("omega_after_pulse", omega, ref_omega, 0.01);
        }
        None => {
            res.record(&format!("tip_w_peak{suffix}"), peak);
            res.record(&format!("omega_after_pulse{suffix}"), omega);
        }
    }
    Ok(Some((t, w)))
}

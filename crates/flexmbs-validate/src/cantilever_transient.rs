//! `cantilever_transient` (seed 001 §5.2; `benchmarks.md`): the tube clamped at x = 0, a vertical
//! tip force ramped from 0 to 2500 N in 0.05 s, then constant, 0.2 s; chains of 1, 3 and 10
//! superelements with the floating frame at the centre of mass or at the first interface point.
//! Qualitative (no reference outside the superelement): the quantities and their convergence in
//! the number of bodies and the step are recorded, not checked (README).

use crate::ValidationResult;
use anyhow::Result;
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings, NewtonSettings};
use flexmbs_core::superelement::{beam_segment, BeamSegmentSpec, FrameLocation, Superelement};
use flexmbs_core::{Joint, Load, LoadCoordinates, ModelSpec, NodeKind, TimeFunction, Workspace};
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::Material;
use flexmbs_io::plot::{LinePlot, Series, Style};
use nalgebra::{Matrix3, Vector3};
use std::path::Path;

const L: f64 = 1.0;
const FORCE: f64 = 2500.0;
const T_END: f64 = 0.2;

/// A tip history `(t, y)` and the error that ended the run early, if any.
type Run = (Vec<(f64, f64)>, Option<String>);

/// Tip vertical position `(t, y)` of a clamped chain of `n` superelements, or the error that
/// ended the run with the part computed so far.
fn simulate(n: usize, frame: FrameLocation, h: f64) -> Result<Run> {
    let mut spec = ModelSpec::new();
    let nodes: Vec<_> = (0..=n)
        .map(|i| spec.add_node(&format!("n{i}"), NodeKind::Pose))
        .collect();
    let mut bodies = vec![];
    for i in 0..n {
        let data = beam_segment(&BeamSegmentSpec {
            length: L / n as f64,
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
    let ground = spec.add_ground_frame("clamp", Vector3::zeros(), Matrix3::identity());
    let root = spec.add_node_owned_frame("root", nodes[0], Vector3::zeros(), Matrix3::identity());
    let tip = spec.add_node_owned_frame("tip", nodes[n], Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::fixed("clamp", ground, root));
    spec.add_load(Load::Force {
        frame: tip,
        vector: Vector3::new(0.0, -FORCE, 0.0),
        time: TimeFunction::Ramp {
            t0: 0.0,
            t1: 0.05,
            v0: 0.0,
            v1: 1.0,
        },
        coordinates: LoadCoordinates::Global,
    });
    let model = spec.compile()?;
    let mut s = model.initial_state();
    let l = L / n as f64;
    for (i, b) in bodies.iter().enumerate() {
        let x = match frame {
            FrameLocation::CentreOfMass => (i as f64 + 0.5) * l,
            FrameLocation::FirstInterface => i as f64 * l,
        };
        model.set_body_pose(&mut s, *b, Vector3::new(x, 0.0, 0.0), Matrix3::identity());
    }
    let mut ws = Workspace::new(&model);
    // rtol 1e-7 as when this case was first run: the elastic forces of absolute coordinates carry
    // a round-off ~K eps |x|, which Newton's floor now includes (Element::force_scale), so the
    // default rtol converges as well (core test superelement_newton)
    let ga = GenAlpha::new(GenAlphaSettings {
        rho_inf: 0.9,
        newton: NewtonSettings {
            rtol: 1e-7,
            ..Default::default()
        },
    })?;
    ga.initialize(&model, &mut s, &mut ws)?;
    let mut path = vec![(0.0, 0.0)];
    let status = ga.integrate(&model, &mut s, &mut ws, h, T_END, |st, _| {
        if let Some(k) = model.frame_kinematics(st, tip) {
            path.push((st.t, k.position.y));
        }
    });
    Ok((path, status.err().map(|e| e.to_string())))
}

/// Runs the case.
pub fn run(out: &Path, quiet: bool) -> Result<ValidationResult> {
    let mut res = ValidationResult::new("cantilever_transient");
    let mut series = Vec::new();
    for (n, frame, h) in [
        (10, FrameLocation::CentreOfMass, 1e-4),
        (10, FrameLocation::CentreOfMass, 5e-5),
        (10, FrameLocation::FirstInterface, 1e-4),
        (3, FrameLocation::CentreOfMass, 1e-4),
        (3, FrameLocation::FirstInterface, 1e-4),
        (1, FrameLocation::CentreOfMass, 1e-4),
        (1, FrameLocation::FirstInterface, 1e-4),
    ] {
        let (path, error) = simulate(n, frame, h)?;
        let suffix = format!(
            "{}{}{}",
            if n == 10 {
                String::new()
            } else {
                format!("_n{n}")
            },
            match frame {
                FrameLocation::CentreOfMass => "",
                FrameLocation::FirstInterface => "_frame_at_interface",
            },
            if h < 1e-4 { "_h5e-5" } else { "" }
        );
        let v_min = path.iter().fold(0.0_f64, |a, p| a.min(p.1));
        match &error {
            None => {
                res.record(&format!("tip_v_min{suffix}"), v_min);
                res.record(
                    &format!("tip_v_at_0.2{suffix}"),
                    path.last().map_or(f64::NAN, |p| p.1),
                );
            }
            Some(e) => {
                res.details.insert(
                    format!("failed{suffix}"),
                    serde_json::Value::String(e.clone()),
                );
            }
        }
        if !quiet {
            println!(
                "  {n} bodies {frame:?} h {h:e}: v_min {v_min:.5} m{}",
                error.map(|e| format!(", ended: {e}")).unwrap_or_default()
            );
        }
        if h >= 1e-4 {
            series.push(Series {
                name: format!(
                    "{n} bodies, frame {}",
                    match frame {
                        FrameLocation::CentreOfMass => "at centre of mass",
                        FrameLocation::FirstInterface => "at clamped interface",
                    }
                ),
                // a diverging run is plotted up to |y| = 1.5 L
                points: path
                    .iter()
                    .step_by(5)
                    .take_while(|p| p.1.abs() <= 1.5 * L)
                    .copied()
                    .collect(),
                style: Style::Line,
            });
        }
    }
    let plot = LinePlot {
        title: "Cantilever tube, tip force ramped to 2500 N in 0.05 s: vertical tip position"
            .into(),
        x_label: "t [s]".into(),
        y_label: "y_tip [m]".into(),
        series,
        log_x: false,
        log_y: false,
    };
    plot.write(&out.join("tip_y.png"))?;
    plot.write(&out.join("tip_y.svg"))?;
    Ok(res)
}

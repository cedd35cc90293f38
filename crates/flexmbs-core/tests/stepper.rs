//! The one stepper contract: generalized-alpha (fixed and adaptive), DOPRI5 and statics run
//! through `drive` as trait objects, with consistent statistics and a callback that stops.
use crate::common;

use common::Pendulum;
use flexmbs_core::integrator::{
    drive, AdaptiveSettings, Dopri5, Dopri5Stepper, GenAlpha, GenAlphaSettings, GenAlphaStepper,
    Statics, StaticsStepper, StepControl, Stepper,
};
use flexmbs_core::{RotationParam, Workspace};
use std::f64::consts::PI;
use std::ops::ControlFlow;

/// Every stepper through `drive` as `dyn Stepper`: the callback sees every accepted step, the
/// statistics count them (and the rejections the driver reports), and a `Break` stops the run
/// right there. Statics of the pendulum hangs it straight down (angle 0 to 1e-9 rad).
#[test]
fn every_stepper_runs_through_the_one_driver() {
    let p = Pendulum::new(RotationParam::Cardan);
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    let adaptive = AdaptiveSettings {
        h_init: 1e-3,
        ..Default::default()
    };
    let cases: Vec<(&str, Box<dyn Stepper>, StepControl, f64)> = vec![
        (
            "generalized-alpha fixed",
            Box::new(GenAlphaStepper::new(ga, None)),
            StepControl::Fixed { h: 1e-3 },
            0.5,
        ),
        (
            "generalized-alpha adaptive",
            Box::new(GenAlphaStepper::new(ga, Some(adaptive))),
            GenAlphaStepper::new(ga, Some(adaptive)).control(0.0),
            0.5,
        ),
        (
            "statics",
            Box::new(StaticsStepper::new(Statics::default())),
            Statics::default().control(),
            1.0,
        ),
    ];
    for (name, mut stepper, control, end) in cases {
        let mut s = p.state(PI / 3.0);
        let mut ws = Workspace::new(&p.model);
        stepper.initialize(&p.model, &mut s, &mut ws).unwrap();
        let mut calls = 0;
        let run = drive(
            stepper.as_mut(),
            &p.model,
            &mut s,
            &mut ws,
            control,
            end,
            |_, _| {
                calls += 1;
                ControlFlow::Continue(())
            },
        )
        .unwrap();
        let st = stepper.statistics();
        println!("{name}: {st:?}, {run:?}");
        assert!(!run.stopped && calls > 0, "{name}");
        assert_eq!(st.accepted, calls, "{name}");
        assert_eq!(st.rejected, run.rejected, "{name}");
        assert!(st.iterations >= st.accepted, "{name}");
        if name == "statics" {
            assert!(p.angle(&s).abs() < 1e-9, "statics angle {}", p.angle(&s));
        } else {
            assert!((s.t - end).abs() < 1e-12, "{name}: t = {}", s.t);
        }
        // a Break after the third step stops the run there
        let mut s = p.state(PI / 3.0);
        stepper.initialize(&p.model, &mut s, &mut ws).unwrap();
        let mut calls = 0;
        let run = drive(
            stepper.as_mut(),
            &p.model,
            &mut s,
            &mut ws,
            control,
            end,
            |_, _| {
                calls += 1;
                if calls == 3 {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            },
        )
        .unwrap();
        assert!(run.stopped || name == "statics", "{name}");
        assert!(calls <= 3, "{name}");
    }
    // DOPRI5 refuses the constrained pendulum at initialization
    let mut s = p.state(PI / 3.0);
    let mut ws = Workspace::new(&p.model);
    let mut d = Dopri5Stepper::new(Dopri5::default());
    assert!(d.initialize(&p.model, &mut s, &mut ws).is_err());
}

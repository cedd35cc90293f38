//! Moreau time-stepping with step-size control (seed 000 ch. 4, MBSim's AutoTimeSteppingSSC):
//! every step is taken once with `H` and twice with `H/2`; the difference estimates the local
//! error of the (first-order) scheme, `err = max_i |y2_i - y1_i| / (atol + rtol |y2_i|)` over `q`
//! and `u`, and the two half steps are kept. Steps in which a contact closes or opens are
//! non-smooth: there the error estimate is not used, but the step is refined until contacts that
//! close penetrate by at most `max_penetration` (gap-based refinement), so impacts are resolved
//! close to their time. In smooth steps without active contacts and joints the result is
//! extrapolated, `y = 2 y2 - y1` (Richardson, second order).

use super::{MoreauSettings, MoreauStepper};
use crate::contact::NormalLaw;
use crate::error::SolverError;
use crate::integrator::{StepAttempt, StepControl, Stepper, StepperStatistics};
use crate::model::Model;
use crate::state::{State, Workspace};
use crate::system;

/// Settings of [`MoreauSscStepper`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoreauSscSettings {
    /// Settings of each Moreau step.
    pub moreau: MoreauSettings,
    /// Relative tolerance of the error estimate. Default 1e-6.
    pub rtol: f64,
    /// Absolute tolerance of the error estimate. Default 1e-6.
    pub atol: f64,
    /// Largest penetration of a closing unilateral contact in an accepted step (length unit;
    /// steps at `h_min` are accepted anyway). Default 1e-6.
    pub max_penetration: f64,
    /// First step. Default 1e-4.
    pub h_init: f64,
    /// Smallest step. Default 1e-9.
    pub h_min: f64,
    /// Largest step. Default 1e-2.
    pub h_max: f64,
    /// Richardson extrapolation of smooth steps without contacts or joints. Default true.
    pub extrapolate: bool,
}

impl Default for MoreauSscSettings {
    fn default() -> Self {
        Self {
            moreau: MoreauSettings::default(),
            rtol: 1e-6,
            atol: 1e-6,
            max_penetration: 1e-6,
            h_init: 1e-4,
            h_min: 1e-9,
            h_max: 1e-2,
            extrapolate: true,
        }
    }
}

/// The Moreau stepper with step-size control by step halving (module documentation).
#[derive(Debug)]
pub struct MoreauSscStepper {
    /// Settings.
    pub settings: MoreauSscSettings,
    inner: MoreauStepper,
    /// The accepted steps' end monitor ([`MoreauStepper::set_end_monitor`]).
    end_monitor: bool,
    start: State,
    full: State,
    stats: StepperStatistics,
}

/// `dst = src` without allocating (same sizes).
fn copy_state(dst: &mut State, src: &State) {
    dst.t = src.t;
    dst.q.copy_from_slice(&src.q);
    dst.u.copy_from_slice(&src.u);
    dst.u_dot.copy_from_slice(&src.u_dot);
    dst.a.copy_from_slice(&src.a);
    dst.lambda.copy_from_slice(&src.lambda);
    dst.contacts.copy_from_slice(&src.contacts);
}

impl MoreauSscStepper {
    /// A stepper with `settings`.
    pub fn new(settings: MoreauSscSettings) -> Self {
        Self {
            settings,
            inner: MoreauStepper::new(settings.moreau),
            end_monitor: true,
            start: State::zeros(0, 0, 0),
            full: State::zeros(0, 0, 0),
            stats: StepperStatistics::default(),
        }
    }

    /// Whether accepted steps evaluate the end state's energy and constraint drift
    /// ([`MoreauStepper::set_end_monitor`]; default: yes).
    pub fn set_end_monitor(&mut self, on: bool) {
        self.end_monitor = on;
        self.inner.set_end_monitor(on);
    }

    /// The driver's control from the settings.
    pub fn control(&self) -> StepControl {
        let c = &self.settings;
        StepControl::Adaptive {
            h_init: c.h_init,
            h_min: c.h_min,
            h_max: c.h_max,
        }
    }

    fn check(&self) -> Result<(), SolverError> {
        let c = &self.settings;
        for (name, v) in [
            ("rtol", c.rtol),
            ("atol", c.atol),
            ("max_penetration", c.max_penetration),
            ("h_init", c.h_init),
            ("h_min", c.h_min),
            ("h_max", c.h_max),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(SolverError::InvalidSetting {
                    name,
                    value: v,
                    reason: "must be finite and > 0",
                });
            }
        }
        if c.h_min > c.h_max {
            return Err(SolverError::InvalidSetting {
                name: "h_min",
                value: c.h_min,
                reason: "must not exceed h_max",
            });
        }
        Ok(())
    }

    /// Scaled difference of the one-step and two-half-step results.
    fn error(&self, half: &State) -> f64 {
        let (rtol, atol) = (self.settings.rtol, self.settings.atol);
        let pairs = half.q.iter().zip(&self.full.q);
        let pairs = pairs.chain(half.u.iter().zip(&self.full.u));
        pairs.fold(0.0_f64, |e, (y2, y1)| {
            e.max((y2 - y1).abs() / (atol + rtol * y2.abs()))
        })
    }
}

impl Stepper for MoreauSscStepper {
    /// Checks the settings, sizes the inner stepper and the saved states.
    fn initialize(
        &mut self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
    ) -> Result<(), SolverError> {
        self.check()?;
        self.inner = MoreauStepper::new(self.settings.moreau);
        self.inner.set_end_monitor(self.end_monitor);
        self.inner.initialize(model, s, ws)?;
        self.start = s.clone();
        self.full = s.clone();
        Ok(())
    }

    fn step(
        &mut self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        h: f64,
    ) -> Result<StepAttempt, SolverError> {
        copy_state(&mut self.start, s);
        copy_state(&mut self.full, s);
        // the full step's and the first half step's energy and drift are not used
        self.inner.set_end_monitor(false);
        self.inner.advance(model, &mut self.full, ws, h)?;
        self.inner.advance(model, s, ws, 0.5 * h)?;
        self.inner.set_end_monitor(self.end_monitor);
        let mut changed = self.contacts_changed(s);
        let first_gaps_penetration = self.penetration_now(model, s, 0.5 * h);
        let mut stats = self.inner.advance(model, s, ws, 0.5 * h)?;
        changed |= self.contacts_changed(s);
        let penetration = first_gaps_penetration.max(self.penetration_now(model, s, 0.5 * h));
        let at_min = h <= self.settings.h_min * (1.0 + 1e-9);
        let c = &self.settings;
        // a contact that changed its activity in the step can be compared between the full and
        // the two half steps only if both end with the same activity (an impact resolved in
        // both: the difference is the restitution's O(h) error from the velocity at the step
        // start); otherwise the step is accepted without an estimate
        let comparable = !changed || self.same_activity(s);
        let (accept, err) = if penetration > c.max_penetration && !at_min {
            (false, f64::INFINITY)
        } else if !comparable {
            (true, 0.0)
        } else {
            let e = self.error(s);
            (e <= 1.0 || at_min, e)
        };
        // a step whose contacts changed has no error estimate: keep its size (doubling it
        // would let a chattering contact grow the step past the stability limit of the smooth
        // forces, which Moreau's scheme treats explicitly)
        let factor = if !comparable {
            1.0
        } else if err > 0.0 {
            (0.9 / err.sqrt()).clamp(0.2, 2.0)
        } else {
            2.0
        };
        if !accept {
            copy_state(s, &self.start);
            self.stats.rejected += 1;
            let factor = if err.is_finite() {
                factor.min(0.5)
            } else {
                0.25
            };
            return Ok(StepAttempt::rejected(err, h * factor));
        }
        let active = s.contacts.iter().any(|c| c.active) || model.nc > 0;
        if c.extrapolate && !changed && !active {
            for (y2, y1) in s.q.iter_mut().zip(&self.full.q) {
                *y2 = 2.0 * *y2 - y1;
            }
            for (y2, y1) in s.u.iter_mut().zip(&self.full.u) {
                *y2 = 2.0 * *y2 - y1;
            }
            system::normalize(model, &mut s.q);
        }
        stats.h = h;
        stats.error_estimate = err;
        self.stats.accepted += 1;
        self.stats.iterations += stats.iterations;
        Ok(StepAttempt {
            accepted: true,
            stats,
            h_next: h * factor,
        })
    }

    fn statistics(&self) -> StepperStatistics {
        self.stats
    }
}

impl MoreauSscStepper {
    /// Do the full step and the two half steps end with the same activity of every contact?
    fn same_activity(&self, half: &State) -> bool {
        half.contacts
            .iter()
            .zip(&self.full.contacts)
            .all(|(a, b)| a.active == b.active)
    }

    /// Did any contact's activity differ from the start of the step?
    fn contacts_changed(&self, s: &State) -> bool {
        s.contacts
            .iter()
            .zip(&self.start.contacts)
            .any(|(a, b)| a.active != b.active)
    }

    /// Largest penetration in the last half step (of size `h`) of a unilateral contact that was
    /// open at the start of the step: closed in the half step, its midpoint gap (where the impact
    /// was resolved); still open, also its gap at the end `g_M + h/2 g_N_dot` (so that no
    /// accepted step ends inside an open contact).
    fn penetration_now(&self, model: &Model, s: &State, h: f64) -> f64 {
        let mut p: f64 = 0.0;
        for ((c, st), now) in model
            .contacts
            .iter()
            .zip(&self.start.contacts)
            .zip(&s.contacts)
        {
            if matches!(c.law.normal, NormalLaw::Unilateral { .. }) && !st.active {
                p = p.max(-now.gap);
                if !now.active {
                    p = p.max(-(now.gap + 0.5 * h * now.gap_velocity));
                }
            }
        }
        p
    }
}

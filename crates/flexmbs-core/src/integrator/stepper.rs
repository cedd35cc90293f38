//! One stepper contract ([`Stepper`]) and one driver ([`drive`]) for fixed and adaptive
//! stepping with an output callback that may stop the run. Generalized-alpha
//! ([`GenAlphaStepper`]), DOPRI5 ([`Dopri5Stepper`]) and statics ([`StaticsStepper`], stepping the
//! load factor) implement it; the integrators' own `integrate*` / `solve*` entry points are thin
//! wrappers around [`drive`].

use super::{AdaptiveSettings, ControlledRun, Dopri5, GenAlpha, StaticStats, Statics, StepStats};
use crate::error::SolverError;
use crate::model::Model;
use crate::state::{State, Workspace};
use std::ops::ControlFlow;

/// Outcome of one attempted step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepAttempt {
    /// The step was accepted and the state advanced (otherwise the state is unchanged).
    pub accepted: bool,
    /// Statistics of the accepted step (rejected: only `error_estimate`).
    pub stats: StepStats,
    /// Proposed next step (adaptive control; the driver bounds it by `h_max`).
    pub h_next: f64,
}

impl StepAttempt {
    /// A rejected attempt with error estimate `error` (NaN: none) and the next step `h_next`.
    pub fn rejected(error: f64, h_next: f64) -> Self {
        Self {
            accepted: false,
            stats: StepStats {
                error_estimate: error,
                ..Default::default()
            },
            h_next,
        }
    }
}

/// Counters of a stepper over a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StepperStatistics {
    /// Accepted steps.
    pub accepted: usize,
    /// Rejected attempts.
    pub rejected: usize,
    /// Newton iterations (implicit) or function evaluations (explicit) of accepted steps.
    pub iterations: usize,
    /// Iteration matrices factored in accepted steps.
    pub factorizations: usize,
}

impl StepperStatistics {
    fn count(&mut self, a: &StepAttempt) {
        if a.accepted {
            self.accepted += 1;
            self.iterations += a.stats.iterations;
            self.factorizations += a.stats.factorizations;
        } else {
            self.rejected += 1;
        }
    }
}

/// A stepping method: prepares a state, attempts steps, keeps statistics.
pub trait Stepper {
    /// Prepares `s` for the first step (checks, consistent accelerations, ...).
    fn initialize(
        &mut self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
    ) -> Result<(), SolverError>;
    /// Attempts one step of size `h` from `s`: accepted (state advanced) or rejected (state
    /// unchanged, with a proposed smaller step); an error ends the run.
    fn step(
        &mut self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        h: f64,
    ) -> Result<StepAttempt, SolverError>;
    /// Counters so far.
    fn statistics(&self) -> StepperStatistics;
    /// The stepped variable of `s`: time (default), or the load factor of statics.
    fn progress(&self, s: &State) -> f64 {
        s.t
    }
}

/// Step-size control of [`drive`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepControl {
    /// Fixed step `h`; the last step is shortened to end at the end point (a remainder below
    /// `1e-6 h` is absorbed into the step before).
    Fixed {
        /// Step size.
        h: f64,
    },
    /// The stepper's proposals bounded by `h_max`; an error [`SolverError::StepTooSmall`] below
    /// `h_min`.
    Adaptive {
        /// First step.
        h_init: f64,
        /// Smallest step.
        h_min: f64,
        /// Largest step.
        h_max: f64,
    },
}

/// Steps `stepper` from its current progress to `end` and calls `on_step` after every accepted
/// step (its `rejected` field set to the rejections so far); `ControlFlow::Break(())` stops the
/// run. Returns the rejected attempts and whether the run was stopped. Allocation-free.
pub fn drive<S: Stepper + ?Sized>(
    stepper: &mut S,
    model: &Model,
    s: &mut State,
    ws: &mut Workspace,
    control: StepControl,
    end: f64,
    mut on_step: impl FnMut(&State, &StepStats) -> ControlFlow<()>,
) -> Result<ControlledRun, SolverError> {
    let mut run = ControlledRun::default();
    let (mut h, h_min, h_max) = match control {
        StepControl::Fixed { h } => (h, 0.0, h),
        StepControl::Adaptive {
            h_init,
            h_min,
            h_max,
        } => (h_init.min(h_max), h_min, h_max),
    };
    let fixed = matches!(control, StepControl::Fixed { .. });
    loop {
        let x = stepper.progress(s);
        let remaining = end - x;
        let hs = if fixed {
            if remaining <= 1e-6 * h_max {
                break;
            }
            if remaining < h_max * (1.0 + 1e-6) {
                remaining
            } else {
                h_max
            }
        } else {
            if x >= end - 1e-14 * end.abs().max(1.0) {
                break;
            }
            h = h.min(remaining);
            h
        };
        let mut a = stepper.step(model, s, ws, hs)?;
        if a.accepted {
            a.stats.rejected = run.rejected;
            if on_step(s, &a.stats).is_break() {
                run.stopped = true;
                return Ok(run);
            }
        } else {
            run.rejected += 1;
        }
        if !fixed {
            h = a.h_next.min(h_max);
            let done = stepper.progress(s) >= end - 1e-14 * end.abs().max(1.0);
            if h < h_min && !done {
                return Err(SolverError::StepTooSmall {
                    t: stepper.progress(s),
                    h,
                    h_min,
                    error: a.stats.error_estimate,
                });
            }
        } else if !a.accepted {
            return Err(SolverError::StepTooSmall {
                t: stepper.progress(s),
                h: hs,
                h_min: hs,
                error: a.stats.error_estimate,
            });
        }
    }
    Ok(run)
}

/// Generalized-alpha as a [`Stepper`]: fixed steps (`adaptive: None`; a Newton failure is an
/// error) or adaptive steps ([`AdaptiveSettings`]; a Newton failure halves the step).
#[derive(Debug, Clone, Copy)]
pub struct GenAlphaStepper {
    /// The integrator.
    pub integrator: GenAlpha,
    /// Step-size control, `None` for fixed steps.
    pub adaptive: Option<AdaptiveSettings>,
    stats: StepperStatistics,
    scales_filled: bool,
}

impl GenAlphaStepper {
    /// Stepper of `integrator`, adaptive with `adaptive`.
    pub fn new(integrator: GenAlpha, adaptive: Option<AdaptiveSettings>) -> Self {
        Self {
            integrator,
            adaptive,
            stats: StepperStatistics::default(),
            scales_filled: false,
        }
    }

    /// The driver's control: the adaptive settings' bounds, or the fixed step `h`.
    pub fn control(&self, h: f64) -> StepControl {
        match self.adaptive {
            Some(c) => StepControl::Adaptive {
                h_init: c.h_init,
                h_min: c.h_min,
                h_max: c.h_max,
            },
            None => StepControl::Fixed { h },
        }
    }
}

impl Stepper for GenAlphaStepper {
    /// [`GenAlpha::initialize`] (and, adaptive, the `rho_inf < 1` check with joints).
    fn initialize(
        &mut self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
    ) -> Result<(), SolverError> {
        if self.adaptive.is_some() {
            self.integrator.check_adaptive(model)?;
        }
        self.integrator.initialize(model, s, ws)
    }

    fn step(
        &mut self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        h: f64,
    ) -> Result<StepAttempt, SolverError> {
        let a = match &self.adaptive {
            Some(ctl) => {
                if !self.scales_filled {
                    let (scales, local) = (&mut ws.error_scales, &mut ws.sys.local);
                    super::genalpha::fill_error_scales(model, scales, local);
                    self.scales_filled = true;
                }
                self.integrator.attempt_adaptive(model, s, ws, ctl, h)?
            }
            None => StepAttempt {
                accepted: true,
                stats: self.integrator.step(model, s, ws, h)?,
                h_next: h,
            },
        };
        self.stats.count(&a);
        Ok(a)
    }

    fn statistics(&self) -> StepperStatistics {
        self.stats
    }
}

/// DOPRI5 as a [`Stepper`] (always adaptive, [`Dopri5::control`]).
#[derive(Debug, Clone, Copy)]
pub struct Dopri5Stepper {
    /// The integrator.
    pub integrator: Dopri5,
    stats: StepperStatistics,
    evals: usize,
}

impl Dopri5Stepper {
    /// Stepper of `integrator`.
    pub fn new(integrator: Dopri5) -> Self {
        Self {
            integrator,
            stats: StepperStatistics::default(),
            evals: 0,
        }
    }

    /// The driver's control from the settings.
    pub fn control(&self) -> StepControl {
        let c = &self.integrator.settings;
        StepControl::Adaptive {
            h_init: c.h_init,
            h_min: c.h_min,
            h_max: c.h_max,
        }
    }
}

impl Stepper for Dopri5Stepper {
    /// Checks (no constraints, state size) and consistent accelerations.
    fn initialize(
        &mut self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
    ) -> Result<(), SolverError> {
        self.integrator.check(model, s)?;
        super::consistent_accelerations(model, s, ws)
    }

    fn step(
        &mut self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        h: f64,
    ) -> Result<StepAttempt, SolverError> {
        let a = self.integrator.attempt(model, s, ws, h, &mut self.evals)?;
        self.stats.count(&a);
        Ok(a)
    }

    fn statistics(&self) -> StepperStatistics {
        self.stats
    }
}

/// Statics as a [`Stepper`]: the stepped variable is the load factor `mu` from 0 to 1
/// ([`Statics::control`]); an accepted step is a converged load increment (its `StepStats::t`
/// is `mu`), a failed one is halved.
#[derive(Debug, Clone, Copy)]
pub struct StaticsStepper {
    /// The solver.
    pub solver: Statics,
    mu: f64,
    tol: f64,
    stats: StepperStatistics,
}

impl StaticsStepper {
    /// Stepper of `solver` at load factor 0.
    pub fn new(solver: Statics) -> Self {
        Self {
            solver,
            mu: 0.0,
            tol: f64::NAN,
            stats: StepperStatistics::default(),
        }
    }

    /// Summary in the form of [`Statics::solve`] (residual and `g_max` of `last`).
    pub fn summary(&self, last: &StepStats) -> StaticStats {
        StaticStats {
            increments: self.stats.accepted,
            iterations: self.stats.iterations,
            residual: last.residual,
            g_max: last.g_max,
        }
    }
}

impl Stepper for StaticsStepper {
    /// Checks the settings, zero velocities, force tolerance from the full load.
    fn initialize(
        &mut self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
    ) -> Result<(), SolverError> {
        self.tol = self.solver.prepare(model, s, ws)?;
        self.mu = 0.0;
        Ok(())
    }

    fn step(
        &mut self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        h: f64,
    ) -> Result<StepAttempt, SolverError> {
        // the last increment ends exactly at the full load
        let target = if h >= 1.0 - self.mu { 1.0 } else { self.mu + h };
        let a = self
            .solver
            .increment(model, s, ws, (self.mu, target, self.tol))?;
        if a.accepted {
            self.mu = target;
        }
        self.stats.count(&a);
        Ok(a)
    }

    fn statistics(&self) -> StepperStatistics {
        self.stats
    }

    fn progress(&self, _s: &State) -> f64 {
        self.mu
    }
}

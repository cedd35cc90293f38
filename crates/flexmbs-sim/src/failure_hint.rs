//! Failure hints chosen by the cause of a solver failure (`flexmbs run` prints them under the
//! error; [`crate::run::RunError::Solver`] carries the [`FailureCause`]).
//!
//! The cause recognised here: **step-frequency growth** of generalized-alpha with joints. The
//! index-3 method has a spurious mode at the step frequency (the joint reactions alternate sign
//! from one step to the next); `rho_inf = 1` leaves it undamped, so round-off and the constraint
//! nonlinearity feed it until Newton fails. A smaller step does not help (the mode lives at
//! every step size; the double-pendulum example fails at 5.8 s with `h` = 1 ms and at 6.2 s
//! with 0.25 ms), numerical damping (`rho_inf < 1`) removes it. It is recognised from the
//! accepted steps: the alternating part of the multipliers,
//! `a_k = max_i |lambda_k,i - 2 lambda_k-1,i + lambda_k-2,i| / 4` (the amplitude of a pure
//! `+-A` alternation), has grown by [`GROWTH`] over its smallest value and makes up at least
//! [`DOMINANCE`] of the multipliers' size when the run fails. Every other failure gets the
//! general hint (smaller or adaptive steps).

use crate::config::SolverConfig;

/// Growth of the alternating multiplier amplitude over its smallest value that marks a
/// step-frequency instability.
pub const GROWTH: f64 = 100.0;

/// Share of the multipliers' size (`max_i |lambda_i|`) the alternating part must reach.
pub const DOMINANCE: f64 = 0.1;

/// The general hint for a failed time integration.
const GENERAL: &str = "a smaller step `h` in [solver], or step size control with `adaptive = {}` (generalized-alpha); check the model at the failure time in the results file";

/// The hint for a failed statics solution.
const STATICS: &str = "more `load_steps` in [solver]; check that every body is held (a free body has no static equilibrium)";

/// The cause of a solver failure, as far as the run could tell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FailureCause {
    /// Nothing specific recognised (time integration).
    Unknown,
    /// The statics solution failed.
    Statics,
    /// Generalized-alpha with joints: the joint reactions ended in a grown step-frequency
    /// oscillation (see the module documentation).
    StepFrequencyGrowth {
        /// First time the alternating part made up [`DOMINANCE`] of the multipliers (s).
        onset: f64,
    },
}

impl FailureCause {
    /// What to try, in words for the user, for a run with `solver`.
    pub fn hint(&self, solver: &SolverConfig) -> String {
        match (self, solver) {
            (Self::Statics, _) => STATICS.to_string(),
            (Self::StepFrequencyGrowth { onset }, SolverConfig::GenAlpha { settings, .. }) => {
                let rho = settings.rho_inf;
                let damps = if rho >= 1.0 {
                    "does not damp"
                } else {
                    "does not damp enough"
                };
                let lower = if rho >= 0.95 {
                    "`rho_inf = 0.9` in [solver]".to_string()
                } else {
                    format!("a smaller `rho_inf` than {rho} in [solver], e.g. 0.7")
                };
                format!("the joint reactions had been oscillating at the step frequency (their sign alternating from one step to the next) with a growing amplitude, dominating them from t = {onset:.4e} s on: high-frequency energy growth that generalized-alpha with rho_inf = {rho} {damps}; a smaller step `h` does not remove it (the oscillation exists at every step size), numerical damping does: use {lower}")
            }
            _ => GENERAL.to_string(),
        }
    }
}

/// Watches the step-frequency (every-other-step) part of the joint multipliers over the accepted
/// steps of a run. Buffers are sized once; observing allocates nothing.
#[derive(Debug)]
pub(crate) struct StepOscillation {
    /// Multipliers of the previous two accepted steps.
    prev: Vec<f64>,
    prev2: Vec<f64>,
    /// Accepted steps seen.
    seen: usize,
    /// Smallest alternating amplitude seen (from the third step on).
    min_amplitude: f64,
    /// Alternating amplitude and multiplier size of the last accepted step.
    amplitude: f64,
    scale: f64,
    /// First time the alternating part made up [`DOMINANCE`] of the multipliers (NaN: never).
    onset: f64,
}

impl StepOscillation {
    /// A monitor for `nc` multipliers.
    pub(crate) fn new(nc: usize) -> Self {
        Self {
            prev: vec![0.0; nc],
            prev2: vec![0.0; nc],
            seen: 0,
            min_amplitude: f64::INFINITY,
            amplitude: 0.0,
            scale: 0.0,
            onset: f64::NAN,
        }
    }

    /// The multipliers `lambda` of an accepted step ending at `t`.
    pub(crate) fn observe(&mut self, t: f64, lambda: &[f64]) {
        if lambda.len() != self.prev.len() || lambda.is_empty() {
            return;
        }
        if self.seen >= 2 {
            let (mut a, mut s) = (0.0f64, 0.0f64);
            for ((l, p), p2) in lambda.iter().zip(&self.prev).zip(&self.prev2) {
                a = a.max((l - 2.0 * p + p2).abs() / 4.0);
                s = s.max(l.abs());
            }
            if a.is_finite() && s.is_finite() {
                self.min_amplitude = self.min_amplitude.min(a);
                self.amplitude = a;
                self.scale = s;
                if self.onset.is_nan() && s > 0.0 && a >= DOMINANCE * s {
                    self.onset = t;
                }
            }
        }
        self.prev2.copy_from_slice(&self.prev);
        self.prev.copy_from_slice(lambda);
        self.seen += 1;
    }

    /// The cause of a failure of a run with `solver` after the steps observed.
    pub(crate) fn cause(&self, solver: &SolverConfig) -> FailureCause {
        match solver {
            SolverConfig::Statics { .. } => FailureCause::Statics,
            SolverConfig::GenAlpha { .. } if self.grown() => {
                FailureCause::StepFrequencyGrowth { onset: self.onset }
            }
            _ => FailureCause::Unknown,
        }
    }

    /// Whether the multipliers end in a grown step-frequency oscillation.
    fn grown(&self) -> bool {
        self.seen > 2
            && self.scale > 0.0
            && self.amplitude >= DOMINANCE * self.scale
            && self.amplitude >= GROWTH * self.min_amplitude
    }
}

//! Time integrators and the static solver, with per-step monitoring ([`StepStats`]).
//!
//! - [`GenAlpha`]: implicit generalized-alpha for index-3 constrained equations (Arnold &
//!   Bruls 2007), fixed or adaptive step.
//! - [`Dopri5`]: explicit adaptive Dormand-Prince 5(4) for unconstrained systems.
//! - [`Statics`]: static equilibrium by Newton with load stepping.
//! - [`MoreauStepper`] / [`MoreauSscStepper`]: Moreau midpoint time-stepping for set-valued
//!   contact ([`crate::contact`]) and joints on velocity level, fixed step or with step-size
//!   control.
//!
//! All are [`Stepper`]s, run by one driver [`drive`] (fixed or adaptive steps, output
//! callback with `ControlFlow`).

mod dopri5;
mod genalpha;
mod genalpha_contact;
mod moreau;
mod statics;
mod stepper;

pub use dopri5::{Dopri5, Dopri5Settings};
pub use genalpha::{AdaptiveSettings, GenAlpha, GenAlphaParams, GenAlphaSettings};
pub use moreau::{MoreauSettings, MoreauSscSettings, MoreauSscStepper, MoreauStepper};
pub use statics::{StaticStats, Statics, StaticsSettings};
pub use stepper::{
    drive, Dopri5Stepper, GenAlphaStepper, StaticsStepper, StepAttempt, StepControl, Stepper,
    StepperStatistics,
};

use crate::algebra::SaddleKind;
use crate::error::SolverError;
use crate::model::Model;
use crate::state::{State, Workspace};
use crate::system::{self, Energy};

/// Monitor output of one accepted step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepStats {
    /// Time at the end of the step.
    pub t: f64,
    /// Step size used.
    pub h: f64,
    /// Newton iterations (implicit) or function evaluations (explicit).
    pub iterations: usize,
    /// Final residual norm (max norm of the force residual; 0 for explicit).
    pub residual: f64,
    /// Energies at the end of the step.
    pub energy: Energy,
    /// Position constraint drift `max |g|`.
    pub g_max: f64,
    /// Velocity constraint drift `max |G u + g_t|`.
    pub g_dot_max: f64,
    /// Scaled local error estimate (1 = tolerance; 0 when not estimated).
    pub error_estimate: f64,
    /// Steps rejected so far in this run (adaptive integrators; 0 for fixed steps).
    pub rejected: usize,
    /// Iteration matrices built and factored in this step (implicit; full Newton: one per
    /// iteration, modified Newton: see [`NewtonSettings::modified`]).
    pub factorizations: usize,
}

/// Outcome of an integration whose step callback can stop it
/// ([`GenAlpha::integrate_adaptive_controlled`], [`Dopri5::integrate_controlled`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ControlledRun {
    /// Rejected steps (error estimate too large or Newton failure).
    pub rejected: usize,
    /// True if the callback stopped the run before `t_end`.
    pub stopped: bool,
}

/// Newton settings of the implicit solvers.
///
/// Generalized-alpha accepts an iterate (after at least one solve) when all of these hold:
/// - constraints: `max |g| <= constraint_tol max(1, |q|_inf)`;
/// - force residual `r = M u_dot - h + G^T lambda`: `max |r| <= rtol F`, with the force scale
///   `F = max(|h|_inf, |M u_dot|_inf)` of the iterate (not `G^T lambda`, so diverging multipliers
///   cannot inflate it);
/// - increments of the last solve: `max |du_dot| <= atol + rtol max |u_dot|` (or at the
///   positions' round-off floor `beta' max |du_dot| <= 16 eps max(1, |q|_inf)`) and
///   `max |d lambda| <= atol + rtol max(|lambda|_inf, F)`; after two solves each increment may be
///   replaced by the error it leaves, `theta / (1 - theta) |d|` with the contraction rate
///   `theta = |d_k| / |d_(k-1)| < 0.5` (Hairer & Wanner, Solving ODEs II, IV.8);
///   or instead of the increment tests: the residual is at round-off, `max |r| <= 1e3 eps F`
///   (an ill-conditioned direction may then amplify rounding noise into increments above the
///   tolerance, which no further iteration reduces).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonSettings {
    /// Maximum iterations per step. Default 25.
    pub max_iterations: usize,
    /// Relative tolerance on the increments and the force residual. Default 1e-10.
    pub rtol: f64,
    /// Absolute tolerance on the increments. Default 1e-10.
    pub atol: f64,
    /// Tolerance on `max |g|` (position constraints), relative to `max(1, |q|_inf)`. Default 1e-12.
    pub constraint_tol: f64,
    /// Modified Newton (generalized-alpha only): keep the factorized iteration matrix across
    /// iterations and steps, and rebuild it (tangent + LU) only when the step size changed, the
    /// scaled increments (of `u_dot` and `lambda`) contract by less than
    /// [`MODIFIED_NEWTON_CONTRACTION`] per iteration, the force residual grows (above its
    /// round-off floor), or after [`MODIFIED_NEWTON_MAX_REUSE`] solves with one matrix (counted
    /// across steps, [`crate::Workspace::newton_matrix_solves`]). A step is accepted only by the
    /// full test above, so never with diverging multipliers; converged steps agree with full
    /// Newton to the Newton tolerances. Default `false` (full Newton: a fresh matrix every
    /// iteration).
    pub modified: bool,
    /// Test only, not a setting: `true` restores the acceptance rule before issue 8, so that a
    /// test can show it fails (`flexmbs-sim/tests/newton.rs`). That rule accepted an iterate on
    /// the acceleration increment (`max |du_dot| <= atol + rtol max |u_dot|`, or at the
    /// positions' round-off floor) and the constraint error alone, never looking at the
    /// multiplier increment or the force residual; modified Newton judged contraction on the
    /// acceleration increment only, and the reuse counter was reset every step. Default `false`.
    #[doc(hidden)]
    pub legacy_acceptance: bool,
}

/// A stale iteration matrix is rebuilt when `|increment_k| > this * |increment_(k-1)|`.
pub const MODIFIED_NEWTON_CONTRACTION: f64 = 0.5;
/// Most solves with one iteration matrix in modified Newton before it is rebuilt.
pub const MODIFIED_NEWTON_MAX_REUSE: usize = 8;

impl Default for NewtonSettings {
    fn default() -> Self {
        Self {
            max_iterations: 25,
            rtol: 1e-10,
            atol: 1e-10,
            constraint_tol: 1e-12,
            modified: false,
            legacy_acceptance: false,
        }
    }
}

/// Consistent accelerations and multipliers at the current state: solves
/// `[M G^T; G 0] [u_dot; lambda] = [h; -g_bias]` (the index-1 form `g_ddot = 0`) and sets
/// `state.u_dot`, `state.a = u_dot`, `state.lambda`.
pub fn consistent_accelerations(
    model: &Model,
    s: &mut State,
    ws: &mut Workspace,
) -> Result<(), SolverError> {
    let (nu, nc) = (model.nu, model.nc);
    let sys = &mut ws.sys;
    system::evaluate(model, &s.q, &s.u, sys).map_err(|e| e.at(s.t, 0.0))?;
    system::assemble_forces(model, s.t, &s.q, &s.u, 1.0, sys);
    let (frames, eval) = (&sys.frames, &sys.eval);
    let h = &mut sys.h;
    crate::contact::regularized::add_regularized_forces(model, frames, eval, &mut ws.contact, h);
    system::update_constraints(model, s.t, sys);
    let rhs = &mut ws.step.rhs;
    rhs[..nu].copy_from_slice(&sys.h);
    for r in 0..nc {
        rhs[nu + r] = -sys.g_bias[r];
    }
    let singular = SolverError::Singular {
        what: "augmented mass",
        t: s.t,
        h: 0.0,
    };
    if nc == 0 && ws.saddle.is_sparse() {
        // M u_dot = h by the block Cholesky of the mass matrix alone
        ws.mass_blocks
            .update(model, &s.q, &mut sys.eval)
            .map_err(|_| singular)?;
        ws.mass_blocks.solve_in_place(rhs, 1);
    } else {
        let saddle = &mut ws.saddle;
        saddle.build(SaddleKind::AugmentedMass, model, &s.q, &s.u, &s.lambda, sys);
        if !saddle.factor() {
            return Err(singular);
        }
        saddle.solve_in_place(rhs);
    }
    if rhs.iter().any(|x| !x.is_finite()) {
        return Err(SolverError::NonFinite {
            what: "initial accelerations",
            t: s.t,
            h: 0.0,
            residual: f64::NAN,
        });
    }
    s.u_dot.copy_from_slice(&rhs[..nu]);
    s.a.copy_from_slice(&rhs[..nu]);
    s.lambda.copy_from_slice(&rhs[nu..]);
    Ok(())
}

/// Energy and constraint drift of a state (evaluates `ws.sys` there: elements, frames and
/// constraints). A state the elements cannot evaluate gives NaN.
pub fn monitor(model: &Model, s: &State, ws: &mut Workspace) -> (Energy, f64, f64) {
    let sys = &mut ws.sys;
    if system::evaluate(model, &s.q, &s.u, sys).is_err() {
        let nan = Energy {
            kinetic: f64::NAN,
            gravity: f64::NAN,
            elastic: f64::NAN,
            springs: f64::NAN,
        };
        return (nan, f64::NAN, f64::NAN);
    }
    system::update_constraints(model, s.t, sys);
    let (g, gd) = ws.saddle.constraint_drift(sys, &s.u);
    (
        system::energy(model, &s.q, &s.u, &mut sys.eval, &sys.frames),
        g,
        gd,
    )
}

/// Max norm.
pub(crate) fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

//! Explicit adaptive Dormand-Prince 5(4) for unconstrained systems.
//!
//! First-order form `y = (q, u)`, `y_dot = (T(q) u, M(q)^-1 h(t, q, u))`, with `M^-1` from the
//! per-element Cholesky factors of [`crate::algebra::BlockMass`] (refactored only where an
//! element's mass changed). Stages combine `q`
//! additively; after each accepted step the coordinates are normalized (unit quaternions).
//! Error norm: RMS of `err_i / (atol + rtol max(|y_i|, |y_new_i|))`; step factor
//! `clamp(0.9 err^(-1/5), 0.2, 5)` (Hairer, Nørsett & Wanner, Solving ODEs I, II.4).
//! FFR bodies with node-load stiffening get `−K_load(c) q_f` with `c` from the loads at each
//! stage ([`crate::system::add_load_stiffening_forces`]; a supported body's acceleration
//! coefficients from the stage's accelerations without that force).

use super::stepper::{drive, Dopri5Stepper, StepAttempt};
use super::{monitor, ControlledRun, StepStats};
use crate::algebra::BlockMass;
use crate::error::SolverError;
use crate::model::Model;
use crate::state::{State, SystemBuffers, Workspace};
use crate::system;
use std::ops::ControlFlow;

/// Settings of [`Dopri5`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dopri5Settings {
    /// Relative tolerance. Default 1e-8.
    pub rtol: f64,
    /// Absolute tolerance. Default 1e-10.
    pub atol: f64,
    /// First step. Default 1e-3.
    pub h_init: f64,
    /// Minimum step. Default 1e-14.
    pub h_min: f64,
    /// Maximum step. Default infinity.
    pub h_max: f64,
}

impl Default for Dopri5Settings {
    fn default() -> Self {
        Self {
            rtol: 1e-8,
            atol: 1e-10,
            h_init: 1e-3,
            h_min: 1e-14,
            h_max: f64::INFINITY,
        }
    }
}

/// The DOPRI5 integrator.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Dopri5 {
    /// Settings.
    pub settings: Dopri5Settings,
}

const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// `dy = (T(q) u, M^-1 h)` at `(t, y)`.
fn derivative(
    model: &Model,
    t: f64,
    y: &[f64],
    dy: &mut [f64],
    sys: &mut SystemBuffers,
    mass: &mut BlockMass,
) -> Result<(), SolverError> {
    let nq = model.nq;
    let (q, u) = y.split_at(nq);
    let (dq, du) = dy.split_at_mut(nq);
    system::q_dot(model, q, u, dq);
    system::evaluate(model, q, u, sys).map_err(|e| e.at(t, 0.0))?;
    system::assemble_forces(model, t, q, u, 1.0, sys);
    if mass.update(model, q, &mut sys.eval).is_err() {
        return Err(SolverError::Singular {
            what: "mass",
            t,
            h: 0.0,
        });
    }
    du.copy_from_slice(&sys.h);
    mass.solve_in_place(du, 1);
    if has_load_stiffening(model) {
        // node-load stiffening: coefficients from the loads at this stage (no multipliers: no
        // constraints) and, for a supported body, from the accelerations `du` without the
        // stiffening force (one fixed-point pass); then `M^-1 (h - K_load(c) q_f)`
        system::add_load_stiffening_forces(model, t, 1.0, du, &[], true, sys);
        du.copy_from_slice(&sys.h);
        mass.solve_in_place(du, 1);
    }
    Ok(())
}

/// Whether a body of `model` carries node-load stiffening ([`crate::ffr::LoadStiffening`]).
fn has_load_stiffening(model: &Model) -> bool {
    model
        .bodies
        .iter()
        .any(|b| b.element.load_stiffened_ffr().is_some())
}

impl Dopri5 {
    /// Integrator with the given settings.
    pub fn new(settings: Dopri5Settings) -> Self {
        Self { settings }
    }

    /// Adaptive integration to `t_end`, calling `on_step` after each accepted step.
    pub fn integrate(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        t_end: f64,
        mut on_step: impl FnMut(&State, &StepStats),
    ) -> Result<(), SolverError> {
        self.integrate_controlled(model, s, ws, t_end, |s, st| {
            on_step(s, st);
            ControlFlow::Continue(())
        })
        .map(|_| ())
    }

    /// As [`Self::integrate`], but `on_step` may stop the run by returning
    /// `ControlFlow::Break(())`. Returns the number of rejected steps and whether it was stopped
    /// ([`super::drive`] with [`Dopri5Stepper`]).
    pub fn integrate_controlled(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        t_end: f64,
        on_step: impl FnMut(&State, &StepStats) -> ControlFlow<()>,
    ) -> Result<ControlledRun, SolverError> {
        self.check(model, s)?;
        let mut stepper = Dopri5Stepper::new(*self);
        let control = stepper.control();
        drive(&mut stepper, model, s, ws, control, t_end, on_step)
    }

    /// The state fits the model and the model has no constraints and no contacts (DOPRI5
    /// would integrate through them as if they were absent).
    pub(super) fn check(&self, model: &Model, s: &State) -> Result<(), SolverError> {
        crate::system::check_state_size(model, s)?;
        if model.nc > 0 {
            return Err(SolverError::ConstraintsUnsupported {
                integrator: "DOPRI5",
                nc: model.nc,
            });
        }
        if !model.contacts.is_empty() {
            return Err(SolverError::InvalidSetting {
                name: "contact",
                value: model.contacts.len() as f64,
                reason: "DOPRI5 does not handle contacts: use generalized-alpha (regularized \
                         laws) or the Moreau stepper",
            });
        }
        Ok(())
    }

    /// One step attempt of size `h`: accepted (state advanced, normalized) if the error norm is
    /// <= 1. `evals` counts the function evaluations since the last accepted step (reported as
    /// its iterations, then reset).
    pub(super) fn attempt(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        h: f64,
        evals: &mut usize,
    ) -> Result<StepAttempt, SolverError> {
        let cfg = &self.settings;
        let (nq, n) = (model.nq, model.nq + model.nu);
        let b = &mut ws.step;
        let [y_stage, y_new] = &mut b.y;
        y_stage[..nq].copy_from_slice(&s.q);
        y_stage[nq..].copy_from_slice(&s.u);
        derivative(
            model,
            s.t,
            y_stage,
            &mut b.stages[0],
            &mut ws.sys,
            &mut ws.mass_blocks,
        )?;
        for i in 1..7 {
            for (k, yk) in y_stage.iter_mut().enumerate() {
                let y0 = if k < nq { s.q[k] } else { s.u[k - nq] };
                *yk = y0 + h * (0..i).map(|j| A[i][j] * b.stages[j][k]).sum::<f64>();
            }
            let (_, rest) = b.stages.split_at_mut(i);
            derivative(
                model,
                s.t + C[i] * h,
                y_stage,
                &mut rest[0],
                &mut ws.sys,
                &mut ws.mass_blocks,
            )?;
        }
        *evals += 7;
        y_new.copy_from_slice(y_stage); // stage 7 state = 5th-order solution (FSAL)
        let mut sum = 0.0;
        for (k, yk) in y_new.iter().enumerate() {
            let e = h * (0..7).map(|j| E[j] * b.stages[j][k]).sum::<f64>();
            let y0 = if k < nq { s.q[k] } else { s.u[k - nq] };
            let sc = cfg.atol + cfg.rtol * y0.abs().max(yk.abs());
            sum += (e / sc).powi(2);
        }
        let err = (sum / n as f64).sqrt();
        if !err.is_finite() {
            return Err(SolverError::NonFinite {
                what: "DOPRI5 error estimate",
                t: s.t,
                h,
                residual: f64::NAN,
            });
        }
        let fac = if err > 0.0 { 0.9 * err.powf(-0.2) } else { 5.0 };
        let h_next = h * fac.clamp(0.2, 5.0);
        if err > 1.0 {
            return Ok(StepAttempt::rejected(err, h_next));
        }
        s.t += h;
        s.q.copy_from_slice(&y_new[..nq]);
        s.u.copy_from_slice(&y_new[nq..]);
        s.u_dot.copy_from_slice(&b.stages[6][nq..]);
        system::normalize(model, &mut s.q);
        let (energy, g_max, g_dot_max) = monitor(model, s, ws);
        let stats = StepStats {
            t: s.t,
            h,
            iterations: *evals,
            residual: 0.0,
            energy,
            g_max,
            g_dot_max,
            error_estimate: err,
            rejected: 0,
            factorizations: 0,
        };
        *evals = 0;
        Ok(StepAttempt {
            accepted: true,
            stats,
            h_next,
        })
    }
}

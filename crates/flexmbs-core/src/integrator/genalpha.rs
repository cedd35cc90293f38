//! Generalized-alpha for index-3 constrained mechanical systems (Arnold & Bruls 2007,
//! "Convergence of the generalized-alpha scheme for constrained mechanical systems").
//!
//! Equations: `M(q) u_dot = h(t, q, u) - G(q)^T lambda`, `g(q, t) = 0`, `q_dot = T(q) u`.
//! One step `n -> n+1` with step `h`:
//!
//! ```text
//! q_{n+1} = q_n ⊕ h (u_n + h (1/2 - beta) a_n + h beta a_{n+1})
//! u_{n+1} = u_n + h (1 - gamma) a_n + h gamma a_{n+1}
//! (1 - alpha_m) a_{n+1} + alpha_m a_n = (1 - alpha_f) u_dot_{n+1} + alpha_f u_dot_n
//! M(q_{n+1}) u_dot_{n+1} = h(t_{n+1}, q_{n+1}, u_{n+1}) - G^T lambda_{n+1},  g(q_{n+1}, t_{n+1}) = 0
//! ```
//!
//! `⊕` is [`crate::Element::integrate_position`]: plain addition for Cardan angles and modal
//! coordinates, the exponential map for quaternions (the Lie-group variant of Brüls, Cardona
//! & Arnold 2012). Newton iterates on `(u_dot_{n+1}, lambda_{n+1})` with the iteration matrix
//!
//! ```text
//! S = [ M - gamma' dh/du - beta' dh/dq   G^T ]    beta'  = h^2 beta (1 - alpha_f) / (1 - alpha_m)
//!     [ G                                0   ]    gamma' = h gamma (1 - alpha_f) / (1 - alpha_m)
//! ```
//!
//! (constraint rows scaled by `1 / beta'`; the derivatives of `M u_dot` and `G^T lambda` with
//! respect to `q` are neglected, which only affects the convergence rate). With
//! [`NewtonSettings::modified`](super::NewtonSettings::modified) the factorized matrix is kept
//! across iterations and steps (modified Newton, as Exudyn does by default) and rebuilt only on a
//! step-size change, slow contraction or after a fixed number of reuses.
//! Parameters from the spectral radius at infinity `rho_inf` in `[0, 1]`:
//! `alpha_m = (2 rho - 1) / (rho + 1)`, `alpha_f = rho / (rho + 1)`,
//! `gamma = 1/2 + alpha_f - alpha_m`, `beta = 1/4 (gamma + 1/2)^2`.

use super::{consistent_accelerations, ControlledRun, NewtonSettings, StepStats};
use crate::algebra::{SaddleKind, SystemMatrix};
use crate::error::SolverError;
use crate::model::Model;
use crate::state::{State, StepBuffers, Workspace};
use crate::system;
use std::ops::ControlFlow;

/// Settings of the generalized-alpha integrator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GenAlphaSettings {
    /// Spectral radius at infinity, in `[0, 1]` (1: no numerical damping). Default 0.9.
    pub rho_inf: f64,
    /// Newton settings.
    pub newton: NewtonSettings,
}

impl Default for GenAlphaSettings {
    fn default() -> Self {
        Self {
            rho_inf: 0.9,
            newton: NewtonSettings::default(),
        }
    }
}

/// The four scheme parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GenAlphaParams {
    /// `alpha_m`.
    pub alpha_m: f64,
    /// `alpha_f`.
    pub alpha_f: f64,
    /// `beta`.
    pub beta: f64,
    /// `gamma`.
    pub gamma: f64,
}

impl GenAlphaParams {
    /// Second-order accurate parameters with spectral radius `rho_inf` at infinity
    /// (Chung & Hulbert 1993 in the Arnold-Bruls form).
    pub fn from_rho_inf(rho: f64) -> Self {
        let alpha_m = (2.0 * rho - 1.0) / (rho + 1.0);
        let alpha_f = rho / (rho + 1.0);
        let gamma = 0.5 + alpha_f - alpha_m;
        Self {
            alpha_m,
            alpha_f,
            beta: 0.25 * (gamma + 0.5).powi(2),
            gamma,
        }
    }
}

/// Step-size control of [`GenAlpha::integrate_adaptive`].
///
/// Local error estimate (Géradin & Cardona 2001): the position error of the scheme is
/// `e = h^2 |beta - 1/6| |u_dot_{n+1} - u_dot_n|` per velocity coordinate; the scaled norm is
/// `max_i e_i / (atol + rtol max(1, |q|_inf))`. A step is accepted if it is <= 1; the next step is
/// `h * clamp(0.9 err^(-1/3), 0.2, 2)`. Newton failures halve the step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdaptiveSettings {
    /// First step. Default 1e-3.
    pub h_init: f64,
    /// Minimum step (error below). Default 1e-12.
    pub h_min: f64,
    /// Maximum step. Default 0.1.
    pub h_max: f64,
    /// Absolute position tolerance. Default 1e-6.
    pub atol: f64,
    /// Relative position tolerance. Default 1e-6.
    pub rtol: f64,
}

impl Default for AdaptiveSettings {
    fn default() -> Self {
        Self {
            h_init: 1e-3,
            h_min: 1e-12,
            h_max: 0.1,
            atol: 1e-6,
            rtol: 1e-6,
        }
    }
}

/// The generalized-alpha integrator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GenAlpha {
    /// Settings.
    pub settings: GenAlphaSettings,
    /// Scheme parameters derived from `rho_inf`.
    pub params: GenAlphaParams,
    /// Evaluate the energies ([`StepStats::energy`](super::StepStats::energy)) after every
    /// accepted step. Default `true`; with `false` the field is left at zero, which saves a
    /// kinetic-energy (mass matrix) evaluation per step; callers that need energies only at
    /// output steps compute them there with [`crate::system::energy`]. The constraint drift
    /// (`g_max`, `g_dot_max`) is always reported.
    pub step_energy: bool,
}

impl GenAlpha {
    /// Integrator with validated settings.
    pub fn new(settings: GenAlphaSettings) -> Result<Self, SolverError> {
        let rho = settings.rho_inf;
        if !(0.0..=1.0).contains(&rho) {
            return Err(SolverError::InvalidSetting {
                name: "rho_inf",
                value: rho,
                reason: "must be in [0, 1]",
            });
        }
        Ok(Self {
            settings,
            params: GenAlphaParams::from_rho_inf(rho),
            step_energy: true,
        })
    }

    /// Sets [`Self::step_energy`] (energies after every step on or off).
    pub fn with_step_energy(mut self, on: bool) -> Self {
        self.step_energy = on;
        self
    }

    /// Prepares a state for the first step: checks that it fits the model and satisfies the
    /// joints ([`system::check_assembly`], tolerance [`system::ASSEMBLY_TOL`]), then sets
    /// consistent `u_dot`, `a` and `lambda`.
    pub fn initialize(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
    ) -> Result<(), SolverError> {
        system::check_assembly(model, s, ws, system::ASSEMBLY_TOL)?;
        consistent_accelerations(model, s, ws)
    }

    /// One step of size `h`; on success the state is advanced, on error it is unchanged.
    pub fn step(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        h: f64,
    ) -> Result<StepStats, SolverError> {
        system::check_state_size(model, s)?;
        let mut stats = self.solve_step(model, s, ws, h)?;
        commit(s, &ws.step, h);
        let (energy, g, gd) = monitor_converged(model, s, ws, self.step_energy);
        (stats.energy, stats.g_max, stats.g_dot_max) = (energy, g, gd);
        Ok(stats)
    }

    /// Newton iterations of one step; the result is left in `ws.step` (`q_new`, `u_new`,
    /// `u_dot_new`, `a_new`, `lambda_new`); `s` is not touched.
    fn solve_step(
        &self,
        model: &Model,
        s: &State,
        ws: &mut Workspace,
        h: f64,
    ) -> Result<StepStats, SolverError> {
        let (p, nt) = (&self.params, &self.settings.newton);
        let (nu, t1) = (model.nu, s.t + h);
        let c = (1.0 - p.alpha_f) / (1.0 - p.alpha_m);
        let (beta_p, gamma_p) = (h * h * p.beta * c, h * p.gamma * c);
        let fail = |what, residual| SolverError::NonFinite {
            what,
            t: s.t,
            h,
            residual,
        };
        if !(h > 0.0 && h.is_finite()) {
            return Err(SolverError::InvalidSetting {
                name: "h",
                value: h,
                reason: "step must be positive",
            });
        }
        let b = &mut ws.step;
        b.u_dot_new.copy_from_slice(&s.u_dot); // predictor: constant acceleration
        b.lambda_new.copy_from_slice(&s.lambda);
        let mut increment = f64::INFINITY;
        // modified Newton: previous increment and solves with the current iteration matrix
        let mut last_increment = f64::INFINITY;
        let mut reuse = 0usize;
        let mut residual = f64::NAN;
        for iter in 1..=nt.max_iterations + 1 {
            kinematic_update(model, p, h, s, b);
            let sys = &mut ws.sys;
            system::update_frames(model, &b.q_new, &b.u_new, &mut sys.frames);
            system::assemble_forces(model, t1, &b.q_new, &b.u_new, 1.0, &sys.frames, &mut sys.h);
            system::assemble_constraints(
                model,
                t1,
                &sys.frames,
                &mut sys.g,
                sys.g_jac.as_mut(),
                &mut sys.g_t,
                &mut sys.g_bias,
            );
            // residual r = M u_dot - h + G^T lambda,  g / beta': the product M u_dot from the
            // elements (no assembled M; that is built only with a new iteration matrix), then
            // -h_i, G_0i lambda_0, G_1i lambda_1, ... (contiguous columns of G)
            let (mut r_max, mut g_max) = (0.0_f64, 0.0_f64);
            let r_acc = &mut b.rhs[..nu];
            let saddle = if nt.modified {
                &mut ws.newton_matrix
            } else {
                &mut ws.saddle
            };
            saddle.mass_times_vector(model, &b.q_new, &b.u_dot_new, sys, r_acc);
            for (r, h) in r_acc.iter_mut().zip(&sys.h) {
                *r -= h;
            }
            saddle.add_g_transpose_times(sys, &b.lambda_new, r_acc);
            for i in 0..nu {
                let r = b.rhs[i];
                if !r.is_finite() {
                    return Err(fail("force residual", residual));
                }
                r_max = r_max.max(r.abs());
                b.rhs[i] = -r;
            }
            for gk in &sys.g {
                if !gk.is_finite() {
                    return Err(fail("constraint", residual));
                }
                g_max = g_max.max(gk.abs());
            }
            residual = r_max;
            // Increment small, or at the round-off floor of the positions (beta' du_dot ~ eps |q|).
            let q_scale = super::max_abs(&b.q_new).max(1.0);
            let small = increment <= nt.atol + nt.rtol * super::max_abs(&b.u_dot_new)
                || beta_p * increment <= 16.0 * f64::EPSILON * q_scale;
            if small && g_max <= nt.constraint_tol * q_scale {
                return Ok(StepStats {
                    t: t1,
                    h,
                    iterations: iter - 1,
                    residual,
                    ..Default::default()
                });
            }
            if iter > nt.max_iterations {
                break;
            }
            let rate = increment / last_increment;
            let refresh = !nt.modified
                || ws.newton_matrix_h.to_bits() != h.to_bits()
                || rate > super::MODIFIED_NEWTON_CONTRACTION
                || reuse >= super::MODIFIED_NEWTON_MAX_REUSE;
            let saddle = if nt.modified {
                &mut ws.newton_matrix
            } else {
                &mut ws.saddle
            };
            if refresh {
                ws.newton_matrix_h = f64::NAN;
                let kind = SaddleKind::Iteration {
                    t: t1,
                    c_u: gamma_p,
                    c_q: beta_p,
                };
                if !build_and_factor(saddle, kind, model, &b.q_new, &b.u_new, sys) {
                    return Err(SolverError::Singular {
                        what: "iteration",
                        t: s.t,
                        h,
                    });
                }
                if nt.modified {
                    ws.newton_matrix_h = h;
                }
                reuse = 0;
            }
            reuse += 1;
            let sol = &mut b.rhs;
            for (k, gk) in sys.g.iter().enumerate() {
                sol[nu + k] = -gk / beta_p;
            }
            saddle.solve_in_place(sol);
            last_increment = increment;
            increment = super::max_abs(&sol[..nu]);
            if sol.iter().any(|x| !x.is_finite()) {
                return Err(fail("Newton increment", residual));
            }
            for (x, d) in b.u_dot_new.iter_mut().zip(&sol[..nu]) {
                *x += d;
            }
            for (l, d) in b.lambda_new.iter_mut().zip(&sol[nu..]) {
                *l += d;
            }
        }
        ws.newton_matrix_h = f64::NAN;
        Err(SolverError::NewtonFailed {
            t: s.t,
            h,
            residual,
            iterations: nt.max_iterations,
        })
    }

    /// Fixed-step integration to `t_end` (last step shortened), calling `on_step` after every step.
    pub fn integrate(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        h: f64,
        t_end: f64,
        mut on_step: impl FnMut(&State, &StepStats),
    ) -> Result<(), SolverError> {
        // A remainder below 1e-6 h is absorbed into the last step (no micro steps).
        while t_end - s.t > 1e-6 * h {
            let remaining = t_end - s.t;
            let hs = if remaining < h * (1.0 + 1e-6) {
                remaining
            } else {
                h
            };
            let stats = self.step(model, s, ws, hs)?;
            on_step(s, &stats);
        }
        Ok(())
    }

    /// Adaptive-step integration to `t_end` (see [`AdaptiveSettings`] for the error estimate).
    pub fn integrate_adaptive(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        ctl: &AdaptiveSettings,
        t_end: f64,
        mut on_step: impl FnMut(&State, &StepStats),
    ) -> Result<(), SolverError> {
        self.integrate_adaptive_controlled(model, s, ws, ctl, t_end, |s, st| {
            on_step(s, st);
            ControlFlow::Continue(())
        })
        .map(|_| ())
    }

    /// As [`Self::integrate_adaptive`], but `on_step` may stop the run by returning
    /// `ControlFlow::Break(())`. Returns the number of rejected steps (error estimate or Newton
    /// failure) and whether it was stopped.
    pub fn integrate_adaptive_controlled(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        ctl: &AdaptiveSettings,
        t_end: f64,
        mut on_step: impl FnMut(&State, &StepStats) -> ControlFlow<()>,
    ) -> Result<ControlledRun, SolverError> {
        let mut run = ControlledRun::default();
        if self.settings.rho_inf >= 1.0 && model.nc > 0 {
            // the undamped spurious oscillation of the constraint forces enters the error
            // estimate and collapses the step (double pendulum: 3e-9 s after 0.27 s)
            return Err(SolverError::InvalidSetting {
                name: "rho_inf",
                value: self.settings.rho_inf,
                reason: "adaptive steps of a constrained model need rho_inf < 1",
            });
        }
        let mut h = ctl.h_init.min(ctl.h_max);
        let err_coeff = (self.params.beta - 1.0 / 6.0).abs();
        while s.t < t_end - 1e-14 * t_end.abs().max(1.0) {
            h = h.min(t_end - s.t);
            let mut err = f64::NAN;
            match self.solve_step(model, s, ws, h) {
                Ok(mut stats) => {
                    let b = &ws.step;
                    let w = ctl.atol + ctl.rtol * super::max_abs(&s.q).max(1.0);
                    err = (0..model.nu)
                        .map(|i| h * h * err_coeff * (b.u_dot_new[i] - s.u_dot[i]).abs() / w)
                        .fold(0.0, f64::max);
                    if err <= 1.0 {
                        commit(s, &ws.step, h);
                        let (energy, g, gd) = monitor_converged(model, s, ws, self.step_energy);
                        (
                            stats.energy,
                            stats.g_max,
                            stats.g_dot_max,
                            stats.error_estimate,
                        ) = (energy, g, gd, err);
                        stats.rejected = run.rejected;
                        if on_step(s, &stats).is_break() {
                            run.stopped = true;
                            return Ok(run);
                        }
                    } else {
                        run.rejected += 1;
                    }
                    let fac = if err > 0.0 {
                        0.9 * err.powf(-1.0 / 3.0)
                    } else {
                        2.0
                    };
                    h = (h * fac.clamp(0.2, 2.0)).min(ctl.h_max);
                }
                Err(SolverError::NewtonFailed { .. }) | Err(SolverError::Singular { .. }) => {
                    run.rejected += 1;
                    h *= 0.5
                }
                Err(e) => return Err(e),
            }
            if h < ctl.h_min {
                return Err(SolverError::StepTooSmall {
                    t: s.t,
                    h,
                    h_min: ctl.h_min,
                    error: err,
                });
            }
        }
        Ok(run)
    }
}

/// Builds the iteration matrix `kind` at `(q, u)` into `saddle` and factors it; `false` if it
/// is singular. The one place where generalized-alpha builds and factors.
fn build_and_factor(
    saddle: &mut SystemMatrix,
    kind: SaddleKind,
    model: &Model,
    q: &[f64],
    u: &[f64],
    sys: &mut crate::state::SystemBuffers,
) -> bool {
    saddle.build(kind, model, q, u, &[], sys);
    saddle.factor()
}

/// `a_{n+1}`, `u_{n+1}` and `q_{n+1} = q_n ⊕ dv` from the current `u_dot_{n+1}` iterate.
fn kinematic_update(model: &Model, p: &GenAlphaParams, h: f64, s: &State, b: &mut StepBuffers) {
    for i in 0..model.nu {
        let a_new = ((1.0 - p.alpha_f) * b.u_dot_new[i] + p.alpha_f * s.u_dot[i]
            - p.alpha_m * s.a[i])
            / (1.0 - p.alpha_m);
        b.a_new[i] = a_new;
        b.u_new[i] = s.u[i] + h * ((1.0 - p.gamma) * s.a[i] + p.gamma * a_new);
        b.dv[i] = h * (s.u[i] + h * ((0.5 - p.beta) * s.a[i] + p.beta * a_new));
    }
    system::integrate_positions(model, &s.q, &b.dv, &mut b.q_new);
}

/// [`super::monitor`] right after a converged [`GenAlpha::solve_step`] and [`commit`]: the last
/// Newton evaluation was at the committed `(t, q, u)`, so the frames and constraint buffers in
/// `ws.sys` are current and are reused (bitwise the same values as a fresh evaluation). Energies
/// only if `with_energy`, else zero.
fn monitor_converged(
    model: &Model,
    s: &State,
    ws: &Workspace,
    with_energy: bool,
) -> (system::Energy, f64, f64) {
    let sys = &ws.sys;
    let (g, gd) = ws.saddle.constraint_drift(sys, &s.u);
    let energy = if with_energy {
        system::energy(model, &s.q, &s.u, &sys.frames)
    } else {
        system::Energy::default()
    };
    (energy, g, gd)
}

/// Copies the converged step into the state.
fn commit(s: &mut State, b: &StepBuffers, h: f64) {
    s.t += h;
    s.q.copy_from_slice(&b.q_new);
    s.u.copy_from_slice(&b.u_new);
    s.u_dot.copy_from_slice(&b.u_dot_new);
    s.a.copy_from_slice(&b.a_new);
    s.lambda.copy_from_slice(&b.lambda_new);
}

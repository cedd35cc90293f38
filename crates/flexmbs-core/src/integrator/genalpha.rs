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

use super::stepper::{drive, GenAlphaStepper, StepAttempt, StepControl};
use super::{consistent_accelerations, ControlledRun, NewtonSettings, StepStats};
use crate::algebra::{SaddleKind, SystemMatrix};
use crate::error::SolverError;
use crate::model::Model;
use crate::state::{State, StepBuffers, SystemBuffers, Workspace};
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
/// `e_i = h^2 |beta - 1/6| |u_dot_{n+1} - u_dot_n|` per velocity coordinate `i`, a displacement
/// for translations, a rotation increment (rad) for angular velocities, a modal amplitude for
/// modal coordinates. Each is turned into a displacement in metres with the length
/// `L_i` of [`crate::Element::velocity_scales`] (1 for translations, the body's radius of
/// gyration or extent for rotations, the mode's largest nodal displacement for a modal
/// coordinate), so the scaled norm is `max_i L_i e_i / (atol + rtol max(1, R))` with `R` the
/// largest distance of a frame from the origin (m) at the new state: the tolerance neither
/// loosens as rotation angles accumulate (it never looks at `q`) nor judges modal coordinates on
/// the scale of positions. A step is accepted if the norm is <= 1; the next step is
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
    /// Largest penetration (length unit) of a regularized contact that was open at the start
    /// of a step, at the step's end: steps are limited from the gap and its rate before a
    /// contact closes and rejected if they end deeper (steps at `h_min` are accepted anyway;
    /// [`super::genalpha_contact`]). Default 1e-6; `f64::INFINITY` switches the restriction off.
    pub max_penetration: f64,
}

impl Default for AdaptiveSettings {
    fn default() -> Self {
        Self {
            h_init: 1e-3,
            h_min: 1e-12,
            h_max: 0.1,
            atol: 1e-6,
            rtol: 1e-6,
            max_penetration: 1e-6,
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
        if let Some((i, _)) = crate::contact::regularized::first_set_valued(model) {
            return Err(SolverError::InvalidSetting {
                name: "contact",
                value: i as f64,
                reason: "a set-valued contact law (unilateral, bilateral, Coulomb friction) \
                         needs the Moreau stepper; generalized-alpha takes regularized laws",
            });
        }
        s.contacts.resize(model.contacts.len(), Default::default());
        ws.contact.start_gap.fill(f64::NEG_INFINITY);
        consistent_accelerations(model, s, ws)?;
        // the contact states of the initial state (the damping of the first step)
        regularized_contacts_converged(model, s, ws, 0.0, false);
        Ok(())
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
        let (mut energy, g, gd) = monitor_converged(model, s, ws, self.step_energy);
        energy.springs += regularized_contacts_converged(model, s, ws, h, self.step_energy);
        (stats.energy, stats.g_max, stats.g_dot_max) = (energy, g, gd);
        Ok(stats)
    }

    /// Newton iterations of one step; the result is left in `ws.step` (`q_new`, `u_new`,
    /// `u_dot_new`, `a_new`, `lambda_new`); `s` is not touched. Convergence:
    /// [`NewtonSettings`](super::NewtonSettings) (increments of `u_dot` and `lambda`, force
    /// residual, constraint error, round-off floor).
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
        if !(h > 0.0 && h.is_finite()) {
            return Err(SolverError::InvalidSetting {
                name: "h",
                value: h,
                reason: "step must be positive",
            });
        }
        crate::contact::regularized::gaps_at_start(&s.contacts, &mut ws.contact);
        if nt.legacy_acceptance {
            // test only: the counter before issue 8 was reset every step
            ws.newton_matrix_solves = 0;
        }
        ws.step.u_dot_new.copy_from_slice(&s.u_dot); // predictor: constant acceleration
        ws.step.lambda_new.copy_from_slice(&s.lambda);
        // max |du_dot|, max |d lambda| of the last solve (none yet)
        let (mut du, mut dl) = (f64::INFINITY, f64::INFINITY);
        // the same of the solve before (contraction estimate)
        let mut prev = (f64::INFINITY, f64::INFINITY);
        // scaled increment and residual of the previous iterate (modified Newton's refresh test)
        let (mut last_e, mut last_r) = (f64::INFINITY, f64::INFINITY);
        let mut factorizations = 0;
        let mut residual = f64::NAN;
        for iter in 1..=nt.max_iterations + 1 {
            kinematic_update(model, p, h, s, &mut ws.step);
            let saddle = if nt.modified {
                &mut ws.newton_matrix
            } else {
                &mut ws.saddle
            };
            // node-load stiffening: coefficients from this iterate's multipliers until the
            // increments are small, then frozen (their multiplier dependence is not in the matrix)
            let update_c = last_e > LOAD_COEFFICIENT_FREEZE;
            let contact = &mut ws.contact;
            let it = newton_residual(
                model,
                t1,
                &mut ws.step,
                &mut ws.sys,
                contact,
                saddle,
                update_c,
            )
            .map_err(|e| e.at(s.t, h, residual))?;
            residual = it.r_max;
            let b = &ws.step;
            let conv = judge_convergence(nt, &it, b, (du, dl), prev, beta_p);
            if iter > 1 && conv.converged {
                return Ok(StepStats {
                    t: t1,
                    h,
                    iterations: iter - 1,
                    residual,
                    factorizations,
                    ..Default::default()
                });
            }
            if iter > nt.max_iterations {
                break;
            }
            // modified Newton: a fresh matrix if the scaled increments contract too slowly or
            // the residual grows (a stale matrix lets the multipliers diverge), after
            // MODIFIED_NEWTON_MAX_REUSE solves (counted across steps), or on a new step size
            let diverging = conv.e > super::MODIFIED_NEWTON_CONTRACTION * last_e
                || (it.r_max > last_r && !conv.at_roundoff);
            let refresh = !nt.modified
                || ws.newton_matrix_h.to_bits() != h.to_bits()
                || diverging
                || ws.newton_matrix_solves >= super::MODIFIED_NEWTON_MAX_REUSE;
            (last_e, last_r) = (conv.e, it.r_max);
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
                let b = &ws.step;
                let (sys, contact) = (&mut ws.sys, &mut ws.contact);
                if !build_and_factor(saddle, kind, model, &b.q_new, &b.u_new, sys, contact) {
                    return Err(SolverError::Singular {
                        what: "iteration",
                        t: s.t,
                        h,
                    });
                }
                factorizations += 1;
                ws.newton_matrix_solves = 0;
                if nt.modified {
                    ws.newton_matrix_h = h;
                }
            }
            ws.newton_matrix_solves += 1;
            prev = (du, dl);
            (du, dl) = apply_newton_increment(nu, beta_p, &ws.sys.g, saddle, &mut ws.step)
                .ok_or_else(|| nonfinite("Newton increment", s.t, h, residual))?;
            if !model.contacts.is_empty() {
                let f = super::genalpha_contact::shorten_increment(model, ws, gamma_p);
                (du, dl) = (f * du, f * dl);
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

    /// Fixed-step integration to `t_end` (last step shortened), calling `on_step` after every step
    /// ([`super::drive`] with [`super::StepControl::Fixed`]).
    pub fn integrate(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        h: f64,
        t_end: f64,
        mut on_step: impl FnMut(&State, &StepStats),
    ) -> Result<(), SolverError> {
        let mut stepper = GenAlphaStepper::new(*self, None);
        let control = StepControl::Fixed { h };
        drive(&mut stepper, model, s, ws, control, t_end, |s, st| {
            on_step(s, st);
            ControlFlow::Continue(())
        })
        .map(|_| ())
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
    /// failure) and whether it was stopped ([`super::drive`] with [`GenAlphaStepper`]).
    pub fn integrate_adaptive_controlled(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        ctl: &AdaptiveSettings,
        t_end: f64,
        on_step: impl FnMut(&State, &StepStats) -> ControlFlow<()>,
    ) -> Result<ControlledRun, SolverError> {
        self.check_adaptive(model)?;
        let mut stepper = GenAlphaStepper::new(*self, Some(*ctl));
        let control = stepper.control(0.0);
        drive(&mut stepper, model, s, ws, control, t_end, on_step)
    }

    /// Adaptive steps of a constrained model need numerical damping: the undamped spurious
    /// oscillation of the constraint forces enters the error estimate and collapses the step
    /// (double pendulum: 3e-9 s after 0.27 s).
    pub(super) fn check_adaptive(&self, model: &Model) -> Result<(), SolverError> {
        if self.settings.rho_inf >= 1.0 && model.nc > 0 {
            return Err(SolverError::InvalidSetting {
                name: "rho_inf",
                value: self.settings.rho_inf,
                reason: "adaptive steps of a constrained model need rho_inf < 1",
            });
        }
        Ok(())
    }

    /// One adaptive step attempt of size `h` (see [`AdaptiveSettings`]): accepted (state
    /// advanced) if the error estimate is <= 1; a Newton failure, a singular iteration matrix or
    /// an iterate an element cannot evaluate is a rejection with half the step (that error is
    /// returned once half the step would fall below `h_min`). `ws.error_scales` must hold the velocity scales.
    pub(super) fn attempt_adaptive(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        ctl: &AdaptiveSettings,
        h: f64,
    ) -> Result<StepAttempt, SolverError> {
        let err_coeff = (self.params.beta - 1.0 / 6.0).abs();
        let h_gap = super::genalpha_contact::closing_step_limit(model, &s.contacts, ctl);
        if h > h_gap {
            return Ok(StepAttempt::rejected(f64::NAN, h_gap));
        }
        let mut stats = match self.solve_step(model, s, ws, h) {
            Ok(stats) => stats,
            // Newton failure, singular matrix, or an iterate outside an element's valid region
            // (overshoot): a smaller step, unless that falls below h_min; then this cause, not a
            // bare "step too small"
            Err(
                e @ (SolverError::NewtonFailed { .. }
                | SolverError::Singular { .. }
                | SolverError::Element { .. }),
            ) => {
                if 0.5 * h < ctl.h_min {
                    return Err(e);
                }
                return Ok(StepAttempt::rejected(f64::NAN, 0.5 * h));
            }
            Err(e) => return Err(e),
        };
        let b = &ws.step;
        // frames are at the converged iterate (the last Newton evaluation)
        let w = ctl.atol + ctl.rtol * frame_extent(&ws.sys.frames).max(1.0);
        let err = (0..model.nu)
            .map(|i| {
                let du = (b.u_dot_new[i] - s.u_dot[i]).abs();
                h * h * err_coeff * ws.error_scales[i] * du / w
            })
            .fold(0.0, f64::max);
        let fac = if err > 0.0 {
            0.9 * err.powf(-1.0 / 3.0)
        } else {
            2.0
        };
        let h_next = h * fac.clamp(0.2, 2.0);
        if err > 1.0 {
            return Ok(StepAttempt::rejected(err, h_next));
        }
        if let Some(h_gap) = super::genalpha_contact::penetration_rejection(model, ws, ctl, h) {
            return Ok(StepAttempt::rejected(f64::INFINITY, h_gap));
        }
        commit(s, &ws.step, h);
        let (mut energy, g, gd) = monitor_converged(model, s, ws, self.step_energy);
        energy.springs += regularized_contacts_converged(model, s, ws, h, self.step_energy);
        let h_next = h_next.min(super::genalpha_contact::closing_step_limit(
            model,
            &s.contacts,
            ctl,
        ));
        (
            stats.energy,
            stats.g_max,
            stats.g_dot_max,
            stats.error_estimate,
        ) = (energy, g, gd, err);
        Ok(StepAttempt {
            accepted: true,
            stats,
            h_next,
        })
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
    contact: &mut crate::contact::ContactWork,
) -> bool {
    saddle.build(kind, model, q, u, &[], sys);
    if let SaddleKind::Iteration { c_u, c_q, .. } = kind {
        saddle.add_contact_tangents(model, q, u, sys, contact, c_q, c_u);
    }
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

/// [`crate::Element::velocity_scales`] of every body into `out` (nu).
/// A scattered body's scales go through its element buffer in `local` (sized whenever a model
/// has scattered bodies), so this does not allocate.
pub(super) fn fill_error_scales(
    model: &Model,
    out: &mut [f64],
    local: &mut [crate::state::ElementBuffers],
) {
    for (i, b) in model.bodies.iter().enumerate() {
        let nu = b.element.nu();
        if b.is_scattered() {
            let l = &mut local[i].h;
            b.element.velocity_scales(l);
            b.dofs().u.scatter_into(l, out);
            continue;
        }
        b.element
            .velocity_scales(&mut out[b.u_offset..b.u_offset + nu]);
    }
}

/// Largest distance of a frame from the origin (m), 0 without frames.
fn frame_extent(frames: &[crate::element::FrameKinematics]) -> f64 {
    frames.iter().map(|k| k.position.norm()).fold(0.0, f64::max)
}

/// A non-finite quantity in the Newton iteration of the step `(t, h)`.
fn nonfinite(what: &'static str, t: f64, h: f64, residual: f64) -> SolverError {
    SolverError::NonFinite {
        what,
        t,
        h,
        residual,
    }
}

/// Why an iterate cannot be judged.
enum IterateError {
    /// A body cannot be evaluated there.
    Element(crate::error::EvaluationError),
    /// The named quantity is not finite.
    NonFinite(&'static str),
}

impl IterateError {
    /// The solver error of the step `(t, h)` (last finite residual `residual`).
    fn at(self, t: f64, h: f64, residual: f64) -> SolverError {
        match self {
            IterateError::Element(e) => e.at(t, h),
            IterateError::NonFinite(what) => nonfinite(what, t, h, residual),
        }
    }
}

/// Residual measures of one Newton iterate.
struct IterateResidual {
    /// `max |r|`, `r = M u_dot - h + G^T lambda`.
    r_max: f64,
    /// `max |g|`.
    g_max: f64,
    /// Force scale `max(|h|_inf, |M u_dot|_inf)` (the terms `r` balances; `G^T lambda` is left
    /// out so that diverging multipliers cannot inflate it).
    f_scale: f64,
}

/// Evaluates the model at the iterate in `b` (frames, forces, constraints into `sys`) and writes
/// `-r` into `b.rhs[..nu]`, `r = M(q) u_dot - h(t, q, u) + G^T lambda` (the product `M u_dot`
/// from the elements; no assembled `M`). Err: a body that cannot be evaluated, or a non-finite
/// quantity.
fn newton_residual(
    model: &Model,
    t1: f64,
    b: &mut StepBuffers,
    sys: &mut SystemBuffers,
    contact: &mut crate::contact::ContactWork,
    saddle: &mut SystemMatrix,
    update_load_coefficients: bool,
) -> Result<IterateResidual, IterateError> {
    let nu = model.nu;
    system::evaluate(model, &b.q_new, &b.u_new, sys).map_err(IterateError::Element)?;
    system::assemble_forces(model, t1, &b.q_new, &b.u_new, 1.0, sys);
    // regularized contacts: the contact search once per evaluation, W_N F_N + W_T F_T into h
    let contact_scale = crate::contact::regularized::add_regularized_forces(
        model,
        &sys.frames,
        &sys.eval,
        contact,
        &mut sys.h,
    );
    let (ud, l) = (&b.u_dot_new, &b.lambda_new);
    system::add_load_stiffening_forces(model, t1, 1.0, ud, l, update_load_coefficients, sys);
    system::update_constraints(model, t1, sys);
    let r_acc = &mut b.rhs[..nu];
    saddle.mass_times_vector(model, &b.q_new, &b.u_dot_new, sys, r_acc);
    // the terms r balances, and the gross terms whose differences the element forces are
    let f_scale = super::max_abs(r_acc)
        .max(super::max_abs(&sys.h))
        .max(system::force_scale_in(model, &b.q_new, &mut sys.eval))
        .max(crate::force::force_element_scale(model, &sys.frames))
        .max(contact_scale);
    // -h, then + G^T lambda (column by column of G, rows in order)
    for (r, h) in r_acc.iter_mut().zip(&sys.h) {
        *r -= h;
    }
    saddle.add_g_transpose_times(sys, &b.lambda_new, r_acc);
    let mut r_max = 0.0_f64;
    for r in r_acc.iter_mut() {
        if !r.is_finite() {
            return Err(IterateError::NonFinite("force residual"));
        }
        r_max = r_max.max(r.abs());
        *r = -*r;
    }
    let mut g_max = 0.0_f64;
    for gk in &sys.g {
        if !gk.is_finite() {
            return Err(IterateError::NonFinite("constraint"));
        }
        g_max = g_max.max(gk.abs());
    }
    Ok(IterateResidual {
        r_max,
        g_max,
        f_scale,
    })
}

/// Outcome of [`judge_convergence`].
struct Convergence {
    /// The iterate is accepted.
    converged: bool,
    /// Scaled increment `max(|du_dot| / w_u, |d lambda| / w_lambda)` of the last solve.
    e: f64,
    /// The force residual is at its round-off floor ([`ROUNDOFF_RESIDUAL`]).
    at_roundoff: bool,
}

/// Scaled Newton increment (1 = converged) below which the node-load stiffening coefficients
/// (`system::add_load_stiffening_forces`) are frozen for the rest of the step: their dependence on
/// the multipliers is not in the iteration matrix, and updating them at every iterate can stall
/// Newton in a cycle at about 1e-10 relative (flexible slider-crank rod); frozen from an iterate
/// whose multipliers are within about 1e3 tolerances of the solution, they differ from the
/// converged multipliers' by about 1e-7 relative.
const LOAD_COEFFICIENT_FREEZE: f64 = 1e3;

/// Force residual at round-off, relative to the force scale: below it, further iterations
/// only move the iterate by rounding noise (an ill-conditioned direction can amplify that
/// noise above the increment tolerance: the clamped slider-crank rod stalled at
/// `|r| = 8e-12` N for `|h| = 230` N, 36 eps relative).
const ROUNDOFF_RESIDUAL: f64 = 1e3 * f64::EPSILON;

/// The Newton acceptance test of [`NewtonSettings`](super::NewtonSettings) for the iterate in
/// `b` with residual `it`, reached by a solve with increments `(du, dl)` (max norms of the
/// accelerations and multipliers; `prev`: the solve before).
fn judge_convergence(
    nt: &super::NewtonSettings,
    it: &IterateResidual,
    b: &StepBuffers,
    (du, dl): (f64, f64),
    prev: (f64, f64),
    beta_p: f64,
) -> Convergence {
    let q_scale = super::max_abs(&b.q_new).max(1.0);
    let w_u = nt.atol + nt.rtol * super::max_abs(&b.u_dot_new);
    let w_l = nt.atol + nt.rtol * super::max_abs(&b.lambda_new).max(it.f_scale);
    let e = (du / w_u).max(dl / w_l);
    // increment at the round-off floor of the positions (beta' du_dot ~ eps |q|)
    let du_floor = beta_p * du <= 16.0 * f64::EPSILON * q_scale;
    let at_roundoff = it.r_max <= ROUNDOFF_RESIDUAL * it.f_scale;
    if nt.legacy_acceptance {
        // test only: the rule before issue 8 (acceleration increment and constraints alone)
        return Convergence {
            converged: it.g_max <= nt.constraint_tol * q_scale && (du <= w_u || du_floor),
            e: du / w_u,
            at_roundoff,
        };
    }
    let residual_ok = it.r_max <= nt.rtol.max(ROUNDOFF_RESIDUAL) * it.f_scale;
    let increments_ok = ((du <= w_u || du_floor) && dl <= w_l)
        || (remaining_error(du, prev.0) <= w_u && remaining_error(dl, prev.1) <= w_l);
    Convergence {
        converged: it.g_max <= nt.constraint_tol * q_scale
            && residual_ok
            && (increments_ok || at_roundoff),
        e,
        at_roundoff,
    }
}

/// Error left in an iterate reached by the increment `d` after the increment `d_prev`, for a
/// linearly converging iteration with rate `theta = d / d_prev`: `theta / (1 - theta) d`
/// (Hairer & Wanner, Solving ODEs II, IV.8, eq. (8.10)); infinite without a previous increment
/// or at a rate >= [`MODIFIED_NEWTON_CONTRACTION`](super::MODIFIED_NEWTON_CONTRACTION).
fn remaining_error(d: f64, d_prev: f64) -> f64 {
    if d == 0.0 {
        return 0.0;
    }
    let theta = d / d_prev;
    if !(d_prev.is_finite() && theta < super::MODIFIED_NEWTON_CONTRACTION) {
        return f64::INFINITY;
    }
    theta / (1.0 - theta) * d
}

/// Solves `S [du_dot; d lambda] = [-r; -g / beta']` (`-r` already in `b.rhs[..nu]`) with the
/// factored `saddle` and adds the increment to `b.u_dot_new`, `b.lambda_new`. Returns the max norms
/// `(|du_dot|, |d lambda|)`, `None` if the increment is not finite.
fn apply_newton_increment(
    nu: usize,
    beta_p: f64,
    g: &[f64],
    saddle: &mut SystemMatrix,
    b: &mut StepBuffers,
) -> Option<(f64, f64)> {
    let sol = &mut b.rhs;
    for (k, gk) in g.iter().enumerate() {
        sol[nu + k] = -gk / beta_p;
    }
    saddle.solve_in_place(sol);
    if sol.iter().any(|x| !x.is_finite()) {
        return None;
    }
    for (x, d) in b.u_dot_new.iter_mut().zip(&sol[..nu]) {
        *x += d;
    }
    for (l, d) in b.lambda_new.iter_mut().zip(&sol[nu..]) {
        *l += d;
    }
    Some((super::max_abs(&sol[..nu]), super::max_abs(&sol[nu..])))
}

/// [`super::monitor`] right after a converged [`GenAlpha::solve_step`] and [`commit`]: the last
/// Newton evaluation was at the committed `(t, q, u)`, so the evaluated elements, frames and
/// constraint buffers in `ws.sys` are current and are reused (bitwise the same values as a fresh evaluation). Energies
/// only if `with_energy`, else zero.
fn monitor_converged(
    model: &Model,
    s: &State,
    ws: &mut Workspace,
    with_energy: bool,
) -> (system::Energy, f64, f64) {
    let sys = &mut ws.sys;
    let (g, gd) = ws.saddle.constraint_drift(sys, &s.u);
    let energy = if with_energy {
        system::energy(model, &s.q, &s.u, &mut sys.eval, &sys.frames)
    } else {
        system::Energy::default()
    };
    (energy, g, gd)
}

/// The regularized contacts after a converged step of size `h` (evaluated state in `ws.sys`):
/// their states into `s.contacts` ([`crate::contact::regularized::update_regularized_states`])
/// and, with `with_energy`, their penalty energy `sum 1/2 k g_N^2` (returned; reported with the
/// springs' energy as the Moreau stepper does). Nothing for a model without contacts.
fn regularized_contacts_converged(
    model: &Model,
    s: &mut State,
    ws: &mut Workspace,
    h: f64,
    with_energy: bool,
) -> f64 {
    if model.contacts.is_empty() {
        return 0.0;
    }
    let (sys, work) = (&ws.sys, &mut ws.contact);
    crate::contact::regularized::update_regularized_states(
        model,
        &sys.frames,
        &sys.eval,
        work,
        h,
        &mut s.contacts,
    );
    if with_energy {
        crate::contact::regularized_energy(model, &sys.frames, &sys.eval, work)
    } else {
        0.0
    }
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

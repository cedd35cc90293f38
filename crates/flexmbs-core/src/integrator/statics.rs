//! Static equilibrium `h(q, u = 0; load factor) - G^T lambda = 0`, `g(q) = 0` by Newton with
//! load stepping: gravity and point loads are scaled by the load factor `mu` (springs and
//! elastic forces are not), `mu` goes `1/n, 2/n, ..., 1`; a failed increment is halved.
//!
//! Newton system per iteration (unknowns: velocity-space position increment `dv`, `lambda`):
//! `[-dh/dq + d(G^T lambda)/dq  G^T; G  0] [dv; d lambda] = [h - G^T lambda; -g]`, `q <- q ⊕ dv`
//! (the geometric stiffness of the constraint forces is what makes a loaded mechanism stiff;
//! it is computed by finite differences, [`crate::system::subtract_constraint_force_tangent`]).
//! FFR bodies with node-load stiffening get `−K_load(c) q_f` with `c` from the iterate's
//! multipliers and loads ([`crate::system::add_load_stiffening_forces`], `u_dot = 0`).

use super::stepper::{drive, StaticsStepper, StepAttempt, StepControl, Stepper};
use super::{NewtonSettings, StepStats};
use crate::algebra::SaddleKind;
use crate::error::SolverError;
use crate::model::Model;
use crate::state::{State, Workspace};
use crate::system;
use std::ops::ControlFlow;

/// Settings of [`Statics`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticsSettings {
    /// Number of equal load increments. Default 1.
    pub load_steps: usize,
    /// Smallest load increment before giving up. Default 1e-4.
    pub min_increment: f64,
    /// Force tolerance relative to `max(1, |h(q0, mu = 1)|_inf)`. Default 1e-10.
    pub force_tol: f64,
    /// Newton settings (`max_iterations`, `constraint_tol` are used).
    pub newton: NewtonSettings,
}

impl Default for StaticsSettings {
    fn default() -> Self {
        Self {
            load_steps: 1,
            min_increment: 1e-4,
            force_tol: 1e-10,
            newton: NewtonSettings::default(),
        }
    }
}

/// Result summary of a static solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticStats {
    /// Load increments solved (incl. bisections).
    pub increments: usize,
    /// Total Newton iterations.
    pub iterations: usize,
    /// Final force residual (max norm).
    pub residual: f64,
    /// Final `max |g|`.
    pub g_max: f64,
}

/// Static equilibrium solver.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Statics {
    /// Settings.
    pub settings: StaticsSettings,
}

impl Statics {
    /// Solver with the given settings.
    pub fn new(settings: StaticsSettings) -> Self {
        Self { settings }
    }

    /// Solves for the equilibrium at full load starting from `s.q`; sets `s.u = 0`, `s.q`,
    /// `s.lambda` (and `s.u_dot = 0`).
    pub fn solve(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
    ) -> Result<StaticStats, SolverError> {
        self.solve_with(model, s, ws, |_, _, _| {})
    }

    /// [`Statics::solve`], calling `on_increment(state, mu, stats)` after every converged load
    /// increment (load factor `mu` in `(0, 1]`, the last call at `mu = 1`): the equilibrium path
    /// of a load-stepped solution, e.g. a load-deflection curve. Bisected increments that fail
    /// are not reported. ([`super::drive`] with [`StaticsStepper`], load factor as its progress.)
    pub fn solve_with(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        mut on_increment: impl FnMut(&State, f64, &StaticStats),
    ) -> Result<StaticStats, SolverError> {
        let mut stepper = StaticsStepper::new(*self);
        stepper.initialize(model, s, ws)?;
        let mut stats = StaticStats {
            increments: 0,
            iterations: 0,
            residual: 0.0,
            g_max: 0.0,
        };
        drive(&mut stepper, model, s, ws, self.control(), 1.0, |s, st| {
            stats = StaticStats {
                increments: stats.increments + 1,
                iterations: stats.iterations + st.iterations,
                residual: st.residual,
                g_max: st.g_max,
            };
            on_increment(s, st.t, &stats);
            ControlFlow::Continue(())
        })?;
        Ok(stats)
    }

    /// Load increments for [`super::drive`]: `1 / load_steps`, halved on failure down to
    /// `min_increment`.
    pub fn control(&self) -> StepControl {
        let dmu = 1.0 / self.settings.load_steps.max(1) as f64;
        StepControl::Adaptive {
            h_init: dmu,
            h_min: self.settings.min_increment,
            h_max: dmu,
        }
    }

    /// Checks the settings, sets `u = u_dot = 0` and returns the force tolerance
    /// `force_tol max(1, |h(q0, mu = 1)|_inf)`, at least `16 eps` times the largest
    /// `Element::force_scale` at `q0`.
    pub(super) fn prepare(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
    ) -> Result<f64, SolverError> {
        system::check_state_size(model, s)?;
        let cfg = &self.settings;
        if cfg.load_steps == 0 {
            return Err(SolverError::InvalidSetting {
                name: "load_steps",
                value: 0.0,
                reason: "must be >= 1",
            });
        }
        s.u.fill(0.0);
        s.u_dot.fill(0.0);
        let sys = &mut ws.sys;
        system::evaluate(model, &s.q, &s.u, sys).map_err(|e| e.at(0.0, 0.0))?;
        system::assemble_forces(model, s.t, &s.q, &s.u, 1.0, sys);
        // not below the round-off of elastic forces of absolute coordinates (superelements:
        // `Element::force_scale`), which a light load (gravity alone) would otherwise ask for
        let roundoff = 16.0 * f64::EPSILON * system::force_scale(model, &s.q);
        Ok((cfg.force_tol * super::max_abs(&ws.sys.h).max(1.0)).max(roundoff))
    }

    /// The load increment from `mu` to `target`: Newton from the current state; on failure
    /// (Newton, singular tangent) the state is restored and the increment is rejected with half
    /// its size, or the error is returned once half would fall below `min_increment`.
    pub(super) fn increment(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        (mu, target, tol): (f64, f64, f64),
    ) -> Result<StepAttempt, SolverError> {
        ws.step.y[0][..model.nq].copy_from_slice(&s.q);
        ws.step.y[1][..model.nc].copy_from_slice(&s.lambda);
        match self.newton(model, s, ws, target, tol) {
            Ok((iterations, residual, g_max)) => Ok(StepAttempt {
                accepted: true,
                stats: StepStats {
                    t: target,
                    h: target - mu,
                    iterations,
                    residual,
                    g_max,
                    ..Default::default()
                },
                h_next: target - mu,
            }),
            Err(e @ SolverError::NewtonFailed { .. }) | Err(e @ SolverError::Singular { .. }) => {
                s.q.copy_from_slice(&ws.step.y[0][..model.nq]);
                s.lambda.copy_from_slice(&ws.step.y[1][..model.nc]);
                let half = 0.5 * (target - mu);
                if half < self.settings.min_increment {
                    return Err(e);
                }
                Ok(StepAttempt::rejected(f64::NAN, half))
            }
            Err(e) => Err(e),
        }
    }

    /// Least-squares multipliers at the current configuration, `G G^T lambda = G h`, via
    /// `[I G^T; G 0] [x; lambda] = [h; 0]`: the start of the geometric stiffness.
    fn multiplier_predictor(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        mu: f64,
    ) -> Result<(), SolverError> {
        let (nu, t, sys) = (model.nu, s.t, &mut ws.sys);
        system::evaluate(model, &s.q, &s.u, sys).map_err(|e| e.at(mu, mu))?;
        system::assemble_forces(model, t, &s.q, &s.u, mu, sys);
        system::add_load_stiffening_forces(model, t, mu, &s.u_dot, &s.lambda, true, sys);
        let (fr, ev) = (&sys.frames, &sys.eval);
        crate::contact::regularized::add_regularized_forces(
            model,
            fr,
            ev,
            &mut ws.contact,
            &mut sys.h,
        );
        system::update_constraints(model, t, sys);
        let saddle = &mut ws.saddle;
        saddle.build(SaddleKind::LeastSquares, model, &s.q, &s.u, &s.lambda, sys);
        if !saddle.factor() {
            return Err(SolverError::Singular {
                what: "constraint Jacobian (redundant constraints?)",
                t: mu,
                h: mu,
            });
        }
        let rhs = &mut ws.step.rhs;
        rhs[..nu].copy_from_slice(&sys.h);
        rhs[nu..].fill(0.0);
        saddle.solve_in_place(rhs);
        s.lambda.copy_from_slice(&rhs[nu..]);
        Ok(())
    }

    /// Newton iterations at load factor `mu`: (iterations, residual, max |g|).
    fn newton(
        &self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        mu: f64,
        tol: f64,
    ) -> Result<(usize, f64, f64), SolverError> {
        let nt = &self.settings.newton;
        let (nu, nc, t) = (model.nu, model.nc, s.t);
        let mut residual = f64::NAN;
        if nc > 0 {
            self.multiplier_predictor(model, s, ws, mu)?;
        }
        for iter in 0..=nt.max_iterations {
            let sys = &mut ws.sys;
            system::evaluate(model, &s.q, &s.u, sys).map_err(|e| e.at(mu, mu))?;
            system::assemble_forces(model, t, &s.q, &s.u, mu, sys);
            // node-load stiffening (`ffr::LoadStiffening`): coefficients from this iterate's
            // multipliers, loads at `mu` and `u_dot = 0`; their dependence on `lambda` is not in
            // the tangent
            system::add_load_stiffening_forces(model, t, mu, &s.u_dot, &s.lambda, true, sys);
            // regularized contacts: reactions of the penalty springs (not scaled by mu)
            let (fr, ev) = (&sys.frames, &sys.eval);
            crate::contact::regularized::add_regularized_forces(
                model,
                fr,
                ev,
                &mut ws.contact,
                &mut sys.h,
            );
            system::update_constraints(model, t, sys);
            let rhs = &mut ws.step.rhs;
            for (i, ri) in rhs[..nu].iter_mut().enumerate() {
                *ri = sys.h[i]
                    - (0..nc)
                        .map(|k| sys.g_jac[(k, i)] * s.lambda[k])
                        .sum::<f64>();
            }
            for k in 0..nc {
                rhs[nu + k] = -sys.g[k];
            }
            if rhs.iter().any(|x| !x.is_finite()) {
                return Err(SolverError::NonFinite {
                    what: "static residual",
                    t: mu,
                    h: mu,
                    residual,
                });
            }
            residual = super::max_abs(&rhs[..nu]);
            let g_max = super::max_abs(&rhs[nu..]);
            // constraints as in generalized-alpha: relative to max(1, |q|_inf)
            let q_scale = super::max_abs(&s.q).max(1.0);
            if residual <= tol && g_max <= nt.constraint_tol * q_scale {
                return Ok((iter, residual, g_max));
            }
            if iter == nt.max_iterations {
                break;
            }
            let saddle = &mut ws.saddle;
            let kind = SaddleKind::StaticTangent { t, mu };
            saddle.build(kind, model, &s.q, &s.u, &s.lambda, sys);
            saddle.add_contact_tangents(model, &s.q, &s.u, sys, &mut ws.contact, 1.0, 0.0);
            if !saddle.factor() {
                return Err(SolverError::Singular {
                    what: "static tangent",
                    t: mu,
                    h: mu,
                });
            }
            saddle.solve_in_place(rhs);
            system::integrate_positions(model, &s.q, &rhs[..nu], &mut ws.step.q_new);
            s.q.copy_from_slice(&ws.step.q_new);
            for k in 0..nc {
                s.lambda[k] += rhs[nu + k];
            }
        }
        Err(SolverError::NewtonFailed {
            t: mu,
            h: mu,
            residual,
            iterations: nt.max_iterations,
        })
    }
}

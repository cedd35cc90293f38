//! Moreau's midpoint time-stepping (seed 000 ch. 4; Moreau 1988, Studer 2009): a velocity-level
//! scheme for set-valued contact laws with impacts and for joints.
//!
//! One step from `(t, q, u)` of size `h`:
//! 1. `q_M = q ⊕ h/2 u` (the midpoint), evaluated there: `M`, `h`, joint rows `G`, contact
//!    kinematics ([`crate::contact::pair`]); regularized contact laws add their forces to `h`.
//! 2. Free velocity `u_F = u + M^-1 h h`; the closed set-valued contacts (`g_N(q_M) <= ` [`MoreauSettings::gap_tolerance`],
//!    bilateral ones always) and the joint rows give `W = [G^T, W_N, W_T]`, the Delassus matrix
//!    `D = W^T M^-1 W` (block Cholesky of `M` with `m` right-hand sides) and
//!    `gamma_E = W^T u_F + w + D Lambda`.
//! 3. The impulses `Lambda` by projected Gauss-Seidel on the prox equations of
//!    [`crate::contact::law`] (joint rows: `gamma_E = 0`), warm-started with the last step's
//!    impulses, with `r_i = relaxation / D_ii` per row (friction: the larger tangent diagonal).
//!    Without closed set-valued contacts (joint and guide rows only) the problem is linear,
//!    `D Lambda = -(W^T u_F + w)`, and is solved directly by a Cholesky factorization of `D`
//!    (which the joint projection reuses); Gauss-Seidel remains the fallback for a singular `D`
//!    (redundant joints).
//! 4. `u_E = u_F + M^-1 W Lambda`, `q_E = q_M ⊕ h/2 u_E`; joints drift on position level, so
//!    `q_E` is projected onto `g = 0` by `dq = M^-1 G^T mu`, `(G M^-1 G^T) mu = -g(q_E)`.
//!
//! Free flight under constant forces is integrated exactly (the midpoint rule is exact for
//! quadratic positions); an impact is resolved within the step whose midpoint penetrates.

use super::{monitor, StepAttempt, StepStats, Stepper, StepperStatistics};
use crate::contact::{ContactGeometry, Friction, NormalLaw};
use crate::error::SolverError;
use crate::model::Model;
use crate::state::{State, Workspace};
use crate::system;
use faer::Mat;

/// Settings of the Moreau time-stepper.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoreauSettings {
    /// Relaxation `omega` of the r-factors `r_i = omega / D_ii` (0 < omega < 2). Default 1
    /// (each row's local problem solved exactly per sweep).
    pub relaxation: f64,
    /// The prox iteration stops when the largest impulse change of a sweep is at most this
    /// times the impulse scale (the largest impulse, or the impulse that stops the free
    /// velocity of a row), or when the relative velocities of the rows changed in the sweep by
    /// at most this times their scale (the largest free or initial rate): redundant contacts
    /// (a block on four corners) leave the impulses free to wander where the velocities have
    /// converged. Default 1e-12.
    pub tolerance: f64,
    /// Most Gauss-Seidel sweeps per step before [`SolverError::ContactSolve`]. Default 10000.
    pub max_iterations: usize,
    /// Newton iterations of the joints' position projection per step (0: none). Default 3.
    pub projection_iterations: usize,
    /// The projection stops when `max |g| <= projection_tol`. Default 1e-12.
    pub projection_tol: f64,
    /// A unilateral contact is closed (enters the step's problem) when its gap at the midpoint
    /// is at most this (model length unit). Default 1e-9: a contact resting at zero gap stays
    /// closed despite round-off in the positions (with 0, corners of a resting block open at
    /// gaps of 1e-18 and it tips). A closed contact that separates gets zero impulse.
    pub gap_tolerance: f64,
}

impl Default for MoreauSettings {
    fn default() -> Self {
        Self {
            relaxation: 1.0,
            tolerance: 1e-12,
            max_iterations: 10_000,
            projection_iterations: 3,
            projection_tol: 1e-12,
            gap_tolerance: 1e-9,
        }
    }
}

/// One block of the velocity-level problem.
#[derive(Debug, Clone, Copy)]
enum Block {
    /// A joint row (equality on velocity level).
    Joint { row: usize },
    /// A contact's rows from `row`: the normal (if set-valued) then `tangents` friction rows.
    Contact {
        contact: usize,
        row: usize,
        normal: Option<NormalRow>,
        tangents: usize,
        mu: f64,
        /// Friction bound of a regularized normal law (`mu F_N h`); `None`: `mu Lambda_N`.
        fixed_bound: Option<f64>,
    },
}

#[derive(Debug, Clone, Copy)]
struct NormalRow {
    restitution: f64,
    bilateral: bool,
}

/// Buffers of the stepper, sized by [`MoreauStepper::initialize`].
#[derive(Debug)]
struct Buffers {
    q_m: Vec<f64>,
    u_free: Vec<f64>,
    rhs: Vec<f64>,
    /// `W` (nu x m, column-major), then `M^-1 W`.
    w: Vec<f64>,
    minv_w: Vec<f64>,
    /// Delassus matrix (m x m, column-major).
    delassus: Vec<f64>,
    /// `W^T u_F + w` and the start rates `W^T u` per row.
    b: Vec<f64>,
    gamma_s: Vec<f64>,
    lambda: Vec<f64>,
    /// Impulses before the last sweep.
    lambda_prev: Vec<f64>,
    blocks: Vec<Block>,
    geometry: Vec<ContactGeometry>,
    /// Regularized normal force per contact.
    normal_force: Vec<f64>,
    /// Regularized friction forces per contact (tangent 1, 2).
    friction_force: Vec<[f64; 2]>,
    projection: Mat<f64>,
    projection_rhs: Vec<f64>,
    /// `projection` holds the Cholesky factor of this step's joint block (the prox problem had
    /// joint rows only and was solved directly).
    joints_factored: bool,
}

impl Buffers {
    /// Buffers for `nq`, `nu`, `nc` joint rows and `nk` contacts (at most 3 rows each).
    fn new(nq: usize, nu: usize, nc: usize, nk: usize) -> Self {
        let m = nc + 3 * nk;
        let v = |n| vec![0.0; n];
        Self {
            q_m: v(nq),
            u_free: v(nu),
            rhs: v(nu),
            w: v(nu * m),
            minv_w: v(nu * m),
            delassus: v(m * m),
            b: v(m),
            gamma_s: v(m),
            lambda: v(m),
            lambda_prev: v(m),
            blocks: Vec::with_capacity(nc + nk),
            geometry: vec![ContactGeometry::ZERO; nk],
            normal_force: v(nk),
            friction_force: vec![[0.0; 2]; nk],
            projection: Mat::zeros(nc, nc),
            projection_rhs: v(nc),
            joints_factored: false,
        }
    }
}

/// The Moreau time-stepper as a [`Stepper`] (fixed steps: [`MoreauStepper::control`]).
#[derive(Debug)]
pub struct MoreauStepper {
    /// Settings.
    pub settings: MoreauSettings,
    stats: StepperStatistics,
    buf: Buffers,
    /// Columns `m` of `W` in the current step (the stride of the Delassus matrix).
    m_last: usize,
    /// [`Self::advance`] evaluates the end state's energy and drift ([`monitor`]); the
    /// step-size control switches it off for the steps whose statistics it discards.
    end_monitor: bool,
}

impl MoreauStepper {
    /// A stepper with `settings`.
    pub fn new(settings: MoreauSettings) -> Self {
        Self {
            settings,
            stats: StepperStatistics::default(),
            buf: Buffers::new(0, 0, 0, 0),
            m_last: 0,
            end_monitor: true,
        }
    }

    /// Fixed steps of size `h` for [`super::drive`].
    pub fn control(&self, h: f64) -> super::StepControl {
        super::StepControl::Fixed { h }
    }

    /// Checks the settings.
    fn check(&self) -> Result<(), SolverError> {
        let s = &self.settings;
        let bad = |name, value, reason| SolverError::InvalidSetting {
            name,
            value,
            reason,
        };
        if !(s.relaxation > 0.0 && s.relaxation < 2.0) {
            return Err(bad("relaxation", s.relaxation, "must lie in (0, 2)"));
        }
        if !(s.tolerance > 0.0 && s.tolerance.is_finite()) {
            return Err(bad("tolerance", s.tolerance, "must be finite and > 0"));
        }
        if s.max_iterations == 0 {
            return Err(bad("max_iterations", 0.0, "must be >= 1"));
        }
        if !(s.projection_tol > 0.0 && s.projection_tol.is_finite()) {
            return Err(bad(
                "projection_tol",
                s.projection_tol,
                "must be finite and > 0",
            ));
        }
        if !(s.gap_tolerance >= 0.0 && s.gap_tolerance.is_finite()) {
            return Err(bad(
                "gap_tolerance",
                s.gap_tolerance,
                "must be finite and >= 0",
            ));
        }
        Ok(())
    }
}

impl Stepper for MoreauStepper {
    /// Checks the settings and the state size, sizes the buffers and the contact states.
    fn initialize(
        &mut self,
        model: &Model,
        s: &mut State,
        _ws: &mut Workspace,
    ) -> Result<(), SolverError> {
        self.check()?;
        system::check_state_size(model, s)?;
        let nk = model.contacts.len();
        self.buf = Buffers::new(model.nq, model.nu, model.nc, nk);
        s.contacts.resize(nk, Default::default());
        Ok(())
    }

    fn step(
        &mut self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        h: f64,
    ) -> Result<StepAttempt, SolverError> {
        let stats = self.advance(model, s, ws, h)?;
        let a = StepAttempt {
            accepted: true,
            stats,
            h_next: h,
        };
        self.stats.accepted += 1;
        self.stats.iterations += stats.iterations;
        Ok(a)
    }

    fn statistics(&self) -> StepperStatistics {
        self.stats
    }
}

impl MoreauStepper {
    /// One step of size `h` (module documentation), the state advanced; without
    /// [`Self::end_monitor`] the statistics hold no energy and drift.
    pub(super) fn advance(
        &mut self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        h: f64,
    ) -> Result<StepStats, SolverError> {
        if self.buf.q_m.len() != model.nq || s.contacts.len() != model.contacts.len() {
            return Err(SolverError::StateSize {
                what: "contacts (stepper not initialized)",
                got: s.contacts.len(),
                expected: model.contacts.len(),
            });
        }
        self.midpoint(model, s, ws, h)?;
        self.regularized_forces(model, ws);
        // free velocity u_F = u + h M^-1 h
        let b = &mut self.buf;
        for (r, f) in b.rhs.iter_mut().zip(&ws.sys.h) {
            *r = h * f;
        }
        ws.mass_blocks.solve_in_place(&mut b.rhs, 1);
        for ((uf, u), du) in b.u_free.iter_mut().zip(&s.u).zip(&b.rhs) {
            *uf = u + du;
        }
        let m = self.assemble_directions(model, s, ws, h);
        self.m_last = m;
        self.delassus(ws, &s.u, m);
        let (iterations, residual) =
            self.solve_prox(m)
                .map_err(|(iterations, residual)| SolverError::ContactSolve {
                    t: s.t,
                    h,
                    residual,
                    iterations,
                })?;
        self.finish(model, s, ws, h, m)?;
        if s.u.iter().chain(&s.q).any(|x| !x.is_finite()) {
            return Err(SolverError::NonFinite {
                what: "state",
                t: s.t - h,
                h,
                residual,
            });
        }
        if !self.end_monitor {
            return Ok(StepStats {
                t: s.t,
                h,
                iterations,
                residual,
                ..Default::default()
            });
        }
        let (mut energy, g_max, g_dot_max) = monitor(model, s, ws);
        // penalty contacts store energy like springs (frames evaluated at the end by `monitor`)
        energy.springs += crate::contact::regularized_energy(
            model,
            &ws.sys.frames,
            &ws.sys.eval,
            &mut ws.contact,
        );
        Ok(StepStats {
            t: s.t,
            h,
            iterations,
            residual,
            energy,
            g_max,
            g_dot_max,
            ..Default::default()
        })
    }

    /// `q_M = q ⊕ h/2 u`, evaluated there: elements, frames, forces `h`, the factored mass
    /// blocks and the joint rows; the contact kinematics into the buffers.
    fn midpoint(
        &mut self,
        model: &Model,
        s: &State,
        ws: &mut Workspace,
        h: f64,
    ) -> Result<(), SolverError> {
        let dv = &mut ws.step.dv;
        for (d, u) in dv.iter_mut().zip(&s.u) {
            *d = 0.5 * h * u;
        }
        let q_m = &mut self.buf.q_m;
        system::integrate_positions(model, &s.q, dv, q_m);
        let t_m = s.t + 0.5 * h;
        let sys = &mut ws.sys;
        system::evaluate(model, q_m, &s.u, sys).map_err(|e| e.at(s.t, h))?;
        system::assemble_forces(model, t_m, q_m, &s.u, 1.0, sys);
        ws.mass_blocks
            .update(model, q_m, &mut sys.eval)
            .map_err(|_| SolverError::Singular {
                what: "mass",
                t: s.t,
                h,
            })?;
        if model.nc > 0 {
            system::update_constraints(model, t_m, sys);
        }
        let work = ws.contact.sides.iter_mut();
        for ((c, g), w) in model.contacts.iter().zip(&mut self.buf.geometry).zip(work) {
            *g = c.geometry(model, &sys.frames, &sys.eval, w);
        }
        Ok(())
    }

    /// Forces of the regularized laws at `(q_M, u)` added to `ws.sys.h`.
    fn regularized_forces(&mut self, model: &Model, ws: &mut Workspace) {
        let sys = &mut ws.sys;
        for (i, c) in model.contacts.iter().enumerate() {
            self.buf.normal_force[i] = 0.0;
            self.buf.friction_force[i] = [0.0; 2];
            let NormalLaw::Regularized { stiffness, damping } = c.law.normal else {
                continue;
            };
            let geo = &self.buf.geometry[i];
            let work = &ws.contact.sides[i];
            let (gn_dot, gt_dot) = geo.gap_velocities();
            let f_n =
                crate::contact::law::regularized_normal_force(stiffness, damping, geo.gap, gn_dot);
            self.buf.normal_force[i] = f_n;
            if f_n == 0.0 {
                continue;
            }
            c.add_direction(model, &sys.frames, work, geo, 0, f_n, &mut sys.h);
            if let Friction::Regularized {
                mu, slip_velocity, ..
            } = c.law.friction
            {
                let n = c.law.friction.num_tangents();
                let mut f_t = [0.0; 2];
                crate::contact::law::regularized_friction_force(
                    mu,
                    slip_velocity,
                    f_n,
                    &gt_dot[..n],
                    &mut f_t[..n],
                );
                for (k, f) in f_t.iter().enumerate().take(n) {
                    c.add_direction(model, &sys.frames, work, geo, 1 + k, *f, &mut sys.h);
                }
                self.buf.friction_force[i] = f_t;
            }
        }
    }
}

impl MoreauStepper {
    /// Whether every step evaluates the end state's energy and constraint drift into its
    /// [`super::StepStats`] (default: yes). The evaluation costs about as much as the step's own
    /// element evaluation (one more [`crate::system::evaluate`] and the energies); a driver that
    /// evaluates what it needs itself at its output times switches it off, and the statistics then
    /// carry zero energy and drift.
    pub fn set_end_monitor(&mut self, on: bool) {
        self.end_monitor = on;
    }
}

mod problem;
mod ssc;
pub use ssc::{MoreauSscSettings, MoreauSscStepper};

//! The velocity-level problem of a Moreau step: the force directions `W`, the Delassus matrix,
//! the prox iteration, and the end of the step (velocity and position update, joint projection).

use super::{Block, MoreauStepper, NormalRow};
use crate::contact::law::{prox_disc, prox_nonnegative};
use crate::contact::{ContactState, Friction, NormalLaw};
use crate::error::SolverError;
use crate::linsolve::{cholesky_in_place, cholesky_solve_in_place};
use crate::model::Model;
use crate::state::{State, Workspace};
use crate::system;

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl MoreauStepper {
    /// Columns of `W` (joint rows first, then the closed set-valued contacts), the explicit
    /// rates `w` into `b`, the warm-start impulses, and the blocks. Returns the column count `m`.
    pub(super) fn assemble_directions(
        &mut self,
        model: &Model,
        s: &State,
        ws: &Workspace,
        h: f64,
    ) -> usize {
        let (nu, sys, b) = (model.nu, &ws.sys, &mut self.buf);
        let gap_tol = self.settings.gap_tolerance;
        b.blocks.clear();
        // W's joint columns are G's rows: read G column by column (contiguous)
        for j in 0..nu {
            for (r, g) in sys.g_jac.col_as_slice(j).iter().enumerate() {
                b.w[r * nu + j] = *g;
            }
        }
        for r in 0..model.nc {
            b.b[r] = sys.g_t[r];
            b.lambda[r] = s.lambda[r] * h;
            b.blocks.push(Block::Joint { row: r });
        }
        let mut m = model.nc;
        for (i, c) in model.contacts.iter().enumerate() {
            let geo = &b.geometry[i];
            if !geo.has_contact_point() {
                continue;
            }
            let normal = match c.law.normal {
                NormalLaw::Unilateral { restitution } if geo.gap <= gap_tol => Some(NormalRow {
                    restitution,
                    bilateral: false,
                }),
                NormalLaw::Bilateral => Some(NormalRow {
                    restitution: 0.0,
                    bilateral: true,
                }),
                _ => None,
            };
            let (tangents, mu) = match c.law.friction {
                Friction::Coulomb { mu, directions } => (directions.count(), mu),
                _ => (0, 0.0),
            };
            let fixed_bound = match c.law.normal {
                NormalLaw::Regularized { .. } if tangents > 0 && b.normal_force[i] > 0.0 => {
                    Some(mu * b.normal_force[i] * h)
                }
                _ => None,
            };
            if normal.is_none() && fixed_bound.is_none() {
                continue;
            }
            let work = &ws.contact.sides[i];
            let first = m;
            let used = normal.iter().map(|_| 0).chain(1..=tangents);
            let warm = &s.contacts[i];
            for k in used {
                let col = &mut b.w[m * nu..(m + 1) * nu];
                col.fill(0.0);
                c.add_direction(model, &sys.frames, work, geo, k, 1.0, col);
                b.b[m] = 0.0;
                b.lambda[m] = if warm.active { warm.impulse[k] } else { 0.0 };
                m += 1;
            }
            b.blocks.push(Block::Contact {
                contact: i,
                row: first,
                normal,
                tangents,
                mu,
                fixed_bound,
            });
        }
        m
    }

    /// `M^-1 W`, the Delassus matrix `D = W^T M^-1 W`, `b += W^T u_F` and the start rates
    /// `gamma_S = W^T u`.
    pub(super) fn delassus(&mut self, ws: &Workspace, u: &[f64], m: usize) {
        if m == 0 {
            return;
        }
        let b = &mut self.buf;
        let nu = u.len();
        b.minv_w[..nu * m].copy_from_slice(&b.w[..nu * m]);
        ws.mass_blocks.solve_in_place(&mut b.minv_w[..nu * m], m);
        for j in 0..m {
            let mw = &b.minv_w[j * nu..(j + 1) * nu];
            for i in 0..=j {
                let d = dot(&b.w[i * nu..(i + 1) * nu], mw);
                b.delassus[j * m + i] = d;
                b.delassus[i * m + j] = d;
            }
        }
        for i in 0..m {
            let wi = &b.w[i * nu..(i + 1) * nu];
            b.b[i] += dot(wi, &b.u_free);
            b.gamma_s[i] = dot(wi, u);
        }
    }

    /// Projected Gauss-Seidel on the prox equations (module documentation of
    /// [`crate::contact::law`]). `Ok((sweeps, relative change))`, or `Err` of the same when
    /// [`super::MoreauSettings::max_iterations`] sweeps do not reach the tolerance.
    pub(super) fn solve_prox(&mut self, m: usize) -> Result<(usize, f64), (usize, f64)> {
        self.buf.joints_factored = false;
        if m == 0 {
            return Ok((0, 0.0));
        }
        if let Some(residual) = self.solve_joint_rows_directly(m) {
            return Ok((1, residual));
        }
        let (omega, b) = (self.settings.relaxation, &mut self.buf);
        let d = |i: usize, j: usize| b.delassus[j * m + i];
        // impulse scale: what stops each row's free rate
        let mut scale0: f64 = 0.0;
        for i in 0..m {
            if d(i, i) > 0.0 {
                scale0 = scale0.max(b.b[i].abs() / d(i, i));
            }
        }
        // velocity scale: the largest free or initial rate of a row
        let v_scale = (0..m).fold(0.0_f64, |a, i| a.max(b.b[i].abs()).max(b.gamma_s[i].abs()));
        let tol = self.settings.tolerance;
        let mut change = 0.0;
        for sweep in 1..=self.settings.max_iterations {
            b.lambda_prev[..m].copy_from_slice(&b.lambda[..m]);
            change = 0.0_f64;
            for blk in &b.blocks {
                change = change.max(sweep_block(
                    blk,
                    omega,
                    m,
                    &b.delassus,
                    &b.b,
                    &b.gamma_s,
                    &mut b.lambda,
                ));
            }
            let lam_max = b.lambda[..m].iter().fold(0.0_f64, |a, x| a.max(x.abs()));
            let scale = lam_max.max(scale0);
            if change <= tol * scale {
                let rel = if scale > 0.0 { change / scale } else { 0.0 };
                return Ok((sweep, rel));
            }
            // change of the rates D (Lambda - Lambda_prev)
            let mut rate_change: f64 = 0.0;
            for i in 0..m {
                let row = &b.delassus[i * m..(i + 1) * m];
                let dr: f64 = (0..m)
                    .map(|j| row[j] * (b.lambda[j] - b.lambda_prev[j]))
                    .sum();
                rate_change = rate_change.max(dr.abs());
            }
            if rate_change <= tol * v_scale {
                return Ok((sweep, change / scale));
            }
        }
        let lam_max = b.lambda[..m].iter().fold(0.0_f64, |a, x| a.max(x.abs()));
        Err((self.settings.max_iterations, change / lam_max.max(scale0)))
    }

    /// A problem of joint rows only (no closed set-valued contact) is linear: `D Lambda = -b`,
    /// solved by a Cholesky factorization of `D` into the joint projection's buffer (which
    /// [`Self::project`] then reuses). Returns the largest residual `|D Lambda + b|` relative to
    /// the rows' velocity scale, or `None` (Gauss-Seidel then) when there are contact rows or
    /// `D` is not numerically positive definite (redundant joints).
    fn solve_joint_rows_directly(&mut self, m: usize) -> Option<f64> {
        let b = &mut self.buf;
        if m != b.projection.nrows() || b.blocks.iter().any(|k| !matches!(k, Block::Joint { .. })) {
            return None;
        }
        for j in 0..m {
            b.projection
                .col_as_slice_mut(j)
                .copy_from_slice(&b.delassus[j * m..(j + 1) * m]);
        }
        if !cholesky_in_place(&mut b.projection) {
            return None;
        }
        b.joints_factored = true;
        for (l, r) in b.lambda[..m].iter_mut().zip(&b.b[..m]) {
            *l = -r;
        }
        cholesky_solve_in_place(&b.projection, &mut b.lambda[..m]);
        let v_scale = (0..m).fold(0.0_f64, |a, i| a.max(b.b[i].abs()).max(b.gamma_s[i].abs()));
        let mut residual: f64 = 0.0;
        for i in 0..m {
            let row = &b.delassus[i * m..(i + 1) * m];
            residual = residual.max((b.b[i] + dot(row, &b.lambda[..m])).abs());
        }
        Some(if v_scale > 0.0 {
            residual / v_scale
        } else {
            residual
        })
    }

    /// `u_E = u_F + M^-1 W Lambda`, `q_E = q_M ⊕ h/2 u_E`, the contact states, the joint
    /// projection, and the state advanced to `t + h`.
    pub(super) fn finish(
        &mut self,
        model: &Model,
        s: &mut State,
        ws: &mut Workspace,
        h: f64,
        m: usize,
    ) -> Result<(), SolverError> {
        let (nu, b) = (model.nu, &mut self.buf);
        let u_e = &mut ws.step.u_new;
        u_e.copy_from_slice(&b.u_free);
        for k in 0..m {
            let l = b.lambda[k];
            if l != 0.0 {
                for (x, y) in u_e.iter_mut().zip(&b.minv_w[k * nu..(k + 1) * nu]) {
                    *x += l * y;
                }
            }
        }
        for (d, u) in ws.step.dv.iter_mut().zip(u_e.iter()) {
            *d = 0.5 * h * u;
        }
        system::integrate_positions(model, &b.q_m, &ws.step.dv, &mut ws.step.q_new);
        self.update_contact_states(model, s, ws, h);
        if model.nc > 0 && self.settings.projection_iterations > 0 {
            self.project(model, s, ws, h)?;
        }
        for r in 0..model.nc {
            s.lambda[r] = self.buf.lambda[r] / h;
        }
        for (((ud, a), u), ue) in s
            .u_dot
            .iter_mut()
            .zip(s.a.iter_mut())
            .zip(s.u.iter_mut())
            .zip(&ws.step.u_new)
        {
            *ud = (ue - *u) / h;
            *a = *ud;
            *u = *ue;
        }
        s.q.copy_from_slice(&ws.step.q_new);
        s.t += h;
        Ok(())
    }

    /// Activity, gap (at `q_M`), gap rate at `u_E`, impulses, forces (impulses over `h`) and
    /// geometry of every contact.
    fn update_contact_states(&mut self, model: &Model, s: &mut State, ws: &mut Workspace, h: f64) {
        let b = &mut self.buf;
        for (i, (c, st)) in model.contacts.iter().zip(&mut s.contacts).enumerate() {
            let geo = &b.geometry[i];
            let mut rate = 0.0;
            let mut penalty_step = if b.normal_force[i] > 0.0 {
                st.penalty_step
            } else {
                0.0
            };
            if geo.has_contact_point() {
                let col = &mut ws.step.dv;
                col.fill(0.0);
                c.add_direction(
                    model,
                    &ws.sys.frames,
                    &ws.contact.sides[i],
                    geo,
                    0,
                    1.0,
                    col,
                );
                rate = dot(col, &ws.step.u_new);
                if let NormalLaw::Regularized { stiffness, .. } = c.law.normal {
                    if b.normal_force[i] > 0.0 && st.force[0] == 0.0 {
                        // the step that closed the contact: `h sqrt(k wᵀ M⁻¹ w)` (the mass
                        // blocks are factored at the step's midpoint)
                        b.rhs.copy_from_slice(col);
                        ws.mass_blocks.solve_in_place(&mut b.rhs, 1);
                        penalty_step = h * (stiffness * dot(col, &b.rhs)).max(0.0).sqrt();
                    }
                }
            }
            let [f1, f2] = b.friction_force[i];
            let f = [b.normal_force[i], f1, f2];
            *st = ContactState {
                active: false,
                gap: geo.gap,
                gap_velocity: rate,
                impulse: [f[0] * h, f[1] * h, f[2] * h],
                coordinates: geo.coordinates,
                force: f,
                penalty_step,
                geometry: Some(*geo),
            };
        }
        for blk in &b.blocks {
            if let Block::Contact {
                contact,
                row,
                normal,
                tangents,
                ..
            } = *blk
            {
                let st = &mut s.contacts[contact];
                st.active = true;
                let mut r = row;
                if normal.is_some() {
                    st.impulse[0] = b.lambda[r];
                    st.force[0] = b.lambda[r] / h;
                    r += 1;
                }
                for k in 0..tangents {
                    st.impulse[1 + k] = b.lambda[r + k];
                    st.force[1 + k] = b.lambda[r + k] / h;
                }
            }
        }
    }

    /// Newton iterations `dq = M^-1 G^T mu`, `(G M^-1 G^T) mu = -g(q_E)` with `G`, `M` of the
    /// midpoint (the joint block of the Delassus matrix), on `ws.step.q_new`; the iterates need
    /// only `g` ([`system::update_constraint_values`]: guides skip their `G`).
    fn project(
        &mut self,
        model: &Model,
        s: &State,
        ws: &mut Workspace,
        h: f64,
    ) -> Result<(), SolverError> {
        let (nc, nu, mm) = (model.nc, model.nu, self.m_last);
        let b = &mut self.buf;
        let t_e = s.t + h;
        // factored by the direct solve of a joint-only prox problem (the same matrix)
        let mut factored = b.joints_factored;
        for _ in 0..self.settings.projection_iterations {
            let sys = &mut ws.sys;
            let (q, u) = (&ws.step.q_new, &ws.step.u_new);
            system::evaluate_kinematics(model, q, u, &mut sys.eval).map_err(|e| e.at(s.t, h))?;
            system::update_frames(model, q, u, &mut sys.eval, &mut sys.frames);
            system::update_constraint_values(model, t_e, sys);
            if sys
                .g
                .iter()
                .all(|g| g.abs() <= self.settings.projection_tol)
            {
                break;
            }
            if !factored {
                for j in 0..nc {
                    for i in 0..nc {
                        b.projection[(i, j)] = b.delassus[j * mm + i];
                    }
                }
                if !cholesky_in_place(&mut b.projection) {
                    return Err(SolverError::Singular {
                        what: "joint projection (G M^-1 G^T)",
                        t: s.t,
                        h,
                    });
                }
                factored = true;
            }
            for (r, g) in b.projection_rhs.iter_mut().zip(&sys.g) {
                *r = -g;
            }
            cholesky_solve_in_place(&b.projection, &mut b.projection_rhs);
            let dv = &mut ws.step.dv;
            dv.fill(0.0);
            for k in 0..nc {
                let mu = b.projection_rhs[k];
                for (x, y) in dv.iter_mut().zip(&b.minv_w[k * nu..(k + 1) * nu]) {
                    *x += mu * y;
                }
            }
            system::integrate_positions(model, &ws.step.q_new, dv, &mut b.q_m);
            ws.step.q_new.copy_from_slice(&b.q_m);
        }
        Ok(())
    }
}

/// One Gauss-Seidel update of a block; returns the largest impulse change.
fn sweep_block(
    blk: &Block,
    omega: f64,
    m: usize,
    delassus: &[f64],
    b: &[f64],
    gamma_s: &[f64],
    lambda: &mut [f64],
) -> f64 {
    let rate = |lambda: &[f64], i: usize| b[i] + dot(&delassus[i * m..(i + 1) * m], &lambda[..m]);
    let diag = |i: usize| delassus[i * m + i];
    let mut change: f64 = 0.0;
    let mut set = |lambda: &mut [f64], i: usize, v: f64| {
        change = change.max((v - lambda[i]).abs());
        lambda[i] = v;
    };
    match *blk {
        Block::Joint { row } => {
            if diag(row) > 0.0 {
                let v = lambda[row] - omega / diag(row) * rate(lambda, row);
                set(lambda, row, v);
            }
        }
        Block::Contact {
            row,
            normal,
            tangents,
            mu,
            fixed_bound,
            ..
        } => {
            let mut r = row;
            if let Some(n) = normal {
                if diag(r) > 0.0 {
                    let xi = rate(lambda, r) + n.restitution * gamma_s[r];
                    let x = lambda[r] - omega / diag(r) * xi;
                    let v = if n.bilateral { x } else { prox_nonnegative(x) };
                    set(lambda, r, v);
                }
                r += 1;
            }
            if tangents > 0 {
                let bound = fixed_bound.unwrap_or_else(|| mu * lambda[row].abs());
                let dmax = (r..r + tangents).map(diag).fold(0.0, f64::max);
                if dmax > 0.0 {
                    let mut x = [0.0; 2];
                    for (k, xk) in x.iter_mut().enumerate().take(tangents) {
                        *xk = lambda[r + k] - omega / dmax * rate(lambda, r + k);
                    }
                    prox_disc(&mut x[..tangents], bound);
                    for (k, xk) in x.iter().enumerate().take(tangents) {
                        set(lambda, r + k, *xk);
                    }
                }
            }
        }
    }
    change
}

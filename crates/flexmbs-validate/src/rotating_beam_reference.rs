//! Geometrically nonlinear reference for `rotating_beam`, independent of the FFR code: a planar
//! finite-segment (Hencky bar-chain) model of the inextensible Euler-Bernoulli beam in the plane
//! of rotation, in minimal coordinates, integrated with a classical fixed-step Runge-Kutta 4.
//!
//! Model: `n` rigid uniform segments of length `l = L/n`, mass `m = rho A l` and centroidal
//! inertia `m l²/12`, joined by rotational springs `EI/l`; the first segment is clamped to the
//! hub (at the rotation axis, hub radius 0) by a spring `2 EI/l` (half-cell: the slope is carried
//! at the segment centres, second order in `l`). The hub angle `phi = Omega t` is prescribed.
//! Coordinates: `theta_i`, the angle of segment `i` in the hub frame; absolute angles
//! `psi_i = phi + theta_i`. Lagrange's equations (exact, no small-deflection assumption):
//!
//! `Σ_j A_ij [cos(psi_i - psi_j) theta_dd_j + sin(psi_i - psi_j) psi_d_j²] + dV/dtheta_i = Q_i`,
//!
//! `A_ij = m l² (n - max(i, j) + 1/2)` (`i != j`, 1-based), `A_ii = m l² (n - i + 1/3)`,
//! `V = ½ (2EI/l) theta_1² + ½ (EI/l) Σ (theta_{i+1} - theta_i)²`, and the tip force `F` along
//! the hub's y axis gives `Q_i = F l cos(theta_i)`. The tip deflection in the rotating frame is
//! `w = Σ l sin(theta_i)`. Centrifugal stiffening, spin softening and all geometric
//! nonlinearities are contained in the exact kinematics; the straight beam is the steady state.

use nalgebra::{DMatrix, DVector};

/// Data of the planar chain.
#[derive(Debug, Clone, Copy)]
pub struct ChainModel {
    /// Number of segments.
    pub n: usize,
    /// Beam length L (m).
    pub length: f64,
    /// Mass per length rho A (kg/m).
    pub rho_a: f64,
    /// Bending stiffness EI in the plane of rotation (N m²).
    pub ei: f64,
    /// Hub angular velocity Omega (rad/s).
    pub omega: f64,
    /// Tip force along the hub y axis (N) during `[0, pulse_end)`.
    pub force: f64,
    /// End of the force pulse (s).
    pub pulse_end: f64,
}

/// Result of a reference run: sampled time and tip deflection, and the step used.
#[derive(Debug, Clone)]
pub struct ChainRun {
    /// Times (s).
    pub t: Vec<f64>,
    /// Tip deflection in the rotating frame (m).
    pub w: Vec<f64>,
    /// Runge-Kutta step (s).
    pub h: f64,
}

impl ChainModel {
    fn seg(&self) -> (f64, f64) {
        let l = self.length / self.n as f64;
        (l, self.rho_a * l)
    }

    /// `theta_dd` from `(t, theta, theta_d)`: assembles `M(theta)` and the right-hand side and
    /// solves by Cholesky (M is SPD). Buffers are reused.
    fn accelerations(&self, t: f64, th: &[f64], thd: &[f64], ws: &mut Work) -> Option<()> {
        let n = self.n;
        let (l, m) = self.seg();
        let k = self.ei / l;
        let f = if t < self.pulse_end { self.force } else { 0.0 };
        for (i, a) in th.iter().enumerate().take(n) {
            ws.c[i] = a.cos();
            ws.s[i] = a.sin();
        }
        for i in 0..n {
            // psi_i - psi_j = theta_i - theta_j (the hub angle cancels)
            let mut rhs = f * l * ws.c[i];
            for (j, &thd_j) in thd.iter().enumerate().take(n) {
                let a = m
                    * l
                    * l
                    * if i == j {
                        (n - i) as f64 - 1.0 + 1.0 / 3.0
                    } else {
                        (n - i.max(j)) as f64 - 1.0 + 0.5
                    };
                let cij = ws.c[i] * ws.c[j] + ws.s[i] * ws.s[j];
                let sij = ws.s[i] * ws.c[j] - ws.c[i] * ws.s[j];
                ws.m[(i, j)] = a * cij;
                let pd = self.omega + thd_j;
                rhs -= a * sij * pd * pd;
            }
            // dV/dtheta_i
            let mut dv = 0.0;
            if i == 0 {
                dv += 2.0 * k * th[0];
            } else {
                dv += k * (th[i] - th[i - 1]);
            }
            if i + 1 < n {
                dv -= k * (th[i + 1] - th[i]);
            }
            ws.rhs[i] = rhs - dv;
        }
        let chol = ws.m.clone().cholesky()?;
        ws.acc.copy_from(&chol.solve(&ws.rhs));
        Some(())
    }

    /// Highest natural frequency of the chain linearized about the steady state (rad/s), for the
    /// explicit step size: `K_lin = K_spring + Omega² K_centrifugal`, where the centrifugal part is
    /// the Hessian of `-½ Omega² Σ m |r|²`-type terms at theta = 0, computed here by central
    /// differences of the accelerations' right-hand side.
    fn highest_frequency(&self) -> Option<f64> {
        let n = self.n;
        let mut ws = Work::new(n);
        let z = vec![0.0; n];
        self.accelerations(1e9, &z, &z, &mut ws)?;
        let m0 = ws.m.clone();
        let mut k = DMatrix::zeros(n, n);
        let eps = 1e-7;
        for j in 0..n {
            let mut th = z.clone();
            th[j] = eps;
            self.accelerations(1e9, &th, &z, &mut ws)?;
            let rp = ws.rhs.clone();
            th[j] = -eps;
            self.accelerations(1e9, &th, &z, &mut ws)?;
            for i in 0..n {
                k[(i, j)] = -(rp[i] - ws.rhs[i]) / (2.0 * eps);
            }
        }
        let k = 0.5 * (&k + k.transpose());
        let l = m0.cholesky()?.l();
        let li = l.try_inverse()?;
        let c = &li * k * li.transpose();
        let ev = c.symmetric_eigenvalues();
        Some(ev.iter().fold(0.0f64, |a, &b| a.max(b)).sqrt())
    }

    /// Integrates from the steady state to `t_end` with RK4; the step is the largest `h <= h_max`
    /// with `h omega_max <= 1.5` (RK4 is stable to 2.8) that divides the pulse length. Samples
    /// every `sample` steps. `None` if the mass matrix is not positive definite.
    pub fn simulate(&self, t_end: f64, h_max: f64, sample_dt: f64) -> Option<ChainRun> {
        let n = self.n;
        let wmax = self.highest_frequency()?;
        let h_stab = (1.5 / wmax).min(h_max);
        let per_pulse = (self.pulse_end / h_stab).ceil();
        let h = self.pulse_end / per_pulse;
        let steps = (t_end / h).round() as usize;
        let sample = ((sample_dt / h).round() as usize).max(1);
        let (l, _) = self.seg();
        let mut ws = Work::new(n);
        let mut y = vec![0.0; 2 * n];
        let mut ks = [
            vec![0.0; 2 * n],
            vec![0.0; 2 * n],
            vec![0.0; 2 * n],
            vec![0.0; 2 * n],
        ];
        let mut tmp = vec![0.0; 2 * n];
        let mut run = ChainRun {
            t: vec![0.0],
            w: vec![0.0],
            h,
        };
        let eval = |t: f64, y: &[f64], out: &mut [f64], ws: &mut Work| -> Option<()> {
            self.accelerations(t, &y[..n], &y[n..], ws)?;
            out[..n].copy_from_slice(&y[n..]);
            out[n..].copy_from_slice(ws.acc.as_slice());
            Some(())
        };
        for step in 0..steps {
            let t = step as f64 * h;
            // stage times inside [t, t + h]; the pulse edge falls on a step boundary, so the
            // force is evaluated consistently within each step (left limit at t + h)
            let tm = t + 0.5 * h;
            let te = t + h * (1.0 - 1e-9);
            eval(t, &y, &mut ks[0], &mut ws)?;
            for stage in 1..4 {
                let (c, ts) = match stage {
                    3 => (h, te),
                    _ => (0.5 * h, tm),
                };
                for i in 0..2 * n {
                    tmp[i] = y[i] + c * ks[stage - 1][i];
                }
                let (done, rest) = ks.split_at_mut(stage);
                let _ = done;
                eval(ts, &tmp, &mut rest[0], &mut ws)?;
            }
            for i in 0..2 * n {
                y[i] += h / 6.0 * (ks[0][i] + 2.0 * ks[1][i] + 2.0 * ks[2][i] + ks[3][i]);
            }
            if (step + 1) % sample == 0 {
                run.t.push((step + 1) as f64 * h);
                run.w.push(y[..n].iter().map(|a| l * a.sin()).sum());
            }
        }
        Some(run)
    }
}

struct Work {
    m: DMatrix<f64>,
    rhs: DVector<f64>,
    acc: DVector<f64>,
    c: Vec<f64>,
    s: Vec<f64>,
}

impl Work {
    fn new(n: usize) -> Self {
        Self {
            m: DMatrix::zeros(n, n),
            rhs: DVector::zeros(n),
            acc: DVector::zeros(n),
            c: vec![0.0; n],
            s: vec![0.0; n],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Without rotation and force the linearized chain is a cantilever: its lowest frequency
    /// converges to 3.5160 sqrt(EI / (rho A L^4)); with rotation the lead-lag frequency is the
    /// exact flap frequency with `-Omega²` (spin softening), near Southwell's `k_1 - 1 = 0.193`.
    #[test]
    fn chain_frequencies_match_cantilever_and_lead_lag_southwell() {
        let base = ChainModel {
            n: 40,
            length: 1.0,
            rho_a: 1.0,
            ei: 1.0,
            omega: 0.0,
            force: 0.0,
            pulse_end: 0.01,
        };
        let lowest = |c: &ChainModel| {
            let mut ws = Work::new(c.n);
            let z = vec![0.0; c.n];
            c.accelerations(1.0, &z, &z, &mut ws).unwrap();
            let m0 = ws.m.clone();
            let mut k = DMatrix::zeros(c.n, c.n);
            for j in 0..c.n {
                let mut th = z.clone();
                th[j] = 1e-7;
                c.accelerations(1.0, &th, &z, &mut ws).unwrap();
                let rp = ws.rhs.clone();
                th[j] = -1e-7;
                c.accelerations(1.0, &th, &z, &mut ws).unwrap();
                for i in 0..c.n {
                    k[(i, j)] = -(rp[i] - ws.rhs[i]) / 2e-7;
                }
            }
            let k = 0.5 * (&k + k.transpose());
            let li = m0.cholesky().unwrap().l().try_inverse().unwrap();
            let ev = (&li * k * li.transpose()).symmetric_eigenvalues();
            ev.iter().fold(f64::INFINITY, |a, &b| a.min(b)).sqrt()
        };
        let w0 = lowest(&base);
        assert!((w0 / 3.5160 - 1.0).abs() < 1e-3, "{w0}");
        let spun = ChainModel { omega: 2.0, ..base };
        let w = lowest(&spun);
        // in-plane = flap frequency squared minus Omega² (same linear mode equation), flap at
        // lambda = 2: 4.1373 (Wright et al. 1982)
        let exact = (4.1373f64.powi(2) - 4.0).sqrt();
        assert!((w / exact - 1.0).abs() < 1e-3, "{w} vs {exact}");
        let k1m1 = (w * w - w0 * w0) / 4.0;
        assert!((k1m1 / 0.193 - 1.0).abs() < 0.03, "{k1m1}");
    }
}

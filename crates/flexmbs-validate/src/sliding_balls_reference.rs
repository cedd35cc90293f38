//! Geometrically nonlinear reference for `sliding_balls` (seed 000 §5.3), sharing no code with
//! the FFR body, the contour/guide code or the superelement: a planar **corotational
//! Euler-Bernoulli beam** (internal forces of
//! [`crate::slider_crank_reference::CorotationalBeam`], Crisfield 1991 ch. 7) clamped at x = 0,
//! with a configuration-dependent consistent mass, carrying a rigid ball whose centre slides
//! without friction along the deformed axis, in reduced coordinates, integrated by the implicit
//! midpoint rule.
//!
//! **Planar motion.** Gravity is 0 and the ball starts with (0.01, -0.002, 0) m/s on the axis of
//! a beam with a doubly symmetric cross-section: nothing drives motion out of the x-y plane (the
//! FFR runs check it: `z_dev`). The beam bends about z; the ball turns about z only.
//!
//! **Kinematics.** Node `i` carries `(x_i, y_i, theta_i)`; node 0 is clamped. On element `e`
//! (nodes `a`, `b`, chord `d = x_b - x_a`, angle `beta = atan2(d_y, d_x)`, local rotations
//! `theta_a' = theta_a - beta`, `theta_b' = theta_b - beta`) the deformed axis at the element
//! coordinate `xi` in [0, 1] is the corotated Hermite cubic
//! `r(xi) = x_a + xi d + (N2(xi) theta_a' + N4(xi) theta_b') perp(d)` with
//! `N2 = xi (1 - xi)^2`, `N4 = xi^2 (xi - 1)`, `perp(d) = (-d_y, d_x)`, and the cross-section
//! angle is `phi(xi) = beta + N2'(xi) theta_a' + N4'(xi) theta_b'` (C^1 across nodes: `phi` is
//! the nodal `theta` there). The ball's coordinate is the material coordinate `s` in [0, L]
//! (`e = floor(s / l0)`, `xi = s / l0 - e`): its centre is `r(s)`, its rotation `phi(s)`
//! (frictionless sliding: `s` is a free coordinate, the bilateral guide holds by construction).
//!
//! **Inertia.** The beam's kinetic energy `½ ∫ (rho A |r_dot|² + rho I phi_dot²) dX` (4-point
//! Gauss per element) and the ball's `½ m |r_dot(s)|² + ½ J phi_dot(s)²` with
//! `r_dot = J_r x_dot`, `phi_dot = J_phi x_dot` (`x = (q, s)`) give, by Lagrange's equations,
//! `M(x) x_dd = -f(q) - c(x, x_dot)` with `M = Σ w (rho A J_r^T J_r + rho I J_phi^T J_phi)` and
//! the convective term `c = Σ w (rho A J_r^T gamma_r + rho I J_phi^T gamma_phi)`,
//! `gamma = J_dot x_dot` (the second directional derivative of `r`, `phi` along `x_dot`, computed
//! exactly with second-order forward-mode numbers [`Jet`]). At the straight configuration `M`
//! is the classical consistent Hermite mass plus rotary inertia.
//!
//! **Initial condition.** The ball's transverse velocity is inconsistent with the beam at rest:
//! a perfectly plastic impact (the bilateral law at velocity level) gives the generalized
//! velocity `M(x0) x_dot0 = J^T (m v_ball)` (the momentum of the ball projected on the
//! constrained motions), the same law the FFR run's first Moreau step applies.
//!
//! **Integrator.** Implicit midpoint: `x1 = x0 + h v_m`, `M(x_m) (v1 - v0) = -h (f(x_m) +
//! c(x_m, v_m))` with `x_m`, `v_m` the midpoint values; modified Newton with the iteration
//! matrix `M + h²/4 K` (K by central differences of `f`), refreshed when the ball enters another
//! element. Second order, no numerical damping, energy conserved for linear systems.

use crate::slider_crank_reference::CorotationalBeam;
use nalgebra::{DMatrix, DVector};
use std::ops::{Add, Mul, Neg, Sub};

/// A second-order forward-mode number: the value of `f(eps)` and its first and second
/// derivatives at `eps = 0` along one direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jet {
    /// f(0).
    pub v: f64,
    /// f'(0).
    pub d: f64,
    /// f''(0).
    pub dd: f64,
}

impl Jet {
    /// A constant.
    pub fn constant(v: f64) -> Self {
        Self { v, d: 0.0, dd: 0.0 }
    }

    /// A variable `v + eps d` (straight line: no second derivative).
    pub fn variable(v: f64, d: f64) -> Self {
        Self { v, d, dd: 0.0 }
    }

    /// `atan2(y, x)` with its derivatives: `f' = N / D`, `N = x y' - y x'`, `D = x² + y²`,
    /// `f'' = (N' D - N D') / D²`, `N' = x y'' - y x''`, `D' = 2 (x x' + y y')`.
    pub fn atan2(y: Jet, x: Jet) -> Self {
        let n = x.v * y.d - y.v * x.d;
        let dn = x.v * y.dd - y.v * x.dd;
        let den = x.v * x.v + y.v * y.v;
        let dden = 2.0 * (x.v * x.d + y.v * y.d);
        Self {
            v: y.v.atan2(x.v),
            d: n / den,
            dd: (dn * den - n * dden) / (den * den),
        }
    }
}

impl Add for Jet {
    type Output = Jet;
    fn add(self, o: Jet) -> Jet {
        Jet {
            v: self.v + o.v,
            d: self.d + o.d,
            dd: self.dd + o.dd,
        }
    }
}

impl Sub for Jet {
    type Output = Jet;
    fn sub(self, o: Jet) -> Jet {
        Jet {
            v: self.v - o.v,
            d: self.d - o.d,
            dd: self.dd - o.dd,
        }
    }
}

impl Neg for Jet {
    type Output = Jet;
    fn neg(self) -> Jet {
        Jet {
            v: -self.v,
            d: -self.d,
            dd: -self.dd,
        }
    }
}

impl Mul for Jet {
    type Output = Jet;
    fn mul(self, o: Jet) -> Jet {
        Jet {
            v: self.v * o.v,
            d: self.d * o.v + self.v * o.d,
            dd: self.dd * o.v + 2.0 * self.d * o.d + self.v * o.dd,
        }
    }
}

impl Mul<f64> for Jet {
    type Output = Jet;
    fn mul(self, o: f64) -> Jet {
        Jet {
            v: self.v * o,
            d: self.d * o,
            dd: self.dd * o,
        }
    }
}

/// Axis point and cross-section angle `(r_x, r_y, phi)` of a corotated Hermite element (module
/// documentation) at element coordinate `xi`; `e = (x_a, y_a, theta_a, x_b, y_b, theta_b)`.
pub fn axis_point(e: [Jet; 6], xi: Jet) -> [Jet; 3] {
    let one = Jet::constant(1.0);
    let (dx, dy) = (e[3] - e[0], e[4] - e[1]);
    let beta = Jet::atan2(dy, dx);
    let (ta, tb) = (e[2] - beta, e[5] - beta);
    let xm = one - xi;
    let n2 = xi * xm * xm;
    let n4 = xi * xi * (xi - one);
    let n2p = xm * (one - xi * 3.0);
    let n4p = xi * (xi * 3.0 - Jet::constant(2.0));
    let w = n2 * ta + n4 * tb;
    [
        e[0] + xi * dx - w * dy,
        e[1] + xi * dy + w * dx,
        beta + n2p * ta + n4p * tb,
    ]
}

/// Kinematics of one axis point: Jacobian rows of `(r_x, r_y, phi)` with respect to the 7
/// local coordinates (element's 6, then `s`) and the convective terms `gamma = J_dot x_dot`.
#[derive(Debug, Clone, Copy)]
struct PointKinematics {
    /// `jac[k][c]`: derivative of component `k` by local coordinate `c`.
    jac: [[f64; 7]; 3],
    /// Velocity `J x_dot`.
    vel: [f64; 3],
    /// `gamma = J_dot x_dot`.
    gamma: [f64; 3],
}

/// Evaluates the kinematics of the point at `xi` of an element with coordinates `q` and
/// velocities `v`; `xi_rate = s_dot / l0` (0 for a material point).
#[allow(clippy::needless_range_loop)]
fn point_kinematics(q: [f64; 6], v: [f64; 6], xi: f64, xi_rate: f64) -> PointKinematics {
    let eval = |dq: [f64; 6], dxi: f64| {
        let e: [Jet; 6] = std::array::from_fn(|k| Jet::variable(q[k], dq[k]));
        axis_point(e, Jet::variable(xi, dxi))
    };
    let along = eval(v, xi_rate);
    let mut jac = [[0.0; 7]; 3];
    for c in 0..7 {
        let dq: [f64; 6] = std::array::from_fn(|k| if k == c { 1.0 } else { 0.0 });
        let p = eval(dq, if c == 6 { 1.0 } else { 0.0 });
        for k in 0..3 {
            jac[k][c] = p[k].d;
        }
    }
    PointKinematics {
        jac,
        vel: along.map(|j| j.d),
        gamma: along.map(|j| j.dd),
    }
}

/// 4-point Gauss-Legendre rule on [0, 1]: (point, weight).
const GAUSS4: [(f64, f64); 4] = [
    (0.069_431_844_202_973_71, 0.173_927_422_568_726_93),
    (0.330_009_478_207_571_9, 0.326_072_577_431_273_07),
    (0.669_990_521_792_428_1, 0.326_072_577_431_273_07),
    (0.930_568_155_797_026_3, 0.173_927_422_568_726_93),
];

/// The clamped beam carrying the sliding ball.
#[derive(Debug, Clone, Copy)]
pub struct BallOnBeam {
    /// The beam (stiffness from [`CorotationalBeam::internal_forces`]).
    pub beam: CorotationalBeam,
    /// Ball mass (kg).
    pub mass: f64,
    /// Ball rotary inertia about z (kg m²).
    pub inertia: f64,
}

/// Errors of the reference run.
#[derive(Debug, Clone, PartialEq)]
pub enum ReferenceError {
    /// The ball left the beam (`s` outside [0, L]).
    BallOffBeam {
        /// Time (s).
        t: f64,
        /// Its coordinate (m).
        s: f64,
    },
    /// Newton did not converge in a step.
    NoConvergence {
        /// Time (s).
        t: f64,
        /// Last correction norm.
        correction: f64,
    },
    /// The iteration matrix is singular.
    Singular,
}

impl std::fmt::Display for ReferenceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::BallOffBeam { t, s } => write!(f, "ball left the beam at t = {t} s (s = {s} m)"),
            Self::NoConvergence { t, correction } => {
                write!(f, "no convergence at t = {t} s (correction {correction:e})")
            }
            Self::Singular => write!(f, "singular iteration matrix"),
        }
    }
}

impl std::error::Error for ReferenceError {}

impl BallOnBeam {
    /// The `sliding_balls` beam (1.5 x 0.05 x 0.05 m, E = 50 MPa, 920 kg/m³) in `n` elements
    /// with Young's modulus scaled by `stiffness_factor` (1 for the case), and the 1 kg ball
    /// with inertia 1e-3 kg m².
    pub fn sliding_balls(n: usize, stiffness_factor: f64) -> Self {
        let (b, e, rho): (f64, f64, f64) = (0.05, 50e6 * stiffness_factor, 920.0);
        let (a, i) = (b * b, b.powi(4) / 12.0);
        Self {
            beam: CorotationalBeam {
                n,
                length: 1.5,
                ea: e * a,
                ei: e * i,
                rho_a: rho * a,
                rho_i: rho * i,
            },
            mass: 1.0,
            inertia: 1e-3,
        }
    }

    /// Number of unknowns: `3 n` free beam coordinates and `s`.
    pub fn dim(&self) -> usize {
        3 * self.beam.n + 1
    }

    /// The straight beam with the ball at `s0`: the full coordinate vector `3 (n + 1)` followed
    /// by `s` (the first three, node 0, stay clamped).
    pub fn straight(&self, s0: f64) -> Vec<f64> {
        let l0 = self.beam.element_length();
        let mut x = vec![0.0; 3 * (self.beam.n + 1) + 1];
        for i in 0..=self.beam.n {
            x[3 * i] = i as f64 * l0;
        }
        x[3 * (self.beam.n + 1)] = s0;
        x
    }

    /// Element and element coordinate of the material coordinate `s`.
    fn locate(&self, s: f64) -> (usize, f64) {
        let l0 = self.beam.element_length();
        let e = ((s / l0).floor().max(0.0) as usize).min(self.beam.n - 1);
        (e, s / l0 - e as f64)
    }

    /// The ball's centre and angle `(r_x, r_y, phi)`.
    pub fn ball_point(&self, x: &[f64]) -> [f64; 3] {
        let (e, xi) = self.locate(x[3 * (self.beam.n + 1)]);
        let q: [f64; 6] = std::array::from_fn(|k| x[3 * e + k]);
        axis_point(q.map(Jet::constant), Jet::constant(xi)).map(|j| j.v)
    }

    /// Visits every inertia point: `visit(first full coordinate, kinematics, weights
    /// [rho A w l0 (translation), rho I w l0 (rotation)], carries_s)`.
    fn for_each_inertia_point(
        &self,
        x: &[f64],
        v: &[f64],
        mut visit: impl FnMut(usize, &PointKinematics, [f64; 2], bool),
    ) {
        let n = self.beam.n;
        let l0 = self.beam.element_length();
        for e in 0..n {
            let q: [f64; 6] = std::array::from_fn(|k| x[3 * e + k]);
            let qd: [f64; 6] = std::array::from_fn(|k| v[3 * e + k]);
            for (xi, w) in GAUSS4 {
                let pk = point_kinematics(q, qd, xi, 0.0);
                let wt = [self.beam.rho_a * w * l0, self.beam.rho_i * w * l0];
                visit(3 * e, &pk, wt, false);
            }
        }
        let is = 3 * (n + 1);
        let (e, xi) = self.locate(x[is]);
        let q: [f64; 6] = std::array::from_fn(|k| x[3 * e + k]);
        let qd: [f64; 6] = std::array::from_fn(|k| v[3 * e + k]);
        let pk = point_kinematics(q, qd, xi, v[is] / l0);
        // the 7th column is d/dxi; s = l0 (e + xi)
        let mut pk = pk;
        for row in &mut pk.jac {
            row[6] /= l0;
        }
        visit(3 * e, &pk, [self.mass, self.inertia], true);
    }

    /// Full coordinate index of local column `c` of a point whose element starts at `first`.
    fn full_index(&self, first: usize, c: usize) -> usize {
        if c == 6 {
            3 * (self.beam.n + 1)
        } else {
            first + c
        }
    }

    /// Kinetic energy `½ x_dot^T M(x) x_dot`.
    pub fn kinetic_energy(&self, x: &[f64], v: &[f64]) -> f64 {
        let mut t = 0.0;
        self.for_each_inertia_point(x, v, |_, pk, w, _| {
            t += 0.5 * (w[0] * (pk.vel[0].powi(2) + pk.vel[1].powi(2)) + w[1] * pk.vel[2].powi(2));
        });
        t
    }

    /// Strain energy of the corotational elements (their internal force is its gradient).
    pub fn strain_energy(&self, x: &[f64]) -> f64 {
        let l0 = self.beam.element_length();
        (0..self.beam.n)
            .map(|e| {
                let (a, b) = (3 * e, 3 * e + 3);
                let (dx, dy) = (x[b] - x[a], x[b + 1] - x[a + 1]);
                let beta = dy.atan2(dx);
                let wrap = |t: f64| t.sin().atan2(t.cos());
                let (ta, tb) = (wrap(x[a + 2] - beta), wrap(x[b + 2] - beta));
                let u = dx.hypot(dy) - l0;
                0.5 * self.beam.ea * u * u / l0
                    + 0.5 * self.beam.ei / l0 * (4.0 * ta * ta + 4.0 * ta * tb + 4.0 * tb * tb)
            })
            .sum()
    }

    /// Total energy.
    pub fn energy(&self, x: &[f64], v: &[f64]) -> f64 {
        self.kinetic_energy(x, v) + self.strain_energy(x)
    }

    /// Dense mass matrix `M(x)` on the unknowns (free beam coordinates, then `s`).
    pub fn mass_matrix(&self, x: &[f64]) -> DMatrix<f64> {
        let nu = self.dim();
        let mut m = DMatrix::zeros(nu, nu);
        let zero = vec![0.0; x.len()];
        self.for_each_inertia_point(x, &zero, |first, pk, w, with_s| {
            let cols = if with_s { 7 } else { 6 };
            for a in 0..cols {
                let ia = self.full_index(first, a);
                if ia < 3 {
                    continue;
                }
                for b in 0..cols {
                    let ib = self.full_index(first, b);
                    if ib < 3 {
                        continue;
                    }
                    m[(ia - 3, ib - 3)] += w[0]
                        * (pk.jac[0][a] * pk.jac[0][b] + pk.jac[1][a] * pk.jac[1][b])
                        + w[1] * pk.jac[2][a] * pk.jac[2][b];
                }
            }
        });
        m
    }

    /// `M(x) a + c(x, v)` on the unknowns into `out` (length `dim`).
    fn inertia_force(&self, x: &[f64], v: &[f64], a: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|o| *o = 0.0);
        self.for_each_inertia_point(x, v, |first, pk, w, with_s| {
            let cols = if with_s { 7 } else { 6 };
            let idx: [usize; 7] = std::array::from_fn(|c| self.full_index(first, c));
            // acceleration of the point: J a + gamma
            let mut acc = pk.gamma;
            for (k, acc_k) in acc.iter_mut().enumerate() {
                for c in 0..cols {
                    *acc_k += pk.jac[k][c] * a[idx[c]];
                }
            }
            let f = [w[0] * acc[0], w[0] * acc[1], w[1] * acc[2]];
            for c in 0..cols {
                if idx[c] >= 3 {
                    out[idx[c] - 3] += (0..3).map(|k| pk.jac[k][c] * f[k]).sum::<f64>();
                }
            }
        });
    }

    /// Internal forces on the unknowns (`s` carries none).
    fn internal_force(&self, x: &[f64], full: &mut [f64], out: &mut [f64]) {
        let nd = 3 * (self.beam.n + 1);
        self.beam.internal_forces(&x[..nd], full);
        out[..nd - 3].copy_from_slice(&full[3..nd]);
        out[nd - 3] = 0.0;
    }

    /// Tangent stiffness `K = df/dq` on the unknowns by central differences.
    pub fn tangent_stiffness(&self, x: &[f64]) -> DMatrix<f64> {
        let nu = self.dim();
        let nd = 3 * (self.beam.n + 1);
        let mut k = DMatrix::zeros(nu, nu);
        let (mut fp, mut fm, mut full) = (vec![0.0; nu], vec![0.0; nu], vec![0.0; nd]);
        let mut xp = x.to_vec();
        let l0 = self.beam.element_length();
        for j in 3..nd {
            let eps = if j % 3 == 2 { 1e-7 } else { 1e-7 * l0 };
            xp[j] = x[j] + eps;
            self.internal_force(&xp, &mut full, &mut fp);
            xp[j] = x[j] - eps;
            self.internal_force(&xp, &mut full, &mut fm);
            xp[j] = x[j];
            for i in 0..nu {
                k[(i, j - 3)] = (fp[i] - fm[i]) / (2.0 * eps);
            }
        }
        k
    }

    /// The plastic impact taking up an inconsistent ball velocity `(vx, vy)` (beam at rest, no
    /// ball spin): the full velocity vector (zeros for the clamped node).
    pub fn impact_velocity(&self, x: &[f64], vx: f64, vy: f64) -> Result<Vec<f64>, ReferenceError> {
        let m = self.mass_matrix(x);
        let mut p = DVector::zeros(self.dim());
        let zero = vec![0.0; x.len()];
        self.for_each_inertia_point(x, &zero, |first, pk, _, with_s| {
            if with_s {
                for c in 0..7 {
                    let i = self.full_index(first, c);
                    if i >= 3 {
                        p[i - 3] += self.mass * (pk.jac[0][c] * vx + pk.jac[1][c] * vy);
                    }
                }
            }
        });
        let u = m.cholesky().ok_or(ReferenceError::Singular)?.solve(&p);
        let mut v = vec![0.0; x.len()];
        v[3..].copy_from_slice(u.as_slice());
        Ok(v)
    }
}

/// A sampled reference run.
#[derive(Debug, Clone, Default)]
pub struct ReferenceRun {
    /// (t, ball x, ball y, tip y, energy) at every `every`-th step (m, J).
    pub samples: Vec<[f64; 5]>,
    /// Energy right after the impact (J).
    pub e0: f64,
    /// Largest |E - E0| / E0.
    pub energy_deviation: f64,
    /// Largest |phi| along the beam's nodes (rad): how large the rotations get.
    pub rotation_max: f64,
    /// Largest |y| of the tip (m).
    pub tip_max: f64,
    /// Newton iterations in total.
    pub iterations: usize,
    /// Steps.
    pub steps: usize,
}

/// Implicit-midpoint integration (module documentation) of `model` from `x` with velocities
/// `v` (full vectors, node 0 clamped) over `steps` steps of `h`, sampling every `every` steps.
pub fn integrate(
    model: &BallOnBeam,
    x: &mut [f64],
    v: &mut [f64],
    h: f64,
    steps: usize,
    every: usize,
) -> Result<ReferenceRun, ReferenceError> {
    let nu = model.dim();
    let n = model.beam.n;
    let nd = 3 * (n + 1);
    let (mut xm, mut vm, mut am) = (x.to_vec(), v.to_vec(), vec![0.0; x.len()]);
    let (mut fin, mut fint, mut full) = (vec![0.0; nu], vec![0.0; nu], vec![0.0; nd]);
    let mut dv = DVector::<f64>::zeros(nu);
    let mut run = ReferenceRun {
        e0: model.energy(x, v),
        ..ReferenceRun::default()
    };
    let sample = |run: &mut ReferenceRun, t: f64, x: &[f64], v: &[f64]| {
        let b = model.ball_point(x);
        let e = model.energy(x, v);
        run.samples.push([t, b[0], b[1], x[nd - 2], e]);
    };
    sample(&mut run, 0.0, x, v);
    // iteration matrix M(x) + h²/4 K: K once (the deformation stays small), M refreshed when
    // the ball has moved by 1/200 of an element (its 1 kg dominates the local mass)
    let k_scaled = model.tangent_stiffness(x) * (h * h / 4.0);
    let mut lu = None;
    let mut s_lu = f64::NAN;
    let refresh = 0.005 * model.beam.element_length();
    let vscale = v.iter().fold(0.0f64, |a, b| a.max(b.abs())).max(1e-6);
    for step in 1..=steps {
        let t = step as f64 * h;
        if lu.is_none() || (x[nd] - s_lu).abs() > refresh {
            lu = Some((model.mass_matrix(x) + &k_scaled).lu());
            s_lu = x[nd];
        }
        let solver = lu.as_ref().ok_or(ReferenceError::Singular)?;
        let mut converged = false;
        let mut correction = f64::INFINITY;
        for _ in 0..20 {
            // midpoint state for the current velocity increment dv
            for j in 3..x.len() {
                xm[j] = x[j] + 0.5 * h * v[j] + 0.25 * h * dv[j - 3];
                vm[j] = v[j] + 0.5 * dv[j - 3];
                am[j] = dv[j - 3] / h;
            }
            model.inertia_force(&xm, &vm, &am, &mut fin);
            model.internal_force(&xm, &mut full, &mut fint);
            let r = DVector::from_iterator(nu, (0..nu).map(|i| -h * (fin[i] + fint[i])));
            let delta = solver.solve(&r).ok_or(ReferenceError::Singular)?;
            dv += &delta;
            run.iterations += 1;
            correction = delta.amax();
            if correction <= 1e-8 * vscale {
                converged = true;
                break;
            }
        }
        if !converged {
            return Err(ReferenceError::NoConvergence { t, correction });
        }
        for j in 3..x.len() {
            x[j] += h * (v[j] + 0.5 * dv[j - 3]);
            v[j] += dv[j - 3];
        }
        let s = x[nd];
        if !(0.0..=model.beam.length).contains(&s) {
            return Err(ReferenceError::BallOffBeam { t, s });
        }
        run.steps += 1;
        let e = model.energy(x, v);
        run.energy_deviation = run.energy_deviation.max(((e - run.e0) / run.e0).abs());
        run.tip_max = run.tip_max.max(x[nd - 2].abs());
        for i in 0..=n {
            run.rotation_max = run.rotation_max.max(x[3 * i + 2].abs());
        }
        if step % every == 0 {
            sample(&mut run, t, x, v);
        }
    }
    Ok(run)
}

/// The `sliding_balls` reference: `n` elements, step `h`, ball from `(x0, 0)` with velocity
/// `(vx0, vy0)` taken up by the plastic impact, to `t_end`, sampled every `sample_dt`.
#[allow(clippy::too_many_arguments)]
pub fn simulate(
    n: usize,
    stiffness_factor: f64,
    h: f64,
    t_end: f64,
    sample_dt: f64,
    x0: f64,
    vx0: f64,
    vy0: f64,
) -> Result<ReferenceRun, ReferenceError> {
    let model = BallOnBeam::sliding_balls(n, stiffness_factor);
    let mut x = model.straight(x0);
    let mut v = model.impact_velocity(&x, vx0, vy0)?;
    let steps = (t_end / h).round() as usize;
    let every = ((sample_dt / h).round() as usize).max(1);
    integrate(&model, &mut x, &mut v, h, steps, every)
}

/// Linear interpolation of sampled column `col` at time `t` (samples sorted by time).
pub fn interpolate(samples: &[[f64; 5]], col: usize, t: f64) -> f64 {
    let k = samples.partition_point(|s| s[0] < t);
    if k == 0 {
        return samples.first().map_or(f64::NAN, |s| s[col]);
    }
    if k >= samples.len() {
        return samples.last().map_or(f64::NAN, |s| s[col]);
    }
    let (a, b) = (samples[k - 1], samples[k]);
    a[col] + (b[col] - a[col]) * (t - a[0]) / (b[0] - a[0])
}

/// Clamped-free bending frequencies (Hz) of the beam alone at the straight configuration:
/// generalized eigenvalues of `K` and `M` (Cholesky of `M`, symmetric eigen of
/// `L^-1 K L^-T`), the lowest `count`.
pub fn clamped_frequencies(model: &BallOnBeam, count: usize) -> Vec<f64> {
    let empty = BallOnBeam {
        mass: 0.0,
        inertia: 0.0,
        ..*model
    };
    let x = empty.straight(0.0);
    let nb = 3 * model.beam.n;
    let m = empty.mass_matrix(&x).view((0, 0), (nb, nb)).into_owned();
    let k = empty
        .tangent_stiffness(&x)
        .view((0, 0), (nb, nb))
        .into_owned();
    let k = 0.5 * (&k + k.transpose());
    let Some(chol) = m.cholesky() else {
        return Vec::new();
    };
    let l = chol.l();
    let Some(linv) = l.clone().try_inverse() else {
        return Vec::new();
    };
    let a = &linv * k * linv.transpose();
    let a = 0.5 * (&a + a.transpose());
    let mut w: Vec<f64> = a.symmetric_eigenvalues().iter().copied().collect();
    w.sort_by(f64::total_cmp);
    w.iter()
        .take(count)
        .map(|l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Jet arithmetic and `atan2` against central differences of a composite function.
    #[test]
    fn jet_derivatives_match_finite_differences() {
        let f = |a: Jet, b: Jet| Jet::atan2(a * b + Jet::constant(0.3), b - a * a) * a;
        let (a0, b0, da, db) = (0.4, 1.3, 0.7, -0.2);
        let j = f(Jet::variable(a0, da), Jet::variable(b0, db));
        let g = |e: f64| f(Jet::constant(a0 + e * da), Jet::constant(b0 + e * db)).v;
        let h = 1e-4;
        let d = (g(h) - g(-h)) / (2.0 * h);
        let dd = (g(h) - 2.0 * g(0.0) + g(-h)) / (h * h);
        assert!((j.d - d).abs() < 1e-8, "{} vs {d}", j.d);
        assert!((j.dd - dd).abs() < 1e-6, "{} vs {dd}", j.dd);
    }

    /// At the straight configuration the mass matrix is the textbook consistent mass: axial
    /// `rho A l/6 [2 1; 1 2]`, bending `rho A l/420 [156 22l 54 -13l; ...]` plus rotary inertia
    /// `rho I/(30 l) [36 3l -36 3l; 3l 4l² -3l -l²; ...]` (Przemieniecki), assembled for two
    /// elements (node 0 clamped, unknowns of nodes 1 and 2), to 1e-12 relative.
    #[test]
    #[allow(clippy::needless_range_loop)]
    fn straight_mass_is_the_consistent_beam_mass() {
        let mut model = BallOnBeam::sliding_balls(2, 1.0);
        model.mass = 0.0;
        model.inertia = 0.0;
        let (l, ra, ri) = (0.75, model.beam.rho_a, model.beam.rho_i);
        let axial = [[2.0, 1.0], [1.0, 2.0]].map(|r| r.map(|v| ra * l / 6.0 * v));
        let bend = [
            [156.0, 22.0 * l, 54.0, -13.0 * l],
            [22.0 * l, 4.0 * l * l, 13.0 * l, -3.0 * l * l],
            [54.0, 13.0 * l, 156.0, -22.0 * l],
            [-13.0 * l, -3.0 * l * l, -22.0 * l, 4.0 * l * l],
        ];
        let rot = [
            [36.0, 3.0 * l, -36.0, 3.0 * l],
            [3.0 * l, 4.0 * l * l, -3.0 * l, -l * l],
            [-36.0, -3.0 * l, 36.0, -3.0 * l],
            [3.0 * l, -l * l, -3.0 * l, 4.0 * l * l],
        ];
        // element matrix in (x_a, y_a, t_a, x_b, y_b, t_b)
        let mut me = [[0.0; 6]; 6];
        for a in 0..2 {
            for b in 0..2 {
                me[3 * a][3 * b] = axial[a][b];
            }
        }
        let bi = [1, 2, 4, 5];
        for a in 0..4 {
            for b in 0..4 {
                me[bi[a]][bi[b]] = ra * l / 420.0 * bend[a][b] + ri / (30.0 * l) * rot[a][b];
            }
        }
        let mut expect = DMatrix::<f64>::zeros(7, 7);
        for e in 0..2 {
            for a in 0..6 {
                for b in 0..6 {
                    let (ia, ib) = (3 * e + a, 3 * e + b);
                    if ia >= 3 && ib >= 3 {
                        expect[(ia - 3, ib - 3)] += me[a][b];
                    }
                }
            }
        }
        let m = model.mass_matrix(&model.straight(0.3));
        let err = (&m - &expect).amax() / expect.amax();
        assert!(err < 1e-12, "{err:e}\n{m}\n{expect}");
    }

    /// Clamped-free bending frequencies without rotary inertia vs Euler-Bernoulli
    /// `(beta_k L)² / (2 pi L²) sqrt(EI / rho A)`, `beta_k L` = 1.8751041, 4.6940911, 7.8547574:
    /// the cubic Hermite elements converge as h^4; at 20 elements within 1e-6 (first) and 2e-5
    /// (third).
    #[test]
    fn clamped_frequencies_match_euler_bernoulli() {
        let mut model = BallOnBeam::sliding_balls(20, 1.0);
        model.beam.rho_i = 0.0;
        let b = model.beam;
        let f = clamped_frequencies(&model, 3);
        let exact: Vec<f64> = [1.875_104_07, 4.694_091_13, 7.854_757_44]
            .iter()
            .map(|bl: &f64| {
                bl * bl / (2.0 * std::f64::consts::PI * b.length * b.length)
                    * (b.ei / b.rho_a).sqrt()
            })
            .collect();
        let rel: Vec<f64> = f.iter().zip(&exact).map(|(a, e)| a / e - 1.0).collect();
        assert!(rel[0].abs() < 1e-6, "{rel:?}");
        assert!(rel[2].abs() < 2e-5, "{rel:?}");
    }

    /// The plastic impact conserves the generalized momentum along the constrained motions and
    /// loses energy (a perfectly plastic impact); the ball's new velocity lies along the axis
    /// tangent plus the beam's velocity at the contact point (constraint kept).
    #[test]
    fn impact_takes_up_the_transverse_velocity() {
        let model = BallOnBeam::sliding_balls(10, 1.0);
        let x = model.straight(0.75);
        let v = model.impact_velocity(&x, 0.01, -0.002).unwrap();
        let e_before = 0.5 * (0.01f64.powi(2) + 0.002f64.powi(2));
        let e_after = model.kinetic_energy(&x, &v);
        assert!(e_after < e_before && e_after > 0.5 * 0.01f64.powi(2));
        // the ball's axial velocity: s_dot on the straight axis equals 0.01 (no x coupling)
        let sd = v[3 * 11];
        assert!((sd - 0.01).abs() < 1e-12, "{sd}");
    }

    /// The reference run conserves energy: 0.5 s, 10 elements, h = 0.5 ms: |E - E0| / E0 below
    /// 1e-5 (measured 6.0e-6; 1.2e-5 at h = 1 ms, 2.1e-6 at 0.25 ms: the implicit midpoint rule
    /// conserves the energy of a linear system exactly, what remains comes from the
    /// configuration-dependent mass and the ball's sliding).
    #[test]
    fn reference_run_conserves_energy() {
        let run = simulate(10, 1.0, 5e-4, 0.5, 0.01, 0.75, 0.01, -0.002).unwrap();
        assert_eq!(run.steps, 1000);
        assert!(run.energy_deviation < 1e-5, "{:e}", run.energy_deviation);
    }

    /// With a very stiff beam (E x 1e6) the axis stays straight and the ball slides at constant
    /// speed: after 1 s its x is x0 + 0.01 m to 1e-7 m (measured 1.1e-8); energy to 5e-5
    /// (measured 2.3e-5: the stiff beam's vibration, 840 Hz and up, is not resolved by h = 0.5 ms).
    #[test]
    fn ball_on_a_stiff_beam_moves_at_constant_speed() {
        let run = simulate(10, 1e6, 5e-4, 1.0, 0.1, 0.75, 0.01, -0.002).unwrap();
        let last = run.samples.last().copied().unwrap_or([f64::NAN; 5]);
        assert!((last[0] - 1.0).abs() < 1e-12);
        assert!((last[1] - 0.76).abs() < 1e-7, "x = {}", last[1]);
        assert!(run.energy_deviation < 5e-5, "{:e}", run.energy_deviation);
    }
}

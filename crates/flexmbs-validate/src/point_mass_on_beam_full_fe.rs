//! The unreduced (full FE) reference of `point_mass_on_beam` with the penalty law (S4).
//!
//! The beam is the benchmark's mesh (25 x 5 x 5 hex20, full integration, consistent mass,
//! clamped on x = 0; 9900 free DOFs) with **all** its DOFs: the stiffness `K` and mass `M` come
//! from the `flexmbs-fe` assembly (checked elsewhere: `tests/calculix_beam.rs` against CalculiX,
//! `fe_cantilever_modes` against beam theory), the clamped DOFs removed. Nothing else is shared with the code under
//! test (no FFR body, no modal reduction, no contour or contact code, no integrator of
//! `flexmbs-core`):
//!
//! - the contact point is a fixed material point of the top face, its displacement a fixed linear
//!   combination of the node displacements `u_c = w^T u` ([`ContactWeights`]): the cubic NURBS
//!   interpolation through the 26 x 11 top-face node grid (the benchmark's contour; basis from
//!   `flexmbs-nurbs`, tested against The NURBS Book) or the 8-node face shape functions of the
//!   hex20 element under the point;
//! - the gap `g = y - (y_top + u_c,y)` of the mass's height `y`, the penalty force
//!   `f = k max(0, -g)` (seed 000 S4, no damping), acting up on the mass and down on the beam;
//! - `M u'' + K u = -w f`, `m y'' = f` integrated by Newmark's average acceleration rule
//!   (trapezoidal, unconditionally stable, energy-conserving for linear systems): one sparse
//!   Cholesky factorization of `K + (4/h^2) M` (faer, AMD ordering) at set-up, the single contact
//!   unknown solved exactly per step (the law is piecewise linear in `f`; Sherman-Morrison with
//!   the precomputed `z = (K + 4/h^2 M)^-1 w`).
//!
//! The small-displacement assumptions (contact at a fixed material point, normal along y) are the
//! same as the FFR body's linear elasticity; the FFR contact search also lets the point slide
//! along the deformed surface, a second-order effect here (slopes of about 1e-2).

use anyhow::{bail, Context, Result};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{LltParams, LltRegularization};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymmetricOrdering,
};
use faer::sparse::Triplet;
use faer::{Conj, Mat, Par, Side, Spec};
use flexmbs_fe::SparseMatrix;
use flexmbs_nurbs::{BasisScratch, CurveInterpolator};
use std::path::Path;
use std::time::Instant;

/// The benchmark's beam with all its DOFs (SI units).
pub struct FullFeBeam {
    /// Stiffness over the free DOFs.
    pub k: SparseMatrix,
    /// Consistent mass over the free DOFs.
    pub m: SparseMatrix,
    /// Node positions (m).
    pub nodes: Vec<[f64; 3]>,
    /// Free DOF index of each node's x, y, z (`None`: clamped).
    pub dofs: Vec<[Option<usize>; 3]>,
}

/// Assembles the benchmark's beam (`fe_spec`: the case's FE body text).
pub fn assemble_full_fe(fe_spec: &str) -> Result<FullFeBeam> {
    let spec = flexmbs_io::model::parse_fe_model(fe_spec, Path::new("point_mass_on_beam.toml"))?;
    let prepared = flexmbs_reduce::pipeline::prepare(&spec.body, Path::new("."), &mut |_| {})?;
    let map = &prepared.system.map;
    let nodes = map.nodes.clone();
    let mut dofs = vec![[None; 3]; nodes.len()];
    for (p, d) in map.independent.iter().enumerate() {
        if d.dir < 3 {
            dofs[d.node][d.dir] = Some(p);
        }
    }
    if map.independent.iter().any(|d| d.dir >= 3) {
        bail!("the full-FE reference expects a solid mesh (translations only)");
    }
    Ok(FullFeBeam {
        k: prepared.system.k.clone(),
        m: prepared.system.m.clone(),
        nodes,
        dofs,
    })
}

/// How the contact point's displacement is interpolated from the node displacements.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Interpolation {
    /// Cubic NURBS interpolation through the top-face grid (the benchmark's 2D neutral contour).
    Nurbs,
    /// The 8-node serendipity shape functions of the hex20 face under the point.
    Hex20Face,
}

/// `u_c,y = sum w_i u_i`: (free DOF, weight) pairs over y DOFs of top-face nodes.
#[derive(Debug, Clone)]
pub struct ContactWeights {
    /// (free DOF index, weight).
    pub terms: Vec<(usize, f64)>,
}

impl ContactWeights {
    /// `w^T u`.
    pub fn dot(&self, u: &[f64]) -> f64 {
        self.terms.iter().map(|&(i, w)| w * u[i]).sum()
    }
    /// The weights as a dense vector of length `n`.
    pub fn dense(&self, n: usize) -> Vec<f64> {
        let mut v = vec![0.0; n];
        for &(i, w) in &self.terms {
            v[i] += w;
        }
        v
    }
}

/// Node at `p` within 1e-9 m.
fn node_at(beam: &FullFeBeam, p: [f64; 3]) -> Option<usize> {
    beam.nodes
        .iter()
        .position(|n| (0..3).all(|k| (n[k] - p[k]).abs() < 1e-9))
}

/// The y free DOF of the node at `p`.
pub fn y_dof_at(beam: &FullFeBeam, p: [f64; 3]) -> Result<usize> {
    let n = node_at(beam, p).with_context(|| format!("no node at {p:?}"))?;
    beam.dofs[n][1].with_context(|| format!("the node at {p:?} is clamped"))
}

/// Weights of the contact point at `(x, z)` on the top face `y = y_top` of a box mesh with
/// corner spacing `dx`, `dz` (`nx`, `nz` elements).
pub fn contact_weights(
    beam: &FullFeBeam,
    how: Interpolation,
    point: [f64; 2],
    y_top: f64,
    spacing: [f64; 2],
    elements: [usize; 2],
) -> Result<ContactWeights> {
    let [x, z] = point;
    let [dx, dz] = spacing;
    let [nx, nz] = elements;
    let mut terms = vec![];
    match how {
        Interpolation::Nurbs => {
            // grid: corner stations along x (nx + 1), every node station along z (2 nz + 1)
            let wx = interpolation_weights(nx + 1, x / (nx as f64 * dx))?;
            let wz = interpolation_weights(2 * nz + 1, z / (nz as f64 * dz))?;
            for (i, a) in wx.iter().enumerate() {
                for (j, b) in wz.iter().enumerate() {
                    let p = [i as f64 * dx, y_top, j as f64 * 0.5 * dz];
                    push_term(beam, &mut terms, p, a * b)?;
                }
            }
        }
        Interpolation::Hex20Face => {
            let (ex, ez) = ((x / dx).floor(), (z / dz).floor());
            let (xc, zc) = ((ex + 0.5) * dx, (ez + 0.5) * dz);
            let (r, s) = (2.0 * (x - xc) / dx, 2.0 * (z - zc) / dz);
            for (ri, si) in [
                (-1, -1),
                (1, -1),
                (1, 1),
                (-1, 1),
                (0, -1),
                (1, 0),
                (0, 1),
                (-1, 0),
            ] {
                let (ri, si) = (ri as f64, si as f64);
                let w = serendipity8(r, s, ri, si);
                let p = [xc + 0.5 * dx * ri, y_top, zc + 0.5 * dz * si];
                push_term(beam, &mut terms, p, w)?;
            }
        }
    }
    terms.retain(|t| t.1 != 0.0);
    Ok(ContactWeights { terms })
}

/// Adds the term of the node at `p` (clamped nodes do not move: no term).
fn push_term(
    beam: &FullFeBeam,
    terms: &mut Vec<(usize, f64)>,
    p: [f64; 3],
    weight: f64,
) -> Result<()> {
    let n = node_at(beam, p).with_context(|| format!("no node at {p:?}"))?;
    if let Some(dof) = beam.dofs[n][1] {
        terms.push((dof, weight));
    }
    Ok(())
}

/// 8-node serendipity shape function of the node at `(ri, si)` evaluated at `(r, s)`.
fn serendipity8(r: f64, s: f64, ri: f64, si: f64) -> f64 {
    if ri != 0.0 && si != 0.0 {
        0.25 * (1.0 + r * ri) * (1.0 + s * si) * (r * ri + s * si - 1.0)
    } else if ri == 0.0 {
        0.5 * (1.0 - r * r) * (1.0 + s * si)
    } else {
        0.5 * (1.0 + r * ri) * (1.0 - s * s)
    }
}

/// Weights `c_i(u)` of the cubic interpolating curve through `k` equally spaced data (uniform
/// chord-length parameters, averaged knots: NURBS Book A9.1) at parameter `u`:
/// `C(u) = sum c_i Q_i` (the curve is linear in the data; column `i` from the data `e_i`).
fn interpolation_weights(k: usize, u: f64) -> Result<Vec<f64>> {
    let params: Vec<f64> = (0..k).map(|i| i as f64 / (k - 1) as f64).collect();
    let ip = CurveInterpolator::new(&params, 3, false)?;
    let knots = ip.knot_vector();
    let mut scratch = BasisScratch::new(3);
    let span = knots.basis_derivatives(u, 0, false, &mut scratch);
    let mut ctrl = vec![0.0; ip.n_ctrl()];
    let mut data = vec![0.0; k];
    let mut out = vec![0.0; k];
    for (i, o) in out.iter_mut().enumerate() {
        data.fill(0.0);
        data[i] = 1.0;
        ip.control_points_into(&data, &mut ctrl)?;
        *o = (0..=3)
            .map(|j| scratch.der(0, j) * ctrl[span - 3 + j])
            .sum();
    }
    Ok(out)
}

/// The mass and the penalty law of the reference.
#[derive(Debug, Clone, Copy)]
pub struct PenaltyImpact {
    /// Point mass (kg).
    pub mass: f64,
    /// Initial height (m) and vertical velocity (m/s) of the mass.
    pub y0: f64,
    /// Initial vertical velocity of the mass (m/s).
    pub v0: f64,
    /// Height of the undeformed top face (m).
    pub y_top: f64,
    /// Penalty stiffness (N/m).
    pub stiffness: f64,
    /// Time step (s).
    pub h: f64,
    /// End time (s).
    pub t_end: f64,
}

/// A reference run: every step recorded.
#[derive(Debug, Clone, Default)]
pub struct ReferenceRun {
    /// Step times (s), from 0.
    pub t: Vec<f64>,
    /// Height of the mass (m).
    pub y: Vec<f64>,
    /// y displacement of the probe DOF (m).
    pub probe: Vec<f64>,
    /// Contact force (N).
    pub force: Vec<f64>,
    /// Vertical velocity of the mass (m/s).
    pub v_y: Vec<f64>,
    /// Smallest height of the mass (m).
    pub y_min: f64,
    /// Final vertical velocity of the mass (m/s).
    pub v_y_final: f64,
    /// Largest |E - E0| / E0 over the steps (E: kinetic + elastic + penalty energy).
    pub energy_error: f64,
    /// Wall time of the integration (s).
    pub cpu: f64,
    /// Wall time of the factorization (s).
    pub cpu_factor: f64,
}

impl ReferenceRun {
    /// The run up to (and including) the step at `t_end` (energy error and times as the whole
    /// run's).
    pub fn truncated(&self, t_end: f64) -> ReferenceRun {
        let n = self
            .t
            .iter()
            .take_while(|&&t| t <= t_end * (1.0 + 1e-12))
            .count();
        ReferenceRun {
            t: self.t[..n].to_vec(),
            y: self.y[..n].to_vec(),
            probe: self.probe[..n].to_vec(),
            force: self.force[..n].to_vec(),
            v_y: self.v_y[..n].to_vec(),
            y_min: self.y[..n].iter().copied().fold(f64::INFINITY, f64::min),
            v_y_final: self.v_y[n - 1],
            ..*self
        }
    }

    /// (first, last) step time with a nonzero contact force and the total time in contact.
    pub fn contact(&self) -> (f64, f64, f64) {
        contact_times(&self.t, &self.force)
    }
}

/// (first time, last time, total time) of the nonzero entries of `force` at times `t`.
pub fn contact_times(t: &[f64], force: &[f64]) -> (f64, f64, f64) {
    let on: Vec<usize> = (0..t.len()).filter(|&i| force[i] > 0.0).collect();
    let (Some(&a), Some(&b)) = (on.first(), on.last()) else {
        return (f64::NAN, f64::NAN, 0.0);
    };
    let h = if t.len() > 1 { t[1] - t[0] } else { 0.0 };
    (t[a], t[b], on.len() as f64 * h)
}

/// A sparse Cholesky factor with its own solve workspace.
struct Factor {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
    mem: MemBuffer,
}

impl Factor {
    fn new(a: &SparseMatrix) -> Result<Self> {
        let params = CholeskySymbolicParams::default();
        let symbolic =
            factorize_symbolic_cholesky(a.symbolic(), Side::Lower, SymmetricOrdering::Amd, params)?;
        let mut values = vec![0.0; symbolic.len_val()];
        let spec = Spec::<LltParams, f64>::default();
        let req = symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, spec);
        let mut mem = MemBuffer::new(req);
        symbolic
            .factorize_numeric_llt(
                &mut values,
                a.as_ref(),
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut mem),
                spec,
            )
            .map_err(|e| anyhow::anyhow!("the matrix is not positive definite: {e:?}"))?;
        let mem = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        Ok(Self {
            symbolic,
            values,
            mem,
        })
    }

    fn solve_in_place(&mut self, x: &mut Mat<f64>) {
        let llt = LltRef::new(&self.symbolic, &self.values);
        llt.solve_in_place_with_conj(Conj::No, x.as_mut(), Par::Seq, MemStack::new(&mut self.mem));
    }
}

/// The static response `K^-1 f` (the sparse Cholesky factorization of the reference).
pub fn static_response(k: &SparseMatrix, f: &[f64]) -> Result<Vec<f64>> {
    if f.len() != k.nrows() {
        bail!("load of size {} for {} DOFs", f.len(), k.nrows());
    }
    let mut x = Mat::<f64>::from_fn(f.len(), 1, |i, _| f[i]);
    Factor::new(k)?.solve_in_place(&mut x);
    Ok((0..f.len()).map(|i| x[(i, 0)]).collect())
}

/// `a + c b` for sparse matrices of equal size.
fn sparse_sum(a: &SparseMatrix, b: &SparseMatrix, c: f64) -> Result<SparseMatrix> {
    let mut t = vec![];
    for (m, s) in [(a, 1.0), (b, c)] {
        for j in 0..m.ncols() {
            let rows = m.row_idx_of_col_raw(j);
            let vals = m.val_of_col(j);
            for (&i, &v) in rows.iter().zip(vals) {
                t.push(Triplet::new(i, j, s * v));
            }
        }
    }
    Ok(SparseMatrix::try_new_from_triplets(
        a.nrows(),
        a.ncols(),
        &t,
    )?)
}

/// `out = A x`.
fn sparse_times_into(a: &SparseMatrix, x: &Mat<f64>, out: &mut Mat<f64>) {
    faer::sparse::linalg::matmul::sparse_dense_matmul(
        out.as_mut(),
        faer::Accum::Replace,
        a.as_ref(),
        x.as_ref(),
        1.0,
        Par::Seq,
    );
}

/// `x^T A x`.
fn quadratic_form(a: &SparseMatrix, x: &Mat<f64>, tmp: &mut Mat<f64>) -> f64 {
    sparse_times_into(a, x, tmp);
    (0..x.nrows()).map(|i| x[(i, 0)] * tmp[(i, 0)]).sum()
}

/// Integrates the beam (`k`, `m`: any linear structure, full FE or modal) hit by the penalty
/// point mass with Newmark's average acceleration rule (module documentation); `w` maps the
/// structure's DOFs to the contact point's y displacement (`u_c,y = w^T u`), `probe` to the
/// recorded displacement (`probe^T u`).
pub fn simulate_penalty_impact(
    k: &SparseMatrix,
    m: &SparseMatrix,
    w: &[f64],
    probe: &[f64],
    p: &PenaltyImpact,
) -> Result<ReferenceRun> {
    simulate_penalty_impact_from(k, m, w, probe, p, None)
}

/// The structure's Newmark state and work vectors.
struct NewmarkStructure {
    u: Mat<f64>,
    v: Mat<f64>,
    a: Mat<f64>,
    /// The predictor `(K + a0 M)^-1 M (a0 u + a1 v + a)`, then free.
    rhs: Mat<f64>,
    tmp: Mat<f64>,
}

impl NewmarkStructure {
    fn new(n: usize, v0: Option<&[f64]>) -> Self {
        Self {
            u: Mat::zeros(n, 1),
            v: Mat::from_fn(n, 1, |i, _| v0.map_or(0.0, |v| v[i])),
            a: Mat::zeros(n, 1),
            rhs: Mat::zeros(n, 1),
            tmp: Mat::zeros(n, 1),
        }
    }

    /// The displacement at `t_{n+1}` without the contact force, into `rhs`.
    fn predict(&mut self, m: &SparseMatrix, factor: &mut Factor, a0: f64, a1: f64) {
        for i in 0..self.u.nrows() {
            self.tmp[(i, 0)] = a0 * self.u[(i, 0)] + a1 * self.v[(i, 0)] + self.a[(i, 0)];
        }
        sparse_times_into(m, &self.tmp, &mut self.rhs);
        factor.solve_in_place(&mut self.rhs);
    }

    /// `u_{n+1} = rhs - z f`, then the average-acceleration updates of `a` and `v`.
    fn correct(&mut self, z: &Mat<f64>, f: f64, a0: f64, a1: f64, h: f64) {
        for i in 0..self.u.nrows() {
            let un = self.rhs[(i, 0)] - z[(i, 0)] * f;
            let an = a0 * (un - self.u[(i, 0)]) - a1 * self.v[(i, 0)] - self.a[(i, 0)];
            self.v[(i, 0)] += 0.5 * h * (self.a[(i, 0)] + an);
            (self.u[(i, 0)], self.a[(i, 0)]) = (un, an);
        }
    }

    /// Kinetic + elastic energy of the structure, kinetic of the mass and the penalty energy.
    fn energy(
        &mut self,
        k: &SparseMatrix,
        m: &SparseMatrix,
        w: &[f64],
        p: &PenaltyImpact,
        (y, vy): (f64, f64),
    ) -> f64 {
        let pen = (p.y_top + dot(w, &self.u) - y).max(0.0);
        0.5 * quadratic_form(m, &self.v, &mut self.tmp)
            + 0.5 * quadratic_form(k, &self.u, &mut self.tmp)
            + 0.5 * p.mass * vy * vy
            + 0.5 * p.stiffness * pen * pen
    }
}

/// `a^T x`.
fn dot(a: &[f64], x: &Mat<f64>) -> f64 {
    (0..a.len()).map(|i| a[i] * x[(i, 0)]).sum::<f64>()
}

/// [`simulate_penalty_impact`] with an initial velocity `v0` of the structure (undeformed: the
/// initial acceleration is zero); `None`: at rest.
pub fn simulate_penalty_impact_from(
    k: &SparseMatrix,
    m: &SparseMatrix,
    w: &[f64],
    probe: &[f64],
    p: &PenaltyImpact,
    v0: Option<&[f64]>,
) -> Result<ReferenceRun> {
    let n = k.nrows();
    if m.nrows() != n || w.len() != n || probe.len() != n || v0.is_some_and(|v| v.len() != n) {
        bail!("structure, weights, probe and initial velocity differ in size");
    }
    if !(p.h > 0.0 && p.t_end > 0.0 && p.mass > 0.0 && p.stiffness >= 0.0) {
        bail!("step, end time and mass must be positive, the stiffness non-negative");
    }
    let (a0, a1) = (4.0 / (p.h * p.h), 4.0 / p.h);
    let start = Instant::now();
    let mut factor = Factor::new(&sparse_sum(k, m, a0)?)?;
    let cpu_factor = start.elapsed().as_secs_f64();
    // z = (K + a0 M)^-1 w: the beam's response to a unit contact force
    let mut z = Mat::<f64>::from_fn(n, 1, |i, _| w[i]);
    factor.solve_in_place(&mut z);
    let c = p.h * p.h / (4.0 * p.mass) + dot(w, &z);
    let mut s = NewmarkStructure::new(n, v0);
    let (mut y, mut vy, mut ay) = (p.y0, p.v0, 0.0);
    let steps = (p.t_end / p.h).round() as usize;
    let mut run = ReferenceRun {
        y_min: y,
        cpu_factor,
        ..ReferenceRun::default()
    };
    let e0 = s.energy(k, m, w, p, (y, vy));
    let record = |run: &mut ReferenceRun, t: f64, (y, vy): (f64, f64), u: &Mat<f64>, f: f64| {
        run.t.push(t);
        run.y.push(y);
        run.v_y.push(vy);
        run.probe.push(dot(probe, u));
        run.force.push(f);
    };
    record(&mut run, 0.0, (y, vy), &s.u, 0.0);
    let mut resting = v0.is_none();
    for step in 1..=steps {
        let t = step as f64 * p.h;
        // predictor: the beam and the mass without the contact force at t_{n+1}
        let y_hat = y + p.h * vy + 0.25 * p.h * p.h * ay;
        if resting && y_hat > p.y_top {
            // the beam is still undeformed and at rest: nothing to solve
            (y, vy) = (y_hat, vy + p.h * ay);
            record(&mut run, t, (y, vy), &s.u, 0.0);
            continue;
        }
        resting = false;
        s.predict(m, &mut factor, a0, a1);
        let g_hat = y_hat - p.y_top - dot(w, &s.rhs);
        // g = g_hat + c f, f = k max(0, -g): exact for the piecewise linear law
        let f = if g_hat < 0.0 {
            -p.stiffness * g_hat / (1.0 + p.stiffness * c)
        } else {
            0.0
        };
        s.correct(&z, f, a0, a1, p.h);
        let ay_new = f / p.mass;
        y = y_hat + 0.25 * p.h * p.h * ay_new;
        vy += 0.5 * p.h * (ay + ay_new);
        ay = ay_new;
        run.y_min = run.y_min.min(y);
        record(&mut run, t, (y, vy), &s.u, f);
        if step % 10 == 0 || step == steps {
            let de = (s.energy(k, m, w, p, (y, vy)) - e0) / e0;
            run.energy_error = run.energy_error.max(de.abs());
        }
    }
    run.v_y_final = vy;
    run.cpu = start.elapsed().as_secs_f64();
    Ok(run)
}

//! System algebra behind one interface: the saddle matrices of the implicit solvers
//! (`[c_m M - c_u dh/du - c_q dh/dq, G^T; G, 0]`, the augmented mass matrix), their
//! factorization and solves, with a **dense** backend (faer dense LU, bitwise the historical
//! path, for small models) and a **sparse** backend (faer sparse LU on a fixed pattern), and a
//! block-Cholesky factorization of the mass matrix alone ([`BlockMass`]).
//!
//! The sparse backend never forms a dense `nu x nu` matrix: element blocks, the load and joint
//! coupling blocks (the local finite-difference tangents of [`crate::system::add_load_tangents`],
//! the same code as the dense backend, written through a slot sink) and the rows of `G` are
//! written into the compressed-column values through slot maps computed once from the
//! [`SystemPattern`] (built from the model's coordinate maps: bodies on shared nodes add into the
//! same slots, node-owned frames couple their node's columns); the symbolic LU and one numeric
//! factorization happen in [`SystemMatrix::new`], so refactorizations and solves do not
//! allocate.

mod blocks;
mod dense;
mod mass;
mod pattern;
mod schur;
mod sparse;

pub use mass::BlockMass;
pub use pattern::{ColumnLists, SystemPattern};

use crate::model::Model;
use crate::state::SystemBuffers;
use dense::DenseSystem;
use sparse::SparseSystem;

/// Linear-solver backend of the system matrices (`solver.linear_solver` in model files).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LinearSolver {
    /// Sparse from [`SPARSE_MIN_DIM`] unknowns `nu + nc` on if at most [`SPARSE_MAX_FILL`] of
    /// the matrix entries are structurally nonzero, dense otherwise (one large flexible body
    /// is a dense block: the sparse LU would only add overhead). Default.
    #[default]
    Auto,
    /// Dense LU (bitwise the historical results).
    Dense,
    /// Sparse LU on the model's fixed pattern.
    Sparse,
}

/// Smallest `nu + nc` for which [`LinearSolver::Auto`] picks the sparse backend (measured
/// crossover, `benches/README.md`).
pub const SPARSE_MIN_DIM: usize = 120;

/// Largest fraction `nnz / (nu + nc)^2` of structurally nonzero entries for which
/// [`LinearSolver::Auto`] picks the sparse backend.
pub const SPARSE_MAX_FILL: f64 = 0.25;

impl LinearSolver {
    /// True if this choice means the sparse backend for a pattern of dimension `dim` with `nnz`
    /// entries.
    pub fn is_sparse(self, dim: usize, nnz: usize) -> bool {
        match self {
            LinearSolver::Auto => {
                dim >= SPARSE_MIN_DIM && (nnz as f64) <= SPARSE_MAX_FILL * (dim * dim) as f64
            }
            LinearSolver::Dense => false,
            LinearSolver::Sparse => true,
        }
    }
}

/// Which matrix [`SystemMatrix`] holds after a build.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SaddleKind {
    /// `[M, G^T; G, 0]` (consistent accelerations).
    AugmentedMass,
    /// `[M - gamma' dh/du - beta' dh/dq, G^T; G, 0]` (generalized-alpha), with
    /// `gamma'` = `c_u`, `beta'` = `c_q`, at time `t`.
    Iteration {
        /// Time of the tangents.
        t: f64,
        /// Coefficient `c_u` of `dh/du`.
        c_u: f64,
        /// Coefficient `c_q` of `dh/dq`.
        c_q: f64,
    },
    /// `[I, G^T; G, 0]` (least-squares multipliers of statics).
    LeastSquares,
    /// `[-dh/dq + d(G^T lambda)/dq, G^T; G, 0]` (statics) at time `t` and load factor `mu`.
    StaticTangent {
        /// Time.
        t: f64,
        /// Load factor.
        mu: f64,
    },
}

/// The saddle matrix `[A, G^T; G, 0]` of dimension `nu + nc` with its factorization.
#[derive(Debug)]
pub struct SystemMatrix {
    backend: Backend,
}

#[derive(Debug)]
enum Backend {
    Dense(DenseSystem),
    Sparse(Box<SparseSystem>),
}

impl SystemMatrix {
    /// Allocates the matrix for `model` with the chosen backend (sparse: pattern from
    /// [`ColumnLists::of_model`], symbolic LU and one numeric factorization).
    pub fn new(model: &Model, choice: LinearSolver) -> Self {
        let dim = model.nu + model.nc;
        let sparse = match choice {
            LinearSolver::Dense => None,
            LinearSolver::Auto if dim < SPARSE_MIN_DIM => None,
            _ => {
                let lists = ColumnLists::of_model(model);
                let pattern = SystemPattern::new(model.nu, &lists);
                choice
                    .is_sparse(dim, pattern.nnz())
                    .then(|| SparseSystem::new(model, &lists, &pattern))
            }
        };
        let backend = match sparse {
            Some(s) => Backend::Sparse(Box::new(s)),
            None => Backend::Dense(DenseSystem::new(dim)),
        };
        Self { backend }
    }

    /// True for the sparse backend.
    pub fn is_sparse(&self) -> bool {
        matches!(self.backend, Backend::Sparse(_))
    }

    /// Dimension `nu + nc`.
    pub fn dim(&self) -> usize {
        match &self.backend {
            Backend::Dense(d) => d.lu.dim(),
            Backend::Sparse(s) => s.dim(),
        }
    }

    /// Builds the matrix `kind` at `(q, u)` (frames and constraints in `sys` must be current;
    /// `lambda` is used by [`SaddleKind::StaticTangent`] only). Leaves frames at `(q, u)`.
    #[allow(clippy::too_many_arguments)]
    pub fn build(
        &mut self,
        kind: SaddleKind,
        model: &Model,
        q: &[f64],
        u: &[f64],
        lambda: &[f64],
        sys: &mut SystemBuffers,
    ) {
        match &mut self.backend {
            Backend::Dense(d) => d.build(kind, model, q, u, lambda, sys),
            Backend::Sparse(s) => s.build(kind, model, q, u, lambda, sys),
        }
    }

    /// Adds `-c_q dh_c/dq - c_u dh_c/du` of the regularized contacts' forces `h_c` at `(q, u)`
    /// ([`crate::system::add_contact_tangents`]: the two contact bodies' coordinates only) to
    /// the last built iteration matrix (`sys` evaluated at `(q, u)`, its frames left there);
    /// nothing for a model without regularized contacts.
    #[allow(clippy::too_many_arguments)]
    pub fn add_contact_tangents(
        &mut self,
        model: &Model,
        q: &[f64],
        u: &[f64],
        sys: &mut SystemBuffers,
        work: &mut crate::contact::ContactWork,
        c_q: f64,
        c_u: f64,
    ) {
        let all = model
            .contacts
            .iter()
            .zip(&mut work.sides)
            .zip(&work.start_gap);
        for (k, ((c, w), &g0)) in all.enumerate() {
            if c.law.set_valued_normal() {
                continue;
            }
            match &mut self.backend {
                Backend::Dense(d) => {
                    let mut sink = dense::MatrixSink::new(&mut d.lu.a, -c_q, -c_u);
                    crate::system::add_contact_tangent(model, c, q, u, sys, w, g0, &mut sink);
                }
                Backend::Sparse(s) => {
                    s.add_contact_tangent(k, model, (q, u), sys, w, g0, -c_q, -c_u)
                }
            }
        }
    }

    /// Factors the last built matrix; `false` if it is numerically singular or not finite.
    pub fn factor(&mut self) -> bool {
        match &mut self.backend {
            Backend::Dense(d) => d.lu.factor(),
            Backend::Sparse(s) => s.factor(),
        }
    }

    /// Solves with the last factorization; `b` (length `nu + nc`) is overwritten by `x`.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        match &mut self.backend {
            Backend::Dense(d) => d.lu.solve_in_place(b),
            Backend::Sparse(s) => s.solve_in_place(b),
        }
    }

    /// `out = M(q) v` (global block-diagonal mass), element by element, from the elements
    /// evaluated at `q` in `sys` ([`crate::system::evaluate`]).
    pub fn mass_times_vector(
        &mut self,
        model: &Model,
        q: &[f64],
        v: &[f64],
        sys: &mut SystemBuffers,
        out: &mut [f64],
    ) {
        match &mut self.backend {
            Backend::Dense(_) => crate::system::mass_times_vector(
                model,
                q,
                v,
                &mut sys.eval,
                sys.mass.as_mut(),
                out,
                &mut sys.local,
            ),
            Backend::Sparse(s) => s.mass_times_vector(model, q, v, &mut sys.eval, out),
        }
    }

    /// Constraint drift `(max |g|, max |G u + g_t|)` with the current `sys` (dense backend:
    /// [`crate::system::constraint_drift`]; sparse: over the pattern of `G`).
    pub fn constraint_drift(&self, sys: &SystemBuffers, u: &[f64]) -> (f64, f64) {
        match &self.backend {
            Backend::Dense(_) => crate::system::constraint_drift(sys, u),
            Backend::Sparse(s) => s.constraint_drift(sys, u),
        }
    }

    /// `out += G^T lambda` with the current `sys.g_jac` (column by column, rows in order).
    pub fn add_g_transpose_times(&self, sys: &SystemBuffers, lambda: &[f64], out: &mut [f64]) {
        match &self.backend {
            Backend::Dense(_) => {
                for (i, r) in out.iter_mut().enumerate() {
                    for (g, l) in sys.g_jac.col_as_slice(i).iter().zip(lambda) {
                        *r += g * l;
                    }
                }
            }
            Backend::Sparse(s) => s.add_g_transpose_times(sys, lambda, out),
        }
    }
}

//! Sparse backend: the saddle matrix in compressed columns on the fixed [`SystemPattern`],
//! factored by faer's sparse LU (COLAMD column ordering, partial pivoting; the matrix is not
//! symmetric). Symbolic analysis and a first numeric factorization (which sizes faer's factor
//! buffers) happen in [`SparseSystem::new`]; every block is written through slot maps.

use super::blocks::{CouplingSlots, ElementBlock};
use super::pattern::{ColumnLists, SystemPattern};
use super::SaddleKind;
use crate::element::ElementScratch;
use crate::model::Model;
use crate::state::SystemBuffers;
use crate::system;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::lu::{
    factorize_symbolic_lu, LuRef, LuSymbolicParams, NumericLu, SymbolicLu,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par};

/// Sparse saddle matrix, its LU and the slot maps of every block.
pub(super) struct SparseSystem {
    nu: usize,
    pattern: SymbolicSparseColMat<usize>,
    values: Vec<f64>,
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    mem: MemBuffer,
    /// Solution of the singularity probe of [`Self::factor`].
    probe: Vec<f64>,
    elements: Vec<ElementBlock>,
    loads: Vec<CouplingSlots>,
    joints: Vec<CouplingSlots>,
    /// Per contact: the coupling block of its two owners (regularized contacts' tangents).
    contacts: Vec<CouplingSlots>,
    /// Per constraint row `r`, entries `g_ptr[r]..g_ptr[r + 1]` of `g_entries`.
    g_ptr: Vec<usize>,
    /// `(column c, slot of (nu + r, c), slot of (c, nu + r))`.
    g_entries: Vec<(usize, usize, usize)>,
    /// Slots of the diagonal of the `nu x nu` block.
    diag_slots: Vec<usize>,
}

impl std::fmt::Debug for SparseSystem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseSystem")
            .field("dim", &self.dim())
            .field("nnz", &self.values.len())
            .finish()
    }
}

impl SparseSystem {
    /// Pattern, slot maps, symbolic LU and one numeric factorization for `model`.
    pub(super) fn new(model: &Model, lists: &ColumnLists, p: &SystemPattern) -> Self {
        let n = p.dim();
        let elements = model
            .bodies
            .iter()
            .zip(&lists.elements)
            .map(|(b, cols)| ElementBlock::new(b, p.block_slots(cols)))
            .collect();
        let coupling = |cols: &Vec<usize>| CouplingSlots::new(cols.clone(), p.block_slots(cols));
        let loads = lists.loads.iter().map(coupling).collect();
        let joints = model
            .joint_rows
            .iter()
            .map(|&r0| coupling(lists.constraint_rows.get(r0).unwrap_or(&Vec::new())))
            .collect();
        let contacts = lists.contacts.iter().map(coupling).collect();
        let mut g_ptr = vec![0];
        let mut g_entries = Vec::new();
        for (r, cols) in lists.constraint_rows.iter().enumerate() {
            for &c in cols {
                let lower = p.slot(p.nu + r, c).expect("G in pattern");
                let upper = p.slot(c, p.nu + r).expect("G^T in pattern");
                g_entries.push((c, lower, upper));
            }
            g_ptr.push(g_entries.len());
        }
        let diag_slots = (0..p.nu).map(|i| p.slot(i, i).expect("diagonal")).collect();
        let nnz = p.nnz();
        let pattern =
            SymbolicSparseColMat::new_checked(n, n, p.col_ptr.clone(), None, p.row_idx.clone());
        let symbolic = factorize_symbolic_lu(pattern.as_ref(), LuSymbolicParams::default())
            .expect("symbolic LU of the system pattern");
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        let mut this = Self {
            nu: p.nu,
            pattern,
            values: vec![0.0; nnz],
            symbolic,
            numeric: NumericLu::new(),
            mem: MemBuffer::new(req),
            probe: vec![0.0; n],
            elements,
            loads,
            joints,
            contacts,
            g_ptr,
            g_entries,
            diag_slots,
        };
        this.size_factor_buffers(p);
        this
    }

    /// Numeric factorizations of generic matrices on the pattern (diagonally dominant `A`,
    /// pseudo-random entries elsewhere), so that faer sizes its factor buffers here and not in
    /// a time step.
    fn size_factor_buffers(&mut self, p: &SystemPattern) {
        for seed in [1usize, 7] {
            for j in 0..p.dim() {
                for k in p.col_ptr[j]..p.col_ptr[j + 1] {
                    let i = p.row_idx[k];
                    let x = ((i * 31 + j * 17 + seed * 13) % 23) as f64 / 23.0 - 0.5;
                    self.values[k] = if i == j && i < p.nu {
                        1.0 + p.dim() as f64
                    } else {
                        x
                    };
                }
            }
            self.factor();
        }
        self.values.fill(0.0);
    }

    /// Adds `c_q dh_c/dq + c_u dh_c/du` of contact `k` (regularized, `c`) into the coupling
    /// block of its owners ([`super::SystemMatrix::add_contact_tangents`]).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn add_contact_tangent(
        &mut self,
        k: usize,
        model: &Model,
        (q, u): (&[f64], &[f64]),
        sys: &mut SystemBuffers,
        work: &mut [crate::contact::ContourScratch; 2],
        start_gap: f64,
        c_q: f64,
        c_u: f64,
    ) {
        let c = &model.contacts[k];
        let mut sink = self.contacts[k].sink(&mut self.values, c_q, c_u);
        system::add_contact_tangent(model, c, q, u, sys, work, start_gap, &mut sink);
    }

    /// Dimension `nu + nc`.
    pub(super) fn dim(&self) -> usize {
        self.probe.len()
    }

    /// Builds the matrix `kind` (see [`super::SystemMatrix::build`]).
    pub(super) fn build(
        &mut self,
        kind: SaddleKind,
        model: &Model,
        q: &[f64],
        u: &[f64],
        lambda: &[f64],
        sys: &mut SystemBuffers,
    ) {
        self.values.fill(0.0);
        let v = &mut self.values;
        match kind {
            SaddleKind::AugmentedMass => {
                let blocks = model.bodies.iter().zip(&mut self.elements);
                for ((b, blk), e) in blocks.zip(&mut sys.eval) {
                    blk.compute_mass(b, q, e);
                    blk.scatter(v, |m, _, _| m);
                }
            }
            SaddleKind::Iteration { t, c_u, c_q } => {
                let g = model.gravity;
                let scratches = sys.tangent_scratch.iter_mut().zip(&mut sys.eval);
                let blocks = model.bodies.iter().zip(&mut self.elements);
                for ((b, blk), (scratch, e)) in blocks.zip(scratches) {
                    blk.compute_mass(b, q, e);
                    blk.compute_tangents(b, t, q, u, &g, e, scratch);
                    blk.scatter(v, |m, kq, ku| m - c_u * ku - c_q * kq);
                }
                for (load, blk) in model.loads.iter().zip(&self.loads) {
                    let mut sink = blk.sink(v, -c_q, -c_u);
                    system::add_one_load_tangent(model, load, t, q, u, 1.0, sys, &mut sink);
                }
            }
            SaddleKind::LeastSquares => {
                for &s in &self.diag_slots {
                    v[s] = 1.0;
                }
            }
            SaddleKind::StaticTangent { t, mu } => {
                let g = model.gravity * mu;
                let scratches = sys.tangent_scratch.iter_mut().zip(&mut sys.eval);
                let blocks = model.bodies.iter().zip(&mut self.elements);
                for ((b, blk), (scratch, e)) in blocks.zip(scratches) {
                    blk.compute_tangents(b, t, q, u, &g, e, scratch);
                    blk.scatter(v, |_, kq, _| -kq);
                }
                // A = -dh/dq + d(G^T lambda)/dq: the local tangents add `-d/dq` of the loads
                // and `-d(G^T lambda)/dq`, both enter with the factor -1
                for (load, blk) in model.loads.iter().zip(&self.loads) {
                    let mut sink = blk.sink(v, -1.0, 0.0);
                    system::add_one_load_tangent(model, load, t, q, u, mu, sys, &mut sink);
                }
                for ((joint, &r0), blk) in
                    model.joints.iter().zip(&model.joint_rows).zip(&self.joints)
                {
                    let lam = &lambda[r0..r0 + joint.num_rows()];
                    let mut sink = blk.sink(v, -1.0, 0.0);
                    system::subtract_one_constraint_force_tangent(
                        model, joint, t, q, u, lam, sys, &mut sink,
                    );
                }
            }
        }
        for r in 0..self.g_ptr.len() - 1 {
            for &(c, lower, upper) in &self.g_entries[self.g_ptr[r]..self.g_ptr[r + 1]] {
                let x = sys.g_jac[(r, c)];
                v[lower] = x;
                v[upper] = x;
            }
        }
    }

    /// Numeric LU of the current values; `false` if a value is not finite, a pivot is
    /// structurally or exactly zero, or the solution of a probe system is not finite.
    pub(super) fn factor(&mut self) -> bool {
        if self.values.iter().any(|x| !x.is_finite()) {
            return false;
        }
        let a = SparseColMatRef::new(self.pattern.as_ref(), &self.values);
        let ok = self
            .symbolic
            .factorize_numeric_lu(
                &mut self.numeric,
                a,
                Par::Seq,
                MemStack::new(&mut self.mem),
                Default::default(),
            )
            .is_ok();
        if !ok {
            return false;
        }
        let mut probe = std::mem::take(&mut self.probe);
        probe.fill(1.0);
        self.solve_in_place(&mut probe);
        let finite = probe.iter().all(|x| x.is_finite());
        self.probe = probe;
        finite
    }

    /// Solves with the last factorization; `b` is overwritten by the solution.
    pub(super) fn solve_in_place(&mut self, b: &mut [f64]) {
        let n = b.len();
        if n == 0 {
            return;
        }
        let lu = LuRef::new_unchecked(&self.symbolic, &self.numeric);
        lu.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(b, n, 1),
            Par::Seq,
            MemStack::new(&mut self.mem),
        );
    }

    /// `out = M(q) v`, element by element, accumulated (bodies on a shared node overlap; the
    /// element mass blocks are the scratch).
    pub(super) fn mass_times_vector(
        &mut self,
        model: &Model,
        q: &[f64],
        v: &[f64],
        eval: &mut [ElementScratch],
        out: &mut [f64],
    ) {
        out.fill(0.0);
        let blocks = model.bodies.iter().zip(&mut self.elements);
        for ((b, blk), e) in blocks.zip(eval.iter_mut()) {
            blk.add_mass_times_vector(b, q, e, v, out);
        }
    }

    /// `(max |g|, max |G u + g_t|)` over the pattern of `G`.
    pub(super) fn constraint_drift(&self, sys: &SystemBuffers, u: &[f64]) -> (f64, f64) {
        let (mut g_max, mut gd_max) = (0.0_f64, 0.0_f64);
        for r in 0..self.g_ptr.len() - 1 {
            let mut gd = sys.g_t[r];
            for &(c, _, _) in &self.g_entries[self.g_ptr[r]..self.g_ptr[r + 1]] {
                gd += sys.g_jac[(r, c)] * u[c];
            }
            g_max = g_max.max(sys.g[r].abs());
            gd_max = gd_max.max(gd.abs());
        }
        (g_max, gd_max)
    }

    /// `out += G^T lambda` over the pattern of `G`.
    pub(super) fn add_g_transpose_times(
        &self,
        sys: &SystemBuffers,
        lambda: &[f64],
        out: &mut [f64],
    ) {
        debug_assert_eq!(out.len(), self.nu);
        for (r, l) in lambda.iter().enumerate() {
            for &(c, _, _) in &self.g_entries[self.g_ptr[r]..self.g_ptr[r + 1]] {
                out[c] += sys.g_jac[(r, c)] * l;
            }
        }
    }
}

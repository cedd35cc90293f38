//! Blocks of the sparse backend and their slot maps: element blocks (mass and force tangents
//! on the element's columns, computed locally and added: blocks of bodies on a shared node add
//! into the same slots) and coupling blocks (the slots over the columns of the owners of a
//! load's or joint's frames, a [`TangentSink`] for the local tangents of
//! `crate::system::local_tangent`, the one finite-difference implementation).

use crate::element::{ElementScratch, TangentScratch};
use crate::gather::{with_local, with_local_q};
use crate::model::Body;
use crate::state::SystemBuffers;
use crate::system::TangentSink;
use faer::Mat;
use nalgebra::Vector3;

/// An element's local `nu_e x nu_e` blocks and their slots (column-major).
pub(super) struct ElementBlock {
    slots: Vec<usize>,
    mass: Mat<f64>,
    dh_dq: Mat<f64>,
    dh_du: Mat<f64>,
    /// Local mass-vector product.
    h: Vec<f64>,
}

impl ElementBlock {
    /// Blocks of `body` written to `slots`.
    pub(super) fn new(body: &Body, slots: Vec<usize>) -> Self {
        let n = body.element.nu();
        Self {
            slots,
            mass: Mat::zeros(n, n),
            dh_dq: Mat::zeros(n, n),
            dh_du: Mat::zeros(n, n),
            h: vec![0.0; n],
        }
    }

    /// Element mass matrix at `q` (the element evaluated there in `eval`).
    pub(super) fn compute_mass(&mut self, body: &Body, q: &[f64], eval: &mut ElementScratch) {
        let m = self.mass.as_mut();
        with_local_q(body, q, eval, |qb, e| body.element.mass_matrix(qb, e, m));
    }

    /// Element force tangents at `(t, q, u)` with gravity `g` (the element evaluated there in
    /// `eval`).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn compute_tangents(
        &mut self,
        body: &Body,
        t: f64,
        q: &[f64],
        u: &[f64],
        g: &Vector3<f64>,
        eval: &mut ElementScratch,
        scratch: &mut TangentScratch,
    ) {
        self.dh_dq.fill(0.0);
        self.dh_du.fill(0.0);
        let (dq, du) = (self.dh_dq.as_mut(), self.dh_du.as_mut());
        with_local(body, q, u, eval, |qb, ub, e| {
            body.element
                .force_tangents(t, qb, ub, g, e, dq, du, scratch)
        });
    }

    /// `values[slot(i, j)] += f(M_ij, dh/dq_ij, dh/du_ij)` over the block.
    pub(super) fn scatter(&self, values: &mut [f64], f: impl Fn(f64, f64, f64) -> f64) {
        let n = self.mass.nrows();
        for j in 0..n {
            let (m, kq, ku) = (
                self.mass.col_as_slice(j),
                self.dh_dq.col_as_slice(j),
                self.dh_du.col_as_slice(j),
            );
            let slots = &self.slots[j * n..(j + 1) * n];
            for i in 0..n {
                values[slots[i]] += f(m[i], kq[i], ku[i]);
            }
        }
    }

    /// `out[cols] += M_e v[cols]` (the mass block is the element's scratch).
    pub(super) fn add_mass_times_vector(
        &mut self,
        body: &Body,
        q: &[f64],
        eval: &mut ElementScratch,
        v: &[f64],
        out: &mut [f64],
    ) {
        let (m, h) = (self.mass.as_mut(), &mut self.h);
        with_local(body, q, v, eval, |qb, vb, e| {
            body.element.mass_times_vector(qb, e, vb, m, h)
        });
        body.dofs().u.scatter_add(&self.h, out);
    }
}

/// The slots of a coupling block: all to all over `cols` (the sorted global columns of the
/// owners of a load's or joint's frames), column-major.
pub(super) struct CouplingSlots {
    cols: Vec<usize>,
    slots: Vec<usize>,
}

impl CouplingSlots {
    /// Slots `slots` of the block over `cols`.
    pub(super) fn new(cols: Vec<usize>, slots: Vec<usize>) -> Self {
        Self { cols, slots }
    }

    /// A sink adding `c_q` times the `d/dq` entries and `c_u` times the `d/du` entries into
    /// `values`.
    pub(super) fn sink<'a>(&'a self, values: &'a mut [f64], c_q: f64, c_u: f64) -> SlotSink<'a> {
        SlotSink {
            block: self,
            values,
            c_q,
            c_u,
        }
    }
}

/// [`TangentSink`] into the compressed-column values of the sparse saddle matrix.
pub(super) struct SlotSink<'a> {
    block: &'a CouplingSlots,
    values: &'a mut [f64],
    c_q: f64,
    c_u: f64,
}

impl TangentSink for SlotSink<'_> {
    fn add(&mut self, _: &mut SystemBuffers, row: usize, col: usize, velocity: bool, value: f64) {
        let cols = &self.block.cols;
        // rows and columns of a local tangent are the owners' columns, all in `cols`
        if let (Ok(i), Ok(j)) = (cols.binary_search(&row), cols.binary_search(&col)) {
            let c = if velocity { self.c_u } else { self.c_q };
            self.values[self.block.slots[j * cols.len() + i]] += c * value;
        } else {
            debug_assert!(false, "tangent entry ({row}, {col}) outside its block");
        }
    }
}

//! Gather and scatter between the global coordinate vectors and element-local slices.
//!
//! A body whose nodes are consecutive in the global layout reads its coordinates as one slice
//! of `q` / `u` (zero copy). A body whose nodes are not (a ring closed onto its first node, a
//! chain whose nodes were added out of order, a superelement starting at an existing interface
//! point) is *scattered*: its element-local `q`, `u` are gathered through its [`DofMap`]s into
//! buffers held next to its evaluated state ([`ElementScratch`]), the element runs on them, and
//! its blocks (forces, mass, tangents, Jacobian columns) are scatter-added through the same maps.

use crate::element::{Element, ElementScratch};
use crate::model::Body;
use crate::node::DofMap;
use faer::{Mat, MatMut};

/// Element-local copies of a scattered body's coordinates (empty for contiguous bodies: never
/// used). Sized on first use, or up front by the workspace ([`ElementScratch::reserve_local`]),
/// so that no time step allocates.
#[derive(Debug, Default)]
pub(crate) struct LocalCoordinates {
    /// Gathered positions (nq).
    pub(crate) q: Vec<f64>,
    /// Gathered velocities, or any other velocity-space vector (nu).
    pub(crate) u: Vec<f64>,
}

impl ElementScratch {
    /// Sizes the gather buffers for an element with `nq`, `nu` coordinates (the workspace does
    /// this for scattered bodies, so that gathering never allocates in a step).
    pub fn reserve_local(&mut self, nq: usize, nu: usize) {
        let l = self.local_mut();
        l.q.resize(nq, 0.0);
        l.u.resize(nu, 0.0);
    }
}

impl DofMap {
    /// `out = x[map]` (element-local order); resizes `out` to the map's length.
    pub(crate) fn gather_into(&self, x: &[f64], out: &mut Vec<f64>) {
        out.resize(self.len(), 0.0);
        for (o, g) in out.iter_mut().zip(self.iter()) {
            *o = x[g];
        }
    }

    /// `x[map] = local`.
    pub(crate) fn scatter_into(&self, local: &[f64], x: &mut [f64]) {
        for (l, g) in local.iter().zip(self.iter()) {
            x[g] = *l;
        }
    }

    /// `x[map] += local`.
    pub(crate) fn scatter_add(&self, local: &[f64], x: &mut [f64]) {
        match self {
            DofMap::Contiguous(r) => {
                for (xi, l) in x[r.clone()].iter_mut().zip(local) {
                    *xi += l;
                }
            }
            DofMap::Scattered(v) => {
                for (l, &g) in local.iter().zip(v) {
                    x[g] += l;
                }
            }
        }
    }

    /// `m[map, map] += block` (column by column).
    pub(crate) fn scatter_add_block(&self, mut m: MatMut<'_, f64>, block: &Mat<f64>) {
        match self {
            DofMap::Contiguous(r) => {
                let o = r.start;
                for j in 0..block.ncols() {
                    for i in 0..block.nrows() {
                        m[(o + i, o + j)] += block[(i, j)];
                    }
                }
            }
            DofMap::Scattered(v) => {
                for (j, &gj) in v.iter().enumerate().take(block.ncols()) {
                    for (i, &gi) in v.iter().enumerate().take(block.nrows()) {
                        m[(gi, gj)] += block[(i, j)];
                    }
                }
            }
        }
    }
}

/// `x[map]` as a slice: the range itself for a contiguous map (zero copy), else gathered into
/// `buf`.
pub(crate) fn gathered<'a>(map: &DofMap, x: &'a [f64], buf: &'a mut Vec<f64>) -> &'a [f64] {
    match map {
        DofMap::Contiguous(r) => &x[r.clone()],
        DofMap::Scattered(_) => {
            map.gather_into(x, buf);
            buf
        }
    }
}

/// Runs `f` on the element-local `q` (through the body's `q` map) and velocity-space vector `v`
/// (through its `u` map: `u`, or e.g. a vector to multiply by the mass) with the body's scratch
/// `e`: slices of the globals for a contiguous body, copies gathered into `e`'s buffers for a
/// scattered one. No allocation once the buffers are sized.
pub(crate) fn with_local<R>(
    body: &Body,
    q: &[f64],
    v: &[f64],
    e: &mut ElementScratch,
    f: impl FnOnce(&[f64], &[f64], &mut ElementScratch) -> R,
) -> R {
    if !body.is_scattered() {
        let (oq, ou) = (body.q_offset, body.u_offset);
        let (nq, nu) = (body.element.nq(), body.element.nu());
        return f(&q[oq..oq + nq], &v[ou..ou + nu], e);
    }
    let mut l = std::mem::take(e.local_mut());
    let dofs = body.dofs();
    dofs.q.gather_into(q, &mut l.q);
    dofs.u.gather_into(v, &mut l.u);
    let r = f(&l.q, &l.u, e);
    *e.local_mut() = l;
    r
}

/// [`with_local`] for queries of `q` alone.
pub(crate) fn with_local_q<R>(
    body: &Body,
    q: &[f64],
    e: &mut ElementScratch,
    f: impl FnOnce(&[f64], &mut ElementScratch) -> R,
) -> R {
    if !body.is_scattered() {
        let oq = body.q_offset;
        return f(&q[oq..oq + body.element.nq()], e);
    }
    let mut l = std::mem::take(e.local_mut());
    body.dofs().q.gather_into(q, &mut l.q);
    let r = f(&l.q, e);
    *e.local_mut() = l;
    r
}

/// Checks an element for a scattered coordinate map at compile time: everything of the engine
/// gathers and scatters except the node-load stiffening of FFR bodies, which reads its body's
/// coordinates in place (an FFR body created by `add_body` is always contiguous).
pub(crate) fn check_scattered_element(element: &dyn Element) -> Result<(), String> {
    if element
        .load_stiffened_ffr()
        .is_some_and(|b| b.load_stiffening().is_some())
    {
        return Err(
            "an FFR body with node-load stiffening must have consecutive nodes (its \
                    coordinates are scattered in the global vectors)"
                .into(),
        );
    }
    Ok(())
}

impl crate::Model {
    /// Element blocks are accumulated (bodies share nodes) or gathered and scatter-added (a
    /// body's coordinates are scattered): the general assembly path; otherwise each body
    /// overwrites its own diagonal block, zero copy.
    pub(crate) fn general_layout(&self) -> bool {
        self.shared_nodes || self.scattered
    }

    /// Element-local coordinates `(q, u)` of one body in global vectors: slices for a body whose
    /// coordinates are contiguous, gathered copies for a scattered one ([`Body::is_scattered`]).
    ///
    /// # Panics
    /// If `body` belongs to another model or a vector is shorter than this model's.
    pub fn body_coordinates<'a>(
        &self,
        body: crate::BodyId,
        q: &'a [f64],
        u: &'a [f64],
    ) -> (std::borrow::Cow<'a, [f64]>, std::borrow::Cow<'a, [f64]>) {
        let b = &self.bodies[body.0];
        let local = |map: &crate::node::DofMap, x: &'a [f64]| match map.as_range() {
            Some(r) => std::borrow::Cow::Borrowed(&x[r]),
            None => std::borrow::Cow::Owned(map.iter().map(|g| x[g]).collect()),
        };
        (local(&b.dofs().q, q), local(&b.dofs().u, u))
    }

    /// The contiguous range of a body's coordinates.
    ///
    /// # Panics
    /// If the body's coordinates are scattered (use [`Self::body_coordinates`] or
    /// [`Self::body_dofs`]).
    pub(crate) fn contiguous(&self, body: crate::BodyId) -> (&Body, usize, usize) {
        let b = &self.bodies[body.0];
        assert!(
            !b.is_scattered(),
            "body `{}` has scattered coordinates: use Model::body_coordinates or body_dofs",
            b.name
        );
        (b, b.q_offset, b.u_offset)
    }
}

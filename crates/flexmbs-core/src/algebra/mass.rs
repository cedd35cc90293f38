//! The mass matrix alone, factored per diagonal block by Cholesky: `M` is block diagonal, one
//! block per element, or, with shared nodes, per group of elements whose coordinates overlap (the
//! union of their contiguous ranges, the elements' matrices added), so `M^-1 B` for `k`
//! right-hand sides costs one triangular pair per block and column. A block is refactored only
//! when its mass changed (compared bitwise with the factored one: a rigid body in body-fixed
//! velocities factors once).

use crate::element::ElementScratch;
use crate::linsolve::{cholesky_in_place, cholesky_solve_in_place};
use crate::model::Model;
use faer::Mat;

/// Per-block Cholesky factors of the mass matrix (for explicit integration, consistent
/// accelerations and `M^-1 W` of a velocity-level stepper).
#[derive(Debug)]
pub struct BlockMass {
    blocks: Vec<MassBlock>,
    refactored: usize,
}

#[derive(Debug)]
struct MassBlock {
    offset: usize,
    /// The bodies of the block (one unless they share nodes), with their element mass scratch
    /// (empty for a single body: its mass is evaluated into `current` directly).
    bodies: Vec<(usize, Mat<f64>)>,
    /// The mass matrix that `factor` belongs to (NaN: none yet).
    factored: Mat<f64>,
    /// Lower Cholesky factor.
    factor: Mat<f64>,
    /// The block's current mass matrix.
    current: Mat<f64>,
}

/// The bodies grouped by overlapping velocity ranges (each body's range is contiguous; sorted
/// by start, a group is a run of ranges each overlapping the union of those before):
/// `(first column, columns, bodies)` per group.
fn overlapping_groups(model: &Model) -> Vec<(usize, usize, Vec<usize>)> {
    let mut order: Vec<usize> = (0..model.bodies.len()).collect();
    order.sort_by_key(|&i| model.bodies[i].u_offset);
    let mut groups: Vec<(usize, usize, Vec<usize>)> = Vec::new();
    for i in order {
        let b = &model.bodies[i];
        let (o, n) = (b.u_offset, b.element.nu());
        match groups.last_mut() {
            Some((start, len, members)) if o < *start + *len => {
                *len = (*len).max(o + n - *start);
                members.push(i);
            }
            _ => groups.push((o, n, vec![i])),
        }
    }
    groups
}

impl BlockMass {
    /// Buffers for `model` (nothing factored yet).
    pub fn new(model: &Model) -> Self {
        let blocks = overlapping_groups(model)
            .into_iter()
            .map(|(offset, n, members)| {
                let scratch = |b: usize| {
                    let m = model.bodies[b].element.nu();
                    Mat::zeros(m, m)
                };
                let bodies = if members.len() == 1 {
                    vec![(members[0], Mat::zeros(0, 0))]
                } else {
                    members.iter().map(|&b| (b, scratch(b))).collect()
                };
                MassBlock {
                    offset,
                    bodies,
                    factored: Mat::from_fn(n, n, |_, _| f64::NAN),
                    factor: Mat::zeros(n, n),
                    current: Mat::zeros(n, n),
                }
            })
            .collect();
        Self {
            blocks,
            refactored: 0,
        }
    }

    /// Evaluates every block's mass matrix at `q` (the elements evaluated there in `eval`, one
    /// scratch per body) and refactors the blocks that changed.
    /// `Err(body index)` (the block's first body) if a block is not numerically positive
    /// definite.
    pub fn update(
        &mut self,
        model: &Model,
        q: &[f64],
        eval: &mut [ElementScratch],
    ) -> Result<(), usize> {
        for blk in &mut self.blocks {
            blk.evaluate(model, q, eval);
            let same = (0..blk.current.ncols()).all(|j| {
                blk.current
                    .col_as_slice(j)
                    .iter()
                    .zip(blk.factored.col_as_slice(j))
                    .all(|(a, b)| a.to_bits() == b.to_bits())
            });
            if same {
                continue;
            }
            blk.factored.copy_from(&blk.current);
            blk.factor.copy_from(&blk.current);
            self.refactored += 1;
            if !cholesky_in_place(&mut blk.factor) {
                blk.factored.fill(f64::NAN);
                return Err(blk.bodies[0].0);
            }
        }
        Ok(())
    }

    /// Solves `M X = B` in place for `k` right-hand sides: `b` holds `B` column-major
    /// (`nu x k`) and is overwritten by `X`.
    pub fn solve_in_place(&self, b: &mut [f64], k: usize) {
        let nu = b.len().checked_div(k).unwrap_or(0);
        debug_assert_eq!(nu * k, b.len(), "right-hand sides nu x k");
        for col in b.chunks_exact_mut(nu.max(1)).take(k) {
            for blk in &self.blocks {
                let n = blk.factor.nrows();
                cholesky_solve_in_place(&blk.factor, &mut col[blk.offset..blk.offset + n]);
            }
        }
    }

    /// Block factorizations done so far (a statistic: constant-mass elements factor once).
    pub fn refactorizations(&self) -> usize {
        self.refactored
    }
}

impl MassBlock {
    /// `current` = the block's mass at `q`: one element's matrix, or the sum of its elements'.
    fn evaluate(&mut self, model: &Model, q: &[f64], eval: &mut [ElementScratch]) {
        if let [(i, _)] = self.bodies[..] {
            let b = &model.bodies[i];
            let oq = b.q_offset;
            let (qb, e) = (&q[oq..oq + b.element.nq()], &mut eval[i]);
            b.element.mass_matrix(qb, e, self.current.as_mut());
            return;
        }
        self.current.fill(0.0);
        for (i, m) in &mut self.bodies {
            let b = &model.bodies[*i];
            let (oq, o) = (b.q_offset, b.u_offset - self.offset);
            let (qb, e) = (&q[oq..oq + b.element.nq()], &mut eval[*i]);
            b.element.mass_matrix(qb, e, m.as_mut());
            for j in 0..m.ncols() {
                for i in 0..m.nrows() {
                    self.current[(o + i, o + j)] += m[(i, j)];
                }
            }
        }
    }
}

//! The mass matrix alone, factored per element block by Cholesky: `M` is block diagonal (one
//! block per element), so `M^-1 B` for `k` right-hand sides costs one triangular pair per
//! block and column. A block is refactored only when its element's mass changed (compared
//! bitwise with the factored one: a rigid body in body-fixed velocities factors once).

use crate::linsolve::{cholesky_in_place, cholesky_solve_in_place};
use crate::model::Model;
use faer::Mat;

/// Per-element Cholesky factors of the mass matrix (for explicit integration, consistent
/// accelerations and `M^-1 W` of a velocity-level stepper).
#[derive(Debug)]
pub struct BlockMass {
    blocks: Vec<MassBlock>,
    refactored: usize,
}

#[derive(Debug)]
struct MassBlock {
    offset: usize,
    /// The mass matrix that `factor` belongs to (NaN: none yet).
    factored: Mat<f64>,
    /// Lower Cholesky factor.
    factor: Mat<f64>,
    /// The element's current mass matrix.
    current: Mat<f64>,
}

impl BlockMass {
    /// Buffers for `model` (nothing factored yet).
    pub fn new(model: &Model) -> Self {
        let blocks = model
            .bodies
            .iter()
            .map(|b| {
                let n = b.element.nu();
                MassBlock {
                    offset: b.u_offset,
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

    /// Evaluates every element's mass matrix at `q` and refactors the blocks that changed.
    /// `Err(body index)` if a block is not numerically positive definite.
    pub fn update(&mut self, model: &Model, q: &[f64]) -> Result<(), usize> {
        for (i, (b, blk)) in model.bodies.iter().zip(&mut self.blocks).enumerate() {
            let oq = b.q_offset;
            b.element
                .mass_matrix(&q[oq..oq + b.element.nq()], blk.current.as_mut());
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
                return Err(i);
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

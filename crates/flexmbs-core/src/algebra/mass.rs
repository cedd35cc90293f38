//! The mass matrix alone, factored per diagonal block by Cholesky: `M` is block diagonal, one
//! block per element, or, with shared nodes, per group of elements whose coordinates overlap (the
//! union of their columns, the elements' matrices added; a block's columns may be scattered in
//! `u`: it is then solved through its column list), so `M^-1 B` for `k`
//! right-hand sides costs one triangular pair per block and column. A block is refactored only
//! when its mass changed (compared bitwise with the factored one: a rigid body in body-fixed
//! velocities factors once).

use super::schur::SchurMass;
use crate::element::ElementScratch;
use crate::gather::with_local_q;
use crate::linsolve::{cholesky_in_place, cholesky_solve_in_place};
use crate::model::Model;
use crate::node::DofMap;
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
    /// Global columns of the block in block order (a single body's: its own map).
    cols: DofMap,
    /// The bodies of the block (one unless they share nodes), with their element mass scratch
    /// (empty for a single body: its mass is evaluated into `current` directly) and the block
    /// index of each of their local coordinates.
    bodies: Vec<(usize, Mat<f64>, Vec<usize>)>,
    /// The mass matrix that `factor` belongs to (NaN: none yet).
    factored: Mat<f64>,
    /// Lower Cholesky factor.
    factor: Mat<f64>,
    /// The block's current mass matrix.
    current: Mat<f64>,
    /// A single contiguous body with a constant trailing mass block
    /// ([`crate::Element::constant_mass_tail`]): factored through its Schur complement
    /// (`schur.rs`) instead of `factor`.
    schur: Option<SchurMass>,
}

/// The bodies grouped by shared velocity columns (connected components: bodies that share a
/// node, directly or through others), ordered by their first column, members by their first
/// column: `(columns, bodies)` per group, the columns sorted, or a single body's own map.
fn overlapping_groups(model: &Model) -> Vec<(DofMap, Vec<usize>)> {
    let n_bodies = model.bodies.len();
    let first = |i: usize| model.bodies[i].dofs().u.iter().min().unwrap_or(0);
    let mut order: Vec<usize> = (0..n_bodies).collect();
    order.sort_by_key(|&i| first(i));
    // union-find over bodies through the first body seen at each column
    let mut parent: Vec<usize> = (0..n_bodies).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut col_owner = vec![usize::MAX; model.nu];
    for &i in &order {
        for c in model.bodies[i].dofs().u.iter() {
            if col_owner[c] == usize::MAX {
                col_owner[c] = i;
            } else {
                let (a, b) = (root(&mut parent, i), root(&mut parent, col_owner[c]));
                parent[a.max(b)] = a.min(b);
            }
        }
    }
    let mut groups: Vec<(usize, Vec<usize>)> = Vec::new();
    for &i in &order {
        let r = root(&mut parent, i);
        match groups.iter_mut().find(|(g, _)| *g == r) {
            Some((_, members)) => members.push(i),
            None => groups.push((r, vec![i])),
        }
    }
    groups
        .into_iter()
        .map(|(_, members)| {
            if let [b] = members[..] {
                return (model.bodies[b].dofs().u.clone(), members);
            }
            let mut cols: Vec<usize> = members
                .iter()
                .flat_map(|&b| model.bodies[b].dofs().u.iter())
                .collect();
            cols.sort_unstable();
            cols.dedup();
            let contiguous = cols.windows(2).all(|w| w[1] == w[0] + 1);
            let map = match (contiguous, cols.first()) {
                (true, Some(&a)) => DofMap::Contiguous(a..a + cols.len()),
                _ => DofMap::Scattered(cols),
            };
            (map, members)
        })
        .collect()
}

impl BlockMass {
    /// Buffers for `model` (nothing factored yet).
    pub fn new(model: &Model) -> Self {
        let blocks = overlapping_groups(model)
            .into_iter()
            .map(|(cols, members)| {
                let n = cols.len();
                let scratch = |b: usize| {
                    let m = model.bodies[b].element.nu();
                    Mat::zeros(m, m)
                };
                let block_index = |b: usize| {
                    let block: Vec<usize> = cols.iter().collect();
                    let local = model.bodies[b].dofs().u.iter();
                    local
                        .map(|g| block.binary_search(&g).expect("column in its block"))
                        .collect()
                };
                let schur = match (&cols, &members[..]) {
                    (DofMap::Contiguous(_), [b]) => {
                        let nc = model.bodies[*b].element.constant_mass_tail();
                        (nc > 0 && nc < n).then(|| SchurMass::new(n, nc))
                    }
                    _ => None,
                };
                let bodies = if members.len() == 1 {
                    vec![(members[0], Mat::zeros(0, 0), Vec::new())]
                } else {
                    let member = |&b: &usize| (b, scratch(b), block_index(b));
                    members.iter().map(member).collect()
                };
                MassBlock {
                    cols,
                    bodies,
                    factored: Mat::from_fn(n, n, |_, _| f64::NAN),
                    factor: Mat::zeros(if schur.is_some() { 0 } else { n }, n),
                    current: Mat::zeros(n, n),
                    schur,
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
            self.refactored += 1;
            if let Some(schur) = &mut blk.schur {
                if schur.factor(blk.current.as_ref()).is_err() {
                    blk.factored.fill(f64::NAN);
                    return Err(blk.bodies[0].0);
                }
                continue;
            }
            blk.factor.copy_from(&blk.current);
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
        // blocks with a constant trailing block: all columns at once
        for blk in &self.blocks {
            if let (DofMap::Contiguous(r), Some(schur)) = (&blk.cols, &blk.schur) {
                let all = faer::MatMut::from_column_major_slice_mut(&mut b[..nu * k], nu, k);
                schur.solve_columns_in_place(all.subrows_mut(r.start, r.len()));
            }
        }
        for col in b.chunks_exact_mut(nu.max(1)).take(k) {
            for blk in &self.blocks {
                match (&blk.cols, &blk.schur) {
                    (DofMap::Contiguous(_), Some(_)) => {}
                    (DofMap::Contiguous(r), None) => {
                        cholesky_solve_in_place(&blk.factor, &mut col[r.clone()])
                    }
                    (DofMap::Scattered(v), _) => cholesky_solve_indexed(&blk.factor, col, v),
                }
            }
        }
    }

    /// Block factorizations done so far (a statistic: constant-mass elements factor once).
    pub fn refactorizations(&self) -> usize {
        self.refactored
    }

    /// Factorizations of constant trailing mass blocks so far (an FFR body's `m_ff`: once per
    /// body; blocks without one count nothing).
    pub fn constant_block_factorizations(&self) -> usize {
        let count = |b: &MassBlock| b.schur.as_ref().map_or(0, |s| s.constant_factorizations());
        self.blocks.iter().map(count).sum()
    }
}

impl MassBlock {
    /// `current` = the block's mass at `q`: one element's matrix, or the sum of its elements'.
    fn evaluate(&mut self, model: &Model, q: &[f64], eval: &mut [ElementScratch]) {
        if let [(i, _, _)] = self.bodies[..] {
            let b = &model.bodies[i];
            let current = self.current.as_mut();
            with_local_q(b, q, &mut eval[i], |qb, e| {
                b.element.mass_matrix(qb, e, current)
            });
            return;
        }
        self.current.fill(0.0);
        for (i, m, idx) in &mut self.bodies {
            let b = &model.bodies[*i];
            let mv = m.as_mut();
            with_local_q(b, q, &mut eval[*i], |qb, e| {
                b.element.mass_matrix(qb, e, mv)
            });
            for j in 0..m.ncols() {
                for i in 0..m.nrows() {
                    self.current[(idx[i], idx[j])] += m[(i, j)];
                }
            }
        }
    }
}

/// Solves `L L^T x = b[cols]` in place with the Cholesky factor `l` of a block whose columns
/// `cols` are scattered in `b` (the forward and back substitutions of
/// [`crate::linsolve::cholesky_solve`], indexed).
fn cholesky_solve_indexed(l: &Mat<f64>, b: &mut [f64], cols: &[usize]) {
    let n = cols.len();
    for j in 0..n {
        let col = l.col_as_slice(j);
        let xj = b[cols[j]] / col[j];
        b[cols[j]] = xj;
        if xj != 0.0 {
            for (k, lij) in col.iter().enumerate().skip(j + 1) {
                b[cols[k]] -= lij * xj;
            }
        }
    }
    for j in (0..n).rev() {
        let col = l.col_as_slice(j);
        let mut s = b[cols[j]];
        for (k, lij) in col.iter().enumerate().skip(j + 1) {
            s -= lij * b[cols[k]];
        }
        b[cols[j]] = s / col[j];
    }
}

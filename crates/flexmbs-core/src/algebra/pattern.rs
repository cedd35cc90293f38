//! Sparsity pattern of the saddle matrix `[A, G^T; G, 0]` (`A`: nu x nu, `G`: nc x nu) and the
//! column lists it is built from.

use crate::model::Model;
use crate::{BodyId, FrameId, Load};

/// Compressed-column pattern (sorted row indices per column) of the `(nu + nc)` square saddle
/// matrix `[A, G^T; G, 0]`.
///
/// `A` couples, all to all, the columns of each element, of each load (the columns of its
/// frames' owners: a load couples the bodies it acts on) and of each constraint row (the
/// geometric stiffness `d(G^T lambda)/dq` of statics couples the owners of a joint's frames);
/// `G` row `r` (matrix row `nu + r`, and column `nu + r` for `G^T`) has the columns of the owners
/// of its frames. The diagonal of `A` is always present.
#[derive(Debug, Clone, PartialEq)]
pub struct SystemPattern {
    /// Velocity coordinates `nu`.
    pub nu: usize,
    /// Constraint rows `nc`.
    pub nc: usize,
    /// Start of each column in [`Self::row_idx`] (`nu + nc + 1` entries).
    pub col_ptr: Vec<usize>,
    /// Row indices, sorted within each column.
    pub row_idx: Vec<usize>,
}

/// The column lists a [`SystemPattern`] is built from, one list of global velocity columns per
/// element, per load and per constraint row (each list sorted, without duplicates).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ColumnLists {
    /// Per element (body): the global velocity columns of its coordinates.
    pub elements: Vec<Vec<usize>>,
    /// Per load: the columns of the owners of its frames (empty for a load on ground only).
    pub loads: Vec<Vec<usize>>,
    /// Per constraint row: the columns of the owners of its joint's frames.
    pub constraint_rows: Vec<Vec<usize>>,
    /// Per contact: the columns of the owners of its two contours' frames (the tangent of a
    /// regularized contact couples them; empty for a set-valued contact).
    pub contacts: Vec<Vec<usize>>,
}

impl ColumnLists {
    /// The lists of a compiled model, from its coordinate maps: an element's columns are
    /// [`Model::body_dofs`]`.u`, a load's or constraint row's the union of
    /// [`Model::frame_cols`] of its frames (a body, a node, or nothing for ground). Bodies on a
    /// shared node have overlapping lists: their blocks add into the same pattern slots.
    pub fn of_model(model: &Model) -> Self {
        let elements: Vec<Vec<usize>> = (0..model.bodies.len())
            .map(|b| model.body_dofs(BodyId(b)).u.iter().collect())
            .collect();
        let owners = |frames: &[FrameId]| -> Vec<usize> {
            let mut cols: Vec<usize> = frames
                .iter()
                .flat_map(|f| model.frame_cols(*f).iter())
                .collect();
            cols.sort_unstable();
            cols.dedup();
            cols
        };
        let loads = model
            .loads
            .iter()
            .map(|l| owners(&load_frames(l)))
            .collect();
        let mut constraint_rows = Vec::with_capacity(model.nc);
        for joint in &model.joints {
            let cols = owners(&[joint.frame_a, joint.frame_b]);
            for _ in 0..joint.num_rows() {
                constraint_rows.push(cols.clone());
            }
        }
        for guide in &model.guides {
            let cols = owners(&[guide.curve.frame, guide.frame]);
            for _ in 0..guide.num_rows() {
                constraint_rows.push(cols.clone());
            }
        }
        let contacts = model
            .contacts
            .iter()
            .map(|c| {
                let (a, b) = c.frames();
                if c.law.set_valued_normal() {
                    Vec::new()
                } else {
                    owners(&[a, b])
                }
            })
            .collect();
        Self {
            elements,
            loads,
            constraint_rows,
            contacts,
        }
    }
}

/// The frames a load acts on.
fn load_frames(load: &Load) -> Vec<FrameId> {
    let mut ids = [FrameId(0); crate::load::MAX_LOAD_FRAMES];
    let n = load.frames(&mut ids);
    ids[..n].to_vec()
}

impl SystemPattern {
    /// The pattern of `[A, G^T; G, 0]` from per-element, per-load and per-constraint-row column
    /// lists ([`ColumnLists`]); `lists.constraint_rows.len()` is `nc`.
    pub fn new(nu: usize, lists: &ColumnLists) -> Self {
        let nc = lists.constraint_rows.len();
        let n = nu + nc;
        let mut cols: Vec<Vec<usize>> = (0..n)
            .map(|j| if j < nu { vec![j] } else { vec![] })
            .collect();
        let mut couple = |list: &[usize]| {
            for &j in list {
                cols[j].extend_from_slice(list);
            }
        };
        for list in lists
            .elements
            .iter()
            .chain(&lists.loads)
            .chain(&lists.contacts)
        {
            couple(list);
        }
        for list in &lists.constraint_rows {
            couple(list);
        }
        for (r, list) in lists.constraint_rows.iter().enumerate() {
            for &j in list {
                cols[j].push(nu + r);
            }
            cols[nu + r].extend_from_slice(list);
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for mut c in cols {
            c.sort_unstable();
            c.dedup();
            row_idx.extend_from_slice(&c);
            col_ptr.push(row_idx.len());
        }
        Self {
            nu,
            nc,
            col_ptr,
            row_idx,
        }
    }

    /// Dimension `nu + nc`.
    pub fn dim(&self) -> usize {
        self.nu + self.nc
    }

    /// Stored entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Position of entry `(row, col)` in the value array, if it is in the pattern.
    pub fn slot(&self, row: usize, col: usize) -> Option<usize> {
        let (a, b) = (self.col_ptr[col], self.col_ptr[col + 1]);
        self.row_idx[a..b].binary_search(&row).ok().map(|k| a + k)
    }

    /// Slots of the all-to-all block over `cols` (column-major: local `(i, j)` at `j * len + i`).
    pub fn block_slots(&self, cols: &[usize]) -> Vec<usize> {
        let mut out = Vec::with_capacity(cols.len() * cols.len());
        for &j in cols {
            for &i in cols {
                out.push(self.slot(i, j).expect("block in pattern"));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two 2-column elements coupled by one constraint row and a load on the second: entries
    /// exactly where the lists put them.
    #[test]
    fn pattern_holds_blocks_and_constraint_rows() {
        let lists = ColumnLists {
            elements: vec![vec![0, 1], vec![2, 3]],
            loads: vec![vec![2, 3]],
            constraint_rows: vec![vec![1, 2]],
            contacts: vec![],
        };
        let p = SystemPattern::new(4, &lists);
        assert_eq!(p.dim(), 5);
        let dense: Vec<Vec<bool>> = (0..5)
            .map(|i| (0..5).map(|j| p.slot(i, j).is_some()).collect())
            .collect();
        let expect = [
            [1, 1, 0, 0, 0],
            [1, 1, 1, 0, 1],
            [0, 1, 1, 1, 1],
            [0, 0, 1, 1, 0],
            [0, 1, 1, 0, 0],
        ];
        for i in 0..5 {
            for j in 0..5 {
                assert_eq!(dense[i][j], expect[i][j] == 1, "({i}, {j})");
            }
        }
        assert_eq!(p.nnz(), 14);
    }
}

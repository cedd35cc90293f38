//! Modal and Craig-Bampton reduction (seed 000 §2.3, seed 001 ch. 3) and the reduced body
//! that a multibody model consumes.

use crate::mesh::ElementKind;
use crate::UnitSystem;
use faer::Mat;
use serde::{Deserialize, Serialize};

/// How a reduced body was obtained.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum ReductionKind {
    /// Normal modes of the structure with its fixed node sets (constrained), lowest first.
    Modal,
    /// Free-free normal modes; the rigid-body modes are reported and excluded from the basis.
    FreeFree,
    /// Craig-Bampton: static constraint modes of the interface nodes followed by
    /// `internal_modes` fixed-interface normal modes (0 = Guyan).
    CraigBampton {
        /// Number of fixed-interface normal modes kept.
        internal_modes: usize,
    },
}

/// Cell of the visualisation mesh stored with a reduced body (VTK export).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Cell {
    /// Element kind (fixes the VTK cell type and node order).
    pub kind: ElementKind,
    /// Node indices into [`ReducedBody::nodes`] (Abaqus order).
    pub nodes: Vec<usize>,
}

/// Where a reduced body came from.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Provenance {
    /// Source description (built-in mesh parameters, file path of a CalculiX deck or seed folder).
    pub source: String,
    /// Program and version that wrote it, e.g. `flexmbs 0.1.0`.
    pub program: String,
    /// Free-form notes (mesh size, element kind, mass formulation, solver).
    pub notes: String,
}

/// Label of one mode (mode bookkeeping).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeLabel {
    /// 1-based mode index in the basis.
    pub index: usize,
    /// Natural frequency in Hz (of the reduced structure with its boundary conditions);
    /// 0 for rigid-body modes, NaN for static constraint modes.
    pub frequency_hz: f64,
    /// Dominant motion: `ux`, `uy`, `uz` (translation), `rx`, `ry`, `rz` (rotation about the centre of mass),
    /// or `static` for constraint modes.
    pub dominant: String,
    /// Effective modal mass fraction in x, y, z (translation participation, sums to <= 1 over all modes).
    pub effective_mass_fraction: [f64; 3],
}

/// A flexible body reduced to a few deformation shapes: everything a multibody model needs,
/// computed once and stored in a reduced-body file.
///
/// Mode shapes are nodal fields: `modes_t` holds the translation of node `i` in mode `k` in rows
/// `3 i .. 3 i + 3` of column `k`; `modes_r` the rotation (zero for solid nodes). Fixed nodes have
/// zero rows (as in the seed's modeShapeMatrix.dat). Reduced matrices are `Phi^T K Phi` and
/// `Phi^T M Phi` in the body's units.
#[derive(Debug, Clone, PartialEq)]
pub struct ReducedBody {
    /// Body name.
    pub name: String,
    /// Unit system of all data.
    pub units: UnitSystem,
    /// Undeformed node positions u0 (seed 000 Listing 4.1).
    pub nodes: Vec<[f64; 3]>,
    /// External node labels.
    pub node_ids: Vec<u64>,
    /// Lumped node masses (seed 000 Listing 4.3), if the body carries them.
    pub node_masses: Option<Vec<f64>>,
    /// Translational mode shapes, 3 N_n x N_f.
    pub modes_t: Mat<f64>,
    /// Rotational mode shapes, 3 N_n x N_f (zero rows for nodes without rotations), if any node has rotations.
    pub modes_r: Option<Mat<f64>>,
    /// Reduced stiffness Phi^T K Phi, N_f x N_f.
    pub k_red: Mat<f64>,
    /// Reduced mass Phi^T M Phi, N_f x N_f.
    pub m_red: Mat<f64>,
    /// Frequencies in Hz of the eigen modes of the reduced structure (N_f values; for Craig-Bampton the
    /// eigenfrequencies of (K_CB, M_CB) with the interface fixed as described in the labels).
    pub frequencies_hz: Vec<f64>,
    /// Mode labels, one per basis vector.
    pub labels: Vec<ModeLabel>,
    /// Interface node indices (Craig-Bampton); empty otherwise.
    pub interface_nodes: Vec<usize>,
    /// Fixed node indices (zero rows in the modes).
    pub fixed_nodes: Vec<usize>,
    /// Reduction that produced it.
    pub kind: ReductionKind,
    /// Visualisation cells.
    pub cells: Vec<Cell>,
    /// Provenance.
    pub provenance: Provenance,
}

impl ReducedBody {
    /// Number of nodes N_n.
    pub fn num_nodes(&self) -> usize {
        self.nodes.len()
    }
    /// Number of basis vectors N_f.
    pub fn num_modes(&self) -> usize {
        self.modes_t.ncols()
    }
}

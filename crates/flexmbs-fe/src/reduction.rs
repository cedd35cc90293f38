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

/// Start of the label of a static load response ([`ModeLabel::dominant`]).
pub const STATIC_LOAD_LABEL: &str = "static load";

/// Label of one mode (mode bookkeeping).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeLabel {
    /// 1-based mode index in the basis.
    pub index: usize,
    /// Natural frequency in Hz (of the reduced structure with its boundary conditions);
    /// 0 for rigid-body modes, NaN for static constraint modes.
    pub frequency_hz: f64,
    /// Dominant motion: `ux`, `uy`, `uz` (translation), `rx`, `ry`, `rz` (rotation about the centre of mass),
    /// `static node ...` for Craig-Bampton constraint modes, or `static load <name>` for the
    /// static response to a load pattern ([`crate::static_modes`]; its frequency is that of the
    /// augmentation block).
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
    /// The body restricted to the basis vectors `cols` (0-based, in that order): mode shapes,
    /// reduced matrices, frequencies and labels.
    pub fn restricted_to(&self, cols: &[usize]) -> ReducedBody {
        let nf = self.num_modes();
        let pick = |m: &Mat<f64>| Mat::from_fn(m.nrows(), cols.len(), |i, j| m[(i, cols[j])]);
        let square =
            |m: &Mat<f64>| Mat::from_fn(cols.len(), cols.len(), |i, j| m[(cols[i], cols[j])]);
        let mut out = self.clone();
        out.modes_t = pick(&self.modes_t);
        out.modes_r = self.modes_r.as_ref().map(pick);
        out.k_red = square(&self.k_red);
        out.m_red = square(&self.m_red);
        if self.frequencies_hz.len() == nf {
            out.frequencies_hz = cols.iter().map(|&c| self.frequencies_hz[c]).collect();
        }
        if self.labels.len() == nf {
            out.labels = cols.iter().map(|&c| self.labels[c].clone()).collect();
        }
        out
    }

    /// Number of nodes N_n.
    pub fn num_nodes(&self) -> usize {
        self.nodes.len()
    }
    /// Number of basis vectors N_f.
    pub fn num_modes(&self) -> usize {
        self.modes_t.ncols()
    }

    /// Number of trailing basis vectors that are static load responses (labelled
    /// [`STATIC_LOAD_LABEL`], appended after the modes by [`reduce_modal_augmented`]).
    pub fn num_static_load_responses(&self) -> usize {
        self.labels
            .iter()
            .rev()
            .take_while(|l| l.dominant.starts_with(STATIC_LOAD_LABEL))
            .count()
    }
}

use crate::assembly::{entries, sparse_from_triplets};
use crate::eigen::{
    dense_generalized, lowest_modes, lowest_modes_from_k_factor, EigenEvent, EigenOptions,
    SparseCholesky,
};
use crate::mechanism::{count_zero_energy, spectrum_scale, ZERO_ENERGY_TOLERANCE};
use crate::modes::{count_rigid, frequencies_hz, label_modes, project_dense};
use crate::system::FeSystem;
use crate::{FeError, Mesh, SparseMatrix};
use faer::sparse::Triplet;

/// Result of a modal analysis of a constrained system.
#[derive(Debug, Clone)]
pub struct ModalResult {
    /// Eigenvalues omega^2, ascending.
    pub omega2: Vec<f64>,
    /// M-normalised eigenvectors over the independent DOFs.
    pub vectors: Mat<f64>,
    /// Mode labels (rigid-body modes recognised).
    pub labels: Vec<ModeLabel>,
    /// Number of rigid-body modes found.
    pub n_rigid: usize,
}

/// Lowest `n_modes` eigenpairs of `K phi = omega^2 M phi` of a constrained system, labelled.
/// For a structure without fixed nodes, six more modes are computed so that `n_modes` elastic modes remain
/// after the rigid-body modes.
///
/// A body has 6 zero-energy modes (no fixed nodes) or none; more among the computed ones
/// ([`crate::mechanism::count_zero_energy`]) are a mechanism and give [`FeError::Mechanism`].
pub fn modal_analysis(
    sys: &FeSystem,
    n_modes: usize,
    opts: &EigenOptions,
    progress: &mut dyn FnMut(EigenEvent),
) -> Result<ModalResult, FeError> {
    let free = sys.map.fixed_nodes.is_empty();
    let wanted = (n_modes + if free { 6 } else { 0 }).min(sys.len());
    let o = EigenOptions {
        n_modes: wanted,
        supported: !free,
        ..opts.clone()
    };
    let expected = if free { 6 } else { 0 };
    let mechanism = |found: usize, computed: usize| FeError::Mechanism {
        found,
        computed,
        expected,
        kind: if free { "free-free" } else { "supported" },
        tolerance: ZERO_ENERGY_TOLERANCE,
    };
    let sol = match lowest_modes(&sys.k, &sys.m, &o, progress) {
        Ok(sol) => sol,
        Err(e @ FeError::EigenNotConverged(_)) => {
            // a mechanism with more zero-energy modes than requested can defeat the eigen
            // solver (a cluster at round-off zero): name the cause if that is it
            return Err(match zero_energy_count_by_inertia(sys) {
                Some(found) if found > expected => mechanism(found, found),
                _ => e,
            });
        }
        Err(e) => return Err(e),
    };
    let found = count_zero_energy(&sol.omega2, spectrum_scale(&sys.k, &sys.m));
    if found > expected {
        return Err(mechanism(found, sol.omega2.len()));
    }
    let labels = label_modes(sys, sol.vectors.as_ref(), &sol.omega2);
    let n_rigid = count_rigid(&labels);
    Ok(ModalResult {
        omega2: sol.omega2,
        vectors: sol.vectors,
        labels,
        n_rigid,
    })
}

/// The number of eigenvalues of `K x = omega^2 M x` below the zero-energy bound
/// `ZERO_ENERGY_TOLERANCE * spectrum_scale` (the definition of [`count_zero_energy`]), from the
/// inertia of `K - b M` (Sturm count), trying the bound and two larger ones if a pivot of the
/// first is numerically zero; `None` if none gives a reliable count.
fn zero_energy_count_by_inertia(sys: &FeSystem) -> Option<usize> {
    let bound = ZERO_ENERGY_TOLERANCE * spectrum_scale(&sys.k, &sys.m);
    for factor in [1.0, 3.0, 10.0] {
        let a = crate::eigen::shifted(&sys.k, &sys.m, factor * bound).ok()?;
        if let Ok(Some(inertia)) = crate::eigen::ldlt_inertia(&a) {
            if inertia.near_zero == 0 {
                return Some(inertia.negative);
            }
        }
    }
    None
}

/// Builds a reduced body from the elastic modes of a modal analysis (rigid-body modes excluded,
/// at most `n_modes` kept). Node masses are the diagonal of the constrained mass matrix when lumped.
pub fn reduce_modal(
    mesh: &Mesh,
    sys: &FeSystem,
    modal: &ModalResult,
    n_modes: usize,
    name: &str,
    provenance: Provenance,
) -> Result<ReducedBody, FeError> {
    reduce_modal_augmented(mesh, sys, modal, n_modes, &[], name, provenance)
}

/// [`reduce_modal`] with the static responses to `loads` appended to the modes
/// ([`crate::static_modes`]): one basis vector per load, labelled `static load <name>`, with the
/// frequency of the augmentation block.
pub fn reduce_modal_augmented(
    mesh: &Mesh,
    sys: &FeSystem,
    modal: &ModalResult,
    n_modes: usize,
    loads: &[crate::static_modes::StaticLoad],
    name: &str,
    provenance: Provenance,
) -> Result<ReducedBody, FeError> {
    let keep: Vec<usize> = (0..modal.labels.len())
        .filter(|&k| !modal.labels[k].dominant.starts_with("rigid"))
        .take(n_modes)
        .collect();
    if keep.is_empty() {
        return Err(FeError::Invalid("no elastic modes to keep".into()));
    }
    let mut v = Mat::<f64>::zeros(sys.len(), keep.len());
    for (c, &k) in keep.iter().enumerate() {
        v.col_mut(c).copy_from(modal.vectors.col(k));
    }
    let mut labels: Vec<ModeLabel> = keep.iter().map(|&k| modal.labels[k].clone()).collect();
    for (i, l) in labels.iter_mut().enumerate() {
        l.index = i + 1;
    }
    let mut omega2: Vec<f64> = keep.iter().map(|&k| modal.omega2[k]).collect();
    if !loads.is_empty() {
        if modal.n_rigid > 0 {
            return Err(FeError::Invalid(
                "static load responses need a supported body: the stiffness of a free-free body \
                 is singular (give the body supports, or use a Craig-Bampton basis)"
                    .into(),
            ));
        }
        let (x, w2) = crate::static_modes::static_responses(sys, v.as_ref(), loads)?;
        let nm = v.ncols();
        let mut vx = Mat::<f64>::zeros(sys.len(), nm + x.ncols());
        vx.as_mut().subcols_mut(0, nm).copy_from(&v);
        vx.as_mut().subcols_mut(nm, x.ncols()).copy_from(&x);
        v = vx;
        for (j, (load, w)) in loads.iter().zip(&w2).enumerate() {
            labels.push(ModeLabel {
                index: nm + j + 1,
                frequency_hz: w.max(0.0).sqrt() / (2.0 * std::f64::consts::PI),
                dominant: format!("{STATIC_LOAD_LABEL} {}", load.name),
                effective_mass_fraction: [0.0; 3],
            });
            omega2.push(*w);
        }
    }
    let kind = if modal.n_rigid > 0 {
        ReductionKind::FreeFree
    } else {
        ReductionKind::Modal
    };
    body_from_basis(
        mesh,
        sys,
        v.as_ref(),
        frequencies_hz(&omega2),
        labels,
        kind,
        name,
        provenance,
    )
}

/// What a Craig-Bampton reduction keeps.
#[derive(Debug, Clone)]
pub struct CraigBamptonOptions<'a> {
    /// Interface nodes: all their independent DOFs are kept as static constraint modes.
    pub interface: &'a [crate::NodeIdx],
    /// Number of fixed-interface normal modes (0 = Guyan).
    pub internal_modes: usize,
    /// Eigen solver options for the fixed-interface modes.
    pub eigen: &'a EigenOptions,
}

/// Craig-Bampton reduction (seed 001 ch. 3): static constraint modes of the independent DOFs of
/// `interface` nodes (`Psi = -K_II^-1 K_IB`) followed by `n_internal` fixed-interface normal modes of
/// `(K_II, M_II)`. `n_internal = 0` is Guyan condensation.
pub fn craig_bampton(
    mesh: &Mesh,
    sys: &FeSystem,
    cb: &CraigBamptonOptions<'_>,
    name: &str,
    provenance: Provenance,
    progress: &mut dyn FnMut(EigenEvent),
) -> Result<ReducedBody, FeError> {
    let (interface, n_internal, opts) = (cb.interface, cb.internal_modes, cb.eigen);
    let n = sys.len();
    let mut is_b = vec![false; n];
    let mut b_dofs = Vec::new();
    for &node in interface {
        let d = sys.map.independent_of_node(node);
        if d.is_empty() {
            return Err(FeError::Invalid(format!(
                "interface node {node} has no free DOFs (fixed or slaved)"
            )));
        }
        for p in d {
            if !is_b[p] {
                is_b[p] = true;
                b_dofs.push(p);
            }
        }
    }
    let i_dofs: Vec<usize> = (0..n).filter(|&p| !is_b[p]).collect();
    let nb = b_dofs.len();
    let ni = i_dofs.len();
    let mut pos = vec![(false, 0usize); n];
    for (a, &p) in b_dofs.iter().enumerate() {
        pos[p] = (true, a);
    }
    for (a, &p) in i_dofs.iter().enumerate() {
        pos[p] = (false, a);
    }
    let (k_ii, k_ib) = split_blocks(&sys.k, &pos, ni, nb)?;
    let (m_ii, _) = split_blocks(&sys.m, &pos, ni, nb)?;
    // static constraint modes Psi = -K_II^-1 K_IB
    progress(EigenEvent::Factorizing {
        n: ni,
        nnz: k_ii.compute_nnz(),
    });
    // K_II - 0 M_II with the eigen solver's ordering: the same factor starts its Lanczos run
    let chol = SparseCholesky::factor_shifted_observed(&k_ii, &m_ii, 0.0, &mut |nnz_l, bytes| {
        progress(EigenEvent::FactorEstimate { nnz_l, bytes })
    })
    .map_err(|e| match e {
        e @ FeError::MemoryRefused { .. } => e,
        _ => FeError::NotPositiveDefinite {
            what: "K_II (stiffness with the interface fixed)".into(),
            hint: ": with the interface held the body still moves without strain energy: the \
                   interface does not stop every rigid-body motion, or the mesh is a mechanism \
                   (hourglass modes of hex20r with one element across a section: use 2 or more \
                   divisions across or hex20; parts not connected to each other)"
                .into(),
        },
    })?;
    crate::memory::check_allocation(
        &format!("the static modes ({ni} x {nb} dense)"),
        8 * ni as u64 * nb as u64,
    )?;
    let mut psi = k_ib.to_dense();
    chol.solve_in_place(psi.as_mut());
    let k_internal = n_internal.min(ni);
    let (phi_i, w2_i) = if k_internal > 0 {
        let opts = EigenOptions {
            n_modes: k_internal,
            // K_ii factored above for the static modes: positive definite
            supported: true,
            ..opts.clone()
        };
        let sol = lowest_modes_from_k_factor(&k_ii, &m_ii, &opts, chol, progress)?;
        (sol.vectors, sol.omega2)
    } else {
        (Mat::<f64>::zeros(ni, 0), Vec::new())
    };
    let nm = nb + k_internal;
    let mut v = Mat::<f64>::zeros(n, nm);
    for (a, &p) in b_dofs.iter().enumerate() {
        v[(p, a)] = 1.0;
    }
    for (r, &p) in i_dofs.iter().enumerate() {
        for c in 0..nb {
            v[(p, c)] = -psi[(r, c)];
        }
        for c in 0..k_internal {
            v[(p, nb + c)] = phi_i[(r, c)];
        }
    }
    let names = ["ux", "uy", "uz", "rx", "ry", "rz"];
    let mut labels: Vec<ModeLabel> = b_dofs
        .iter()
        .enumerate()
        .map(|(a, &p)| {
            let d = sys.map.independent[p];
            ModeLabel {
                index: a + 1,
                frequency_hz: f64::NAN,
                dominant: format!("static node {} {}", node_label(mesh, d.node), names[d.dir]),
                effective_mass_fraction: [0.0; 3],
            }
        })
        .collect();
    let fixed_labels = label_modes(sys, v.as_ref().subcols(nb, k_internal), &w2_i);
    for (c, mut l) in fixed_labels.into_iter().enumerate() {
        l.index = nb + c + 1;
        labels.push(l);
    }
    // frequencies of the reduced model itself (free interface)
    let k_cb = project_dense(&sys.k, v.as_ref());
    let m_cb = project_dense(&sys.m, v.as_ref());
    let (w2_cb, _) = dense_generalized(k_cb.as_ref(), m_cb.as_ref())?;
    let kind = ReductionKind::CraigBampton {
        internal_modes: k_internal,
    };
    let mut body = body_from_basis(
        mesh,
        sys,
        v.as_ref(),
        frequencies_hz(&w2_cb),
        labels,
        kind,
        name,
        provenance,
    )?;
    body.interface_nodes = interface.to_vec();
    Ok(body)
}

fn node_label(mesh: &Mesh, node: usize) -> String {
    mesh.node_ids
        .get(node)
        .map(|id| id.to_string())
        .unwrap_or_else(|| format!("interface#{}", node - mesh.num_nodes()))
}

/// Splits a sparse matrix into the internal block `A_II` and the coupling block `A_IB` (dense later).
fn split_blocks(
    a: &SparseMatrix,
    pos: &[(bool, usize)],
    ni: usize,
    nb: usize,
) -> Result<(SparseMatrix, SparseMatrix), FeError> {
    let mut ii = Vec::new();
    let mut ib = Vec::new();
    for (r, c, v) in entries(a) {
        match (pos[r], pos[c]) {
            ((false, i), (false, j)) => ii.push(Triplet::new(i, j, v)),
            ((false, i), (true, j)) => ib.push(Triplet::new(i, j, v)),
            _ => {}
        }
    }
    let a_ii = sparse_from_triplets(ni, &ii)?;
    let a_ib = SparseMatrix::try_new_from_triplets(ni, nb, &ib)
        .map_err(|e| FeError::Invalid(format!("sparse block assembly failed: {e:?}")))?;
    Ok((a_ii, a_ib))
}

/// Assembles a [`ReducedBody`] from a basis `v` over the independent DOFs.
#[allow(clippy::too_many_arguments)]
fn body_from_basis(
    mesh: &Mesh,
    sys: &FeSystem,
    v: faer::MatRef<'_, f64>,
    frequencies_hz: Vec<f64>,
    labels: Vec<ModeLabel>,
    kind: ReductionKind,
    name: &str,
    provenance: Provenance,
) -> Result<ReducedBody, FeError> {
    let k_red = project_dense(&sys.k, v);
    let m_red = project_dense(&sys.m, v);
    let (modes_t, modes_r) = sys.map.expand(v);
    let has_rot = sys.map.dofs.count.contains(&6);
    let n_nodes = sys.map.nodes.len();
    let mut node_ids = mesh.node_ids.clone();
    let max_id = node_ids.iter().copied().max().unwrap_or(0);
    node_ids.extend((0..n_nodes - mesh.num_nodes()).map(|i| max_id + 1 + i as u64));
    let node_masses = sys.node_masses.clone();
    let cells = mesh
        .elements
        .iter()
        .map(|e| Cell {
            kind: e.kind,
            nodes: e.nodes.clone(),
        })
        .collect();
    Ok(ReducedBody {
        name: name.to_string(),
        units: mesh.units,
        nodes: sys.map.nodes.clone(),
        node_ids,
        node_masses,
        modes_t,
        modes_r: has_rot.then_some(modes_r),
        k_red,
        m_red,
        frequencies_hz,
        labels,
        interface_nodes: sys.map.interface_nodes.clone(),
        fixed_nodes: sys.map.fixed_nodes.clone(),
        kind,
        cells,
        provenance,
    })
}

//! Craig-Bampton data of a straight 3D beam segment from the FE beam element
//! ([`flexmbs_fe::element::beam::beam_local`]): the segment along its local x axis, meshed with an
//! even number of elements (a mesh node at the centre of mass), interface points at both ends
//! (6 DOF each), static constraint modes `Ψ = −K_II⁻¹ K_IB` and optionally fixed-interface normal
//! modes (seed 001 §3.1).

use super::{Interface, SuperelementData, SuperelementError};
use flexmbs_fe::element::beam::beam_local;
use flexmbs_fe::element::MassKind;
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::Material;
use nalgebra::{DMatrix, Matrix3, Vector3};

/// Where the floating frame of the segment sits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FrameLocation {
    /// At the undeformed centre of mass (the segment's midpoint), seed 001's choice.
    #[default]
    CentreOfMass,
    /// At the first interface point (the "traditional" variant, seed 001 §5.2).
    FirstInterface,
}

/// A uniform straight beam segment.
#[derive(Debug, Clone, PartialEq)]
pub struct BeamSegmentSpec {
    /// Length (m).
    pub length: f64,
    /// Material.
    pub material: Material,
    /// Cross-section (local y, z axes = segment y, z).
    pub section: BeamSection,
    /// Beam theory of the FE elements.
    pub theory: BeamTheory,
    /// FE elements along the segment (rounded up to an even number).
    pub elements: usize,
    /// Fixed-interface normal modes kept (0: static modes only).
    pub internal_modes: usize,
    /// Floating-frame location.
    pub frame: FrameLocation,
}

/// The Craig-Bampton data of a beam segment along x (interfaces at its ends, axes parallel to the
/// segment's), consistent FE mass.
pub fn beam_segment(spec: &BeamSegmentSpec) -> Result<SuperelementData, SuperelementError> {
    Ok(beam_segment_basis(spec, MassKind::Consistent)?.0)
}

/// [`beam_segment`] with the FE mass `mass`, also returning the FE model it reduces: the
/// Craig-Bampton basis `V` (6 DOF per FE node, node `i` at `x = i L / n_e` from the first
/// interface; columns = the superelement's local coordinates) and the assembled FE mass matrix.
pub fn beam_segment_basis(
    spec: &BeamSegmentSpec,
    mass: MassKind,
) -> Result<(SuperelementData, DMatrix<f64>, DMatrix<f64>), SuperelementError> {
    let ne = even_elements(spec);
    beam_segment_with_interfaces(spec, mass, &[0, ne])
}

/// Number of FE elements of the segment: `spec.elements` rounded up to an even number (a node at
/// the centre of mass), at least 2.
pub fn even_elements(spec: &BeamSegmentSpec) -> usize {
    spec.elements.max(2).div_ceil(2) * 2
}

/// [`beam_segment_basis`] with interface points at the FE nodes `interface_nodes` (indices
/// `0..=n_e`, node `i` at `x = i L / n_e`; [`even_elements`]), in that order: any number of
/// interfaces (seed 001 §8.4).
pub fn beam_segment_with_interfaces(
    spec: &BeamSegmentSpec,
    mass: MassKind,
    interface_nodes: &[usize],
) -> Result<(SuperelementData, DMatrix<f64>, DMatrix<f64>), SuperelementError> {
    let ne = even_elements(spec);
    let (k, m) = assemble_beam(spec, mass, ne);
    if interface_nodes.is_empty() || interface_nodes.iter().any(|&i| i > ne) {
        return Err(SuperelementError::NoInterface);
    }
    let v = craig_bampton_basis(&k, &m, interface_nodes, spec.internal_modes)?;
    let nm = v.ncols() - 6 * interface_nodes.len();
    let sym = |a: DMatrix<f64>| (&a + a.transpose()) * 0.5;
    let m_cb = sym(v.transpose() * &m * &v);
    let k_cb = sym(v.transpose() * &k * &v);
    let (frame_node, origin) = match spec.frame {
        FrameLocation::CentreOfMass => (ne / 2, 0.5 * spec.length),
        FrameLocation::FirstInterface => (
            interface_nodes[0],
            spec.length * interface_nodes[0] as f64 / ne as f64,
        ),
    };
    let phi_cb = v.rows(6 * frame_node, 6).into_owned();
    let at = |node: usize| Interface {
        position: Vector3::new(spec.length * node as f64 / ne as f64 - origin, 0.0, 0.0),
        rotation: Matrix3::identity(),
    };
    let data = SuperelementData {
        interfaces: interface_nodes.iter().map(|&i| at(i)).collect(),
        internal_modes: nm,
        m_cb,
        k_cb,
        phi_cb,
        centre_of_mass: Vector3::new(0.5 * spec.length - origin, 0.0, 0.0),
    };
    Ok((data, v, m))
}

/// Stiffness and mass of `ne` equal beam elements along x (6 DOF per node).
fn assemble_beam(
    spec: &BeamSegmentSpec,
    mass: MassKind,
    ne: usize,
) -> (DMatrix<f64>, DMatrix<f64>) {
    let ndof = 6 * (ne + 1);
    let le = spec.length / ne as f64;
    let (ke, me) = beam_local(le, &spec.material, &spec.section, spec.theory, mass);
    let (mut k, mut m) = (DMatrix::zeros(ndof, ndof), DMatrix::zeros(ndof, ndof));
    for e in 0..ne {
        for i in 0..12 {
            for j in 0..12 {
                k[(6 * e + i, 6 * e + j)] += ke[(i, j)];
                m[(6 * e + i, 6 * e + j)] += me[(i, j)];
            }
        }
    }
    (k, m)
}

/// The Craig-Bampton basis `V` (ndof x (6 N_b + m)): unit interface DOFs with the static modes
/// `Ψ = −K_II⁻¹ K_IB` in the interior, then `m` mass-normalized fixed-interface modes.
fn craig_bampton_basis(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    interface_nodes: &[usize],
    internal_modes: usize,
) -> Result<DMatrix<f64>, SuperelementError> {
    let ndof = k.nrows();
    let boundary: Vec<usize> = interface_nodes
        .iter()
        .flat_map(|&i| 6 * i..6 * i + 6)
        .collect();
    let interior: Vec<usize> = (0..ndof).filter(|p| !boundary.contains(p)).collect();
    let (nb, ni) = (boundary.len(), interior.len());
    let pick = |a: &DMatrix<f64>, r: &[usize], c: &[usize]| {
        DMatrix::from_fn(r.len(), c.len(), |i, j| a[(r[i], c[j])])
    };
    let k_ii = pick(k, &interior, &interior);
    let k_ib = pick(k, &interior, &boundary);
    let m_ii = pick(m, &interior, &interior);
    let not_pd = |what: &'static str| SuperelementError::NotSymmetric { what };
    let chol_k = k_ii.clone().cholesky().ok_or(not_pd("K_II"))?;
    let psi = -chol_k.solve(&k_ib);
    let nm = internal_modes.min(ni);
    let phi_i = if nm > 0 {
        let l = m_ii.cholesky().ok_or(not_pd("M_II"))?.l();
        let l_inv = l.clone().try_inverse().ok_or(not_pd("M_II"))?;
        let a = &l_inv * &k_ii * l_inv.transpose();
        let eig = ((&a + a.transpose()) * 0.5).symmetric_eigen();
        let mut order: Vec<usize> = (0..ni).collect();
        order.sort_by(|&x, &y| eig.eigenvalues[x].total_cmp(&eig.eigenvalues[y]));
        let y = DMatrix::from_fn(ni, nm, |i, j| eig.eigenvectors[(i, order[j])]);
        l_inv.transpose() * y
    } else {
        DMatrix::zeros(ni, 0)
    };
    let mut v = DMatrix::<f64>::zeros(ndof, nb + nm);
    for (a, &p) in boundary.iter().enumerate() {
        v[(p, a)] = 1.0;
    }
    for (r, &p) in interior.iter().enumerate() {
        for c in 0..nb {
            v[(p, c)] = psi[(r, c)];
        }
        for c in 0..nm {
            v[(p, nb + c)] = phi_i[(r, c)];
        }
    }
    Ok(v)
}

//! Linear stress recovery: nodal stresses of a displacement field and the modal stress fields of
//! a reduced body (stress = sum of modal stress fields times the elastic coordinates).
//!
//! Solid elements: `sigma = D B(xi_a) u_e` evaluated at each element node `a` from the element's
//! own displacement interpolation (exact wherever the element represents the field: constant
//! strain for all solids, linear strain for `Hex20`, `Hex20R` and `Tet10`), then averaged with
//! equal weights over the solid elements sharing the node. `Hex8I` adds its incompatible
//! (bubble) modes, recovered from the nodal displacements by the static condensation of its
//! stiffness, `alpha = -K_ii^-1 K_ic u` (so it gives pure bending exactly, like its stiffness).
//! Components: Voigt order xx, yy, zz, xy, yz, zx in the
//! mesh (body) axes.
//!
//! Beam elements: the section resultants at the element ends, `-f_1` at node 1 and `+f_2` at
//! node 2 with `f = K_local T u_e` (exact for the element's end-loaded solution), turned into
//! six *section stresses* per node (documented slot order, local beam axes):
//! `[N/A, M_y c_z / I_y, -M_z c_y / I_z, T c_t / J, V_y / A, V_z / A]`, i.e. the axial stress,
//! the bending stresses at the fibres `z = +c_z` and `y = +c_y`, the torsion shear stress at the
//! torsion fibre and the mean transverse shear stresses. Averaged over the beams sharing the
//! node. Their equivalent stress ([`equivalent_stress`]) takes the extreme fibre normal stress
//! `|s0| + |s1| + |s2|` (exact at the corner of a rectangle, conservative for round sections)
//! with the torsion shear: `sqrt(sigma^2 + 3 tau_T^2)`.
//!
//! A node used by both solids and beams takes the solid value. Nodes without an element
//! (rigid-interface nodes) have kind [`NodeStressKind::None`] and zero stress.

use crate::element::beam::{beam_frame, beam_local};
use crate::element::gauss::hex_rule;
use crate::element::solid::{b_block, b_matrix, eval_point, ShapeFn};
use crate::element::{hex20, hex8, tet10, MassKind};
use crate::mesh::{BeamSection, ElementKind, Property};
use crate::reduction::ReducedBody;
use crate::{FeError, Mesh};
use faer::Mat;
use nalgebra::{DMatrix, DVector};

/// What the six stress values of a node mean.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum NodeStressKind {
    /// No element at the node (rigid-interface node): zero stress.
    None = 0,
    /// Solid node: Cauchy stress xx, yy, zz, xy, yz, zx in body axes.
    Solid = 1,
    /// Beam node: section stresses `[N/A, M_y c_z/I_y, -M_z c_y/I_z, T c_t/J, V_y/A, V_z/A]`.
    Beam = 2,
}

impl NodeStressKind {
    /// The kind stored as `code` (0, 1, 2), if valid.
    pub fn from_code(code: u8) -> Option<Self> {
        match code {
            0 => Some(Self::None),
            1 => Some(Self::Solid),
            2 => Some(Self::Beam),
            _ => None,
        }
    }
}

/// Distances of a beam section's stress points from its centroid (mesh units): `cy`, `cz` the
/// extreme fibres along the local y and z axes, `ct` the torsion fibre, `tau_T = T ct / J`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamFibres {
    /// Extreme fibre distance along local y.
    pub cy: f64,
    /// Extreme fibre distance along local z.
    pub cz: f64,
    /// Torsion stress point: `tau_max = T ct / J`.
    pub ct: f64,
}

impl BeamFibres {
    /// Solid rectangle `b` (local y) x `h` (local z): `cy = b/2`, `cz = h/2`; torsion after Roark
    /// (table 10.1 case 4, half-sides `a >= c`): `tau_max = T (3a + 1.8c) / (8 a^2 c^2)`, so
    /// `ct = J (3a + 1.8c) / (8 a^2 c^2)` with the section's `J`.
    pub fn rectangle(b: f64, h: f64, j: f64) -> Self {
        let (a, c) = if b >= h {
            (b / 2.0, h / 2.0)
        } else {
            (h / 2.0, b / 2.0)
        };
        Self {
            cy: b / 2.0,
            cz: h / 2.0,
            ct: j * (3.0 * a + 1.8 * c) / (8.0 * a * a * c * c),
        }
    }

    /// Round section (solid circle or tube) of outer radius `r`: all fibres at `r` (exact).
    pub fn round(r: f64) -> Self {
        Self {
            cy: r,
            cz: r,
            ct: r,
        }
    }

    /// Section without known dimensions: the solid rectangle with the same `A`, `I_y`, `I_z`
    /// (`c = sqrt(3 I / A)`), torsion fibre at the larger distance (documented approximation).
    pub fn equivalent_rectangle(s: &BeamSection) -> Self {
        let cy = (3.0 * s.iz / s.area).sqrt();
        let cz = (3.0 * s.iy / s.area).sqrt();
        Self {
            cy,
            cz,
            ct: cy.max(cz),
        }
    }
}

/// Modal stress fields of a reduced body: column `k` holds the six stress values of node `i` in
/// mode `k` in rows `6 i .. 6 i + 6` (body units), meaning given by `kinds[i]`.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalStress {
    /// Meaning of each node's six values.
    pub kinds: Vec<NodeStressKind>,
    /// Stress per unit modal coordinate, `6 N_n x N_f`.
    pub fields: Mat<f64>,
}

impl ModalStress {
    /// Number of nodes.
    pub fn num_nodes(&self) -> usize {
        self.kinds.len()
    }

    /// Number of modes.
    pub fn num_modes(&self) -> usize {
        self.fields.ncols()
    }

    /// The fields of the modes `cols` (in that order), as a body restricted to these modes.
    pub fn select_modes(&self, cols: &[usize]) -> Self {
        let mut fields = Mat::<f64>::zeros(self.fields.nrows(), cols.len());
        for (c, &k) in cols.iter().enumerate() {
            fields.col_mut(c).copy_from(self.fields.col(k));
        }
        Self {
            kinds: self.kinds.clone(),
            fields,
        }
    }

    /// The same fields times `factor` (unit conversion: for a body converted to SI, whose modal
    /// coordinate is `q_si = q L / c`, the factor is `stress_to_si c / L`).
    pub fn scaled(&self, factor: f64) -> Self {
        Self {
            kinds: self.kinds.clone(),
            fields: &self.fields * faer::Scale(factor),
        }
    }

    /// Linear recovery of node `node`'s six stress values at elastic coordinates `q`
    /// (`sum_k fields[6 node + c, k] q_k`); no allocation.
    pub fn node_stress(&self, node: usize, q: &[f64]) -> [f64; 6] {
        let mut s = [0.0; 6];
        for (k, qk) in q.iter().enumerate().take(self.fields.ncols()) {
            for (c, sc) in s.iter_mut().enumerate() {
                *sc += self.fields[(6 * node + c, k)] * qk;
            }
        }
        s
    }
}

/// Von Mises equivalent of a solid stress (Voigt xx, yy, zz, xy, yz, zx):
/// `sqrt(((sx-sy)^2 + (sy-sz)^2 + (sz-sx)^2)/2 + 3 (txy^2 + tyz^2 + tzx^2))`.
pub fn von_mises(s: &[f64; 6]) -> f64 {
    let d = (s[0] - s[1]).powi(2) + (s[1] - s[2]).powi(2) + (s[2] - s[0]).powi(2);
    (0.5 * d + 3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5])).sqrt()
}

/// Equivalent (von Mises) stress of a node's six values by their kind: [`von_mises`] for solids;
/// for beams `sqrt(sigma^2 + 3 tau^2)` with the extreme fibre stress
/// `sigma = |s0| + |s1| + |s2|` and the torsion shear `tau = s3`; 0 for [`NodeStressKind::None`].
pub fn equivalent_stress(kind: NodeStressKind, s: &[f64; 6]) -> f64 {
    match kind {
        NodeStressKind::None => 0.0,
        NodeStressKind::Solid => von_mises(s),
        NodeStressKind::Beam => {
            let sigma = s[0].abs() + s[1].abs() + s[2].abs();
            (sigma * sigma + 3.0 * s[3] * s[3]).sqrt()
        }
    }
}

/// The stress kind of each of `n_nodes` nodes (mesh nodes first, extra nodes get `None`).
pub fn node_stress_kinds(mesh: &Mesh, n_nodes: usize) -> Vec<NodeStressKind> {
    let mut kinds = vec![NodeStressKind::None; n_nodes.max(mesh.num_nodes())];
    for el in &mesh.elements {
        for &n in &el.nodes {
            kinds[n] = match (kinds[n], el.kind.is_solid()) {
                (_, true) => NodeStressKind::Solid,
                (NodeStressKind::Solid, false) => NodeStressKind::Solid,
                (_, false) => NodeStressKind::Beam,
            };
        }
    }
    kinds.truncate(n_nodes);
    kinds
}

/// Shape function and reference node coordinates of a solid kind.
fn solid_shape(kind: ElementKind) -> Option<(ShapeFn, &'static [[f64; 3]])> {
    match kind {
        ElementKind::Hex8 | ElementKind::Hex8I => Some((hex8::hex8_shape, &hex8::HEX8_NODES[..])),
        ElementKind::Hex20 | ElementKind::Hex20R => {
            Some((hex20::hex20_shape, &hex20::HEX20_NODES[..]))
        }
        ElementKind::Tet10 => Some((tet10::tet10_shape, &tet10::TET10_NODES[..])),
        ElementKind::Beam2 => None,
    }
}

/// Stress operator of one element: `S_e` (6 n_nodes x element DOFs) mapping the element's
/// node-major displacement vector (3 or 6 DOFs per node) to the six stress values at each of its
/// nodes (module doc). `fibres` are used for beams.
pub fn element_stress_operator(
    mesh: &Mesh,
    element: usize,
    fibres: &dyn Fn(usize, &BeamSection) -> BeamFibres,
) -> Result<DMatrix<f64>, FeError> {
    let el = mesh
        .elements
        .get(element)
        .ok_or_else(|| FeError::Invalid(format!("element index {element} out of range")))?;
    let x: Vec<[f64; 3]> = el.nodes.iter().map(|&n| mesh.nodes[n]).collect();
    let prop = mesh.properties.get(el.property).ok_or_else(|| {
        FeError::Invalid(format!(
            "element {element} refers to missing property {}",
            el.property
        ))
    })?;
    match (solid_shape(el.kind), prop) {
        (Some(_), Property::Solid { material }) if el.kind == ElementKind::Hex8I => {
            hex8i_stress_operator(&x, &material.elasticity_matrix(), element)
        }
        (Some((shape, xi_nodes)), Property::Solid { material }) => {
            let d = crate::element::solid::dyn_d(&material.elasticity_matrix());
            let nn = x.len();
            let mut s = DMatrix::zeros(6 * nn, 3 * nn);
            for (a, xi) in xi_nodes.iter().enumerate().take(nn) {
                let e = eval_point(shape, &x, *xi, element, a)?;
                let db = &d * b_matrix(&e.dndx);
                s.view_mut((6 * a, 0), (6, 3 * nn)).copy_from(&db);
            }
            Ok(s)
        }
        (
            None,
            Property::Beam {
                material,
                section,
                theory,
                orientation,
            },
        ) => {
            let (r, l) = beam_frame(x[0], x[1], *orientation, element)?;
            let (kl, _) = beam_local(l, material, section, *theory, MassKind::Consistent);
            let mut t = DMatrix::zeros(12, 12);
            for b in 0..4 {
                t.view_mut((3 * b, 3 * b), (3, 3)).copy_from(&r);
            }
            let f = kl * t; // local end forces per global element displacement
            let c = fibres(el.property, section);
            let sc = section_stress_rows(section, &c);
            let mut s = DMatrix::zeros(12, 12);
            for (node, sign) in [(0usize, -1.0), (1, 1.0)] {
                for (row, (res, factor)) in sc.iter().enumerate() {
                    for col in 0..12 {
                        s[(6 * node + row, col)] = sign * factor * f[(6 * node + res, col)];
                    }
                }
            }
            Ok(s)
        }
        _ => Err(FeError::Invalid(format!(
            "element {element} ({:?}) has a property of the wrong kind",
            el.kind
        ))),
    }
}

/// Strain-displacement matrix (6 x 9) of the nine `Hex8I` bubble modes `(1 - xi_k^2) e_c` at
/// `xi`, mapped with the centre Jacobian and scaled by det J0 / det J (as its stiffness,
/// [`hex8::hex8i_stiffness`]).
fn hex8i_bubble_b(xi: [f64; 3], j0inv: &nalgebra::Matrix3<f64>, ratio: f64) -> DMatrix<f64> {
    let mut bi = DMatrix::zeros(6, 9);
    for k in 0..3 {
        let mut g = nalgebra::Vector3::zeros();
        g[k] = -2.0 * xi[k];
        b_block(&mut bi, 3 * k, &(j0inv * g * ratio));
    }
    bi
}

/// Stress operator (48 x 24) of a `Hex8I` element: `D (B_c + B_i A)` at each corner node, with
/// the bubble amplitudes `alpha = A u = -K_ii^-1 K_ic u` of its static condensation.
fn hex8i_stress_operator(
    x: &[[f64; 3]],
    d: &nalgebra::Matrix6<f64>,
    element: usize,
) -> Result<DMatrix<f64>, FeError> {
    let dd = crate::element::solid::dyn_d(d);
    let center = eval_point(hex8::hex8_shape, x, [0.0; 3], element, 0)?;
    let j0inv = center.jac.try_inverse().ok_or(FeError::BadJacobian {
        element,
        point: 0,
        det: center.det,
    })?;
    let (mut kic, mut kii) = (DMatrix::zeros(9, 24), DMatrix::zeros(9, 9));
    for (ip, p) in hex_rule(2).iter().enumerate() {
        let e = eval_point(hex8::hex8_shape, x, p.xi, element, ip)?;
        let bi = hex8i_bubble_b(p.xi, &j0inv, center.det / e.det);
        let dbi = &dd * &bi;
        kic.gemm_tr(e.det * p.w, &dbi, &b_matrix(&e.dndx), 1.0);
        kii.gemm_tr(e.det * p.w, &bi, &dbi, 1.0);
    }
    let chol = kii.cholesky().ok_or_else(|| {
        FeError::Invalid(format!(
            "element {element}: Hex8I internal-mode stiffness not positive definite"
        ))
    })?;
    let a = -chol.solve(&kic);
    let mut s = DMatrix::zeros(48, 24);
    for (n, xi) in hex8::HEX8_NODES.iter().enumerate() {
        let e = eval_point(hex8::hex8_shape, x, *xi, element, n)?;
        let b = b_matrix(&e.dndx) + hex8i_bubble_b(*xi, &j0inv, center.det / e.det) * &a;
        s.view_mut((6 * n, 0), (6, 24)).copy_from(&(&dd * b));
    }
    Ok(s)
}

/// For each of the six beam slots: the section resultant it comes from (local N, V_y, V_z, T,
/// M_y, M_z = 0..6) and its factor.
fn section_stress_rows(s: &BeamSection, c: &BeamFibres) -> [(usize, f64); 6] {
    [
        (0, 1.0 / s.area),
        (4, c.cz / s.iy),
        (5, -c.cy / s.iz),
        (3, c.ct / s.j),
        (1, 1.0 / s.area),
        (2, 1.0 / s.area),
    ]
}

/// Nodal stress fields of the displacement fields `disp` (columns; node `i` translation in rows
/// `3 i..3 i + 3` of `t`, rotation in the same rows of `r`, as [`ReducedBody::modes_t`] and
/// `modes_r`) of a mesh with `n_nodes >= mesh.num_nodes()` nodes: `6 n_nodes x ncols`, averaged
/// over the elements sharing each node (module doc).
pub fn nodal_stress_fields(
    mesh: &Mesh,
    n_nodes: usize,
    t: faer::MatRef<'_, f64>,
    r: Option<faer::MatRef<'_, f64>>,
    fibres: &dyn Fn(usize, &BeamSection) -> BeamFibres,
) -> Result<(Vec<NodeStressKind>, Mat<f64>), FeError> {
    if n_nodes < mesh.num_nodes() || t.nrows() != 3 * n_nodes {
        return Err(FeError::Invalid(format!(
            "stress recovery: {} displacement rows for {n_nodes} nodes of a mesh with {}",
            t.nrows(),
            mesh.num_nodes()
        )));
    }
    let kinds = node_stress_kinds(mesh, n_nodes);
    let nc = t.ncols();
    let mut out = Mat::<f64>::zeros(6 * n_nodes, nc);
    let mut count = vec![0usize; n_nodes];
    for (ei, el) in mesh.elements.iter().enumerate() {
        let solid = el.kind.is_solid();
        if !solid && r.is_none() {
            return Err(FeError::Invalid(format!(
                "stress recovery: beam element {ei} but no rotation fields"
            )));
        }
        let s = element_stress_operator(mesh, ei, fibres)?;
        let npn = el.kind.dofs_per_node();
        let mut ue = DVector::zeros(npn * el.nodes.len());
        for col in 0..nc {
            for (a, &n) in el.nodes.iter().enumerate() {
                for d in 0..npn {
                    ue[npn * a + d] = match (d < 3, r) {
                        (true, _) => t[(3 * n + d, col)],
                        (false, Some(r)) => r[(3 * n + d - 3, col)],
                        (false, None) => 0.0,
                    };
                }
            }
            let se = &s * &ue;
            for (a, &n) in el.nodes.iter().enumerate() {
                if solid != (kinds[n] == NodeStressKind::Solid) {
                    continue;
                }
                for c in 0..6 {
                    out[(6 * n + c, col)] += se[6 * a + c];
                }
            }
        }
        for &n in &el.nodes {
            if solid == (kinds[n] == NodeStressKind::Solid) {
                count[n] += 1;
            }
        }
    }
    for (n, &c) in count.iter().enumerate() {
        if c > 1 {
            for row in 6 * n..6 * n + 6 {
                for col in 0..nc {
                    out[(row, col)] /= c as f64;
                }
            }
        }
    }
    Ok((kinds, out))
}

/// Modal stress fields of `body` reduced from `mesh` (same node numbering, extra nodes after the
/// mesh nodes): the nodal stress of each mode shape.
pub fn modal_stress(
    mesh: &Mesh,
    body: &ReducedBody,
    fibres: &dyn Fn(usize, &BeamSection) -> BeamFibres,
) -> Result<ModalStress, FeError> {
    let r = body.modes_r.as_ref().map(|r| r.as_ref());
    let (kinds, fields) =
        nodal_stress_fields(mesh, body.num_nodes(), body.modes_t.as_ref(), r, fibres)?;
    Ok(ModalStress { kinds, fields })
}

/// Default fibre rule: [`BeamFibres::equivalent_rectangle`] of the section.
pub fn default_fibres(_property: usize, s: &BeamSection) -> BeamFibres {
    BeamFibres::equivalent_rectangle(s)
}

/// Static displacements of a constrained FE system under nodal loads: solves `K v = T^T f`
/// (sparse Cholesky) and expands `v` to nodal translation and rotation fields (`3 N x 1` each,
/// as [`ReducedBody::modes_t`] / `modes_r`). `loads` are `(node, [Fx, Fy, Fz, Mx, My, Mz])` in
/// body axes; moments at nodes without rotations are an error.
pub fn static_displacements(
    sys: &crate::system::FeSystem,
    loads: &[(crate::NodeIdx, [f64; 6])],
) -> Result<(Mat<f64>, Mat<f64>), FeError> {
    let map = &sys.map;
    let mut f = Mat::<f64>::zeros(sys.len(), 1);
    for &(node, load) in loads {
        for (dir, &v) in load.iter().enumerate() {
            if v == 0.0 {
                continue;
            }
            let eq = map.dofs.dof(node, dir).ok_or_else(|| {
                FeError::Invalid(format!("load on node {node} direction {dir}: no such DOF"))
            })?;
            for &(p, c) in &map.rows[eq] {
                f[(p, 0)] += c * v;
            }
        }
    }
    let chol = crate::eigen::SparseCholesky::factor(&sys.k)?;
    chol.solve_in_place(f.as_mut());
    Ok(map.expand(f.as_ref()))
}

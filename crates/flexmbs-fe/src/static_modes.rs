//! Static responses to load patterns as extra basis vectors of a modal basis (modal truncation
//! augmentation).
//!
//! A basis of the lowest modes converges slowly for a load that acts on a small region (a contact,
//! a point force): the local deformation under the load lies in the high modes. The static
//! response `x = K^-1 f` to the load pattern `f` holds it; appended to the modes it makes the
//! quasi-static part of the response exact (Dickens and Wilson's modal truncation augmentation;
//! Craig-Bampton's constraint modes are the static responses of interface displacements).
//!
//! The vectors are stored as computed (`K^-1 f`, scaled to unit `M`-norm), not orthogonalized
//! against the modes: any subset of the modes together with them spans the same space as the
//! subset with its own augmentation vectors, so a multibody model may keep fewer modes than the
//! reduction computed. The reduced matrices then couple the modes and the static vectors (an FFR
//! body takes full `K_ff`, `M_ff`). The frequencies reported for the static vectors are those of
//! the augmentation block: the eigenvalues of the pair restricted to their part `M`-orthogonal to
//! the modes, which with the modal frequencies are the eigenvalues of the whole reduced pair.

use faer::Mat;

use crate::eigen::{dense_generalized, SparseCholesky};
use crate::system::{sparse_times, FeSystem};
use crate::FeError;

/// A static load pattern over a system's independent DOFs.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticLoad {
    /// Name used in the basis vector's label (`static load <name>`).
    pub name: String,
    /// The load pattern `f` over the independent DOFs.
    pub force: Vec<f64>,
}

/// Smallest part of a static response (relative, in the `M`-norm) outside the modes and the
/// earlier static responses; below it the response adds nothing to the basis and is refused.
pub const INDEPENDENCE_TOLERANCE: f64 = 1e-6;

/// The static responses `x_i = K^-1 f_i` of `loads`, each scaled to `x^T M x = 1` (columns), and
/// the eigenvalues `omega^2` (ascending) of the augmentation block: the pair `(K, M)` projected on
/// the parts of the responses `M`-orthogonal to the modes `v` (`M`-orthonormal columns over the
/// independent DOFs) and to each other.
///
/// Errors: a body without supports ([`FeError::Invalid`]: `K` is singular), a load that acts on
/// fixed DOFs only, a response (nearly) in the span of the modes and the earlier responses.
pub fn static_responses(
    sys: &FeSystem,
    v: faer::MatRef<'_, f64>,
    loads: &[StaticLoad],
) -> Result<(Mat<f64>, Vec<f64>), FeError> {
    let n = sys.len();
    if loads.is_empty() {
        return Ok((Mat::zeros(n, 0), Vec::new()));
    }
    let chol = SparseCholesky::factor(&sys.k).map_err(|e| match e {
        FeError::NotPositiveDefinite { .. } => FeError::Invalid(
            "static load responses need a supported body: the stiffness of a body without \
             fixed nodes is singular (give the body supports, or use a Craig-Bampton basis)"
                .into(),
        ),
        e => e,
    })?;
    let mut x = Mat::<f64>::zeros(n, loads.len());
    for (j, load) in loads.iter().enumerate() {
        if load.force.len() != n {
            return Err(FeError::Invalid(format!(
                "static load {}: {} entries for {n} independent DOFs",
                load.name,
                load.force.len()
            )));
        }
        if load.force.iter().all(|f| *f == 0.0) {
            return Err(FeError::Invalid(format!(
                "static load {} acts on fixed DOFs only: its response is zero",
                load.name
            )));
        }
        for (i, f) in load.force.iter().enumerate() {
            x[(i, j)] = *f;
        }
    }
    chol.solve_in_place(x.as_mut());
    let mx = sparse_times(&sys.m, x.as_ref());
    for j in 0..loads.len() {
        let norm = (x.col(j).transpose() * mx.col(j)).sqrt();
        for i in 0..n {
            x[(i, j)] /= norm;
        }
    }
    let y = orthogonal_parts(sys, v, x.as_ref(), loads)?;
    let ky = crate::modes::project_dense(&sys.k, y.as_ref());
    let my = crate::modes::project_dense(&sys.m, y.as_ref());
    let (mut omega2, _) = dense_generalized(ky.as_ref(), my.as_ref())?;
    omega2.sort_by(f64::total_cmp);
    Ok((x, omega2))
}

/// The parts of the columns of `x` (unit `M`-norm) `M`-orthogonal to `v` and to the earlier
/// columns, `M`-orthonormalised (classical Gram-Schmidt, twice); refuses a column whose part is
/// below [`INDEPENDENCE_TOLERANCE`].
fn orthogonal_parts(
    sys: &FeSystem,
    v: faer::MatRef<'_, f64>,
    x: faer::MatRef<'_, f64>,
    loads: &[StaticLoad],
) -> Result<Mat<f64>, FeError> {
    let n = sys.len();
    let mut y = Mat::<f64>::zeros(n, x.ncols());
    for j in 0..x.ncols() {
        let mut col = x.col(j).to_owned();
        for _ in 0..2 {
            let mcol = sparse_times(&sys.m, col.as_mat());
            for k in 0..v.ncols() {
                let c = v.col(k).transpose() * mcol.col(0);
                for i in 0..n {
                    col[i] -= c * v[(i, k)];
                }
            }
            for k in 0..j {
                let c = y.col(k).transpose() * mcol.col(0);
                for i in 0..n {
                    col[i] -= c * y[(i, k)];
                }
            }
        }
        let mcol = sparse_times(&sys.m, col.as_mat());
        let part = (col.transpose() * mcol.col(0)).max(0.0).sqrt();
        if part.is_nan() || part <= INDEPENDENCE_TOLERANCE {
            return Err(FeError::Invalid(format!(
                "the static response to load {} lies in the span of the modes and the earlier \
                 static loads (its part outside them is {part:.1e} of its size): it adds nothing \
                 to the basis; remove the load",
                loads[j].name
            )));
        }
        for i in 0..n {
            y[(i, j)] = col[i] / part;
        }
    }
    Ok(y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraint::BoundaryConditions;
    use crate::element::MassKind;
    use crate::mesh::generate::box_mesh;
    use crate::reduction::modal_analysis;
    use crate::{ElementKind, Material, UnitSystem};
    use faer::linalg::solvers::Solve;

    /// A clamped hex8i cantilever 1 x 0.1 x 0.1 m.
    fn cantilever() -> FeSystem {
        let mesh = box_mesh(
            [1.0, 0.1, 0.1],
            [10, 1, 1],
            ElementKind::Hex8I,
            Material::steel(),
            UnitSystem::Si,
        )
        .unwrap();
        let bc = BoundaryConditions {
            fixed: mesh.node_set("xmin").unwrap().to_vec(),
            rigid: Vec::new(),
        };
        FeSystem::assemble(&mesh, &bc, MassKind::Consistent, &mut |_, _| {}).unwrap()
    }

    fn tip_load(sys: &FeSystem, dir: usize) -> StaticLoad {
        let mut force = vec![0.0; sys.len()];
        for (p, d) in sys.map.independent.iter().enumerate() {
            if d.dir == dir && (sys.map.nodes[d.node][0] - 1.0).abs() < 1e-9 {
                force[p] = 1.0;
            }
        }
        StaticLoad {
            name: format!("tip {dir}"),
            force,
        }
    }

    /// `K x = f` for the returned vector up to its scale; the augmentation frequency lies above
    /// the kept modes; the whole basis spans the static response exactly (Rayleigh-Ritz on
    /// modes + static response reproduces the static tip deflection to round-off).
    #[test]
    fn static_response_solves_the_load_and_completes_the_statics() {
        let sys = cantilever();
        let modal =
            modal_analysis(&sys, 3, &crate::eigen::EigenOptions::default(), &mut |_| {}).unwrap();
        let v = modal.vectors.as_ref().subcols(0, 3);
        let load = tip_load(&sys, 1);
        let (x, w2) = static_responses(&sys, v, std::slice::from_ref(&load)).unwrap();
        assert_eq!((x.ncols(), w2.len()), (1, 1));
        // K x is parallel to f
        let kx = sparse_times(&sys.k, x.as_ref());
        let scale = kx
            .col(0)
            .iter()
            .zip(&load.force)
            .map(|(a, b)| a * b)
            .sum::<f64>()
            / load.force.iter().map(|b| b * b).sum::<f64>();
        let residual = (0..sys.len())
            .map(|i| (kx[(i, 0)] - scale * load.force[i]).abs())
            .fold(0.0, f64::max);
        let kmax = kx.col(0).iter().fold(0.0f64, |m, a| m.max(a.abs()));
        assert!(residual < 1e-9 * kmax, "residual {residual:e} of {kmax:e}");
        assert!(w2[0] > modal.omega2[2], "{} <= {}", w2[0], modal.omega2[2]);
        // Ritz statics on [modes, x] equal the full statics (x is in the basis)
        let mut basis = Mat::<f64>::zeros(sys.len(), 4);
        basis.as_mut().subcols_mut(0, 3).copy_from(v);
        basis.col_mut(3).copy_from(x.col(0));
        let kr = crate::modes::project_dense(&sys.k, basis.as_ref());
        let fr: Mat<f64> = Mat::from_fn(4, 1, |i, _| {
            (0..sys.len()).map(|p| basis[(p, i)] * load.force[p]).sum()
        });
        let qr = kr.as_ref().partial_piv_lu().solve(fr.as_ref());
        let ur = &basis * &qr;
        let full = {
            let mut f = Mat::from_fn(sys.len(), 1, |i, _| load.force[i]);
            SparseCholesky::factor(&sys.k)
                .unwrap()
                .solve_in_place(f.as_mut());
            f
        };
        let err = (0..sys.len())
            .map(|i| (ur[(i, 0)] - full[(i, 0)]).abs())
            .fold(0.0, f64::max);
        let umax = full.col(0).iter().fold(0.0f64, |m, a| m.max(a.abs()));
        assert!(err < 1e-8 * umax, "Ritz statics off by {err:e} of {umax:e}");
        // the modes alone miss part of it
        let kr3 = crate::modes::project_dense(&sys.k, v);
        let fr3 = fr.as_ref().subrows(0, 3);
        let u3 = v * kr3.as_ref().partial_piv_lu().solve(fr3);
        let err3 = (0..sys.len())
            .map(|i| (u3[(i, 0)] - full[(i, 0)]).abs())
            .fold(0.0, f64::max);
        assert!(err3 > 1e3 * err, "modes alone: {err3:e}");
    }

    #[test]
    fn refusals_name_the_cause() {
        let sys = cantilever();
        let modal =
            modal_analysis(&sys, 3, &crate::eigen::EigenOptions::default(), &mut |_| {}).unwrap();
        let v = modal.vectors.as_ref().subcols(0, 3);
        // twice the same load: the second adds nothing
        let l = tip_load(&sys, 1);
        let e = static_responses(&sys, v, &[l.clone(), l]).unwrap_err();
        assert!(e.to_string().contains("lies in the span"), "{e}");
        // a load on fixed DOFs only
        let zero = StaticLoad {
            name: "root".into(),
            force: vec![0.0; sys.len()],
        };
        let e = static_responses(&sys, v, &[zero]).unwrap_err();
        assert!(e.to_string().contains("fixed DOFs only"), "{e}");
    }
}

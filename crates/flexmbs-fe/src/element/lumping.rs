//! Diagonal (lumped) mass matrices by the HRZ method (Hinton, Rock and Zienkiewicz 1976).
//!
//! For each translation direction c, the diagonal entries M_ii of the consistent matrix that
//! belong to c are scaled by m_c / sum_i M_ii, where m_c = u_c^T M u_c is the element mass seen
//! by a unit translation in c. Since every consistent diagonal entry int rho N_a^2 dV is positive,
//! the lumped masses are positive and sum to the element mass. Row-sum lumping is not used: it
//! gives negative corner masses for 20-node serendipity elements.

use crate::FeError;
use nalgebra::DMatrix;

/// HRZ-lumped diagonal mass of a solid element with 3 translational DOFs per node (node-major).
pub fn hrz_lump_solid(m: &DMatrix<f64>, element: usize) -> Result<DMatrix<f64>, FeError> {
    let nd = m.nrows();
    if !nd.is_multiple_of(3) || m.ncols() != nd {
        return Err(FeError::Invalid(format!(
            "element {element}: mass matrix {}x{} is not 3n x 3n",
            nd,
            m.ncols()
        )));
    }
    let nn = nd / 3;
    let mut out = DMatrix::zeros(nd, nd);
    for c in 0..3 {
        let mut total = 0.0;
        let mut diag = 0.0;
        for a in 0..nn {
            diag += m[(3 * a + c, 3 * a + c)];
            for b in 0..nn {
                total += m[(3 * a + c, 3 * b + c)];
            }
        }
        for a in 0..nn {
            let mii = m[(3 * a + c, 3 * a + c)];
            if mii.is_nan() || mii <= 0.0 || diag <= 0.0 {
                return Err(FeError::Invalid(format!(
                    "element {element}: consistent mass diagonal {mii:e} at DOF {} is not positive; cannot lump",
                    3 * a + c
                )));
            }
            out[(3 * a + c, 3 * a + c)] = mii * total / diag;
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hrz_preserves_mass_and_keeps_positive() {
        // a 2-node bar consistent mass rho A L/6 [2 1; 1 2] in 3D: lumps to rho A L/2 per node
        let mut m = DMatrix::zeros(6, 6);
        for c in 0..3 {
            m[(c, c)] = 2.0;
            m[(3 + c, 3 + c)] = 2.0;
            m[(c, 3 + c)] = 1.0;
            m[(3 + c, c)] = 1.0;
        }
        let l = hrz_lump_solid(&m, 0).unwrap();
        for i in 0..6 {
            assert!((l[(i, i)] - 3.0).abs() < 1e-15);
        }
        // a negative diagonal is rejected with an error
        m[(0, 0)] = -1.0;
        assert!(hrz_lump_solid(&m, 0).is_err());
    }
}

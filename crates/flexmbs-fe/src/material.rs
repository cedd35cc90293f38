//! Linear isotropic elastic material.

use crate::{FeError, UnitSystem};
use nalgebra::Matrix6;
use serde::{Deserialize, Serialize};

/// Linear isotropic elastic material: Young's modulus `e`, Poisson's ratio `nu`, density `rho`,
/// in the unit system of the mesh it is used with.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Young's modulus E.
    pub e: f64,
    /// Poisson's ratio nu (0 <= nu < 0.5).
    pub nu: f64,
    /// Mass density rho.
    pub rho: f64,
}

impl Material {
    /// Creates a checked material.
    pub fn new(e: f64, nu: f64, rho: f64) -> Result<Self, FeError> {
        let m = Self { e, nu, rho };
        m.validate()?;
        Ok(m)
    }

    /// Structural steel in SI: E = 210 GPa, nu = 0.3, rho = 7850 kg/m^3.
    pub fn steel() -> Self {
        Self { e: 210e9, nu: 0.3, rho: 7850.0 }
    }

    /// Checks E > 0, -1 < nu < 0.5, rho > 0, all finite.
    pub fn validate(&self) -> Result<(), FeError> {
        if !(self.e.is_finite() && self.e > 0.0) {
            return Err(FeError::Invalid(format!("Young's modulus must be > 0, got {}", self.e)));
        }
        if !(self.nu.is_finite() && self.nu > -1.0 && self.nu < 0.5) {
            return Err(FeError::Invalid(format!("Poisson's ratio must be in (-1, 0.5), got {}", self.nu)));
        }
        if !(self.rho.is_finite() && self.rho > 0.0) {
            return Err(FeError::Invalid(format!("density must be > 0, got {}", self.rho)));
        }
        Ok(())
    }

    /// Shear modulus G = E / (2 (1 + nu)).
    pub fn shear_modulus(&self) -> f64 {
        self.e / (2.0 * (1.0 + self.nu))
    }

    /// The same material expressed in SI, from values given in `units`.
    pub fn to_si(&self, units: UnitSystem) -> Self {
        Self { e: self.e * units.stress_to_si(), nu: self.nu, rho: self.rho * units.density_to_si() }
    }

    /// Isotropic elasticity matrix in Voigt order (xx, yy, zz, xy, yz, zx) with engineering shear strains.
    pub fn elasticity_matrix(&self) -> Matrix6<f64> {
        let (e, nu) = (self.e, self.nu);
        let lam = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let g = self.shear_modulus();
        let mut d = Matrix6::zeros();
        for i in 0..3 {
            for j in 0..3 {
                d[(i, j)] = lam;
            }
            d[(i, i)] = lam + 2.0 * g;
            d[(i + 3, i + 3)] = g;
        }
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniaxial_stress_gives_young_modulus() {
        let m = Material::steel();
        // compliance: invert D, the xx-xx entry of C must be 1/E and xx-yy -nu/E
        let c = m.elasticity_matrix().try_inverse().unwrap();
        assert!((c[(0, 0)] * m.e - 1.0).abs() < 1e-12);
        assert!((c[(0, 1)] * m.e + m.nu).abs() < 1e-12);
        assert!((c[(3, 3)] * m.shear_modulus() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn rejects_bad_values() {
        assert!(Material::new(-1.0, 0.3, 1.0).is_err());
        assert!(Material::new(1.0, 0.5, 1.0).is_err());
        assert!(Material::new(1.0, 0.3, 0.0).is_err());
        assert!(Material::new(f64::NAN, 0.3, 1.0).is_err());
    }
}

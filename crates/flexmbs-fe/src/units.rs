//! Consistent unit systems (seed 000 Table 5.1).
//!
//! | System  | Length | Force | Mass  | Time | Stress | Energy | Density |
//! |---------|--------|-------|-------|------|--------|--------|---------|
//! | SI      | m      | N     | kg    | s    | Pa     | J      | kg/m^3  |
//! | SI(mm)  | mm     | N     | t     | s    | MPa    | mJ     | t/mm^3  |

use serde::{Deserialize, Serialize};

/// A consistent system of units. All flexmbs simulations run in [`UnitSystem::Si`];
/// FE data given in another system is converted when it enters a model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum UnitSystem {
    /// m, N, kg, s.
    #[default]
    #[serde(rename = "SI")]
    Si,
    /// mm, N, t (1000 kg), s.
    #[serde(rename = "SI(mm)", alias = "SI_mm", alias = "mm")]
    SiMm,
}

impl UnitSystem {
    /// Length of one unit of this system in metres.
    pub fn length_to_si(self) -> f64 {
        match self {
            UnitSystem::Si => 1.0,
            UnitSystem::SiMm => 1e-3,
        }
    }
    /// Mass of one unit of this system in kilograms.
    pub fn mass_to_si(self) -> f64 {
        match self {
            UnitSystem::Si => 1.0,
            UnitSystem::SiMm => 1e3,
        }
    }
    /// Force of one unit in newtons (1 in both systems).
    pub fn force_to_si(self) -> f64 {
        1.0
    }
    /// Stiffness (force/length) of one unit in N/m.
    pub fn stiffness_to_si(self) -> f64 {
        self.force_to_si() / self.length_to_si()
    }
    /// Stress (force/length^2) of one unit in Pa.
    pub fn stress_to_si(self) -> f64 {
        self.force_to_si() / self.length_to_si().powi(2)
    }
    /// Density (mass/length^3) of one unit in kg/m^3.
    pub fn density_to_si(self) -> f64 {
        self.mass_to_si() / self.length_to_si().powi(3)
    }
    /// Energy (force x length) of one unit in J.
    pub fn energy_to_si(self) -> f64 {
        self.force_to_si() * self.length_to_si()
    }
    /// Scale of mass-normalised mode shapes: `Phi_si = Phi * mode_to_si()` keeps
    /// `Phi_si^T M_si Phi_si = I` (a mass-normalised mode has units 1/sqrt(mass), independent of
    /// length); the modal coordinate scales as `q_si = q * length_to_si / mode_to_si`.
    pub fn mode_to_si(self) -> f64 {
        1.0 / self.mass_to_si().sqrt()
    }
    /// Short name as written in files.
    pub fn name(self) -> &'static str {
        match self {
            UnitSystem::Si => "SI",
            UnitSystem::SiMm => "SI(mm)",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Steel in SI(mm) (seed 000 §5.1) converts to the familiar SI values.
    #[test]
    fn si_mm_steel_converts() {
        let u = UnitSystem::SiMm;
        assert!((7.987e-9 * u.density_to_si() - 7987.0).abs() < 1e-9);
        assert!((210000.0 * u.stress_to_si() - 210e9).abs() < 1e-3);
        assert!((1.0 * u.energy_to_si() - 1e-3).abs() < 1e-18);
        // frequency is invariant: sqrt(k/m) with k in N/mm and m in t
        let k_si = 1.0 * u.stiffness_to_si();
        let m_si = 1.0 * u.mass_to_si();
        assert!(((k_si / m_si).sqrt() - 1.0).abs() < 1e-12);
    }
}

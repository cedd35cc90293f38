//! The `result.json` of a validation case.

use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// Outcome of a validation case.
#[derive(Debug, Clone, Serialize)]
pub struct ValidationResult {
    /// Case name.
    pub case: String,
    /// Computed quantities (SI, Hz for `_hz`).
    pub quantities: BTreeMap<String, f64>,
    /// Reference values.
    pub reference: BTreeMap<String, f64>,
    /// Relative tolerances.
    pub tolerance: BTreeMap<String, f64>,
    /// Whether every quantity with a reference is within its tolerance.
    pub pass: bool,
    /// Free-form details (tables, notes).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub details: BTreeMap<String, serde_json::Value>,
}

impl ValidationResult {
    /// An empty result for `case`.
    pub fn new(case: &str) -> Self {
        Self {
            case: case.to_string(),
            quantities: BTreeMap::new(),
            reference: BTreeMap::new(),
            tolerance: BTreeMap::new(),
            pass: true,
            details: BTreeMap::new(),
        }
    }

    /// Records a quantity with its reference and relative tolerance and updates `pass`.
    pub fn check(&mut self, name: &str, value: f64, reference: f64, rel_tol: f64) {
        self.quantities.insert(name.to_string(), value);
        self.reference.insert(name.to_string(), reference);
        self.tolerance.insert(name.to_string(), rel_tol);
        let within = Self::rel_err(value, reference) <= rel_tol; // false for NaN
        if !within {
            self.pass = false;
        }
    }

    /// Records a quantity without a reference.
    pub fn record(&mut self, name: &str, value: f64) {
        self.quantities.insert(name.to_string(), value);
    }

    /// Relative error |v - r| / |r|.
    pub fn rel_err(v: f64, r: f64) -> f64 {
        (v - r).abs() / r.abs()
    }

    /// Writes `result.json`.
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        let s = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        std::fs::write(path, s + "\n")
    }

    /// A short text summary: one line per checked quantity.
    pub fn summary(&self) -> String {
        let mut s = format!(
            "{}: {}\n",
            self.case,
            if self.pass { "PASS" } else { "FAIL" }
        );
        for (k, r) in &self.reference {
            let v = self.quantities[k];
            let e = Self::rel_err(v, *r);
            let tol = self.tolerance[k];
            s += &format!(
                "  {k:24} {v:14.6} ref {r:14.6}  err {:+.4} %  tol {:.3} %  {}\n",
                100.0 * (v - r) / r,
                100.0 * tol,
                if e <= tol { "ok" } else { "FAIL" }
            );
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_fails_outside_tolerance_and_on_nan() {
        let mut r = ValidationResult::new("x");
        r.check("a", 1.001, 1.0, 0.01);
        assert!(r.pass);
        r.check("b", 1.1, 1.0, 0.01);
        assert!(!r.pass);
        let mut r = ValidationResult::new("x");
        r.check("c", f64::NAN, 1.0, 0.01);
        assert!(!r.pass);
    }
}

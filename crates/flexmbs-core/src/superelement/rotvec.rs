//! The rotation vector (logarithm of a rotation) as the measure of local interface rotations, its
//! inverse left Jacobian and that Jacobian's derivative: the pieces the superelement's exact
//! variation and tangent need (`docs/engine.md`, "Superelements").
//!
//! Conventions: `exp(a~)` is the rotation by the vector `a`; the left Jacobian `J_l(θ)` is defined
//! by `exp((θ + δθ)~) = exp((J_l(θ) δθ)~) exp(θ~)` to first order, so a left increment `δπ` of the
//! rotation changes the rotation vector by `δθ = J_l⁻¹(θ) δπ`.

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

use crate::rotation::skew;

/// Below this angle (rad) the series of `b(φ)` and `b'(φ)/φ` are used (error < 1e-17).
const SERIES_ANGLE: f64 = 1e-2;

/// Rotation vector `θ = log(p)` of a unit quaternion (`|θ| ≤ π`), accurate for small angles
/// (no `acos`).
pub fn log_quaternion(p: &UnitQuaternion<f64>) -> Vector3<f64> {
    let (mut w, mut v) = (p.w, p.imag());
    if w < 0.0 {
        w = -w;
        v = -v;
    }
    let s = v.norm();
    if s < 1e-300 {
        return v * (2.0 / w.max(1e-300));
    }
    v * (2.0 * s.atan2(w) / s)
}

/// Unit quaternion `exp(θ)` of a rotation vector.
pub fn exp_quaternion(theta: &Vector3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::from_scaled_axis(*theta)
}

/// Quaternion `[w, x, y, z]` of a pose node's coordinates as a unit quaternion (normalized).
pub fn node_quaternion(q: &[f64]) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(Quaternion::new(q[0], q[1], q[2], q[3]))
}

/// `b(φ) = 1/φ² − (1 + cos φ) / (2 φ sin φ)` and `b'(φ)/φ`: the coefficient of `θ~θ~` in
/// `J_l⁻¹(θ) = I − ½ θ~ + b(φ) θ~θ~` (`φ = |θ|`) and its derivative over `φ`.
fn inverse_jacobian_coefficient(phi: f64) -> (f64, f64) {
    if phi < SERIES_ANGLE {
        let p2 = phi * phi;
        // b = 1/12 + φ²/720 + φ⁴/30240 (from x cot x = 1 − x²/3 − x⁴/45 − 2x⁶/945, x = φ/2)
        (
            1.0 / 12.0 + p2 / 720.0 + p2 * p2 / 30240.0,
            1.0 / 360.0 + p2 / 7560.0,
        )
    } else {
        let half = 0.5 * phi;
        let cot = half.cos() / half.sin();
        let csc2 = 1.0 / (half.sin() * half.sin());
        // c(φ) = cot(φ/2) / (2φ), b = 1/φ² − c
        let b = 1.0 / (phi * phi) - cot / (2.0 * phi);
        let dc = -csc2 / (4.0 * phi) - cot / (2.0 * phi * phi);
        let db = -2.0 / phi.powi(3) - dc;
        (b, db / phi)
    }
}

/// Inverse left Jacobian `J_l⁻¹(θ) = I − ½ θ~ + b(|θ|) θ~θ~`.
pub fn inverse_left_jacobian(theta: &Vector3<f64>) -> Matrix3<f64> {
    let (b, _) = inverse_jacobian_coefficient(theta.norm());
    let t = skew(theta);
    Matrix3::identity() - 0.5 * t + b * t * t
}

/// `∂(J_l⁻ᵀ(θ) m)/∂θ` for a fixed vector `m`, with `J_l⁻ᵀ(θ) m = m + ½ θ×m + b θ×(θ×m)`:
/// `−½ m~ + θ×(θ×m) (b'/φ) θᵀ + b ((θ·m) I + θ mᵀ − 2 m θᵀ)`.
pub fn inverse_left_jacobian_transpose_derivative(
    theta: &Vector3<f64>,
    m: &Vector3<f64>,
) -> Matrix3<f64> {
    let (b, db_over_phi) = inverse_jacobian_coefficient(theta.norm());
    let ttm = theta.cross(&theta.cross(m));
    -0.5 * skew(m)
        + ttm * theta.transpose() * db_over_phi
        + b * (Matrix3::identity() * theta.dot(m) + theta * m.transpose()
            - 2.0 * m * theta.transpose())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn left_jacobian_fd(theta: &Vector3<f64>) -> Matrix3<f64> {
        // columns: log(exp(θ + ε e_i) exp(θ)^-1) / ε, central
        let mut j = Matrix3::zeros();
        let base = exp_quaternion(theta);
        for i in 0..3 {
            let mut d = Vector3::zeros();
            d[i] = 1e-6;
            let plus = log_quaternion(&(exp_quaternion(&(theta + d)) * base.inverse()));
            let minus = log_quaternion(&(exp_quaternion(&(theta - d)) * base.inverse()));
            j.set_column(i, &((plus - minus) / 2e-6));
        }
        j
    }

    #[test]
    fn log_inverts_exp_at_small_and_large_angles() {
        for theta in [
            Vector3::new(1e-9, -2e-9, 3e-10),
            Vector3::new(0.003, -0.002, 0.001),
            Vector3::new(0.4, -1.1, 0.7),
            Vector3::new(0.0, 3.0, 0.0),
        ] {
            let back = log_quaternion(&exp_quaternion(&theta));
            assert!((back - theta).norm() <= 1e-15 * (1.0 + theta.norm()) * 4.0);
        }
    }

    #[test]
    fn inverse_left_jacobian_inverts_the_finite_difference_left_jacobian() {
        for theta in [
            Vector3::new(0.002, -0.004, 0.001),
            Vector3::new(0.4, -1.1, 0.7),
            Vector3::new(-0.05, 0.02, 0.009),
        ] {
            let e = inverse_left_jacobian(&theta) * left_jacobian_fd(&theta) - Matrix3::identity();
            assert!(e.norm() < 1e-8, "{theta:?}: {e}");
        }
    }

    #[test]
    fn derivative_of_inverse_jacobian_transpose_matches_finite_differences() {
        let m = Vector3::new(0.3, -1.2, 0.8);
        for theta in [
            Vector3::new(0.002, -0.004, 0.001),
            Vector3::new(0.004, 0.009, -0.003),
            Vector3::new(0.4, -1.1, 0.7),
        ] {
            let d = inverse_left_jacobian_transpose_derivative(&theta, &m);
            for i in 0..3 {
                let mut e = Vector3::zeros();
                e[i] = 1e-6;
                let fd = (inverse_left_jacobian(&(theta + e)).transpose() * m
                    - inverse_left_jacobian(&(theta - e)).transpose() * m)
                    / 2e-6;
                assert!((fd - d.column(i)).norm() < 1e-9, "{theta:?} col {i}");
            }
        }
    }
}

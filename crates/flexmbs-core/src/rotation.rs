//! Rotation parametrizations (Cardan angles, seed 000 (2.22), (2.31); unit quaternions;
//! rotation vectors).
//!
//! Conventions (see `docs/notation-ffr.md`): `A` maps body-frame components to global
//! components (`r = R + A u_bar`, seed 000 (2.21)); `omega_bar` is the angular velocity of the
//! body frame expressed in the body frame, `skew(omega_bar) = A^T A_dot`.

use nalgebra::{Matrix3, Matrix3x4, Vector3, Vector4};
use thiserror::Error;

/// Errors of the rotation parametrizations.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum RotationError {
    /// The Cardan angle beta is (close to) +-pi/2 where `G_bar` (2.31) is singular.
    #[error("Cardan angles singular: beta = {beta} (|cos beta| = {cos_beta:e} < {tolerance:e}); quaternion rotation coordinates have no such singularity")]
    CardanSingular {
        /// The second Cardan angle.
        beta: f64,
        /// |cos(beta)| = |det G_bar|.
        cos_beta: f64,
        /// Threshold used.
        tolerance: f64,
    },
    /// A quaternion of (nearly) zero or non-finite norm cannot be normalized.
    #[error("quaternion cannot be normalized: norm = {norm}")]
    DegenerateQuaternion {
        /// Its Euclidean norm.
        norm: f64,
    },
}

/// `|cos beta|` below which Cardan angles are singular ([`check_cardan`]): rigid and FFR bodies
/// refuse to evaluate there.
pub const CARDAN_SINGULARITY_TOLERANCE: f64 = 1e-8;

/// Skew-symmetric cross-product matrix `skew(a) b = a x b` (seed 000 (2.29)).
#[inline]
pub fn skew(a: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// Axial vector of the skew-symmetric part of `m`: `unskew(skew(a)) = a`.
#[inline]
pub fn unskew(m: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        0.5 * (m[(2, 1)] - m[(1, 2)]),
        0.5 * (m[(0, 2)] - m[(2, 0)]),
        0.5 * (m[(1, 0)] - m[(0, 1)]),
    )
}

/// Rotation matrix of the Cardan (Tait-Bryan x-y-z) angles `theta = (alpha, beta, gamma)`,
/// `A = Rx(alpha) Ry(beta) Rz(gamma)`, exactly seed 000 (2.22).
pub fn cardan_matrix(theta: &Vector3<f64>) -> Matrix3<f64> {
    let (sa, ca) = theta.x.sin_cos();
    let (sb, cb) = theta.y.sin_cos();
    let (sg, cg) = theta.z.sin_cos();
    Matrix3::new(
        cb * cg,
        -cb * sg,
        sb,
        ca * sg + cg * sa * sb,
        ca * cg - sa * sb * sg,
        -cb * sa,
        sa * sg - ca * cg * sb,
        cg * sa + ca * sb * sg,
        ca * cb,
    )
}

/// Body-frame angular velocity matrix of the Cardan angles, seed 000 (2.31):
/// `omega_bar = G_bar(theta) theta_dot`. `det G_bar = cos(beta)`.
pub fn cardan_g_bar(theta: &Vector3<f64>) -> Matrix3<f64> {
    let (sb, cb) = theta.y.sin_cos();
    let (sg, cg) = theta.z.sin_cos();
    Matrix3::new(cb * cg, sg, 0.0, -cb * sg, cg, 0.0, sb, 0.0, 1.0)
}

/// Time derivative of [`cardan_g_bar`], seed 000 (2.80).
pub fn cardan_g_bar_dot(theta: &Vector3<f64>, theta_dot: &Vector3<f64>) -> Matrix3<f64> {
    let (sb, cb) = theta.y.sin_cos();
    let (sg, cg) = theta.z.sin_cos();
    let (bd, gd) = (theta_dot.y, theta_dot.z);
    Matrix3::new(
        -sb * cg * bd - cb * sg * gd,
        cg * gd,
        0.0,
        sb * sg * bd - cb * cg * gd,
        -sg * gd,
        0.0,
        cb * bd,
        0.0,
        0.0,
    )
}

/// Global `G(alpha, beta)` with `omega = G theta_dot` for Cardan x-y-z angles (`G = A G_bar`,
/// seed 000 (2.31)).
pub fn cardan_g(a: f64, b: f64) -> Matrix3<f64> {
    let (sa, ca) = a.sin_cos();
    let (sb, cb) = b.sin_cos();
    Matrix3::new(1.0, 0.0, sb, 0.0, ca, -sa * cb, 0.0, sa, ca * cb)
}

/// `G_dot theta_dot` (global `G`, see [`cardan_g`]) for Cardan x-y-z angles.
pub fn cardan_g_dot_theta_dot(a: f64, b: f64, td: &Vector3<f64>) -> Vector3<f64> {
    let (sa, ca) = a.sin_cos();
    let (sb, cb) = b.sin_cos();
    let dg_da = Matrix3::new(0.0, 0.0, 0.0, 0.0, -sa, -ca * cb, 0.0, ca, -sa * cb);
    let dg_db = Matrix3::new(0.0, 0.0, cb, 0.0, 0.0, sa * sb, 0.0, 0.0, -ca * sb);
    (dg_da * td.x + dg_db * td.y) * td
}

/// Checks that the Cardan angles are away from the singularity `beta = +-pi/2`:
/// error if `|cos beta| < tolerance` (then `G_bar` (2.31) cannot be inverted).
pub fn check_cardan(theta: &Vector3<f64>, tolerance: f64) -> Result<(), RotationError> {
    let cos_beta = theta.y.cos().abs();
    if cos_beta < tolerance || !cos_beta.is_finite() {
        return Err(RotationError::CardanSingular {
            beta: theta.y,
            cos_beta,
            tolerance,
        });
    }
    Ok(())
}

/// Cardan angles of a rotation matrix (inverse of [`cardan_matrix`], `beta` in [-pi/2, pi/2]).
/// Errors at the singularity `|cos beta| < tolerance`.
pub fn cardan_from_matrix(a: &Matrix3<f64>, tolerance: f64) -> Result<Vector3<f64>, RotationError> {
    let beta = a[(0, 2)].clamp(-1.0, 1.0).asin();
    let theta = Vector3::new(
        (-a[(1, 2)]).atan2(a[(2, 2)]),
        beta,
        (-a[(0, 1)]).atan2(a[(0, 0)]),
    );
    check_cardan(&theta, tolerance)?;
    Ok(theta)
}

/// Rotation matrix of a unit quaternion `p = [w, x, y, z]` (scalar first). The formula is the
/// homogeneous one divided by `|p|^2`, so it is orthonormal for any non-zero `p`.
pub fn quaternion_matrix(p: &Vector4<f64>) -> Matrix3<f64> {
    let (w, x, y, z) = (p[0], p[1], p[2], p[3]);
    let s = 2.0 / p.norm_squared();
    Matrix3::new(
        1.0 - s * (y * y + z * z),
        s * (x * y - w * z),
        s * (x * z + w * y),
        s * (x * y + w * z),
        1.0 - s * (x * x + z * z),
        s * (y * z - w * x),
        s * (x * z - w * y),
        s * (y * z + w * x),
        1.0 - s * (x * x + y * y),
    )
}

/// The 4 x 3 matrix `E(p)` of the quaternion kinematics `p_dot = 1/2 E(p) omega_bar`
/// (`p_dot = 1/2 p (x) [0, omega_bar]`, body-frame angular velocity). For a unit quaternion
/// `E^T E = I` and `omega_bar = 2 E^T p_dot`. Returned transposed (3 x 4) as `E^T`.
pub fn quaternion_e_transpose(p: &Vector4<f64>) -> Matrix3x4<f64> {
    let (w, x, y, z) = (p[0], p[1], p[2], p[3]);
    Matrix3x4::new(-x, w, z, -y, -y, -z, w, x, -z, y, -x, w)
}

/// Quaternion rate of a body-frame angular velocity: `p_dot = 1/2 E(p) omega_bar`.
pub fn quaternion_rate(p: &Vector4<f64>, omega_bar: &Vector3<f64>) -> Vector4<f64> {
    0.5 * quaternion_e_transpose(p).transpose() * omega_bar
}

/// Normalized copy of a quaternion; error if its norm is zero or not finite.
pub fn normalize_quaternion(p: &Vector4<f64>) -> Result<Vector4<f64>, RotationError> {
    let norm = p.norm();
    if !(norm.is_finite() && norm > 1e-300) {
        return Err(RotationError::DegenerateQuaternion { norm });
    }
    Ok(p / norm)
}

/// Unit quaternion of a rotation vector `phi` (axis times angle).
pub fn quaternion_from_rotation_vector(phi: &Vector3<f64>) -> Vector4<f64> {
    let angle = phi.norm();
    let half = 0.5 * angle;
    // sin(half)/angle, with its Taylor series near 0
    let k = if angle < 1e-6 {
        0.5 - angle * angle / 48.0
    } else {
        half.sin() / angle
    };
    Vector4::new(half.cos(), k * phi.x, k * phi.y, k * phi.z)
}

/// Rotation matrix of a rotation vector (Rodrigues' formula).
pub fn rotation_vector_matrix(phi: &Vector3<f64>) -> Matrix3<f64> {
    quaternion_matrix(&quaternion_from_rotation_vector(phi))
}

/// Below this rotation angle the SO(3) coefficient functions use their Taylor series (the
/// closed forms lose digits to cancellation near 0; at 0.5 rad the nine-term series is exact to
/// round-off and the closed forms agree with it to 1e-13 relative).
const SO3_SERIES_ANGLE: f64 = 0.5;

/// The coefficients of the SO(3) left Jacobian and their derivatives for a rotation angle
/// `phi = |theta|`: `a = (1 - cos phi)/phi^2`, `b = (phi - sin phi)/phi^3`,
/// `da = a'(phi)/phi`, `db = b'(phi)/phi` (so that `a_dot = da (theta . theta_dot)`).
fn so3_coefficients(phi: f64) -> [f64; 4] {
    if phi < SO3_SERIES_ANGLE {
        // a = sum (-1)^k phi^2k/(2k+2)!, b = sum (-1)^k phi^2k/(2k+3)!, and term-wise derivatives
        let p2 = phi * phi;
        let (mut a, mut b, mut da, mut db) = (0.0, 0.0, 0.0, 0.0);
        let mut pow = 1.0; // phi^2k
        let mut pow_m = 0.0; // phi^(2k-2)
        let mut fact = 2.0; // (2k+2)!
        let mut sign = 1.0;
        for k in 0..9 {
            let kf = k as f64;
            let fact3 = fact * (2.0 * kf + 3.0); // (2k+3)!
            a += sign * pow / fact;
            b += sign * pow / fact3;
            da += sign * 2.0 * kf * pow_m / fact;
            db += sign * 2.0 * kf * pow_m / fact3;
            pow_m = pow;
            pow *= p2;
            fact = fact3 * (2.0 * kf + 4.0);
            sign = -sign;
        }
        [a, b, da, db]
    } else {
        let (s, c) = phi.sin_cos();
        let p2 = phi * phi;
        let a = (1.0 - c) / p2;
        let b = (phi - s) / (p2 * phi);
        let da = (phi * s - 2.0 * (1.0 - c)) / (p2 * p2);
        let db = (1.0 - c) / (p2 * p2) - 3.0 * (phi - s) / (p2 * p2 * phi);
        [a, b, da, db]
    }
}

/// Left Jacobian of SO(3), `J_l(theta) = I + a skew(theta) + b skew(theta)^2` with
/// `a = (1 - cos phi)/phi^2`, `b = (phi - sin phi)/phi^3`, `phi = |theta|` (Taylor series near
/// 0): the rotation `F = exp(skew(theta))` has `F_dot F^T = skew(J_l(theta) theta_dot)`, i.e.
/// `J_l` maps the rate of a rotation vector to the angular velocity in the fixed axes.
pub fn so3_left_jacobian(theta: &Vector3<f64>) -> Matrix3<f64> {
    let [a, b, _, _] = so3_coefficients(theta.norm());
    let t = skew(theta);
    Matrix3::identity() + a * t + b * t * t
}

/// Time derivative of [`so3_left_jacobian`] along `theta_dot`:
/// `J_l_dot = a_dot skew(theta) + a skew(theta_dot) + b_dot skew(theta)^2
/// + b (skew(theta_dot) skew(theta) + skew(theta) skew(theta_dot))` with
/// `a_dot = (a'(phi)/phi) theta . theta_dot` and likewise `b_dot` (Taylor series near 0).
pub fn so3_left_jacobian_dot(theta: &Vector3<f64>, theta_dot: &Vector3<f64>) -> Matrix3<f64> {
    let [a, b, da, db] = so3_coefficients(theta.norm());
    let td = theta.dot(theta_dot);
    let t = skew(theta);
    let tdot = skew(theta_dot);
    (da * td) * t + a * tdot + (db * td) * t * t + b * (tdot * t + t * tdot)
}

/// Unit quaternion of a rotation matrix (Shepperd's method, `w >= 0`).
pub fn quaternion_from_matrix(a: &Matrix3<f64>) -> Vector4<f64> {
    let tr = a.trace();
    let p = if tr > a[(0, 0)] && tr > a[(1, 1)] && tr > a[(2, 2)] {
        let s = (1.0 + tr).sqrt() * 2.0;
        Vector4::new(
            0.25 * s,
            (a[(2, 1)] - a[(1, 2)]) / s,
            (a[(0, 2)] - a[(2, 0)]) / s,
            (a[(1, 0)] - a[(0, 1)]) / s,
        )
    } else if a[(0, 0)] > a[(1, 1)] && a[(0, 0)] > a[(2, 2)] {
        let s = (1.0 + a[(0, 0)] - a[(1, 1)] - a[(2, 2)]).sqrt() * 2.0;
        Vector4::new(
            (a[(2, 1)] - a[(1, 2)]) / s,
            0.25 * s,
            (a[(0, 1)] + a[(1, 0)]) / s,
            (a[(0, 2)] + a[(2, 0)]) / s,
        )
    } else if a[(1, 1)] > a[(2, 2)] {
        let s = (1.0 + a[(1, 1)] - a[(0, 0)] - a[(2, 2)]).sqrt() * 2.0;
        Vector4::new(
            (a[(0, 2)] - a[(2, 0)]) / s,
            (a[(0, 1)] + a[(1, 0)]) / s,
            0.25 * s,
            (a[(1, 2)] + a[(2, 1)]) / s,
        )
    } else {
        let s = (1.0 + a[(2, 2)] - a[(0, 0)] - a[(1, 1)]).sqrt() * 2.0;
        Vector4::new(
            (a[(1, 0)] - a[(0, 1)]) / s,
            (a[(0, 2)] + a[(2, 0)]) / s,
            (a[(1, 2)] + a[(2, 1)]) / s,
            0.25 * s,
        )
    };
    if p[0] < 0.0 {
        -p
    } else {
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic pseudo-random numbers in [-1, 1) (no extra dependency).
    fn rnd(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    fn rvec(seed: &mut u64, s: f64) -> Vector3<f64> {
        Vector3::new(rnd(seed) * s, rnd(seed) * s, rnd(seed) * s)
    }

    fn orthonormality_error(a: &Matrix3<f64>) -> f64 {
        (a.transpose() * a - Matrix3::identity()).abs().max() + (a.determinant() - 1.0).abs()
    }

    /// (2.22) is Rx Ry Rz, orthonormal with det 1; `cardan_from_matrix` inverts it.
    #[test]
    fn cardan_matrix_is_rotation_and_invertible() {
        let mut s = 1;
        for _ in 0..50 {
            let th = rvec(&mut s, 1.5);
            let a = cardan_matrix(&th);
            assert!(orthonormality_error(&a) < 1e-14);
            let rx = nalgebra::Rotation3::from_axis_angle(&Vector3::x_axis(), th.x);
            let ry = nalgebra::Rotation3::from_axis_angle(&Vector3::y_axis(), th.y);
            let rz = nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), th.z);
            assert!((a - (rx * ry * rz).matrix()).abs().max() < 1e-14);
            let back = cardan_from_matrix(&a, 1e-8).unwrap();
            assert!((back - th).abs().max() < 1e-12);
        }
    }

    /// skew(G_bar theta_dot) = A^T A_dot with A_dot from central differences (1e-7), and
    /// G_bar_dot (2.80) against finite differences of (2.31).
    #[test]
    fn cardan_g_bar_matches_finite_differences() {
        let mut s = 7;
        let h = 1e-5;
        for _ in 0..50 {
            let th = rvec(&mut s, 1.4);
            let thd = rvec(&mut s, 2.0);
            let a_dot =
                (cardan_matrix(&(th + h * thd)) - cardan_matrix(&(th - h * thd))) / (2.0 * h);
            let w_fd = cardan_matrix(&th).transpose() * a_dot;
            let w = cardan_g_bar(&th) * thd;
            assert!(
                (w_fd - skew(&w)).abs().max() < 1e-7,
                "{}",
                (w_fd - skew(&w)).abs().max()
            );
            let gd_fd = (cardan_g_bar(&(th + h * thd)) - cardan_g_bar(&(th - h * thd))) / (2.0 * h);
            assert!((gd_fd - cardan_g_bar_dot(&th, &thd)).abs().max() < 1e-8);
            assert!((cardan_g_bar(&th).determinant() - th.y.cos()).abs() < 1e-14);
        }
    }

    /// beta = pi/2 is reported as singular with its value.
    #[test]
    fn cardan_singularity_detected() {
        let th = Vector3::new(0.3, std::f64::consts::FRAC_PI_2, -0.2);
        match check_cardan(&th, 1e-6) {
            Err(RotationError::CardanSingular { beta, .. }) => assert_eq!(beta, th.y),
            other => panic!("expected singularity, got {other:?}"),
        }
        assert!(check_cardan(&Vector3::new(0.3, 1.0, 0.1), 1e-6).is_ok());
        let a = cardan_matrix(&th);
        assert!(cardan_from_matrix(&a, 1e-6).is_err());
    }

    /// Quaternion: A(p) orthonormal, agrees with nalgebra's UnitQuaternion, the kinematics
    /// `p_dot = 1/2 E omega_bar` reproduce skew(omega_bar) = A^T A_dot (1e-7), E^T E = I,
    /// and matrix -> quaternion -> matrix round-trips.
    #[test]
    fn quaternion_kinematics() {
        let mut s = 3;
        let h = 1e-5;
        for _ in 0..50 {
            let p = normalize_quaternion(&Vector4::new(
                rnd(&mut s),
                rnd(&mut s),
                rnd(&mut s),
                rnd(&mut s),
            ))
            .unwrap();
            let a = quaternion_matrix(&p);
            assert!(orthonormality_error(&a) < 1e-14);
            let uq = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                p[0], p[1], p[2], p[3],
            ));
            assert!((a - uq.to_rotation_matrix().matrix()).abs().max() < 1e-14);
            let w = rvec(&mut s, 3.0);
            let pd = quaternion_rate(&p, &w);
            assert!(p.dot(&pd).abs() < 1e-15);
            let a_dot =
                (quaternion_matrix(&(p + h * pd)) - quaternion_matrix(&(p - h * pd))) / (2.0 * h);
            assert!((a.transpose() * a_dot - skew(&w)).abs().max() < 1e-7);
            let et = quaternion_e_transpose(&p);
            assert!((et * et.transpose() - Matrix3::identity()).abs().max() < 1e-14);
            assert!((2.0 * et * pd - w).abs().max() < 1e-14);
            let p2 = quaternion_from_matrix(&a);
            assert!((p2 - p).abs().max() < 1e-12 || (p2 + p).abs().max() < 1e-12);
        }
        assert!(normalize_quaternion(&Vector4::zeros()).is_err());
    }

    /// A rotation vector about z by 90 degrees maps x to y; small vectors use the series.
    #[test]
    fn rotation_vector() {
        let a = rotation_vector_matrix(&Vector3::new(0.0, 0.0, std::f64::consts::FRAC_PI_2));
        assert!((a * Vector3::x() - Vector3::y()).norm() < 1e-15);
        let phi = Vector3::new(1e-8, -2e-8, 3e-8);
        let a = rotation_vector_matrix(&phi);
        assert!((a - Matrix3::identity() - skew(&phi)).abs().max() < 1e-15);
        assert!((unskew(&skew(&phi)) - phi).norm() == 0.0);
    }

    /// J_l: skew(J_l(theta) theta_dot) = F_dot F^T for F = exp(skew(theta)) by central
    /// differences (1e-8), J_l_dot against central differences of J_l (1e-8), on both sides of
    /// the series threshold and at tiny angles (series and closed form agree to 1e-13 at the
    /// threshold).
    #[test]
    fn so3_left_jacobian_matches_finite_differences() {
        let mut s = 5;
        let h = 1e-5;
        for scale in [1e-9, 1e-3, 0.1, 0.49, 0.51, 0.7, 2.5] {
            for _ in 0..20 {
                let th = rvec(&mut s, 1.0).normalize() * scale * (0.9 + 0.1 * rnd(&mut s));
                let thd = rvec(&mut s, 2.0);
                let f = rotation_vector_matrix(&th);
                let f_dot = (rotation_vector_matrix(&(th + h * thd))
                    - rotation_vector_matrix(&(th - h * thd)))
                    / (2.0 * h);
                let w = so3_left_jacobian(&th) * thd;
                let e = (f_dot * f.transpose() - skew(&w)).abs().max();
                assert!(e < 1e-8, "scale {scale}: {e:e}");
                let jd_fd = (so3_left_jacobian(&(th + h * thd))
                    - so3_left_jacobian(&(th - h * thd)))
                    / (2.0 * h);
                let e = (jd_fd - so3_left_jacobian_dot(&th, &thd)).abs().max();
                assert!(e < 1e-8, "scale {scale}: {e:e}");
            }
        }
        let below = so3_coefficients(SO3_SERIES_ANGLE * (1.0 - 1e-12));
        let above = so3_coefficients(SO3_SERIES_ANGLE * (1.0 + 1e-12));
        for (x, y) in below.iter().zip(&above) {
            assert!((x - y).abs() < 1e-13 * x.abs(), "{x} vs {y}");
        }
        assert_eq!(so3_left_jacobian(&Vector3::zeros()), Matrix3::identity());
    }
}

//! Two-node 3D beam (12 DOFs: u, v, w, theta_x, theta_y, theta_z per node), Euler-Bernoulli or
//! Timoshenko.
//!
//! Local frame: x along node 1 -> node 2, y = the part of the property's `orientation` vector
//! orthogonal to x (normalised), z = x cross y. Bending in x-y (v, theta_z = dv/dx for
//! Euler-Bernoulli) uses I_z, bending in x-z (w, theta_y = -dw/dx) uses I_y.
//!
//! Timoshenko: the exact-stiffness two-node element (Przemieniecki 1968) with
//! phi = 12 E I / (k G A L^2); phi = 0 gives Euler-Bernoulli. Its interpolation (cubic
//! deflection, quadratic rotation, both depending on phi) is the exact static solution of the
//! Timoshenko beam with end loads, so one element gives the exact tip deflection
//! P L^3/(3EI) + P L/(kGA).
//!
//! Consistent mass: the same interpolation integrated exactly (4-point Gauss on cubic x cubic):
//! rho A N_v^T N_v + rho I N_theta^T N_theta in both bending planes, rho A L/6 [2 1; 1 2] axial and
//! rho (I_y + I_z) L/6 [2 1; 1 2] for torsion (polar inertia of the section).
//!
//! Lumped mass (documented choice): rho A L/2 per node and translation; torsion
//! rho (I_y + I_z) L/2; bending rotations rho A L^3/78 + rho I L/2, where rho A L^3/78 is the HRZ
//! scaling of the Euler-Bernoulli consistent rotational diagonal (4 L^2/420 * 420/312) and rho I L/2
//! the lumped section rotary inertia. The matrix is diagonal in the local frame; in global
//! coordinates each node's 3x3 rotational block is full when the beam is not axis-aligned.

use super::MassKind;
use crate::mesh::{BeamSection, BeamTheory};
use crate::{FeError, Material};
use nalgebra::{DMatrix, Matrix3, Vector3};

/// Local frame rows (e_x, e_y, e_z) and length of a beam from its end points and orientation.
pub fn beam_frame(
    x1: [f64; 3],
    x2: [f64; 3],
    orientation: [f64; 3],
    element: usize,
) -> Result<(Matrix3<f64>, f64), FeError> {
    let d = Vector3::from(x2) - Vector3::from(x1);
    let l = d.norm();
    if !l.is_finite() || l <= 0.0 {
        return Err(FeError::Invalid(format!(
            "beam element {element} has zero or invalid length {l}"
        )));
    }
    let ex = d / l;
    let o = Vector3::from(orientation);
    let on = o.norm();
    let y = o - ex * o.dot(&ex);
    if !on.is_finite() || on <= 0.0 || y.norm() <= 1e-8 * on {
        return Err(FeError::Invalid(format!(
            "beam element {element}: orientation {orientation:?} is zero or parallel to the beam axis"
        )));
    }
    let ey = y / y.norm();
    let ez = ex.cross(&ey);
    Ok((
        Matrix3::from_rows(&[ex.transpose(), ey.transpose(), ez.transpose()]),
        l,
    ))
}

/// Checks section constants (positive, finite; shear factors positive for Timoshenko).
fn validate_section(s: &BeamSection, theory: BeamTheory, element: usize) -> Result<(), FeError> {
    let vals = [("area", s.area), ("iy", s.iy), ("iz", s.iz), ("j", s.j)];
    for (name, v) in vals {
        if !(v.is_finite() && v > 0.0) {
            return Err(FeError::Invalid(format!(
                "beam element {element}: section {name} must be > 0, got {v}"
            )));
        }
    }
    if theory == BeamTheory::Timoshenko {
        for (name, v) in [("ky", s.ky), ("kz", s.kz)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(FeError::Invalid(format!(
                    "beam element {element}: shear factor {name} must be > 0, got {v}"
                )));
            }
        }
    }
    Ok(())
}

/// Shear parameter phi = 12 E I / (k G A L^2) (0 for Euler-Bernoulli).
pub fn shear_parameter(e: f64, g: f64, i: f64, k: f64, a: f64, l: f64, theory: BeamTheory) -> f64 {
    match theory {
        BeamTheory::EulerBernoulli => 0.0,
        BeamTheory::Timoshenko => 12.0 * e * i / (k * g * a * l * l),
    }
}

/// Bending stiffness in one plane for DOFs (v1, theta1, v2, theta2) with theta = dv/dx in the
/// Euler-Bernoulli limit: a = EI/(L^3 (1+phi)) times
/// [12, 6L, -12, 6L; 6L, (4+phi)L^2, -6L, (2-phi)L^2; ...].
pub fn plane_bending_stiffness(ei: f64, l: f64, phi: f64) -> [[f64; 4]; 4] {
    let a = ei / (l.powi(3) * (1.0 + phi));
    let (p, q, r) = (12.0 * a, 6.0 * a * l, a * l * l);
    [
        [p, q, -p, q],
        [q, (4.0 + phi) * r, -q, (2.0 - phi) * r],
        [-p, -q, p, -q],
        [q, (2.0 - phi) * r, -q, (4.0 + phi) * r],
    ]
}

/// Interpolation of the exact two-node Timoshenko element at s = x/L in [0, 1]: deflection
/// functions N_v and rotation functions N_theta for DOFs (v1, theta1, v2, theta2).
pub fn plane_bending_shape(s: f64, l: f64, phi: f64) -> ([f64; 4], [f64; 4]) {
    let c = 1.0 / (1.0 + phi);
    let (s2, s3) = (s * s, s * s * s);
    let nv = [
        c * (1.0 - 3.0 * s2 + 2.0 * s3 + phi * (1.0 - s)),
        c * l * (s - 2.0 * s2 + s3 + 0.5 * phi * (s - s2)),
        c * (3.0 * s2 - 2.0 * s3 + phi * s),
        c * l * (-s2 + s3 + 0.5 * phi * (s2 - s)),
    ];
    let nt = [
        c * 6.0 / l * (s2 - s),
        c * (1.0 - 4.0 * s + 3.0 * s2 + phi * (1.0 - s)),
        c * 6.0 / l * (s - s2),
        c * (-2.0 * s + 3.0 * s2 + phi * s),
    ];
    (nv, nt)
}

/// Consistent bending mass in one plane: int_0^L (rho A N_v^T N_v + rho I N_theta^T N_theta) dx,
/// 4-point Gauss (exact: integrands are of degree 6).
pub fn plane_bending_mass(rho_a: f64, rho_i: f64, l: f64, phi: f64) -> [[f64; 4]; 4] {
    let mut m = [[0.0; 4]; 4];
    for &(xg, wg) in super::gauss::gauss_legendre(4) {
        let s = 0.5 * (xg + 1.0);
        let w = 0.5 * wg * l;
        let (nv, nt) = plane_bending_shape(s, l, phi);
        for i in 0..4 {
            for j in 0..4 {
                m[i][j] += w * (rho_a * nv[i] * nv[j] + rho_i * nt[i] * nt[j]);
            }
        }
    }
    m
}

/// Local DOF indices and signs of the two bending planes: x-y (v, theta_z) and x-z (w, -theta_y).
const PLANE_XY: ([usize; 4], [f64; 4]) = ([1, 5, 7, 11], [1.0, 1.0, 1.0, 1.0]);
const PLANE_XZ: ([usize; 4], [f64; 4]) = ([2, 4, 8, 10], [1.0, -1.0, 1.0, -1.0]);

fn scatter_plane(k: &mut DMatrix<f64>, plane: ([usize; 4], [f64; 4]), kp: &[[f64; 4]; 4]) {
    let (idx, sg) = plane;
    for i in 0..4 {
        for j in 0..4 {
            k[(idx[i], idx[j])] += sg[i] * sg[j] * kp[i][j];
        }
    }
}

fn scatter_bar(k: &mut DMatrix<f64>, i: usize, j: usize, a: f64, b: f64) {
    k[(i, i)] += a;
    k[(j, j)] += a;
    k[(i, j)] += b;
    k[(j, i)] += b;
}

/// Local 12 x 12 stiffness and mass of a beam of length `l`.
pub fn beam_local(
    l: f64,
    mat: &Material,
    s: &BeamSection,
    theory: BeamTheory,
    mass: MassKind,
) -> (DMatrix<f64>, DMatrix<f64>) {
    let (e, g, rho) = (mat.e, mat.shear_modulus(), mat.rho);
    let phi_y = shear_parameter(e, g, s.iz, s.ky, s.area, l, theory); // bending in x-y
    let phi_z = shear_parameter(e, g, s.iy, s.kz, s.area, l, theory); // bending in x-z
    let mut k = DMatrix::zeros(12, 12);
    scatter_bar(&mut k, 0, 6, e * s.area / l, -e * s.area / l);
    scatter_bar(&mut k, 3, 9, g * s.j / l, -g * s.j / l);
    scatter_plane(
        &mut k,
        PLANE_XY,
        &plane_bending_stiffness(e * s.iz, l, phi_y),
    );
    scatter_plane(
        &mut k,
        PLANE_XZ,
        &plane_bending_stiffness(e * s.iy, l, phi_z),
    );
    let mut m = DMatrix::zeros(12, 12);
    let ma = rho * s.area * l;
    let jp = rho * (s.iy + s.iz) * l;
    match mass {
        MassKind::Consistent => {
            scatter_bar(&mut m, 0, 6, ma / 3.0, ma / 6.0);
            scatter_bar(&mut m, 3, 9, jp / 3.0, jp / 6.0);
            scatter_plane(
                &mut m,
                PLANE_XY,
                &plane_bending_mass(rho * s.area, rho * s.iz, l, phi_y),
            );
            scatter_plane(
                &mut m,
                PLANE_XZ,
                &plane_bending_mass(rho * s.area, rho * s.iy, l, phi_z),
            );
        }
        MassKind::Lumped => {
            let rot = ma * l * l / 78.0;
            for n in [0, 6] {
                for c in 0..3 {
                    m[(n + c, n + c)] = 0.5 * ma;
                }
                m[(n + 3, n + 3)] = 0.5 * jp;
                m[(n + 4, n + 4)] = rot + 0.5 * rho * s.iy * l;
                m[(n + 5, n + 5)] = rot + 0.5 * rho * s.iz * l;
            }
        }
    }
    (k, m)
}

/// Global stiffness and mass of a beam element: T^T K_local T with T = diag(R, R, R, R).
#[allow(clippy::too_many_arguments)]
pub fn beam_matrices(
    x1: [f64; 3],
    x2: [f64; 3],
    mat: &Material,
    s: &BeamSection,
    theory: BeamTheory,
    orientation: [f64; 3],
    mass: MassKind,
    element: usize,
) -> Result<(DMatrix<f64>, DMatrix<f64>), FeError> {
    mat.validate()?;
    validate_section(s, theory, element)?;
    let (r, l) = beam_frame(x1, x2, orientation, element)?;
    let (kl, ml) = beam_local(l, mat, s, theory, mass);
    let mut t = DMatrix::zeros(12, 12);
    for b in 0..4 {
        t.view_mut((3 * b, 3 * b), (3, 3)).copy_from(&r);
    }
    let mut k = t.transpose() * kl * &t;
    let mut m = t.transpose() * ml * &t;
    super::solid::symmetrize(&mut k);
    super::solid::symmetrize(&mut m);
    Ok((k, m))
}

//! Tests of the two-node beam: exact static responses, interpolation-based cross-checks,
//! rigid modes, mass, and the cantilever frequency of a 20-element model.

use super::beam::{plane_bending_mass, plane_bending_shape, plane_bending_stiffness};
use super::test_util::*;
use super::{element_matrices, MassKind};
use crate::mesh::{BeamSection, BeamTheory, Element, ElementKind, Mesh, Property};
use crate::{FeError, Material};
use nalgebra::{DMatrix, DVector, Vector3};

fn steel() -> Material {
    Material::steel()
}

/// A straight beam of `n` elements from `a` to `b`.
fn beam_mesh(
    n: usize,
    a: [f64; 3],
    b: [f64; 3],
    section: BeamSection,
    theory: BeamTheory,
    orientation: [f64; 3],
) -> Mesh {
    let mut m = Mesh::default();
    for i in 0..=n {
        let s = i as f64 / n as f64;
        m.add_node([0, 1, 2].map(|c| a[c] + s * (b[c] - a[c])));
    }
    let property = m.add_property(Property::Beam {
        material: steel(),
        section,
        theory,
        orientation,
    });
    for i in 0..n {
        m.elements.push(Element {
            kind: ElementKind::Beam2,
            nodes: vec![i, i + 1],
            property,
        });
    }
    m
}

fn section() -> BeamSection {
    // rectangular 20 mm x 50 mm section (iy != iz so that a wrong plane mapping is detected)
    BeamSection::rectangle(0.02, 0.05)
}

/// Skewed beam: from the origin along direction `dir` with length L, local y from `orient`.
fn skew() -> ([f64; 3], [f64; 3], f64, [f64; 3]) {
    let d = Vector3::new(1.0, 2.0, -0.5).normalize();
    let l = 0.8;
    ([0.0; 3], (d * l).into(), l, [0.3, -0.1, 1.0])
}

/// Cantilever (node 0 clamped) tip displacement for tip load `f` (6 components, global).
fn tip_response(mesh: &Mesh, f: [f64; 6]) -> DVector<f64> {
    let (k, _) = assemble(mesh, MassKind::Consistent);
    let n = k.nrows();
    let mut load = DVector::zeros(n);
    for c in 0..6 {
        load[n - 6 + c] = f[c];
    }
    let fixed: Vec<usize> = (0..6).collect();
    solve_prescribed(&k, &load, &fixed, &[0.0; 6])
}

/// Local axes of the skewed beam (ex, ey, ez) computed independently of the element code.
fn axes() -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    let (_, b, _, o) = skew();
    let ex = Vector3::from(b).normalize();
    let o = Vector3::from(o);
    let ey = (o - ex * ex.dot(&o)).normalize();
    (ex, ey, ex.cross(&ey))
}

#[test]
fn one_element_cantilever_exact_euler_bernoulli_and_timoshenko() {
    let (a, b, l, o) = skew();
    let s = section();
    let m = steel();
    let (e, g) = (m.e, m.shear_modulus());
    let (ex, ey, ez) = axes();
    let p = 1000.0;
    for theory in [BeamTheory::EulerBernoulli, BeamTheory::Timoshenko] {
        let mesh = beam_mesh(1, a, b, s, theory, o);
        let shear = theory == BeamTheory::Timoshenko;
        // load along local y: deflection P L^3/(3 E Iz) (+ P L/(ky G A))
        for (dir, i, k) in [(ey, s.iz, s.ky), (ez, s.iy, s.kz)] {
            let f = dir * p;
            let u = tip_response(&mesh, [f[0], f[1], f[2], 0.0, 0.0, 0.0]);
            let tip = Vector3::new(u[6], u[7], u[8]);
            let exact =
                p * l.powi(3) / (3.0 * e * i) + if shear { p * l / (k * g * s.area) } else { 0.0 };
            let got = tip.dot(&dir);
            assert!(
                (got / exact - 1.0).abs() < 1e-10,
                "{theory:?}: {got} vs {exact}"
            );
            // no coupling into the other directions
            assert!((tip - dir * got).norm() < 1e-10 * exact);
            // tip rotation P L^2/(2EI) about the axis ex x dir (for both theories)
            let rot = Vector3::new(u[9], u[10], u[11]).dot(&ex.cross(&dir));
            let rexact = p * l * l / (2.0 * e * i);
            assert!(
                (rot / rexact - 1.0).abs() < 1e-10,
                "{theory:?} tip rotation {rot} vs {rexact}"
            );
        }
        // axial P L / (E A) and torsion T L / (G J)
        let u = tip_response(&mesh, [ex[0] * p, ex[1] * p, ex[2] * p, 0.0, 0.0, 0.0]);
        let ax = Vector3::new(u[6], u[7], u[8]).dot(&ex);
        assert!((ax / (p * l / (e * s.area)) - 1.0).abs() < 1e-10);
        let t = 50.0;
        let u = tip_response(&mesh, [0.0, 0.0, 0.0, ex[0] * t, ex[1] * t, ex[2] * t]);
        let tw = Vector3::new(u[9], u[10], u[11]).dot(&ex);
        assert!((tw / (t * l / (g * s.j)) - 1.0).abs() < 1e-10);
    }
}

/// The closed-form Timoshenko stiffness equals the energy of its own interpolation,
/// int EI theta'^2 + kGA (v' - theta)^2 dx, evaluated with finite-difference derivatives and
/// a 4-point Gauss rule (independent of the closed form).
#[test]
fn timoshenko_stiffness_matches_interpolation_energy() {
    let (ei, kga, l) = (2.0e4, 3.0e6, 0.7);
    let phi = 12.0 * ei / (kga * l * l);
    let kc = plane_bending_stiffness(ei, l, phi);
    let h = 1e-5;
    let mut kn = [[0.0; 4]; 4];
    for &(xg, wg) in super::gauss::gauss_legendre(4) {
        let s = 0.5 * (xg + 1.0);
        let w = 0.5 * wg * l;
        let (_, nt) = plane_bending_shape(s, l, phi);
        let (vp, tp) = plane_bending_shape(s + h, l, phi);
        let (vm, tm) = plane_bending_shape(s - h, l, phi);
        let dt = |k: usize| (tp[k] - tm[k]) / (2.0 * h * l);
        let gam = |k: usize| (vp[k] - vm[k]) / (2.0 * h * l) - nt[k];
        for (i, row) in kn.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v += w * (ei * dt(i) * dt(j) + kga * gam(i) * gam(j));
            }
        }
    }
    for i in 0..4 {
        for j in 0..4 {
            let scale = (kc[i][i] * kc[j][j]).sqrt();
            assert!(
                (kn[i][j] - kc[i][j]).abs() < 1e-7 * scale,
                "K[{i}][{j}]: {} vs {}",
                kn[i][j],
                kc[i][j]
            );
        }
    }
    // the shear strain of the interpolation is constant along the element (exact-stiffness element)
    let gamma = |s: f64| {
        let (vp, _) = plane_bending_shape(s + h, l, phi);
        let (vm, _) = plane_bending_shape(s - h, l, phi);
        let (_, t0) = plane_bending_shape(s, l, phi);
        (vp[0] - vm[0]) / (2.0 * h * l) - t0[0]
    };
    assert!((gamma(0.1) - gamma(0.9)).abs() < 1e-6 * gamma(0.5).abs());
}

/// phi = 0 and no rotary inertia: the classical Hermite consistent mass rho A L/420 [156, 22L, ...].
#[test]
fn euler_bernoulli_consistent_mass_is_classical() {
    let (ra, l) = (3.0, 1.7);
    let m = plane_bending_mass(ra, 0.0, l, 0.0);
    let c = ra * l / 420.0;
    let exact = [
        [156.0, 22.0 * l, 54.0, -13.0 * l],
        [22.0 * l, 4.0 * l * l, 13.0 * l, -3.0 * l * l],
        [54.0, 13.0 * l, 156.0, -22.0 * l],
        [-13.0 * l, -3.0 * l * l, -22.0 * l, 4.0 * l * l],
    ];
    for i in 0..4 {
        for j in 0..4 {
            assert!((m[i][j] - c * exact[i][j]).abs() < 1e-13 * c * 156.0);
        }
    }
    // rotary inertia part: rho I/(30 L) [36, 3L, -36, 3L; 3L, 4L^2, -3L, -L^2; ...]
    let ri = 0.25;
    let mr = plane_bending_mass(0.0, ri, l, 0.0);
    let c = ri / (30.0 * l);
    let exact = [
        [36.0, 3.0 * l, -36.0, 3.0 * l],
        [3.0 * l, 4.0 * l * l, -3.0 * l, -l * l],
        [-36.0, -3.0 * l, 36.0, -3.0 * l],
        [3.0 * l, -l * l, -3.0 * l, 4.0 * l * l],
    ];
    for i in 0..4 {
        for j in 0..4 {
            assert!((mr[i][j] - c * exact[i][j]).abs() < 1e-13 * c * 36.0);
        }
    }
}

#[test]
fn beam_rigid_modes_rank_and_mass() {
    let (a, b, l, o) = skew();
    let s = section();
    let x = [a, b];
    let r = rigid_modes(&x, 6);
    let rho = steel().rho;
    for theory in [BeamTheory::EulerBernoulli, BeamTheory::Timoshenko] {
        let mesh = beam_mesh(1, a, b, s, theory, o);
        for mass in [MassKind::Consistent, MassKind::Lumped] {
            let em = element_matrices(&mesh, 0, mass).unwrap();
            let k = &em.k;
            let kmax = max_abs(k);
            assert!(max_abs(&(k - k.transpose())) <= 1e-14 * kmax);
            let kr = max_abs(&(k * &r)) / (kmax * max_abs(&r));
            assert!(kr < 1e-10, "{theory:?}: |KR| rel {kr:e}");
            let ev = sym_eigenvalues(k);
            let lmax = *ev.last().unwrap();
            assert_eq!(ev.iter().filter(|v| v.abs() < 1e-10 * lmax).count(), 6);
            assert!(ev[0] > -1e-10 * lmax);
            // translational mass rho A L in every direction
            for c in 0..3 {
                let rc = r.column(c);
                let mt = (rc.transpose() * &em.m * rc)[(0, 0)];
                assert!(
                    (mt / (rho * s.area * l) - 1.0).abs() < 1e-12,
                    "{mass:?} dir {c}"
                );
            }
            // rotation about the beam axis through node 0: polar inertia rho (Iy+Iz) L
            let (ex, _, _) = axes();
            let rot = r.columns(3, 3) * DVector::from_column_slice(ex.as_slice());
            let jx = (rot.transpose() * &em.m * &rot)[(0, 0)];
            assert!(
                (jx / (rho * (s.iy + s.iz) * l) - 1.0).abs() < 1e-12,
                "{mass:?} torsional inertia"
            );
            let mev = sym_eigenvalues(&em.m);
            assert!(mev[0] > 0.0, "{mass:?} mass not positive definite");
        }
    }
}

/// Clamped-free beam of 20 consistent-mass Euler-Bernoulli elements: first frequency
/// 1.875104^2 sqrt(EI/(rho A L^4))/(2 pi) within 0.1 %; lumped mass within 0.5 %.
#[test]
fn cantilever_first_frequency_20_elements() {
    let s = BeamSection::circle(0.02);
    let l = 1.0;
    let mesh = beam_mesh(
        20,
        [0.0; 3],
        [l, 0.0, 0.0],
        s,
        BeamTheory::EulerBernoulli,
        [0.0, 1.0, 0.0],
    );
    let m = steel();
    let f_exact = 1.875_104_f64.powi(2) * (m.e * s.iz / (m.rho * s.area * l.powi(4))).sqrt()
        / (2.0 * std::f64::consts::PI);
    let fixed: Vec<usize> = (0..6).collect();
    for (mass, tol) in [(MassKind::Consistent, 1e-3), (MassKind::Lumped, 5e-3)] {
        let (k, mm) = assemble(&mesh, mass);
        let ev = gen_eigenvalues(&k, &mm, &fixed);
        let f1 = ev[0].sqrt() / (2.0 * std::f64::consts::PI);
        println!(
            "{mass:?}: f1 = {f1:.5} Hz, exact {f_exact:.5} Hz, rel {:.2e}",
            f1 / f_exact - 1.0
        );
        assert!((f1 / f_exact - 1.0).abs() < tol);
        // circular section: the two bending modes coincide
        assert!((ev[1] / ev[0] - 1.0).abs() < 1e-8);
    }
}

#[test]
fn beam_errors() {
    let s = section();
    let mesh = beam_mesh(
        1,
        [0.0; 3],
        [1.0, 0.0, 0.0],
        s,
        BeamTheory::EulerBernoulli,
        [2.0, 0.0, 0.0],
    );
    assert!(matches!(
        element_matrices(&mesh, 0, MassKind::Consistent),
        Err(FeError::Invalid(_))
    ));
    let mesh = beam_mesh(
        1,
        [0.0; 3],
        [0.0; 3],
        s,
        BeamTheory::EulerBernoulli,
        [0.0, 1.0, 0.0],
    );
    assert!(matches!(
        element_matrices(&mesh, 0, MassKind::Consistent),
        Err(FeError::Invalid(_))
    ));
    let mut bad = s;
    bad.ky = 0.0;
    let mesh = beam_mesh(
        1,
        [0.0; 3],
        [1.0, 0.0, 0.0],
        bad,
        BeamTheory::Timoshenko,
        [0.0, 1.0, 0.0],
    );
    assert!(matches!(
        element_matrices(&mesh, 0, MassKind::Consistent),
        Err(FeError::Invalid(_))
    ));
    // solid property on a beam element
    let mut mesh = beam_mesh(
        1,
        [0.0; 3],
        [1.0, 0.0, 0.0],
        s,
        BeamTheory::EulerBernoulli,
        [0.0, 1.0, 0.0],
    );
    mesh.properties[0] = Property::Solid { material: steel() };
    assert!(matches!(
        element_matrices(&mesh, 0, MassKind::Consistent),
        Err(FeError::Invalid(_))
    ));
    let _unused: DMatrix<f64> = DMatrix::zeros(1, 1);
}

/// Stubby simply supported Timoshenko beam (L/b = 5, 40 elements, consistent mass with rotary
/// inertia): first frequency against the exact Timoshenko value, the smaller root omega^2 of
/// det [[kGA a^2 - rho A w^2, -kGA a], [-kGA a, EI a^2 + kGA - rho I w^2]] = 0 with a = pi/L.
#[test]
fn simply_supported_timoshenko_frequency() {
    let s = section();
    let l = 0.1;
    let mesh = beam_mesh(
        40,
        [0.0; 3],
        [l, 0.0, 0.0],
        s,
        BeamTheory::Timoshenko,
        [0.0, 1.0, 0.0],
    );
    let m = steel();
    let (e, g, rho) = (m.e, m.shear_modulus(), m.rho);
    // bending in x-y (I_z, k_y) is the softest plane for this section
    let (ei, kga, ra, ri) = (e * s.iz, s.ky * g * s.area, rho * s.area, rho * s.iz);
    let a = std::f64::consts::PI / l;
    // (kGA a^2 - ra w2)(EI a^2 + kGA - ri w2) - (kGA a)^2 = 0: quadratic c2 w2^2 + c1 w2 + c0 = 0
    let c2 = ra * ri;
    let c1 = -(kga * a * a * ri + ra * (ei * a * a + kga));
    let c0 = kga * a * a * (ei * a * a + kga) - (kga * a).powi(2);
    let w2 = (-c1 - (c1 * c1 - 4.0 * c2 * c0).sqrt()) / (2.0 * c2);
    let w2_eb = ei * a.powi(4) / ra;
    let n = mesh.num_nodes();
    // pins: u, v, w at node 0, v, w at the last node, twist at node 0
    let fixed = vec![0, 1, 2, 3, 6 * (n - 1) + 1, 6 * (n - 1) + 2];
    let (k, mm) = assemble(&mesh, MassKind::Consistent);
    let ev = gen_eigenvalues(&k, &mm, &fixed);
    println!(
        "SS Timoshenko: omega1^2 FE {:.6e}, exact {w2:.6e}, Euler-Bernoulli {w2_eb:.6e}",
        ev[0]
    );
    assert!(
        w2 < 0.9 * w2_eb,
        "the test case must be shear-dominated enough to matter"
    );
    assert!((ev[0] / w2 - 1.0).abs() < 1e-3, "rel {}", ev[0] / w2 - 1.0);
}

//! Tests of the solid elements: rigid modes, rank, mass, lumping, patch tests, bending.

use super::test_util::*;
use super::{element_matrices, solid, MassKind};
use crate::mesh::ElementKind;
use crate::{FeError, Material};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector6};

const SOLIDS: [ElementKind; 5] = [
    ElementKind::Hex8,
    ElementKind::Hex8I,
    ElementKind::Hex20,
    ElementKind::Hex20R,
    ElementKind::Tet10,
];

fn mat() -> Material {
    Material {
        e: 210e3,
        nu: 0.3,
        rho: 7.85e-9,
    }
}

/// A general (non-symmetric) affine map with det > 0.
fn affine() -> (Matrix3<f64>, Vector3<f64>) {
    (
        Matrix3::new(1.3, 0.2, -0.1, 0.1, 0.9, 0.25, -0.15, 0.05, 1.1),
        Vector3::new(0.4, -1.2, 2.0),
    )
}

/// Corner positions moved by an affine map plus a non-affine perturbation; mid-edge nodes at
/// the midpoints of the moved corners (straight edges), so reduced rules stay exact for volume.
fn distorted(kind: ElementKind, nonlinear: f64) -> Vec<[f64; 3]> {
    let (a, t) = affine();
    let refn = reference_nodes(kind);
    let ncorner = if kind == ElementKind::Tet10 { 4 } else { 8 };
    let mut x: Vec<[f64; 3]> = refn
        .iter()
        .take(ncorner)
        .enumerate()
        .map(|(i, r)| {
            let p = a * Vector3::from(*r) + t;
            let s = nonlinear * if kind == ElementKind::Tet10 { 0.0 } else { 1.0 };
            let d = Vector3::new(
                (1.7 * i as f64).sin(),
                (2.3 * i as f64).cos(),
                (0.9 * i as f64 + 0.4).sin(),
            ) * s;
            (p + d).into()
        })
        .collect();
    let edges: &[(usize, usize)] = match kind {
        ElementKind::Hex20 | ElementKind::Hex20R => &[
            (0, 1),
            (1, 2),
            (2, 3),
            (3, 0),
            (4, 5),
            (5, 6),
            (6, 7),
            (7, 4),
            (0, 4),
            (1, 5),
            (2, 6),
            (3, 7),
        ],
        ElementKind::Tet10 => &[(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)],
        _ => &[],
    };
    for &(i, j) in edges {
        x.push([0, 1, 2].map(|c| 0.5 * (x[i][c] + x[j][c])));
    }
    x
}

fn ref_volume(kind: ElementKind) -> f64 {
    if kind == ElementKind::Tet10 {
        1.0 / 6.0
    } else {
        8.0
    }
}

#[test]
fn every_solid_has_six_rigid_modes_and_correct_rank() {
    for kind in SOLIDS {
        let x = distorted(kind, 0.12);
        let em = element_matrices(&single_solid(kind, &x, mat()), 0, MassKind::Consistent).unwrap();
        let k = &em.k;
        let kmax = max_abs(k);
        assert!(
            max_abs(&(k - k.transpose())) <= 1e-14 * kmax,
            "{kind:?} K not symmetric"
        );
        let r = rigid_modes(&x, 3);
        let kr = max_abs(&(k * &r)) / (kmax * max_abs(&r));
        assert!(kr < 1e-10, "{kind:?}: |K R| / (|K| |R|) = {kr:e}");
        let ev = sym_eigenvalues(k);
        let lmax = *ev.last().unwrap();
        let zeros = ev.iter().filter(|l| l.abs() < 1e-8 * lmax).count();
        assert!(ev[0] > -1e-10 * lmax, "{kind:?} K indefinite: {}", ev[0]);
        // Hex20R: 2x2x2 integration leaves 6 spurious zero-energy modes in a single element
        // (48 strain samples against 54 deformation modes), as for CalculiX C3D20R.
        let expected = if kind == ElementKind::Hex20R { 12 } else { 6 };
        println!(
            "{kind:?}: {zeros} zero eigenvalues, |KR| rel {kr:.2e}, next {:.3e}",
            ev[zeros] / lmax
        );
        assert_eq!(zeros, expected, "{kind:?} zero eigenvalue count");
        assert!(
            ev[zeros] > 1e-6 * lmax,
            "{kind:?}: smallest nonzero eigenvalue too close to zero"
        );
    }
}

#[test]
fn mass_totals_and_lumping() {
    let (a, _) = affine();
    for kind in SOLIDS {
        let x = distorted(kind, 0.0);
        let vol = a.determinant() * ref_volume(kind);
        let mesh = single_solid(kind, &x, mat());
        let r = rigid_modes(&x, 3);
        for mass in [MassKind::Consistent, MassKind::Lumped] {
            let m = element_matrices(&mesh, 0, mass).unwrap().m;
            for c in 0..3 {
                let rc = r.column(c);
                let mt = (rc.transpose() * &m * rc)[(0, 0)];
                let err = (mt / (mat().rho * vol) - 1.0).abs();
                assert!(err < 1e-12, "{kind:?} {mass:?} dir {c}: mass error {err:e}");
            }
            if mass == MassKind::Lumped {
                let nd = m.nrows();
                for i in 0..nd {
                    assert!(m[(i, i)] > 0.0, "{kind:?} lumped mass {i} not positive");
                    for j in 0..nd {
                        assert!(i == j || m[(i, j)] == 0.0);
                    }
                }
            }
        }
        // distorted element: total mass = rho * volume from an independent 4x4x4 / 14-point rule
        let x = distorted(kind, 0.12);
        let m = element_matrices(&single_solid(kind, &x, mat()), 0, MassKind::Lumped)
            .unwrap()
            .m;
        let v = volume_high(kind, &x);
        let tot: f64 = (0..m.nrows()).map(|i| m[(i, i)]).sum::<f64>() / 3.0;
        assert!(
            (tot / (mat().rho * v) - 1.0).abs() < 1e-12,
            "{kind:?} distorted lumped mass"
        );
    }
}

fn shape_of(kind: ElementKind) -> solid::ShapeFn {
    match kind {
        ElementKind::Hex8 | ElementKind::Hex8I => super::hex8::hex8_shape,
        ElementKind::Hex20 | ElementKind::Hex20R => super::hex20::hex20_shape,
        _ => super::tet10::tet10_shape,
    }
}

fn volume_high(kind: ElementKind, x: &[[f64; 3]]) -> f64 {
    let rule = if kind == ElementKind::Tet10 {
        super::gauss::tet_rule_14()
    } else {
        super::gauss::hex_rule(4)
    };
    solid::volume(shape_of(kind), x, &rule, 0).unwrap()
}

#[test]
fn hex20_row_sums_negative_but_hrz_positive() {
    let x = distorted(ElementKind::Hex20, 0.0);
    let mesh = single_solid(ElementKind::Hex20, &x, mat());
    let mc = element_matrices(&mesh, 0, MassKind::Consistent).unwrap().m;
    let corner_row_sum: f64 = mc.row(0).iter().sum();
    assert!(corner_row_sum < 0.0, "corner row sum {corner_row_sum}");
    let ml = element_matrices(&mesh, 0, MassKind::Lumped).unwrap().m;
    // undistorted-shape HRZ masses: corner / mid-edge ratio is fixed by the shape functions
    assert!(ml[(0, 0)] > 0.0 && ml[(24, 24)] > ml[(0, 0)]);
}

/// Energy of a linear field u = A x + c on a distorted element equals 1/2 eps^T D eps V.
#[test]
fn constant_strain_energy_exact_on_distorted_elements() {
    let g = Matrix3::new(
        1.0e-3, 2.0e-4, -3.0e-4, -1.0e-4, -5.0e-4, 4.0e-4, 6.0e-4, 1.0e-4, 2.0e-4,
    );
    let eps = Vector6::new(
        g[(0, 0)],
        g[(1, 1)],
        g[(2, 2)],
        g[(0, 1)] + g[(1, 0)],
        g[(1, 2)] + g[(2, 1)],
        g[(2, 0)] + g[(0, 2)],
    );
    let d = mat().elasticity_matrix();
    for kind in SOLIDS {
        let x = distorted(kind, 0.12);
        let k = element_matrices(&single_solid(kind, &x, mat()), 0, MassKind::Consistent)
            .unwrap()
            .k;
        let u = DVector::from_iterator(
            3 * x.len(),
            x.iter().flat_map(|p| {
                (g * Vector3::from(*p) + Vector3::new(1e-4, 2e-4, -3e-4))
                    .data
                    .0[0]
            }),
        );
        let energy = 0.5 * (u.transpose() * &k * &u)[(0, 0)];
        let exact = 0.5 * (eps.transpose() * d * eps)[(0, 0)] * volume_high(kind, &x);
        let err = (energy / exact - 1.0).abs();
        println!("{kind:?}: constant-strain energy error {err:.2e}");
        assert!(err < 1e-10, "{kind:?}: energy error {err:e}");
    }
}

/// Classical patch test: a 3x3x3 patch on the unit cube with distorted interior nodes
/// (straight-edged elements), a linear field prescribed on the boundary; the interior nodal
/// displacements must reproduce the linear field.
#[test]
fn patch_test_interior_nodes_reproduce_linear_field() {
    let g = Matrix3::new(
        1.0e-3, 2.0e-4, -3.0e-4, -1.0e-4, -5.0e-4, 4.0e-4, 6.0e-4, 1.0e-4, 2.0e-4,
    );
    let pert = |l: [usize; 3], lmax: [usize; 3]| -> Vector3<f64> {
        if (0..3).any(|c| l[c] == 0 || l[c] == lmax[c]) {
            return Vector3::zeros();
        }
        let s = (l[0] * 7 + l[1] * 13 + l[2] * 29) as f64;
        Vector3::new(s.sin(), (1.3 * s).cos(), (0.7 * s + 1.0).sin()) * 0.05
    };
    let map = |l: [usize; 3], lmax: [usize; 3], p: [f64; 3]| -> [f64; 3] {
        let odd = l.map(|v| v % 2);
        let d = if odd == [0, 0, 0] {
            pert(l, lmax)
        } else {
            let lo = [0, 1, 2].map(|c| l[c] - odd[c]);
            let hi = [0, 1, 2].map(|c| l[c] + odd[c]);
            (pert(lo, lmax) + pert(hi, lmax)) * 0.5
        };
        (Vector3::from(p) + d).into()
    };
    for kind in SOLIDS {
        let (mesh, lattice) = box_mesh(kind, [3, 3, 3], [1.0, 1.0, 1.0], mat(), &map);
        let (k, _) = assemble(&mesh, MassKind::Consistent);
        let lin = |i: usize| g * Vector3::from(mesh.nodes[i]) + Vector3::new(0.01, -0.02, 0.03);
        let mut fixed = Vec::new();
        let mut vals = Vec::new();
        for (i, l) in lattice.iter().enumerate() {
            if (0..3).any(|c| l[c] == 0 || l[c] == 6) {
                for c in 0..3 {
                    fixed.push(3 * i + c);
                    vals.push(lin(i)[c]);
                }
            }
        }
        let u = solve_prescribed(&k, &DVector::zeros(k.nrows()), &fixed, &vals);
        let mut err: f64 = 0.0;
        for i in 0..mesh.num_nodes() {
            for c in 0..3 {
                err = err.max((u[3 * i + c] - lin(i)[c]).abs());
            }
        }
        println!("{kind:?}: patch test max interior error {err:.2e} (field ~1e-3)");
        assert!(err < 1e-12, "{kind:?}: patch test error {err:e}");
    }
}

/// Pure bending of one rectangular element: nodal values of the exact field
/// u = k x z, v = -nu k y z, w = -k x^2/2 + nu k (y^2 - z^2)/2 give the exact energy
/// E k^2 I_y L / 2 with Hex8I; Hex8 overestimates it (shear locking).
#[test]
fn hex8i_pure_bending_exact_hex8_locks() {
    let (l, b, h) = (2.0, 1.0, 0.5);
    let m = mat();
    let x: Vec<[f64; 3]> = super::hex8::HEX8_NODES
        .iter()
        .map(|r| [0.5 * l * (r[0] + 1.0), b * 0.5 * r[1], h * 0.5 * r[2]])
        .collect();
    let kap = 1e-3;
    let u = DVector::from_iterator(
        24,
        x.iter().flat_map(|p| {
            let (px, py, pz) = (p[0], p[1], p[2]);
            [
                kap * px * pz,
                -m.nu * kap * py * pz,
                -0.5 * kap * px * px + 0.5 * m.nu * kap * (py * py - pz * pz),
            ]
        }),
    );
    let exact = 0.5 * m.e * kap * kap * (b * h.powi(3) / 12.0) * l;
    let mut ratios = Vec::new();
    for kind in [ElementKind::Hex8I, ElementKind::Hex8] {
        let k = element_matrices(&single_solid(kind, &x, m), 0, MassKind::Consistent)
            .unwrap()
            .k;
        ratios.push(0.5 * (u.transpose() * &k * &u)[(0, 0)] / exact);
    }
    println!(
        "pure bending energy / exact: Hex8I {:.12}, Hex8 {:.4}",
        ratios[0], ratios[1]
    );
    assert!((ratios[0] - 1.0).abs() < 1e-10);
    assert!(ratios[1] > 1.5, "Hex8 should lock in bending (L/h = 4)");
}

/// Tip deflection (work-conjugate: f^T u / P) of a cantilever box mesh clamped at x = 0 with a
/// uniform shear traction of resultant P in y on the face x = L (consistent nodal loads).
fn cantilever_tip(
    kind: ElementKind,
    n: [usize; 3],
    len: [f64; 3],
    material: Material,
    p: f64,
) -> f64 {
    let (mesh, lattice) = box_mesh(kind, n, len, material, &|_, _, x| x);
    let (k, _) = assemble(&mesh, MassKind::Consistent);
    let lx = 2 * n[0];
    let fixed: Vec<usize> = lattice
        .iter()
        .enumerate()
        .filter(|(_, l)| l[0] == 0)
        .flat_map(|(i, _)| (0..3).map(move |c| 3 * i + c))
        .collect();
    // consistent loads: f_a = t int N_a dA over element faces at x = L (3x3 Gauss on the face)
    let t = p / (len[1] * len[2]);
    let mut f = DVector::zeros(k.nrows());
    let shape = shape_of(kind);
    for el in &mesh.elements {
        let on_tip: Vec<bool> = el.nodes.iter().map(|&nd| lattice[nd][0] == lx).collect();
        let face_nodes = match kind {
            ElementKind::Hex8 | ElementKind::Hex8I => 4,
            ElementKind::Tet10 => 6,
            _ => 8,
        };
        if on_tip.iter().filter(|&&b| b).count() < face_nodes {
            continue;
        }
        let x: Vec<[f64; 3]> = el.nodes.iter().map(|&nd| mesh.nodes[nd]).collect();
        face_load(shape, kind, &x, &on_tip, t, &el.nodes, &mut f);
    }
    let u = solve_prescribed(&k, &f, &fixed, &vec![0.0; fixed.len()]);
    f.dot(&u) / p
}

/// Adds t int_face N_a dA (y direction) for the face whose nodes are flagged in `on_face`, by a
/// 3x3 Gauss rule on the face in reference coordinates (hex: xi = +1; tet: parametrised face).
fn face_load(
    shape: solid::ShapeFn,
    kind: ElementKind,
    x: &[[f64; 3]],
    on_face: &[bool],
    t: f64,
    nodes: &[usize],
    f: &mut DVector<f64>,
) {
    let nn = x.len();
    let refn = reference_nodes(kind);
    let fr: Vec<[f64; 3]> = (0..nn)
        .filter(|&a| on_face[a])
        .map(|a| refn[a])
        .take(if kind == ElementKind::Tet10 { 3 } else { 0 })
        .collect();
    let g = super::gauss::gauss_legendre(4);
    let mut n = vec![0.0; nn];
    let mut dn = vec![[0.0; 3]; nn];
    for &(s1, w1) in g {
        for &(s2, w2) in g {
            // map (s1, s2) in [-1,1]^2 to a reference face point and tangent vectors
            let (xi, t1, t2, w) = if kind == ElementKind::Tet10 {
                // collapsed square -> triangle with corners fr[0..3]: (a, b) in [0,1]^2
                let (a, b) = (0.5 * (s1 + 1.0), 0.5 * (s2 + 1.0));
                let p =
                    |c: usize| fr[0][c] + a * (fr[1][c] - fr[0][c]) + a * b * (fr[2][c] - fr[1][c]);
                let t1 = [0, 1, 2].map(|c| (fr[1][c] - fr[0][c]) + b * (fr[2][c] - fr[1][c]));
                let t2 = [0, 1, 2].map(|c| a * (fr[2][c] - fr[1][c]));
                ([p(0), p(1), p(2)], t1, t2, 0.25 * w1 * w2)
            } else {
                ([1.0, s1, s2], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], w1 * w2)
            };
            shape(xi, &mut n, &mut dn);
            let j = solid::jacobian(x, &dn);
            // physical tangents dx/ds = J^T t
            let a1 = j.transpose() * Vector3::from(t1);
            let a2 = j.transpose() * Vector3::from(t2);
            let da = a1.cross(&a2).norm() * w;
            for a in 0..nn {
                f[3 * nodes[a] + 1] += t * n[a] * da;
            }
        }
    }
}

#[test]
fn hex8i_cantilever_strip_matches_beam_theory_hex8_locks() {
    let m = Material {
        e: 1000.0,
        nu: 0.0,
        rho: 1.0,
    };
    let (l, b, h, p): (f64, f64, f64, f64) = (10.0, 1.0, 1.0, 1.0);
    let i = b * h.powi(3) / 12.0;
    let eb = p * l.powi(3) / (3.0 * m.e * i);
    let d8i = cantilever_tip(ElementKind::Hex8I, [10, 1, 1], [l, b, h], m, p);
    let d8 = cantilever_tip(ElementKind::Hex8, [10, 1, 1], [l, b, h], m, p);
    println!(
        "10x1x1 cantilever tip / Euler-Bernoulli: Hex8I {:.5}, Hex8 {:.5}",
        d8i / eb,
        d8 / eb
    );
    assert!((d8i / eb - 1.0).abs() < 0.02);
    assert!(d8 / eb < 0.8, "Hex8 expected to lock");
}

#[test]
fn hex20_cantilever_matches_timoshenko() {
    let m = Material {
        e: 1000.0,
        nu: 0.0,
        rho: 1.0,
    };
    let (l, b, h, p): (f64, f64, f64, f64) = (10.0, 1.0, 1.0, 1.0);
    let i = b * h.powi(3) / 12.0;
    let timo = p * l.powi(3) / (3.0 * m.e * i) + p * l / (5.0 / 6.0 * m.shear_modulus() * b * h);
    // Hex20R needs 2 elements across: in a single column its spurious modes propagate (below).
    for (kind, n) in [
        (ElementKind::Hex20, [10, 1, 1]),
        (ElementKind::Hex20R, [10, 2, 2]),
        (ElementKind::Tet10, [10, 1, 1]),
    ] {
        let d = cantilever_tip(kind, n, [l, b, h], m, p);
        println!(
            "{kind:?} {n:?} cantilever tip / Timoshenko = {:.5}",
            d / timo
        );
        let tol = if kind == ElementKind::Tet10 {
            0.03
        } else {
            0.01
        };
        assert!((d / timo - 1.0).abs() < tol, "{kind:?}: {}", d / timo);
    }
}

#[test]
fn hex20_cantilever_first_frequency_near_beam_theory() {
    // 10 x 1 x 1 cantilever, nu = 0: first bending frequency vs Euler-Bernoulli; shear and rotary
    // inertia lower it by about (1 + 1.25 * r^2 ...) ~ 1 % at L/h = 10; tolerance 2 %.
    let m = Material {
        e: 1000.0,
        nu: 0.0,
        rho: 1.0,
    };
    let (l, b, h) = (10.0, 1.0, 1.0);
    let (mesh, lattice) = box_mesh(ElementKind::Hex20, [10, 1, 1], [l, b, h], m, &|_, _, x| x);
    let (k, mm) = assemble(&mesh, MassKind::Consistent);
    let fixed: Vec<usize> = lattice
        .iter()
        .enumerate()
        .filter(|(_, q)| q[0] == 0)
        .flat_map(|(i, _)| (0..3).map(move |c| 3 * i + c))
        .collect();
    let ev = gen_eigenvalues(&k, &mm, &fixed);
    let w_eb =
        1.875_104_f64.powi(2) * (m.e * b * h.powi(3) / 12.0 / (m.rho * b * h * l.powi(4))).sqrt();
    let ratio = ev[0].sqrt() / w_eb;
    println!("Hex20 cantilever omega1 / omega_EB = {ratio:.5}");
    assert!(
        (ev[0] - ev[1]).abs() < 1e-8 * ev[0],
        "square section: two equal bending modes"
    );
    assert!(ratio < 1.0 && ratio > 0.98, "ratio {ratio}");
}

#[test]
fn errors_for_bad_input() {
    // inverted element: swap bottom and top faces
    let mut x = reference_nodes(ElementKind::Hex8);
    x.rotate_left(4);
    let r = element_matrices(
        &single_solid(ElementKind::Hex8, &x, mat()),
        0,
        MassKind::Consistent,
    );
    assert!(matches!(r, Err(FeError::BadJacobian { .. })), "{r:?}");
    let r = element_matrices(
        &single_solid(ElementKind::Hex8I, &x, mat()),
        0,
        MassKind::Consistent,
    );
    assert!(matches!(r, Err(FeError::BadJacobian { .. })));
    // degenerate Tet10: all corners coplanar
    let mut t = reference_nodes(ElementKind::Tet10);
    for p in &mut t {
        p[2] = 0.0;
    }
    let r = element_matrices(
        &single_solid(ElementKind::Tet10, &t, mat()),
        0,
        MassKind::Consistent,
    );
    assert!(matches!(r, Err(FeError::BadJacobian { .. })));
    let mesh = single_solid(
        ElementKind::Hex8,
        &reference_nodes(ElementKind::Hex8),
        mat(),
    );
    assert!(matches!(
        element_matrices(&mesh, 1, MassKind::Consistent),
        Err(FeError::Invalid(_))
    ));
    let mut bad = mesh.clone();
    bad.elements[0].nodes.pop();
    assert!(matches!(
        element_matrices(&bad, 0, MassKind::Consistent),
        Err(FeError::Invalid(_))
    ));
    let mut bad = mesh.clone();
    bad.properties[0] = crate::mesh::Property::Solid {
        material: Material {
            e: -1.0,
            nu: 0.3,
            rho: 1.0,
        },
    };
    assert!(element_matrices(&bad, 0, MassKind::Consistent).is_err());
    let _unused: DMatrix<f64> = DMatrix::zeros(1, 1);
}

/// Zero-energy modes of Hex20R meshes (free-free, 2x2x2 rule): a single element has 6 spurious
/// modes; they are all suppressed in a 2x2x2 block, but 4 survive in a 3x1x1 single column
/// (so a 10x1x1 Hex20R cantilever is singular; use at least 2 elements across).
#[test]
fn hex20r_spurious_modes_in_meshes() {
    let m = Material {
        e: 1000.0,
        nu: 0.3,
        rho: 1.0,
    };
    let mut counts = Vec::new();
    for n in [[1, 1, 1], [3, 1, 1], [2, 2, 2]] {
        let (mesh, _) = box_mesh(
            ElementKind::Hex20R,
            n,
            [n[0] as f64, n[1] as f64, n[2] as f64],
            m,
            &|_, _, x| x,
        );
        let (k, _) = assemble(&mesh, MassKind::Consistent);
        let ev = sym_eigenvalues(&k);
        let lmax = *ev.last().unwrap();
        let zeros = ev.iter().filter(|l| l.abs() < 1e-8 * lmax).count();
        println!("Hex20R {n:?}: {zeros} zero eigenvalues (6 rigid)");
        counts.push(zeros);
    }
    assert_eq!(counts[0], 12);
    assert_eq!(counts[1], 10);
    assert_eq!(counts[2], 6, "2x2x2 block of Hex20R has only rigid modes");
}

/// The node-block stiffness (`B` has three nonzeros per column) equals the dense
/// `sum_p B^T D B det J w` to round-off, for a distorted hex20 and tet10 and a full (anisotropic)
/// symmetric `D`.
#[test]
fn node_block_stiffness_matches_dense_product() {
    use super::gauss::{hex_rule, tet_rule_4};
    use super::{hex20, tet10};
    let d = nalgebra::Matrix6::from_fn(|i, j| {
        let (a, b) = (i.min(j) as f64, i.max(j) as f64);
        if i == j {
            10.0 + a
        } else {
            0.3 * (a + 1.0) / (b + 2.0)
        }
    });
    let (a, t) = affine();
    for (kind, shape, rule) in [
        (
            ElementKind::Hex20,
            hex20::hex20_shape as solid::ShapeFn,
            hex_rule(3),
        ),
        (
            ElementKind::Tet10,
            tet10::tet10_shape as solid::ShapeFn,
            tet_rule_4(),
        ),
    ] {
        let x: Vec<[f64; 3]> = reference_nodes(kind)
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let v = a * Vector3::new(p[0], p[1], p[2]) + t;
                let w = 0.03 * (i as f64).sin();
                [v[0] + w, v[1] - w, v[2] + 0.5 * w]
            })
            .collect();
        let k = solid::stiffness(shape, &x, &d, &rule, 0).unwrap();
        let dd = solid::dyn_d(&d);
        let mut r = DMatrix::zeros(k.nrows(), k.ncols());
        for (ip, p) in rule.iter().enumerate() {
            let e = solid::eval_point(shape, &x, p.xi, 0, ip).unwrap();
            let b = solid::b_matrix(&e.dndx);
            r.gemm_tr(e.det * p.w, &b, &(&dd * &b), 1.0);
        }
        solid::symmetrize(&mut r);
        assert!(max_abs(&(&k - &r)) <= 1e-13 * max_abs(&r), "{kind:?}");
    }
}

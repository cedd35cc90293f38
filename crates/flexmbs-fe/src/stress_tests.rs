//! Stress recovery against closed-form elasticity: uniaxial stress and pure bending imposed as
//! exact displacement fields on solid meshes, and an end-loaded beam cantilever solved by the FE
//! model (Euler-Bernoulli beam elements are nodally exact for end loads) against N/A, M c/I,
//! T c/J and V/A.

use crate::mesh::generate::{beam_line, box_mesh};
use crate::mesh::{BeamSection, BeamTheory, Element, ElementKind, Property};
use crate::stress::*;
use crate::system::FeSystem;
use crate::{constraint::BoundaryConditions, element::MassKind, Material, Mesh, UnitSystem};
use faer::Mat;

const E: f64 = 70e9;
const NU: f64 = 0.33;

fn material() -> Material {
    Material::new(E, NU, 2700.0).unwrap()
}

/// Translation field `u(x)` sampled at the mesh nodes (one column).
fn field(mesh: &Mesh, u: impl Fn([f64; 3]) -> [f64; 3]) -> Mat<f64> {
    let mut t = Mat::<f64>::zeros(3 * mesh.num_nodes(), 1);
    for (i, x) in mesh.nodes.iter().enumerate() {
        let v = u(*x);
        for d in 0..3 {
            t[(3 * i + d, 0)] = v[d];
        }
    }
    t
}

fn node_values(s: &Mat<f64>, node: usize) -> [f64; 6] {
    std::array::from_fn(|c| s[(6 * node + c, 0)])
}

/// Uniaxial stress sigma_xx = E eps: the field u = eps (x, -nu y, -nu z) is linear, so every
/// solid element reproduces it exactly (1e-9 of E eps) at every node.
#[test]
fn uniaxial_stress_field_is_exact_for_solids() {
    let eps = 1e-3;
    let u = |x: [f64; 3]| [eps * x[0], -NU * eps * x[1], -NU * eps * x[2]];
    for kind in [
        ElementKind::Hex8,
        ElementKind::Hex8I,
        ElementKind::Hex20,
        ElementKind::Hex20R,
    ] {
        let mesh = box_mesh(
            [0.4, 0.05, 0.03],
            [3, 2, 2],
            kind,
            material(),
            UnitSystem::Si,
        )
        .unwrap();
        let n = mesh.num_nodes();
        let (kinds, s) =
            nodal_stress_fields(&mesh, n, field(&mesh, u).as_ref(), None, &default_fibres).unwrap();
        assert_eq!(kinds.len(), n);
        for (i, kind) in kinds.iter().enumerate() {
            assert_eq!(*kind, NodeStressKind::Solid);
            let v = node_values(&s, i);
            let want = [E * eps, 0.0, 0.0, 0.0, 0.0, 0.0];
            for c in 0..6 {
                assert!(
                    (v[c] - want[c]).abs() < 1e-9 * E * eps,
                    "{kind:?} node {i} comp {c}: {} vs {}",
                    v[c],
                    want[c]
                );
            }
            assert!((von_mises(&v) - E * eps).abs() < 1e-9 * E * eps);
        }
    }
}

/// Exact pure bending about z (3D elasticity, Timoshenko & Goodier):
/// u = kappa (-x y, (x^2 + nu (y^2 - z^2)) / 2, nu y z) gives sigma_xx = -E kappa y and zero
/// elsewhere, so sigma at the fibre c is M c / I with M = E I kappa. Quadratic: exact for Hex20
/// and Tet10, and for Hex8I on parallelepipeds through its bubble modes (1e-9 of E kappa c).
#[test]
fn pure_bending_is_exact_for_quadratic_solids() {
    let kappa = 0.02;
    let (b, h) = (0.05, 0.03);
    let yc = b / 2.0;
    let u = |x: [f64; 3]| {
        let (y, z) = (x[1] - yc, x[2] - h / 2.0);
        [
            -kappa * x[0] * y,
            0.5 * kappa * (x[0] * x[0] + NU * (y * y - z * z)),
            kappa * NU * y * z,
        ]
    };
    let scale = E * kappa * yc;
    let mut meshes = vec![box_mesh(
        [0.4, b, h],
        [3, 2, 2],
        ElementKind::Hex20,
        material(),
        UnitSystem::Si,
    )
    .unwrap()];
    meshes.push(distorted_tet10());
    meshes.push(
        box_mesh(
            [0.4, b, h],
            [3, 2, 2],
            ElementKind::Hex8I,
            material(),
            UnitSystem::Si,
        )
        .unwrap(),
    );
    for mesh in &meshes {
        let n = mesh.num_nodes();
        let (_, s) =
            nodal_stress_fields(mesh, n, field(mesh, u).as_ref(), None, &default_fibres).unwrap();
        for (i, x) in mesh.nodes.iter().enumerate() {
            let v = node_values(&s, i);
            let want = -E * kappa * (x[1] - yc);
            assert!(
                (v[0] - want).abs() < 1e-9 * scale,
                "node {i}: {} vs {want}",
                v[0]
            );
            for (c, vc) in v.iter().enumerate().skip(1) {
                assert!(vc.abs() < 1e-9 * scale, "node {i} comp {c}: {vc}");
            }
        }
    }
    // at the extreme fibre y = b/2: sigma = M c / I with M = E I kappa
    let i_z = h * b.powi(3) / 12.0;
    let m = E * i_z * kappa;
    assert!((E * kappa * yc - m * yc / i_z).abs() < 1e-9 * scale);
}

/// One straight-edged but skewed 10-node tetrahedron.
fn distorted_tet10() -> Mesh {
    let corners = [
        [0.0, 0.0, 0.0],
        [0.3, 0.01, 0.0],
        [0.05, 0.05, 0.002],
        [0.02, 0.01, 0.03],
    ];
    let mid = |a: usize, b: usize| std::array::from_fn(|d| 0.5 * (corners[a][d] + corners[b][d]));
    let mut mesh = Mesh::default();
    for c in corners {
        mesh.add_node(c);
    }
    for (a, b) in [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)] {
        mesh.add_node(mid(a, b));
    }
    let p = mesh.add_property(Property::Solid {
        material: material(),
    });
    mesh.elements.push(Element {
        kind: ElementKind::Tet10,
        nodes: (0..10).collect(),
        property: p,
    });
    mesh
}

/// End-loaded beam cantilever (axial N, shear P_y, P_z, torque T at the tip), solved by the FE
/// model: the section stresses at every node equal N/A, M_y c_z/I_y, -M_z c_y/I_z, T c_t/J,
/// V_y/A, V_z/A with M(x) = P (L - x) (Euler-Bernoulli elements are nodally exact for end loads;
/// 1e-8 of the largest value). The clamp's equivalent stress for P_y alone is M c / I.
#[test]
fn end_loaded_beam_cantilever_matches_section_formulas() {
    let (l, b, h) = (1.2, 0.03, 0.05);
    let sec = BeamSection::rectangle(b, h);
    let fib = BeamFibres::rectangle(b, h, sec.j);
    let fibres = |_: usize, _: &BeamSection| fib;
    let mesh = beam_line(
        [0.0; 3],
        [l, 0.0, 0.0],
        6,
        sec,
        BeamTheory::EulerBernoulli,
        [0.0, 1.0, 0.0],
        material(),
        UnitSystem::Si,
    )
    .unwrap();
    let bc = BoundaryConditions {
        fixed: mesh.node_set("start").unwrap().to_vec(),
        rigid: vec![],
    };
    let sys = FeSystem::assemble(&mesh, &bc, MassKind::Consistent, &mut |_, _| {}).unwrap();
    let tip = mesh.node_set("end").unwrap()[0];
    let (nx, py, pz, tq) = (3e3, 500.0, -800.0, 120.0);
    let (t, r) = static_displacements(&sys, &[(tip, [nx, py, pz, tq, 0.0, 0.0])]).unwrap();
    let (kinds, s) = nodal_stress_fields(
        &mesh,
        mesh.num_nodes(),
        t.as_ref(),
        Some(r.as_ref()),
        &fibres,
    )
    .unwrap();
    let scale = py.abs().max(pz.abs()) * l * fib.cz / sec.iy;
    for (i, x) in mesh.nodes.iter().enumerate() {
        assert_eq!(kinds[i], NodeStressKind::Beam);
        let arm = l - x[0];
        // M_z = E I_z v'' = P_y (L - x); M_y = -E I_y w'' = -P_z (L - x)
        let want = [
            nx / sec.area,
            -pz * arm * fib.cz / sec.iy,
            -py * arm * fib.cy / sec.iz,
            tq * fib.ct / sec.j,
            py / sec.area,
            pz / sec.area,
        ];
        let v = node_values(&s, i);
        for c in 0..6 {
            assert!(
                (v[c] - want[c]).abs() < 1e-8 * scale,
                "node {i} slot {c}: {} vs {}",
                v[c],
                want[c]
            );
        }
    }
    // bending alone: the clamp's equivalent stress is M c / I = P L c / I
    let (t, r) = static_displacements(&sys, &[(tip, [0.0, py, 0.0, 0.0, 0.0, 0.0])]).unwrap();
    let (_, s) = nodal_stress_fields(
        &mesh,
        mesh.num_nodes(),
        t.as_ref(),
        Some(r.as_ref()),
        &fibres,
    )
    .unwrap();
    let clamp = mesh.node_set("start").unwrap()[0];
    let mc_i = py * l * (b / 2.0) / sec.iz;
    let eq = equivalent_stress(NodeStressKind::Beam, &node_values(&s, clamp));
    assert!((eq - mc_i).abs() < 1e-9 * mc_i, "{eq} vs {mc_i}");
}

/// Fibre rules: a square's torsion point gives Roark's tau_max = T / (0.208 a^3) within 0.5 %;
/// round sections put every fibre at the radius; the equivalent rectangle of a rectangle's
/// constants is the rectangle's own fibres.
#[test]
fn fibre_rules() {
    let a = 0.04;
    let s = BeamSection::rectangle(a, a);
    let f = BeamFibres::rectangle(a, a, s.j);
    let tau_per_t = f.ct / s.j;
    let roark = 1.0 / (0.208 * a.powi(3));
    assert!(
        (tau_per_t / roark - 1.0).abs() < 5e-3,
        "{tau_per_t} vs {roark}"
    );
    assert_eq!(
        BeamFibres::round(0.1),
        BeamFibres {
            cy: 0.1,
            cz: 0.1,
            ct: 0.1
        }
    );
    let r = BeamSection::rectangle(0.03, 0.05);
    let e = BeamFibres::equivalent_rectangle(&r);
    assert!((e.cy - 0.015).abs() < 1e-15 && (e.cz - 0.025).abs() < 1e-15);
}

/// Von Mises of pure shear tau is sqrt(3) tau; of a hydrostatic state zero.
#[test]
fn von_mises_closed_forms() {
    let tau = 7.0;
    assert!((von_mises(&[0.0, 0.0, 0.0, tau, 0.0, 0.0]) - 3f64.sqrt() * tau).abs() < 1e-12);
    assert!(von_mises(&[5.0, 5.0, 5.0, 0.0, 0.0, 0.0]).abs() < 1e-12);
    assert_eq!(equivalent_stress(NodeStressKind::None, &[1.0; 6]), 0.0);
}

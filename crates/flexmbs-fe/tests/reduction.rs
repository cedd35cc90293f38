//! Reference problems of the FE front end: rigid-body modes of a free structure, Craig-Bampton
//! completeness, Guyan stiffness against beam theory, rigid interfaces.

use flexmbs_fe::constraint::{BoundaryConditions, RigidInterface};
use flexmbs_fe::eigen::{dense_generalized, EigenMethod, EigenOptions};
use flexmbs_fe::element::MassKind;
use flexmbs_fe::mesh::generate::box_mesh;
use flexmbs_fe::modes::project_dense;
use flexmbs_fe::reduction::{
    craig_bampton, modal_analysis, reduce_modal, CraigBamptonOptions, Provenance,
};
use flexmbs_fe::system::{sparse_times, FeSystem};
use flexmbs_fe::{ElementKind, Material, Mesh, UnitSystem};

fn beam(kind: ElementKind, n: [usize; 3], size: [f64; 3]) -> Mesh {
    box_mesh(size, n, kind, Material::steel(), UnitSystem::Si).unwrap()
}

fn dense_opts(n: usize) -> EigenOptions {
    EigenOptions {
        n_modes: n,
        method: EigenMethod::Dense,
        ..EigenOptions::default()
    }
}

/// A free-free body has exactly six rigid-body modes, recognised and excluded from the reduced body.
#[test]
fn free_free_has_exactly_six_rigid_modes() {
    for (kind, mass) in [
        (ElementKind::Hex20R, MassKind::Consistent),
        (ElementKind::Hex8I, MassKind::Lumped),
    ] {
        let n = if kind == ElementKind::Hex20R {
            [6, 2, 2]
        } else {
            [12, 2, 2]
        };
        let mesh = beam(kind, n, [0.3, 0.04, 0.03]);
        let sys = FeSystem::assemble(&mesh, &BoundaryConditions::default(), mass, &mut |_, _| {})
            .unwrap();
        for method in [EigenMethod::Dense, EigenMethod::Lanczos] {
            let opts = EigenOptions {
                method,
                ..EigenOptions::default()
            };
            let r = modal_analysis(&sys, 6, &opts, &mut |_| {}).unwrap();
            assert_eq!(r.omega2.len(), 12);
            assert_eq!(r.n_rigid, 6, "{kind:?} {method:?}: labels {:?}", r.labels);
            assert!(r.labels[..6]
                .iter()
                .all(|l| l.dominant.starts_with("rigid")));
            assert!(r.omega2[6] > 1e3, "first elastic omega^2 {}", r.omega2[6]);
            let body = reduce_modal(&mesh, &sys, &r, 6, "free", Provenance::default()).unwrap();
            assert_eq!(body.num_modes(), 6);
            assert!(body.frequencies_hz.iter().all(|&f| f > 10.0));
        }
    }
}

/// Craig-Bampton with all internal modes retained is an exact change of basis: its lowest ten
/// eigenfrequencies equal the full model's to 1e-8 relative.
#[test]
fn craig_bampton_with_all_internal_modes_reproduces_full_model() {
    let mesh = beam(ElementKind::Hex8I, [8, 1, 1], [0.4, 0.05, 0.05]);
    let xmin = mesh.node_set("xmin").unwrap().to_vec();
    let xmax = mesh.node_set("xmax").unwrap().to_vec();
    let bc = BoundaryConditions {
        fixed: vec![],
        rigid: vec![
            RigidInterface {
                name: "a".into(),
                nodes: xmin,
                point: None,
            },
            RigidInterface {
                name: "b".into(),
                nodes: xmax,
                point: None,
            },
        ],
    };
    let sys = FeSystem::assemble(&mesh, &bc, MassKind::Consistent, &mut |_, _| {}).unwrap();
    let iface = sys.map.interface_nodes.clone();
    let n_internal = sys.len() - 12;
    let body = craig_bampton(
        &mesh,
        &sys,
        &CraigBamptonOptions {
            interface: &iface,
            internal_modes: n_internal,
            eigen: &dense_opts(0),
        },
        "cb",
        Provenance::default(),
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(body.num_modes(), sys.len());
    let (full, _) =
        dense_generalized(sys.k.to_dense().as_ref(), sys.m.to_dense().as_ref()).unwrap();
    let f_full: Vec<f64> = full.iter().map(|w| w.max(0.0).sqrt()).collect();
    let f_cb: Vec<f64> = body
        .frequencies_hz
        .iter()
        .map(|f| f * 2.0 * std::f64::consts::PI)
        .collect();
    // skip the six rigid modes (zero up to round-off); compare the next ten
    for k in 6..16 {
        let rel = (f_cb[k] - f_full[k]).abs() / f_full[k];
        assert!(
            rel < 1e-8,
            "mode {k}: CB {} vs full {} (rel {rel:e})",
            f_cb[k],
            f_full[k]
        );
    }
    for k in 0..6 {
        assert!(f_full[k] < 1e-4 * f_full[6] && f_cb[k] < 1e-4 * f_full[6]);
    }
}

/// Guyan condensation of a clamped cantilever onto a rigid tip interface: the tip stiffness in y
/// is within 1 % of 3EI/L^3 (slender beam: shear adds 3 (1+nu) (h/L)^2 / (5 k) ~ 0.03 %).
#[test]
fn guyan_tip_stiffness_matches_beam_theory() {
    let (l, a) = (1.0, 0.02);
    let mesh = beam(ElementKind::Hex20R, [40, 2, 2], [l, a, a]);
    let tip = mesh.node_set("xmax").unwrap().to_vec();
    let bc = BoundaryConditions {
        fixed: mesh.node_set("xmin").unwrap().to_vec(),
        rigid: vec![RigidInterface {
            name: "tip".into(),
            nodes: tip,
            point: None,
        }],
    };
    let sys = FeSystem::assemble(&mesh, &bc, MassKind::Consistent, &mut |_, _| {}).unwrap();
    let iface = sys.map.interface_nodes.clone();
    let body = craig_bampton(
        &mesh,
        &sys,
        &CraigBamptonOptions {
            interface: &iface,
            internal_modes: 0,
            eigen: &EigenOptions::default(),
        },
        "guyan",
        Provenance::default(),
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(body.num_modes(), 6);
    // K_red is the 6x6 stiffness of the interface node; the tip force in y with free rotation:
    // condense the rotation rz: k = K_yy - K_y,rz^2 / K_rz,rz
    let k = &body.k_red;
    let k_free = k[(1, 1)] - k[(1, 5)] * k[(5, 1)] / k[(5, 5)];
    let e = Material::steel().e;
    let k_beam = 3.0 * e * a.powi(4) / 12.0 / l.powi(3);
    let rel = (k_free - k_beam) / k_beam;
    assert!(
        rel.abs() < 0.01,
        "Guyan tip stiffness {k_free} vs 3EI/L^3 {k_beam} (rel {rel:+e})"
    );
}

/// A rigid interface moves its nodes rigidly: rigid motions of a free body with two rigid interfaces
/// cost no strain energy, and the interface node carries the slaves' mass.
#[test]
fn rigid_interface_transmits_rigid_motion() {
    let mesh = beam(ElementKind::Hex8I, [4, 2, 2], [0.2, 0.02, 0.02]);
    let bc = BoundaryConditions {
        fixed: vec![],
        rigid: vec![RigidInterface {
            name: "end".into(),
            nodes: mesh.node_set("xmax").unwrap().to_vec(),
            point: None,
        }],
    };
    let sys = FeSystem::assemble(&mesh, &bc, MassKind::Lumped, &mut |_, _| {}).unwrap();
    let (mass, c) = sys.mass_and_center();
    let expected = 7850.0 * 0.2 * 0.02 * 0.02;
    assert!(
        (mass - expected).abs() < 1e-12 * expected,
        "mass {mass} vs {expected}"
    );
    assert!(
        (c[0] - 0.1).abs() < 1e-12 && (c[1] - 0.01).abs() < 1e-12 && (c[2] - 0.01).abs() < 1e-12
    );
    let r = sys.rigid_body_vectors([0.05, 0.0, 0.01]);
    let kr = sparse_times(&sys.k, r.as_ref());
    let kmax = flexmbs_fe::assembly::diagonal(&sys.k)
        .iter()
        .fold(0.0f64, |a, &b| a.max(b.abs()));
    for j in 0..6 {
        for i in 0..sys.len() {
            assert!(
                kr[(i, j)].abs() < 1e-9 * kmax,
                "K r_{j} not zero: {}",
                kr[(i, j)]
            );
        }
    }
    let rmr = project_dense(&sys.m, r.as_ref());
    assert!((rmr[(0, 0)] - expected).abs() < 1e-12 * expected);
}

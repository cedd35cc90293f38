//! FFR body of a beam mesh with lumped node rotary inertia: without it the torsion mode has zero
//! modal mass (only translational node masses enter, and torsion moves no node of the beam axis);
//! with the rotational blocks of the lumped beam mass added (`FfrBody::set_rotary_inertia`) the
//! FFR modal mass equals the FE projection `Phi^T M Phi` (= identity) to round-off.

use flexmbs_core::ffr::{reduced_body_to_si, FfrBody, RotationParam};
use flexmbs_fe::assembly::assemble;
use flexmbs_fe::constraint::BoundaryConditions;
use flexmbs_fe::eigen::EigenOptions;
use flexmbs_fe::element::MassKind;
use flexmbs_fe::mesh::generate::beam_line;
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::reduction::{modal_analysis, reduce_modal, Provenance};
use flexmbs_fe::system::FeSystem;
use flexmbs_fe::{Material, UnitSystem};
use flexmbs_reduce::full_mass::{node_rotary_inertias, rotary_inertias_to_si};

/// Cantilever steel beam 1000 x 20 x 10 mm (SI(mm)), 10 Euler-Bernoulli elements, lumped mass,
/// 12 modes (one of them torsion, 594 Hz by thin-beam theory). Lumped beam mass has no translation-rotation coupling, so
/// `Phi^T M Phi = sum m_j Phi_t^T Phi_t + sum Phi_r^T I_j Phi_r` exactly: the FFR
/// `m_ff + D` equals `m_red` to 1e-12, while `m_ff` alone misses the torsion mode's mass
/// entirely (its diagonal entry < 1e-9 instead of 1).
#[test]
fn beam_torsion_mode_mass_from_rotary_inertia() {
    let mat = Material::new(210000.0, 0.3, 7.85e-9).unwrap();
    let mesh = beam_line(
        [0.0; 3],
        [1000.0, 0.0, 0.0],
        10,
        BeamSection::rectangle(20.0, 10.0),
        BeamTheory::EulerBernoulli,
        [0.0, 1.0, 0.0],
        mat,
        UnitSystem::SiMm,
    )
    .unwrap();
    let bc = BoundaryConditions {
        fixed: mesh.node_set("start").unwrap().to_vec(),
        rigid: Vec::new(),
    };
    let a = assemble(&mesh, MassKind::Lumped, &[], &mut |_, _| {}).unwrap();
    let sys = FeSystem::from_assembled(&mesh, &a, &bc).unwrap();
    let opts = EigenOptions {
        n_modes: 12,
        ..EigenOptions::default()
    };
    let modal = modal_analysis(&sys, 12, &opts, &mut |_| {}).unwrap();
    let body = reduce_modal(&mesh, &sys, &modal, 12, "beam", Provenance::default()).unwrap();
    // the torsion mode (rotation about the beam axis x dominates)
    let torsion = (0..body.num_modes())
        .find(|&k| body.labels[k].dominant == "rx")
        .unwrap_or_else(|| panic!("no torsion mode among {:?}", body.labels));
    eprintln!("torsion mode {torsion}: {:?}", body.labels[torsion]);
    let si = reduced_body_to_si(&body);
    let mut ffr = FfrBody::from_reduced(&si, RotationParam::Cardan).unwrap();
    let mff = &ffr.invariants.m_ff;
    assert!(
        mff[(torsion, torsion)].abs() < 1e-9,
        "torsion mode {torsion}: translational modal mass {}",
        mff[(torsion, torsion)]
    );
    let inertias = rotary_inertias_to_si(
        &node_rotary_inertias(&a.m, &mesh.node_dofs(), si.num_nodes()).unwrap(),
        body.units,
    );
    ffr.set_rotary_inertia(&inertias).unwrap();
    let total = &ffr.invariants.m_ff + &ffr.rotary.as_ref().unwrap().d;
    let n = si.num_modes();
    let mut dev = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            dev = dev.max((total[(i, j)] - si.m_red[(i, j)]).abs());
        }
    }
    eprintln!("torsion mode {torsion}; max |m_ff + D - Phi^T M Phi| = {dev:e}");
    assert!(dev < 1e-12, "{dev:e}");
    assert!((si.m_red[(torsion, torsion)] - 1.0).abs() < 1e-9);
}

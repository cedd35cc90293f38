//! No heap allocation in Moreau steps of a point mass on the neutral surface of a clamped FFR body
//! with many modes (60): the sizes at which the Schur mass factorization and the contour's
//! matrix-vector product use faer's blocked kernels (the plate of `contact_flexible.rs` has 3
//! modes). Counted by the test binary's counting global allocator.

use crate::counting_alloc;

use faer::Mat;
use flexmbs_core::contact::{Contact, ContactLaw, NeutralSurface, PointContour};
use flexmbs_core::ffr::contour::{ContourSettings, FfrSurfaceContour};
use flexmbs_core::ffr::{FfrBody, FfrElement, FfrInvariants, RotationParam};
use flexmbs_core::integrator::{
    MoreauSettings, MoreauSscSettings, MoreauSscStepper, MoreauStepper, Stepper,
};
use flexmbs_core::{BodyId, Joint, ModelSpec, RigidBody, Workspace};
use nalgebra::{Matrix3, Vector3};

const NX: usize = 13;
const NY: usize = 5;
const NF: usize = 60;

/// A deterministic pseudo-random number in [-1, 1).
fn rnd(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

/// A plate 0.6 x 0.2 m in z = 0 with `NF` small random modes (lumped masses 0.1 kg, modal
/// stiffness 10 .. 600: modal frequencies below 1000 rad/s, stable at h = 1e-4 s).
fn plate() -> FfrBody {
    let mut seed = 11;
    let u0: Vec<[f64; 3]> = (0..NX * NY)
        .map(|n| [0.05 * (n / NY) as f64, 0.05 * (n % NY) as f64, 0.0])
        .collect();
    let masses = vec![0.1; NX * NY];
    let modes = Mat::from_fn(3 * NX * NY, NF, |_, _| 0.01 * rnd(&mut seed));
    let k = Mat::from_fn(
        NF,
        NF,
        |i, j| if i == j { 10.0 * (i + 1) as f64 } else { 0.0 },
    );
    let inv = FfrInvariants::from_lumped(&u0, &masses, modes.as_ref()).unwrap();
    FfrBody::new(
        inv,
        RotationParam::Cardan,
        &u0,
        modes.as_ref(),
        None,
        k.as_ref(),
    )
    .unwrap()
}

#[test]
fn moreau_steps_on_a_many_mode_contour_allocate_nothing() {
    let body = plate();
    let grid: Vec<usize> = (0..NX * NY).collect();
    let surface = FfrSurfaceContour::new(&body, &grid, NX, NY, ContourSettings::default()).unwrap();
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, 0.0, -9.81));
    let p = spec.add_body("plate", FfrElement::new(body));
    let fp = spec.add_frame("plate", p, Vector3::zeros(), Matrix3::identity());
    let fg = spec.add_ground_frame("ground", Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::fixed("clamp", fg, fp));
    let m = spec.add_body("mass", RigidBody::new(0.2, Matrix3::identity() * 1e-6));
    let fm = spec.add_frame("mass", m, Vector3::zeros(), Matrix3::identity());
    spec.add_contact(Contact::new(
        "contact",
        NeutralSurface::new(fp, surface).unwrap(),
        PointContour { frame: fm },
        ContactLaw::unilateral(0.0),
    ));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    let start = Vector3::new(0.31, 0.1, 0.0015);
    model.set_body_pose(&mut s, BodyId(1), start, Matrix3::identity());
    let v = Vector3::new(0.05, 0.0, -1.0);
    model.set_body_velocity(&mut s, BodyId(1), v, Vector3::zeros());
    let mut ws = Workspace::new(&model);
    let mut fixed = MoreauStepper::new(MoreauSettings::default());
    let mut ssc = MoreauSscStepper::new(MoreauSscSettings::default());
    let mut s2 = s.clone();
    let mut ws2 = Workspace::new(&model);
    fixed.initialize(&model, &mut s, &mut ws).unwrap();
    ssc.initialize(&model, &mut s2, &mut ws2).unwrap();
    // warm-up: the first (plastic) impact after 1.5 ms and the first full search happen here
    for _ in 0..20 {
        fixed.step(&model, &mut s, &mut ws, 1e-4).unwrap();
        ssc.step(&model, &mut s2, &mut ws2, 1e-4).unwrap();
    }
    // steps with the contact closed (impulses in the problem), counted without allocating
    let mut closed = 0;
    let n = counting_alloc::allocations_in(|| {
        for _ in 0..200 {
            fixed.step(&model, &mut s, &mut ws, 1e-4).unwrap();
            ssc.step(&model, &mut s2, &mut ws2, 5e-5).unwrap();
            closed += usize::from(s.contacts[0].active) + usize::from(s2.contacts[0].active);
        }
    });
    assert_eq!(n, 0, "{n} allocations in 400 steps");
    assert!(
        closed > 0,
        "the contact was never closed in the counted steps"
    );
}

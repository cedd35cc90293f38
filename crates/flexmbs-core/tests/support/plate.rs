//! The test plate of the neutral-contour tests: 0.6 x 0.15 m, NX x NY nodes in z = 0, smooth
//! random modes. Include with `#[path = "support/plate.rs"] mod plate;`.

use faer::Mat;
use flexmbs_core::ffr::{FfrBody, FfrInvariants, RotationParam};

/// A deterministic pseudo-random number in [-1, 1).
pub fn rnd(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

pub const NX: usize = 7;
pub const NY: usize = 4;
pub const NF: usize = 3;

/// A plate 0.6 x 0.15 m of NX x NY nodes in the plane z = 0 with smooth modes (lumped masses
/// 0.2 kg, modal stiffness 100).
pub fn plate(seed: &mut u64) -> FfrBody {
    let u0: Vec<[f64; 3]> = (0..NX * NY)
        .map(|n| [0.1 * (n / NY) as f64, 0.05 * (n % NY) as f64, 0.0])
        .collect();
    let masses = vec![0.2; NX * NY];
    let c: Vec<f64> = (0..3 * NF).map(|_| rnd(seed)).collect();
    let modes_t = Mat::from_fn(3 * NX * NY, NF, |r, k| {
        let p = u0[r / 3];
        let (x, y) = (p[0], p[1]);
        match r % 3 {
            2 => {
                c[3 * k] * (x * x) + c[3 * k + 1] * x * y + 0.1 * (k as f64 + 1.0) * (5.0 * x).sin()
            }
            0 => 0.02 * c[3 * k + 2] * x,
            _ => 0.01 * c[3 * k] * y,
        }
    });
    let k = Mat::from_fn(NF, NF, |i, j| if i == j { 100.0 } else { 0.0 });
    let inv = FfrInvariants::from_lumped(&u0, &masses, modes_t.as_ref()).unwrap();
    FfrBody::new(
        inv,
        RotationParam::Quaternion,
        &u0,
        modes_t.as_ref(),
        None,
        k.as_ref(),
    )
    .unwrap()
}

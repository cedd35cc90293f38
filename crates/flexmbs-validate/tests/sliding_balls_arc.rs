//! The C^2 check of sliding contact on a curved flexible contour (`sliding_balls_arc`): a light
//! ball guided along a stiff quarter ring (FFR, 16 beam elements, 6 clamped modes).

use flexmbs_validate::sliding_balls_arc::{
    reduce_ring, simulate_arc, JUMP_TOLERANCE, RADIUS, SPEED, STEP, TURNING_FACTOR,
};

/// The cubic contour: no velocity jump (1 % of v0^2 / R, fixed before the first run), the
/// acceleration turning smoothly (at most twice its turning per step, set after the first runs)
/// and equal to the ring's centripetal acceleration to 1 %; the polygon and the quadratic contour
/// are caught by these checks (so they can fail).
#[test]
fn cubic_contour_has_no_acceleration_jumps_and_the_checks_see_kinks() {
    let dir = flexmbs_io::test_tools::scratch_dir("arc");
    let ring = reduce_ring(&dir).unwrap();
    let runs: Vec<_> = [1, 2, 3]
        .iter()
        .map(|&d| simulate_arc(&ring, d).unwrap())
        .collect();
    let _ = std::fs::remove_dir_all(&dir);
    let turning = SPEED * STEP / RADIUS;
    for r in &runs {
        println!(
            "degree {}: jump {:.3e} ({:.2} x turning), curvature dev {:.3e}, speed loss {:.3e}",
            r.degree,
            r.jump_max,
            r.jump_max / turning,
            r.curvature_dev_max,
            r.speed_loss
        );
    }
    let [c0, c1, c2] = [&runs[0], &runs[1], &runs[2]];
    assert!(c2.jump_max < JUMP_TOLERANCE, "{}", c2.jump_max);
    assert!(c2.jump_max / turning < TURNING_FACTOR, "{}", c2.jump_max);
    assert!(c2.curvature_dev_max < 0.01, "{}", c2.curvature_dev_max);
    // frictionless sliding on a smooth contour keeps the speed (Moreau's first-order loss)
    assert!(c2.speed_loss < 1e-3, "{}", c2.speed_loss);
    assert!(c0.jump_max > JUMP_TOLERANCE, "{}", c0.jump_max);
    assert!(c1.jump_max / turning > TURNING_FACTOR, "{}", c1.jump_max);
    // a polygon loses speed at each of its 12 kinks (1 - cos of the kink angle)
    assert!(c0.speed_loss > 0.01, "{}", c0.speed_loss);
}

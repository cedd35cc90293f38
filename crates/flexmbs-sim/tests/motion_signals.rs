//! Signals `<frame>.acceleration`, `<frame>.angular_acceleration`, `<joint>.coordinates` and
//! `<joint>.rates` against closed forms: a body under a constant force, a rigid pendulum (exact
//! equation of motion, energy and small-angle solution), a crank driven at constant rate over
//! several turns.

use crate::common;

use flexmbs_io::results::{read_results, Results};
use flexmbs_sim::compile_model;
use flexmbs_sim::run::{run_model, RunOptions};
use std::path::Path;

fn run(dir: &Path, tag: &str, text: &str) -> Results {
    let file = dir.join(format!("{tag}.toml"));
    std::fs::write(&file, text).unwrap();
    let cm = compile_model(text, &file).unwrap();
    let out = dir.join(tag);
    run_model(&cm, &RunOptions::new(&out), &mut |_| {}).unwrap();
    read_results(&out.join("results.h5")).unwrap()
}

fn series(r: &Results, name: &str) -> Vec<f64> {
    r.series(name)
        .unwrap_or_else(|e| panic!("{name}: {e} ({:?})", r.series_names()))
}

/// A free rigid body of 2 kg under the constant force (3, -4, 5) N at its centre of mass, no
/// gravity: `a = F / m` and zero angular acceleration at every row, the first included, with the
/// generalized-alpha and DOPRI5 solvers (1e-10 m/s^2); the moreau solver writes NaN in the first
/// row (no acceleration before its first step) and `F / m` after.
#[test]
fn constant_force_gives_f_over_m() {
    let dir = common::work_dir("motion", "force");
    for solver in [
        "type = \"generalized-alpha\"\nh = \"1 ms\"",
        "type = \"dopri5\"",
        "type = \"moreau\"\nh = \"1 ms\"",
    ] {
        let text = format!(
            r#"
[model]
name = "push"
[solver]
{solver}
t_end = "0.1 s"
[[body]]
name = "block"
type = "rigid"
mass = "2 kg"
inertia = [0.01, 0.02, 0.03]
angular_velocity = [0, 0, "1 rad/s"]
[[load]]
type = "force"
frame = "block"
vector = ["3 N", "-4 N", "5 N"]
[output]
signals = ["block.acceleration", "block.angular_acceleration"]
animation = false
"#
        );
        let r = run(&dir, "push", &text);
        let expected = [1.5, -2.0, 2.5];
        let moreau = solver.contains("moreau");
        let mut worst = 0.0f64;
        for (c, e) in ["x", "y", "z"].iter().zip(expected) {
            let a = series(&r, &format!("block.acceleration.{c}"));
            let w = series(&r, &format!("block.angular_acceleration.{c}"));
            assert!(a.len() >= 2, "{solver}: {} rows", a.len());
            for (i, (a, w)) in a.iter().zip(&w).enumerate() {
                if moreau && i == 0 {
                    assert!(a.is_nan() && w.is_nan(), "moreau first row: {a} {w}");
                    continue;
                }
                worst = worst.max((a - e).abs()).max(w.abs());
            }
        }
        eprintln!("{solver}: max |a - F/m|, |alpha| = {worst:e}");
        assert!(worst < 1e-10, "{solver}: {worst:e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Rigid pendulum: a 1 kg rod of length 0.5 m (centre of mass at l = 0.25 m from the pivot,
/// pivot inertia I_p = m L^2 / 3) hanging along -y, released at rest turned by phi0 = 0.1 rad
/// about z. With the joint angle phi of `<joint>.coordinates`:
/// (generalized-alpha with rho_inf = 0.8: at rho_inf = 1 the accelerations of a constrained model
/// keep the undamped step-frequency oscillation of the index-3 scheme, here 1.6e-4 m/s^2)
/// - the tangential acceleration of the centre of mass equals the exact equation of motion,
///   `l phi_ddot = -(m g l^2 / I_p) sin(phi)`, and the normal one `l phi_dot^2`, to 1e-6 m/s^2;
///   the angular acceleration is `phi_ddot` about z;
/// - the rate `<joint>.rates` satisfies the energy solution
///   `phi_dot^2 = 2 m g l (cos phi - cos phi0) / I_p` to 1e-5 rad^2/s^2;
/// - the angle follows the small-angle solution `phi0 cos(omega t)`, `omega^2 = m g l / I_p`,
///   to 1.5e-3 rad over one period (the amplitude-dependent period shift, phi0^2/16 relative,
///   gives about 1e-3 rad after one period).
#[test]
fn pendulum_acceleration_and_angle_match_the_closed_forms() {
    let dir = common::work_dir("motion", "pendulum");
    let (m, g, len) = (1.0f64, 9.81f64, 0.5f64);
    let l = len / 2.0;
    let ip = m * len * len / 3.0;
    let phi0 = 0.1f64;
    let (s0, c0) = phi0.sin_cos();
    // centre of mass at the pivot + A(phi0) (0, -l, 0)
    let text = format!(
        r#"
[model]
name = "pendulum"
gravity = [0, -9.81, 0]
[solver]
type = "generalized-alpha"
rho_inf = 0.8
h = "0.2 ms"
t_end = "1.2 s"
[[body]]
name = "rod"
type = "rigid"
mass = "1 kg"
inertia = [0.0208333333333333333, 1e-4, 0.0208333333333333333]
position = [{px}, {py}, 0]
orientation = {{ matrix = [[{c0}, {ms0}, 0], [{s0}, {c0}, 0], [0, 0, 1]] }}
[[frame]]
name = "pivot"
body = "ground"
[[frame]]
name = "top"
body = "rod"
position = [0, {l}, 0]
[[joint]]
name = "hinge"
type = "revolute"
a = "pivot"
b = "top"
[output]
every = 10
signals = ["rod.acceleration", "rod.angular_acceleration", "hinge.coordinates", "hinge.rates", "rod.position"]
animation = false
"#,
        px = l * s0,
        py = -l * c0,
        ms0 = -s0,
    );
    let r = run(&dir, "pendulum", &text);
    let phi = series(&r, "hinge.coordinates.rz");
    let rate = series(&r, "hinge.rates.rz");
    let (ax, ay) = (
        series(&r, "rod.acceleration.x"),
        series(&r, "rod.acceleration.y"),
    );
    let alpha = series(&r, "rod.angular_acceleration.z");
    let omega = (m * g * l / ip).sqrt();
    let (mut e_acc, mut e_energy, mut e_small) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..phi.len() {
        let t = r.time[i];
        let (s, c) = phi[i].sin_cos();
        // tangent (direction of increasing phi) and outward normal of the centre of mass
        let tangent = [c, s];
        let outward = [s, -c];
        let a_t = ax[i] * tangent[0] + ay[i] * tangent[1];
        let a_n = -(ax[i] * outward[0] + ay[i] * outward[1]);
        let phi_ddot = -(m * g * l / ip) * s;
        e_acc = e_acc
            .max((a_t - l * phi_ddot).abs())
            .max((a_n - l * rate[i] * rate[i]).abs())
            .max((alpha[i] - phi_ddot).abs() * l);
        let energy = 2.0 * m * g * l * (c - phi0.cos()) / ip;
        e_energy = e_energy.max((rate[i] * rate[i] - energy).abs());
        if omega * t <= 2.0 * std::f64::consts::PI {
            e_small = e_small.max((phi[i] - phi0 * (omega * t).cos()).abs());
        }
    }
    eprintln!(
        "{} rows: acceleration {e_acc:e} m/s^2, energy {e_energy:e} rad^2/s^2, small-angle {e_small:e} rad",
        phi.len()
    );
    assert!(
        e_acc < 1e-6,
        "acceleration vs equation of motion: {e_acc:e}"
    );
    assert!(e_energy < 1e-5, "rate vs energy: {e_energy:e}");
    assert!(
        e_small < 1.5e-3,
        "angle vs small-angle solution: {e_small:e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A crank driven at omega = 10 rad/s (`angular_velocity` drive) for 3 s, about 4.8 turns: the
/// joint angle is `omega t`, unwrapped, to 1e-8 rad and its rate omega to 1e-8 rad/s, also with
/// output rows 0.5 s apart (5 rad between rows: unwrapped through the steps in between). A
/// body spinning freely at omega about z (isotropic inertia, no load) on a spherical joint at
/// the axis reports the rotation vector `(0, 0, wrap(omega t))` and its rate `(0, 0, omega)`.
#[test]
fn crank_angle_is_unwrapped_over_turns() {
    let dir = common::work_dir("motion", "crank");
    let crank = driven_crank(CRANK_START);
    for every in ["every = 1", "dt = \"0.5 s\""] {
        let text = format!(
            r#"
[model]
name = "crank"
[solver]
type = "generalized-alpha"
h = "1 ms"
t_end = "3 s"
{crank}
[[body]]
name = "probe"
type = "rigid"
mass = "1 kg"
inertia = [0.01, 0.01, 0.01]
angular_velocity = [0, 0, "10 rad/s"]
[[frame]]
name = "probe_hub"
body = "probe"
[[joint]]
name = "ball"
type = "spherical"
a = "axis"
b = "probe_hub"
[output]
{every}
signals = ["drive.coordinates", "drive.rates", "ball.coordinates", "ball.rates"]
animation = false
"#
        );
        let r = run(&dir, "crank", &text);
        let phi = series(&r, "drive.coordinates.rz");
        let rate = series(&r, "drive.rates.rz");
        let theta: Vec<Vec<f64>> = ["rx", "ry", "rz"]
            .iter()
            .map(|c| series(&r, &format!("ball.coordinates.{c}")))
            .collect();
        let theta_dot: Vec<Vec<f64>> = ["rx", "ry", "rz"]
            .iter()
            .map(|c| series(&r, &format!("ball.rates.{c}")))
            .collect();
        let (mut e_phi, mut e_rate, mut e_ball) = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..phi.len() {
            let t = r.time[i];
            e_phi = e_phi.max((phi[i] - 10.0 * t).abs());
            e_rate = e_rate.max((rate[i] - 10.0).abs());
            let wrapped = flexmbs_core::force::wrap_angle(10.0 * t);
            if (wrapped.abs() - std::f64::consts::PI).abs() > 1e-6 {
                e_ball = e_ball
                    .max(theta[0][i].abs())
                    .max(theta[1][i].abs())
                    .max((theta[2][i] - wrapped).abs());
            }
            e_ball = e_ball
                .max(theta_dot[0][i].abs())
                .max(theta_dot[1][i].abs())
                .max((theta_dot[2][i] - 10.0).abs());
        }
        let last = *phi.last().unwrap();
        eprintln!(
            "every {every}: {} rows, final angle {last} rad ({:.2} turns); errors angle {e_phi:e}, \
             rate {e_rate:e}, spherical {e_ball:e}",
            phi.len(),
            last / (2.0 * std::f64::consts::PI)
        );
        assert!((last - 30.0).abs() < 1e-8, "final angle {last}");
        assert!(e_phi < 1e-8 && e_rate < 1e-8, "{e_phi:e} {e_rate:e}");
        assert!(e_ball < 1e-8, "spherical joint: {e_ball:e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Initial velocities of the crank of [`driven_crank`] turning at 10 rad/s about the axis.
const CRANK_START: &str = "angular_velocity = [0, 0, \"10 rad/s\"]\nvelocity = [0, 1.0, 0]";

/// A crank 0.1 m long, hinged to ground at the origin by the revolute joint `drive` driven at
/// 10 rad/s; `start`: its initial velocities (empty for a restart).
fn driven_crank(start: &str) -> String {
    format!(
        r#"[[body]]
name = "crank"
type = "rigid"
mass = "1 kg"
inertia = [0.001, 0.01, 0.01]
position = [0.1, 0, 0]
{start}
[[frame]]
name = "axis"
body = "ground"
[[frame]]
name = "hub"
body = "crank"
position = [-0.1, 0, 0]
[[joint]]
name = "drive"
type = "revolute"
a = "axis"
b = "hub"
angular_velocity = "10 rad/s""#
    )
}

/// The crank driven at 10 rad/s to 1 s (10 rad, more than one and a half turns), restarted from
/// its last row to 1.5 s: the restarted run continues the unwrapped angle (`phi = 10 t` to
/// 1e-9 rad, its first row equal to the stored 10 rad) instead of starting again in (-pi, pi].
#[test]
fn restart_continues_the_unwrapped_angle() {
    let dir = common::work_dir("motion", "restart_angle");
    let text = |t_end: &str, restart: &str, start: &str| {
        let crank = driven_crank(start);
        format!(
            r#"
[model]
name = "crank"
[solver]
type = "generalized-alpha"
h = "1 ms"
t_end = "{t_end}"
{restart}
{crank}
[output]
signals = ["drive.coordinates"]
animation = false
"#
        )
    };
    let first = run(&dir, "first", &text("1 s", "", CRANK_START));
    let stored = *series(&first, "drive.coordinates.rz").last().unwrap();
    assert!((stored - 10.0).abs() < 1e-9, "{stored}");
    let key = format!("restart = {{ results = \"{}\" }}", first.path().display());
    // the restarted model takes the state from the results file: no initial velocities
    let second = run(&dir, "second", &text("1.5 s", &key, ""));
    let phi = series(&second, "drive.coordinates.rz");
    assert!((phi[0] - stored).abs() < 1e-12, "{} vs {stored}", phi[0]);
    let worst = second
        .time
        .iter()
        .zip(&phi)
        .map(|(t, p)| (p - 10.0 * t).abs())
        .fold(0.0f64, f64::max);
    assert!(worst < 1e-9, "max |phi - 10 t| = {worst:e}");
}

//! One generic joint: a constraint between two frames with a mask of locked relative DOFs.
//!
//! Relative translation `d = A_a^T (p_b - p_a)` and relative rotation `R = A_a^T A_b` are
//! measured in the first frame `a`. Locked translation `i` gives the row `g = e_i^a . (p_b - p_a)`.
//! Locked rotation `i` (with `(i, j, k)` cyclic) gives, depending on how many rotations are locked:
//! - 3 (fixed): `g = 1/2 (e_k^a . e_j^b - e_j^a . e_k^b)`, the `i`-component of the vector part
//!   of `R` (`sin` of a small rotation about `i`);
//! - 2 (one free axis `f`, the other locked axis `o`): `g = e_f^a . e_o^b` (axis `f` of `a` stays
//!   perpendicular to the locked axes of `b`: regular for any angle about `f`, unlike the vector
//!   part which is singular at 180°);
//! - 1: the universal-joint form `g = e_j^a . e_k^b`.
//!
//! Rows are ordered tx, ty, tz, rx, ry, rz, then the prescribed-motion row.

use crate::element::FrameKinematics;
use crate::ids::FrameId;
use crate::time_function::TimeFunction;
use nalgebra::Vector3;

/// Prescribed relative motion on a free DOF of a joint (one extra constraint row).
#[derive(Debug, Clone, PartialEq)]
pub enum PrescribedMotion {
    /// Relative angle about `z` of frame `a`: `phi(t) = f(t)`.
    /// Row: `g = sin(phi - f(t))` with `phi` measured from `x^a` to `x^b`.
    RevoluteAngle(TimeFunction),
    /// Relative angular velocity about `z`: `phi(t) = initial_angle + int_0^t rate`.
    RevoluteRate {
        /// Angle at `t = 0`.
        initial_angle: f64,
        /// Angular velocity as a function of time.
        rate: TimeFunction,
    },
    /// Relative displacement along `x` of frame `a`: `d_x = f(t)`.
    PrismaticDisplacement(TimeFunction),
}

/// A joint between frames `a` and `b`.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    /// Name.
    pub name: String,
    /// First frame (the relative motion is measured in its axes).
    pub frame_a: FrameId,
    /// Second frame.
    pub frame_b: FrameId,
    /// Locked relative DOFs `[tx, ty, tz, rx, ry, rz]` in frame `a`.
    pub locked: [bool; 6],
    /// Optional prescribed motion of the free `rz` (revolute) or `tx` (prismatic) DOF.
    pub prescribed: Option<PrescribedMotion>,
}

impl Joint {
    /// Generic joint with a locked-DOF mask.
    pub fn new(name: &str, frame_a: FrameId, frame_b: FrameId, locked: [bool; 6]) -> Self {
        Self {
            name: name.to_string(),
            frame_a,
            frame_b,
            locked,
            prescribed: None,
        }
    }
    /// All six relative DOFs locked.
    pub fn fixed(name: &str, a: FrameId, b: FrameId) -> Self {
        Self::new(name, a, b, [true; 6])
    }
    /// Rotation about `z` of frame `a` free.
    pub fn revolute(name: &str, a: FrameId, b: FrameId) -> Self {
        Self::new(name, a, b, [true, true, true, true, true, false])
    }
    /// All rotations free.
    pub fn spherical(name: &str, a: FrameId, b: FrameId) -> Self {
        Self::new(name, a, b, [true, true, true, false, false, false])
    }
    /// Translation along `x` of frame `a` free.
    pub fn prismatic(name: &str, a: FrameId, b: FrameId) -> Self {
        Self::new(name, a, b, [false, true, true, true, true, true])
    }
    /// Translation along and rotation about `z` of frame `a` free (the revolute axis).
    pub fn cylindrical(name: &str, a: FrameId, b: FrameId) -> Self {
        Self::new(name, a, b, [true, true, false, true, true, false])
    }
    /// Adds prescribed motion.
    pub fn with_prescribed(mut self, motion: PrescribedMotion) -> Self {
        self.prescribed = Some(motion);
        self
    }
    /// Names of the constraint rows in order: the locked DOFs (`tx`, `ty`, `tz`, `rx`, `ry`,
    /// `rz`), then `motion` for a prescribed motion.
    pub fn row_names(&self) -> impl Iterator<Item = &'static str> + '_ {
        const DOFS: [&str; 6] = ["tx", "ty", "tz", "rx", "ry", "rz"];
        (0..6)
            .filter(|&d| self.locked[d])
            .map(|d| DOFS[d])
            .chain(self.prescribed.as_ref().map(|_| "motion"))
    }

    /// Unit of row `name` of [`Joint::row_names`] (position level): `m` for translations and a
    /// prescribed displacement, `rad` otherwise.
    pub fn row_unit(&self, name: &str) -> &'static str {
        match (name, &self.prescribed) {
            ("tx" | "ty" | "tz", _) => "m",
            ("motion", Some(PrescribedMotion::PrismaticDisplacement(_))) => "m",
            _ => "rad",
        }
    }

    /// Number of constraint rows.
    pub fn num_rows(&self) -> usize {
        self.locked.iter().filter(|&&l| l).count() + usize::from(self.prescribed.is_some())
    }
}

/// One constraint row in terms of frame quantities: `G_row = t_b^T J_T^b + r_b^T J_R^b +
/// t_a^T J_T^a + r_a^T J_R^a`, `g_dot = G_row u + g_t`, `g_ddot = G_row u_dot + bias`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConstraintRow {
    /// Constraint value `g`.
    pub g: f64,
    /// Coefficient of `J_T` of frame `b`.
    pub t_b: Vector3<f64>,
    /// Coefficient of `J_R` of frame `b`.
    pub r_b: Vector3<f64>,
    /// Coefficient of `J_T` of frame `a`.
    pub t_a: Vector3<f64>,
    /// Coefficient of `J_R` of frame `a`.
    pub r_a: Vector3<f64>,
    /// Explicit time derivative `g_t`.
    pub g_t: f64,
    /// Acceleration bias.
    pub bias: f64,
}

/// `f = e_j^a . e_k^b`, its rate direction `n` (`f_dot = n . (omega_b - omega_a)`) and the
/// bias part of `f_ddot` (everything but `n . (J_R^b - J_R^a) u_dot`).
fn axis_pair(
    ka: &FrameKinematics,
    kb: &FrameKinematics,
    j: usize,
    k: usize,
) -> (f64, Vector3<f64>, f64) {
    let ea = ka.rotation.column(j).into_owned();
    let eb = kb.rotation.column(k).into_owned();
    let (wa, wb) = (ka.angular_velocity, kb.angular_velocity);
    let n = eb.cross(&ea);
    let n_dot = wb.cross(&eb).cross(&ea) + eb.cross(&wa.cross(&ea));
    let bias = (kb.bias_ang_acc - ka.bias_ang_acc).dot(&n) + (wb - wa).dot(&n_dot);
    (ea.dot(&eb), n, bias)
}

fn rotation_row(g: f64, n: Vector3<f64>, bias: f64) -> ConstraintRow {
    ConstraintRow {
        g,
        t_b: Vector3::zeros(),
        r_b: n,
        t_a: Vector3::zeros(),
        r_a: -n,
        g_t: 0.0,
        bias,
    }
}

/// Rows of a joint at time `t` (in the order documented in the module), written to `out`
/// (length [`Joint::num_rows`]).
pub fn joint_rows(
    joint: &Joint,
    t: f64,
    ka: &FrameKinematics,
    kb: &FrameKinematics,
    out: &mut [ConstraintRow],
) {
    let dp = kb.position - ka.position;
    let dv = kb.velocity - ka.velocity;
    let wa = ka.angular_velocity;
    let mut r = 0;
    for i in 0..3 {
        if joint.locked[i] {
            out[r] = translation_row(ka, kb, i, &dp, &dv, &wa);
            r += 1;
        }
    }
    let n_rot = joint.locked[3..].iter().filter(|&&l| l).count();
    for i in 0..3 {
        if joint.locked[3 + i] {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            out[r] = match n_rot {
                3 => {
                    let (f_kj, n_kj, b_kj) = axis_pair(ka, kb, k, j);
                    let (f_jk, n_jk, b_jk) = axis_pair(ka, kb, j, k);
                    rotation_row(
                        0.5 * (f_kj - f_jk),
                        0.5 * (n_kj - n_jk),
                        0.5 * (b_kj - b_jk),
                    )
                }
                2 => {
                    // free axis f, other locked axis o: e_f^a . e_o^b = 0 (any angle about f)
                    let f = (3..6).find(|&d| !joint.locked[d]).map_or(0, |d| d - 3);
                    let o = 3 - f - i;
                    let (g, n, b) = axis_pair(ka, kb, f, o);
                    rotation_row(g, n, b)
                }
                _ => {
                    // universal-joint form: e_j^a . e_k^b = 0
                    let (g, n, b) = axis_pair(ka, kb, j, k);
                    rotation_row(g, n, b)
                }
            };
            r += 1;
        }
    }
    match &joint.prescribed {
        None => {}
        Some(PrescribedMotion::PrismaticDisplacement(f)) => {
            let mut row = translation_row(ka, kb, 0, &dp, &dv, &wa);
            row.g -= f.value(t);
            row.g_t = -f.derivative(t);
            row.bias -= f.second_derivative(t);
            out[r] = row;
        }
        Some(m) => {
            let (p, pd, pdd) = match m {
                PrescribedMotion::RevoluteAngle(f) => {
                    (f.value(t), f.derivative(t), f.second_derivative(t))
                }
                PrescribedMotion::RevoluteRate {
                    initial_angle,
                    rate,
                } => (
                    initial_angle + rate.integral(t),
                    rate.value(t),
                    rate.derivative(t),
                ),
                PrescribedMotion::PrismaticDisplacement(_) => unreachable!("handled above"),
            };
            // S = sin(phi), C = cos(phi) from the x-y block of R; g = S cos p - C sin p.
            let (f_yx, n_yx, b_yx) = axis_pair(ka, kb, 1, 0);
            let (f_xy, n_xy, b_xy) = axis_pair(ka, kb, 0, 1);
            let (f_xx, n_xx, b_xx) = axis_pair(ka, kb, 0, 0);
            let (f_yy, n_yy, b_yy) = axis_pair(ka, kb, 1, 1);
            let (s, ns, bs) = (
                0.5 * (f_yx - f_xy),
                0.5 * (n_yx - n_xy),
                0.5 * (b_yx - b_xy),
            );
            let (c, nc, bc) = (
                0.5 * (f_xx + f_yy),
                0.5 * (n_xx + n_yy),
                0.5 * (b_xx + b_yy),
            );
            let w = kb.angular_velocity - ka.angular_velocity;
            let (s_dot, c_dot) = (ns.dot(&w), nc.dot(&w));
            let (sp, cp) = p.sin_cos();
            let mut row = rotation_row(s * cp - c * sp, ns * cp - nc * sp, 0.0);
            row.g_t = -(s * sp + c * cp) * pd;
            row.bias = cp * bs
                - sp * bc
                - 2.0 * pd * (s_dot * sp + c_dot * cp)
                - pd * pd * (s * cp - c * sp)
                - pdd * (s * sp + c * cp);
            out[r] = row;
        }
    }
}

/// Locked relative translation along axis `i` of frame `a`: `g = e_i^a . (p_b - p_a)`.
fn translation_row(
    ka: &FrameKinematics,
    kb: &FrameKinematics,
    i: usize,
    dp: &Vector3<f64>,
    dv: &Vector3<f64>,
    wa: &Vector3<f64>,
) -> ConstraintRow {
    let e = ka.rotation.column(i).into_owned();
    let exdp = e.cross(dp);
    let bias = e.dot(&(kb.bias_acc - ka.bias_acc))
        + 2.0 * wa.cross(&e).dot(dv)
        + exdp.dot(&ka.bias_ang_acc)
        + wa.cross(&wa.cross(&e)).dot(dp);
    ConstraintRow {
        g: e.dot(dp),
        t_b: e,
        r_b: Vector3::zeros(),
        t_a: -e,
        r_a: exdp,
        g_t: 0.0,
        bias,
    }
}

impl ConstraintRow {
    /// A row with every coefficient zero.
    pub const ZERO: Self = Self {
        g: 0.0,
        t_b: Vector3::new(0.0, 0.0, 0.0),
        r_b: Vector3::new(0.0, 0.0, 0.0),
        t_a: Vector3::new(0.0, 0.0, 0.0),
        r_a: Vector3::new(0.0, 0.0, 0.0),
        g_t: 0.0,
        bias: 0.0,
    };
}

/// Most rows a joint can have: six locked DOFs and a prescribed motion.
pub const MAX_JOINT_ROWS: usize = 7;

/// The reaction wrench of a joint: the force and torque it exerts on frame `b` (the torque about
/// the origin of `b`), both in the axes of frame `a`, from the joint's multipliers `lambda`
/// (length [`Joint::num_rows`]). The constraint force in the equations of motion is
/// `-G^T lambda` (`M u_dot = h - G^T lambda`); the part acting through frame `b` is
/// `J_T^b^T F + J_R^b^T T` with `F = -sum_r lambda_r t_b,r`, `T = -sum_r lambda_r r_b,r`.
/// A prescribed motion row contributes the driving force or torque. Frame `a` receives the
/// opposite force (and the matching torque about its own origin). No allocation.
pub fn joint_reaction(
    joint: &Joint,
    t: f64,
    ka: &FrameKinematics,
    kb: &FrameKinematics,
    lambda: &[f64],
) -> (Vector3<f64>, Vector3<f64>) {
    let n = joint.num_rows();
    let mut rows = [ConstraintRow::ZERO; MAX_JOINT_ROWS];
    joint_rows(joint, t, ka, kb, &mut rows[..n]);
    let (mut force, mut torque) = (Vector3::zeros(), Vector3::zeros());
    for (row, l) in rows[..n].iter().zip(lambda) {
        force -= row.t_b * *l;
        torque -= row.r_b * *l;
    }
    let at = ka.rotation.transpose();
    (at * force, at * torque)
}

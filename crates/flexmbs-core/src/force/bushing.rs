//! A 6-DOF bushing: linear stiffness and damping matrices between two frames.

use super::{ForceElement, Wrench};
use crate::element::FrameKinematics;
use crate::ids::FrameId;
use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

/// A linear 6-DOF bushing between frames `a` and `b`. The deflection, in the axes of `a`, is
///
/// ```text
/// x = [A_a^T (p_b - p_a);  theta],   theta_i = (e_k^a . e_j^b - e_j^a . e_k^b) / 2   (i, j, k cyclic)
/// ```
///
/// (`theta`: the small-angle rotation measure of the fixed joint's rotation rows, the vector
/// part of `A_a^T A_b`: `sin(alpha) e` for a rotation `alpha` about one axis `e` of `a`, so
/// the bushing is linear for small rotations only). The generalized force is
/// `F = -K x - D x_dot` (6 x 6 `K` symmetric, `D`), applied through the exact variation of
/// `x`: on `b` the force `f = A_a F_t` and the moment `m = sum_i F_r,i c_i`
/// (`c_i = (e_j^b x e_k^a - e_k^b x e_j^a)/2`, `dtheta_i = c_i . (dtheta_b - dtheta_a)`), on
/// `a` the force `-f` and the moment `f x r - m` (`r = p_b - p_a`). So `V = x^T K x / 2` is its
/// potential energy and `x_dot^T D x_dot` the dissipated power, exactly.
#[derive(Debug, Clone, PartialEq)]
pub struct Bushing {
    /// Name.
    pub name: String,
    /// Frames `a`, `b`.
    pub frames: [FrameId; 2],
    /// Stiffness `K` (translations then rotations: N/m, N/rad, N m/m, N m/rad), symmetric.
    pub stiffness: Matrix6<f64>,
    /// Damping `D` (likewise, per velocity).
    pub damping: Matrix6<f64>,
}

/// Deflection `x`, its rate, the rotation measure's variation vectors `c_i` (columns) and
/// `r = p_b - p_a`.
struct Deflection {
    x: Vector6<f64>,
    x_dot: Vector6<f64>,
    c: Matrix3<f64>,
    r: Vector3<f64>,
}

impl Bushing {
    /// A bushing with diagonal stiffness and damping matrices.
    pub fn diagonal(name: &str, a: FrameId, b: FrameId, k: [f64; 6], d: [f64; 6]) -> Self {
        Self {
            name: name.to_string(),
            frames: [a, b],
            stiffness: Matrix6::from_diagonal(&Vector6::from(k)),
            damping: Matrix6::from_diagonal(&Vector6::from(d)),
        }
    }

    fn deflection(&self, frames: &[FrameKinematics]) -> Deflection {
        let [a, b] = self.frames;
        let (ka, kb) = (&frames[a.index()], &frames[b.index()]);
        let (ra, rb) = (&ka.rotation, &kb.rotation);
        let r = kb.position - ka.position;
        let xt = ra.transpose() * r;
        let vt = ra.transpose() * (kb.velocity - ka.velocity - ka.angular_velocity.cross(&r));
        let w = kb.angular_velocity - ka.angular_velocity;
        let mut x = Vector6::zeros();
        let mut x_dot = Vector6::zeros();
        let mut c = Matrix3::zeros();
        for i in 0..3 {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            x[i] = xt[i];
            x_dot[i] = vt[i];
            x[3 + i] = 0.5 * (ra.column(k).dot(&rb.column(j)) - ra.column(j).dot(&rb.column(k)));
            let ci = 0.5 * (rb.column(j).cross(&ra.column(k)) - rb.column(k).cross(&ra.column(j)));
            x_dot[3 + i] = ci.dot(&w);
            c.set_column(i, &ci);
        }
        Deflection { x, x_dot, c, r }
    }
}

impl ForceElement for Bushing {
    fn name(&self) -> &str {
        &self.name
    }
    fn frames(&self) -> &[FrameId] {
        &self.frames
    }
    fn validate(&self) -> Result<(), String> {
        for (name, m) in [("stiffness", &self.stiffness), ("damping", &self.damping)] {
            if !m.iter().all(|x| x.is_finite()) {
                return Err(format!("`{name}` must be finite"));
            }
            if (0..6).any(|i| m[(i, i)] < 0.0) {
                return Err(format!("`{name}` must have a diagonal >= 0"));
            }
            let scale = m.amax().max(f64::MIN_POSITIVE);
            if (m - m.transpose()).amax() > 1e-12 * scale {
                return Err(format!("`{name}` must be symmetric"));
            }
        }
        Ok(())
    }
    fn wrenches(&self, _t: f64, frames: &[FrameKinematics], out: &mut [Wrench]) {
        let d = self.deflection(frames);
        let g = -(self.stiffness * d.x) - self.damping * d.x_dot;
        let ra = &frames[self.frames[0].index()].rotation;
        let f = ra * Vector3::new(g[0], g[1], g[2]);
        let m = d.c * Vector3::new(g[3], g[4], g[5]);
        out[0] = Wrench {
            force: -f,
            moment: f.cross(&d.r) - m,
        };
        out[1] = Wrench {
            force: f,
            moment: m,
        };
    }
    fn depends_on_velocity(&self) -> bool {
        self.damping.iter().any(|x| *x != 0.0)
    }
    fn force_scale(&self, frames: &[FrameKinematics]) -> f64 {
        self.stiffness.amax() * super::position_scale(&self.frames, frames)
    }
    fn potential_energy(&self, frames: &[FrameKinematics]) -> f64 {
        let d = self.deflection(frames);
        0.5 * d.x.dot(&(self.stiffness * d.x))
    }
    fn nonconservative_power(&self, _t: f64, frames: &[FrameKinematics]) -> f64 {
        let d = self.deflection(frames);
        -d.x_dot.dot(&(self.damping * d.x_dot))
    }
}

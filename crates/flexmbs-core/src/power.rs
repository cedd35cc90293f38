//! Power of what the energy of [`crate::system::energy`] does not contain: point loads, dampers
//! and prescribed motions (drives), and its time integral, the external work `W`, so that
//! `E(t) - W(t)` is the conserved quantity of a model without other non-conservative forces.
//!
//! - Point force `f` and torque `m` on a frame: `P = f . v + m . omega`.
//! - Spring-damper: the spring is in the energy (`springs`); the damper force `d l_dot` along the
//!   line does `P = -d l_dot^2`.
//! - Joints: the constraint force is `-G^T lambda` (`M u_dot = h - G^T lambda`), its power
//!   `-lambda^T G u = lambda^T g_t` on the velocity constraint `G u + g_t = 0`. Rows without
//!   explicit time dependence (`g_t = 0`, ideal joints) do no work; a prescribed-motion row
//!   delivers `lambda g_t`, the drive power.
//!
//! - Force elements ([`crate::force`]): their potential energy is in `springs`, the rest is
//!   [`crate::force::ForceElement::nonconservative_power`] (in `loads`).
//! - Geometric stiffening of an FFR body: the force `-K_geo(omega_bar) q_f` has no potential in
//!   the elastic energy and is not conservative when `omega_bar` varies; its power
//!   `-q_f_dot^T K_geo(omega_bar) q_f` is [`stiffening_power`] (per body: the element contract
//!   does not expose it, so the caller keeps the stiffened bodies).

use crate::element::FrameKinematics;
use crate::ffr::{FfrBody, FfrScratch};
use crate::ids::FrameId;
use crate::joint::{joint_rows, ConstraintRow, MAX_JOINT_ROWS};
use crate::load::Load;
use crate::model::Model;

/// Instantaneous external power by source (W).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Power {
    /// Point forces and torques (`f . v + m . omega`).
    pub loads: f64,
    /// Dampers of spring-dampers (`-d l_dot^2`, never positive).
    pub dampers: f64,
    /// Prescribed motions (`lambda^T g_t` of the joint rows).
    pub drives: f64,
}

impl Power {
    /// Sum of all sources.
    pub fn total(&self) -> f64 {
        self.loads + self.dampers + self.drives
    }
}

/// True if the model has anything that [`external_power`] can see: loads or prescribed
/// motions. Without them the power is zero and `E` alone is conserved.
pub fn has_external_work(model: &Model) -> bool {
    !model.loads.is_empty() || model.joints.iter().any(|j| j.prescribed.is_some())
}

/// The frames [`external_power`] reads: those of the loads and of the prescribed joints
/// (sorted, without repeats), to be updated with [`crate::system::update_selected_frames`].
pub fn power_frames(model: &Model) -> Vec<FrameId> {
    let mut ids: Vec<FrameId> = Vec::new();
    for load in &model.loads {
        let mut f = [FrameId(0); crate::load::MAX_LOAD_FRAMES];
        let n = load.frames(&mut f);
        ids.extend_from_slice(&f[..n]);
    }
    for j in model.joints.iter().filter(|j| j.prescribed.is_some()) {
        ids.extend([j.frame_a, j.frame_b]);
    }
    ids.sort();
    ids.dedup();
    ids
}

/// External power at time `t` from up-to-date kinematics of the [`power_frames`] in `frames`
/// ([`crate::system::update_frames`] or [`crate::system::update_selected_frames`]) and the
/// multipliers `lambda`. No allocation.
pub fn external_power(model: &Model, t: f64, frames: &[FrameKinematics], lambda: &[f64]) -> Power {
    let mut p = Power::default();
    for load in &model.loads {
        match load {
            Load::SpringDamper {
                frame_a,
                frame_b,
                damping,
                ..
            } => {
                let (ka, kb) = (&frames[frame_a.index()], &frames[frame_b.index()]);
                let d = kb.position - ka.position;
                let l = d.norm();
                if l > 0.0 {
                    let l_dot = (d / l).dot(&(kb.velocity - ka.velocity));
                    p.dampers -= damping * l_dot * l_dot;
                }
            }
            Load::Element(e) => p.loads += e.nonconservative_power(t, frames),
            _ => {
                let mut w = [(frame_a_of(load), Default::default(), Default::default());
                    crate::load::MAX_LOAD_FRAMES];
                let n = load.wrenches(t, 1.0, frames, &mut w);
                for (frame, f, m) in &w[..n] {
                    let k = &frames[frame.index()];
                    p.loads += f.dot(&k.velocity) + m.dot(&k.angular_velocity);
                }
            }
        }
    }
    let mut rows = [ConstraintRow::ZERO; MAX_JOINT_ROWS];
    for (joint, &first) in model.joints.iter().zip(&model.joint_rows) {
        if joint.prescribed.is_none() {
            continue;
        }
        let n = joint.num_rows();
        let (ka, kb) = (
            &frames[joint.frame_a.index()],
            &frames[joint.frame_b.index()],
        );
        joint_rows(joint, t, ka, kb, &mut rows[..n]);
        for (row, l) in rows[..n].iter().zip(&lambda[first..first + n]) {
            p.drives += l * row.g_t;
        }
    }
    p
}

/// Some frame of a point load (to initialize the wrench buffer).
fn frame_a_of(load: &Load) -> FrameId {
    match load {
        Load::Force { frame, .. } | Load::Torque { frame, .. } => *frame,
        Load::SpringDamper { frame_a, .. } => *frame_a,
        Load::Element(e) => e.frames()[0],
    }
}

/// Accumulates the external work `W = int P dt` over accepted steps with the trapezoidal rule
/// (second order, like the integrators' energy error).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WorkMeter {
    last: Option<(f64, f64)>,
    work: f64,
}

impl WorkMeter {
    /// Adds the step from the previous call to time `t` with power `power` at `t` (the first
    /// call only sets the start).
    pub fn advance(&mut self, t: f64, power: f64) {
        if let Some((t0, p0)) = self.last {
            self.work += 0.5 * (t - t0) * (p0 + power);
        }
        self.last = Some((t, power));
    }

    /// Work done since the first call (J).
    pub fn work(&self) -> f64 {
        self.work
    }
}

/// Power `q_f_dot^T (-K_geo(omega_bar) q_f)` of the geometric stiffening force of an FFR body at
/// its coordinates `q`, `u` (zero without stiffening; NaN for an invalid state). `s` is the
/// body's scratch and `buf` has length `body.nu()`. No allocation.
pub fn stiffening_power(
    body: &FfrBody,
    q: &[f64],
    u: &[f64],
    s: &mut FfrScratch,
    buf: &mut [f64],
) -> f64 {
    if body.geometric_stiffening().is_none() {
        return 0.0;
    }
    if body.update(q, u, s).is_err() {
        return f64::NAN;
    }
    buf.fill(0.0);
    body.add_geometric_stiffening_force(s, buf);
    buf.iter().zip(u).skip(6).map(|(f, v)| f * v).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ffr::{FfrInvariants, RotationParam};
    use faer::Mat;
    use flexmbs_fe::geometric::{GeometricStiffness, InertialLoad};
    use nalgebra::{DVector, Vector3};

    /// `stiffening_power` equals `-q_f_dot^T K_geo(omega_bar) q_f` with `K_geo` assembled by
    /// `geometric_stiffness_matrix` from `omega_bar = u[3..6]` (quaternion body) to 1e-13
    /// relative, and is zero without stiffening.
    #[test]
    fn stiffening_power_is_the_modal_power_of_the_stiffening_force() {
        let (n, nf) = (4, 3);
        let x = |i: usize, j: usize| ((7 * i + 3 * j + 1) % 11) as f64 / 11.0 - 0.5;
        let u0: Vec<[f64; 3]> = (0..n).map(|i| [i as f64 * 0.3, x(i, 1), x(i, 2)]).collect();
        let masses = vec![1.0; n];
        let modes = Mat::from_fn(3 * n, nf, x);
        let k = Mat::from_fn(nf, nf, |i, j| if i == j { 10.0 } else { 0.0 });
        let inv = FfrInvariants::from_lumped(&u0, &masses, modes.as_ref()).unwrap();
        let plain = FfrBody::new(
            inv,
            RotationParam::Quaternion,
            &u0,
            modes.as_ref(),
            None,
            k.as_ref(),
        )
        .unwrap();
        let pats = InertialLoad::centrifugal();
        let matrices = (0..pats.len())
            .map(|p| Mat::from_fn(nf, nf, |i, j| x(i + p, j) + x(j + p, i)))
            .collect();
        let g = GeometricStiffness {
            load_patterns: pats,
            matrices,
        };
        let body = plain.clone().with_geometric_stiffening(&g).unwrap();
        let q = [0.1, 0.2, 0.3, 0.9, 0.1, -0.3, 0.2, 0.02, -0.01, 0.03];
        let mut qn = q;
        body.normalize(&mut qn).unwrap();
        let u = [0.5, -0.2, 0.1, 3.0, -1.0, 2.0, 0.4, -0.7, 0.2];
        let mut s = FfrScratch::new(nf);
        let mut buf = vec![0.0; body.nu()];
        let p = stiffening_power(&body, &qn, &u, &mut s, &mut buf);
        let kg = body.geometric_stiffness_matrix(&Vector3::new(u[3], u[4], u[5]));
        let qf = DVector::from_column_slice(&qn[7..]);
        let qfd = DVector::from_column_slice(&u[6..]);
        let want = -(qfd.transpose() * (&kg * &qf))[(0, 0)];
        assert!(want.abs() > 1e-3, "{want}");
        assert!((p - want).abs() < 1e-13 * want.abs(), "{p} vs {want}");
        assert_eq!(stiffening_power(&plain, &qn, &u, &mut s, &mut buf), 0.0);
    }
}

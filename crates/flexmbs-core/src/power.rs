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
//! Not included: the geometric stiffening force of FFR bodies `-K_geo(omega_bar) q_f`, which
//! has no potential in the elastic energy and is not conservative when `omega_bar` varies; with
//! stiffening on, `E - W` is not conserved (documented in `docs/model-file.md`).

use crate::element::FrameKinematics;
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

/// External power at time `t` from up-to-date frame kinematics `frames`
/// ([`crate::system::update_frames`]) and the multipliers `lambda`. No allocation.
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
            _ => {
                let mut w = [(frame_a_of(load), Default::default(), Default::default()); 2];
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
fn frame_a_of(load: &Load) -> crate::ids::FrameId {
    match load {
        Load::Force { frame, .. } | Load::Torque { frame, .. } => *frame,
        Load::SpringDamper { frame_a, .. } => *frame_a,
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

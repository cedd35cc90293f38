//! Run-time plausibility warnings: what a run computes without error but a user should not trust
//! without a second look. Checked on output rows, reported in [`crate::run::RunSummary::warnings`]
//! and printed by `flexmbs run`.
//!
//! * **Large elastic deformation** of a flexible body: the largest elastic displacement of its
//!   drawn points (the FE nodes) above [`DEFORMATION_FRACTION`] of the body's size (the diagonal of
//!   its undeformed bounding box). A reduced (FFR) body is linear in its modes: beyond a few
//!   percent its results leave the small-deformation assumption.
//! * **Constraint drift**: position constraints violated by more than [`POSITION_DRIFT`] (m or
//!   rad), or velocity constraints by more than [`VELOCITY_DRIFT`] times `max(1, max |u|)` of the
//!   step (index-3 integration keeps positions, not velocities, on the constraints: a large
//!   velocity drift means inconsistent initial velocities or steps too large for the motion).
//! * **Unstable penalty step**: Moreau time-stepping treats a regularized contact's force
//!   explicitly; when `h sqrt(k / m_eff)` at a closing contact exceeds [`PENALTY_STEP`]
//!   ([`flexmbs_core::contact::ContactState::penalty_step`]) the penalty oscillation grows.

use crate::compile::CompiledModel;
use flexmbs_core::contact::ContactState;

/// Elastic displacement, as a fraction of a flexible body's size, above which a run warns.
pub const DEFORMATION_FRACTION: f64 = 0.1;

/// Position constraint violation (m or rad) above which a run warns.
pub const POSITION_DRIFT: f64 = 1e-6;

/// Velocity constraint violation, relative to `max(1, max |u|)`, above which a run warns. Index-3
/// generalized-alpha leaves velocity errors of a few percent in the first steps of a fast but
/// smooth move (3 % measured for a quintic 90 deg move in 80 steps); a drive whose velocity jumps
/// gives O(1) to O(100).
pub const VELOCITY_DRIFT: f64 = 0.1;

/// `h sqrt(k / m_eff)` of a closing penalty contact above which a Moreau run warns (the stability
/// limit of the explicit penalty force).
pub const PENALTY_STEP: f64 = 2.0;

/// Output rows between two deformation checks when no animation frame is written there.
pub const DEFORMATION_CHECK_EVERY: usize = 10;

/// The largest value seen and when.
#[derive(Debug, Clone, Copy, Default)]
struct Peak {
    value: f64,
    t: f64,
}

impl Peak {
    fn observe(&mut self, value: f64, t: f64) {
        if value > self.value {
            *self = Peak { value, t };
        }
    }
}

/// Peaks of the monitored quantities of one run.
#[derive(Debug)]
pub(crate) struct Plausibility {
    /// Size of each body of `cm.bodies` (0 for rigid bodies and point masses: not checked).
    sizes: Vec<f64>,
    deformation: Vec<Peak>,
    position_drift: Peak,
    velocity_drift: Peak,
    /// Per contact: the largest `h sqrt(k / m_eff)` of a closing penalty contact.
    penalty_step: Vec<Peak>,
}

impl Plausibility {
    /// Monitors for the bodies of `cm`.
    pub(crate) fn new(cm: &CompiledModel) -> Self {
        let sizes = cm
            .bodies
            .iter()
            .map(|b| {
                let g = &b.geometry;
                if g.modes == 0 || !g.fe_nodes || g.points.is_empty() {
                    return 0.0;
                }
                let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
                for p in &g.points {
                    for d in 0..3 {
                        lo[d] = lo[d].min(p[d]);
                        hi[d] = hi[d].max(p[d]);
                    }
                }
                (0..3).map(|d| (hi[d] - lo[d]).powi(2)).sum::<f64>().sqrt()
            })
            .collect();
        Self {
            deformation: vec![Peak::default(); cm.bodies.len()],
            sizes,
            position_drift: Peak::default(),
            velocity_drift: Peak::default(),
            penalty_step: vec![Peak::default(); cm.model.contacts.len()],
        }
    }

    /// The contacts' penalty step ratios after an accepted step at `t`.
    pub(crate) fn observe_contacts(&mut self, t: f64, contacts: &[ContactState]) {
        for (peak, c) in self.penalty_step.iter_mut().zip(contacts) {
            peak.observe(c.penalty_step, t);
        }
    }

    /// Elastic displacements of every body's points at time `t` (global axes).
    pub(crate) fn observe_deformation(&mut self, t: f64, elastic: &[Vec<[f64; 3]>]) {
        for ((peak, size), el) in self.deformation.iter_mut().zip(&self.sizes).zip(elastic) {
            if *size > 0.0 {
                let max = el
                    .iter()
                    .map(|d| (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt())
                    .fold(0.0, f64::max);
                peak.observe(max, t);
            }
        }
    }

    /// Constraint drift of an accepted step at `t` with velocities `u`.
    pub(crate) fn observe_drift(&mut self, t: f64, g_max: f64, g_dot_max: f64, u: &[f64]) {
        self.position_drift.observe(g_max, t);
        let scale = u.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        self.velocity_drift.observe(g_dot_max / scale, t);
    }

    /// The warnings of the run so far.
    pub(crate) fn warnings(&self, cm: &CompiledModel) -> Vec<String> {
        let mut out = Vec::new();
        for ((peak, size), b) in self.deformation.iter().zip(&self.sizes).zip(&cm.bodies) {
            if *size > 0.0 && peak.value > DEFORMATION_FRACTION * size {
                out.push(format!(
                    "body `{}`: the elastic deformation reached {:.3e} m at t = {:.6e} s, {:.0} % of the body's size {:.3e} m (above {:.0} %): a reduced body is linear in its modes, so beyond a few percent its results leave the small-deformation assumption; check the loads and units, or model the component as a chain of superelements",
                    b.name,
                    peak.value,
                    peak.t,
                    100.0 * peak.value / size,
                    size,
                    100.0 * DEFORMATION_FRACTION
                ));
            }
        }
        let p = self.position_drift;
        if p.value > POSITION_DRIFT {
            out.push(format!(
                "the position constraints were violated by up to {:.3e} (m or rad) at t = {:.6e} s (above {POSITION_DRIFT:e}): the joints did not hold; use a smaller step or tighter Newton tolerances",
                p.value, p.t
            ));
        }
        for (p, c) in self.penalty_step.iter().zip(&cm.model.contacts) {
            if p.value > PENALTY_STEP {
                out.push(format!(
                    "contact `{}`: the penalty step h sqrt(k / m_eff) reached {:.3} at t = {:.6e} s (above {PENALTY_STEP}; m_eff is the effective mass of the contact's normal direction, without the joints): Moreau's step treats the penalty force explicitly and its contact oscillation grows; use a smaller step (by the factor {:.2}), `adaptive` steps, a set-valued law (`unilateral`) or `generalized-alpha`",
                    c.name,
                    p.value,
                    p.t,
                    PENALTY_STEP / p.value
                ));
            }
        }
        let v = self.velocity_drift;
        if v.value > VELOCITY_DRIFT {
            out.push(format!(
                "the velocity constraints were violated by up to {:.3e} times max(1, max |u|) at t = {:.6e} s (above {VELOCITY_DRIFT:e}): a drive whose velocity jumps, initial velocities inconsistent with the joints, or steps too large for the motion; the positions hold, the velocities and reactions are off",
                v.value, v.t
            ));
        }
        out
    }
}

//! Regularized contacts in generalized-alpha's Newton iteration and step-size control.
//!
//! **Trust region on the slip velocity.** Regularized Coulomb friction
//! ([`crate::contact::law::regularized_friction_force`]) is linear with the steep slope
//! `mu F_N / v_reg` for slip velocities `|g_T_dot| < v_reg` and saturated (constant magnitude,
//! zero slope along the slip) above. Where sliding stops within a step, full Newton from a
//! saturated iterate extrapolates with the saturated slope, jumps across the linear zone to the
//! opposite saturated branch and back, and cycles without converging. Before an increment is
//! taken, [`slip_trust_factor`] predicts every sliding contact's slip velocity at the new
//! iterate, `g_T_dot + gamma' W_T^T du_dot` (`u_{n+1}` moves by `gamma' du_dot`), and if the
//! segment from a saturated slip velocity crosses the linear zone to a saturated one (it passes
//! within `v_reg` of zero), the whole increment is shortened to the segment's point closest to
//! zero: the next iterate lies on the linear branch, from where Newton sees the law's slope
//! and converges (exactly, for the piecewise linear law of a block). Increments that stay on one
//! side, or end within the zone, are taken in full: a step without a stick transition is not
//! changed.
//!
//! **Gap-based step restriction.** The error estimate of [`super::AdaptiveSettings`] looks at
//! accelerations, which do not change before a contact closes: a step may end deep inside a
//! penalty contact (or pass a thin one). With
//! [`AdaptiveSettings::max_penetration`](super::AdaptiveSettings::max_penetration) a
//! regularized contact that is open at the start of a step (`g_N >= 0`) may penetrate at most
//! that much at its end: [`closing_step_limit`] bounds the step from the gap and its rate at the
//! start (the linear prediction ends half the tolerance before the contact, then a short step
//! closes it half the tolerance deep: [`target_gap`]), and [`penetration_rejection`] rejects a
//! step that ends deeper anyway (a contact closing by acceleration), with the step that the
//! linear interpolation of the gap puts at its target, as the Moreau stepper's gap-based
//! refinement does ([`super::MoreauSscSettings::max_penetration`]). A body cannot pass a thin
//! contact (a ball past a ball) within one step, which the error estimate would not notice.

use super::AdaptiveSettings;
use crate::contact::regularized::regularized_contact_forces;
use crate::contact::{ContactState, ContactWork, Friction};
use crate::model::Model;
use crate::state::{SystemBuffers, Workspace};

/// The factor `alpha` in `(0, 1]` by which the Newton increment `du_dot` (accelerations, nu)
/// is shortened so that no regularized friction contact's slip velocity jumps across the linear
/// zone `|g_T_dot| < v_reg` from one saturated branch to another (module documentation).
/// `gamma_p = h gamma (1 - alpha_f) / (1 - alpha_m)` is `d u_{n+1} / d u_dot_{n+1}`. Expects
/// `sys` evaluated at the current iterate; `sys.h_plus` is used as a buffer. 1 for a model
/// without regularized friction.
pub(super) fn slip_trust_factor(
    model: &Model,
    sys: &mut SystemBuffers,
    work: &mut ContactWork,
    du_dot: &[f64],
    gamma_p: f64,
) -> f64 {
    let mut alpha = 1.0_f64;
    let all = model
        .contacts
        .iter()
        .zip(&mut work.sides)
        .zip(&work.start_gap);
    for ((c, w), &g0) in all {
        let Friction::Regularized { slip_velocity, .. } = c.law.friction else {
            continue;
        };
        let geo = c.geometry(model, &sys.frames, &sys.eval, w);
        match regularized_contact_forces(c, &geo, g0) {
            Some(f) if f[0] > 0.0 => {}
            _ => continue,
        }
        let (_, v0) = geo.gap_velocities();
        let mut dv = [0.0; 2];
        for (k, dvk) in dv
            .iter_mut()
            .enumerate()
            .take(c.law.friction.num_tangents())
        {
            sys.h_plus.fill(0.0);
            c.add_direction(model, &sys.frames, w, &geo, k + 1, 1.0, &mut sys.h_plus);
            let w_du: f64 = sys.h_plus.iter().zip(du_dot).map(|(a, b)| a * b).sum();
            *dvk = gamma_p * w_du;
        }
        if let Some(s) = linear_zone_crossing(v0, dv, slip_velocity) {
            alpha = alpha.min(s);
        }
    }
    alpha
}

/// The parameter `s` in `(0, 1)` of the point of the segment `v0 + s dv` (slip velocities)
/// closest to zero if the segment starts and ends on the saturated branch (`|v| >= v_reg`) and
/// passes through the linear zone (`|v| < v_reg`) between; `None` otherwise.
pub(super) fn linear_zone_crossing(v0: [f64; 2], dv: [f64; 2], v_reg: f64) -> Option<f64> {
    let norm = |v: [f64; 2]| (v[0] * v[0] + v[1] * v[1]).sqrt();
    let v1 = [v0[0] + dv[0], v0[1] + dv[1]];
    let dd = dv[0] * dv[0] + dv[1] * dv[1];
    if norm(v0) < v_reg || norm(v1) < v_reg || dd == 0.0 {
        return None;
    }
    let s = -(v0[0] * dv[0] + v0[1] * dv[1]) / dd;
    let closest = [v0[0] + s * dv[0], v0[1] + s * dv[1]];
    (s > 0.0 && s < 1.0 && norm(closest) < v_reg).then_some(s)
}

/// The gap a step that starts at the open gap `g0` should end at (linear prediction): well
/// open (`g0 > p`, `p` = [`AdaptiveSettings::max_penetration`]), just before the contact, `+p/2`;
/// about to close (`g0 <= p`), just inside it, `-p/2`. A contact thus closes in a step of about
/// `p / |g_N_dot|`, short enough that the penalty spring does not act in it (its iteration matrix
/// stays that of the free body, and the closing step's first-order error, `damping_factor`, is
/// negligible), instead of in a step of the free flight's size.
fn target_gap(g0: f64, p: f64) -> f64 {
    if g0 > p {
        0.5 * p
    } else {
        -0.5 * p
    }
}

/// The largest step from a state with contact states `contacts` for which no regularized
/// contact that is open (`g_N >= 0`) and closing (`g_N_dot < 0`) ends, linearly predicted,
/// beyond its [`target_gap`]: `min (g_N - target) / -g_N_dot`, at least `h_min` (infinite if
/// none closes). Set-valued contacts are not looked at.
pub(super) fn closing_step_limit(
    model: &Model,
    contacts: &[ContactState],
    ctl: &AdaptiveSettings,
) -> f64 {
    let p = ctl.max_penetration;
    let mut h = f64::INFINITY;
    for (c, st) in model.contacts.iter().zip(contacts) {
        if c.law.set_valued_normal() || !(st.gap >= 0.0 && st.gap.is_finite()) {
            continue;
        }
        if st.gap_velocity < 0.0 {
            h = h.min((st.gap - target_gap(st.gap, p)) / -st.gap_velocity);
        }
    }
    h.max(ctl.h_min)
}

/// After a converged step of size `h` (its last evaluation in `ws.sys`, the start gaps in
/// `ws.contact`): `Some(h_next)` if a regularized contact that was open at the start
/// (`g_N >= 0`) ends closed although it started more than `p` =
/// [`AdaptiveSettings::max_penetration`] away (an approach step that an acceleration towards
/// the contact carried past the linear prediction), or ends deeper than `p` (the step is to be
/// rejected), with `h_next` where the gap, linear in time over the step, reaches its
/// [`target_gap`] (at most `h / 2`, at least `h / 20`, not below `h_min`); `None` if the step
/// stands or is at `h_min`.
pub(super) fn penetration_rejection(
    model: &Model,
    ws: &mut Workspace,
    ctl: &AdaptiveSettings,
    h: f64,
) -> Option<f64> {
    if h <= ctl.h_min * (1.0 + 1e-9) {
        return None;
    }
    let (sys, work) = (&ws.sys, &mut ws.contact);
    let all = model
        .contacts
        .iter()
        .zip(&mut work.sides)
        .zip(&work.start_gap);
    let p = ctl.max_penetration;
    let mut factor = f64::INFINITY;
    for ((c, w), &g0) in all {
        if c.law.set_valued_normal() || !(g0 >= 0.0 && g0.is_finite()) {
            continue;
        }
        let g1 = c.geometry(model, &sys.frames, &sys.eval, w).gap;
        // an approach step (from well open) must not close the contact, a closing step not
        // penetrate deeper than the tolerance
        let limit = if g0 > p { 0.0 } else { -p };
        if g1 < limit {
            factor = factor.min((g0 - target_gap(g0, p)) / (g0 - g1));
        }
    }
    factor
        .is_finite()
        .then(|| (h * factor.clamp(0.05, 0.5)).max(ctl.h_min))
}

/// Shortens the Newton increment just added to `ws.step` (`u_dot_new`, `lambda_new`; the
/// increment itself in `ws.step.rhs`) by [`slip_trust_factor`]; returns the factor (1: the
/// increment stands). Expects `ws.sys` evaluated at the iterate before the increment.
pub(super) fn shorten_increment(model: &Model, ws: &mut Workspace, gamma_p: f64) -> f64 {
    let nu = model.nu;
    let b = &mut ws.step;
    let alpha = slip_trust_factor(model, &mut ws.sys, &mut ws.contact, &b.rhs[..nu], gamma_p);
    if alpha < 1.0 {
        for (x, d) in b.u_dot_new.iter_mut().zip(&b.rhs[..nu]) {
            *x -= (1.0 - alpha) * d;
        }
        for (l, d) in b.lambda_new.iter_mut().zip(&b.rhs[nu..]) {
            *l -= (1.0 - alpha) * d;
        }
    }
    alpha
}

#[cfg(test)]
mod tests {
    use super::linear_zone_crossing;

    /// Planar: from the saturated branch at +2 to -3 (v_reg 1): shortened to zero, s = 0.4; a
    /// segment that ends in the zone or stays on one side is not shortened.
    #[test]
    fn crossing_of_the_linear_zone_is_cut_at_zero_slip() {
        let s = linear_zone_crossing([2.0, 0.0], [-5.0, 0.0], 1.0).unwrap();
        assert!((s - 0.4).abs() < 1e-15, "{s}");
        assert_eq!(linear_zone_crossing([2.0, 0.0], [-1.5, 0.0], 1.0), None);
        assert_eq!(linear_zone_crossing([2.0, 0.0], [3.0, 0.0], 1.0), None);
        assert_eq!(linear_zone_crossing([0.5, 0.0], [-3.0, 0.0], 1.0), None);
        // spatial: passing zero at a distance 0.5 (inside), and at 1.5 (outside)
        let s = linear_zone_crossing([2.0, 0.5], [-4.0, 0.0], 1.0).unwrap();
        assert!((s - 0.5).abs() < 1e-15, "{s}");
        assert_eq!(linear_zone_crossing([2.0, 1.5], [-4.0, 0.0], 1.0), None);
    }
}

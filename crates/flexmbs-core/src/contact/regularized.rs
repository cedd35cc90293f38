//! Regularized (penalty) contact as generalized forces of the implicit integrators: per
//! contact with a [`NormalLaw::Regularized`] law, the contact search at the evaluated state
//! ([`Contact::geometry`]: once per evaluation, the evaluation stage), the normal force
//! `F_N = max(0, -k g_N - d g_N_dot)` for `g_N < 0` ([`law::regularized_normal_force`]) and the
//! regularized friction `F_T` ([`law::regularized_friction_force`]) applied as
//! `h += W_N F_N + W_T F_T` (seed 000 §3.1, (3.4), (3.8)), the same forces the Moreau stepper
//! adds at its midpoint. Their tangent (stiffness and damping parts, on the two contact bodies'
//! coordinates only) is [`crate::system::add_contact_tangent`].

use super::{law, Contact, ContactGeometry, ContactState, ContactWork, ContourScratch};
use super::{Friction, NormalLaw};
use crate::element::{ElementScratch, FrameKinematics};
use crate::model::Model;

/// Forces `[F_N, F_T1, F_T2]` of a regularized contact with geometry `geo` (`None` for a
/// set-valued normal law; zero when apart or without a contact point), the damping scaled by
/// [`damping_factor`] of the gap `start_gap` at the start of the step.
pub fn regularized_contact_forces(
    c: &Contact,
    geo: &ContactGeometry,
    start_gap: f64,
) -> Option<[f64; 3]> {
    let NormalLaw::Regularized { stiffness, damping } = c.law.normal else {
        return None;
    };
    let damping = damping * damping_factor(start_gap, geo.gap);
    let mut f = [0.0; 3];
    if !geo.has_contact_point() {
        return Some(f);
    }
    let (gn_dot, gt_dot) = geo.gap_velocities();
    f[0] = law::regularized_normal_force(stiffness, damping, geo.gap, gn_dot);
    if let Friction::Regularized {
        mu, slip_velocity, ..
    } = c.law.friction
    {
        let n = c.law.friction.num_tangents();
        law::regularized_friction_force(mu, slip_velocity, f[0], &gt_dot[..n], &mut f[1..1 + n]);
    }
    Some(f)
}

/// Adds `W_N F_N + W_T F_T` of contact `c` (geometry `geo`, contour buffers `work`, frames
/// `frames`; gap `start_gap` at the start of the step) to `h`; returns the forces (`None`:
/// set-valued law, nothing added).
pub fn add_regularized_contact_force(
    model: &Model,
    c: &Contact,
    frames: &[FrameKinematics],
    work: &[ContourScratch; 2],
    geo: &ContactGeometry,
    start_gap: f64,
    h: &mut [f64],
) -> Option<[f64; 3]> {
    let f = regularized_contact_forces(c, geo, start_gap)?;
    if f[0] != 0.0 {
        for (k, fk) in f.iter().enumerate() {
            if *fk != 0.0 {
                c.add_direction(model, frames, work, geo, k, *fk, h);
            }
        }
    }
    Some(f)
}

/// Adds the generalized forces of every regularized contact of `model` at the evaluated state
/// (`frames`, `eval`: [`crate::system::evaluate`]) to `h`. Set-valued contacts add nothing.
/// Returns the force scale of the contacts, the largest `|F_N| + |F_T|` (the size of the terms
/// a resting contact's force balances: Newton's residual scale).
pub fn add_regularized_forces(
    model: &Model,
    frames: &[FrameKinematics],
    eval: &[ElementScratch],
    work: &mut ContactWork,
    h: &mut [f64],
) -> f64 {
    let mut scale = 0.0_f64;
    let all = model
        .contacts
        .iter()
        .zip(&mut work.sides)
        .zip(&work.start_gap);
    for ((c, w), &g0) in all {
        if c.law.set_valued_normal() {
            continue;
        }
        let geo = c.geometry(model, frames, eval, w);
        if let Some(f) = add_regularized_contact_force(model, c, frames, w, &geo, g0, h) {
            let ft = (f[1] * f[1] + f[2] * f[2]).sqrt();
            scale = scale.max(f[0].abs() + ft);
        }
    }
    scale
}

/// The contact states of the regularized contacts at the evaluated state (`frames`, `eval`)
/// after a step of size `h`: gap, gap rate, activity (a positive normal force), impulses
/// `F h` (normal, tangents), forces `F`, contour coordinates and geometry. Set-valued contacts are left alone.
pub fn update_regularized_states(
    model: &Model,
    frames: &[FrameKinematics],
    eval: &[ElementScratch],
    work: &mut ContactWork,
    h: f64,
    states: &mut [ContactState],
) {
    let all = model
        .contacts
        .iter()
        .zip(&mut work.sides)
        .zip(&work.start_gap);
    for (((c, w), &g0), st) in all.zip(states) {
        if c.law.set_valued_normal() {
            continue;
        }
        let geo = c.geometry(model, frames, eval, w);
        let f = regularized_contact_forces(c, &geo, g0).unwrap_or_default();
        *st = ContactState {
            active: f[0] > 0.0,
            gap: geo.gap,
            gap_velocity: if geo.has_contact_point() {
                geo.gap_velocities().0
            } else {
                0.0
            },
            impulse: [f[0] * h, f[1] * h, f[2] * h],
            coordinates: geo.coordinates,
            force: f,
            penalty_step: 0.0,
            geometry: Some(geo),
        };
    }
}

/// The first contact of `model` with a set-valued law (unilateral, bilateral or Coulomb
/// friction), which only the Moreau stepper solves: its index and name.
pub fn first_set_valued(model: &Model) -> Option<(usize, &str)> {
    model
        .contacts
        .iter()
        .position(|c| {
            c.law.set_valued_normal() || matches!(c.law.friction, Friction::Coulomb { .. })
        })
        .map(|i| (i, model.contacts[i].name.as_str()))
}

/// The share of a regularized law's damping in a step from gap `g0` to gap `g` (implicit
/// integrators): 1 if the contact penetrated at the start (`g0 < 0`), else the fraction of the
/// step spent penetrating, linear in the gap, `-g / (g0 - g)` for `g < 0` (0 apart). The
/// spring-damper's force jumps by `d |g_N_dot|` where a contact closes; with that jump inside a
/// step the step's equations may have no solution (Newton cycles across it), with the damping
/// faded in by the penetrated fraction they are continuous, and the closing step still gets
/// the damping impulse of its penetrating part to first order.
pub fn damping_factor(g0: f64, g: f64) -> f64 {
    if g0 < 0.0 {
        1.0
    } else if g < 0.0 {
        -g / (g0 - g)
    } else {
        0.0
    }
}

/// Sets the start gaps of every contact ([`ContactWork::start_gap`]) for the next step of an
/// implicit integrator from the contact states at its start (an open contact without a contact
/// point: `+inf`, no damping until it penetrates at a step start).
pub fn gaps_at_start(states: &[ContactState], work: &mut ContactWork) {
    for (st, g0) in states.iter().zip(&mut work.start_gap) {
        *g0 = st.gap;
    }
}

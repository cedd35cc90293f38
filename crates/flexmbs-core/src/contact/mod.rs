//! Contact between contours (seed 000 ch. 3): contour geometry ([`contour`]), pair kinematics
//! through a dispatch table ([`pair`]) and force laws ([`law`]), each separate.
//!
//! A [`Contact`] joins two [`Contour`]s (each attached to a frame) under a [`ContactLaw`]; it is
//! added with [`crate::ModelSpec::add_contact`] and checked when the model compiles (supported
//! pair, valid parameters, not both contours on one owner). Set-valued laws are solved on
//! velocity level by the Moreau time-stepper ([`crate::integrator::MoreauStepper`]), which also
//! applies regularized laws as forces. What evolves per contact (activity, gap, impulses, contour
//! coordinates for warm starts) is a [`ContactState`] in [`crate::State::contacts`].

pub mod contour;
pub mod law;
pub mod pair;

pub use contour::{CircleContour, Contour, ContourKind, PlaneContour, PointContour, SphereContour};
pub use law::{ContactLaw, Friction, NormalLaw, TangentDirections};
pub use pair::{ContactGeometry, PairFn};

use crate::element::FrameKinematics;
use crate::error::ModelError;
use crate::ids::FrameId;
use crate::joint::ConstraintRow;
use crate::model::{Frame, FrameOwner, Model};

/// A contact: contour `a`, contour `b`, and the law between them.
#[derive(Debug)]
pub struct Contact {
    /// Name (messages and output).
    pub name: String,
    /// First contour (after compiling: the one whose normal defines the contact frame).
    pub contour_a: Box<dyn Contour>,
    /// Second contour.
    pub contour_b: Box<dyn Contour>,
    /// Force law.
    pub law: ContactLaw,
}

impl Contact {
    /// A contact between `a` and `b` under `law` (in either order of the pair: the model
    /// swaps them into the dispatch table's order when it compiles).
    pub fn new(
        name: &str,
        a: impl Contour + 'static,
        b: impl Contour + 'static,
        law: ContactLaw,
    ) -> Self {
        Self {
            name: name.to_string(),
            contour_a: Box::new(a),
            contour_b: Box::new(b),
            law,
        }
    }

    /// The frames of contour `a` and `b`.
    pub fn frames(&self) -> (FrameId, FrameId) {
        (self.contour_a.frame(), self.contour_b.frame())
    }

    /// The pair function (supported pairs only: checked at compile time).
    fn pair(&self) -> PairFn {
        pair::pair_function(self.contour_a.kind(), self.contour_b.kind())
            .expect("contact pair checked when the model was compiled")
    }

    /// Contact kinematics from the frames' kinematics `frames` (all frames of the model).
    pub fn geometry(&self, frames: &[FrameKinematics]) -> ContactGeometry {
        let (fa, fb) = self.frames();
        (self.pair())(
            self.contour_a.as_ref(),
            self.contour_b.as_ref(),
            &frames[fa.0],
            &frames[fb.0],
        )
    }
}

/// What evolves per contact, kept with the state ([`crate::State::contacts`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactState {
    /// The contact was closed (in the velocity-level problem) in the last step.
    pub active: bool,
    /// Normal gap `g_N` at the last evaluation (the step's midpoint for the Moreau stepper).
    pub gap: f64,
    /// Normal gap rate `g_N_dot` at the end of the last step.
    pub gap_velocity: f64,
    /// Impulses of the last step: normal, tangent 1, tangent 2 (for regularized laws the force
    /// times the step).
    pub impulse: [f64; 3],
    /// Contour coordinates `(eta, xi)` of contour `a` and `b` (warm start of a contact search on
    /// flexible contours; unused by rigid contours).
    pub coordinates: [f64; 4],
}

/// Checks the contacts against the frames and puts each pair into the dispatch table's order.
pub(crate) fn check_contacts(frames: &[Frame], contacts: &mut [Contact]) -> Result<(), ModelError> {
    for c in contacts.iter_mut() {
        let invalid = |reason: String| ModelError::InvalidContact {
            contact: c.name.clone(),
            reason,
        };
        let (ka, kb) = (c.contour_a.kind(), c.contour_b.kind());
        let swap = pair::canonical_order(ka, kb).ok_or_else(|| {
            invalid(format!(
                "no contact kinematics for a {ka:?} and a {kb:?} contour"
            ))
        })?;
        for contour in [&c.contour_a, &c.contour_b] {
            contour
                .validate()
                .map_err(|r| invalid(format!("{:?} contour: {r}", contour.kind())))?;
        }
        let owner = |f: FrameId| {
            frames
                .get(f.0)
                .map(|fr| fr.owner)
                .ok_or_else(|| invalid(format!("unknown frame {f}")))
        };
        let (oa, ob) = (owner(c.contour_a.frame())?, owner(c.contour_b.frame())?);
        if oa == ob {
            let what = if oa == FrameOwner::Ground {
                "both contours are on the ground"
            } else {
                "both contours are on the same owner"
            };
            return Err(invalid(what.into()));
        }
        c.law
            .validate()
            .map_err(|(name, value, reason)| invalid(format!("{name} = {value}: {reason}")))?;
        if swap {
            std::mem::swap(&mut c.contour_a, &mut c.contour_b);
        }
    }
    Ok(())
}

/// Adds `scale` times the row's generalized direction `t_a^T J_T^a + r_a^T J_R^a + t_b^T J_T^b
/// + r_b^T J_R^b` to `out` (length nu): a column of `W`, or a generalized force `W F`.
pub fn add_row_direction(
    model: &Model,
    (fa, fb): (FrameId, FrameId),
    row: &ConstraintRow,
    frames: &[FrameKinematics],
    scale: f64,
    out: &mut [f64],
) {
    for (f, t, r) in [(fa, &row.t_a, &row.r_a), (fb, &row.t_b, &row.r_b)] {
        let k = &frames[f.0];
        let cols = model.frame_cols(f);
        for j in 0..cols.len() {
            let (jt, jr) = (k.jac_t.col_as_slice(j), k.jac_r.col_as_slice(j));
            let mut s = 0.0;
            for d in 0..3 {
                s += t[d] * jt[d] + r[d] * jr[d];
            }
            out[cols.global(j)] += scale * s;
        }
    }
}

/// Potential energy `sum 1/2 k g_N^2` of the penetrating regularized contacts, from the frames'
/// kinematics (the penalty energy of a run's energy balance).
pub fn regularized_energy(model: &Model, frames: &[FrameKinematics]) -> f64 {
    model
        .contacts
        .iter()
        .map(|c| match c.law.normal {
            NormalLaw::Regularized { stiffness, .. } => {
                law::regularized_energy(stiffness, c.geometry(frames).gap)
            }
            _ => 0.0,
        })
        .sum()
}

#[cfg(test)]
mod tests;

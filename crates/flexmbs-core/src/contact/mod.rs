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
pub mod drawing;
pub mod flexible;
pub mod guide;
pub mod law;
pub mod pair;
pub mod regularized;

pub use contour::{
    CircleContour, Contour, ContourKind, ContourScratch, PlaneContour, PointContour, SphereContour,
};
pub use flexible::{FlexibleBand, NeutralCurve, NeutralSurface};
pub use guide::CurveGuide;
pub use law::{ContactLaw, Friction, NormalLaw, TangentDirections};
pub use pair::{ContactGeometry, PairFn, Side};

use crate::element::{ElementScratch, FrameKinematics};
use crate::error::ModelError;
use crate::ids::FrameId;
use crate::model::{Frame, FrameOwner, Model};
use nalgebra::Vector3;

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

    /// Contact kinematics at the evaluated state: `frames` (all frames of the model) and `eval`
    /// (the bodies' evaluated states, [`crate::system::evaluate`]); `work` are this contact's
    /// contour buffers ([`ContactWork`]). Fills the contact-point velocities of rigid contours
    /// from their frames.
    pub fn geometry(
        &self,
        model: &Model,
        frames: &[FrameKinematics],
        eval: &[ElementScratch],
        work: &mut [ContourScratch; 2],
    ) -> ContactGeometry {
        let (fa, fb) = self.frames();
        let owner_state = |f: FrameId| match model.frames[f.0].owner {
            FrameOwner::Body(b) => eval.get(b.0),
            _ => None,
        };
        let [wa, wb] = work;
        let a = Side {
            contour: self.contour_a.as_ref(),
            frame: &frames[fa.0],
            body: owner_state(fa),
            scratch: wa,
        };
        let b = Side {
            contour: self.contour_b.as_ref(),
            frame: &frames[fb.0],
            body: owner_state(fb),
            scratch: wb,
        };
        let mut g = (self.pair())(a, b);
        if !self.contour_a.is_flexible() {
            g.velocity_a = pair::frame_point_velocity(&frames[fa.0], &g.point_a);
        }
        if !self.contour_b.is_flexible() {
            g.velocity_b = pair::frame_point_velocity(&frames[fb.0], &g.point_b);
        }
        g
    }

    /// Adds `scale` times the generalized direction of contact direction `k` (0 normal, 1 and
    /// 2 tangents) of `geo` to `out` (length nu): `d^T J_Cb - d^T J_Ca`, a column of `W`, or
    /// with a force as `scale` the generalized force `W F`.
    #[allow(clippy::too_many_arguments)]
    pub fn add_direction(
        &self,
        model: &Model,
        frames: &[FrameKinematics],
        work: &[ContourScratch; 2],
        geo: &ContactGeometry,
        k: usize,
        scale: f64,
        out: &mut [f64],
    ) {
        let d = geo.direction(k);
        let (fa, fb) = self.frames();
        self.contour_a.add_direction(
            model,
            &frames[fa.0],
            &work[0],
            &geo.point_a,
            &-d,
            scale,
            out,
        );
        self.contour_b
            .add_direction(model, &frames[fb.0], &work[1], &geo.point_b, &d, scale, out);
    }
}

/// Evaluation buffers of every contact's two contours (one per contact side, created once per
/// model: the workspace holds one, output recorders their own).
#[derive(Debug)]
pub struct ContactWork {
    /// Per contact: the buffers of contour `a` and `b`.
    pub sides: Vec<[ContourScratch; 2]>,
    /// Per contact: the gap at the start of the step, which scales a regularized law's damping
    /// in a step that closes the contact ([`regularized::damping_factor`]; default `-inf`: full
    /// damping). Generalized-alpha sets it per step ([`regularized::gaps_at_start`]).
    pub start_gap: Vec<f64>,
}

impl ContactWork {
    /// Buffers for every contact of `model` (allocates).
    pub fn new(model: &Model) -> Self {
        Self {
            sides: model
                .contacts
                .iter()
                .map(|c| [c.contour_a.new_scratch(), c.contour_b.new_scratch()])
                .collect(),
            start_gap: vec![f64::NEG_INFINITY; model.contacts.len()],
        }
    }
}

/// A unit vector along `v`, or zero for a zero `v`.
pub(crate) fn unit_or_zero(v: Vector3<f64>) -> Vector3<f64> {
    let n = v.norm();
    if n > 0.0 {
        v / n
    } else {
        v
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
    /// Forces of the last step in the contact frame: normal, tangent 1, tangent 2 (N; `F_N > 0`
    /// pushes `b` along the normal). Regularized laws: the law's forces at the evaluation of
    /// [`Self::gap`]; set-valued laws (Moreau): the impulses over the step, `impulse / h`.
    pub force: [f64; 3],
    /// Moreau time-stepping with a regularized normal law: `h sqrt(k / m_eff)` at the step that
    /// closed the contact (kept while it stays closed, 0 before), with `m_eff = 1 / (wᵀ M⁻¹ w)`
    /// the effective mass of the contact's normal direction `w` over the unconstrained mass
    /// matrix. Moreau's step is explicit in the penalty force: above 2 the penalty oscillation
    /// grows. Joints that stiffen the contact make the true ratio smaller (this is its upper
    /// bound).
    pub penalty_step: f64,
    /// The contact geometry at the evaluation of [`Self::gap`] (contact points, contact frame,
    /// contour coordinates; the step's midpoint for the Moreau stepper, the step's end for the
    /// implicit integrators); `None` before the first evaluation.
    pub geometry: Option<ContactGeometry>,
}

/// Checks the contacts against the frames and puts each pair into the dispatch table's order.
pub(crate) fn check_contacts(
    frames: &[Frame],
    owner_state: &dyn Fn(usize) -> Option<ElementScratch>,
    contacts: &mut [Contact],
) -> Result<(), ModelError> {
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
        for (contour, o) in [(&c.contour_a, oa), (&c.contour_b, ob)] {
            if !contour.is_flexible() {
                continue;
            }
            let what = format!("{:?} contour", contour.kind());
            let frame = &frames[contour.frame().0];
            let at_origin = frame.local.mesh_node.is_none()
                && frame.local.position == Vector3::zeros()
                && frame.local.rotation == nalgebra::Matrix3::identity();
            let state = match o {
                FrameOwner::Body(b) if at_origin => owner_state(b.0),
                _ => None,
            };
            let state = state.ok_or_else(|| {
                invalid(format!(
                    "{what}: its frame '{}' must be the reference frame of the body the contour \
                     belongs to (at the body origin, body axes)",
                    frame.name
                ))
            })?;
            contour
                .check_owner(&state)
                .map_err(|r| invalid(format!("{what}: {r}")))?;
        }
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

/// Potential energy `sum 1/2 k g_N^2` of the penetrating regularized contacts at the evaluated
/// state (`frames`, `eval`; the penalty energy of a run's energy balance).
pub fn regularized_energy(
    model: &Model,
    frames: &[FrameKinematics],
    eval: &[ElementScratch],
    work: &mut ContactWork,
) -> f64 {
    model
        .contacts
        .iter()
        .zip(&mut work.sides)
        .map(|(c, w)| match c.law.normal {
            NormalLaw::Regularized { stiffness, .. } => {
                law::regularized_energy(stiffness, c.geometry(model, frames, eval, w).gap)
            }
            _ => 0.0,
        })
        .sum()
}

#[cfg(test)]
mod tests;

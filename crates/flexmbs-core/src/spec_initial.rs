//! The initial state as part of the model description: body poses and velocities, and springs
//! that are unstressed in it, resolved once by [`ModelSpec::compile`] so that the compiled
//! [`Model`] is never changed afterwards.

use crate::error::ModelError;
use crate::ids::{BodyId, LoadId};
use crate::load::Load;
use crate::model::{Model, ModelSpec};
use nalgebra::{Matrix3, Vector3};

/// What [`ModelSpec`] records about the initial state.
#[derive(Debug, Default)]
pub(crate) struct InitialSpec {
    /// Pose (global position, rotation) of a body's reference frame.
    poses: Vec<(BodyId, Vector3<f64>, Matrix3<f64>)>,
    /// Velocity and angular velocity (global) of a body's reference frame.
    velocities: Vec<(BodyId, Vector3<f64>, Vector3<f64>)>,
    /// Spring-dampers whose free length is their length in the initial state.
    unstressed: Vec<LoadId>,
    /// Elastic (modal) coordinates and their rates of a body's `Vector` node.
    elastic: Vec<(BodyId, Vec<f64>, Vec<f64>)>,
}

impl ModelSpec {
    /// Places `body` in the initial state: its reference frame at `position` with `rotation`
    /// (global). Applied in the order given, after the reference configuration.
    pub fn set_initial_pose(
        &mut self,
        body: BodyId,
        position: Vector3<f64>,
        rotation: Matrix3<f64>,
    ) {
        self.initial.poses.push((body, position, rotation));
    }

    /// Initial velocity and angular velocity (global) of `body`'s reference frame (after all
    /// poses).
    pub fn set_initial_velocity(
        &mut self,
        body: BodyId,
        velocity: Vector3<f64>,
        omega: Vector3<f64>,
    ) {
        self.initial.velocities.push((body, velocity, omega));
    }

    /// Initial elastic coordinates `q` and their rates `u` of `body`: the coordinates of its
    /// element's `Vector` node (the modal coordinates of an FFR body, the internal modes of a
    /// superelement). `u` may be empty (at rest). Checked by [`ModelSpec::compile`]: the body must
    /// have exactly one `Vector` node, of the length of `q`.
    pub fn set_initial_elastic(&mut self, body: BodyId, q: Vec<f64>, u: Vec<f64>) {
        self.initial.elastic.push((body, q, u));
    }

    /// The spring-damper `load` is unstressed in the initial state: [`ModelSpec::compile`] sets its
    /// free length to the distance of its frames there (its given free length is ignored).
    pub fn set_spring_unstressed_initially(&mut self, load: LoadId) {
        self.initial.unstressed.push(load);
    }
}

impl InitialSpec {
    /// Writes the initial state into `model` and the free lengths of the unstressed springs.
    pub(crate) fn resolve(self, model: &mut Model) -> Result<(), ModelError> {
        let mut s = model.reference_state();
        let n_bodies = model.bodies.len();
        let check = |b: BodyId, what: &str| {
            if b.0 < n_bodies {
                Ok(())
            } else {
                Err(ModelError::UnknownBody {
                    frame: format!("initial {what}"),
                    body: b,
                })
            }
        };
        for (b, p, r) in self.poses {
            check(b, "pose")?;
            model.set_body_pose(&mut s, b, p, r);
        }
        for (b, q, u) in self.elastic {
            check(b, "elastic coordinates")?;
            model.set_body_elastic(&mut s, b, &q, &u)?;
        }
        for (b, v, w) in self.velocities {
            check(b, "velocity")?;
            model.set_body_velocity(&mut s, b, v, w);
        }
        for id in self.unstressed {
            let (a, b) = match model.loads.get(id.0) {
                Some(Load::SpringDamper {
                    frame_a, frame_b, ..
                }) => (*frame_a, *frame_b),
                _ => {
                    return Err(ModelError::InvalidParameter {
                        name: "unstressed spring",
                        value: id.0 as f64,
                        reason: "not a spring-damper load of this model",
                    })
                }
            };
            let position = |f| model.frame_kinematics(&s, f).map(|k| k.position);
            // a state the elements cannot evaluate: NaN, left for the solvers' initial checks
            let length = match (position(a), position(b)) {
                (Some(pa), Some(pb)) => (pb - pa).norm(),
                _ => f64::NAN,
            };
            if let Some(Load::SpringDamper { free_length, .. }) = model.loads.get_mut(id.0) {
                *free_length = length;
            }
        }
        model.initial = s;
        Ok(())
    }
}

impl Model {
    /// Sets the elastic coordinates `q` and rates `u` (empty: unchanged) of `body` in `state`:
    /// the coordinates of its element's single `Vector` node ([`ModelSpec::set_initial_elastic`]).
    pub fn set_body_elastic(
        &self,
        state: &mut crate::State,
        body: BodyId,
        q: &[f64],
        u: &[f64],
    ) -> Result<(), ModelError> {
        let b = &self.bodies[body.0];
        let err = |reason: String| ModelError::InitialElastic {
            body: b.name.clone(),
            reason,
        };
        let kinds = b.element.node_kinds();
        let vectors: Vec<usize> = (0..kinds.len())
            .filter(|&i| matches!(kinds[i], crate::NodeKind::Vector(_)))
            .collect();
        let [k] = vectors[..] else {
            return Err(err(format!(
                "the body has {} vector (elastic) nodes, expected one",
                vectors.len()
            )));
        };
        let crate::NodeKind::Vector(n) = kinds[k] else {
            unreachable!("filtered above")
        };
        if q.len() != n || !(u.is_empty() || u.len() == n) {
            return Err(err(format!(
                "{} coordinates and {} rates given, the body has {n}",
                q.len(),
                u.len()
            )));
        }
        if let Some(x) = q.iter().chain(u).find(|x| !x.is_finite()) {
            return Err(err(format!("value {x} is not finite")));
        }
        let q0: usize = kinds[..k].iter().map(|k| k.nq()).sum();
        let u0: usize = kinds[..k].iter().map(|k| k.nu()).sum();
        let dofs = self.body_dofs(body);
        for (i, x) in q.iter().enumerate() {
            state.q[dofs.q.global(q0 + i)] = *x;
        }
        for (i, x) in u.iter().enumerate() {
            state.u[dofs.u.global(u0 + i)] = *x;
        }
        Ok(())
    }
}

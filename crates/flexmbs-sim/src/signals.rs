//! Output signals (frame kinematics, node deformation, joint reactions), the names of the
//! coordinates and multipliers, and the plottable series names of a run.

use crate::compile::{BodyInfo, Ctx, DOFS};
use crate::error::SimError;
use crate::schema::RotationName;
use flexmbs_core::model::FrameOwner;
use flexmbs_core::{FrameId, FrameKinematics, Load, Model};
use nalgebra::Vector3;
use std::collections::HashMap;

/// What a signal measures.
#[derive(Debug, Clone, PartialEq)]
pub enum SignalKind {
    /// Global position of a frame origin (m).
    Position(FrameId),
    /// Global velocity of a frame origin (m/s).
    Velocity(FrameId),
    /// Global angular velocity of a frame (rad/s).
    AngularVelocity(FrameId),
    /// Cardan angles x-y-z of a frame's global orientation (rad).
    Orientation(FrameId),
    /// Global acceleration of a frame origin (m/s^2; written by
    /// [`crate::motion_signals::fill_motion_signals`], left NaN by [`evaluate_signals`]).
    Acceleration(FrameId),
    /// Global angular acceleration of a frame (rad/s^2; written like
    /// [`SignalKind::Acceleration`]).
    AngularAcceleration(FrameId),
    /// Relative coordinates of a joint (this joint index), [`crate::motion_signals`] (written
    /// like [`SignalKind::Acceleration`]).
    JointCoordinates(usize),
    /// Rates of the relative coordinates of a joint (written like [`SignalKind::Acceleration`]).
    JointRates(usize),
    /// Elastic displacement of a node frame in the axes of its body's reference frame:
    /// `A^T (r_node - R) - u0` (m).
    Deformation {
        /// The node frame.
        frame: FrameId,
        /// The body's reference frame.
        body_frame: FrameId,
        /// Undeformed node position `u0` (body coordinates).
        reference: Vector3<f64>,
    },
    /// Lagrange multipliers of a joint (for locked translations: minus the force on frame `b`
    /// along the axes of frame `a`, N).
    Reaction {
        /// First row in `lambda`.
        row: usize,
        /// Number of rows.
        rows: usize,
    },
    /// Force the joint exerts on its frame `b`, in the axes of its frame `a` (N);
    /// [`flexmbs_core::joint::joint_reaction`].
    JointForce(usize),
    /// Torque the joint exerts on its frame `b` about the origin of `b`, in the axes of frame
    /// `a` (N m); a prescribed motion contributes the drive torque.
    JointTorque(usize),
    /// The output of a force element (`Load::Element` at this load index): a servo's drive
    /// torque or force, a joint spring's or friction's torque or force (on frame `b`).
    ForceOutput(usize),
    /// Normal gap of a contact (m) at the last step's midpoint (moreau solver).
    ContactGap(usize),
    /// Impulses of a contact in the last step, normal and two tangents (N s; regularized laws:
    /// force times step).
    ContactImpulse(usize),
    /// Forces of a contact in the last step in the contact frame, normal and two tangents (N;
    /// set-valued laws: impulse over the step; [`flexmbs_core::contact::ContactState::force`]).
    ContactForce(usize),
    /// Contact point (global, m) on the contour `side` (0: the engine's `a`, 1: `b`) at the
    /// evaluation of the gap; NaN without a contact point.
    ContactPoint {
        /// The contact.
        contact: usize,
        /// The engine's side.
        side: usize,
    },
    /// Unit normal of the contact frame (global): outward of the engine's contour `a`, towards
    /// `b`; NaN without a contact point.
    ContactNormal(usize),
    /// Contour coordinates `(eta, xi)` of the contact point on the flexible contour on the
    /// engine's side `side`; NaN without a contact point (`xi` NaN on a curve).
    ContactCoordinates {
        /// The contact.
        contact: usize,
        /// The engine's side of the flexible contour.
        side: usize,
        /// Whether the contour has a second coordinate (surface: `xi`, band: across the band).
        two: bool,
    },
    /// Stress at an FE node of an ffr body (Pa): equivalent (von Mises) stress and the node's six
    /// stress values, recovered linearly from the modal stress fields ([`crate::stress`];
    /// written by [`crate::stress::fill_stress_signals`], left NaN by [`evaluate_signals`]).
    Stress {
        /// The body.
        body: flexmbs_core::BodyId,
        /// Node index in the body.
        node: usize,
        /// The body's modal stress fields (SI).
        fields: std::sync::Arc<flexmbs_fe::stress::ModalStress>,
    },
    /// Local coordinates `q_loc` of a superelement (interface displacements and rotation vectors
    /// in its floating frame, internal-mode amplitudes; written by
    /// `superelement_output::fill_superelement_signals`, left NaN by [`evaluate_signals`]).
    SuperelementDeformation(flexmbs_core::BodyId),
    /// Newton iterations of a superelement's floating-frame recovery (written like
    /// [`SignalKind::SuperelementDeformation`]).
    FrameIterations(flexmbs_core::BodyId),
}

/// A requested output signal.
#[derive(Debug, Clone, PartialEq)]
pub struct Signal {
    /// Name as requested, e.g. `tip.position`.
    pub name: String,
    /// Unit of all components.
    pub unit: String,
    /// Component names.
    pub components: Vec<String>,
    /// What it measures.
    pub kind: SignalKind,
}

const XYZ: [&str; 3] = ["x", "y", "z"];

/// Parses `output.signals`: `<frame>.position|velocity|angular_velocity|orientation|deformation|stress`
/// and `acceleration|angular_acceleration` (every body has a frame named like the body),
/// `<joint>.force|torque|reaction|coordinates|rates`,
/// `<contact>.gap|impulse|force|point_a|point_b|normal|coordinates` (`swapped`: per contact,
/// whether the engine's `a` is the file's `b`, [`crate::contacts`]) and `<force>.output`.
pub fn parse_signals(
    ctx: &Ctx,
    list: &[String],
    model: &Model,
    frames: &HashMap<String, FrameId>,
    bodies: &[BodyInfo],
    joints: &[(String, usize)],
    swapped: &[bool],
) -> Result<Vec<Signal>, SimError> {
    let mut out: Vec<Signal> = Vec::new();
    for (k, s) in list.iter().enumerate() {
        let path = format!("output.signals[{k}]");
        let err = |m: String| ctx.err(&path, m);
        let Some((item, what)) = s.rsplit_once('.') else {
            return Err(err(format!(
                "`{s}`: expected `<frame>.<quantity>` or `<joint>.force|torque|reaction`"
            )));
        };
        if out.iter().any(|o| o.name == *s) {
            return Err(err(format!("signal `{s}` listed twice")));
        }
        let xyz = || XYZ.iter().map(|c| c.to_string()).collect::<Vec<_>>();
        let joint_index = |item: &str| {
            joints.iter().position(|(n, _)| n == item).ok_or_else(|| {
                let names: Vec<&str> = joints.iter().map(|(n, _)| n.as_str()).collect();
                err(format!(
                    "unknown joint `{item}` (joints: {})",
                    names.join(", ")
                ))
            })
        };
        let contact = model.contacts.iter().position(|c| c.name == item);
        let force = model
            .loads
            .iter()
            .position(|l| matches!(l, Load::Element(e) if e.name() == item));
        let (unit, components, kind) = if let Some(l) = force {
            let Load::Element(e) = &model.loads[l] else {
                unreachable!("found as an element")
            };
            if what != "output" || e.output_unit().is_empty() {
                return Err(err(format!(
                    "unknown quantity `{what}` of force `{item}`{}",
                    if e.output_unit().is_empty() {
                        " (it has no output)"
                    } else {
                        " (output)"
                    }
                )));
            }
            (
                e.output_unit().to_string(),
                vec!["value".to_string()],
                SignalKind::ForceOutput(l),
            )
        } else if let Some(c) = contact {
            match what {
                "gap" => (
                    "m".to_string(),
                    vec!["n".to_string()],
                    SignalKind::ContactGap(c),
                ),
                "impulse" => (
                    "N s".to_string(),
                    ["n", "t1", "t2"].iter().map(|c| c.to_string()).collect(),
                    SignalKind::ContactImpulse(c),
                ),
                "force" => (
                    "N".to_string(),
                    ["n", "t1", "t2"].iter().map(|c| c.to_string()).collect(),
                    SignalKind::ContactForce(c),
                ),
                "point_a" | "point_b" => {
                    // the file's a or b: the engine's other side if it swapped the pair
                    let file_side = usize::from(what == "point_b");
                    let side = file_side ^ usize::from(swapped.get(c).copied().unwrap_or(false));
                    (
                        "m".to_string(),
                        xyz(),
                        SignalKind::ContactPoint { contact: c, side },
                    )
                }
                "normal" => ("1".to_string(), xyz(), SignalKind::ContactNormal(c)),
                "coordinates" => {
                    let k = &model.contacts[c];
                    let Some(side) = [&k.contour_a, &k.contour_b]
                        .iter()
                        .position(|x| x.is_flexible())
                    else {
                        return Err(err(format!(
                            "contact `{item}` has no flexible contour (surface, curve, band): \
                             no contour coordinates"
                        )));
                    };
                    let kind = [&k.contour_a, &k.contour_b][side].kind();
                    use flexmbs_core::contact::ContourKind;
                    let two = kind != ContourKind::NeutralCurve;
                    // a band's second coordinate is a distance across it
                    let unit = if kind == ContourKind::FlexibleBand {
                        "1 | m"
                    } else {
                        "1"
                    };
                    (
                        unit.to_string(),
                        vec!["eta".to_string(), "xi".to_string()],
                        SignalKind::ContactCoordinates {
                            contact: c,
                            side,
                            two,
                        },
                    )
                }
                _ => {
                    return Err(err(format!(
                        "unknown quantity `{what}` of contact `{item}` (gap, impulse, force, \
                         point_a, point_b, normal, coordinates)"
                    )))
                }
            }
        } else if what == "coordinates" || what == "rates" {
            let j = joint_index(item)?;
            crate::motion_signals::joint_signal(model, j, what)
                .ok_or_else(|| err(format!("unknown quantity `{what}` of joint `{item}`")))?
        } else if what == "force" || what == "torque" {
            let j = joint_index(item)?;
            if what == "force" {
                ("N".to_string(), xyz(), SignalKind::JointForce(j))
            } else {
                ("N m".to_string(), xyz(), SignalKind::JointTorque(j))
            }
        } else if what == "reaction" && model.guides.iter().any(|g| g.name == *item) {
            // a bilateral contact on a curve: its constraint rows (`crate::guides`)
            let g = model
                .guides
                .iter()
                .position(|g| g.name == *item)
                .unwrap_or(0);
            let guide = &model.guides[g];
            (
                "N | N m".to_string(),
                guide.row_names().iter().map(|n| n.to_string()).collect(),
                SignalKind::Reaction {
                    row: model.guide_rows[g],
                    rows: guide.num_rows(),
                },
            )
        } else if what == "reaction" {
            let Some(j) = joints.iter().position(|(n, _)| n == item) else {
                let names: Vec<&str> = joints.iter().map(|(n, _)| n.as_str()).collect();
                return Err(err(format!(
                    "unknown joint `{item}` (joints: {})",
                    names.join(", ")
                )));
            };
            let joint = &model.joints[j];
            let mut comps: Vec<String> = (0..6)
                .filter(|&d| joint.locked[d])
                .map(|d| DOFS[d].to_string())
                .collect();
            if joint.prescribed.is_some() {
                comps.push("motion".into());
            }
            (
                "N | N m".to_string(),
                comps,
                SignalKind::Reaction {
                    row: model.joint_rows[j],
                    rows: joints[j].1,
                },
            )
        } else {
            let Some(&f) = frames.get(item) else {
                let mut names: Vec<&str> = frames.keys().map(|s| s.as_str()).collect();
                names.sort();
                return Err(err(format!(
                    "unknown frame `{item}` (frames: {})",
                    names.join(", ")
                )));
            };
            if let Some(sig) = crate::superelement_output::segment_signal(model, bodies, f, what) {
                sig
            } else if let Some(sig) = crate::motion_signals::frame_signal(what, f) {
                sig
            } else {
                match what {
                "position" => ("m".into(), xyz(), SignalKind::Position(f)),
                "velocity" => ("m/s".into(), xyz(), SignalKind::Velocity(f)),
                "angular_velocity" => ("rad/s".into(), xyz(), SignalKind::AngularVelocity(f)),
                "orientation" => ("rad".into(), xyz(), SignalKind::Orientation(f)),
                "stress" => crate::stress::stress_signal(model, bodies, item, f).map_err(err)?,
                "deformation" => {
                    let fr = &model.frames[f.0];
                    let (Some(_), FrameOwner::Body(b)) = (fr.local.mesh_node, fr.owner) else {
                        return Err(err(format!("`{item}` is not a node frame of an ffr body: `deformation` needs `node` or `nearest`")));
                    };
                    let body_frame = bodies.iter().find(|x| x.id == b).map(|x| x.frame).ok_or_else(|| err("internal: body without frame".into()))?;
                    ("m".into(), xyz(), SignalKind::Deformation { frame: f, body_frame, reference: fr.local.position })
                }
                _ => return Err(err(format!("unknown quantity `{what}` (frames: position, velocity, angular_velocity, orientation, acceleration, angular_acceleration, deformation, stress; superelement frames: deformation, frame_iterations; joints: force, torque, reaction, coordinates, rates)"))),
            }
            }
        };
        out.push(Signal {
            name: s.clone(),
            unit,
            components,
            kind,
        });
    }
    Ok(out)
}

/// Number of signal components.
pub fn signal_width(signals: &[Signal]) -> usize {
    signals.iter().map(|s| s.components.len()).sum()
}

/// The geometry of contact `c`'s last evaluation, if it has a contact point.
fn contact_geometry(
    contacts: &[flexmbs_core::contact::ContactState],
    c: usize,
) -> Option<flexmbs_core::contact::ContactGeometry> {
    contacts
        .get(c)
        .and_then(|s| s.geometry)
        .filter(|g| g.has_contact_point())
}

/// Evaluates all signals at time `t` into `out` (cleared first); `frames` must be up to date.
pub fn evaluate_signals(
    signals: &[Signal],
    model: &Model,
    t: f64,
    frames: &[FrameKinematics],
    lambda: &[f64],
    contacts: &[flexmbs_core::contact::ContactState],
    out: &mut Vec<f64>,
) {
    let wrench = |j: usize| {
        let joint = &model.joints[j];
        let r0 = model.joint_rows[j];
        flexmbs_core::joint::joint_reaction(
            joint,
            t,
            &frames[joint.frame_a.0],
            &frames[joint.frame_b.0],
            &lambda[r0..r0 + joint.num_rows()],
        )
    };
    let nan3 = Vector3::repeat(f64::NAN);
    out.clear();
    for s in signals {
        match &s.kind {
            SignalKind::Position(f) => out.extend(frames[f.0].position.iter()),
            SignalKind::Velocity(f) => out.extend(frames[f.0].velocity.iter()),
            SignalKind::AngularVelocity(f) => out.extend(frames[f.0].angular_velocity.iter()),
            SignalKind::Orientation(f) => {
                let th = flexmbs_core::rotation::cardan_from_matrix(&frames[f.0].rotation, 0.0)
                    .unwrap_or(Vector3::repeat(f64::NAN));
                out.extend(th.iter());
            }
            SignalKind::Deformation {
                frame,
                body_frame,
                reference,
            } => {
                let (k, b) = (&frames[frame.0], &frames[body_frame.0]);
                let d = b.rotation.transpose() * (k.position - b.position) - reference;
                out.extend(d.iter());
            }
            SignalKind::Reaction { row, rows } => out.extend(&lambda[*row..row + rows]),
            SignalKind::JointForce(j) => out.extend(wrench(*j).0.iter()),
            SignalKind::JointTorque(j) => out.extend(wrench(*j).1.iter()),
            SignalKind::ForceOutput(l) => out.push(match &model.loads[*l] {
                Load::Element(e) => e.output(t, frames).unwrap_or(f64::NAN),
                _ => f64::NAN,
            }),
            SignalKind::ContactGap(c) => out.push(contacts.get(*c).map_or(f64::NAN, |c| c.gap)),
            SignalKind::ContactImpulse(c) => {
                out.extend(contacts.get(*c).map_or([f64::NAN; 3], |c| c.impulse))
            }
            SignalKind::ContactForce(c) => {
                out.extend(contacts.get(*c).map_or([f64::NAN; 3], |c| c.force))
            }
            SignalKind::ContactPoint { contact, side } => {
                let p = contact_geometry(contacts, *contact).map_or(nan3, |g| {
                    if *side == 0 {
                        g.point_a
                    } else {
                        g.point_b
                    }
                });
                out.extend(p.iter());
            }
            SignalKind::ContactNormal(c) => {
                let n = contact_geometry(contacts, *c).map_or(nan3, |g| g.normal);
                out.extend(n.iter());
            }
            SignalKind::ContactCoordinates { contact, side, two } => {
                let x = contact_geometry(contacts, *contact).map_or([f64::NAN; 2], |g| {
                    let x = [g.coordinates[2 * side], g.coordinates[2 * side + 1]];
                    if *two {
                        x
                    } else {
                        [x[0], f64::NAN]
                    }
                });
                out.extend(x);
            }
            SignalKind::Stress { .. } => out.extend([f64::NAN; 7]),
            SignalKind::Acceleration(_)
            | SignalKind::AngularAcceleration(_)
            | SignalKind::JointCoordinates(_)
            | SignalKind::JointRates(_) => {
                out.extend(std::iter::repeat_n(f64::NAN, s.components.len()))
            }
            SignalKind::SuperelementDeformation(_) | SignalKind::FrameIterations(_) => {
                out.extend(std::iter::repeat_n(f64::NAN, s.components.len()))
            }
        }
    }
}

/// Names of the position coordinates, velocity coordinates and multipliers
/// (`rod.R_x`, `rod.q_f3`, `pin.tz`).
pub fn coordinate_names(
    model: &Model,
    bodies: &[BodyInfo],
) -> (Vec<String>, Vec<String>, Vec<String>) {
    // written at each body's global indices: bodies that share nodes name them alike
    let (mut q, mut u) = (vec![String::new(); model.nq], vec![String::new(); model.nu]);
    for b in bodies {
        let g = &b.geometry;
        let mut qn: Vec<String> = XYZ.iter().map(|c| format!("R_{c}")).collect();
        match g.rotation {
            RotationName::Cardan => qn.extend(XYZ.iter().map(|c| format!("theta_{c}"))),
            RotationName::Quaternion => qn.extend((0..4).map(|k| format!("p{k}"))),
        }
        qn.extend((1..=g.modes).map(|k| format!("q_f{k}")));
        let mut un: Vec<String> = XYZ.iter().map(|c| format!("v_{c}")).collect();
        un.extend(XYZ.iter().map(|c| format!("w_{c}")));
        un.extend((1..=g.modes).map(|k| format!("qd_f{k}")));
        let el = &model.bodies[b.id.0].element;
        if el.nq() == 3 && el.nu() == 3 && g.modes == 0 {
            // a point mass: its position and velocity
            qn.truncate(3);
            un.truncate(3);
        }
        if qn.len() != el.nq() {
            qn = (0..el.nq()).map(|k| format!("q{k}")).collect();
        }
        if un.len() != el.nu() {
            un = (0..el.nu()).map(|k| format!("u{k}")).collect();
        }
        let mut qn: Vec<String> = qn.into_iter().map(|n| format!("{}.{n}", b.name)).collect();
        let mut un: Vec<String> = un.into_iter().map(|n| format!("{}.{n}", b.name)).collect();
        if let Some(names) = crate::superelement_output::node_coordinate_names(model, b.id) {
            (qn, un) = names;
        }
        let dofs = model.body_dofs(b.id);
        for (g, n) in dofs.q.iter().zip(qn) {
            q[g] = n;
        }
        for (g, n) in dofs.u.iter().zip(un) {
            u[g] = n;
        }
    }
    // bodies the compiler adds (a servo's integral state: after the file's bodies)
    for (i, b) in model.bodies.iter().enumerate() {
        if bodies.iter().all(|x| x.id.0 != i) {
            let dofs = model.body_dofs(flexmbs_core::BodyId(i));
            for (k, g) in dofs.q.iter().enumerate() {
                q[g] = format!("{}.q{k}", b.name);
            }
            for (k, g) in dofs.u.iter().enumerate() {
                u[g] = format!("{}.u{k}", b.name);
            }
        }
    }
    let mut lambda = Vec::new();
    for j in &model.joints {
        for d in (0..6).filter(|&d| j.locked[d]) {
            lambda.push(format!("{}.{}", j.name, DOFS[d]));
        }
        if j.prescribed.is_some() {
            lambda.push(format!("{}.motion", j.name));
        }
    }
    for g in &model.guides {
        lambda.extend(g.row_names().iter().map(|r| format!("{}.{r}", g.name)));
    }
    (q, u, lambda)
}

/// Every plottable series of a run (the names `flexmbs_io::results::Results::series_names`
/// gives for the same layout).
pub fn series_names(model: &Model, bodies: &[BodyInfo], signals: &[Signal]) -> Vec<String> {
    let (q, u, l) = coordinate_names(model, bodies);
    let mut names: Vec<String> = q.iter().map(|n| format!("q/{n}")).collect();
    names.extend(u.iter().map(|n| format!("u/{n}")));
    names.extend(l.iter().map(|n| format!("lambda/{n}")));
    for e in ["kinetic", "gravity", "elastic", "springs", "total"] {
        names.push(format!("energy/{e}"));
    }
    names.push("drift/position".into());
    names.push("drift/velocity".into());
    for s in ["h", "iterations", "residual"] {
        names.push(format!("step/{s}"));
    }
    for s in signals {
        names.extend(s.components.iter().map(|c| format!("{}.{c}", s.name)));
    }
    names
}

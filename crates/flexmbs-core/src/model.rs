//! Editable [`ModelSpec`] (builder) and the immutable compiled [`Model`].

use crate::contact::{Contact, ContactState};
use crate::element::{Element, FrameKinematics, LocalFrame};
use crate::error::ModelError;
use crate::ids::{BodyId, FrameId, JointId, LoadId, NodeId};
use crate::joint::{Joint, PrescribedMotion};
use crate::load::Load;
use crate::node::{DofMap, Node, NodeKind};
use crate::state::State;
use nalgebra::{Matrix3, Vector3};

/// Who carries a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameOwner {
    /// The inertial ground (zero velocity, no coordinates).
    Ground,
    /// A body (element) of the model.
    Body(BodyId),
    /// A node (fixed to its pose, or a point node): rigid-offset frames without an element, e.g.
    /// interface points shared by several bodies ([`ModelSpec::add_node_owned_frame`]).
    Node(NodeId),
}

/// A frame: the attachment point of joints, loads and springs.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Name (for messages and output).
    pub name: String,
    /// Owner.
    pub owner: FrameOwner,
    /// Position/orientation in the owner's reference frame (global for ground).
    pub local: LocalFrame,
}

/// A body entry of a model.
#[derive(Debug)]
pub struct Body {
    /// Name.
    pub name: String,
    /// The element.
    pub element: Box<dyn Element>,
    /// Offset of its coordinates in the global `q` (contiguous layout).
    pub(crate) q_offset: usize,
    /// Offset of its velocity coordinates in the global `u` (contiguous layout).
    pub(crate) u_offset: usize,
    /// Where its coordinates lie in the global vectors.
    dofs: BodyDofs,
    /// Its nodes, in the element's order.
    pub(crate) nodes: Vec<NodeId>,
}

impl Body {
    /// Where its coordinates lie in the global `q` and `u` (as [`Model::body_dofs`]).
    pub fn dofs(&self) -> &BodyDofs {
        &self.dofs
    }

    /// Its coordinates are scattered in the global vectors (not one contiguous range): element
    /// queries then run on gathered copies ([`crate::gather`]).
    pub fn is_scattered(&self) -> bool {
        self.dofs.u.as_range().is_none()
    }
}

/// Global indices of a body's (element-local) coordinates: [`Model::body_dofs`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BodyDofs {
    /// Position coordinates `q` (nq of the element).
    pub q: DofMap,
    /// Velocity coordinates `u` (nu of the element): also the body's columns of `M`, the
    /// tangents and `G`.
    pub u: DofMap,
}

/// Editable model description. Add bodies, frames, joints and loads, then [`ModelSpec::compile`].
#[derive(Debug)]
pub struct ModelSpec {
    /// Gravitational acceleration (global). Default `(0, 0, 0)`.
    pub gravity: Vector3<f64>,
    nodes: Vec<(String, NodeKind)>,
    bodies: Vec<(String, Box<dyn Element>, Vec<NodeId>)>,
    frames: Vec<Frame>,
    joints: Vec<Joint>,
    loads: Vec<Load>,
    /// The initial state, resolved in [`ModelSpec::compile`] (`spec_initial.rs`).
    pub(crate) initial: crate::spec_initial::InitialSpec,
    contacts: Vec<Contact>,
    guides: Vec<crate::contact::CurveGuide>,
}

impl Default for ModelSpec {
    fn default() -> Self {
        Self::new()
    }
}

impl ModelSpec {
    /// Empty model without gravity.
    pub fn new() -> Self {
        Self {
            gravity: Vector3::zeros(),
            nodes: Vec::new(),
            bodies: Vec::new(),
            frames: Vec::new(),
            joints: Vec::new(),
            loads: Vec::new(),
            initial: Default::default(),
            contacts: Vec::new(),
            guides: Vec::new(),
        }
    }

    /// Sets the gravitational acceleration.
    pub fn set_gravity(&mut self, g: Vector3<f64>) -> &mut Self {
        self.gravity = g;
        self
    }

    /// Adds a body with its own nodes: one new node per entry of
    /// [`Element::node_kinds`], in order, named `name` (one node) or `name.0`, `name.1`, ...
    pub fn add_body(&mut self, name: &str, element: impl Element + 'static) -> BodyId {
        let kinds = element.node_kinds().to_vec();
        let nodes = kinds
            .iter()
            .enumerate()
            .map(|(i, k)| {
                let node_name = if kinds.len() == 1 {
                    name.to_string()
                } else {
                    format!("{name}.{i}")
                };
                self.add_node(&node_name, *k)
            })
            .collect();
        self.bodies
            .push((name.to_string(), Box::new(element), nodes));
        BodyId(self.bodies.len() - 1)
    }

    /// Adds a node of `kind` (coordinates in the reference configuration until a body on it is
    /// placed). Nodes get their global coordinates in the order they are added.
    pub fn add_node(&mut self, name: &str, kind: NodeKind) -> NodeId {
        self.nodes.push((name.to_string(), kind));
        NodeId(self.nodes.len() - 1)
    }

    /// Adds a body whose element lives on existing `nodes` (in the order and of the kinds of its
    /// [`Element::node_kinds`]): bodies that share a node share its coordinates, with no
    /// constraint between them. Checked by [`Self::compile`].
    pub fn add_body_on(
        &mut self,
        name: &str,
        element: impl Element + 'static,
        nodes: &[NodeId],
    ) -> BodyId {
        self.bodies
            .push((name.to_string(), Box::new(element), nodes.to_vec()));
        BodyId(self.bodies.len() - 1)
    }

    /// Adds a frame on a body at `position` (body reference coordinates) with `rotation`.
    pub fn add_frame(
        &mut self,
        name: &str,
        body: BodyId,
        position: Vector3<f64>,
        rotation: Matrix3<f64>,
    ) -> FrameId {
        self.push_frame(
            name,
            FrameOwner::Body(body),
            LocalFrame {
                position,
                rotation,
                mesh_node: None,
            },
        )
    }

    /// Adds a frame that follows FE node `node` of a flexible body (axes parallel to the
    /// node's deformed frame). Pass the node's undeformed position in the body reference frame
    /// as `position`: it is stored as [`LocalFrame::position`] (the reference of deformation
    /// outputs), but the frame's kinematics come from the node alone, so it is not an offset.
    pub fn add_node_frame(
        &mut self,
        name: &str,
        body: BodyId,
        node: usize,
        position: Vector3<f64>,
    ) -> FrameId {
        self.add_oriented_node_frame(name, body, node, position, Matrix3::identity())
    }

    /// [`Self::add_node_frame`] with axes rotated by `rotation` relative to the node's deformed
    /// frame (columns = frame axes in the node frame): e.g. a revolute axis at an FE node that is
    /// not the body's z axis. The rotation is constant, so the frame's angular velocity and
    /// Jacobians are the node's.
    pub fn add_oriented_node_frame(
        &mut self,
        name: &str,
        body: BodyId,
        node: usize,
        position: Vector3<f64>,
        rotation: Matrix3<f64>,
    ) -> FrameId {
        let local = LocalFrame {
            position,
            rotation,
            mesh_node: Some(node),
        };
        self.push_frame(name, FrameOwner::Body(body), local)
    }

    /// Adds a frame fixed to `node` (a `Pose`, `PoseCardan` or `Vector(3)` node) at `position`
    /// in the node's axes, with `rotation` relative to them: its Jacobians have the node's
    /// columns only, whichever bodies share the node.
    pub fn add_node_owned_frame(
        &mut self,
        name: &str,
        node: NodeId,
        position: Vector3<f64>,
        rotation: Matrix3<f64>,
    ) -> FrameId {
        let local = LocalFrame {
            position,
            rotation,
            mesh_node: None,
        };
        self.push_frame(name, FrameOwner::Node(node), local)
    }

    /// Adds a ground frame at a global position and orientation.
    pub fn add_ground_frame(
        &mut self,
        name: &str,
        position: Vector3<f64>,
        rotation: Matrix3<f64>,
    ) -> FrameId {
        self.push_frame(
            name,
            FrameOwner::Ground,
            LocalFrame {
                position,
                rotation,
                mesh_node: None,
            },
        )
    }

    fn push_frame(&mut self, name: &str, owner: FrameOwner, local: LocalFrame) -> FrameId {
        self.frames.push(Frame {
            name: name.to_string(),
            owner,
            local,
        });
        FrameId(self.frames.len() - 1)
    }

    /// Adds a joint (see the named constructors of [`Joint`]).
    pub fn add_joint(&mut self, joint: Joint) -> JointId {
        self.joints.push(joint);
        JointId(self.joints.len() - 1)
    }

    /// Adds a load.
    pub fn add_load(&mut self, load: Load) -> LoadId {
        self.loads.push(load);
        LoadId(self.loads.len() - 1)
    }

    /// Adds a contact between two contours ([`crate::contact`]); its pair, contours and law are
    /// checked by [`Self::compile`].
    pub fn add_contact(&mut self, contact: Contact) -> usize {
        self.contacts.push(contact);
        self.contacts.len() - 1
    }

    /// Adds a bilateral guide of a frame on a 1D neutral contour ([`crate::contact::guide`]):
    /// constraint rows after the joints' ([`Model::guide_rows`]), checked by [`Self::compile`].
    pub fn add_guide(&mut self, guide: crate::contact::CurveGuide) -> usize {
        self.guides.push(guide);
        self.guides.len() - 1
    }

    /// Validates the description and builds the immutable model.
    pub fn compile(mut self) -> Result<Model, ModelError> {
        let initial = std::mem::take(&mut self.initial);
        let (nodes, nq, nu) = layout_nodes(&self.nodes);
        let mut users = vec![0usize; nodes.len()];
        let mut bodies = Vec::with_capacity(self.bodies.len());
        let mut scattered = false;
        for (name, element, body_nodes) in self.bodies {
            let invalid = |reason: String| ModelError::InvalidBody {
                body: name.clone(),
                reason,
            };
            element.validate().map_err(invalid)?;
            let dofs = body_dofs(&nodes, element.as_ref(), &body_nodes).map_err(invalid)?;
            for n in &body_nodes {
                users[n.0] += 1;
            }
            // a scattered body has no offsets: every access goes through its maps (an access
            // that forgot them fails loudly instead of reading another body's coordinates)
            let (q_offset, u_offset) = match (dofs.q.as_range(), dofs.u.as_range()) {
                (Some(q), Some(u)) => (q.start, u.start),
                _ => {
                    crate::gather::check_scattered_element(element.as_ref()).map_err(invalid)?;
                    scattered = true;
                    (usize::MAX, usize::MAX)
                }
            };
            bodies.push(Body {
                name,
                element,
                q_offset,
                u_offset,
                dofs,
                nodes: body_nodes,
            });
        }
        let shared_nodes = users.iter().any(|&c| c > 1);
        for f in &self.frames {
            if let FrameOwner::Node(n) = f.owner {
                let node = nodes.get(n.0).ok_or_else(|| ModelError::InvalidBody {
                    body: f.name.clone(),
                    reason: format!("frame on {n}, which does not exist"),
                })?;
                if !node.kind.carries_frames() {
                    return Err(ModelError::InvalidBody {
                        body: node.name.clone(),
                        reason: format!(
                            "frame `{}`: a {:?} node carries no frames (Pose, PoseCardan or \
                             Vector(3) do)",
                            f.name, node.kind
                        ),
                    });
                }
            }
            if let FrameOwner::Body(b) = f.owner {
                let body = bodies.get(b.0).ok_or(ModelError::UnknownBody {
                    frame: f.name.clone(),
                    body: b,
                })?;
                if let Some(node) = f.local.mesh_node {
                    let num_nodes = body.element.num_mesh_nodes();
                    if node >= num_nodes {
                        return Err(ModelError::InvalidNode {
                            frame: f.name.clone(),
                            node,
                            num_nodes,
                        });
                    }
                }
            }
        }
        if let Some(n) = users.iter().position(|&c| c == 0) {
            return Err(ModelError::InvalidBody {
                body: nodes[n].name.clone(),
                reason: "node used by no body (its coordinates would have no mass)".into(),
            });
        }
        let check_frame = |item: String, id: FrameId| -> Result<FrameOwner, ModelError> {
            self.frames
                .get(id.0)
                .map(|f| f.owner)
                .ok_or(ModelError::UnknownFrame { item, frame: id })
        };
        let mut joint_rows = Vec::with_capacity(self.joints.len());
        let mut nc = 0;
        for (j, joint) in self.joints.iter().enumerate() {
            let oa = check_frame(format!("joint `{}`", joint.name), joint.frame_a)?;
            let ob = check_frame(format!("joint `{}`", joint.name), joint.frame_b)?;
            if oa == ob {
                return Err(ModelError::SameOwner {
                    item: joint.name.clone(),
                });
            }
            match &joint.prescribed {
                Some(PrescribedMotion::RevoluteAngle(f))
                | Some(PrescribedMotion::RevoluteRate { rate: f, .. }) => {
                    if joint.locked[5] {
                        return Err(ModelError::PrescribedOnLockedDof {
                            joint: JointId(j),
                            dof: "rz",
                        });
                    }
                    f.validate(None)?;
                }
                Some(PrescribedMotion::PrismaticDisplacement(f)) => {
                    if joint.locked[0] {
                        return Err(ModelError::PrescribedOnLockedDof {
                            joint: JointId(j),
                            dof: "tx",
                        });
                    }
                    f.validate(None)?;
                }
                None => {}
            }
            joint_rows.push(nc);
            nc += joint.num_rows();
        }
        let mut guide_rows = Vec::with_capacity(self.guides.len());
        for guide in &self.guides {
            guide_rows.push(nc);
            nc += guide.num_rows();
        }
        for (l, load) in self.loads.iter().enumerate() {
            let id = LoadId(l);
            match load {
                Load::Force { frame, time, .. } | Load::Torque { frame, time, .. } => {
                    check_frame(format!("load {id}"), *frame)?;
                    time.validate(Some(id))?;
                }
                Load::Element(e) => {
                    let mut owners = Vec::new();
                    for f in e.frames() {
                        owners.push(check_frame(format!("load {id}"), *f)?);
                    }
                    crate::force::check_force_element(&**e, &owners)?;
                }
                Load::SpringDamper {
                    frame_a,
                    frame_b,
                    stiffness,
                    damping,
                    free_length,
                } => {
                    let oa = check_frame(format!("load {id}"), *frame_a)?;
                    let ob = check_frame(format!("load {id}"), *frame_b)?;
                    if oa == ob && oa == FrameOwner::Ground {
                        return Err(ModelError::SameOwner {
                            item: format!("spring {id}"),
                        });
                    }
                    for (name, v) in [
                        ("stiffness", *stiffness),
                        ("damping", *damping),
                        ("free_length", *free_length),
                    ] {
                        if !(v >= 0.0 && v.is_finite()) {
                            return Err(ModelError::InvalidParameter {
                                name,
                                value: v,
                                reason: "must be finite and >= 0",
                            });
                        }
                    }
                }
            }
        }
        if !self.gravity.iter().all(|g| g.is_finite()) {
            return Err(ModelError::InvalidParameter {
                name: "gravity",
                value: self.gravity.norm(),
                reason: "must be finite",
            });
        }
        let owner_state = |b: usize| bodies.get(b).map(|b: &Body| b.element.new_scratch());
        crate::contact::check_contacts(&self.frames, &owner_state, &mut self.contacts)?;
        crate::contact::guide::check_guides(&self.frames, &owner_state, &self.guides)?;
        let frame_cols = self
            .frames
            .iter()
            .map(|f| match f.owner {
                FrameOwner::Ground => DofMap::Contiguous(0..0),
                FrameOwner::Body(b) => bodies[b.0].dofs.u.clone(),
                FrameOwner::Node(n) => DofMap::Contiguous(nodes[n.0].u.clone()),
            })
            .collect();
        let mut model = Model {
            gravity: self.gravity,
            nodes,
            shared_nodes,
            scattered,
            bodies,
            frame_cols,
            frames: self.frames,
            joints: self.joints,
            joint_rows,
            loads: self.loads,
            contacts: self.contacts,
            guides: self.guides,
            guide_rows,
            nq,
            nu,
            nc,
            initial: State::zeros(nq, nu, nc),
        };
        initial.resolve(&mut model)?;
        Ok(model)
    }
}

/// Global coordinate ranges of the nodes, in the order they were added; totals `nq`, `nu`.
fn layout_nodes(spec: &[(String, NodeKind)]) -> (Vec<Node>, usize, usize) {
    let (mut nq, mut nu) = (0, 0);
    let nodes = spec
        .iter()
        .map(|(name, kind)| {
            let node = Node {
                name: name.clone(),
                kind: *kind,
                q: nq..nq + kind.nq(),
                u: nu..nu + kind.nu(),
            };
            (nq, nu) = (node.q.end, node.u.end);
            node
        })
        .collect();
    (nodes, nq, nu)
}

/// The coordinate maps of a body on `body_nodes` (the concatenation of their ranges), after
/// checking them against the element's node kinds and sizes.
fn body_dofs(
    nodes: &[Node],
    element: &dyn Element,
    body_nodes: &[NodeId],
) -> Result<BodyDofs, String> {
    let kinds = element.node_kinds();
    if kinds.len() != body_nodes.len() {
        return Err(format!(
            "the element lives on {} nodes, {} given",
            kinds.len(),
            body_nodes.len()
        ));
    }
    let (mut q, mut u) = (Vec::new(), Vec::new());
    for (i, (id, kind)) in body_nodes.iter().zip(kinds).enumerate() {
        let node = nodes
            .get(id.0)
            .ok_or_else(|| format!("node {i}: {id} does not exist"))?;
        if node.kind != *kind {
            return Err(format!(
                "node {i} (`{}`) is {:?}, the element needs {kind:?}",
                node.name, node.kind
            ));
        }
        q.extend(node.q.clone());
        u.extend(node.u.clone());
    }
    if (q.len(), u.len()) != (element.nq(), element.nu()) {
        return Err(format!(
            "node kinds give {} + {} coordinates, the element has nq = {}, nu = {}",
            q.len(),
            u.len(),
            element.nq(),
            element.nu()
        ));
    }
    let map = |v: Vec<usize>| match (v.first(), v.last()) {
        (Some(&a), Some(&b)) if v.windows(2).all(|w| w[1] == w[0] + 1) => {
            DofMap::Contiguous(a..b + 1)
        }
        (None, _) => DofMap::Contiguous(0..0),
        _ => DofMap::Scattered(v),
    };
    Ok(BodyDofs {
        q: map(q),
        u: map(u),
    })
}

/// The compiled, immutable model: bodies with coordinate offsets, frames, joints, loads.
#[derive(Debug)]
pub struct Model {
    /// Gravitational acceleration.
    pub gravity: Vector3<f64>,
    /// Nodes (owners of the coordinates), in the order of the global vectors.
    pub nodes: Vec<Node>,
    /// Some node is used by more than one body: element blocks overlap and are accumulated.
    pub(crate) shared_nodes: bool,
    /// Some body's coordinates are scattered ([`Body::is_scattered`]): its element blocks are
    /// gathered and scatter-added.
    pub(crate) scattered: bool,
    /// Bodies (elements) with their coordinate maps.
    pub bodies: Vec<Body>,
    /// Frames.
    pub frames: Vec<Frame>,
    /// Global columns of each frame's Jacobians (empty for ground frames).
    frame_cols: Vec<DofMap>,
    /// Joints.
    pub joints: Vec<Joint>,
    /// First constraint row of each joint.
    pub joint_rows: Vec<usize>,
    /// Loads.
    pub loads: Vec<Load>,
    /// Contacts ([`crate::contact`]; each pair in the dispatch table's order).
    pub contacts: Vec<Contact>,
    /// Bilateral guides on 1D neutral contours ([`crate::contact::guide`]).
    pub guides: Vec<crate::contact::CurveGuide>,
    /// First constraint row of each guide (after all joints' rows).
    pub guide_rows: Vec<usize>,
    /// Total position coordinates.
    pub nq: usize,
    /// Total velocity coordinates.
    pub nu: usize,
    /// Total constraint rows (Lagrange multipliers).
    pub nc: usize,
    /// The initial state (reference coordinates, then the spec's initial poses and velocities).
    pub(crate) initial: State,
}

impl Model {
    /// The initial state: every element in its reference configuration, at rest, then the poses
    /// and velocities set with [`ModelSpec::set_initial_pose`] and
    /// [`ModelSpec::set_initial_velocity`].
    pub fn initial_state(&self) -> State {
        self.initial.clone()
    }

    /// State at `t = 0` with every element in its reference configuration, at rest.
    pub fn reference_state(&self) -> State {
        let mut s = State::zeros(self.nq, self.nu, self.nc);
        s.contacts = vec![ContactState::default(); self.contacts.len()];
        for b in &self.bodies {
            let (nq, nu) = (b.element.nq(), b.element.nu());
            if b.is_scattered() {
                let (mut q, mut u) = (vec![0.0; nq], vec![0.0; nu]);
                b.element.reference_coordinates(&mut q, &mut u);
                b.dofs.q.scatter_into(&q, &mut s.q);
                b.dofs.u.scatter_into(&u, &mut s.u);
                continue;
            }
            b.element.reference_coordinates(
                &mut s.q[b.q_offset..b.q_offset + nq],
                &mut s.u[b.u_offset..b.u_offset + nu],
            );
        }
        s
    }

    /// Sets pose (global position and rotation of the body reference frame) of a body in `state`.
    pub fn set_body_pose(
        &self,
        state: &mut State,
        body: BodyId,
        position: Vector3<f64>,
        rotation: Matrix3<f64>,
    ) {
        let b = &self.bodies[body.0];
        let nq = b.element.nq();
        if b.is_scattered() {
            let mut q = Vec::new();
            b.dofs.q.gather_into(&state.q, &mut q);
            b.element.set_pose(&mut q, &position, &rotation);
            b.dofs.q.scatter_into(&q, &mut state.q);
            return;
        }
        b.element.set_pose(
            &mut state.q[b.q_offset..b.q_offset + nq],
            &position,
            &rotation,
        );
    }

    /// Sets velocity and angular velocity (global) of a body in `state` (after its pose).
    pub fn set_body_velocity(
        &self,
        state: &mut State,
        body: BodyId,
        velocity: Vector3<f64>,
        omega: Vector3<f64>,
    ) {
        let b = &self.bodies[body.0];
        let (nq, nu) = (b.element.nq(), b.element.nu());
        if b.is_scattered() {
            let (mut q, mut u) = (Vec::new(), Vec::new());
            b.dofs.q.gather_into(&state.q, &mut q);
            b.dofs.u.gather_into(&state.u, &mut u);
            b.element.set_velocity(&q, &mut u, &velocity, &omega);
            b.dofs.u.scatter_into(&u, &mut state.u);
            return;
        }
        b.element.set_velocity(
            &state.q[b.q_offset..b.q_offset + nq],
            &mut state.u[b.u_offset..b.u_offset + nu],
            &velocity,
            &omega,
        );
    }

    /// Where the coordinates of `body` lie in the global `q` and `u` (its columns of `M`, the
    /// tangents and `G`): for assembly patterns (e.g. a sparse iteration matrix) and output.
    ///
    /// # Panics
    /// If `body` belongs to another model ([`Self::body_id`] gives ids by name).
    pub fn body_dofs(&self, body: BodyId) -> &BodyDofs {
        &self.bodies[body.0].dofs
    }

    /// Global columns of the Jacobians of `frame` ([`FrameKinematics::jac_t`] column `j` is global
    /// column `frame_cols(frame).global(j)`); empty for a ground frame.
    ///
    /// # Panics
    /// If `frame` belongs to another model.
    pub fn frame_cols(&self, frame: FrameId) -> &DofMap {
        &self.frame_cols[frame.0]
    }

    /// Coordinates of one body in a global vector.
    ///
    /// # Panics
    /// If `body` belongs to another model or `q` is shorter than this model's `nq` (as indexing a
    /// slice out of bounds), or the body's coordinates are scattered ([`Body::is_scattered`]:
    /// use [`Self::body_coordinates`]); [`Self::body_id`] gives ids by name.
    pub fn body_q<'a>(&self, body: BodyId, q: &'a [f64]) -> &'a [f64] {
        let (b, oq, _) = self.contiguous(body);
        &q[oq..oq + b.element.nq()]
    }

    /// Velocity coordinates of one body in a global vector.
    ///
    /// # Panics
    /// As [`Self::body_q`], for `u` and `nu`.
    pub fn body_u<'a>(&self, body: BodyId, u: &'a [f64]) -> &'a [f64] {
        let (b, _, ou) = self.contiguous(body);
        &u[ou..ou + b.element.nu()]
    }

    /// [`Self::body_q`], mutable (e.g. to set initial modal coordinates).
    ///
    /// # Panics
    /// As [`Self::body_q`].
    pub fn body_q_mut<'a>(&self, body: BodyId, q: &'a mut [f64]) -> &'a mut [f64] {
        let (b, oq, _) = self.contiguous(body);
        &mut q[oq..oq + b.element.nq()]
    }

    /// [`Self::body_u`], mutable (e.g. to set initial modal velocities).
    ///
    /// # Panics
    /// As [`Self::body_q`], for `u` and `nu`.
    pub fn body_u_mut<'a>(&self, body: BodyId, u: &'a mut [f64]) -> &'a mut [f64] {
        let (b, _, ou) = self.contiguous(body);
        &mut u[ou..ou + b.element.nu()]
    }

    /// Position coordinates of one node in a global vector: for a `Pose` node the position of
    /// its origin then its unit quaternion (scalar first), for `PoseCardan` the position then the
    /// Cardan angles, for `Vector(n)` its `n` values. A node's coordinates are always contiguous,
    /// also when a body on it is scattered; for post-processing that works node by node (code
    /// outside this crate reads no raw coordinate offsets).
    ///
    /// # Panics
    /// If `node` belongs to another model or `q` is shorter than this model's `nq`.
    pub fn node_q<'a>(&self, node: NodeId, q: &'a [f64]) -> &'a [f64] {
        &q[self.nodes[node.0].q.clone()]
    }

    /// Velocity coordinates of one node in a global vector (`Pose`: origin velocity then the
    /// body-frame angular velocity; `PoseCardan`: origin velocity then the Cardan angle rates;
    /// `Vector(n)`: its `n` rates).
    ///
    /// # Panics
    /// As [`Self::node_q`], for `u` and `nu`.
    pub fn node_u<'a>(&self, node: NodeId, u: &'a [f64]) -> &'a [f64] {
        &u[self.nodes[node.0].u.clone()]
    }

    /// [`Self::node_u`], mutable.
    ///
    /// # Panics
    /// As [`Self::node_u`].
    pub fn node_u_mut<'a>(&self, node: NodeId, u: &'a mut [f64]) -> &'a mut [f64] {
        &mut u[self.nodes[node.0].u.clone()]
    }

    /// Ids of all nodes, in the order of the global vectors.
    pub fn node_ids(&self) -> impl Iterator<Item = NodeId> + '_ {
        (0..self.nodes.len()).map(NodeId)
    }

    /// The node that owns global position coordinate `g`, and `g`'s index within
    /// [`Self::node_q`] of that node; `None` if `g >= nq`.
    pub fn q_owner(&self, g: usize) -> Option<(NodeId, usize)> {
        let i = self.nodes.partition_point(|n| n.q.end <= g);
        let n = self.nodes.get(i)?;
        n.q.contains(&g).then(|| (NodeId(i), g - n.q.start))
    }

    /// The node that owns global velocity coordinate `g`, and `g`'s index within
    /// [`Self::node_u`] of that node; `None` if `g >= nu`.
    pub fn u_owner(&self, g: usize) -> Option<(NodeId, usize)> {
        let i = self.nodes.partition_point(|n| n.u.end <= g);
        let n = self.nodes.get(i)?;
        n.u.contains(&g).then(|| (NodeId(i), g - n.u.start))
    }

    /// One zeroed [`FrameKinematics`] per frame, sized for its owner (the buffers
    /// [`crate::system::update_frames`] writes).
    pub fn frame_buffers(&self) -> Vec<FrameKinematics> {
        (0..self.frames.len())
            .map(|f| FrameKinematics::for_frame(self, FrameId(f)))
            .collect()
    }

    /// The body called `name`.
    pub fn body_id(&self, name: &str) -> Option<BodyId> {
        self.bodies.iter().position(|b| b.name == name).map(BodyId)
    }

    /// The frame called `name`.
    pub fn frame_id(&self, name: &str) -> Option<FrameId> {
        self.frames.iter().position(|f| f.name == name).map(FrameId)
    }

    /// Position, orientation, velocities and Jacobians (columns of the frame's own body) of one
    /// frame in state `s`: for post-processing (it allocates; inside a step the integrators use
    /// [`crate::system::evaluate`] on workspace buffers). `None` for a frame id of another
    /// model, a state of the wrong size, or a state the frame's element cannot evaluate.
    pub fn frame_kinematics(&self, s: &State, frame: FrameId) -> Option<FrameKinematics> {
        let f = self.frames.get(frame.0)?;
        if s.q.len() != self.nq || s.u.len() != self.nu {
            return None;
        }
        let mut k = FrameKinematics::for_frame(self, frame);
        match f.owner {
            FrameOwner::Ground => {
                k.position = f.local.position;
                k.rotation = f.local.rotation;
                Some(k)
            }
            FrameOwner::Body(b) => {
                let body = self.bodies.get(b.0)?;
                let (q, u) = self.body_coordinates(b, &s.q, &s.u);
                let b = body;
                let mut e = b.element.new_scratch();
                b.element.update_kinematics(&q, &u, &mut e).ok()?;
                b.element.frame_kinematics(&q, &u, &mut e, &f.local, &mut k);
                Some(k)
            }
            FrameOwner::Node(n) => {
                let n = self.nodes.get(n.0)?;
                let (q, u) = (&s.q[n.q.clone()], &s.u[n.u.clone()]);
                n.kind.frame_kinematics(q, u, &f.local, &mut k);
                Some(k)
            }
        }
    }
}

impl FrameKinematics {
    /// Zeroed kinematics sized for `frame` of `model` (Jacobians with the columns of its owner,
    /// none for ground).
    ///
    /// # Panics
    /// If `frame` belongs to another model.
    pub fn for_frame(model: &Model, frame: FrameId) -> Self {
        Self::new(model.frame_cols(frame).len())
    }

    /// Zeroed kinematics for a frame on `body` of `model` (e.g. for output points of the body).
    ///
    /// # Panics
    /// If `body` belongs to another model.
    pub fn for_body(model: &Model, body: BodyId) -> Self {
        Self::new(model.body_dofs(body).u.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::point_mass::PointMass;
    use crate::rigid::RigidBody;
    use crate::RotationParam;

    /// `node_q`/`node_u` are each node's block of the global vectors (Cardan rigid body: 6 + 6,
    /// quaternion rigid body: 7 + 6, point mass: 3 + 3) and `q_owner`/`u_owner` invert them for
    /// every global coordinate.
    #[test]
    fn node_coordinates_and_owners() {
        let mut spec = ModelSpec::new();
        let i = Matrix3::identity();
        spec.add_body("cardan", RigidBody::new(1.0, i));
        let p = spec.add_node("p", NodeKind::Vector(3));
        spec.add_body(
            "quat",
            RigidBody::new(1.0, i).with_rotation(RotationParam::Quaternion),
        );
        spec.add_body_on("mass", PointMass::new(1.0), &[p]);
        let model = spec.compile().unwrap();
        assert_eq!((model.nq, model.nu), (16, 15));
        let q: Vec<f64> = (0..model.nq).map(|k| k as f64).collect();
        let mut u: Vec<f64> = (0..model.nu).map(|k| 100.0 + k as f64).collect();
        let ids: Vec<NodeId> = model.node_ids().collect();
        assert_eq!(ids, [NodeId(0), NodeId(1), NodeId(2)]);
        assert_eq!(model.node_q(ids[0], &q), &q[0..6]);
        assert_eq!(model.node_q(ids[1], &q), &q[6..9]);
        assert_eq!(model.node_q(ids[2], &q), &q[9..16]);
        assert_eq!(model.node_u(ids[0], &u), &u[0..6]);
        assert_eq!(model.node_u(ids[1], &u), &u[6..9]);
        assert_eq!(model.node_u(ids[2], &u), &u[9..15]);
        model.node_u_mut(ids[1], &mut u).fill(-1.0);
        assert_eq!(&u[5..10], &[105.0, -1.0, -1.0, -1.0, 109.0]);
        for id in model.node_ids() {
            for (k, &x) in model.node_q(id, &q).iter().enumerate() {
                assert_eq!(model.q_owner(x as usize), Some((id, k)));
            }
            let u0: Vec<f64> = (0..model.nu).map(|k| k as f64).collect();
            for (k, &x) in model.node_u(id, &u0).iter().enumerate() {
                assert_eq!(model.u_owner(x as usize), Some((id, k)));
            }
        }
        assert_eq!(model.q_owner(16), None);
        assert_eq!(model.u_owner(15), None);
    }
}

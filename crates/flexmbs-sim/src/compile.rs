//! Model file -> [`flexmbs_core::ModelSpec`] -> compiled model, initial state, solver and output
//! configuration. Every error names the key path and its line.

use crate::bodies::{build_body, BodyGeometry, BuiltElement};
pub use crate::config::{orientation, time_function, OutputConfig, OutputEvery, SolverConfig};
use crate::config::{output_config, solver_config};
use crate::drives::{check_drive_smoothness, DriveLevel};
use crate::error::SimError;
use crate::fe_frames::{check_rotation_lock_at_node, RotationUse};
use crate::locate::{line_of, line_of_path};
use crate::point_mass_body::{refuse_rotation_on_point_mass, RotationalUse};
use crate::schema::{CoordinatesName, JointType, LoadType, ModelFile};
use crate::signals::{parse_signals, Signal};
use crate::units::{Dimension, Quantity};
use flexmbs_core::ffr::FfrBody;
use flexmbs_core::{
    BodyId, FrameId, Joint, Load, LoadCoordinates, Model, ModelError, ModelSpec, PrescribedMotion,
    State, TimeFunction,
};
use nalgebra::{Matrix3, Vector3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The text and name of the file being compiled: turns key paths into errors with lines.
#[derive(Debug)]
pub struct Ctx<'a> {
    /// File text.
    pub text: &'a str,
    /// File name for messages.
    pub file: &'a Path,
}

impl Ctx<'_> {
    /// Error at key path `path`.
    pub fn err(&self, path: &str, message: impl Into<String>) -> SimError {
        SimError::Model {
            file: self.file.to_path_buf(),
            line: line_of_path(self.text, path),
            path: path.to_string(),
            message: message.into(),
        }
    }
    /// A quantity in SI, finite.
    pub fn q(&self, q: &Quantity, dim: Dimension, path: &str) -> Result<f64, SimError> {
        let v = q.to_si(dim).map_err(|m| self.err(path, m))?;
        if !v.is_finite() {
            return Err(self.err(path, "must be a finite number"));
        }
        Ok(v)
    }
    /// A 3-vector in SI.
    pub fn vec3(
        &self,
        v: &[Quantity; 3],
        dim: Dimension,
        path: &str,
    ) -> Result<Vector3<f64>, SimError> {
        let mut out = Vector3::zeros();
        for k in 0..3 {
            out[k] = self.q(&v[k], dim, &format!("{path}[{k}]"))?;
        }
        Ok(out)
    }
    /// Errors on keys present that the item's type does not use.
    pub fn only(
        &self,
        p: &str,
        what: &str,
        present: &[(&str, bool)],
        allowed: &[&str],
    ) -> Result<(), SimError> {
        for (k, is) in present {
            if *is && !allowed.contains(k) {
                return Err(self.err(&format!("{p}.{k}"), format!("`{k}` is not used by {what}")));
            }
        }
        Ok(())
    }
}

/// A body of the compiled model with its name and geometry.
#[derive(Debug, Clone)]
pub struct BodyInfo {
    /// Name.
    pub name: String,
    /// Id in the model.
    pub id: BodyId,
    /// The body's reference frame (named like the body).
    pub frame: FrameId,
    /// Animation geometry and FE data.
    pub geometry: BodyGeometry,
}

/// A compiled model file: the engine model, its initial state and everything the run needs.
#[derive(Debug)]
pub struct CompiledModel {
    /// Model name.
    pub name: String,
    /// The model file.
    pub file: PathBuf,
    /// The engine model.
    pub model: Model,
    /// Initial state (poses and velocities from the file, accelerations not yet consistent).
    pub initial: State,
    /// Solver.
    pub solver: SolverConfig,
    /// Linear-solver backend (`solver.linear_solver`).
    pub linear_solver: flexmbs_core::algebra::LinearSolver,
    /// Output.
    pub output: OutputConfig,
    /// Bodies.
    pub bodies: Vec<BodyInfo>,
    /// Requested signals.
    pub signals: Vec<Signal>,
    /// Copies of the ffr bodies with geometric stiffening, for the power of the stiffening
    /// force in the energy balance (`flexmbs_core::power::stiffening_power`).
    pub stiffened: Vec<(BodyId, FfrBody)>,
    /// Warnings about legal but suspicious input (file, line, key path and message each), which
    /// `check` and `run` print.
    pub warnings: Vec<String>,
    /// `solver.initial = "static"`: the run starts from static equilibrium at t = 0.
    pub initial_static: bool,
    /// The text of the model file as compiled (stored in the results file).
    pub text: String,
    /// `solver.restart`: the unwrapped angles `(joint index, rad)` of the revolute joints whose
    /// `coordinates` signal the results file holds at the restart row, so the restarted run
    /// continues them on the same branch (not back in (-pi, pi]).
    pub restart_angles: Vec<(usize, f64)>,
}

/// Parses model-file text into the schema (errors with key path and line).
pub fn parse_model_file(text: &str, file: &Path) -> Result<ModelFile, SimError> {
    let de = toml::Deserializer::parse(text).map_err(|e| SimError::Model {
        file: file.to_path_buf(),
        line: e.span().map(|s| line_of(text, s.start)).unwrap_or(0),
        path: String::new(),
        message: e.message().to_string(),
    })?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let line = match inner.span() {
            Some(s) => line_of(text, s.start),
            None => line_of_path(text, &path),
        };
        SimError::Model {
            file: file.to_path_buf(),
            line,
            path,
            message: inner.message().to_string(),
        }
    })
}

/// True if `text` is a multibody model file (has a top-level `[model]` table) rather than an FE
/// body file (top-level `[body]` table).
pub fn is_multibody_model(text: &str) -> bool {
    flexmbs_io::file_kind::classify_model_text(text)
        == flexmbs_io::file_kind::ModelFileKind::Multibody
}

/// Reads and compiles a model file.
pub fn load_model(path: &Path) -> Result<CompiledModel, SimError> {
    let text = flexmbs_io::source_file::read_to_string(path).map_err(|source| SimError::Read {
        file: path.to_path_buf(),
        source,
    })?;
    compile_model(&text, path)
}

/// Compiles model-file text; relative sources are resolved against `file`'s folder.
pub fn compile_model(text: &str, file: &Path) -> Result<CompiledModel, SimError> {
    let mf = parse_model_file(text, file)?;
    let ctx = Ctx { text, file };
    let base = file.parent().unwrap_or(Path::new("."));
    check_names(&ctx, &mf)?;
    let mut spec = ModelSpec::new();
    if let Some(g) = &mf.model.gravity {
        spec.set_gravity(ctx.vec3(g, Dimension::Acceleration, "model.gravity")?);
    }
    let i3 = Matrix3::identity();
    let mut frames: HashMap<String, FrameId> = HashMap::new();
    let mut bodies = Vec::new();
    // frames fixed in the floating frame of an ffr body whose modes do not clamp it
    let mut point_frames: HashMap<FrameId, String> = HashMap::new();
    let mut abstract_frames: HashMap<FrameId, String> = HashMap::new();
    let mut abstract_bodies = Vec::new();
    // frames on FE nodes: (body index, node index)
    let mut node_frames: HashMap<FrameId, (usize, usize)> = HashMap::new();
    let mut stiffened = Vec::new();
    // the ffr bodies flexible contours are built from (only when the model has contacts)
    let mut contour_bodies: HashMap<String, flexmbs_core::ffr::FfrBody> = HashMap::new();
    for (i, b) in mf.body.iter().enumerate() {
        if b.is_superelement() {
            continue;
        }
        let (element, geometry) = build_body(&ctx, i, b, base, &mf.frame)?;
        if let (BuiltElement::Ffr(f), false) = (&element, mf.contact.is_empty()) {
            contour_bodies.insert(b.name.clone(), f.body().clone());
        }
        abstract_bodies.push(match &element {
            BuiltElement::Ffr(f) => !f.body().floating_frame_is_material(),
            BuiltElement::Rigid(_) | BuiltElement::PointMass(_) => false,
        });
        let point_mass = matches!(element, BuiltElement::PointMass(_));
        let id = match element {
            BuiltElement::Rigid(r) => spec.add_body(&b.name, r),
            BuiltElement::PointMass(p) => spec.add_body(&b.name, p),
            BuiltElement::Ffr(f) => {
                let stiffened_body = f.body().geometric_stiffening().map(|_| f.body().clone());
                let id = spec.add_body(&b.name, *f);
                stiffened.extend(stiffened_body.map(|body| (id, body)));
                id
            }
        };
        let frame = spec.add_frame(&b.name, id, Vector3::zeros(), i3);
        frames.insert(b.name.clone(), frame);
        if point_mass {
            point_frames.insert(frame, b.name.clone());
        }
        if abstract_bodies.last() == Some(&true) {
            abstract_frames.insert(frame, b.name.clone());
        }
        bodies.push(BodyInfo {
            name: b.name.clone(),
            id,
            frame,
            geometry,
        });
    }
    let regular_bodies = bodies.len();
    let se = crate::superelements::add_superelement_beams(&ctx, &mf, &mut spec, &mut frames)?;
    for info in &se.bodies {
        abstract_frames.insert(info.frame, info.name.clone());
        abstract_bodies.push(true);
    }
    bodies.extend(se.bodies.iter().cloned());
    let body_names: Vec<&str> = bodies.iter().map(|b| b.name.as_str()).collect();
    for (i, f) in mf.frame.iter().enumerate() {
        let p = format!("frame[{i}]");
        let rotation = match &f.orientation {
            Some(o) => orientation(&ctx, o, &format!("{p}.orientation"))?,
            None => i3,
        };
        let id = if f.body == "ground" {
            if f.node.is_some() || f.nearest.is_some() || f.interface.is_some() {
                return Err(ctx.err(&p, "ground frames cannot refer to FE nodes or interfaces"));
            }
            let pos = opt_vec(
                &ctx,
                &f.position,
                Dimension::Length,
                &format!("{p}.position"),
            )?;
            spec.add_ground_frame(&f.name, pos, rotation)
        } else if let Some(c) = se.component(&f.body) {
            crate::superelement_output::interface_frame(&ctx, &p, f, c, &se, &mut spec)?
        } else {
            let Some(bi) = bodies.iter().position(|b| b.name == f.body) else {
                return Err(ctx.err(
                    &format!("{p}.body"),
                    format!(
                        "unknown body `{}` (bodies: ground, {})",
                        f.body,
                        body_names.join(", ")
                    ),
                ));
            };
            let body = &bodies[bi];
            if f.node.is_none() && f.nearest.is_none() && f.interface.is_none() {
                let pos = opt_vec(
                    &ctx,
                    &f.position,
                    Dimension::Length,
                    &format!("{p}.position"),
                )?;
                let id = spec.add_frame(&f.name, body.id, pos, rotation);
                if point_frames.values().any(|n| n == &f.body) {
                    point_frames.insert(id, f.body.clone());
                }
                if abstract_bodies[bi] {
                    abstract_frames.insert(id, f.body.clone());
                }
                id
            } else {
                if let Some(message) = se.segment_node_frame_message(&f.body) {
                    return Err(ctx.err(&p, message));
                }
                let g = &body.geometry;
                let n = crate::fe_frames::frame_node(&ctx, &p, f, g)?;
                let id = spec.add_oriented_node_frame(
                    &f.name,
                    body.id,
                    n,
                    Vector3::from(g.points[n]),
                    rotation,
                );
                node_frames.insert(id, (bi, n));
                id
            }
        };
        frames.insert(f.name.clone(), id);
    }
    let known = || {
        let mut v: Vec<&str> = frames.keys().map(|s| s.as_str()).collect();
        v.sort();
        v.join(", ")
    };
    let frame = |name: &str, path: String| -> Result<FrameId, SimError> {
        frames.get(name).copied().ok_or_else(|| {
            ctx.err(
                &path,
                format!("unknown frame `{name}` (frames: {})", known()),
            )
        })
    };
    let mut joint_rows = Vec::new();
    let mut joint_refs = Vec::new();
    let mut drives = Vec::new();
    for (i, j) in mf.joint.iter().enumerate() {
        let p = format!("joint[{i}]");
        let (a, b) = (
            frame(&j.a, format!("{p}.a"))?,
            frame(&j.b, format!("{p}.b"))?,
        );
        for (side, name, id) in [("a", &j.a, a), ("b", &j.b, b)] {
            if let Some(body) = abstract_frames.get(&id) {
                let message = se.floating_frame_joint_message(name, body);
                return Err(ctx.err(
                    &format!("{p}.{side}"),
                    message.unwrap_or_else(|| floating_frame_joint_message(name, body)),
                ));
            }
        }
        let mut joint = match j.kind {
            JointType::Fixed => Joint::fixed(&j.name, a, b),
            JointType::Revolute => Joint::revolute(&j.name, a, b),
            JointType::Spherical => Joint::spherical(&j.name, a, b),
            JointType::Prismatic => Joint::prismatic(&j.name, a, b),
            JointType::Cylindrical => Joint::cylindrical(&j.name, a, b),
            JointType::Generic => {
                let list = j.locked.as_ref().ok_or_else(|| {
                    ctx.err(
                        &p,
                        "a generic joint needs `locked` (any of tx ty tz rx ry rz)",
                    )
                })?;
                let mut mask = [false; 6];
                for (k, d) in list.iter().enumerate() {
                    let idx = DOFS.iter().position(|x| x == d).ok_or_else(|| {
                        ctx.err(
                            &format!("{p}.locked[{k}]"),
                            format!("unknown DOF `{d}` (use tx, ty, tz, rx, ry, rz)"),
                        )
                    })?;
                    mask[idx] = true;
                }
                Joint::new(&j.name, a, b, mask)
            }
        };
        if j.kind != JointType::Generic && j.locked.is_some() {
            return Err(ctx.err(
                &format!("{p}.locked"),
                "`locked` is only used by generic joints",
            ));
        }
        let motions = [
            j.angle.is_some(),
            j.angular_velocity.is_some(),
            j.displacement.is_some(),
        ];
        if motions.iter().filter(|&&m| m).count() > 1 {
            return Err(ctx.err(
                &p,
                "give at most one of `angle`, `angular_velocity`, `displacement`",
            ));
        }
        if j.initial_angle.is_some() && j.angular_velocity.is_none() {
            return Err(ctx.err(
                &format!("{p}.initial_angle"),
                "`initial_angle` needs `angular_velocity`",
            ));
        }
        let free = |d: usize, what: &str| {
            if joint.locked[d] {
                Err(ctx.err(
                    &format!("{p}.{what}"),
                    format!(
                        "the joint locks `{}`: prescribed motion needs it free",
                        DOFS[d]
                    ),
                ))
            } else {
                Ok(())
            }
        };
        let prescribed = if let Some(f) = &j.angle {
            free(5, "angle")?;
            Some(PrescribedMotion::RevoluteAngle(time_function(
                &ctx,
                f,
                Dimension::Angle,
                &format!("{p}.angle"),
            )?))
        } else if let Some(f) = &j.angular_velocity {
            free(5, "angular_velocity")?;
            let initial_angle = match &j.initial_angle {
                Some(q) => ctx.q(q, Dimension::Angle, &format!("{p}.initial_angle"))?,
                None => 0.0,
            };
            let rate = time_function(
                &ctx,
                f,
                Dimension::AngularVelocity,
                &format!("{p}.angular_velocity"),
            )?;
            Some(PrescribedMotion::RevoluteRate {
                initial_angle,
                rate,
            })
        } else if let Some(f) = &j.displacement {
            free(0, "displacement")?;
            Some(PrescribedMotion::PrismaticDisplacement(time_function(
                &ctx,
                f,
                Dimension::Length,
                &format!("{p}.displacement"),
            )?))
        } else {
            None
        };
        if let Some(m) = &prescribed {
            let (key, f, level) = match m {
                PrescribedMotion::RevoluteAngle(f) => {
                    ("angle", f, DriveLevel::Position { unit: "rad" })
                }
                PrescribedMotion::RevoluteRate { rate, .. } => {
                    ("angular_velocity", rate, DriveLevel::Rate)
                }
                PrescribedMotion::PrismaticDisplacement(f) => {
                    ("displacement", f, DriveLevel::Position { unit: "m" })
                }
            };
            drives.push((format!("{p}.{key}"), j.name.clone(), f.clone(), level));
        }
        joint.prescribed = prescribed;
        // a driven revolute joint locks its rz through the drive row
        if joint.locked[3..].iter().any(|&l| l) || j.angle.is_some() || j.angular_velocity.is_some()
        {
            for (side, name, id) in [("a", &j.a, a), ("b", &j.b, b)] {
                if let Some(body) = point_frames.get(&id) {
                    let path = format!("{p}.{side}");
                    let user = RotationalUse::Joint(&j.name);
                    refuse_rotation_on_point_mass(&ctx, &path, user, name, body)?;
                }
                if let Some(&(bi, n)) = node_frames.get(&id) {
                    check_rotation_lock_at_node(
                        &ctx,
                        &format!("{p}.{side}"),
                        RotationUse::Joint(&j.name),
                        name,
                        &bodies[bi].name,
                        &bodies[bi].geometry,
                        n,
                    )?;
                }
            }
        }
        joint_rows.push(joint.num_rows());
        joint_refs.push(crate::forces::JointRef::of(&joint));
        spec.add_joint(joint);
    }
    check_forces_on_point_masses(&ctx, &mf, &frames, &point_frames)?;
    crate::forces::add_forces(&ctx, &mf.force, &mut spec, &frame, &joint_refs)?;
    // `fixed` interface points of superelement beams, after the file's joints
    let mut fixed_joint_names = Vec::new();
    for j in &se.fixed {
        fixed_joint_names.push((j.joint.name.clone(), j.joint.num_rows()));
        spec.add_joint(j.joint.clone());
    }
    let mut free_length_from_initial = Vec::new();
    for (i, l) in mf.load.iter().enumerate() {
        let p = format!("load[{i}]");
        let present = [
            ("frame", l.frame.is_some()),
            ("vector", l.vector.is_some()),
            ("time", l.time.is_some()),
            ("coordinates", l.coordinates != CoordinatesName::Global),
            ("a", l.a.is_some()),
            ("b", l.b.is_some()),
            ("stiffness", l.stiffness.is_some()),
            ("damping", l.damping.is_some()),
            ("free_length", l.free_length.is_some()),
        ];
        let load = match l.kind {
            LoadType::Force | LoadType::Torque => {
                ctx.only(
                    &p,
                    "a force or torque",
                    &present,
                    &["frame", "vector", "time", "coordinates"],
                )?;
                let f = l
                    .frame
                    .as_ref()
                    .ok_or_else(|| ctx.err(&p, "needs `frame`"))?;
                let frame = frame(f, format!("{p}.frame"))?;
                if let (LoadType::Torque, Some(body)) = (l.kind, point_frames.get(&frame)) {
                    let path = format!("{p}.frame");
                    refuse_rotation_on_point_mass(&ctx, &path, RotationalUse::Torque, f, body)?;
                }
                if let (LoadType::Torque, Some(&(bi, n))) = (l.kind, node_frames.get(&frame)) {
                    check_rotation_lock_at_node(
                        &ctx,
                        &format!("{p}.frame"),
                        RotationUse::Torque,
                        f,
                        &bodies[bi].name,
                        &bodies[bi].geometry,
                        n,
                    )?;
                }
                let v = l
                    .vector
                    .as_ref()
                    .ok_or_else(|| ctx.err(&p, "needs `vector`"))?;
                let dim = if l.kind == LoadType::Force {
                    Dimension::Force
                } else {
                    Dimension::Torque
                };
                let vector = ctx.vec3(v, dim, &format!("{p}.vector"))?;
                let time = match &l.time {
                    Some(t) => {
                        time_function(&ctx, t, Dimension::Dimensionless, &format!("{p}.time"))?
                    }
                    None => TimeFunction::Constant(1.0),
                };
                let coordinates = match l.coordinates {
                    CoordinatesName::Global => LoadCoordinates::Global,
                    CoordinatesName::Body => LoadCoordinates::Frame,
                };
                if l.kind == LoadType::Force {
                    Load::Force {
                        frame,
                        vector,
                        time,
                        coordinates,
                    }
                } else {
                    Load::Torque {
                        frame,
                        vector,
                        time,
                        coordinates,
                    }
                }
            }
            LoadType::SpringDamper => {
                ctx.only(
                    &p,
                    "a spring-damper",
                    &present,
                    &["a", "b", "stiffness", "damping", "free_length"],
                )?;
                let (Some(a), Some(b)) = (&l.a, &l.b) else {
                    return Err(ctx.err(&p, "a spring-damper needs frames `a` and `b`"));
                };
                let (frame_a, frame_b) = (frame(a, format!("{p}.a"))?, frame(b, format!("{p}.b"))?);
                let nonneg = |q: &Option<Quantity>,
                              dim,
                              key: &str,
                              required: bool|
                 -> Result<f64, SimError> {
                    let path = format!("{p}.{key}");
                    match q {
                        None if required => {
                            Err(ctx.err(&p, format!("a spring-damper needs `{key}`")))
                        }
                        None => Ok(0.0),
                        Some(q) => {
                            let v = ctx.q(q, dim, &path)?;
                            if v < 0.0 {
                                return Err(ctx.err(&path, format!("must be >= 0, got {v}")));
                            }
                            Ok(v)
                        }
                    }
                };
                Load::SpringDamper {
                    frame_a,
                    frame_b,
                    stiffness: nonneg(&l.stiffness, Dimension::Stiffness, "stiffness", true)?,
                    damping: nonneg(&l.damping, Dimension::Damping, "damping", false)?,
                    // absent: the distance of `a` and `b` in the initial state, set below
                    free_length: nonneg(&l.free_length, Dimension::Length, "free_length", false)?,
                }
            }
        };
        let id = spec.add_load(load);
        if matches!(l.kind, LoadType::SpringDamper) && l.free_length.is_none() {
            free_length_from_initial.push(id);
        }
    }
    let regular = mf
        .body
        .iter()
        .enumerate()
        .filter(|(_, b)| !b.is_superelement());
    for ((i, b), info) in regular.zip(&bodies[..regular_bodies]) {
        let p = format!("body[{i}]");
        let pos = opt_vec(
            &ctx,
            &b.position,
            Dimension::Length,
            &format!("{p}.position"),
        )?;
        let rot = match &b.orientation {
            Some(o) => orientation(&ctx, o, &format!("{p}.orientation"))?,
            None => i3,
        };
        spec.set_initial_pose(info.id, pos, rot);
        let v = opt_vec(
            &ctx,
            &b.velocity,
            Dimension::Velocity,
            &format!("{p}.velocity"),
        )?;
        let w = opt_vec(
            &ctx,
            &b.angular_velocity,
            Dimension::AngularVelocity,
            &format!("{p}.angular_velocity"),
        )?;
        spec.set_initial_velocity(info.id, v, w);
        crate::initial::set_initial_modal(&ctx, &mut spec, b, info, &p)?;
    }
    for id in free_length_from_initial {
        spec.set_spring_unstressed_initially(id);
    }
    let owner = |name: &str, path: String| -> Result<crate::contacts::FlexibleOwner, SimError> {
        let info = bodies.iter().find(|b| b.name == name);
        let segment = se.contour_nodes.get(name);
        match (info, contour_bodies.get(name), segment) {
            (Some(info), Some(body), _) => Ok(crate::contacts::FlexibleOwner {
                frame: info.frame,
                body,
                node_ids: &info.geometry.node_ids,
                points: &info.geometry.points,
            }),
            (Some(info), None, Some(seg)) => Ok(crate::contacts::FlexibleOwner {
                frame: info.frame,
                body: &seg.table,
                node_ids: &seg.ids,
                points: &seg.points,
            }),
            (Some(_), None, None) => Err(ctx.err(
                &path,
                format!(
                    "`{name}` has no neutral contours (a rigid body or point mass): flexible \
                     contours need an ffr body, a superelement of a superelement_beam \
                     (`<beam>.s<k>`) or an FE-file superelement"
                ),
            )),
            (None, _, _) => Err(ctx.err(
                &path,
                format!("unknown body `{name}` (bodies: {})", body_names.join(", ")),
            )),
        }
    };
    crate::contacts::add_contacts(&ctx, &mf.contact, &frame, &owner, &mut spec)?;
    let has_joints = spec_has_joints(&mf) || !se.fixed.is_empty();
    let solver = solver_config(&ctx, &mf, &has_joints)?;
    let static_start = mf.solver.initial == Some(crate::schema::InitialName::Static);
    crate::contacts::check_contact_solver(&ctx, &mf.contact, &solver, static_start)?;
    crate::stiffening::check_load_stiffening_solver(&ctx, &mf.body, &solver)?;
    let model = spec.compile().map_err(|source| {
        if let ModelError::InvalidContact { contact, reason } = &source {
            if let Some(i) = mf.contact.iter().position(|c| &c.name == contact) {
                return ctx.err(&format!("contact[{i}]"), reason.clone());
            }
        }
        if let ModelError::SameOwner { item } = &source {
            let joint = mf.joint.iter().position(|j| &j.name == item);
            if let Some(i) = joint {
                return ctx.err(&format!("joint[{i}].b"), format!("joint `{item}`: frames `a` and `b` belong to the same body (or both to ground); a joint connects two different bodies"));
            }
        }
        SimError::Engine {
            file: file.to_path_buf(),
            source,
        }
    })?;
    let mut initial = model.initial_state();
    let mut restart_angles = Vec::new();
    if let Some(r) = &mf.solver.restart {
        crate::initial::check_restart_allowed(&ctx, &mf, &solver)?;
        let t_end = solver.t_end();
        restart_angles =
            crate::restart::apply_restart(&ctx, r, base, &model, &bodies, t_end, &mut initial)?;
    }
    for (i, info) in bodies.iter().enumerate() {
        let (q, u) = model.body_coordinates(info.id, &initial.q, &initial.u);
        if q.iter().chain(u.iter()).any(|x| !x.is_finite()) {
            return Err(ctx.err(&format!("body[{i}].orientation"), "this orientation is singular for Cardan angles (beta = +-90 deg): use rotation = \"quaternion\""));
        }
    }
    let initial_static = mf.solver.initial == Some(crate::schema::InitialName::Static);
    if initial_static {
        crate::initial::check_static_start(&ctx, &mf)?;
    }
    // statics solves g = 0 itself (and sets u = 0): a roughly placed start is legitimate there
    if !matches!(solver, SolverConfig::Statics { .. }) && !initial_static {
        crate::initial::check_initial_assembly(&ctx, &model, &initial)?;
    }
    let joint_names: Vec<(String, usize)> = mf
        .joint
        .iter()
        .zip(&joint_rows)
        .map(|(j, &r)| (j.name.clone(), r))
        .chain(fixed_joint_names)
        .collect();
    let swapped = crate::contacts::swapped_contacts(&mf.contact, &model);
    let signals = parse_signals(
        &ctx,
        &mf.output.signals,
        &model,
        &frames,
        &bodies,
        &joint_names,
        &swapped,
    )?;
    let output = output_config(&ctx, &mf, &model, &bodies, &signals)?;
    let row_values = 10 + model.nq + model.nu + model.nc + crate::signals::signal_width(&signals);
    crate::config::check_output_size(&ctx, &solver, &output, row_values)?;
    let mut warnings = Vec::new();
    // statics has no velocities or accelerations to spoil
    if !matches!(solver, SolverConfig::Statics { .. }) {
        for (path, joint, f, level) in &drives {
            let t_end = Some(solver.t_end());
            check_drive_smoothness(&ctx, path, joint, f, *level, t_end, &mut warnings)?;
        }
    }
    Ok(CompiledModel {
        name: mf.model.name.clone(),
        file: file.to_path_buf(),
        model,
        initial,
        solver,
        linear_solver: crate::config::linear_solver(&mf),
        output,
        bodies,
        signals,
        stiffened,
        warnings,
        initial_static,
        text: text.to_string(),
        restart_angles,
    })
}

/// Force elements that act on rotations at a point mass's frame: a bushing with rotational
/// stiffness or damping, a joint-axis element on the rotation axis of a joint at a point mass.
fn check_forces_on_point_masses(
    ctx: &Ctx,
    mf: &ModelFile,
    frames: &HashMap<String, FrameId>,
    point_frames: &HashMap<FrameId, String>,
) -> Result<(), SimError> {
    use crate::forces::{AxisName, ForceType};
    let on_point = |name: &Option<String>| {
        name.as_ref()
            .and_then(|n| frames.get(n))
            .and_then(|id| point_frames.get(id).map(|b| (n_of(name), b.clone())))
    };
    fn n_of(name: &Option<String>) -> String {
        name.clone().unwrap_or_default()
    }
    for (i, f) in mf.force.iter().enumerate() {
        let sides: Vec<(String, Option<String>)> = match f.kind {
            ForceType::Bushing
                if f.rotational_stiffness.is_some() || f.rotational_damping.is_some() =>
            {
                vec![("a".into(), f.a.clone()), ("b".into(), f.b.clone())]
            }
            ForceType::Bushing => Vec::new(),
            _ if f.axis == Some(AxisName::Rotation) || f.axis.is_none() => {
                let joint = mf.joint.iter().find(|j| Some(&j.name) == f.joint.as_ref());
                joint.map_or_else(Vec::new, |j| {
                    vec![
                        ("joint".into(), Some(j.a.clone())),
                        ("joint".into(), Some(j.b.clone())),
                    ]
                })
            }
            _ => Vec::new(),
        };
        for (key, frame) in sides {
            if let Some((frame, body)) = on_point(&frame) {
                let path = format!("force[{i}].{key}");
                let user = RotationalUse::Force(&f.name);
                refuse_rotation_on_point_mass(ctx, &path, user, &frame, &body)?;
            }
        }
    }
    Ok(())
}

/// DOF names in mask order.
pub const DOFS: [&str; 6] = ["tx", "ty", "tz", "rx", "ry", "rz"];

fn spec_has_joints(mf: &ModelFile) -> bool {
    !mf.joint.is_empty()
}

/// Unique names across bodies, frames and joints; `ground` is reserved. The model name must be a
/// plain file name (it names the animation and CSV files).
fn check_names(ctx: &Ctx, mf: &ModelFile) -> Result<(), SimError> {
    let model = &mf.model.name;
    if !crate::config::is_plain_file_stem(model) {
        return Err(ctx.err(
            "model.name",
            format!(
                "invalid model name `{model}`: {}",
                crate::config::PLAIN_FILE_STEM
            ),
        ));
    }
    let mut seen: HashMap<&str, String> = HashMap::new();
    let items = mf
        .body
        .iter()
        .enumerate()
        .map(|(i, b)| (b.name.as_str(), format!("body[{i}].name")))
        .chain(
            mf.frame
                .iter()
                .enumerate()
                .map(|(i, f)| (f.name.as_str(), format!("frame[{i}].name"))),
        )
        .chain(
            mf.joint
                .iter()
                .enumerate()
                .map(|(i, j)| (j.name.as_str(), format!("joint[{i}].name"))),
        )
        .chain(
            mf.force
                .iter()
                .enumerate()
                .map(|(i, f)| (f.name.as_str(), format!("force[{i}].name"))),
        );
    for (name, path) in items {
        if name == "ground" || name.is_empty() || name.contains(['.', '/']) {
            return Err(ctx.err(
                &path,
                format!("invalid name `{name}` (`ground` is reserved; no `.` or `/`)"),
            ));
        }
        if let Some(first) = seen.get(name) {
            return Err(ctx.err(
                &path,
                format!("duplicate name `{name}` (first used at `{first}`)"),
            ));
        }
        seen.insert(name, path);
    }
    Ok(())
}

fn opt_vec(
    ctx: &Ctx,
    v: &Option<[Quantity; 3]>,
    dim: Dimension,
    path: &str,
) -> Result<Vector3<f64>, SimError> {
    v.as_ref()
        .map_or(Ok(Vector3::zeros()), |v| ctx.vec3(v, dim, path))
}

/// Why a joint may not attach to a frame fixed in the floating frame of an ffr body whose modes
/// do not clamp that frame (see `FfrBody::floating_frame_is_material`).
fn floating_frame_joint_message(frame: &str, body: &str) -> String {
    format!(
        "frame `{frame}` is fixed in the floating frame of ffr body `{body}`, whose modes do not \
         clamp it (free-free or interface modes: the floating frame is then, to first order, a \
         mean-axis frame, not a material point), so a joint there would constrain an abstract \
         frame and miss the body's compliance at the joint: attach the joint to an FE node of \
         `{body}` (frame `node` or `nearest`), or reduce `{body}` with modes clamped at the joint \
         (`[body.boundary] fixed`)"
    )
}

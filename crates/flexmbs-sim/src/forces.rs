//! `[[force]]`: force elements of the model file (joint spring-dampers, bushings, servos, joint
//! friction), compiled to [`flexmbs_core::force`] elements.

use crate::compile::Ctx;
use crate::config::time_function;
use crate::error::SimError;
use crate::schema::TimeSpec;
use crate::units::{Dimension, Quantity};
use flexmbs_core::force::{
    add_joint_servo, Bushing, ForceElementRef, JointAxis, JointFriction, JointServo,
    JointSpringDamper, ServoGains,
};
use flexmbs_core::{FrameId, Joint, Load, ModelSpec};
use nalgebra::{Matrix6, Vector6};
use serde::Deserialize;

/// Force element types.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ForceType {
    /// Spring-damper on a joint's free axis.
    JointSpring,
    /// 6-DOF bushing between two frames.
    Bushing,
    /// PD/PID servo on a joint's free axis.
    Servo,
    /// Regularized Coulomb friction on a joint's free axis.
    Friction,
}

/// Which free axis of the joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AxisName {
    /// Rotation about z of frame a.
    Rotation,
    /// Translation along x of frame a.
    Translation,
}

/// `[[force]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForceSpec {
    /// Unique name.
    pub name: String,
    /// Type.
    #[serde(rename = "type")]
    pub kind: ForceType,
    /// The joint (joint-spring, servo, friction).
    pub joint: Option<String>,
    /// The joint's axis, if it has both a free rotation about z and a free translation along x.
    pub axis: Option<AxisName>,
    /// First frame (bushing).
    pub a: Option<String>,
    /// Second frame (bushing).
    pub b: Option<String>,
    /// Stiffness (joint-spring).
    pub stiffness: Option<Quantity>,
    /// Damping (joint-spring), default 0.
    pub damping: Option<Quantity>,
    /// Unstressed coordinate (joint-spring, default 0) or reference motion (servo, required).
    pub reference: Option<TimeSpec>,
    /// Preload (joint-spring), default 0.
    pub preload: Option<Quantity>,
    /// Bushing stiffness along x, y, z of frame a.
    pub translational_stiffness: Option<[Quantity; 3]>,
    /// Bushing stiffness about x, y, z of frame a.
    pub rotational_stiffness: Option<[Quantity; 3]>,
    /// Bushing damping along x, y, z.
    pub translational_damping: Option<[Quantity; 3]>,
    /// Bushing damping about x, y, z.
    pub rotational_damping: Option<[Quantity; 3]>,
    /// Servo proportional gain.
    pub kp: Option<Quantity>,
    /// Servo integral gain (SI number: N m/(rad s) or N/(m s)), default 0.
    pub ki: Option<f64>,
    /// Servo derivative gain, default 0.
    pub kd: Option<Quantity>,
    /// Lag of the servo's integrator (time), default 1 ms.
    pub integral_lag: Option<Quantity>,
    /// Friction torque or force at sliding.
    pub friction: Option<Quantity>,
    /// Slip velocity of the regularized friction.
    pub slip_velocity: Option<Quantity>,
}

/// Default lag of a servo's integrator (s).
pub const DEFAULT_INTEGRAL_LAG: f64 = 1e-3;

/// A compiled joint for the force elements: name, frames, locked mask.
pub struct JointRef {
    /// Name.
    pub name: String,
    /// Frame a.
    pub a: FrameId,
    /// Frame b.
    pub b: FrameId,
    /// Locked DOFs `[tx ty tz rx ry rz]` (a prescribed motion locks its axis too).
    pub locked: [bool; 6],
}

impl JointRef {
    /// From a compiled joint.
    pub fn of(j: &Joint) -> Self {
        let mut locked = j.locked;
        match &j.prescribed {
            Some(flexmbs_core::PrescribedMotion::PrismaticDisplacement(_)) => locked[0] = true,
            Some(_) => locked[5] = true,
            None => {}
        }
        Self {
            name: j.name.clone(),
            a: j.frame_a,
            b: j.frame_b,
            locked,
        }
    }
}

/// Adds the `[[force]]` elements to `spec`. `frame` resolves a frame name (with a located
/// error), `joints` are the model's joints.
pub fn add_forces(
    ctx: &Ctx,
    forces: &[ForceSpec],
    spec: &mut ModelSpec,
    frame: &dyn Fn(&str, String) -> Result<FrameId, SimError>,
    joints: &[JointRef],
) -> Result<(), SimError> {
    for (i, f) in forces.iter().enumerate() {
        let p = format!("force[{i}]");
        let load = match f.kind {
            ForceType::Bushing => bushing(ctx, &p, f, frame)?,
            _ => {
                let (a, b, axis) = joint_axis(ctx, &p, f, joints)?;
                match f.kind {
                    ForceType::JointSpring => joint_spring(ctx, &p, f, [a, b], axis)?,
                    ForceType::Friction => friction(ctx, &p, f, [a, b], axis)?,
                    _ => {
                        servo(ctx, &p, f, [a, b], axis, spec)?;
                        continue;
                    }
                }
            }
        };
        spec.add_load(load);
    }
    Ok(())
}

/// The keys present in `f`.
fn present(f: &ForceSpec) -> [(&'static str, bool); 18] {
    [
        ("joint", f.joint.is_some()),
        ("axis", f.axis.is_some()),
        ("a", f.a.is_some()),
        ("b", f.b.is_some()),
        ("stiffness", f.stiffness.is_some()),
        ("damping", f.damping.is_some()),
        ("reference", f.reference.is_some()),
        ("preload", f.preload.is_some()),
        (
            "translational_stiffness",
            f.translational_stiffness.is_some(),
        ),
        ("rotational_stiffness", f.rotational_stiffness.is_some()),
        ("translational_damping", f.translational_damping.is_some()),
        ("rotational_damping", f.rotational_damping.is_some()),
        ("kp", f.kp.is_some()),
        ("ki", f.ki.is_some()),
        ("kd", f.kd.is_some()),
        ("integral_lag", f.integral_lag.is_some()),
        ("friction", f.friction.is_some()),
        ("slip_velocity", f.slip_velocity.is_some()),
    ]
}

/// The frames and axis of the joint `f.joint`: `axis` if given (that DOF must be free), else
/// the free rotation about z, else the free translation along x.
fn joint_axis(
    ctx: &Ctx,
    p: &str,
    f: &ForceSpec,
    joints: &[JointRef],
) -> Result<(FrameId, FrameId, JointAxis), SimError> {
    let Some(name) = &f.joint else {
        return Err(ctx.err(p, "needs `joint` (the joint whose free axis it acts on)"));
    };
    let Some(j) = joints.iter().find(|j| &j.name == name) else {
        let names: Vec<&str> = joints.iter().map(|j| j.name.as_str()).collect();
        return Err(ctx.err(
            &format!("{p}.joint"),
            format!("unknown joint `{name}` (joints: {})", names.join(", ")),
        ));
    };
    let (rot_free, tr_free) = (!j.locked[5], !j.locked[0]);
    let axis = match f.axis {
        Some(AxisName::Rotation) if rot_free => JointAxis::Rotation,
        Some(AxisName::Translation) if tr_free => JointAxis::Translation,
        Some(a) => {
            return Err(ctx.err(
                &format!("{p}.axis"),
                format!("joint `{name}` locks the {a:?} axis (rz or tx), or a drive does"),
            ))
        }
        None if rot_free && tr_free => {
            return Err(ctx.err(
                p,
                format!("joint `{name}` has a free rotation about z and a free translation along x: give `axis = \"rotation\"` or `\"translation\"`"),
            ))
        }
        None if rot_free => JointAxis::Rotation,
        None if tr_free => JointAxis::Translation,
        None => {
            return Err(ctx.err(
                &format!("{p}.joint"),
                format!("joint `{name}` has neither a free rotation about z (revolute, cylindrical) nor a free translation along x (prismatic) without a drive"),
            ))
        }
    };
    Ok((j.a, j.b, axis))
}

/// Dimensions of a joint axis: coordinate, generalized force, stiffness, damping, velocity.
fn dims(axis: JointAxis) -> [Dimension; 5] {
    match axis {
        JointAxis::Rotation => [
            Dimension::Angle,
            Dimension::Torque,
            Dimension::RotationalStiffness,
            Dimension::RotationalDamping,
            Dimension::AngularVelocity,
        ],
        JointAxis::Translation => [
            Dimension::Length,
            Dimension::Force,
            Dimension::Stiffness,
            Dimension::Damping,
            Dimension::Velocity,
        ],
    }
}

/// An optional quantity, `>= 0` (default `default`).
fn nonneg(
    ctx: &Ctx,
    p: &str,
    key: &str,
    q: &Option<Quantity>,
    dim: Dimension,
    default: Option<f64>,
) -> Result<f64, SimError> {
    let path = format!("{p}.{key}");
    let v = match (q, default) {
        (Some(q), _) => ctx.q(q, dim, &path)?,
        (None, Some(d)) => return Ok(d),
        (None, None) => return Err(ctx.err(p, format!("needs `{key}`"))),
    };
    if v < 0.0 {
        return Err(ctx.err(&path, format!("must be >= 0, got {v}")));
    }
    Ok(v)
}

fn element(e: impl flexmbs_core::force::ForceElement + 'static) -> Load {
    Load::Element(ForceElementRef::new(e))
}

fn joint_spring(
    ctx: &Ctx,
    p: &str,
    f: &ForceSpec,
    frames: [FrameId; 2],
    axis: JointAxis,
) -> Result<Load, SimError> {
    let allowed = [
        "joint",
        "axis",
        "stiffness",
        "damping",
        "reference",
        "preload",
    ];
    ctx.only(p, "a joint-spring", &present(f), &allowed)?;
    let [x, q, k, d, _] = dims(axis);
    let reference = match &f.reference {
        None => 0.0,
        Some(TimeSpec::Constant(r)) => ctx.q(r, x, &format!("{p}.reference"))?,
        Some(TimeSpec::Function(_)) => {
            return Err(ctx.err(
                &format!("{p}.reference"),
                "a joint-spring's reference is a constant (a moving reference is a `servo`)",
            ))
        }
    };
    Ok(element(JointSpringDamper {
        name: f.name.clone(),
        frames,
        axis,
        stiffness: nonneg(ctx, p, "stiffness", &f.stiffness, k, None)?,
        damping: nonneg(ctx, p, "damping", &f.damping, d, Some(0.0))?,
        reference,
        preload: match &f.preload {
            Some(v) => ctx.q(v, q, &format!("{p}.preload"))?,
            None => 0.0,
        },
    }))
}

fn friction(
    ctx: &Ctx,
    p: &str,
    f: &ForceSpec,
    frames: [FrameId; 2],
    axis: JointAxis,
) -> Result<Load, SimError> {
    let allowed = ["joint", "axis", "friction", "slip_velocity"];
    ctx.only(p, "a friction", &present(f), &allowed)?;
    let [_, q, _, _, v] = dims(axis);
    let slip_velocity = nonneg(ctx, p, "slip_velocity", &f.slip_velocity, v, None)?;
    if slip_velocity == 0.0 {
        return Err(ctx.err(&format!("{p}.slip_velocity"), "must be > 0"));
    }
    Ok(element(JointFriction {
        name: f.name.clone(),
        frames,
        axis,
        coulomb: nonneg(ctx, p, "friction", &f.friction, q, None)?,
        slip_velocity,
    }))
}

fn servo(
    ctx: &Ctx,
    p: &str,
    f: &ForceSpec,
    frames: [FrameId; 2],
    axis: JointAxis,
    spec: &mut ModelSpec,
) -> Result<(), SimError> {
    let allowed = [
        "joint",
        "axis",
        "reference",
        "kp",
        "ki",
        "kd",
        "integral_lag",
    ];
    ctx.only(p, "a servo", &present(f), &allowed)?;
    let [x, _, k, d, _] = dims(axis);
    let Some(r) = &f.reference else {
        return Err(ctx.err(p, "a servo needs `reference` (the motion to follow)"));
    };
    let reference = time_function(ctx, r, x, &format!("{p}.reference"))?;
    let ki = f.ki.unwrap_or(0.0);
    if !(ki.is_finite() && ki >= 0.0) {
        return Err(ctx.err(&format!("{p}.ki"), format!("must be >= 0, got {ki}")));
    }
    let lag = nonneg(
        ctx,
        p,
        "integral_lag",
        &f.integral_lag,
        Dimension::Time,
        Some(DEFAULT_INTEGRAL_LAG),
    )?;
    if lag == 0.0 {
        return Err(ctx.err(&format!("{p}.integral_lag"), "must be > 0"));
    }
    if f.integral_lag.is_some() && ki == 0.0 {
        return Err(ctx.err(&format!("{p}.integral_lag"), "needs `ki` > 0"));
    }
    let servo = JointServo {
        name: f.name.clone(),
        frames: frames.to_vec(),
        axis,
        reference,
        gains: ServoGains {
            kp: nonneg(ctx, p, "kp", &f.kp, k, None)?,
            ki,
            kd: nonneg(ctx, p, "kd", &f.kd, d, Some(0.0))?,
        },
    };
    add_joint_servo(spec, servo, lag);
    Ok(())
}

fn bushing(
    ctx: &Ctx,
    p: &str,
    f: &ForceSpec,
    frame: &dyn Fn(&str, String) -> Result<FrameId, SimError>,
) -> Result<Load, SimError> {
    let allowed = [
        "a",
        "b",
        "translational_stiffness",
        "rotational_stiffness",
        "translational_damping",
        "rotational_damping",
    ];
    ctx.only(p, "a bushing", &present(f), &allowed)?;
    let (Some(a), Some(b)) = (&f.a, &f.b) else {
        return Err(ctx.err(p, "a bushing needs frames `a` and `b`"));
    };
    let (a, b) = (frame(a, format!("{p}.a"))?, frame(b, format!("{p}.b"))?);
    let diag = |key: &str, v: &Option<[Quantity; 3]>, dim| -> Result<[f64; 3], SimError> {
        let Some(v) = v else {
            return Ok([0.0; 3]);
        };
        let path = format!("{p}.{key}");
        let x = ctx.vec3(v, dim, &path)?;
        if x.iter().any(|c| *c < 0.0) {
            return Err(ctx.err(&path, format!("must be >= 0, got {:?}", x.as_slice())));
        }
        Ok([x[0], x[1], x[2]])
    };
    let kt = diag(
        "translational_stiffness",
        &f.translational_stiffness,
        Dimension::Stiffness,
    )?;
    let kr = diag(
        "rotational_stiffness",
        &f.rotational_stiffness,
        Dimension::RotationalStiffness,
    )?;
    let dt = diag(
        "translational_damping",
        &f.translational_damping,
        Dimension::Damping,
    )?;
    let dr = diag(
        "rotational_damping",
        &f.rotational_damping,
        Dimension::RotationalDamping,
    )?;
    if f.translational_stiffness.is_none() && f.rotational_stiffness.is_none() {
        return Err(ctx.err(
            p,
            "a bushing needs `translational_stiffness` or `rotational_stiffness`",
        ));
    }
    let six = |t: [f64; 3], r: [f64; 3]| {
        Matrix6::from_diagonal(&Vector6::new(t[0], t[1], t[2], r[0], r[1], r[2]))
    };
    Ok(element(Bushing {
        name: f.name.clone(),
        frames: [a, b],
        stiffness: six(kt, kr),
        damping: six(dt, dr),
    }))
}

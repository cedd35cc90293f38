//! The TOML schema of a multibody model file (reference: `docs/model-file.md`, "Multibody
//! models"). Plain serde structs with `deny_unknown_fields`; variants are flat structs with a
//! `type` key (not internally tagged enums, which would lose key paths and lines of errors).
//! Physical values are [`Quantity`]s, converted to SI by [`crate::compile`].

use crate::units::Quantity;
use flexmbs_fe::UnitSystem;
use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::fmt;
use std::path::PathBuf;

/// A multibody model file. Told apart from an FE body file by the required `[model]` table.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelFile {
    /// Name and gravity.
    pub model: ModelSection,
    /// Integrator or static solver.
    pub solver: SolverSpec,
    /// Bodies (`[[body]]`).
    #[serde(default)]
    pub body: Vec<BodySpec>,
    /// Frames (`[[frame]]`).
    #[serde(default)]
    pub frame: Vec<FrameSpec>,
    /// Joints (`[[joint]]`).
    #[serde(default)]
    pub joint: Vec<JointSpec>,
    /// Loads (`[[load]]`).
    #[serde(default)]
    pub load: Vec<LoadSpec>,
    /// Contacts (`[[contact]]`, `moreau` solver).
    #[serde(default)]
    pub contact: Vec<crate::contacts::ContactSpec>,
    /// `[[force]]` force elements.
    #[serde(default)]
    pub force: Vec<crate::forces::ForceSpec>,
    /// Output selection.
    #[serde(default)]
    pub output: OutputSpec,
}

/// `[model]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelSection {
    /// Model name (results file attribute, animation name).
    pub name: String,
    /// Free text.
    pub description: Option<String>,
    /// Gravitational acceleration (global), default zero.
    pub gravity: Option<[Quantity; 3]>,
}

/// Solver names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SolverType {
    /// Implicit generalized-alpha (index-3 constraints).
    GeneralizedAlpha,
    /// Explicit Dormand-Prince 5(4), unconstrained models only.
    Dopri5,
    /// Static equilibrium with load steps.
    Statics,
    /// Moreau time-stepping (set-valued contacts and impacts), fixed step or adaptive.
    Moreau,
}

/// `[solver]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// Solver type.
    #[serde(rename = "type")]
    pub kind: SolverType,
    /// End time (time integrators).
    pub t_end: Option<Quantity>,
    /// Step size (generalized-alpha fixed step; first step when adaptive).
    pub h: Option<Quantity>,
    /// Spectral radius at infinity (generalized-alpha), default 0.9.
    pub rho_inf: Option<f64>,
    /// Adaptive step control (generalized-alpha).
    pub adaptive: Option<AdaptiveSpec>,
    /// Newton settings (generalized-alpha, statics).
    pub newton: Option<NewtonSpec>,
    /// Relative tolerance (dopri5), default 1e-8.
    pub rtol: Option<f64>,
    /// Absolute tolerance (dopri5), default 1e-10.
    pub atol: Option<f64>,
    /// Largest step (dopri5), default unlimited.
    pub h_max: Option<Quantity>,
    /// Load steps (statics), default 1.
    pub load_steps: Option<usize>,
    /// Linear-solver backend of the system matrices, default `auto`.
    pub linear_solver: Option<LinearSolverName>,
    /// Initial state of a time integration, default `given`.
    pub initial: Option<InitialName>,
    /// Start from a row of an earlier run's results file (time integrators).
    pub restart: Option<RestartSpec>,
}

/// `[solver.restart]`: the results file of an earlier run of a model with the same coordinates
/// and the output time to start from.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RestartSpec {
    /// Results file (`results.h5`), relative to the model file.
    pub results: PathBuf,
    /// Output time to start from, default the last row.
    pub time: Option<Quantity>,
}

/// `solver.initial` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum InitialName {
    /// The bodies' poses and velocities as given.
    Given,
    /// Static equilibrium at t = 0 (under gravity, loads and drives at t = 0), at rest.
    Static,
}

/// `solver.linear_solver` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LinearSolverName {
    /// Dense below a size threshold, sparse above.
    Auto,
    /// Dense LU.
    Dense,
    /// Sparse LU.
    Sparse,
}

/// `[solver.adaptive]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AdaptiveSpec {
    /// Relative position tolerance, default 1e-6.
    pub rtol: Option<f64>,
    /// Absolute position tolerance, default 1e-6.
    pub atol: Option<f64>,
    /// Minimum step, default 1e-12 s.
    pub h_min: Option<Quantity>,
    /// Maximum step, default 0.1 s.
    pub h_max: Option<Quantity>,
    /// Largest penetration of a contact closing in a step (length), default 1e-6 m.
    pub max_penetration: Option<Quantity>,
}

/// `[solver.newton]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NewtonSpec {
    /// Maximum iterations per step, default 25.
    pub max_iterations: Option<usize>,
    /// Relative and absolute increment tolerance, default 1e-10.
    pub tol: Option<f64>,
    /// Tolerance on the position constraints, relative to `max(1, |q|_inf)`, default 1e-12.
    pub constraint_tol: Option<f64>,
    /// Modified Newton (keep the factorized iteration matrix across iterations and steps;
    /// generalized-alpha only), default false.
    pub modified: Option<bool>,
}

/// Body types.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BodyType {
    /// Rigid body.
    Rigid,
    /// Floating-frame-of-reference flexible body.
    Ffr,
    /// A particle: mass only, three translations.
    #[serde(rename = "point_mass")]
    PointMass,
    /// A straight beam split into a chain of superelements.
    #[serde(rename = "superelement_beam")]
    SuperelementBeam,
    /// One superelement from an FE body file ([`crate::superelement_fe_body`]).
    #[serde(rename = "superelement")]
    Superelement,
}

/// Rotation parametrizations.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum RotationName {
    /// Cardan angles x-y-z (default).
    #[default]
    Cardan,
    /// Unit quaternion (no singularity).
    Quaternion,
}

/// `[[body]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Unique name (also the name of the body's reference frame).
    pub name: String,
    /// `rigid` or `ffr`.
    #[serde(rename = "type")]
    pub kind: BodyType,
    /// Mass (rigid).
    pub mass: Option<Quantity>,
    /// Principal moments of inertia about the centre of mass (rigid), or the mass model
    /// `"lumped"` / `"consistent"` of the inertia invariants (ffr, default lumped).
    pub inertia: Option<InertiaSpec>,
    /// Full inertia tensor about the centre of mass in body axes (rigid).
    pub inertia_matrix: Option<[[Quantity; 3]; 3]>,
    /// Edge lengths of the box drawn in the animation (rigid; default from the inertia).
    #[serde(rename = "box")]
    pub box_size: Option<[Quantity; 3]>,
    /// FE model file, `.fmb.h5` body file or seed 4-file folder (ffr), relative to the model file.
    pub source: Option<PathBuf>,
    /// Units of a seed folder (ffr), default SI.
    pub units: Option<UnitSystem>,
    /// Mode count or list of 1-based mode numbers (ffr), default all.
    pub modes: Option<ModeSelection>,
    /// Modal damping (ffr).
    pub damping: Option<DampingSpec>,
    /// Centrifugal geometric stiffening (ffr, FE model-file source with fixed nodes), default
    /// false.
    pub geometric_stiffening: Option<bool>,
    /// Geometric stiffening by the joint reactions and loads at the body's node frames (ffr, FE
    /// model-file source; inertia relief for a free-free body), default false.
    pub load_stiffening: Option<bool>,
    /// Lumped node rotary inertias of a beam mesh (ffr, FE model-file source or a reduced-body
    /// file that stores them in `nodes/rotary_inertia`), default true when available; false
    /// reproduces the translational-only node masses of seed 000/001.
    pub rotary_inertia: Option<bool>,
    /// Rotation parametrization.
    #[serde(default)]
    pub rotation: RotationName,
    /// Initial position of the body reference frame (global).
    pub position: Option<[Quantity; 3]>,
    /// Initial orientation.
    pub orientation: Option<OrientationSpec>,
    /// Initial velocity of the reference frame origin (global).
    pub velocity: Option<[Quantity; 3]>,
    /// Initial angular velocity (global).
    pub angular_velocity: Option<[Quantity; 3]>,
    /// Initial modal coordinates (ffr), one per kept mode, in the units of the mode shapes in SI
    /// (the node displacement is `Σ_k Φ_k q_k` in m). Default 0 (undeformed).
    pub modal_coordinates: Option<Vec<f64>>,
    /// Initial modal velocities (ffr), one per kept mode (units of `modal_coordinates` per
    /// second). Default 0.
    pub modal_velocities: Option<Vec<f64>>,
    /// Beam material `{ e, nu, rho }`, SI (superelement_beam).
    pub material: Option<flexmbs_io::model::MaterialSpec>,
    /// Beam cross-section `{ shape = ... }`, SI (superelement_beam).
    pub section: Option<flexmbs_io::model::SectionSpec>,
    /// Beam theory of the FE elements (superelement_beam), default Euler-Bernoulli.
    pub theory: Option<flexmbs_io::model::TheoryName>,
    /// Beam axis, global (superelement_beam; alternative to `orientation`).
    pub direction: Option<[f64; 3]>,
    /// Total length split into `segments` equal superelements (superelement_beam).
    pub length: Option<Quantity>,
    /// Number of equal superelements (superelement_beam).
    pub segments: Option<usize>,
    /// Lengths of the superelements from the start (superelement_beam).
    pub lengths: Option<Vec<Quantity>>,
    /// FE beam elements per superelement (superelement_beam), default 2.
    pub elements: Option<usize>,
    /// Internal Craig-Bampton modes per superelement (superelement_beam), default 0.
    pub internal_modes: Option<usize>,
    /// Floating-frame location (superelement_beam), default centre of mass.
    pub frame: Option<crate::superelements::FrameName>,
    /// Transformation matrices (superelement_beam), default exact.
    pub matrices: Option<crate::superelements::MatricesName>,
    /// Fictitious forces (superelement_beam), default neglected.
    pub fictitious_forces: Option<crate::superelements::FictitiousName>,
    /// Names of the interface points, start to end (superelement_beam).
    pub interfaces: Option<Vec<String>>,
    /// Interface points clamped to ground (superelement_beam).
    pub fixed: Option<Vec<String>>,
}

impl BodySpec {
    /// A `superelement_beam` or `superelement` body (compiled by [`crate::superelements`]).
    pub fn is_superelement(&self) -> bool {
        matches!(
            self.kind,
            BodyType::SuperelementBeam | BodyType::Superelement
        )
    }
}

/// The `inertia` key: three principal moments (rigid body) or a mass model name (ffr body).
#[derive(Debug, Clone, PartialEq)]
pub enum InertiaSpec {
    /// Principal moments of inertia about the centre of mass (rigid).
    Principal([Quantity; 3]),
    /// Mass model of the inertia invariants (ffr).
    Model(MassModel),
}

/// Mass model of the inertia invariants of an FFR body.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MassModel {
    /// Lumped node masses of the reduced body (seed 000 §2.4, default).
    #[default]
    Lumped,
    /// The full consistent FE mass matrix projected on the rigid fields and modes
    /// (seed 000 §6.2 outlook), from the FE model file or as stored in a reduced-body file.
    Consistent,
}

impl<'de> Deserialize<'de> for InertiaSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = InertiaSpec;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(
                    "three principal moments (rigid body) or \"lumped\" / \"consistent\" (ffr body)",
                )
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<InertiaSpec, E> {
                match v {
                    "lumped" => Ok(InertiaSpec::Model(MassModel::Lumped)),
                    "consistent" => Ok(InertiaSpec::Model(MassModel::Consistent)),
                    _ => Err(E::custom(format!(
                        "unknown mass model \"{v}\": expected \"lumped\" or \"consistent\" \
                         (ffr body), or three principal moments (rigid body)"
                    ))),
                }
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut a: A) -> Result<InertiaSpec, A::Error> {
                let mut v = Vec::with_capacity(3);
                while let Some(x) = a.next_element::<Quantity>()? {
                    v.push(x);
                }
                let n = v.len();
                <[Quantity; 3]>::try_from(v)
                    .map(InertiaSpec::Principal)
                    .map_err(|_| de::Error::invalid_length(n, &"three principal moments"))
            }
        }
        d.deserialize_any(V)
    }
}

/// Mode selection of an FFR body: a count (the first n) or a list of 1-based mode numbers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ModeSelection {
    /// The first n modes.
    Count(usize),
    /// These modes (1-based).
    List(Vec<usize>),
}

impl<'de> Deserialize<'de> for ModeSelection {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = ModeSelection;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a mode count or a list of 1-based mode numbers")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<ModeSelection, E> {
                usize::try_from(v)
                    .map(ModeSelection::Count)
                    .map_err(|_| E::custom(format!("mode count must be >= 0, got {v}")))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<ModeSelection, E> {
                Ok(ModeSelection::Count(v as usize))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut a: A) -> Result<ModeSelection, A::Error> {
                let mut v = Vec::new();
                while let Some(x) = a.next_element::<usize>()? {
                    v.push(x);
                }
                Ok(ModeSelection::List(v))
            }
        }
        d.deserialize_any(V)
    }
}

/// `damping = { rayleigh = [alpha, beta] }` or `{ modal = [zeta, ...] }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DampingSpec {
    /// Rayleigh coefficients `alpha` (1/s) and `beta` (s): `D = alpha M_ff + beta K_ff`.
    pub rayleigh: Option<[f64; 2]>,
    /// Modal damping ratios (one per selected mode, or one for all).
    pub modal: Option<Vec<f64>>,
}

/// An orientation: exactly one of `matrix`, `axis` + `angle`, `cardan`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OrientationSpec {
    /// Rotation matrix, rows (columns = frame axes in the parent).
    pub matrix: Option<[[f64; 3]; 3]>,
    /// Rotation axis (normalized).
    pub axis: Option<[f64; 3]>,
    /// Rotation angle about `axis`.
    pub angle: Option<Quantity>,
    /// Cardan angles x-y-z.
    pub cardan: Option<[Quantity; 3]>,
}

/// `[[frame]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameSpec {
    /// Unique name.
    pub name: String,
    /// Owning body name or `ground`.
    pub body: String,
    /// Position in the body reference frame (global for ground).
    pub position: Option<[Quantity; 3]>,
    /// Orientation relative to the body reference frame.
    pub orientation: Option<OrientationSpec>,
    /// FE node id (ffr bodies): the frame follows this node.
    pub node: Option<u64>,
    /// The FE node nearest to this point (body coordinates) (ffr bodies).
    pub nearest: Option<[Quantity; 3]>,
    /// A named rigid interface of the body's FE model (ffr bodies): the frame follows its node.
    pub interface: Option<String>,
}

/// Joint types.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum JointType {
    /// All six relative DOFs locked.
    Fixed,
    /// Rotation about z of frame a free.
    Revolute,
    /// All rotations free.
    Spherical,
    /// Translation along x of frame a free.
    Prismatic,
    /// Translation along and rotation about z of frame a free.
    Cylindrical,
    /// The DOFs listed in `locked` are locked.
    Generic,
}

/// `[[joint]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointSpec {
    /// Unique name.
    pub name: String,
    /// Joint type.
    #[serde(rename = "type")]
    pub kind: JointType,
    /// First frame (relative motion measured in its axes).
    pub a: String,
    /// Second frame.
    pub b: String,
    /// Locked DOFs of a generic joint: any of `tx ty tz rx ry rz`.
    pub locked: Option<Vec<String>>,
    /// Prescribed relative angle about z (revolute, cylindrical, generic with rz free).
    pub angle: Option<TimeSpec>,
    /// Prescribed relative angular velocity about z.
    pub angular_velocity: Option<TimeSpec>,
    /// Angle at t = 0 with `angular_velocity`, default 0.
    pub initial_angle: Option<Quantity>,
    /// Prescribed relative displacement along x (prismatic).
    pub displacement: Option<TimeSpec>,
}

/// Load types.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum LoadType {
    /// Point force at a frame origin.
    Force,
    /// Torque on a frame.
    Torque,
    /// Linear spring-damper between two frame origins.
    SpringDamper,
}

/// Load vector axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum CoordinatesName {
    /// Global axes (default).
    #[default]
    Global,
    /// Axes of the loaded frame (follower load).
    Body,
}

/// `[[load]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadSpec {
    /// Optional name.
    pub name: Option<String>,
    /// Load type.
    #[serde(rename = "type")]
    pub kind: LoadType,
    /// Loaded frame (force, torque).
    pub frame: Option<String>,
    /// Force (N) or torque (N m) vector at time-function value 1.
    pub vector: Option<[Quantity; 3]>,
    /// Axes of `vector`.
    #[serde(default)]
    pub coordinates: CoordinatesName,
    /// Time function (dimensionless factor), default constant 1.
    pub time: Option<TimeSpec>,
    /// First frame (spring-damper).
    pub a: Option<String>,
    /// Second frame (spring-damper).
    pub b: Option<String>,
    /// Stiffness (spring-damper).
    pub stiffness: Option<Quantity>,
    /// Damping coefficient (spring-damper), default 0.
    pub damping: Option<Quantity>,
    /// Free length (spring-damper).
    pub free_length: Option<Quantity>,
}

/// A time function: a bare quantity (constant) or a table with `type`.
#[derive(Debug, Clone, PartialEq)]
pub enum TimeSpec {
    /// Constant value.
    Constant(Quantity),
    /// Typed function.
    Function(Box<TimeFunctionSpec>),
}

impl<'de> Deserialize<'de> for TimeSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = TimeSpec;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a constant (number or \"value unit\") or a table with `type`")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<TimeSpec, E> {
                Ok(TimeSpec::Constant(Quantity::si(v as f64)))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<TimeSpec, E> {
                Ok(TimeSpec::Constant(Quantity::si(v as f64)))
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<TimeSpec, E> {
                Ok(TimeSpec::Constant(Quantity::si(v)))
            }
            fn visit_str<E: de::Error>(self, s: &str) -> Result<TimeSpec, E> {
                crate::units::parse_quantity(s)
                    .map(TimeSpec::Constant)
                    .map_err(E::custom)
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<TimeSpec, A::Error> {
                TimeFunctionSpec::deserialize(de::value::MapAccessDeserializer::new(map))
                    .map(|f| TimeSpec::Function(Box::new(f)))
            }
        }
        d.deserialize_any(V)
    }
}

/// Time function types.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TimeType {
    /// `value`.
    Constant,
    /// `v0` until `t0`, linear to `v1` at `t1`.
    Ramp,
    /// `before` until `t0`, `after` from `t0`.
    Step,
    /// `value` for `t0 <= t < t1`, else 0.
    Pulse,
    /// `offset + amplitude sin(2 pi frequency t + phase)`.
    Harmonic,
    /// Piecewise linear through (`times`, `values`).
    Table,
    /// Cubic smooth step (Adams STEP) from `v0` at `t0` to `v1` at `t1`.
    Step3,
    /// Quintic smooth step (Adams STEP5) from `v0` at `t0` to `v1` at `t1`.
    Step5,
    /// Cycloidal move from `v0` at `t0` to `v1` at `t1`.
    Cycloidal,
    /// Trapezoidal-velocity move with S-curve corners (`ramp` fraction) from `v0` to `v1`.
    Move,
}

/// A typed time function; values carry the dimension of the quantity it drives.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeFunctionSpec {
    /// Function type.
    #[serde(rename = "type")]
    pub kind: TimeType,
    /// Constant / pulse value.
    pub value: Option<Quantity>,
    /// Start time.
    pub t0: Option<Quantity>,
    /// End time.
    pub t1: Option<Quantity>,
    /// Ramp start value (default 0).
    pub v0: Option<Quantity>,
    /// Ramp end value.
    pub v1: Option<Quantity>,
    /// Step value before `t0` (default 0).
    pub before: Option<Quantity>,
    /// Step value from `t0`.
    pub after: Option<Quantity>,
    /// Harmonic amplitude.
    pub amplitude: Option<Quantity>,
    /// Harmonic frequency.
    pub frequency: Option<Quantity>,
    /// Harmonic phase (default 0).
    pub phase: Option<Quantity>,
    /// Harmonic offset (default 0).
    pub offset: Option<Quantity>,
    /// Table times.
    pub times: Option<Vec<Quantity>>,
    /// Table values.
    pub values: Option<Vec<Quantity>>,
    /// Fraction of a `move` in each acceleration ramp (default 0.25).
    pub ramp: Option<Quantity>,
}

/// `[output]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Output every n-th step (default 1 unless `dt` is given).
    pub every: Option<usize>,
    /// Output whenever the time passes a multiple of `dt`.
    pub dt: Option<Quantity>,
    /// Signals: `<frame>.position|velocity|angular_velocity|orientation|deformation`,
    /// `<joint>.reaction`.
    #[serde(default)]
    pub signals: Vec<String>,
    /// Write a ParaView animation (default true).
    #[serde(default = "yes")]
    pub animation: bool,
    /// Animation frame every n-th output row (default 1).
    pub animation_every: Option<usize>,
    /// Scale of the elastic deformation in the animation's points (default 1).
    pub deformation_scale: Option<f64>,
    /// Stress fields (`stress`, `von_mises`) in the animation (default false).
    #[serde(default)]
    pub stress: bool,
    /// Plots: file stem -> list of series.
    #[serde(default)]
    pub plots: BTreeMap<String, Vec<String>>,
    /// Series written to `<name>.csv` (first column t); empty: no CSV.
    #[serde(default)]
    pub csv: Vec<String>,
}

fn yes() -> bool {
    true
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            every: None,
            dt: None,
            signals: Vec::new(),
            animation: true,
            animation_every: None,
            deformation_scale: None,
            stress: false,
            plots: BTreeMap::new(),
            csv: Vec::new(),
        }
    }
}

//! Bodies of a model file: rigid bodies (mass, inertia) and FFR bodies from an FE model file, a
//! reduced-body file or a seed folder (mode selection, damping, SI conversion).

use crate::body_loading::{load_body_source, mode_columns, select_modes};
pub use crate::body_loading::{load_fe_body, load_reduced, load_reduced_with_fe, LoadedBody};
use crate::compile::Ctx;
use crate::error::SimError;
use crate::fe_frames::{rotating_nodes, translation_only_nodes, FeInterface};
use crate::mass_model::{
    beam_rotary_inertias, check_consistent_source, full_mass_to_si, stored_consistent_inertia,
    CONSISTENT_NEEDS_FE_MODEL, NO_STORED_CONSISTENT_INERTIA, USE_STORED_CONSISTENT_INERTIA,
};
use crate::schema::{BodySpec, BodyType, DampingSpec, InertiaSpec, MassModel, RotationName};
use crate::stiffening::{centrifugal_stiffness, geometric_to_si, FeModel, NO_STORED_STIFFNESS};
use crate::units::Dimension;
use flexmbs_core::ffr::{self, reduced_body_to_si, FfrBody, FfrElement};
use flexmbs_core::{RigidBody, RotationParam};
use flexmbs_fe::element::MassKind;
use flexmbs_fe::geometric::GeometricStiffness;
use flexmbs_fe::reduction::Cell;
use flexmbs_fe::ElementKind;
use flexmbs_reduce::full_mass::rotary_inertias_to_si;
use flexmbs_reduce::pipeline::resolve;
use nalgebra::{Matrix3, Vector3};
use std::path::Path;

/// An element ready to be added to the model.
#[derive(Debug)]
pub enum BuiltElement {
    /// Rigid body.
    Rigid(RigidBody),
    /// FFR body.
    Ffr(Box<FfrElement>),
    /// Point mass (particle).
    PointMass(flexmbs_core::point_mass::PointMass),
}

/// What the runner needs to know about a body besides its element.
#[derive(Debug, Clone)]
pub struct BodyGeometry {
    /// Points drawn in the animation, body coordinates (SI): FE nodes of an FFR body, the 8
    /// corners of a box for a rigid body.
    pub points: Vec<[f64; 3]>,
    /// True if `points` are FE nodes (followed through the node kinematics).
    pub fe_nodes: bool,
    /// FE node ids (ffr).
    pub node_ids: Vec<u64>,
    /// Cells over `points`.
    pub cells: Vec<Cell>,
    /// Number of elastic modes (0 for rigid bodies).
    pub modes: usize,
    /// Rotation parametrization.
    pub rotation: RotationName,
    /// Named rigid interfaces (FE model-file sources; empty otherwise).
    pub interfaces: Vec<FeInterface>,
    /// Per point: an FE node that moves in the modes without rotating in any
    /// ([`crate::fe_frames::translation_only_nodes`]; empty for rigid bodies).
    pub translation_only: Vec<bool>,
    /// Per point: an FE node whose rotation appears in some mode (empty for rigid bodies).
    pub rotating: Vec<bool>,
    /// Modal stress fields over `points` (SI, the selected modes), or why the body has none
    /// ([`crate::stress`]).
    pub stress: Result<std::sync::Arc<flexmbs_fe::stress::ModalStress>, String>,
}

/// Error of `geometric_stiffening = true` on a source without an FE model or stored geometric
/// stiffness.
const NO_FE_MODEL: &str = "geometric stiffening needs an FE model file (.toml with a built-in \
     mesh or a CalculiX deck) or a reduced-body file (.fmb.h5) with stored geometric stiffness \
     as `source`; a seed folder has no FE mesh and system";

/// Error of an ffr body whose source has no modes (a reduced-body file or seed folder written
/// without them): the FFR equations need at least one elastic coordinate.
const NO_MODES_IN_SOURCE: &str = "the body has no modes (0 elastic coordinates): an ffr body \
     needs at least one; reduce it again with `modes >= 1` (`flexmbs reduce`), or make it a \
     rigid body (`type = \"rigid\"` with `mass` and `inertia`)";

/// Error of `modes = 0` or `modes = []`.
pub(crate) const NO_MODES_SELECTED: &str =
    "no mode selected: an ffr body needs at least one elastic mode \
     (`modes = n` with n >= 1 or a non-empty list); a body without elastic modes is a rigid body \
     (`type = \"rigid\"` with `mass` and `inertia`)";

/// Error of `rotary_inertia = true` without a beam mesh.
const NO_BEAM_MESH: &str = "node rotary inertias need an FE model file (.toml) with a beam mesh \
     (nodes with rotational DOFs) or a reduced-body file (.fmb.h5) that stores them";

/// Error of `rotary_inertia = true` on a reduced-body file without `nodes/rotary_inertia`.
pub const NO_STORED_ROTARY_INERTIA: &str = "the reduced-body file has no node rotary inertias \
     (dataset nodes/rotary_inertia: written by `flexmbs reduce` for beam meshes only, and not by \
     older versions): re-export it with `flexmbs reduce` from the FE model file of the beam mesh, \
     or use that FE model file as `source`";

/// Builds the element of `body[i]`; `base` is the model file's folder.
pub fn build_body(
    ctx: &Ctx,
    i: usize,
    b: &BodySpec,
    base: &Path,
    frames: &[crate::schema::FrameSpec],
) -> Result<(BuiltElement, BodyGeometry), SimError> {
    let p = format!("body[{i}]");
    let mut present = vec![
        ("mass", b.mass.is_some()),
        ("inertia", b.inertia.is_some()),
        ("inertia_matrix", b.inertia_matrix.is_some()),
        ("box", b.box_size.is_some()),
        ("source", b.source.is_some()),
        ("units", b.units.is_some()),
        ("modes", b.modes.is_some()),
        ("damping", b.damping.is_some()),
        ("geometric_stiffening", b.geometric_stiffening.is_some()),
        ("rotary_inertia", b.rotary_inertia.is_some()),
        ("load_stiffening", b.load_stiffening.is_some()),
    ];
    present.extend(crate::superelements::superelement_keys_present(b));
    match b.kind {
        BodyType::Rigid => {
            ctx.only(
                &p,
                "a rigid body",
                &present,
                &["mass", "inertia", "inertia_matrix", "box"],
            )?;
            rigid_body(ctx, &p, b)
        }
        BodyType::Ffr => {
            ctx.only(
                &p,
                "an ffr body",
                &present,
                &[
                    "source",
                    "units",
                    "modes",
                    "damping",
                    "geometric_stiffening",
                    "inertia",
                    "rotary_inertia",
                    "load_stiffening",
                ],
            )?;
            ffr_body(ctx, &p, b, base, frames)
        }
        BodyType::PointMass => {
            ctx.only(&p, "a point mass", &present, &["mass", "box"])?;
            crate::point_mass_body::point_mass_body(ctx, &p, b)
        }
        // compiled by `crate::superelements::add_superelement_beams`
        BodyType::SuperelementBeam | BodyType::Superelement => {
            Err(ctx.err(&p, "internal: superelement bodies are not built here"))
        }
    }
}

fn rigid_body(ctx: &Ctx, p: &str, b: &BodySpec) -> Result<(BuiltElement, BodyGeometry), SimError> {
    let mass_q = b
        .mass
        .as_ref()
        .ok_or_else(|| ctx.err(p, "a rigid body needs `mass`"))?;
    let mass = ctx.q(mass_q, Dimension::Mass, &format!("{p}.mass"))?;
    if !(mass > 0.0 && mass.is_finite()) {
        return Err(ctx.err(
            &format!("{p}.mass"),
            format!("mass must be > 0, got {mass} kg"),
        ));
    }
    let inertia = rigid_inertia(ctx, p, b)?;
    let rotation = match b.rotation {
        RotationName::Cardan => RotationParam::Cardan,
        RotationName::Quaternion => RotationParam::Quaternion,
    };
    let size = match &b.box_size {
        Some(s) => {
            let v = ctx.vec3(s, Dimension::Length, &format!("{p}.box"))?;
            if !v.iter().all(|x| *x > 0.0 && x.is_finite()) {
                return Err(ctx.err(&format!("{p}.box"), "box edges must be > 0"));
            }
            v
        }
        None => equivalent_box(mass, &inertia),
    };
    let geometry = BodyGeometry {
        points: box_corners(&size),
        fe_nodes: false,
        node_ids: Vec::new(),
        cells: vec![Cell {
            kind: ElementKind::Hex8,
            nodes: (0..8).collect(),
        }],
        modes: 0,
        rotation: b.rotation,
        interfaces: Vec::new(),
        translation_only: Vec::new(),
        rotating: Vec::new(),
        stress: Err(crate::stress::RIGID_BODY.into()),
    };
    Ok((
        BuiltElement::Rigid(RigidBody::new(mass, inertia).with_rotation(rotation)),
        geometry,
    ))
}

/// The inertia tensor of a rigid body (kg m^2) from `inertia` (principal moments) or
/// `inertia_matrix`: symmetric, positive definite and a real mass distribution's.
fn rigid_inertia(ctx: &Ctx, p: &str, b: &BodySpec) -> Result<Matrix3<f64>, SimError> {
    let principal = match &b.inertia {
        Some(InertiaSpec::Principal(d)) => Some(d),
        Some(InertiaSpec::Model(_)) => {
            return Err(ctx.err(
                &format!("{p}.inertia"),
                "a rigid body takes three principal moments as `inertia`; \"lumped\" and \
                 \"consistent\" are mass models of ffr bodies",
            ))
        }
        None => None,
    };
    let inertia = match (principal, &b.inertia_matrix) {
        (Some(d), None) => {
            Matrix3::from_diagonal(&ctx.vec3(d, Dimension::Inertia, &format!("{p}.inertia"))?)
        }
        (None, Some(m)) => {
            let key = format!("{p}.inertia_matrix");
            let mut a = Matrix3::zeros();
            for r in 0..3 {
                for c in 0..3 {
                    a[(r, c)] = ctx.q(&m[r][c], Dimension::Inertia, &format!("{key}[{r}][{c}]"))?;
                }
            }
            if (a - a.transpose()).abs().max() > 1e-12 * a.abs().max() {
                return Err(ctx.err(&key, "the inertia matrix must be symmetric"));
            }
            a
        }
        (Some(_), Some(_)) => {
            return Err(ctx.err(
                &format!("{p}.inertia_matrix"),
                "give either `inertia` (principal moments) or `inertia_matrix`, not both",
            ))
        }
        (None, None) => {
            return Err(ctx.err(
                p,
                "a rigid body needs `inertia` (principal moments) or `inertia_matrix`",
            ))
        }
    };
    let key = if b.inertia.is_some() {
        "inertia"
    } else {
        "inertia_matrix"
    };
    // positive definite: the engine's one small dense Cholesky factors it (`flexmbs_core::linsolve`)
    let mut factor = faer::Mat::from_fn(3, 3, |r, c| inertia[(r, c)]);
    if !inertia.iter().all(|x| x.is_finite())
        || flexmbs_core::linsolve::cholesky_factor(factor.as_mut(), 0.0).is_err()
    {
        return Err(ctx.err(
            &format!("{p}.{key}"),
            format!(
                "the inertia tensor must be positive definite, got {:?} kg m^2",
                inertia.as_slice()
            ),
        ));
    }
    // principal moments of a real body: each at most the sum of the other two
    // (I_1 + I_2 - I_3 = 2 int z^2 dm >= 0); equality for a plane lamina
    let m = inertia.symmetric_eigenvalues();
    let total = m.sum();
    for k in 0..3 {
        let (a, b2, c) = (m[k], m[(k + 1) % 3], m[(k + 2) % 3]);
        if a > b2 + c + 1e-9 * total {
            return Err(ctx.err(
                &format!("{p}.{key}"),
                format!(
                    "principal moments {:?} kg m^2 violate the triangle inequality ({a:e} > {b2:e} + {c:e}): no real mass distribution has them",
                    m.as_slice()
                ),
            ));
        }
    }
    Ok(inertia)
}

/// Edge lengths of the homogeneous box with the same mass and principal moments (diagonal of
/// `inertia`): `I_x = m (l_y^2 + l_z^2) / 12`, so `l_x^2 = 6 (I_y + I_z - I_x) / m`. Edges are
/// kept at >= 5 % of the longest (>= 1 cm for a point mass) so the box stays visible.
pub fn equivalent_box(mass: f64, inertia: &Matrix3<f64>) -> Vector3<f64> {
    let d = inertia.diagonal();
    let l = Vector3::new(
        (6.0 * (d.y + d.z - d.x) / mass).max(0.0).sqrt(),
        (6.0 * (d.x + d.z - d.y) / mass).max(0.0).sqrt(),
        (6.0 * (d.x + d.y - d.z) / mass).max(0.0).sqrt(),
    );
    let lmax = l.max().max(0.01);
    l.map(|x| x.max(0.05 * lmax))
}

/// The 8 corners of a centred box in VTK hexahedron order.
pub(crate) fn box_corners(s: &Vector3<f64>) -> Vec<[f64; 3]> {
    let (x, y, z) = (s.x / 2.0, s.y / 2.0, s.z / 2.0);
    vec![
        [-x, -y, -z],
        [x, -y, -z],
        [x, y, -z],
        [-x, y, -z],
        [-x, -y, z],
        [x, -y, z],
        [x, y, z],
        [-x, y, z],
    ]
}

/// Where an ffr body's data comes from, decided once from its `source` path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BodySource {
    /// A seed 4-file folder (seed 000 §5.3): reduced data only, no FE model.
    SeedFolder,
    /// An FE model file (`.toml`), reduced through the pipeline; a built-in mesh or a CalculiX
    /// deck gives an FE model, a `seed` mesh does not (known once it is read).
    FeModel,
    /// A reduced-body file (`.h5`, as `flexmbs reduce` writes), which may store `K_G` and node
    /// rotary inertias.
    BodyFile,
}

impl BodySource {
    /// The kind of the resolved source `path`: a folder, a `.toml` or an `.h5` file. Errors as
    /// text (the caller adds the key path).
    pub fn of(path: &Path) -> Result<Self, String> {
        if path.is_dir() {
            return Ok(BodySource::SeedFolder);
        }
        match path.extension().and_then(|e| e.to_str()) {
            Some("toml") => Ok(BodySource::FeModel),
            Some("h5") => Ok(BodySource::BodyFile),
            _ => Err(format!(
                "{}: not an FE model file (.toml), a reduced-body file (.h5) or a seed folder",
                path.display()
            )),
        }
    }

    /// Can have an FE model (mesh and system): needed by the consistent mass model and by
    /// computed `K_G` and rotary inertias.
    pub fn can_have_fe_model(self) -> bool {
        self == BodySource::FeModel
    }

    /// Can store the geometric stiffness `K_G` (group `geometric` of a reduced-body file).
    pub fn can_store_geometric_stiffness(self) -> bool {
        self == BodySource::BodyFile
    }

    /// Can store node rotary inertias (dataset `nodes/rotary_inertia` of a reduced-body file).
    pub fn can_store_rotary_inertia(self) -> bool {
        self == BodySource::BodyFile
    }

    /// Can store the consistent inertia (dataset `inertia/gram` of a reduced-body file).
    pub fn can_store_consistent_inertia(self) -> bool {
        self == BodySource::BodyFile
    }
}

/// Reads the mass model of an ffr body (`inertia = "lumped" | "consistent"`, default lumped)
/// and refuses options that the kind of source cannot serve, before it is loaded (an FE model
/// file with a `seed` mesh is refused after loading, when it shows it has no FE model).
fn check_source_options(
    ctx: &Ctx,
    p: &str,
    b: &BodySpec,
    kind: BodySource,
) -> Result<MassModel, SimError> {
    let fe = kind.can_have_fe_model();
    if b.geometric_stiffening == Some(true) && !fe && !kind.can_store_geometric_stiffness() {
        return Err(ctx.err(&format!("{p}.geometric_stiffening"), NO_FE_MODEL));
    }
    let ikey = format!("{p}.inertia");
    let mass_model = match &b.inertia {
        None => MassModel::Lumped,
        Some(InertiaSpec::Model(m)) => *m,
        Some(InertiaSpec::Principal(_)) => {
            return Err(ctx.err(
                &ikey,
                "an ffr body takes `inertia = \"lumped\"` or `\"consistent\"` (its inertia \
                 comes from the FE model); principal moments are for rigid bodies",
            ))
        }
    };
    if mass_model == MassModel::Consistent && !fe && !kind.can_store_consistent_inertia() {
        return Err(ctx.err(&ikey, CONSISTENT_NEEDS_FE_MODEL));
    }
    if b.rotary_inertia == Some(true) && !fe && !kind.can_store_rotary_inertia() {
        return Err(ctx.err(&format!("{p}.rotary_inertia"), NO_BEAM_MESH));
    }
    Ok(mass_model)
}

fn ffr_body(
    ctx: &Ctx,
    p: &str,
    b: &BodySpec,
    base: &Path,
    frames: &[crate::schema::FrameSpec],
) -> Result<(BuiltElement, BodyGeometry), SimError> {
    let source = b.source.as_ref().ok_or_else(|| {
        ctx.err(
            p,
            "an ffr body needs `source` (FE model file, .h5 body file or seed folder)",
        )
    })?;
    let key = format!("{p}.source");
    let path = resolve(base, source);
    let kind = BodySource::of(&path).map_err(|m| ctx.err(&key, m))?;
    let consistent = check_source_options(ctx, p, b, kind)? == MassModel::Consistent;
    let units = b.units.unwrap_or_default();
    let mut loaded =
        load_body_source(kind, &path, &b.name, units, consistent).map_err(|m| ctx.err(&key, m))?;
    let ikey = format!("{p}.inertia");
    if consistent {
        match (&loaded.fe, &loaded.full_mass, &loaded.inertia_gram) {
            (Some(fe), Some(_), _) => check_consistent_source(fe).map_err(|m| ctx.err(&ikey, m))?,
            (None, None, Some(_)) => {}
            _ if kind.can_store_consistent_inertia() => {
                return Err(ctx.err(&ikey, NO_STORED_CONSISTENT_INERTIA))
            }
            _ => return Err(ctx.err(&ikey, CONSISTENT_NEEDS_FE_MODEL)),
        }
    }
    if loaded.reduced.num_modes() == 0 {
        return Err(ctx.err(&key, NO_MODES_IN_SOURCE));
    }
    let rotary = node_rotary_inertias(ctx, p, b, kind, &loaded)?;
    let geometric = geometric_stiffness(ctx, p, b, kind, &loaded)?;
    let interfaces = loaded.fe.as_ref().map(named_interfaces).unwrap_or_default();
    let n_static = loaded.reduced.num_static_load_responses();
    let stress = crate::stress::selected_stress(&mut loaded, |nf| match &b.modes {
        Some(sel) => mode_columns(ctx, p, nf, n_static, sel),
        None => Ok((0..nf).collect()),
    })?;
    let LoadedBody {
        reduced,
        fe,
        full_mass,
        inertia_gram,
        ..
    } = loaded;
    // a stored consistent inertia, restricted to the selected modes (SI)
    let gram = match (&inertia_gram, consistent) {
        (Some(g), true) => {
            let cols = b
                .modes
                .as_ref()
                .map(|sel| mode_columns(ctx, p, reduced.num_modes(), n_static, sel))
                .transpose()?;
            let g =
                stored_consistent_inertia(g, reduced.num_modes(), cols.as_deref(), reduced.units);
            Some(g.map_err(|m| ctx.err(&ikey, m))?)
        }
        _ => None,
    };
    let (reduced, geometric) = select_modes(ctx, p, b, reduced, geometric)?;
    let geometric = geometric.map(|g| geometric_to_si(&g, reduced.units));
    let si = reduced_body_to_si(&reduced);
    let rotation = match b.rotation {
        RotationName::Cardan => ffr::RotationParam::Cardan,
        RotationName::Quaternion => ffr::RotationParam::Quaternion,
    };
    // `full_mass` is loaded only for the consistent mass model
    let mut body = match (full_mass, gram) {
        (None, None) => FfrBody::from_reduced(&si, rotation).map_err(|e| {
            let hint = match &fe {
                Some(fe) if fe.mass == MassKind::Consistent => {
                    " (the FE model's mass is consistent: set `inertia = \"consistent\"`)"
                }
                _ if inertia_gram.is_some() => USE_STORED_CONSISTENT_INERTIA,
                _ => "",
            };
            ctx.err(&key, format!("{e}{hint}"))
        })?,
        (Some(m), _) => {
            FfrBody::from_reduced_consistent(&si, &full_mass_to_si(&m, &reduced), rotation)
                .map_err(|e| ctx.err(&ikey, e.to_string()))?
        }
        (None, Some(g)) => FfrBody::from_reduced_gram(&si, &g, rotation)
            .map_err(|e| ctx.err(&ikey, e.to_string()))?,
    };
    if let Some(r) = &rotary {
        body.set_rotary_inertia(r)
            .map_err(|e| ctx.err(&key, format!("node rotary inertias: {e}")))?;
    }
    if let Some(g) = &geometric {
        body = body
            .with_geometric_stiffening(g)
            .map_err(|e| ctx.err(&format!("{p}.geometric_stiffening"), e.to_string()))?;
    }
    if let Some(d) = &b.damping {
        set_damping(ctx, &format!("{p}.damping"), d, &mut body)?;
    }
    let geometry = BodyGeometry {
        points: si.nodes.clone(),
        fe_nodes: true,
        node_ids: si.node_ids.clone(),
        cells: si.cells.clone(),
        modes: si.num_modes(),
        rotation: b.rotation,
        interfaces,
        translation_only: translation_only_nodes(&si),
        rotating: rotating_nodes(&si),
        stress,
    };
    let body = crate::stiffening::with_load_stiffening(
        ctx,
        p,
        b,
        frames,
        &geometry,
        fe.as_ref(),
        &reduced,
        body,
    )?;
    Ok((BuiltElement::Ffr(Box::new(FfrElement::new(body))), geometry))
}

/// The rigid interfaces of an FE model (`[[body.boundary.rigid]]`, in order: their nodes follow
/// the mesh nodes) with their names.
fn named_interfaces(fe: &FeModel) -> Vec<FeInterface> {
    let p = &fe.prepared;
    p.bc.rigid
        .iter()
        .zip(&p.system.map.interface_nodes)
        .map(|(r, &node)| FeInterface {
            name: r.name.clone(),
            node,
            slaves: r.nodes.clone(),
        })
        .collect()
}

/// Node rotary inertias of an ffr body (SI), if asked for or available: computed from a beam
/// mesh of the FE model, or stored in a reduced-body file (body units, converted like the
/// computed ones). `rotary_inertia = false` turns them off; `true` requires them.
fn node_rotary_inertias(
    ctx: &Ctx,
    p: &str,
    b: &BodySpec,
    kind: BodySource,
    loaded: &LoadedBody,
) -> Result<Option<Vec<Matrix3<f64>>>, SimError> {
    let rkey = format!("{p}.rotary_inertia");
    let required = b.rotary_inertia == Some(true);
    match (&loaded.fe, b.rotary_inertia) {
        (_, Some(false)) => Ok(None),
        (Some(fe), _) => match beam_rotary_inertias(fe, &loaded.reduced)
            .map_err(|m| ctx.err(&format!("{p}.source"), m))?
        {
            None if required => Err(ctx.err(&rkey, NO_BEAM_MESH)),
            found => Ok(found),
        },
        (None, _) => match &loaded.rotary_inertia {
            Some(i) => Ok(Some(rotary_inertias_to_si(i, loaded.reduced.units))),
            None if required && kind.can_store_rotary_inertia() => {
                Err(ctx.err(&rkey, NO_STORED_ROTARY_INERTIA))
            }
            None if required => Err(ctx.err(&rkey, NO_BEAM_MESH)),
            None => Ok(None),
        },
    }
}

/// The geometric stiffness `K_G` of an ffr body with `geometric_stiffening = true` (all modes,
/// body units): computed from the FE model, or stored in a reduced-body file.
fn geometric_stiffness(
    ctx: &Ctx,
    p: &str,
    b: &BodySpec,
    kind: BodySource,
    loaded: &LoadedBody,
) -> Result<Option<GeometricStiffness>, SimError> {
    let gkey = format!("{p}.geometric_stiffening");
    if !b.geometric_stiffening.unwrap_or(false) {
        return Ok(None);
    }
    // a free-free body with load stiffening: relieved centrifugal patterns, built with the node
    // loads (`stiffening::with_load_stiffening`)
    if b.load_stiffening == Some(true)
        && loaded
            .fe
            .as_ref()
            .is_some_and(|fe| fe.prepared.bc.fixed.is_empty())
    {
        return Ok(None);
    }
    match (&loaded.fe, &loaded.geometric) {
        (Some(fe), _) => centrifugal_stiffness(fe, &loaded.reduced)
            .map(Some)
            .map_err(|m| ctx.err(&gkey, m)),
        (None, Some(g)) => Ok(Some(g.clone())),
        (None, None) if kind.can_store_geometric_stiffness() => {
            Err(ctx.err(&gkey, NO_STORED_STIFFNESS))
        }
        (None, None) => Err(ctx.err(&gkey, NO_FE_MODEL)),
    }
}

/// Sets the damping of an ffr body: `rayleigh = [alpha, beta]` or `modal = [zeta, ...]` (one
/// ratio per selected mode, or one for all). `dk` is the key path of the `damping` table.
fn set_damping(ctx: &Ctx, dk: &str, d: &DampingSpec, body: &mut FfrBody) -> Result<(), SimError> {
    match (&d.rayleigh, &d.modal) {
        (Some([a, bb]), None) => {
            if !(*a >= 0.0 && *bb >= 0.0) {
                return Err(ctx.err(&format!("{dk}.rayleigh"), "alpha and beta must be >= 0"));
            }
            body.set_rayleigh_damping(*a, *bb);
        }
        (None, Some(z)) => {
            let zeta = if z.len() == 1 {
                vec![z[0]; body.nf()]
            } else {
                z.clone()
            };
            if zeta.iter().any(|x| x.is_nan() || *x < 0.0) {
                return Err(ctx.err(&format!("{dk}.modal"), "damping ratios must be >= 0"));
            }
            body.set_modal_damping(&zeta).map_err(|e| {
                let hint = match e {
                    flexmbs_core::ffr::FfrError::NotDiagonal { .. } => {
                        "modal damping ratios need a basis of modes; this body's reduced \
                         matrices couple its basis vectors (static load responses, or a \
                         non-modal basis): use `rayleigh = [alpha, beta]`"
                    }
                    _ => "give one ratio per selected mode, or one for all",
                };
                ctx.err(&format!("{dk}.modal"), format!("{e} ({hint})"))
            })?;
        }
        _ => {
            return Err(ctx.err(
                dk,
                "give exactly one of `rayleigh = [alpha, beta]` and `modal = [zeta, ...]`",
            ))
        }
    }
    if body.d_ff.iter().any(|v| !v.is_finite()) {
        // e.g. alpha = 1e300: d_ff overflows and the first step would fail on NaN
        return Err(ctx.err(
            dk,
            "the modal damping matrix overflows (non-finite entries): the coefficients are far too large",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn source_kind_is_decided_by_folder_or_extension() {
        let dir = std::env::temp_dir();
        assert_eq!(BodySource::of(&dir), Ok(BodySource::SeedFolder));
        let kind = |f: &str| BodySource::of(&dir.join("flexmbs-no-such-dir").join(f));
        assert_eq!(kind("blade.toml"), Ok(BodySource::FeModel));
        assert_eq!(kind("blade.fmb.h5"), Ok(BodySource::BodyFile));
        for bad in ["blade.txt", "blade"] {
            let e = kind(bad).unwrap_err();
            assert!(
                e.ends_with(
                    ": not an FE model file (.toml), a reduced-body file (.h5) or a seed folder"
                ),
                "{e}"
            );
        }
        let caps = |k: BodySource| {
            (
                k.can_have_fe_model(),
                k.can_store_geometric_stiffness(),
                k.can_store_rotary_inertia(),
                k.can_store_consistent_inertia(),
            )
        };
        assert_eq!(caps(BodySource::SeedFolder), (false, false, false, false));
        assert_eq!(caps(BodySource::FeModel), (true, false, false, false));
        assert_eq!(caps(BodySource::BodyFile), (false, true, true, true));
    }
}

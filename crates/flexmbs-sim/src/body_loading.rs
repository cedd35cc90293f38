//! Loading the reduced data of an FFR body: an FE model file (`.toml`, reduced through the
//! pipeline), a reduced-body file (`.fmb.h5`) or a seed 4-file folder, and the selection of its
//! modes (`modes = N` or a list).

use crate::bodies::{BodySource, NO_MODES_SELECTED};
use crate::compile::Ctx;
use crate::error::SimError;
use crate::schema::{BodySpec, ModeSelection};
use crate::stiffening::{select_geometric_modes, FeModel};
use flexmbs_fe::geometric::GeometricStiffness;
use flexmbs_fe::reduction::ReducedBody;
use flexmbs_fe::SparseMatrix;
use flexmbs_reduce::pipeline::{prepare, resolve, run_reduction};
use nalgebra::Matrix3;
use std::path::Path;
/// Reads a reduced body: FE model file (`.toml`, reduced through the pipeline), reduced-body
/// file (`.h5`) or seed 4-file folder. Errors as text (the caller adds the key path).
pub fn load_reduced(
    source: &Path,
    base: &Path,
    name: &str,
    units: flexmbs_fe::UnitSystem,
) -> Result<ReducedBody, String> {
    load_reduced_with_fe(source, base, name, units).map(|(body, _)| body)
}

/// [`load_reduced`], also returning the FE model (prepared mesh and system) of an FE model file
/// with a built-in mesh or a CalculiX deck (`None` for `.h5` files and seed folders).
pub fn load_reduced_with_fe(
    source: &Path,
    base: &Path,
    name: &str,
    units: flexmbs_fe::UnitSystem,
) -> Result<(ReducedBody, Option<FeModel>), String> {
    load_fe_body(source, base, name, units, false).map(|l| (l.reduced, l.fe))
}

/// A body source as loaded: the reduced body, its FE model (FE model files with a built-in mesh
/// or a CalculiX deck), if asked for, the full translational FE mass matrix (body units), and the
/// geometric stiffness stored in a reduced-body file.
#[derive(Debug, Clone)]
pub struct LoadedBody {
    /// The reduced body.
    pub reduced: ReducedBody,
    /// Prepared mesh and system of an FE model file.
    pub fe: Option<FeModel>,
    /// Full translational mass matrix over the body's nodes
    /// ([`flexmbs_reduce::full_mass::prepare_with_mass`]).
    pub full_mass: Option<SparseMatrix>,
    /// Geometric stiffness `K_G` stored in a reduced-body file (group `geometric`: all modes,
    /// body units); `None` for other sources and files without it.
    pub geometric: Option<GeometricStiffness>,
    /// Node rotary inertias stored in a reduced-body file (dataset `nodes/rotary_inertia`: one
    /// per node, body units); `None` for other sources and files without them (an FE model
    /// file's are computed from `fe`, [`crate::mass_model::beam_rotary_inertias`]).
    pub rotary_inertia: Option<Vec<Matrix3<f64>>>,
    /// Modal stress fields over all modes (body units): computed from an FE model file, or
    /// stored in a reduced-body file (group `stress`); `Err` with the reason and the fix when
    /// the source has none ([`crate::stress`]).
    pub stress: Result<flexmbs_fe::stress::ModalStress, String>,
    /// Consistent inertia stored in a reduced-body file (dataset `inertia/gram`: Gram matrix
    /// over all modes, body units; [`crate::mass_model::stored_consistent_inertia`]); `None`
    /// for other sources and files without it.
    pub inertia_gram: Option<nalgebra::DMatrix<f64>>,
}

/// [`load_reduced_with_fe`], with the full translational mass matrix of an FE model when
/// `full_mass` is true (CalculiX decks are then exported once, without `*BOUNDARY` cards).
pub fn load_fe_body(
    source: &Path,
    base: &Path,
    name: &str,
    units: flexmbs_fe::UnitSystem,
    full_mass: bool,
) -> Result<LoadedBody, String> {
    let path = resolve(base, source);
    load_body_source(BodySource::of(&path)?, &path, name, units, full_mass)
}

impl LoadedBody {
    /// A body with reduced data only (a seed folder).
    fn reduced_only(reduced: ReducedBody) -> Self {
        LoadedBody {
            reduced,
            fe: None,
            full_mass: None,
            geometric: None,
            rotary_inertia: None,
            stress: Err(crate::stress::NO_FE_MESH.into()),
            inertia_gram: None,
        }
    }
}

/// Loads the resolved source `path` of kind `kind` ([`load_fe_body`]).
pub(crate) fn load_body_source(
    kind: BodySource,
    path: &Path,
    name: &str,
    units: flexmbs_fe::UnitSystem,
    full_mass: bool,
) -> Result<LoadedBody, String> {
    match kind {
        BodySource::SeedFolder => flexmbs_io::seed_body::read_seed_body(path, name, units)
            .map(LoadedBody::reduced_only)
            .map_err(|e| e.to_string()),
        BodySource::FeModel => load_fe_model_file(path, full_mass),
        BodySource::BodyFile => flexmbs_io::body_file::read_body_file(path)
            .map(|f| LoadedBody {
                reduced: f.body,
                fe: None,
                full_mass: None,
                geometric: f.geometric,
                rotary_inertia: f.rotary_inertia,
                stress: f
                    .stress
                    .ok_or_else(|| crate::stress::NO_STORED_STRESS.into()),
                inertia_gram: f.inertia_gram,
            })
            .map_err(|e| e.to_string()),
    }
}

/// Reads an FE model file and reduces it (a `seed` mesh is read as the seed folder it names);
/// errors of meshing, supports and reduction are located at the line of the FE file's key.
fn load_fe_model_file(path: &Path, full_mass: bool) -> Result<LoadedBody, String> {
    let source = flexmbs_io::model_check::FeModelSource::read(path).map_err(|e| e.to_string())?;
    let spec = source.model.body.clone();
    let fe_base = path.parent().unwrap_or(Path::new("."));
    if let flexmbs_io::model::MeshSpec::Seed { dir } = &spec.mesh {
        let dir = resolve(fe_base, dir);
        return flexmbs_io::seed_body::read_seed_body(&dir, &spec.name, spec.units)
            .map(LoadedBody::reduced_only)
            .map_err(|e| e.to_string());
    }
    let located = |e: flexmbs_reduce::pipeline::PipelineError| source.locate(e).to_string();
    let (prepared, m_full) = if full_mass {
        let (p, m) = flexmbs_reduce::full_mass::prepare_with_mass(&spec, fe_base, &mut |_| {})
            .map_err(located)?;
        (p, Some(m))
    } else {
        (prepare(&spec, fe_base, &mut |_| {}).map_err(located)?, None)
    };
    let body = run_reduction(&spec, &prepared, &mut |_| {}).map_err(located)?;
    let mass = FeModel::mass_kind(&spec.mesh, spec.reduction.mass);
    let stress = flexmbs_reduce::stress::modal_stress_fields(&spec, &prepared, &body)
        .map_err(|e| format!("stress recovery: {e}"));
    Ok(LoadedBody {
        stress,
        reduced: body,
        fe: Some(FeModel { prepared, mass }),
        full_mass: m_full,
        geometric: None,
        rotary_inertia: None,
        inertia_gram: None,
    })
}

/// The body and its `K_G` restricted to the modes selected by `modes` (all if absent).
pub(crate) fn select_modes(
    ctx: &Ctx,
    p: &str,
    b: &BodySpec,
    reduced: ReducedBody,
    geometric: Option<GeometricStiffness>,
) -> Result<(ReducedBody, Option<GeometricStiffness>), SimError> {
    let Some(sel) = &b.modes else {
        return Ok((reduced, geometric));
    };
    let cols = mode_columns(
        ctx,
        p,
        reduced.num_modes(),
        reduced.num_static_load_responses(),
        sel,
    )?;
    Ok((
        reduced.restricted_to(&cols),
        geometric.map(|g| select_geometric_modes(&g, &cols)),
    ))
}

/// The 0-based columns of the selected basis vectors (1-based numbers in the file) of a body
/// with `nf` of them, the last `n_static` of which are static load responses: a count selects
/// the first modes and keeps every static load response (they belong to the basis the reduction
/// was asked for); a list selects exactly the listed columns.
pub(crate) fn mode_columns(
    ctx: &Ctx,
    p: &str,
    nf: usize,
    n_static: usize,
    sel: &ModeSelection,
) -> Result<Vec<usize>, SimError> {
    let cols: Vec<usize> = match sel {
        ModeSelection::Count(n) => {
            let n_modes = nf - n_static.min(nf);
            if *n > n_modes {
                let extra = if n_static > 0 {
                    format!(" (and {n_static} static load responses, kept with any count)")
                } else {
                    String::new()
                };
                return Err(ctx.err(
                    &format!("{p}.modes"),
                    format!("{n} modes requested but the body has {n_modes}{extra}"),
                ));
            }
            (0..*n).chain(n_modes..nf).collect()
        }
        ModeSelection::List(list) => {
            let mut cols = Vec::with_capacity(list.len());
            for (k, &m) in list.iter().enumerate() {
                if m == 0 || m > nf {
                    return Err(ctx.err(
                        &format!("{p}.modes[{k}]"),
                        format!("mode {m} out of range: the body has modes 1..={nf}"),
                    ));
                }
                if cols.contains(&(m - 1)) {
                    return Err(ctx.err(
                        &format!("{p}.modes[{k}]"),
                        format!("mode {m} selected twice"),
                    ));
                }
                cols.push(m - 1);
            }
            cols
        }
    };
    if cols.is_empty() {
        return Err(ctx.err(&format!("{p}.modes"), NO_MODES_SELECTED));
    }
    Ok(cols)
}

//! From a model file's FE body to a modal analysis or a reduced body: builds the mesh (built-in
//! generators, CalculiX deck, seed folder), applies boundary conditions, assembles or imports K and M,
//! and calls the FE front end. No physics here: this module only wires the pieces together.

use flexmbs_fe::constraint::{BoundaryConditions, RigidInterface};
use flexmbs_fe::eigen::{EigenEvent, EigenMethod, EigenOptions};
use flexmbs_fe::element::MassKind;
use flexmbs_fe::mesh::generate;
use flexmbs_fe::mesh::profile::Profile;
use flexmbs_fe::reduction::{
    craig_bampton, modal_analysis, reduce_modal_augmented, CraigBamptonOptions, ModalResult,
    Provenance, ReducedBody,
};
use flexmbs_fe::static_modes::StaticLoad;
use flexmbs_fe::system::FeSystem;
use flexmbs_fe::{ElementKind, FeError, Material, Mesh, NodeIdx};
use flexmbs_io::model::{
    BoundarySpec, CcxMatrices, FeBodySpec, MassName, MeshSpec, NodeSelector, ProfileSpec,
    ReductionMethod, SolverName,
};
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Errors of building a body from its specification.
#[derive(Debug, Error)]
pub enum PipelineError {
    /// FE front end error, with the key path it concerns.
    #[error("{context}: {source}")]
    Fe {
        /// What was being done (key path or stage).
        context: String,
        /// Cause.
        source: FeError,
    },
    /// File reading error.
    #[error(transparent)]
    Io(#[from] flexmbs_io::IoError),
    /// A selection or name in the model does not match the mesh.
    #[error("at `{path}`: {message}")]
    Model {
        /// Key path.
        path: String,
        /// What is wrong.
        message: String,
    },
}

impl flexmbs_io::model_check::ErrorAtKey for PipelineError {
    fn key_and_message(self, body: &FeBodySpec) -> (String, String) {
        match self {
            PipelineError::Fe { context, source } => (context, source.to_string()),
            PipelineError::Model { path, message } => (path, message),
            PipelineError::Io(io) => {
                let key = match body.mesh {
                    MeshSpec::Calculix { .. } => "body.mesh.deck",
                    MeshSpec::Seed { .. } => "body.mesh.dir",
                    _ => "body.mesh",
                };
                (key.to_string(), io.to_string())
            }
        }
    }
}

fn fe(context: &str) -> impl FnOnce(FeError) -> PipelineError + '_ {
    move |source| PipelineError::Fe {
        context: context.to_string(),
        source,
    }
}

/// Progress of the pipeline stages, for progress bars.
#[derive(Debug, Clone)]
pub enum Stage {
    /// A named stage started (meshing, importing, running ccx, ...).
    Started(String),
    /// Element assembly: elements done of total.
    Assembly {
        /// Elements done.
        done: usize,
        /// Elements in total.
        total: usize,
    },
    /// Eigen solver events.
    Eigen(EigenEvent),
}

/// A body ready for analysis: its mesh, boundary conditions and constrained system.
#[derive(Debug, Clone)]
pub struct PreparedBody {
    /// The mesh (in the body's units).
    pub mesh: Mesh,
    /// Boundary conditions.
    pub bc: BoundaryConditions,
    /// Constrained system.
    pub system: FeSystem,
    /// Interface nodes for Craig-Bampton (indices in the constrained system's node list).
    pub interface: Vec<NodeIdx>,
    /// Static load patterns whose responses enrich a modal basis (`reduction.static_loads`).
    pub static_loads: Vec<StaticLoad>,
    /// Human-readable source description.
    pub source: String,
}

/// Builds the mesh of a built-in or CalculiX source (not for seed folders).
pub fn build_mesh(spec: &FeBodySpec, base: &Path) -> Result<Mesh, PipelineError> {
    let u = spec.units;
    let ctx = "body.mesh";
    let mesh = match &spec.mesh {
        MeshSpec::Box {
            size,
            divisions,
            element,
            material,
        } => generate::box_mesh(
            *size,
            *divisions,
            ElementKind::from(*element),
            Material::from(*material),
            u,
        )
        .map_err(fe(ctx))?,
        MeshSpec::Boxes {
            boxes,
            element_size,
            element,
            material,
        } => {
            let regions: Vec<generate::BoxRegion> = boxes
                .iter()
                .map(|b| generate::BoxRegion {
                    min: b.min,
                    max: b.max,
                })
                .collect();
            generate::union_of_boxes(
                &regions,
                *element_size,
                ElementKind::from(*element),
                Material::from(*material),
                u,
            )
            .map_err(fe(ctx))?
        }
        MeshSpec::Profile {
            profile,
            length,
            element_size,
            element,
            material,
        } => {
            let p = build_profile(profile).map_err(fe("body.mesh.profile"))?;
            generate::extrude_profile(
                &p,
                *length,
                *element_size,
                ElementKind::from(*element),
                Material::from(*material),
                u,
            )
            .map_err(fe(ctx))?
        }
        MeshSpec::Beam {
            start,
            end,
            elements,
            section,
            theory,
            orientation,
            material,
        } => {
            let axis = [end[0] - start[0], end[1] - start[1], end[2] - start[2]];
            let o =
                orientation.unwrap_or(if axis[0].abs() < 1e-12 * (axis[1].abs() + axis[2].abs()) {
                    [0.0, 0.0, 1.0]
                } else {
                    [0.0, 1.0, 0.0]
                });
            generate::beam_line(
                *start,
                *end,
                *elements,
                (*section).into(),
                (*theory).into(),
                o,
                Material::from(*material),
                u,
            )
            .map_err(fe(ctx))?
        }
        MeshSpec::Calculix { deck, .. } => {
            let path = resolve(base, deck);
            deck_mesh(&path, u)?
        }
        MeshSpec::Seed { .. } => {
            return Err(PipelineError::Model {
                path: "body.mesh.type".into(),
                message: "a seed folder holds an already reduced body; it has no mesh to analyse"
                    .into(),
            })
        }
    };
    Ok(mesh)
}

/// The mesh of a CalculiX deck, with the nodes fully fixed by its `*BOUNDARY` cards (all three
/// translations, value 0) collected in the node set `DECK_BOUNDARY`. Partial or non-zero
/// boundary conditions are refused: flexmbs fixes whole nodes.
fn deck_mesh(path: &Path, units: flexmbs_fe::UnitSystem) -> Result<Mesh, PipelineError> {
    let deck = flexmbs_io::calculix::inp::read_inp(path, units)?;
    let mut mesh = deck.mesh;
    let mut dirs = std::collections::BTreeMap::<NodeIdx, u8>::new();
    for b in &deck.boundaries {
        if b.value != 0.0 || b.dof > 3 {
            return Err(PipelineError::Model {
                path: "body.mesh.deck".into(),
                message: format!(
                    "{}: *BOUNDARY on node {} DOF {} = {} is not supported (only fixed translations); fix nodes in [body.boundary] instead",
                    path.display(),
                    mesh.node_ids[b.node],
                    b.dof,
                    b.value
                ),
            });
        }
        *dirs.entry(b.node).or_insert(0) |= 1 << (b.dof - 1);
    }
    if let Some((&n, _)) = dirs.iter().find(|(_, &m)| m != 0b111) {
        return Err(PipelineError::Model {
            path: "body.mesh.deck".into(),
            message: format!(
                "{}: node {} is fixed in some directions only; flexmbs fixes whole nodes (use [body.boundary])",
                path.display(),
                mesh.node_ids[n]
            ),
        });
    }
    if !dirs.is_empty() {
        mesh.node_sets
            .insert(DECK_BOUNDARY.into(), dirs.into_keys().collect());
    }
    Ok(mesh)
}

/// Node set holding the nodes fixed by a CalculiX deck's `*BOUNDARY`; always applied.
pub const DECK_BOUNDARY: &str = "DECK_BOUNDARY";

fn build_profile(p: &ProfileSpec) -> Result<Profile, FeError> {
    match p {
        ProfileSpec::Rectangle { width, height } => Profile::rectangle(*width, *height),
        ProfileSpec::T {
            flange_width,
            flange_thickness,
            web_width,
            web_height,
        } => Profile::t_section(*flange_width, *flange_thickness, *web_width, *web_height),
        ProfileSpec::L {
            width,
            height,
            thickness,
        } => Profile::l_section(*width, *height, *thickness),
        ProfileSpec::I {
            flange_width,
            flange_thickness,
            web_thickness,
            height,
        } => Profile::i_section(*flange_width, *flange_thickness, *web_thickness, *height),
        ProfileSpec::Polygon { vertices } => Profile::polygon(vertices),
    }
}

/// Resolves a path given in a model file relative to the model file's folder.
pub fn resolve(base: &Path, p: &Path) -> PathBuf {
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        base.join(p)
    }
}

/// Selects nodes of `mesh` (`key` is the key path for errors).
pub fn select_nodes(
    mesh: &Mesh,
    sel: &NodeSelector,
    key: &str,
) -> Result<Vec<NodeIdx>, PipelineError> {
    let bad = |m: String| PipelineError::Model {
        path: key.to_string(),
        message: m,
    };
    let size = mesh_size(mesh);
    let nodes = match sel {
        NodeSelector::Set(name) => mesh
            .node_set(name)
            .map_err(|_| {
                let known: Vec<&str> = mesh.node_sets.keys().map(|s| s.as_str()).collect();
                bad(format!(
                    "no node set '{name}' (known: {})",
                    known.join(", ")
                ))
            })?
            .to_vec(),
        NodeSelector::Plane { plane } => {
            let axis = match plane.axis.as_str() {
                "x" | "X" => 0,
                "y" | "Y" => 1,
                "z" | "Z" => 2,
                a => return Err(bad(format!("plane axis must be x, y or z, got '{a}'"))),
            };
            mesh.nodes_on_plane(axis, plane.value, plane.tol.unwrap_or(1e-9 * size))
        }
        NodeSelector::Within { within } => mesh.nodes_in_box(within.min, within.max, 1e-9 * size),
        NodeSelector::Nearest { nearest } => {
            vec![mesh
                .nearest_node(*nearest)
                .ok_or_else(|| bad("the mesh has no nodes".into()))?]
        }
    };
    if nodes.is_empty() {
        return Err(bad("the selection matches no node".into()));
    }
    Ok(nodes)
}

fn mesh_size(mesh: &Mesh) -> f64 {
    let (lo, hi) = mesh.bounding_box();
    (0..3)
        .map(|d| hi[d] - lo[d])
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE)
}

/// Boundary conditions of the spec applied to `mesh`.
pub fn boundary_conditions(
    mesh: &Mesh,
    b: &BoundarySpec,
) -> Result<BoundaryConditions, PipelineError> {
    let mut bc = BoundaryConditions::default();
    if let Some(deck_fixed) = mesh.node_sets.get(DECK_BOUNDARY) {
        bc.fixed.extend(deck_fixed);
    }
    for (i, sel) in b.fixed.iter().enumerate() {
        bc.fixed.extend(select_nodes(
            mesh,
            sel,
            &format!("body.boundary.fixed[{i}]"),
        )?);
    }
    bc.fixed.sort_unstable();
    bc.fixed.dedup();
    for (i, r) in b.rigid.iter().enumerate() {
        let nodes = select_nodes(mesh, &r.nodes, &format!("body.boundary.rigid[{i}].nodes"))?;
        bc.rigid.push(RigidInterface {
            name: r.name.clone(),
            nodes,
            point: r.point,
        });
    }
    Ok(bc)
}

/// Builds mesh, boundary conditions and the constrained system of a body.
pub fn prepare(
    spec: &FeBodySpec,
    base: &Path,
    progress: &mut dyn FnMut(Stage),
) -> Result<PreparedBody, PipelineError> {
    prepare_keeping_mass(spec, base, false, progress).map(|(body, _)| body)
}

/// [`prepare`], also returning the unconstrained mass matrix (mesh DOF numbering,
/// [`flexmbs_fe::assembly::DofMap::from_counts`]`(mesh.node_dofs())`), built-in or imported.
/// With `free_export` a CalculiX import runs without the deck's `*BOUNDARY` (which would remove
/// the fixed nodes' mass from the export); the boundary conditions are applied by flexmbs.
pub(crate) fn prepare_keeping_mass(
    spec: &FeBodySpec,
    base: &Path,
    free_export: bool,
    progress: &mut dyn FnMut(Stage),
) -> Result<(PreparedBody, flexmbs_fe::SparseMatrix), PipelineError> {
    progress(Stage::Started("meshing".into()));
    let mesh = build_mesh(spec, base)?;
    let bc = boundary_conditions(&mesh, &spec.boundary)?;
    if !matches!(
        spec.mesh,
        MeshSpec::Calculix {
            matrices: CcxMatrices::Ccx,
            ..
        }
    ) {
        // CalculiX's matrices may couple parts through its equations (*EQUATION, *TIE)
        check_connected(spec, &mesh, &bc)?;
    }
    let mass = match spec.reduction.mass {
        MassName::Lumped => MassKind::Lumped,
        MassName::Consistent => MassKind::Consistent,
    };
    let assembled = match &spec.mesh {
        MeshSpec::Calculix {
            deck,
            matrices: CcxMatrices::Ccx,
        } => {
            progress(Stage::Started("running ccx (matrix export)".into()));
            let path = resolve(base, deck);
            let assembled = if free_export {
                crate::full_mass::import_free_matrices(&path, &mesh)?
            } else {
                flexmbs_io::calculix::import_matrices(&path, &mesh)?
            };
            if mass == MassKind::Lumped {
                progress(Stage::Started(
                    "ccx mass matrices are consistent; lumping not applied".into(),
                ));
            }
            assembled
        }
        _ => {
            progress(Stage::Started("assembling".into()));
            flexmbs_fe::assembly::assemble(&mesh, mass, &[], &mut |done, total| {
                progress(Stage::Assembly { done, total })
            })
            .map_err(fe("assembly"))?
        }
    };
    let system = FeSystem::from_assembled(&mesh, &assembled, &bc).map_err(fe("body.boundary"))?;
    let mut interface = Vec::new();
    for (i, sel) in spec.reduction.interface.iter().enumerate() {
        let key = format!("body.reduction.interface[{i}]");
        if let NodeSelector::Set(name) = sel {
            if let Some(r) = bc.rigid.iter().position(|r| &r.name == name) {
                interface.push(system.map.interface_nodes[r]);
                continue;
            }
        }
        interface.extend(select_nodes(&mesh, sel, &key)?);
    }
    if spec.reduction.method == ReductionMethod::Modal {
        check_mode_count(&system, spec.reduction.modes)?;
    }
    let static_loads = static_load_patterns(spec, &mesh, &system)?;
    let source = describe_source(spec, base);
    Ok((
        PreparedBody {
            mesh,
            bc,
            system,
            interface,
            static_loads,
            source,
        },
        assembled.m,
    ))
}

/// The load patterns of `reduction.static_loads` over the independent DOFs, named by their index
/// (1-based); a selection without nodes or on fixed nodes only is a located error.
fn static_load_patterns(
    spec: &FeBodySpec,
    mesh: &Mesh,
    system: &FeSystem,
) -> Result<Vec<StaticLoad>, PipelineError> {
    let mut out = Vec::new();
    for (i, l) in spec.reduction.static_loads.iter().enumerate() {
        let key = format!("body.reduction.static_loads[{i}]");
        let norm = l.direction.iter().map(|c| c * c).sum::<f64>().sqrt();
        let dir = l.direction.map(|c| c / norm);
        let (weights, what) = match (&l.nodes, l.point) {
            (None, Some(p)) if l.face.is_some() => {
                let face = l.face.as_deref().unwrap_or_default();
                let w = crate::face_load::face_point_weights(mesh, face, p).map_err(|message| {
                    PipelineError::Model {
                        path: format!("{key}.point"),
                        message,
                    }
                })?;
                (w, "point")
            }
            (Some(sel), _) => {
                let nodes = select_nodes(mesh, sel, &format!("{key}.nodes"))?;
                let share = 1.0 / nodes.len().max(1) as f64;
                let w: Vec<(NodeIdx, f64)> = nodes.iter().map(|&n| (n, share)).collect();
                (w, "nodes")
            }
            (None, Some(p)) => {
                let w = flexmbs_fe::point_load::point_weights(mesh, p).map_err(|e| {
                    PipelineError::Model {
                        path: format!("{key}.point"),
                        message: e.to_string(),
                    }
                })?;
                (w, "point")
            }
            (None, None) => {
                return Err(PipelineError::Model {
                    path: key,
                    message: "give `nodes` or `point`".into(),
                })
            }
        };
        let force = system.map.weighted_nodal_load(&weights, dir);
        if force.iter().all(|f| *f == 0.0) {
            return Err(PipelineError::Model {
                path: format!("{key}.{what}"),
                message: format!(
                    "loads {} nodes, none of them free to move along {dir:?}: the load has no \
                     effect",
                    weights.len()
                ),
            });
        }
        out.push(StaticLoad {
            name: (i + 1).to_string(),
            force,
        });
    }
    Ok(out)
}

fn describe_source(spec: &FeBodySpec, base: &Path) -> String {
    match &spec.mesh {
        MeshSpec::Calculix { deck, matrices } => format!(
            "CalculiX deck {} (matrices: {matrices:?})",
            resolve(base, deck).display()
        ),
        MeshSpec::Seed { dir } => format!("seed 4-file folder {}", resolve(base, dir).display()),
        other => format!("built-in mesh {other:?}"),
    }
}

/// Key path of the mesh source of `spec`: where mesh-wide problems are reported.
fn mesh_key(spec: &FeBodySpec) -> &'static str {
    match spec.mesh {
        MeshSpec::Calculix { .. } => "body.mesh.deck",
        MeshSpec::Seed { .. } => "body.mesh.dir",
        _ => "body.mesh",
    }
}

/// The structure must be one connected part ([`flexmbs_fe::mechanism::mesh_parts`]): parts that
/// share no node, rigid interface or support move apart without strain energy.
fn check_connected(
    spec: &FeBodySpec,
    mesh: &Mesh,
    bc: &BoundaryConditions,
) -> Result<(), PipelineError> {
    let parts = flexmbs_fe::mechanism::mesh_parts(mesh, bc);
    if parts.len() < 2 {
        return Ok(());
    }
    let sizes: Vec<String> = parts.iter().map(|p| p.len().to_string()).collect();
    let id = |p: &Vec<NodeIdx>| mesh.node_ids[p[0]];
    Err(PipelineError::Model {
        path: mesh_key(spec).into(),
        message: format!(
            "the mesh has {} parts not connected to each other ({} nodes; e.g. node {} and node \
             {} share no element, rigid interface or support): each part would move on its own \
             without strain energy, which no elastic mode can describe; join the parts (shared \
             nodes, a rigid interface) or model them as separate bodies",
            parts.len(),
            sizes.join(" + "),
            id(&parts[0]),
            id(&parts[1])
        ),
    })
}

/// A located error for a mechanism found by the modal analysis ([`FeError::Mechanism`]): at the
/// element type when the mesh has reduced-integration hex20r elements (hourglass modes), at the
/// supports when it has fixed nodes, at the mesh otherwise.
fn mechanism_error(spec: &FeBodySpec, body: &PreparedBody, e: FeError) -> PipelineError {
    let hex20r = body
        .mesh
        .elements
        .iter()
        .any(|el| el.kind == ElementKind::Hex20R);
    let (path, cause) = match &spec.mesh {
        MeshSpec::Calculix { .. } | MeshSpec::Seed { .. } => (mesh_key(spec), ""),
        _ if hex20r => (
            "body.mesh.element",
            "the mesh has hex20r elements (reduced integration): with one element across a \
             section their hourglass modes have zero energy; ",
        ),
        _ if !body.bc.fixed.is_empty() => ("body.boundary.fixed", ""),
        _ => ("body.mesh", ""),
    };
    PipelineError::Model {
        path: path.into(),
        message: format!("{cause}{e}"),
    }
}

/// Eigen solver options from the spec.
pub fn eigen_options(spec: &FeBodySpec) -> EigenOptions {
    let r = &spec.reduction;
    EigenOptions {
        n_modes: r.modes,
        shift: r.shift,
        tol: r.tol,
        // a roomier Krylov basis than the solver's default (max(4k, 2k + 80)): with 30 modes the
        // default restarts stagnated at residuals of 1e-7 (complex beam example)
        max_basis: (8 * r.modes).max(2 * r.modes + 120),
        method: match r.solver {
            SolverName::Auto => EigenMethod::Auto,
            SolverName::Dense => EigenMethod::Dense,
            SolverName::Lanczos => EigenMethod::Lanczos,
        },
        ..EigenOptions::default()
    }
}

/// `n_modes` elastic modes must exist: at most the independent DOFs minus the 6 rigid-body
/// modes of a body without fixed nodes.
fn check_mode_count(system: &FeSystem, n_modes: usize) -> Result<(), PipelineError> {
    let ndof = system.len();
    let rigid = if system.map.fixed_nodes.is_empty() {
        6
    } else {
        0
    };
    if n_modes + rigid > ndof {
        return Err(PipelineError::Model {
            path: "body.reduction.modes".into(),
            message: format!(
                "{n_modes} elastic modes requested, but the FE model has {ndof} independent DOFs{}: at most {} elastic modes (refine the mesh for more)",
                if rigid > 0 { " and 6 rigid-body modes" } else { "" },
                ndof.saturating_sub(rigid)
            ),
        });
    }
    Ok(())
}

/// Modal analysis of a prepared body: `n_modes` elastic modes (plus rigid-body modes if free).
pub fn run_modal(
    spec: &FeBodySpec,
    body: &PreparedBody,
    n_modes: usize,
    progress: &mut dyn FnMut(Stage),
) -> Result<ModalResult, PipelineError> {
    check_mode_count(&body.system, n_modes)?;
    progress(Stage::Started("eigen solution".into()));
    modal_analysis(&body.system, n_modes, &eigen_options(spec), &mut |e| {
        progress(Stage::Eigen(e))
    })
    .map_err(|e| match e {
        FeError::Mechanism { .. } => mechanism_error(spec, body, e),
        e => fe("modal analysis")(e),
    })
}

/// The reduced body the spec asks for.
pub fn run_reduction(
    spec: &FeBodySpec,
    body: &PreparedBody,
    progress: &mut dyn FnMut(Stage),
) -> Result<ReducedBody, PipelineError> {
    let provenance = Provenance {
        source: body.source.clone(),
        program: format!("flexmbs {}", env!("CARGO_PKG_VERSION")),
        notes: format!(
            "{} nodes, {} elements, {} independent DOFs, mass {:?}, reduction {:?}",
            body.mesh.num_nodes(),
            body.mesh.elements.len(),
            body.system.len(),
            spec.reduction.mass,
            spec.reduction.method
        ),
    };
    let r = &spec.reduction;
    match r.method {
        ReductionMethod::Modal => {
            let modal = run_modal(spec, body, r.modes, progress)?;
            if !body.static_loads.is_empty() {
                progress(Stage::Started("static load responses".into()));
            }
            reduce_modal_augmented(
                &body.mesh,
                &body.system,
                &modal,
                r.modes,
                &body.static_loads,
                &spec.name,
                provenance,
            )
            .map_err(|e| match e {
                FeError::Invalid(message) if !body.static_loads.is_empty() => {
                    PipelineError::Model {
                        path: "body.reduction.static_loads".into(),
                        message,
                    }
                }
                e => fe("reduction")(e),
            })
        }
        ReductionMethod::CraigBampton | ReductionMethod::Guyan => {
            let k = if r.method == ReductionMethod::Guyan {
                0
            } else {
                r.modes
            };
            progress(Stage::Started("Craig-Bampton reduction".into()));
            craig_bampton(
                &body.mesh,
                &body.system,
                &CraigBamptonOptions {
                    interface: &body.interface,
                    internal_modes: k,
                    eigen: &eigen_options(spec),
                },
                &spec.name,
                provenance,
                &mut |e| progress(Stage::Eigen(e)),
            )
            .map_err(|e| match e {
                // K_II singular: a mechanism with the interface held
                FeError::NotPositiveDefinite { ref what, .. } if what.starts_with("K_II") => {
                    mechanism_error(spec, body, e)
                }
                e => fe("Craig-Bampton reduction")(e),
            })
        }
    }
}

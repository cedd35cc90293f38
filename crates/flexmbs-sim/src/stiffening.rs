//! Centrifugal geometric stiffening of an FFR body from its FE model (`geometric_stiffening =
//! true`): the unit-load method of [`flexmbs_fe::geometric::geometric_stiffness`] on the prepared
//! mesh and system of the body's FE model file, or the same matrices stored in a reduced-body
//! file (`.fmb.h5`, group `geometric`, written by `flexmbs reduce`), restricted to the selected
//! modes and converted to SI like the reduced body ([`flexmbs_core::ffr::reduced_body_to_si`]).

use flexmbs_fe::element::MassKind;
use flexmbs_fe::geometric::GeometricStiffness;
use flexmbs_fe::reduction::ReducedBody;
use flexmbs_fe::UnitSystem;
use flexmbs_io::model::{MassName, MeshSpec};
use flexmbs_reduce::pipeline::PreparedBody;

/// The FE model behind a reduced body read from an FE model file: the pipeline's prepared mesh,
/// boundary conditions and constrained system, and the element mass kind the system uses.
#[derive(Debug, Clone)]
pub struct FeModel {
    /// Mesh, boundary conditions and constrained system (body units).
    pub prepared: PreparedBody,
    /// Element mass kind of the system's mass matrix (inertial loads use the same).
    pub mass: MassKind,
}

impl FeModel {
    /// Mass kind of the system `prepare` assembles for `mesh`/`mass` of an FE model file: the
    /// requested kind, except that matrices exported by CalculiX are consistent
    /// ([`flexmbs_reduce::geometric::system_mass_kind`]).
    pub fn mass_kind(mesh: &MeshSpec, mass: MassName) -> MassKind {
        flexmbs_reduce::geometric::system_mass_kind(mesh, mass)
    }
}

/// Message of a reduced-body file without stored geometric stiffness asked for geometric
/// stiffening.
pub const NO_STORED_STIFFNESS: &str = "the reduced-body file has no geometric stiffness (group \
     `geometric`): re-export it with `flexmbs reduce` from an FE model with supports (fixed \
     nodes), or use the FE model file (.toml) as `source`";

/// Message of a free-free body (no fixed nodes) asked for geometric stiffening.
pub const NEEDS_SUPPORTS: &str =
    "geometric stiffening needs supports (fixed nodes in the FE model)";

/// The six centrifugal geometric stiffness matrices `K_G,ab` of `body` (reduced from `fe`, all
/// its modes, body units), supported on the fixed nodes of the FE model
/// ([`flexmbs_reduce::geometric::centrifugal_geometric_stiffness`], the same computation
/// `flexmbs reduce` stores in a reduced-body file). Errors as text: a body without fixed nodes
/// ([`NEEDS_SUPPORTS`]) or a failure of the FE computation.
pub fn centrifugal_stiffness(
    fe: &FeModel,
    body: &ReducedBody,
) -> Result<GeometricStiffness, String> {
    flexmbs_reduce::geometric::centrifugal_geometric_stiffness(&fe.prepared, fe.mass, body)
        .map_err(|e| format!("geometric stiffness: {e}"))?
        .ok_or_else(|| NEEDS_SUPPORTS.to_string())
}

/// `g` restricted to the basis vectors `cols` (0-based, in the order of the selection).
pub fn select_geometric_modes(g: &GeometricStiffness, cols: &[usize]) -> GeometricStiffness {
    GeometricStiffness {
        load_patterns: g.load_patterns.clone(),
        matrices: g
            .matrices
            .iter()
            .map(|m| faer::Mat::from_fn(cols.len(), cols.len(), |i, j| m[(cols[i], cols[j])]))
            .collect(),
    }
}

/// `g` (units `units`) in SI, scaled exactly like the modal stiffness by
/// [`flexmbs_core::ffr::reduced_body_to_si`]: `K_G` is `Φᵀ K_σ Φ` per (rad/s)² with `K_σ` a
/// stiffness (force/length), so it takes the factor `c² · stiffness_to_si` of `k_ff` (`c` =
/// [`UnitSystem::mode_to_si`]). With mass-normalised modes both factors are 1 in effect
/// (`K_G` is dimensionless), which the SI(mm) test checks.
pub fn geometric_to_si(g: &GeometricStiffness, units: UnitSystem) -> GeometricStiffness {
    let c = units.mode_to_si();
    let fk = c * c * units.stiffness_to_si();
    GeometricStiffness {
        load_patterns: g.load_patterns.clone(),
        matrices: g
            .matrices
            .iter()
            .map(|m| faer::Mat::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)] * fk))
            .collect(),
    }
}

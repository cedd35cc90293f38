//! What a body type supplies for its neutral contours (`docs/engine.md`, "Neutral contours"):
//! the [`NeutralContourSource`] its evaluated state implements, and the [`ContourNodes`] it
//! interpolates its contours from.
//!
//! A neutral contour interpolates, once at set-up, the undeformed positions `ū_0` of some
//! material nodes and the shape fields `φ_k` that multiply the body's **field coordinates**
//! `q_k` (body axes of a floating frame; [`crate::ffr::contour`]). A contour point at `(eta,
//! xi)` is then a material point of the body:
//!
//! ```text
//!     ū = ū_0(eta, xi) + Σ_k q_k φ_k(eta, xi),     r = R + A ū,     v = Ṙ + A (ω̄ × ū + Σ_k q̇_k φ_k),
//!     δr = δR + δπ × A ū + A Σ_k φ_k δq_k
//! ```
//!
//! with the floating frame `(R, A)`, its angular velocity `ω̄` (frame axes) and variation `δπ`
//! (global). The contact code needs only these quantities and the linear maps from the body's
//! velocity coordinates `u` to `(δR, δπ, δq)`, which the trait supplies as whole operations
//! (Jacobian of a material point, rows of the frame's rotation and of the field coordinates), so
//! a body type keeps its sparsity: an FFR body's `u = [Ṙ, w, q̇_f]` maps trivially, a
//! superelement's absolute interface velocities map through its frame recovery (`Z P`) and its
//! local coordinates (`Λ T P`).
//!
//! A body type opts in by creating its [`ElementScratch`] with
//! [`ElementScratch::with_contour_source`]; [`ElementScratch::contour_source`] then hands the
//! contact code the trait object, without it knowing the body type.
//!
//! [`ElementScratch`]: crate::element::ElementScratch
//! [`ElementScratch::with_contour_source`]: crate::element::ElementScratch::with_contour_source
//! [`ElementScratch::contour_source`]: crate::element::ElementScratch::contour_source

use faer::MatMut;
use nalgebra::{Matrix3, Vector3};

/// The evaluated state of a body with a floating frame and linear shape fields, as neutral
/// contours see it (module documentation). Implemented by the element's scratch content; every
/// method reads the state of the last [`crate::element::Element::update`] and is
/// allocation-free.
pub trait NeutralContourSource: Send + Sync {
    /// Rotation `A` of the floating frame (frame axes to global).
    fn frame_rotation(&self) -> &Matrix3<f64>;

    /// Angular velocity `ω̄` of the floating frame in its own axes.
    fn frame_angular_velocity(&self) -> &Vector3<f64>;

    /// The field coordinates `q` multiplying the shape fields (`n_q` of them).
    fn field_coordinates(&self) -> &[f64];

    /// Their rates `q̇`.
    fn field_velocities(&self) -> &[f64];

    /// Number of the body's velocity coordinates `n_u`: the columns of a contour point's
    /// Jacobian.
    fn num_velocities(&self) -> usize;

    /// The translational Jacobian `J_T` (3 x `n_u`, into `jt`) of the material point at `u`
    /// (frame axes, deformed) whose shape vectors are `phi` (`n_q` of them, frame axes):
    /// `δr = J_T δu`.
    fn point_jacobian(&self, u: &Vector3<f64>, phi: &[Vector3<f64>], jt: MatMut<'_, f64>);

    /// Adds the rigid rotation of an arm `d` (global) to `jac` (3 x `n_u`):
    /// `jac += -d~ J_π` with `δπ = J_π δu` (`δ(d) = δπ × d`).
    fn add_arm_jacobian(&self, d: &Vector3<f64>, jac: MatMut<'_, f64>);

    /// `J_π` (3 x `n_u`, global: `δπ = J_π δu`, `ω = J_π u`) into `jac` (every entry written).
    fn rotation_jacobian(&self, jac: MatMut<'_, f64>);

    /// `out[j] += scale (J_π̄ᵀ v)_j` for every body column `j`, with `J_π̄ = Aᵀ J_π` the frame
    /// rotation's map in frame axes and `v` a frame-axes vector (`out` has `n_u` entries).
    fn add_rotation_row(&self, v: &Vector3<f64>, scale: f64, out: &mut [f64]);

    /// `out[j] += (J_qᵀ c)_j` for every body column `j`, with `δq = J_q δu` and `c_k = c(k)`
    /// (`k < n_q`).
    fn add_field_row(&self, c: &dyn Fn(usize) -> f64, out: &mut [f64]);
}

/// The material nodes a body type offers for neutral contours: undeformed positions and the
/// translational shape vectors multiplying the field coordinates, both in the axes of the body's
/// floating frame ([`NeutralContourSource`]).
pub trait ContourNodes {
    /// Number of nodes.
    fn num_nodes(&self) -> usize;
    /// Undeformed position of node `i` (frame axes).
    fn node_position(&self, i: usize) -> Vector3<f64>;
    /// Number of field coordinates `n_q`.
    fn num_fields(&self) -> usize;
    /// Shape vector `φ_k` at node `i` (frame axes): the node's displacement per unit `q_k`.
    fn node_shape(&self, i: usize, k: usize) -> Vector3<f64>;
    /// Number of the body's velocity coordinates `n_u` ([`NeutralContourSource::num_velocities`]).
    fn num_velocities(&self) -> usize;
}

/// Nodes given as a table: positions and a `3 N x n_q` shape matrix (row `3 i + c`: component `c`
/// of node `i`), e.g. the FE nodes of a superelement with the translational rows of its
/// Craig-Bampton basis.
#[derive(Debug, Clone, PartialEq)]
pub struct NodeTable {
    /// Undeformed positions (frame axes).
    pub positions: Vec<Vector3<f64>>,
    /// Shape matrix, `3 N x n_q`.
    pub shapes: nalgebra::DMatrix<f64>,
    /// `n_u` of the body.
    pub velocities: usize,
}

impl ContourNodes for NodeTable {
    fn num_nodes(&self) -> usize {
        self.positions.len()
    }
    fn node_position(&self, i: usize) -> Vector3<f64> {
        self.positions[i]
    }
    fn num_fields(&self) -> usize {
        self.shapes.ncols()
    }
    fn node_shape(&self, i: usize, k: usize) -> Vector3<f64> {
        let s = &self.shapes;
        Vector3::new(s[(3 * i, k)], s[(3 * i + 1, k)], s[(3 * i + 2, k)])
    }
    fn num_velocities(&self) -> usize {
        self.velocities
    }
}

/// A source whose field coordinates and velocities are another's scaled (drawing a contour
/// with its deformation exaggerated). Its Jacobians are the unscaled source's.
pub struct ScaledSource<'a> {
    inner: &'a dyn NeutralContourSource,
    q: Vec<f64>,
    qd: Vec<f64>,
}

impl<'a> ScaledSource<'a> {
    /// `inner` with `q`, `q̇` times `scale` (allocates: for output).
    pub fn new(inner: &'a dyn NeutralContourSource, scale: f64) -> Self {
        let q = inner
            .field_coordinates()
            .iter()
            .map(|x| x * scale)
            .collect();
        let qd = inner.field_velocities().iter().map(|x| x * scale).collect();
        Self { inner, q, qd }
    }
}

impl NeutralContourSource for ScaledSource<'_> {
    fn frame_rotation(&self) -> &Matrix3<f64> {
        self.inner.frame_rotation()
    }
    fn frame_angular_velocity(&self) -> &Vector3<f64> {
        self.inner.frame_angular_velocity()
    }
    fn field_coordinates(&self) -> &[f64] {
        &self.q
    }
    fn field_velocities(&self) -> &[f64] {
        &self.qd
    }
    fn num_velocities(&self) -> usize {
        self.inner.num_velocities()
    }
    fn point_jacobian(&self, u: &Vector3<f64>, phi: &[Vector3<f64>], jt: MatMut<'_, f64>) {
        self.inner.point_jacobian(u, phi, jt)
    }
    fn add_arm_jacobian(&self, d: &Vector3<f64>, jac: MatMut<'_, f64>) {
        self.inner.add_arm_jacobian(d, jac)
    }
    fn rotation_jacobian(&self, jac: MatMut<'_, f64>) {
        self.inner.rotation_jacobian(jac)
    }
    fn add_rotation_row(&self, v: &Vector3<f64>, scale: f64, out: &mut [f64]) {
        self.inner.add_rotation_row(v, scale, out)
    }
    fn add_field_row(&self, c: &dyn Fn(usize) -> f64, out: &mut [f64]) {
        self.inner.add_field_row(c, out)
    }
}

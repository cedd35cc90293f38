//! Neutral contours of FFR bodies (seed 000 §3.2.2, §4.4): a NURBS surface through a grid of mesh
//! nodes (the node index matrix `O` (3.24), row `i` along `eta`, column `j` along `xi`), or a
//! NURBS curve through an ordered node list, with continuous position, velocity, orientation and
//! Jacobian fields for contact.
//!
//! The interpolation is linear in the node values, and an FFR node sits at `ū = u_0 + Φ q_f` in
//! body axes. So the undeformed positions and every mode shape are interpolated **once** at
//! set-up (knots and parameters from the undeformed geometry, chord length by default), and the
//! deformed contour of an evaluation is the control net `C(q_f) = C_0 + Σ_k q_f,k C_k` (O(n_ctrl
//! n_f), no solve). At a contour point `(eta, xi)` the body-axes position `ū`, the tangents
//! `t_eta`, `t_xi` (3.25)-(3.26) and the mode-shape matrix `Φ(eta, xi)` are field evaluations of
//! these nets, and the point moves as a material point of the body (the formula of mesh-node
//! frames, (2.70)):
//!
//! ```text
//!     r = R + A ū,   v = Ṙ + A (ω̄ × ū + Φ q̇_f),   J_T = [I, -A ū~ H, A Φ],
//!     n = A (t_eta × t_xi)/|..| (3.27, sign: outward),  t_1 = A t_eta/|t_eta| (3.28),  t_2 = n × t_1 (3.29).
//! ```
//!
//! The contact search runs on the deformed contour in body axes (the point transformed by
//! `Aᵀ (p - R)`), so the rigid motion never enters the search.
//!
//! Nothing here is specific to FFR bodies: the contours are built from any body's
//! [`ContourNodes`] (an FFR body's nodes and modes, a superelement's FE nodes and Craig-Bampton
//! basis) and evaluated from any [`NeutralContourSource`] (the field coordinates `q` in place of
//! `q_f`, the body's own point Jacobian in place of the FFR formula above).

use crate::contour_source::{ContourNodes, NeutralContourSource};
use faer::MatMut;
use flexmbs_fe::BoxFace;
use flexmbs_nurbs::{
    CurveInterpolator, CurveProjection, CurveScratch, CurveSearch, NurbsCurve, NurbsError,
    NurbsSurface, ParamMethod, SearchGrid, SearchSettings, SurfaceInterpolator, SurfaceProjection,
    SurfaceScratch, SurfaceSearch,
};
use nalgebra::Vector3;

/// Why a neutral contour cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ContourError {
    /// A node index the body does not have.
    #[error("contour node {node} does not exist (the body has {nodes} nodes)")]
    UnknownNode {
        /// The index.
        node: usize,
        /// Number of nodes of the body.
        nodes: usize,
    },
    /// A node listed twice.
    #[error("contour node {node} appears twice")]
    DuplicateNode {
        /// The index.
        node: usize,
    },
    /// The node index matrix is not `n_eta x n_xi`.
    #[error("the node index matrix has {got} entries, expected {rows} x {cols}")]
    Shape {
        /// Rows (`eta`).
        rows: usize,
        /// Columns (`xi`).
        cols: usize,
        /// Entries given.
        got: usize,
    },
    /// The NURBS set-up failed (too few nodes for the degree, coincident nodes, ...).
    #[error(transparent)]
    Nurbs(#[from] NurbsError),
}

/// Settings of a neutral contour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContourSettings {
    /// Degree in each direction (3: C^2, as sliding contact needs). Default 3.
    pub degree: usize,
    /// Parameters from the undeformed nodes. Default chord length.
    pub params: ParamMethod,
    /// Closed (periodic) in `eta` / `xi` (a tube's circumference). Default open.
    pub closed: [bool; 2],
    /// Flip the normal `t_eta × t_xi` so that it points out of the material. Default `false`.
    pub flip_normal: bool,
}

impl Default for ContourSettings {
    fn default() -> Self {
        Self {
            degree: 3,
            params: ParamMethod::ChordLength,
            closed: [false, false],
            flip_normal: false,
        }
    }
}

/// Checks node indices against the body: all exist, none twice.
fn check_nodes(body: &dyn ContourNodes, nodes: &[usize]) -> Result<(), ContourError> {
    let mut seen = vec![false; body.num_nodes()];
    for &n in nodes {
        let s = seen.get_mut(n).ok_or(ContourError::UnknownNode {
            node: n,
            nodes: body.num_nodes(),
        })?;
        if *s {
            return Err(ContourError::DuplicateNode { node: n });
        }
        *s = true;
    }
    Ok(())
}

/// Translational mode `k` at the listed nodes (body axes).
fn mode_values(body: &dyn ContourNodes, nodes: &[usize], k: usize) -> Vec<Vector3<f64>> {
    nodes.iter().map(|&n| body.node_shape(n, k)).collect()
}

/// The control nets of a neutral contour: undeformed `C_0` and one per translational mode `C_k`
/// (body axes), interpolated once; a deformation is their superposition.
#[derive(Debug, Clone)]
struct ModalNets {
    net0: Vec<Vector3<f64>>,
    modes: Vec<Vec<Vector3<f64>>>,
    /// The same nets control point by control point (`modes.rs`).
    by_ctrl: Vec<Vector3<f64>>,
    /// The mode nets as one column-major `3 n_ctrl x n_f` matrix (`modes.rs`).
    flat: Vec<f64>,
    /// `n_u` of the body ([`ContourNodes::num_velocities`]).
    velocities: usize,
}

mod modes;
mod source;
use modes::ModeShapes;

impl ModalNets {
    /// The nets of the listed nodes through `interpolate` (node values -> control points).
    fn new(
        body: &dyn ContourNodes,
        nodes: &[usize],
        n_ctrl: usize,
        interpolate: impl Fn(&[Vector3<f64>], &mut [Vector3<f64>]) -> Result<(), NurbsError>,
    ) -> Result<Self, NurbsError> {
        let u0: Vec<Vector3<f64>> = nodes.iter().map(|&n| body.node_position(n)).collect();
        let mut net0 = vec![Vector3::zeros(); n_ctrl];
        interpolate(&u0, &mut net0)?;
        let modes = (0..body.num_fields())
            .map(|k| {
                let mut net = vec![Vector3::zeros(); n_ctrl];
                interpolate(&mode_values(body, nodes, k), &mut net)?;
                Ok(net)
            })
            .collect::<Result<Vec<_>, NurbsError>>()?;
        let by_ctrl = Self::by_control_point(&modes, n_ctrl);
        let flat = modes
            .iter()
            .flatten()
            .flat_map(|v| v.iter().copied())
            .collect();
        Ok(Self {
            net0,
            modes,
            by_ctrl,
            flat,
            velocities: body.num_velocities(),
        })
    }
}

/// A 2D neutral contour of an FFR body: the NURBS surface through the node grid `O`.
#[derive(Debug, Clone)]
pub struct FfrSurfaceContour {
    interp: SurfaceInterpolator,
    nets: ModalNets,
    sign: f64,
}

/// The evaluated state of an [`FfrSurfaceContour`]: the deformed contour in body axes and the
/// evaluation scratch (one per contour, in the contact state; created once).
#[derive(Debug, Clone)]
pub struct SurfaceContourState {
    /// The deformed contour in body axes (for the contact search).
    pub surface: NurbsSurface,
    net: Vec<Vector3<f64>>,
    scratch: SurfaceScratch,
    shapes: ModeShapes,
}

/// Kinematics of a contour point `(eta, xi)` in global coordinates.
#[derive(Debug, Clone)]
pub struct ContourPoint {
    /// Position `r`.
    pub position: Vector3<f64>,
    /// Velocity of the material point there.
    pub velocity: Vector3<f64>,
    /// Outward unit normal `n` (3.27).
    pub normal: Vector3<f64>,
    /// Unit tangents `t_1` (3.28), `t_2` (3.29): with `n` an orthonormal right-handed frame.
    pub tangents: [Vector3<f64>; 2],
    /// Parametric tangents `t_eta`, `t_xi` (global, not normalized; the search's directions).
    pub t_param: [Vector3<f64>; 2],
    /// The point in body axes `ū`.
    pub local: Vector3<f64>,
}

impl FfrSurfaceContour {
    /// The contour through the nodes `grid` (row-major `n_eta x n_xi`, the matrix `O` of (3.24))
    /// of `body`. Interpolates the undeformed positions and the `n_f` mode shapes once.
    pub fn new(
        body: &dyn ContourNodes,
        grid: &[usize],
        n_eta: usize,
        n_xi: usize,
        settings: ContourSettings,
    ) -> Result<Self, ContourError> {
        if grid.len() != n_eta * n_xi {
            return Err(ContourError::Shape {
                rows: n_eta,
                cols: n_xi,
                got: grid.len(),
            });
        }
        check_nodes(body, grid)?;
        let u0: Vec<Vector3<f64>> = grid.iter().map(|&n| body.node_position(n)).collect();
        let degrees = [settings.degree; 2];
        let interp = SurfaceInterpolator::from_grid(
            &u0,
            n_eta,
            n_xi,
            settings.params,
            degrees,
            settings.closed,
        )?;
        let nets = ModalNets::new(body, grid, interp.n_ctrl(), |v, c| {
            interp.control_points_into(v, c)
        })?;
        Ok(Self {
            interp,
            nets,
            sign: if settings.flip_normal { -1.0 } else { 1.0 },
        })
    }

    /// The interpolator (parameters, knots) of the contour.
    pub fn interpolator(&self) -> &SurfaceInterpolator {
        &self.interp
    }

    /// Number of modes `n_f` the contour was interpolated with.
    pub fn num_modes(&self) -> usize {
        self.nets.modes.len()
    }

    /// Number of the body's velocity coordinates `n_u` (columns of a point's Jacobian).
    pub fn num_velocities(&self) -> usize {
        self.nets.velocities
    }

    /// A state for [`Self::update`] (allocates; create once).
    pub fn state(&self) -> Result<SurfaceContourState, ContourError> {
        let (eta, xi) = (self.interp.eta(), self.interp.xi());
        let surface = NurbsSurface::new(
            eta.knot_vector().clone(),
            xi.knot_vector().clone(),
            &self.nets.net0,
            &vec![1.0; self.nets.net0.len()],
        )?;
        let degrees = [eta.knot_vector().degree(), xi.knot_vector().degree()];
        Ok(SurfaceContourState {
            shapes: ModeShapes::new(degrees, self.num_modes(), self.nets.net0.len()),
            scratch: surface.scratch(),
            surface,
            net: self.nets.net0.clone(),
        })
    }

    /// The deformed contour of the evaluated body state `s`: `C = C_0 + Σ q_f,k C_k`.
    /// O(n_ctrl n_f), no allocation.
    pub fn update(
        &self,
        s: &dyn NeutralContourSource,
        state: &mut SurfaceContourState,
    ) -> Result<(), ContourError> {
        self.nets
            .deformed_into(s.field_coordinates(), &mut state.shapes, &mut state.net);
        state.surface.set_control_points(&state.net)?;
        Ok(())
    }

    /// Kinematics of the contour point `(eta, xi)` for the body state `s` (positions `r`,
    /// velocity `r_dot` of the floating frame) and the contour `state` updated for it.
    pub fn point(
        &self,
        r: &Vector3<f64>,
        r_dot: &Vector3<f64>,
        s: &dyn NeutralContourSource,
        state: &mut SurfaceContourState,
        eta: f64,
        xi: f64,
    ) -> Result<ContourPoint, ContourError> {
        let d = self
            .interp
            .field_derivatives(&state.net, eta, xi, &mut state.scratch)?;
        self.nets
            .surface_shapes(&self.interp, eta, xi, &mut state.shapes)?;
        let mut phi_qd = Vector3::zeros();
        for (phi_k, qd) in state.shapes.phi.iter().zip(s.field_velocities()) {
            phi_qd += phi_k * *qd;
        }
        Ok(material_point(
            r,
            r_dot,
            s,
            d[0],
            phi_qd,
            [d[1], d[2]],
            self.sign,
        ))
    }

    /// Translational Jacobian `J_T = [I, -A ū~ H, A Φ(eta, xi)]` (3 x n_u) of the contour point
    /// `(eta, xi)` into `jt`.
    pub fn jacobian_translation(
        &self,
        s: &dyn NeutralContourSource,
        state: &mut SurfaceContourState,
        eta: f64,
        xi: f64,
        jt: MatMut<'_, f64>,
    ) -> Result<(), ContourError> {
        let u = self
            .interp
            .field_derivatives(&state.net, eta, xi, &mut state.scratch)?[0];
        self.nets
            .surface_shapes(&self.interp, eta, xi, &mut state.shapes)?;
        s.point_jacobian(&u, &state.shapes.phi, jt);
        Ok(())
    }
}

impl SurfaceContourState {
    /// A contact search on this contour (coarse grids `[eta, xi]`; allocates, create once).
    pub fn new_search(
        &self,
        grids: [SearchGrid; 2],
        settings: SearchSettings,
    ) -> Result<SurfaceSearch, NurbsError> {
        SurfaceSearch::new(&self.surface, grids, settings)
    }

    /// The normal projection of `x` (body axes) onto the deformed contour (seed Alg. 6: warm
    /// start from the search's last solution, full search on failure); `None`: none.
    pub fn project(
        &mut self,
        search: &mut SurfaceSearch,
        x: &Vector3<f64>,
    ) -> Option<SurfaceProjection> {
        search.search(&self.surface, &mut self.scratch, x)
    }
}

impl CurveContourState {
    /// A contact search on this contour (coarse grid; allocates, create once).
    pub fn new_search(
        &self,
        grid: SearchGrid,
        settings: SearchSettings,
    ) -> Result<CurveSearch, NurbsError> {
        CurveSearch::new(&self.curve, grid, settings)
    }

    /// The normal projection of `x` (body axes) onto the deformed contour; `None`: none.
    pub fn project(
        &mut self,
        search: &mut CurveSearch,
        x: &Vector3<f64>,
    ) -> Option<CurveProjection> {
        search.search(&self.curve, &mut self.scratch, x)
    }
}

/// A 1D neutral contour of an FFR body: the NURBS curve through an ordered node list (a beam's
/// axis, an edge).
#[derive(Debug, Clone)]
pub struct FfrCurveContour {
    interp: CurveInterpolator,
    nets: ModalNets,
}

/// The evaluated state of an [`FfrCurveContour`] (see [`SurfaceContourState`]).
#[derive(Debug, Clone)]
pub struct CurveContourState {
    /// The deformed contour in body axes.
    pub curve: NurbsCurve,
    net: Vec<Vector3<f64>>,
    scratch: CurveScratch,
    shapes: ModeShapes,
}

impl FfrCurveContour {
    /// The contour through `nodes` (in order) of `body`; `settings.closed[0]` closes it.
    pub fn new(
        body: &dyn ContourNodes,
        nodes: &[usize],
        settings: ContourSettings,
    ) -> Result<Self, ContourError> {
        check_nodes(body, nodes)?;
        let u0: Vec<Vector3<f64>> = nodes.iter().map(|&n| body.node_position(n)).collect();
        let interp = CurveInterpolator::from_points(
            &u0,
            settings.params,
            settings.degree,
            settings.closed[0],
        )?;
        let nets = ModalNets::new(body, nodes, interp.n_ctrl(), |v, c| {
            interp.control_points_into(v, c)
        })?;
        Ok(Self { interp, nets })
    }

    /// The interpolator (parameters, knots) of the contour.
    pub fn interpolator(&self) -> &CurveInterpolator {
        &self.interp
    }

    /// Number of modes `n_f` the contour was interpolated with.
    pub fn num_modes(&self) -> usize {
        self.nets.modes.len()
    }

    /// Number of the body's velocity coordinates `n_u` (columns of a point's Jacobian).
    pub fn num_velocities(&self) -> usize {
        self.nets.velocities
    }

    /// A state for [`Self::update`] (allocates; create once).
    pub fn state(&self) -> Result<CurveContourState, ContourError> {
        let net_w = self.nets.net0.iter().map(|p| p.push(1.0)).collect();
        let curve = NurbsCurve::from_knot_vector(self.interp.knot_vector().clone(), net_w)?;
        let degree = self.interp.knot_vector().degree();
        Ok(CurveContourState {
            shapes: ModeShapes::new([degree; 2], self.num_modes(), self.nets.net0.len()),
            scratch: self.interp.scratch(),
            curve,
            net: self.nets.net0.clone(),
        })
    }

    /// The deformed contour of the evaluated body state `s`. O(n_ctrl n_f), no allocation.
    pub fn update(
        &self,
        s: &dyn NeutralContourSource,
        state: &mut CurveContourState,
    ) -> Result<(), ContourError> {
        self.nets
            .deformed_into(s.field_coordinates(), &mut state.shapes, &mut state.net);
        state.curve.set_control_points(&state.net)?;
        Ok(())
    }

    /// Position, velocity and the curve tangent (`tangents[0]`, unit; `normal` and
    /// `tangents[1]` are zero: a curve has no normal of its own) of the point at `eta`.
    pub fn point(
        &self,
        r: &Vector3<f64>,
        r_dot: &Vector3<f64>,
        s: &dyn NeutralContourSource,
        state: &mut CurveContourState,
        eta: f64,
    ) -> Result<ContourPoint, ContourError> {
        let d = self
            .interp
            .field_derivatives(&state.net, eta, &mut state.scratch)?;
        self.nets
            .curve_shapes(&self.interp, eta, &mut state.shapes)?;
        let mut phi_qd = Vector3::zeros();
        for (phi_k, qd) in state.shapes.phi.iter().zip(s.field_velocities()) {
            phi_qd += phi_k * *qd;
        }
        let mut p = material_point(r, r_dot, s, d[0], phi_qd, [d[1], Vector3::zeros()], 1.0);
        p.normal = Vector3::zeros();
        p.tangents[1] = Vector3::zeros();
        Ok(p)
    }

    /// The deformed curve (body axes) at `eta`: `[ū, ū', ū'']` (derivatives by `eta`), from
    /// the state updated by [`Self::update`]. Allocation-free.
    pub fn fields(
        &self,
        state: &mut CurveContourState,
        eta: f64,
    ) -> Result<[Vector3<f64>; 3], ContourError> {
        Ok(self
            .interp
            .field_derivatives(&state.net, eta, &mut state.scratch)?)
    }

    /// Mode `k`'s interpolated shape on the curve at `eta`: `[Φ_k, Φ_k', Φ_k'']` (body axes).
    /// Allocation-free.
    pub fn mode_fields(
        &self,
        state: &mut CurveContourState,
        eta: f64,
        k: usize,
    ) -> Result<[Vector3<f64>; 3], ContourError> {
        Ok(self
            .interp
            .field_derivatives(&self.nets.modes[k], eta, &mut state.scratch)?)
    }

    /// Every mode's slope on the curve at `eta`, `[Φ_0', ..., Φ_{n_f-1}']` (body axes), from one
    /// basis evaluation shared with [`Self::jacobian_translation`] at the same `eta`: bitwise
    /// the `[1]` of [`Self::mode_fields`]. Allocation-free.
    pub fn mode_slopes<'s>(
        &self,
        state: &'s mut CurveContourState,
        eta: f64,
    ) -> Result<&'s [Vector3<f64>], ContourError> {
        self.nets
            .curve_shapes(&self.interp, eta, &mut state.shapes)?;
        Ok(&state.shapes.phi1)
    }

    /// `J_T` (3 x n_u) of the curve point at `eta` into `jt`.
    pub fn jacobian_translation(
        &self,
        s: &dyn NeutralContourSource,
        state: &mut CurveContourState,
        eta: f64,
        jt: MatMut<'_, f64>,
    ) -> Result<(), ContourError> {
        let u = self
            .interp
            .field_derivatives(&state.net, eta, &mut state.scratch)?[0];
        self.nets
            .curve_shapes(&self.interp, eta, &mut state.shapes)?;
        s.point_jacobian(&u, &state.shapes.phi, jt);
        Ok(())
    }
}

/// Global kinematics of a material point at `u` (body axes) with elastic velocity `phi_qd`
/// (`Φ q̇_f`) and body-axes parametric tangents `t`: (2.70) and (3.27)-(3.29).
fn material_point(
    r: &Vector3<f64>,
    r_dot: &Vector3<f64>,
    s: &dyn NeutralContourSource,
    u: Vector3<f64>,
    phi_qd: Vector3<f64>,
    t: [Vector3<f64>; 2],
    sign: f64,
) -> ContourPoint {
    let a = *s.frame_rotation();
    let (te, tx) = (a * t[0], a * t[1]);
    let n = te.cross(&tx);
    let n = if n.norm() > 0.0 {
        sign * n / n.norm()
    } else {
        n
    };
    let t1 = if te.norm() > 0.0 { te / te.norm() } else { te };
    let t2 = n.cross(&t1);
    let t2 = if t2.norm() > 0.0 { t2 / t2.norm() } else { t2 };
    ContourPoint {
        position: r + a * u,
        velocity: r_dot + a * (s.frame_angular_velocity().cross(&u) + phi_qd),
        normal: n,
        tangents: [t1, t2],
        t_param: [te, tx],
        local: u,
    }
}

/// The node index matrix `O` (3.24) of the bounding-box face `face` of the nodes `points`
/// ([`face_grid`] on the face's plane, within 1e-6 of the bounding box's diagonal): what a
/// surface contour or a face load given by `face = "xmin"` ... `"zmax"` is built on.
pub fn box_face_grid(points: &[Vector3<f64>], face: BoxFace) -> Option<(Vec<usize>, usize, usize)> {
    let first = *points.first()?;
    let (lo, hi) = points
        .iter()
        .fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
    let plane = face.plane(lo.into(), hi.into());
    face_grid(points, face.axis(), plane, 1e-6 * (hi - lo).norm())
}

/// The node index matrix `O` (3.24) of a face of a structured mesh: the nodes with coordinate
/// `axis` equal to `value` (within `tol`), rows along the first other axis (`eta`), columns along
/// the second (`xi`), each sorted ascending. Serendipity meshes (20-node hexahedra) have midside
/// nodes on one family of grid lines only: the rows are the lines carrying the most nodes, the
/// columns the stations present on every row, so the grid is complete. Returns `(O row-major,
/// n_eta, n_xi)`, or `None` when fewer than 2 x 2 nodes form a grid.
pub fn face_grid(
    points: &[Vector3<f64>],
    axis: usize,
    value: f64,
    tol: f64,
) -> Option<(Vec<usize>, usize, usize)> {
    let (i1, i2) = match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    let face: Vec<usize> = (0..points.len())
        .filter(|&n| (points[n][axis] - value).abs() <= tol)
        .collect();
    // stations along each direction, merged within `tol`
    let stations = |k: usize| {
        let mut v: Vec<f64> = face.iter().map(|&n| points[n][k]).collect();
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| (*a - *b).abs() <= tol);
        v
    };
    let (s1, s2) = (stations(i1), stations(i2));
    let find = |a: f64, b: f64| {
        face.iter()
            .copied()
            .find(|&n| (points[n][i1] - a).abs() <= tol && (points[n][i2] - b).abs() <= tol)
    };
    let count = |a: f64| s2.iter().filter(|&&b| find(a, b).is_some()).count();
    let full = s1.iter().map(|&a| count(a)).max()?;
    let rows: Vec<f64> = s1.into_iter().filter(|&a| count(a) == full).collect();
    let cols: Vec<f64> = s2
        .into_iter()
        .filter(|&b| rows.iter().all(|&a| find(a, b).is_some()))
        .collect();
    if rows.len() < 2 || cols.len() < 2 {
        return None;
    }
    let grid = rows
        .iter()
        .flat_map(|&a| cols.iter().map(move |&b| (a, b)))
        .map(|(a, b)| find(a, b))
        .collect::<Option<Vec<usize>>>()?;
    Some((grid, rows.len(), cols.len()))
}

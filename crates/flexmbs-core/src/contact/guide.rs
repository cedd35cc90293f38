//! A bilateral guide: the origin of a frame (a slider, the centre of a ball) kept on a 1D neutral
//! contour of a flexible body (a beam's neutral axis; any body supplying a
//! [`crate::contour_source::NeutralContourSource`]), optionally with the frame's rotation following
//! the contour frame (seed 000 §5.3, a ball sliding on a beam).
//!
//! The guide is a constraint with joint rows (`g`, `G`, counted in [`crate::Model::nc`], its
//! multipliers in [`crate::State::lambda`]), so every stepper that handles joints handles it: the
//! Moreau steppers solve its rows on velocity level and project the positions, generalized-alpha
//! takes `g` and `G`. Per evaluation ([`crate::system::update_constraints`]):
//! 1. the deformed curve from the body's modal coordinates, and the slider point `c` in body
//!    axes, `x̄ = Aᵀ (c - R)`, projected on it by the contact search (warm start from the last
//!    parameter, full search on failure): the curve point `C` at `eta`, `d = c - r_C`;
//! 2. the **contour frame** `(t, n_1, n_2)`: `τ = ū'/|ū'|`, `n̄_1` the body-axes reference
//!    direction `ν` made perpendicular to `τ`, `n̄_2 = τ × n̄_1`, global `t = A τ`, ... It comes
//!    from the body's material frame along the curve (the normals are defined on the axis, where
//!    a radial direction is not). A solid body's nodes carry no rotations: the frame follows the
//!    curve's bending, not the section's torsion;
//! 3. rows `g_i = n_iᵀ (c - r_C)` (`i = 1, 2`) and, with rotations, the vector part of the
//!    relative rotation `Cᵀ B` of the slider frame `B` and the contour frame `C`,
//!    `g = 1/2 (c_k·b_j - c_j·b_k)` (`(i, j, k)` cyclic, as a fixed joint): the slider frame's
//!    axes stay on the contour frame's `(t, n_1, n_2)`.
//!
//! The rows' Jacobian `G` is exact at any state, not only on the constraint manifold: with the
//! contour frame's angular velocity `ω_C`,
//! `ġ_i = n_iᵀ (v_c - v_C) + (n_i × d)ᵀ ω_C` (the curve point's motion along `t` drops out,
//! `n_i ⊥ t`) and `ġ_rot = r_iᵀ (ω_B - ω_C)` with `r_i = 1/2 (b_j × c_k - b_k × c_j)`.
//! `ω_C = A (ω̄ + ω̄_rel)`, the frame's rotation relative to the body
//! `ω̄_rel = m̄ (n̄_2·τ̇) + n̄_2 (n̄_1·τ̇)`, `m̄ = -(ν·τ)/|P_τ ν| τ - n̄_1`, from the tangent rate
//! `τ̇ = P_τ (ū'' η̇ + Φ' q̇_f)/|ū'|`, and the parameter rate of the projection (differentiating
//! `ū'ᵀ (x̄ - ū) = 0`):
//! `η̇ = [tᵀ (v_c - v_C) - ω̄ᵀ (d̄ × ū') + (Φ' q̇_f)ᵀ d̄] / (|ū'|² - ū''ᵀ d̄)` with `t = A ū'`.
//! All are linear in `u`. `g_t = 0`; the acceleration bias `Ġ u` is not computed (zero): the
//! index-1 forms (DOPRI5, consistent initial accelerations) see an approximate `g̈`, the
//! velocity-level Moreau steps and the index-3 generalized-alpha iteration do not use it.
//!
//! Beyond an open end of the curve (no normal projection) the rows hold at the nearest end
//! point: the slider continues on the end's normal planes, and [`GuideWork::beyond_end`] is set.

use super::NeutralCurve;
use crate::contour_source::NeutralContourSource;
use crate::element::{ElementScratch, FrameKinematics};
use crate::error::ModelError;
use crate::ffr::contour::{CurveContourState, FfrCurveContour};
use crate::ids::FrameId;
use crate::model::{Frame, FrameOwner, Model};
use faer::{Mat, MatMut};
use flexmbs_nurbs::{CurveSearch, SearchGrid, SearchSettings};
use nalgebra::{Matrix3, Vector3};

/// Most rows of a guide: two translations, three rotations.
pub const MAX_GUIDE_ROWS: usize = 5;

/// A bilateral guide of the origin of `frame` on a 1D neutral contour (module documentation).
#[derive(Debug, Clone)]
pub struct CurveGuide {
    /// Name (messages and output).
    pub name: String,
    /// The curve (its frame is the reference frame of its body; its tube radius is unused).
    pub curve: NeutralCurve,
    /// The slider frame: its origin stays on the curve.
    pub frame: FrameId,
    /// The reference direction `ν` of the contour frame's first normal `n_1`, in the curve
    /// body's axes (not along the curve).
    pub normal: Vector3<f64>,
    /// The slider frame's axes follow the contour frame `(t, n_1, n_2)` (3 more rows).
    pub rotations: bool,
}

impl CurveGuide {
    /// A guide of `frame` on `curve` with the first normal along `normal` (body axes); with
    /// `rotations` the slider frame's axes also follow the contour frame.
    pub fn new(
        name: &str,
        curve: NeutralCurve,
        frame: FrameId,
        normal: Vector3<f64>,
        rotations: bool,
    ) -> Self {
        Self {
            name: name.to_string(),
            curve,
            frame,
            normal,
            rotations,
        }
    }

    /// Constraint rows: 2, or 5 with rotations.
    pub fn num_rows(&self) -> usize {
        if self.rotations {
            5
        } else {
            2
        }
    }

    /// Names of the rows in order: `n1`, `n2` (the slider's offset along the normals), then
    /// `rt`, `rn1`, `rn2` (the relative rotation about `t`, `n_1`, `n_2`).
    pub fn row_names(&self) -> &'static [&'static str] {
        const NAMES: [&str; MAX_GUIDE_ROWS] = ["n1", "n2", "rt", "rn1", "rn2"];
        &NAMES[..self.num_rows()]
    }

    /// Evaluation buffers (allocates; one per guide, in [`crate::state::SystemBuffers`]).
    pub fn new_work(&self) -> GuideWork {
        let contour = self.curve.contour();
        let state = contour
            .state()
            .expect("the contour's state was built when the curve was created");
        let grid = SearchGrid::Nodes(contour.interpolator().params().to_vec());
        let search = state
            .new_search(grid, SearchSettings::default())
            .expect("the contour's search was built when the curve was created");
        let nb = contour.num_velocities();
        GuideWork {
            state,
            search,
            jac_c: Mat::zeros(3, nb),
            jac_w: Mat::zeros(3, nb),
            rate: vec![vec![0.0; nb]; 3],
            rows: Mat::zeros(MAX_GUIDE_ROWS, nb),
            slider: [(Vector3::zeros(), Vector3::zeros()); MAX_GUIDE_ROWS],
            g: [0.0; MAX_GUIDE_ROWS],
            eta: f64::NAN,
            beyond_end: false,
            frame: [Vector3::zeros(); 3],
            point: Vector3::zeros(),
        }
    }
}

/// The evaluation buffers of a [`CurveGuide`]: deformed curve, search warm start, the rows.
#[derive(Debug, Clone)]
pub struct GuideWork {
    state: CurveContourState,
    search: CurveSearch,
    /// `J_C` of the curve point (3 x n_u of the body).
    jac_c: Mat<f64>,
    /// `J_ωC` of the contour frame, the body's columns (3 x n_u of the body).
    jac_w: Mat<f64>,
    /// Body columns of the rate rows `η̇`, `n̄_1·τ̇`, `n̄_2·τ̇` (times `|ū'|`).
    rate: Vec<Vec<f64>>,
    /// `G` rows in the body's columns.
    rows: Mat<f64>,
    /// Per row the coefficients `(t_s, r_s)` of the slider frame's `J_T`, `J_R`.
    slider: [(Vector3<f64>, Vector3<f64>); MAX_GUIDE_ROWS],
    /// Row values `g`.
    g: [f64; MAX_GUIDE_ROWS],
    /// Curve parameter of the projection at the last evaluation.
    pub eta: f64,
    /// The slider's projection lay beyond an open end at the last evaluation.
    pub beyond_end: bool,
    /// Contour frame `(t, n_1, n_2)` (global) at the last evaluation.
    pub frame: [Vector3<f64>; 3],
    /// The curve point `r_C` (global) at the last evaluation.
    pub point: Vector3<f64>,
}

impl GuideWork {
    /// Row values `g` of the last evaluation (length [`CurveGuide::num_rows`] used).
    pub fn values(&self) -> &[f64; MAX_GUIDE_ROWS] {
        &self.g
    }
}

/// Evaluation buffers of every guide of `model` (allocates).
pub fn new_works(model: &Model) -> Vec<GuideWork> {
    model.guides.iter().map(CurveGuide::new_work).collect()
}

/// Checks the guides: frames exist, the curve is on a contour-source body's reference frame with the
/// curve's mode count, the slider is on another owner, the normal is a finite non-zero vector.
pub(crate) fn check_guides(
    frames: &[Frame],
    owner_state: &dyn Fn(usize) -> Option<ElementScratch>,
    guides: &[CurveGuide],
) -> Result<(), ModelError> {
    for g in guides {
        let invalid = |reason: String| ModelError::InvalidContact {
            contact: g.name.clone(),
            reason,
        };
        let owner = |f: FrameId| {
            frames
                .get(f.0)
                .map(|fr| fr.owner)
                .ok_or_else(|| invalid(format!("unknown frame {f}")))
        };
        let (oc, os) = (owner(g.curve.frame)?, owner(g.frame)?);
        let cf = &frames[g.curve.frame.0];
        let at_origin = cf.local.mesh_node.is_none()
            && cf.local.position == Vector3::zeros()
            && cf.local.rotation == Matrix3::identity();
        let state = match oc {
            FrameOwner::Body(b) if at_origin => owner_state(b.0),
            _ => None,
        }
        .ok_or_else(|| {
            invalid(format!(
                "the curve's frame '{}' must be the reference frame of the body the curve \
                 belongs to",
                cf.name
            ))
        })?;
        super::Contour::check_owner(&g.curve, &state)
            .map_err(|r| invalid(format!("curve: {r}")))?;
        if oc == os {
            return Err(invalid(
                "the slider frame is on the curve's own body".into(),
            ));
        }
        if !(g.normal.norm() > 0.0 && g.normal.iter().all(|x| x.is_finite())) {
            return Err(invalid(
                "the normal direction must be a finite non-zero vector".into(),
            ));
        }
        // the contour frame needs the normal off the tangent: checked at the curve's nodes
        let contour = g.curve.contour();
        let nu = g.normal.normalize();
        if let Ok(mut st) = contour.state() {
            for (i, &eta) in contour.interpolator().params().iter().enumerate() {
                let Ok(f) = contour.fields(&mut st, eta) else {
                    continue;
                };
                if f[1].normalize().dot(&nu).abs() > 0.99 {
                    return Err(invalid(format!(
                        "the normal direction {:?} is (nearly) along the curve at its node {i}: \
                         choose a direction across the curve",
                        g.normal.as_slice()
                    )));
                }
            }
        }
    }
    Ok(())
}

/// Writes the rows of every guide of `model` into `g`, `G`, `g_t`, `g_bias` (from row
/// [`Model::guide_rows`] on) at the evaluated state (`frames`, `eval`). The rows' `G` entries
/// outside the two owners' columns are not touched (zero from the allocation on, as for joints).
/// Allocation-free.
#[allow(clippy::too_many_arguments)]
pub fn assemble_guides(
    model: &Model,
    frames: &[FrameKinematics],
    eval: &[ElementScratch],
    works: &mut [GuideWork],
    g: &mut [f64],
    mut g_jac: MatMut<'_, f64>,
    g_t: &mut [f64],
    g_bias: &mut [f64],
) {
    for ((guide, &r0), w) in model.guides.iter().zip(&model.guide_rows).zip(works) {
        let n = guide.num_rows();
        evaluate_guide(model, guide, frames, eval, w, true);
        g[r0..r0 + n].copy_from_slice(&w.g[..n]);
        g_t[r0..r0 + n].fill(0.0);
        g_bias[r0..r0 + n].fill(0.0);
        let body = model.frame_cols(guide.curve.frame);
        for j in 0..body.len() {
            let rows = &w.rows.col_as_slice(j)[..n];
            write_rows(g_jac.as_mut(), r0, n, body.global(j), |i| rows[i]);
        }
        let k = &frames[guide.frame.0];
        let cols = model.frame_cols(guide.frame);
        for j in 0..cols.len() {
            let (jt, jr) = (k.jac_t.col_as_slice(j), k.jac_r.col_as_slice(j));
            write_rows(g_jac.as_mut(), r0, n, cols.global(j), |i| {
                let (ts, rs) = &w.slider[i];
                let mut s = 0.0;
                for d in 0..3 {
                    s += ts[d] * jt[d] + rs[d] * jr[d];
                }
                s
            });
        }
    }
}

/// The values `g` of every guide's rows (from row [`Model::guide_rows`] on) at the evaluated
/// state, without `G`, `g_t`, `g_bias` (the Moreau steppers' position projection checks `g`
/// with the midpoint's `G`): the same projection and values as [`assemble_guides`], bit for bit.
/// Allocation-free.
pub fn guide_values(
    model: &Model,
    frames: &[FrameKinematics],
    eval: &[ElementScratch],
    works: &mut [GuideWork],
    g: &mut [f64],
) {
    for ((guide, &r0), w) in model.guides.iter().zip(&model.guide_rows).zip(works) {
        let n = guide.num_rows();
        evaluate_guide(model, guide, frames, eval, w, false);
        g[r0..r0 + n].copy_from_slice(&w.g[..n]);
    }
}

/// `G[r0 + i, c] = value(i)` for `i < n`: through the column's contiguous slice when `G` is
/// column-major (no per-entry bounds-checked indexing).
fn write_rows(g_jac: MatMut<'_, f64>, r0: usize, n: usize, c: usize, value: impl Fn(usize) -> f64) {
    let mut col = g_jac.col_mut(c).subrows_mut(r0, n);
    if let Some(contiguous) = col.as_mut().try_as_col_major_mut() {
        for (i, x) in contiguous.as_slice_mut().iter_mut().enumerate() {
            *x = value(i);
        }
        return;
    }
    for i in 0..n {
        col[i] = value(i);
    }
}

/// The contour source of the curve's body.
fn curve_body<'a>(
    model: &Model,
    guide: &CurveGuide,
    eval: &'a [ElementScratch],
) -> &'a dyn NeutralContourSource {
    let FrameOwner::Body(b) = model.frames[guide.curve.frame.0].owner else {
        unreachable!("checked when the model was compiled: the curve is on a body")
    };
    eval[b.0]
        .contour_source()
        .expect("checked when the model was compiled: the curve's body supplies contours")
}

/// The projection of `x` (body axes) on the deformed curve: `(eta, beyond an end)`.
fn project(contour: &FfrCurveContour, w: &mut GuideWork, x: &Vector3<f64>) -> (f64, bool) {
    if let Some(p) = w.state.project(&mut w.search, x) {
        return (p.eta, false);
    }
    let (lo, hi) = w.state.curve.domain();
    let dist = |eta: f64, w: &mut GuideWork| match contour.fields(&mut w.state, eta) {
        Ok(f) => (f[0] - x).norm(),
        Err(_) => f64::INFINITY,
    };
    let eta = if dist(lo, w) <= dist(hi, w) { lo } else { hi };
    (eta, true)
}

/// One guide's rows at the evaluated state into its work buffers (module documentation); with
/// `jacobian` false only the values `g` (and the projection, frame and point), not `G`.
fn evaluate_guide(
    model: &Model,
    guide: &CurveGuide,
    frames: &[FrameKinematics],
    eval: &[ElementScratch],
    w: &mut GuideWork,
    jacobian: bool,
) {
    let contour = guide.curve.contour();
    let s = curve_body(model, guide, eval);
    let (kc, ks) = (&frames[guide.curve.frame.0], &frames[guide.frame.0]);
    let fields = contour.update(s, &mut w.state).and_then(|_| {
        let x = s.frame_rotation().transpose() * (ks.position - kc.position);
        let (eta, beyond) = project(contour, w, &x);
        w.eta = eta;
        w.beyond_end = beyond;
        if jacobian {
            contour.jacobian_translation(s, &mut w.state, eta, w.jac_c.as_mut())?;
        }
        contour.fields(&mut w.state, eta)
    });
    let Ok([u, u1, u2]) = fields else {
        w.g = [f64::NAN; MAX_GUIDE_ROWS];
        return;
    };
    let a = *s.frame_rotation();
    let len = u1.norm();
    let tau = u1 / len;
    let p = guide.normal - guide.normal.dot(&tau) * tau;
    let (n1, pn) = (p / p.norm(), p.norm());
    let n2 = tau.cross(&n1);
    let c = [a * tau, a * n1, a * n2];
    w.frame = c;
    w.point = kc.position + a * u;
    let d = ks.position - w.point;
    for (i, ni) in [c[1], c[2]].iter().enumerate() {
        w.g[i] = ni.dot(&d);
    }
    let b = ks.rotation;
    if guide.rotations {
        for i in 0..3 {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            let (bj, bk) = (b.column(j).into_owned(), b.column(k).into_owned());
            w.g[2 + i] = 0.5 * (c[k].dot(&bj) - c[j].dot(&bk));
        }
    }
    if !jacobian {
        return;
    }
    let m = -guide.normal.dot(&tau) / pn * tau - n1;
    let db = a.transpose() * d;
    let t_full = a * u1;
    let den = len * len - u2.dot(&db);
    rate_rows(contour, s, w, &u1, &u2, &db, &t_full, &n1, &n2, den);
    // J_ωC (body columns): the body's J_π (FFR: A H on the rotation columns), plus
    // A m s_2 + A n_2 s_1
    let (am, an2) = (a * m, a * n2);
    s.rotation_jacobian(w.jac_w.as_mut());
    let nb = w.jac_w.ncols();
    for j in 0..nb {
        let col = w.jac_w.col_as_slice_mut(j);
        for (i, x) in col.iter_mut().enumerate() {
            let rot = *x;
            *x = rot + am[i] * w.rate[2][j] + an2[i] * w.rate[1][j];
        }
    }
    // the slider's J_T coefficient of ω_C through η̇: A m σ_2ᵀ + A n_2 σ_1ᵀ, σ_i = (n̄_i·ū'')/(|ū'| den) t
    let sigma = |n: &Vector3<f64>| t_full * (n.dot(&u2) / (len * den));
    let (sig1, sig2) = (sigma(&n1), sigma(&n2));
    let slider_w = |wv: &Vector3<f64>| sig2 * wv.dot(&am) + sig1 * wv.dot(&an2);
    // translation rows
    for (i, ni) in [c[1], c[2]].iter().enumerate() {
        let arm = ni.cross(&d);
        for j in 0..nb {
            let (jc, jw) = (w.jac_c.col_as_slice(j), w.jac_w.col_as_slice(j));
            let mut v = 0.0;
            for k in 0..3 {
                v += -ni[k] * jc[k] + arm[k] * jw[k];
            }
            w.rows.col_as_slice_mut(j)[i] = v;
        }
        w.slider[i] = (ni + slider_w(&arm), Vector3::zeros());
    }
    if guide.rotations {
        for i in 0..3 {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            let (bj, bk) = (b.column(j).into_owned(), b.column(k).into_owned());
            let r = 0.5 * (bj.cross(&c[k]) - bk.cross(&c[j]));
            for jj in 0..nb {
                let jw = w.jac_w.col_as_slice(jj);
                let mut v = 0.0;
                for kk in 0..3 {
                    v -= r[kk] * jw[kk];
                }
                w.rows.col_as_slice_mut(jj)[2 + i] = v;
            }
            w.slider[2 + i] = (-slider_w(&r), r);
        }
    }
}

/// The body columns of `η̇` (`rate[0]`) and of `n̄_i·τ̇` (`rate[i]`), module documentation.
#[allow(clippy::too_many_arguments)]
fn rate_rows(
    contour: &FfrCurveContour,
    s: &dyn NeutralContourSource,
    w: &mut GuideWork,
    u1: &Vector3<f64>,
    u2: &Vector3<f64>,
    db: &Vector3<f64>,
    t_full: &Vector3<f64>,
    n1: &Vector3<f64>,
    n2: &Vector3<f64>,
    den: f64,
) {
    let nb = w.jac_c.ncols();
    let len = u1.norm();
    // η̇ = [-tᵀ J_C - (d̄ × ū')ᵀ J_π̄ (rotation) + Φ'_kᵀ d̄ J_q (fields)] u / den (+ the
    // slider's tᵀ v_c / den)
    for j in 0..nb {
        let jc = w.jac_c.col_as_slice(j);
        let mut v = 0.0;
        for k in 0..3 {
            v -= t_full[k] * jc[k];
        }
        w.rate[0][j] = v;
    }
    s.add_rotation_row(&db.cross(u1), -1.0, &mut w.rate[0]);
    w.rate[1].fill(0.0);
    w.rate[2].fill(0.0);
    // every field's slope Φ_k' from one basis evaluation (that of `J_C` at the same `eta`)
    let rate = &mut w.rate;
    let nan = [Vector3::repeat(f64::NAN)];
    let slopes = match contour.mode_slopes(&mut w.state, w.eta) {
        Ok(slopes) => slopes,
        Err(_) => &nan[..],
    };
    let slope = |k: usize| slopes.get(k).unwrap_or(&nan[0]);
    s.add_field_row(&|k| slope(k).dot(db), &mut rate[0]);
    s.add_field_row(&|k| n1.dot(slope(k)) / len, &mut rate[1]);
    s.add_field_row(&|k| n2.dot(slope(k)) / len, &mut rate[2]);
    let (c1, c2) = (n1.dot(u2) / len, n2.dot(u2) / len);
    for j in 0..nb {
        w.rate[0][j] /= den;
        w.rate[1][j] += c1 * w.rate[0][j];
        w.rate[2][j] += c2 * w.rate[0][j];
    }
}

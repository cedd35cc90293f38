//! Knot vectors and B-spline basis functions (seed 000 (3.11)-(3.14); NURBS Book A2.1, A2.2 and
//! the derivative formula (2.7) that A2.3 also implements).

use crate::error::NurbsError;
use crate::MAX_DERIVATIVE;

/// A validated knot vector of one parametric direction, with its degree and control point count.
///
/// Open (clamped or not) vectors have the parameter domain `[U_p, U_n]` (`n` = number of control
/// points); parameters outside are clamped to it. Periodic vectors (closed contours) repeat their
/// spacing with the period `T = U_n - U_p`, and parameters are wrapped into `[U_p, U_p + T)`.
#[derive(Debug, Clone, PartialEq)]
pub struct KnotVector {
    degree: usize,
    n_ctrl: usize,
    knots: Vec<f64>,
    periodic: bool,
}

/// Scratch of the basis function recursions (NURBS Book A2.2, (2.7)), sized for one degree.
#[derive(Debug, Clone)]
pub struct BasisScratch {
    degree: usize,
    left: Vec<f64>,
    right: Vec<f64>,
    /// `ndu[q * (p + 1) + j] = N_{span-q+j,q}(u)`: the nonzero functions of every degree `q <= p`.
    ndu: Vec<f64>,
    /// `N'_{span-q+j,q}` of degree `q = p - 1` (for the second derivatives).
    d1_lower: Vec<f64>,
    /// `ders[k * (p + 1) + j]`: k-th derivative of `N_{span-p+j,p}`.
    ders: Vec<f64>,
}

impl BasisScratch {
    /// Scratch for basis functions of degree `degree` (allocates once).
    pub fn new(degree: usize) -> Self {
        let p1 = degree + 1;
        Self {
            degree,
            left: vec![0.0; p1],
            right: vec![0.0; p1],
            ndu: vec![0.0; p1 * p1],
            d1_lower: vec![0.0; p1],
            ders: vec![0.0; (MAX_DERIVATIVE + 1) * p1],
        }
    }

    /// The degree the scratch was made for.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The `k`-th derivative of the `j`-th nonzero basis function `N_{span-p+j,p}` of the last
    /// evaluation (`k <= 2`, `j <= p`).
    #[inline]
    pub fn der(&self, k: usize, j: usize) -> f64 {
        self.ders[k * (self.degree + 1) + j]
    }
}

impl KnotVector {
    /// Validates an open knot vector for `n_ctrl` control points of degree `degree`:
    /// finite, non-decreasing, `n_ctrl + degree + 1` knots, `n_ctrl >= degree + 1`, interior
    /// multiplicity at most `degree`, end multiplicity at most `degree + 1`, nonempty domain.
    pub fn new(degree: usize, knots: Vec<f64>, n_ctrl: usize) -> Result<Self, NurbsError> {
        validate_knots(degree, &knots, n_ctrl)?;
        Ok(Self {
            degree,
            n_ctrl,
            knots,
            periodic: false,
        })
    }

    /// Validates a periodic knot vector: as [`KnotVector::new`], and the `k = n_ctrl - degree`
    /// spans repeat, `U_{i+k} - U_i = T` for every `i` (relative tolerance 1e-10). The control
    /// points of such a direction must be wrapped (`P_{k+j} = P_j`, `j < degree`).
    pub fn periodic(degree: usize, knots: Vec<f64>, n_ctrl: usize) -> Result<Self, NurbsError> {
        validate_knots(degree, &knots, n_ctrl)?;
        let k = n_ctrl - degree;
        let period = knots[n_ctrl] - knots[degree];
        for i in 0..knots.len() - k {
            if ((knots[i + k] - knots[i]) - period).abs() > 1e-10 * period {
                return Err(NurbsError::NotPeriodic {
                    reason: "knot spacing",
                    index: i,
                });
            }
        }
        Ok(Self {
            degree,
            n_ctrl,
            knots,
            periodic: true,
        })
    }

    /// Degree `p`.
    pub fn degree(&self) -> usize {
        self.degree
    }
    /// Number of control points (periodic: including the `p` wrapped ones).
    pub fn n_ctrl(&self) -> usize {
        self.n_ctrl
    }
    /// The knots.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }
    /// Whether the direction is periodic (closed contour).
    pub fn is_periodic(&self) -> bool {
        self.periodic
    }
    /// Parameter domain `[U_p, U_n]`.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.n_ctrl])
    }

    /// Maps a parameter into the domain: clamped (open) or wrapped by the period (periodic).
    #[inline]
    pub fn map_parameter(&self, u: f64) -> f64 {
        let (lo, hi) = self.domain();
        if self.periodic {
            let w = lo + (u - lo).rem_euclid(hi - lo);
            // rem_euclid may round up to the period itself
            if w >= hi {
                lo
            } else {
                w
            }
        } else {
            u.clamp(lo, hi)
        }
    }

    /// Knot span index `s` with `U_s <= u < U_{s+1}` (NURBS Book A2.1); `u` must be in the
    /// domain; at the domain end the last nonempty span. With `left`, the span with
    /// `U_s < u <= U_{s+1}` instead (one-sided limits from the left at a knot).
    pub fn find_span(&self, u: f64, left: bool) -> usize {
        let (p, n, k) = (self.degree, self.n_ctrl, &self.knots);
        if u >= k[n] || (left && u > k[n - 1]) {
            let mut s = n - 1;
            while s > p && k[s] >= k[n] {
                s -= 1;
            }
            return s;
        }
        if u <= k[p] {
            let mut s = p;
            while s + 1 < n && k[s + 1] <= k[p] {
                s += 1;
            }
            return s;
        }
        let (mut low, mut high) = (p, n);
        let mut mid = (low + high) / 2;
        loop {
            let inside = if left {
                k[mid] < u && u <= k[mid + 1]
            } else {
                k[mid] <= u && u < k[mid + 1]
            };
            if inside || high - low <= 1 {
                return mid;
            }
            if (left && u <= k[mid]) || (!left && u < k[mid]) {
                high = mid;
            } else {
                low = mid;
            }
            mid = (low + high) / 2;
        }
    }

    /// Nonzero basis functions and their derivatives up to order `nd <= 2` at `u` (mapped into
    /// the domain), written to `scratch`; returns the span `s`, so `scratch.der(k, j)` is the
    /// `k`-th derivative of `N_{s-p+j,p}(u)`. Recursion (3.11)-(3.13) as in NURBS Book A2.2,
    /// derivatives by (2.7) from the functions of degree `p - 1` and `p - 2` (the result of A2.3).
    pub fn basis_derivatives(&self, u: f64, nd: usize, left: bool, s: &mut BasisScratch) -> usize {
        debug_assert_eq!(s.degree, self.degree);
        let mut u = self.map_parameter(u);
        if left && self.periodic && u == self.domain().0 {
            // one-sided limit from the left at the seam: the end of the previous period
            u = self.domain().1;
        }
        let span = self.find_span(u, left);
        fill_ndu(&self.knots, self.degree, span, u, s);
        fill_derivatives(&self.knots, self.degree, span, nd.min(MAX_DERIVATIVE), s);
        span
    }
}

/// Validation of a knot vector (shared by open and periodic).
fn validate_knots(degree: usize, knots: &[f64], n_ctrl: usize) -> Result<(), NurbsError> {
    if degree == 0 {
        return Err(NurbsError::ZeroDegree { degree });
    }
    if n_ctrl < degree + 1 {
        return Err(NurbsError::TooFewPoints {
            got: n_ctrl,
            needed: degree + 1,
            degree,
        });
    }
    let expected = n_ctrl + degree + 1;
    if knots.len() != expected {
        return Err(NurbsError::KnotCountMismatch {
            got: knots.len(),
            expected,
            n_ctrl,
            degree,
        });
    }
    for (index, &value) in knots.iter().enumerate() {
        if !value.is_finite() {
            return Err(NurbsError::NonFiniteKnot { index, value });
        }
        if index > 0 && knots[index - 1] > value {
            let prev = knots[index - 1];
            return Err(NurbsError::KnotsNotNondecreasing {
                index,
                prev,
                next: value,
            });
        }
    }
    let (lo, hi) = (knots[degree], knots[n_ctrl]);
    if lo >= hi {
        return Err(NurbsError::EmptyDomain { lo, hi });
    }
    let mut i = 0;
    while i < knots.len() {
        let mut j = i;
        while j + 1 < knots.len() && knots[j + 1] == knots[i] {
            j += 1;
        }
        let multiplicity = j - i + 1;
        let interior = knots[i] > lo && knots[i] < hi;
        let allowed = if interior { degree } else { degree + 1 };
        if multiplicity > allowed {
            return Err(NurbsError::KnotMultiplicity {
                value: knots[i],
                multiplicity,
                allowed,
                degree,
            });
        }
        i = j + 1;
    }
    Ok(())
}

/// Nonzero basis functions of all degrees `q = 0..p` at `u` in span `span` (recursion
/// (3.11)-(3.13) in the triangular form of NURBS Book A2.2), row `q` of `s.ndu`.
fn fill_ndu(knots: &[f64], p: usize, span: usize, u: f64, s: &mut BasisScratch) {
    let p1 = p + 1;
    s.ndu[0] = 1.0;
    for j in 1..=p {
        s.left[j] = u - knots[span + 1 - j];
        s.right[j] = knots[span + j] - u;
        let (prev, cur) = s.ndu.split_at_mut(j * p1);
        let prev = &prev[(j - 1) * p1..(j - 1) * p1 + j];
        let mut saved = 0.0;
        for r in 0..j {
            let temp = prev[r] / (s.right[r + 1] + s.left[j - r]);
            cur[r] = saved + s.right[r + 1] * temp;
            saved = s.left[j - r] * temp;
        }
        cur[j] = saved;
    }
}

/// Derivatives of degree `q` basis functions from the functions (or derivatives) `lower` of
/// degree `q - 1` (NURBS Book (2.7)): with `c_j = q lower_j / (U_{span+j+1} - U_{span-q+1+j})`,
/// `N^(k)_{span-q+j,q} = c_{j-1} - c_j` (`c_{-1} = c_q = 0`). Writes `q + 1` values to `out`.
fn derivative_from_lower(knots: &[f64], q: usize, span: usize, lower: &[f64], out: &mut [f64]) {
    let mut prev = 0.0;
    for j in 0..q {
        let c = q as f64 * lower[j] / (knots[span + j + 1] - knots[span + 1 + j - q]);
        out[j] = prev - c;
        prev = c;
    }
    out[q] = prev;
}

/// First and second derivatives of the degree `p` functions (zero above the degree).
fn fill_derivatives(knots: &[f64], p: usize, span: usize, nd: usize, s: &mut BasisScratch) {
    let p1 = p + 1;
    s.ders[..p1].copy_from_slice(&s.ndu[p * p1..p * p1 + p1]);
    s.ders[p1..].iter_mut().for_each(|d| *d = 0.0);
    if nd >= 1 {
        let (lower, ders) = (
            &s.ndu[(p - 1) * p1..(p - 1) * p1 + p],
            &mut s.ders[p1..2 * p1],
        );
        derivative_from_lower(knots, p, span, lower, ders);
    }
    if nd >= 2 && p >= 2 {
        let lower = &s.ndu[(p - 2) * p1..(p - 2) * p1 + p - 1];
        derivative_from_lower(knots, p - 1, span, lower, &mut s.d1_lower[..p]);
        derivative_from_lower(
            knots,
            p,
            span,
            &s.d1_lower[..p],
            &mut s.ders[2 * p1..3 * p1],
        );
    }
}

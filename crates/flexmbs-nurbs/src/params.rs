//! Interpolation parameters and knot vectors: chord-length and centripetal parameters
//! (seed 000 (3.19)-(3.21); NURBS Book (9.4)-(9.6)), knot averaging (9.8) and periodic knots.

use crate::error::NurbsError;
use nalgebra::Vector3;

/// How interpolation parameters follow from the point distances (seed 000 (3.19)-(3.21)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ParamMethod {
    /// `u_i - u_{i-1} ~ |Q_i - Q_{i-1}|` (chord length, (3.19)-(3.21)).
    #[default]
    ChordLength,
    /// `u_i - u_{i-1} ~ |Q_i - Q_{i-1}|^(1/2)` (centripetal, NURBS Book (9.6)).
    Centripetal,
}

impl ParamMethod {
    fn distance(self, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
        let d = (a - b).norm();
        match self {
            ParamMethod::ChordLength => d,
            ParamMethod::Centripetal => d.sqrt(),
        }
    }
}

/// Parameters of `k` points: open `u_0 = 0 < ... < u_{k-1} = 1` ((3.19)-(3.21)); closed, the
/// total includes the closing chord `Q_{k-1} -> Q_0` and the parameters lie in `[0, 1)` (the seam
/// `u = 1` is `Q_0` again). Coincident consecutive points are an error.
pub fn curve_parameters(
    points: &[Vector3<f64>],
    method: ParamMethod,
    closed: bool,
) -> Result<Vec<f64>, NurbsError> {
    let k = points.len();
    if k < 2 {
        return Err(NurbsError::TooFewPoints {
            got: k,
            needed: 2,
            degree: 1,
        });
    }
    for (i, p) in points.iter().enumerate() {
        if !p.iter().all(|x| x.is_finite()) {
            return Err(NurbsError::NonFiniteValue {
                what: "point",
                index: i,
            });
        }
    }
    let segments = if closed { k } else { k - 1 };
    let mut u = vec![0.0; k];
    let mut total = 0.0;
    for i in 0..segments {
        let next = (i + 1) % k;
        let d = method.distance(&points[i], &points[next]);
        if d <= 0.0 {
            return Err(NurbsError::CoincidentPoints { index: i, next });
        }
        total += d;
        if next != 0 {
            u[next] = total;
        }
    }
    for v in u.iter_mut() {
        *v /= total;
    }
    if !closed {
        u[k - 1] = 1.0;
    }
    Ok(u)
}

/// Parameters of a grid `Q_ij` (row-major `i * n_xi + j`): the parameters of every line along a
/// direction, averaged over the lines (NURBS Book (9.24)-(9.25)). Returns `(eta, xi)`.
pub fn surface_parameters(
    grid: &[Vector3<f64>],
    n_eta: usize,
    n_xi: usize,
    method: ParamMethod,
    closed: [bool; 2],
) -> Result<(Vec<f64>, Vec<f64>), NurbsError> {
    if grid.len() != n_eta * n_xi {
        return Err(NurbsError::SizeMismatch {
            what: "grid points",
            expected: n_eta * n_xi,
            got: grid.len(),
        });
    }
    let mut eta = vec![0.0; n_eta];
    let mut line = Vec::with_capacity(n_eta.max(n_xi));
    for j in 0..n_xi {
        line.clear();
        line.extend((0..n_eta).map(|i| grid[i * n_xi + j]));
        for (e, u) in eta
            .iter_mut()
            .zip(curve_parameters(&line, method, closed[0])?)
        {
            *e += u / n_xi as f64;
        }
    }
    let mut xi = vec![0.0; n_xi];
    for i in 0..n_eta {
        let row = &grid[i * n_xi..(i + 1) * n_xi];
        for (x, u) in xi.iter_mut().zip(curve_parameters(row, method, closed[1])?) {
            *x += u / n_eta as f64;
        }
    }
    Ok((eta, xi))
}

/// Open knot vector by averaging (NURBS Book (9.8)): `p + 1` knots `u_0` and `u_{k-1}` at the
/// ends, interior knots `u_{j+p} = (1/p) sum_{i=j}^{j+p-1} u_i`, `j = 1..k-p-1`.
pub fn averaged_knots(params: &[f64], degree: usize) -> Vec<f64> {
    let k = params.len();
    let mut knots = vec![params[0]; k + degree + 1];
    for j in 1..k - degree {
        knots[j + degree] = params[j..j + degree].iter().sum::<f64>() / degree as f64;
    }
    for v in knots.iter_mut().skip(k) {
        *v = params[k - 1];
    }
    knots
}

/// Periodic knot vector for `k` parameters of period 1 in `[0, 1)`: inner knots `t_i` at the
/// parameters (odd degree) or at the midpoints between them (even degree), extended periodically
/// by `p` knots on each side (`U_{p+i} = t_i`, `t_{i+k} = t_i + 1`); `k + 2p + 1` knots, control
/// points `P_0 .. P_{k+p-1}` with `P_{k+j} = P_j`.
pub fn periodic_knots(params: &[f64], degree: usize) -> Vec<f64> {
    let k = params.len() as isize;
    let p = degree as isize;
    let at = |i: isize| -> f64 {
        let (q, r) = (i.div_euclid(k), i.rem_euclid(k));
        params[r as usize] + q as f64
    };
    (-p..=k + p)
        .map(|i| {
            if degree % 2 == 1 {
                at(i)
            } else {
                0.5 * (at(i) + at(i + 1))
            }
        })
        .collect()
}

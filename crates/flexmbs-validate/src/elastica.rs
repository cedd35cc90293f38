//! The cantilever elastica under a tip force that stays vertical: the reference of
//! `cantilever_static`, independent of the superelement code.
//!
//! Inextensible (Bisshopp & Drucker 1945): with `α = P L²/EI` the modulus `k` solves
//! `√α = K(k) − F(φ₁, k)`, `sin φ₁ = 1/(k√2)`; the tip deflection is
//! `v/L = 1 − 2 (E(k) − E(φ₁, k))/√α` and the tip abscissa `x_L/L = √(2 (2k² − 1)/α)`
//! (elliptic integrals by Carlson's symmetric forms `R_F`, `R_D`). Checked against, and extended
//! to the extensible beam by, a shooting solution of `θ'' = −(P/EI)(1 + ε) cos θ`.

/// Carlson's `R_F(x, y, z)` by duplication (error 4^-40 of the spread).
fn carlson_rf(mut x: f64, mut y: f64, mut z: f64) -> f64 {
    for _ in 0..40 {
        let l = (x * y).sqrt() + (y * z).sqrt() + (z * x).sqrt();
        x = 0.25 * (x + l);
        y = 0.25 * (y + l);
        z = 0.25 * (z + l);
    }
    1.0 / ((x + y + z) / 3.0).sqrt()
}

/// Carlson's `R_D(x, y, z)` by duplication.
fn carlson_rd(mut x: f64, mut y: f64, mut z: f64) -> f64 {
    let (mut sum, mut fac) = (0.0, 1.0);
    for _ in 0..40 {
        let l = (x * y).sqrt() + (y * z).sqrt() + (z * x).sqrt();
        sum += fac / (z.sqrt() * (z + l));
        fac *= 0.25;
        x = 0.25 * (x + l);
        y = 0.25 * (y + l);
        z = 0.25 * (z + l);
    }
    let mu = (x + y + 3.0 * z) / 5.0;
    3.0 * sum + fac * mu.powf(-1.5)
}

/// Incomplete elliptic integrals of the first and second kind `F(φ, k)`, `E(φ, k)`.
pub fn elliptic_f_e(phi: f64, k: f64) -> (f64, f64) {
    let (s, c) = phi.sin_cos();
    let y = 1.0 - k * k * s * s;
    let rf = carlson_rf(c * c, y, 1.0);
    (
        s * rf,
        s * rf - k * k * s.powi(3) / 3.0 * carlson_rd(c * c, y, 1.0),
    )
}

/// Tip `(u, v)` of the inextensible elastica of length `l`, bending stiffness `ei`, tip force
/// `p`: horizontal shortening and deflection along the force.
pub fn elastica_elliptic(p: f64, l: f64, ei: f64) -> (f64, f64) {
    let alpha = p * l * l / ei;
    let sa = alpha.sqrt();
    let f = |k: f64| {
        let phi1 = (1.0 / (k * 2f64.sqrt())).min(1.0).asin();
        let (kk, ek) = elliptic_f_e(std::f64::consts::FRAC_PI_2, k);
        let (f1, e1) = elliptic_f_e(phi1, k);
        (kk - f1 - sa, ek - e1)
    };
    let (mut lo, mut hi) = (1.0 / 2f64.sqrt(), 1.0 - 1e-15);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid).0 < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let k = 0.5 * (lo + hi);
    let v = l * (1.0 - 2.0 * f(k).1 / sa);
    let x = l * (2.0 * (2.0 * k * k - 1.0) / alpha).sqrt();
    (l - x, v)
}

/// Tip `(u, v)` by shooting: `θ'' = −(P/EI)(1 + ε) cos θ`, `θ(0) = 0`, `θ'(L) = 0`,
/// `x' = (1 + ε) cos θ`, `y' = (1 + ε) sin θ`, axial strain `ε = P sin θ / EA` (`ea =
/// f64::INFINITY`: inextensible); RK4 with `steps` steps; bisection on `θ'(0)` after a scan down
/// from `P L / EI` (the first sign change of `θ'(L)` is the equilibrium without inflection).
pub fn elastica_shooting(p: f64, l: f64, ei: f64, ea: f64, steps: usize) -> (f64, f64) {
    let c = p / ei;
    let integrate = |kappa0: f64, steps: usize| {
        let h = l / steps as f64;
        let rhs = |y: [f64; 4]| {
            let stretch = 1.0 + p * y[2].sin() / ea;
            [
                stretch * y[2].cos(),
                stretch * y[2].sin(),
                y[3],
                -c * stretch * y[2].cos(),
            ]
        };
        let mut y = [0.0, 0.0, 0.0, kappa0];
        let add = |a: [f64; 4], b: [f64; 4], s: f64| -> [f64; 4] {
            std::array::from_fn(|i| a[i] + s * b[i])
        };
        for _ in 0..steps {
            let k1 = rhs(y);
            let k2 = rhs(add(y, k1, 0.5 * h));
            let k3 = rhs(add(y, k2, 0.5 * h));
            let k4 = rhs(add(y, k3, h));
            y = std::array::from_fn(|i| {
                y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
            });
        }
        y
    };
    let scan = 400;
    let k_at = |i: usize| c * l * i as f64 / scan as f64;
    let first = (0..scan)
        .rev()
        .find(|&i| integrate(k_at(i), 200)[3] < 0.0)
        .unwrap_or(0);
    let (mut lo, mut hi) = (k_at(first), k_at(first + 1));
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if integrate(mid, steps)[3] < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let y = integrate(0.5 * (lo + hi), steps);
    (l - y[0], y[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elliptic_solution_matches_shooting_and_linear_theory() {
        let ei = 189.07;
        for p in [1.0, 100.0, 1000.0, 10000.0] {
            let (ue, ve) = elastica_elliptic(p, 1.0, ei);
            let (us, vs) = elastica_shooting(p, 1.0, ei, f64::INFINITY, 4000);
            assert!((ue - us).abs() < 1e-8 && (ve - vs).abs() < 1e-8, "{p}");
        }
        let v = elastica_elliptic(1.0, 1.0, ei).1;
        assert!((v - 1.0 / (3.0 * ei)).abs() < 1e-4 * v);
        // complete integrals: K(1/√2) = 1.854074677301372, E(1/√2) = 1.350643881047675
        let (k, e) = elliptic_f_e(std::f64::consts::FRAC_PI_2, 0.5f64.sqrt());
        assert!((k - 1.854074677301372).abs() < 1e-14 && (e - 1.350643881047675).abs() < 1e-14);
    }
}

//! Geometrically nonlinear reference for `slider_crank_3d`, sharing no code with the superelement,
//! the FFR body or the planar corotational reference: a spatial **discrete elastic rod** of point
//! masses (a chain of rigid-length-free segments joined by rotational springs), integrated by
//! velocity Verlet.
//!
//! Model: the rod of length `L` in `n` equal segments of length `l0 = L/n`; node `i` carries its
//! global position `x_i` only (a round rod: the cross-section's orientation enters neither the
//! bending energy nor, at this slenderness, the kinetic energy; torsion is not loaded). Strain
//! energy
//! `E = sum_e ½ (EA/l0) (|e_e| - l0)² + sum_(interior i) (EI/l0) (1 - t_(i-1) . t_i)`
//! with the segment vectors `e_i = x_(i+1) - x_i` and their unit tangents `t_i`:
//! `1 - cos(phi) = ½ phi² + O(phi⁴)` of the turning angle `phi` between neighbouring segments, so
//! the bending term is the Euler-Bernoulli energy `½ EI kappa² l0` with `kappa = phi/l0` (the
//! three-point finite difference of the curvature, second order in `l0`), exact for rigid
//! rotations of any size (large rotations, small strains). The ends carry no moment: the
//! spherical joint at the crank pin and the universal joint at the slider transmit none in
//! bending.
//!
//! Masses `rho A l0` per interior node (half at the ends), the slider's mass on the last node's
//! along-guide coordinate; no rotary inertia of the cross-section (its effect on the first
//! pinned-pinned frequency is `-½ (pi r_g/L)² = -1.2e-4`). The crank pin's motion is prescribed
//! on node 0, the slider guide holds node n on the guide line (only its coordinate along the
//! guide is free). A constant diagonal mass: `M x'' = -grad E` on the free coordinates, velocity
//! Verlet at a fraction of its stability limit `2/omega_max` (power iteration).

use nalgebra::Vector3;
use std::f64::consts::PI;

/// A spatial discrete elastic rod (point masses, axial and rotational springs).
#[derive(Debug, Clone, Copy)]
pub struct DiscreteRod {
    /// Number of segments.
    pub n: usize,
    /// Undeformed length (m).
    pub length: f64,
    /// Axial stiffness EA (N).
    pub ea: f64,
    /// Bending stiffness EI (N m²).
    pub ei: f64,
    /// Mass per length rho A (kg/m).
    pub rho_a: f64,
}

impl DiscreteRod {
    /// The solid round steel rod of the slider-crank (d = 6 mm, E = 200 GPa, rho = 7870 kg/m³,
    /// L = 0.3 m).
    pub fn slider_crank_rod(n: usize) -> Self {
        let (d, e, rho) = (0.006, 200e9, 7870.0);
        let a = PI * d * d / 4.0;
        Self {
            n,
            length: 0.3,
            ea: e * a,
            ei: e * PI * d.powi(4) / 64.0,
            rho_a: rho * a,
        }
    }

    /// Segment length `l0`.
    pub fn segment_length(&self) -> f64 {
        self.length / self.n as f64
    }

    /// Lumped node masses (`n + 1`).
    pub fn node_masses(&self) -> Vec<f64> {
        let m = self.rho_a * self.segment_length();
        (0..=self.n)
            .map(|i| if i == 0 || i == self.n { 0.5 * m } else { m })
            .collect()
    }

    /// Strain energy at node positions `x` (`n + 1`).
    pub fn strain_energy(&self, x: &[Vector3<f64>]) -> f64 {
        let l0 = self.segment_length();
        let (ka, kb) = (self.ea / l0, self.ei / l0);
        let mut e = 0.0;
        for i in 0..self.n {
            let s = (x[i + 1] - x[i]).norm() - l0;
            e += 0.5 * ka * s * s;
        }
        for i in 1..self.n {
            let ta = (x[i] - x[i - 1]).normalize();
            let tb = (x[i + 1] - x[i]).normalize();
            e += kb * (1.0 - ta.dot(&tb));
        }
        e
    }

    /// Gradient of [`Self::strain_energy`] into `f` (the internal forces, `n + 1`); returns the
    /// largest compressive axial force (N, >= 0).
    pub fn internal_forces(&self, x: &[Vector3<f64>], f: &mut [Vector3<f64>]) -> f64 {
        f.iter_mut().for_each(|v| *v = Vector3::zeros());
        let l0 = self.segment_length();
        let (ka, kb) = (self.ea / l0, self.ei / l0);
        let mut compression: f64 = 0.0;
        for i in 0..self.n {
            let e = x[i + 1] - x[i];
            let l = e.norm();
            let axial = ka * (l - l0);
            compression = compression.max(-axial);
            let g = e * (axial / l);
            f[i + 1] += g;
            f[i] -= g;
        }
        for i in 1..self.n {
            let (ea, eb) = (x[i] - x[i - 1], x[i + 1] - x[i]);
            let (la, lb) = (ea.norm(), eb.norm());
            let (ta, tb) = (ea / la, eb / lb);
            let c = ta.dot(&tb);
            // d(-kb ta.tb)/d e_a and / d e_b
            let ga = -(tb - ta * c) * (kb / la);
            let gb = -(ta - tb * c) * (kb / lb);
            f[i - 1] -= ga;
            f[i] += ga - gb;
            f[i + 1] += gb;
        }
        compression
    }

    /// Largest angular frequency of `M^-1 K` at the straight configuration along x with the
    /// coordinates marked `free` (3 per node): power iteration with finite-difference `K v`.
    pub fn highest_frequency(&self, masses: &[f64], free: &[bool]) -> f64 {
        let n = self.n + 1;
        let l0 = self.segment_length();
        let x0: Vec<Vector3<f64>> = (0..n)
            .map(|i| Vector3::new(i as f64 * l0, 0.0, 0.0))
            .collect();
        let mut v: Vec<f64> = (0..3 * n)
            .map(|k| if free[k] { 1.0 + (k % 7) as f64 } else { 0.0 })
            .collect();
        let (mut f0, mut f1) = (vec![Vector3::zeros(); n], vec![Vector3::zeros(); n]);
        self.internal_forces(&x0, &mut f0);
        let mut xp = x0.clone();
        let mut lambda = 0.0;
        for _ in 0..500 {
            let norm = (0..3 * n)
                .map(|k| v[k] * v[k] * masses[k / 3])
                .sum::<f64>()
                .sqrt();
            let eps = 1e-9 * l0 * masses.iter().fold(0.0f64, |a, &m| a.max(m)).sqrt();
            for k in 0..3 * n {
                v[k] /= norm;
                xp[k / 3][k % 3] = x0[k / 3][k % 3] + eps * v[k];
            }
            self.internal_forces(&xp, &mut f1);
            let kv = |k: usize| (f1[k / 3][k % 3] - f0[k / 3][k % 3]) / eps;
            lambda = (0..3 * n).map(|k| v[k] * kv(k)).sum::<f64>();
            for k in 0..3 * n {
                v[k] = if free[k] { kv(k) / masses[k / 3] } else { 0.0 };
            }
        }
        lambda.max(0.0).sqrt()
    }
}

/// The crank of a (spatial or planar) slider-crank: pin `c + r (e1 cos theta + e2 sin theta)`,
/// `theta = Omega t`, the rotation axis `e1 x e2`; the slider on the global x axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crank {
    /// Centre of the crank circle (a point of the rotation axis).
    pub centre: Vector3<f64>,
    /// Direction of the crank at angle 0.
    pub e1: Vector3<f64>,
    /// Direction of the crank at angle 90°.
    pub e2: Vector3<f64>,
    /// Crank length r (m).
    pub radius: f64,
    /// Crank angular velocity Omega (rad/s).
    pub omega: f64,
}

impl Crank {
    /// Pin position and velocity at crank angle `theta`.
    pub fn pin(&self, theta: f64) -> (Vector3<f64>, Vector3<f64>) {
        let (s, c) = theta.sin_cos();
        (
            self.centre + (self.e1 * c + self.e2 * s) * self.radius,
            (self.e2 * c - self.e1 * s) * (self.radius * self.omega),
        )
    }

    /// Slider position on the x axis of the rigid mechanism with a rod of length `l` at crank
    /// angle `theta` (closed form, the slider on the pin's +x side): `x = p_x + sqrt(l² - p_y² -
    /// p_z²)`, and its velocity.
    pub fn rigid_slider(&self, l: f64, theta: f64) -> (f64, f64) {
        let (p, v) = self.pin(theta);
        let root = (l * l - p[1] * p[1] - p[2] * p[2]).sqrt();
        (p[0] + root, v[0] - (p[1] * v[1] + p[2] * v[2]) / root)
    }
}

/// Local y of the rod: the unit normal of the chord `chord` (unit) in the horizontal plane,
/// `normalize(z x chord)` (the rod's universal-joint pin axis at the slider).
pub fn local_y(chord: &Vector3<f64>) -> Vector3<f64> {
    Vector3::z().cross(chord).normalize()
}

/// Result of a reference run.
#[derive(Debug, Clone)]
pub struct RodRun {
    /// Rod midpoint deflection along the rod's local y (m), every sample interval from `t = 0`.
    pub w_y: Vec<f64>,
    /// The same along local z = chord x local y (m).
    pub w_z: Vec<f64>,
    /// Time step (s).
    pub h: f64,
    /// Largest compressive axial force (N).
    pub compression_max: f64,
}

/// Node masses with the slider's on the last node, and the free coordinates (node 0 prescribed,
/// node n on the guide line along x).
fn slider_crank_masses(rod: &DiscreteRod, slider_mass: f64) -> (Vec<f64>, Vec<bool>) {
    let n = rod.n;
    let mut masses = rod.node_masses();
    masses[n] += slider_mass;
    let mut free = vec![true; 3 * (n + 1)];
    free[..3].iter_mut().for_each(|f| *f = false);
    free[3 * n + 1] = false;
    free[3 * n + 2] = false;
    (masses, free)
}

/// The stable step `2 / omega_max` of velocity Verlet on the slider-crank rod.
pub fn critical_step(rod: &DiscreteRod, slider_mass: f64) -> f64 {
    let (masses, free) = slider_crank_masses(rod, slider_mass);
    2.0 / rod.highest_frequency(&masses, &free)
}

/// Simulates the slider-crank with the rod as `rod` (even `n`: the midpoint is a node) and a
/// slider of mass `slider_mass` for `revolutions` crank revolutions from the straight rod with
/// the rigid-mechanism velocities at crank angle 0, `substeps` Verlet steps per sample interval
/// `sample_dt`. Errors on an odd count or a step above 0.9 x the stability limit.
pub fn simulate(
    rod: &DiscreteRod,
    crank: &Crank,
    slider_mass: f64,
    revolutions: f64,
    sample_dt: f64,
    substeps: usize,
) -> Result<RodRun, String> {
    let n = rod.n;
    if !n.is_multiple_of(2) || n == 0 || substeps == 0 {
        return Err(format!(
            "{n} segments, {substeps} substeps: need an even count"
        ));
    }
    let (masses, _) = slider_crank_masses(rod, slider_mass);
    let h = sample_dt / substeps as f64;
    let h_crit = critical_step(rod, slider_mass);
    if h > 0.9 * h_crit {
        return Err(format!(
            "step {h:e} s above 0.9 x the stable step {h_crit:e} s"
        ));
    }
    // straight rod, rigid-mechanism velocities (the spin about the rod axis moves no node)
    let (a0, va) = crank.pin(0.0);
    let (xs, vs) = crank.rigid_slider(rod.length, 0.0);
    let b0 = Vector3::new(xs, 0.0, 0.0);
    let t = (b0 - a0) / rod.length;
    let omega = t.cross(&(Vector3::new(vs, 0.0, 0.0) - va)) / rod.length;
    let l0 = rod.segment_length();
    let mut x: Vec<Vector3<f64>> = (0..=n).map(|i| a0 + t * (i as f64 * l0)).collect();
    let mut v: Vec<Vector3<f64>> = (0..=n)
        .map(|i| va + omega.cross(&(t * (i as f64 * l0))))
        .collect();
    let mut f = vec![Vector3::zeros(); n + 1];
    let mut compression = rod.internal_forces(&x, &mut f);
    let accel = |f: &[Vector3<f64>], a: &mut [Vector3<f64>]| {
        for i in 1..=n {
            a[i] = -f[i] / masses[i];
        }
        a[n][1] = 0.0;
        a[n][2] = 0.0;
    };
    let mut a = vec![Vector3::zeros(); n + 1];
    accel(&f, &mut a);
    let steps = (revolutions * 2.0 * PI / crank.omega / h).round() as usize;
    let mid = n / 2;
    let (mut w_y, mut w_z) = (Vec::new(), Vec::new());
    let mut sample = |x: &[Vector3<f64>]| {
        let chord = (x[n] - x[0]).normalize();
        let y = local_y(&chord);
        let d = x[mid] - x[0];
        w_y.push(d.dot(&y));
        w_z.push(d.dot(&chord.cross(&y)));
    };
    sample(&x);
    for step in 1..=steps {
        for i in 1..=n {
            v[i] += a[i] * (0.5 * h);
            x[i] += v[i] * h;
        }
        let (p, vp) = crank.pin(crank.omega * step as f64 * h);
        x[0] = p;
        v[0] = vp;
        compression = compression.max(rod.internal_forces(&x, &mut f));
        accel(&f, &mut a);
        for i in 1..=n {
            v[i] += a[i] * (0.5 * h);
        }
        if step % substeps == 0 {
            sample(&x);
        }
    }
    Ok(RodRun {
        w_y,
        w_z,
        h,
        compression_max: compression,
    })
}

/// First pinned-pinned bending frequency (rad/s) of the rod from a free vibration started in the
/// analytic mode shape (midpoint velocity amplitude `amplitude` times the analytic frequency),
/// measured from the zero crossings of the midpoint deflection over `periods` periods.
pub fn pinned_pinned_frequency(rod: &DiscreteRod, amplitude: f64, periods: usize) -> f64 {
    let n = rod.n;
    let masses = rod.node_masses();
    let mut free = vec![true; 3 * (n + 1)];
    free[..3].iter_mut().for_each(|f| *f = false);
    free[3 * n + 1] = false;
    free[3 * n + 2] = false;
    let len = rod.length;
    let omega_ref = PI * PI / (len * len) * (rod.ei / rod.rho_a).sqrt();
    let h = 0.5 * 2.0 / rod.highest_frequency(&masses, &free);
    let l0 = rod.segment_length();
    let k = PI / len;
    let mut x: Vec<Vector3<f64>> = (0..=n)
        .map(|i| Vector3::new(i as f64 * l0, 0.0, 0.0))
        .collect();
    let mut v: Vec<Vector3<f64>> = (0..=n)
        .map(|i| Vector3::new(0.0, 0.0, amplitude * omega_ref * (k * i as f64 * l0).sin()))
        .collect();
    let mut f = vec![Vector3::zeros(); n + 1];
    rod.internal_forces(&x, &mut f);
    let steps = (periods as f64 * 2.0 * PI / omega_ref / h).ceil() as usize;
    let mut crossings: Vec<f64> = Vec::new();
    let mut prev = 0.0;
    for step in 1..=steps {
        for i in 1..=n {
            let mut a = -f[i] / masses[i];
            if i == n {
                a[1] = 0.0;
                a[2] = 0.0;
            }
            v[i] += a * (0.5 * h);
            x[i] += v[i] * h;
        }
        rod.internal_forces(&x, &mut f);
        for i in 1..=n {
            let mut a = -f[i] / masses[i];
            if i == n {
                a[1] = 0.0;
                a[2] = 0.0;
            }
            v[i] += a * (0.5 * h);
        }
        let w = x[n / 2][2];
        let t = step as f64 * h;
        if step > 1 && (prev > 0.0 && w <= 0.0 || prev < 0.0 && w >= 0.0) {
            crossings.push(t - h + h * prev / (prev - w));
        }
        prev = w;
    }
    match (crossings.first(), crossings.last()) {
        (Some(a), Some(b)) if crossings.len() > 1 => PI * (crossings.len() - 1) as f64 / (b - a),
        _ => f64::NAN,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bent_state(rod: &DiscreteRod) -> Vec<Vector3<f64>> {
        (0..=rod.n)
            .map(|i| {
                let s = i as f64;
                Vector3::new(
                    0.07 * s + 1e-4 * s * s,
                    0.04 * s + 2e-3 * (1.3 * s).sin(),
                    0.03 * (0.5 * s).cos(),
                )
            })
            .collect()
    }

    /// The internal force is the gradient of the strain energy: central differences at a bent,
    /// stretched spatial state agree to 1e-6 relative.
    #[test]
    fn internal_force_is_the_energy_gradient() {
        let rod = DiscreteRod::slider_crank_rod(5);
        let x = bent_state(&rod);
        let mut f = vec![Vector3::zeros(); rod.n + 1];
        rod.internal_forces(&x, &mut f);
        let scale = f.iter().fold(0.0f64, |a, v| a.max(v.amax()));
        for i in 0..=rod.n {
            for d in 0..3 {
                let e = 1e-8;
                let (mut xp, mut xm) = (x.clone(), x.clone());
                xp[i][d] += e;
                xm[i][d] -= e;
                let fd = (rod.strain_energy(&xp) - rod.strain_energy(&xm)) / (2.0 * e);
                assert!(
                    (fd - f[i][d]).abs() < 1e-6 * scale,
                    "node {i}, dir {d}: {fd} vs {}",
                    f[i][d]
                );
            }
        }
    }

    /// A rigid rotation of the straight rod is stress-free (objectivity).
    #[test]
    fn rigid_rotation_is_stress_free() {
        let rod = DiscreteRod::slider_crank_rod(6);
        let t = Vector3::new(0.3, -0.8, 0.52).normalize();
        let x: Vec<_> = (0..=rod.n)
            .map(|i| Vector3::new(0.1, 0.2, -0.3) + t * (i as f64 * rod.segment_length()))
            .collect();
        let mut f = vec![Vector3::zeros(); rod.n + 1];
        rod.internal_forces(&x, &mut f);
        assert!(f.iter().all(|v| v.amax() < 1e-6), "{f:?}");
    }

    /// First pinned-pinned bending frequency vs Euler-Bernoulli `pi² sqrt(EI/(rho A L⁴))` (no
    /// rotary inertia in either): the error is the three-point curvature's
    /// `(sin(k l0/2)/(k l0/2))² - 1 = -(pi/n)²/12 + O(n⁻⁴)` (`k = pi/L`; -3.2e-3 at 16 segments,
    /// -8.0e-4 at 32), checked to 1e-4 absolute: second order, converging to the beam.
    #[test]
    fn pinned_pinned_frequency_converges_to_euler_bernoulli() {
        let b = DiscreteRod::slider_crank_rod(2);
        let exact = PI * PI / (b.length * b.length) * (b.ei / b.rho_a).sqrt();
        for n in [16usize, 32] {
            let err =
                pinned_pinned_frequency(&DiscreteRod::slider_crank_rod(n), 1e-6, 4) / exact - 1.0;
            let half = PI / n as f64 / 2.0;
            let discrete = (half.sin() / half).powi(2) - 1.0;
            eprintln!("n = {n}: error {err:e}, discrete theory {discrete:e}");
            assert!(
                (err - discrete).abs() < 1e-4,
                "n = {n}: {err:e} vs {discrete:e}"
            );
        }
    }

    /// The closed-form slider position satisfies the rod length, and its velocity is its time
    /// derivative (central difference).
    #[test]
    fn rigid_slider_closed_form() {
        let crank = Crank {
            centre: Vector3::new(0.0, 0.1, 0.0),
            e1: Vector3::z(),
            e2: -Vector3::y(),
            radius: 0.15,
            omega: 150.0,
        };
        for k in 0..12 {
            let th = 0.5 * k as f64;
            let (x, v) = crank.rigid_slider(0.3, th);
            let (p, _) = crank.pin(th);
            assert!(((Vector3::new(x, 0.0, 0.0) - p).norm() - 0.3).abs() < 1e-15);
            let dt = 1e-7;
            let fd = (crank.rigid_slider(0.3, th + 150.0 * dt).0
                - crank.rigid_slider(0.3, th - 150.0 * dt).0)
                / (2.0 * dt);
            assert!((fd - v).abs() < 1e-6 * v.abs().max(1.0), "{fd} vs {v}");
        }
    }
}

//! Reuse of the `q_f`-dependent moments between evaluations at the same deformation.
//!
//! [`FfrBody::update`] costs O(9 n_f^2), almost all of it in the deformed moments `P_kl`, `S_t`,
//! `Ī_θθ`, `Ī_θf` (2.55)-(2.68), which depend on `q_f` only. One Newton iteration evaluates the
//! body several times at the same `q` (frames, mass matrix, forces, tangent), the mass matrix
//! even with `u = 0`; [`FfrBody::update_cached`] recomputes the moments only when `q_f` changed
//! (bitwise comparison), so its results are bitwise identical to [`FfrBody::update`].

use super::{FfrBody, FfrError, FfrScratch};
use crate::rotation::RotationError;
use nalgebra::{Vector3, Vector4};

/// The `q_f` for which the moments in an [`FfrScratch`] were computed, and the rotation
/// coordinates and velocities of its rotation state (`A`, `H`, `omega_bar`, `H_dot w`, `q_f_dot`).
#[derive(Debug, Clone)]
pub struct MomentCache {
    qf: Vec<f64>,
    valid: bool,
    /// Rotation coordinates (bits) of `A`, `H` in the scratch; valid with `valid`.
    rot: [u64; 4],
    /// Velocities (bits) of `omega_bar`, `H_dot w`, `q_f_dot` in the scratch.
    u: Vec<u64>,
}

impl MomentCache {
    /// An empty cache for a body with `nf` modes.
    pub fn new(nf: usize) -> Self {
        Self {
            qf: vec![f64::NAN; nf],
            valid: false,
            rot: [u64::MAX; 4],
            u: vec![u64::MAX; 6 + nf],
        }
    }

    /// Forgets the cached deformation (the next update recomputes the moments).
    pub fn invalidate(&mut self) {
        self.qf.fill(f64::NAN);
        self.rot = [u64::MAX; 4];
        self.u.fill(u64::MAX);
        self.valid = false;
    }
}

impl FfrBody {
    /// [`Self::update`], skipping the `q_f`-dependent moments when `q_f` equals the one cached in
    /// `cache` (and `s` was last updated through this cache). O(n_f) on a hit.
    pub fn update_cached(
        &self,
        q: &[f64],
        u: &[f64],
        s: &mut FfrScratch,
        cache: &mut MomentCache,
    ) -> Result<(), FfrError> {
        self.update_cached_parts(q, u, true, s, cache)
    }

    /// [`Self::update_cached`] that also skips the rotation state when the rotation coordinates
    /// (and, with `velocity`, all of `u`) equal the cached ones bitwise. With `velocity = false`
    /// only the `q`-dependent quantities (`A`, `H`, moments) are guaranteed current (enough for
    /// the mass matrix and the gravity potential); `u` is then used only if the moments must be
    /// recomputed, and the velocity-dependent quantities stay those of the cached `u`.
    pub fn update_cached_parts(
        &self,
        q: &[f64],
        u: &[f64],
        velocity: bool,
        s: &mut FfrScratch,
        cache: &mut MomentCache,
    ) -> Result<(), FfrError> {
        let nf = self.nf();
        let nr = self.rotation.num_coordinates();
        let hit = cache.valid
            && q.len() == self.nq()
            && u.len() == self.nu()
            && s.qf.len() == nf
            && cache.qf.len() == nf
            && cache.u.len() == u.len()
            && cache.qf.as_slice() == &q[3 + nr..];
        if !hit {
            cache.invalidate();
            self.update(q, u, s)?;
            if cache.qf.len() == nf && cache.u.len() == u.len() {
                cache.qf.copy_from_slice(&q[3 + nr..]);
                store_bits(&q[3..3 + nr], &mut cache.rot[..nr]);
                store_bits(u, &mut cache.u);
                cache.valid = true;
            }
            return Ok(());
        }
        let rot_hit = same_bits(&q[3..3 + nr], &cache.rot[..nr]);
        if rot_hit && (!velocity || same_bits(u, &cache.u)) {
            return Ok(());
        }
        if self.rotation == super::RotationParam::Quaternion {
            let norm = Vector4::new(q[3], q[4], q[5], q[6]).norm();
            if !(norm.is_finite() && norm > 1e-12) {
                return Err(RotationError::DegenerateQuaternion { norm }.into());
            }
        }
        // the velocity state to (re)build: the new `u`, or the cached one (q-only request)
        let w = if velocity {
            Vector3::new(u[3], u[4], u[5])
        } else {
            Vector3::from_fn(|i, _| f64::from_bits(cache.u[3 + i]))
        };
        // on error the scratch is partly overwritten: forget the keys first
        cache.valid = false;
        self.set_rotation_state(&q[3..3 + nr], &w, s)?;
        store_bits(&q[3..3 + nr], &mut cache.rot[..nr]);
        if velocity {
            s.qfd.copy_from_slice(&u[6..]);
            store_bits(u, &mut cache.u);
        }
        cache.valid = true;
        Ok(())
    }
}

fn store_bits(x: &[f64], out: &mut [u64]) {
    for (o, v) in out.iter_mut().zip(x) {
        *o = v.to_bits();
    }
}

fn same_bits(x: &[f64], key: &[u64]) -> bool {
    x.len() == key.len() && x.iter().zip(key).all(|(v, k)| v.to_bits() == *k)
}

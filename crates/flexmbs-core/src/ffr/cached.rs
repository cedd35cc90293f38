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

/// The `q_f` for which the moments in an [`FfrScratch`] were computed.
#[derive(Debug, Clone)]
pub struct MomentCache {
    qf: Vec<f64>,
    valid: bool,
}

impl MomentCache {
    /// An empty cache for a body with `nf` modes.
    pub fn new(nf: usize) -> Self {
        Self {
            qf: vec![f64::NAN; nf],
            valid: false,
        }
    }

    /// Forgets the cached deformation (the next update recomputes the moments).
    pub fn invalidate(&mut self) {
        self.qf.fill(f64::NAN);
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
        let nf = self.nf();
        let nr = self.rotation.num_coordinates();
        let hit = cache.valid
            && q.len() == self.nq()
            && u.len() == self.nu()
            && s.qf.len() == nf
            && cache.qf.len() == nf
            && cache.qf.as_slice() == &q[3 + nr..];
        if !hit {
            cache.invalidate();
            self.update(q, u, s)?;
            if cache.qf.len() == nf {
                cache.qf.copy_from_slice(&q[3 + nr..]);
                cache.valid = true;
            }
            return Ok(());
        }
        if self.rotation == super::RotationParam::Quaternion {
            let norm = Vector4::new(q[3], q[4], q[5], q[6]).norm();
            if !(norm.is_finite() && norm > 1e-12) {
                return Err(RotationError::DegenerateQuaternion { norm }.into());
            }
        }
        self.set_rotation_state(&q[3..3 + nr], &Vector3::new(u[3], u[4], u[5]), s)?;
        s.qfd.copy_from_slice(&u[6..]);
        Ok(())
    }
}

//! Conversion of a reduced body to SI units before it enters a model.

use flexmbs_fe::reduction::ReducedBody;
use flexmbs_fe::UnitSystem;

/// Copy of `body` in SI units. With `c = units.mode_to_si()`, `L = length_to_si`,
/// `Ms = mass_to_si`, `Ks = stiffness_to_si`:
/// `u0 *= L`, `m_j *= Ms`, `Φ_t *= c`, `Φ_r *= c / L` (rotations are dimensionless, so
/// `Φ_r q` stays the same rotation for the modal coordinate `q_si = q L / c`),
/// `m_red *= c^2 Ms`, `k_red *= c^2 Ks`: `m_red`, `k_red` stay `Φ^T M Φ`, `Φ^T K Φ` of the
/// converted data, and the modal frequencies are unchanged.
///
/// With `c = 1 / sqrt(Ms)` (`UnitSystem::mode_to_si`) mass-normalised modes stay mass-normalised
/// in SI (`m_red` unchanged) and `k_red` is unchanged too (`Ks / Ms = 1` for SI(mm)).
pub fn reduced_body_to_si(body: &ReducedBody) -> ReducedBody {
    let u = body.units;
    let mut out = body.clone();
    if u == UnitSystem::Si {
        return out;
    }
    let l = u.length_to_si();
    let ms = u.mass_to_si();
    let c = u.mode_to_si();
    out.units = UnitSystem::Si;
    for x in &mut out.nodes {
        for v in x.iter_mut() {
            *v *= l;
        }
    }
    if let Some(m) = &mut out.node_masses {
        for v in m.iter_mut() {
            *v *= ms;
        }
    }
    out.modes_t = faer::Mat::from_fn(body.modes_t.nrows(), body.modes_t.ncols(), |i, j| {
        body.modes_t[(i, j)] * c
    });
    out.modes_r = body
        .modes_r
        .as_ref()
        .map(|r| faer::Mat::from_fn(r.nrows(), r.ncols(), |i, j| r[(i, j)] * c / l));
    let fm = c * c * ms;
    let fk = c * c * u.stiffness_to_si();
    out.m_red = faer::Mat::from_fn(body.m_red.nrows(), body.m_red.ncols(), |i, j| {
        body.m_red[(i, j)] * fm
    });
    out.k_red = faer::Mat::from_fn(body.k_red.nrows(), body.k_red.ncols(), |i, j| {
        body.k_red[(i, j)] * fk
    });
    out
}

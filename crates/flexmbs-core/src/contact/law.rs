//! Contact force laws (seed 000 §3.4): set-valued laws solved on velocity level by proximal
//! points (Moreau time-stepping, [`crate::integrator::MoreauStepper`]) and single-valued
//! (regularized) laws that give forces from the gap and its rate.
//!
//! Set-valued laws in impulse form for one time step, with the relative velocities
//! `gamma = W^T u` at the start (`S`) and end (`E`) of the step and the impulses `Lambda`:
//! - unilateral with Newton impact, `xi_N = gamma_N,E + C_R gamma_N,S`:
//!   `Lambda_N = prox_{R+}(Lambda_N - r xi_N)` (`Lambda_N >= 0`, `xi_N >= 0`,
//!   `Lambda_N xi_N = 0`);
//! - Coulomb friction (planar: one tangent, spatial: two):
//!   `Lambda_T = prox_{C_T}(Lambda_T - r gamma_T,E)` with the disc
//!   `C_T = {|Lambda_T| <= mu Lambda_N}` (stick: `gamma_T,E = 0`, slip: `|Lambda_T| = mu Lambda_N`
//!   opposing `gamma_T,E`).

/// The normal direction's law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NormalLaw {
    /// Set-valued unilateral contact (Signorini) with Newton's impact law: the normal velocity
    /// after an impact is `-restitution` times the one before (`0 <= restitution <= 1`).
    Unilateral {
        /// Coefficient of restitution `C_R`.
        restitution: f64,
    },
    /// Set-valued bilateral contact: the gap rate is zero (the contour points stay in contact;
    /// the gap itself may drift, no position projection).
    Bilateral,
    /// Regularized unilateral contact: a spring-damper acting only when penetrating,
    /// `F_N = max(0, -stiffness g_N - damping g_N_dot)` for `g_N < 0`, else 0.
    Regularized {
        /// Stiffness `k` (> 0).
        stiffness: f64,
        /// Damping `d` (>= 0).
        damping: f64,
    },
}

/// How many tangent directions carry friction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TangentDirections {
    /// One: `t_1` of the contact frame (planar motion; for a plane contour its frame's x axis).
    Planar,
    /// Both tangents (spatial friction, an isotropic disc).
    Spatial,
}

impl TangentDirections {
    /// Number of tangent rows (1 or 2).
    pub fn count(self) -> usize {
        match self {
            TangentDirections::Planar => 1,
            TangentDirections::Spatial => 2,
        }
    }
}

/// The tangential law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Friction {
    /// Frictionless.
    None,
    /// Set-valued Coulomb friction with coefficient `mu` (stick and slip).
    Coulomb {
        /// Friction coefficient (>= 0).
        mu: f64,
        /// Planar or spatial.
        directions: TangentDirections,
    },
    /// Regularized Coulomb friction: `F_T = -mu F_N g_T_dot / max(|g_T_dot|, slip_velocity)`
    /// (linear in the slip velocity below `slip_velocity`). Only with a regularized normal law.
    Regularized {
        /// Friction coefficient (>= 0).
        mu: f64,
        /// Slip velocity of full friction (> 0).
        slip_velocity: f64,
        /// Planar or spatial.
        directions: TangentDirections,
    },
}

impl Friction {
    /// Tangent rows this law uses (0, 1 or 2).
    pub fn num_tangents(&self) -> usize {
        match self {
            Friction::None => 0,
            Friction::Coulomb { directions, .. } | Friction::Regularized { directions, .. } => {
                directions.count()
            }
        }
    }
}

/// The law of a contact: normal and tangential.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactLaw {
    /// Normal law.
    pub normal: NormalLaw,
    /// Tangential law.
    pub friction: Friction,
}

impl ContactLaw {
    /// Frictionless unilateral contact with Newton impact `C_R = restitution`.
    pub fn unilateral(restitution: f64) -> Self {
        Self {
            normal: NormalLaw::Unilateral { restitution },
            friction: Friction::None,
        }
    }

    /// Regularized (penalty) unilateral contact without friction.
    pub fn regularized(stiffness: f64, damping: f64) -> Self {
        Self {
            normal: NormalLaw::Regularized { stiffness, damping },
            friction: Friction::None,
        }
    }

    /// Same law with set-valued Coulomb friction.
    pub fn with_coulomb(mut self, mu: f64, directions: TangentDirections) -> Self {
        self.friction = Friction::Coulomb { mu, directions };
        self
    }

    /// Same law with regularized friction.
    pub fn with_regularized_friction(
        mut self,
        mu: f64,
        slip_velocity: f64,
        directions: TangentDirections,
    ) -> Self {
        self.friction = Friction::Regularized {
            mu,
            slip_velocity,
            directions,
        };
        self
    }

    /// Is the normal law set-valued (solved on velocity level)?
    pub fn set_valued_normal(&self) -> bool {
        !matches!(self.normal, NormalLaw::Regularized { .. })
    }

    /// Checks the parameters: `(name, value, reason)` of the first bad one.
    pub fn validate(&self) -> Result<(), (&'static str, f64, &'static str)> {
        let finite_nonneg = |name, v: f64| {
            if v >= 0.0 && v.is_finite() {
                Ok(())
            } else {
                Err((name, v, "must be finite and >= 0"))
            }
        };
        match self.normal {
            NormalLaw::Unilateral { restitution } => {
                if !(0.0..=1.0).contains(&restitution) {
                    return Err(("restitution", restitution, "must lie in [0, 1]"));
                }
            }
            NormalLaw::Bilateral => {}
            NormalLaw::Regularized { stiffness, damping } => {
                finite_nonneg("stiffness", stiffness)?;
                if stiffness == 0.0 {
                    return Err(("stiffness", stiffness, "must be > 0"));
                }
                finite_nonneg("damping", damping)?;
            }
        }
        match self.friction {
            Friction::None => {}
            Friction::Coulomb { mu, .. } => finite_nonneg("mu", mu)?,
            Friction::Regularized {
                mu, slip_velocity, ..
            } => {
                finite_nonneg("mu", mu)?;
                if !(slip_velocity > 0.0 && slip_velocity.is_finite()) {
                    return Err(("slip_velocity", slip_velocity, "must be finite and > 0"));
                }
                if self.set_valued_normal() {
                    return Err((
                        "slip_velocity",
                        slip_velocity,
                        "regularized friction needs a regularized normal law",
                    ));
                }
            }
        }
        Ok(())
    }
}

/// `prox_{R+}(x) = max(x, 0)`: the proximal point of the unilateral normal impulse.
pub fn prox_nonnegative(x: f64) -> f64 {
    x.max(0.0)
}

/// Proximal point of `x` (length 1 or 2) on the disc (interval) of radius `bound`, in place.
pub fn prox_disc(x: &mut [f64], bound: f64) {
    let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
    if norm > bound {
        let s = if norm > 0.0 { bound / norm } else { 0.0 };
        x.iter_mut().for_each(|v| *v *= s);
    }
}

/// Regularized normal force `F_N >= 0` of a spring-damper at gap `g` and rate `g_dot`
/// (0 when apart; never pulling).
pub fn regularized_normal_force(stiffness: f64, damping: f64, g: f64, g_dot: f64) -> f64 {
    if g >= 0.0 {
        0.0
    } else {
        (-stiffness * g - damping * g_dot).max(0.0)
    }
}

/// Regularized friction force components (length 1 or 2) for the slip velocity `g_t_dot`:
/// `-mu F_N g_T_dot / max(|g_T_dot|, slip_velocity)`.
pub fn regularized_friction_force(
    mu: f64,
    slip_velocity: f64,
    normal_force: f64,
    g_t_dot: &[f64],
    out: &mut [f64],
) {
    let v = g_t_dot.iter().map(|x| x * x).sum::<f64>().sqrt();
    let s = mu * normal_force / v.max(slip_velocity);
    for (o, g) in out.iter_mut().zip(g_t_dot) {
        *o = -s * g;
    }
}

/// Potential energy `1/2 k g_N^2` of a penetrating regularized contact (0 when apart).
pub fn regularized_energy(stiffness: f64, g: f64) -> f64 {
    if g < 0.0 {
        0.5 * stiffness * g * g
    } else {
        0.0
    }
}

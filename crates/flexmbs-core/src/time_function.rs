//! Scalar functions of time for loads and prescribed motion.

use crate::error::ModelError;
use crate::ids::LoadId;
use std::f64::consts::PI;

/// A scalar function of time `f(t)`: load amplitudes and prescribed joint motion.
///
/// All variants are piecewise smooth; [`TimeFunction::derivative`] and
/// [`TimeFunction::second_derivative`] return the one-sided (right) derivative at kinks and
/// ignore jumps (a step has derivative 0 everywhere).
#[derive(Debug, Clone, PartialEq)]
pub enum TimeFunction {
    /// `f(t) = value`.
    Constant(f64),
    /// Linear ramp from `v0` at `t0` to `v1` at `t1`; constant `v0` before and `v1` after.
    Ramp {
        /// Start time.
        t0: f64,
        /// End time (> t0).
        t1: f64,
        /// Value up to t0.
        v0: f64,
        /// Value from t1 on.
        v1: f64,
    },
    /// Jump from `before` to `after` at `t0` (`f(t0) = after`).
    Step {
        /// Jump time.
        t0: f64,
        /// Value before t0.
        before: f64,
        /// Value from t0 on.
        after: f64,
    },
    /// Rectangular pulse: `value` for `t0 <= t < t1`, zero otherwise.
    Pulse {
        /// Start time.
        t0: f64,
        /// End time (> t0).
        t1: f64,
        /// Pulse height.
        value: f64,
    },
    /// `offset + amplitude * sin(2 pi frequency_hz t + phase)`.
    Harmonic {
        /// Amplitude.
        amplitude: f64,
        /// Frequency in Hz.
        frequency_hz: f64,
        /// Phase in rad.
        phase: f64,
        /// Constant offset.
        offset: f64,
    },
    /// Piecewise-linear interpolation of `(times[i], values[i])`, constant extrapolation.
    Table {
        /// Strictly increasing sample times.
        times: Vec<f64>,
        /// Sample values (same length).
        values: Vec<f64>,
    },
    /// Smooth move from `v0` at `t0` to `v1` at `t1` along a normalized motion law:
    /// `f = v0 + (v1 - v0) s(tau)`, `tau = (t - t0) / (t1 - t0)`; constant `v0` before and `v1`
    /// after, with zero velocity at both ends.
    Move {
        /// Start time.
        t0: f64,
        /// End time (> t0).
        t1: f64,
        /// Value up to t0.
        v0: f64,
        /// Value from t1 on.
        v1: f64,
        /// Shape `s(tau)` of the move.
        law: MotionLaw,
    },
    /// A user's function ([`crate::user_function::UserTimeFunction`]): the extension point for
    /// time functions the variants above do not cover.
    User(crate::user_function::UserFunctionRef),
}

/// A normalized motion law `s(tau)` on `[0, 1]` with `s(0) = 0`, `s(1) = 1`, `s'(0) = s'(1) = 0`,
/// point-symmetric about `(1/2, 1/2)` (so `int_0^1 s = 1/2`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MotionLaw {
    /// `s = 3 tau^2 - 2 tau^3` (Adams STEP): zero velocity at both ends, the acceleration jumps
    /// by `6 (v1 - v0) / T^2` there (finite; the jerk is infinite).
    Cubic,
    /// `s = 10 tau^3 - 15 tau^4 + 6 tau^5` (Adams STEP5): zero velocity and acceleration at both
    /// ends.
    Quintic,
    /// Cycloid `s = tau - sin(2 pi tau) / (2 pi)`: zero velocity and acceleration at both ends,
    /// sinusoidal acceleration.
    Cycloidal,
    /// Trapezoidal velocity with smoothed (S-curve) corners: the velocity rises along a cycloid
    /// over the first `ramp` fraction of the move, stays at its peak `1 / (1 - ramp)`, and falls
    /// symmetrically over the last `ramp` fraction; the acceleration is a `1 - cos` pulse in each
    /// ramp, so it is continuous (zero at both ends and at the corners).
    Trapezoid {
        /// Fraction of the move spent in each of the acceleration and deceleration ramps,
        /// `0 < ramp <= 1/2` (`1/2`: no constant-velocity phase).
        ramp: f64,
    },
}

impl MotionLaw {
    /// Position `s`, velocity `s'`, acceleration `s''` and integral `S = int_0^tau s` of the law
    /// at `tau` in `[0, 1]`.
    pub fn eval(&self, tau: f64) -> [f64; 4] {
        let x = tau;
        match *self {
            Self::Cubic => [
                x * x * (3.0 - 2.0 * x),
                6.0 * x * (1.0 - x),
                6.0 - 12.0 * x,
                x.powi(3) * (1.0 - 0.5 * x),
            ],
            Self::Quintic => [
                x.powi(3) * (10.0 + x * (-15.0 + 6.0 * x)),
                30.0 * x * x * (1.0 - x) * (1.0 - x),
                60.0 * x * (1.0 - x) * (1.0 - 2.0 * x),
                x.powi(4) * (2.5 + x * (-3.0 + x)),
            ],
            Self::Cycloidal => {
                let w = 2.0 * PI;
                [
                    x - (w * x).sin() / w,
                    1.0 - (w * x).cos(),
                    w * (w * x).sin(),
                    0.5 * x * x + ((w * x).cos() - 1.0) / (w * w),
                ]
            }
            Self::Trapezoid { ramp } => trapezoid(ramp, x),
        }
    }
}

/// [`MotionLaw::Trapezoid`] at `tau`: peak velocity `v = 1 / (1 - r)`; in the first ramp
/// (`x = tau / r`) `s' = v c(x)` with the cycloid `c(x) = x - sin(2 pi x) / (2 pi)`, so
/// `s = v r P(x)`, `P = x^2/2 + (cos 2 pi x - 1)/(4 pi^2)`, `s'' = v (1 - cos 2 pi x) / r` and
/// `S = v r^2 Q(x)`, `Q = x^3/6 + (sin(2 pi x)/(2 pi) - x)/(4 pi^2)`; constant velocity between the
/// ramps; the last ramp by the point symmetry `s(tau) = 1 - s(1 - tau)`,
/// `S(tau) = S(1) - (1 - tau) + S(1 - tau)` with `S(1) = 1/2`.
fn trapezoid(r: f64, tau: f64) -> [f64; 4] {
    let v = 1.0 / (1.0 - r);
    let w = 2.0 * PI;
    let first = |tau: f64| -> [f64; 4] {
        if tau <= r {
            let x = tau / r;
            [
                v * r * (0.5 * x * x + ((w * x).cos() - 1.0) / (w * w)),
                v * (x - (w * x).sin() / w),
                v * (1.0 - (w * x).cos()) / r,
                v * r * r * (x.powi(3) / 6.0 + ((w * x).sin() / w - x) / (w * w)),
            ]
        } else {
            // s(r) = v r / 2, S(r) = v r^2 / 6 (at x = 1)
            let d = tau - r;
            [
                v * (0.5 * r + d),
                v,
                0.0,
                v * r * r / 6.0 + v * (0.5 * r * d + 0.5 * d * d),
            ]
        }
    };
    if tau <= 0.5 {
        first(tau)
    } else {
        let [s, ds, dds, int] = first(1.0 - tau);
        [1.0 - s, ds, -dds, 0.5 - (1.0 - tau) + int]
    }
}

/// A discontinuity of a time function: a jump of its value (`order` 0) or of its first
/// derivative (`order` 1, a kink) at time `t`, of size `jump` (right minus left limit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Discontinuity {
    /// Time of the jump.
    pub t: f64,
    /// 0: the value jumps; 1: the first derivative jumps.
    pub order: u8,
    /// Right limit minus left limit.
    pub jump: f64,
}

impl TimeFunction {
    /// Checks the parameters (finite numbers, ordered times, table consistency).
    pub fn validate(&self, load: Option<LoadId>) -> Result<(), ModelError> {
        let bad = |name, value, reason| {
            Err(ModelError::InvalidParameter {
                name,
                value,
                reason,
            })
        };
        match self {
            Self::Ramp { t0, t1, .. } | Self::Pulse { t0, t1, .. } | Self::Move { t0, t1, .. }
                if t1.partial_cmp(t0) != Some(std::cmp::Ordering::Greater) =>
            {
                bad("t1", *t1, "must be greater than t0")
            }
            Self::Move {
                law: MotionLaw::Trapezoid { ramp },
                ..
            } if !(*ramp > 0.0 && *ramp <= 0.5) => bad("ramp", *ramp, "must be in (0, 0.5]"),
            Self::Table { times, values } => {
                if times.is_empty() || times.len() != values.len() {
                    return Err(ModelError::InvalidTimeTable {
                        load,
                        reason: "times and values must be non-empty and of equal length",
                    });
                }
                if times
                    .windows(2)
                    .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
                {
                    return Err(ModelError::InvalidTimeTable {
                        load,
                        reason: "times must be strictly increasing",
                    });
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }

    /// Value `f(t)`.
    pub fn value(&self, t: f64) -> f64 {
        match self {
            Self::Constant(c) => *c,
            Self::User(f) => f.0.value(t),
            Self::Ramp { t0, t1, v0, v1 } => {
                if t <= *t0 {
                    *v0
                } else if t >= *t1 {
                    *v1
                } else {
                    v0 + (v1 - v0) * (t - t0) / (t1 - t0)
                }
            }
            Self::Step { t0, before, after } => {
                if t < *t0 {
                    *before
                } else {
                    *after
                }
            }
            Self::Pulse { t0, t1, value } => {
                if t >= *t0 && t < *t1 {
                    *value
                } else {
                    0.0
                }
            }
            Self::Harmonic {
                amplitude,
                frequency_hz,
                phase,
                offset,
            } => offset + amplitude * (2.0 * PI * frequency_hz * t + phase).sin(),
            Self::Table { times, values } => {
                let (i, s) = table_segment(times, t);
                match s {
                    None => values[i],
                    Some(s) => values[i] + s * (values[i + 1] - values[i]),
                }
            }
            Self::Move {
                t0,
                t1,
                v0,
                v1,
                law,
                ..
            } => match move_phase(*t0, *t1, t) {
                MovePhase::Before => *v0,
                MovePhase::After => *v1,
                MovePhase::During(tau) => v0 + (v1 - v0) * law.eval(tau)[0],
            },
        }
    }

    /// First time derivative `f'(t)` (right derivative at kinks, jumps ignored).
    pub fn derivative(&self, t: f64) -> f64 {
        match self {
            Self::Constant(_) | Self::Step { .. } | Self::Pulse { .. } => 0.0,
            Self::User(f) => f.0.derivative(t),
            Self::Ramp { t0, t1, v0, v1 } => {
                if t >= *t0 && t < *t1 {
                    (v1 - v0) / (t1 - t0)
                } else {
                    0.0
                }
            }
            Self::Harmonic {
                amplitude,
                frequency_hz,
                phase,
                ..
            } => {
                let w = 2.0 * PI * frequency_hz;
                amplitude * w * (w * t + phase).cos()
            }
            Self::Table { times, values } => match table_segment(times, t) {
                (i, Some(_)) => (values[i + 1] - values[i]) / (times[i + 1] - times[i]),
                _ => 0.0,
            },
            Self::Move {
                t0,
                t1,
                v0,
                v1,
                law,
                ..
            } => match move_phase(*t0, *t1, t) {
                MovePhase::During(tau) => (v1 - v0) / (t1 - t0) * law.eval(tau)[1],
                _ => 0.0,
            },
        }
    }

    /// Second time derivative `f''(t)` (zero for the piecewise-linear variants).
    pub fn second_derivative(&self, t: f64) -> f64 {
        match self {
            Self::User(f) => f.0.second_derivative(t),
            Self::Harmonic {
                amplitude,
                frequency_hz,
                phase,
                ..
            } => {
                let w = 2.0 * PI * frequency_hz;
                -amplitude * w * w * (w * t + phase).sin()
            }
            Self::Move {
                t0,
                t1,
                v0,
                v1,
                law,
                ..
            } => match move_phase(*t0, *t1, t) {
                MovePhase::During(tau) => (v1 - v0) / ((t1 - t0) * (t1 - t0)) * law.eval(tau)[2],
                _ => 0.0,
            },
            _ => 0.0,
        }
    }

    /// The jumps of the value and of the first derivative (kinks), in time order. A position
    /// drive with a kink has an infinite (Dirac) acceleration there, which
    /// [`TimeFunction::second_derivative`] cannot report; [`TimeFunction::Move`] and
    /// [`TimeFunction::Harmonic`] have none.
    pub fn discontinuities(&self) -> Vec<Discontinuity> {
        let jump = |t, order, jump| Discontinuity { t, order, jump };
        let mut out = match self {
            Self::Constant(_) | Self::Harmonic { .. } | Self::Move { .. } | Self::User(_) => {
                Vec::new()
            }
            Self::Ramp { t0, t1, v0, v1 } => {
                let slope = (v1 - v0) / (t1 - t0);
                vec![jump(*t0, 1, slope), jump(*t1, 1, -slope)]
            }
            Self::Step { t0, before, after } => vec![jump(*t0, 0, after - before)],
            Self::Pulse { t0, t1, value } => vec![jump(*t0, 0, *value), jump(*t1, 0, -value)],
            Self::Table { times, values } => {
                let n = times.len();
                let slope = |i: usize| {
                    if i == 0 || i == n {
                        0.0
                    } else {
                        (values[i] - values[i - 1]) / (times[i] - times[i - 1])
                    }
                };
                (0..n)
                    .map(|i| jump(times[i], 1, slope(i + 1) - slope(i)))
                    .collect()
            }
        };
        out.retain(|d| d.jump != 0.0);
        out
    }

    /// Integral `int_0^t f(s) ds` (exact for every variant).
    pub fn integral(&self, t: f64) -> f64 {
        if let Self::User(f) = self {
            return f.0.integral(t);
        }
        self.antiderivative(t) - self.antiderivative(0.0)
    }

    /// An antiderivative `F` with `F' = f` (arbitrary constant).
    fn antiderivative(&self, t: f64) -> f64 {
        match self {
            Self::Constant(c) => c * t,
            Self::Ramp { t0, t1, v0, v1 } => {
                if t <= *t0 {
                    v0 * (t - t0)
                } else if t >= *t1 {
                    0.5 * (v0 + v1) * (t1 - t0) + v1 * (t - t1)
                } else {
                    let f = self.value(t);
                    0.5 * (v0 + f) * (t - t0)
                }
            }
            Self::Step { t0, before, after } => {
                if t < *t0 {
                    before * (t - t0)
                } else {
                    after * (t - t0)
                }
            }
            Self::Pulse { t0, t1, value } => value * (t.clamp(*t0, *t1) - t0),
            Self::Harmonic {
                amplitude,
                frequency_hz,
                phase,
                offset,
            } => {
                let w = 2.0 * PI * frequency_hz;
                if w == 0.0 {
                    (offset + amplitude * phase.sin()) * t
                } else {
                    offset * t - amplitude / w * (w * t + phase).cos()
                }
            }
            Self::Table { times, values } => {
                if t <= times[0] {
                    return values[0] * (t - times[0]);
                }
                let mut acc = 0.0;
                for i in 0..times.len() - 1 {
                    if t <= times[i + 1] {
                        let f = self.value(t);
                        return acc + 0.5 * (values[i] + f) * (t - times[i]);
                    }
                    acc += 0.5 * (values[i] + values[i + 1]) * (times[i + 1] - times[i]);
                }
                acc + values[values.len() - 1] * (t - times[times.len() - 1])
            }
            Self::Move {
                t0,
                t1,
                v0,
                v1,
                law,
                ..
            } => {
                let dur = t1 - t0;
                match move_phase(*t0, *t1, t) {
                    MovePhase::Before => v0 * (t - t0),
                    MovePhase::During(tau) => v0 * (t - t0) + (v1 - v0) * dur * law.eval(tau)[3],
                    MovePhase::After => 0.5 * (v0 + v1) * dur + v1 * (t - t1),
                }
            }
            Self::User(f) => f.0.integral(t),
        }
    }
}

/// Where `t` lies relative to a move over `[t0, t1]`.
enum MovePhase {
    Before,
    /// Normalized time `tau = (t - t0) / (t1 - t0)` in `[0, 1)`.
    During(f64),
    After,
}

fn move_phase(t0: f64, t1: f64, t: f64) -> MovePhase {
    if t < t0 {
        MovePhase::Before
    } else if t >= t1 {
        MovePhase::After
    } else {
        MovePhase::During((t - t0) / (t1 - t0))
    }
}

/// Segment index `i` and local coordinate `s` in `[0, 1)` of `t` in a table; `s = None` outside
/// the table (value `values[i]` then, with `i` the first or last sample).
fn table_segment(times: &[f64], t: f64) -> (usize, Option<f64>) {
    let n = times.len();
    if t < times[0] {
        return (0, None);
    }
    if t >= times[n - 1] {
        return (n - 1, None);
    }
    let i = times.partition_point(|&x| x <= t) - 1;
    (i, Some((t - times[i]) / (times[i + 1] - times[i])))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all_variants() -> Vec<TimeFunction> {
        vec![
            TimeFunction::Constant(2.5),
            TimeFunction::Ramp {
                t0: 0.2,
                t1: 0.7,
                v0: -1.0,
                v1: 3.0,
            },
            TimeFunction::Step {
                t0: 0.4,
                before: 1.0,
                after: -2.0,
            },
            TimeFunction::Pulse {
                t0: 0.3,
                t1: 0.6,
                value: 4.0,
            },
            TimeFunction::Harmonic {
                amplitude: 1.5,
                frequency_hz: 2.0,
                phase: 0.3,
                offset: 0.5,
            },
            TimeFunction::Table {
                times: vec![0.1, 0.5, 0.8],
                values: vec![1.0, -1.0, 2.0],
            },
        ]
        .into_iter()
        .chain(moves())
        .collect()
    }

    /// One move of each law from -1 at 0.2 s to 3 at 0.9 s.
    fn moves() -> Vec<TimeFunction> {
        [
            MotionLaw::Cubic,
            MotionLaw::Quintic,
            MotionLaw::Cycloidal,
            MotionLaw::Trapezoid { ramp: 0.25 },
            MotionLaw::Trapezoid { ramp: 0.5 },
        ]
        .into_iter()
        .map(|law| TimeFunction::Move {
            t0: 0.2,
            t1: 0.9,
            v0: -1.0,
            v1: 3.0,
            law,
        })
        .collect()
    }

    /// Cubic (Adams STEP), quintic (STEP5) and cycloidal moves against their closed forms in `t`
    /// (value, velocity, acceleration, integral from 0), inside, before and after the move.
    #[test]
    fn smooth_steps_match_closed_forms() {
        let (t0, t1, v0, v1) = (0.2, 0.9, -1.0, 3.0);
        let (d, big_t) = (v1 - v0, t1 - t0);
        type Closed = fn(f64) -> [f64; 4];
        // [s, ds/dtau, d2s/dtau2, int_0^tau s]
        let cubic: Closed = |x| {
            [
                3.0 * x * x - 2.0 * x.powi(3),
                6.0 * x - 6.0 * x * x,
                6.0 - 12.0 * x,
                x.powi(3) - 0.5 * x.powi(4),
            ]
        };
        let quintic: Closed = |x| {
            [
                6.0 * x.powi(5) - 15.0 * x.powi(4) + 10.0 * x.powi(3),
                30.0 * x.powi(4) - 60.0 * x.powi(3) + 30.0 * x * x,
                120.0 * x.powi(3) - 180.0 * x * x + 60.0 * x,
                x.powi(6) - 3.0 * x.powi(5) + 2.5 * x.powi(4),
            ]
        };
        let cycloidal: Closed = |x| {
            let a = 2.0 * PI * x;
            [
                x - a.sin() / (2.0 * PI),
                1.0 - a.cos(),
                2.0 * PI * a.sin(),
                x * x / 2.0 - (1.0 - a.cos()) / (4.0 * PI * PI),
            ]
        };
        for (law, closed) in [
            (MotionLaw::Cubic, cubic),
            (MotionLaw::Quintic, quintic),
            (MotionLaw::Cycloidal, cycloidal),
        ] {
            let f = TimeFunction::Move {
                t0,
                t1,
                v0,
                v1,
                law,
            };
            f.validate(None).unwrap();
            assert_eq!(f.discontinuities(), vec![]);
            for k in 0..=40 {
                let t = 1.1 * k as f64 / 40.0;
                let tau = ((t - t0) / big_t).clamp(0.0, 1.0);
                let [s, ds, dds, int] = closed(tau);
                let inside = t >= t0 && t < t1;
                let expect = [
                    v0 + d * s,
                    if inside { d * ds / big_t } else { 0.0 },
                    if inside { d * dds / big_t.powi(2) } else { 0.0 },
                    // int_0^t: v0 t + d T S(tau), plus v1 - v0 times the time after t1
                    v0 * t + d * big_t * int + d * (t - t1).max(0.0),
                ];
                let got = [
                    f.value(t),
                    f.derivative(t),
                    f.second_derivative(t),
                    f.integral(t),
                ];
                for (i, (g, e)) in got.iter().zip(expect).enumerate() {
                    assert!((g - e).abs() < 1e-12, "{law:?} t {t} [{i}]: {g} vs {e}");
                }
            }
            // zero velocity at both ends; zero acceleration too except for the cubic
            let ends = [closed(0.0), closed(1.0)];
            let acc_at_ends = ends[0][2].abs() + ends[1][2].abs();
            assert!(ends[0][1].abs() + ends[1][1].abs() < 1e-12, "{law:?}");
            assert_eq!(law == MotionLaw::Cubic, acc_at_ends > 1.0, "{law:?}");
        }
    }

    /// The S-curve trapezoid: velocity and acceleration continuous (left and right limits at
    /// the ends and corners agree to the finite-difference error), peak velocity `D / ((1 - r) T)`
    /// and peak acceleration `2 D / (r (1 - r) T^2)`, and the position from integrating its
    /// acceleration twice (trapezoidal rule, not the position formula).
    #[test]
    fn s_curve_trapezoid_is_smooth_and_reaches_its_peaks() {
        let (t0, t1, v0, v1) = (0.2, 0.9, -1.0, 3.0);
        let (d, big_t) = (v1 - v0, t1 - t0);
        for r in [0.1, 0.25, 0.5] {
            let f = TimeFunction::Move {
                t0,
                t1,
                v0,
                v1,
                law: MotionLaw::Trapezoid { ramp: r },
            };
            f.validate(None).unwrap();
            let e = 1e-9;
            for tc in [t0, t0 + r * big_t, t1 - r * big_t, t1] {
                for g in [
                    &(|t| f.value(t)) as &dyn Fn(f64) -> f64,
                    &|t| f.derivative(t),
                    &|t| f.second_derivative(t),
                ] {
                    assert!((g(tc + e) - g(tc - e)).abs() < 1e-6, "r {r} at {tc}");
                }
            }
            let v_peak = f.derivative(0.5 * (t0 + t1));
            assert!((v_peak - d / ((1.0 - r) * big_t)).abs() < 1e-12, "r {r}");
            let a_peak = f.second_derivative(t0 + 0.5 * r * big_t);
            let expect = 2.0 * d / (r * (1.0 - r) * big_t * big_t);
            assert!((a_peak - expect).abs() < 1e-9 * expect, "r {r}");
            let n = 200_000;
            let h = 1.0 / n as f64;
            let (mut x, mut v) = (f.value(0.0), 0.0);
            for k in 0..n {
                let (a, b) = (k as f64 * h, (k + 1) as f64 * h);
                let v_next = v + 0.5 * h * (f.second_derivative(a) + f.second_derivative(b));
                x += 0.5 * h * (v + v_next);
                v = v_next;
            }
            assert!((x - f.value(1.0)).abs() < 1e-8, "r {r}: {x}");
            assert!((x - v1).abs() < 1e-8, "r {r}: {x}");
        }
        let bad = TimeFunction::Move {
            t0,
            t1,
            v0,
            v1,
            law: MotionLaw::Trapezoid { ramp: 0.6 },
        };
        assert!(matches!(
            bad.validate(None),
            Err(ModelError::InvalidParameter { name: "ramp", .. })
        ));
    }

    /// Finite differences of value and derivative at many points of every move.
    #[test]
    fn moves_match_finite_differences() {
        let e = 1e-6;
        for f in moves() {
            for k in 1..60 {
                let t = 1.1 * k as f64 / 60.0;
                let fd = (f.value(t + e) - f.value(t - e)) / (2.0 * e);
                assert!((fd - f.derivative(t)).abs() < 1e-6, "{f:?} t {t}");
                let fd2 = (f.derivative(t + e) - f.derivative(t - e)) / (2.0 * e);
                assert!((fd2 - f.second_derivative(t)).abs() < 1e-3, "{f:?} t {t}");
            }
        }
    }

    #[test]
    fn discontinuities_of_piecewise_functions() {
        let d = |t, order, jump| Discontinuity { t, order, jump };
        let ramp = TimeFunction::Ramp {
            t0: 0.5,
            t1: 1.5,
            v0: 0.0,
            v1: 2.0,
        };
        assert_eq!(
            ramp.discontinuities(),
            vec![d(0.5, 1, 2.0), d(1.5, 1, -2.0)]
        );
        let step = TimeFunction::Step {
            t0: 0.3,
            before: 1.0,
            after: -2.0,
        };
        assert_eq!(step.discontinuities(), vec![d(0.3, 0, -3.0)]);
        let table = TimeFunction::Table {
            times: vec![0.0, 1.0, 2.0, 3.0],
            values: vec![0.0, 1.0, 2.0, 0.0],
        };
        // slope 1, 1, -2: kinks at 0 (+1), 2 (-3) and 3 (+2); none at 1
        assert_eq!(
            table.discontinuities(),
            vec![d(0.0, 1, 1.0), d(2.0, 1, -3.0), d(3.0, 1, 2.0)]
        );
    }

    /// The integral agrees with composite Simpson quadrature of `value` (kinks at sample points
    /// are resolved by a fine grid), the derivative with central differences away from kinks.
    #[test]
    fn integral_and_derivative_match_numerical_quadrature() {
        for f in all_variants() {
            f.validate(None).unwrap();
            let t_end = 1.13;
            let n = 200_000;
            let h = t_end / n as f64;
            let mut sum = 0.0;
            for k in 0..n {
                let (a, b) = (k as f64 * h, (k + 1) as f64 * h);
                sum += h / 6.0 * (f.value(a) + 4.0 * f.value(0.5 * (a + b)) + f.value(b));
            }
            assert!(
                (sum - f.integral(t_end)).abs() < 1e-4,
                "{f:?}: {sum} vs {}",
                f.integral(t_end)
            );
            let t = 0.45;
            let e = 1e-6;
            let fd = (f.value(t + e) - f.value(t - e)) / (2.0 * e);
            assert!(
                (fd - f.derivative(t)).abs() < 1e-6,
                "{f:?}: {fd} vs {}",
                f.derivative(t)
            );
            let fd2 = (f.derivative(t + e) - f.derivative(t - e)) / (2.0 * e);
            assert!((fd2 - f.second_derivative(t)).abs() < 1e-4, "{f:?}");
        }
    }

    #[test]
    fn invalid_tables_are_rejected() {
        let f = TimeFunction::Table {
            times: vec![0.0, 0.0],
            values: vec![1.0, 2.0],
        };
        assert!(matches!(
            f.validate(None),
            Err(ModelError::InvalidTimeTable { .. })
        ));
        let f = TimeFunction::Ramp {
            t0: 1.0,
            t1: 0.5,
            v0: 0.0,
            v1: 1.0,
        };
        assert!(matches!(
            f.validate(None),
            Err(ModelError::InvalidParameter { .. })
        ));
    }
}

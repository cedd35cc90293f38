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
            Self::Ramp { t0, t1, .. } | Self::Pulse { t0, t1, .. }
                if t1.partial_cmp(t0) != Some(std::cmp::Ordering::Greater) =>
            {
                bad("t1", *t1, "must be greater than t0")
            }
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
        }
    }

    /// First time derivative `f'(t)` (right derivative at kinks, jumps ignored).
    pub fn derivative(&self, t: f64) -> f64 {
        match self {
            Self::Constant(_) | Self::Step { .. } | Self::Pulse { .. } => 0.0,
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
        }
    }

    /// Second time derivative `f''(t)` (zero for the piecewise-linear variants).
    pub fn second_derivative(&self, t: f64) -> f64 {
        match self {
            Self::Harmonic {
                amplitude,
                frequency_hz,
                phase,
                ..
            } => {
                let w = 2.0 * PI * frequency_hz;
                -amplitude * w * w * (w * t + phase).sin()
            }
            _ => 0.0,
        }
    }

    /// Integral `int_0^t f(s) ds` (exact for every variant).
    pub fn integral(&self, t: f64) -> f64 {
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
        }
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

//! The open extension point for time functions: a Rust user implements [`UserTimeFunction`]
//! and wraps it in [`crate::TimeFunction::User`]; it then drives loads, prescribed motions and
//! servos like the built-in functions.

use std::sync::Arc;

/// A user's scalar function of time. `value` is required; the derivatives default to central
/// differences of `value` (step `1e-6 max(1, |t|)`, error `O(step^2)`), the integral to
/// composite Simpson over `[0, t]` (64 panels per unit of time, at least 64). Give them in closed
/// form where you can. No method may allocate (they run inside a time step).
pub trait UserTimeFunction: std::fmt::Debug + Send + Sync {
    /// `f(t)`.
    fn value(&self, t: f64) -> f64;

    /// `f'(t)`.
    fn derivative(&self, t: f64) -> f64 {
        let e = 1e-6 * t.abs().max(1.0);
        (self.value(t + e) - self.value(t - e)) / (2.0 * e)
    }

    /// `f''(t)`.
    fn second_derivative(&self, t: f64) -> f64 {
        let e = 1e-4 * t.abs().max(1.0);
        (self.value(t + e) - 2.0 * self.value(t) + self.value(t - e)) / (e * e)
    }

    /// `int_0^t f(s) ds`.
    fn integral(&self, t: f64) -> f64 {
        let n = 2 * ((32.0 * t.abs()).ceil() as usize).max(32);
        let h = t / n as f64;
        let mut s = self.value(0.0) + self.value(t);
        for i in 1..n {
            s += if i % 2 == 1 { 4.0 } else { 2.0 } * self.value(i as f64 * h);
        }
        s * h / 3.0
    }
}

/// A shared handle to a [`UserTimeFunction`], the payload of [`crate::TimeFunction::User`].
/// Two handles are equal when they point to the same function.
#[derive(Debug, Clone)]
pub struct UserFunctionRef(pub Arc<dyn UserTimeFunction>);

impl UserFunctionRef {
    /// Wraps a function.
    pub fn new(f: impl UserTimeFunction + 'static) -> Self {
        Self(Arc::new(f))
    }
}

impl PartialEq for UserFunctionRef {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

//! Smoothness of prescribed joint motions: a position drive (`angle`, `displacement`) must be
//! continuous with a continuous rate, a rate drive (`angular_velocity`) continuous, after t = 0.
//! A position jump is refused (infinite velocity); a kink of a position drive or a jump of a rate
//! drive (infinite acceleration: an impulse that the solver sees only as a velocity jump, and a
//! spike in the joint's reaction) gives a warning that names the time, the jump and the smooth
//! functions to use instead.

use crate::compile::Ctx;
use crate::error::SimError;
use flexmbs_core::TimeFunction;

/// What a drive prescribes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DriveLevel {
    /// A position: `angle` (rad) or `displacement` (m).
    Position {
        /// SI unit of the position (`rad`, `m`).
        unit: &'static str,
    },
    /// A rate: `angular_velocity` (rad/s).
    Rate,
}

/// The smooth functions to use instead, for messages.
const USE_SMOOTH: &str = "use a smooth move instead: `type = \"step5\"` (quintic), \
     `\"cycloidal\"` or `\"move\"` (trapezoidal velocity with smooth corners), which start and \
     end with zero velocity and acceleration (see the time functions in the model-file reference)";

/// Checks the drive `f` of joint `joint` at key path `path` for jumps after t = 0 up to `t_end`
/// (all of them if `None`): errors for a position jump, warnings (pushed to `warnings`) for an
/// infinite acceleration.
pub fn check_drive_smoothness(
    ctx: &Ctx,
    path: &str,
    joint: &str,
    f: &TimeFunction,
    level: DriveLevel,
    t_end: Option<f64>,
    warnings: &mut Vec<String>,
) -> Result<(), SimError> {
    for d in f.discontinuities() {
        if d.t <= 0.0 || t_end.is_some_and(|t_end| d.t > t_end) {
            continue;
        }
        let t = d.t;
        let message = match (level, d.order) {
            (DriveLevel::Position { unit }, 0) => {
                return Err(ctx.err(
                    path,
                    format!(
                        "the prescribed motion of joint `{joint}` jumps by {:.6e} {unit} at t = {t} s: \
                         a position cannot jump (infinite velocity); {USE_SMOOTH}",
                        d.jump
                    ),
                ));
            }
            (DriveLevel::Position { unit }, _) => format!(
                "the prescribed motion of joint `{joint}` has a kink at t = {t} s: its rate jumps \
                 by {:.6e} {unit}/s, so its acceleration is infinite there (an impulse: the \
                 joint's reaction spikes and the bodies' velocities jump); {USE_SMOOTH}",
                d.jump
            ),
            (DriveLevel::Rate, 0) => format!(
                "the prescribed angular velocity of joint `{joint}` jumps by {:.6e} rad/s at \
                 t = {t} s, so its angular acceleration is infinite there (an impulse: the joint's \
                 reaction spikes); {USE_SMOOTH}",
                d.jump
            ),
            // a kink of a rate is a finite acceleration jump
            (DriveLevel::Rate, _) => continue,
        };
        warnings.push(ctx.err(path, message).to_string());
    }
    Ok(())
}

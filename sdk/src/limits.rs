//! The host's checks of the numbers it sends: finite values, positive limits, and the limits of
//! a point-to-point move. A leaf module (it imports only the error type), used by every module
//! that sends a command.

use crate::error::{Error, Result};

/// Limits of a point-to-point move, in user units (see
/// [`Axis::set_scale`](crate::Axis::set_scale)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveLimits {
    /// Maximum velocity.
    pub velocity: f64,
    /// Maximum acceleration.
    pub acceleration: f64,
    /// Maximum deceleration.
    pub deceleration: f64,
    /// Jerk of the seven-segment phases 1, 3 (acceleration) and 5, 7 (deceleration).
    pub jerk: [f64; 4],
}

impl MoveLimits {
    /// Symmetric limits: deceleration = acceleration, one jerk for all phases.
    pub fn new(velocity: f64, acceleration: f64, jerk: f64) -> Self {
        Self {
            velocity,
            acceleration,
            deceleration: acceleration,
            jerk: [jerk; 4],
        }
    }

    /// With a different deceleration.
    pub fn deceleration(mut self, d: f64) -> Self {
        self.deceleration = d;
        self
    }

    /// With a different jerk for the deceleration phases (5 and 7).
    pub fn decel_jerk(mut self, j: f64) -> Self {
        self.jerk[2] = j;
        self.jerk[3] = j;
        self
    }

    pub(crate) fn check(&self) -> Result<()> {
        let named = [
            ("velocity", self.velocity),
            ("acceleration", self.acceleration),
            ("deceleration", self.deceleration),
            ("jerk (phase 1)", self.jerk[0]),
            ("jerk (phase 3)", self.jerk[1]),
            ("jerk (phase 5)", self.jerk[2]),
            ("jerk (phase 7)", self.jerk[3]),
        ];
        named
            .into_iter()
            .try_for_each(|(what, v)| positive(what, v))
    }
}

/// Finite and greater than zero (a limit): `NotFinite` or `NonPositiveLimit` otherwise.
pub(crate) fn positive(what: &'static str, v: f64) -> Result<()> {
    finite(what, v)?;
    if v <= 0.0 {
        return Err(Error::NonPositive { what, value: v });
    }
    Ok(())
}

pub(crate) fn finite(what: &'static str, v: f64) -> Result<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(Error::NotFinite { what, value: v })
    }
}

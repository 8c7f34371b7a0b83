//! The errors of the NURBS interpolation layer ([`super::nurbs_interp`], [`super::path_speed`],
//! [`super::saturation`]), in a file of their own so those modules share them without
//! importing each other.

use super::nurbs::NurbsError;
use crate::servo::pdplus::ModelError;
use core::fmt;

/// Upper limit of Newton corrections after the Taylor predictor.
pub const MAX_CORRECTIONS: u32 = 8;

/// Errors of the interpolation layer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InterpError {
    /// The curve rejected an evaluation.
    Curve(NurbsError),
    /// Sample time not finite or not in (0, 1] s.
    BadSampleTime,
    /// Feed not finite or not > 0 (or a per-tick feed that is negative / NaN).
    BadFeed,
    /// Tangential acceleration limit not finite or not > 0.
    BadAccel,
    /// Tangential jerk limit not finite or not > 0.
    BadJerk,
    /// Chord tolerance not finite or not > 0.
    BadChordTolerance,
    /// `max_corrections > MAX_CORRECTIONS`.
    BadCorrections,
    /// The curve has (numerically) zero length.
    ZeroLengthCurve,
    /// An axis count does not match the curve / model dimension.
    DimensionMismatch { expected: usize, got: usize },
    /// A drive model (PD+ gains, drive constants, Umax) is refused.
    Model(ModelError),
    /// Planning budget fraction not in (0, 1].
    BadBudget,
    /// A measured / predicted state fed to the saturation predictor is NaN or infinite.
    NonFiniteInput,
}

impl fmt::Display for InterpError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Curve(e) => write!(f, "curve: {e}"),
            Self::BadSampleTime => write!(f, "sample time must be finite and in (0, 1] s"),
            Self::BadFeed => write!(f, "feed must be finite and > 0"),
            Self::BadAccel => write!(f, "acceleration limit must be finite and > 0"),
            Self::BadJerk => write!(f, "jerk limit must be finite and > 0"),
            Self::BadChordTolerance => write!(f, "chord tolerance must be finite and > 0"),
            Self::BadCorrections => write!(f, "at most {MAX_CORRECTIONS} corrections"),
            Self::ZeroLengthCurve => write!(f, "curve has zero length"),
            Self::DimensionMismatch { expected, got } => {
                write!(f, "expected {expected} axes, got {got}")
            }
            Self::Model(e) => write!(f, "{e}"),
            Self::BadBudget => write!(f, "budget fraction must be in (0, 1]"),
            Self::NonFiniteInput => write!(f, "non-finite state input"),
        }
    }
}

impl core::error::Error for InterpError {}

impl From<ModelError> for InterpError {
    fn from(e: ModelError) -> Self {
        match e {
            ModelError::BadSampleTime => Self::BadSampleTime,
            e => Self::Model(e),
        }
    }
}

impl From<NurbsError> for InterpError {
    fn from(e: NurbsError) -> Self {
        Self::Curve(e)
    }
}

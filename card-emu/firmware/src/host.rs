//! What a host shares with the card: the checks a configuration must pass before the card
//! takes it, and the offline planners. A host (the SDK) reaches this crate only through here,
//! so it runs the card's own code for these and nothing of the firmware besides.
//!
//! - Configuration checks, the card's own, which the SDK runs on a configuration file before it
//!   applies anything: the axis, group and path blocks, the filter bank's decoding, the safety,
//!   axis-safety, homing and I/O configurations (layout 1.11: the analog inputs, the PSO and
//!   the servo output's filters), and the defaults they start from.
//! - Refusals: the nack the card gives for a NURBS curve's fault ([`nurbs_nack`]).
//! - The offline planners: the S-curve planner and the time-optimal planner from any state
//!   ([`plan`]), NURBS curves (their checks, knot vectors, the split into pieces the card
//!   takes), the acc/dec filters' kinds and the papers' presets, the path engine's smoothing
//!   turn.
//! - Cam tables as the card builds and evaluates them ([`CamTable`]): a host that makes a table
//!   checks what the card will follow (the G-code runner's threads).

/// Layout 1.11: the analog inputs' and the PSO's checks at a servo rate (beyond the commands'
/// decoding), and a servo-output filter's check and design.
pub use crate::firmware::analog::{input_nack as analog_input_nack, pso_nack};
pub use crate::firmware::axis_safety::AxisSafetyConfig;
pub use crate::firmware::config::{
    decode_axis_filter, pdplus_block, pidff_block, validate_axis_config, validate_group_config,
};
pub use crate::firmware::group::{nurbs_nack, validate_path_config, FilterConfig};
pub use crate::firmware::homing::HomingConfig;
pub use crate::firmware::io::IoConfig;
pub use crate::firmware::safety::{
    SafetyConfig, MAX_STOP_TIME_DEFAULT_US, WATCHDOG_TIMEOUT_DEFAULT_US,
};
pub use crate::motion::cam::{CamSample, CamTable};
pub use crate::motion::filters::{FilterKind, FilterPreset};
pub use crate::motion::nurbs::{
    clamped_uniform_knots, split_curve, Nurbs, NurbsError, MAX_CTRL, MAX_DEGREE, MAX_DIM, MAX_KNOTS,
};
pub use crate::motion::path::SMOOTH_TURN;
pub use crate::presets::die_bonder_volts;
pub use crate::servo::biquad::design as design_biquad;
pub use firmware_proto::MAX_POSITION;

/// The card's S-curve planner ([`Profile`](plan::Profile), [`Limits`](plan::Limits)) and the
/// time-optimal planner from any state ([`Trajectory`](plan::Trajectory)), for planning a move
/// on the host.
pub mod plan {
    pub use crate::motion::otg::{OtgLimits, Trajectory};
    pub use crate::motion::scurve::*;
}

/// Layout 1.9: the compensation table's checks and arithmetic, which the SDK runs on a table
/// before it sends any of it (the card runs the same on each point).
pub use crate::firmware::comp::comp_nack;
pub use crate::motion::comp::{
    interpolate, CompError, CompParams, CompPoint, MAX_POINTS as COMP_MAX_POINTS,
};

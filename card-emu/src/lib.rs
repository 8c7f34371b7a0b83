//! The motion card in software.
//!
//! [`firmware`] is the card's complete firmware (command manager, PLCopen axis states, S-curve
//! profiles, FFPIV servo loops); [`plant`] simulates what hangs off the card (DAC, amplifier,
//! motor and load, encoder); [`emulator`] puts them behind a DPRAM window with an interrupt
//! line and drives them on a stepped, free-running or real-time clock; [`safety`] is the
//! firmware's safety layer (watchdog, limits, following error, e-stop) and [`faults`] the fault
//! injector tests drive; [`server`] serves a card
//! to another process (`emu:NAME`). The firmware only sees the window, exactly as it would on
//! the card's DSP.
#![deny(unsafe_op_in_unsafe_fn)]

pub mod axis;
pub mod circle;
pub mod emulator;
pub mod faults;
pub mod filters;
pub mod firmware;
#[doc(hidden)]
pub mod fuzzing;
pub mod group;
pub mod nurbs;
pub mod plant;
pub mod safety;
pub mod scurve;
pub mod server;
pub mod servo;
pub mod shm;
pub mod yeh;

pub use emulator::{Clock, EmuOptions, Emulator, Runner};
pub use firmware::Firmware;
pub use plant::{Motor, MotorParams, Switches};

use firmware_proto::NackCode;

pub use firmware_proto::{
    limit_range, MAX_MOVE_TIME, MAX_POSITION, SERVO_RATE_MAX_HZ, SERVO_RATE_MIN_HZ,
};

/// [`scurve::check_limits`] with the card's nack codes.
pub(crate) fn check_ranges(rate_hz: u32, limits: &[(i32, f64)]) -> Result<(), NackCode> {
    scurve::check_limits(limits, rate_hz).map_err(plan_nack)
}

/// The nack for a planner refusal.
pub(crate) fn plan_nack(e: scurve::PlanError) -> NackCode {
    match e {
        scurve::PlanError::NonFinite => NackCode::NotFinite,
        scurve::PlanError::NonPositiveLimit => NackCode::NonPositiveLimit,
        scurve::PlanError::Infeasible | scurve::PlanError::StartVelocityTooHigh => {
            NackCode::Infeasible
        }
        scurve::PlanError::LimitRange => NackCode::LimitRange,
        scurve::PlanError::PlanCheck => NackCode::PlanCheck,
    }
}

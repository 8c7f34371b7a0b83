//! The servo laws the firmware runs every tick.
#![forbid(unsafe_code)]

pub mod biquad;
pub mod ffpiv;
pub mod pdplus;
pub mod pidff;

//! The plain structs of the C ABI and their conversions from the SDK's types.
//!
//! Enumerations cross as `uint32_t` fields with `MC_` constants (a C enum holding a value the
//! library does not know would be undefined behaviour in C++). The constants that are the
//! card's codes are generated from the register map (`crate::codes`); those here are the C
//! ABI's own (the emulated card's options, the feed types, `MC_GROUP_ACCDEC_BOTH`,
//! `MC_EVENT_CARD_WIDE`).

mod axis;
mod group;
mod safety;
mod sim;

pub use axis::*;
pub use group::*;
pub use safety::*;
pub use sim::*;

//! Test support shared by this crate's tests, the emulator's and the SDK's: the one seeded
//! generator and the trajectory planner's cases.

pub mod otg;
pub mod rng;

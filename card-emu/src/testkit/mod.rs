//! Test support shared by the fuzz targets, the garbage tests and the unit tests.

#[cfg(feature = "emulator")]
pub mod fuzzing;
pub mod otg;
pub mod rng;

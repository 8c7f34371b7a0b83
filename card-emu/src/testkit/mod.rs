//! Test support shared by the fuzz targets, the garbage tests and the unit tests. The seeded
//! generator and the trajectory cases are the firmware crate's (its own tests use them).

#[cfg(feature = "emulator")]
pub mod fuzzing;
pub use card_firmware::testkit::{otg, rng};

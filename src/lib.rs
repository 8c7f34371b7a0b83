//! `motioncard`: the umbrella crate of the workspace. It re-exports the SDK so that the
//! workspace-level examples and tests read like an application would.
pub use motioncard_sdk::*;

pub mod cli;
pub mod gcode;
pub mod papers;
pub mod path_report;
pub mod plot;
pub mod run;
pub mod serve;
pub mod tuning;

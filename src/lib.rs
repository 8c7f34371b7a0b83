//! `mcctl`'s library: the command-line tool's subcommands ([`cli`]), `mcctl run` ([`run`],
//! measured by the SDK's [`motioncard_sdk::report`]), the tuning page ([`serve`],
//! [`tuning`]), plots ([`plot`]), and the papers' figures reproduced on the card ([`papers`],
//! for the `papers` example and tests). The SDK is the crate `motioncard_sdk`; its items are
//! in scope here as `crate::…` for these modules' own use, not re-exported.
pub(crate) use motioncard_sdk::*;

pub mod cli;
pub mod papers;
pub mod plot;
pub mod run;
pub mod serve;
pub mod tuning;

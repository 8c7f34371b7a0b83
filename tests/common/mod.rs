//! Helpers shared by the end-to-end tests.
#![allow(dead_code)]

use motioncard_sdk::plan::{Limits, Profile};
use motioncard_sdk::{Card, Clock, EmuOptions, PathLimits, SimOptions};

/// A stepped emulated card: deterministic on any machine.
pub fn stepped_card() -> Card {
    stepped_card_with(EmuOptions::default())
}

/// A stepped emulated card with explicit options.
pub fn stepped_card_with(emu: EmuOptions) -> Card {
    Card::open_sim(SimOptions {
        clock: Clock::Stepped,
        emu,
    })
    .expect("open stepped sim")
}

/// The seeded generator every test shares (card-emu's testkit): the same numbers on every
/// machine. (Like every helper here, not every test file uses it.)
#[allow(unused_imports)]
pub use card_emu::testkit::rng::Rng;

/// Duration of a rest-to-rest move of `distance` within `l` alone (the card's planner, one
/// jerk for every phase).
pub fn rest_to_rest_time(l: &PathLimits, distance: f64) -> f64 {
    let lim = Limits {
        vmax: l.velocity,
        amax: l.acceleration,
        dmax: l.deceleration,
        j1: l.jerk,
        j3: l.jerk,
        j5: l.jerk,
        j7: l.jerk,
    };
    Profile::plan(0.0, distance.abs(), 0.0, 0.0, &lim)
        .unwrap()
        .duration()
}

//! Helpers shared by the end-to-end tests.
#![allow(dead_code)]

use motioncard::{Card, Clock, EmuOptions, SimOptions};

/// A stepped emulated card: deterministic on any machine.
pub fn stepped_card() -> Card {
    stepped_card_with(EmuOptions::default())
}

/// A stepped emulated card with explicit options.
pub fn stepped_card_with(emu: EmuOptions) -> Card {
    Card::open_sim(SimOptions { clock: Clock::Stepped, emu }).expect("open stepped sim")
}

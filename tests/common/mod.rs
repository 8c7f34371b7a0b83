//! Helpers shared by the end-to-end tests.
#![allow(dead_code)]

use motioncard::plan::{Limits, Profile};
use motioncard::{Card, Clock, EmuOptions, PathLimits, SimOptions};

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

/// A small deterministic generator (xorshift64*), so tests need no crate and repeat exactly.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed.max(1))
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Log-uniform in [lo, hi).
    pub fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.uniform(lo.ln(), hi.ln()).exp()
    }
}

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

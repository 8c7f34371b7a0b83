//! The engine's entry points, each built twice: for the x86-64 baseline (SSE2) and for
//! x86-64-v3 (AVX2, FMA, BMI1/2, LZCNT), the second chosen at run time where the CPU has it
//! ([`detected`], kept in `Path::v3`). Their bodies (`push_impl`, `tick_plan_impl`,
//! `tick_move_impl`, `walk_impl`) and what those call are `#[inline(always)]`, so that the
//! compiler builds all of it with three-operand vector instructions instead of SSE2's register
//! copies (and the blend cap four samples at a time, `geom::LANES_V3`): about a fifth fewer
//! instructions on the dense benchmark
//! (`benches/path_callgrind.sh`, with and without `--baseline`).
//!
//! **The same motion to the last bit.** Rust never fuses a multiplication and an addition
//! into an FMA on its own, nor reorders a floating-point sum; every operation is the same IEEE
//! operation in either build (`tests::the_v3_build_moves_as_the_baseline_build`).
//!
//! This is the only place of `motion` with `unsafe`: calling a function built for features
//! the caller's build does not assume, after checking that the CPU has them.

use super::exec::{Envelope, Passed, Visit, Walked};
use super::*;

/// Whether this CPU has what the x86-64-v3 build of the engine uses.
pub(super) fn detected() -> bool {
    // The CPU is asked through std; a build without it (the card's) runs the baseline build.
    #[cfg(all(target_arch = "x86_64", feature = "host"))]
    {
        std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma")
            && std::arch::is_x86_feature_detected!("bmi1")
            && std::arch::is_x86_feature_detected!("bmi2")
            && std::arch::is_x86_feature_detected!("lzcnt")
    }
    #[cfg(not(all(target_arch = "x86_64", feature = "host")))]
    {
        false
    }
}

impl<const D: usize> Path<D> {
    /// Appends a segment: validates it, builds the blend with the previous one and computes
    /// the caps. Allocates nothing.
    #[inline(never)] // a function of its own in profiles: the cost benchmark counts it
    pub fn push(&mut self, seg: Segment<D>) -> Result<(), PathError> {
        #[cfg(target_arch = "x86_64")]
        if self.v3 {
            // SAFETY: `v3` is true only where the CPU has the features (`detected`)
            return unsafe { self.push_v3(seg) };
        }
        self.push_impl(seg)
    }

    /// The first half of [`tick`](Self::tick): dwells, then the look-ahead and the speed
    /// planner decide the next planning step (nothing moves yet), unless one is being run.
    /// Public for the cost benchmark, which times the two halves apart; call
    /// [`tick_move`](Self::tick_move) with the result at once.
    #[doc(hidden)]
    #[inline(never)]
    pub fn tick_plan(&mut self, feed_override: f64, ev: &mut impl FnMut(PathEvent)) -> TickPlan {
        #[cfg(target_arch = "x86_64")]
        if self.v3 {
            // SAFETY: as in `push`
            return unsafe { self.tick_plan_v3(feed_override, ev) };
        }
        self.tick_plan_impl(feed_override, ev)
    }

    /// The second half of [`tick`](Self::tick): moves along the path by the planned step
    /// (segment events and outputs on the way) and interpolates the position there.
    #[doc(hidden)]
    #[inline(never)]
    pub fn tick_move(&mut self, plan: TickPlan, ev: &mut impl FnMut(PathEvent)) -> [f64; D] {
        #[cfg(target_arch = "x86_64")]
        if self.v3 {
            // SAFETY: as in `push`
            return unsafe { self.tick_move_v3(plan, ev) };
        }
        self.tick_move_impl(plan, ev)
    }

    /// See `walk_impl`. A function of its own, out of `look`'s common tick (which a walk
    /// serves: fewer instructions than inlined).
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    pub(super) fn walk(
        &self,
        until: (f64, f64),
        below: f64,
        ovr: f64,
        wend: usize,
        env: Option<Envelope>,
        passed: &mut Passed,
        f: &mut impl Visit,
    ) -> Walked {
        #[cfg(target_arch = "x86_64")]
        if self.v3 {
            // SAFETY: as in `push`
            return unsafe { self.walk_v3(until, below, ovr, wend, env, passed, f) };
        }
        self.walk_impl(until, below, ovr, wend, env, passed, f)
    }

    /// Runs the x86-64-v3 build where the CPU has it (`true`, the default), or the baseline
    /// build (`false`: for comparing the two).
    #[doc(hidden)]
    pub fn set_v3(&mut self, on: bool) {
        self.v3 = on && detected();
    }

    /// Whether push and tick run the x86-64-v3 build.
    #[doc(hidden)]
    pub fn runs_v3(&self) -> bool {
        self.v3
    }
}

#[cfg(target_arch = "x86_64")]
impl<const D: usize> Path<D> {
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt")] // what `detected` checks
    #[inline(never)]
    fn push_v3(&mut self, seg: Segment<D>) -> Result<(), PathError> {
        self.push_impl(seg)
    }

    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt")] // what `detected` checks
    #[inline(never)]
    fn tick_plan_v3(&mut self, feed_override: f64, ev: &mut impl FnMut(PathEvent)) -> TickPlan {
        self.tick_plan_impl(feed_override, ev)
    }

    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt")] // what `detected` checks
    #[inline(never)]
    fn tick_move_v3(&mut self, plan: TickPlan, ev: &mut impl FnMut(PathEvent)) -> [f64; D] {
        self.tick_move_impl(plan, ev)
    }

    #[allow(clippy::too_many_arguments)]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt")] // what `detected` checks
    #[inline(never)]
    fn walk_v3(
        &self,
        until: (f64, f64),
        below: f64,
        ovr: f64,
        wend: usize,
        env: Option<Envelope>,
        passed: &mut Passed,
        f: &mut impl Visit,
    ) -> Walked {
        self.walk_impl(until, below, ovr, wend, env, passed, f)
    }
}

//! The handwheel (layout 1.10, issue 35): an auxiliary encoder input (a manual pulse
//! generator) jogs an axis. One [`Handwheel`] per axis, stepped by `Firmware::tick` after the
//! gearing step (which senses the auxiliary encoders) and before homing and the servo loops.
//!
//! **The target is exact.** Each detent (`detent` auxiliary counts) moves the axis's target by
//! `ratio` counts:
//!
//! ```text
//! target = x_a + ratio · (m − m_a) / detent
//! ```
//!
//! with `m` the input's count this tick and `(m_a, x_a)` the anchor (the count and the target
//! where the wheel was taken, or where a turn was last dropped). Nothing is summed tick by tick:
//! a wheel turned forth and back by the same counts brings the target back to the same number.
//!
//! **Within the axis's limits.** The axis follows the target along a time-optimal jerk-limited
//! trajectory from its commanded state (the axis's own planner: `Axis::handwheel_target`),
//! within its jog limits (`jog_max_vel`, `jog_accel`, `jog_jerk`), replanned on the ticks the
//! target changes; the override does not scale it. PLCopen state: SynchronizedMotion (the axis
//! is coupled to an external master, as a geared slave of an auxiliary encoder is).
//!
//! **No backlog.** The target is never further from the commanded position than
//! [`Handwheel::reach`]: the stop distance from `jog_max_vel` at `jog_accel` and `jog_jerk`, plus
//! one servo period at `jog_max_vel`. That is room enough to run at `jog_max_vel` (each plan
//! cruises a tick, then could stop at the target), and what the wheel turns beyond it is dropped
//! (the anchor moves to the clamped target): once the wheel stops, the axis comes to rest at the
//! target, at most `reach` from where its commanded position was. Turning back acts at once.
//!
//! **Soft limits.** Once the axis is homed with soft limits on, the wheel cannot move the target
//! further beyond a soft limit (the turns beyond are dropped): the axis stops at the limit
//! without a trip, and turning back moves it off at once.
//!
//! **Selecting.** From Standstill, or Aborting a move or velocity mode (the target starts where
//! the axis's jog ramp stops it), or on the axis's own handwheel (a new input, ratio or detent,
//! anchored at the target it has; the motion and its seq go on). An input drives one axis: taking
//! it for another hands it over, the first axis going on to its target as a DiscreteMotion (its
//! motion done with its handwheel's seq). `MC_OP_HANDWHEEL_OFF` does the same on its axis. A
//! halt, stop, power off or safety stop ends the axis's motion, and with it the handwheel (the
//! step finds the axis's motion is no longer the handwheel's).
//!
//! No allocation, no panic, no clock; time is the tick count.
#![forbid(unsafe_code)]

use crate::firmware::axis::Axis;
use crate::firmware::nack::{check_ranges, plan_nack};
use crate::firmware::Firmware;
use crate::motion::scurve::{plan_stop, Limits};
use firmware_proto::{cmd, AxisSafetyFlags, AxisState, Mem, NackCode, AUX_ENCODERS, MAX_AXES};

/// One axis's handwheel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Handwheel {
    /// The `MC_OP_HANDWHEEL` that started the motion (its seq is the axis's motion's).
    seq: u32,
    /// The auxiliary encoder input.
    input: usize,
    /// Axis counts per detent (signed).
    ratio: i64,
    /// Auxiliary counts per detent.
    detent: i64,
    /// The anchor: the input's count ...
    anchor_count: i64,
    /// ... and the target there, counts.
    anchor_pos: f64,
    /// The target the axis runs to, counts.
    target: f64,
    /// The jog limits.
    lim: Limits,
    /// The furthest the target may be from the commanded position, counts.
    reach: f64,
}

impl Handwheel {
    /// The auxiliary encoder input.
    pub fn input(&self) -> usize {
        self.input
    }

    /// The target the axis runs to, counts.
    pub fn target(&self) -> f64 {
        self.target
    }

    /// The furthest the target may be from the commanded position: the stop distance from
    /// `jog_max_vel` plus one servo period at it, counts.
    pub fn reach(&self) -> f64 {
        self.reach
    }

    /// Does it still drive `axis` (the axis's motion is still this handwheel's)?
    pub fn drives(&self, axis: &Axis) -> bool {
        axis.state == AxisState::SynchronizedMotion && axis.pending_motion() == Some(self.seq)
    }

    /// Where the target of a count `m` lies, before any clamp.
    fn wheel_target(&self, m: i64) -> f64 {
        let turned = i128::from(m.wrapping_sub(self.anchor_count)) * i128::from(self.ratio);
        self.anchor_pos + turned as f64 / self.detent as f64
    }

    /// One tick: the input's count `m`; the axis is replanned when the target moves.
    fn step(&mut self, axis: &mut Axis, m: i64, rate_hz: u32) {
        let wheel = self.wheel_target(m);
        if wheel == self.target {
            return;
        }
        let p = axis.reference().pos;
        let (mut lo, mut hi) = (p - self.reach, p + self.reach);
        let c = &axis.safety.config;
        if c.has(AxisSafetyFlags::SOFT_LIMITS) && axis.homed() {
            // Never further beyond a soft limit than the target already is.
            hi = hi.min(c.soft_limit_pos.max(self.target));
            lo = lo.max(c.soft_limit_neg.min(self.target));
        }
        let mut t = if lo <= hi {
            wheel.clamp(lo, hi)
        } else {
            self.target
        };
        if t != wheel {
            // The turn beyond the reach (or the soft limit) is dropped.
            self.anchor_count = m;
            self.anchor_pos = t;
        }
        if t != self.target && axis.handwheel_target(t, &self.lim, rate_hz).is_err() {
            // Cannot be planned from here (it always can from a verified state): the turn is
            // dropped, the axis goes on to the target it has.
            t = self.target;
            self.anchor_count = m;
            self.anchor_pos = t;
        }
        self.target = t;
    }
}

/// The jog limits of `axis`, and the handwheel's reach with them at `rate_hz`.
fn limits(axis: &Axis, rate_hz: u32) -> Result<(Limits, f64), NackCode> {
    let c = &axis.config;
    let lim = Limits::symmetric(c.jog_max_vel, c.jog_accel, c.jog_jerk);
    check_ranges(rate_hz, &[(1, lim.vmax), (2, lim.amax), (3, lim.j1)])?;
    let stop = plan_stop(0.0, lim.vmax, 0.0, lim.amax, lim.j1).map_err(plan_nack)?;
    Ok((lim, stop.end_pos() + lim.vmax / f64::from(rate_hz)))
}

// ---- The command manager's and the control loop's side ----
impl<M: Mem + Clone> Firmware<M> {
    /// One axis's handwheel, while it drives the axis (for inspection by tests).
    pub fn handwheel(&self, i: usize) -> Option<&Handwheel> {
        let hw = self.handwheels[..self.num_axes].get(i)?.as_ref()?;
        hw.drives(&self.axes[i]).then_some(hw)
    }

    /// Is axis `i` driven by its handwheel?
    pub(super) fn handwheel_drives(&self, i: usize) -> bool {
        self.handwheels[i]
            .as_ref()
            .is_some_and(|h| h.drives(&self.axes[i]))
    }

    /// `MC_OP_HANDWHEEL` (command `seq`, decoded: `h`) on axis `ax` (one of the card's, not in an
    /// enabled group, past the safety layer's check): the axis's old state, whether it took the
    /// axis over (Aborting), and the axis it handed the input over from with that one's old
    /// state.
    pub(super) fn start_handwheel(
        &mut self,
        seq: u32,
        ax: usize,
        h: &cmd::Handwheel,
    ) -> Result<HandwheelStart, NackCode> {
        let rate = self.servo_rate_hz;
        let input = usize::from(h.input);
        if input >= AUX_ENCODERS {
            return Err(NackCode::HandwheelInput);
        }
        let own = self
            .handwheel_drives(ax)
            .then_some(self.handwheels[ax])
            .flatten();
        let axis = &mut self.axes[ax];
        match axis.state {
            AxisState::Standstill | AxisState::DiscreteMotion | AxisState::ContinuousMotion => {}
            AxisState::SynchronizedMotion if own.is_some() => {}
            AxisState::Disabled => return Err(NackCode::AxisDisabled),
            AxisState::Homing => return Err(NackCode::AxisHoming),
            _ => return Err(NackCode::InvalidState),
        }
        let (lim, reach) = limits(axis, rate)?;
        let m = self.aux.count[input];
        let (changed, takes_over, hw) = match own {
            // A new input, ratio or detent: anchored at the target it has, the motion goes on.
            Some(old) => (
                None,
                false,
                Handwheel {
                    input,
                    ratio: i64::from(h.ratio),
                    detent: i64::from(h.detent),
                    anchor_count: m,
                    anchor_pos: old.target,
                    lim,
                    reach,
                    ..old
                },
            ),
            None => {
                // From rest where it stands; from motion where the jog ramp stops it.
                let r = axis.reference();
                let target = if r.vel == 0.0 && r.acc == 0.0 {
                    r.pos
                } else {
                    plan_stop(r.pos, r.vel, r.acc, lim.amax, lim.j1)
                        .map_err(plan_nack)?
                        .end_pos()
                };
                let changed = axis.begin_handwheel(seq, target, &lim, rate)?;
                let hw = Handwheel {
                    seq,
                    input,
                    ratio: i64::from(h.ratio),
                    detent: i64::from(h.detent),
                    anchor_count: m,
                    anchor_pos: target,
                    target,
                    lim,
                    reach,
                };
                (changed, true, hw)
            }
        };
        self.handwheels[ax] = Some(hw);
        // The input drives one axis: another that has it goes on to its target.
        let mut handed = None;
        for b in 0..self.num_axes {
            if b != ax
                && self.handwheels[b].is_some_and(|o| o.input == input)
                && self.handwheel_drives(b)
            {
                handed = Some((b, self.axes[b].end_handwheel()));
                self.handwheels[b] = None;
            }
        }
        Ok(HandwheelStart {
            seq: hw.seq,
            changed,
            takes_over,
            handed,
        })
    }

    /// `MC_OP_HANDWHEEL_OFF` on axis `ax`: the axis goes on to the wheel's last target as a
    /// DiscreteMotion. Its old state.
    pub(super) fn stop_handwheel(&mut self, ax: usize) -> Result<Option<AxisState>, NackCode> {
        if !self.handwheel_drives(ax) {
            return Err(NackCode::InvalidState);
        }
        self.handwheels[ax] = None;
        Ok(self.axes[ax].end_handwheel())
    }

    /// The handwheels' step of a tick (after the gearing step sensed the auxiliary encoders,
    /// before homing and the servo loops). Nothing but a look at each axis's slot when none is
    /// selected.
    pub(super) fn handwheel_tick(&mut self) {
        if self.handwheels[..self.num_axes].iter().all(Option::is_none) {
            return;
        }
        self.handwheel_step();
    }

    #[inline(never)]
    fn handwheel_step(&mut self) {
        let rate = self.servo_rate_hz;
        for i in 0..self.num_axes {
            let Some(hw) = self.handwheels[i].as_mut() else {
                continue;
            };
            let axis = &mut self.axes[i];
            if !hw.drives(axis) {
                // A halt, stop, power off, safety stop (or a command that took the axis after
                // one) ended it; each reported its own end.
                self.handwheels[i] = None;
                continue;
            }
            let m = self.aux.count[hw.input];
            hw.step(axis, m, rate);
        }
    }
}

/// What `MC_OP_HANDWHEEL` did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct HandwheelStart {
    /// The seq of the handwheel's motion (this command's, or a reselection's first one's).
    pub seq: u32,
    /// The axis's old state, if it changed.
    pub changed: Option<AxisState>,
    /// It took the axis over (PLCopen Aborting: the motion in progress is aborted).
    pub takes_over: bool,
    /// The axis the input was handed over from, and its old state if it changed.
    pub handed: Option<(usize, Option<AxisState>)>,
}

/// The slots of every axis (none selected at boot).
pub(super) type Handwheels = [Option<Handwheel>; MAX_AXES];

#[cfg(test)]
mod tests {
    use super::*;

    fn wheel(ratio: i64, detent: i64) -> Handwheel {
        Handwheel {
            seq: 1,
            input: 0,
            ratio,
            detent,
            anchor_count: 1_000,
            anchor_pos: 50.0,
            target: 50.0,
            lim: Limits::symmetric(1e4, 1e5, 1e7),
            reach: 1e3,
        }
    }

    #[test]
    fn the_target_is_exact_and_does_not_drift() {
        let hw = wheel(10, 4);
        assert_eq!(hw.wheel_target(1_004), 60.0);
        assert_eq!(hw.wheel_target(996), 40.0);
        // A third of a count a step, forth and back over 10^9 counts: the same number.
        let hw = wheel(1, 3);
        assert_eq!(hw.wheel_target(1_000 + 3_000_000_000), 50.0 + 1e9);
        assert_eq!(hw.wheel_target(1_000), 50.0);
        assert_eq!(wheel(-100, 4).wheel_target(1_008), -150.0);
    }

    #[test]
    fn the_reach_is_the_stop_distance_from_the_jog_velocity_and_a_tick() {
        let mut a = Axis::new();
        a.config.block.jog_max_vel = 10_000.0;
        a.config.block.jog_accel = 100_000.0;
        a.config.block.jog_jerk = 1e7;
        let (_, reach) = limits(&a, 10_000).unwrap();
        // v·(v/a + a/j)/2 with v ≥ a²/j: 10^4·(0.1 + 0.01)/2 = 550, and 1 count a tick.
        assert!((reach - 551.0).abs() < 1e-6, "{reach}");
    }
}

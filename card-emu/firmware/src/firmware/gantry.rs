//! Gantry axes (layout 1.10): a master and its slaves, each with its own servo loop and drive,
//! moving as one logical axis. One [`Gantry`] per formed gantry, stepped by `Firmware::tick`
//! after homing and before the servo loops (`gantry_tick`), and once more after the safety
//! layer (`gantry_trips`).
//!
//! **Following.** Every tick each slave's reference is the master's commanded reference of the
//! same tick plus the slave's offset in force (`hold`) on the position and the yaw loop's
//! correction `c` on the acceleration:
//!
//! ```text
//! e = (slave actual − master actual) − hold                 skew, counts (this tick's sensing)
//! moving:  I ← I + ki·(e − clamp(e, ±1))·Ts;   c = −(kp·e + I)
//! at rest: I = 0;                              c = −kp·(e − clamp(e, ±1))
//! |I|, |c| ≤ the slave's stop deceleration
//! slave reference = (m.pos + hold, m.vel, m.acc + c)        m: the master's reference
//! ```
//!
//! The master's reference is taken before the slaves' servo loops run (the master's
//! `Axis::reference_into` runs early, as gearing's commanded masters do), so a slave follows
//! the master's reference of the same tick, whoever set it: its own trajectory, a group or a
//! path (the group's step ran before), a coupling or a stream. Why the acceleration: the servo
//! law turns it into drive output at once (its acceleration feed-forward), so the correction is
//! a force on the slave that needs no position error of its own to act; a correction on the
//! position passes through the slave's position loop, whose own lag is what makes the skew
//! (on the plant's default motors, a slave 30 % heavier skews 23 counts on a 5·10⁶ counts/s²
//! S-curve without the yaw loop; kp, ki on the position reference got it to 15, on the
//! acceleration to 2). The skew is the difference of two encoders: at a speed it dithers by a
//! count, so the integral takes only what is beyond a count (else it winds up against the
//! slave's own servo integrator), and at rest nothing within a count is corrected. `kp` in
//! 1/s² (`[0, 10⁹]`), `ki` in 1/s³ (`[0, 10¹²]`).
//!
//! **Within a count** (issue 35 part 1). The encoders see the skew in whole counts; what they
//! cannot see is where each shaft runs within its count. Every member's FFPIV loop reads its
//! count at its middle while its reference moves (from the formation to the dissolution, not in
//! a stop: `Ffpiv::set_mid_count`), which holds each shaft on the count edge nearest its
//! reference, so two sides on the same reference run on the same edge (without it, at 10⁶
//! counts/s, 100 counts a tick, each shaft wanders within its count and the encoders'
//! difference reads 2 whenever the shafts part by just over one). The rest is the drives'
//! own tuning: a slave whose load differs is tuned for it (its FFPIV's `kv` and `kaff` times
//! the load ratio, which a frequency sweep of each side measures), and the yaw loop corrects
//! what the tuning leaves (`tests/gantry.rs`: within a count tuned, 2 counts untuned).
//!
//! `hold` is the skew the slave had when it was coupled (forming, or re-coupling after a power
//! cycle or a reset: no slave ever jumps), and the square offset once `MC_OP_GANTRY_HOME`
//! squared the bridge. A re-coupling that moves `hold` by more than a count clears `squared`.
//!
//! **Stopping together.** |e| beyond the skew limit while coupled stops every member with a
//! category 1 stop, reason `GantrySkew`; a safety stop of any member (a following error, an
//! alarm, a limit…) stops the others with the same category, reason `Gantry`. While the master
//! has power a slave in ErrorStop keeps following the master's stop ramp, so the bridge stops
//! square; each member's own stop bound (`Safety::bound_stop`) still holds. Both post
//! `MC_EV_GANTRY_FAULT` naming the gantry.
//!
//! **Homing.** `MC_OP_GANTRY_HOME` suspends the coupling and runs each member's own homing
//! method (`homing.rs`, home position 0), then moves each slave to `master + offset` within
//! its homing block's search velocity and acceleration, couples them with `hold = offset` and
//! posts `MC_EV_GANTRY_HOMED`. A side that fails or is stopped ends it for all: the others
//! are halted and the gantry couples where they stand.
//!
//! No allocation, no panic, no clock; time is the tick count.
#![forbid(unsafe_code)]

use crate::firmware::axis::{MoveKind, TickReport};
use crate::firmware::homing::HomingReport;
use crate::firmware::Firmware;
use crate::motion::scurve::Limits;
use crate::servo::ffpiv::Reference;
use firmware_proto::cmd::{AxisCmd, GantryForm, GANTRY_KI_MAX, GANTRY_KP_MAX, GANTRY_MAX_SLAVES};
use firmware_proto::{
    layout, raw, AxisState, Event, EventKind, Mem, NackCode, StopCategory, StopReason, MAX_AXES,
    MAX_POSITION,
};
use heapless::Vec;

pub use firmware_proto::cmd::MAX_GANTRIES;

/// `MC_EV_GANTRY_HOMED`'s code when a halt, stop, power off or safety stop ended a side's
/// homing (not one of the `MC_HOMING_ERR_*`).
pub const HOMING_ABORTED: i32 = -1;

/// One slave and its yaw loop.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Side {
    /// The slave axis.
    pub axis: usize,
    /// The square offset (slave − master when square), counts.
    pub offset: f64,
    /// The offset in force, counts.
    pub hold: f64,
    /// The yaw loop's integral, counts.
    integ: f64,
    /// This tick's skew, counts.
    pub skew: f64,
    /// This tick's correction, counts/s².
    pub correction: f64,
    /// The largest |skew| while coupled, counts.
    pub max_skew: f64,
}

/// What the gantry is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// The slaves follow the master.
    Coupled,
    /// `MC_OP_GANTRY_HOME` (command `seq`): each member homes on its own; `done`: bit k for
    /// member k (0: the master, 1..: the slaves) homed.
    Homing { seq: u32, done: u8 },
    /// The slaves move to their square offsets.
    Squaring { seq: u32 },
}

/// A formed gantry.
#[derive(Debug, Clone, PartialEq)]
pub struct Gantry {
    /// The master axis.
    pub master: usize,
    /// The slaves.
    pub slaves: Vec<Side, GANTRY_MAX_SLAVES>,
    /// Proportional gain of the yaw loop, 1/s².
    pub kp: f64,
    /// Integral gain of the yaw loop, 1/s³.
    pub ki: f64,
    /// The skew beyond which the gantry stops, counts.
    pub skew_limit: f64,
    /// What it is doing.
    pub phase: Phase,
    /// Squared by `MC_OP_GANTRY_HOME` (and not uncoupled since by more than a count).
    pub squared: bool,
}

impl Gantry {
    /// Is `a` one of its members?
    pub fn has(&self, a: usize) -> bool {
        self.master == a || self.slaves.iter().any(|s| s.axis == a)
    }

    /// Is `a` one of its slaves?
    pub fn has_slave(&self, a: usize) -> bool {
        self.slaves.iter().any(|s| s.axis == a)
    }

    /// The members, master first.
    pub fn members(&self) -> Vec<usize, { GANTRY_MAX_SLAVES + 1 }> {
        let mut m = Vec::new();
        let _ = m.push(self.master);
        for s in &self.slaves {
            let _ = m.push(s.axis);
        }
        m
    }

    /// The status block.
    pub fn status(&self) -> raw::mc_gantry_status {
        let mut b = raw::mc_gantry_status {
            phase: match self.phase {
                Phase::Coupled => raw::MC_GANTRY_COUPLED,
                Phase::Homing { .. } => raw::MC_GANTRY_HOMING,
                Phase::Squaring { .. } => raw::MC_GANTRY_SQUARING,
            },
            master: self.master as u32,
            nslaves: self.slaves.len() as u32,
            squared: u32::from(self.squared),
            kp: self.kp,
            ki: self.ki,
            skew_limit: self.skew_limit,
            ..Default::default()
        };
        for (k, s) in self.slaves.iter().enumerate() {
            b.slave[k] = s.axis as u32;
            b.offset[k] = s.offset;
            b.hold[k] = s.hold;
            b.skew[k] = s.skew;
            b.correction[k] = s.correction;
            b.max_skew[k] = s.max_skew;
        }
        b
    }

    /// The yaw loop of one tick for slave `k` with skew `e` (the slave follows; `moving`: the
    /// master's reference moves): its correction, counts/s², within `amax`.
    fn yaw(&mut self, k: usize, e: f64, moving: bool, ts: f64, amax: f64) -> f64 {
        let (kp, ki) = (self.kp, self.ki);
        let s = &mut self.slaves[k];
        if !moving {
            // At rest the skew is the encoders' resolution: within a count nothing is
            // corrected (no hunting between two counts), and the integral is let go.
            s.integ = 0.0;
            s.correction = if e.abs() <= 1.0 {
                0.0
            } else {
                (-kp * (e - e.signum())).clamp(-amax, amax)
            };
            return s.correction;
        }
        // The integral takes only what is beyond the encoders' resolution: two shafts at a
        // speed read a skew that dithers by a count, which would otherwise wind it up against
        // the slave's own servo integrator.
        let beyond = e - e.clamp(-1.0, 1.0);
        s.integ = (s.integ + ki * beyond * ts).clamp(-amax, amax);
        s.correction = (-(kp * e + s.integ)).clamp(-amax, amax);
        s.correction
    }
}

/// The numbers of a formation, checked: non-finite `NotFinite`; out of range `GantryGains`.
pub fn check_gains(f: &GantryForm) -> Result<(), NackCode> {
    let offsets = f.slaves.iter().map(|s| s.offset);
    if ![f.kp, f.ki, f.skew_limit]
        .into_iter()
        .chain(offsets.clone())
        .all(f64::is_finite)
    {
        return Err(NackCode::NotFinite);
    }
    let ok = (0.0..GANTRY_KP_MAX).contains(&f.kp)
        && (0.0..=GANTRY_KI_MAX).contains(&f.ki)
        && f.skew_limit > 0.0
        && f.skew_limit <= MAX_POSITION
        && offsets.into_iter().all(|o| o.abs() <= MAX_POSITION);
    if ok {
        Ok(())
    } else {
        Err(NackCode::GantryGains)
    }
}

/// The skew of slave `a` (the scope's `MC_SIG_GANTRY_SKEW`); 0 for an axis that is no slave.
pub fn skew_of(gantries: &[Option<Gantry>], a: usize) -> f64 {
    gantries
        .iter()
        .flatten()
        .flat_map(|g| g.slaves.iter())
        .find(|s| s.axis == a)
        .map_or(0.0, |s| s.skew)
}

/// The slaves' references of a tick: `Some` for each slave its gantry drives now.
pub type Follow = [Option<Reference>; MAX_AXES];

impl<M: Mem + Clone> Firmware<M> {
    /// One gantry (for inspection by tests).
    pub fn gantry(&self, g: usize) -> Option<&Gantry> {
        self.gantries.get(g).and_then(Option::as_ref)
    }

    /// The gantry `a` is a slave of.
    pub(crate) fn gantry_of_slave(&self, a: usize) -> Option<usize> {
        self.gantries
            .iter()
            .position(|g| g.as_ref().is_some_and(|g| g.has_slave(a)))
    }

    /// The gantry `a` is the master of.
    pub(crate) fn gantry_of_master(&self, a: usize) -> Option<usize> {
        self.gantries
            .iter()
            .position(|g| g.as_ref().is_some_and(|g| g.master == a))
    }

    /// `MC_OP_GANTRY_FORM` of gantry `g` (checked in the card's order: see the header).
    pub(super) fn gantry_form(&mut self, g: usize, f: &GantryForm) -> Result<f64, NackCode> {
        let n = self.num_axes;
        let master = usize::from(f.master);
        let mut members: Vec<usize, { GANTRY_MAX_SLAVES + 1 }> = Vec::new();
        let _ = members.push(master);
        for s in &f.slaves {
            let a = usize::from(s.axis);
            if members.contains(&a) {
                return Err(NackCode::GantryAxes);
            }
            let _ = members.push(a);
        }
        if members.iter().any(|&a| a >= n) {
            return Err(NackCode::GantryAxes);
        }
        check_gains(f)?;
        if self.gantries[g].is_some() {
            return Err(NackCode::GantryState);
        }
        for &a in &members {
            let in_gantry = self.gantries.iter().flatten().any(|o| o.has(a));
            let coupled =
                self.gears[a].engaged() || self.pvt[a].as_ref().is_some_and(|s| s.running());
            let slave_grouped = a != master && self.groups.iter().any(|gr| gr.contains(a));
            if in_gantry || coupled || slave_grouped {
                return Err(NackCode::GantryInUse);
            }
        }
        let state = self.axes[master].state;
        let at_rest = matches!(state, AxisState::Standstill | AxisState::Disabled)
            && members.iter().all(|&a| {
                self.axes[a].state == state
                    && !self.axes[a].busy_with_motion()
                    && !self.homing[a].active()
            });
        if !at_rest {
            return Err(NackCode::GantryState);
        }
        let m = self.axes[master].reference().pos;
        let mut slaves = Vec::new();
        for s in &f.slaves {
            let a = usize::from(s.axis);
            let hold = self.axes[a].reference().pos - m;
            let _ = slaves.push(Side {
                axis: a,
                offset: s.offset,
                hold,
                ..Side::default()
            });
        }
        let gantry = Gantry {
            master,
            slaves,
            kp: f.kp,
            ki: f.ki,
            skew_limit: f.skew_limit,
            phase: Phase::Coupled,
            squared: false,
        };
        let tick = self.tick;
        if state == AxisState::Standstill {
            for s in &gantry.slaves {
                if let Ok(Some(old)) = self.axes[s.axis].begin_sync(0) {
                    self.outbox.push(super::state_event(
                        s.axis as u16,
                        old,
                        self.axes[s.axis].state,
                        tick,
                    ));
                }
            }
        }
        for &a in &members {
            self.axes[a].set_mid_count(true);
        }
        self.gantries[g] = Some(gantry);
        Ok(0.0)
    }

    /// `MC_OP_GANTRY_DISSOLVE` of gantry `g`: the master at rest; the slaves hold.
    pub(super) fn gantry_dissolve(&mut self, g: usize) -> Result<f64, NackCode> {
        let Some(gantry) = &self.gantries[g] else {
            return Err(NackCode::GantryState);
        };
        let m = &self.axes[gantry.master];
        let at_rest = gantry.phase == Phase::Coupled
            && match m.state {
                AxisState::Standstill | AxisState::Disabled => !m.busy_with_motion(),
                AxisState::ErrorStop => !m.profile_running(),
                _ => false,
            };
        if !at_rest {
            return Err(NackCode::GantryState);
        }
        let tick = self.tick;
        self.axes[gantry.master].set_mid_count(false);
        for s in gantry.slaves.clone() {
            self.axes[s.axis].set_mid_count(false);
            let axis = &mut self.axes[s.axis];
            if let Some(old) = axis.release_from_gantry() {
                self.outbox
                    .push(super::state_event(s.axis as u16, old, axis.state, tick));
            }
        }
        self.gantries[g] = None;
        self.gantry_dirty |= 1 << g;
        Ok(0.0)
    }

    /// Can `gantry` start homing: coupled, the master at rest in Standstill, the slaves
    /// following?
    pub(super) fn gantry_ready(&self, gantry: &Gantry) -> bool {
        gantry.phase == Phase::Coupled
            && gantry.members().iter().enumerate().all(|(k, &a)| {
                let st = self.axes[a].state;
                if k == 0 {
                    st == AxisState::Standstill && !self.axes[a].busy_with_motion()
                } else {
                    st == AxisState::SynchronizedMotion
                }
            })
    }

    /// `MC_OP_GANTRY_HOME` (command `seq`) of gantry `g`: every member starts its own homing.
    pub(super) fn gantry_home(&mut self, g: usize, seq: u32) -> Result<f64, NackCode> {
        self.gantry_home_from(g, seq, false)
    }

    /// Gantry homing, from `MC_OP_GANTRY_HOME` or (`grouped`: layout 1.11) a group homing
    /// that has the master as a member (a gantry in an enabled group homes only so).
    pub(super) fn gantry_home_from(
        &mut self,
        g: usize,
        seq: u32,
        grouped: bool,
    ) -> Result<f64, NackCode> {
        let Some(gantry) = &self.gantries[g] else {
            return Err(NackCode::GantryState);
        };
        let members = gantry.members();
        let ready = self.gantry_ready(gantry)
            && (grouped || self.groups.iter().all(|gr| !gr.owns_enabled(members[0])));
        if !ready {
            return Err(NackCode::GantryState);
        }
        let rate = self.servo_rate_hz;
        // Every side's homing is checked before any starts.
        for &a in &members {
            self.homing[a].check(&self.axes[a], 0.0, rate)?;
        }
        let tick = self.tick;
        for &a in &members {
            let axis = &mut self.axes[a];
            if a != members[0] {
                axis.release_from_gantry();
            }
            let old = axis.state;
            self.homing[a].start(axis, seq, 0.0, rate)?;
            if old != axis.state {
                self.outbox
                    .push(super::state_event(a as u16, old, axis.state, tick));
            }
        }
        if let Some(gantry) = &mut self.gantries[g] {
            gantry.phase = Phase::Homing { seq, done: 0 };
            gantry.squared = false;
        }
        Ok(0.0)
    }

    /// The gantries' step of a tick, after homing and before the servo loops: the homing
    /// phases, re-coupling, the skews, the skew limit, and each following slave's reference
    /// (its master's taken early into `early`). `None`: no gantry is formed.
    pub(super) fn gantry_tick(
        &mut self,
        ts: f64,
        early: &mut [Option<(bool, TickReport)>; MAX_AXES],
        homed: &Option<[HomingReport; MAX_AXES]>,
        dac: &mut [f64; MAX_AXES],
    ) -> Option<Follow> {
        if self.gantries.iter().all(Option::is_none) {
            return None;
        }
        Some(self.gantry_step(ts, early, homed, dac))
    }

    #[inline(never)]
    fn gantry_step(
        &mut self,
        ts: f64,
        early: &mut [Option<(bool, TickReport)>; MAX_AXES],
        homed: &Option<[HomingReport; MAX_AXES]>,
        dac: &mut [f64; MAX_AXES],
    ) -> Follow {
        let mut follow: Follow = [None; MAX_AXES];
        for g in 0..MAX_GANTRIES {
            let Some(mut gantry) = self.gantries[g].take() else {
                continue;
            };
            match gantry.phase {
                Phase::Homing { seq, done } => self.gantry_homing(g, &mut gantry, seq, done, homed),
                Phase::Squaring { seq } => self.gantry_squaring(g, &mut gantry, seq),
                Phase::Coupled => {}
            }
            if gantry.phase == Phase::Coupled {
                self.gantry_follow(g, &mut gantry, ts, early, &mut follow, dac);
            }
            self.gantries[g] = Some(gantry);
        }
        follow
    }

    /// A coupled gantry's tick.
    fn gantry_follow(
        &mut self,
        g: usize,
        gantry: &mut Gantry,
        ts: f64,
        early: &mut [Option<(bool, TickReport)>; MAX_AXES],
        follow: &mut Follow,
        dac: &mut [f64; MAX_AXES],
    ) {
        let tick = self.tick;
        let mi = gantry.master;
        let m_powered = self.axes[mi].is_powered();
        // A slave at rest in Standstill (a power on, a reset, the end of squaring) is coupled
        // again where it stands.
        if m_powered && self.axes[mi].state != AxisState::ErrorStop {
            let m = self.axes[mi].reference().pos;
            for s in gantry.slaves.iter_mut() {
                let axis = &mut self.axes[s.axis];
                if axis.state != AxisState::Standstill {
                    continue;
                }
                let hold = axis.reference().pos - m;
                if (hold - s.hold).abs() > 1.0 {
                    gantry.squared = false;
                }
                s.hold = hold;
                s.integ = 0.0;
                if let Ok(Some(old)) = axis.begin_sync(0) {
                    self.outbox
                        .push(super::state_event(s.axis as u16, old, axis.state, tick));
                }
            }
        }
        // The skews of this tick's sensing.
        let m_act = self.axes[mi].actual().0;
        let mut beyond = None;
        let mut any_follows = false;
        for s in gantry.slaves.iter_mut() {
            let axis = &self.axes[s.axis];
            s.skew = axis.actual().0 - m_act - s.hold;
            let follows = m_powered
                && axis.is_powered()
                && matches!(
                    axis.state,
                    AxisState::SynchronizedMotion | AxisState::ErrorStop
                );
            any_follows |= follows;
            if axis.state == AxisState::SynchronizedMotion {
                s.max_skew = s.max_skew.max(s.skew.abs());
                if s.skew.abs() > gantry.skew_limit && beyond.is_none() {
                    beyond = Some(s.skew);
                }
            }
        }
        if let Some(e) = beyond {
            // [safety] the bridge racks: every member stops, together.
            let members = gantry.members();
            self.safety.trip_gantry(
                &self.mem,
                tick,
                &mut self.axes[..self.num_axes],
                &members,
                StopCategory::Cat1,
                StopReason::GantrySkew,
                e,
                dac,
            );
            self.post_gantry_fault(g, StopReason::GantrySkew, e);
        }
        if !any_follows {
            for s in gantry.slaves.iter_mut() {
                s.integ = 0.0;
                s.correction = 0.0;
            }
            return;
        }
        // The master's reference of this tick, before the slaves follow it.
        let powered = match &early[mi] {
            Some((p, _)) => *p,
            None => {
                let mut r = TickReport::default();
                let p = self.axes[mi].reference_into(ts, &mut r);
                early[mi] = Some((p, r));
                p
            }
        };
        if !powered {
            return;
        }
        let m = self.axes[mi].reference();
        for k in 0..gantry.slaves.len() {
            let s = gantry.slaves[k];
            let axis = &self.axes[s.axis];
            let follows = axis.is_powered()
                && matches!(
                    axis.state,
                    AxisState::SynchronizedMotion | AxisState::ErrorStop
                );
            if !follows {
                gantry.slaves[k].integ = 0.0;
                gantry.slaves[k].correction = 0.0;
                continue;
            }
            let amax = axis.safety.config.stop_decel;
            let moving = m.vel != 0.0 || m.acc != 0.0;
            let c = gantry.yaw(k, s.skew, moving, ts, amax);
            follow[s.axis] = Some(Reference {
                pos: m.pos + s.hold,
                vel: m.vel,
                acc: m.acc + c,
            });
        }
    }

    /// Gantry homing: each side homes on its own.
    fn gantry_homing(
        &mut self,
        g: usize,
        gantry: &mut Gantry,
        seq: u32,
        mut done: u8,
        homed: &Option<[HomingReport; MAX_AXES]>,
    ) {
        let members = gantry.members();
        let mut failed = None;
        for (k, &a) in members.iter().enumerate() {
            if done & (1 << k) != 0 {
                continue;
            }
            let report = homed.as_ref().map(|h| &h[a]);
            if let Some((_, why, _)) = report.and_then(|r| r.failed) {
                failed.get_or_insert((why as i32, a));
            } else if report.is_some_and(|r| r.done.is_some()) {
                done |= 1 << k;
            } else if self.axes[a].state != AxisState::Homing {
                // A halt, stop, power off or safety stop ended it.
                failed.get_or_insert((HOMING_ABORTED, a));
            }
        }
        if let Some((code, a)) = failed {
            // Every side still homing halts; the gantry couples where they stop.
            let max_time = self.safety.config().max_stop_time();
            let tick = self.tick;
            for &b in &members {
                let axis = &mut self.axes[b];
                if axis.state == AxisState::Homing {
                    let c = axis.safety.config;
                    if let Ok(Some(old)) =
                        axis.start_stop(seq, false, c.stop_decel, c.stop_jerk, max_time)
                    {
                        self.outbox
                            .push(super::state_event(b as u16, old, axis.state, tick));
                    }
                }
            }
            gantry.phase = Phase::Coupled;
            self.post_gantry_event(EventKind::GantryHomed, seq, g, code, a as f64);
            return;
        }
        if usize::from(done.count_ones() as u8) < members.len() {
            gantry.phase = Phase::Homing { seq, done };
            return;
        }
        // Every side is homed: each slave moves to master + offset.
        let rate = self.servo_rate_hz;
        let m = self.axes[gantry.master].reference().pos;
        let tick = self.tick;
        for s in &gantry.slaves {
            let b = self.homing[s.axis].config().block;
            let lim = Limits::symmetric(b.search_vel, b.accel, b.jerk);
            let axis = &mut self.axes[s.axis];
            match axis.start_move(seq, MoveKind::Absolute, m + s.offset, &lim, false, rate) {
                Ok((Some(old), _)) => {
                    self.outbox
                        .push(super::state_event(s.axis as u16, old, axis.state, tick))
                }
                Ok((None, _)) => {}
                Err(_) => {
                    gantry.phase = Phase::Coupled;
                    self.post_gantry_event(
                        EventKind::GantryHomed,
                        seq,
                        g,
                        firmware_proto::HomingError::Plan as i32,
                        s.axis as f64,
                    );
                    return;
                }
            }
        }
        gantry.phase = Phase::Squaring { seq };
    }

    /// Gantry homing: the slaves square the bridge.
    fn gantry_squaring(&mut self, g: usize, gantry: &mut Gantry, seq: u32) {
        let mut all_done = true;
        for s in &gantry.slaves {
            match self.axes[s.axis].state {
                AxisState::Standstill => {}
                AxisState::DiscreteMotion => all_done = false,
                _ => {
                    gantry.phase = Phase::Coupled;
                    self.post_gantry_event(
                        EventKind::GantryHomed,
                        seq,
                        g,
                        HOMING_ABORTED,
                        s.axis as f64,
                    );
                    return;
                }
            }
        }
        if !all_done {
            return;
        }
        let m = self.axes[gantry.master].reference().pos;
        let m_act = self.axes[gantry.master].actual().0;
        let tick = self.tick;
        for s in gantry.slaves.iter_mut() {
            let axis = &mut self.axes[s.axis];
            s.hold = s.offset;
            s.integ = 0.0;
            s.skew = axis.actual().0 - m_act - s.hold;
            debug_assert!((axis.reference().pos - m - s.offset).abs() < 1e-6);
            if let Ok(Some(old)) = axis.begin_sync(seq) {
                self.outbox
                    .push(super::state_event(s.axis as u16, old, axis.state, tick));
            }
        }
        gantry.phase = Phase::Coupled;
        gantry.squared = true;
        let skew = gantry.slaves.first().map_or(0.0, |s| s.skew);
        self.post_gantry_event(EventKind::GantryHomed, seq, g, 0, skew);
    }

    /// After the safety layer's tick: a member that made a safety stop stops the others (the
    /// harshest category among the stopped members, reason `Gantry`).
    pub(super) fn gantry_trips(&mut self, dac: &mut [f64; MAX_AXES]) {
        if self.gantries.iter().all(Option::is_none) {
            return;
        }
        let tick = self.tick;
        for g in 0..MAX_GANTRIES {
            let Some(gantry) = &self.gantries[g] else {
                continue;
            };
            let members = gantry.members();
            let mut first = None;
            let mut category = None::<StopCategory>;
            let mut running = false;
            for &a in &members {
                let axis = &self.axes[a];
                match (axis.state, axis.safety.stop) {
                    (AxisState::ErrorStop, Some(stop)) => {
                        first.get_or_insert((a, axis.safety.stop_reason));
                        if category.is_none_or(|c| (stop.category as u32) < (c as u32)) {
                            category = Some(stop.category);
                        }
                    }
                    (AxisState::Disabled | AxisState::ErrorStop, _) => {}
                    _ => running = true,
                }
            }
            let (Some((a, reason)), Some(category), true) = (first, category, running) else {
                continue;
            };
            self.safety.trip_gantry(
                &self.mem,
                tick,
                &mut self.axes[..self.num_axes],
                &members,
                category,
                StopReason::Gantry,
                a as f64,
                dac,
            );
            if reason != StopReason::GantrySkew {
                self.post_gantry_fault(g, reason, a as f64);
            }
        }
    }

    fn post_gantry_fault(&mut self, g: usize, reason: StopReason, value: f64) {
        self.post_gantry_event(EventKind::GantryFault, 0, g, reason as i32, value);
    }

    fn post_gantry_event(&mut self, kind: EventKind, seq: u32, g: usize, code: i32, value: f64) {
        if kind == EventKind::GantryHomed {
            // Layout 1.11: a group homing waits for it (group_home.rs).
            self.gantry_homed[g] = Some((code, value));
        }
        self.outbox.push(Event {
            seq,
            kind: kind as u16,
            axis: g as u16,
            code,
            tick: self.tick,
            value,
        });
    }

    /// Publish the formed gantries' status blocks (and a dissolved one's, once).
    pub(super) fn publish_gantries(&mut self) {
        for g in 0..MAX_GANTRIES {
            let b = match &self.gantries[g] {
                Some(gantry) => gantry.status(),
                None if self.gantry_dirty & (1 << g) != 0 => raw::mc_gantry_status::default(),
                None => continue,
            };
            layout::GANTRY_STATUS.at(g).write(&self.mem, &b);
        }
        self.gantry_dirty = 0;
    }

    /// What a command on axis `ax` meets in a gantry (`execute_axis`): a slave refuses it
    /// (`GantrySlave`); the master refuses MC_Home and MC_SetPosition, and motion while the
    /// gantry homes (`GantryState`).
    pub(super) fn gantry_gate(&self, ax: usize, cmd: &AxisCmd) -> Result<(), NackCode> {
        if self.gantry_of_slave(ax).is_some() {
            return Err(NackCode::GantrySlave);
        }
        let Some(g) = self.gantry_of_master(ax) else {
            return Ok(());
        };
        let homing = self.gantries[g]
            .as_ref()
            .is_some_and(|g| g.phase != Phase::Coupled);
        match cmd {
            AxisCmd::Home(_) | AxisCmd::SetPosition(_) => Err(NackCode::GantryState),
            AxisCmd::Halt(_) | AxisCmd::Stop(_) | AxisCmd::PowerOff => Ok(()),
            _ if homing => Err(NackCode::GantryState),
            _ => Ok(()),
        }
    }

    /// MC_Power and MC_Reset of a gantry's master act on its slaves too (after the master's
    /// own checks). Power on: every slave must take it first (its safety check), else that
    /// nack and nothing changes.
    pub(super) fn gantry_slaves_check(&self, ax: usize, cmd: &AxisCmd) -> Result<(), NackCode> {
        let Some(g) = self.gantry_of_master(ax) else {
            return Ok(());
        };
        if let (AxisCmd::PowerOn, Some(gantry)) = (cmd, &self.gantries[g]) {
            for s in &gantry.slaves {
                self.safety.check_command(cmd, &self.axes[s.axis])?;
                if self.axes[s.axis].state == AxisState::ErrorStop {
                    return Err(NackCode::InvalidState);
                }
            }
        }
        Ok(())
    }

    /// The slaves' part of the master's MC_Power or MC_Reset (accepted on the master).
    pub(super) fn gantry_slaves_follow(&mut self, ax: usize, cmd: &AxisCmd) {
        let Some(gantry) = self
            .gantry_of_master(ax)
            .and_then(|g| self.gantries[g].clone())
        else {
            return;
        };
        let tick = self.tick;
        for s in &gantry.slaves {
            let axis = &mut self.axes[s.axis];
            let changed = match cmd {
                AxisCmd::PowerOn => axis.power(true).ok().flatten(),
                AxisCmd::PowerOff => axis.power(false).ok().flatten(),
                AxisCmd::Reset if axis.state == AxisState::ErrorStop => axis.reset().ok().flatten(),
                _ => None,
            };
            if let Some(old) = changed {
                self.outbox
                    .push(super::state_event(s.axis as u16, old, axis.state, tick));
            }
        }
    }
}

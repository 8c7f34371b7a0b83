//! Position compare: the "EQU" outputs of a motion card's encoder interface (layout 1.7).
//!
//! A channel watches one axis's actual position and pulses one digital output when the
//! position crosses a compare position in the channel's direction: a single position (either
//! direction allowed), a linear series `start + k·pitch` (k = 0..count−1, the pitch signed by
//! the direction), or a table streamed in with `MC_OP_COMPARE_TABLE` (a ring of
//! [`COMPARE_TABLE_LEN`] positions, strictly monotonic in the direction).
//!
//! The firing instant is found the way an FPGA comparator on the encoder counter would find
//! it: between the counts at the two ends of the tick, each count `n` taken as the middle of
//! its cell (`n + 0.5`; the shaft is somewhere in `[n, n+1)`), linearly interpolated
//! ([`crossing`]). With the tick's motion nearly linear (the shaft's acceleration over one
//! period moves it `a·T²/8` off the chord: 0.0125 counts at 10⁷ counts/s² and 10 kHz) the
//! instant is within half a count of the crossing, at any speed.
//!
//! Nothing is skipped silently. A position already behind the axis when it becomes the next one
//! (armed behind, queued too late, passed while the loop bound deferred it) is **missed**; so
//! is one whose instant falls inside the pulse before it (the output is still on and cannot
//! make a second pulse), and one the axis crossed and crossed back within one tick (the
//! encoder interface's extreme counts of the tick reach it while neither end does: there is
//! no instant to give it, [`crossed_back`]). Every fire and miss is counted; the firmware posts one
//! `MC_EV_COMPARE` per code, channel and tick (the last position of that tick).
//!
//! Pure logic over plain numbers: no window, no clock, no allocation after [`Compare::new`].

use crate::math;
use crate::ram::FixedVec;
use firmware_proto::cmd::{CompareArm, CompareKind, Direction};
use firmware_proto::{raw, NackCode, COMPARE_TABLE_LEN, MAX_POSITION, OUTPUTS};

/// Positions a channel examines per tick at most (fires and misses); the rest wait for the
/// next tick (and are then missed if the axis passed them: reported, never silent). A pulse
/// is at least 1 µs, so no more than 100 fires fit in a 10 kHz tick.
pub const MAX_PER_TICK: usize = 512;

/// The crossing instant of `p` between the positions `x0` and `x1` at the two ends of a tick,
/// as a fraction of the tick in `(0, 1]`: moving up (`dir > 0`) when `x0 < p <= x1`, down
/// (`dir < 0`) when `x0 > p >= x1`, either way for `dir == 0`.
pub fn crossing(x0: f64, x1: f64, p: f64, dir: i8) -> Option<f64> {
    let up = x0 < p && p <= x1;
    let down = x0 > p && p >= x1;
    let hit = match dir {
        1 => up,
        -1 => down,
        _ => up || down,
    };
    hit.then(|| ((p - x0) / (x1 - x0)).clamp(0.0, 1.0))
}

/// Did the axis cross `p` in `dir` and come back within the tick, seen from the ends `x0`, `x1`
/// (no [`crossing`] between them) and the extremes `lo`, `hi` it reached in between?
pub fn crossed_back(x0: f64, x1: f64, (lo, hi): (f64, f64), p: f64, dir: i8) -> bool {
    let up = x0 < p && x1 < p && hi >= p;
    let down = x0 > p && x1 > p && lo <= p;
    match dir {
        1 => up,
        -1 => down,
        _ => up || down,
    }
}

/// Is `p` behind the position `x` for a channel moving in `dir` (already passed)?
fn behind(x: f64, p: f64, dir: i8) -> bool {
    match dir {
        1 => x >= p,
        -1 => x <= p,
        _ => false,
    }
}

/// What a channel fires at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Source {
    /// One position; `dir` 0 fires either way.
    Single {
        /// The position, counts.
        at: f64,
    },
    /// `start + k·pitch`, k = `next`..`count` (pitch signed by the direction).
    Series {
        /// The first position.
        start: f64,
        /// The step, signed.
        pitch: f64,
        /// How many.
        count: u32,
        /// The next k.
        next: u32,
    },
    /// The channel's table, in queue order.
    Table,
}

/// An armed channel's parameters, validated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arm {
    /// The axis watched.
    pub axis: usize,
    /// The output pulsed.
    pub output: u32,
    /// The pulse width, ticks (fractional).
    pub pulse_ticks: f64,
    /// `MC_EV_COMPARE` low water when the table's queue falls to this (0: none).
    pub low_water: u32,
    /// +1 up, −1 down, 0 either way (single only).
    pub dir: i8,
    /// What it fires at.
    pub source: Source,
    /// The arm command's seq.
    pub seq: u32,
    /// Layout 1.13: the period of the modulo axis watched when armed, counts (0: a linear
    /// axis). Nonzero: the channel is turn-aware (its positions are places on the turn).
    pub modulo: f64,
    /// Layout 1.13, `MC_CMP_EACH_TURN`: a single position or a series fires on every turn.
    pub each_turn: bool,
}

/// One fire, for whoever records the output (the emulator's output recorder).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fire {
    /// The channel.
    pub channel: u8,
    /// The output pulsed.
    pub output: u8,
    /// The axis watched.
    pub axis: u8,
    /// The position programmed, counts.
    pub position: f64,
    /// The instant within the tick just ended, a fraction of the period in `(0, 1]`.
    pub frac: f64,
}

/// What a channel did in a tick.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct TickReport {
    /// The last position fired this tick.
    pub fired: Option<f64>,
    /// The last position missed this tick.
    pub missed: Option<f64>,
    /// The table's queue fell to the low-water mark: how many are queued.
    pub low_water: Option<u32>,
}

/// The state of one compare channel.
#[derive(Debug)]
pub struct Compare {
    arm: Option<Arm>,
    done: bool,
    table: FixedVec<f64, COMPARE_TABLE_LEN>,
    head: usize,
    len: usize,
    /// The table's direction (+1, −1), fixed by its first entry; 0 while empty.
    table_dir: i8,
    fires: u32,
    missed: u32,
    last_fired: f64,
    last_fire_tick: f64,
    last_missed: f64,
    /// When the current pulse ends, ticks since boot (fractional).
    pulse_end: f64,
    /// Ticks the output stays on in `card.outputs`.
    pulse_left: u32,
    low_water_sent: bool,
}

impl Default for Compare {
    fn default() -> Self {
        Self::new()
    }
}

impl Compare {
    /// A disarmed channel with room for its table (the only allocation).
    pub fn new() -> Self {
        Self {
            arm: None,
            done: false,
            table: FixedVec::from_elem(0.0, COMPARE_TABLE_LEN),
            head: 0,
            len: 0,
            table_dir: 0,
            fires: 0,
            missed: 0,
            last_fired: 0.0,
            last_fire_tick: 0.0,
            last_missed: 0.0,
            pulse_end: f64::NEG_INFINITY,
            pulse_left: 0,
            low_water_sent: false,
        }
    }

    /// Is the channel armed (firing, or waiting for table positions)?
    pub fn armed(&self) -> Option<&Arm> {
        self.arm.as_ref()
    }

    /// The output it holds, as a mask: while armed, and while its last pulse is on (0
    /// otherwise).
    pub fn output_mask(&self) -> u32 {
        match self.arm {
            Some(a) if !self.done || self.pulse_left > 0 => 1 << a.output,
            _ => 0,
        }
    }

    /// The output bit while a pulse is on.
    pub fn pulse_bits(&self) -> u32 {
        match self.arm {
            Some(a) if self.pulse_left > 0 => 1 << a.output,
            _ => 0,
        }
    }

    /// Arm with `arm` (a position already behind the axis is missed at the next tick); a
    /// channel that is done may be armed again. `MC_NACK_COMPARE_BUSY` when armed, or a table
    /// channel whose queue runs the other way.
    pub fn start(&mut self, arm: Arm) -> Result<(), NackCode> {
        if self.arm.is_some() && !self.done {
            return Err(NackCode::CompareBusy);
        }
        if matches!(arm.source, Source::Table) && self.table_dir != 0 && self.table_dir != arm.dir {
            return Err(NackCode::CompareBusy);
        }
        if arm.modulo > 0.0 && matches!(arm.source, Source::Table) {
            let n = self.table.len();
            let on_turn = |i: usize| (0.0..arm.modulo).contains(&self.table[(self.head + i) % n]);
            if !(0..self.len).all(on_turn) {
                return Err(NackCode::CompareTurn);
            }
        }
        self.arm = Some(arm);
        self.done = false;
        self.fires = 0;
        self.missed = 0;
        self.pulse_end = f64::NEG_INFINITY;
        self.pulse_left = 0;
        self.low_water_sent = false;
        Ok(())
    }

    /// Disarm, drop the table, end the pulse.
    pub fn stop(&mut self) {
        self.arm = None;
        self.done = false;
        self.head = 0;
        self.len = 0;
        self.table_dir = 0;
        self.pulse_left = 0;
    }

    /// Queue `positions` in the table, moving in `dir`: all or none. Returns the room left.
    pub fn queue(&mut self, dir: i8, positions: &[f64]) -> Result<u32, NackCode> {
        if let Some(a) = self.arm {
            if !matches!(a.source, Source::Table) || a.dir != dir {
                return Err(NackCode::CompareBusy);
            }
        }
        if self.table_dir != 0 && self.table_dir != dir {
            return Err(NackCode::CompareBusy);
        }
        if positions.iter().any(|p| !p.is_finite()) {
            return Err(NackCode::NotFinite);
        }
        if positions.iter().any(|p| p.abs() > MAX_POSITION) {
            return Err(NackCode::OutOfRange);
        }
        // Layout 1.13: armed on a modulo axis, the positions are places on the turn, in any
        // order (each fires at the next crossing after the one before).
        let turn = self.arm.map_or(0.0, |a| a.modulo);
        if turn > 0.0 && positions.iter().any(|p| !(0.0..turn).contains(p)) {
            return Err(NackCode::CompareTurn);
        }
        if positions.len() > self.table.len() - self.len {
            return Err(NackCode::CompareFull);
        }
        let mut last =
            (self.len > 0).then(|| self.table[(self.head + self.len - 1) % self.table.len()]);
        for &p in positions {
            if let (Some(l), false) = (last, turn > 0.0) {
                if (p - l) * f64::from(dir) <= 0.0 {
                    return Err(NackCode::CompareOrder);
                }
            }
            last = Some(p);
        }
        let n = self.table.len();
        for &p in positions {
            self.table[(self.head + self.len) % n] = p;
            self.len += 1;
        }
        self.table_dir = dir;
        if self.len > self.arm.map_or(0, |a| a.low_water) as usize {
            self.low_water_sent = false;
        }
        Ok((n - self.len) as u32)
    }

    /// The next position, if any.
    fn next(&self) -> Option<f64> {
        let a = self.arm?;
        match a.source {
            Source::Single { at } => (!self.done).then_some(at),
            Source::Series {
                start,
                pitch,
                count,
                next,
            } if a.modulo > 0.0 => (next < count).then(|| on_turn(start, next, pitch, a.modulo)),
            Source::Series {
                start,
                pitch,
                count,
                next,
            } => (next < count).then(|| start + f64::from(next) * pitch),
            Source::Table => (self.len > 0).then(|| self.table[self.head]),
        }
    }

    /// The axis an armed channel watches while it still has positions to fire (not done).
    pub fn watching(&self) -> Option<usize> {
        self.arm.filter(|_| !self.done).map(|a| a.axis)
    }

    /// Positions still to come.
    pub fn pending(&self) -> u32 {
        match self.arm.map(|a| a.source) {
            Some(Source::Single { .. }) => u32::from(!self.done),
            // An endless series: the positions of a turn.
            Some(Source::Series { count, .. }) if self.arm.is_some_and(|a| a.each_turn) => count,
            Some(Source::Series { count, next, .. }) => count - next,
            _ => self.len as u32,
        }
    }

    /// Consume the next position.
    fn advance(&mut self) {
        let Some(a) = self.arm.as_mut() else { return };
        match &mut a.source {
            Source::Single { .. } => self.done = !a.each_turn,
            Source::Series { next, count, .. } => {
                *next += 1;
                if a.each_turn && *next >= *count {
                    *next = 0; // the next turn's first
                }
                self.done = *next >= *count;
            }
            Source::Table => {
                self.head = (self.head + 1) % self.table.len();
                self.len -= 1;
                if self.len == 0 {
                    self.table_dir = a.dir; // the queue keeps its direction while armed
                }
            }
        }
    }

    /// [`Compare::tick`] of a channel not armed: its last pulse counts down, nothing else.
    #[inline]
    pub fn tick_unarmed(&mut self) {
        debug_assert!(self.arm.is_none());
        self.pulse_left = self.pulse_left.saturating_sub(1);
    }

    /// One tick: the axis moved from `x0` to `x1` (cell middles, the axis frame) over the tick
    /// ending at `tick`, reaching `range` (lowest, highest) in between. Fires go to `fires` (as
    /// many as fit; the count is what matters).
    pub fn tick<const N: usize>(
        &mut self,
        channel: u8,
        (x0, x1): (f64, f64),
        range: (f64, f64),
        tick: u64,
        fires: &mut heapless::Vec<Fire, N>,
    ) -> TickReport {
        self.pulse_left = self.pulse_left.saturating_sub(1);
        let mut out = TickReport::default();
        let Some(arm) = self.arm else { return out };
        if arm.modulo > 0.0 {
            self.tick_turns(channel, &arm, (x0, x1), range, tick, fires, &mut out);
            self.low_water(&arm, &mut out);
            return out;
        }
        let t0 = tick as f64 - 1.0;
        for _ in 0..MAX_PER_TICK {
            if self.done {
                break;
            }
            // A series entirely behind the axis is missed in one step.
            if let Source::Series {
                start,
                pitch,
                count,
                next,
            } = arm_source(&self.arm)
            {
                let p = start + f64::from(next) * pitch;
                if behind(x0, p, arm.dir) {
                    let n =
                        (math::floor((x0 - p) / pitch) + 1.0).clamp(1.0, f64::from(count - next));
                    let n = n as u32;
                    self.missed = self.missed.wrapping_add(n);
                    self.last_missed = start + f64::from(next + n - 1) * pitch;
                    out.missed = Some(self.last_missed);
                    if let Some(Arm {
                        source: Source::Series { next: k, .. },
                        ..
                    }) = self.arm.as_mut()
                    {
                        *k += n;
                        self.done = *k >= count;
                    }
                    continue;
                }
            }
            let Some(p) = self.next() else { break };
            if behind(x0, p, arm.dir) {
                self.miss(p, &mut out);
                continue;
            }
            let Some(frac) = crossing(x0, x1, p, arm.dir) else {
                if crossed_back(x0, x1, range, p, arm.dir) {
                    self.miss(p, &mut out);
                    continue;
                }
                break;
            };
            self.fire_at(channel, &arm, p, t0 + frac, frac, fires, &mut out);
        }
        self.low_water(&arm, &mut out);
        out
    }

    /// A table's queue at or under its low-water mark: reported once until it fills again.
    fn low_water(&mut self, arm: &Arm, out: &mut TickReport) {
        if matches!(arm.source, Source::Table)
            && arm.low_water > 0
            && self.len <= arm.low_water as usize
            && !self.low_water_sent
        {
            self.low_water_sent = true;
            out.low_water = Some(self.len as u32);
        }
    }

    /// [`Compare::tick`] of a turn-aware channel (layout 1.13, a modulo axis of period
    /// `arm.modulo`): each position `p` (a place on the turn) fires where the motion crosses
    /// `p + j·m` for any whole `j` in the channel's direction, each at the next crossing after
    /// the position before it. `x0`, `x1` and `range` are in one frame (the axis's turns
    /// taken out exactly, so they stay near the turn however many it made); `cursor` is where
    /// the search for the next crossing starts, moved to each crossing consumed, so the
    /// positions of one tick fire in order along the motion.
    #[allow(clippy::too_many_arguments)]
    fn tick_turns<const N: usize>(
        &mut self,
        channel: u8,
        arm: &Arm,
        (x0, x1): (f64, f64),
        (lo, hi): (f64, f64),
        tick: u64,
        fires: &mut heapless::Vec<Fire, N>,
        out: &mut TickReport,
    ) {
        let m = arm.modulo;
        let t0 = tick as f64 - 1.0;
        // The way the axis moved over the tick, and whether the channel fires that way.
        let s: i8 = if x1 > x0 {
            1
        } else if x1 < x0 {
            -1
        } else {
            0
        };
        let fires_this_way = s != 0 && (arm.dir == 0 || arm.dir == s);
        // An endless series is a set of places: its next is the one the axis comes to first
        // from where the tick starts (the axis may have turned back since the last).
        if arm.each_turn && matches!(arm.source, Source::Series { .. }) {
            self.seek_series(arm, x0);
        }
        let mut cursor = x0;
        // Where the searches for a crossing undone within the tick start (above the ends for
        // an upward one, below them for a downward one).
        let (mut back_up, mut back_down) = (x0.max(x1), x0.min(x1));
        for _ in 0..MAX_PER_TICK {
            if self.done {
                return;
            }
            let Some(p) = self.next() else { return };
            if fires_this_way {
                let q = next_turn(cursor, p, m, s);
                if (x1 - q) * f64::from(s) >= 0.0 {
                    cursor = q;
                    let frac = ((q - x0) / (x1 - x0)).clamp(0.0, 1.0);
                    self.fire_at(channel, arm, p, t0 + frac, frac, fires, out);
                    continue;
                }
            }
            // Crossed and crossed back within the tick: the extremes reach a crossing beyond
            // both ends, in a direction the channel fires.
            if arm.dir >= 0 {
                let q = next_turn(back_up, p, m, 1);
                if q <= hi {
                    back_up = q;
                    self.miss(p, out);
                    continue;
                }
            }
            if arm.dir <= 0 {
                let q = next_turn(back_down, p, m, -1);
                if q >= lo {
                    back_down = q;
                    self.miss(p, out);
                    continue;
                }
            }
            return;
        }
        // The bound on the positions examined in a tick: the crossings left in the motion
        // are missed, counted here (the axis has passed them; on a turn they would otherwise
        // wait for the next turn).
        if fires_this_way && !self.done {
            self.miss_rest(arm, cursor, x1, s, out);
        }
    }

    /// An endless series goes on from the position the axis, at `x`, comes to first moving the
    /// channel's way (every tick: each place fires at every crossing, back and forth).
    fn seek_series(&mut self, arm: &Arm, x: f64) {
        let Source::Series {
            start,
            pitch,
            count,
            ..
        } = arm.source
        else {
            return;
        };
        let (m, s) = (arm.modulo, arm.dir);
        // The way to the start, in (0, m], then the first k whose position is past a turn
        // from there; of it and the one before, whichever is nearer (rounding at a boundary).
        let d = next_turn(x, start, m, s) - x;
        let k = (math::floor((m - d.abs()) / pitch.abs()) + 1.0).clamp(0.0, f64::from(count));
        let k = if k >= f64::from(count) { 0 } else { k as u32 };
        let before = if k == 0 { count - 1 } else { k - 1 };
        let dist = |i: u32| (next_turn(x, on_turn(start, i, pitch, m), m, s) - x).abs();
        let k = if dist(before) < dist(k) { before } else { k };
        if let Some(Arm {
            source: Source::Series { next, .. },
            ..
        }) = self.arm.as_mut()
        {
            *next = k;
        }
    }

    /// A position fires at `at` (ticks since boot; `frac` within this tick), or is missed when
    /// that falls inside the pulse before it.
    #[allow(clippy::too_many_arguments)]
    fn fire_at<const N: usize>(
        &mut self,
        channel: u8,
        arm: &Arm,
        p: f64,
        at: f64,
        frac: f64,
        fires: &mut heapless::Vec<Fire, N>,
        out: &mut TickReport,
    ) {
        if at < self.pulse_end {
            self.miss(p, out);
            return;
        }
        self.fires = self.fires.wrapping_add(1);
        self.last_fired = p;
        self.last_fire_tick = at;
        self.pulse_end = at + arm.pulse_ticks;
        self.pulse_left = (math::ceil(arm.pulse_ticks) as u32).max(1);
        out.fired = Some(p);
        let _ = fires.push(Fire {
            channel,
            output: arm.output as u8,
            axis: arm.axis as u8,
            position: p,
            frac,
        });
        self.advance();
    }

    /// A turn-aware channel's crossings in `(cursor, x1]` (moving `s`) beyond the per-tick
    /// bound, all missed and counted at once (a series or a single in closed form, a table
    /// one by one: it is finite).
    fn miss_rest(&mut self, arm: &Arm, cursor: f64, x1: f64, s: i8, out: &mut TickReport) {
        let m = arm.modulo;
        let sf = f64::from(s);
        let Some(p) = self.next() else { return };
        let q = next_turn(cursor, p, m, s);
        let ahead = (x1 - q) * sf; // how far the motion goes past the next crossing
        if ahead < 0.0 {
            return;
        }
        // The source as it stands now (`arm` is the copy the tick started with).
        match arm_source(&self.arm) {
            Source::Single { at } => {
                // Endless (a single once fires or is missed within the bound).
                let n = math::floor(ahead / m) + 1.0;
                self.missed = self.missed.wrapping_add(n as u32);
                self.last_missed = at;
                out.missed = Some(at);
            }
            Source::Series {
                start,
                pitch,
                count,
                next,
            } => {
                let step = pitch.abs();
                let n = if arm.each_turn {
                    // Crossings (turn t, index k) from index `next` on: the base (index 0 of
                    // this turn) is `next` pitches behind q.
                    let l = ahead + f64::from(next) * step;
                    let full = math::floor(l / m);
                    let r = l - full * m;
                    let part = (math::floor(r / step) + 1.0).min(f64::from(count));
                    full * f64::from(count) + part - f64::from(next)
                } else {
                    (math::floor(ahead / step) + 1.0).min(f64::from(count - next))
                };
                let n = n.max(1.0) as u64;
                let k = if arm.each_turn {
                    ((u64::from(next) + n) % u64::from(count)) as u32
                } else {
                    next + n as u32
                };
                let last = (u64::from(next) + n - 1) % u64::from(count);
                self.missed = self.missed.wrapping_add(n as u32);
                self.last_missed = on_turn(start, last as u32, pitch, m);
                out.missed = Some(self.last_missed);
                if let Some(Arm {
                    source: Source::Series { next, .. },
                    ..
                }) = self.arm.as_mut()
                {
                    *next = k;
                }
                self.done = !arm.each_turn && k >= count;
            }
            Source::Table => {
                let mut c = cursor;
                for _ in 0..COMPARE_TABLE_LEN {
                    let Some(p) = self.next() else { return };
                    let q = next_turn(c, p, m, s);
                    if (x1 - q) * sf < 0.0 {
                        return;
                    }
                    c = q;
                    self.miss(p, out);
                }
            }
        }
    }

    fn miss(&mut self, p: f64, out: &mut TickReport) {
        self.missed = self.missed.wrapping_add(1);
        self.last_missed = p;
        out.missed = Some(p);
        self.advance();
    }

    /// The status block.
    pub fn status(&self) -> raw::mc_compare_status {
        let (state, axis, output) = match self.arm {
            None => (raw::MC_IO_IDLE, 0, 0),
            Some(a) if self.done => (raw::MC_IO_DONE, a.axis as u32, a.output),
            Some(a) => (raw::MC_IO_ARMED, a.axis as u32, a.output),
        };
        raw::mc_compare_status {
            state,
            axis,
            fires: self.fires,
            missed: self.missed,
            pending: self.pending(),
            output,
            next: self.next().unwrap_or(0.0),
            last_fired: self.last_fired,
            last_fire_tick: self.last_fire_tick,
            last_missed: self.last_missed,
        }
    }
}

/// Position `k` of a series on a turn of `m` counts: `start + k·pitch` wrapped into `[0, m)`
/// (the series spans less than a turn, so one wrap at most).
fn on_turn(start: f64, k: u32, pitch: f64, m: f64) -> f64 {
    let v = start + f64::from(k) * pitch;
    if v >= m {
        v - m
    } else if v < 0.0 {
        let w = v + m;
        if w >= m {
            0.0
        } else {
            w
        }
    } else {
        v
    }
}

/// The first place `p + j·m` (a whole `j`) strictly beyond `c` moving `s` (+1 up, −1 down):
/// where the axis next crosses the position `p` of a turn of `m` counts.
pub fn next_turn(c: f64, p: f64, m: f64, s: i8) -> f64 {
    // The place of turn j is always `p + j·m` (one rounding), so a neighbour that the division
    // misjudged by a rounding is judged on the same numbers as the one chosen.
    let at = |j: f64| p + j * m;
    if s > 0 {
        let j = math::floor((c - p) / m) + 1.0;
        if at(j) <= c {
            at(j + 1.0)
        } else if at(j - 1.0) > c {
            at(j - 1.0)
        } else {
            at(j)
        }
    } else {
        let j = math::ceil((c - p) / m) - 1.0;
        if at(j) >= c {
            at(j - 1.0)
        } else if at(j + 1.0) < c {
            at(j + 1.0)
        } else {
            at(j)
        }
    }
}

fn arm_source(a: &Option<Arm>) -> Source {
    a.map_or(Source::Table, |a| a.source)
}

/// Validate `MC_OP_COMPARE_ARM`'s numbers (decoding checked the channel, the mode and the
/// direction): output, pulse_us, low_water, position/start, pitch, count; `rate_hz` the servo
/// rate; `modulo` the period of the axis watched, counts (0: linear; layout 1.13: the
/// positions are then places on the turn, `MC_NACK_COMPARE_TURN` for what does not fit one).
pub fn validate_arm(
    axis: usize,
    a: &CompareArm,
    rate_hz: u32,
    seq: u32,
    modulo: f64,
) -> Result<Arm, NackCode> {
    let (output, pulse_us, low_water) = (a.output, a.pulse_us, a.low_water);
    let (p0, pitch, count) = (a.position, a.pitch, a.count);
    let dir: i8 = a.direction.map_or(0, Direction::sign);
    let int_in = |x: f64, lo: f64, hi: f64| math::fract(x) == 0.0 && (lo..=hi).contains(&x);
    let finite = [output, pulse_us, low_water, p0, pitch, count];
    let used = match a.kind {
        CompareKind::Single => &finite[..4],
        CompareKind::Series => &finite[..],
        CompareKind::Table => &finite[..3],
    };
    if used.iter().any(|x| !x.is_finite()) {
        return Err(NackCode::NotFinite);
    }
    if !int_in(output, 0.0, (OUTPUTS - 1) as f64)
        || !int_in(pulse_us, 1.0, f64::from(raw::MC_PULSE_MAX_US))
        || !int_in(low_water, 0.0, (COMPARE_TABLE_LEN - 1) as f64)
    {
        return Err(NackCode::CompareMode);
    }
    if modulo > 0.0 {
        return validate_turn(
            axis,
            a,
            modulo,
            (pulse_us * 1e-6 * f64::from(rate_hz), dir, seq),
        );
    }
    if a.each_turn {
        return Err(NackCode::CompareTurn);
    }
    let source = match a.kind {
        CompareKind::Single => {
            if p0.abs() > MAX_POSITION {
                return Err(NackCode::OutOfRange);
            }
            Source::Single { at: p0 }
        }
        CompareKind::Series => {
            if !(1.0..=MAX_POSITION).contains(&pitch) || !int_in(count, 1.0, f64::from(i32::MAX)) {
                return Err(NackCode::CompareMode);
            }
            let end = p0 + f64::from(dir) * pitch * (count - 1.0);
            if p0.abs() > MAX_POSITION || end.abs() > MAX_POSITION {
                return Err(NackCode::OutOfRange);
            }
            Source::Series {
                start: p0,
                pitch: f64::from(dir) * pitch,
                count: count as u32,
                next: 0,
            }
        }
        CompareKind::Table => Source::Table,
    };
    Ok(Arm {
        axis,
        output: output as u32,
        pulse_ticks: pulse_us * 1e-6 * f64::from(rate_hz),
        low_water: low_water as u32,
        dir,
        source,
        seq,
        modulo: 0.0,
        each_turn: false,
    })
}

/// [`validate_arm`] on a modulo axis of period `m` (layout 1.13), the output, pulse and
/// low-water mark checked: every position a place on the turn (`0 <= p < m`), a series within
/// one turn (with `each_turn`, `count·pitch <= m`; count 0: `floor(m / pitch)`). A product is
/// allowed a relative 1e-12 over the turn (under a count: a pitch is at least one), so a pitch of `m / n` given in decimals still makes
/// `n` a turn.
fn validate_turn(
    axis: usize,
    a: &CompareArm,
    m: f64,
    (pulse_ticks, dir, seq): (f64, i8, u32),
) -> Result<Arm, NackCode> {
    let (p0, pitch, count) = (a.position, a.pitch, a.count);
    let slack = m * (1.0 + 1e-12);
    let source = match a.kind {
        CompareKind::Single => {
            if !(0.0..m).contains(&p0) {
                return Err(NackCode::CompareTurn);
            }
            Source::Single { at: p0 }
        }
        CompareKind::Series => {
            let whole = |x: f64| math::fract(x) == 0.0 && (0.0..=f64::from(i32::MAX)).contains(&x);
            if !(1.0..=MAX_POSITION).contains(&pitch) || !whole(count) {
                return Err(NackCode::CompareMode);
            }
            if count == 0.0 && !a.each_turn {
                return Err(NackCode::CompareMode);
            }
            let n = if count == 0.0 {
                math::floor(slack / pitch)
            } else {
                count
            };
            if n > f64::from(i32::MAX) {
                return Err(NackCode::CompareMode);
            }
            let span = if a.each_turn { n } else { n - 1.0 };
            let fits = if a.each_turn {
                span * pitch <= slack
            } else {
                span * pitch < m
            };
            if !(0.0..m).contains(&p0) || n < 1.0 || !fits {
                return Err(NackCode::CompareTurn);
            }
            Source::Series {
                start: p0,
                pitch: f64::from(dir) * pitch,
                count: n as u32,
                next: 0,
            }
        }
        CompareKind::Table => Source::Table,
    };
    Ok(Arm {
        axis,
        output: a.output as u32,
        pulse_ticks,
        low_water: a.low_water as u32,
        dir,
        source,
        seq,
        modulo: m,
        each_turn: a.each_turn,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arm(dir: i8, source: Source) -> Arm {
        Arm {
            axis: 0,
            output: 3,
            pulse_ticks: 0.1,
            low_water: 0,
            dir,
            source,
            seq: 7,
            modulo: 0.0,
            each_turn: false,
        }
    }

    /// [`arm`] on a modulo axis of period `m`, endless or not.
    fn turn_arm(dir: i8, source: Source, m: f64, each_turn: bool) -> Arm {
        Arm {
            modulo: m,
            each_turn,
            ..arm(dir, source)
        }
    }

    type Fires = heapless::Vec<Fire, 1024>;

    /// Run a channel over a ramp of positions `x(k)`, k = 0..n; the fires' instants.
    fn run(c: &mut Compare, x: impl Fn(u64) -> f64, n: u64) -> (Vec<(f64, f64)>, TickReport) {
        let mut all = Vec::new();
        let mut last = TickReport::default();
        for k in 1..=n {
            let mut f = Fires::new();
            let (x0, x1) = (x(k - 1), x(k));
            let r = c.tick(0, (x0, x1), (x0.min(x1), x0.max(x1)), k, &mut f);
            if r != TickReport::default() {
                last = r;
            }
            all.extend(f.iter().map(|f| (f.position, k as f64 - 1.0 + f.frac)));
        }
        (all, last)
    }

    #[test]
    fn the_crossing_instant_is_interpolated_within_the_tick() {
        assert_eq!(crossing(0.5, 200.5, 50.5, 1), Some(0.25));
        assert_eq!(crossing(0.5, 200.5, 50.5, -1), None);
        assert_eq!(crossing(200.5, 0.5, 50.5, -1), Some(0.75));
        assert_eq!(crossing(200.5, 0.5, 50.5, 0), Some(0.75));
        assert_eq!(crossing(0.5, 0.5, 0.5, 0), None, "no motion, no crossing");
        assert_eq!(crossing(0.5, 1.5, 1.5, 1), Some(1.0));
    }

    /// A series at 200 counts per tick, pitch 50: every position fires once, at the instant
    /// the ramp passes it, and the series ends done.
    #[test]
    fn a_series_fires_every_position_at_its_instant() {
        let mut c = Compare::new();
        let source = Source::Series {
            start: 1_000.0,
            pitch: 50.0,
            count: 100,
            next: 0,
        };
        c.start(arm(1, source)).unwrap();
        let (fires, _) = run(&mut c, |k| 0.5 + 200.0 * k as f64, 100);
        assert_eq!(fires.len(), 100);
        for (i, (p, t)) in fires.iter().enumerate() {
            assert_eq!(*p, 1_000.0 + 50.0 * i as f64);
            assert!((0.5 + 200.0 * t - p).abs() < 1e-9, "{p} at {t}");
        }
        let s = c.status();
        assert_eq!(
            (s.state, s.fires, s.missed, s.pending),
            (raw::MC_IO_DONE, 100, 0, 0)
        );
    }

    /// Armed behind the axis: the positions already passed are missed (counted, the last
    /// reported), the rest fire.
    #[test]
    fn positions_passed_before_the_arm_are_missed() {
        let mut c = Compare::new();
        let source = Source::Series {
            start: 0.0,
            pitch: 10.0,
            count: 20,
            next: 0,
        };
        c.start(arm(1, source)).unwrap();
        let (fires, last) = run(&mut c, |k| 95.5 + k as f64, 200);
        assert_eq!(fires.len(), 10); // 100..190
        assert_eq!((c.status().missed, c.status().fires), (10, 10));
        assert!(last.fired.is_some());
        let mut c = Compare::new();
        c.start(arm(-1, Source::Single { at: 500.0 })).unwrap();
        let mut f = Fires::new();
        let r = c.tick(0, (400.5, 300.5), (300.5, 400.5), 1, &mut f);
        assert_eq!(r.missed, Some(500.0));
        assert_eq!(c.status().state, raw::MC_IO_DONE);
        assert_eq!(c.output_mask(), 0, "done: the output is free");
        c.start(arm(-1, Source::Single { at: 200.0 })).unwrap();
        assert_eq!(
            c.start(arm(-1, Source::Single { at: 100.0 })),
            Err(NackCode::CompareBusy)
        );
        assert_eq!((c.status().state, c.status().missed), (raw::MC_IO_ARMED, 0));
    }

    /// Crossed and crossed back within one tick: no instant, reported missed; a single either
    /// way too. Not reached: nothing.
    #[test]
    fn a_position_crossed_and_crossed_back_in_one_tick_is_missed() {
        assert!(crossed_back(9.5, 9.5, (9.5, 10.5), 10.0, 1));
        assert!(!crossed_back(9.5, 9.5, (9.5, 9.5), 10.0, 1));
        assert!(!crossed_back(9.5, 9.5, (9.5, 10.5), 10.0, -1));
        assert!(crossed_back(10.5, 10.5, (9.5, 10.5), 10.0, 0));
        let mut c = Compare::new();
        c.start(arm(1, Source::Single { at: 10.0 })).unwrap();
        let mut f = Fires::new();
        let r = c.tick(0, (9.5, 9.5), (9.5, 9.5), 1, &mut f);
        assert_eq!(r, TickReport::default());
        let r = c.tick(0, (9.5, 9.5), (9.5, 10.5), 2, &mut f);
        assert_eq!((r.missed, r.fired, f.len()), (Some(10.0), None, 0));
        assert_eq!(c.status().state, raw::MC_IO_DONE);
    }

    /// Two positions closer than the pulse: the second comes while the output is on and is
    /// reported missed.
    #[test]
    fn a_position_inside_the_pulse_before_is_missed() {
        let mut c = Compare::new();
        let source = Source::Series {
            start: 10.0,
            pitch: 5.0,
            count: 4,
            next: 0,
        };
        let a = Arm {
            pulse_ticks: 0.06, // 12 counts at 200 counts per tick
            ..arm(1, source)
        };
        c.start(a).unwrap();
        let (fires, _) = run(&mut c, |k| 0.5 + 200.0 * k as f64, 1);
        assert_eq!(fires.iter().map(|f| f.0).collect::<Vec<_>>(), [10.0, 25.0]);
        assert_eq!(c.status().missed, 2);
        assert_eq!(c.pulse_bits(), 1 << 3);
    }

    /// A table streamed in: order checked, all or nothing, full refused, low water once.
    #[test]
    fn the_table_streams_with_room_order_and_low_water() {
        let mut c = Compare::new();
        assert_eq!(c.queue(1, &[1.0, 2.0, 2.0]), Err(NackCode::CompareOrder));
        assert_eq!(c.status().pending, 0, "nothing taken");
        let n = COMPARE_TABLE_LEN as u32;
        assert_eq!(c.queue(1, &[10.0, 20.0]), Ok(n - 2));
        assert_eq!(c.queue(1, &[15.0]), Err(NackCode::CompareOrder));
        assert_eq!(c.queue(-1, &[5.0]), Err(NackCode::CompareBusy));
        let a = Arm {
            low_water: 2,
            ..arm(1, Source::Table)
        };
        c.start(a).unwrap();
        assert_eq!(c.queue(1, &[30.0, 40.0]), Ok(n - 4));
        let (fires, last) = run(&mut c, |k| 0.5 + 5.0 * k as f64, 5);
        assert_eq!(fires.len(), 2);
        assert_eq!((last.fired, last.low_water), (Some(20.0), Some(2)));
        let mut f = Fires::new();
        let r = c.tick(0, (25.5, 25.6), (25.5, 25.6), 6, &mut f);
        assert_eq!(r.low_water, None, "once");
        assert_eq!(c.status().pending, 2);
        let many: Vec<f64> = (0..COMPARE_TABLE_LEN).map(|i| 100.0 + i as f64).collect();
        assert_eq!(c.queue(1, &many), Err(NackCode::CompareFull));
        assert_eq!(c.queue(1, &many[..COMPARE_TABLE_LEN - 2]), Ok(0));
    }

    /// `MC_OP_COMPARE_ARM` with these flags and arguments (after the channel, 0), decoded as
    /// the card decodes it, then validated.
    fn validate_arm(
        axis: usize,
        flags: u32,
        args: &[f64],
        rate_hz: u32,
        seq: u32,
    ) -> Result<Arm, NackCode> {
        use firmware_proto::cmd::Args;
        let mut a = [0.0; firmware_proto::CMD_ARGS];
        a[1..1 + args.len()].copy_from_slice(args);
        let arm = CompareArm::decode(flags, &a).map_err(|e| e.nack)?;
        super::validate_arm(axis, &arm, rate_hz, seq, 0.0)
    }

    /// The same on a modulo axis of period `m`.
    fn validate_turn_arm(flags: u32, args: &[f64], m: f64) -> Result<Arm, NackCode> {
        use firmware_proto::cmd::Args;
        let mut a = [0.0; firmware_proto::CMD_ARGS];
        a[1..1 + args.len()].copy_from_slice(args);
        let arm = CompareArm::decode(flags, &a).map_err(|e| e.nack)?;
        super::validate_arm(0, &arm, 10_000, 1, m)
    }

    #[test]
    fn the_arm_is_validated() {
        let ok = [2.0, 10.0, 0.0, 100.0, 5.0, 10.0];
        let series = raw::MC_CMP_MODE_SERIES | raw::MC_CMP_DIR_POS;
        assert!(validate_arm(0, series, &ok, 10_000, 1).is_ok());
        let bad = |i: usize, v: f64| {
            let mut a = ok;
            a[i] = v;
            validate_arm(0, series, &a, 10_000, 1)
        };
        assert_eq!(bad(0, 16.0).unwrap_err(), NackCode::CompareMode);
        assert_eq!(bad(0, 1.5).unwrap_err(), NackCode::CompareMode);
        assert_eq!(bad(1, 0.0).unwrap_err(), NackCode::CompareMode);
        assert_eq!(bad(1, f64::NAN).unwrap_err(), NackCode::NotFinite);
        assert_eq!(bad(3, 1e300).unwrap_err(), NackCode::OutOfRange);
        assert_eq!(bad(4, 1e-310).unwrap_err(), NackCode::CompareMode);
        assert_eq!(bad(5, 0.0).unwrap_err(), NackCode::CompareMode);
        assert_eq!(bad(4, MAX_POSITION).unwrap_err(), NackCode::OutOfRange);
        let both = raw::MC_CMP_MODE_SERIES | raw::MC_CMP_DIR_POS | raw::MC_CMP_DIR_NEG;
        assert_eq!(
            validate_arm(0, both, &ok, 10_000, 1).unwrap_err(),
            NackCode::CompareMode
        );
        let single = raw::MC_CMP_DIR_POS | raw::MC_CMP_DIR_NEG;
        assert_eq!(validate_arm(0, single, &ok, 10_000, 1).unwrap().dir, 0);
        assert_eq!(
            validate_arm(0, 3, &ok, 10_000, 1).unwrap_err(),
            NackCode::CompareMode
        );
        assert_eq!(
            validate_arm(0, 1 << 9, &ok, 10_000, 1).unwrap_err(),
            NackCode::CompareMode
        );
    }

    /// The crossing instants of `p + j·m` over a straight run from `a` to `b`, in order.
    fn crossings(a: f64, b: f64, p: f64, m: f64) -> Vec<f64> {
        let (lo, hi) = (a.min(b), a.max(b));
        let mut v: Vec<f64> = (-5..=5)
            .map(|j| p + f64::from(j) * m)
            .filter(|q| {
                if b > a {
                    *q > lo && *q <= hi
                } else {
                    *q >= lo && *q < hi
                }
            })
            .collect();
        if b < a {
            v.reverse();
        }
        v
    }

    #[test]
    fn the_next_crossing_on_a_turn_is_strictly_beyond_the_cursor() {
        let m = 360.0;
        assert_eq!(next_turn(100.0, 90.0, m, 1), 450.0);
        assert_eq!(next_turn(90.0, 90.0, m, 1), 450.0, "strictly beyond");
        assert_eq!(next_turn(-5.0, 0.0, m, 1), 0.0);
        assert_eq!(next_turn(100.0, 90.0, m, -1), 90.0);
        assert_eq!(next_turn(90.0, 90.0, m, -1), -270.0);
        assert_eq!(next_turn(365.0, 0.0, m, -1), 360.0);
        // Far from the turn (a frame standing still while synchronised): still the next one.
        let c = 1e9 * m + 17.25;
        assert_eq!(next_turn(c, 20.0, m, 1), 1e9 * m + 20.0);
        assert_eq!(next_turn(c, 20.0, m, -1), 1e9 * m + 20.0 - m);
        for (c, p) in [(0.0, 0.0), (359.999, 0.0), (0.001, 359.999), (-0.25, 0.0)] {
            let up = next_turn(c, p, m, 1);
            let down = next_turn(c, p, m, -1);
            assert!(up > c && up - m <= c, "{c} {p}: {up}");
            assert!(down < c && down + m >= c, "{c} {p}: {down}");
        }
    }

    /// A single position on a turn of 360 with `each_turn`: one fire per crossing, at the
    /// interpolated instant, over the wrap (the frame moves by a turn between ticks, as the
    /// axis's does), up and then down for a channel either way; without `each_turn` the first
    /// crossing only, never a miss for being behind.
    #[test]
    fn a_single_on_a_turn_fires_at_every_crossing_across_the_wrap() {
        let m = 360.0;
        for p in [0.0, 0.3, 90.0, 359.8] {
            let mut c = Compare::new();
            c.start(turn_arm(0, Source::Single { at: p }, m, true))
                .unwrap();
            // 7 counts a tick from 100 up for 400 ticks, the frame wrapped into [0, 360) at
            // each tick's start, then back down for 400 ticks.
            let mut x = 100.0;
            let mut expect = Vec::new();
            let mut got = Vec::new();
            for k in 1..=800u64 {
                let v = if k <= 400 { 7.0 } else { -7.0 };
                let x0 = x - math::floor(x / m) * m;
                let x1 = x0 + v;
                expect.extend(
                    crossings(x0, x1, p, m)
                        .iter()
                        .map(|q| k as f64 - 1.0 + (q - x0) / v),
                );
                let mut f = Fires::new();
                c.tick(0, (x0, x1), (x0.min(x1), x0.max(x1)), k, &mut f);
                got.extend(f.iter().map(|f| k as f64 - 1.0 + f.frac));
                assert!(f.iter().all(|f| f.position == p));
                x = x1;
            }
            assert_eq!(got.len(), expect.len(), "{p}");
            assert!(expect.len() >= 14, "{p}: {} crossings", expect.len());
            for (g, e) in got.iter().zip(&expect) {
                assert!((g - e).abs() < 1e-9, "{p}: {g} vs {e}");
            }
            let s = c.status();
            assert_eq!(
                (s.state, s.fires, s.missed, s.pending),
                (raw::MC_IO_ARMED, got.len() as u32, 0, 1)
            );
        }
        // Once: the first crossing, armed "behind" the axis (no miss: it comes round).
        let mut c = Compare::new();
        c.start(turn_arm(1, Source::Single { at: 50.0 }, m, false))
            .unwrap();
        let mut f = Fires::new();
        c.tick(0, (100.5, 300.5), (100.5, 300.5), 1, &mut f);
        assert_eq!((c.status().fires, c.status().missed), (0, 0));
        c.tick(0, (300.5 - m, 60.5), (300.5 - m, 60.5), 2, &mut f);
        assert_eq!(f.len(), 1);
        assert!((f[0].frac - (50.0 + 59.5) / 120.0).abs() < 1e-12);
        assert_eq!(c.status().state, raw::MC_IO_DONE);
    }

    /// A series each turn (every 10 from 5, a whole turn of 360: count 0), up at 13 counts a
    /// tick over 1000 turns in a frame that stays within the turn: every position of every turn
    /// fires once, in order, at its instant; down, a series starting before the wrap.
    #[test]
    fn a_series_each_turn_fires_every_position_of_every_turn() {
        let m = 360.0;
        let a = validate_turn_arm(
            raw::MC_CMP_MODE_SERIES | raw::MC_CMP_DIR_POS | raw::MC_CMP_EACH_TURN,
            &[3.0, 1.0, 0.0, 5.0, 10.0, 0.0],
            m,
        )
        .unwrap();
        assert_eq!(
            a.source,
            Source::Series {
                start: 5.0,
                pitch: 10.0,
                count: 36,
                next: 0
            }
        );
        let mut c = Compare::new();
        c.start(Arm {
            pulse_ticks: 0.01,
            ..a
        })
        .unwrap();
        let ticks = 1000 * 360 / 13;
        let (mut x, mut n) = (0.25f64, 0usize);
        for k in 1..=ticks {
            let x0 = x - math::floor(x / m) * m;
            let x1 = x0 + 13.0;
            let mut f = Fires::new();
            c.tick(0, (x0, x1), (x0, x1), k, &mut f);
            let mut want: Vec<f64> = (0..36)
                .flat_map(|i| crossings(x0, x1, 5.0 + 10.0 * f64::from(i), m))
                .collect();
            want.sort_by(f64::total_cmp);
            assert_eq!(f.len(), want.len(), "tick {k}");
            for (f, q) in f.iter().zip(&want) {
                assert!((f.frac - (q - x0) / 13.0).abs() < 1e-12);
                assert_eq!(f.position, q - math::floor(q / m) * m);
            }
            n += f.len();
            x = x1;
        }
        let s = c.status();
        assert_eq!(
            (s.fires as usize, s.missed, s.pending, s.state),
            (n, 0, 36, raw::MC_IO_ARMED)
        );
        assert!(n >= 36 * 999, "{n}");
        // Down from 20: 355, 345, 335 are 25, 35, 45 counts on, across the wrap.
        let source = Source::Series {
            start: 355.0,
            pitch: -10.0,
            count: 3,
            next: 0,
        };
        let mut c = Compare::new();
        c.start(turn_arm(-1, source, m, false)).unwrap();
        let (fires, _) = run(&mut c, |k| 20.0 - 10.0 * k as f64, 6);
        assert_eq!(
            fires.iter().map(|f| f.0).collect::<Vec<_>>(),
            [355.0, 345.0, 335.0]
        );
        for ((_, t), d) in fires.iter().zip([25.0, 35.0, 45.0]) {
            assert!((t - d / 10.0).abs() < 1e-12, "{t}");
        }
        assert_eq!(c.status().state, raw::MC_IO_DONE);
    }

    /// Crossed and crossed back within a tick, on a turn: missed (no instant); a crossing
    /// against the channel's direction: nothing; the per-tick bound: the rest of the tick's
    /// crossings are counted missed at once (an endless series at 40 turns a tick).
    #[test]
    fn turn_misses_are_counted() {
        let m = 100.0;
        let mut c = Compare::new();
        c.start(turn_arm(1, Source::Single { at: 0.0 }, m, true))
            .unwrap();
        let mut f = Fires::new();
        c.tick(0, (99.5, 99.5), (99.5, 100.5), 1, &mut f);
        assert_eq!((c.status().missed, f.len()), (1, 0));
        c.tick(0, (99.5, 90.5), (90.5, 99.5), 2, &mut f);
        c.tick(0, (-9.5, -20.5), (-20.5, -9.5), 3, &mut f);
        assert_eq!(
            (c.status().missed, c.status().fires),
            (1, 0),
            "down: not this channel's way"
        );
        let source = Source::Series {
            start: 0.0,
            pitch: 1.0,
            count: 100,
            next: 0,
        };
        let mut c = Compare::new();
        c.start(Arm {
            pulse_ticks: 1e-9,
            ..turn_arm(1, source, m, true)
        })
        .unwrap();
        let mut f = Fires::new();
        c.tick(0, (0.5, 4000.5), (0.5, 4000.5), 1, &mut f);
        let s = c.status();
        assert_eq!(s.fires + s.missed, 4000, "every crossing, fired or missed");
        assert_eq!(s.fires as usize, MAX_PER_TICK);
        assert_eq!(s.last_missed, 0.0);
        assert_eq!(s.next, 1.0, "the series goes on from the next one");
        // Once, 30 of 40 ahead: the same, then done.
        let source = Source::Series {
            start: 50.0,
            pitch: 2.0,
            count: 30,
            next: 0,
        };
        let mut c = Compare::new();
        c.start(Arm {
            pulse_ticks: 1e-9,
            ..turn_arm(1, source, m, false)
        })
        .unwrap();
        c.tick(0, (40.5, 140.5), (40.5, 140.5), 1, &mut Fires::new());
        assert_eq!((c.status().fires, c.status().state), (30, raw::MC_IO_DONE));
    }

    /// What a turn refuses: positions off the turn, a series longer than a turn, count 0
    /// without each turn, each turn on a linear axis (and with a table, at decoding); a table
    /// queued off the turn, and any order on a turn.
    #[test]
    fn the_turn_arm_is_validated() {
        let m = 360.0;
        let single = raw::MC_CMP_DIR_POS;
        let series = raw::MC_CMP_MODE_SERIES | raw::MC_CMP_DIR_POS;
        let each = raw::MC_CMP_EACH_TURN;
        let ok = |f: u32, a: &[f64]| validate_turn_arm(f, a, m);
        let turn = Err(NackCode::CompareTurn);
        assert!(ok(single, &[0.0, 1.0, 0.0, 0.0]).is_ok());
        assert_eq!(ok(single, &[0.0, 1.0, 0.0, 360.0]).map(|_| ()), turn);
        assert_eq!(ok(single, &[0.0, 1.0, 0.0, -1e-9]).map(|_| ()), turn);
        assert_eq!(
            ok(series, &[0.0, 1.0, 0.0, 350.0, 10.0, 37.0]).map(|_| ()),
            turn
        );
        assert!(ok(series, &[0.0, 1.0, 0.0, 350.0, 10.0, 36.0]).is_ok());
        assert!(ok(series | each, &[0.0, 1.0, 0.0, 350.0, 10.0, 36.0]).is_ok());
        assert_eq!(
            ok(series | each, &[0.0, 1.0, 0.0, 0.0, 10.0, 37.0]).map(|_| ()),
            turn
        );
        assert_eq!(
            ok(series | each, &[0.0, 1.0, 0.0, 0.0, 361.0, 0.0]).map(|_| ()),
            turn
        );
        assert_eq!(
            ok(series, &[0.0, 1.0, 0.0, 0.0, 10.0, 0.0]).map(|_| ()),
            Err(NackCode::CompareMode)
        );
        // A pitch of a seventh of the turn in decimals: 7 a turn.
        let a = ok(series | each, &[0.0, 1.0, 0.0, 0.0, m / 7.0, 0.0]).unwrap();
        assert!(matches!(a.source, Source::Series { count: 7, .. }));
        let a = ok(series | each, &[0.0, 1.0, 0.0, 0.0, 7.0, 0.0]).unwrap();
        assert!(matches!(a.source, Source::Series { count: 51, .. }));
        assert_eq!(
            validate_arm(0, single | each, &[0.0, 1.0, 0.0, 5.0], 10_000, 1).unwrap_err(),
            NackCode::CompareTurn
        );
        assert_eq!(
            ok(
                raw::MC_CMP_MODE_TABLE | raw::MC_CMP_DIR_POS | each,
                &[0.0, 1.0, 0.0]
            )
            .map(|_| ()),
            Err(NackCode::CompareMode)
        );
        // A table queued before the arm keeps the linear order; the arm on a turn checks it.
        let mut c = Compare::new();
        c.queue(1, &[10.0, 400.0]).unwrap();
        let t = turn_arm(1, Source::Table, m, false);
        assert_eq!(c.start(t), Err(NackCode::CompareTurn));
        assert_eq!(c.status().state, raw::MC_IO_IDLE, "nothing changed");
        c.stop();
        c.queue(1, &[10.0, 300.0]).unwrap();
        c.start(t).unwrap();
        assert_eq!(c.queue(1, &[360.0]), Err(NackCode::CompareTurn));
        assert_eq!(
            c.queue(1, &[20.0, 20.0, 5.0]),
            Ok(COMPARE_TABLE_LEN as u32 - 5)
        );
        // 10, 300, then 20, 20 (a turn later), 5: from 0.5 up 100 counts a tick.
        let (fires, _) = run(&mut c, |k| 0.5 + 100.0 * k as f64, 12);
        let at: Vec<f64> = fires.iter().map(|f| f.1 * 100.0 + 0.5).collect();
        let want = [10.0, 300.0, 380.0, 740.0, 1085.0];
        assert_eq!(
            fires.iter().map(|f| f.0).collect::<Vec<_>>(),
            [10.0, 300.0, 20.0, 20.0, 5.0]
        );
        for (a, w) in at.iter().zip(want) {
            assert!((a - w).abs() < 1e-9, "{a} vs {w}");
        }
    }
}

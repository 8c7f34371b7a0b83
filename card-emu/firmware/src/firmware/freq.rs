//! Layout 1.12: the frequency response measured on the card: a stepped sine injected into one
//! axis's servo loop (on the position reference or on the servo output), correlated at the
//! servo rate with the injected sine, the encoder position and the DAC output (a single-bin
//! DFT over whole periods), point by point into `freq_status`. The header's comment before
//! `MC_OP_FREQ_START` is the contract.
//!
//! Each point runs whole measurement windows of `m` ticks holding exactly `c` periods: the
//! phase of tick `n` of a window is `2π·((c·n) mod m)/m`, computed from integers, so it never
//! drifts, every window starts at phase 0 (the sine goes on continuously from window to window
//! and from point to point), and over a window the DFT's bin is exact: a constant (the
//! position held, the DAC's offset) and every harmonic sum to zero. The first windows of a
//! point let the loop settle; the last is measured.

use super::axis::{Axis, Injection};
use crate::math;
use firmware_proto::cmd::{FreqMode, FreqStart};
use firmware_proto::{raw, AxisSafetyFlags, NackCode, MAX_POSITION};

/// The sweep in progress.
#[derive(Debug, Clone)]
pub struct Sweep {
    /// The axis swept.
    pub axis: usize,
    /// Its `MC_OP_FREQ_START`'s seq.
    pub seq: u32,
    start: FreqStart,
    rate: f64,
    /// The position held at the start, counts.
    hold: f64,
    /// The point running.
    point: u16,
    /// Its window: ticks, periods, the settle windows before the measured one.
    m: u32,
    c: u32,
    settle: u32,
    /// The window running (`settle` is the measured one) and its tick.
    window: u32,
    n: u32,
    /// This tick's sine and its cosine and sine of the phase.
    value: f64,
    cs: (f64, f64),
    /// The correlations of d, x, u: re, im each.
    acc: [f64; 6],
}

/// What a tick of the sweep produced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Progress {
    /// Nothing to write.
    Running,
    /// Point `k` measured.
    Point(u16, raw::mc_freq_point),
    /// Point `k` measured, and it was the last.
    Done(u16, raw::mc_freq_point),
}

/// Check a sweep against the axis and the card: `MC_NACK_FREQ_RANGE`, `_AMPLITUDE`,
/// `_LIMITS` (the header's order: range, amplitude, limits).
pub fn check(s: &FreqStart, axis: &Axis, rate_hz: u32) -> Result<(), NackCode> {
    let all = [s.from_hz, s.to_hz, s.amplitude, s.settle_s];
    if all.iter().any(|x| !x.is_finite()) {
        return Err(NackCode::NotFinite);
    }
    let quarter = rate_hz as f64 / 4.0;
    let in_range = raw::MC_FREQ_MIN_HZ <= s.from_hz
        && s.from_hz <= s.to_hz
        && s.to_hz <= quarter
        && (0.0..=raw::MC_FREQ_SETTLE_MAX).contains(&s.settle_s);
    if !in_range {
        return Err(NackCode::FreqRange);
    }
    if s.amplitude <= 0.0 {
        return Err(NackCode::FreqAmplitude);
    }
    match s.mode {
        FreqMode::Output => {
            if s.amplitude > axis.config.dac_limit_v {
                return Err(NackCode::FreqAmplitude);
            }
        }
        FreqMode::Reference => {
            let w = 2.0 * core::f64::consts::PI * s.to_hz;
            let c = &axis.safety.config;
            let amax = *firmware_proto::limit_range(2, rate_hz).end();
            let (hold, _) = axis.actual();
            let soft = c.has(AxisSafetyFlags::SOFT_LIMITS) && axis.homed() && !axis.is_modulo();
            let out_of_soft = soft
                && (hold + s.amplitude > c.soft_limit_pos || hold - s.amplitude < c.soft_limit_neg);
            if s.amplitude * w > c.max_velocity
                || s.amplitude * w * w > amax
                || 2.0 * s.amplitude > c.min_ferror
                || s.amplitude > MAX_POSITION
                || out_of_soft
            {
                return Err(NackCode::FreqLimits);
            }
        }
    }
    Ok(())
}

impl Sweep {
    /// A sweep of `axis` (checked) by command `seq`, from the position it holds.
    pub fn new(axis_index: usize, seq: u32, start: FreqStart, axis: &Axis, rate_hz: u32) -> Self {
        let mut s = Self {
            axis: axis_index,
            seq,
            start,
            rate: rate_hz as f64,
            hold: axis.actual().0,
            point: 0,
            m: 1,
            c: 1,
            settle: 1,
            window: 0,
            n: 0,
            value: 0.0,
            cs: (1.0, 0.0),
            acc: [0.0; 6],
        };
        s.begin_point();
        s
    }

    /// What `freq_status`'s header holds for this sweep in `state` with `done` points.
    pub fn header(&self, state: u32, done: u32) -> raw::mc_freq_status {
        raw::mc_freq_status {
            state,
            axis: self.axis as u32,
            mode: self.start.mode.code(),
            points: self.start.points as u32,
            done,
            seq: self.seq,
            cycles: self.start.cycles as u32,
            from_hz: self.start.from_hz,
            to_hz: self.start.to_hz,
            amplitude: self.start.amplitude,
            settle_s: self.start.settle_s,
            hold_pos: self.hold,
            ..Default::default()
        }
    }

    /// The frequency asked for at point `k`: log-spaced from `from_hz` to `to_hz`.
    fn asked_hz(&self, k: u16) -> f64 {
        let s = &self.start;
        if s.points <= 1 || s.to_hz == s.from_hz {
            return s.from_hz;
        }
        let t = k as f64 / (s.points - 1) as f64;
        s.from_hz * math::powf(s.to_hz / s.from_hz, t)
    }

    /// The frequency run at the point in progress, Hz.
    pub fn hz(&self) -> f64 {
        self.c as f64 * self.rate / self.m as f64
    }

    /// Lay out the point `self.point`: its window (at least `cycles` periods and
    /// `MC_FREQ_WINDOW_MIN` ticks) and its settle windows (at least one, covering settle_s).
    fn begin_point(&mut self) {
        let f = self.asked_hz(self.point);
        let per_period = self.rate / f;
        let min_c = math::ceil(raw::MC_FREQ_WINDOW_MIN as f64 / per_period);
        let c = (self.start.cycles as f64).max(min_c);
        let m = math::round(c * per_period).max(4.0);
        self.c = c as u32;
        self.m = m as u32;
        let settle = math::ceil(self.start.settle_s * self.rate / m).max(1.0);
        self.settle = settle.min(u32::MAX as f64) as u32;
        self.window = 0;
        self.n = 0;
        self.acc = [0.0; 6];
    }

    /// This tick's injection (call before the axis's servo runs).
    pub fn injection(&mut self) -> Injection {
        let phase = ((self.c as u64 * self.n as u64) % self.m as u64) as f64 / self.m as f64;
        let (s, c) = math::sin_cos(2.0 * core::f64::consts::PI * phase);
        self.cs = (c, s);
        // The first window of the sweep ramps the amplitude up from 0: a sine force started
        // at full amplitude from rest leaves the shaft a mean velocity of A/ω (its integral,
        // A(1 − cos)/ω, starts at 0), a drift a slow loop would take long to correct. The
        // ramp is a settle window, never measured.
        let envelope = if self.point == 0 && self.window == 0 {
            self.n as f64 / self.m as f64
        } else {
            1.0
        };
        self.value = self.start.amplitude * envelope * s;
        match self.start.mode {
            FreqMode::Reference => Injection {
                reference: self.value,
                output: 0.0,
            },
            FreqMode::Output => Injection {
                reference: 0.0,
                output: self.value,
            },
        }
    }

    /// The sine of the tick (the scope's `MC_SIG_FREQ_INJECT`).
    pub fn value(&self) -> f64 {
        self.value
    }

    /// Take this tick's measurements (after the safety layer: `dac` is what went out) and
    /// move on by a tick.
    pub fn sample(&mut self, position: f64, dac: f64) -> Progress {
        if self.window == self.settle {
            let (c, s) = self.cs;
            let x = position - self.hold;
            for (k, y) in [self.value, x, dac].into_iter().enumerate() {
                self.acc[2 * k] += y * c;
                self.acc[2 * k + 1] -= y * s;
            }
        }
        self.n += 1;
        if self.n < self.m {
            return Progress::Running;
        }
        self.n = 0;
        if self.window < self.settle {
            self.window += 1;
            return Progress::Running;
        }
        let g = 2.0 / self.m as f64;
        let a = self.acc;
        let p = raw::mc_freq_point {
            hz: self.hz(),
            d_re: a[0] * g,
            d_im: a[1] * g,
            x_re: a[2] * g,
            x_im: a[3] * g,
            u_re: a[4] * g,
            u_im: a[5] * g,
            window: self.m,
            _reserved0: 0,
        };
        let k = self.point;
        self.point += 1;
        if self.point >= self.start.points {
            return Progress::Done(k, p);
        }
        self.begin_point();
        Progress::Point(k, p)
    }
}

impl Sweep {
    /// The points measured so far.
    pub fn done(&self) -> u16 {
        self.point
    }
}

impl<M: firmware_proto::Mem + Clone> super::Firmware<M> {
    /// `MC_OP_FREQ_START` on axis `ax` (command `seq`): one sweep at a time, on an axis
    /// enabled and holding its position, checked (freq.rs `check`).
    pub(super) fn execute_freq_start(
        &mut self,
        seq: u32,
        ax: usize,
        start: &FreqStart,
    ) -> Result<f64, NackCode> {
        let rate = self.servo_rate_hz;
        check(start, &self.axes[ax], rate)?;
        if self.sweep.is_some() {
            return Err(NackCode::FreqBusy);
        }
        let axis = &self.axes[ax];
        if !axis.is_powered() || axis.state == firmware_proto::AxisState::Disabled {
            return Err(NackCode::AxisDisabled);
        }
        if !axis.holding() {
            return Err(NackCode::InvalidState);
        }
        let sw = Sweep::new(ax, seq, *start, axis, rate);
        write_header(&self.mem, &sw.header(raw::MC_FREQ_RUNNING, 0));
        self.sweep = Some(sw);
        Ok(0.0)
    }

    /// `MC_OP_FREQ_STOP`: the sweep running ends (none: nothing changes).
    pub(super) fn execute_freq_stop(&mut self) -> Result<f64, NackCode> {
        self.end_sweep(raw::MC_FREQ_ABORTED);
        Ok(0.0)
    }

    /// A command on axis `ax` while a sweep runs on it: a halt, stop, power-off or reset ends
    /// the sweep and goes on; the settings that do not move the axis pass; anything else that
    /// would move it or change its frame is refused (`MC_NACK_FREQ_BUSY`).
    pub(super) fn sweep_gate(
        &mut self,
        ax: usize,
        cmd: &firmware_proto::cmd::AxisCmd,
    ) -> Result<(), NackCode> {
        use firmware_proto::cmd::AxisCmd as C;
        if self.sweep.as_ref().is_none_or(|s| s.axis != ax) {
            return Ok(());
        }
        match cmd {
            C::Halt(_) | C::Stop(_) | C::PowerOff | C::Reset => {
                self.end_sweep(raw::MC_FREQ_ABORTED);
                Ok(())
            }
            C::PowerOn
            | C::SetOverride(_)
            | C::StopRelease
            | C::CompRead(_)
            | C::ServoFilterSet(_)
            | C::ServoFilterClear(_)
            | C::FreqStart(_)
            | C::FreqStop => Ok(()),
            _ => Err(NackCode::FreqBusy),
        }
    }

    /// The sweep's measurement of the tick, after the safety layer (`dac`: what went out);
    /// the axis no longer holding its position (a safety stop, a group or coupling took it)
    /// ends it.
    pub(super) fn sweep_tick(&mut self, dac: &[f64; firmware_proto::MAX_AXES]) {
        let Some(sw) = self.sweep.as_mut() else {
            return;
        };
        let a = sw.axis;
        if !self.axes[a].holding() {
            self.end_sweep(raw::MC_FREQ_ABORTED);
            return;
        }
        let progress = sw.sample(self.axes[a].actual().0, dac[a]);
        let status = firmware_proto::layout::FREQ_STATUS;
        let field = |f: usize| status.offset() + f;
        match progress {
            Progress::Running => {}
            Progress::Point(k, p) | Progress::Done(k, p) => {
                let at = field(core::mem::offset_of!(raw::mc_freq_status, point))
                    + k as usize * core::mem::size_of::<raw::mc_freq_point>();
                firmware_proto::BlockAt::<raw::mc_freq_point>::new(at).write(&self.mem, &p);
                self.mem.store32(
                    field(core::mem::offset_of!(raw::mc_freq_status, done)),
                    k as u32 + 1,
                    core::sync::atomic::Ordering::Release,
                );
                if let Progress::Done(..) = progress {
                    self.end_sweep(raw::MC_FREQ_DONE);
                }
            }
        }
    }

    /// End the sweep running (if any) in `state`: the sine off, the header written, the
    /// event to post after the status.
    fn end_sweep(&mut self, state: u32) {
        let Some(sw) = self.sweep.take() else {
            return;
        };
        self.axes[sw.axis].set_injection(Injection::default());
        let done = sw.done() as u32;
        write_header(&self.mem, &sw.header(state, done));
        self.sweep_event = Some(firmware_proto::Event {
            seq: sw.seq,
            kind: firmware_proto::EventKind::FreqDone as u16,
            axis: sw.axis as u16,
            code: state as i32,
            tick: self.tick,
            value: done as f64,
        });
    }
}

/// The scope's `MC_SIG_FREQ_HZ` (`hz`) or `MC_SIG_FREQ_INJECT` of the sweep's axis.
pub fn signal(s: &Sweep, hz: bool) -> f64 {
    if hz {
        s.hz()
    } else {
        s.value()
    }
}

/// Write `h`'s header, every field before the points (the points measured stay): the fields
/// after `state` first, `state` last.
fn write_header<M: firmware_proto::Mem>(mem: &M, h: &raw::mc_freq_status) {
    use core::mem::offset_of;
    type S = raw::mc_freq_status;
    let at = |f: usize| firmware_proto::layout::FREQ_STATUS.field(f);
    for (f, v) in [
        (offset_of!(S, axis), h.axis),
        (offset_of!(S, mode), h.mode),
        (offset_of!(S, points), h.points),
        (offset_of!(S, done), h.done),
        (offset_of!(S, seq), h.seq),
        (offset_of!(S, cycles), h.cycles),
    ] {
        mem.write32(at(f), v);
    }
    for (f, v) in [
        (offset_of!(S, from_hz), h.from_hz),
        (offset_of!(S, to_hz), h.to_hz),
        (offset_of!(S, amplitude), h.amplitude),
        (offset_of!(S, settle_s), h.settle_s),
        (offset_of!(S, hold_pos), h.hold_pos),
    ] {
        mem.write64(at(f), v.to_bits());
    }
    mem.store32(
        at(offset_of!(S, state)),
        h.state,
        core::sync::atomic::Ordering::Release,
    );
}

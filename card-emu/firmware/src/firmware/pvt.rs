//! PT/PVT streaming (layout 1.7): per axis, a buffer of [`PVT_LEN`] points run as cubic
//! Hermite segments (`motion::pvt`), stepped by `Firmware::tick` after gearing and before the
//! servo loops. The register map's header (`MC_OP_PVT_BEGIN`) states the protocol.
//!
//! - `MC_OP_PVT_BEGIN` opens a stream at the axis's commanded position, at rest, time 0, with
//!   its limits and low water; its buffer is made the first time the axis streams (the command
//!   manager's allocation) and kept for the card's life: the tick never touches the heap.
//! - `MC_OP_PVT_POINTS` appends up to [`PVT_POINTS_MAX`] points, all or none: each is checked
//!   (finite, in range, a servo period or more after the one before), and every segment whose
//!   end velocity is known (PVT: at once; PT: when the next point, or the last mark, gives it)
//!   against the limits (`check_segment`, exact).
//! - `MC_OP_PVT_START` runs the streams of an axis mask from the same tick. Time is the tick
//!   count over the rate (no sum of periods), so a point time that is a whole number of
//!   periods is met on its tick, where the position is the point's exactly.
//! - The stream ends at its last point (done, then motion done in position), or it runs dry
//!   (starved: the axis stops on its stop ramp), or a halt, stop or safety stop ends it.
#![forbid(unsafe_code)]

use crate::firmware::axis::Axis;
use crate::firmware::Firmware;
use crate::math;
use crate::motion::pvt::{
    check_point, check_segment, pt_velocity, sample, PvtError, PvtLimits, PvtPoint,
};
use crate::ram::Lazy;
use crate::servo::ffpiv::Reference;
use firmware_proto::cmd;
use firmware_proto::{
    AxisState, EventKind, Mem, NackCode, Opcode, PvtEvent, MAX_AXES, MAX_MOVE_TIME, PVT_LEN,
    PVT_POINTS_MAX,
};
use heapless::{Deque, Vec};

/// One buffered point: its velocity may still be unknown (PT, the newest point).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Slot {
    pt: PvtPoint,
    known: bool,
    last: bool,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase {
    /// No stream.
    Idle,
    /// Opened, loading points.
    Loading,
    /// Running since `start_tick` (the ticks since the start, `k`).
    Running { k: u64 },
}

/// One axis's stream.
#[derive(Debug)]
pub struct PvtStream {
    phase: Phase,
    pt_mode: bool,
    lim: PvtLimits,
    low_water: u32,
    low_armed: bool,
    /// The start of the segment running (the origin, then the last point passed).
    prev: Slot,
    /// The point before the newest (PT: the estimate of the newest's velocity needs it).
    before_back: PvtPoint,
    /// A point marked last was queued.
    closed: bool,
    seq: u32,
    buf: Deque<Slot, PVT_LEN>,
}

/// What a tick of the streams tells the command manager.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PvtReport {
    /// (seq, event, value) of an `MC_EV_PVT`.
    pub event: Option<(u32, PvtEvent, f64)>,
    /// The low water was reached: (seq, points queued).
    pub low: Option<(u32, f64)>,
    /// The stream of `seq` ran dry: its motion is aborted.
    pub aborted: Option<u32>,
    /// The axis's state changed from this one.
    pub state_from: Option<AxisState>,
}

impl PvtStream {
    fn new() -> Self {
        Self {
            phase: Phase::Idle,
            pt_mode: false,
            lim: PvtLimits {
                vmax: 1.0,
                amax: 1.0,
            },
            low_water: 0,
            low_armed: false,
            prev: Slot::default(),
            before_back: PvtPoint::default(),
            closed: false,
            seq: 0,
            buf: Deque::new(),
        }
    }

    /// Points queued.
    pub fn queued(&self) -> usize {
        self.buf.len()
    }

    /// Points free.
    pub fn free(&self) -> usize {
        PVT_LEN - self.buf.len()
    }

    /// Is the stream running?
    pub fn running(&self) -> bool {
        matches!(self.phase, Phase::Running { .. })
    }

    /// The newest point (or the origin).
    fn back(&self) -> Slot {
        self.buf.back().copied().unwrap_or(self.prev)
    }

    /// `MC_OP_PVT_POINTS`: append `pts` (the last one marked last when `last`), all or none.
    fn push(&mut self, pts: &[PvtPoint], last: bool, ts: f64) -> Result<(), NackCode> {
        if self.phase == Phase::Idle || self.closed {
            return Err(NackCode::PvtSequence);
        }
        if pts.len() > self.free() {
            return Err(NackCode::QueueFull);
        }
        let nack = |e: PvtError| match e {
            PvtError::NotFinite => NackCode::NotFinite,
            PvtError::Time => NackCode::PvtTime,
            PvtError::Position => NackCode::OutOfRange,
            PvtError::Limit => NackCode::PvtLimit,
        };
        // Staged: the newest point's velocity (PT), then the new points.
        let (mut a, mut b) = (self.before_back, self.back());
        let mut back_v = None;
        let mut staged: Vec<Slot, PVT_POINTS_MAX> = Vec::new();
        for (i, p) in pts.iter().enumerate() {
            check_point(&b.pt, p, ts, MAX_MOVE_TIME).map_err(nack)?;
            let is_last = last && i + 1 == pts.len();
            if is_last && !self.pt_mode && p.v != 0.0 {
                // The last point ends at rest.
                return Err(NackCode::PvtLimit);
            }
            let mut n = Slot {
                pt: *p,
                known: !self.pt_mode,
                last: is_last,
            };
            if self.pt_mode {
                n.pt.v = 0.0;
                if !b.known {
                    b.pt.v = pt_velocity(&a, &b.pt, &n.pt);
                    b.known = true;
                    check_segment(&a, &b.pt, &self.lim).map_err(nack)?;
                    match staged.last_mut() {
                        Some(s) => *s = b,
                        None => back_v = Some(b.pt.v),
                    }
                }
                n.known = is_last;
            }
            if n.known {
                check_segment(&b.pt, &n.pt, &self.lim).map_err(nack)?;
            }
            let _ = staged.push(n); // at most PVT_POINTS_MAX: checked by the caller
            a = b.pt;
            b = n;
        }
        if let Some(v) = back_v {
            match self.buf.back_mut() {
                Some(s) => {
                    s.pt.v = v;
                    s.known = true;
                }
                None => self.prev.known = true,
            }
        }
        for s in staged {
            let _ = self.buf.push_back(s); // room checked above
        }
        self.before_back = a;
        self.closed = last;
        if self.buf.len() > self.low_water as usize {
            self.low_armed = true;
        }
        Ok(())
    }

    /// One tick of a running stream: drive `axis`.
    fn tick(&mut self, axis: &mut Axis, rate_hz: u32, max_stop_time: f64) -> PvtReport {
        let mut report = PvtReport::default();
        let Phase::Running { k } = &mut self.phase else {
            return report;
        };
        if axis.state != AxisState::SynchronizedMotion {
            // A halt, stop, power off or safety stop ended it (and reported its end).
            self.phase = Phase::Idle;
            self.buf.clear();
            return report;
        }
        *k += 1;
        let t = *k as f64 / rate_hz as f64;
        while let Some(f) = self.buf.front().copied() {
            if !(f.known && t >= f.pt.t) {
                break;
            }
            self.prev = f;
            let _ = self.buf.pop_front();
            if self.low_armed && self.buf.len() <= self.low_water as usize && !f.last {
                self.low_armed = false;
                report.low = Some((self.seq, self.buf.len() as f64));
            }
        }
        let prev = self.prev;
        if prev.last {
            axis.drive(Reference {
                pos: prev.pt.p,
                vel: 0.0,
                acc: 0.0,
            });
            report.state_from = axis.end_stream(prev.pt.p);
            report.event = Some((self.seq, PvtEvent::Done, prev.pt.p));
            self.phase = Phase::Idle;
            return report;
        }
        match self.buf.front() {
            Some(f) if f.known => {
                let (pos, vel, acc) = sample(&prev.pt, &f.pt, t - prev.pt.t);
                axis.drive(Reference { pos, vel, acc });
            }
            _ => {
                // Dry: from the last point passed (its position and velocity, the last
                // acceleration commanded), a stop on the axis's stop ramp.
                let acc = axis.reference().acc;
                axis.drive(Reference {
                    pos: prev.pt.p,
                    vel: prev.pt.v,
                    acc,
                });
                report.state_from = axis.sync_stop(max_stop_time, true);
                report.event = Some((self.seq, PvtEvent::Starved, prev.pt.t));
                report.aborted = Some(self.seq);
                self.phase = Phase::Idle;
                self.buf.clear();
            }
        }
        report
    }
}

/// Every axis's stream slot, made on the axis's first `MC_OP_PVT_BEGIN`.
pub type PvtStreams = [Lazy<PvtStream>; MAX_AXES];

// ---- The command manager's and the control loop's side (Firmware's fields are the parent's) ----
impl<M: Mem + Clone> Firmware<M> {
    /// One axis's PT/PVT stream (for inspection by tests), once it has one.
    pub fn pvt(&self, i: usize) -> Option<&PvtStream> {
        self.pvt.get(i).and_then(|s| s.as_ref())
    }

    /// `MC_OP_PVT_BEGIN` on axis `ax` (one of the card's, not in an enabled group, no latch):
    /// the old state and the ack's value (the points free), or the nack.
    pub(super) fn pvt_begin(
        &mut self,
        ax: usize,
        b: &cmd::PvtBegin,
    ) -> Result<(Option<AxisState>, f64), NackCode> {
        let a = [b.vmax, b.amax, b.low_water];
        if a.iter().any(|x| !x.is_finite()) {
            return Err(NackCode::NotFinite);
        }
        crate::firmware::nack::check_ranges(self.servo_rate_hz, &[(1, a[0]), (2, a[1])])?;
        let lw = a[2];
        if math::fract(lw) != 0.0 || !(0.0..PVT_LEN as f64).contains(&lw) {
            return Err(NackCode::OutOfRange);
        }
        if b.other_flags != 0 {
            return Err(NackCode::BadConfig);
        }
        if self.pvt[ax].as_ref().is_some_and(|s| s.running()) {
            return Err(NackCode::PvtSequence);
        }
        let axis = &self.axes[ax];
        match axis.state {
            AxisState::Standstill => {}
            AxisState::Disabled => return Err(NackCode::AxisDisabled),
            AxisState::Homing => return Err(NackCode::AxisHoming),
            _ => return Err(NackCode::InvalidState),
        }
        let origin = PvtPoint {
            t: 0.0,
            p: axis.reference().pos,
            v: 0.0,
        };
        let s = self.pvt[ax].get_or_insert_with(PvtStream::new);
        s.buf.clear();
        s.phase = Phase::Loading;
        s.pt_mode = b.pt;
        s.lim = PvtLimits {
            vmax: a[0],
            amax: a[1],
        };
        s.low_water = lw as u32;
        s.low_armed = false;
        s.prev = Slot {
            pt: origin,
            known: true,
            last: false,
        };
        s.before_back = origin;
        s.closed = false;
        Ok((None, s.free() as f64))
    }

    /// `MC_OP_PVT_POINTS` on axis `ax`: the ack's value is the points still free.
    pub(super) fn pvt_points(
        &mut self,
        ax: usize,
        p: &cmd::PvtPoints,
    ) -> Result<(Option<AxisState>, f64), NackCode> {
        let ts = self.ts();
        let mut pts: Vec<PvtPoint, PVT_POINTS_MAX> = Vec::new();
        for q in &p.points {
            let _ = pts.push(PvtPoint {
                t: q.time,
                p: q.position,
                v: q.velocity,
            });
        }
        let s = self.pvt[ax].as_mut().ok_or(NackCode::PvtSequence)?;
        s.push(&pts, p.last, ts)?;
        Ok((None, s.free() as f64))
    }

    /// `MC_OP_PVT_START` (command `seq`) over a mask of axes (0: axis `ax`): all checked, then
    /// all started.
    pub(super) fn pvt_start(
        &mut self,
        seq: u32,
        ax: usize,
        st: &cmd::PvtStart,
    ) -> Result<(Option<AxisState>, f64), NackCode> {
        let all = (1u32 << self.num_axes) - 1;
        if st.mask > all {
            return Err(NackCode::BadAxis);
        }
        let mask = if st.mask == 0 { 1 << ax } else { st.mask };
        let members = (0..self.num_axes).filter(|i| mask & (1 << i) != 0);
        for i in members.clone() {
            let ok = self.pvt[i].as_ref().is_some_and(|s| {
                s.phase == Phase::Loading
                    && !s.buf.is_empty()
                    && self.axes[i].state == AxisState::Standstill
                    && self.axes[i].reference().pos == s.prev.pt.p
            });
            let grouped = self.groups.iter().any(|g| g.owns_enabled(i));
            if !ok || grouped {
                return Err(NackCode::PvtSequence);
            }
        }
        let mut changed = None;
        for i in members {
            let was = self.axes[i].begin_sync(seq)?;
            if i == ax {
                changed = was;
            } else if let Some(old) = was {
                let e = super::state_event(i as u16, old, self.axes[i].state, self.tick);
                self.outbox.push(e);
            }
            if let Some(s) = self.pvt[i].as_mut() {
                s.phase = Phase::Running { k: 0 };
                s.seq = seq;
            }
        }
        Ok((changed, 0.0))
    }

    /// The PT/PVT step of a tick.
    /// `None` when no stream runs: each stream's step returns at once then, with nothing to
    /// post.
    pub(super) fn pvt_tick(&mut self) -> Option<[PvtReport; MAX_AXES]> {
        let running = self.pvt[..self.num_axes]
            .iter()
            .any(|s| s.as_ref().is_some_and(|s| s.running()));
        if !running {
            return None;
        }
        Some(self.pvt_step())
    }

    /// The streams' step, some running.
    #[inline(never)]
    fn pvt_step(&mut self) -> [PvtReport; MAX_AXES] {
        let (rate, n) = (self.servo_rate_hz, self.num_axes);
        let max_stop_time = self.safety.config().max_stop_time();
        core::array::from_fn(
            |i| match (self.pvt[i].as_mut(), self.axes[..n].get_mut(i)) {
                (Some(s), Some(axis)) => s.tick(axis, rate, max_stop_time),
                _ => PvtReport::default(),
            },
        )
    }

    /// Post the events of a PT/PVT step (after the status was published).
    pub(super) fn post_pvt_events(&mut self, reports: &Option<[PvtReport; MAX_AXES]>) {
        let Some(reports) = reports else { return };
        for (i, r) in reports[..self.num_axes].iter().enumerate() {
            let axis = i as u16;
            let tick = self.tick;
            if let Some((seq, value)) = r.low {
                self.post_axis_event(EventKind::Pvt, seq, axis, PvtEvent::LowWater as i32, value);
            }
            if let Some((seq, what, value)) = r.event {
                self.post_axis_event(EventKind::Pvt, seq, axis, what as i32, value);
            }
            if let Some(seq) = r.aborted {
                self.post_axis_event(
                    EventKind::MotionAborted,
                    seq,
                    axis,
                    Opcode::Halt as i32,
                    0.0,
                );
            }
            if let Some(old) = r.state_from {
                let e = super::state_event(axis, old, self.axes[i].state, tick);
                self.post(e);
            }
        }
    }

    /// The streams' words of the synchronised-motion status block.
    pub(super) fn pvt_status(&self) -> ([u32; MAX_AXES], [u32; MAX_AXES]) {
        let mut q = [0u32; MAX_AXES];
        let mut f = [0u32; MAX_AXES];
        for i in 0..self.num_axes {
            (q[i], f[i]) = self.pvt[i].as_ref().map_or((0, PVT_LEN as u32), |s| {
                (s.queued() as u32, s.free() as u32)
            });
        }
        (q, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stream(pt_mode: bool) -> PvtStream {
        let mut s = PvtStream::new();
        s.phase = Phase::Loading;
        s.pt_mode = pt_mode;
        s.lim = PvtLimits {
            vmax: 1e4,
            amax: 1e6,
        };
        s.prev.known = true;
        s
    }

    fn p(t: f64, p: f64, v: f64) -> PvtPoint {
        PvtPoint { t, p, v }
    }

    #[test]
    fn a_refused_command_changes_nothing() {
        let mut s = stream(false);
        s.push(&[p(0.01, 10.0, 1000.0)], false, 1e-4).unwrap();
        // The second point of this command breaks the velocity limit: neither is taken.
        let e = s.push(&[p(0.02, 20.0, 1000.0), p(0.03, 300.0, 0.0)], false, 1e-4);
        assert_eq!(e, Err(NackCode::PvtLimit));
        assert_eq!(s.queued(), 1);
        assert_eq!(
            s.push(&[p(0.02, 20.0, f64::NAN)], false, 1e-4),
            Err(NackCode::NotFinite)
        );
        assert_eq!(
            s.push(&[p(0.01, 20.0, 0.0)], false, 1e-4),
            Err(NackCode::PvtTime)
        );
        assert_eq!(
            s.push(&[p(0.02, 20.0, 1000.0)], true, 1e-4),
            Err(NackCode::PvtLimit),
            "a last point ends at rest"
        );
        s.push(&[p(0.02, 20.0, 0.0)], true, 1e-4).unwrap();
        assert_eq!(s.queued(), 2);
        assert_eq!(
            s.push(&[p(0.03, 30.0, 0.0)], false, 1e-4),
            Err(NackCode::PvtSequence),
            "after the last point"
        );
    }

    #[test]
    fn pt_velocities_arrive_with_the_next_point() {
        let mut s = stream(true);
        s.push(&[p(0.1, 100.0, 0.0)], false, 1e-4).unwrap();
        assert!(!s.buf.back().unwrap().known);
        s.push(&[p(0.2, 300.0, 0.0), p(0.3, 400.0, 0.0)], false, 1e-4)
            .unwrap();
        let b: std::vec::Vec<Slot> = s.buf.iter().copied().collect();
        // 0.1: chords 1000 and 2000 counts/s, equal durations: 1500.
        assert_eq!(b[0].pt.v, 1500.0);
        assert!(b[0].known && b[1].known && !b[2].known);
        s.push(&[p(0.4, 400.0, 0.0)], true, 1e-4).unwrap();
        let b: std::vec::Vec<Slot> = s.buf.iter().copied().collect();
        assert!(b.iter().all(|x| x.known));
        assert_eq!(b[3].pt.v, 0.0);
    }
}

//! PT/PVT streaming (layout 1.7), as Googol GTS's PVT mode and Delta Tau's PVT moves: an axis
//! runs through streamed points of (time, position) or (time, position, velocity), cubic
//! Hermite segments between them, exactly through every point with a continuous velocity.
//!
//! [`Axis::pvt_begin`] opens a stream where the axis stands (at rest, time 0) with its limits;
//! [`Axis::pvt_push`] appends points (times from the start); [`Axis::pvt_start`] (or
//! [`Card::pvt_start`] for several axes on one tick) runs it, and the returned motion is done
//! once the last point is reached and the axis is in position. The card holds
//! [`PVT_LEN`](firmware_proto::PVT_LEN) points per axis; [`Axis::pvt_free`] reads the room
//! left without a command, and a low-water event (`EventKind::Pvt`, code
//! [`PvtEvent::LowWater`](crate::PvtEvent::LowWater)) says when to send more. PT velocities
//! and the rules are in `card_firmware::motion::pvt` and the register map's header
//! (`MC_OP_PVT_BEGIN`).

use crate::card::{finite, positive, Axis, Card, Motion};
use crate::error::{nack_reason, Error, Result, Target};
use firmware_proto::cmd::{self, SyncCmd};
use firmware_proto::{layout, NackCode, MAX_MOVE_TIME, PVT_POINTS_MAX};

/// Why the card refused a point for its time (`PvtTime`), given how long after the point
/// before it comes (`None`: not known; the stream starts at time 0): too soon, or later than
/// the longest segment, [`MAX_MOVE_TIME`] (10⁶ s).
pub fn pvt_time_reason(gap: Option<f64>) -> &'static str {
    match gap {
        Some(h) if h > MAX_MOVE_TIME => {
            "a PT/PVT point must come at most 1e6 s (the longest move) after the one before"
        }
        Some(_) => "a PT/PVT point must come at least one servo period after the one before",
        None => nack_reason(NackCode::PvtTime),
    }
}

/// How the velocities at the points are given.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PvtMode {
    /// PT: the card estimates each point's velocity from its neighbours (the stream starts and,
    /// at a point pushed `last`, ends at rest); the velocities given are ignored.
    Pt,
    /// PVT: each point's velocity as given.
    Pvt,
}

/// One point, in the axis's user units: seconds from the stream's start, position, velocity.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PvtPoint {
    /// Seconds from the start of the stream (a whole number of servo periods to be met on a
    /// tick).
    pub time: f64,
    /// Position.
    pub position: f64,
    /// Velocity (PVT).
    pub velocity: f64,
}

impl PvtPoint {
    /// A point.
    pub fn new(time: f64, position: f64, velocity: f64) -> Self {
        Self {
            time,
            position,
            velocity,
        }
    }
}

/// A stream's limits, user units: every segment's velocity and acceleration stay within them
/// (else the point is refused, `PvtLimit`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PvtLimits {
    /// Velocity.
    pub velocity: f64,
    /// Acceleration.
    pub acceleration: f64,
}

impl Axis {
    /// Open a PT/PVT stream at the axis's commanded position (Standstill), at rest, time 0,
    /// within `limits`; a low-water event once `low_water` points or fewer are left (0: none).
    /// A stream loaded but not started is dropped.
    pub fn pvt_begin(&self, mode: PvtMode, limits: &PvtLimits, low_water: u32) -> Result<()> {
        positive("velocity", limits.velocity)?;
        positive("acceleration", limits.acceleration)?;
        let s = self.scale().abs();
        let begin = cmd::PvtBegin {
            vmax: limits.velocity * s,
            amax: limits.acceleration * s,
            low_water: low_water as f64,
            pt: mode == PvtMode::Pt,
            other_flags: 0,
        };
        self.run(self.cmd(SyncCmd::PvtBegin(begin)), "pvt_begin")
            .map(|_| ())
    }

    /// Append `points` to the stream (the last of them ends it when `last`), four to a
    /// command; returns the points still free on the card. A point the card refuses is
    /// [`Error::PvtPoint`] naming it (its kind the nack's: `PvtLimit`, `PvtTime`, `NotFinite`,
    /// `OutOfRange`, `QueueFull`, `PvtSequence`); the points before it were queued.
    pub fn pvt_push(&self, points: &[PvtPoint], last: bool) -> Result<usize> {
        let s = self.scale();
        let mut free = 0.0;
        let mut i = 0;
        while i < points.len() {
            let n = (points.len() - i).min(PVT_POINTS_MAX);
            match self.send_points(&points[i..i + n], last && i + n == points.len(), s) {
                Ok(f) => free = f,
                Err(Error::Nack { .. }) if n > 1 => {
                    // All or none: find the point, one at a time (those before it go in).
                    for (k, p) in points[i..i + n].iter().enumerate() {
                        let end = last && i + k + 1 == points.len();
                        free = self
                            .send_points(std::slice::from_ref(p), end, s)
                            .map_err(|e| self.point_error(e, points, i + k))?;
                    }
                }
                Err(e) => return Err(self.point_error(e, points, i)),
            }
            i += n;
        }
        Ok(free as usize)
    }

    fn send_points(&self, pts: &[PvtPoint], last: bool, s: f64) -> Result<f64> {
        // At most PVT_POINTS_MAX points (the caller's chunks).
        let points = pts
            .iter()
            .map(|p| {
                finite("point time", p.time)?;
                finite("point position", p.position)?;
                finite("point velocity", p.velocity)?;
                Ok(cmd::PvtPoint {
                    time: p.time,
                    position: p.position * s,
                    velocity: p.velocity * s,
                })
            })
            .collect::<Result<_>>()?;
        let c = self.cmd(SyncCmd::PvtPoints(cmd::PvtPoints { points, last }));
        self.card()
            .execute_value(c, "pvt_push", Target::Axis(self.index()))
            .map(|(_, free)| free)
    }

    /// The refusal of `points[index]` as [`Error::PvtPoint`] (the reason of a `PvtTime` from
    /// the point before it, when it is among `points`).
    fn point_error(&self, e: Error, points: &[PvtPoint], index: usize) -> Error {
        match e {
            Error::Nack { code, .. } => Error::PvtPoint {
                target: Target::Axis(self.index()),
                index,
                code,
                reason: match code {
                    NackCode::PvtTime => pvt_time_reason(
                        index
                            .checked_sub(1)
                            .map(|b| points[index].time - points[b].time),
                    ),
                    _ => nack_reason(code),
                },
            },
            e => e,
        }
    }

    /// Run this axis's stream (SynchronizedMotion): the motion is done once the last point is
    /// reached and the axis in position; it is `Aborted` if the stream runs dry first (the
    /// axis stops on its stop ramp) or by a halt, stop or safety stop.
    pub fn pvt_start(&self) -> Result<Motion> {
        let start = cmd::PvtStart { mask: 0 };
        let seq = self.run(self.cmd(SyncCmd::PvtStart(start)), "pvt_start")?;
        Ok(self.started(seq))
    }

    /// Points queued in the stream, and free, as the card published them last tick.
    pub fn pvt_room(&self) -> (usize, usize) {
        let b = layout::SYNC_STATUS.read(self.card().window());
        let i = self.index();
        (b.pvt_queued[i] as usize, b.pvt_free[i] as usize)
    }

    /// Points free in the stream (see [`Axis::pvt_room`]).
    pub fn pvt_free(&self) -> usize {
        self.pvt_room().1
    }
}

impl Card {
    /// Run the streams of `axes` from the same servo tick: one motion per axis (the same
    /// command).
    pub fn pvt_start(&self, axes: &[usize]) -> Result<Vec<Motion>> {
        let n = self.info().axes;
        let mut mask = 0u32;
        for &a in axes {
            if a >= n {
                return Err(Error::BadAxis { axis: a, count: n });
            }
            mask |= 1 << a;
        }
        let first = *axes.first().ok_or(Error::Refused {
            command: "pvt_start",
            target: Target::Card,
            code: NackCode::PvtSequence,
            reason: nack_reason(NackCode::PvtSequence),
        })?;
        let x = self.axis(first)?;
        let seq = x.run(
            x.cmd(SyncCmd::PvtStart(cmd::PvtStart { mask })),
            "pvt_start",
        )?;
        axes.iter()
            .map(|&a| Ok(self.axis(a)?.started(seq)))
            .collect()
    }
}

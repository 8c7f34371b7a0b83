//! Leadscrew pitch-error and backlash compensation (layout 1.9): a table per axis, loaded in
//! order (`MC_OP_COMP_TABLE`, then `MC_OP_COMP_DATA` entries) and read back
//! (`MC_OP_COMP_READ`). Single-axis commands: the target is the axis.
//!
//! Decoding refuses what makes an entry unreadable (a count or index that is not an integer in
//! range, unknown flags); the card checks the numbers (finite, ranges, order, bound) itself.

use super::{bit, put, set, uint, Args, DecodeError, Fault};
use crate::raw;
use crate::wire::{NackCode, CMD_ARGS};

/// Most points of a table (`MC_COMP_MAX_POINTS`).
pub const COMP_MAX_POINTS: usize = raw::MC_COMP_MAX_POINTS as usize;
/// Points per `MC_OP_COMP_DATA` entry.
pub const COMP_DATA_MAX: usize = raw::MC_COMP_DATA_MAX as usize;
/// Points per read-back (`MC_OP_COMP_READ`).
pub const COMP_READ_MAX: usize = raw::MC_COMP_READ_MAX as usize;
/// `MC_OP_COMP_TABLE` flag: a correction per direction.
pub const COMP_BIDIR: u32 = raw::MC_COMP_BIDIR;

const _: () = assert!(2 + 3 * COMP_DATA_MAX <= CMD_ARGS);

/// `MC_OP_COMP_TABLE` (args: points, bound, backlash, ramp velocity, ramp acceleration; flags:
/// `MC_COMP_BIDIR`). A count that is NaN is `MC_NACK_NOT_FINITE`; a count out of range or
/// other flags `MC_NACK_COMP_TABLE`. The other numbers are the card's to check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompHeader {
    /// Points that follow (0..=[`COMP_MAX_POINTS`]; 0: only the backlash, or off).
    pub points: u16,
    /// The largest |correction ± backlash/2|, counts.
    pub bound: f64,
    /// Backlash, counts.
    pub backlash: f64,
    /// The ramp's velocity, counts/s.
    pub ramp_vel: f64,
    /// The ramp's acceleration, counts/s².
    pub ramp_acc: f64,
    /// A correction per direction.
    pub bidir: bool,
}

impl Args for CompHeader {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        let a = [
            self.points as f64,
            self.bound,
            self.backlash,
            self.ramp_vel,
            self.ramp_acc,
        ];
        put(args, 0, &a);
        set(self.bidir, COMP_BIDIR)
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let bad = NackCode::CompTable;
        let points = uint(args, 0, COMP_MAX_POINTS as u64, NackCode::NotFinite, bad)? as u16;
        if flags & !COMP_BIDIR != 0 {
            return Err(DecodeError::flags(bad));
        }
        Ok(Self {
            points,
            bound: args[1],
            backlash: args[2],
            ramp_vel: args[3],
            ramp_acc: args[4],
            bidir: bit(flags, COMP_BIDIR),
        })
    }
}

/// One point: position, forward and reverse corrections, counts.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CompPointArgs {
    /// Position.
    pub position: f64,
    /// Correction moving forward.
    pub forward: f64,
    /// Correction moving in reverse.
    pub reverse: f64,
}

/// `MC_OP_COMP_DATA` (args: index of the first point, count (1..MC_COMP_DATA_MAX), then
/// position, forward, reverse of each). NaN index or count: `MC_NACK_NOT_FINITE`; out of
/// range: `MC_NACK_COMP_SEQUENCE`. The points' numbers are the card's to check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompData {
    /// The index of the first point.
    pub first: u16,
    /// Points in use (1..=[`COMP_DATA_MAX`]).
    pub count: u8,
    /// The points (`count` of them; the rest zero).
    pub point: [CompPointArgs; COMP_DATA_MAX],
}

impl CompData {
    /// The points in use.
    pub fn points(&self) -> &[CompPointArgs] {
        &self.point[..usize::from(self.count).min(COMP_DATA_MAX)]
    }

    /// An entry's worth of `points` (at most [`COMP_DATA_MAX`] taken) from index `first`.
    pub fn new(first: u16, points: &[CompPointArgs]) -> Self {
        let n = points.len().min(COMP_DATA_MAX);
        let mut point = [CompPointArgs::default(); COMP_DATA_MAX];
        point[..n].copy_from_slice(&points[..n]);
        Self {
            first,
            count: n as u8,
            point,
        }
    }
}

impl Args for CompData {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.first as f64, self.points().len() as f64]);
        for (k, p) in self.points().iter().enumerate() {
            put(args, 2 + 3 * k, &[p.position, p.forward, p.reverse]);
        }
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let seq = NackCode::CompSequence;
        let first = uint(
            args,
            0,
            COMP_MAX_POINTS as u64 - 1,
            NackCode::NotFinite,
            seq,
        )? as u16;
        let n = uint(args, 1, COMP_DATA_MAX as u64, NackCode::NotFinite, seq)? as usize;
        if n == 0 {
            return Err(DecodeError::arg(1, Fault::OutOfRange, seq));
        }
        let mut point = [CompPointArgs::default(); COMP_DATA_MAX];
        for (k, p) in point.iter_mut().enumerate().take(n) {
            *p = CompPointArgs {
                position: args[2 + 3 * k],
                forward: args[3 + 3 * k],
                reverse: args[4 + 3 * k],
            };
        }
        Ok(Self {
            first,
            count: n as u8,
            point,
        })
    }
}

/// `MC_OP_COMP_READ` (args: index of the first point, 0..=MC_COMP_MAX_POINTS). NaN:
/// `MC_NACK_NOT_FINITE`; out of range: `MC_NACK_COMP_SEQUENCE`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CompRead {
    /// The index of the first point to write into `comp_readback`.
    pub first: u16,
}

impl Args for CompRead {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        args[0] = self.first as f64;
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let seq = NackCode::CompSequence;
        let first = uint(args, 0, COMP_MAX_POINTS as u64, NackCode::NotFinite, seq)? as u16;
        Ok(Self { first })
    }
}

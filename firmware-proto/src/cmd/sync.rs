//! Synchronised motion (layout 1.7): electronic gearing, camming and PT/PVT streams. The
//! command's target is the slave or streaming axis (any axis for a cam table's commands).
//!
//! The card requires every argument of a gear, cam-in or cam-table command finite before it
//! looks at anything else, so their decoding checks that first.

use super::{all_finite, bit, not_in_family, put, set, uint, Args, DecodeError, Fault};
use crate::motion_sync::{
    MasterSource, AUX_ENCODERS, CAM_AT_CYCLE_END, CAM_CUBIC, CAM_DATA_MAX, CAM_MAX_POINTS,
    CAM_PERIODIC, CAM_RELATIVE, CAM_TABLES, PVT_LAST, PVT_POINTS_MAX, PVT_PT,
};
use crate::wire::{Command, NackCode, Opcode, CMD_ARGS};
use crate::MAX_AXES;
use heapless::Vec;

// The pairs of a cam data entry and the points of a PT/PVT entry fit in a command.
const _: () = assert!(3 + 2 * CAM_DATA_MAX <= CMD_ARGS);
const _: () = assert!(3 * PVT_POINTS_MAX < CMD_ARGS);

/// What a slave follows: the source (the flags) and its number (`args[0]`: the master axis, or
/// an auxiliary encoder). Decoding refuses an unknown source and a number that is not an
/// integer below [`MAX_AXES`] (an axis) or [`AUX_ENCODERS`] (`MC_NACK_SYNC_MASTER`); the card
/// checks the axis against its own axes and the slave.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Master {
    /// Commanded or actual position of an axis, or an auxiliary encoder.
    pub source: MasterSource,
    /// The axis or encoder number.
    pub index: u8,
}

impl Master {
    fn decode(source_bits: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let source =
            MasterSource::from_raw(source_bits).ok_or(DecodeError::flags(NackCode::SyncMaster))?;
        let count = match source {
            MasterSource::Aux => AUX_ENCODERS,
            _ => MAX_AXES,
        };
        let bad = NackCode::SyncMaster;
        let index = uint(args, 0, count as u64 - 1, NackCode::NotFinite, bad)? as u8;
        Ok(Self { source, index })
    }
}

/// The limits a slave catches up within (counts, seconds).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SyncLimits {
    /// Velocity.
    pub vmax: f64,
    /// Acceleration.
    pub amax: f64,
    /// Jerk.
    pub jerk: f64,
}

/// `MC_OP_GEAR_IN`, MC_GearIn (args: master, numerator, denominator, vmax, amax, jerk; flags:
/// `MC_MASTER_*`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GearIn {
    /// The master.
    pub master: Master,
    /// The ratio's numerator (an integer, nonzero; checked by the card after the master, with
    /// [`crate::GearRatio::from_args`]).
    pub numerator: f64,
    /// The ratio's denominator (a positive integer).
    pub denominator: f64,
    /// The catch-up's limits.
    pub limits: SyncLimits,
}

impl GearIn {
    fn put(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        let l = &self.limits;
        let a = [
            self.master.index as f64,
            self.numerator,
            self.denominator,
            l.vmax,
            l.amax,
            l.jerk,
        ];
        put(args, 0, &a);
        self.master.source.to_raw()
    }

    fn get(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            master: Master::decode(flags, args)?,
            numerator: args[1],
            denominator: args[2],
            limits: SyncLimits {
                vmax: args[3],
                amax: args[4],
                jerk: args[5],
            },
        })
    }
}

impl Args for GearIn {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        self.put(args)
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        all_finite(args, 0..6)?;
        Self::get(flags, args)
    }
}

/// `MC_OP_GEAR_IN_POS`, MC_GearInPos (args: as `MC_OP_GEAR_IN`, then the master's and the
/// slave's sync positions).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GearInPos {
    /// Master, ratio and limits, as MC_GearIn's.
    pub gear: GearIn,
    /// The master position at which the slave is in sync, counts.
    pub master_position: f64,
    /// The slave position it is in sync at, counts.
    pub slave_position: f64,
}

impl Args for GearInPos {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 6, &[self.master_position, self.slave_position]);
        self.gear.put(args)
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        all_finite(args, 0..8)?;
        Ok(Self {
            gear: GearIn::get(flags, args)?,
            master_position: args[6],
            slave_position: args[7],
        })
    }
}

/// `MC_OP_CAM_TABLE` (args: table, points; flags: `MC_CAM_CUBIC`, `MC_CAM_PERIODIC`): opens a
/// table for its points. Any fault but a NaN is `MC_NACK_CAM_TABLE`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CamTable {
    /// The table (below [`CAM_TABLES`]).
    pub table: u8,
    /// Its points (2..=[`CAM_MAX_POINTS`]; cubic: 3..).
    pub points: u16,
    /// Cubic spline (else linear).
    pub cubic: bool,
    /// Periodic.
    pub periodic: bool,
}

impl Args for CamTable {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.table as f64, self.points as f64]);
        set(self.cubic, CAM_CUBIC) | set(self.periodic, CAM_PERIODIC)
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        all_finite(args, 0..2)?;
        let bad = NackCode::CamTable;
        let table = uint(args, 0, CAM_TABLES as u64 - 1, bad, bad)? as u8;
        let cubic = bit(flags, CAM_CUBIC);
        let points = uint(args, 1, CAM_MAX_POINTS as u64, bad, bad)? as u16;
        if points < if cubic { 3 } else { 2 } {
            return Err(DecodeError::arg(1, Fault::OutOfRange, bad));
        }
        if flags & !(CAM_CUBIC | CAM_PERIODIC) != 0 {
            return Err(DecodeError::flags(bad));
        }
        Ok(Self {
            table,
            points,
            cubic,
            periodic: bit(flags, CAM_PERIODIC),
        })
    }
}

/// `MC_OP_CAM_DATA` (args: table, index of the first point, count (1..MC_CAM_DATA_MAX), then
/// master, slave of each). The card requires every argument finite, those past the count too
/// (`MC_NACK_NOT_FINITE`, before anything else); a table number out of range is
/// `MC_NACK_CAM_TABLE`, a count or first index `MC_NACK_CAM_SEQUENCE` (the card looks at the
/// table being loaded before those).
#[derive(Debug, Clone, PartialEq)]
pub struct CamData {
    /// The table.
    pub table: u8,
    /// The index of the first point.
    pub first: u16,
    /// The points (master, slave), counts.
    pub points: Vec<(f64, f64), CAM_DATA_MAX>,
}

impl Args for CamData {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        let head = [
            self.table as f64,
            self.first as f64,
            self.points.len() as f64,
        ];
        put(args, 0, &head);
        for (k, (m, s)) in self.points.iter().enumerate() {
            put(args, 3 + 2 * k, &[*m, *s]);
        }
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        all_finite(args, 0..CMD_ARGS)?;
        let table = uint(
            args,
            0,
            CAM_TABLES as u64 - 1,
            NackCode::NotFinite,
            NackCode::CamTable,
        )?;
        let seq = NackCode::CamSequence;
        let count = uint(args, 2, CAM_DATA_MAX as u64, seq, seq)? as usize;
        if count == 0 {
            return Err(DecodeError::arg(2, Fault::OutOfRange, seq));
        }
        let first = uint(args, 1, CAM_MAX_POINTS as u64 - 1, seq, seq)? as u16;
        let mut points = Vec::new();
        for k in 0..count {
            let _ = points.push((args[3 + 2 * k], args[4 + 2 * k])); // count <= capacity
        }
        Ok(Self {
            table: table as u8,
            first,
            points,
        })
    }
}

/// `MC_OP_CAM_IN`, MC_CamIn (args: master, table, master offset, slave offset, master scale,
/// slave scale, vmax, amax, jerk; flags: `MC_MASTER_*`, `MC_CAM_AT_CYCLE_END`,
/// `MC_CAM_RELATIVE`). The slave follows `slave offset + slave scale · table((master − master
/// offset) / master scale)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CamIn {
    /// The master.
    pub master: Master,
    /// The table (an integer below [`CAM_TABLES`]; checked by the card after the master).
    pub table: f64,
    /// Master offset, counts.
    pub master_offset: f64,
    /// Slave offset, counts.
    pub slave_offset: f64,
    /// Master scale.
    pub master_scale: f64,
    /// Slave scale.
    pub slave_scale: f64,
    /// The catch-up's limits.
    pub limits: SyncLimits,
    /// Switch at the end of the current cycle (MC_CamTableSelect).
    pub at_cycle_end: bool,
    /// PLCopen StartMode relative.
    pub relative: bool,
}

impl Args for CamIn {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        let l = &self.limits;
        let a = [
            self.master.index as f64,
            self.table,
            self.master_offset,
            self.slave_offset,
            self.master_scale,
            self.slave_scale,
            l.vmax,
            l.amax,
            l.jerk,
        ];
        put(args, 0, &a);
        self.master.source.to_raw()
            | set(self.at_cycle_end, CAM_AT_CYCLE_END)
            | set(self.relative, CAM_RELATIVE)
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        all_finite(args, 0..9)?;
        let master = Master::decode(flags & !(CAM_AT_CYCLE_END | CAM_RELATIVE), args)?;
        Ok(Self {
            master,
            table: args[1],
            master_offset: args[2],
            slave_offset: args[3],
            master_scale: args[4],
            slave_scale: args[5],
            limits: SyncLimits {
                vmax: args[6],
                amax: args[7],
                jerk: args[8],
            },
            at_cycle_end: bit(flags, CAM_AT_CYCLE_END),
            relative: bit(flags, CAM_RELATIVE),
        })
    }
}

/// `MC_OP_PVT_BEGIN` (args: vmax, amax, low water; flags: `MC_PVT_PT`). The card checks the
/// limits, then the low water, then the flags.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PvtBegin {
    /// The stream's velocity limit.
    pub vmax: f64,
    /// The stream's acceleration limit.
    pub amax: f64,
    /// The low-water mark, points (an integer below `MC_PVT_LEN`; 0: none).
    pub low_water: f64,
    /// PT (velocities from the neighbouring points), else PVT.
    pub pt: bool,
    /// Flag bits besides `MC_PVT_PT`: the card refuses any (`MC_NACK_BAD_CONFIG`).
    pub other_flags: u32,
}

impl Args for PvtBegin {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.vmax, self.amax, self.low_water]);
        set(self.pt, PVT_PT) | self.other_flags & !PVT_PT
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            vmax: args[0],
            amax: args[1],
            low_water: args[2],
            pt: bit(flags, PVT_PT),
            other_flags: flags & !PVT_PT,
        })
    }
}

/// One PT/PVT point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PvtPoint {
    /// Time from the stream's start, s.
    pub time: f64,
    /// Position, counts.
    pub position: f64,
    /// Velocity, counts/s (ignored in PT).
    pub velocity: f64,
}

/// `MC_OP_PVT_POINTS` (args: count (1..MC_PVT_POINTS_MAX), then time, position, velocity of
/// each; flags: `MC_PVT_LAST`). A count that is NaN is `MC_NACK_NOT_FINITE`, any other
/// `MC_NACK_OUT_OF_RANGE`; other flags `MC_NACK_BAD_CONFIG`.
#[derive(Debug, Clone, PartialEq)]
pub struct PvtPoints {
    /// The points, in order.
    pub points: Vec<PvtPoint, PVT_POINTS_MAX>,
    /// The last of them is the stream's last.
    pub last: bool,
}

impl Args for PvtPoints {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        args[0] = self.points.len() as f64;
        for (k, p) in self.points.iter().enumerate() {
            put(args, 1 + 3 * k, &[p.time, p.position, p.velocity]);
        }
        set(self.last, PVT_LAST)
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let bad = NackCode::OutOfRange;
        let n = uint(args, 0, PVT_POINTS_MAX as u64, NackCode::NotFinite, bad)? as usize;
        if n == 0 {
            return Err(DecodeError::arg(0, Fault::OutOfRange, bad));
        }
        if flags & !PVT_LAST != 0 {
            return Err(DecodeError::flags(NackCode::BadConfig));
        }
        let mut points = Vec::new();
        for k in 0..n {
            let a = &args[1 + 3 * k..4 + 3 * k];
            let _ = points.push(PvtPoint {
                time: a[0],
                position: a[1],
                velocity: a[2],
            }); // n <= capacity
        }
        Ok(Self {
            points,
            last: bit(flags, PVT_LAST),
        })
    }
}

/// `MC_OP_PVT_START` (args: axis mask, bit i: axis i; 0: the command's axis). A mask that is
/// NaN is `MC_NACK_NOT_FINITE`, one that is not an integer of [`MAX_AXES`] bits
/// `MC_NACK_BAD_AXIS` (the card checks it against its own axes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PvtStart {
    /// The axes whose streams start on the same tick.
    pub mask: u32,
}

impl Args for PvtStart {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        args[0] = self.mask as f64;
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let all = (1u64 << MAX_AXES) - 1;
        let mask = uint(args, 0, all, NackCode::NotFinite, NackCode::BadAxis)?;
        Ok(Self { mask: mask as u32 })
    }
}

/// Gearing, camming, PT/PVT.
#[derive(Debug, Clone, PartialEq)]
pub enum SyncCmd {
    /// `MC_OP_GEAR_IN`.
    GearIn(GearIn),
    /// `MC_OP_GEAR_IN_POS`.
    GearInPos(GearInPos),
    /// `MC_OP_GEAR_OUT`.
    GearOut,
    /// `MC_OP_CAM_TABLE` (any axis).
    CamTable(CamTable),
    /// `MC_OP_CAM_DATA` (any axis).
    CamData(CamData),
    /// `MC_OP_CAM_IN`.
    CamIn(CamIn),
    /// `MC_OP_CAM_OUT`.
    CamOut,
    /// `MC_OP_PVT_BEGIN`.
    PvtBegin(PvtBegin),
    /// `MC_OP_PVT_POINTS`.
    PvtPoints(PvtPoints),
    /// `MC_OP_PVT_START`.
    PvtStart(PvtStart),
    /// `MC_OP_GANTRY_FORM` (target: the gantry; layout 1.10).
    GantryForm(super::GantryForm),
    /// `MC_OP_GANTRY_DISSOLVE` (target: the gantry).
    GantryDissolve,
    /// `MC_OP_GANTRY_HOME` (target: the gantry).
    GantryHome,
}

impl SyncCmd {
    /// The opcode.
    pub fn opcode(&self) -> Opcode {
        match self {
            Self::GearIn(_) => Opcode::GearIn,
            Self::GearInPos(_) => Opcode::GearInPos,
            Self::GearOut => Opcode::GearOut,
            Self::CamTable(_) => Opcode::CamTable,
            Self::CamData(_) => Opcode::CamData,
            Self::CamIn(_) => Opcode::CamIn,
            Self::CamOut => Opcode::CamOut,
            Self::PvtBegin(_) => Opcode::PvtBegin,
            Self::PvtPoints(_) => Opcode::PvtPoints,
            Self::PvtStart(_) => Opcode::PvtStart,
            Self::GantryForm(_) => Opcode::GantryForm,
            Self::GantryDissolve => Opcode::GantryDissolve,
            Self::GantryHome => Opcode::GantryHome,
        }
    }

    /// Decode an entry of an opcode of this family.
    pub fn decode(op: Opcode, flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let f = flags;
        Ok(match op {
            Opcode::GearIn => Self::GearIn(Args::decode(f, args)?),
            Opcode::GearInPos => Self::GearInPos(Args::decode(f, args)?),
            Opcode::GearOut => Self::GearOut,
            Opcode::CamTable => Self::CamTable(Args::decode(f, args)?),
            Opcode::CamData => Self::CamData(Args::decode(f, args)?),
            Opcode::CamIn => Self::CamIn(Args::decode(f, args)?),
            Opcode::CamOut => Self::CamOut,
            Opcode::PvtBegin => Self::PvtBegin(Args::decode(f, args)?),
            Opcode::PvtPoints => Self::PvtPoints(Args::decode(f, args)?),
            Opcode::PvtStart => Self::PvtStart(Args::decode(f, args)?),
            Opcode::GantryForm => Self::GantryForm(Args::decode(f, args)?),
            Opcode::GantryDissolve | Opcode::GantryHome if f != 0 => {
                return Err(DecodeError::flags(NackCode::GantryState))
            }
            Opcode::GantryDissolve => Self::GantryDissolve,
            Opcode::GantryHome => Self::GantryHome,
            _ => return Err(not_in_family()),
        })
    }

    /// The entry for axis `axis` (seq 0, no deadline).
    pub fn command(&self, axis: u16) -> Command {
        let op = self.opcode();
        match self {
            Self::GearIn(a) => super::entry(op, axis, a),
            Self::GearInPos(a) => super::entry(op, axis, a),
            Self::GearOut | Self::CamOut => Command::new(op, axis),
            Self::CamTable(a) => super::entry(op, axis, a),
            Self::CamData(a) => super::entry(op, axis, a),
            Self::CamIn(a) => super::entry(op, axis, a),
            Self::PvtBegin(a) => super::entry(op, axis, a),
            Self::PvtPoints(a) => super::entry(op, axis, a),
            Self::PvtStart(a) => super::entry(op, axis, a),
            Self::GantryForm(a) => super::entry(op, axis, a),
            Self::GantryDissolve | Self::GantryHome => Command::new(op, axis),
        }
    }
}

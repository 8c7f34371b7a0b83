//! Configuration, sessions and safety: the applies of the configuration blocks (no arguments:
//! the block is the argument), the configuration read-back and the scale (layout 1.8), the host
//! sessions, the e-stop and the safety reset.

use super::{not_in_family, uint, Args, DecodeError, Fault};
use crate::wire::{Command, ConfigKind, NackCode, Opcode, StopCategory, CMD_ARGS};

/// `MC_OP_ESTOP` (args: category). Every axis; latched.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct EStop {
    /// The stop category (0, 1 or 2; else `MC_NACK_BAD_CATEGORY`).
    pub category: StopCategory,
}

impl Args for EStop {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        args[0] = self.category as u32 as f64;
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let a = args[0];
        if !a.is_finite() {
            return Err(DecodeError::arg(0, Fault::NotFinite, NackCode::NotFinite));
        }
        let category = StopCategory::ALL
            .iter()
            .find(|k| **k as u32 as f64 == a)
            .ok_or(DecodeError::arg(
                0,
                Fault::UnknownCode,
                NackCode::BadCategory,
            ))?;
        Ok(Self {
            category: *category,
        })
    }
}

/// `MC_OP_READ_CONFIG` (layout 1.8; args: block kind, index): the card writes the settings it
/// holds into that block. Both arguments must be integers (else `MC_NACK_CONFIG_KIND`); the
/// index is checked against the card's axes or groups by the card.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ReadConfig {
    /// The block.
    pub kind: ConfigKind,
    /// The axis or group (0 for a card-wide block).
    pub index: u16,
}

impl Args for ReadConfig {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        args[0] = self.kind as u32 as f64;
        args[1] = self.index as f64;
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let bad = NackCode::ConfigKind;
        let kind = uint(args, 0, u16::MAX as u64, bad, bad)?;
        let kind = ConfigKind::from_raw(kind as u32).ok_or(DecodeError::arg(
            0,
            Fault::UnknownCode,
            bad,
        ))?;
        let index = uint(args, 1, u16::MAX as u64, bad, bad)? as u16;
        Ok(Self { kind, index })
    }
}

super::value_args! {
    /// `MC_OP_SET_SCALE` (layout 1.8; args: counts per user unit): kept for hosts.
    SetScale { /// Counts per user unit (|scale| in [`crate::SCALE_RANGE`]; negative: the
    /// user's axis runs against the encoder).
    scale }
}

/// `MC_OP_HOST_ATTACH`, `MC_OP_HOST_DETACH` (flags: the session id; no arguments).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Session {
    /// The session id (nonzero for an attach).
    pub id: u32,
}

impl Args for Session {
    fn encode(&self, _: &mut [f64; CMD_ARGS]) -> u32 {
        self.id
    }
    fn decode(flags: u32, _: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self { id: flags })
    }
}

/// The largest tick a timed command may name: 2^53 (a tick is carried exactly in an `f64`; at
/// 20 kHz that is 14,000 years of ticks).
pub const MAX_TICK: u64 = 1 << 53;

/// `MC_OP_AT_TICK` (layout 1.12; args: tick, key): run the entry published with it on `tick`,
/// once the commit of `key` is seen (0: no commit needed). Both are whole numbers (else
/// `MC_NACK_TICK_FAR`, NaN `MC_NACK_NOT_FINITE`); how far ahead the tick may be is the card's
/// to check.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct AtTick {
    /// The card tick to run the command on.
    pub tick: u64,
    /// The commit key (0: none).
    pub key: u32,
}

fn tick_and_key(
    args: &[f64; CMD_ARGS],
    tick: usize,
    key: usize,
) -> Result<(u64, u32), DecodeError> {
    let far = NackCode::TickFar;
    let t = uint(args, tick, MAX_TICK, NackCode::NotFinite, far)?;
    let k = uint(args, key, u32::MAX as u64, NackCode::NotFinite, far)?;
    Ok((t, k as u32))
}

impl Args for AtTick {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        args[0] = self.tick as f64;
        args[1] = self.key as f64;
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let (tick, key) = tick_and_key(args, 0, 1)?;
        Ok(Self { tick, key })
    }
}

/// `MC_OP_SYNC_COMMIT` (layout 1.12; args: key, tick): let the timed commands of `key` run on
/// their tick, on this card and on every follower of its sync bus. Key 0 is
/// `MC_NACK_TICK_FAR` (it needs no commit).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SyncCommit {
    /// The key committed (nonzero).
    pub key: u32,
    /// The tick its commands run on: the commit must be served before it.
    pub tick: u64,
}

impl Args for SyncCommit {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        args[0] = self.key as f64;
        args[1] = self.tick as f64;
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let (tick, key) = tick_and_key(args, 1, 0)?;
        if key == 0 {
            return Err(DecodeError::arg(0, Fault::OutOfRange, NackCode::TickFar));
        }
        Ok(Self { key, tick })
    }
}

/// `MC_OP_TIMED_CANCEL` (layout 1.12; args: key, 0 for every held command).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TimedCancel {
    /// The key whose held commands are dropped (0: all).
    pub key: u32,
}

impl Args for TimedCancel {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        args[0] = self.key as f64;
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let far = NackCode::TickFar;
        let key = uint(args, 0, u32::MAX as u64, NackCode::NotFinite, far)? as u32;
        Ok(Self { key })
    }
}

/// Configuration, sessions and safety.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CardCmd {
    /// `MC_OP_NOP`: the round-trip probe.
    Nop,
    /// `MC_OP_APPLY_CARD_CONFIG`.
    ApplyCardConfig,
    /// `MC_OP_APPLY_AXIS_CONFIG` (target: the axis).
    ApplyAxisConfig,
    /// `MC_OP_APPLY_AXIS_FILTER` (target: the axis).
    ApplyAxisFilter,
    /// `MC_OP_APPLY_AXIS_HOMING` (target: the axis).
    ApplyAxisHoming,
    /// `MC_OP_APPLY_AXIS_SAFETY` (target: the axis).
    ApplyAxisSafety,
    /// `MC_OP_APPLY_SAFETY_CONFIG`.
    ApplySafetyConfig,
    /// `MC_OP_ESTOP`.
    EStop(EStop),
    /// `MC_OP_SAFETY_RESET`.
    SafetyReset,
    /// `MC_OP_HOST_ATTACH`.
    HostAttach(Session),
    /// `MC_OP_HOST_DETACH`.
    HostDetach(Session),
    /// `MC_OP_READ_CONFIG`.
    ReadConfig(ReadConfig),
    /// `MC_OP_SET_SCALE` (target: the axis).
    SetScale(SetScale),
    /// `MC_OP_AT_TICK` (layout 1.12).
    AtTick(AtTick),
    /// `MC_OP_SYNC_COMMIT` (layout 1.12).
    SyncCommit(SyncCommit),
    /// `MC_OP_TIMED_CANCEL` (layout 1.12).
    TimedCancel(TimedCancel),
}

impl CardCmd {
    /// The opcode.
    pub fn opcode(&self) -> Opcode {
        match self {
            Self::Nop => Opcode::Nop,
            Self::ApplyCardConfig => Opcode::ApplyCardConfig,
            Self::ApplyAxisConfig => Opcode::ApplyAxisConfig,
            Self::ApplyAxisFilter => Opcode::ApplyAxisFilter,
            Self::ApplyAxisHoming => Opcode::ApplyAxisHoming,
            Self::ApplyAxisSafety => Opcode::ApplyAxisSafety,
            Self::ApplySafetyConfig => Opcode::ApplySafetyConfig,
            Self::EStop(_) => Opcode::EStop,
            Self::SafetyReset => Opcode::SafetyReset,
            Self::HostAttach(_) => Opcode::HostAttach,
            Self::HostDetach(_) => Opcode::HostDetach,
            Self::ReadConfig(_) => Opcode::ReadConfig,
            Self::SetScale(_) => Opcode::SetScale,
            Self::AtTick(_) => Opcode::AtTick,
            Self::SyncCommit(_) => Opcode::SyncCommit,
            Self::TimedCancel(_) => Opcode::TimedCancel,
        }
    }

    /// Decode an entry of an opcode of this family.
    pub fn decode(op: Opcode, flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let f = flags;
        Ok(match op {
            Opcode::Nop => Self::Nop,
            Opcode::ApplyCardConfig => Self::ApplyCardConfig,
            Opcode::ApplyAxisConfig => Self::ApplyAxisConfig,
            Opcode::ApplyAxisFilter => Self::ApplyAxisFilter,
            Opcode::ApplyAxisHoming => Self::ApplyAxisHoming,
            Opcode::ApplyAxisSafety => Self::ApplyAxisSafety,
            Opcode::ApplySafetyConfig => Self::ApplySafetyConfig,
            Opcode::EStop => Self::EStop(Args::decode(f, args)?),
            Opcode::SafetyReset => Self::SafetyReset,
            Opcode::HostAttach => Self::HostAttach(Args::decode(f, args)?),
            Opcode::HostDetach => Self::HostDetach(Args::decode(f, args)?),
            Opcode::ReadConfig => Self::ReadConfig(Args::decode(f, args)?),
            Opcode::SetScale => Self::SetScale(Args::decode(f, args)?),
            Opcode::AtTick => Self::AtTick(Args::decode(f, args)?),
            Opcode::SyncCommit => Self::SyncCommit(Args::decode(f, args)?),
            Opcode::TimedCancel => Self::TimedCancel(Args::decode(f, args)?),
            _ => return Err(not_in_family()),
        })
    }

    /// The entry for `target` (the axis of the per-axis ones, else 0; seq 0, no deadline).
    pub fn command(&self, target: u16) -> Command {
        let op = self.opcode();
        match self {
            Self::EStop(a) => super::entry(op, target, a),
            Self::HostAttach(a) | Self::HostDetach(a) => super::entry(op, target, a),
            Self::ReadConfig(a) => super::entry(op, target, a),
            Self::SetScale(a) => super::entry(op, target, a),
            Self::AtTick(a) => super::entry(op, target, a),
            Self::SyncCommit(a) => super::entry(op, target, a),
            Self::TimedCancel(a) => super::entry(op, target, a),
            _ => Command::new(op, target),
        }
    }
}

//! Typed commands: one struct per opcode's arguments, encoded into and decoded from a command
//! entry's flags and `args` in one place.
//!
//! A command entry ([`crate::Command`]) carries an opcode, a target (axis or group), a flags
//! word and [`CMD_ARGS`] arguments as `f64`. Which argument is which is written here and
//! nowhere else: the host builds its commands with [`Cmd::command`] (or a family's), the card
//! decodes each entry once with [`Cmd::decode`] (a family's `decode` after its target check)
//! and hands the typed value to the function that executes it. The header's comments before
//! each `MC_OP_*` say the same for C.
//!
//! The commands are grouped in the card's families, an enum each: [`AxisCmd`] (single-axis
//! motion), [`GroupCmd`] (axes groups, NURBS curves, the path), [`SyncCmd`] (gearing, camming,
//! PT/PVT), [`IoCmd`] (outputs, compare, probes), [`CardCmd`] (configuration, sessions,
//! safety) and [`ScopeCmd`]; [`family`] names an opcode's.
//!
//! **What decoding refuses.** `decode` refuses an entry that cannot be read as its command: an
//! index or count that is not an integer in its range, a code the layout does not define, flag
//! bits the command does not take ([`DecodeError`], with the nack the card answers it with).
//! It does not judge plain numbers: a NaN target, a negative limit, a position out of range are
//! the card's to refuse where it always has (the firmware's value checks), so that each fault
//! keeps its nack. Where the card looks at its own state or at another argument's value before
//! it reads a field (a NURBS header's degree after the group's state, a path segment's id after
//! its targets, a gear ratio after the master), that field is carried as sent (an `f64`, the
//! flag bits) and the card checks it in its order: a command with two faults is refused for
//! the one it always was. The few commands the card requires finite in every argument before
//! anything else (gearing, camming) have that check in `decode` too.
//!
//! No heap: variable-length commands decode into [`heapless::Vec`]s of fixed capacity.

mod axis;
mod card;
mod comp;
mod filter;
mod freq;
mod gantry;
mod group;
mod io;
mod sync;
#[cfg(test)]
mod tests;

pub use axis::*;
pub use card::*;
pub use comp::*;
pub use filter::*;
pub use freq::*;
pub use gantry::*;
pub use group::*;
pub use io::*;
pub use sync::*;

use crate::wire::{Command, NackCode, Opcode, CMD_ARGS};

/// The arguments (and flags) of one command, encoded and decoded in one place.
pub trait Args: Sized {
    /// Write the arguments into `args` (whose other entries the caller set, zeros in a fresh
    /// entry) and return the flags word.
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32;
    /// Read an entry's flags and arguments; a malformed entry is the fault the card refuses.
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError>;
}

/// Where in an entry a fault is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Field {
    /// The opcode.
    Opcode,
    /// The flags word.
    Flags,
    /// `args[i]`.
    Arg(u8),
}

/// What is wrong with a field.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Fault {
    /// An opcode the layout does not define.
    UnknownOpcode,
    /// NaN or infinite.
    NotFinite,
    /// A fraction where an integer is expected.
    NotInteger,
    /// An integer (an index, a count) out of its range.
    OutOfRange,
    /// A value that names none of the codes it may be (a stop category, a block kind).
    UnknownCode,
    /// Flag bits the command does not take, or a combination it refuses.
    Flags,
}

/// Why an entry does not decode as its command: the field, the fault, and the nack the card
/// answers it with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DecodeError {
    /// The field at fault.
    pub field: Field,
    /// What is wrong with it.
    pub fault: Fault,
    /// The card's answer.
    pub nack: NackCode,
}

impl DecodeError {
    /// A fault in `args[i]`.
    pub fn arg(i: usize, fault: Fault, nack: NackCode) -> Self {
        Self {
            field: Field::Arg(i as u8),
            fault,
            nack,
        }
    }

    /// A fault in the flags word.
    pub fn flags(nack: NackCode) -> Self {
        Self {
            field: Field::Flags,
            fault: Fault::Flags,
            nack,
        }
    }
}

impl core::fmt::Display for DecodeError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let what = match self.fault {
            Fault::UnknownOpcode => "unknown opcode",
            Fault::NotFinite => "not finite",
            Fault::NotInteger => "not an integer",
            Fault::OutOfRange => "out of range",
            Fault::UnknownCode => "no such code",
            Fault::Flags => "flags refused",
        };
        match self.field {
            Field::Opcode => write!(f, "opcode: {what}"),
            Field::Flags => write!(f, "flags: {what}"),
            Field::Arg(i) => write!(f, "argument {i}: {what}"),
        }?;
        write!(f, " ({:?})", self.nack)
    }
}

#[cfg(feature = "std")]
impl std::error::Error for DecodeError {}

/// `args[i]` as an integer in `0..=max`: NaN and infinities are `not_finite`, fractions and
/// integers beyond the range `bad` (the card's test: finite, no fraction, in range).
pub(crate) fn uint(
    args: &[f64; CMD_ARGS],
    i: usize,
    max: u64,
    not_finite: NackCode,
    bad: NackCode,
) -> Result<u64, DecodeError> {
    let x = args[i];
    if !x.is_finite() {
        return Err(DecodeError::arg(i, Fault::NotFinite, not_finite));
    }
    if x != trunc(x) {
        return Err(DecodeError::arg(i, Fault::NotInteger, bad));
    }
    if !(0.0..=max as f64).contains(&x) {
        return Err(DecodeError::arg(i, Fault::OutOfRange, bad));
    }
    Ok(x as u64)
}

/// `x` without its fraction (`f64::trunc` without std).
fn trunc(x: f64) -> f64 {
    if x.abs() >= 4_503_599_627_370_496.0 || x.is_nan() {
        x // 2^52 and beyond has no fraction
    } else {
        (x as i64) as f64
    }
}

/// Every `args[i]` of `range` finite (the check the card makes first for a few commands).
pub(crate) fn all_finite(
    args: &[f64; CMD_ARGS],
    range: core::ops::Range<usize>,
) -> Result<(), DecodeError> {
    match range.clone().find(|&i| !args[i].is_finite()) {
        Some(i) => Err(DecodeError::arg(i, Fault::NotFinite, NackCode::NotFinite)),
        None => Ok(()),
    }
}

/// A flag bit as a `bool`.
pub(crate) fn bit(flags: u32, b: u32) -> bool {
    flags & b != 0
}

/// `b` if `on`.
pub(crate) fn set(on: bool, b: u32) -> u32 {
    if on {
        b
    } else {
        0
    }
}

/// `values` from `args[at]` on.
pub(crate) fn put(args: &mut [f64; CMD_ARGS], at: usize, values: &[f64]) {
    for (dst, v) in args[at..].iter_mut().zip(values) {
        *dst = *v;
    }
}

/// `N` arguments from `args[at]` on (zeros past the end).
pub(crate) fn take<const N: usize>(args: &[f64; CMD_ARGS], at: usize) -> [f64; N] {
    core::array::from_fn(|k| args.get(at + k).copied().unwrap_or(0.0))
}

/// The limits of a halt or stop: MC_Halt, MC_Stop, MC_GroupHalt, MC_GroupStop (args: dmax,
/// jerk).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StopRamp {
    /// Deceleration (counts/s²; a group's along its path).
    pub dmax: f64,
    /// Jerk (counts/s³).
    pub jerk: f64,
}

impl Args for StopRamp {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.dmax, self.jerk]);
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            dmax: args[0],
            jerk: args[1],
        })
    }
}

/// The family of commands an opcode belongs to: which part of the card executes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Family {
    /// Single-axis motion ([`AxisCmd`]).
    Axis,
    /// Axes groups, NURBS curves and the path ([`GroupCmd`]).
    Group,
    /// Gearing, camming, PT/PVT, gantries ([`SyncCmd`]).
    Sync,
    /// Outputs, position compare, touch probes ([`IoCmd`]).
    Io,
    /// Configuration, sessions and safety ([`CardCmd`]).
    Card,
    /// The scope ([`ScopeCmd`]).
    Scope,
}

/// The family of `op`.
pub fn family(op: Opcode) -> Family {
    use Opcode as O;
    match op {
        O::PowerOn
        | O::PowerOff
        | O::MoveAbsolute
        | O::MoveRelative
        | O::MoveAdditive
        | O::MoveVelocity
        | O::Jog
        | O::SetOverride
        | O::Halt
        | O::Stop
        | O::StopRelease
        | O::Reset
        | O::Home
        | O::SetPosition
        | O::CompTable
        | O::CompData
        | O::CompRead
        | O::Handwheel
        | O::HandwheelOff
        | O::SetModulo
        | O::ServoFilterSet
        | O::ServoFilterClear
        | O::FreqStart
        | O::FreqStop => Family::Axis,
        O::GroupConfigure
        | O::GroupEnable
        | O::GroupDisable
        | O::GroupStop
        | O::GroupStopRelease
        | O::GroupReset
        | O::GroupHalt
        | O::GroupMoveLinear
        | O::GroupMoveCircular
        | O::GroupMovePtp
        | O::GroupPtpLimits
        | O::GroupSetOverride
        | O::NurbsBegin
        | O::NurbsData
        | O::NurbsEnd
        | O::PathLine
        | O::PathArc
        | O::PathDwell
        | O::PathOutput
        | O::PathNurbs
        | O::PathPause
        | O::ApplyGroupPath
        | O::GroupHome
        | O::PathArcPlane
        | O::PathArcNormal
        | O::GroupMoveCircularNormal
        | O::GroupCircularPlane
        | O::ApplyGroupDims
        | O::PathMore
        | O::PathRelease => Family::Group,
        O::GearIn
        | O::GearInPos
        | O::GearOut
        | O::CamTable
        | O::CamData
        | O::CamIn
        | O::CamOut
        | O::PvtBegin
        | O::PvtPoints
        | O::PvtStart
        | O::GantryForm
        | O::GantryDissolve
        | O::GantryHome => Family::Sync,
        O::SetOutputs
        | O::ApplyIoConfig
        | O::CompareArm
        | O::CompareTable
        | O::CompareDisarm
        | O::ProbeArm
        | O::ProbeAbort
        | O::AnalogInput
        | O::AnalogOutput
        | O::Pso
        | O::PsoOff => Family::Io,
        O::ScopeConfigure | O::ScopeArm | O::ScopeTrigger | O::ScopeStop => Family::Scope,
        O::Nop
        | O::ApplyCardConfig
        | O::ApplyAxisConfig
        | O::ApplyAxisFilter
        | O::ApplyAxisHoming
        | O::ApplyAxisSafety
        | O::ApplySafetyConfig
        | O::EStop
        | O::SafetyReset
        | O::HostAttach
        | O::HostDetach
        | O::ReadConfig
        | O::SetScale
        | O::AtTick
        | O::SyncCommit
        | O::TimedCancel => Family::Card,
    }
}

/// The scope's commands (layout 1.8; no arguments: the configuration is its block).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ScopeCmd {
    /// `MC_OP_SCOPE_CONFIGURE`.
    Configure,
    /// `MC_OP_SCOPE_ARM`.
    Arm,
    /// `MC_OP_SCOPE_TRIGGER`.
    Trigger,
    /// `MC_OP_SCOPE_STOP`.
    Stop,
}

impl ScopeCmd {
    /// The opcode.
    pub fn opcode(&self) -> Opcode {
        match self {
            Self::Configure => Opcode::ScopeConfigure,
            Self::Arm => Opcode::ScopeArm,
            Self::Trigger => Opcode::ScopeTrigger,
            Self::Stop => Opcode::ScopeStop,
        }
    }

    /// Decode an entry of a scope opcode.
    pub fn decode(op: Opcode, _flags: u32, _args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(match op {
            Opcode::ScopeConfigure => Self::Configure,
            Opcode::ScopeArm => Self::Arm,
            Opcode::ScopeTrigger => Self::Trigger,
            Opcode::ScopeStop => Self::Stop,
            _ => return Err(not_in_family()),
        })
    }

    /// The entry for the card (seq 0, no deadline).
    pub fn command(&self) -> Command {
        Command::new(self.opcode(), 0)
    }
}

/// An opcode asked of a family it is not in.
pub(crate) fn not_in_family() -> DecodeError {
    DecodeError {
        field: Field::Opcode,
        fault: Fault::UnknownOpcode,
        nack: NackCode::UnknownOpcode,
    }
}

/// `flags` and `args` of a fresh entry of `op` for `target`, from a command's [`Args`].
pub(crate) fn entry<A: Args>(op: Opcode, target: u16, a: &A) -> Command {
    let mut c = Command::new(op, target);
    c.flags = a.encode(&mut c.args);
    c
}

/// Any command, typed.
#[derive(Debug, Clone, PartialEq)]
pub enum Cmd {
    /// Single-axis motion.
    Axis(AxisCmd),
    /// Groups, NURBS curves, the path.
    Group(GroupCmd),
    /// Gearing, camming, PT/PVT.
    Sync(SyncCmd),
    /// Outputs, compare, probes.
    Io(IoCmd),
    /// Configuration, sessions, safety.
    Card(CardCmd),
    /// The scope.
    Scope(ScopeCmd),
}

macro_rules! from_family {
    ($($family:ident => $variant:ident),+) => {
        $(impl From<$family> for Cmd {
            fn from(c: $family) -> Self {
                Self::$variant(c)
            }
        })+
    };
}

from_family!(AxisCmd => Axis, GroupCmd => Group, SyncCmd => Sync, IoCmd => Io, CardCmd => Card, ScopeCmd => Scope);

impl Cmd {
    /// Decode an entry's opcode, flags and arguments.
    pub fn decode(opcode: u16, flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let op = Opcode::from_raw(opcode).ok_or_else(not_in_family)?;
        Ok(match family(op) {
            Family::Axis => Self::Axis(AxisCmd::decode(op, flags, args)?),
            Family::Group => Self::Group(GroupCmd::decode(op, flags, args)?),
            Family::Sync => Self::Sync(SyncCmd::decode(op, flags, args)?),
            Family::Io => Self::Io(IoCmd::decode(op, flags, args)?),
            Family::Card => Self::Card(CardCmd::decode(op, flags, args)?),
            Family::Scope => Self::Scope(ScopeCmd::decode(op, flags, args)?),
        })
    }

    /// Decode a command entry.
    pub fn from_command(c: &Command) -> Result<Self, DecodeError> {
        Self::decode(c.opcode, c.flags, &c.args)
    }

    /// The opcode.
    pub fn opcode(&self) -> Opcode {
        match self {
            Self::Axis(c) => c.opcode(),
            Self::Group(c) => c.opcode(),
            Self::Sync(c) => c.opcode(),
            Self::Io(c) => c.opcode(),
            Self::Card(c) => c.opcode(),
            Self::Scope(c) => c.opcode(),
        }
    }

    /// The entry for `target` (an axis, a group, or 0 for the card-wide ones; seq 0, no
    /// deadline).
    pub fn command(&self, target: u16) -> Command {
        match self {
            Self::Axis(c) => c.command(target),
            Self::Group(c) => c.command(target),
            Self::Sync(c) => c.command(target),
            Self::Io(c) => c.command(target),
            Self::Card(c) => c.command(target),
            Self::Scope(c) => {
                let mut e = c.command();
                e.axis = target;
                e
            }
        }
    }
}

/// A command whose only argument is one plain number (`args[0]`, no flags).
macro_rules! value_args {
    ($(#[$m:meta])* $name:ident { $(#[$fm:meta])* $field:ident }) => {
        $(#[$m])*
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct $name {
            $(#[$fm])*
            pub $field: f64,
        }

        impl $crate::cmd::Args for $name {
            fn encode(&self, args: &mut [f64; $crate::wire::CMD_ARGS]) -> u32 {
                args[0] = self.$field;
                0
            }
            fn decode(
                _: u32,
                args: &[f64; $crate::wire::CMD_ARGS],
            ) -> Result<Self, $crate::cmd::DecodeError> {
                Ok(Self { $field: args[0] })
            }
        }
    };
}
pub(crate) use value_args;

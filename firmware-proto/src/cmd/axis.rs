//! Single-axis motion: MC_Power, the position moves, velocity mode and jog, the override,
//! MC_Halt and MC_Stop, MC_Reset, MC_Home and MC_SetPosition. Every argument is a plain number
//! (counts, seconds): decoding never fails, the card checks the values.

use super::{bit, not_in_family, put, set, take, uint, Args, DecodeError, Fault, StopRamp};
use crate::raw;
use crate::raw::{MC_HANDWHEEL_DETENT_MAX, MC_HANDWHEEL_RATIO_MAX};
use crate::wire::{Command, MoveFlags, NackCode, Opcode, CMD_ARGS, SET_POSITION_RELATIVE};

/// Which of PLCopen's single-axis position moves (the opcode of a [`PositionMove`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MoveKind {
    /// MC_MoveAbsolute (`MC_OP_MOVE_ABSOLUTE`): to a target position.
    Absolute,
    /// MC_MoveRelative (`MC_OP_MOVE_RELATIVE`): by a distance from the commanded position
    /// (buffered: from the target of the move before it).
    Relative,
    /// MC_MoveAdditive (`MC_OP_MOVE_ADDITIVE`): by a distance from the target of the last move.
    Additive,
}

impl MoveKind {
    /// Every kind.
    pub const ALL: [MoveKind; 3] = [Self::Absolute, Self::Relative, Self::Additive];

    /// The opcode.
    pub fn opcode(self) -> Opcode {
        match self {
            Self::Absolute => Opcode::MoveAbsolute,
            Self::Relative => Opcode::MoveRelative,
            Self::Additive => Opcode::MoveAdditive,
        }
    }
}

/// The limits of a single-axis move (counts, seconds): velocity, acceleration, deceleration
/// and the jerks of the S-curve's four jerk phases.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveLimits {
    /// Velocity.
    pub vmax: f64,
    /// Acceleration.
    pub amax: f64,
    /// Deceleration.
    pub dmax: f64,
    /// Jerk while the acceleration rises.
    pub j1: f64,
    /// Jerk while the acceleration falls.
    pub j3: f64,
    /// Jerk while the deceleration rises.
    pub j5: f64,
    /// Jerk while the deceleration falls.
    pub j7: f64,
}

impl MoveLimits {
    /// As arguments, in order.
    pub fn to_array(&self) -> [f64; 7] {
        [
            self.vmax, self.amax, self.dmax, self.j1, self.j3, self.j5, self.j7,
        ]
    }

    /// From arguments, in order.
    pub fn from_array(a: [f64; 7]) -> Self {
        let [vmax, amax, dmax, j1, j3, j5, j7] = a;
        Self {
            vmax,
            amax,
            dmax,
            j1,
            j3,
            j5,
            j7,
        }
    }
}

/// Which way an absolute move on a modulo axis goes (layout 1.10, PLCopen `MC_Direction`; the
/// 2-bit field `MC_MOVE_DIR_*` of `MC_OP_MOVE_ABSOLUTE`'s flags).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum MoveDirection {
    /// `mcShortestWay` (`MC_MOVE_DIR_SHORTEST`): the shorter way round; the only one a linear
    /// axis takes.
    #[default]
    Shortest,
    /// `mcPositiveDirection` (`MC_MOVE_DIR_POSITIVE`).
    Positive,
    /// `mcNegativeDirection` (`MC_MOVE_DIR_NEGATIVE`).
    Negative,
    /// `mcCurrentDirection` (`MC_MOVE_DIR_CURRENT`): that of the motion in progress, else of the
    /// last one (positive if the axis never moved).
    Current,
}

impl MoveDirection {
    /// Every direction.
    pub const ALL: [MoveDirection; 4] = [
        Self::Shortest,
        Self::Positive,
        Self::Negative,
        Self::Current,
    ];

    /// The `MC_MOVE_DIR_*` code.
    pub fn code(self) -> u32 {
        match self {
            Self::Shortest => raw::MC_MOVE_DIR_SHORTEST,
            Self::Positive => raw::MC_MOVE_DIR_POSITIVE,
            Self::Negative => raw::MC_MOVE_DIR_NEGATIVE,
            Self::Current => raw::MC_MOVE_DIR_CURRENT,
        }
    }

    /// From a `MC_MOVE_DIR_*` code (two bits: every value is one).
    pub fn from_code(code: u32) -> Self {
        match code & 3 {
            raw::MC_MOVE_DIR_POSITIVE => Self::Positive,
            raw::MC_MOVE_DIR_NEGATIVE => Self::Negative,
            raw::MC_MOVE_DIR_CURRENT => Self::Current,
            _ => Self::Shortest,
        }
    }
}

/// `MC_OP_MOVE_ABSOLUTE`, `_RELATIVE`, `_ADDITIVE` (args: target or distance, vmax, amax, dmax,
/// j1, j3, j5, j7; flags: `MC_MOVE_BUFFERED`, and for an absolute move the direction,
/// `MC_MOVE_DIR_*` at `MC_MOVE_DIR_SHIFT`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PositionMove {
    /// The target (absolute) or the distance (relative, additive), counts.
    pub position: f64,
    /// The limits.
    pub limits: MoveLimits,
    /// PLCopen Buffered (else Aborting).
    pub buffered: bool,
    /// The way round on a modulo axis (layout 1.10): an absolute move's; the card ignores it in
    /// a relative or additive move (their distance says the way), the SDK sends `Shortest`.
    pub direction: MoveDirection,
}

impl Args for PositionMove {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        args[0] = self.position;
        put(args, 1, &self.limits.to_array());
        set(self.buffered, MoveFlags::BUFFERED.bits())
            | (self.direction.code() << raw::MC_MOVE_DIR_SHIFT)
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            position: args[0],
            limits: MoveLimits::from_array(take(args, 1)),
            buffered: bit(flags, MoveFlags::BUFFERED.bits()),
            direction: MoveDirection::from_code(flags >> raw::MC_MOVE_DIR_SHIFT),
        })
    }
}

super::value_args! {
    /// `MC_OP_SET_MODULO` (layout 1.10; args: the period): an axis's modulo period.
    SetModulo { /// The period, counts (0: a linear axis; else in
    /// [`crate::MODULO_RANGE`]).
    modulo }
}

/// `MC_OP_MOVE_VELOCITY`, MC_MoveVelocity (args: velocity (signed), amax, dmax, jerk).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityMove {
    /// The velocity, counts/s; its sign is the direction.
    pub velocity: f64,
    /// Acceleration.
    pub amax: f64,
    /// Deceleration.
    pub dmax: f64,
    /// Jerk.
    pub jerk: f64,
}

impl Args for VelocityMove {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.velocity, self.amax, self.dmax, self.jerk]);
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let [velocity, amax, dmax, jerk] = take(args, 0);
        Ok(Self {
            velocity,
            amax,
            dmax,
            jerk,
        })
    }
}

super::value_args! {
    /// `MC_OP_JOG`: velocity mode at the axis's jog limits (args: velocity).
    Jog { /// The velocity, counts/s, signed; |v| at most the axis's `jog_max_vel`.
    velocity }
}

super::value_args! {
    /// `MC_OP_SET_OVERRIDE`, MC_SetOverride (args: factor).
    Override { /// The velocity factor, 0 to [`crate::OVERRIDE_MAX`].
    factor }
}

super::value_args! {
    /// `MC_OP_HOME`, MC_Home (args: position).
    Home { /// What the home point reads, before the axis's home offset, counts.
    position }
}

/// `MC_OP_SET_POSITION`, MC_SetPosition (args: position; flags: `MC_SET_POSITION_RELATIVE`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SetPosition {
    /// The new position, or the shift (relative), counts.
    pub position: f64,
    /// Move the position by `position` (else it becomes `position`).
    pub relative: bool,
}

impl Args for SetPosition {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        args[0] = self.position;
        set(self.relative, SET_POSITION_RELATIVE)
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            position: args[0],
            relative: bit(flags, SET_POSITION_RELATIVE),
        })
    }
}

/// `MC_OP_HANDWHEEL` (layout 1.10): an auxiliary encoder jogs the axis (args: input, ratio,
/// detent). Decoding refuses an input the card does not have (`HandwheelInput`) and a ratio or
/// detent that is not a whole number in its range (`HandwheelRatio`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Handwheel {
    /// The auxiliary encoder input, `0..AUX_ENCODERS`.
    pub input: u8,
    /// Axis counts per detent, `1 ≤ |ratio| ≤ MC_HANDWHEEL_RATIO_MAX` (negative: the other way).
    pub ratio: i32,
    /// Auxiliary counts per detent, `1..=MC_HANDWHEEL_DETENT_MAX`.
    pub detent: u16,
}

impl Args for Handwheel {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(
            args,
            0,
            &[
                f64::from(self.input),
                f64::from(self.ratio),
                f64::from(self.detent),
            ],
        );
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let last = crate::AUX_ENCODERS as u64 - 1;
        let input = uint(args, 0, last, NackCode::NotFinite, NackCode::HandwheelInput)? as u8;
        let bad = NackCode::HandwheelRatio;
        let r = args[1];
        if !r.is_finite() {
            return Err(DecodeError::arg(1, Fault::NotFinite, NackCode::NotFinite));
        }
        let max = f64::from(MC_HANDWHEEL_RATIO_MAX);
        if r == 0.0 || r.abs() > max {
            return Err(DecodeError::arg(1, Fault::OutOfRange, bad));
        }
        let ratio = r as i32; // |r| <= the maximum: exact when whole
        if f64::from(ratio) != r {
            return Err(DecodeError::arg(1, Fault::NotInteger, bad));
        }
        let detent = uint(
            args,
            2,
            u64::from(MC_HANDWHEEL_DETENT_MAX),
            NackCode::NotFinite,
            bad,
        )?;
        if detent == 0 {
            return Err(DecodeError::arg(2, Fault::OutOfRange, bad));
        }
        Ok(Self {
            input,
            ratio,
            detent: detent as u16,
        })
    }
}

/// A single-axis motion command (the command's target is the axis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AxisCmd {
    /// `MC_OP_POWER_ON`.
    PowerOn,
    /// `MC_OP_POWER_OFF`.
    PowerOff,
    /// `MC_OP_MOVE_ABSOLUTE`, `_RELATIVE`, `_ADDITIVE`.
    Move(MoveKind, PositionMove),
    /// `MC_OP_MOVE_VELOCITY`.
    MoveVelocity(VelocityMove),
    /// `MC_OP_JOG`.
    Jog(Jog),
    /// `MC_OP_SET_OVERRIDE`.
    SetOverride(Override),
    /// `MC_OP_HALT`.
    Halt(StopRamp),
    /// `MC_OP_STOP`.
    Stop(StopRamp),
    /// `MC_OP_STOP_RELEASE`.
    StopRelease,
    /// `MC_OP_RESET`.
    Reset,
    /// `MC_OP_HOME`.
    Home(Home),
    /// `MC_OP_SET_POSITION`.
    SetPosition(SetPosition),
    /// `MC_OP_COMP_TABLE` (layout 1.9).
    CompTable(super::CompHeader),
    /// `MC_OP_COMP_DATA`.
    CompData(super::CompData),
    /// `MC_OP_COMP_READ`.
    CompRead(super::CompRead),
    /// `MC_OP_HANDWHEEL` (layout 1.10).
    Handwheel(Handwheel),
    /// `MC_OP_HANDWHEEL_OFF`.
    HandwheelOff,
    /// `MC_OP_SET_MODULO` (layout 1.10).
    SetModulo(SetModulo),
    /// `MC_OP_SERVO_FILTER_SET` (layout 1.11).
    ServoFilterSet(super::ServoFilterSet),
    /// `MC_OP_SERVO_FILTER_CLEAR`.
    ServoFilterClear(super::ServoFilterClear),
    /// `MC_OP_FREQ_START` (layout 1.12).
    FreqStart(super::FreqStart),
    /// `MC_OP_FREQ_STOP`.
    FreqStop,
}

impl AxisCmd {
    /// The opcode.
    pub fn opcode(&self) -> Opcode {
        match self {
            Self::PowerOn => Opcode::PowerOn,
            Self::PowerOff => Opcode::PowerOff,
            Self::Move(k, _) => k.opcode(),
            Self::MoveVelocity(_) => Opcode::MoveVelocity,
            Self::Jog(_) => Opcode::Jog,
            Self::SetOverride(_) => Opcode::SetOverride,
            Self::Halt(_) => Opcode::Halt,
            Self::Stop(_) => Opcode::Stop,
            Self::StopRelease => Opcode::StopRelease,
            Self::Reset => Opcode::Reset,
            Self::Home(_) => Opcode::Home,
            Self::SetPosition(_) => Opcode::SetPosition,
            Self::CompTable(_) => Opcode::CompTable,
            Self::CompData(_) => Opcode::CompData,
            Self::CompRead(_) => Opcode::CompRead,
            Self::Handwheel(_) => Opcode::Handwheel,
            Self::HandwheelOff => Opcode::HandwheelOff,
            Self::SetModulo(_) => Opcode::SetModulo,
            Self::ServoFilterSet(_) => Opcode::ServoFilterSet,
            Self::ServoFilterClear(_) => Opcode::ServoFilterClear,
            Self::FreqStart(_) => Opcode::FreqStart,
            Self::FreqStop => Opcode::FreqStop,
        }
    }

    /// Decode an entry of a single-axis opcode (never fails for one).
    pub fn decode(op: Opcode, flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let f = flags;
        Ok(match op {
            Opcode::PowerOn => Self::PowerOn,
            Opcode::PowerOff => Self::PowerOff,
            Opcode::MoveAbsolute => Self::Move(MoveKind::Absolute, Args::decode(f, args)?),
            Opcode::MoveRelative => Self::Move(MoveKind::Relative, Args::decode(f, args)?),
            Opcode::MoveAdditive => Self::Move(MoveKind::Additive, Args::decode(f, args)?),
            Opcode::MoveVelocity => Self::MoveVelocity(Args::decode(f, args)?),
            Opcode::Jog => Self::Jog(Args::decode(f, args)?),
            Opcode::SetOverride => Self::SetOverride(Args::decode(f, args)?),
            Opcode::Halt => Self::Halt(Args::decode(f, args)?),
            Opcode::Stop => Self::Stop(Args::decode(f, args)?),
            Opcode::StopRelease => Self::StopRelease,
            Opcode::Reset => Self::Reset,
            Opcode::Home => Self::Home(Args::decode(f, args)?),
            Opcode::SetPosition => Self::SetPosition(Args::decode(f, args)?),
            Opcode::CompTable => Self::CompTable(Args::decode(f, args)?),
            Opcode::CompData => Self::CompData(Args::decode(f, args)?),
            Opcode::CompRead => Self::CompRead(Args::decode(f, args)?),
            Opcode::Handwheel => Self::Handwheel(Args::decode(f, args)?),
            Opcode::HandwheelOff => Self::HandwheelOff,
            Opcode::SetModulo => Self::SetModulo(Args::decode(f, args)?),
            Opcode::ServoFilterSet => Self::ServoFilterSet(Args::decode(f, args)?),
            Opcode::ServoFilterClear => Self::ServoFilterClear(Args::decode(f, args)?),
            Opcode::FreqStart => Self::FreqStart(Args::decode(f, args)?),
            Opcode::FreqStop => Self::FreqStop,
            _ => return Err(not_in_family()),
        })
    }

    /// The entry for axis `axis` (seq 0, no deadline).
    pub fn command(&self, axis: u16) -> Command {
        let op = self.opcode();
        match self {
            Self::PowerOn
            | Self::PowerOff
            | Self::StopRelease
            | Self::Reset
            | Self::HandwheelOff => Command::new(op, axis),
            Self::Move(_, m) => super::entry(op, axis, m),
            Self::MoveVelocity(m) => super::entry(op, axis, m),
            Self::Jog(v) => super::entry(op, axis, v),
            Self::SetOverride(v) => super::entry(op, axis, v),
            Self::Home(v) => super::entry(op, axis, v),
            Self::Halt(r) | Self::Stop(r) => super::entry(op, axis, r),
            Self::SetPosition(p) => super::entry(op, axis, p),
            Self::CompTable(h) => super::entry(op, axis, h),
            Self::CompData(d) => super::entry(op, axis, d),
            Self::CompRead(r) => super::entry(op, axis, r),
            Self::Handwheel(h) => super::entry(op, axis, h),
            Self::SetModulo(m) => super::entry(op, axis, m),
            Self::ServoFilterSet(v) => super::entry(op, axis, v),
            Self::ServoFilterClear(v) => super::entry(op, axis, v),
            Self::FreqStart(v) => super::entry(op, axis, v),
            Self::FreqStop => super::entry(op, axis, &super::FreqStop),
        }
    }
}

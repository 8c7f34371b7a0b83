//! Digital outputs, position compare and touch probes (layout 1.7; the outputs 1.6). A compare
//! or probe command's target is the axis it watches; its channel is `args[0]`.

use super::{bit, not_in_family, put, set, uint, Args, DecodeError, Fault};
use crate::wire::{Command, NackCode, Opcode, CMD_ARGS};
use crate::{
    raw, ANALOG_INPUTS, ANALOG_OUTPUTS, COMPARE_CHANNELS, COMPARE_TABLE_MAX, OUTPUTS,
    PROBE_CHANNELS,
};
use heapless::Vec;

/// The largest output word (`2^MC_OUTPUTS - 1`).
const OUTPUT_WORD: u64 = (1 << OUTPUTS) - 1;

/// `MC_OP_SET_OUTPUTS` (args: mask, value, each 0..2^MC_OUTPUTS-1, else `MC_NACK_PATH_OUTPUT`):
/// the outputs in `mask` become `value`'s bits now.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SetOutputs {
    /// The outputs set (bit i: output i).
    pub mask: u32,
    /// Their new values.
    pub value: u32,
}

impl Args for SetOutputs {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[self.mask as f64, self.value as f64]);
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let bad = NackCode::PathOutput;
        Ok(Self {
            mask: uint(args, 0, OUTPUT_WORD, bad, bad)? as u32,
            value: uint(args, 1, OUTPUT_WORD, bad, bad)? as u32,
        })
    }
}

/// A channel number in `args[0]`: NaN is `NotFinite`, anything but an integer below `n`
/// `IoChannel`.
fn channel(args: &[f64; CMD_ARGS], n: usize) -> Result<u8, DecodeError> {
    uint(
        args,
        0,
        n as u64 - 1,
        NackCode::NotFinite,
        NackCode::IoChannel,
    )
    .map(|c| c as u8)
}

/// The direction a compare position is crossed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Direction {
    /// Upwards (`MC_CMP_DIR_POS`).
    Up,
    /// Downwards (`MC_CMP_DIR_NEG`).
    Down,
}

impl Direction {
    fn bits(self) -> u32 {
        match self {
            Self::Up => raw::MC_CMP_DIR_POS,
            Self::Down => raw::MC_CMP_DIR_NEG,
        }
    }

    /// +1 up, -1 down.
    pub fn sign(self) -> i8 {
        match self {
            Self::Up => 1,
            Self::Down => -1,
        }
    }
}

/// What a compare channel fires on (`MC_CMP_MODE_*`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CompareKind {
    /// One position.
    Single,
    /// `start + k * pitch`, `k = 0..count-1`.
    Series,
    /// The positions queued with `MC_OP_COMPARE_TABLE`.
    Table,
}

/// `MC_OP_COMPARE_ARM` (args: channel, output, pulse_us, low_water, position or start, pitch,
/// count; flags: `MC_CMP_MODE_*`, `MC_CMP_DIR_*`). The channel and the flags are decoded; the
/// numbers are the card's to check (after the axis and the flags, each in its own order).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompareArm {
    /// The channel.
    pub channel: u8,
    /// Single, series or table.
    pub kind: CompareKind,
    /// The crossing direction; `None`: either way (a single position only).
    pub direction: Option<Direction>,
    /// The output pulsed (an integer, 0..MC_OUTPUTS-1).
    pub output: f64,
    /// The pulse width, µs (an integer, 1..MC_PULSE_MAX_US).
    pub pulse_us: f64,
    /// A table's low-water mark (an integer below MC_COMPARE_TABLE_LEN; 0: none).
    pub low_water: f64,
    /// The position (single) or the first one (series), counts.
    pub position: f64,
    /// The series' pitch (counts, ≥ 1).
    pub pitch: f64,
    /// The series' count (an integer, 1..2^31-1; 0 with `each_turn`: a whole turn).
    pub count: f64,
    /// Layout 1.13, `MC_CMP_EACH_TURN`: on a modulo axis a single position or a series fires on
    /// every turn, endless (the card refuses it on a linear axis or with a table).
    pub each_turn: bool,
}

impl Args for CompareArm {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        args[0] = self.channel as f64;
        put(
            args,
            1,
            &[
                self.output,
                self.pulse_us,
                self.low_water,
                self.position,
                self.pitch,
                self.count,
            ],
        );
        let kind = match self.kind {
            CompareKind::Single => raw::MC_CMP_MODE_SINGLE,
            CompareKind::Series => raw::MC_CMP_MODE_SERIES,
            CompareKind::Table => raw::MC_CMP_MODE_TABLE,
        };
        let dir = self
            .direction
            .map_or(raw::MC_CMP_DIR_POS | raw::MC_CMP_DIR_NEG, |d| d.bits());
        let each = if self.each_turn {
            raw::MC_CMP_EACH_TURN
        } else {
            0
        };
        kind | dir | each
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let channel = channel(args, COMPARE_CHANNELS)?;
        let bad = DecodeError::flags(NackCode::CompareMode);
        let known = raw::MC_CMP_MODE_MASK
            | raw::MC_CMP_DIR_POS
            | raw::MC_CMP_DIR_NEG
            | raw::MC_CMP_EACH_TURN;
        if flags & !known != 0 {
            return Err(bad);
        }
        let kind = match flags & raw::MC_CMP_MODE_MASK {
            raw::MC_CMP_MODE_SINGLE => CompareKind::Single,
            raw::MC_CMP_MODE_SERIES => CompareKind::Series,
            raw::MC_CMP_MODE_TABLE => CompareKind::Table,
            _ => return Err(bad),
        };
        let direction = match (
            bit(flags, raw::MC_CMP_DIR_POS),
            bit(flags, raw::MC_CMP_DIR_NEG),
        ) {
            (true, false) => Some(Direction::Up),
            (false, true) => Some(Direction::Down),
            (true, true) if kind == CompareKind::Single => None,
            _ => return Err(bad),
        };
        let each_turn = bit(flags, raw::MC_CMP_EACH_TURN);
        if each_turn && kind == CompareKind::Table {
            return Err(bad);
        }
        let [output, pulse_us, low_water, position, pitch, count] = super::take(args, 1);
        Ok(Self {
            channel,
            kind,
            direction,
            output,
            pulse_us,
            low_water,
            position,
            pitch,
            count,
            each_turn,
        })
    }
}

/// `MC_OP_COMPARE_TABLE` (args: channel, n (1..MC_COMPARE_TABLE_MAX), then n positions; flags:
/// the table's direction, `MC_CMP_DIR_POS` or `_NEG`).
#[derive(Debug, Clone, PartialEq)]
pub struct CompareTable {
    /// The channel.
    pub channel: u8,
    /// The table's direction.
    pub direction: Direction,
    /// The positions queued, counts (1 to [`COMPARE_TABLE_MAX`]).
    pub positions: Vec<f64, COMPARE_TABLE_MAX>,
}

impl Args for CompareTable {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        args[0] = self.channel as f64;
        args[1] = self.positions.len() as f64;
        put(args, 2, &self.positions);
        self.direction.bits()
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let channel = channel(args, COMPARE_CHANNELS)?;
        let n = uint(
            args,
            1,
            COMPARE_TABLE_MAX as u64,
            NackCode::NotFinite,
            NackCode::CompareMode,
        )?;
        if n == 0 {
            return Err(DecodeError::arg(
                1,
                Fault::OutOfRange,
                NackCode::CompareMode,
            ));
        }
        let direction = match flags {
            raw::MC_CMP_DIR_POS => Direction::Up,
            raw::MC_CMP_DIR_NEG => Direction::Down,
            _ => return Err(DecodeError::flags(NackCode::CompareMode)),
        };
        let n = n as usize;
        Ok(Self {
            channel,
            direction,
            positions: Vec::from_slice(&args[2..2 + n]).unwrap_or_default(),
        })
    }
}

/// `MC_OP_COMPARE_DISARM` (args: channel).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CompareDisarm {
    /// The channel.
    pub channel: u8,
}

impl Args for CompareDisarm {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        args[0] = self.channel as f64;
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            channel: channel(args, COMPARE_CHANNELS)?,
        })
    }
}

/// The probe input of the axis's encoder index pulse (`MC_PROBE_INDEX`).
pub const PROBE_INDEX: u8 = raw::MC_PROBE_INDEX as u8;

/// `MC_OP_PROBE_ARM`, MC_TouchProbe (args: channel, input, window_lo, window_hi; flags:
/// `MC_PROBE_RISING` / `_FALLING` (one or both), `MC_PROBE_CONTINUOUS`, `MC_PROBE_WINDOW`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProbeArm {
    /// The channel.
    pub channel: u8,
    /// The input (0..MC_INPUTS-1), or [`PROBE_INDEX`].
    pub input: u8,
    /// Capture on rising edges.
    pub rising: bool,
    /// Capture on falling edges.
    pub falling: bool,
    /// Keep capturing (else one capture).
    pub continuous: bool,
    /// Only edges whose position lies in `[lo, hi]` (counts; checked by the card).
    pub window: Option<(f64, f64)>,
    /// A capture halts the axis's group or the axis (`MC_PROBE_HALT`).
    pub halt: bool,
}

impl Args for ProbeArm {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        let (lo, hi) = self.window.unwrap_or((0.0, 0.0));
        put(args, 0, &[self.channel as f64, self.input as f64, lo, hi]);
        set(self.rising, raw::MC_PROBE_RISING)
            | set(self.falling, raw::MC_PROBE_FALLING)
            | set(self.continuous, raw::MC_PROBE_CONTINUOUS)
            | set(self.window.is_some(), raw::MC_PROBE_WINDOW)
            | set(self.halt, raw::MC_PROBE_HALT)
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let channel = channel(args, PROBE_CHANNELS)?;
        let known = raw::MC_PROBE_RISING
            | raw::MC_PROBE_FALLING
            | raw::MC_PROBE_CONTINUOUS
            | raw::MC_PROBE_WINDOW
            | raw::MC_PROBE_HALT;
        let rising = bit(flags, raw::MC_PROBE_RISING);
        let falling = bit(flags, raw::MC_PROBE_FALLING);
        if flags & !known != 0 || !(rising || falling) {
            return Err(DecodeError::flags(NackCode::ProbeInput));
        }
        let input = uint(
            args,
            1,
            PROBE_INDEX as u64,
            NackCode::NotFinite,
            NackCode::ProbeInput,
        )?;
        Ok(Self {
            channel,
            input: input as u8,
            rising,
            falling,
            continuous: bit(flags, raw::MC_PROBE_CONTINUOUS),
            window: bit(flags, raw::MC_PROBE_WINDOW).then_some((args[2], args[3])),
            halt: bit(flags, raw::MC_PROBE_HALT),
        })
    }
}

/// `MC_OP_PROBE_ABORT`, MC_AbortTrigger (args: channel).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ProbeAbort {
    /// The channel.
    pub channel: u8,
}

impl Args for ProbeAbort {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        args[0] = self.channel as f64;
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self {
            channel: channel(args, PROBE_CHANNELS)?,
        })
    }
}

/// `MC_OP_ANALOG_INPUT` (layout 1.11; args: input, cutoff_hz, threshold, hysteresis; flags:
/// `MC_ANALOG_EV_RISE` / `_FALL`). Decoding checks all but the cut-off's Nyquist bound (the
/// servo rate's: the card's check).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnalogInput {
    /// The input, `0..ANALOG_INPUTS`.
    pub input: u8,
    /// The filter's cut-off, Hz (0: none; ≥ 0).
    pub cutoff_hz: f64,
    /// The threshold, V (within ±`MC_ANALOG_RANGE`).
    pub threshold: f64,
    /// The hysteresis, V (0..=2·`MC_ANALOG_RANGE`): below again at `threshold - hysteresis`.
    pub hysteresis: f64,
    /// `MC_EV_ANALOG` going above.
    pub rise_event: bool,
    /// `MC_EV_ANALOG` going below again.
    pub fall_event: bool,
}

impl Args for AnalogInput {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(
            args,
            0,
            &[
                f64::from(self.input),
                self.cutoff_hz,
                self.threshold,
                self.hysteresis,
            ],
        );
        set(self.rise_event, raw::MC_ANALOG_EV_RISE) | set(self.fall_event, raw::MC_ANALOG_EV_FALL)
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let input = analog_channel(args, ANALOG_INPUTS)?;
        super::all_finite(args, 1..4)?;
        let [cutoff_hz, threshold, hysteresis] = super::take(args, 1);
        if cutoff_hz < 0.0 {
            return Err(DecodeError::arg(
                1,
                Fault::OutOfRange,
                NackCode::AnalogFilter,
            ));
        }
        let bad = NackCode::AnalogThreshold;
        let range = raw::MC_ANALOG_RANGE;
        if threshold.abs() > range {
            return Err(DecodeError::arg(2, Fault::OutOfRange, bad));
        }
        if !(0.0..=2.0 * range).contains(&hysteresis) {
            return Err(DecodeError::arg(3, Fault::OutOfRange, bad));
        }
        if flags & !(raw::MC_ANALOG_EV_RISE | raw::MC_ANALOG_EV_FALL) != 0 {
            return Err(DecodeError::flags(bad));
        }
        Ok(Self {
            input,
            cutoff_hz,
            threshold,
            hysteresis,
            rise_event: bit(flags, raw::MC_ANALOG_EV_RISE),
            fall_event: bit(flags, raw::MC_ANALOG_EV_FALL),
        })
    }
}

/// An analog channel number in `args[0]`: NaN is `NotFinite`, anything but an integer below
/// `n` `AnalogChannel`.
fn analog_channel(args: &[f64; CMD_ARGS], n: usize) -> Result<u8, DecodeError> {
    uint(
        args,
        0,
        n as u64 - 1,
        NackCode::NotFinite,
        NackCode::AnalogChannel,
    )
    .map(|c| c as u8)
}

/// `MC_OP_ANALOG_OUTPUT` (layout 1.11; args: output, volts): a spare DAC output. The volts are
/// the card's to clamp to the DAC's range (NaN and infinities are refused here).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnalogOutput {
    /// The output, `0..ANALOG_OUTPUTS`.
    pub output: u8,
    /// The voltage asked for.
    pub volts: f64,
}

impl Args for AnalogOutput {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(args, 0, &[f64::from(self.output), self.volts]);
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let output = analog_channel(args, ANALOG_OUTPUTS)?;
        super::all_finite(args, 1..2)?;
        Ok(Self {
            output,
            volts: args[1],
        })
    }
}

/// Where the PSO's output goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PsoOutput {
    /// A spare DAC output, `0..ANALOG_OUTPUTS` (min and max in volts).
    Dac(u8),
    /// A PWM on a digital output, `0..OUTPUTS`, at `hz` (min and max are duties 0..1).
    Pwm {
        /// The digital output.
        output: u8,
        /// The PWM frequency, Hz (`1..=MC_PSO_PWM_HZ_MAX`).
        hz: f64,
    },
}

/// `MC_OP_PSO` (layout 1.11; the command's target is the group; args: output, gate, min, max,
/// v_ref, pwm_hz, filter_hz; flags: `MC_PSO_PWM`). Decoding checks every argument; the group (configured)
/// and a PWM output a compare channel pulses are the card's to check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pso {
    /// The output.
    pub output: PsoOutput,
    /// The digital output whose bit in `card.outputs` gates the PSO.
    pub gate: u8,
    /// The output at rest (V or duty).
    pub min: f64,
    /// The output at `v_ref` and beyond (V or duty).
    pub max: f64,
    /// The tangential speed of full output, counts/s (> 0).
    pub v_ref: f64,
    /// The speed filter's cut-off, Hz (0: none; ≥ 0; the card checks it against Nyquist).
    pub filter_hz: f64,
}

impl Args for Pso {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        let (out, hz, flags) = match self.output {
            PsoOutput::Dac(o) => (o, 0.0, 0),
            PsoOutput::Pwm { output, hz } => (output, hz, raw::MC_PSO_PWM),
        };
        put(
            args,
            0,
            &[
                f64::from(out),
                f64::from(self.gate),
                self.min,
                self.max,
                self.v_ref,
                hz,
                self.filter_hz,
            ],
        );
        flags
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let bad = NackCode::PsoConfig;
        let pwm = bit(flags, raw::MC_PSO_PWM);
        super::all_finite(args, 0..5)?;
        super::all_finite(args, 6..7)?;
        if pwm {
            super::all_finite(args, 5..6)?;
        }
        if flags & !raw::MC_PSO_PWM != 0 {
            return Err(DecodeError::flags(bad));
        }
        let outputs = if pwm { OUTPUTS } else { ANALOG_OUTPUTS };
        let out = uint(args, 0, outputs as u64 - 1, bad, bad)? as u8;
        let gate = uint(args, 1, OUTPUTS as u64 - 1, bad, bad)? as u8;
        let [min, max, v_ref, hz, filter_hz] = super::take(args, 2);
        let (lo, hi) = if pwm {
            (0.0, 1.0)
        } else {
            (-raw::MC_ANALOG_RANGE, raw::MC_ANALOG_RANGE)
        };
        if !(lo..=hi).contains(&min) {
            return Err(DecodeError::arg(2, Fault::OutOfRange, bad));
        }
        if !(lo..=hi).contains(&max) || min > max {
            return Err(DecodeError::arg(3, Fault::OutOfRange, bad));
        }
        if v_ref <= 0.0 {
            return Err(DecodeError::arg(4, Fault::OutOfRange, bad));
        }
        if filter_hz < 0.0 {
            return Err(DecodeError::arg(6, Fault::OutOfRange, bad));
        }
        let output = if pwm {
            if !(1.0..=raw::MC_PSO_PWM_HZ_MAX).contains(&hz) {
                return Err(DecodeError::arg(5, Fault::OutOfRange, bad));
            }
            if gate == out {
                return Err(DecodeError::arg(1, Fault::OutOfRange, bad));
            }
            PsoOutput::Pwm { output: out, hz }
        } else {
            PsoOutput::Dac(out)
        };
        Ok(Self {
            output,
            gate,
            min,
            max,
            v_ref,
            filter_hz,
        })
    }
}

/// Outputs, position compare and touch probes.
#[derive(Debug, Clone, PartialEq)]
pub enum IoCmd {
    /// `MC_OP_SET_OUTPUTS` (card-wide).
    SetOutputs(SetOutputs),
    /// `MC_OP_APPLY_IO_CONFIG` (card-wide).
    ApplyConfig,
    /// `MC_OP_COMPARE_ARM`.
    CompareArm(CompareArm),
    /// `MC_OP_COMPARE_TABLE`.
    CompareTable(CompareTable),
    /// `MC_OP_COMPARE_DISARM`.
    CompareDisarm(CompareDisarm),
    /// `MC_OP_PROBE_ARM`.
    ProbeArm(ProbeArm),
    /// `MC_OP_PROBE_ABORT`.
    ProbeAbort(ProbeAbort),
    /// `MC_OP_ANALOG_INPUT` (layout 1.11, card-wide).
    AnalogInput(AnalogInput),
    /// `MC_OP_ANALOG_OUTPUT` (card-wide).
    AnalogOutput(AnalogOutput),
    /// `MC_OP_PSO` (target: the group).
    Pso(Pso),
    /// `MC_OP_PSO_OFF` (card-wide).
    PsoOff,
}

impl IoCmd {
    /// The opcode.
    pub fn opcode(&self) -> Opcode {
        match self {
            Self::SetOutputs(_) => Opcode::SetOutputs,
            Self::ApplyConfig => Opcode::ApplyIoConfig,
            Self::CompareArm(_) => Opcode::CompareArm,
            Self::CompareTable(_) => Opcode::CompareTable,
            Self::CompareDisarm(_) => Opcode::CompareDisarm,
            Self::ProbeArm(_) => Opcode::ProbeArm,
            Self::ProbeAbort(_) => Opcode::ProbeAbort,
            Self::AnalogInput(_) => Opcode::AnalogInput,
            Self::AnalogOutput(_) => Opcode::AnalogOutput,
            Self::Pso(_) => Opcode::Pso,
            Self::PsoOff => Opcode::PsoOff,
        }
    }

    /// Decode an entry of an opcode of this family.
    pub fn decode(op: Opcode, flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let f = flags;
        Ok(match op {
            Opcode::SetOutputs => Self::SetOutputs(Args::decode(f, args)?),
            Opcode::ApplyIoConfig => Self::ApplyConfig,
            Opcode::CompareArm => Self::CompareArm(Args::decode(f, args)?),
            Opcode::CompareTable => Self::CompareTable(Args::decode(f, args)?),
            Opcode::CompareDisarm => Self::CompareDisarm(Args::decode(f, args)?),
            Opcode::ProbeArm => Self::ProbeArm(Args::decode(f, args)?),
            Opcode::ProbeAbort => Self::ProbeAbort(Args::decode(f, args)?),
            Opcode::AnalogInput => Self::AnalogInput(Args::decode(f, args)?),
            Opcode::AnalogOutput => Self::AnalogOutput(Args::decode(f, args)?),
            Opcode::Pso => Self::Pso(Args::decode(f, args)?),
            Opcode::PsoOff => Self::PsoOff,
            _ => return Err(not_in_family()),
        })
    }

    /// The entry for `target` (the axis of a compare or probe command, the group of a PSO,
    /// else 0; seq 0, no deadline).
    pub fn command(&self, target: u16) -> Command {
        let op = self.opcode();
        match self {
            Self::SetOutputs(a) => super::entry(op, target, a),
            Self::ApplyConfig => Command::new(op, target),
            Self::CompareArm(a) => super::entry(op, target, a),
            Self::CompareTable(a) => super::entry(op, target, a),
            Self::CompareDisarm(a) => super::entry(op, target, a),
            Self::ProbeArm(a) => super::entry(op, target, a),
            Self::ProbeAbort(a) => super::entry(op, target, a),
            Self::AnalogInput(a) => super::entry(op, target, a),
            Self::AnalogOutput(a) => super::entry(op, target, a),
            Self::Pso(a) => super::entry(op, target, a),
            Self::PsoOff => Command::new(op, target),
        }
    }
}

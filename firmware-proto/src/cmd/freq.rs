//! Layout 1.12: the frequency-response sweep (`MC_OP_FREQ_START`, `MC_OP_FREQ_STOP`). The
//! mode, the points and the cycles are integers the decoding checks (`MC_NACK_FREQ_RANGE`,
//! NaN `MC_NACK_NOT_FINITE`); the frequencies, the amplitude and the settle time are the
//! card's to check against the axis.

use super::{put, uint, Args, DecodeError, Fault};
use crate::raw;
use crate::wire::{NackCode, CMD_ARGS};

/// Points per sweep at most (`MC_FREQ_POINTS_MAX`).
pub const FREQ_POINTS_MAX: usize = raw::MC_FREQ_POINTS_MAX as usize;

/// Where the sweep's sine enters the loop (`MC_FREQ_*`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FreqMode {
    /// `MC_FREQ_REF`: on the servo's position reference, counts (the closed loop).
    Reference,
    /// `MC_FREQ_OUTPUT`: on the servo output before the DAC, volts (the plant, the open loop).
    Output,
}

impl FreqMode {
    /// Its `MC_FREQ_*` code.
    pub fn code(self) -> u32 {
        match self {
            Self::Reference => raw::MC_FREQ_REF,
            Self::Output => raw::MC_FREQ_OUTPUT,
        }
    }

    /// The mode of a code.
    pub fn from_code(code: u32) -> Option<Self> {
        [Self::Reference, Self::Output]
            .into_iter()
            .find(|m| m.code() == code)
    }
}

/// `MC_OP_FREQ_START` (args: mode, from_hz, to_hz, points, amplitude, cycles, settle_s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreqStart {
    /// Where the sine enters.
    pub mode: FreqMode,
    /// The first frequency, Hz.
    pub from_hz: f64,
    /// The last frequency, Hz.
    pub to_hz: f64,
    /// Points, 1..=[`FREQ_POINTS_MAX`].
    pub points: u16,
    /// Counts ([`FreqMode::Reference`]) or volts ([`FreqMode::Output`]).
    pub amplitude: f64,
    /// Periods measured per point, 1..=`MC_FREQ_CYCLES_MAX`.
    pub cycles: u16,
    /// The least settling before each measured window, s.
    pub settle_s: f64,
}

impl Args for FreqStart {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(
            args,
            0,
            &[
                self.mode.code() as f64,
                self.from_hz,
                self.to_hz,
                self.points as f64,
                self.amplitude,
                self.cycles as f64,
                self.settle_s,
            ],
        );
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let bad = NackCode::FreqRange;
        let code = uint(args, 0, u32::MAX as u64, NackCode::NotFinite, bad)? as u32;
        let mode = FreqMode::from_code(code).ok_or(DecodeError::arg(0, Fault::UnknownCode, bad))?;
        let points = uint(args, 3, FREQ_POINTS_MAX as u64, NackCode::NotFinite, bad)? as u16;
        let cycles = uint(
            args,
            5,
            raw::MC_FREQ_CYCLES_MAX as u64,
            NackCode::NotFinite,
            bad,
        )? as u16;
        if points == 0 {
            return Err(DecodeError::arg(3, Fault::OutOfRange, bad));
        }
        if cycles == 0 {
            return Err(DecodeError::arg(5, Fault::OutOfRange, bad));
        }
        Ok(Self {
            mode,
            from_hz: args[1],
            to_hz: args[2],
            points,
            amplitude: args[4],
            cycles,
            settle_s: args[6],
        })
    }
}

/// `MC_OP_FREQ_STOP` (no arguments).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FreqStop;

impl Args for FreqStop {
    fn encode(&self, _: &mut [f64; CMD_ARGS]) -> u32 {
        0
    }
    fn decode(_: u32, _: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        Ok(Self)
    }
}

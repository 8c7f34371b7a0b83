//! Layout 1.11: the biquad filters on an axis's servo output (`MC_OP_SERVO_FILTER_SET`,
//! `MC_OP_SERVO_FILTER_CLEAR`). The slot and the kind are integers the decoding checks
//! (`MC_NACK_FILTER_KIND`, NaN `MC_NACK_NOT_FINITE`); the numbers are the card's to check.

use super::{put, uint, Args, DecodeError, Fault};
use crate::raw;
use crate::wire::{NackCode, CMD_ARGS};

/// Filters per axis (`MC_BIQUADS`).
pub const BIQUADS: usize = raw::MC_BIQUADS as usize;

/// What a biquad filter is (`MC_BIQUAD_*`, the empty slot excepted).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BiquadKind {
    /// `MC_BIQUAD_NOTCH`: centre frequency, damping (width), depth.
    Notch,
    /// `MC_BIQUAD_LOWPASS`: second-order low-pass, corner frequency and damping.
    LowPass,
    /// `MC_BIQUAD_LEAD_LAG`: first-order lead or lag, the zero's and the pole's frequencies.
    LeadLag,
    /// `MC_BIQUAD_RAW`: the coefficients as given.
    Raw,
}

impl BiquadKind {
    /// Every kind.
    pub const ALL: [BiquadKind; 4] = [Self::Notch, Self::LowPass, Self::LeadLag, Self::Raw];

    /// Its `MC_BIQUAD_*` code.
    pub fn code(self) -> u32 {
        match self {
            Self::Notch => raw::MC_BIQUAD_NOTCH,
            Self::LowPass => raw::MC_BIQUAD_LOWPASS,
            Self::LeadLag => raw::MC_BIQUAD_LEAD_LAG,
            Self::Raw => raw::MC_BIQUAD_RAW,
        }
    }

    /// The kind of an `MC_BIQUAD_*` code (`None` for `MC_BIQUAD_NONE` and unknown codes).
    pub fn from_code(code: u32) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.code() == code)
    }
}

/// One filter as the host gives it (`MC_OP_SERVO_FILTER_SET`'s arguments after the slot):
/// the arguments its kind does not use are 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BiquadSpec {
    /// The kind.
    pub kind: BiquadKind,
    /// Notch: the centre; low-pass: the corner; lead/lag: the zero's frequency, Hz.
    pub freq_hz: f64,
    /// Notch, low-pass: the damping ratio (a notch's width).
    pub damping: f64,
    /// Notch: the gain at the centre, dB (-120..0).
    pub depth_db: f64,
    /// Lead/lag: the pole's frequency, Hz.
    pub freq2_hz: f64,
    /// Raw: b0, b1, b2, a1, a2 (a0 = 1).
    pub coeffs: [f64; 5],
}

impl BiquadSpec {
    /// A notch at `hz` with damping `damping` and gain `depth_db` (dB, ≤ 0) at its centre.
    pub fn notch(hz: f64, damping: f64, depth_db: f64) -> Self {
        Self {
            freq_hz: hz,
            damping,
            depth_db,
            ..Self::empty(BiquadKind::Notch)
        }
    }

    /// A second-order low-pass at `hz` with damping `damping`.
    pub fn low_pass(hz: f64, damping: f64) -> Self {
        Self {
            freq_hz: hz,
            damping,
            ..Self::empty(BiquadKind::LowPass)
        }
    }

    /// A first-order lead/lag `(1 + s/ω_zero)/(1 + s/ω_pole)`.
    pub fn lead_lag(zero_hz: f64, pole_hz: f64) -> Self {
        Self {
            freq_hz: zero_hz,
            freq2_hz: pole_hz,
            ..Self::empty(BiquadKind::LeadLag)
        }
    }

    /// The coefficients as given: b0, b1, b2, a1, a2 (a0 = 1).
    pub fn raw(coeffs: [f64; 5]) -> Self {
        Self {
            coeffs,
            ..Self::empty(BiquadKind::Raw)
        }
    }

    fn empty(kind: BiquadKind) -> Self {
        Self {
            kind,
            freq_hz: 0.0,
            damping: 0.0,
            depth_db: 0.0,
            freq2_hz: 0.0,
            coeffs: [0.0; 5],
        }
    }
}

/// `MC_OP_SERVO_FILTER_SET` (args: slot, kind, freq_hz, damping, depth_db, freq2_hz, b0, b1,
/// b2, a1, a2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoFilterSet {
    /// The slot, 0..[`BIQUADS`].
    pub slot: u8,
    /// The filter.
    pub spec: BiquadSpec,
}

const _: () = assert!(11 <= CMD_ARGS);

impl Args for ServoFilterSet {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        let s = &self.spec;
        put(
            args,
            0,
            &[
                self.slot as f64,
                s.kind.code() as f64,
                s.freq_hz,
                s.damping,
                s.depth_db,
                s.freq2_hz,
            ],
        );
        put(args, 6, &s.coeffs);
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let bad = NackCode::FilterKind;
        let slot = uint(args, 0, BIQUADS as u64 - 1, NackCode::NotFinite, bad)? as u8;
        let code = uint(args, 1, u32::MAX as u64, NackCode::NotFinite, bad)? as u32;
        let kind =
            BiquadKind::from_code(code).ok_or(DecodeError::arg(1, Fault::UnknownCode, bad))?;
        Ok(Self {
            slot,
            spec: BiquadSpec {
                kind,
                freq_hz: args[2],
                damping: args[3],
                depth_db: args[4],
                freq2_hz: args[5],
                coeffs: [args[6], args[7], args[8], args[9], args[10]],
            },
        })
    }
}

/// `MC_OP_SERVO_FILTER_CLEAR` (args: slot).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoFilterClear {
    /// The slot, 0..[`BIQUADS`].
    pub slot: u8,
}

impl Args for ServoFilterClear {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        args[0] = self.slot as f64;
        0
    }
    fn decode(_: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let slot = uint(
            args,
            0,
            BIQUADS as u64 - 1,
            NackCode::NotFinite,
            NackCode::FilterKind,
        )? as u8;
        Ok(Self { slot })
    }
}

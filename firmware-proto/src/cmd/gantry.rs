//! Gantry axes (layout 1.10): `MC_OP_GANTRY_FORM`, `MC_OP_GANTRY_DISSOLVE`, `MC_OP_GANTRY_HOME`.
//! The command's target (`axis`) is the gantry's index; they are of the synchronised-motion
//! family ([`super::SyncCmd`]).
//!
//! Decoding refuses what makes a formation unreadable: an axis or a slave count that is not an
//! integer in range (`MC_NACK_GANTRY_AXES`, NaN: `MC_NACK_NOT_FINITE`) and any flag. The gains,
//! the skew limit and the offsets are the card's to check, and so is an axis against the card's
//! own axes and the other members.

use super::{put, uint, Args, DecodeError};
use crate::wire::{NackCode, CMD_ARGS};
use crate::{raw, MAX_AXES};
use heapless::Vec;

/// Gantries on a card (`MC_MAX_GANTRIES`).
pub const MAX_GANTRIES: usize = raw::MC_MAX_GANTRIES as usize;
/// Slaves of one gantry at most (`MC_GANTRY_MAX_SLAVES`).
pub const GANTRY_MAX_SLAVES: usize = raw::MC_GANTRY_MAX_SLAVES as usize;
/// The yaw loop's proportional gain is at most this, 1/s² (`MC_GANTRY_KP_MAX`).
pub const GANTRY_KP_MAX: f64 = raw::MC_GANTRY_KP_MAX;
/// The yaw loop's integral gain is at most this, 1/s³ (`MC_GANTRY_KI_MAX`).
pub const GANTRY_KI_MAX: f64 = raw::MC_GANTRY_KI_MAX;

const _: () = assert!(5 + 2 * GANTRY_MAX_SLAVES <= CMD_ARGS);

/// One slave of a formation: its axis and its square offset (slave − master when the bridge is
/// square, counts).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GantrySlave {
    /// The slave axis (below [`MAX_AXES`]; the card checks it against its own).
    pub axis: u8,
    /// The square offset, counts.
    pub offset: f64,
}

/// `MC_OP_GANTRY_FORM` (args: master, n, kp, ki, skew limit, then each slave's axis and
/// offset).
#[derive(Debug, Clone, PartialEq)]
pub struct GantryForm {
    /// The master axis.
    pub master: u8,
    /// The yaw loop's proportional gain, 1/s², `[0, GANTRY_KP_MAX]`.
    pub kp: f64,
    /// The yaw loop's integral gain, 1/s³, `[0, GANTRY_KI_MAX]`.
    pub ki: f64,
    /// The skew beyond which the gantry stops, counts (> 0).
    pub skew_limit: f64,
    /// The slaves (1..=[`GANTRY_MAX_SLAVES`]).
    pub slaves: Vec<GantrySlave, GANTRY_MAX_SLAVES>,
}

impl Args for GantryForm {
    fn encode(&self, args: &mut [f64; CMD_ARGS]) -> u32 {
        put(
            args,
            0,
            &[
                f64::from(self.master),
                self.slaves.len() as f64,
                self.kp,
                self.ki,
                self.skew_limit,
            ],
        );
        for (k, s) in self.slaves.iter().enumerate() {
            put(args, 5 + 2 * k, &[f64::from(s.axis), s.offset]);
        }
        0
    }
    fn decode(flags: u32, args: &[f64; CMD_ARGS]) -> Result<Self, DecodeError> {
        let bad = NackCode::GantryAxes;
        let axis_max = MAX_AXES as u64 - 1;
        let master = uint(args, 0, axis_max, NackCode::NotFinite, bad)? as u8;
        let n = uint(args, 1, GANTRY_MAX_SLAVES as u64, NackCode::NotFinite, bad)? as usize;
        if n == 0 {
            return Err(DecodeError::arg(1, super::Fault::OutOfRange, bad));
        }
        if flags != 0 {
            return Err(DecodeError::flags(bad));
        }
        let mut slaves = Vec::new();
        for k in 0..n {
            let axis = uint(args, 5 + 2 * k, axis_max, NackCode::NotFinite, bad)? as u8;
            // n <= capacity: never full.
            let _ = slaves.push(GantrySlave {
                axis,
                offset: args[6 + 2 * k],
            });
        }
        Ok(Self {
            master,
            kp: args[2],
            ki: args[3],
            skew_limit: args[4],
            slaves,
        })
    }
}

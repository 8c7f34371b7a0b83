//! Leadscrew pitch-error and backlash compensation (layout 1.9): an axis's table loaded,
//! read back and cleared. The same thin skin as [`crate::api`]: check the pointers, look the
//! handle up, call the SDK (`Axis::set_compensation`, `compensation`, `clear_compensation`),
//! write the outputs only on success, all inside `guard`.

use crate::api::axis_of;
use crate::ffi::{read_in, read_slice, ArrayBuf, Out};
use crate::registry::mc_card;
use crate::result::{guard, mc_result};
use motioncard_sdk::{CompPoint, Compensation};

/// An axis's compensation settings, in the axis's user units and seconds.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_comp_settings {
    /// Nonzero: each point gives a forward and a reverse correction (else they must be equal).
    pub bidirectional: u32,
    /// Backlash (>= 0): +backlash/2 moving forward, -backlash/2 in reverse.
    pub backlash: f64,
    /// The largest |correction ± backlash/2| allowed (> 0).
    pub bound: f64,
    /// The velocity of the ramp that takes up a jump of the correction (> 0).
    pub ramp_velocity: f64,
    /// Its acceleration (> 0).
    pub ramp_acceleration: f64,
}

/// One point of a compensation table, user units.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_comp_table_point {
    /// Position (strictly increasing along the table).
    pub position: f64,
    /// Correction moving forward.
    pub forward: f64,
    /// Correction moving in reverse.
    pub reverse: f64,
}

/// Load `axis`'s compensation: `settings` and `n` points (at most 256; 0: only the backlash, or
/// compensation off). Checked whole first: `MC_ERR_COMP_TABLE` (count, bound, backlash, ramp),
/// `MC_ERR_COMP_ORDER` (positions not strictly increasing), `MC_ERR_COMP_BOUND`,
/// `MC_ERR_NOT_FINITE`; `MC_ERR_COMP_BUSY` if the axis is not at rest. A refusal changes
/// nothing. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_set_compensation(
    card: mc_card,
    axis: u32,
    settings: *const mc_comp_settings,
    points: *const mc_comp_table_point,
    n: usize,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_comp_settings.
        let s = unsafe { read_in(settings, "settings") }?;
        // SAFETY: the caller gives NULL (n = 0) or n readable points.
        let pts = unsafe { read_slice(points, n, "points") }?;
        let (_, a) = axis_of(card, axis)?;
        let comp = Compensation {
            points: pts
                .iter()
                .map(|p| CompPoint {
                    position: p.position,
                    forward: p.forward,
                    reverse: p.reverse,
                })
                .collect(),
            bidirectional: s.bidirectional != 0,
            backlash: s.backlash,
            bound: s.bound,
            ramp_velocity: s.ramp_velocity,
            ramp_acceleration: s.ramp_acceleration,
        };
        Ok(a.set_compensation(&comp)?)
    })
}

/// Switch `axis`'s compensation off (its correction ramps out). `MC_ERR_COMP_BUSY` if the axis
/// is not at rest.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_clear_compensation(card: mc_card, axis: u32) -> mc_result {
    guard(|| {
        let (_, a) = axis_of(card, axis)?;
        Ok(a.clear_compensation()?)
    })
}

/// Read `axis`'s compensation back from the card: its settings into `*settings` and its points
/// into `points` (room for `len`), their count into `*needed` (0 and zero settings: no
/// compensation). `MC_ERR_BUFFER_TOO_SMALL` (only `*needed` written) if `len` is short.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_get_compensation(
    card: mc_card,
    axis: u32,
    settings: *mut mc_comp_settings,
    points: *mut mc_comp_table_point,
    len: usize,
    needed: *mut usize,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let buf = ArrayBuf::new(points, len, needed)?;
        let (_, a) = axis_of(card, axis)?;
        let c = a.compensation()?;
        let (s, pts) = match c {
            Some(c) => (
                mc_comp_settings {
                    bidirectional: u32::from(c.bidirectional),
                    backlash: c.backlash,
                    bound: c.bound,
                    ramp_velocity: c.ramp_velocity,
                    ramp_acceleration: c.ramp_acceleration,
                },
                c.points
                    .iter()
                    .map(|p| mc_comp_table_point {
                        position: p.position,
                        forward: p.forward,
                        reverse: p.reverse,
                    })
                    .collect::<Vec<_>>(),
            ),
            None => (mc_comp_settings::default(), Vec::new()),
        };
        // SAFETY: `points` has room for `len` points and `needed` is writable (the contract).
        unsafe { buf.fill(&pts) }?;
        // SAFETY: checked non-NULL; writable by the contract.
        unsafe { out.write(s) };
        Ok(())
    })
}

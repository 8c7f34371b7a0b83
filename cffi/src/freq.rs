//! Layout 1.12: the frequency response measured on the card: a stepped sine on an axis's
//! position reference (the closed loop) or its servo output (the plant, the open loop).

use crate::api::{axis_of, ms};
use crate::ffi::{read_in, ArrayBuf, Out};
use crate::registry::mc_card;
use crate::result::{guard, mc_result, Failure};
use motioncard_sdk::{ErrorKind, FreqMode, FreqResponse, FreqSweep};

/// `mc_freq_sweep.mode`: the sine on the position reference (user units): the closed loop.
pub const MC_FREQ_MODE_REFERENCE: u32 = 0;
/// `mc_freq_sweep.mode`: the sine on the servo output (volts): the plant and the open loop.
pub const MC_FREQ_MODE_OUTPUT: u32 = 1;

/// A sweep: `points` frequencies log-spaced from `from_hz` to `to_hz` (0.1 Hz <= from <= to
/// <= a quarter of the servo rate, 1..256 points), the sine's `amplitude` (user units, or
/// volts with `MC_FREQ_MODE_OUTPUT`), `cycles` periods measured at each (1..1000; the card
/// measures at least 1000 servo ticks) after at least `settle_s` seconds of settling (0..60).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_freq_sweep {
    /// `MC_FREQ_MODE_REFERENCE` or `MC_FREQ_MODE_OUTPUT`.
    pub mode: u32,
    pub points: u32,
    pub from_hz: f64,
    pub to_hz: f64,
    pub amplitude: f64,
    pub cycles: u32,
    pub _reserved0: u32,
    pub settle_s: f64,
}

/// One point of a measured response: the mode's response (the closed loop X/D, or the plant
/// X/U with `MC_FREQ_MODE_OUTPUT`), the plant (user units per volt) and the open loop, gain in
/// dB and phase in degrees.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_freq_point {
    /// The frequency the card ran, Hz.
    pub hz: f64,
    pub gain_db: f64,
    pub phase_deg: f64,
    pub plant_gain_db: f64,
    pub plant_phase_deg: f64,
    pub open_gain_db: f64,
    pub open_phase_deg: f64,
}

/// A resonance (or anti-resonance: `anti` 1) found in the mode's response.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_freq_resonance {
    pub hz: f64,
    /// The response's gain there, dB.
    pub gain_db: f64,
    /// How far it stands out of its neighbours, dB.
    pub height_db: f64,
    pub anti: u32,
    pub _reserved0: u32,
}

fn sweep_of(s: &mc_freq_sweep) -> Result<FreqSweep, Failure> {
    let mode = match s.mode {
        MC_FREQ_MODE_REFERENCE => FreqMode::Reference,
        MC_FREQ_MODE_OUTPUT => FreqMode::Output,
        m => {
            return Err(Failure::new(
                ErrorKind::FreqRange.code(),
                format!("sweep mode {m}: MC_FREQ_MODE_REFERENCE (0) or MC_FREQ_MODE_OUTPUT (1)"),
            ))
        }
    };
    Ok(FreqSweep {
        mode,
        from_hz: s.from_hz,
        to_hz: s.to_hz,
        points: s.points as usize,
        amplitude: s.amplitude,
        cycles: s.cycles,
        settle_s: s.settle_s,
    })
}

fn points_of(r: &FreqResponse) -> Vec<mc_freq_point> {
    let (t, p, l) = (r.response(), r.plant(), r.open_loop());
    (0..t.len())
        .map(|k| mc_freq_point {
            hz: t[k].hz,
            gain_db: t[k].gain_db,
            phase_deg: t[k].phase_deg,
            plant_gain_db: p[k].gain_db,
            plant_phase_deg: p[k].phase_deg,
            open_gain_db: l[k].gain_db,
            open_phase_deg: l[k].phase_deg,
        })
        .collect()
}

/// Run a sweep on an enabled axis at rest and wait for its end (up to `timeout_ms` of the
/// card's time): its points into `points` (`len` of them; `*needed` the count; too small:
/// `MC_ERR_BUFFER_TOO_SMALL`, the sweep's result stays on the card for
/// `mc_axis_freq_result`). Refused, nothing changed: `MC_ERR_FREQ_RANGE`,
/// `MC_ERR_FREQ_AMPLITUDE`, `MC_ERR_FREQ_LIMITS`, `MC_ERR_FREQ_BUSY`, `MC_ERR_NOT_FINITE`,
/// `MC_ERR_AXIS_DISABLED`, `MC_ERR_INVALID_STATE`; ended early (a stop, a safety stop):
/// `MC_ERR_ABORTED`.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_freq_response(
    card: mc_card,
    axis: u32,
    sweep: *const mc_freq_sweep,
    timeout_ms: u32,
    points: *mut mc_freq_point,
    len: usize,
    needed: *mut usize,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_freq_sweep.
        let s = sweep_of(&unsafe { read_in(sweep, "sweep") }?)?;
        let buf = ArrayBuf::new(points, len, needed)?;
        let r = axis_of(card, axis)?
            .1
            .frequency_response(&s, ms(timeout_ms))?;
        // SAFETY: checked by ArrayBuf::new; valid by the caller's contract.
        unsafe { buf.fill(&points_of(&r)) }
    })
}

/// The last sweep's points of this axis as the card holds them (the same as
/// `mc_axis_freq_response` gave), and `*complete` 1 when every point was measured. Never
/// blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_freq_result(
    card: mc_card,
    axis: u32,
    points: *mut mc_freq_point,
    len: usize,
    needed: *mut usize,
    complete: *mut u32,
) -> mc_result {
    guard(|| {
        let done = Out::new(complete, "complete")?;
        let buf = ArrayBuf::new(points, len, needed)?;
        let r = axis_of(card, axis)?.1.freq_result();
        // SAFETY: checked; valid by the caller's contract.
        unsafe {
            done.write(u32::from(r.complete));
            buf.fill(&points_of(&r))
        }
    })
}

/// The resonances (peaks) and anti-resonances (dips) of the axis's last sweep's response
/// standing out by at least 3 dB (the plant's with its rigid-body slope taken out). Never
/// blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_freq_resonances(
    card: mc_card,
    axis: u32,
    found: *mut mc_freq_resonance,
    len: usize,
    needed: *mut usize,
) -> mc_result {
    guard(|| {
        let buf = ArrayBuf::new(found, len, needed)?;
        let r = axis_of(card, axis)?.1.freq_result();
        let v: Vec<mc_freq_resonance> = r
            .resonances()
            .iter()
            .map(|x| mc_freq_resonance {
                hz: x.hz,
                gain_db: x.gain_db,
                height_db: x.height_db,
                anti: u32::from(x.anti),
                _reserved0: 0,
            })
            .collect();
        // SAFETY: checked; valid by the caller's contract.
        unsafe { buf.fill(&v) }
    })
}

/// Stop the card's sweep (none running: nothing happens). Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_freq_stop(card: mc_card, axis: u32) -> mc_result {
    guard(|| Ok(axis_of(card, axis)?.1.stop_frequency_sweep()?))
}

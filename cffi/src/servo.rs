//! Layout 1.11: the PID + feed-forward servo law and the biquad filters on an axis's servo
//! output.

use crate::api::axis_of;
use crate::ffi::{read_in, Out};
use crate::registry::mc_card;
use crate::result::{guard, mc_result, Failure};
use motioncard_sdk::{BiquadKind, BiquadSpec, ErrorKind, PidffSettings};

/// The PID + feed-forward law of an axis (Kim §5), in counts, seconds and volts: the card's
/// `mc_axis_pidff` register block. `u = kp·e + ki·∫e + kd·ė + kvff·v_ref + kaff·a_ref +
/// friction·sgn(v_ref)`: e the following error, ė through a first-order filter at
/// `d_filter_hz`, the integrator clamped to the DAC limit (and stopped while the output is
/// saturated in e's direction), the friction term 0 while |v_ref| <= `friction_deadband`.
#[allow(non_camel_case_types)]
pub type mc_pidff_settings = firmware_proto::raw::mc_axis_pidff;

/// One servo filter: `kind` (`MC_BIQUAD_NOTCH`, `_LOWPASS`, `_LEAD_LAG`, `_RAW`; read back,
/// `MC_BIQUAD_NONE` for an empty slot) and its parameters; the ones its kind does not use are
/// 0.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_servo_filter {
    /// `MC_BIQUAD_*`.
    pub kind: u32,
    pub _reserved0: u32,
    /// Notch: the centre; low-pass: the corner; lead/lag: the zero's frequency, Hz.
    pub freq_hz: f64,
    /// Notch, low-pass: the damping ratio (a notch's width: its -3 dB band is about
    /// 2·damping·freq_hz wide).
    pub damping: f64,
    /// Notch: the gain at the centre, dB (-120..0).
    pub depth_db: f64,
    /// Lead/lag: the pole's frequency, Hz.
    pub freq2_hz: f64,
    /// `MC_BIQUAD_RAW`: b0, b1, b2, a1, a2 (a0 = 1). Read back (every kind): the coefficients
    /// the card designed at the servo rate.
    pub coeffs: [f64; 5],
}

/// The card's default PID+FF tuning, or (accel_per_volt > 0) gains placed for a drive of that
/// many counts/s² per volt at a crossover of `bandwidth_hz` (NaN, infinite or not above 0:
/// `MC_ERR_BAD_CONFIG`). Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_pidff_settings_for_drive(
    accel_per_volt: f64,
    bandwidth_hz: f64,
    settings: *mut mc_pidff_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let s = if accel_per_volt == 0.0 && bandwidth_hz == 0.0 {
            PidffSettings::default()
        } else if accel_per_volt.is_finite()
            && accel_per_volt > 0.0
            && bandwidth_hz.is_finite()
            && bandwidth_hz > 0.0
        {
            PidffSettings::for_drive(accel_per_volt, 2.0 * std::f64::consts::PI * bandwidth_hz)
        } else {
            return Err(Failure::new(
                ErrorKind::BadConfig.code(),
                format!(
                    "accel_per_volt {accel_per_volt} and bandwidth_hz {bandwidth_hz} must be \
                     finite and above 0 (both 0: the default tuning)"
                ),
            ));
        };
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s) };
        Ok(())
    })
}

/// Switch an axis to the PID + feed-forward law with these gains (any state; at rest the switch
/// does not step the output). A gain negative, a derivative cut-off or friction deadband not
/// above 0: `MC_ERR_PIDFF_GAINS`; NaN or infinity: `MC_ERR_NOT_FINITE`. A refusal changes
/// nothing. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_configure_pidff(
    card: mc_card,
    axis: u32,
    settings: *const mc_pidff_settings,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_pidff_settings.
        let s = unsafe { read_in(settings, "settings") }?;
        Ok(axis_of(card, axis)?.1.configure_pidff(&s)?)
    })
}

/// The axis's PID+FF gains as the card holds them (read back): `*active` is 1 and `*settings`
/// the gains when the axis runs PID+FF, else `*active` is 0 and `*settings` all zero. Blocks
/// until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_get_pidff(
    card: mc_card,
    axis: u32,
    settings: *mut mc_pidff_settings,
    active: *mut u32,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let on = Out::new(active, "active")?;
        let p = axis_of(card, axis)?.1.pidff_settings()?;
        // SAFETY: both checked non-NULL; valid for writes by the caller's contract.
        unsafe {
            on.write(u32::from(p.is_some()));
            out.write(p.unwrap_or(zero_pidff()));
        }
        Ok(())
    })
}

fn zero_pidff() -> mc_pidff_settings {
    mc_pidff_settings {
        kp: 0.0,
        ki: 0.0,
        kd: 0.0,
        kvff: 0.0,
        kaff: 0.0,
        friction: 0.0,
        friction_deadband: 0.0,
        d_filter_hz: 0.0,
        _reserved: [0.0; 8],
    }
}

/// Set servo filter `slot` (0..`MC_BIQUADS`-1) of an axis: on the servo law's output, before
/// the DAC clamp, designed by the card at the servo rate (bilinear transform with pre-warping)
/// and checked. Refused, nothing changed: a slot or kind out of range `MC_ERR_FILTER_KIND`, a
/// frequency not above 0 and below half the servo rate `MC_ERR_FILTER_FREQ`, a damping
/// (0..10], depth (-120..0 dB) or raw b (|b| <= 1e6) out of range `MC_ERR_FILTER_PARAM`, a pole
/// not inside the unit circle `MC_ERR_FILTER_UNSTABLE`, NaN or infinity `MC_ERR_NOT_FINITE`.
/// Any state: the filter starts from the steady state of the output of the tick. Blocks until
/// the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_set_servo_filter(
    card: mc_card,
    axis: u32,
    slot: u32,
    filter: *const mc_servo_filter,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_servo_filter.
        let f = unsafe { read_in(filter, "filter") }?;
        let kind = BiquadKind::from_code(f.kind).ok_or_else(|| {
            Failure::new(
                ErrorKind::FilterKind.code(),
                format!("unknown filter kind {}", f.kind),
            )
        })?;
        let spec = BiquadSpec {
            kind,
            freq_hz: f.freq_hz,
            damping: f.damping,
            depth_db: f.depth_db,
            freq2_hz: f.freq2_hz,
            coeffs: f.coeffs,
        };
        Ok(axis_of(card, axis)?
            .1
            .set_servo_filter(slot as usize, &spec)?)
    })
}

/// Empty servo filter `slot` of an axis (an empty slot stays empty; out of range:
/// `MC_ERR_FILTER_KIND`). Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_axis_clear_servo_filter(card: mc_card, axis: u32, slot: u32) -> mc_result {
    guard(|| Ok(axis_of(card, axis)?.1.clear_servo_filter(slot as usize)?))
}

/// Servo filter `slot` of an axis as the card holds it: its kind and parameters, and in
/// `coeffs` the coefficients the card designed (`kind` `MC_BIQUAD_NONE` and the rest 0: the
/// slot is empty; out of range: `MC_ERR_FILTER_KIND`).
#[no_mangle]
pub unsafe extern "C" fn mc_axis_get_servo_filter(
    card: mc_card,
    axis: u32,
    slot: u32,
    filter: *mut mc_servo_filter,
) -> mc_result {
    guard(|| {
        let out = Out::new(filter, "filter")?;
        let all = axis_of(card, axis)?.1.servo_filters()?;
        let Some(held) = all.get(slot as usize) else {
            return Err(Failure::new(
                ErrorKind::FilterKind.code(),
                format!("filter slot {slot}: the slots are 0..{}", all.len() - 1),
            ));
        };
        let f = held.map_or(mc_servo_filter::default(), |h| mc_servo_filter {
            kind: h.spec.kind.code(),
            _reserved0: 0,
            freq_hz: h.spec.freq_hz,
            damping: h.spec.damping,
            depth_db: h.spec.depth_db,
            freq2_hz: h.spec.freq2_hz,
            coeffs: h.coeffs,
        });
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(f) };
        Ok(())
    })
}

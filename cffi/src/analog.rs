//! Analog I/O and the path-speed output (layout 1.11): `mc_analog_*`, `mc_pso_*`. The same thin
//! skin as [`crate::api`]: check the pointers, look the handle up, call the SDK, write the
//! outputs, all inside `guard`.

use crate::ffi::{read_in, Out};
use crate::group::group_of;
use crate::registry::{self, mc_card};
use crate::result::{guard, mc_result};
use motioncard_sdk::{AnalogInputSettings, Pso, PsoOutput, PsoState};

/// Groups per card.
const MAX_GROUPS: usize = motioncard_sdk::proto::raw::MC_MAX_GROUPS as usize;

/// `mc_pso_info.state`: not configured.
pub const MC_PSO_STATE_OFF: u32 = 0;
/// `mc_pso_info.state`: configured, its gate output off: the output is 0.
pub const MC_PSO_STATE_CLOSED: u32 = 1;
/// `mc_pso_info.state`: the gate output on: the output follows the path speed.
pub const MC_PSO_STATE_ON: u32 = 2;

/// An analog input's filter and threshold (`mc_analog_input_configure`). All zero: the boot
/// state (no filter, threshold 0 V, no hysteresis, no events).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_analog_input_settings {
    /// The first-order filter's cut-off, Hz (0: none; at most half the servo rate).
    pub cutoff_hz: f64,
    /// The threshold, V (within +-10 V).
    pub threshold: f64,
    /// The hysteresis, V (0..20): the input is below again at `threshold - hysteresis`.
    pub hysteresis: f64,
    /// Nonzero: an `MC_EVENT_ANALOG` event (axis: the input, code 1) going above.
    pub rise_event: u32,
    /// Nonzero: an `MC_EVENT_ANALOG` event (code 0) going below again.
    pub fall_event: u32,
}

/// An analog input as the card sampled it at its last tick (`mc_analog_input_read`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_analog_input_info {
    /// The 16-bit ADC's sample, V (a multiple of 20/65536 V).
    pub sample: f64,
    /// The filtered value, V.
    pub value: f64,
    /// 1 while above the threshold.
    pub above: u32,
    /// Reserved (0).
    pub reserved: u32,
    /// The settings the card holds.
    pub settings: mc_analog_input_settings,
}

/// The path-speed output's settings (`mc_pso_configure`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_pso_settings {
    /// 0: a spare DAC output (`output` 0..3, `min`/`max` in volts); nonzero: a PWM on digital
    /// output `output` (0..15) at `pwm_hz`, `min`/`max` duties 0..1.
    pub pwm: u32,
    /// The output.
    pub output: u32,
    /// The digital output (0..15) whose level switches the PSO on (the path's M62..M65).
    pub gate: u32,
    /// Reserved (0).
    pub reserved: u32,
    /// The output at rest.
    pub min: f64,
    /// The output at `v_ref` and beyond.
    pub max: f64,
    /// The tangential speed of full output, the group's user units per second (> 0).
    pub v_ref: f64,
    /// The PWM's frequency, Hz (1..100000; ignored for a DAC).
    pub pwm_hz: f64,
    /// The speed filter's cut-off, Hz (0: none; at most half the servo rate).
    pub filter_hz: f64,
}

/// The path-speed output's state of the last tick (`mc_pso_get_info`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_pso_info {
    /// `MC_PSO_STATE_*`.
    pub state: u32,
    /// Its group.
    pub group: u32,
    /// The group's actual tangential speed, encoder counts per second.
    pub speed_counts: f64,
    /// The output: V, or the PWM's duty.
    pub value: f64,
}

/// Set analog input `input`'s (0..7) filter and threshold. The filter keeps its value; the
/// threshold state is taken again from it, without an event. Refused: `MC_ERR_ANALOG_CHANNEL`,
/// `MC_ERR_ANALOG_FILTER` (a cut-off below 0 or above half the servo rate),
/// `MC_ERR_ANALOG_THRESHOLD`, `MC_ERR_NOT_FINITE`; nothing changes then. Blocks until the card
/// answers.
#[no_mangle]
pub unsafe extern "C" fn mc_analog_input_configure(
    card: mc_card,
    input: u32,
    settings: *const mc_analog_input_settings,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller's contract (NULL is refused by read_in).
        let s = unsafe { read_in(settings, "settings")? };
        let s = AnalogInputSettings {
            cutoff_hz: s.cutoff_hz,
            threshold: s.threshold,
            hysteresis: s.hysteresis,
            rise_event: s.rise_event != 0,
            fall_event: s.fall_event != 0,
        };
        Ok(registry::get(card)?
            .card
            .configure_analog_input(input as usize, &s)?)
    })
}

/// Analog input `input` (0..7) as the card sampled it at its last tick. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_analog_input_read(
    card: mc_card,
    input: u32,
    info: *mut mc_analog_input_info,
) -> mc_result {
    guard(|| {
        let out = Out::new(info, "info")?;
        let a = registry::get(card)?.card.analog_input(input as usize)?;
        let v = mc_analog_input_info {
            sample: a.sample,
            value: a.value,
            above: u32::from(a.above),
            reserved: 0,
            settings: mc_analog_input_settings {
                cutoff_hz: a.settings.cutoff_hz,
                threshold: a.settings.threshold,
                hysteresis: a.settings.hysteresis,
                rise_event: u32::from(a.settings.rise_event),
                fall_event: u32::from(a.settings.fall_event),
            },
        };
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(v) };
        Ok(())
    })
}

/// Set spare DAC output `output` (0..3) to `volts`, clamped to the 12-bit DAC's range (-10 V ..
/// 10 V - 20/4096 V) and quantised; `*produced` (may be NULL) receives the volts it puts out.
/// Refused: `MC_ERR_ANALOG_CHANNEL` (no such output, or the one the PSO drives),
/// `MC_ERR_NOT_FINITE`. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_analog_output_set(
    card: mc_card,
    output: u32,
    volts: f64,
    produced: *mut f64,
) -> mc_result {
    guard(|| {
        let v = registry::get(card)?
            .card
            .set_analog_output(output as usize, volts)?;
        if !produced.is_null() {
            // SAFETY: non-NULL; valid for writes by the caller's contract.
            unsafe { produced.write(v) };
        }
        Ok(())
    })
}

/// Spare DAC output `output` (0..3) now, V. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_analog_output_get(
    card: mc_card,
    output: u32,
    volts: *mut f64,
) -> mc_result {
    guard(|| {
        let out = Out::new(volts, "volts")?;
        let v = registry::get(card)?.card.analog_output(output as usize)?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(v) };
        Ok(())
    })
}

/// Run the path-speed output on `group`: every tick, while the gate output is on, the output is
/// `clamp(min + (max - min) * v / v_ref, min, max)`, v the group's actual tangential speed
/// (its axes' velocity estimates through the speed filter); 0 (0 V, or duty 0) while the gate
/// is off. Replaces a PSO running. Refused: `MC_ERR_PSO_GROUP` (no such group, or not
/// configured), `MC_ERR_PSO_CONFIG` (min > max, a range, output, gate, v_ref, frequency or
/// filter out of range), `MC_ERR_NOT_FINITE`; nothing changes then. Blocks until the card
/// answers.
#[no_mangle]
pub unsafe extern "C" fn mc_pso_configure(
    card: mc_card,
    group: u32,
    settings: *const mc_pso_settings,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller's contract (NULL is refused by read_in).
        let s = unsafe { read_in(settings, "settings")? };
        let p = Pso {
            output: if s.pwm != 0 {
                PsoOutput::Pwm {
                    output: s.output as usize,
                    hz: s.pwm_hz,
                }
            } else {
                PsoOutput::Dac(s.output as usize)
            },
            gate: s.gate as usize,
            min: s.min,
            max: s.max,
            v_ref: s.v_ref,
            filter_hz: s.filter_hz,
        };
        if (group as usize) < MAX_GROUPS {
            let (_, g) = group_of(card, group)?;
            Ok(g.pso(&p)?)
        } else {
            // No such group: the card says so (MC_ERR_PSO_GROUP).
            Ok(registry::get(card)?.card.pso_counts(group as usize, &p)?)
        }
    })
}

/// Stop the path-speed output: its output goes to 0. Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_pso_off(card: mc_card) -> mc_result {
    guard(|| Ok(registry::get(card)?.card.pso_off()?))
}

/// The path-speed output's state, speed and value of the last tick. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_pso_get_info(card: mc_card, info: *mut mc_pso_info) -> mc_result {
    guard(|| {
        let out = Out::new(info, "info")?;
        let s = registry::get(card)?.card.pso_status()?;
        let v = mc_pso_info {
            state: match s.state {
                PsoState::Off => MC_PSO_STATE_OFF,
                PsoState::Closed => MC_PSO_STATE_CLOSED,
                PsoState::On => MC_PSO_STATE_ON,
            },
            group: s.group as u32,
            speed_counts: s.speed_counts,
            value: s.value,
        };
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(v) };
        Ok(())
    })
}

/// Stepped sim: drive analog input `input`'s pin at `volts` now. `MC_ERR_UNSUPPORTED` on any
/// other card. Never blocks.
#[no_mangle]
pub extern "C" fn mc_sim_set_analog_input(card: mc_card, input: u32, volts: f64) -> mc_result {
    guard(|| {
        #[cfg(feature = "emulator")]
        {
            let src = motioncard_sdk::AnalogSource::Constant(volts);
            crate::api::sim_of(card)?.with_emulator(|e| e.analog().set(input as usize, src));
            Ok(())
        }
        #[cfg(not(feature = "emulator"))]
        {
            let _ = (card, input, volts);
            Err(crate::api::no_emulator())
        }
    })
}

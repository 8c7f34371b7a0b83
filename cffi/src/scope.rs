//! The card's scope (layout 1.8): up to 16 channels sampled on the card every n-th servo tick,
//! a trigger with pre-trigger samples, one-shot or continuous, drained from the card's ring.
//! The same thin skin as [`crate::api`]: check the pointers, look the handle up, call the SDK,
//! write the outputs, all inside [`guard`].

use crate::ffi::{read_in, Out};
use crate::registry::{self, mc_card};
use crate::result::{guard, mc_result, Failure, MC_ERR_BUFFER_TOO_SMALL};

/// The scope's configuration: the card's `mc_scope_config` register block. `source[k]` is
/// channel k's signal: `MC_SCOPE_SIG_*` | index << 16 (the axis for axis signals, the group for
/// group signals, 0 for the card's); `n_channels` 1..16; `divider` 1..65536 (a sample every
/// `divider` servo ticks); `mode` `MC_SCOPE_ONE_SHOT` (then `post_trigger` samples from the
/// trigger sample on) or `MC_SCOPE_CONTINUOUS`; `trigger` `MC_SCOPE_TRIG_*` with
/// `trigger_channel` and `level` (level crossing), `trigger_input` (input edge) and `edge`
/// `MC_SCOPE_RISING`, `_FALLING`, `_EITHER`; `pre_trigger` 0..1024 samples from before the
/// trigger. Start from `mc_scope_settings_default`.
#[allow(non_camel_case_types)]
pub type mc_scope_settings = firmware_proto::raw::mc_scope_config;
/// One sample: the servo tick it was taken at and each channel's value (counts, seconds,
/// volts, words as their double), exactly the card's status values of that tick.
#[allow(non_camel_case_types)]
pub type mc_scope_sample = firmware_proto::raw::mc_scope_sample;
/// The scope's state: `state` `MC_SCOPE_STATE_*`, the arm's seq, the capture's channels and
/// divider, the trigger sample's tick (0: not yet), the samples put in the ring and lost since
/// the arm.
#[allow(non_camel_case_types)]
pub type mc_scope_info = firmware_proto::raw::mc_scope_status;

/// Channels per sample, at most.
pub const MC_SCOPE_CHANNELS: u32 = 16;
/// Samples the card's ring holds (204.8 ms at 20 kHz).
pub const MC_SCOPE_RING_LEN: u32 = 4096;
/// Axis signals (index: the axis): commanded position, velocity, acceleration, actual
/// position and velocity, following error, DAC volts, the servo output before the clamp, the
/// raw encoder count, the servo law's P, I, D (velocity feedback) and feed-forward terms.
pub const MC_SCOPE_SIG_CMD_POS: u32 = 1;
pub const MC_SCOPE_SIG_CMD_VEL: u32 = 2;
pub const MC_SCOPE_SIG_CMD_ACC: u32 = 3;
pub const MC_SCOPE_SIG_ACT_POS: u32 = 4;
pub const MC_SCOPE_SIG_ACT_VEL: u32 = 5;
pub const MC_SCOPE_SIG_FERR: u32 = 6;
pub const MC_SCOPE_SIG_DAC: u32 = 7;
pub const MC_SCOPE_SIG_U_REQUEST: u32 = 8;
pub const MC_SCOPE_SIG_ENCODER: u32 = 9;
pub const MC_SCOPE_SIG_SERVO_P: u32 = 10;
pub const MC_SCOPE_SIG_SERVO_I: u32 = 11;
pub const MC_SCOPE_SIG_SERVO_D: u32 = 12;
pub const MC_SCOPE_SIG_SERVO_FF: u32 = 13;
/// Group signals (index: the group): path speed, path acceleration, distance along the move.
pub const MC_SCOPE_SIG_PATH_SPEED: u32 = 32;
pub const MC_SCOPE_SIG_PATH_ACC: u32 = 33;
pub const MC_SCOPE_SIG_PATH_POS: u32 = 34;
/// Card signals (index 0): debounced inputs, outputs, inputs as sampled.
pub const MC_SCOPE_SIG_INPUTS: u32 = 48;
pub const MC_SCOPE_SIG_OUTPUTS: u32 = 49;
pub const MC_SCOPE_SIG_INPUTS_RAW: u32 = 50;
/// `mode`.
pub const MC_SCOPE_ONE_SHOT: u32 = 0;
pub const MC_SCOPE_CONTINUOUS: u32 = 1;
/// `trigger`.
pub const MC_SCOPE_TRIG_IMMEDIATE: u32 = 0;
pub const MC_SCOPE_TRIG_COMMAND: u32 = 1;
pub const MC_SCOPE_TRIG_LEVEL: u32 = 2;
pub const MC_SCOPE_TRIG_INPUT: u32 = 3;
pub const MC_SCOPE_TRIG_FAULT: u32 = 4;
/// `edge`.
pub const MC_SCOPE_RISING: u32 = 0;
pub const MC_SCOPE_FALLING: u32 = 1;
pub const MC_SCOPE_EITHER: u32 = 2;
/// `mc_scope_info.state`.
pub const MC_SCOPE_STATE_IDLE: u32 = 0;
pub const MC_SCOPE_STATE_WAITING: u32 = 1;
pub const MC_SCOPE_STATE_CAPTURING: u32 = 2;
pub const MC_SCOPE_STATE_DONE: u32 = 3;
/// Triggered (`value`: the trigger sample's tick).
pub const MC_SCOPE_EVENT_TRIGGERED: i32 = 1;
/// A one-shot capture ended (`value`: its samples).
pub const MC_SCOPE_EVENT_DONE: i32 = 2;
/// A sample found the ring full (`value`: the samples lost since the arm).
pub const MC_SCOPE_EVENT_LOST: i32 = 3;

/// A configuration to start from: no channels, every tick, immediate trigger, one-shot.
/// Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_scope_settings_default(settings: *mut mc_scope_settings) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let s = mc_scope_settings {
            divider: 1,
            ..Default::default()
        };
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s) };
        Ok(())
    })
}

/// Check the configuration and have the card take it (`MC_ERR_SCOPE_*` for what it refuses;
/// `MC_ERR_SCOPE_STATE` while the scope is armed). Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_scope_configure(
    card: mc_card,
    settings: *const mc_scope_settings,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_scope_settings.
        let s = unsafe { read_in(settings, "settings") }?;
        Ok(registry::get(card)?.card.scope().configure_block(&s)?)
    })
}

/// Arm the scope: samples left in the ring are dropped, sampling starts into the pre-trigger
/// history, and the capture waits for its trigger. `seq` (may be NULL) receives the arm's seq.
/// Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_scope_arm(card: mc_card, seq: *mut u32) -> mc_result {
    guard(|| {
        let out = Out::optional(seq);
        let s = registry::get(card)?.card.scope().arm()?;
        if let Some(out) = out {
            // SAFETY: non-NULL; valid for writes by the caller's contract.
            unsafe { out.write(s) };
        }
        Ok(())
    })
}

/// Trigger the waiting scope at its next sample. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_scope_trigger(card: mc_card) -> mc_result {
    guard(|| Ok(registry::get(card)?.card.scope().trigger()?))
}

/// Stop the scope (the samples in the ring stay to be read). Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_scope_stop(card: mc_card) -> mc_result {
    guard(|| Ok(registry::get(card)?.card.scope().stop()?))
}

/// Take up to `len` samples from the ring, oldest first, into `buf`; `n` receives how many.
/// Never blocks. `buf` may be NULL only when `len` is 0.
#[no_mangle]
pub unsafe extern "C" fn mc_scope_read(
    card: mc_card,
    buf: *mut mc_scope_sample,
    len: usize,
    n: *mut usize,
) -> mc_result {
    guard(|| {
        let count = Out::new(n, "n")?;
        if buf.is_null() && len > 0 {
            return Err(Failure::null("buf"));
        }
        let mut got = Vec::new();
        registry::get(card)?.card.scope().read_max(&mut got, len)?;
        if got.len() > len {
            return Err(Failure::new(MC_ERR_BUFFER_TOO_SMALL, "scope samples"));
        }
        // SAFETY: got.len() <= len, `buf` valid for `len` writes by the caller's contract
        // (non-NULL when len > 0), written unaligned; `n` checked non-NULL.
        unsafe {
            for (i, s) in got.iter().enumerate() {
                buf.add(i).write_unaligned(mc_scope_sample {
                    tick: s.tick,
                    value: s.value,
                });
            }
            count.write(got.len());
        }
        Ok(())
    })
}

/// The scope's state, counters included. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_scope_get_info(card: mc_card, info: *mut mc_scope_info) -> mc_result {
    guard(|| {
        let out = Out::new(info, "info")?;
        let s = registry::get(card)?.card.scope().status()?;
        let i = mc_scope_info {
            state: s.state as u32,
            arm_seq: s.arm_seq,
            n_channels: s.channels as u32,
            divider: s.divider,
            trigger_tick: s.trigger_tick,
            samples: s.samples,
            lost: s.lost,
            ..Default::default()
        };
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(i) };
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use firmware_proto::raw;

    #[test]
    fn the_constants_are_the_cards() {
        let pairs = [
            (MC_SCOPE_CHANNELS, raw::MC_SCOPE_CHANNELS),
            (MC_SCOPE_RING_LEN, raw::MC_SCOPE_RING_LEN),
            (MC_SCOPE_SIG_CMD_POS, raw::MC_SIG_CMD_POS),
            (MC_SCOPE_SIG_CMD_VEL, raw::MC_SIG_CMD_VEL),
            (MC_SCOPE_SIG_CMD_ACC, raw::MC_SIG_CMD_ACC),
            (MC_SCOPE_SIG_ACT_POS, raw::MC_SIG_ACT_POS),
            (MC_SCOPE_SIG_ACT_VEL, raw::MC_SIG_ACT_VEL),
            (MC_SCOPE_SIG_FERR, raw::MC_SIG_FERR),
            (MC_SCOPE_SIG_DAC, raw::MC_SIG_DAC),
            (MC_SCOPE_SIG_U_REQUEST, raw::MC_SIG_U_REQUEST),
            (MC_SCOPE_SIG_ENCODER, raw::MC_SIG_ENCODER),
            (MC_SCOPE_SIG_SERVO_P, raw::MC_SIG_SERVO_P),
            (MC_SCOPE_SIG_SERVO_I, raw::MC_SIG_SERVO_I),
            (MC_SCOPE_SIG_SERVO_D, raw::MC_SIG_SERVO_D),
            (MC_SCOPE_SIG_SERVO_FF, raw::MC_SIG_SERVO_FF),
            (MC_SCOPE_SIG_PATH_SPEED, raw::MC_SIG_PATH_SPEED),
            (MC_SCOPE_SIG_PATH_ACC, raw::MC_SIG_PATH_ACC),
            (MC_SCOPE_SIG_PATH_POS, raw::MC_SIG_PATH_POS),
            (MC_SCOPE_SIG_INPUTS, raw::MC_SIG_INPUTS),
            (MC_SCOPE_SIG_OUTPUTS, raw::MC_SIG_OUTPUTS),
            (MC_SCOPE_SIG_INPUTS_RAW, raw::MC_SIG_INPUTS_RAW),
            (MC_SCOPE_ONE_SHOT, raw::MC_SCOPE_ONE_SHOT),
            (MC_SCOPE_CONTINUOUS, raw::MC_SCOPE_CONTINUOUS),
            (MC_SCOPE_TRIG_IMMEDIATE, raw::MC_SCOPE_TRIG_IMMEDIATE),
            (MC_SCOPE_TRIG_COMMAND, raw::MC_SCOPE_TRIG_COMMAND),
            (MC_SCOPE_TRIG_LEVEL, raw::MC_SCOPE_TRIG_LEVEL),
            (MC_SCOPE_TRIG_INPUT, raw::MC_SCOPE_TRIG_INPUT),
            (MC_SCOPE_TRIG_FAULT, raw::MC_SCOPE_TRIG_FAULT),
            (MC_SCOPE_RISING, raw::MC_SCOPE_RISING),
            (MC_SCOPE_FALLING, raw::MC_SCOPE_FALLING),
            (MC_SCOPE_EITHER, raw::MC_SCOPE_EITHER),
            (MC_SCOPE_STATE_IDLE, raw::MC_SCOPE_IDLE),
            (MC_SCOPE_STATE_WAITING, raw::MC_SCOPE_WAITING),
            (MC_SCOPE_STATE_CAPTURING, raw::MC_SCOPE_CAPTURING),
            (MC_SCOPE_STATE_DONE, raw::MC_SCOPE_DONE),
        ];
        for (k, (a, b)) in pairs.iter().enumerate() {
            assert_eq!(a, b, "pair {k}");
        }
        assert_eq!(MC_SCOPE_EVENT_TRIGGERED, raw::MC_SCOPE_EV_TRIGGERED as i32);
        assert_eq!(MC_SCOPE_EVENT_DONE, raw::MC_SCOPE_EV_DONE as i32);
        assert_eq!(MC_SCOPE_EVENT_LOST, raw::MC_SCOPE_EV_LOST as i32);
    }
}

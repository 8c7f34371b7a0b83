//! The card's scope (layout 1.8): up to 16 channels sampled on the card every n-th servo tick,
//! a trigger with pre-trigger samples, one-shot or continuous, drained from the card's ring.
//! The same thin skin as [`crate::api`]: check the pointers, look the handle up, call the SDK,
//! write the outputs, all inside `guard`.

use crate::ffi::{read_in, Out};
use crate::registry::{self, mc_card};
use crate::result::{guard, mc_result, Failure, MC_ERR_BUFFER_TOO_SMALL};
use motioncard_sdk::ScopeStatus;

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
/// One sample: the servo tick it was taken at and each channel's value, exactly the card's
/// status value of that tick in the card's units, not user units (the scope runs on the
/// card): positions, following errors and distances in encoder counts, velocities in
/// counts/s, accelerations in counts/s², the DAC in volts, times in seconds, states, bits
/// and words as their double. Divide a position by the axis's scale (`mc_set_scale`) for
/// user units.
#[allow(non_camel_case_types)]
pub type mc_scope_sample = firmware_proto::raw::mc_scope_sample;
/// The scope's state: `state` `MC_SCOPE_STATE_*`, the arm's seq, the capture's channels and
/// divider, the trigger sample's tick (0: not yet), the samples put in the ring and lost since
/// the arm, and `pre_captured`: how many pre-trigger samples the capture took, first in the
/// ring (`pre_trigger`, or fewer when the trigger came before that many samples had been
/// taken since the arm; 0 until the trigger).
#[allow(non_camel_case_types)]
pub type mc_scope_info = firmware_proto::raw::mc_scope_status;

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

/// The C view of the scope's status.
fn info_of(s: &ScopeStatus) -> mc_scope_info {
    mc_scope_info {
        state: s.state as u32,
        arm_seq: s.arm_seq,
        n_channels: s.channels as u32,
        divider: s.divider,
        trigger_tick: s.trigger_tick,
        samples: s.samples,
        lost: s.lost,
        pre_captured: s.pre_trigger,
        ..Default::default()
    }
}

/// The scope's state, counters included. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_scope_get_info(card: mc_card, info: *mut mc_scope_info) -> mc_result {
    guard(|| {
        let out = Out::new(info, "info")?;
        let s = registry::get(card)?.card.scope().status()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(info_of(&s)) };
        Ok(())
    })
}

/// Wait up to `timeout_ms` (emulated time on a stepped sim, which is stepped) until the
/// one-shot capture armed last is done, or the scope was stopped; `info` (may be NULL)
/// receives the scope's state then (as `mc_scope_get_info`). `MC_ERR_TIMEOUT` while it still
/// waits for its trigger or captures; `MC_ERR_SCOPE_STATE` when the scope is not armed or
/// runs a continuous capture (which never ends: `mc_scope_stop` it). Reads nothing from the
/// ring: a capture longer than `MC_SCOPE_RING_LEN` samples loses what does not fit unless
/// another thread calls `mc_scope_read` meanwhile. Blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_scope_wait(
    card: mc_card,
    timeout_ms: u32,
    info: *mut mc_scope_info,
) -> mc_result {
    guard(|| {
        let out = Out::optional(info);
        let s = registry::get(card)?
            .card
            .scope()
            .wait_done(std::time::Duration::from_millis(timeout_ms.into()))?;
        if let Some(out) = out {
            // SAFETY: non-NULL; valid for writes by the caller's contract.
            unsafe { out.write(info_of(&s)) };
        }
        Ok(())
    })
}

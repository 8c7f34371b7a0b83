//! Layout 1.8: configuration files (`mc_config_save`, `mc_config_load`, `mc_config_diff`) and
//! the settings the card holds, read back from the card (`mc_axis_get_settings` and the
//! other getters). The file's format and checks are the SDK's (`motioncard_sdk::Config`).

use crate::api::axis_of;
use crate::ffi::{uri, Out, StrBuf};
use crate::group::group_of;
use crate::homing::mc_homing_settings;
use crate::io::mc_io_settings;
use crate::registry::{self, mc_card};
use crate::result::{guard, mc_result};
use crate::types::{
    mc_axis_settings, mc_filter_settings, mc_group_settings, mc_pdplus_settings, mc_safety_settings,
};
use std::ffi::c_char;

/// The card-wide safety settings as the card holds them (`mc_get_card_safety`): the register
/// map's `mc_safety_config` block (watchdog timeout in µs, the e-stop input's stop category,
/// the maximum stop time in µs).
#[allow(non_camel_case_types)]
pub type mc_card_safety_settings = firmware_proto::raw::mc_safety_config;

/// Save what the card holds, read back from the card (never this library's memory), to the
/// TOML file `path` (created or replaced). Loading the file on a card of the same axes and
/// saving it again gives the same bytes. Blocks until the card answers its read-backs.
#[no_mangle]
pub unsafe extern "C" fn mc_config_save(card: mc_card, path: *const c_char) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a NUL-terminated string.
        let path = unsafe { uri(path, "path") }?;
        let e = registry::get(card)?;
        Ok(e.card.save_config_file(path)?)
    })
}

/// Load the TOML configuration file `path`: the whole file is checked first with the card's
/// own rules, and nothing is applied when anything is wrong (`MC_ERR_CONFIG_FILE`;
/// `mc_last_error_message` gives `FILE:LINE: KEY: what is wrong`, e.g.
/// `a.toml:31: axis.0.ffpiv.kp: ...`); then the sections that differ from what the card holds
/// are applied and the card is read back and compared. A section the card refuses after the
/// checks passed (its state changed meanwhile) returns the refusal's code, and the message
/// lists what was applied before it. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_config_load(card: mc_card, path: *const c_char) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a NUL-terminated string.
        let path = unsafe { uri(path, "path") }?;
        let e = registry::get(card)?;
        e.card.load_config_file(path)?;
        Ok(())
    })
}

/// Compare the TOML configuration file `path` with what the card holds, key by key (the file
/// is checked as by `mc_config_load`; nothing is applied). `*differences` (may be NULL) is the
/// number of keys that differ (0: the card holds what the file says); the text, one
/// `KEY: file VALUE, card VALUE` line per key, is copied into `buf` (`len` bytes, NUL
/// included; `*needed` its size: `MC_ERR_BUFFER_TOO_SMALL` when it does not fit, and then
/// nothing else is written). Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_config_diff(
    card: mc_card,
    path: *const c_char,
    differences: *mut u32,
    buf: *mut c_char,
    len: usize,
    needed: *mut usize,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a NUL-terminated string.
        let path = unsafe { uri(path, "path") }?;
        let out = StrBuf::new(buf, len, needed)?;
        let count = Out::optional(differences);
        let e = registry::get(card)?;
        let d = e.card.diff_config_file(path)?;
        let mut s = String::new();
        for x in &d {
            let card = x.card.as_deref().unwrap_or("(none)");
            s.push_str(&format!("{}: file {}, card {card}\n", x.key, x.file));
        }
        // SAFETY: the caller gives `len` writable bytes at `buf` and a writable `*needed`.
        unsafe { out.fill(&s) }?;
        if let Some(c) = count {
            // SAFETY: non-NULL; valid for writes by the caller's contract.
            unsafe { c.write(d.len() as u32) };
        }
        Ok(())
    })
}

/// The axis's servo configuration as the card holds it (read back from the card): servo law,
/// FFPIV gains, DAC limit, in-position windows, jog limits and `scale` (counts per user unit,
/// which the card keeps for hosts). Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_get_settings(
    card: mc_card,
    axis: u32,
    settings: *mut mc_axis_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let (_, a) = axis_of(card, axis)?;
        let s = a.settings()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s) };
        Ok(())
    })
}

/// The axis's PD+ law as the card holds it (read back): `*active` is 1 and `*settings` the
/// gains, drive model and Umax when the axis runs PD+, else `*active` is 0 and `*settings` all
/// zero. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_get_pdplus(
    card: mc_card,
    axis: u32,
    settings: *mut mc_pdplus_settings,
    active: *mut u32,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let on = Out::new(active, "active")?;
        let (_, a) = axis_of(card, axis)?;
        let p = a.pdplus_settings()?;
        // SAFETY: both checked non-NULL; valid for writes by the caller's contract.
        unsafe {
            on.write(u32::from(p.is_some()));
            out.write(p.unwrap_or(firmware_proto::AxisPdPlus {
                gains: Default::default(),
                drive: Default::default(),
                umax: 0.0,
                _reserved: [0.0; 8],
            }));
        }
        Ok(())
    })
}

/// The axis's acc/dec filters as the card holds them (read back). Blocks until the card
/// answers.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_get_filters(
    card: mc_card,
    axis: u32,
    settings: *mut mc_filter_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let (_, a) = axis_of(card, axis)?;
        let f = a.filter_settings()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(f.into()) };
        Ok(())
    })
}

/// The axis's safety configuration as the card holds it (read back), in user units. Blocks
/// until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_get_safety(
    card: mc_card,
    axis: u32,
    settings: *mut mc_safety_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let (_, a) = axis_of(card, axis)?;
        let s = a.safety_settings()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s.into()) };
        Ok(())
    })
}

/// The axis's homing configuration as the card holds it (read back). Blocks until the card
/// answers.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_get_homing(
    card: mc_card,
    axis: u32,
    settings: *mut mc_homing_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let (_, a) = axis_of(card, axis)?;
        let h = a.homing_settings()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(h) };
        Ok(())
    })
}

/// The digital inputs' configuration as the card holds it (read back). Blocks until the card
/// answers.
#[no_mangle]
pub unsafe extern "C" fn mc_get_io_settings(
    card: mc_card,
    settings: *mut mc_io_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let s = registry::get(card)?.card.io_settings()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s) };
        Ok(())
    })
}

/// The card-wide safety settings as the card holds them (read back). Blocks until the card
/// answers.
#[no_mangle]
pub unsafe extern "C" fn mc_get_card_safety(
    card: mc_card,
    settings: *mut mc_card_safety_settings,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let s = registry::get(card)?.card.safety_settings()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(s) };
        Ok(())
    })
}

/// The servo rate the card runs at (read back), Hz. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_get_servo_rate(card: mc_card, hz: *mut u32) -> mc_result {
    guard(|| {
        let out = Out::new(hz, "hz")?;
        let r = registry::get(card)?.card.servo_rate()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(r) };
        Ok(())
    })
}

/// A group's configuration as the card holds it (read back), the tolerance in the first
/// axis's user units: `*configured` is 1 and `*settings` the configuration, or `*configured`
/// is 0 and `*settings` all zero for a group that is not configured. Blocks until the card
/// answers.
#[no_mangle]
pub unsafe extern "C" fn mc_group_get_settings(
    card: mc_card,
    group: u32,
    settings: *mut mc_group_settings,
    configured: *mut u32,
) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let on = Out::new(configured, "configured")?;
        let (_, g) = group_of(card, group)?;
        let s = g.settings()?;
        // SAFETY: both checked non-NULL; valid for writes by the caller's contract.
        unsafe {
            on.write(u32::from(s.is_some()));
            out.write(s.as_ref().map(Into::into).unwrap_or_default());
        }
        Ok(())
    })
}

//! Gantry axes (layout 1.10): a master and its slaves formed into one logical axis, homed and
//! squared, read and dissolved. The same thin skin as [`crate::api`]: check the pointers, look
//! the handle up, call the SDK (`Card::gantry_at`, `Gantry::home`, `status`, `dissolve`),
//! write the outputs only on success, all inside `guard`. The gantry is commanded through
//! its master axis (every `mc_` motion call on the master moves the bridge).

use crate::api::ms;
use crate::ffi::{read_in, read_slice, Out};
use crate::registry::{self, mc_card};
use crate::result::{guard, mc_result};
use motioncard_sdk::{GantryConfig, GantryPhase};

/// Most slaves of a gantry.
pub const MC_GANTRY_SLAVES_MAX: u32 = 4;

/// A gantry's yaw loop and skew limit (the limit in the master's user units).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_gantry_settings {
    /// Proportional gain of the yaw loop, 1/s² (0..1e9): the slave's acceleration correction
    /// per count of skew.
    pub kp: f64,
    /// Integral gain of the yaw loop, 1/s³ (0..1e12).
    pub ki: f64,
    /// The skew beyond which every axis of the gantry stops (> 0).
    pub skew_limit: f64,
}

/// A gantry as the card reports it (the master's user units).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(non_camel_case_types)]
pub struct mc_gantry_info {
    /// 1 coupled, 2 homing, 3 squaring (`MC_GANTRY_*` of the register map).
    pub phase: u32,
    /// The master axis.
    pub master: u32,
    /// Slaves in use.
    pub nslaves: u32,
    /// Nonzero once `mc_gantry_home` squared the bridge.
    pub squared: u32,
    /// The slave axes.
    pub slave: [u32; 4],
    /// Each slave's skew of the last tick: slave actual - master actual - offset in force.
    pub skew: [f64; 4],
    /// Each slave's largest |skew| while coupled since the gantry was formed.
    pub max_skew: [f64; 4],
    /// Each slave's offset in force.
    pub hold: [f64; 4],
}

/// Form gantry `index` (0..3) of `master` and `nslaves` slaves (1..4, each with the master's
/// scale), `offsets` the slaves' square offsets (NULL: all 0). Every member at rest, all
/// powered or all disabled; nothing moves. Refused: `MC_ERR_GANTRY_AXES` (the master among the
/// slaves, a slave twice, a count), `MC_ERR_BAD_AXIS`, `MC_ERR_GANTRY_GAINS`,
/// `MC_ERR_NOT_FINITE`, `MC_ERR_GANTRY_IN_USE` (a member in another gantry, geared, streaming;
/// a slave in a group), `MC_ERR_GANTRY_STATE`, `MC_ERR_BAD_CONFIG` (different scales).
#[no_mangle]
pub unsafe extern "C" fn mc_gantry_form(
    card: mc_card,
    index: u32,
    master: u32,
    slaves: *const u32,
    nslaves: usize,
    settings: *const mc_gantry_settings,
    offsets: *const f64,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_gantry_settings.
        let s = unsafe { read_in(settings, "settings") }?;
        let n = nslaves.min(MC_GANTRY_SLAVES_MAX as usize + 1);
        // SAFETY: the caller gives nslaves readable axis numbers.
        let sl = unsafe { read_slice(slaves, n, "slaves") }?;
        let off = if offsets.is_null() {
            Vec::new()
        } else {
            // SAFETY: the caller gives NULL or nslaves readable offsets.
            unsafe { read_slice(offsets, n, "offsets") }?
        };
        let e = registry::get(card)?;
        let slaves: Vec<usize> = sl.iter().map(|&a| a as usize).collect();
        let cfg = GantryConfig {
            kp: s.kp,
            ki: s.ki,
            skew_limit: s.skew_limit,
            offsets: off,
        };
        e.card
            .gantry_at(index as usize, master as usize, &slaves, &cfg)?;
        Ok(())
    })
}

/// Home gantry `index` and wait up to `timeout_ms`: each side runs its own homing method, then
/// the slaves square the bridge to their offsets. `*skew` (may be NULL): slave 0's skew once
/// squared. `MC_ERR_HOMING_FAILED` when a side failed (the message names the gantry and the
/// axis; the gantry is coupled where it stopped), `MC_ERR_GANTRY_STATE` when a member is not at
/// rest, `MC_ERR_TIMEOUT`.
#[no_mangle]
pub unsafe extern "C" fn mc_gantry_home(
    card: mc_card,
    index: u32,
    timeout_ms: u32,
    skew: *mut f64,
) -> mc_result {
    guard(|| {
        let out = Out::optional(skew);
        let e = registry::get(card)?;
        let g = e.card.gantry_handle(index as usize)?;
        let s = g.home()?.wait(ms(timeout_ms))?;
        if let Some(out) = out {
            // SAFETY: a non-NULL `skew` is valid for a write by the caller's contract.
            unsafe { out.write(s) };
        }
        Ok(())
    })
}

/// Gantry `index`'s status. `MC_ERR_GANTRY_STATE` when it is not formed.
#[no_mangle]
pub unsafe extern "C" fn mc_gantry_get_info(
    card: mc_card,
    index: u32,
    info: *mut mc_gantry_info,
) -> mc_result {
    guard(|| {
        let out = Out::new(info, "info")?;
        let e = registry::get(card)?;
        let st = e.card.gantry_handle(index as usize)?.status()?;
        let mut i = mc_gantry_info {
            phase: match st.phase {
                GantryPhase::Coupled => 1,
                GantryPhase::Homing => 2,
                GantryPhase::Squaring => 3,
            },
            master: st.master as u32,
            nslaves: st.slaves.len() as u32,
            squared: u32::from(st.squared),
            ..Default::default()
        };
        for (k, s) in st.slaves.iter().enumerate().take(4) {
            i.slave[k] = s.axis as u32;
            i.skew[k] = s.skew;
            i.max_skew[k] = s.max_skew;
            i.hold[k] = s.hold;
        }
        // SAFETY: `info` is valid for a write by the caller's contract.
        unsafe { out.write(i) };
        Ok(())
    })
}

/// Dissolve gantry `index`: the master at rest (`MC_ERR_GANTRY_STATE`); the slaves hold where
/// they are, each its own axis again.
#[no_mangle]
pub unsafe extern "C" fn mc_gantry_dissolve(card: mc_card, index: u32) -> mc_result {
    guard(|| {
        let e = registry::get(card)?;
        e.card.gantry_handle(index as usize)?.dissolve()?;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::api::{mc_close, mc_enable, mc_open_sim_stepped};
    use motioncard_sdk::ErrorKind;

    /// Formed, read and dissolved through the C calls on a stepped card, each refusal its own
    /// code.
    #[test]
    fn a_gantry_from_c() {
        let mut card: mc_card = 0;
        unsafe {
            assert_eq!(mc_open_sim_stepped(2, 10_000, &mut card), 0);
            for a in 0..2 {
                assert_eq!(mc_enable(card, a), 0);
            }
            let s = mc_gantry_settings {
                kp: 1e6,
                ki: 0.0,
                skew_limit: 100.0,
            };
            let same = [0u32];
            let code = mc_gantry_form(card, 0, 0, same.as_ptr(), 1, &s, std::ptr::null());
            assert_eq!(code, ErrorKind::GantryAxes.code());
            let bad = mc_gantry_settings { kp: -1.0, ..s };
            let slaves = [1u32];
            let code = mc_gantry_form(card, 0, 0, slaves.as_ptr(), 1, &bad, std::ptr::null());
            assert_eq!(code, ErrorKind::GantryGains.code());
            let mut info = mc_gantry_info::default();
            assert_eq!(
                mc_gantry_get_info(card, 0, &mut info),
                ErrorKind::GantryState.code()
            );
            let offs = [2.5];
            assert_eq!(
                mc_gantry_form(card, 0, 0, slaves.as_ptr(), 1, &s, offs.as_ptr()),
                0
            );
            assert_eq!(mc_gantry_get_info(card, 0, &mut info), 0);
            assert_eq!((info.phase, info.master, info.nslaves), (1, 0, 1));
            assert_eq!(info.slave[0], 1);
            assert_eq!(mc_gantry_dissolve(card, 0), 0);
            assert_eq!(mc_gantry_dissolve(card, 0), ErrorKind::GantryState.code());
            assert_eq!(mc_close(card), 0);
        }
    }
}

//! Layout 1.11: group homing (PLCopen Part 4 MC_GroupHome) from C, the same thin skin as
//! [`crate::api`].

use crate::api::ms;
use crate::ffi::{read_slice, Out};
use crate::group::group_of;
use crate::registry::mc_card;
use crate::result::{guard, mc_result};

/// Home group `group` in stages and wait up to `timeout_ms`. The order is `nstages` stages of
/// group axis indices (0: the group's first axis, X), one after another in `axes`, stage k
/// holding `stage_sizes[k]` of them: `axes = {2, 0, 1}`, `stage_sizes = {1, 2}` homes Z, then X
/// and Y together. `nstages` 0 (the pointers may be NULL): the group's configured order (the
/// configuration file's `home_order`). Each axis homes with its own homing settings; a
/// member that is a gantry's master homes its gantry. `*stages_run` (may be NULL): the stages
/// run. The group is in GroupHoming until it ends, then GroupStandby. Refused:
/// `MC_ERR_HOME_AXIS` (an index the group does not have), `MC_ERR_HOME_TWICE` (an axis twice),
/// `MC_ERR_HOME_STAGE` (an empty stage; or no order and none configured), `MC_ERR_BAD_CONFIG`
/// (more than 8 stages), `MC_ERR_GROUP_DISABLED`, `MC_ERR_INVALID_STATE` (not at rest),
/// `MC_ERR_AXIS_BUSY`, and each axis's homing refusals. `MC_ERR_HOMING_FAILED` when it failed
/// as a whole (the message names the axis and its error; the group's other members were
/// halted and the group is at rest), `MC_ERR_TIMEOUT`.
#[no_mangle]
pub unsafe extern "C" fn mc_group_home(
    card: mc_card,
    group: u32,
    axes: *const u32,
    stage_sizes: *const u32,
    nstages: usize,
    timeout_ms: u32,
    stages_run: *mut u32,
) -> mc_result {
    guard(|| {
        let out = Out::optional(stages_run);
        let (sizes, flat) = if nstages == 0 {
            (Vec::new(), Vec::new())
        } else {
            // SAFETY: the caller gives nstages readable sizes.
            let sizes = unsafe { read_slice(stage_sizes, nstages, "stage_sizes") }?;
            let total = sizes.iter().map(|&n| n as usize).sum();
            // SAFETY: the caller gives as many readable axes as the sizes add up to.
            let flat = unsafe { read_slice(axes, total, "axes") }?;
            (sizes, flat)
        };
        let mut stages: Vec<Vec<usize>> = Vec::with_capacity(sizes.len());
        let mut at = 0;
        for &n in &sizes {
            let n = n as usize;
            stages.push(flat[at..at + n].iter().map(|&a| a as usize).collect());
            at += n;
        }
        let order: Vec<&[usize]> = stages.iter().map(Vec::as_slice).collect();
        let (_e, g) = group_of(card, group)?;
        let run = g.home(&order)?.wait(ms(timeout_ms))?;
        if let Some(out) = out {
            // SAFETY: a non-NULL `stages_run` is valid for a write by the caller's contract.
            unsafe { out.write(run as u32) };
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::api::{mc_close, mc_enable, mc_open_sim_stepped};
    use crate::group::{
        mc_group_configure, mc_group_disable, mc_group_enable, mc_group_settings_new,
    };
    use crate::registry;
    use crate::types::mc_group_settings;
    use motioncard_sdk::{ErrorKind, GroupState};

    /// A group of three axes homed from C in two stages (each axis's boot method: the current
    /// position), and each refusal its own code; the order configured through
    /// `mc_group_settings` (read back by `mc_group_get_settings`, a bad one refused with the
    /// configuration kept) is the one run with no stages given.
    #[test]
    fn group_homing_from_c() {
        let mut card = 0;
        unsafe {
            assert_eq!(mc_open_sim_stepped(3, 10_000, &mut card), 0);
            for a in 0..3 {
                assert_eq!(mc_enable(card, a), 0);
            }
            let mut set = mc_group_settings::default();
            assert_eq!(mc_group_settings_new([0, 1, 2].as_ptr(), 3, &mut set), 0);
            assert_eq!(set.home_stages, 0, "none by default");
            assert_eq!(mc_group_configure(card, 0, &set), 0);
            assert_eq!(mc_group_enable(card, 0), 0);
            let home = |axes: &[u32], sizes: &[u32]| {
                let mut run = 0u32;
                let code = mc_group_home(
                    card,
                    0,
                    axes.as_ptr(),
                    sizes.as_ptr(),
                    sizes.len(),
                    10_000,
                    &mut run,
                );
                (code, run)
            };
            assert_eq!(home(&[3], &[1]).0, ErrorKind::HomeAxis.code());
            assert_eq!(home(&[0, 1, 0], &[2, 1]).0, ErrorKind::HomeTwice.code());
            assert_eq!(home(&[0], &[1, 0]).0, ErrorKind::HomeStage.code());
            let none = mc_group_home(
                card,
                0,
                std::ptr::null(),
                std::ptr::null(),
                0,
                1000,
                std::ptr::null_mut(),
            );
            assert_eq!(none, ErrorKind::HomeStage.code());
            // Z, then X and Y together, configured as masks and read back.
            assert_eq!(mc_group_disable(card, 0), 0);
            let ordered = mc_group_settings {
                home_stages: 2,
                home_order: [1 << 2, 1 << 0 | 1 << 1, 0, 0, 0, 0, 0, 0],
                ..set
            };
            assert_eq!(mc_group_configure(card, 0, &ordered), 0);
            let (mut back, mut configured) = (mc_group_settings::default(), 0u32);
            assert_eq!(
                crate::config::mc_group_get_settings(card, 0, &mut back, &mut configured),
                0
            );
            assert_eq!((configured, back), (1, ordered));
            for (stages, masks, code) in [
                (2, [1 << 2, 1 << 2 | 1 << 1], ErrorKind::HomeTwice),
                (1, [1 << 3, 0], ErrorKind::HomeAxis),
                (1, [1 << 9, 0], ErrorKind::HomeAxis),
                (2, [1, 0], ErrorKind::HomeStage),
                (9, [1, 2], ErrorKind::BadConfig),
            ] {
                let mut bad = ordered;
                bad.home_stages = stages;
                bad.home_order[..2].copy_from_slice(&masks);
                assert_eq!(mc_group_configure(card, 0, &bad), code.code(), "{masks:?}");
                assert_eq!(
                    crate::config::mc_group_get_settings(card, 0, &mut back, &mut configured),
                    0
                );
                assert_eq!(back, ordered, "{masks:?}: kept");
            }
            assert_eq!(mc_group_enable(card, 0), 0);
            let run = {
                let mut run = 0u32;
                let code = mc_group_home(
                    card,
                    0,
                    std::ptr::null(),
                    std::ptr::null(),
                    0,
                    10_000,
                    &mut run,
                );
                (code, run)
            };
            assert_eq!(run, (0, 2));
            // An order given in the call still runs in place of the configured one.
            assert_eq!(home(&[1, 0, 2], &[2, 1]), (0, 2));
            let e = registry::get(card).unwrap();
            let g = e.card.group(0).unwrap();
            assert_eq!(g.status().unwrap().0, GroupState::Standby);
            for a in 0..3 {
                assert!(
                    e.card.axis(a).unwrap().status().unwrap().homed(),
                    "axis {a}"
                );
            }
            drop(e);
            assert_eq!(mc_close(card), 0);
        }
    }
}

//! Raw commands: [`mc_send_raw`] and the register map's opcodes (`MC_OP_`), for tools and tests
//! that need what the typed calls would refuse. The numbers are the card's (`mc_dpram.h`);
//! a test holds them equal to firmware-proto's bindings, one for each opcode the card knows.

use crate::ffi::Out;
use crate::registry;
use crate::result::{guard, mc_result, Failure};
use motioncard_sdk::proto::{Command, Opcode};
use motioncard_sdk::ErrorKind;

/// Does nothing but answer: the round-trip probe.
pub const MC_OP_NOP: u32 = 1;
/// MC_Power, Enable = TRUE.
pub const MC_OP_POWER_ON: u32 = 2;
/// MC_Power, Enable = FALSE.
pub const MC_OP_POWER_OFF: u32 = 3;
/// MC_MoveAbsolute: args target, vmax, amax, dmax, j1, j3, j5, j7.
pub const MC_OP_MOVE_ABSOLUTE: u32 = 4;
/// MC_MoveRelative: args distance, vmax, amax, dmax, j1, j3, j5, j7.
pub const MC_OP_MOVE_RELATIVE: u32 = 5;
/// MC_Halt: args dmax, jerk.
pub const MC_OP_HALT: u32 = 6;
/// MC_Stop (Execute rising): args dmax, jerk.
pub const MC_OP_STOP: u32 = 7;
/// MC_Stop (Execute falling): leave Stopping once at rest.
pub const MC_OP_STOP_RELEASE: u32 = 8;
/// MC_Reset.
pub const MC_OP_RESET: u32 = 9;
/// Validate and copy `axis_config[axis]`.
pub const MC_OP_APPLY_AXIS_CONFIG: u32 = 10;
/// Validate and copy `card_config`.
pub const MC_OP_APPLY_CARD_CONFIG: u32 = 11;
/// MC_MoveAdditive: args distance from the target of the last move, then the limits as
/// `MoveAbsolute`.
pub const MC_OP_MOVE_ADDITIVE: u32 = 12;
/// MC_MoveVelocity: args velocity (signed), amax, dmax, jerk.
pub const MC_OP_MOVE_VELOCITY: u32 = 13;
/// Jog: velocity mode at the axis's jog limits; arg velocity (signed).
pub const MC_OP_JOG: u32 = 14;
/// MC_SetOverride: arg velocity factor, 0 to `OVERRIDE_MAX`.
pub const MC_OP_SET_OVERRIDE: u32 = 15;
/// Validate and copy `group_config[group]`.
pub const MC_OP_GROUP_CONFIGURE: u32 = 16;
/// Validate and copy `axis_filter[axis]`.
pub const MC_OP_APPLY_AXIS_FILTER: u32 = 17;
/// MC_GroupEnable.
pub const MC_OP_GROUP_ENABLE: u32 = 18;
/// MC_GroupDisable.
pub const MC_OP_GROUP_DISABLE: u32 = 19;
/// MC_GroupStop (Execute rising): args dmax, jerk.
pub const MC_OP_GROUP_STOP: u32 = 20;
/// MC_GroupStop (Execute falling).
pub const MC_OP_GROUP_STOP_RELEASE: u32 = 21;
/// MC_GroupReset.
pub const MC_OP_GROUP_RESET: u32 = 22;
/// MC_GroupHalt: args dmax, jerk.
pub const MC_OP_GROUP_HALT: u32 = 23;
/// MC_MoveLinearAbsolute / MC_MoveLinearRelative.
pub const MC_OP_GROUP_MOVE_LINEAR: u32 = 24;
/// MC_MoveCircularAbsolute / MC_MoveCircularRelative (and helical).
pub const MC_OP_GROUP_MOVE_CIRCULAR: u32 = 25;
/// Synchronised multi-axis point-to-point (Kim eq 10–14).
pub const MC_OP_GROUP_MOVE_PTP: u32 = 26;
/// Stage per-axis limits for the next point-to-point move: args first group axis, count, then
/// v, a, d, j of each.
pub const MC_OP_GROUP_PTP_LIMITS: u32 = 30;
/// MC_SetOverride of a group: args feed factor (lines, arcs), rapid factor (point-to-point
/// moves).
pub const MC_OP_GROUP_SET_OVERRIDE: u32 = 31;
/// Open a NURBS curve transfer: args degree, n_ctrl, n_knots, feed, accel, jerk, chord
/// tolerance, saturation budget.
pub const MC_OP_NURBS_BEGIN: u32 = 27;
/// Continuation entry: args offset, count, values.
pub const MC_OP_NURBS_DATA: u32 = 28;
/// Validate the curve and queue the move.
pub const MC_OP_NURBS_END: u32 = 29;
/// Validate and copy `safety` (watchdog timeout, e-stop input category).
pub const MC_OP_APPLY_SAFETY_CONFIG: u32 = 32;
/// Validate and copy `axis_safety[axis]` (limits, following error, stop ramp).
pub const MC_OP_APPLY_AXIS_SAFETY: u32 = 33;
/// E-stop every axis: arg category (0, 1 or 2). Latched.
pub const MC_OP_ESTOP: u32 = 34;
/// Clear the card-wide latches (watchdog, e-stop) once their causes are gone.
pub const MC_OP_SAFETY_RESET: u32 = 35;
/// A host begins its session (flags: the session id): a previous session still open stops every
/// enabled axis with `StopReason::HostChanged`.
pub const MC_OP_HOST_ATTACH: u32 = 36;
/// A host ends its session cleanly (flags: the session id): moving axes halt, the watchdog is
/// disarmed, no fault.
pub const MC_OP_HOST_DETACH: u32 = 37;
/// Validate and copy `axis_homing[axis]` (the CiA 402 homing method and its limits).
pub const MC_OP_APPLY_AXIS_HOMING: u32 = 48;
/// MC_Home: arg the position the home point reads (before the home offset).
pub const MC_OP_HOME: u32 = 49;
/// MC_SetPosition: arg the position (flags: `SET_POSITION_RELATIVE`).
pub const MC_OP_SET_POSITION: u32 = 50;
/// Queue a line in the group's path: args id, feed, tolerance, targets.
pub const MC_OP_PATH_LINE: u32 = 56;
/// Queue an arc or helix in the group's path: args id, feed, tolerance, end, aux, the other
/// axes' targets.
pub const MC_OP_PATH_ARC: u32 = 57;
/// Queue a dwell in the group's path: args id, seconds.
pub const MC_OP_PATH_DWELL: u32 = 58;
/// An output action for the next path segment: args output, on, distance.
pub const MC_OP_PATH_OUTPUT: u32 = 59;
/// Validate and copy `group_path[group]` (look-ahead, low water, axis limits).
pub const MC_OP_APPLY_GROUP_PATH: u32 = 60;
/// Set the digital outputs in a mask: args mask, value.
pub const MC_OP_SET_OUTPUTS: u32 = 61;
/// A NURBS curve as one path segment (its data follows as for a NURBS move).
pub const MC_OP_PATH_NURBS: u32 = 62;
/// Validate and copy `io_config` (input polarity, debounce, edge events).
pub const MC_OP_APPLY_IO_CONFIG: u32 = 64;
/// Arm a position-compare channel: args channel, output, pulse_us, low_water, position or
/// start, pitch, count; flags mode and direction.
pub const MC_OP_COMPARE_ARM: u32 = 65;
/// Queue positions in a compare channel's table: args channel, n, positions.
pub const MC_OP_COMPARE_TABLE: u32 = 66;
/// Disarm a compare channel and drop its table: arg channel.
pub const MC_OP_COMPARE_DISARM: u32 = 67;
/// MC_TouchProbe: args channel, input, window_lo, window_hi; flags edges and mode.
pub const MC_OP_PROBE_ARM: u32 = 68;
/// MC_AbortTrigger: arg channel.
pub const MC_OP_PROBE_ABORT: u32 = 69;
/// Layout 1.7 (sync): MC_GearIn: args master, numerator, denominator, vmax, amax, jerk; flags
/// the master source (`MasterSource`).
pub const MC_OP_GEAR_IN: u32 = 80;
/// MC_GearInPos: as `GearIn`, then master and slave sync positions.
pub const MC_OP_GEAR_IN_POS: u32 = 81;
/// MC_GearOut: the slave leaves the coupling in velocity mode at its velocity.
pub const MC_OP_GEAR_OUT: u32 = 82;
/// Open a PT/PVT stream: args vmax, amax, low water; flags `MC_PVT_PT`.
pub const MC_OP_PVT_BEGIN: u32 = 83;
/// Append points: args count, then time, position, velocity of each.
pub const MC_OP_PVT_POINTS: u32 = 84;
/// Start the streams of an axis mask.
pub const MC_OP_PVT_START: u32 = 85;
/// Open a cam table: args table, points; flags cubic, periodic.
pub const MC_OP_CAM_TABLE: u32 = 86;
/// Cam table points: args table, first index, count, then master, slave of each.
pub const MC_OP_CAM_DATA: u32 = 87;
/// MC_CamIn: args master, table, offsets, scales, vmax, amax, jerk.
pub const MC_OP_CAM_IN: u32 = 88;
/// MC_CamOut: as `GearOut`.
pub const MC_OP_CAM_OUT: u32 = 89;
/// Layout 1.8: validate and copy `scope_config`.
pub const MC_OP_SCOPE_CONFIGURE: u32 = 90;
/// Arm the scope: sample into the pre-trigger history, wait for the trigger.
pub const MC_OP_SCOPE_ARM: u32 = 91;
/// Trigger the waiting scope at its next sample.
pub const MC_OP_SCOPE_TRIGGER: u32 = 92;
/// Stop the scope.
pub const MC_OP_SCOPE_STOP: u32 = 93;
/// Layout 1.8: the card writes the settings it holds into a configuration block: args kind
/// (`ConfigKind`), index.
pub const MC_OP_READ_CONFIG: u32 = 96;
/// Layout 1.8: an axis's scale (counts per user unit), kept for hosts: args scale.
pub const MC_OP_SET_SCALE: u32 = 97;

/// Send one command of the card's register map as it is, for tools and tests that need what
/// the typed calls would refuse: `opcode` one of the `MC_OP_` values (their arguments and
/// flags are the register map's, `firmware-proto/include/mc_dpram.h` in the source), `axis`
/// the axis or group it names, `flags` its flags word, and `nargs` (0..14) arguments from
/// `args` (the rest 0; `args` may be NULL when `nargs` is 0). Blocks until the card answers:
/// `MC_OK` when it accepted the command (`value`, may be NULL, receives its ack's value), or
/// the `MC_ERR_` code of its refusal. The card checks it as any other command. It goes around
/// the library's bookkeeping: a motion started this way has no `mc_motion`, and
/// `MC_OP_HOST_DETACH` with this program's session (`mc_get_safety_status`) ends the session on
/// the card while the handle stays open; the card then halts what moves and refuses motion,
/// power, outputs and configuration (`MC_ERR_NO_SESSION`) until an `MC_OP_HOST_ATTACH` of a
/// session (which arms the watchdog at once). An `opcode` or `axis` above 65535, or more than
/// 14 arguments: `MC_ERR_OUT_OF_RANGE`, nothing sent.
#[no_mangle]
pub unsafe extern "C" fn mc_send_raw(
    card: registry::mc_card,
    opcode: u32,
    axis: u32,
    flags: u32,
    args: *const f64,
    nargs: usize,
    value: *mut f64,
) -> mc_result {
    guard(|| {
        let out = Out::optional(value);
        let max = motioncard_sdk::proto::raw::MC_CMD_ARGS as usize;
        let (Ok(op), Ok(target)) = (u16::try_from(opcode), u16::try_from(axis)) else {
            return Err(Failure::new(
                ErrorKind::OutOfRange.code(),
                format!("opcode {opcode} or axis {axis} does not fit a command (0..65535)"),
            ));
        };
        if nargs > max {
            return Err(Failure::new(
                ErrorKind::OutOfRange.code(),
                format!("{nargs} arguments: a command has at most {max}"),
            ));
        }
        // SAFETY: `args` holds `nargs` values by the caller's contract (nargs is bounded).
        let list = unsafe { crate::ffi::read_slice(args, nargs, "args") }?;
        let mut cmd = Command::new(Opcode::Nop, target).with_args(&list);
        cmd.opcode = op;
        cmd.flags = flags;
        let v = registry::get(card)?.card.execute_raw(cmd)?;
        if let Some(out) = out {
            // SAFETY: checked non-NULL; valid for writes by the caller's contract.
            unsafe { out.write(v) };
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use motioncard_sdk::proto::raw;

    /// Every opcode the card knows, each with the card's number.
    #[test]
    fn opcodes_are_the_cards() {
        let ours = [
            (MC_OP_NOP, raw::MC_OP_NOP),
            (MC_OP_POWER_ON, raw::MC_OP_POWER_ON),
            (MC_OP_POWER_OFF, raw::MC_OP_POWER_OFF),
            (MC_OP_MOVE_ABSOLUTE, raw::MC_OP_MOVE_ABSOLUTE),
            (MC_OP_MOVE_RELATIVE, raw::MC_OP_MOVE_RELATIVE),
            (MC_OP_HALT, raw::MC_OP_HALT),
            (MC_OP_STOP, raw::MC_OP_STOP),
            (MC_OP_STOP_RELEASE, raw::MC_OP_STOP_RELEASE),
            (MC_OP_RESET, raw::MC_OP_RESET),
            (MC_OP_APPLY_AXIS_CONFIG, raw::MC_OP_APPLY_AXIS_CONFIG),
            (MC_OP_APPLY_CARD_CONFIG, raw::MC_OP_APPLY_CARD_CONFIG),
            (MC_OP_MOVE_ADDITIVE, raw::MC_OP_MOVE_ADDITIVE),
            (MC_OP_MOVE_VELOCITY, raw::MC_OP_MOVE_VELOCITY),
            (MC_OP_JOG, raw::MC_OP_JOG),
            (MC_OP_SET_OVERRIDE, raw::MC_OP_SET_OVERRIDE),
            (MC_OP_GROUP_CONFIGURE, raw::MC_OP_GROUP_CONFIGURE),
            (MC_OP_APPLY_AXIS_FILTER, raw::MC_OP_APPLY_AXIS_FILTER),
            (MC_OP_GROUP_ENABLE, raw::MC_OP_GROUP_ENABLE),
            (MC_OP_GROUP_DISABLE, raw::MC_OP_GROUP_DISABLE),
            (MC_OP_GROUP_STOP, raw::MC_OP_GROUP_STOP),
            (MC_OP_GROUP_STOP_RELEASE, raw::MC_OP_GROUP_STOP_RELEASE),
            (MC_OP_GROUP_RESET, raw::MC_OP_GROUP_RESET),
            (MC_OP_GROUP_HALT, raw::MC_OP_GROUP_HALT),
            (MC_OP_GROUP_MOVE_LINEAR, raw::MC_OP_GROUP_MOVE_LINEAR),
            (MC_OP_GROUP_MOVE_CIRCULAR, raw::MC_OP_GROUP_MOVE_CIRCULAR),
            (MC_OP_GROUP_MOVE_PTP, raw::MC_OP_GROUP_MOVE_PTP),
            (MC_OP_GROUP_PTP_LIMITS, raw::MC_OP_GROUP_PTP_LIMITS),
            (MC_OP_GROUP_SET_OVERRIDE, raw::MC_OP_GROUP_SET_OVERRIDE),
            (MC_OP_NURBS_BEGIN, raw::MC_OP_NURBS_BEGIN),
            (MC_OP_NURBS_DATA, raw::MC_OP_NURBS_DATA),
            (MC_OP_NURBS_END, raw::MC_OP_NURBS_END),
            (MC_OP_APPLY_SAFETY_CONFIG, raw::MC_OP_APPLY_SAFETY_CONFIG),
            (MC_OP_APPLY_AXIS_SAFETY, raw::MC_OP_APPLY_AXIS_SAFETY),
            (MC_OP_ESTOP, raw::MC_OP_ESTOP),
            (MC_OP_SAFETY_RESET, raw::MC_OP_SAFETY_RESET),
            (MC_OP_HOST_ATTACH, raw::MC_OP_HOST_ATTACH),
            (MC_OP_HOST_DETACH, raw::MC_OP_HOST_DETACH),
            (MC_OP_APPLY_AXIS_HOMING, raw::MC_OP_APPLY_AXIS_HOMING),
            (MC_OP_HOME, raw::MC_OP_HOME),
            (MC_OP_SET_POSITION, raw::MC_OP_SET_POSITION),
            (MC_OP_PATH_LINE, raw::MC_OP_PATH_LINE),
            (MC_OP_PATH_ARC, raw::MC_OP_PATH_ARC),
            (MC_OP_PATH_DWELL, raw::MC_OP_PATH_DWELL),
            (MC_OP_PATH_OUTPUT, raw::MC_OP_PATH_OUTPUT),
            (MC_OP_APPLY_GROUP_PATH, raw::MC_OP_APPLY_GROUP_PATH),
            (MC_OP_SET_OUTPUTS, raw::MC_OP_SET_OUTPUTS),
            (MC_OP_PATH_NURBS, raw::MC_OP_PATH_NURBS),
            (MC_OP_APPLY_IO_CONFIG, raw::MC_OP_APPLY_IO_CONFIG),
            (MC_OP_COMPARE_ARM, raw::MC_OP_COMPARE_ARM),
            (MC_OP_COMPARE_TABLE, raw::MC_OP_COMPARE_TABLE),
            (MC_OP_COMPARE_DISARM, raw::MC_OP_COMPARE_DISARM),
            (MC_OP_PROBE_ARM, raw::MC_OP_PROBE_ARM),
            (MC_OP_PROBE_ABORT, raw::MC_OP_PROBE_ABORT),
            (MC_OP_GEAR_IN, raw::MC_OP_GEAR_IN),
            (MC_OP_GEAR_IN_POS, raw::MC_OP_GEAR_IN_POS),
            (MC_OP_GEAR_OUT, raw::MC_OP_GEAR_OUT),
            (MC_OP_PVT_BEGIN, raw::MC_OP_PVT_BEGIN),
            (MC_OP_PVT_POINTS, raw::MC_OP_PVT_POINTS),
            (MC_OP_PVT_START, raw::MC_OP_PVT_START),
            (MC_OP_CAM_TABLE, raw::MC_OP_CAM_TABLE),
            (MC_OP_CAM_DATA, raw::MC_OP_CAM_DATA),
            (MC_OP_CAM_IN, raw::MC_OP_CAM_IN),
            (MC_OP_CAM_OUT, raw::MC_OP_CAM_OUT),
            (MC_OP_SCOPE_CONFIGURE, raw::MC_OP_SCOPE_CONFIGURE),
            (MC_OP_SCOPE_ARM, raw::MC_OP_SCOPE_ARM),
            (MC_OP_SCOPE_TRIGGER, raw::MC_OP_SCOPE_TRIGGER),
            (MC_OP_SCOPE_STOP, raw::MC_OP_SCOPE_STOP),
            (MC_OP_READ_CONFIG, raw::MC_OP_READ_CONFIG),
            (MC_OP_SET_SCALE, raw::MC_OP_SET_SCALE),
        ];
        for (c, r) in ours {
            assert_eq!(c, r);
        }
        assert_eq!(ours.len(), Opcode::ALL.len());
        for op in Opcode::ALL {
            assert!(ours.iter().any(|(c, _)| *c == *op as u32), "{op:?}");
        }
    }
}

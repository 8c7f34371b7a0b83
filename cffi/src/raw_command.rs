//! Raw commands: [`mc_send_raw`], for tools and tests that need what the typed calls would
//! refuse. The register map's opcodes (`MC_OP_`), one for each opcode the card knows, are in
//! [`crate::codes`], generated from `mc_dpram.h`.

use crate::ffi::Out;
use crate::registry;
use crate::result::{guard, mc_result, Failure};
use motioncard_sdk::proto::{Command, Opcode};
use motioncard_sdk::ErrorKind;

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

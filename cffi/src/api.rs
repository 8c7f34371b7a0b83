//! The exported functions. Each one is a thin skin over the SDK: check the pointers, look the
//! handle up, call the SDK, write the outputs, all inside `guard` (the panic boundary).

use crate::ffi::{read_in, Out, StrBuf};
use crate::registry::{self, lock, mc_card, mc_event_callback, Callback, Entry};
use crate::result::{
    describe_ptr, guard, guard_quiet, last_error, mc_result, Failure, MC_ERR_BAD_HANDLE,
};
use crate::types::{
    mc_axis_settings, mc_card_info, mc_event, mc_motion, mc_move_limits, mc_sim_options, mc_status,
};
use motioncard_sdk::ErrorKind;
use motioncard_sdk::{AxisSettings, Card, Error, MoveLimits, EVENT_QUEUE_CAP};
#[cfg(feature = "emulator")]
use motioncard_sdk::{Clock, EmuOptions, SimOptions};
use std::ffi::{c_char, c_int, c_void};
use std::os::fd::AsRawFd;
use std::sync::Arc;
use std::time::Duration;

pub(crate) fn ms(timeout_ms: u32) -> Duration {
    Duration::from_millis(u64::from(timeout_ms))
}

/// The card and one of its axes.
pub(crate) fn axis_of(
    card: mc_card,
    axis: u32,
) -> Result<(Arc<Entry>, motioncard_sdk::Axis), Failure> {
    let e = registry::get(card)?;
    let a = e.card.axis(axis as usize)?;
    Ok((e, a))
}

/// A library built without the emulated card (cargo feature `emulator`) has the `mc_sim_`
/// calls, and they say so.
#[cfg(not(feature = "emulator"))]
pub(crate) fn no_emulator() -> Failure {
    Error::Unsupported("this library was built without the emulated card".into()).into()
}

/// The stepping control of a stepped sim card.
#[cfg(feature = "emulator")]
pub(crate) fn sim_of(card: mc_card) -> Result<motioncard_sdk::Sim, Failure> {
    registry::get(card)?.sim.clone().ok_or_else(|| {
        Error::Unsupported(
            "the card is not a stepped sim (open it with mc_open_sim_stepped)".into(),
        )
        .into()
    })
}

// ---------------------------------------------------------------------------------------------
// Results, errors, versions
// ---------------------------------------------------------------------------------------------

/// A static description of a result code ("unknown result code" for a value that is not one).
/// Never NULL; the string lives as long as the program. Never blocks, never fails.
#[no_mangle]
pub extern "C" fn mc_result_str(code: mc_result) -> *const c_char {
    describe_ptr(code)
}

/// The detailed message of the last failed `mc_` call on the calling thread ("" when none
/// failed). Successful calls leave it as it was. Copies the message and a NUL into `buf` and
/// the size it takes (including the NUL) into `*needed`. When `len` is too small, writes only
/// `*needed` and returns `MC_ERR_BUFFER_TOO_SMALL`; `buf` may be NULL when `len` is 0 (to ask
/// for the size). This call's own failures do not replace the message.
#[no_mangle]
pub unsafe extern "C" fn mc_last_error_message(
    buf: *mut c_char,
    len: usize,
    needed: *mut usize,
) -> mc_result {
    guard_quiet(|| {
        let out = StrBuf::new(buf, len, needed)?;
        // SAFETY: the caller gives `len` writable bytes at `buf` and a writable `*needed`.
        unsafe { out.fill(&last_error()) }
    })
}

/// The library's version, `major << 16 | minor << 8 | patch` (as `mc_card_info.firmware_version`).
#[no_mangle]
pub unsafe extern "C" fn mc_version(version: *mut u32) -> mc_result {
    guard(|| {
        let out = Out::new(version, "version")?;
        let part = |s: &str| s.parse::<u32>().unwrap_or(0);
        let v = part(env!("CARGO_PKG_VERSION_MAJOR")) << 16
            | part(env!("CARGO_PKG_VERSION_MINOR")) << 8
            | part(env!("CARGO_PKG_VERSION_PATCH"));
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(v) };
        Ok(())
    })
}

/// The library's version as a string ("0.1.0"), with the buffer rules of
/// `mc_last_error_message`.
#[no_mangle]
pub unsafe extern "C" fn mc_version_string(
    buf: *mut c_char,
    len: usize,
    needed: *mut usize,
) -> mc_result {
    guard(|| {
        let out = StrBuf::new(buf, len, needed)?;
        // SAFETY: the caller gives `len` writable bytes at `buf` and a writable `*needed`.
        unsafe { out.fill(env!("CARGO_PKG_VERSION")) }
    })
}

/// Test builds only (feature `test-panic`: not in the header, never in an installed library):
/// the calling thread's next `mc_` call panics inside the library, which must turn it into
/// `MC_ERR_PANIC` with the panic's message. Declare it yourself:
/// `mc_result mc__test_panic_next_call(void);`.
#[cfg(feature = "test-panic")]
#[no_mangle]
pub extern "C" fn mc__test_panic_next_call() -> mc_result {
    crate::result::panic_next_call();
    crate::result::MC_OK
}

// ---------------------------------------------------------------------------------------------
// Cards
// ---------------------------------------------------------------------------------------------

fn register(card: Card, out: Out<mc_card>) -> Result<(), Failure> {
    let h = registry::insert(Entry::new(card))?;
    // SAFETY: checked non-NULL by the caller of `register`; valid by the function's contract.
    unsafe { out.write(h) };
    Ok(())
}

/// Open a card by URI: `sim` (an emulated card in this process, real-time clock), `emu:NAME`
/// (a `card-emu` process), `uio:/dev/uioN` or `pci:DDDD:BB:DD.F` (hardware). Writes its handle
/// to `*card`. Blocks until the card has answered (at most about a second).
#[no_mangle]
pub unsafe extern "C" fn mc_open(uri: *const c_char, card: *mut mc_card) -> mc_result {
    guard(|| {
        let out = Out::new(card, "card")?;
        // SAFETY: the caller gives a NUL-terminated string that outlives this call.
        let uri = unsafe { crate::ffi::uri(uri, "uri") }?;
        register(Card::open(uri)?, out)
    })
}

/// Open an emulated card in this process whose time advances only in `mc_sim_step` and in
/// waits (a wait's timeout is then in emulated time): deterministic, for tests. `axes` is
/// 1..8 and `servo_rate_hz` 1000..20000; anything outside is `MC_ERR_BAD_CONFIG` (as
/// `mc_open_sim`, of which this is the stepped, default-plant case).
#[no_mangle]
pub unsafe extern "C" fn mc_open_sim_stepped(
    axes: c_int,
    servo_rate_hz: u32,
    card: *mut mc_card,
) -> mc_result {
    guard(|| {
        let out = Out::new(card, "card")?;
        let axes = usize::try_from(axes)
            .map_err(|_| Failure::new(ErrorKind::BadConfig.code(), format!("axes = {axes}")))?;
        #[cfg(feature = "emulator")]
        return register(
            Card::open_sim(SimOptions {
                clock: Clock::Stepped,
                emu: EmuOptions::new(axes, servo_rate_hz),
            })?,
            out,
        );
        #[cfg(not(feature = "emulator"))]
        {
            let _ = (out, axes, servo_rate_hz);
            Err(no_emulator())
        }
    })
}

/// The options of `mc_open("sim")`: real-time clock, 8 axes, 10 kHz, the default plant.
/// Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_sim_options_default(options: *mut mc_sim_options) -> mc_result {
    guard(|| {
        let out = Out::new(options, "options")?;
        #[cfg(feature = "emulator")]
        {
            // SAFETY: checked non-NULL; valid for writes by the caller's contract.
            unsafe { out.write(SimOptions::default().into()) };
            Ok(())
        }
        #[cfg(not(feature = "emulator"))]
        {
            let _ = out;
            Err(no_emulator())
        }
    })
}

/// Open an emulated card in this process with explicit options: its clock
/// (`MC_SIM_CLOCK_REAL_TIME`, `_FREE_RUNNING`, or `_STEPPED` for a card whose time advances only
/// in `mc_sim_step` and waits), axes (1..8), servo rate (1000..20000 Hz) and plant
/// (`MC_SIM_PLANT_`). Values out of range, or unknown clocks and plants, are
/// `MC_ERR_BAD_CONFIG`. Blocks until the card has booted.
#[no_mangle]
pub unsafe extern "C" fn mc_open_sim(
    options: *const mc_sim_options,
    card: *mut mc_card,
) -> mc_result {
    guard(|| {
        let out = Out::new(card, "card")?;
        // SAFETY: the caller gives NULL or a readable mc_sim_options.
        let opts = unsafe { read_in(options, "options") }?;
        #[cfg(feature = "emulator")]
        return register(Card::open_sim(opts.to_sdk()?)?, out);
        #[cfg(not(feature = "emulator"))]
        {
            let _ = (out, opts);
            Err(no_emulator())
        }
    })
}

/// Close a card: the clean end of this program's session. Moving axes and groups halt along
/// their stop ramps (stop reason `MC_STOP_REASON_HOST_DETACH`), the card's watchdog is
/// disarmed without latching a fault (the next program opens a card that is ready to move),
/// and the heartbeat stops. Every call blocked on this card in another thread
/// (`mc_motion_wait`, `mc_wait_done`, `mc_wait_event`, `mc_group_wait_done`,
/// `mc_dispatch_events`...) returns `MC_ERR_CLOSED` at once. The handle is invalid afterwards:
/// closing it again, or any other call with it, returns `MC_ERR_BAD_HANDLE` and does nothing
/// else (double close is harmless). The handle is closed even when the card could not be told
/// (a card that does not answer: the code says why, and its watchdog then stops it). Blocks
/// until the card has answered the close.
#[no_mangle]
pub extern "C" fn mc_close(card: mc_card) -> mc_result {
    guard(|| {
        let entry = registry::remove(card)?;
        let closed = entry.card.close();
        drop(entry); // outside the registry's lock
        Ok(closed?)
    })
}

/// End every wait in progress on this card in other threads (`mc_motion_wait`, `mc_wait_done`,
/// `mc_wait_event`, `mc_group_wait_done`, `mc_group_motion_wait`, `mc_dispatch_events`): each
/// returns `MC_ERR_CANCELLED`. Waits that begin afterwards are not affected; a call waiting for
/// the card's answer to its own command is not cancelled (the command may still run). Never
/// blocks.
#[no_mangle]
pub extern "C" fn mc_cancel_waits(card: mc_card) -> mc_result {
    guard(|| {
        registry::get(card)?.card.cancel_waits();
        Ok(())
    })
}

/// How many axes this program's `mc_open` stopped because the program before it left the card
/// without closing it (it crashed or was killed): those axes are in ErrorStop with stop reason
/// `MC_STOP_REASON_HOST_CHANGED` until `mc_reset_faults`. 0 when the previous program closed
/// the card or left nothing enabled. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_inherited_stops(card: mc_card, axes: *mut u32) -> mc_result {
    guard(|| {
        let out = Out::new(axes, "axes")?;
        let n = registry::get(card)?.card.inherited_stops();
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(n) };
        Ok(())
    })
}

/// What the card says about itself: firmware and layout versions, axes, servo rate.
#[no_mangle]
pub unsafe extern "C" fn mc_get_info(card: mc_card, info: *mut mc_card_info) -> mc_result {
    guard(|| {
        let out = Out::new(info, "info")?;
        let i = registry::get(card)?.card.info();
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(i.into()) };
        Ok(())
    })
}

/// The card's servo tick counter.
#[no_mangle]
pub unsafe extern "C" fn mc_get_tick(card: mc_card, tick: *mut u64) -> mc_result {
    guard(|| {
        let out = Out::new(tick, "tick")?;
        let t = registry::get(card)?.card.tick()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(t) };
        Ok(())
    })
}

/// A command that does nothing but come back: one round trip through the card. Blocks until
/// the card answers.
#[no_mangle]
pub extern "C" fn mc_ping(card: mc_card) -> mc_result {
    guard(|| Ok(registry::get(card)?.card.ping()?))
}

/// Change the servo rate (1000..20000 Hz; every axis must be disabled). Blocks until the card
/// answers.
#[no_mangle]
pub extern "C" fn mc_set_servo_rate(card: mc_card, servo_rate_hz: u32) -> mc_result {
    guard(|| Ok(registry::get(card)?.card.set_servo_rate(servo_rate_hz)?))
}

/// Events lost: `*dropped` were dropped from the library's queue because nobody took them
/// (beyond 4096 waiting), `*card_lost` could not be posted by the card (its ring was full).
#[no_mangle]
pub unsafe extern "C" fn mc_events_lost(
    card: mc_card,
    dropped: *mut u64,
    card_lost: *mut u32,
) -> mc_result {
    guard(|| {
        let dropped = Out::new(dropped, "dropped")?;
        let card_lost = Out::new(card_lost, "card_lost")?;
        let (d, c) = registry::get(card)?.card.events_lost();
        // SAFETY: both checked non-NULL; valid for writes by the caller's contract.
        unsafe {
            dropped.write(d);
            card_lost.write(c);
        }
        Ok(())
    })
}

// ---------------------------------------------------------------------------------------------
// Axes
// ---------------------------------------------------------------------------------------------

/// The default servo gains and in-position windows.
#[no_mangle]
pub unsafe extern "C" fn mc_axis_settings_default(settings: *mut mc_axis_settings) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(AxisSettings::default()) };
        Ok(())
    })
}

/// Write an axis's servo and in-position configuration and have the card apply it (the card
/// checks every value: `MC_ERR_BAD_CONFIG`). Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_configure(
    card: mc_card,
    axis: u32,
    settings: *const mc_axis_settings,
) -> mc_result {
    guard(|| {
        // SAFETY: the caller gives NULL or a readable mc_axis_settings.
        let s = unsafe { read_in(settings, "settings") }?;
        let (_, a) = axis_of(card, axis)?;
        Ok(a.configure(&s)?)
    })
}

/// Counts per user unit for this axis (default 1: positions in counts). Positions, velocities,
/// limits and status fields other than `raw` are then in user units. A negative scale reverses
/// the axis; zero, and |scale| outside 1e-9..1e12, is `MC_ERR_BAD_CONFIG`. Layout 1.8: the card
/// keeps the scale for hosts (`mc_axis_settings.scale`, read back with `mc_axis_get_settings`),
/// and a process that opens the card later adopts it. Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_set_scale(card: mc_card, axis: u32, counts_per_unit: f64) -> mc_result {
    guard(|| Ok(axis_of(card, axis)?.1.set_scale(counts_per_unit)?))
}

/// MC_Power on. Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_enable(card: mc_card, axis: u32) -> mc_result {
    guard(|| Ok(axis_of(card, axis)?.1.enable()?))
}

/// MC_Power off (a moving axis loses power at once; its motion is aborted). Blocks until the
/// card answers.
#[no_mangle]
pub extern "C" fn mc_disable(card: mc_card, axis: u32) -> mc_result {
    guard(|| Ok(axis_of(card, axis)?.1.disable()?))
}

/// Symmetric move limits: deceleration = acceleration, one jerk for all four phases. Fills
/// `*limits`; nothing is checked until a move uses them.
#[no_mangle]
pub unsafe extern "C" fn mc_move_limits_symmetric(
    velocity: f64,
    acceleration: f64,
    jerk: f64,
    limits: *mut mc_move_limits,
) -> mc_result {
    guard(|| {
        let out = Out::new(limits, "limits")?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(MoveLimits::new(velocity, acceleration, jerk).into()) };
        Ok(())
    })
}

/// Write a started motion to `*motion` (when given) and keep it for `mc_motion_wait`.
pub(crate) fn started(
    e: &Entry,
    m: motioncard_sdk::Motion,
    axis: u32,
    motion: *mut mc_motion,
) -> Result<(), Failure> {
    let seq = m.seq();
    e.remember(axis, m);
    if let Some(out) = Out::optional(motion) {
        // SAFETY: non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(mc_motion { axis, seq }) };
    }
    Ok(())
}

unsafe fn start_move(
    card: mc_card,
    axis: u32,
    value: f64,
    limits: *const mc_move_limits,
    motion: *mut mc_motion,
    relative: bool,
) -> Result<(), Failure> {
    // SAFETY: the caller gives NULL or a readable mc_move_limits.
    let l: MoveLimits = unsafe { read_in(limits, "limits") }?.into();
    let (e, a) = axis_of(card, axis)?;
    let m = if relative {
        a.move_relative(value, &l)?
    } else {
        a.move_absolute(value, &l)?
    };
    started(&e, m, axis, motion)
}

/// MC_MoveAbsolute (PLCopen Aborting): a time-optimal S-curve to `target` within `*limits`,
/// from Standstill or from whatever the axis is doing (it takes over in the tick the card
/// serves it; the motion it replaces is aborted). `MC_ERR_AXIS_DISABLED` when disabled,
/// `MC_ERR_INVALID_STATE` while stopping or in ErrorStop. Buffered moves: `mc_move`. `motion`
/// may be NULL; otherwise it receives the motion to wait for. Blocks until the card has
/// accepted or refused the move, not until it is done.
#[no_mangle]
pub unsafe extern "C" fn mc_move_absolute(
    card: mc_card,
    axis: u32,
    target: f64,
    limits: *const mc_move_limits,
    motion: *mut mc_motion,
) -> mc_result {
    // SAFETY: forwarded from this function's contract.
    guard(|| unsafe { start_move(card, axis, target, limits, motion, false) })
}

/// MC_MoveRelative: a time-optimal S-curve by `distance`; otherwise as `mc_move_absolute`.
#[no_mangle]
pub unsafe extern "C" fn mc_move_relative(
    card: mc_card,
    axis: u32,
    distance: f64,
    limits: *const mc_move_limits,
    motion: *mut mc_motion,
) -> mc_result {
    // SAFETY: forwarded from this function's contract.
    guard(|| unsafe { start_move(card, axis, distance, limits, motion, true) })
}

/// MC_Halt: decelerate (at most `deceleration`, with `jerk`), then Standstill. The
/// interrupted move is aborted. `motion` (may be NULL) receives the halt, which is done when
/// the axis is at rest in position. Blocks until the card answers.
#[no_mangle]
pub unsafe extern "C" fn mc_halt(
    card: mc_card,
    axis: u32,
    deceleration: f64,
    jerk: f64,
    motion: *mut mc_motion,
) -> mc_result {
    guard(|| {
        let (e, a) = axis_of(card, axis)?;
        started(&e, a.halt(deceleration, jerk)?, axis, motion)
    })
}

/// MC_Stop: decelerate and stay in Stopping (moves refused) until `mc_release_stop`.
/// Otherwise as `mc_halt`.
#[no_mangle]
pub unsafe extern "C" fn mc_stop(
    card: mc_card,
    axis: u32,
    deceleration: f64,
    jerk: f64,
    motion: *mut mc_motion,
) -> mc_result {
    guard(|| {
        let (e, a) = axis_of(card, axis)?;
        started(&e, a.stop(deceleration, jerk)?, axis, motion)
    })
}

/// Leave Stopping (once at rest the axis goes to Standstill). Blocks until the card answers.
#[no_mangle]
pub extern "C" fn mc_release_stop(card: mc_card, axis: u32) -> mc_result {
    guard(|| Ok(axis_of(card, axis)?.1.release_stop()?))
}

/// MC_Reset: ErrorStop → Standstill (`MC_ERR_INVALID_STATE` in any other state). Blocks until
/// the card answers.
#[no_mangle]
pub extern "C" fn mc_reset(card: mc_card, axis: u32) -> mc_result {
    guard(|| Ok(axis_of(card, axis)?.1.reset()?))
}

/// A consistent snapshot of an axis's status, read from the block the card publishes every
/// servo tick (and before each event it posts). Does not wait for the card; see the header's
/// notes on blocking.
#[no_mangle]
pub unsafe extern "C" fn mc_get_status(
    card: mc_card,
    axis: u32,
    status: *mut mc_status,
) -> mc_result {
    guard(|| {
        let out = Out::new(status, "status")?;
        let s = axis_of(card, axis)?.1.status()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write((&s).into()) };
        Ok(())
    })
}

/// The status of several axes in one call: `statuses[i]` is the status of axis `axes[i]`, for
/// `n` axes (1..=8; each a valid axis, repeats allowed), all of the same servo tick (equal
/// `raw.tick`: a read that straddles two ticks is read again), each a consistent snapshot,
/// and one check that the card is alive. Like
/// `mc_get_status`, never stale: `MC_ERR_NOT_RESPONDING` when the card's tick has stood still
/// too long. Does not wait for the card.
#[no_mangle]
pub unsafe extern "C" fn mc_get_statuses(
    card: mc_card,
    axes: *const u32,
    n: usize,
    statuses: *mut mc_status,
) -> mc_result {
    guard(|| {
        if n == 0 || n > motioncard_sdk::proto::raw::MC_MAX_AXES as usize {
            return Err(Failure::new(
                ErrorKind::BadAxis.code(),
                format!("{n} axes: ask for 1 to 8"),
            ));
        }
        if statuses.is_null() {
            return Err(Failure::null("statuses"));
        }
        // SAFETY: `axes` holds `n` values by the caller's contract (n is bounded above).
        let list = unsafe { crate::ffi::read_slice(axes, n, "axes") }?;
        let list: Vec<usize> = list.into_iter().map(|a| a as usize).collect();
        let all = registry::get(card)?.card.statuses(&list)?;
        for (i, st) in all.iter().enumerate() {
            // SAFETY: `statuses` is non-NULL and valid for writes of `n` elements by the
            // caller's contract; i < n.
            unsafe { statuses.add(i).write_unaligned(st.into()) };
        }
        Ok(())
    })
}

/// Wait until a motion is done (in position). `position` may be NULL; otherwise it receives
/// the actual position when the motion was done. `MC_ERR_ABORTED` when another command or a
/// fault ended it, `MC_ERR_TIMEOUT` after `timeout_ms` (0: only look). A motion can be waited
/// for more than once. `MC_ERR_BAD_HANDLE` for a motion that was not started on this card (the
/// last 1024 motions are kept). Blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_motion_wait(
    card: mc_card,
    motion: mc_motion,
    timeout_ms: u32,
    position: *mut f64,
) -> mc_result {
    guard(|| {
        let out = Out::optional(position);
        let p = motion_of(card, motion)?.wait(ms(timeout_ms))?;
        if let Some(out) = out {
            // SAFETY: non-NULL; valid for writes by the caller's contract.
            unsafe { out.write(p) };
        }
        Ok(())
    })
}

/// A motion started on this card (the last [`registry::MOTIONS_KEPT`] are kept).
pub(crate) fn motion_of(
    card: mc_card,
    motion: mc_motion,
) -> Result<motioncard_sdk::Motion, Failure> {
    let e = registry::get(card)?;
    e.motion(motion.axis, motion.seq).ok_or_else(|| {
        Failure::new(
            MC_ERR_BAD_HANDLE,
            format!(
                "no motion with seq {} on axis {} was started on card {card} (or it is older than the last {})",
                motion.seq,
                motion.axis,
                registry::MOTIONS_KEPT
            ),
        )
    })
}

/// Wait for the last motion started on this axis by this process, as `mc_motion_wait`
/// (`position` may be NULL). `MC_ERR_NO_MOTION` when none was started since the card was opened
/// (nothing to wait for). Blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_wait_done(
    card: mc_card,
    axis: u32,
    timeout_ms: u32,
    position: *mut f64,
) -> mc_result {
    guard(|| {
        let out = Out::optional(position);
        let p = axis_of(card, axis)?.1.wait_done(ms(timeout_ms))?;
        if let Some(out) = out {
            // SAFETY: non-NULL; valid for writes by the caller's contract.
            unsafe { out.write(p) };
        }
        Ok(())
    })
}

// ---------------------------------------------------------------------------------------------
// Events
// ---------------------------------------------------------------------------------------------

/// Take the next event from the card, waiting up to `timeout_ms` (0: don't wait);
/// `MC_ERR_TIMEOUT` when none came. Each event is delivered once, to whichever of
/// `mc_wait_event` and `mc_dispatch_events` takes it first. Blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_wait_event(
    card: mc_card,
    timeout_ms: u32,
    event: *mut mc_event,
) -> mc_result {
    guard(|| {
        let out = Out::new(event, "event")?;
        let e = registry::get(card)?;
        match e.card.next_event(ms(timeout_ms))? {
            Some(ev) => {
                // SAFETY: checked non-NULL; valid for writes by the caller's contract.
                unsafe { out.write((&ev).into()) };
                Ok(())
            }
            None => Err(Failure::new(
                ErrorKind::Timeout.code(),
                format!("no event from card {card} within {timeout_ms} ms"),
            )),
        }
    })
}

/// The card's interrupt file descriptor, for the application's own poll/epoll loop: it becomes
/// readable when the card raises an interrupt; then call `mc_dispatch_events` (or
/// `mc_poll_events`). The descriptor belongs to the library: do not read, write or close it;
/// it stays valid until `mc_close`. `MC_ERR_UNSUPPORTED` for `pci:` cards (no interrupt line).
#[no_mangle]
pub unsafe extern "C" fn mc_irq_fd(card: mc_card, fd: *mut c_int) -> mc_result {
    guard(|| {
        let out = Out::new(fd, "fd")?;
        let e = registry::get(card)?;
        let raw = e
            .card
            .irq_fd()
            .map(|f| f.as_raw_fd())
            .ok_or_else(|| Error::Unsupported("this card has no interrupt line".into()))?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(raw) };
        Ok(())
    })
}

/// Take what the card posted into the library's event queue without waiting (clears the
/// interrupt descriptor's readiness); `*queued` is how many events were added. Never blocks.
#[no_mangle]
pub unsafe extern "C" fn mc_poll_events(card: mc_card, queued: *mut usize) -> mc_result {
    guard(|| {
        let out = Out::new(queued, "queued")?;
        let n = registry::get(card)?.card.poll_events()?;
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(n) };
        Ok(())
    })
}

/// Set the card's event callback (NULL: none). `user` is handed back to it untouched. The
/// callback is called only from `mc_dispatch_events`, on the thread that calls it: the library
/// starts no thread that calls into the application. It may call any `mc_` function, including
/// `mc_close` on this card.
#[no_mangle]
pub unsafe extern "C" fn mc_set_event_callback(
    card: mc_card,
    callback: mc_event_callback,
    user: *mut c_void,
) -> mc_result {
    guard(|| {
        let e = registry::get(card)?;
        *lock(&e.callback) = callback.map(|f| Callback {
            f,
            user: user as usize,
        });
        Ok(())
    })
}

/// Take the card's events and call the callback once for each, in order, on this thread.
/// Waits up to `timeout_ms` for the first one (0: don't wait; call it when the descriptor of
/// `mc_irq_fd` is readable), then takes the rest without waiting (at most 4096 per call); the
/// callback then gets every event taken, even if it closes the card. A close from another
/// thread ends the wait: `MC_ERR_CLOSED`.
/// Without a callback the events are taken and dropped. `*dispatched` is how many were taken;
/// 0 with `MC_OK` when none came. Blocks up to `timeout_ms`.
#[no_mangle]
pub unsafe extern "C" fn mc_dispatch_events(
    card: mc_card,
    timeout_ms: u32,
    dispatched: *mut usize,
) -> mc_result {
    guard(|| {
        let out = Out::new(dispatched, "dispatched")?;
        let e = registry::get(card)?;
        e.card.poll_events()?;
        // Take this call's events first: a callback that closes the card still gets them all.
        let mut taken = Vec::new();
        let mut next = e.card.next_event(ms(timeout_ms))?;
        while let Some(ev) = next {
            taken.push(mc_event::from(&ev));
            if taken.len() >= EVENT_QUEUE_CAP {
                break;
            }
            next = e.card.next_event(Duration::ZERO)?;
        }
        for c in &taken {
            // Copied out: no lock is held while the application runs.
            let cb = *lock(&e.callback);
            if let Some(cb) = cb {
                // SAFETY: the application registered `f` for this card with `user`; `c` lives
                // for the whole call.
                unsafe { (cb.f)(card, c, cb.user as *mut c_void) };
            }
        }
        // SAFETY: checked non-NULL; valid for writes by the caller's contract.
        unsafe { out.write(taken.len()) };
        Ok(())
    })
}

// ---------------------------------------------------------------------------------------------
// Stepped sim
// ---------------------------------------------------------------------------------------------

/// Advance a stepped sim card (`mc_open_sim_stepped`) by `ticks` servo periods.
/// `MC_ERR_UNSUPPORTED` on any other card. Blocks for the computation.
#[no_mangle]
pub extern "C" fn mc_sim_step(card: mc_card, ticks: u64) -> mc_result {
    guard(|| {
        #[cfg(feature = "emulator")]
        {
            sim_of(card)?.step(ticks);
            Ok(())
        }
        #[cfg(not(feature = "emulator"))]
        {
            let _ = (card, ticks);
            Err(no_emulator())
        }
    })
}

/// Emulated time of a stepped sim card since boot, in seconds.
#[no_mangle]
pub unsafe extern "C" fn mc_sim_time(card: mc_card, seconds: *mut f64) -> mc_result {
    guard(|| {
        let out = Out::new(seconds, "seconds")?;
        #[cfg(feature = "emulator")]
        {
            let t = sim_of(card)?.time();
            // SAFETY: checked non-NULL; valid for writes by the caller's contract.
            unsafe { out.write(t) };
            Ok(())
        }
        #[cfg(not(feature = "emulator"))]
        {
            let _ = (out, card);
            Err(no_emulator())
        }
    })
}

#[cfg(all(test, feature = "emulator"))]
mod tests {
    use super::*;
    use crate::result::MC_OK;
    use firmware_proto::{layout, Mem};
    use motioncard_sdk::ErrorKind;

    fn stepped() -> mc_card {
        let mut h = 0;
        // SAFETY: a valid out pointer.
        assert_eq!(unsafe { mc_open_sim_stepped(2, 10_000, &mut h) }, MC_OK);
        h
    }

    fn status(h: mc_card) -> (mc_result, mc_status) {
        let mut s = mc_status::default();
        // SAFETY: a valid out pointer.
        let r = unsafe { mc_get_status(h, 0, &mut s) };
        (r, s)
    }

    /// Write into the card's DPRAM behind the library's back.
    fn scribble(h: mc_card, f: impl FnOnce(&dyn Mem)) {
        let sim = registry::get(h).unwrap().sim.clone().unwrap();
        sim.with_emulator(|e| f(&**e.window()));
    }

    #[test]
    fn a_stalled_or_corrupt_status_block_gives_its_code() {
        let h = stepped();
        assert_eq!(status(h).0, MC_OK);
        let seq = layout::axis_status(0);
        // The writer died mid-write: seq stays odd.
        scribble(h, |w| w.write32(seq, w.read32(seq) | 1));
        let (r, s) = status(h);
        assert_eq!(
            (r, s),
            (ErrorKind::NotResponding.code(), mc_status::default())
        );
        assert!(last_error().contains("stayed busy"), "{}", last_error());
        // A consistent copy that fails its checksum.
        scribble(h, |w| {
            w.write32(seq, (w.read32(seq) & !1) + 2);
            w.write64(seq + layout::STATUS_PAYLOAD + 16, 0x1234);
        });
        assert_eq!(status(h).0, ErrorKind::Protocol.code());
        assert!(last_error().contains("checksum"), "{}", last_error());
        // The next tick rewrites the block.
        assert_eq!(mc_sim_step(h, 1), MC_OK);
        assert_eq!(status(h).0, MC_OK);
        assert_eq!(mc_close(h), MC_OK);
    }

    unsafe extern "C" fn close_own_card(card: mc_card, event: *const mc_event, user: *mut c_void) {
        // SAFETY: `user` is the counter the test registered; `event` is valid during the call.
        let (n, e) = unsafe { (&mut *user.cast::<u32>(), *event) };
        *n += 1;
        assert_eq!(e.kind, crate::codes::MC_EVENT_STATE_CHANGED);
        assert_eq!(
            mc_close(card),
            if *n == 1 { MC_OK } else { MC_ERR_BAD_HANDLE }
        );
    }

    #[test]
    fn a_callback_may_close_its_own_card() {
        let h = stepped();
        assert_eq!(mc_enable(h, 0), MC_OK);
        assert_eq!(mc_enable(h, 1), MC_OK); // two state-change events queued
        let mut calls = 0u32;
        let user = (&mut calls as *mut u32).cast::<c_void>();
        // SAFETY: the callback matches the contract; `calls` outlives the dispatch below.
        assert_eq!(
            unsafe { mc_set_event_callback(h, Some(close_own_card), user) },
            MC_OK
        );
        let mut n = 0;
        // SAFETY: a valid out pointer.
        assert_eq!(unsafe { mc_dispatch_events(h, 0, &mut n) }, MC_OK);
        assert_eq!((n, calls), (2, 2), "every queued event is still delivered");
        assert_eq!(mc_close(h), MC_ERR_BAD_HANDLE);
    }
}

//! Result codes, the per-thread message of the last failure, and the panic boundary.

use motioncard_sdk::{Error, ErrorKind};
use std::cell::RefCell;
use std::ffi::{c_char, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// What every `mc_` function returns: `MC_OK` (0) on success, a negative `MC_ERR_` code on
/// failure. The codes are stable: a code keeps its number in every later version.
#[allow(non_camel_case_types)]
pub type mc_result = i32;

/// Success.
pub const MC_OK: mc_result = 0;
/// The URI is not one of `sim`, `emu:NAME`, `uio:/dev/uioN`, `pci:DDDD:BB:DD.F` (or not UTF-8).
pub const MC_ERR_BAD_URI: mc_result = -1;
/// No card at that URI.
pub const MC_ERR_NOT_FOUND: mc_result = -2;
/// Another process has the card open.
pub const MC_ERR_BUSY: mc_result = -3;
/// The card's DPRAM layout major version differs from this library's.
pub const MC_ERR_VERSION_MISMATCH: mc_result = -4;
/// The card does not answer.
pub const MC_ERR_NOT_RESPONDING: mc_result = -5;
/// The card broke the protocol (corrupt ring indices, bad signature, torn status).
pub const MC_ERR_PROTOCOL: mc_result = -6;
/// The command ring is full: nothing was queued.
pub const MC_ERR_RING_FULL: mc_result = -7;
/// A wait ran out of time.
pub const MC_ERR_TIMEOUT: mc_result = -8;
/// The motion waited for was aborted by another command or a fault.
pub const MC_ERR_ABORTED: mc_result = -9;
/// The card has no such axis.
pub const MC_ERR_BAD_AXIS: mc_result = -10;
/// An argument is NaN or infinite.
pub const MC_ERR_NOT_FINITE: mc_result = -11;
/// A limit (or the scale) is zero or negative.
pub const MC_ERR_NON_POSITIVE_LIMIT: mc_result = -12;
/// The axis is disabled.
pub const MC_ERR_AXIS_DISABLED: mc_result = -13;
/// The command is not allowed in the axis's current state.
pub const MC_ERR_INVALID_STATE: mc_result = -14;
/// A configuration value is out of range.
pub const MC_ERR_BAD_CONFIG: mc_result = -15;
/// No motion profile satisfies the request.
pub const MC_ERR_INFEASIBLE: mc_result = -16;
/// A position is beyond the card's range.
pub const MC_ERR_OUT_OF_RANGE: mc_result = -17;
/// The card configuration can only change while all axes are disabled.
pub const MC_ERR_AXES_ENABLED: mc_result = -18;
/// The firmware does not know the command.
pub const MC_ERR_UNKNOWN_COMMAND: mc_result = -19;
/// An operating-system call failed.
pub const MC_ERR_IO: mc_result = -20;
/// The card or backend cannot do this (for example stepping a card that is not a stepped sim).
pub const MC_ERR_UNSUPPORTED: mc_result = -21;
/// No such axes group.
pub const MC_ERR_BAD_GROUP: mc_result = -22;
/// An axis already belongs to another group.
pub const MC_ERR_AXIS_IN_OTHER_GROUP: mc_result = -23;
/// The move needs an axis the group does not have.
pub const MC_ERR_AXIS_NOT_IN_GROUP: mc_result = -24;
/// An axis of the group is moving on its own.
pub const MC_ERR_AXIS_BUSY: mc_result = -25;
/// The axis belongs to an enabled group.
pub const MC_ERR_AXIS_GROUPED: mc_result = -26;
/// The arc has zero length or zero radius.
pub const MC_ERR_ZERO_LENGTH_ARC: mc_result = -27;
/// The centre is not equidistant from start and end.
pub const MC_ERR_CENTRE_NOT_EQUIDISTANT: mc_result = -28;
/// The radius is shorter than half the chord.
pub const MC_ERR_RADIUS_TOO_SMALL: mc_result = -29;
/// The three points of the arc are on one line.
pub const MC_ERR_COLLINEAR_POINTS: mc_result = -30;
/// The group's move queue is full.
pub const MC_ERR_QUEUE_FULL: mc_result = -31;
/// The interpolator cannot run with this acc/dec mode.
pub const MC_ERR_INCOMPATIBLE_MODE: mc_result = -32;
/// The group is disabled or not configured.
pub const MC_ERR_GROUP_DISABLED: mc_result = -33;
/// The filter still holds distance.
pub const MC_ERR_FILTER_BUSY: mc_result = -34;
/// NURBS data out of sequence.
pub const MC_ERR_NURBS_SEQUENCE: mc_result = -35;
/// NURBS degree outside 1..5.
pub const MC_ERR_NURBS_DEGREE: mc_result = -36;
/// NURBS curves need a group of at least 2 axes.
pub const MC_ERR_NURBS_DIMENSION: mc_result = -37;
/// Too few or too many NURBS control points.
pub const MC_ERR_NURBS_CTRL_COUNT: mc_result = -38;
/// The knot count must be control points + degree + 1.
pub const MC_ERR_NURBS_KNOT_COUNT: mc_result = -39;
/// The knots decrease.
pub const MC_ERR_NURBS_KNOTS_DECREASING: mc_result = -40;
/// An interior knot is repeated more than degree times.
pub const MC_ERR_NURBS_KNOT_MULTIPLICITY: mc_result = -41;
/// The knot vector is not clamped.
pub const MC_ERR_NURBS_NOT_CLAMPED: mc_result = -42;
/// A NURBS weight is not finite and positive.
pub const MC_ERR_NURBS_WEIGHT: mc_result = -43;
/// A control point is not finite.
pub const MC_ERR_NURBS_POINT: mc_result = -44;
/// The curve does not start where the group is.
pub const MC_ERR_NURBS_START: mc_result = -45;
/// The curve has zero length.
pub const MC_ERR_NURBS_ZERO_LENGTH: mc_result = -46;
/// The host watchdog tripped: reset the card's faults first.
pub const MC_ERR_WATCHDOG_TRIPPED: mc_result = -47;
/// An e-stop is latched: reset the card's faults first.
pub const MC_ERR_ESTOP_ACTIVE: mc_result = -48;
/// The move goes further into an active limit switch.
pub const MC_ERR_HARD_LIMIT: mc_result = -49;
/// The move goes further beyond a soft limit.
pub const MC_ERR_SOFT_LIMIT: mc_result = -50;
/// The cause of the fault is still present.
pub const MC_ERR_CAUSE_ACTIVE: mc_result = -51;
/// Watchdog timeout zero or under 1.5 x the host's heartbeat period.
pub const MC_ERR_WATCHDOG_TIMEOUT: mc_result = -52;
/// Stop category must be 0, 1 or 2.
pub const MC_ERR_BAD_CATEGORY: mc_result = -53;
/// A NURBS knot is not finite.
pub const MC_ERR_NURBS_KNOT: mc_result = -54;
/// A kinematic limit outside the range the card accepts (denormal, absurdly small or large).
pub const MC_ERR_LIMIT_RANGE: mc_result = -55;
/// The planned profile failed the card's own check and was refused: nothing moved.
pub const MC_ERR_PLAN_CHECK: mc_result = -56;
/// The card served the command after its deadline and refused it: it was not executed.
pub const MC_ERR_EXPIRED: mc_result = -57;
/// A stop ramp longer than the card's maximum stop time, or a maximum stop time out of range.
pub const MC_ERR_STOP_TOO_LONG: mc_result = -58;
/// The card's session belongs to another host.
pub const MC_ERR_SESSION: mc_result = -59;
/// The card went away (its process exited or was killed).
pub const MC_ERR_CARD_GONE: mc_result = -60;
/// The card was closed while the call waited (or before it).
pub const MC_ERR_CLOSED: mc_result = -61;
/// The wait was cancelled from another thread (`mc_cancel_waits`).
pub const MC_ERR_CANCELLED: mc_result = -62;
/// The card's server refused this user.
pub const MC_ERR_PERMISSION_DENIED: mc_result = -63;
/// The card handle (or motion) is unknown: never opened, or already closed.
pub const MC_ERR_BAD_HANDLE: mc_result = -100;
/// A pointer argument that must not be NULL was NULL.
pub const MC_ERR_NULL_POINTER: mc_result = -101;
/// The buffer is too small; the size needed (with the terminating NUL) was written to `*needed`.
pub const MC_ERR_BUFFER_TOO_SMALL: mc_result = -102;
/// The library panicked (a bug in libmotioncard); the call had no effect on the caller's
/// outputs. The message is in `mc_last_error_message`.
pub const MC_ERR_PANIC: mc_result = -103;

/// The code of an SDK error kind: one code per kind. An exhaustive match, so that a new kind
/// does not compile until it has its code.
pub(crate) fn code_of(kind: ErrorKind) -> mc_result {
    match kind {
        ErrorKind::BadUri => MC_ERR_BAD_URI,
        ErrorKind::NotFound => MC_ERR_NOT_FOUND,
        ErrorKind::Busy => MC_ERR_BUSY,
        ErrorKind::VersionMismatch => MC_ERR_VERSION_MISMATCH,
        ErrorKind::NotResponding => MC_ERR_NOT_RESPONDING,
        ErrorKind::Protocol => MC_ERR_PROTOCOL,
        ErrorKind::RingFull => MC_ERR_RING_FULL,
        ErrorKind::Timeout => MC_ERR_TIMEOUT,
        ErrorKind::Aborted => MC_ERR_ABORTED,
        ErrorKind::BadAxis => MC_ERR_BAD_AXIS,
        ErrorKind::NotFinite => MC_ERR_NOT_FINITE,
        ErrorKind::NonPositiveLimit => MC_ERR_NON_POSITIVE_LIMIT,
        ErrorKind::AxisDisabled => MC_ERR_AXIS_DISABLED,
        ErrorKind::InvalidState => MC_ERR_INVALID_STATE,
        ErrorKind::BadConfig => MC_ERR_BAD_CONFIG,
        ErrorKind::Infeasible => MC_ERR_INFEASIBLE,
        ErrorKind::OutOfRange => MC_ERR_OUT_OF_RANGE,
        ErrorKind::AxesEnabled => MC_ERR_AXES_ENABLED,
        ErrorKind::UnknownCommand => MC_ERR_UNKNOWN_COMMAND,
        ErrorKind::Io => MC_ERR_IO,
        ErrorKind::Unsupported => MC_ERR_UNSUPPORTED,
        ErrorKind::BadGroup => MC_ERR_BAD_GROUP,
        ErrorKind::AxisInOtherGroup => MC_ERR_AXIS_IN_OTHER_GROUP,
        ErrorKind::AxisNotInGroup => MC_ERR_AXIS_NOT_IN_GROUP,
        ErrorKind::AxisBusy => MC_ERR_AXIS_BUSY,
        ErrorKind::AxisGrouped => MC_ERR_AXIS_GROUPED,
        ErrorKind::ZeroLengthArc => MC_ERR_ZERO_LENGTH_ARC,
        ErrorKind::CentreNotEquidistant => MC_ERR_CENTRE_NOT_EQUIDISTANT,
        ErrorKind::RadiusTooSmall => MC_ERR_RADIUS_TOO_SMALL,
        ErrorKind::CollinearPoints => MC_ERR_COLLINEAR_POINTS,
        ErrorKind::QueueFull => MC_ERR_QUEUE_FULL,
        ErrorKind::IncompatibleMode => MC_ERR_INCOMPATIBLE_MODE,
        ErrorKind::GroupDisabled => MC_ERR_GROUP_DISABLED,
        ErrorKind::FilterBusy => MC_ERR_FILTER_BUSY,
        ErrorKind::NurbsSequence => MC_ERR_NURBS_SEQUENCE,
        ErrorKind::NurbsDegree => MC_ERR_NURBS_DEGREE,
        ErrorKind::NurbsDimension => MC_ERR_NURBS_DIMENSION,
        ErrorKind::NurbsCtrlCount => MC_ERR_NURBS_CTRL_COUNT,
        ErrorKind::NurbsKnotCount => MC_ERR_NURBS_KNOT_COUNT,
        ErrorKind::NurbsKnotsDecreasing => MC_ERR_NURBS_KNOTS_DECREASING,
        ErrorKind::NurbsKnotMultiplicity => MC_ERR_NURBS_KNOT_MULTIPLICITY,
        ErrorKind::NurbsNotClamped => MC_ERR_NURBS_NOT_CLAMPED,
        ErrorKind::NurbsWeight => MC_ERR_NURBS_WEIGHT,
        ErrorKind::NurbsPoint => MC_ERR_NURBS_POINT,
        ErrorKind::NurbsStart => MC_ERR_NURBS_START,
        ErrorKind::NurbsZeroLength => MC_ERR_NURBS_ZERO_LENGTH,
        ErrorKind::NurbsKnot => MC_ERR_NURBS_KNOT,
        ErrorKind::WatchdogTripped => MC_ERR_WATCHDOG_TRIPPED,
        ErrorKind::EStopActive => MC_ERR_ESTOP_ACTIVE,
        ErrorKind::HardLimit => MC_ERR_HARD_LIMIT,
        ErrorKind::SoftLimit => MC_ERR_SOFT_LIMIT,
        ErrorKind::CauseActive => MC_ERR_CAUSE_ACTIVE,
        ErrorKind::WatchdogTimeout => MC_ERR_WATCHDOG_TIMEOUT,
        ErrorKind::BadCategory => MC_ERR_BAD_CATEGORY,
        ErrorKind::LimitRange => MC_ERR_LIMIT_RANGE,
        ErrorKind::PlanCheck => MC_ERR_PLAN_CHECK,
        ErrorKind::Expired => MC_ERR_EXPIRED,
        ErrorKind::StopTooLong => MC_ERR_STOP_TOO_LONG,
        ErrorKind::Session => MC_ERR_SESSION,
        ErrorKind::CardGone => MC_ERR_CARD_GONE,
        ErrorKind::Closed => MC_ERR_CLOSED,
        ErrorKind::Cancelled => MC_ERR_CANCELLED,
        ErrorKind::PermissionDenied => MC_ERR_PERMISSION_DENIED,
    }
}

/// The static description of a code (`mc_result_str`).
pub(crate) fn describe(code: mc_result) -> &'static CStr {
    match code {
        MC_OK => c"success",
        MC_ERR_BAD_URI => c"bad card URI",
        MC_ERR_NOT_FOUND => c"no card at that URI",
        MC_ERR_BUSY => c"the card is in use by another process",
        MC_ERR_VERSION_MISMATCH => c"the card's DPRAM layout version differs from the library's",
        MC_ERR_NOT_RESPONDING => c"the card does not respond",
        MC_ERR_PROTOCOL => c"the card broke the protocol",
        MC_ERR_RING_FULL => c"the command ring is full",
        MC_ERR_TIMEOUT => c"timed out",
        MC_ERR_ABORTED => c"the motion was aborted",
        MC_ERR_BAD_AXIS => c"no such axis",
        MC_ERR_NOT_FINITE => c"an argument is NaN or infinite",
        MC_ERR_NON_POSITIVE_LIMIT => c"a limit is zero or negative",
        MC_ERR_AXIS_DISABLED => c"the axis is disabled",
        MC_ERR_INVALID_STATE => c"not allowed in the axis's current state",
        MC_ERR_BAD_CONFIG => c"a configuration value is out of range",
        MC_ERR_INFEASIBLE => c"no motion profile satisfies the request",
        MC_ERR_OUT_OF_RANGE => c"position out of range",
        MC_ERR_AXES_ENABLED => c"all axes must be disabled first",
        MC_ERR_UNKNOWN_COMMAND => c"the firmware does not know the command",
        MC_ERR_IO => c"an operating-system call failed",
        MC_ERR_UNSUPPORTED => c"not supported by this card",
        MC_ERR_BAD_GROUP => c"no such axes group",
        MC_ERR_AXIS_IN_OTHER_GROUP => c"an axis already belongs to another group",
        MC_ERR_AXIS_NOT_IN_GROUP => c"the move needs an axis the group does not have",
        MC_ERR_AXIS_BUSY => c"an axis of the group is moving on its own",
        MC_ERR_AXIS_GROUPED => c"the axis belongs to an enabled group",
        MC_ERR_ZERO_LENGTH_ARC => c"the arc has zero length or zero radius",
        MC_ERR_CENTRE_NOT_EQUIDISTANT => c"the centre is not equidistant from start and end",
        MC_ERR_RADIUS_TOO_SMALL => c"the radius is shorter than half the chord",
        MC_ERR_COLLINEAR_POINTS => c"the three points of the arc are on one line",
        MC_ERR_QUEUE_FULL => c"the group's move queue is full",
        MC_ERR_INCOMPATIBLE_MODE => c"the interpolator cannot run with this acc/dec mode",
        MC_ERR_GROUP_DISABLED => c"the group is disabled or not configured",
        MC_ERR_FILTER_BUSY => c"the filter still holds distance",
        MC_ERR_NURBS_SEQUENCE => c"NURBS data out of sequence",
        MC_ERR_NURBS_DEGREE => c"NURBS degree outside 1..5",
        MC_ERR_NURBS_DIMENSION => c"NURBS curves need a group of at least 2 axes",
        MC_ERR_NURBS_CTRL_COUNT => c"too few or too many NURBS control points",
        MC_ERR_NURBS_KNOT_COUNT => c"the knot count must be control points + degree + 1",
        MC_ERR_NURBS_KNOTS_DECREASING => c"the knots decrease",
        MC_ERR_NURBS_KNOT_MULTIPLICITY => c"an interior knot is repeated more than degree times",
        MC_ERR_NURBS_NOT_CLAMPED => c"the knot vector is not clamped",
        MC_ERR_NURBS_WEIGHT => c"a NURBS weight is not finite and positive",
        MC_ERR_NURBS_POINT => c"a control point is not finite",
        MC_ERR_NURBS_START => c"the curve does not start where the group is",
        MC_ERR_NURBS_ZERO_LENGTH => c"the curve has zero length",
        MC_ERR_NURBS_KNOT => c"a knot is not finite",
        MC_ERR_WATCHDOG_TRIPPED => c"the host watchdog tripped: reset the card's faults first",
        MC_ERR_ESTOP_ACTIVE => c"an e-stop is latched: reset the card's faults first",
        MC_ERR_HARD_LIMIT => c"the move goes further into an active limit switch",
        MC_ERR_SOFT_LIMIT => c"the move goes further beyond a soft limit",
        MC_ERR_CAUSE_ACTIVE => c"the cause of the fault is still present",
        MC_ERR_WATCHDOG_TIMEOUT => {
            c"watchdog timeout zero or under 1.5 x the host's heartbeat period"
        }
        MC_ERR_BAD_CATEGORY => c"stop category must be 0, 1 or 2",
        MC_ERR_LIMIT_RANGE => c"a limit is outside the range the card accepts",
        MC_ERR_PLAN_CHECK => c"the planned profile failed the card's check; nothing moved",
        MC_ERR_EXPIRED => c"the card served the command after its deadline; not executed",
        MC_ERR_STOP_TOO_LONG => c"the stop ramp is longer than the card's maximum stop time",
        MC_ERR_SESSION => c"another host's session is attached",
        MC_ERR_CARD_GONE => c"the card went away",
        MC_ERR_CLOSED => c"the card was closed",
        MC_ERR_CANCELLED => c"the wait was cancelled",
        MC_ERR_PERMISSION_DENIED => c"the card's server refused this user",
        MC_ERR_BAD_HANDLE => c"unknown or closed handle",
        MC_ERR_NULL_POINTER => c"a required pointer is NULL",
        MC_ERR_BUFFER_TOO_SMALL => c"the buffer is too small",
        MC_ERR_PANIC => c"internal error in libmotioncard (panic)",
        _ => c"unknown result code",
    }
}

/// Why a call failed: its code and the detailed message kept for `mc_last_error_message`.
#[derive(Debug)]
pub(crate) struct Failure {
    pub code: mc_result,
    pub message: String,
}

impl Failure {
    pub(crate) fn new(code: mc_result, message: impl Into<String>) -> Self {
        Self {
            code,
            message: message.into(),
        }
    }

    pub(crate) fn null(what: &str) -> Self {
        Self::new(MC_ERR_NULL_POINTER, format!("{what} is NULL"))
    }
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Self::new(code_of(e.kind()), e.to_string())
    }
}

thread_local! {
    static LAST_ERROR: RefCell<String> = const { RefCell::new(String::new()) };
}

/// Keep `message` as this thread's last failure.
fn set_last_error(message: String) {
    // During thread exit the slot may be gone; the message is then lost, nothing else.
    let _ = LAST_ERROR.try_with(|m| *m.borrow_mut() = message);
}

/// This thread's last failure ("" when there was none).
pub(crate) fn last_error() -> String {
    LAST_ERROR
        .try_with(|m| m.borrow().clone())
        .unwrap_or_default()
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> &str {
    if let Some(s) = payload.downcast_ref::<&str>() {
        s
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s
    } else {
        "(no message)"
    }
}

#[cfg(any(test, feature = "test-panic"))]
thread_local! {
    /// Set by `mc__test_panic_next_call`: the thread's next guarded call panics.
    static PANIC_NEXT: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Test builds only (`cfg(test)` or the `test-panic` feature): make the calling thread's next
/// `mc_` call panic inside its panic boundary.
#[cfg(any(test, feature = "test-panic"))]
pub(crate) fn panic_next_call() {
    PANIC_NEXT.with(|p| p.set(true));
}

/// Where a test build panics on request, first thing inside the boundary; nothing in a release
/// library.
#[inline(always)]
fn test_panic_point() {
    #[cfg(any(test, feature = "test-panic"))]
    if PANIC_NEXT.with(|p| p.replace(false)) {
        panic!("test panic requested by mc__test_panic_next_call");
    }
}

/// The panic boundary: every exported function runs its body in here. A failure becomes its
/// code and this thread's last-error message; a panic becomes `MC_ERR_PANIC`.
pub(crate) fn guard(body: impl FnOnce() -> Result<(), Failure>) -> mc_result {
    let body = || {
        test_panic_point();
        body()
    };
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => MC_OK,
        Ok(Err(f)) => {
            set_last_error(f.message);
            f.code
        }
        Err(payload) => {
            set_last_error(format!(
                "libmotioncard panicked: {}",
                panic_message(&*payload)
            ));
            MC_ERR_PANIC
        }
    }
}

/// [`guard`] for the calls that read the last error: their own failures must not replace the
/// message the caller is trying to read.
pub(crate) fn guard_quiet(body: impl FnOnce() -> Result<(), Failure>) -> mc_result {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => MC_OK,
        Ok(Err(f)) => f.code,
        Err(_) => MC_ERR_PANIC,
    }
}

/// The description of a code as a C string.
pub(crate) fn describe_ptr(code: mc_result) -> *const c_char {
    describe(code).as_ptr()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every `ErrorKind`, listed once and used twice: as the array the test walks, and as the
    /// arms of a match the compiler checks for exhaustiveness. A kind added to the SDK does not
    /// compile here until it is listed, so the list cannot go stale.
    macro_rules! every_kind {
        ($($k:ident),+ $(,)?) => {
            const KINDS: &[ErrorKind] = &[$(ErrorKind::$k),+];
            #[allow(dead_code)]
            fn listed(k: ErrorKind) {
                match k {
                    $(ErrorKind::$k => {})+
                }
            }
        };
    }

    every_kind!(
        BadUri,
        NotFound,
        Busy,
        VersionMismatch,
        NotResponding,
        Protocol,
        RingFull,
        Timeout,
        Aborted,
        BadAxis,
        NotFinite,
        NonPositiveLimit,
        AxisDisabled,
        InvalidState,
        BadConfig,
        Infeasible,
        OutOfRange,
        AxesEnabled,
        UnknownCommand,
        Io,
        Unsupported,
        BadGroup,
        AxisInOtherGroup,
        AxisNotInGroup,
        AxisBusy,
        AxisGrouped,
        ZeroLengthArc,
        CentreNotEquidistant,
        RadiusTooSmall,
        CollinearPoints,
        QueueFull,
        IncompatibleMode,
        GroupDisabled,
        FilterBusy,
        NurbsSequence,
        NurbsDegree,
        NurbsDimension,
        NurbsCtrlCount,
        NurbsKnotCount,
        NurbsKnotsDecreasing,
        NurbsKnotMultiplicity,
        NurbsNotClamped,
        NurbsWeight,
        NurbsPoint,
        NurbsStart,
        NurbsZeroLength,
        NurbsKnot,
        WatchdogTripped,
        EStopActive,
        HardLimit,
        SoftLimit,
        CauseActive,
        WatchdogTimeout,
        BadCategory,
        LimitRange,
        PlanCheck,
        Expired,
        StopTooLong,
        Session,
        CardGone,
        Closed,
        Cancelled,
        PermissionDenied,
    );

    #[test]
    fn codes_are_one_to_one_with_kinds_and_described() {
        // Listed once each (a kind listed twice would also pass the match).
        let distinct: std::collections::HashSet<_> = KINDS.iter().collect();
        assert_eq!(distinct.len(), KINDS.len(), "a kind is listed twice");
        let mut codes: Vec<mc_result> = KINDS.iter().map(|k| code_of(*k)).collect();
        codes.extend([
            MC_ERR_BAD_HANDLE,
            MC_ERR_NULL_POINTER,
            MC_ERR_BUFFER_TOO_SMALL,
            MC_ERR_PANIC,
        ]);
        let mut seen = std::collections::HashSet::new();
        for c in &codes {
            assert!(*c < 0, "{c} is not negative");
            assert!(seen.insert(*c), "code {c} used twice");
            let d = describe(*c).to_str().unwrap();
            assert_ne!(d, "unknown result code", "code {c} has no description");
        }
        let descriptions: std::collections::HashSet<_> =
            codes.iter().map(|c| describe(*c)).collect();
        assert_eq!(
            descriptions.len(),
            codes.len(),
            "two codes share a description"
        );
        assert_eq!(describe(MC_OK).to_str().unwrap(), "success");
        assert_eq!(describe(-9999).to_str().unwrap(), "unknown result code");
        assert_eq!(describe(7).to_str().unwrap(), "unknown result code");
    }

    #[test]
    fn a_panic_becomes_mc_err_panic_with_its_message() {
        let r = guard(|| panic!("deliberate test panic {}", 42));
        assert_eq!(r, MC_ERR_PANIC);
        assert!(
            last_error().contains("deliberate test panic 42"),
            "{}",
            last_error()
        );
        assert_eq!(guard_quiet(|| panic!("quiet")), MC_ERR_PANIC);
        assert!(last_error().contains("deliberate test panic 42"));
    }

    #[test]
    fn an_exported_function_driven_into_a_panic_returns_mc_err_panic() {
        use crate::api::{mc_close, mc_get_status, mc_last_error_message, mc_open_sim_stepped};
        let mut h = 0;
        // SAFETY: valid out pointers throughout.
        assert_eq!(unsafe { mc_open_sim_stepped(1, 1000, &mut h) }, MC_OK);
        let mut st = crate::types::mc_status {
            state: 99,
            ..Default::default()
        };
        panic_next_call();
        // SAFETY: as above.
        assert_eq!(unsafe { mc_get_status(h, 0, &mut st) }, MC_ERR_PANIC);
        assert_eq!(st.state, 99, "output written by a call that panicked");
        let mut buf = [0 as std::ffi::c_char; 256];
        let mut needed = 0;
        // SAFETY: `buf` holds 256 bytes.
        let r = unsafe { mc_last_error_message(buf.as_mut_ptr(), buf.len(), &mut needed) };
        assert_eq!(r, MC_OK);
        // SAFETY: NUL-terminated by mc_last_error_message.
        let msg = unsafe { CStr::from_ptr(buf.as_ptr()) }.to_str().unwrap();
        assert!(msg.contains("panicked: test panic requested"), "{msg}");
        // The card and the thread carry on.
        // SAFETY: as above.
        assert_eq!(unsafe { mc_get_status(h, 0, &mut st) }, MC_OK);
        assert_eq!(st.state, crate::types::MC_AXIS_STATE_DISABLED);
        assert_eq!(mc_close(h), MC_OK);
    }

    #[test]
    fn failures_set_the_per_thread_message_and_quiet_ones_do_not() {
        assert_eq!(
            guard(|| Err(Failure::new(MC_ERR_BAD_AXIS, "axis 9 on thread A"))),
            MC_ERR_BAD_AXIS
        );
        std::thread::spawn(|| {
            assert_eq!(last_error(), "");
            guard(|| Err(Failure::null("thread B's pointer")));
            assert_eq!(last_error(), "thread B's pointer is NULL");
        })
        .join()
        .unwrap();
        assert_eq!(last_error(), "axis 9 on thread A");
        assert_eq!(
            guard_quiet(|| Err(Failure::new(MC_ERR_BUFFER_TOO_SMALL, "x"))),
            MC_ERR_BUFFER_TOO_SMALL
        );
        assert_eq!(last_error(), "axis 9 on thread A");
        assert_eq!(guard(|| Ok(())), MC_OK);
        assert_eq!(
            last_error(),
            "axis 9 on thread A",
            "success keeps the last failure"
        );
    }
}

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
/// The card handle (or motion) is unknown: never opened, or already closed.
pub const MC_ERR_BAD_HANDLE: mc_result = -100;
/// A pointer argument that must not be NULL was NULL.
pub const MC_ERR_NULL_POINTER: mc_result = -101;
/// The buffer is too small; the size needed (with the terminating NUL) was written to `*needed`.
pub const MC_ERR_BUFFER_TOO_SMALL: mc_result = -102;
/// The library panicked (a bug in libmotioncard); the call had no effect on the caller's
/// outputs. The message is in `mc_last_error_message`.
pub const MC_ERR_PANIC: mc_result = -103;

/// The code of an SDK error kind (the SDK's table of kinds holds it).
pub(crate) fn code_of(kind: ErrorKind) -> mc_result {
    kind.code()
}

/// An unknown enumeration value from C.
pub(crate) fn unknown(what: &str, v: u32) -> Failure {
    Failure::new(ErrorKind::BadConfig.code(), format!("unknown {what} {v}"))
}

/// The static description of a code (`mc_result_str`).
pub(crate) fn describe(code: mc_result) -> &'static CStr {
    match code {
        MC_OK => c"success",
        MC_ERR_BAD_HANDLE => c"unknown or closed handle",
        MC_ERR_NULL_POINTER => c"a required pointer is NULL",
        MC_ERR_BUFFER_TOO_SMALL => c"the buffer is too small",
        MC_ERR_PANIC => c"internal error in libmotioncard (panic)",
        _ => ErrorKind::from_code(code).map_or(c"unknown result code", ErrorKind::c_description),
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

    const KINDS: &[ErrorKind] = ErrorKind::ALL;

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
        assert_eq!(st.state, crate::codes::MC_AXIS_STATE_DISABLED);
        assert_eq!(mc_close(h), MC_OK);
    }

    #[test]
    fn failures_set_the_per_thread_message_and_quiet_ones_do_not() {
        assert_eq!(
            guard(|| Err(Failure::new(
                ErrorKind::BadAxis.code(),
                "axis 9 on thread A"
            ))),
            ErrorKind::BadAxis.code()
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

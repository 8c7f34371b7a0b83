//! The one helper every layer shares: a mutex lock that survives poisoning. A leaf module: it
//! imports nothing of this crate, so the session, the trace and the card can all use it.

use std::sync::{Mutex, MutexGuard};

/// Lock a mutex, recovering from a poisoned one (a panicking user thread must not brick the card).
pub(crate) fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

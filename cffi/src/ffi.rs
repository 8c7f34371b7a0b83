//! Pointers from C: checked for NULL before anything happens, written only at the end.
//!
//! Reads and writes are unaligned (`read_unaligned` / `write_unaligned`), so a misaligned
//! pointer from C is not undefined behaviour on our side either.

use crate::result::{Failure, MC_ERR_BUFFER_TOO_SMALL};
use motioncard_sdk::ErrorKind;
use std::ffi::{c_char, CStr};

/// A checked, non-NULL output pointer. Check every output first, compute, then write: a
/// failed call leaves the caller's outputs untouched.
pub(crate) struct Out<T>(*mut T);

impl<T> Out<T> {
    /// Check `p`; `what` names the parameter in the error message.
    pub(crate) fn new(p: *mut T, what: &str) -> Result<Self, Failure> {
        if p.is_null() {
            Err(Failure::null(what))
        } else {
            Ok(Out(p))
        }
    }

    /// An optional output ("may be NULL" in the header): `None` for NULL, which the caller
    /// then simply does not write.
    pub(crate) fn optional(p: *mut T) -> Option<Self> {
        (!p.is_null()).then_some(Out(p))
    }

    /// Store the result.
    ///
    /// # Safety
    /// The pointer given to [`Out::new`] is valid for a write of a `T` (the caller's side of
    /// the function's contract).
    pub(crate) unsafe fn write(self, value: T) {
        // SAFETY: non-NULL (checked in `new`), valid for writes by the caller's contract;
        // unaligned writes need no alignment.
        unsafe { self.0.write_unaligned(value) }
    }
}

/// Read an input struct.
///
/// # Safety
/// `p` is NULL or valid for a read of a `T`, and every bit pattern is a valid `T` (plain
/// numbers).
pub(crate) unsafe fn read_in<T: Copy>(p: *const T, what: &str) -> Result<T, Failure> {
    if p.is_null() {
        return Err(Failure::null(what));
    }
    // SAFETY: non-NULL, valid for reads by the caller's contract; any bits are a valid `T`.
    Ok(unsafe { p.read_unaligned() })
}

/// Copy an input array of `n` elements. `p` may be NULL only when `n` is 0. The caller bounds
/// `n` first (the copy allocates `n` elements).
///
/// # Safety
/// `p` is NULL or valid for reads of `n` consecutive `T`s, and every bit pattern is a valid `T`.
pub(crate) unsafe fn read_slice<T: Copy>(
    p: *const T,
    n: usize,
    what: &str,
) -> Result<Vec<T>, Failure> {
    if n == 0 {
        return Ok(Vec::new());
    }
    if p.is_null() {
        return Err(Failure::null(what));
    }
    // SAFETY: non-NULL, valid for reads of `n` elements by the caller's contract, so every
    // `p.add(i)` with i < n stays inside that range; unaligned reads need no alignment.
    Ok((0..n)
        .map(|i| unsafe { p.add(i).read_unaligned() })
        .collect())
}

/// Read element `i` of an input array (the caller has checked `p` for NULL and bounded `i` by
/// the array's length): arrays of structs are read one element at a time, so nothing is
/// allocated for a length the caller merely claims.
///
/// # Safety
/// `p` is non-NULL and valid for reads of at least `i + 1` consecutive `T`s, and every bit
/// pattern is a valid `T`.
pub(crate) unsafe fn read_at<T: Copy>(p: *const T, i: usize) -> T {
    // SAFETY: `p.add(i)` stays inside the caller's array by the contract; unaligned reads need
    // no alignment.
    unsafe { p.add(i).read_unaligned() }
}

/// A caller's array for an output of variable length: `buf` of `len` elements, and `needed`
/// for the number of elements the result has. `buf` may be NULL only when `len` is 0 (a size
/// query).
pub(crate) struct ArrayBuf<T> {
    buf: *mut T,
    len: usize,
    needed: Out<usize>,
}

impl<T: Copy> ArrayBuf<T> {
    pub(crate) fn new(buf: *mut T, len: usize, needed: *mut usize) -> Result<Self, Failure> {
        let needed = Out::new(needed, "needed")?;
        if buf.is_null() && len > 0 {
            return Err(Failure::null("buf"));
        }
        Ok(Self { buf, len, needed })
    }

    /// Copy `values` into the array and their count into `*needed`; or, when they do not fit,
    /// only the count into `*needed` and `MC_ERR_BUFFER_TOO_SMALL`.
    ///
    /// # Safety
    /// `buf` is valid for writes of `len` elements and `needed` for a write of a `size_t`.
    pub(crate) unsafe fn fill(self, values: &[T]) -> Result<(), Failure> {
        let n = values.len();
        if n > self.len {
            // SAFETY: `needed` was checked non-NULL; valid by the caller's contract.
            unsafe { self.needed.write(n) };
            return Err(Failure::new(
                MC_ERR_BUFFER_TOO_SMALL,
                format!("the array holds {} values, {n} are needed", self.len),
            ));
        }
        // SAFETY: n <= len, so `buf` (non-NULL when n > 0, since then len > 0) has room for the
        // n elements, written unaligned one by one; `needed` is valid by the contract.
        unsafe {
            for (i, v) in values.iter().enumerate() {
                self.buf.add(i).write_unaligned(*v);
            }
            self.needed.write(n);
        }
        Ok(())
    }
}

/// Borrow a NUL-terminated UTF-8 string (a URI).
///
/// # Safety
/// `p` is NULL or points to a NUL-terminated string that stays alive and unchanged for `'a`.
pub(crate) unsafe fn uri<'a>(p: *const c_char, what: &str) -> Result<&'a str, Failure> {
    if p.is_null() {
        return Err(Failure::null(what));
    }
    // SAFETY: non-NULL and NUL-terminated by the caller's contract.
    let s = unsafe { CStr::from_ptr(p) };
    s.to_str().map_err(|_| {
        Failure::new(
            ErrorKind::BadUri.code(),
            format!("{what} is not valid UTF-8"),
        )
    })
}

/// A caller's string buffer: `buf` of `len` bytes, and `needed` for the size the string takes
/// (bytes + the terminating NUL). `buf` may be NULL only when `len` is 0 (a size query).
pub(crate) struct StrBuf {
    buf: *mut c_char,
    len: usize,
    needed: Out<usize>,
}

impl StrBuf {
    pub(crate) fn new(buf: *mut c_char, len: usize, needed: *mut usize) -> Result<Self, Failure> {
        let needed = Out::new(needed, "needed")?;
        if buf.is_null() && len > 0 {
            return Err(Failure::null("buf"));
        }
        Ok(Self { buf, len, needed })
    }

    /// Copy `s` and a NUL into the buffer and its size into `*needed`; or, when it does not
    /// fit, only the size into `*needed` and `MC_ERR_BUFFER_TOO_SMALL`.
    ///
    /// # Safety
    /// `buf` is valid for writes of `len` bytes and `needed` for a write of a `size_t`.
    pub(crate) unsafe fn fill(self, s: &str) -> Result<(), Failure> {
        let n = s.len() + 1;
        if n > self.len {
            // SAFETY: `needed` was checked non-NULL; valid by the caller's contract.
            unsafe { self.needed.write(n) };
            return Err(Failure::new(
                MC_ERR_BUFFER_TOO_SMALL,
                format!("the buffer holds {} bytes, {n} are needed", self.len),
            ));
        }
        // SAFETY: n <= len, so `buf` (non-NULL, since len > 0) has room for the n bytes; the
        // source is a Rust string, which cannot overlap the caller's buffer.
        unsafe {
            std::ptr::copy_nonoverlapping(s.as_ptr(), self.buf.cast::<u8>(), s.len());
            self.buf.add(s.len()).write(0);
            self.needed.write(n);
        }
        Ok(())
    }
}

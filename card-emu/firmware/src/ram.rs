//! The firmware's large stores: a path's segments, a NURBS curve's control points and
//! profile, the curve slots, PT/PVT buffers, cam tables, compare tables, the scope's history.
//!
//! Each has a fixed capacity `N` and is made in the command manager (at boot or the first time
//! it is needed), never in the servo tick; a full one refuses what does not fit (`push` returns
//! it), and whoever pushes reports the refusal. Both builds hold at most `N` and refuse the
//! same pushes; they differ only in where the bytes are:
//!
//! - on the card (no feature `host`) a store is inline, in the card's RAM: [`FixedVec`] is a
//!   `heapless::Vec`, [`Lazy`] an `Option`. Nothing is allocated, ever.
//! - on a host (feature `host`: the emulator and the SDK) a store is on the heap, reserved
//!   when it is made ([`FixedVec::with_capacity`], [`Lazy::get_or_insert_with`]): an emulated
//!   card boots without reserving the stores it may never use (the fuzzers boot thousands), a
//!   store of several megabytes is never built on a thread's stack, and a curve the SDK
//!   builds takes the room of its points, not of the largest curve. The servo tick allocates
//!   nothing (`card-emu/tests/no_alloc.rs` counts it).

use core::ops::{Deref, DerefMut};

/// A store is full: what did not fit was not stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Full;

/// A vector of at most `N` values.
#[derive(Clone)]
pub struct FixedVec<T, const N: usize> {
    #[cfg(feature = "host")]
    v: alloc::vec::Vec<T>,
    #[cfg(not(feature = "host"))]
    v: heapless::Vec<T, N>,
}

impl<T, const N: usize> FixedVec<T, N> {
    /// Empty; a host reserves nothing yet.
    pub const fn new() -> Self {
        Self {
            #[cfg(feature = "host")]
            v: alloc::vec::Vec::new(),
            #[cfg(not(feature = "host"))]
            v: heapless::Vec::new(),
        }
    }

    /// Empty; a host reserves room for `n` (at most `N`) now, so that pushing as many
    /// allocates nothing.
    pub fn with_capacity(n: usize) -> Self {
        #[cfg(feature = "host")]
        let v = alloc::vec::Vec::with_capacity(n.min(N));
        #[cfg(not(feature = "host"))]
        let v = {
            let _ = n;
            heapless::Vec::new()
        };
        Self { v }
    }

    /// `len` copies of `x` (at most `N`).
    pub fn from_elem(x: T, len: usize) -> Self
    where
        T: Clone,
    {
        let len = len.min(N);
        let mut s = Self::with_capacity(len);
        for _ in 0..len {
            let _ = s.push(x.clone());
        }
        s
    }

    /// Appends `x`, or hands it back when `N` values are held.
    #[inline]
    pub fn push(&mut self, x: T) -> Result<(), T> {
        #[cfg(feature = "host")]
        {
            if self.v.len() >= N {
                return Err(x);
            }
            self.v.push(x);
            Ok(())
        }
        #[cfg(not(feature = "host"))]
        self.v.push(x)
    }

    /// Appends all of `xs`, or nothing when they do not all fit.
    pub fn extend_from_slice(&mut self, xs: &[T]) -> Result<(), Full>
    where
        T: Clone,
    {
        if self.v.len() + xs.len() > N {
            return Err(Full);
        }
        for x in xs {
            let _ = self.push(x.clone());
        }
        Ok(())
    }

    /// Removes every value (the storage stays).
    #[inline]
    pub fn clear(&mut self) {
        self.v.clear();
    }

    /// Keeps the first `len` values.
    #[inline]
    pub fn truncate(&mut self, len: usize) {
        self.v.truncate(len);
    }
}

impl<T, const N: usize> Default for FixedVec<T, N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T, const N: usize> Deref for FixedVec<T, N> {
    type Target = [T];
    #[inline]
    fn deref(&self) -> &[T] {
        &self.v
    }
}

impl<T, const N: usize> DerefMut for FixedVec<T, N> {
    #[inline]
    fn deref_mut(&mut self) -> &mut [T] {
        &mut self.v
    }
}

impl<T: PartialEq, const N: usize> PartialEq for FixedVec<T, N> {
    fn eq(&self, o: &Self) -> bool {
        self[..] == o[..]
    }
}

impl<T: core::fmt::Debug, const N: usize> core::fmt::Debug for FixedVec<T, N> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

/// A store made the first time the command manager needs it and kept for the card's life.
#[derive(Clone, Default)]
pub struct Lazy<T> {
    #[cfg(feature = "host")]
    v: Option<alloc::boxed::Box<T>>,
    #[cfg(not(feature = "host"))]
    v: Option<T>,
}

impl<T> Lazy<T> {
    /// Not made yet.
    pub const fn new() -> Self {
        Self { v: None }
    }

    /// The store, if made.
    #[inline]
    pub fn as_ref(&self) -> Option<&T> {
        #[cfg(feature = "host")]
        return self.v.as_deref();
        #[cfg(not(feature = "host"))]
        return self.v.as_ref();
    }

    /// The store, if made.
    #[inline]
    pub fn as_mut(&mut self) -> Option<&mut T> {
        #[cfg(feature = "host")]
        return self.v.as_deref_mut();
        #[cfg(not(feature = "host"))]
        return self.v.as_mut();
    }

    /// The store, made by `make` if it was not.
    #[inline]
    pub fn get_or_insert_with(&mut self, make: impl FnOnce() -> T) -> &mut T {
        #[cfg(feature = "host")]
        return self.v.get_or_insert_with(|| alloc::boxed::Box::new(make()));
        #[cfg(not(feature = "host"))]
        return self.v.get_or_insert_with(make);
    }

    /// Made?
    #[inline]
    pub fn is_some(&self) -> bool {
        self.v.is_some()
    }
}

impl<T: core::fmt::Debug> core::fmt::Debug for Lazy<T> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        self.as_ref().fmt(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_full_vector_refuses_and_keeps_what_it_holds() {
        let mut v: FixedVec<u32, 4> = FixedVec::with_capacity(2);
        for x in 0..4 {
            assert_eq!(v.push(x), Ok(()));
        }
        assert_eq!(v.push(9), Err(9));
        assert_eq!(&v[..], &[0, 1, 2, 3]);
        v.truncate(1);
        assert_eq!(v.extend_from_slice(&[5, 6, 7, 8]), Err(Full));
        assert_eq!(&v[..], &[0]);
        assert_eq!(v.extend_from_slice(&[5, 6, 7]), Ok(()));
        assert_eq!(&v[..], &[0, 5, 6, 7]);
        v.clear();
        assert!(v.is_empty());
        let f: FixedVec<f64, 3> = FixedVec::from_elem(1.5, 5);
        assert_eq!(&f[..], &[1.5; 3]);
    }

    #[test]
    fn a_lazy_store_is_made_once() {
        let mut l: Lazy<FixedVec<u8, 8>> = Lazy::new();
        assert!(!l.is_some() && l.as_ref().is_none());
        let _ = l.get_or_insert_with(|| FixedVec::from_elem(1, 2)).push(2);
        let _ = l.get_or_insert_with(|| FixedVec::from_elem(7, 8));
        assert_eq!(l.as_ref().map(|v| &v[..]), Some(&[1, 1, 2][..]));
        let _ = l.as_mut().map(|v| v.clear());
        assert_eq!(l.as_ref().map(|v| v.len()), Some(0));
    }
}

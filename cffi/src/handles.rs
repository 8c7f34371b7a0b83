//! Integer handles of what the library holds for a C program between calls (path streamers,
//! paths across cards): never 0, the slot + 1 in the low 16 bits and the slot's generation
//! above, so that a handle used after it was freed is refused (`MC_ERR_BAD_HANDLE`) rather than
//! finding the slot's next tenant.

use crate::result::{Failure, MC_ERR_BAD_HANDLE};
use std::sync::Mutex;

/// A table of handles to `T`s (`what` names them in refusals).
pub(crate) struct Handles<T> {
    slots: Mutex<Vec<(u16, Option<T>)>>,
    what: &'static str,
}

impl<T> Handles<T> {
    /// An empty table.
    pub(crate) const fn new(what: &'static str) -> Self {
        Self {
            slots: Mutex::new(Vec::new()),
            what,
        }
    }

    fn missing(&self, h: u32) -> Failure {
        Failure::new(
            MC_ERR_BAD_HANDLE,
            format!("no {} with handle {h}", self.what),
        )
    }

    /// Keep `v`: its handle, or `v` back with the refusal when 65,535 are held.
    pub(crate) fn insert(&self, v: T) -> Result<u32, (Failure, T)> {
        let mut all = self.slots.lock().unwrap_or_else(|p| p.into_inner());
        let slot = match all.iter().position(|(_, s)| s.is_none()) {
            Some(i) => i,
            None if all.len() < 0xffff => {
                all.push((1, None));
                all.len() - 1
            }
            None => {
                let f = Failure::new(
                    MC_ERR_BAD_HANDLE,
                    format!("65535 of {}s are held: free some", self.what),
                );
                return Err((f, v));
            }
        };
        all[slot].1 = Some(v);
        Ok((all[slot].0 as u32) << 16 | (slot as u32 + 1))
    }

    /// Run `f` on what handle `h` holds (`Some`, checked); `take` frees the handle after it.
    pub(crate) fn with<R>(
        &self,
        h: u32,
        take: bool,
        f: impl FnOnce(&mut Option<T>) -> R,
    ) -> Result<R, Failure> {
        let mut all = self.slots.lock().unwrap_or_else(|p| p.into_inner());
        let slot = ((h & 0xffff) as usize)
            .checked_sub(1)
            .filter(|&s| s < all.len())
            .ok_or_else(|| self.missing(h))?;
        let (generation, v) = &mut all[slot];
        if *generation != (h >> 16) as u16 || v.is_none() {
            return Err(self.missing(h));
        }
        let out = f(v);
        if take {
            *v = None;
            *generation = generation.wrapping_add(1).max(1);
        }
        Ok(out)
    }
}

//! The parameters of RS274/NGC: numbered (`#1`–`#5602`), named local (`#<name>`, one set per
//! subroutine call) and named global (`#<_name>`). A subroutine call saves #1–#30, sets them
//! from its arguments, and gets them back on return, with its named locals dropped.

use std::collections::HashMap;

/// The highest numbered parameter (LinuxCNC's).
pub const MAX_PARAM: u32 = 5602;
/// The parameters a subroutine call passes and restores: #1 to #30.
pub const CALL_PARAMS: usize = 30;

/// One call's saved state: the caller's #1–#30 and the callee's named locals.
#[derive(Debug, Clone, Default)]
struct Frame {
    saved: [f64; CALL_PARAMS],
    locals: HashMap<String, f64>,
}

/// Every parameter of a running program.
#[derive(Debug, Clone)]
pub struct Params {
    numbered: Vec<f64>,
    globals: HashMap<String, f64>,
    /// The main program's frame first, then one per active call.
    frames: Vec<Frame>,
}

impl Default for Params {
    fn default() -> Self {
        Self::new()
    }
}

impl Params {
    /// All zero, no named parameter, no call active.
    pub fn new() -> Self {
        Params {
            numbered: vec![0.0; MAX_PARAM as usize + 1],
            globals: HashMap::new(),
            frames: vec![Frame::default()],
        }
    }

    /// Numbered parameter `n` (`None` when `n` is 0 or above [`MAX_PARAM`]).
    pub fn get(&self, n: u32) -> Option<f64> {
        (1..=MAX_PARAM)
            .contains(&n)
            .then(|| self.numbered[n as usize])
    }

    /// Sets numbered parameter `n`; `false` (and nothing set) when out of range.
    pub fn set(&mut self, n: u32, v: f64) -> bool {
        if !(1..=MAX_PARAM).contains(&n) {
            return false;
        }
        self.numbered[n as usize] = v;
        true
    }

    /// A named parameter, given lower-case with spaces removed (LinuxCNC's rule). Names that
    /// start with `_` are global; others are the current call's.
    pub fn named(&self, name: &str) -> Option<f64> {
        if name.starts_with('_') {
            self.globals.get(name).copied()
        } else {
            self.frames.last().and_then(|f| f.locals.get(name).copied())
        }
    }

    /// Sets a named parameter (global when it starts with `_`).
    pub fn set_named(&mut self, name: &str, v: f64) {
        if name.starts_with('_') {
            self.globals.insert(name.to_owned(), v);
        } else if let Some(f) = self.frames.last_mut() {
            f.locals.insert(name.to_owned(), v);
        }
    }

    /// Enters a subroutine: #1–#30 saved, then set to `args` (missing ones 0).
    pub fn call(&mut self, args: &[f64]) {
        let mut saved = [0.0; CALL_PARAMS];
        saved.copy_from_slice(&self.numbered[1..=CALL_PARAMS]);
        for (i, slot) in self.numbered[1..=CALL_PARAMS].iter_mut().enumerate() {
            *slot = args.get(i).copied().unwrap_or(0.0);
        }
        self.frames.push(Frame {
            saved,
            locals: HashMap::new(),
        });
    }

    /// Leaves a subroutine: the caller's #1–#30 back, the callee's locals dropped. `false`
    /// when no call is active.
    pub fn ret(&mut self) -> bool {
        if self.frames.len() < 2 {
            return false;
        }
        let f = self.frames.pop().expect("checked above");
        self.numbered[1..=CALL_PARAMS].copy_from_slice(&f.saved);
        true
    }

    /// Active calls (0 in the main program).
    pub fn depth(&self) -> usize {
        self.frames.len() - 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_call_restores_the_callers_first_thirty_and_drops_its_locals() {
        let mut p = Params::new();
        p.set(1, 7.0);
        p.set(31, 9.0);
        p.set_named("_g", 1.0);
        p.set_named("x", 2.0);
        p.call(&[3.0]);
        assert_eq!(p.get(1), Some(3.0));
        assert_eq!(p.get(2), Some(0.0));
        assert_eq!(p.named("x"), None);
        p.set_named("x", 5.0);
        p.set_named("_g", 4.0);
        p.set(31, 10.0);
        assert!(p.ret());
        assert_eq!(p.get(1), Some(7.0));
        assert_eq!(p.get(31), Some(10.0), "#31 and above are not restored");
        assert_eq!(p.named("x"), Some(2.0));
        assert_eq!(p.named("_g"), Some(4.0));
        assert!(!p.ret());
    }

    #[test]
    fn out_of_range_numbers_are_refused() {
        let mut p = Params::new();
        assert!(!p.set(0, 1.0));
        assert!(!p.set(MAX_PARAM + 1, 1.0));
        assert_eq!(p.get(0), None);
        assert_eq!(p.get(MAX_PARAM), Some(0.0));
    }
}

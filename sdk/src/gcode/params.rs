//! The parameters of RS274/NGC: numbered (`#1`–`#5602`), named local (`#<name>`, one set per
//! subroutine call) and named global (`#<_name>`). A subroutine call saves #1–#30, sets them
//! from its arguments, and gets them back on return, with its named locals dropped.

use std::collections::HashMap;

/// The highest numbered parameter (LinuxCNC's).
pub const MAX_PARAM: u32 = 5602;
/// The parameters a subroutine call passes and restores: #1 to #30.
pub const CALL_PARAMS: usize = 30;

/// LinuxCNC's predefined named parameters: read-only, kept by the interpreter after every
/// block (see [`Predefined`] for what each holds).
pub const PREDEFINED: [&str; Predefined::COUNT] = [
    "_vmajor",
    "_vminor",
    "_line",
    "_motion_mode",
    "_plane",
    "_ccomp",
    "_metric",
    "_imperial",
    "_absolute",
    "_incremental",
    "_inverse_time",
    "_units_per_minute",
    "_units_per_rev",
    "_coord_system",
    "_tool_offset",
    "_retract_r_plane",
    "_retract_old_z",
    "_spindle_rpm_mode",
    "_spindle_css_mode",
    "_ijk_absolute_mode",
    "_lathe_diameter_mode",
    "_lathe_radius_mode",
    "_spindle_on",
    "_spindle_cw",
    "_mist",
    "_flood",
    "_speed_override",
    "_feed_override",
    "_adaptive_feed",
    "_feed_hold",
    "_feed",
    "_rpm",
    "_x",
    "_y",
    "_z",
    "_a",
    "_b",
    "_c",
    "_u",
    "_v",
    "_w",
    "_abs_x",
    "_abs_y",
    "_abs_z",
    "_abs_a",
    "_abs_b",
    "_abs_c",
    "_current_tool",
    "_current_pocket",
    "_selected_tool",
    "_selected_pocket",
    "_call_level",
    "_remap_level",
    "_task",
];

/// The predefined named parameters, in [`PREDEFINED`]'s order. Flags are 1 or 0; codes are
/// a G-code times ten (`_motion_mode` 10 for G1, 382 for G38.2, 800 after G80; `_plane` 170;
/// `_ccomp` 400/410/420; `_coord_system` 540 … 593); `_feed` is F in program units, `_rpm` S;
/// `_x` … `_w` the position in program coordinates and units (#5420–#5428), `_abs_x` … in
/// machine coordinates (program units); `_line` the source line being read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
#[repr(usize)]
pub enum Predefined {
    Vmajor,
    Vminor,
    Line,
    MotionMode,
    Plane,
    Ccomp,
    Metric,
    Imperial,
    Absolute,
    Incremental,
    InverseTime,
    UnitsPerMinute,
    UnitsPerRev,
    CoordSystem,
    ToolOffset,
    RetractRPlane,
    RetractOldZ,
    SpindleRpmMode,
    SpindleCssMode,
    IjkAbsoluteMode,
    LatheDiameterMode,
    LatheRadiusMode,
    SpindleOn,
    SpindleCw,
    Mist,
    Flood,
    SpeedOverride,
    FeedOverride,
    AdaptiveFeed,
    FeedHold,
    Feed,
    Rpm,
    /// `_x`; `_y` … `_w` follow.
    X,
    /// `_abs_x`; `_abs_y` … `_abs_c` follow.
    AbsX = 41,
    CurrentTool = 47,
    CurrentPocket,
    SelectedTool,
    SelectedPocket,
    CallLevel,
    RemapLevel,
    Task,
}

impl Predefined {
    /// How many there are.
    pub const COUNT: usize = 54;
}

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
    predefined: [f64; Predefined::COUNT],
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
            predefined: [0.0; Predefined::COUNT],
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
            match PREDEFINED.iter().position(|&p| p == name) {
                Some(i) => Some(self.predefined[i]),
                None => self.globals.get(name).copied(),
            }
        } else {
            self.frames.last().and_then(|f| f.locals.get(name).copied())
        }
    }

    /// Sets a named parameter (global when it starts with `_`); `false` (and nothing set)
    /// for a predefined one, which the program may only read.
    pub fn set_named(&mut self, name: &str, v: f64) -> bool {
        if name.starts_with('_') {
            if PREDEFINED.contains(&name) {
                return false;
            }
            self.globals.insert(name.to_owned(), v);
        } else if let Some(f) = self.frames.last_mut() {
            f.locals.insert(name.to_owned(), v);
        }
        true
    }

    /// Sets predefined parameter `p` (the interpreter's; `offset` for the ones that follow
    /// it, as `_y` after `_x`).
    pub fn set_predefined(&mut self, p: Predefined, offset: usize, v: f64) {
        if let Some(slot) = self.predefined.get_mut(p as usize + offset) {
            *slot = v;
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
    fn the_predefined_names_are_in_their_order_and_read_only() {
        use Predefined as P;
        for (p, name) in [
            (P::Vmajor, "_vmajor"),
            (P::Rpm, "_rpm"),
            (P::X, "_x"),
            (P::AbsX, "_abs_x"),
            (P::CurrentTool, "_current_tool"),
            (P::Task, "_task"),
        ] {
            assert_eq!(PREDEFINED[p as usize], name);
        }
        assert_eq!(PREDEFINED[P::X as usize + 8], "_w");
        assert_eq!(PREDEFINED[P::AbsX as usize + 5], "_abs_c");
        let mut params = Params::new();
        params.set_predefined(P::X, 1, 2.5);
        assert_eq!(params.named("_y"), Some(2.5));
        assert!(!params.set_named("_y", 1.0));
        assert_eq!(params.named("_y"), Some(2.5));
        assert!(params.set_named("_mine", 1.0));
        assert_eq!(params.named("_mine"), Some(1.0));
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

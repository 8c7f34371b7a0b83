//! G-code programs (`mc_gcode_*`): an RS274/NGC program (as LinuxCNC documents it for
//! milling) read by the SDK's interpreter and run on a group's path (`motioncard_sdk::gcode`).
//! A program is an integer handle (`mc_gcode`), as cards are; the host's hooks (spindle,
//! coolant, tool change, messages, M100–M199, pauses) are callbacks run inside
//! `mc_gcode_poll` and `mc_gcode_run`, on the caller's thread. A spindle on a card axis and
//! coolant on card outputs are settings (`mc_gcode_settings.spindle_axis`, `mist_output`,
//! `flood_output`; `motioncard_sdk::gcode::spindle`): G33/G33.1 need the spindle.

use crate::ffi::{read_in, uri, Out, StrBuf};
use crate::group::group_of;
use crate::registry::mc_card;
use crate::result::{guard, mc_result, Failure, MC_ERR_BAD_HANDLE};
use motioncard_sdk::gcode::run::{
    group_position, Hooks, RunSettings, RunState, Runner, SpindleSettings,
};
use motioncard_sdk::gcode::{
    FileSource, Options, PauseKind, Program, Source, SpindleDir, TextSource, ToolTable,
};
use motioncard_sdk::{Error, ErrorKind};
use std::ffi::{c_char, c_void, CString};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// A program handle: an integer (`generation << 16 | (slot + 1)`, as card handles). 0 is
/// never a handle.
#[allow(non_camel_case_types)]
pub type mc_gcode = u32;

/// `mc_gcode_poll` / `mc_gcode_run`: items are queued or run.
pub const MC_GCODE_RUNNING: u32 = 0;
/// Waiting for the motion queued so far to end (before a spindle, tool or pause operation,
/// or at the end).
pub const MC_GCODE_DRAINING: u32 = 1;
/// Paused (M0, M1 with the optional stop on, M60, or `mc_gcode_pause`), the motion ended:
/// `mc_gcode_resume` goes on.
pub const MC_GCODE_PAUSED: u32 = 2;
/// The program ended and all its motion is done.
pub const MC_GCODE_DONE: u32 = 3;
/// Aborted (`mc_gcode_abort`, or an error: `mc_gcode_error` says which line): nothing more
/// is read.
pub const MC_GCODE_ABORTED: u32 = 4;

/// How a program runs (`mc_gcode_default_settings` fills the defaults).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct mc_gcode_settings {
    /// The program's axis letter of each group axis in group order, NUL-terminated: "XYZ"
    /// (the default), "XYZA", ... Arcs need X, Y, Z as the group's first three axes. The
    /// group's axes are taken to be in mm and degrees.
    pub axes: [c_char; 8],
    /// Rapid (G0) speed, mm/s.
    pub rapid_feed: f64,
    /// The largest feed, mm/s: a faster programmed feed runs at this.
    pub max_feed: f64,
    /// Corner tolerance of G64 without P, mm (a P in the program wins).
    pub tolerance: f64,
    /// How closely splines (G5) are followed, mm.
    pub spline_tolerance: f64,
    /// 1: lines starting with '/' are skipped.
    pub block_delete: u32,
    /// 1: M1 pauses.
    pub optional_stop: u32,
    /// The card's digital input (0..15) the touch probe of G38.2–G38.5 is wired to; -1
    /// (the default): none, a probing move is then an error.
    pub probe_input: i32,
    /// The spindle's card axis (enabled, not one of the group's; its user unit a revolution:
    /// its scale the encoder's counts per revolution, whole revolutions its index), or -1
    /// (the default): no spindle on the card, the spindle hook only, G33/G33.1 refused. With
    /// one, M3/M4 with S turn it (M3 forward), M5 halts it, and G33/G33.1 follow its encoder.
    pub spindle_axis: i32,
    /// The card output M7 sets (M9 clears), or -1 (the default): none.
    pub mist_output: i32,
    /// The card output M8 sets (M9 clears), or -1 (the default): none.
    pub flood_output: i32,
    /// The spindle's largest speed, rpm (default 3000): a larger S runs at this, with a
    /// message.
    pub spindle_max_rpm: f64,
    /// The spindle's acceleration, rev/s² (default 100).
    pub spindle_acceleration: f64,
    /// The spindle's jerk, rev/s³ (default 2000).
    pub spindle_jerk: f64,
    /// 1 (the default): the run is measured as it goes, for `mc_gcode_report`; 0: not.
    pub report: u32,
}

/// What a run did (`mc_gcode_report`), measured from the X, Y and Z axes' commanded and
/// actual positions of every tick the run saw: each poll of `mc_gcode_poll` or
/// `mc_gcode_run` samples the card once, so on a stepped card (`mc_gcode_run` steps it a
/// tick a poll) every tick is seen, and on a card running on its own those read
/// (`ticks_seen` of `ticks`; the peaks then come from consecutive ticks only). Lengths in
/// mm, the programmed path taken from the program (splines as fine polylines).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct mc_path_report {
    /// Seconds from the last tick at rest before the motion to the first at rest after it.
    pub path_time: f64,
    /// Motion blocks of the program so far (lines and arcs, rapids included; an arc with P
    /// turns counts one a turn; a spline its polyline).
    pub segments: u64,
    /// The worst axis's peak commanded velocity over its path limit
    /// (`mc_group_configure_path`'s `vmax`; an axis with none counts 0).
    pub peak_velocity_ratio: f64,
    /// The same for acceleration (`amax`).
    pub peak_acceleration_ratio: f64,
    /// The same for jerk (`jmax`).
    pub peak_jerk_ratio: f64,
    /// The largest distance from a commanded point to the programmed path, mm.
    pub max_deviation: f64,
    /// The largest distance from an actual point (the encoders) to the programmed path, mm:
    /// the contour error.
    pub max_contour_error: f64,
    /// The largest distance between the commanded and the actual point of one tick, mm.
    pub max_following_error: f64,
    /// Stops between the first and the last move (dwells count).
    pub exact_stops: u64,
    /// Ticks from the first sample to the last.
    pub ticks: u64,
    /// Of them, the ticks sampled.
    pub ticks_seen: u64,
}

/// The C settings' defaults of the spindle: 3000 rpm, 100 rev/s², 2000 rev/s³.
const SPINDLE_DEFAULTS: (f64, f64, f64) = (3000.0, 100.0, 2000.0);

/// An axis or output number, or -1 for none.
fn optional(v: i32, what: &str) -> Result<Option<u32>, Failure> {
    match v {
        -1 => Ok(None),
        v if v >= 0 => Ok(Some(v as u32)),
        v => Err(Failure::new(
            ErrorKind::BadConfig.code(),
            format!("settings.{what} is {v}: a number, or -1 for none"),
        )),
    }
}

/// The host's hooks, called inside `mc_gcode_poll` and `mc_gcode_run` once the motion
/// before the operation has ended (the message hook does not wait). Each may be NULL: the
/// operation is then passed, except M100–M199, which are then an error
/// (`MC_ERR_UNSUPPORTED`). A hook returning non-zero stops the run with that code.
/// `direction`: 3 (M3, clockwise), 4 (M4) or 5 (M5, off). `pause`: 0 M0, 1 M1, 2 M60;
/// return 1 to pause, 0 to go on. `user` is the pointer given to `mc_gcode_set_hooks`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
#[allow(clippy::type_complexity)]
pub struct mc_gcode_hooks {
    /// M3/M4/M5 and S (rpm).
    pub spindle: Option<unsafe extern "C" fn(speed: f64, direction: u32, user: *mut c_void) -> i32>,
    /// M7/M8/M9: mist and flood on (1) or off (0).
    pub coolant: Option<unsafe extern "C" fn(mist: u32, flood: u32, user: *mut c_void) -> i32>,
    /// M6 with its T.
    pub tool_change: Option<unsafe extern "C" fn(tool: u32, user: *mut c_void) -> i32>,
    /// (MSG, ...): `text` is valid during the call.
    pub message: Option<unsafe extern "C" fn(line: u32, text: *const c_char, user: *mut c_void)>,
    /// M100-M199 with P and Q (`has_p`, `has_q`: 1 when given).
    pub hook: Option<
        unsafe extern "C" fn(
            code: u32,
            has_p: u32,
            p: f64,
            has_q: u32,
            q: f64,
            user: *mut c_void,
        ) -> i32,
    >,
    /// M0, M1, M60.
    pub pause: Option<unsafe extern "C" fn(kind: u32, user: *mut c_void) -> i32>,
}

/// The C hooks and their user pointer (kept as an integer: it is the application's, only
/// handed back).
#[derive(Default)]
struct CHooks {
    hooks: mc_gcode_hooks,
    user: usize,
}

// SAFETY: the function pointers and the user pointer are only called or handed back on the
// thread that calls `mc_gcode_poll` or `mc_gcode_run`; the application's contract.
unsafe impl Send for CHooks {}

fn hook_result(r: i32, what: &str) -> motioncard_sdk::Result<()> {
    if r == 0 {
        Ok(())
    } else {
        Err(Error::Unsupported(format!("the {what} hook returned {r}")))
    }
}

impl Hooks for CHooks {
    fn spindle(&mut self, speed: f64, dir: SpindleDir) -> motioncard_sdk::Result<()> {
        let Some(f) = self.hooks.spindle else {
            return Ok(());
        };
        let d = match dir {
            SpindleDir::Cw => 3,
            SpindleDir::Ccw => 4,
            SpindleDir::Off => 5,
        };
        // SAFETY: the application's function, called as its documentation says.
        hook_result(unsafe { f(speed, d, self.user as *mut c_void) }, "spindle")
    }

    fn coolant(&mut self, mist: bool, flood: bool) -> motioncard_sdk::Result<()> {
        let Some(f) = self.hooks.coolant else {
            return Ok(());
        };
        // SAFETY: as above.
        let r = unsafe { f(u32::from(mist), u32::from(flood), self.user as *mut c_void) };
        hook_result(r, "coolant")
    }

    fn tool_change(&mut self, tool: u32) -> motioncard_sdk::Result<()> {
        let Some(f) = self.hooks.tool_change else {
            return Ok(());
        };
        // SAFETY: as above.
        hook_result(unsafe { f(tool, self.user as *mut c_void) }, "tool change")
    }

    fn message(&mut self, line: usize, text: &str) {
        let Some(f) = self.hooks.message else {
            return;
        };
        let c = CString::new(text.replace('\0', " ")).unwrap_or_default();
        // SAFETY: as above; `c` outlives the call.
        unsafe { f(line as u32, c.as_ptr(), self.user as *mut c_void) }
    }

    fn hook(&mut self, code: u32, p: Option<f64>, q: Option<f64>) -> motioncard_sdk::Result<()> {
        let Some(f) = self.hooks.hook else {
            return Err(Error::Unsupported(format!("M{code}: no host hook for it")));
        };
        let (hp, pv) = (u32::from(p.is_some()), p.unwrap_or(0.0));
        let (hq, qv) = (u32::from(q.is_some()), q.unwrap_or(0.0));
        // SAFETY: as above.
        let r = unsafe { f(code, hp, pv, hq, qv, self.user as *mut c_void) };
        hook_result(r, &format!("M{code}"))
    }

    fn pause(&mut self, kind: PauseKind) -> bool {
        let Some(f) = self.hooks.pause else {
            return true;
        };
        let k = match kind {
            PauseKind::Program => 0,
            PauseKind::Optional => 1,
            PauseKind::Pallet => 2,
        };
        // SAFETY: as above.
        unsafe { f(k, self.user as *mut c_void) != 0 }
    }
}

/// A loaded program.
struct Job {
    runner: Runner<Box<dyn Source + Send>, CHooks>,
    /// The error that stopped the run: its line (0: none) and message.
    error: Option<(usize, String)>,
}

/// A slot of the table: its generation, and its program when one is loaded there.
type Slot = (u16, Option<Arc<Mutex<Job>>>);

/// The programs, by handle.
static JOBS: Mutex<Vec<Slot>> = Mutex::new(Vec::new());

fn bad_handle(h: mc_gcode) -> Failure {
    Failure::new(
        MC_ERR_BAD_HANDLE,
        format!("no G-code program with handle {h}"),
    )
}

fn job(h: mc_gcode) -> Result<Arc<Mutex<Job>>, Failure> {
    let slot = (h & 0xffff) as usize;
    let jobs = JOBS.lock().unwrap_or_else(|p| p.into_inner());
    match slot.checked_sub(1).and_then(|s| jobs.get(s)) {
        Some((generation, Some(j))) if *generation == (h >> 16) as u16 => Ok(j.clone()),
        _ => Err(bad_handle(h)),
    }
}

fn insert(j: Job) -> mc_gcode {
    let mut jobs = JOBS.lock().unwrap_or_else(|p| p.into_inner());
    let j = Some(Arc::new(Mutex::new(j)));
    let slot = match jobs.iter().position(|(_, x)| x.is_none()) {
        Some(s) => {
            jobs[s].1 = j;
            s
        }
        None => {
            jobs.push((1, j));
            jobs.len() - 1
        }
    };
    (u32::from(jobs[slot].0) << 16) | (slot as u32 + 1)
}

fn settings_of(s: &mc_gcode_settings) -> Result<(RunSettings, Options), Failure> {
    let bytes: Vec<u8> = s
        .axes
        .iter()
        .take_while(|&&c| c != 0)
        .map(|&c| c as u8)
        .collect();
    if bytes.len() == s.axes.len() {
        return Err(Failure::new(
            ErrorKind::BadConfig.code(),
            "settings.axes is not NUL-terminated",
        ));
    }
    let axes = String::from_utf8(bytes)
        .map_err(|_| Failure::new(ErrorKind::BadConfig.code(), "settings.axes is not text"))?;
    let run = RunSettings {
        axes,
        rapid_feed: s.rapid_feed,
        max_feed: s.max_feed,
        tolerance: s.tolerance,
        spline_tolerance: s.spline_tolerance,
        probe_input: match s.probe_input {
            -1 => None,
            i @ 0..=15 => Some(i as u32),
            i => {
                return Err(Failure::new(
                    ErrorKind::BadConfig.code(),
                    format!("settings.probe_input {i}: an input 0..15, or -1 for none"),
                ))
            }
        },
        spindle: optional(s.spindle_axis, "spindle_axis")?.map(|a| {
            SpindleSettings::new(
                a as usize,
                s.spindle_max_rpm,
                s.spindle_acceleration,
                s.spindle_jerk,
            )
        }),
        mist_output: optional(s.mist_output, "mist_output")?,
        flood_output: optional(s.flood_output, "flood_output")?,
        report: match s.report {
            0 | 1 => s.report == 1,
            r => {
                return Err(Failure::new(
                    ErrorKind::BadConfig.code(),
                    format!("settings.report is {r}: 1 to measure the run, 0 not to"),
                ))
            }
        },
        ..RunSettings::default()
    };
    let opts = Options {
        block_delete: s.block_delete != 0,
        optional_stop: s.optional_stop != 0,
        ..Options::default()
    };
    Ok((run, opts))
}

/// The defaults: axes "XYZ", rapids and feeds up to 100 mm/s, 0.01 mm corners and splines,
/// block delete and optional stop off, no probe input, no spindle or coolant outputs on
/// the card (-1), the run measured (`report` 1).
#[no_mangle]
pub unsafe extern "C" fn mc_gcode_default_settings(settings: *mut mc_gcode_settings) -> mc_result {
    guard(|| {
        let out = Out::new(settings, "settings")?;
        let d = RunSettings::default();
        let mut axes = [0 as c_char; 8];
        for (a, c) in axes.iter_mut().zip(d.axes.bytes()) {
            *a = c as c_char;
        }
        // SAFETY: checked non-NULL; valid by the caller's contract.
        unsafe {
            out.write(mc_gcode_settings {
                axes,
                rapid_feed: d.rapid_feed,
                max_feed: d.max_feed,
                tolerance: d.tolerance,
                spline_tolerance: d.spline_tolerance,
                block_delete: 0,
                optional_stop: 0,
                probe_input: -1,
                spindle_axis: -1,
                mist_output: -1,
                flood_output: -1,
                spindle_max_rpm: SPINDLE_DEFAULTS.0,
                spindle_acceleration: SPINDLE_DEFAULTS.1,
                spindle_jerk: SPINDLE_DEFAULTS.2,
                report: u32::from(d.report),
            })
        };
        Ok(())
    })
}

/// Loads a program from `source` (made by `open`, twice: once to check it whole, once to
/// run) for `group` of `card`, and writes its handle.
unsafe fn load(
    card: mc_card,
    group: u32,
    tool_table: *const c_char,
    settings: *const mc_gcode_settings,
    program: *mut mc_gcode,
    dir: Option<&std::path::Path>,
    open: impl Fn() -> Result<Box<dyn Source + Send>, Failure>,
) -> Result<(), Failure> {
    let out = Out::new(program, "program")?;
    let s = if settings.is_null() {
        let mut d = std::mem::MaybeUninit::<mc_gcode_settings>::uninit();
        // SAFETY: a valid place for the write.
        unsafe { mc_gcode_default_settings(d.as_mut_ptr()) };
        // SAFETY: written just above.
        unsafe { d.assume_init() }
    } else {
        // SAFETY: non-NULL, valid by the caller's contract; plain numbers and chars.
        unsafe { read_in(settings, "settings") }?
    };
    let (run, mut opts) = settings_of(&s)?;
    // (a file's subroutine files are looked for beside it)
    opts.subroutine_path.extend(dir.map(|d| d.to_path_buf()));
    if !tool_table.is_null() {
        // SAFETY: NUL-terminated by the caller's contract.
        let path = unsafe { uri(tool_table, "tool_table") }?;
        opts.tools = ToolTable::load(std::path::Path::new(path)).map_err(Error::from)?;
    }
    let (_, g) = group_of(card, group)?;
    opts.start = group_position(&g, &run.axes)?;
    // Checked whole first: nothing moves when a line is wrong.
    for op in Program::new(open()?, &opts) {
        op.map_err(Error::from)?;
    }
    let runner = Runner::new(&g, Program::new(open()?, &opts), run, CHooks::default())?;
    let h = insert(Job {
        runner,
        error: None,
    });
    // SAFETY: checked non-NULL; valid by the caller's contract.
    unsafe { out.write(h) };
    Ok(())
}

/// Load the program file `path` for `group` of `card` (enabled, its path configured with
/// `mc_group_configure_path`): it is read whole once and checked (`MC_ERR_GCODE` for the
/// first wrong line, `mc_last_error_message` giving `line N: what`; nothing is queued), then
/// `*program` is its handle. It starts where the group is. `tool_table` (may be NULL) is a
/// tool table file in LinuxCNC's format; `settings` may be NULL for the defaults. A call of
/// a subroutine the program does not define (`o<name> call`) runs `name.ngc` from the
/// program's directory.
#[no_mangle]
pub unsafe extern "C" fn mc_gcode_load_file(
    card: mc_card,
    group: u32,
    path: *const c_char,
    tool_table: *const c_char,
    settings: *const mc_gcode_settings,
    program: *mut mc_gcode,
) -> mc_result {
    guard(|| {
        // SAFETY: NUL-terminated by the caller's contract.
        let path = std::path::PathBuf::from(unsafe { uri(path, "path") }?);
        let open = || -> Result<Box<dyn Source + Send>, Failure> {
            let f = FileSource::open(&path).map_err(|source| Error::Io {
                context: path.display().to_string(),
                source,
            })?;
            Ok(Box::new(f))
        };
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => ".".into(),
        };
        // SAFETY: the caller's contract, passed on.
        unsafe { load(card, group, tool_table, settings, program, Some(&dir), open) }
    })
}

/// `mc_gcode_load_file` for a program in memory: `text`, NUL-terminated (copied).
#[no_mangle]
pub unsafe extern "C" fn mc_gcode_load_string(
    card: mc_card,
    group: u32,
    text: *const c_char,
    tool_table: *const c_char,
    settings: *const mc_gcode_settings,
    program: *mut mc_gcode,
) -> mc_result {
    guard(|| {
        // SAFETY: NUL-terminated by the caller's contract.
        let text = unsafe { uri(text, "text") }?.to_owned();
        let open = || -> Result<Box<dyn Source + Send>, Failure> {
            Ok(Box::new(TextSource::new(text.clone())))
        };
        // SAFETY: the caller's contract, passed on.
        unsafe { load(card, group, tool_table, settings, program, None, open) }
    })
}

/// Set the program's hooks (`hooks` copied; NULL clears them) and the `user` pointer they
/// get back.
#[no_mangle]
pub unsafe extern "C" fn mc_gcode_set_hooks(
    program: mc_gcode,
    hooks: *const mc_gcode_hooks,
    user: *mut c_void,
) -> mc_result {
    guard(|| {
        let h = if hooks.is_null() {
            mc_gcode_hooks::default()
        } else {
            // SAFETY: non-NULL, valid by the caller's contract; NULL or function pointers.
            unsafe { read_in(hooks, "hooks") }?
        };
        let j = job(program)?;
        let mut j = j.lock().unwrap_or_else(|p| p.into_inner());
        *j.runner.hooks_mut() = CHooks {
            hooks: h,
            user: user as usize,
        };
        Ok(())
    })
}

fn state_code(s: RunState) -> u32 {
    match s {
        RunState::Running => MC_GCODE_RUNNING,
        RunState::Draining => MC_GCODE_DRAINING,
        RunState::Paused => MC_GCODE_PAUSED,
        RunState::Done => MC_GCODE_DONE,
        RunState::Aborted => MC_GCODE_ABORTED,
    }
}

/// One poll of the job; an error is kept for `mc_gcode_error`.
fn poll(j: &mut Job) -> Result<RunState, Failure> {
    j.runner.poll().map_err(|e| {
        let line = match &e {
            Error::Gcode(g) => g.line,
            _ => j.runner.read_line(),
        };
        j.error = Some((line, e.to_string()));
        Failure::from(e)
    })
}

/// One step of the run, never blocking: program lines read and queued while the path has
/// room, a waiting operation done once the motion before it has ended (its hook called).
/// `*state` (may be NULL): `MC_GCODE_*`. An error (`MC_ERR_GCODE` for a wrong line, or the
/// card's or a hook's code) aborts the run; what was queued before it runs to its end.
#[no_mangle]
pub unsafe extern "C" fn mc_gcode_poll(program: mc_gcode, state: *mut u32) -> mc_result {
    guard(|| {
        let out = Out::optional(state);
        let j = job(program)?;
        let s = poll(&mut j.lock().unwrap_or_else(|p| p.into_inner()))?;
        if let Some(o) = out {
            // SAFETY: non-NULL; valid by the caller's contract.
            unsafe { o.write(state_code(s)) };
        }
        Ok(())
    })
}

/// Poll until the program is done, paused or aborted, at most `timeout_ms` (`MC_ERR_TIMEOUT`
/// after it, the run going on). A stepped in-process card is stepped here. Another thread
/// may call `mc_gcode_pause`, `mc_gcode_abort` or `mc_gcode_line` meanwhile.
#[no_mangle]
pub unsafe extern "C" fn mc_gcode_run(
    program: mc_gcode,
    timeout_ms: u32,
    state: *mut u32,
) -> mc_result {
    guard(|| {
        let out = Out::optional(state);
        let j = job(program)?;
        let deadline = Instant::now() + Duration::from_millis(u64::from(timeout_ms));
        loop {
            // The lock is held for one poll only.
            let s = poll(&mut j.lock().unwrap_or_else(|p| p.into_inner()))?;
            if matches!(s, RunState::Done | RunState::Paused | RunState::Aborted) {
                if let Some(o) = out {
                    // SAFETY: non-NULL; valid by the caller's contract.
                    unsafe { o.write(state_code(s)) };
                }
                return Ok(());
            }
            if Instant::now() >= deadline {
                return Err(Error::Timeout(Duration::from_millis(u64::from(timeout_ms))).into());
            }
            // (a tick of a stepped card, else half a millisecond: short enough to hold the
            // lock through)
            j.lock().unwrap_or_else(|p| p.into_inner()).runner.idle()?;
        }
    })
}

/// Pause at the end of a block: the card brings the path to rest at the end of the first block
/// it can stop at within its limits from where it is (the running block where it can; an exact
/// stop or a dwell's end always can), and `mc_gcode_run` then returns `MC_GCODE_PAUSED`. A block
/// followed by a blend pauses where the blend starts, within its tolerance of the block's end.
/// What is queued stays queued; `mc_gcode_resume` goes on along the same path.
#[no_mangle]
pub extern "C" fn mc_gcode_pause(program: mc_gcode) -> mc_result {
    guard(|| {
        job(program)?
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .runner
            .pause()
            .map_err(Into::into)
    })
}

/// Go on after a pause (M0/M1/M60 or `mc_gcode_pause`).
#[no_mangle]
pub extern "C" fn mc_gcode_resume(program: mc_gcode) -> mc_result {
    guard(|| {
        job(program)?
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .runner
            .resume()
            .map_err(Into::into)
    })
}

/// Abort: the path halts along its geometry within `deceleration` (mm/s²) and `jerk`
/// (mm/s³), nothing more is read; the state is `MC_GCODE_ABORTED`.
#[no_mangle]
pub extern "C" fn mc_gcode_abort(program: mc_gcode, deceleration: f64, jerk: f64) -> mc_result {
    guard(|| {
        let j = job(program)?;
        let mut j = j.lock().unwrap_or_else(|p| p.into_inner());
        Ok(j.runner.abort(deceleration, jerk)?)
    })
}

/// `*running` (may be NULL): the source line of the segment the card runs (0 when none);
/// `*read` (may be NULL): the last source line read.
#[no_mangle]
pub unsafe extern "C" fn mc_gcode_line(
    program: mc_gcode,
    running: *mut u32,
    read: *mut u32,
) -> mc_result {
    guard(|| {
        let (o_run, o_read) = (Out::optional(running), Out::optional(read));
        let j = job(program)?;
        let j = j.lock().unwrap_or_else(|p| p.into_inner());
        let r = j.runner.running_line()? as u32;
        let l = j.runner.read_line() as u32;
        // SAFETY: non-NULL; valid by the caller's contract.
        unsafe {
            if let Some(o) = o_run {
                o.write(r);
            }
            if let Some(o) = o_read {
                o.write(l);
            }
        }
        Ok(())
    })
}

/// What the run did so far (`mc_path_report`): during the run, or after it (done, paused or
/// aborted). `MC_ERR_UNSUPPORTED` when the program was loaded with `settings.report` 0, or
/// when the card moved before the program had a motion to measure it against.
#[no_mangle]
pub unsafe extern "C" fn mc_gcode_report(
    program: mc_gcode,
    report: *mut mc_path_report,
) -> mc_result {
    guard(|| {
        let out = Out::new(report, "report")?;
        let j = job(program)?;
        let j = j.lock().unwrap_or_else(|p| p.into_inner());
        let r = j
            .runner
            .report()
            .ok_or_else(|| {
                Error::Unsupported("the program was loaded with settings.report 0".into())
            })?
            .map_err(|e| Error::Unsupported(format!("the run's report: {e}")))?;
        // SAFETY: checked non-NULL; valid by the caller's contract.
        unsafe {
            out.write(mc_path_report {
                path_time: r.path_time,
                segments: r.segments as u64,
                peak_velocity_ratio: r.peak_vel_ratio,
                peak_acceleration_ratio: r.peak_accel_ratio,
                peak_jerk_ratio: r.peak_jerk_ratio,
                max_deviation: r.max_deviation,
                max_contour_error: r.max_contour_error,
                max_following_error: r.max_following_error,
                exact_stops: r.exact_stops as u64,
                ticks: r.ticks,
                ticks_seen: r.ticks_seen,
            })
        };
        Ok(())
    })
}

/// The error that stopped the run: `*line` its source line (0: no error, or none to name)
/// and its message into `buf` (the string conventions; "" when none).
#[no_mangle]
pub unsafe extern "C" fn mc_gcode_error(
    program: mc_gcode,
    line: *mut u32,
    buf: *mut c_char,
    len: usize,
    needed: *mut usize,
) -> mc_result {
    guard(|| {
        let o_line = Out::new(line, "line")?;
        let text = StrBuf::new(buf, len, needed)?;
        let j = job(program)?;
        let (l, m) = j
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .error
            .clone()
            .unwrap_or_default();
        // SAFETY: checked; valid by the caller's contract.
        unsafe {
            text.fill(&m)?;
            o_line.write(l as u32);
        }
        Ok(())
    })
}

/// Close the program: its handle is no longer valid. Motion already queued on the card runs
/// on (`mc_gcode_abort` first to stop it).
#[no_mangle]
pub extern "C" fn mc_gcode_close(program: mc_gcode) -> mc_result {
    guard(|| {
        let mut jobs = JOBS.lock().unwrap_or_else(|p| p.into_inner());
        let slot = ((program & 0xffff) as usize)
            .checked_sub(1)
            .filter(|&s| s < jobs.len())
            .ok_or_else(|| bad_handle(program))?;
        let (generation, j) = &mut jobs[slot];
        if *generation != (program >> 16) as u16 || j.is_none() {
            return Err(bad_handle(program));
        }
        *j = None;
        *generation = generation.wrapping_add(1).max(1);
        Ok(())
    })
}

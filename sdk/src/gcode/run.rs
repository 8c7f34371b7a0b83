//! A program on a card: its operations ([`Op`]) turned into path items and streamed into a
//! group's path buffer as it frees room; what the path cannot carry (spindle, coolant, tool
//! changes, pauses, hooks, waits on inputs) waits for the motion before it to end and goes to
//! the host's [`Hooks`]. A spindle on a card axis, coolant outputs and G33/G33.1 on the
//! card's camming are [`super::spindle`]'s (with [`RunSettings::spindle`]).
//!
//! The group's axes are the program's, in the order [`RunSettings::axes`] names them, in mm
//! and degrees (the axes' scales make them so). The runner is polled ([`Runner::poll`]: it
//! never blocks) or run to the end ([`Runner::run`]); on a stepped in-process card `run`
//! steps the card itself.

use super::probe::ProbeRun;
pub use super::spindle::SpindleSettings;
use super::spindle::SpindleUnit;
use super::{Blend, GcodeError, Op, OpKind, PauseKind, Plane, Pos, Program, Source, SpindleDir};
use crate::report::{blocks_of, AxisLimits, Block, PathReport, Report, ReportError};
use crate::{
    ArcSpec, Error, Geometry, Group, GroupState, Nurbs, PathBuffer, PathItem, PauseState, Result,
    Segment, Transition,
};
use std::time::{Duration, Instant};

/// How a program runs on a group.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSettings {
    /// The program's axis letter of each group axis, in group order (`"XYZ"`, `"XYZA"`, …).
    /// Arcs in a plane of two axes need X, Y and Z as the group's first three axes; arcs
    /// about a normal ([`OpKind::ArcNormal`]) need X, Y and Z in the group, with one scale.
    pub axes: String,
    /// The speed of rapids (G0), mm/s.
    pub rapid_feed: f64,
    /// The largest feed, mm/s: a faster programmed feed runs at this.
    pub max_feed: f64,
    /// The corner tolerance of G64 without P, mm.
    pub tolerance: f64,
    /// How closely splines (G5) are followed, mm.
    pub spline_tolerance: f64,
    /// Items held before a batch is sent (then as many more as the path has room for): the
    /// chord fitter fits within a batch.
    pub batch: usize,
    /// The card's digital input the touch probe of G38.2–G38.5 is wired to (none: G38 is an
    /// error). See [`super::probe`](self) for how the move runs.
    pub probe_input: Option<u32>,
    /// The spindle on a card axis (M3/M4/M5, S, G33, G33.1); `None`: the spindle is the
    /// host's ([`Hooks::spindle`] only) and G33/G33.1 are refused.
    pub spindle: Option<SpindleSettings>,
    /// The card output M7 turns on (M9 off), if any.
    pub mist_output: Option<u32>,
    /// The card output M8 turns on (M9 off), if any.
    pub flood_output: Option<u32>,
    /// Measure the run as it goes ([`Runner::report`]): each tick the runner sees, the X, Y
    /// and Z axes' commanded and actual positions against the programmed path.
    pub report: bool,
}

impl Default for RunSettings {
    /// X, Y, Z; rapids and feeds up to 100 mm/s; 0.01 mm corners and splines; batches of 512;
    /// no spindle or coolant on the card.
    fn default() -> Self {
        Self {
            axes: "XYZ".into(),
            rapid_feed: 100.0,
            max_feed: 100.0,
            tolerance: 0.01,
            spline_tolerance: 0.01,
            batch: 512,
            probe_input: None,
            spindle: None,
            mist_output: None,
            flood_output: None,
            report: true,
        }
    }
}

/// What the host does for the operations the card's path does not carry. Each is called
/// once the motion before it has ended (M64/M65 and messages do not wait). The defaults do
/// nothing, refuse what needs hardware they cannot know (M100–M199), and make M0/M60 (and
/// M1 with the optional stop on) pause the runner until [`Runner::resume`].
pub trait Hooks {
    /// Every operation as it is read, before it is queued (a report, a preview).
    fn op(&mut self, _op: &Op) {}
    /// M3/M4/M5, S (rpm as programmed; with [`RunSettings::spindle`], called before the card's
    /// spindle is set).
    fn spindle(&mut self, _speed: f64, _dir: SpindleDir) -> Result<()> {
        Ok(())
    }
    /// M7/M8/M9 (with [`RunSettings::mist_output`] or `flood_output`, called before the
    /// outputs are set).
    fn coolant(&mut self, _mist: bool, _flood: bool) -> Result<()> {
        Ok(())
    }
    /// M6.
    fn tool_change(&mut self, _tool: u32) -> Result<()> {
        Ok(())
    }
    /// `(MSG, …)`.
    fn message(&mut self, _line: usize, _text: &str) {}
    /// M100–M199.
    fn hook(&mut self, code: u32, _p: Option<f64>, _q: Option<f64>) -> Result<()> {
        Err(Error::Unsupported(format!("M{code}: no host hook for it")))
    }
    /// M0, M1, M60: `true` pauses the runner (the default).
    fn pause(&mut self, _kind: PauseKind) -> bool {
        true
    }
}

/// Hooks that do nothing but pause at M0/M1/M60.
#[derive(Debug, Default, Clone, Copy)]
pub struct NoHooks;

impl Hooks for NoHooks {}

/// Where a run is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunState {
    /// Items are being queued or run.
    Running,
    /// Waiting for the motion queued so far to end (before a spindle, tool or pause
    /// operation, or at the end), or for the card's spindle (to reach its speed, or a
    /// G33/G33.1 pass to end).
    Draining,
    /// Paused: M0/M1/M60 with the motion before it ended, or [`Runner::pause`] at rest at the
    /// end of a block (more may be queued on the card). [`Runner::resume`] goes on.
    Paused,
    /// The program ended and every motion of it is done.
    Done,
    /// Aborted: the path halted along its geometry, nothing more is read.
    Aborted,
}

/// A program running on a group.
pub struct Runner<S: Source, H: Hooks = NoHooks> {
    program: Program<S>,
    group: Group,
    settings: RunSettings,
    hooks: H,
    /// Group axis of each program axis (X..C), if the group has it.
    axis_of: [Option<usize>; 6],
    /// Items made and not yet sent.
    batch: Vec<PathItem>,
    /// The size the batch is filled to (the path's room when it reached `settings.batch`;
    /// 0: not decided).
    fill_to: usize,
    /// The last segment made, held back so that the last of the program can be marked.
    held: Option<Segment>,
    /// An operation that waits for the motion before it to end.
    waiting: Option<Op>,
    /// A probing move under way: nothing is read until it ends.
    probing: Option<ProbeRun>,
    state: RunState,
    /// [`Runner::pause`] asked the card to pause.
    pausing: bool,
    read_all: bool,
    /// The reader stops before this source line until the limit moves.
    read_limit: Option<usize>,
    ops: u64,
    error_line: usize,
    /// The spindle and coolant on the card.
    spindle: SpindleUnit,
    /// The run's report, with [`RunSettings::report`].
    monitor: Option<Monitor>,
}

/// Program lines a reporting run reads ahead of the line the card runs (more than the chord
/// fitter holds before it sends a curve: a straight run of 16 chunks of 1024 points), so
/// that the programmed path the report holds stays bounded whatever the fitter makes of the
/// lines.
const AHEAD_LINES: usize = 32 * 1024;

/// A run's report as it goes ([`Report`]) and where it samples the card.
struct Monitor {
    report: Report,
    /// The card axes of X, Y and Z (a program axis the group lacks is 0).
    axes: [Option<usize>; 3],
    /// The card's tick of the last sample.
    tick: Option<u64>,
    /// The source line the card runs (0: none yet).
    running: usize,
    blocks: Vec<Block>,
    error: Option<ReportError>,
}

impl Monitor {
    /// The report of a run on `group`: the servo period and the path's per-axis limits
    /// (mm/s, mm/s², mm/s³; one the card leaves unlimited counts as infinite), a tick at
    /// rest when its point moves less than a thousandth of a count.
    fn new(group: &Group, axis_of: &[Option<usize>; 6]) -> Result<Monitor> {
        let card = group.card_pub();
        let (_, ids) = group.axes_pub()?;
        let path = group.path_config()?;
        let ts = 1.0 / f64::from(card.info().servo_rate_hz.max(1));
        let axes = [0, 1, 2].map(|i| axis_of[i].map(|g| ids[g]));
        let mut limits = [AxisLimits {
            vmax: f64::INFINITY,
            amax: f64::INFINITY,
            jmax: f64::INFINITY,
        }; 3];
        let mut finest = f64::INFINITY;
        for i in 0..3 {
            let (Some(g), Some(a)) = (axis_of[i], axes[i]) else {
                continue;
            };
            let s = card.scale(a).abs();
            finest = finest.min(1.0 / s);
            let unit = |v: f64| if v > 0.0 { v / s } else { f64::INFINITY };
            limits[i] = AxisLimits {
                vmax: unit(path.vmax[g]),
                amax: unit(path.amax[g]),
                jmax: unit(path.jmax[g]),
            };
        }
        let rest = if finest.is_finite() {
            1e-3 * finest / ts
        } else {
            0.0
        };
        let report = Report::new(ts, &limits, rest)
            .map_err(|e| Error::BadConfig(format!("the run's report: {e}")))?;
        Ok(Monitor {
            report,
            axes,
            tick: None,
            running: 0,
            blocks: Vec::new(),
            error: None,
        })
    }

    /// The blocks of an operation read, added to the programmed path.
    fn add(&mut self, op: &Op) {
        self.blocks.clear();
        blocks_of(op, &mut self.blocks);
        for b in &self.blocks {
            self.report.add_block(b);
        }
    }
}

impl<S: Source, H: Hooks> Runner<S, H> {
    /// `program` on `group` (enabled, its path configured), with `hooks`. The group's axes are
    /// checked against `settings.axes`.
    pub fn new(
        group: &Group,
        program: Program<S>,
        settings: RunSettings,
        hooks: H,
    ) -> Result<Self> {
        let n = group.axes()?.0;
        let letters: Vec<char> = settings
            .axes
            .chars()
            .map(|c| c.to_ascii_uppercase())
            .collect();
        if letters.len() != n {
            return Err(Error::BadConfig(format!(
                "the group has {n} axes, the run names {} ('{}')",
                letters.len(),
                settings.axes
            )));
        }
        let mut axis_of = [None; 6];
        for (g, l) in letters.iter().enumerate() {
            let i = super::AXIS_LETTERS
                .iter()
                .position(|a| a == l)
                .ok_or_else(|| Error::BadConfig(format!("'{l}' is not an axis of G-code")))?;
            if axis_of[i].replace(g).is_some() {
                return Err(Error::BadConfig(format!("axis '{l}' named twice")));
            }
        }
        for (what, v) in [
            ("rapid feed", settings.rapid_feed),
            ("largest feed", settings.max_feed),
            ("spline tolerance", settings.spline_tolerance),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::BadConfig(format!(
                    "the {what} must be above 0, not {v}"
                )));
            }
        }
        if !(settings.tolerance.is_finite() && settings.tolerance >= 0.0) {
            return Err(Error::BadConfig(format!(
                "the tolerance must be 0 or more, not {}",
                settings.tolerance
            )));
        }
        let spindle = SpindleUnit::new(
            group,
            settings.spindle.clone(),
            settings.mist_output,
            settings.flood_output,
        )?;
        let monitor = if settings.report {
            Some(Monitor::new(group, &axis_of)?)
        } else {
            None
        };
        Ok(Runner {
            monitor,
            spindle,
            program,
            group: group.clone(),
            batch: Vec::with_capacity(settings.batch.max(1)),
            fill_to: 0,
            settings,
            hooks,
            axis_of,
            held: None,
            waiting: None,
            probing: None,
            state: RunState::Running,
            pausing: false,
            read_all: false,
            read_limit: None,
            ops: 0,
            error_line: 0,
        })
    }

    /// One step of the run, never blocking: items queued while the path has room, an
    /// operation that waits done once the motion before it has ended. The state after it.
    pub fn poll(&mut self) -> Result<RunState> {
        match self.state {
            RunState::Done | RunState::Aborted | RunState::Paused => return Ok(self.state),
            RunState::Running | RunState::Draining => {}
        }
        self.sample()?;
        let r = self.advance();
        if r.is_err() {
            // Nothing more is queued after an error; what is queued runs to its end.
            self.state = RunState::Aborted;
        }
        let s = r?;
        if !self.pausing {
            return Ok(s);
        }
        if s != RunState::Running && s != RunState::Draining {
            // (the pause point was the program's end, or an M0's stop came first)
            self.pausing = false;
            self.group.path_resume()?;
            return Ok(s);
        }
        if matches!(self.group.path_pause_state()?, PauseState::Paused { .. }) {
            return Ok(self.set(RunState::Paused));
        }
        Ok(s)
    }

    fn advance(&mut self) -> Result<RunState> {
        loop {
            if self.probing.is_some() {
                if !self.motion_done()? {
                    return Ok(self.set(RunState::Running));
                }
                if let Some(p) = self.probing.take() {
                    let stopped = group_position(&self.group, &self.settings.axes)?;
                    let r = p.finish(&self.group, stopped)?;
                    self.program.probe_result(r.at, r.stopped, r.tripped);
                }
            }
            // The spindle's work (a speed to reach, a thread off the group) ends before
            // anything more is read or sent.
            if !self.spindle.poll(&self.group)? {
                return Ok(self.set(RunState::Draining));
            }
            if self.waiting.is_some() || self.read_all {
                // Everything before it must be sent and done.
                if !self.flush(true)? {
                    return Ok(self.set(RunState::Running));
                }
                if !self.motion_done()? {
                    return Ok(self.set(RunState::Draining));
                }
                if let Some(op) = self.waiting.take() {
                    if self.sync_op(&op)? {
                        return Ok(self.set(RunState::Paused));
                    }
                    continue;
                }
                return Ok(self.set(RunState::Done));
            }
            // A batch is at least `settings.batch` items and as many more as the path has
            // room for when it reaches that: the fitter's runs are cut only where batches
            // meet.
            if self.batch.len() >= self.settings.batch.max(1) {
                if self.fill_to == 0 {
                    self.fill_to = self.group.path_free()?;
                }
                if self.batch.len() >= self.fill_to {
                    if !self.flush(false)? {
                        self.fill_to = 0;
                        return Ok(self.set(RunState::Running));
                    }
                    continue;
                }
            }
            // (the next line read is at least the one after the last)
            let report_limit = self.monitor.as_ref().map(|m| m.running + AHEAD_LINES);
            let limit = match (self.read_limit, report_limit) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
            if limit.is_some_and(|l| self.program.line() + 1 >= l) {
                // Held at the limit: what is made goes as soon as it fits.
                self.flush(false)?;
                return Ok(self.set(RunState::Running));
            }
            match self.program.next_op() {
                None => self.read_all = true,
                Some(Err(e)) => {
                    self.error_line = e.line;
                    // What came before the error runs (waiting for room if it must);
                    // nothing after it.
                    if let Some(s) = self.held.take() {
                        self.batch.push(s.last().into());
                    }
                    let items: Vec<PathItem> = self.batch.drain(..).collect();
                    self.group.stream_path(items, |_| {}).map_err(|e| e.error)?;
                    return Err(e.into());
                }
                Some(Ok(op)) => {
                    self.ops += 1;
                    self.hooks.op(&op);
                    if let Some(m) = &mut self.monitor {
                        m.add(&op);
                    }
                    self.take(op)?;
                }
            }
        }
    }

    fn set(&mut self, s: RunState) -> RunState {
        self.state = s;
        s
    }

    /// Whether the group has run everything queued.
    fn motion_done(&self) -> Result<bool> {
        let (state, st) = self.group.status()?;
        Ok(state == GroupState::Standby && st.path_queued == 0)
    }

    /// Sends the batch (`last`: the held segment too, marked the last of its stretch) when
    /// the path has room for all of it: `false` when it must wait (a send never blocks).
    fn flush(&mut self, last: bool) -> Result<bool> {
        let n = self.batch.len() + usize::from(last && self.held.is_some());
        if n == 0 {
            return Ok(true);
        }
        if self.group.path_free()? < n {
            return Ok(false);
        }
        if last {
            if let Some(s) = self.held.take() {
                self.batch.push(s.last().into());
            }
        }
        self.fill_to = 0;
        let items: Vec<PathItem> = self.batch.drain(..).collect();
        self.group.stream_path(items, |_| {}).map_err(|e| e.error)?;
        Ok(true)
    }

    /// An operation read: an item for the path, or one that waits for the motion.
    fn take(&mut self, op: Op) -> Result<()> {
        let err = |m: String| Error::Gcode(GcodeError::new(op.line, m));
        match &op.kind {
            OpKind::Message { text } => self.hooks.message(op.line, text),
            OpKind::Output {
                index,
                on,
                synced: true,
            } => self.batch.push(PathItem::Output {
                output: u8::try_from(*index).map_err(|_| err(format!("no output {index}")))?,
                on: *on,
                at: crate::OutputAt::Start,
            }),
            OpKind::Output {
                index,
                on,
                synced: false,
            } => {
                let bit = 1u32
                    .checked_shl(*index)
                    .ok_or_else(|| err(format!("no output {index}")))?;
                self.group
                    .card_pub()
                    .set_outputs(bit, if *on { bit } else { 0 })?;
            }
            OpKind::AnalogOutput { .. } => {
                return Err(err("M67/M68: this card has no analog outputs".into()))
            }
            OpKind::SpindleSync { tap, .. } if !self.spindle.configured() => {
                return Err(err(format!(
                    "{}: no spindle is configured on the card",
                    if *tap { "G33.1" } else { "G33" }
                )))
            }
            // The override switches are the operator's (the card's override is set by the
            // host): nothing to do, and no reason to stop the motion.
            OpKind::Overrides { .. } => {}
            OpKind::WaitInput { .. }
            | OpKind::Probe { .. }
            | OpKind::Spindle { .. }
            | OpKind::SpindleOrient { .. }
            | OpKind::SpindleSync { .. }
            | OpKind::Coolant { .. }
            | OpKind::ToolChange { .. }
            | OpKind::Pause { .. }
            | OpKind::Hook { .. }
            | OpKind::End { .. } => self.waiting = Some(op.clone()),
            _ => {
                for seg in self.segments(&op)? {
                    if let Some(prev) = self.held.replace(seg) {
                        self.batch.push(prev.into());
                    }
                }
            }
        }
        Ok(())
    }

    /// An operation that waited for the motion before it: `true` pauses the run.
    fn sync_op(&mut self, op: &Op) -> Result<bool> {
        match op.kind {
            OpKind::Spindle { speed, dir } => {
                self.hooks.spindle(speed, dir)?;
                if let Some(m) = self.spindle.set(&self.group, op.line, speed, dir)? {
                    self.hooks.message(op.line, &m);
                }
            }
            OpKind::SpindleOrient { angle, dir } => {
                self.spindle.orient(&self.group, op.line, angle, dir)?;
            }
            OpKind::Coolant { mist, flood } => {
                self.hooks.coolant(mist, flood)?;
                self.spindle.coolant(&self.group, mist, flood)?;
            }
            OpKind::SpindleSync {
                start,
                end,
                pitch,
                tap,
            } => {
                let (s, e) = (self.target(&start, op.line)?, self.target(&end, op.line)?);
                self.spindle
                    .start_thread(&self.group, op.line, (&s, &e), pitch, tap)?;
            }
            OpKind::ToolChange { tool } => self.hooks.tool_change(tool)?,
            OpKind::Hook { code, p, q } => self.hooks.hook(code, p, q)?,
            OpKind::Pause { kind } => return Ok(self.hooks.pause(kind)),
            OpKind::WaitInput {
                index,
                analog,
                mode,
                timeout,
            } => {
                let v = self.wait_input(op.line, index, analog, mode, timeout)?;
                self.program.input_result(v);
            }
            OpKind::Probe {
                start,
                end,
                feed,
                toward,
                ..
            } => {
                self.probing = Some(ProbeRun::start(
                    &self.group,
                    &self.axis_of,
                    self.target(&end, op.line)?,
                    (op.line, start, end),
                    feed.min(self.settings.max_feed),
                    toward,
                    self.settings.probe_input,
                )?);
            }
            // End: nothing after it is read.
            _ => {}
        }
        Ok(false)
    }

    /// M66 on a digital input: mode 0 reads at once, 1/2 wait for a rising/falling edge, 3/4
    /// for high/low; the input's value, or −1 after `timeout` seconds.
    fn wait_input(
        &self,
        line: usize,
        index: u32,
        analog: bool,
        mode: u8,
        timeout: f64,
    ) -> Result<f64> {
        if analog || index >= 32 {
            return Err(Error::Gcode(GcodeError::new(
                line,
                format!(
                    "M66: no {} input {index}",
                    if analog { "analog" } else { "digital" }
                ),
            )));
        }
        let card = self.group.card_pub();
        let read = || -> Result<bool> { Ok(card.inputs()? >> index & 1 == 1) };
        let first = read()?;
        if mode == 0 {
            return Ok(f64::from(u8::from(first)));
        }
        let deadline = Instant::now() + Duration::from_secs_f64(timeout.clamp(0.0, 1e6));
        let mut prev = first;
        loop {
            let now = read()?;
            let met = match mode {
                1 => now && !prev,
                2 => !now && prev,
                3 => now,
                _ => !now,
            };
            if met {
                return Ok(f64::from(u8::from(now)));
            }
            prev = now;
            if Instant::now() >= deadline {
                return Ok(-1.0);
            }
            let_card_run(card, Duration::from_micros(200));
        }
    }

    /// The group axes' values of a program position.
    fn target(&self, p: &Pos, line: usize) -> Result<Vec<f64>> {
        let n = self.settings.axes.len();
        let mut t = vec![0.0; n];
        for (i, g) in self.axis_of.iter().enumerate() {
            match g {
                Some(g) => t[*g] = p[i],
                None if p[i] != 0.0 => {
                    return Err(Error::Gcode(GcodeError::new(
                        line,
                        format!(
                            "the program moves {}, which the group does not have",
                            super::AXIS_LETTERS[i]
                        ),
                    )))
                }
                None => {}
            }
        }
        Ok(t)
    }

    /// How a motion joins the one before it.
    fn join(&self, blend: Blend) -> (PathBuffer, Transition) {
        match blend {
            Blend::ExactStop => (PathBuffer::Buffered, Transition::None),
            // Exact path: no rounding; a corner stops, a tangent join keeps the speed (a
            // deviation of a nanometre is no rounding a machine can show).
            Blend::ExactPath => (PathBuffer::BlendingLow, Transition::MaxDeviation(1e-6)),
            Blend::Blended { tolerance, .. } => (
                PathBuffer::BlendingLow,
                Transition::MaxDeviation(tolerance.unwrap_or(self.settings.tolerance)),
            ),
        }
    }

    /// The segments of a motion (an arc with extra turns is one segment a turn).
    fn segments(&self, op: &Op) -> Result<Vec<Segment>> {
        let id = u32::try_from(op.line).unwrap_or(u32::MAX);
        let feed = |f: f64| f.min(self.settings.max_feed);
        let with = |s: Segment, blend: Blend| {
            let (b, t) = self.join(blend);
            let s = s.buffer(b).transition(t);
            // G64 Q: the chord fitter's own tolerance (none: P's, as LinuxCNC's default)
            match blend {
                Blend::Blended { naive: Some(q), .. } => s.fit_within(q),
                _ => s,
            }
        };
        if op.kind.is_null_motion() {
            return Ok(Vec::new());
        }
        let segs = match &op.kind {
            OpKind::Rapid { end, blend, .. } => {
                vec![with(
                    Segment::line(
                        id,
                        &self.target(end, op.line)?,
                        self.settings.rapid_feed,
                        0.0,
                    ),
                    *blend,
                )]
            }
            OpKind::Feed {
                end,
                feed: f,
                blend,
                ..
            } => {
                vec![with(
                    Segment::line(id, &self.target(end, op.line)?, feed(*f), 0.0),
                    *blend,
                )]
            }
            OpKind::Dwell { seconds } => vec![Segment::dwell(id, *seconds)],
            OpKind::Arc {
                start,
                end,
                centre,
                plane,
                ccw,
                turns,
                feed: f,
                blend,
            } => {
                let mut out = Vec::new();
                let total = op.kind.arc_sweep().unwrap_or(std::f64::consts::TAU);
                let (a, b, _) = plane.axes();
                // Full turns first, each ending where the arc started, the other axes moved
                // by their share of the whole sweep; then the arc to its end.
                let mut turn_end = *start;
                for k in 1..=*turns {
                    let share = f64::from(k) * std::f64::consts::TAU / total;
                    for i in 0..6 {
                        if i != a && i != b {
                            turn_end[i] = start[i] + share * (end[i] - start[i]);
                        }
                    }
                    out.push(self.arc_segment(
                        id,
                        &turn_end,
                        centre,
                        *plane,
                        *ccw,
                        feed(*f),
                        op.line,
                    )?);
                }
                out.push(self.arc_segment(id, end, centre, *plane, *ccw, feed(*f), op.line)?);
                out.into_iter().map(|s| with(s, *blend)).collect()
            }
            OpKind::ArcNormal {
                start,
                end,
                centre,
                normal,
                ccw,
                turns,
                feed: f,
                blend,
            } => {
                let axes = self.normal_arc_axes(op.line)?;
                let total = op.kind.arc_sweep().unwrap_or(std::f64::consts::TAU);
                let m = normal.iter().map(|x| x * x).sum::<f64>().sqrt();
                let n = normal.map(|x| x / m);
                let rise: f64 = (0..3).map(|i| (end[i] - start[i]) * n[i]).sum();
                // counter-clockwise about the normal sent (the right-hand rule)
                let sent = if *ccw { n } else { n.map(|x| -x) };
                // Full turns first, each ending above where the arc started by its share of
                // the rise (its centre too: in the plane through the turn's start), A, B, C by
                // their share; then the arc to its end.
                let at = |share: f64| -> (Pos, [f64; 3]) {
                    let p = std::array::from_fn(|i| {
                        if i < 3 {
                            start[i] + share * rise * n[i]
                        } else {
                            start[i] + share * (end[i] - start[i])
                        }
                    });
                    let c = std::array::from_fn(|i| centre[i] + share * rise * n[i]);
                    (p, c)
                };
                let mut out = Vec::new();
                for k in 1..=*turns {
                    let (_, c) = at(f64::from(k - 1) * std::f64::consts::TAU / total);
                    let (p, _) = at(f64::from(k) * std::f64::consts::TAU / total);
                    out.push(self.normal_arc_segment(id, axes, &p, c, sent, feed(*f), op.line)?);
                }
                let (_, c) = at(f64::from(*turns) * std::f64::consts::TAU / total);
                out.push(self.normal_arc_segment(id, axes, end, c, sent, feed(*f), op.line)?);
                out.into_iter().map(|s| with(s, *blend)).collect()
            }
            OpKind::Spline {
                spline,
                feed: f,
                blend,
                ..
            } => {
                let dim = self.settings.axes.len();
                let mut ctrl = Vec::with_capacity(spline.points.len() * dim);
                for p in &spline.points {
                    ctrl.extend(self.target(p, op.line)?);
                }
                let curve = Nurbs::new(spline.degree, dim, &ctrl, &spline.weights, &spline.knots)
                    .map_err(|e| {
                    Error::Gcode(GcodeError::new(op.line, format!("the spline: {e:?}")))
                })?;
                vec![with(
                    Segment::nurbs(id, curve, feed(*f), 0.0, self.settings.spline_tolerance),
                    *blend,
                )]
            }
            _ => Vec::new(),
        };
        Ok(segs)
    }

    #[allow(clippy::too_many_arguments)]
    fn arc_segment(
        &self,
        id: u32,
        end: &Pos,
        centre: &[f64; 3],
        plane: Plane,
        ccw: bool,
        feed: f64,
        line: usize,
    ) -> Result<Segment> {
        let (a, b, _) = plane.axes();
        if self.axis_of[..3] != [Some(0), Some(1), Some(2)] {
            return Err(Error::Gcode(GcodeError::new(
                line,
                "arcs need X, Y and Z as the group's first three axes",
            )));
        }
        let target = self.target(end, line)?;
        let helix: Vec<f64> = (0..target.len())
            .filter(|&g| g != a && g != b)
            .map(|g| target[g])
            .collect();
        let plane = match plane {
            Plane::Xy => crate::Plane::XY,
            Plane::Yz => crate::Plane::YZ,
            Plane::Zx => crate::Plane::ZX,
        };
        let arc = ArcSpec::Centre {
            end: [end[a], end[b]],
            centre: [centre[a], centre[b]],
            ccw,
        };
        Ok(Segment::arc(id, arc, plane, &helix, feed, 0.0))
    }

    /// The group axes of X, Y and Z for an arc in a plane given by its normal, checked: the
    /// group has the three, one scale on them (a circle in mm is one in counts), and the card
    /// runs such arcs (layout 1.12).
    fn normal_arc_axes(&self, line: usize) -> Result<[usize; 3]> {
        let refuse = |m: String| Err(Error::Gcode(GcodeError::new(line, m)));
        let [Some(x), Some(y), Some(z)] = [self.axis_of[0], self.axis_of[1], self.axis_of[2]]
        else {
            return refuse(
                "an arc outside the planes of two machine axes needs X, Y and Z in the group"
                    .into(),
            );
        };
        let card = self.group.card_pub();
        let layout = card.info().layout;
        if layout.1 < 12 {
            return refuse(format!(
                "an arc outside the planes of two machine axes (G18/G19 in a rotated coordinate \
                 system) needs a card of layout 1.12 (this one has 1.{})",
                layout.1
            ));
        }
        let (_, ids) = self.group.axes()?;
        let s = [x, y, z].map(|g| card.scale(ids[g]));
        if s[1] != s[0] || s[2] != s[0] {
            return refuse(format!(
                "an arc outside the planes of two machine axes needs one scale on X, Y and Z \
                 (they have {}, {}, {})",
                s[0], s[1], s[2]
            ));
        }
        Ok([x, y, z])
    }

    /// A normal-vector arc's segment to `end` about `centre` (X, Y, Z, in the plane through
    /// where the segment starts), counter-clockwise about `normal`; the end's height above
    /// that plane is a rise, the other group axes move to their targets.
    #[allow(clippy::too_many_arguments)]
    fn normal_arc_segment(
        &self,
        id: u32,
        axes: [usize; 3],
        end: &Pos,
        centre: [f64; 3],
        normal: [f64; 3],
        feed: f64,
        line: usize,
    ) -> Result<Segment> {
        let target = self.target(end, line)?;
        let helix: Vec<f64> = (0..target.len())
            .filter(|g| !axes.contains(g))
            .map(|g| target[g])
            .collect();
        let end = [end[0], end[1], end[2]];
        let mut s = Segment::arc_normal(id, axes, normal, centre, end, feed, 0.0);
        // (the end's height is the interpreter's: a helix's rise, or a rounding)
        s.geometry = Geometry::ArcNormal {
            axes,
            normal,
            centre,
            end,
            rise: true,
            helix,
        };
        Ok(s)
    }

    /// Pauses at the end of a block: the card brings the path to rest at the end of the first
    /// block it can stop at within its limits from where it is (the block running if it can,
    /// and it can where an exact stop or a dwell ends it; see [`Group::path_pause`]), and
    /// the state is [`RunState::Paused`] once it is there. What is queued stays queued, and
    /// [`resume`](Self::resume) goes on along the same path. A block followed by a blend
    /// pauses where the blend starts, within its tolerance of the block's end.
    pub fn pause(&mut self) -> Result<()> {
        if matches!(self.state, RunState::Running | RunState::Draining) && !self.pausing {
            self.group.path_pause()?;
            self.pausing = true;
        }
        Ok(())
    }

    /// Goes on after a pause (M0/M1/M60 or [`pause`](Self::pause)).
    pub fn resume(&mut self) -> Result<()> {
        if self.pausing {
            self.group.path_resume()?;
            self.pausing = false;
        }
        if self.state == RunState::Paused {
            self.state = RunState::Running;
        }
        Ok(())
    }

    /// Halts the path along its geometry (within `deceleration` and `jerk`, mm/s² and
    /// mm/s³) and ends the run: nothing more is read.
    pub fn abort(&mut self, deceleration: f64, jerk: f64) -> Result<()> {
        self.state = RunState::Aborted;
        // (a halt ends the card's pause; a path at rest has nothing to go on with)
        if std::mem::take(&mut self.pausing) {
            self.group.path_resume()?;
        }
        self.batch.clear();
        self.held = None;
        self.waiting = None;
        // A thread's axes are off the group: they and a tap's spindle halt.
        if !self.spindle.abort(&self.group) && !self.motion_done()? {
            self.group.halt(deceleration, jerk)?;
        }
        Ok(())
    }

    /// Polls until the run is done, paused or aborted; a stepped in-process card is stepped
    /// a tick at a time, another waited on. `timeout` bounds the whole.
    pub fn run(&mut self, timeout: Duration) -> Result<RunState> {
        let deadline = Instant::now() + timeout;
        loop {
            let s = self.poll()?;
            if matches!(s, RunState::Done | RunState::Paused | RunState::Aborted) {
                return Ok(s);
            }
            if Instant::now() >= deadline {
                return Err(Error::Timeout(timeout));
            }
            self.idle()?;
        }
    }

    /// Reads no source line at or past `line` (`None`: no limit) until the limit moves: a
    /// host that keeps something per line read (a report) bounds it so, whatever the chord
    /// fitter makes of the lines.
    pub fn set_read_limit(&mut self, line: Option<usize>) {
        self.read_limit = line;
    }

    /// Where the run is.
    pub fn state(&self) -> RunState {
        self.state
    }

    /// The source line of the segment the card runs (0 when none runs): the id of the
    /// running segment; paused, the block the pause ended.
    pub fn running_line(&self) -> Result<usize> {
        let (_, st) = self.group.status()?;
        let running =
            firmware_proto::raw::MC_PATHST_RUNNING | firmware_proto::raw::MC_PATHST_PAUSED;
        Ok(if st.path_flags & running != 0 {
            st.path_id as usize
        } else {
            0
        })
    }

    /// The source line the reader has reached.
    pub fn read_line(&self) -> usize {
        self.program.line()
    }

    /// The line of the error that stopped the run (0: none).
    pub fn error_line(&self) -> usize {
        self.error_line
    }

    /// Operations read so far.
    pub fn operations(&self) -> u64 {
        self.ops
    }

    /// The program (its interpreter's state and parameters).
    pub fn program(&self) -> &Program<S> {
        &self.program
    }

    /// Lets the card run between two polls: a tick of a stepped in-process card (which only
    /// moves when stepped), else half a millisecond; then the report's sample.
    pub fn idle(&mut self) -> Result<()> {
        let_card_run(self.group.card_pub(), Duration::from_micros(500));
        self.sample()
    }

    /// With [`RunSettings::report`]: the card's tick, if new since the last sample, measured
    /// (the X, Y, Z axes' commanded and actual positions, all of one tick, and the line the
    /// card runs). [`Runner::poll`] and [`Runner::idle`] sample; a host that lets the card
    /// run by itself between polls samples after each tick it lets run. On a stepped card
    /// polled and stepped a tick at a time every tick is seen; on a card running on its own,
    /// those the host reads ([`PathReport::ticks_seen`]).
    pub fn sample(&mut self) -> Result<()> {
        let Some(m) = &mut self.monitor else {
            return Ok(());
        };
        let ids: Vec<usize> = m.axes.iter().flatten().copied().collect();
        if ids.is_empty() {
            return Ok(());
        }
        let card = self.group.card_pub();
        let st = card.statuses(&ids)?;
        let tick = st[0].raw.tick;
        if m.tick.is_some_and(|t| tick <= t) {
            return Ok(());
        }
        m.tick = Some(tick);
        let (_, gs) = self.group.status()?;
        if gs.path_flags & firmware_proto::raw::MC_PATHST_RUNNING != 0 && gs.path_id != 0 {
            m.running = gs.path_id as usize;
            m.report.running(m.running);
        }
        let (mut cmd, mut act) = ([0.0; 3], [0.0; 3]);
        let mut k = 0;
        for (i, a) in m.axes.iter().enumerate() {
            if a.is_some() {
                cmd[i] = st[k].command_position;
                act[i] = st[k].actual_position;
                k += 1;
            }
        }
        let r = m
            .report
            .push_at(tick, cmd)
            .and_then(|()| m.report.push_actual(act));
        if let Err(e) = r {
            m.error.get_or_insert(e);
        }
        Ok(())
    }

    /// The run's report so far (with [`RunSettings::report`]; `None` without): path time,
    /// peaks against the path's limits, the largest deviation of the commanded path and of
    /// the actual one from the programmed path, the largest following error, stops, and how
    /// many ticks were seen.
    pub fn report(&self) -> Option<std::result::Result<PathReport, ReportError>> {
        let m = self.monitor.as_ref()?;
        Some(match &m.error {
            Some(e) => Err(e.clone()),
            None => m.report.finish(),
        })
    }

    /// The hooks.
    pub fn hooks_mut(&mut self) -> &mut H {
        &mut self.hooks
    }
}

/// One tick of a stepped in-process card (it moves only when stepped), else `sleep`.
fn let_card_run(card: &crate::Card, sleep: Duration) {
    #[cfg(feature = "emulator")]
    if let Some(sim) = card.sim() {
        sim.step(1);
        return;
    }
    let _ = card;
    std::thread::sleep(sleep);
}

/// Where `group` is, as a program position: each group axis's commanded position under the
/// letter `axes` gives it (`"XYZ"`: group axes 0, 1, 2 are X, Y, Z), the others 0. A program
/// run on the group starts here ([`super::Options::start`]).
pub fn group_position(group: &Group, axes: &str) -> Result<Pos> {
    let (n, ids) = group.axes()?;
    let status = group.card_pub().statuses(&ids[..n])?;
    let mut p = [0.0; 6];
    for (s, l) in status.iter().zip(axes.chars()) {
        let l = l.to_ascii_uppercase();
        if let Some(i) = super::AXIS_LETTERS.iter().position(|&a| a == l) {
            p[i] = s.command_position;
        }
    }
    Ok(p)
}

//! Homing: PLCopen MC_Home with the homing methods of CiA 402 (IEC 61800-7-201 §"Homing
//! mode"), and MC_SetPosition.
//!
//! A homing method finds a *home point* and sets the axis's position so that the home point
//! reads `position + home_offset` (`position`: MC_Home's argument; `home_offset`: the axis's
//! homing block), as CiA 402 drives set their actual position to the home offset there. The
//! position is a frame over the encoder count (`axis/`): it moves, the count never does.
//!
//! | method        | home point                                   | final approach      |
//! | ------------- | -------------------------------------------- | ------------------- |
//! | 1 / 17        | edge of the negative limit switch (+ index)  | positive            |
//! | 2 / 18        | edge of the positive limit switch (+ index)  | negative            |
//! | 3, 4 / 19, 20 | edge of a home switch active above it        | 3: neg., 4: pos.    |
//! | 5, 6 / 21, 22 | edge of a home switch active below it        | 5: pos., 6: neg.    |
//! | 7–10 / 23–26  | lower (7, 8) or upper (9, 10) edge, start +  | 7, 9 neg.; 8, 10 pos. |
//! | 11–14 / 27–30 | upper (11, 12) or lower (13, 14) edge, start − | 11, 13 pos.; 12, 14 neg. |
//! | 33, 34        | the next index pulse                         | 33 neg., 34 pos.    |
//! | 35, 37        | the current position                         | none                |
//! | −1, −2        | a hard stop (negative, positive), then index | away from the stop  |
//! | −3, −4        | a hard stop (negative, positive)             | into the stop       |
//!
//! Methods 1–14 take the first index pulse beyond the edge in the direction of the final
//! approach; 17–30 are the same without the index (the home point is the edge). The negative
//! numbers are the hard-stop methods as several drives number them (−1/−2 with the index,
//! −3/−4 without).
//!
//! Every switch method makes its final approach the same way, whatever the start: it crosses
//! the edge at the *search* velocity going against the final direction (so the axis is on the
//! near side of the edge, by its braking distance), reverses to the *creep* velocity and takes
//! the edge where the switch input changes going the final way. The creep velocity is reached
//! before the edge (braking from the search velocity takes longer than reaching the creep
//! one), so the edge is always crossed at the creep velocity from the same side: its position is
//! known to one count plus `creep·Ts`. To get there the search always heads for the edge sought:
//! the switch input says which side of it the axis is on, except outside a switch with two
//! edges, where the search starts in the method's direction and reverses once at the limit
//! switch ahead. From a position on the limit switch of methods 1, 2, 17, 18 the axis creeps off
//! it directly, as CiA 402 says. The index is the encoder interface's latch (`IndexLatch`):
//! exact, wherever between two ticks it was crossed.
//!
//! A hard stop is a following error of at least `hard_stop_ferror` held for `hard_stop_dwell`
//! while the axis creeps towards it; the reference then holds where the axis stalled.
//!
//! Once the home point is found the axis stops, the position is set, and (with
//! `MC_HOMING_MOVE_TO_HOME`) it moves to the home point; motion done comes once in position.
//! A failure (a limit switch the method does not reverse at, the maximum distance, the timeout,
//! no index) stops the axis on the homing deceleration and reports `HomingFailed` once at rest,
//! in Standstill and not homed.
//!
//! The safety layer: a method with limit switches in its definition watches both of them
//! (`Axis::homing_limits`), so reversing there does not trip the hard-limit stop; under the
//! other methods a limit switch is unexpected and trips it as always. Soft limits hold only once
//! homed. Halt, stop, power off and safety stops end the Homing state, and with it the method.
//!
//! Like the rest of the firmware: no allocation, no panic, no clock; time is the tick count.
#![forbid(unsafe_code)]

use crate::firmware::axis::Axis;
use crate::firmware::nack::check_ranges;
use crate::firmware::safety::IndexLatch;
use crate::motion::scurve::Limits;
use firmware_proto::{
    AxisHoming, AxisState, HomingError, HomingFlags, Io, NackCode, MAX_MOVE_TIME, MAX_POSITION,
};

/// Where a method's home point is (see the module's table).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Geometry {
    /// 1, 2, 17, 18: the edge of a limit switch (`pos`: the positive one).
    Limit { pos: bool },
    /// 3–6, 19–22: the edge of a home switch active above it (`above`) or below it.
    OneSided { above: bool },
    /// 7–14, 23–30: an edge of a home switch of some width (`upper`: its upper edge); the
    /// search starts in direction `first`.
    Width { upper: bool, first: f64 },
    /// 33, 34: the next index pulse.
    Index,
    /// 35, 37: the current position.
    Current,
    /// −1 to −4: a hard stop.
    HardStop,
}

/// A CiA 402 homing method, decoded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Method {
    /// Its number.
    pub number: i32,
    geometry: Geometry,
    /// The direction of the final approach (switch methods and index methods), or towards
    /// the hard stop.
    dir: f64,
    /// The home point is the first index pulse after the edge or hard stop.
    index: bool,
}

impl Method {
    /// The method with this CiA 402 number, if this firmware has it.
    pub fn from_number(number: i32) -> Option<Method> {
        use Geometry::*;
        let (geometry, dir, index) = match number {
            -1 | -3 => (HardStop, -1.0, number == -1),
            -2 | -4 => (HardStop, 1.0, number == -2),
            33 => (Index, -1.0, true),
            34 => (Index, 1.0, true),
            35 | 37 => (Current, 1.0, false),
            1..=14 | 17..=30 => {
                let index = number <= 14;
                let (geometry, dir) = match if index { number } else { number - 16 } {
                    1 => (Limit { pos: false }, 1.0),
                    2 => (Limit { pos: true }, -1.0),
                    3 => (OneSided { above: true }, -1.0),
                    4 => (OneSided { above: true }, 1.0),
                    5 => (OneSided { above: false }, 1.0),
                    6 => (OneSided { above: false }, -1.0),
                    7 => (
                        Width {
                            upper: false,
                            first: 1.0,
                        },
                        -1.0,
                    ),
                    8 => (
                        Width {
                            upper: false,
                            first: 1.0,
                        },
                        1.0,
                    ),
                    9 => (
                        Width {
                            upper: true,
                            first: 1.0,
                        },
                        -1.0,
                    ),
                    10 => (
                        Width {
                            upper: true,
                            first: 1.0,
                        },
                        1.0,
                    ),
                    11 => (
                        Width {
                            upper: true,
                            first: -1.0,
                        },
                        1.0,
                    ),
                    12 => (
                        Width {
                            upper: true,
                            first: -1.0,
                        },
                        -1.0,
                    ),
                    13 => (
                        Width {
                            upper: false,
                            first: -1.0,
                        },
                        1.0,
                    ),
                    _ => (
                        Width {
                            upper: false,
                            first: -1.0,
                        },
                        -1.0,
                    ),
                };
                (geometry, dir, index)
            }
            _ => return None,
        };
        Some(Method {
            number,
            geometry,
            dir,
            index,
        })
    }

    /// Does its home point need the encoder's index channel?
    pub fn needs_index(&self) -> bool {
        self.index
    }

    /// The limit switches it watches itself (those in its definition): the safety layer does
    /// not trip on them while it runs.
    pub fn watched_limits(&self) -> Io {
        match self.geometry {
            Geometry::Limit { .. } | Geometry::Width { .. } => Io::LIMIT_POS | Io::LIMIT_NEG,
            _ => Io::empty(),
        }
    }

    /// The switch input it looks for.
    fn signal(&self, io: Io) -> bool {
        match self.geometry {
            Geometry::Limit { pos: true } => io.contains(Io::LIMIT_POS),
            Geometry::Limit { pos: false } => io.contains(Io::LIMIT_NEG),
            _ => io.contains(Io::HOME),
        }
    }

    /// Which side of the sought edge the switch is active on (+1 above it, −1 below it).
    fn active_side(&self) -> f64 {
        match self.geometry {
            Geometry::Limit { pos } | Geometry::OneSided { above: pos } => sign(pos),
            // Between the edges: above the lower one, below the upper one.
            Geometry::Width { upper, .. } => sign(!upper),
            _ => 1.0,
        }
    }

    /// The switch input on the near side of the edge, before the final approach crosses it.
    fn pre(&self) -> bool {
        self.active_side() == -self.dir
    }
}

fn sign(positive: bool) -> f64 {
    if positive {
        1.0
    } else {
        -1.0
    }
}

/// The validated copy of an axis's homing block.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HomingConfig {
    /// The block as the host wrote it (`mc_axis_homing`).
    pub block: AxisHoming,
    /// Its method.
    pub method: Method,
}

/// The block's velocities, acceleration and jerk within the card's range at `rate_hz`
/// (`LimitRange`): at `validate`, and again at MC_Home in case the servo rate changed since.
fn speeds_in_range(b: &AxisHoming, rate_hz: u32) -> Result<(), NackCode> {
    check_ranges(
        rate_hz,
        &[
            (1, b.search_vel),
            (1, b.creep_vel),
            (2, b.accel),
            (3, b.jerk),
        ],
    )
}

impl HomingConfig {
    /// Check every field of `block` at servo rate `rate_hz`: not finite `NotFinite`; an unknown
    /// method, or an index method without `MC_HOMING_INDEX`, `HomingMethod`; a velocity,
    /// acceleration or jerk outside the card's range `LimitRange`; anything else out of range
    /// `BadConfig` (`OutOfRange` for the home offset).
    pub fn validate(block: &AxisHoming, rate_hz: u32) -> Result<HomingConfig, NackCode> {
        let b = block;
        let all = [
            b.search_vel,
            b.creep_vel,
            b.accel,
            b.jerk,
            b.home_offset,
            b.timeout,
            b.max_distance,
            b.index_distance,
            b.hard_stop_ferror,
            b.hard_stop_dwell,
        ];
        if all.iter().any(|x| !x.is_finite()) {
            return Err(NackCode::NotFinite);
        }
        let method = Method::from_number(b.method).ok_or(NackCode::HomingMethod)?;
        let flags = HomingFlags::from_bits(b.flags).ok_or(NackCode::BadConfig)?;
        if method.needs_index() && !flags.contains(HomingFlags::INDEX) {
            return Err(NackCode::HomingMethod);
        }
        if [b.search_vel, b.creep_vel, b.accel, b.jerk]
            .iter()
            .any(|x| *x <= 0.0)
        {
            return Err(NackCode::BadConfig);
        }
        speeds_in_range(b, rate_hz)?;
        if b.home_offset.abs() > MAX_POSITION {
            return Err(NackCode::OutOfRange);
        }
        let positive_up_to = |x: f64, max: f64| x > 0.0 && x <= max;
        if b.creep_vel > b.search_vel
            || !positive_up_to(b.timeout, MAX_MOVE_TIME)
            || !positive_up_to(b.max_distance, 2.0 * MAX_POSITION)
            || !positive_up_to(b.index_distance, 2.0 * MAX_POSITION)
            || b.hard_stop_ferror <= 0.0
            || !(0.0..=10.0).contains(&b.hard_stop_dwell)
        {
            return Err(NackCode::BadConfig);
        }
        Ok(HomingConfig {
            block: *block,
            method,
        })
    }

    fn flags(&self) -> HomingFlags {
        HomingFlags::from_bits_retain(self.block.flags)
    }

    /// The kinematic limits of its motions: the search velocity, its acceleration and jerk.
    fn limits(&self) -> Limits {
        Limits::symmetric(self.block.search_vel, self.block.accel, self.block.jerk)
    }
}

impl Default for HomingConfig {
    fn default() -> Self {
        let block = AxisHoming::default();
        HomingConfig {
            method: Method::from_number(block.method).unwrap_or(Method {
                number: 37,
                geometry: Geometry::Current,
                dir: 1.0,
                index: false,
            }),
            block,
        }
    }
}

/// What the homing of an axis tells the command manager after a tick.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HomingReport {
    /// Homing of command `seq` is done, homed and in position: motion done with (seq, actual
    /// position).
    pub done: Option<(u32, f64)>,
    /// Homing of command `seq` failed (and the axis is at rest): (seq, why, actual position).
    pub failed: Option<(u32, HomingError, f64)>,
    /// The axis's state changed from this one.
    pub state_from: Option<AxisState>,
}

/// Where a switch with two edges is relative to the axis (methods 7–14, 23–30).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Region {
    /// Below the lower edge.
    Below,
    /// On the switch.
    On,
    /// Above the upper edge.
    Above,
    /// Off the switch, not yet known on which side.
    Unknown,
}

/// The phases of a method.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase {
    /// Searching at the search velocity in `dir`; `reversed`: the search already turned at a
    /// limit switch.
    Search { dir: f64, reversed: bool },
    /// The final approach at the creep velocity; `armed`: the input shows the near side.
    Creep { armed: bool },
    /// Creeping on in `dir` from `from` until the index latch moves from `latches`.
    Index { from: f64, dir: f64, latches: u32 },
    /// Creeping towards a hard stop; the following error has been over the threshold for
    /// `over` s.
    Push { over: f64 },
    /// The home point (in the old frame) is found: stopping.
    Stopping { home_point: f64 },
    /// Moving to the home point.
    MoveHome,
    /// In position for `settled` s.
    Settle { settled: f64 },
    /// Failed: stopping, then the report.
    Failing { why: HomingError, at: f64 },
}

/// A homing in progress.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Run {
    seq: u32,
    cfg: HomingConfig,
    /// What the home point reads: MC_Home's position + the home offset.
    home: f64,
    /// Where it began (the actual position).
    start: f64,
    elapsed: f64,
    phase: Phase,
    /// The switch input of the last tick.
    last: bool,
    region: Region,
    /// A velocity to command once the stop in progress ends (the planner could not reach it
    /// from where the axis was).
    pending: Option<f64>,
}

/// The homing of one axis: its configuration and the method in progress.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Homing {
    config: HomingConfig,
    run: Option<Run>,
}

/// What the homing step sees of the card this tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HomingInputs {
    /// The axis's inputs (limit and home switches).
    pub io: Io,
    /// The index latch of its encoder interface.
    pub index: IndexLatch,
    /// Servo period, s.
    pub ts: f64,
    /// Servo rate, Hz.
    pub rate_hz: u32,
    /// The card's maximum stop time, s.
    pub max_stop_time: f64,
}

impl Homing {
    /// The active configuration.
    pub fn config(&self) -> &HomingConfig {
        &self.config
    }

    /// Is a homing running?
    pub fn active(&self) -> bool {
        self.run.is_some()
    }

    /// `MC_OP_APPLY_AXIS_HOMING`: the validated block becomes the configuration of the next
    /// MC_Home (a homing in progress keeps its own).
    pub fn apply(&mut self, cfg: HomingConfig) {
        self.config = cfg;
    }

    /// The checks of [`Homing::start`] made without starting (its configuration against the
    /// axis, the home position): the home point's position, or the nack. A gantry checks
    /// every side before any starts (`gantry.rs`).
    pub fn check(&self, axis: &Axis, position: f64, rate_hz: u32) -> Result<f64, NackCode> {
        let cfg = self.config;
        let b = &cfg.block;
        let home = position + b.home_offset;
        if !home.is_finite() || home.abs() > MAX_POSITION {
            return Err(NackCode::OutOfRange);
        }
        if cfg.method.geometry == Geometry::HardStop {
            let at_dwell = b.hard_stop_ferror + b.creep_vel * b.hard_stop_dwell;
            if at_dwell >= axis.safety.config.ferror_limit(b.creep_vel) {
                return Err(NackCode::BadConfig);
            }
        }
        speeds_in_range(b, rate_hz)?;
        Ok(home)
    }

    /// MC_Home (command `seq`): the home point will read `position` + the home offset. From
    /// Standstill; a hard-stop method whose threshold the axis's following-error limit would
    /// trip first is refused (`BadConfig`). Returns the old state.
    pub fn start(
        &mut self,
        axis: &mut Axis,
        seq: u32,
        position: f64,
        rate_hz: u32,
    ) -> Result<Option<AxisState>, NackCode> {
        let home = self.check(axis, position, rate_hz)?;
        let cfg = self.config;
        let changed = axis.begin_homing(seq, cfg.method.watched_limits())?;
        self.run = Some(Run {
            seq,
            cfg,
            home,
            start: axis.actual().0,
            elapsed: 0.0,
            phase: Phase::Settle { settled: 0.0 },
            last: false,
            region: Region::Unknown,
            pending: None,
        });
        Ok(changed)
    }

    /// One servo tick, after the axis sensed its encoder and before its servo loop runs: the
    /// method looks at the inputs and drives the axis.
    pub fn tick(&mut self, axis: &mut Axis, inp: &HomingInputs) -> HomingReport {
        let mut report = HomingReport::default();
        let Some(mut run) = self.run.take() else {
            return report;
        };
        if axis.state != AxisState::Homing {
            // A halt, stop, power off or safety stop ended it (and reported its end).
            return report;
        }
        let first = run.elapsed == 0.0;
        run.elapsed += inp.ts;
        if first {
            run.begin(axis, inp);
        } else {
            run.step(axis, inp);
        }
        match run.finished(axis) {
            Some(Ok(pos)) => report.done = Some((run.seq, pos)),
            Some(Err((why, at))) => report.failed = Some((run.seq, why, at)),
            None => {
                self.run = Some(run);
                return report;
            }
        }
        let (changed, _) = axis.end_homing(report.done.is_some());
        report.state_from = changed;
        report
    }
}

impl Run {
    fn begin(&mut self, axis: &mut Axis, inp: &HomingInputs) {
        let m = self.cfg.method;
        let s = m.signal(inp.io);
        self.last = s;
        let creep = self.cfg.block.creep_vel;
        match m.geometry {
            Geometry::Current => {
                let here = axis.actual().0;
                self.found(axis, inp, here);
            }
            Geometry::Index => {
                let from = axis.actual().0;
                self.phase = Phase::Index {
                    from,
                    dir: m.dir,
                    latches: inp.index.latches,
                };
                self.go(axis, inp, m.dir * creep);
            }
            Geometry::HardStop => {
                self.phase = Phase::Push { over: 0.0 };
                self.go(axis, inp, m.dir * creep);
            }
            Geometry::Limit { .. } if s == m.pre() => {
                // On the limit switch: creep off it (CiA 402).
                self.phase = Phase::Creep { armed: true };
                self.go(axis, inp, m.dir * creep);
            }
            _ => {
                let mut reversed = false;
                if let Geometry::Width { first, .. } = m.geometry {
                    self.region = if s { Region::On } else { Region::Unknown };
                    if !s && self.limit_ahead(inp.io, first) {
                        // Off the switch, on the limit switch the search would start into:
                        // the switch is the other way (the reversal, made at once).
                        self.region = if first > 0.0 {
                            Region::Above
                        } else {
                            Region::Below
                        };
                        reversed = true;
                    }
                }
                let dir = self.toward_edge(s);
                self.phase = Phase::Search { dir, reversed };
                self.go(axis, inp, dir * self.cfg.block.search_vel);
            }
        }
    }

    /// Which way the edge sought is from here (`s`: the switch input), or, off a switch with
    /// two edges on an unknown side, the method's first direction.
    fn toward_edge(&self, s: bool) -> f64 {
        let m = self.cfg.method;
        let side = match m.geometry {
            Geometry::Width { upper, first } => match self.region {
                Region::Below => -1.0,
                Region::Above => 1.0,
                // Between the edges: above the lower one, below the upper one.
                Region::On => sign(!upper),
                Region::Unknown => return first,
            },
            // One edge: the input says which side.
            _ => {
                if s {
                    m.active_side()
                } else {
                    -m.active_side()
                }
            }
        };
        -side
    }

    /// Command velocity `v` (or, if it cannot be planned from the axis's state, stop first and
    /// command it at rest; if not even that, fail).
    fn go(&mut self, axis: &mut Axis, inp: &HomingInputs, v: f64) {
        let lim = self.cfg.limits();
        if axis.homing_velocity(v, &lim, inp.rate_hz).is_ok() {
            self.pending = None;
            return;
        }
        let r = axis.reference();
        let b = &self.cfg.block;
        let at_rest = r.vel == 0.0 && r.acc == 0.0 && !axis.profile_running();
        if !at_rest
            && axis
                .run_bounded_stop(b.accel, b.jerk, inp.max_stop_time)
                .is_ok()
        {
            self.pending = Some(v);
        } else {
            let at = axis.actual().0;
            self.fail(axis, inp, HomingError::Plan, at);
        }
    }

    fn step(&mut self, axis: &mut Axis, inp: &HomingInputs) {
        let m = self.cfg.method;
        let b = self.cfg.block;
        let here = axis.actual().0;
        let s = m.signal(inp.io);
        let last = core::mem::replace(&mut self.last, s);
        // The way the axis moves now (a transition of the input is crossed this way).
        let cmd_vel = axis.reference().vel;
        if let Some(v) = self.pending {
            if !axis.profile_running() {
                self.go(axis, inp, v);
            }
        }
        let searching = !matches!(
            self.phase,
            Phase::Stopping { .. } | Phase::MoveHome | Phase::Settle { .. } | Phase::Failing { .. }
        );
        if searching {
            if self.elapsed > b.timeout {
                return self.fail(axis, inp, HomingError::Timeout, here);
            }
            if (here - self.start).abs() > b.max_distance {
                return self.fail(axis, inp, HomingError::DistanceExceeded, here);
            }
        }
        match self.phase {
            Phase::Search { dir, reversed } => {
                let moving = if cmd_vel != 0.0 {
                    cmd_vel.signum()
                } else {
                    dir
                };
                if s != last {
                    if let Geometry::Width { upper, .. } = m.geometry {
                        // Which edge was crossed, and where the axis now is.
                        let lower_edge = (moving > 0.0) == s;
                        self.region = if s {
                            Region::On
                        } else if moving > 0.0 {
                            Region::Above
                        } else {
                            Region::Below
                        };
                        if lower_edge == upper {
                            // The other edge: not the one sought.
                            return self.head_for_edge(axis, inp, s, dir, reversed);
                        }
                    }
                    if moving == -m.dir {
                        // The edge, crossed against the final direction at the search
                        // velocity: the axis is on its near side. Creep back.
                        self.phase = Phase::Creep {
                            armed: s == m.pre(),
                        };
                        return self.go(axis, inp, m.dir * b.creep_vel);
                    }
                    return self.head_for_edge(axis, inp, s, dir, reversed);
                }
                if self.limit_ahead(inp.io, dir) {
                    match m.geometry {
                        Geometry::Width { first, .. } if !reversed && dir == first => {
                            // Not met going the first way: the switch is behind (CiA 402:
                            // reverse at the limit switch).
                            self.region = if dir > 0.0 {
                                Region::Above
                            } else {
                                Region::Below
                            };
                            let back = self.toward_edge(s);
                            self.phase = Phase::Search {
                                dir: back,
                                reversed: true,
                            };
                            self.go(axis, inp, back * b.search_vel);
                        }
                        _ => self.fail(axis, inp, HomingError::LimitReached, here),
                    }
                }
            }
            Phase::Creep { armed } => {
                let moving = if cmd_vel != 0.0 {
                    cmd_vel.signum()
                } else {
                    m.dir
                };
                if armed && s != m.pre() && moving == m.dir {
                    // The edge.
                    if m.index {
                        self.phase = Phase::Index {
                            from: here,
                            dir: m.dir,
                            latches: inp.index.latches,
                        };
                    } else {
                        self.found(axis, inp, here);
                    }
                    return;
                }
                self.phase = Phase::Creep {
                    armed: s == m.pre(),
                };
                if self.limit_ahead(inp.io, m.dir) {
                    self.fail(axis, inp, HomingError::LimitReached, here);
                }
            }
            Phase::Index { from, dir, latches } => {
                if inp.index.latches != latches {
                    let point = axis.position_of_count(inp.index.count);
                    return self.found(axis, inp, point);
                }
                if (here - from).abs() > b.index_distance {
                    return self.fail(axis, inp, HomingError::NoIndex, here);
                }
                if self.limit_ahead(inp.io, dir) {
                    self.fail(axis, inp, HomingError::LimitReached, here);
                }
            }
            Phase::Push { over } => {
                let ferr = (axis.reference().pos - here) * m.dir;
                let over = if ferr >= b.hard_stop_ferror {
                    over + inp.ts
                } else {
                    0.0
                };
                self.phase = Phase::Push { over };
                if over + 1e-12 >= b.hard_stop_dwell && ferr >= b.hard_stop_ferror {
                    // Stalled on the hard stop: hold there.
                    axis.hold_at_actual();
                    if m.index {
                        self.phase = Phase::Index {
                            from: here,
                            dir: -m.dir,
                            latches: inp.index.latches,
                        };
                        self.go(axis, inp, -m.dir * b.creep_vel);
                    } else {
                        self.found(axis, inp, here);
                    }
                }
            }
            Phase::Stopping { home_point } => {
                if !axis.profile_running() {
                    axis.shift_position(self.home - home_point);
                    let target = self.home;
                    let flags = self.cfg.flags();
                    // The current position is the home point: nothing moves there.
                    let far = (target - axis.reference().pos).abs() > 1e-9
                        && m.geometry != Geometry::Current;
                    if flags.contains(HomingFlags::MOVE_TO_HOME) && far {
                        match axis.homing_move(target, &self.cfg.limits(), inp.rate_hz) {
                            Ok(()) => self.phase = Phase::MoveHome,
                            Err(_) => self.fail(axis, inp, HomingError::Plan, here),
                        }
                    } else {
                        self.phase = Phase::Settle { settled: 0.0 };
                    }
                }
            }
            Phase::MoveHome => {
                if !axis.profile_running() {
                    self.phase = Phase::Settle { settled: 0.0 };
                }
            }
            Phase::Settle { settled } => {
                let at = axis.reference().pos;
                let settled = if axis.in_position_at(at) {
                    settled + inp.ts
                } else {
                    0.0
                };
                self.phase = Phase::Settle { settled };
            }
            Phase::Failing { .. } => {}
        }
    }

    /// After a transition that is not the one sought: head for the edge (reversing if it is
    /// behind).
    fn head_for_edge(
        &mut self,
        axis: &mut Axis,
        inp: &HomingInputs,
        s: bool,
        dir: f64,
        reversed: bool,
    ) {
        let next = self.toward_edge(s);
        self.phase = Phase::Search {
            dir: next,
            reversed,
        };
        if next != dir {
            self.go(axis, inp, next * self.cfg.block.search_vel);
        }
    }

    /// Is a limit switch this method watches (other than the one it homes on) active ahead of
    /// motion in `dir`?
    fn limit_ahead(&self, io: Io, dir: f64) -> bool {
        let ahead = if dir > 0.0 {
            Io::LIMIT_POS
        } else {
            Io::LIMIT_NEG
        };
        let own = match self.cfg.method.geometry {
            Geometry::Limit { pos } => Some(if pos { Io::LIMIT_POS } else { Io::LIMIT_NEG }),
            _ => None,
        };
        let watched = self.cfg.method.watched_limits();
        watched.contains(ahead) && io.contains(ahead) && own != Some(ahead)
    }

    /// The home point is at `point` (in the frame of now): stop, then set the position.
    fn found(&mut self, axis: &mut Axis, inp: &HomingInputs, point: f64) {
        self.pending = None;
        self.phase = Phase::Stopping { home_point: point };
        if axis.profile_running() {
            let b = &self.cfg.block;
            if axis
                .run_bounded_stop(b.accel, b.jerk, inp.max_stop_time)
                .is_err()
            {
                axis.hold_at_actual();
            }
        }
    }

    /// Homing fails (`why`, at position `at`): stop where the axis is going, then report.
    fn fail(&mut self, axis: &mut Axis, inp: &HomingInputs, why: HomingError, at: f64) {
        self.pending = None;
        self.phase = Phase::Failing { why, at };
        if axis.profile_running() {
            let b = &self.cfg.block;
            if axis
                .run_bounded_stop(b.accel, b.jerk, inp.max_stop_time)
                .is_err()
            {
                axis.hold_at_actual();
            }
        }
    }

    /// Has it ended: `Ok(actual position)` done, `Err((why, where))` failed.
    fn finished(&self, axis: &Axis) -> Option<Result<f64, (HomingError, f64)>> {
        match self.phase {
            Phase::Settle { settled } if settled + 1e-12 >= axis.config.settle_time => {
                Some(Ok(axis.actual().0))
            }
            Phase::Failing { why, at } if !axis.profile_running() => Some(Err((why, at))),
            _ => None,
        }
    }
}

/// MC_SetPosition: the axis's actual and commanded positions become `arg` (or, `relative`,
/// move by `arg`) without moving it, and it is homed. In Standstill with no motion left, or
/// Disabled; `AxisHoming` while it homes, `InvalidState` otherwise, `OutOfRange` beyond the
/// position range.
pub fn set_position(axis: &mut Axis, arg: f64, relative: bool) -> Result<(), NackCode> {
    match axis.state {
        AxisState::Standstill | AxisState::Disabled => {}
        AxisState::Homing => return Err(NackCode::AxisHoming),
        _ => return Err(NackCode::InvalidState),
    }
    if axis.busy_with_motion() {
        return Err(NackCode::InvalidState);
    }
    let here = axis.actual().0;
    let to = if relative { here + arg } else { arg };
    if !to.is_finite() || to.abs() > MAX_POSITION {
        return Err(NackCode::OutOfRange);
    }
    axis.shift_position(to - here);
    axis.set_homed(true);
    Ok(())
}

#[cfg(test)]
mod tests {
    //! Every method on an ideal drive (the shaft is where the reference says, the encoder
    //! counts it down to whole counts), with switches and an index every 10,000 counts: the home
    //! point is the same count from every start, and it is the count the geometry says.
    use super::*;

    const TS: f64 = 1e-4;
    const RATE: u32 = 10_000;
    const INDEX: i64 = 10_000;

    /// The plant around one axis.
    #[derive(Clone, Copy)]
    struct World {
        limit_neg: f64,
        limit_pos: f64,
        home: Option<(f64, f64)>,
        wall: Option<f64>,
    }

    impl World {
        fn io(&self, x: f64) -> Io {
            let mut io = Io::empty();
            io.set(Io::LIMIT_NEG, x <= self.limit_neg);
            io.set(Io::LIMIT_POS, x >= self.limit_pos);
            io.set(
                Io::HOME,
                self.home.is_some_and(|(lo, hi)| (lo..=hi).contains(&x)),
            );
            io
        }
    }

    struct Bench {
        axis: Axis,
        homing: Homing,
        world: World,
        /// The shaft, counts.
        x: f64,
        latch: IndexLatch,
        last_count: i64,
        events: Vec<HomingReport>,
    }

    impl Bench {
        fn new(world: World, start: f64, block: AxisHoming) -> Self {
            let mut axis = Axis::new();
            let count = start.floor() as i64;
            axis.sense(count, TS);
            axis.power(true).unwrap();
            let mut homing = Homing::default();
            homing.apply(HomingConfig::validate(&block, RATE).unwrap());
            Self {
                axis,
                homing,
                world,
                x: start,
                latch: IndexLatch::default(),
                last_count: count,
                events: Vec::new(),
            }
        }

        /// One tick: sense, homing, servo loop, then the ideal drive moves the shaft.
        fn step(&mut self) {
            let count = self.x.floor() as i64;
            // The latch: pulses at multiples of INDEX, entered from either side.
            let (a, b) = (self.last_count, count);
            for p in a.min(b)..=a.max(b) {
                let entered = if b > a { p > a } else { p < a };
                if p != a && entered && p.rem_euclid(INDEX) == 0 {
                    self.latch = IndexLatch {
                        count: p,
                        latches: self.latch.latches + 1,
                    };
                }
            }
            self.last_count = count;
            self.axis.sense(count, TS);
            let inp = HomingInputs {
                io: self.world.io(self.x),
                index: self.latch,
                ts: TS,
                rate_hz: RATE,
                max_stop_time: 2.0,
            };
            let r = self.homing.tick(&mut self.axis, &inp);
            if r != HomingReport::default() {
                self.events.push(r);
            }
            self.axis.control(TS);
            let offset = self.axis.position_of_count(0);
            let mut x = self.axis.reference().pos - offset;
            if let Some(w) = self.world.wall {
                x = if w < 0.0 { x.max(w) } else { x.min(w) };
            }
            self.x = x;
        }

        /// Home, run to the end; the report and the raw count of the home point.
        fn home(&mut self, position: f64, max_ticks: u32) -> (HomingReport, f64) {
            self.homing
                .start(&mut self.axis, 7, position, RATE)
                .expect("MC_Home accepted");
            assert_eq!(self.axis.state, AxisState::Homing);
            for _ in 0..max_ticks {
                self.step();
                if self.axis.state != AxisState::Homing {
                    let r = *self.events.last().unwrap();
                    let block = self.homing.config().block;
                    let raw = position + block.home_offset - self.axis.position_of_count(0);
                    return (r, raw);
                }
            }
            panic!("still homing after {max_ticks} ticks at {}", self.x);
        }
    }

    fn block(method: i32) -> AxisHoming {
        AxisHoming {
            method,
            ..AxisHoming::default()
        }
    }

    fn switches() -> World {
        World {
            limit_neg: -35_000.5,
            limit_pos: 35_000.5,
            home: Some((5_000.5, 8_000.5)),
            wall: None,
        }
    }

    /// The count of the home point of each switch method, on [`switches`]: edges at 5,000.5
    /// (lower: count 5,000 from either side) and 8,000.5 (upper: 8,000), the limit switches at
    /// ±35,000.5 (counts -35,001 and 35,000), index pulses at multiples of 10,000.
    fn expected(method: i32) -> f64 {
        match method {
            1 => -30_000.0,
            2 => 30_000.0,
            17 => -35_001.0,
            18 => 35_000.0,
            // The lower edge seen as a one-sided switch (active above it or below it).
            3 | 6 | 7 | 9 | 12 | 14 => 0.0,
            4 | 5 | 8 | 10 | 11 | 13 => 10_000.0,
            19..=22 | 23 | 24 | 29 | 30 => 5_000.0,
            25..=28 => 8_000.0,
            _ => unreachable!(),
        }
    }

    fn world_for(method: i32) -> World {
        let m = Method::from_number(method).unwrap();
        let mut w = switches();
        match m.geometry {
            Geometry::OneSided { above: true } => w.home = Some((5_000.5, f64::INFINITY)),
            Geometry::OneSided { above: false } => w.home = Some((f64::NEG_INFINITY, 5_000.5)),
            _ => {}
        }
        w
    }

    #[test]
    fn every_switch_method_finds_its_home_point_from_every_start() {
        for method in (1..=14).chain(17..=30) {
            for start in [
                -35_200.0, -12_345.6, 4_990.0, 6_500.2, 8_010.0, 29_000.0, 35_300.0,
            ] {
                let mut b = Bench::new(world_for(method), start, block(method));
                let (r, raw) = b.home(100.0, 2_000_000);
                assert!(
                    r.done.is_some(),
                    "method {method} from {start}: {r:?} at {}",
                    b.x
                );
                assert_eq!(raw, expected(method), "method {method} from {start}");
                // It ends at the home point, which reads 100.
                let (act, _) = b.axis.actual();
                assert!((act - 100.0).abs() <= 1.0, "method {method}: at {act}");
                assert!(b.axis.homed() && b.axis.state == AxisState::Standstill);
                assert_eq!(r.state_from, Some(AxisState::Homing));
            }
        }
    }

    #[test]
    fn index_hard_stop_and_current_position_methods() {
        let w = World {
            home: None,
            ..switches()
        };
        for (method, start, home) in [(33, 4_321.0, 0.0), (34, 4_321.0, 10_000.0)] {
            let mut b = Bench::new(w, start, block(method));
            let (r, raw) = b.home(0.0, 400_000);
            assert!(r.done.is_some(), "{method}");
            assert_eq!(raw, home, "{method}");
        }
        let wall = World {
            wall: Some(-25_000.5),
            ..w
        };
        for (method, home) in [(-1, -20_000.0), (-3, -25_001.0)] {
            for start in [-24_000.0, -3_000.0] {
                let mut b = Bench::new(wall, start, block(method));
                let (r, raw) = b.home(0.0, 800_000);
                assert!(r.done.is_some(), "{method} from {start}: {r:?}");
                assert_eq!(raw, home, "{method} from {start}");
            }
        }
        let mut b = Bench::new(w, 1_234.0, block(37));
        let (r, raw) = b.home(-50.0, 1_000);
        assert!(r.done.is_some());
        assert_eq!(raw, 1_234.0);
        assert_eq!(b.axis.actual().0, -50.0);
    }

    #[test]
    fn failures_stop_the_axis_and_say_why() {
        // No home switch: the search reverses at the positive limit, then meets the negative one.
        let w = World {
            home: None,
            ..switches()
        };
        let mut b = Bench::new(w, 0.0, block(23));
        let (r, _) = b.home(0.0, 2_000_000);
        let (_, why, at) = r.failed.expect("failed");
        assert_eq!(why, HomingError::LimitReached);
        assert!(at <= -35_000.0 && b.x > -37_000.0, "{at} {}", b.x);
        assert!(!b.axis.homed() && b.axis.state == AxisState::Standstill);
        // No switch and no limits: the maximum distance.
        let open = World {
            limit_neg: f64::NEG_INFINITY,
            limit_pos: f64::INFINITY,
            home: None,
            wall: None,
        };
        let mut b = Bench::new(
            open,
            0.0,
            AxisHoming {
                max_distance: 50_000.0,
                ..block(19)
            },
        );
        let (r, _) = b.home(0.0, 2_000_000);
        assert_eq!(r.failed.map(|f| f.1), Some(HomingError::DistanceExceeded));
        assert!(b.x.abs() < 52_000.0, "{}", b.x);
        // Timeout.
        let mut b = Bench::new(
            open,
            0.0,
            AxisHoming {
                timeout: 0.5,
                ..block(19)
            },
        );
        let (r, _) = b.home(0.0, 2_000_000);
        assert_eq!(r.failed.map(|f| f.1), Some(HomingError::Timeout));
        // An index channel that never pulses (index every 10,000 counts but a distance of 5,000).
        let mut b = Bench::new(
            switches(),
            6_000.0,
            AxisHoming {
                index_distance: 4_000.0,
                ..block(8)
            },
        );
        let (r, _) = b.home(0.0, 2_000_000);
        assert_eq!(r.failed.map(|f| f.1), Some(HomingError::NoIndex));
    }

    #[test]
    fn the_configuration_is_checked() {
        let ok = |b: AxisHoming| HomingConfig::validate(&b, RATE);
        assert!(ok(AxisHoming::default()).is_ok());
        for m in [0, 15, 16, 31, 32, 36, 38, -5, i32::MIN] {
            assert_eq!(ok(block(m)), Err(NackCode::HomingMethod), "{m}");
        }
        let no_index = |m| AxisHoming {
            flags: HomingFlags::MOVE_TO_HOME.bits(),
            ..block(m)
        };
        for m in [1, 14, 33, 34, -1, -2] {
            assert_eq!(ok(no_index(m)), Err(NackCode::HomingMethod), "{m}");
        }
        for m in [17, 30, 35, 37, -3, -4] {
            assert!(ok(no_index(m)).is_ok(), "{m}");
        }
        let bad = [
            AxisHoming {
                creep_vel: 30_000.0,
                ..block(1)
            },
            AxisHoming {
                timeout: 0.0,
                ..block(1)
            },
            AxisHoming {
                flags: 1 << 7,
                ..block(1)
            },
            AxisHoming {
                hard_stop_dwell: -1.0,
                ..block(1)
            },
        ];
        for b in bad {
            assert_eq!(ok(b), Err(NackCode::BadConfig), "{b:?}");
        }
        assert_eq!(
            ok(AxisHoming {
                accel: f64::NAN,
                ..block(1)
            }),
            Err(NackCode::NotFinite)
        );
        assert_eq!(
            ok(AxisHoming {
                jerk: 1e300,
                ..block(1)
            }),
            Err(NackCode::LimitRange)
        );
    }

    #[test]
    fn set_position_moves_the_frame_not_the_axis() {
        let mut axis = Axis::new();
        axis.sense(1_000, TS);
        assert_eq!(set_position(&mut axis, 5.0, false), Ok(()));
        assert_eq!(axis.actual().0, 5.0);
        assert!(axis.homed());
        axis.sense(1_003, TS);
        assert_eq!(axis.actual().0, 8.0);
        axis.power(true).unwrap();
        assert_eq!(set_position(&mut axis, -10.0, true), Ok(()));
        assert_eq!(axis.actual().0, -2.0);
        assert_eq!(axis.reference().pos, -2.0);
        assert_eq!(axis.status(0).encoder, 1_003);
        assert_eq!(
            set_position(&mut axis, f64::MAX, false),
            Err(NackCode::OutOfRange)
        );
    }
}

//! `CardSet` (cards on one sync bus, commands timed to one tick), `SyncScope` (the `with`
//! block of `CardSet.sync()`), `SetPath` (a path whose axes live on several cards of the set),
//! `PathSettings` and `SetPathProgress`.
use crate::card::{sim_options, Card};
use crate::errors::py;
use crate::group::Segment;
use crate::wait::wait_sliced;
use motioncard_sdk as sdk;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::sync::RwLock;
use std::time::Duration;

/// Cards on one sync bus, the first its master, driven as one: commands on several cards
/// timed to one tick (`with cards.sync(): ...`), a synchronised halt, hold and override,
/// paths across the cards.
#[pyclass(module = "motioncard", frozen)]
pub struct CardSet {
    set: sdk::CardSet,
    uris: Vec<String>,
}

fn with_margin(mut set: sdk::CardSet, margin: Option<f64>) -> PyResult<sdk::CardSet> {
    if let Some(m) = margin {
        let d = Duration::try_from_secs_f64(m)
            .map_err(|e| PyValueError::new_err(format!("margin {m}: {e}")))?;
        set.set_margin(d);
    }
    Ok(set)
}

#[pymethods]
impl CardSet {
    /// `n` emulated cards (1 to 16) in this process on one sync bus, the first the master.
    /// `clock` as `Card.open_sim`'s: with `"stepped"`, stepping or waiting on any card steps
    /// all of them, so their tick counters are always equal. `margin`: how far ahead (s)
    /// `sync()` times its commands (default 0.02).
    #[staticmethod]
    #[pyo3(signature = (n, *, clock = "stepped", axes = 8, servo_rate_hz = 10_000, margin = None))]
    fn sim(
        p: Python<'_>,
        n: usize,
        clock: &str,
        axes: usize,
        servo_rate_hz: u32,
        margin: Option<f64>,
    ) -> PyResult<CardSet> {
        let opts = sim_options(clock, axes, servo_rate_hz)?;
        let set = py(p.allow_threads(|| sdk::CardSet::sim(n, opts)))?;
        Ok(CardSet {
            set: with_margin(set, margin)?,
            uris: vec!["sim".into(); n],
        })
    }

    /// Open the cards of one bus by URI, the master first (`BadConfigError` unless every
    /// other card follows it, locked).
    #[staticmethod]
    #[pyo3(signature = (uris, *, margin = None))]
    fn open(p: Python<'_>, uris: Vec<String>, margin: Option<f64>) -> PyResult<CardSet> {
        let refs: Vec<&str> = uris.iter().map(String::as_str).collect();
        let set = py(p.allow_threads(|| sdk::CardSet::open(&refs)))?;
        Ok(CardSet {
            set: with_margin(set, margin)?,
            uris,
        })
    }

    /// The cards, the master first.
    #[getter]
    fn cards(&self) -> Vec<Card> {
        self.set
            .cards()
            .iter()
            .zip(&self.uris)
            .map(|(c, u)| Card {
                card: c.clone(),
                uri: u.clone(),
            })
            .collect()
    }

    fn __len__(&self) -> usize {
        self.set.cards().len()
    }

    /// The master's tick.
    fn tick(&self) -> PyResult<u64> {
        py(self.set.tick())
    }

    /// `with cards.sync() as s:` every command this thread sends in the block, to any card
    /// of the set, is timed to one tick (`s.tick`, a margin ahead) and held by its card;
    /// leaving the block commits them, and they run on that tick on every card, or on none
    /// (a refusal raises at once; leaving by an exception cancels them everywhere). Keep
    /// the scope on the thread that made it.
    fn sync(&self) -> PyResult<SyncScope> {
        let scope = py(self.set.begin())?;
        Ok(SyncScope {
            tick: scope.tick(),
            scope: Some(scope),
            committed: None,
        })
    }

    /// Halt every moving axis of every card on one tick (MC_Halt with `deceleration` and
    /// `jerk`, each in its axis's units): the tick.
    fn halt(&self, p: Python<'_>, deceleration: f64, jerk: f64) -> PyResult<u64> {
        py(p.allow_threads(|| self.set.halt(deceleration, jerk)))
    }

    /// Hold every moving axis of every card on one tick (override 0); `set_override` with a
    /// factor above 0 resumes them together. The tick.
    fn hold(&self, p: Python<'_>) -> PyResult<u64> {
        py(p.allow_threads(|| self.set.hold()))
    }

    /// The override of every moving axis of every card, on one tick: the tick.
    fn set_override(&self, p: Python<'_>, factor: f64) -> PyResult<u64> {
        py(p.allow_threads(|| self.set.set_override(factor)))
    }

    /// A path across the cards: `parts` are (card index, group index) pairs, each group
    /// configured over its axes and enabled, at rest; the path's dimensions are those
    /// groups' axes in order (1 to 16), `settings` gives their limits. Push segments with
    /// one target per dimension.
    fn path(
        &self,
        p: Python<'_>,
        parts: Vec<(usize, usize)>,
        settings: &PathSettings,
    ) -> PyResult<SetPath> {
        let parts: Vec<sdk::PathPart> = parts
            .into_iter()
            .map(|(card, group)| sdk::PathPart { card, group })
            .collect();
        let path = py(p.allow_threads(|| self.set.path(&parts, &settings.settings)))?;
        Ok(SetPath {
            path: RwLock::new(path),
        })
    }

    fn __repr__(&self) -> String {
        format!("<motioncard.CardSet of {} cards>", self.set.cards().len())
    }
}

/// Commands being timed to one tick on the cards of a set (`CardSet.sync()`): a context
/// manager; `commit()` or leaving the block runs them, `cancel()` or leaving it by an
/// exception drops them. Bound to the thread that made it.
#[pyclass(module = "motioncard", unsendable)]
pub struct SyncScope {
    scope: Option<sdk::SyncScope>,
    tick: u64,
    committed: Option<u64>,
}

#[pymethods]
impl SyncScope {
    /// The tick the commands run on.
    #[getter]
    fn tick(&self) -> u64 {
        self.tick
    }

    /// Whether the commands were committed (and ran).
    #[getter]
    fn committed(&self) -> bool {
        self.committed.is_some()
    }

    /// Commit: every command sent since `sync()` runs on the tick on every card; returns
    /// once all ran, with the tick (`CommitLateError`: too late, nothing ran anywhere).
    fn commit(&mut self) -> PyResult<u64> {
        let scope = self.scope.take().ok_or_else(|| {
            crate::errors::of_kind(
                sdk::ErrorKind::InvalidState,
                "the sync scope was committed or cancelled already".into(),
            )
        })?;
        // (not Send: it waits with the GIL held, for the margin's ticks at most)
        let t = py(scope.commit())?;
        self.committed = Some(t);
        Ok(t)
    }

    /// Drop the commands held: nothing of them runs on any card. Harmless after a commit.
    fn cancel(&mut self) {
        self.scope = None;
    }

    fn __enter__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    #[pyo3(signature = (exc_type, _exc = None, _tb = None))]
    fn __exit__(
        &mut self,
        exc_type: Option<&Bound<'_, PyAny>>,
        _exc: Option<&Bound<'_, PyAny>>,
        _tb: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<bool> {
        match exc_type {
            Some(t) if !t.is_none() => self.cancel(),
            _ => {
                if self.scope.is_some() {
                    self.commit()?;
                }
            }
        }
        Ok(false)
    }
}

/// The limits of a path across cards: each dimension's velocity, acceleration and jerk (in
/// its axis's units), the look-ahead, the tangential limits (the first dimension's units;
/// 0: from the axes) and the planner period (s; 0: the card's default).
#[pyclass(module = "motioncard", frozen)]
#[derive(Clone)]
pub struct PathSettings {
    settings: sdk::PathSettings,
}

#[pymethods]
impl PathSettings {
    #[new]
    #[pyo3(signature = (vmax, amax, jmax, *, lookahead = 256, accel = 0.0, jerk = 0.0, plan_period = 0.0))]
    fn new(
        vmax: Vec<f64>,
        amax: Vec<f64>,
        jmax: Vec<f64>,
        lookahead: usize,
        accel: f64,
        jerk: f64,
        plan_period: f64,
    ) -> Self {
        let mut s = sdk::PathSettings::uniform(vmax.len(), 0.0, 0.0, 0.0);
        s.vmax = vmax;
        s.amax = amax;
        s.jmax = jmax;
        s.lookahead = lookahead;
        s.accel = accel;
        s.jerk = jerk;
        s.plan_period = plan_period;
        PathSettings { settings: s }
    }

    /// `n` dimensions with the same limits.
    #[staticmethod]
    fn uniform(n: usize, velocity: f64, acceleration: f64, jerk: f64) -> Self {
        PathSettings {
            settings: sdk::PathSettings::uniform(n, velocity, acceleration, jerk),
        }
    }

    /// Each dimension's velocity limit.
    #[getter]
    fn vmax(&self) -> Vec<f64> {
        self.settings.vmax.clone()
    }

    /// Each dimension's acceleration limit.
    #[getter]
    fn amax(&self) -> Vec<f64> {
        self.settings.amax.clone()
    }

    /// Each dimension's jerk limit.
    #[getter]
    fn jmax(&self) -> Vec<f64> {
        self.settings.jmax.clone()
    }

    /// Look-ahead, segments.
    #[getter]
    fn lookahead(&self) -> usize {
        self.settings.lookahead
    }
}

/// Where a path across cards is: `staged` (pushed, not released), `queued` (released and
/// not finished, on the card that has the most), `done` (finished, on the card that has the
/// fewest).
#[pyclass(module = "motioncard", frozen, get_all)]
pub struct SetPathProgress {
    staged: usize,
    queued: usize,
    done: u32,
}

#[pymethods]
impl SetPathProgress {
    fn __repr__(&self) -> String {
        format!(
            "SetPathProgress(staged={}, queued={}, done={})",
            self.staged, self.queued, self.done
        )
    }
}

/// A path across the cards of a `CardSet` (`CardSet.path`): every card plans the same
/// profile from every segment and drives its own group's axes. `push` stages segments on
/// every card, `release` puts them into every card's path on one tick (the first release
/// starts it), `run` does both for a whole program.
#[pyclass(module = "motioncard", frozen)]
pub struct SetPath {
    path: RwLock<sdk::SetPath>,
}

impl SetPath {
    fn read(&self) -> std::sync::RwLockReadGuard<'_, sdk::SetPath> {
        self.path.read().unwrap_or_else(|e| e.into_inner())
    }

    fn write(&self) -> std::sync::RwLockWriteGuard<'_, sdk::SetPath> {
        self.path.write().unwrap_or_else(|e| e.into_inner())
    }
}

#[pymethods]
impl SetPath {
    /// Dimensions of the path.
    #[getter]
    fn dims(&self) -> usize {
        self.read().dims()
    }

    /// Stage `segment` on every card (a line with a target per dimension, an arc in
    /// dimensions 0 and 1 whose helix is the others, a dwell): refused by every card or none;
    /// `QueueFullError` once 256 are staged (`release` first).
    fn push(&self, p: Python<'_>, segment: &Segment) -> PyResult<()> {
        py(p.allow_threads(|| self.write().push(&segment.segment)))
    }

    /// Release everything staged into every card's path on one tick, once every path has
    /// room: the tick. The first release starts the path.
    fn release(&self, p: Python<'_>) -> PyResult<u64> {
        py(p.allow_threads(|| self.write().release()))
    }

    /// Push and release a whole program (in batches as the staging fills): the tick of the
    /// first release, the start.
    fn run(&self, p: Python<'_>, segments: Vec<Segment>) -> PyResult<u64> {
        let items: Vec<sdk::Segment> = segments.into_iter().map(|s| s.segment).collect();
        py(p.allow_threads(|| self.write().run(&items)))
    }

    /// How far the path has come.
    fn progress(&self) -> PyResult<SetPathProgress> {
        let pr = py(self.read().progress())?;
        Ok(SetPathProgress {
            staged: pr.staged,
            queued: pr.queued,
            done: pr.done,
        })
    }

    /// Wait until every card's path has run everything released and its group is at rest
    /// (`TimeoutError`; None: no end). A group that faults or stops on one card halts the
    /// others at once and raises `InvalidStateError`.
    #[pyo3(signature = (timeout = None))]
    fn wait(&self, p: Python<'_>, timeout: Option<f64>) -> PyResult<()> {
        wait_sliced(p, timeout, |s| self.read().wait(s))
    }

    /// Halt the path on every card on one tick within `deceleration` and `jerk` (the first
    /// dimension's units); what is staged is dropped. The tick.
    fn halt(&self, p: Python<'_>, deceleration: f64, jerk: f64) -> PyResult<u64> {
        py(p.allow_threads(|| self.write().halt(deceleration, jerk)))
    }

    /// Hold the path on every card on one tick (feed override 0); `set_override` above 0
    /// resumes it. The tick.
    fn hold(&self, p: Python<'_>) -> PyResult<u64> {
        py(p.allow_threads(|| self.read().hold()))
    }

    /// The feed override of every card's group, on one tick: the tick.
    fn set_override(&self, p: Python<'_>, factor: f64) -> PyResult<u64> {
        py(p.allow_threads(|| self.read().set_override(factor)))
    }

    /// Pause at the end of a segment on every card on one tick (`False`: go on). The tick.
    #[pyo3(signature = (on = true))]
    fn pause(&self, p: Python<'_>, on: bool) -> PyResult<u64> {
        py(p.allow_threads(|| self.read().pause(on)))
    }
}

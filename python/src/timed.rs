//! Commands timed to a tick on one card: `Card.timed(tick)`, a context manager (`TimedScope`)
//! like `CardSet.sync()`, and the commit and cancel of a key.
use crate::errors::py;
use motioncard_sdk as sdk;
use pyo3::prelude::*;

/// Commands this thread sends, to any card, timed to one tick (`Card.timed(tick, key=...)`):
/// each is checked and held by its card when sent (a refusal raises at once:
/// `TickPassedError`, `TickFarError`, `TimedFullError`, or the command's own error), and runs
/// as the first thing of that tick; a motion call returns its motion at once and the motion
/// starts on the tick. With a key, the commands run only once the key is committed: leaving
/// the block commits it (all of them run on the tick, or none), leaving it by an exception
/// cancels them. Without a key (0) each runs on the tick as it was held. Bound to the thread
/// that made it.
#[pyclass(module = "motioncard", unsendable)]
pub struct TimedScope {
    card: sdk::Card,
    at: sdk::Timing,
    scope: Option<sdk::TimingScope>,
    held: Option<sdk::TimedCommands>,
}

impl TimedScope {
    pub(crate) fn begin(card: &sdk::Card, tick: u64, key: u32) -> TimedScope {
        let at = sdk::Timing { tick, key };
        TimedScope {
            card: card.clone(),
            at,
            scope: Some(sdk::TimingScope::begin(at)),
            held: None,
        }
    }

    fn stop(&mut self) {
        if let Some(s) = self.scope.take() {
            self.held = Some(s.end());
        }
    }
}

#[pymethods]
impl TimedScope {
    /// The tick the commands run on.
    #[getter]
    fn tick(&self) -> u64 {
        self.at.tick
    }

    /// The key whose commit they wait for (0: none).
    #[getter]
    fn key(&self) -> u32 {
        self.at.key
    }

    /// The commands held so far (all of them once the timing ended).
    #[getter]
    fn held(&self) -> usize {
        self.held.as_ref().map_or(0, |h| h.len())
    }

    /// Whether the timing ended (commands sent now run at once again).
    #[getter]
    fn ended(&self) -> bool {
        self.scope.is_none()
    }

    /// End the timing: what this thread sends from now runs at once again. The commands held
    /// stay held (a key's until its commit). Harmless twice. How many were held.
    fn end(&mut self) -> usize {
        self.stop();
        self.held()
    }

    /// Wait for every held command's answer (they come on the tick): the first refusal (its
    /// error: `NotCommittedError` for a key never committed, `TimedCancelledError`), after all
    /// have answered; `TimeoutError` when `timeout` seconds pass first. Ends the timing.
    #[pyo3(signature = (timeout = 5.0))]
    fn wait(&mut self, p: Python<'_>, timeout: f64) -> PyResult<()> {
        self.stop();
        let t = crate::safety::seconds("timeout", timeout)?;
        match &self.held {
            Some(h) => py(p.allow_threads(|| h.wait(t))),
            None => Ok(()),
        }
    }

    fn __enter__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    #[pyo3(signature = (exc_type, _exc = None, _tb = None))]
    fn __exit__(
        &mut self,
        p: Python<'_>,
        exc_type: Option<&Bound<'_, PyAny>>,
        _exc: Option<&Bound<'_, PyAny>>,
        _tb: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<bool> {
        let failed = exc_type.is_some_and(|t| !t.is_none());
        let was_open = self.scope.is_some();
        self.stop();
        let (card, at) = (&self.card, self.at);
        if at.key != 0 && was_open {
            if failed {
                // the exception goes on; a cancel that fails adds nothing to it
                let _ = p.allow_threads(|| card.cancel_timed(at.key));
            } else {
                py(p.allow_threads(|| card.sync_commit(at.key, at.tick)))?;
            }
        }
        Ok(false)
    }

    fn __repr__(&self) -> String {
        format!(
            "<motioncard.TimedScope tick={} key={} held={}>",
            self.at.tick,
            self.at.key,
            self.held()
        )
    }
}

//! The step test and the move test on a card: arm a one-shot scope capture of the axis's
//! commanded position, actual position, following error and DAC (every servo tick, with
//! [`PRE_TRIGGER`] samples from before the command), run the motion, capture until the
//! motion is done and a tail after it, then measure the capture ([`super::figures`]).
//!
//! - The step test: the commanded position jumps by the step. The card has no step command;
//!   it gets a relative move with the largest limits it accepts
//!   ([`card_emu::limit_range`]: the whole position range in one servo tick), which its
//!   planner finishes within one tick, as a step on a real card is made.
//! - The move test: an S-curve of the distance within the limits given.
//!
//! Both start from Standstill (optionally powering the axis on first) and leave the axis
//! where the motion ended. The capture ends [`TAIL_MIN`] (or half the motion's time, if
//! longer) after the card reports the motion done (in position), or after [`MAX_CAPTURE`].

use super::{figures, Band, Figures, Response};
use crate::{
    AxisState, Card, Edge, Error, MoveLimits, Scope, ScopeMode, ScopeSample, ScopeSettings,
    ScopeTrigger, Signal, Source,
};
use serde::{Deserialize, Serialize};
use std::time::{Duration, Instant};

/// Samples kept from before the command.
pub const PRE_TRIGGER: u32 = 200;
/// The longest capture, s of card time (at one sample per tick).
pub const MAX_CAPTURE: f64 = 5.0;
/// The shortest capture after the motion is done, s.
pub const TAIL_MIN: f64 = 0.05;
/// What a test samples, in this order.
pub const CHANNELS: [Signal; 4] = [Signal::CmdPos, Signal::ActPos, Signal::Ferr, Signal::Dac];

/// Which test.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TestKind {
    /// The commanded position jumps by the distance.
    Step,
    /// An S-curve move by the distance.
    Move,
}

/// Kinematic limits, counts and seconds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Limits {
    /// Velocity, counts/s.
    pub vmax: f64,
    /// Acceleration and deceleration, counts/s².
    pub amax: f64,
    /// Jerk, counts/s³.
    pub jmax: f64,
}

impl Default for Limits {
    /// The card's default per-axis limits for the default motor (`mc_group_path`'s reset
    /// values): 10⁵ counts/s, 10⁶ counts/s², 10⁸ counts/s³.
    fn default() -> Self {
        Self {
            vmax: 1e5,
            amax: 1e6,
            jmax: 1e8,
        }
    }
}

/// A test to run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TestSpec {
    /// Step or move.
    pub kind: TestKind,
    /// The axis.
    pub axis: usize,
    /// The step or the move's distance, counts (signed).
    pub distance: f64,
    /// The move's limits (a step uses the card's largest).
    pub limits: Limits,
    /// Power the axis on first if it is disabled.
    pub enable: bool,
}

/// The captured channels, one entry per servo tick.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Samples {
    /// The sample's servo tick.
    pub tick: Vec<u64>,
    /// Seconds from the command's start (the first sample whose command moved).
    pub t: Vec<f64>,
    /// Commanded position, counts.
    pub cmd: Vec<f64>,
    /// Actual position, counts.
    pub act: Vec<f64>,
    /// Following error, counts.
    pub ferr: Vec<f64>,
    /// DAC output, V.
    pub dac: Vec<f64>,
}

impl Samples {
    /// The capture as [`figures`] takes it.
    pub fn response(&self) -> Response<'_> {
        Response {
            t: &self.t,
            cmd: &self.cmd,
            act: &self.act,
            ferr: &self.ferr,
        }
    }
}

/// A finished test: what was asked, what the card did, and the figures.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TestRun {
    /// Step or move.
    pub kind: TestKind,
    /// The axis.
    pub axis: usize,
    /// The step or distance, counts.
    pub distance: f64,
    /// The limits the motion was sent with, counts and seconds.
    pub limits: Limits,
    /// The card's servo rate (samples per second).
    pub servo_rate_hz: u32,
    /// The tick of the capture's trigger sample.
    pub trigger_tick: u64,
    /// The tick of the command's start (t = 0).
    pub start_tick: u64,
    /// Whether the card reported the motion done (in position) during the capture.
    pub in_position: bool,
    /// What the card said about the motion: "in position", or its error.
    pub outcome: String,
    /// The axis's state at the end.
    pub end_state: String,
    /// The figures.
    pub figures: Figures,
    /// The samples.
    pub samples: Samples,
}

/// Why a test did not run or could not be measured.
#[derive(Debug)]
pub enum TestError {
    /// The request itself is wrong (a distance of 0, limits not positive, a move longer
    /// than a capture).
    Request(String),
    /// The axis is not ready (not at rest, disabled) or the scope is in use.
    NotReady(String),
    /// The card refused or failed (the SDK's error).
    Card(Error),
    /// The card ended the motion before it was done (a safety stop: a following error beyond
    /// its limit, a limit switch), leaving nothing to measure.
    Aborted(String),
    /// The capture cannot be measured.
    Capture(String),
}

impl std::fmt::Display for TestError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TestError::Request(s)
            | TestError::NotReady(s)
            | TestError::Capture(s)
            | TestError::Aborted(s) => f.write_str(s),
            TestError::Card(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for TestError {}

impl From<Error> for TestError {
    fn from(e: Error) -> Self {
        TestError::Card(e)
    }
}

/// Counts per user unit of `axis` on this host: positions and limits go to the SDK in user
/// units, the scope and the status's raw words are counts (the scale the card keeps for its
/// hosts, which this host adopted on open).
fn counts_per_unit(axis: &crate::Axis) -> f64 {
    axis.scale_factor()
}

/// The largest limits the card accepts at `rate_hz` (half its bound, clear of rounding when
/// the SDK scales them), counts and seconds.
pub fn step_limits(rate_hz: u32) -> Limits {
    let top = |order| 0.5 * *card_emu::limit_range(order, rate_hz).end();
    Limits {
        vmax: top(1),
        amax: top(2),
        jmax: top(3),
    }
}

/// Let `d` pass on the card: a stepped card is stepped, a real one given the time.
fn pass(card: &Card, d: Duration) {
    match card.sim() {
        Some(sim) => {
            sim.step((d.as_secs_f64() * card.info().servo_rate_hz as f64).ceil() as u64);
        }
        None => std::thread::sleep(d),
    }
}

/// Let `n` servo ticks pass on the card: stepped on a stepped card, waited for (by its tick
/// counter, up to 10 s of wall clock) on a running one.
fn pass_ticks(card: &Card, n: u64) -> crate::Result<()> {
    if let Some(sim) = card.sim() {
        sim.step(n);
        return Ok(());
    }
    let (t0, wall) = (card.tick()?, Instant::now());
    while card.tick()?.wrapping_sub(t0) < n && wall.elapsed() < Duration::from_secs(10) {
        std::thread::sleep(Duration::from_millis(1));
    }
    Ok(())
}

/// Stops an armed capture when the test leaves early (an error), so the scope is free again.
struct Armed<'a>(Option<&'a Scope>);

impl Armed<'_> {
    fn stop(mut self) -> crate::Result<()> {
        match self.0.take() {
            Some(s) => s.stop(),
            None => Ok(()),
        }
    }
}

impl Drop for Armed<'_> {
    fn drop(&mut self) {
        if let Some(s) = self.0.take() {
            let _ = s.stop();
        }
    }
}

impl TestSpec {
    fn check(&self, rate_hz: u32) -> Result<(), TestError> {
        let d = self.distance;
        if !d.is_finite() || d == 0.0 {
            return Err(TestError::Request(format!(
                "the {} must be a finite number of counts other than 0, got {d}",
                self.what()
            )));
        }
        if d.abs() > card_emu::MAX_POSITION {
            return Err(TestError::Request(format!(
                "the {} must be at most {} counts, got {d}",
                self.what(),
                card_emu::MAX_POSITION
            )));
        }
        if self.kind == TestKind::Move {
            let l = &self.limits;
            for (what, v, order) in [
                ("vmax", l.vmax, 1),
                ("amax", l.amax, 2),
                ("jmax", l.jmax, 3),
            ] {
                let range = card_emu::limit_range(order, rate_hz);
                if !range.contains(&v) {
                    return Err(TestError::Request(format!(
                        "{what} must be between {:e} and {:e} at {rate_hz} Hz, got {v}",
                        range.start(),
                        range.end()
                    )));
                }
            }
            let lim = crate::plan::Limits::symmetric(l.vmax, l.amax, l.jmax);
            let p = crate::plan::Profile::plan(0.0, d.abs(), 0.0, 0.0, &lim)
                .map_err(|e| TestError::Request(format!("no S-curve for this move: {e}")))?;
            let longest = MAX_CAPTURE - TAIL_MIN - f64::from(PRE_TRIGGER) / f64::from(rate_hz);
            if p.duration() > longest {
                return Err(TestError::Request(format!(
                    "the move takes {:.3} s; a test captures at most {MAX_CAPTURE} s at one \
                     sample per servo tick: shorten it to {longest:.3} s or less",
                    p.duration()
                )));
            }
        }
        Ok(())
    }

    fn what(&self) -> &'static str {
        match self.kind {
            TestKind::Step => "step",
            TestKind::Move => "distance",
        }
    }
}

/// The axis's state, with the reason of its last stop when the safety layer made it
/// ("ErrorStop (FollowingError)").
pub fn state_name(axis: &crate::Axis) -> crate::Result<String> {
    let s = axis.status()?;
    Ok(match s.stop_reason() {
        Some(r) if s.state == AxisState::ErrorStop => format!("{:?} ({r:?})", s.state),
        _ => format!("{:?}", s.state),
    })
}

/// Get the axis to Standstill for a test (or a sweep, [`super::sweep`]): power it on when it is
/// disabled and `enable`.
pub(crate) fn ready(card: &Card, axis: &crate::Axis, enable: bool) -> Result<(), TestError> {
    let s = axis.status()?;
    let n = axis.index();
    match s.state {
        AxisState::Standstill => return Ok(()),
        AxisState::Disabled if enable => axis.enable()?,
        AxisState::Disabled => {
            return Err(TestError::NotReady(format!(
                "axis {n} is disabled: power it on first"
            )))
        }
        AxisState::ErrorStop => {
            return Err(TestError::NotReady(format!(
                "axis {n} is in {}: reset it (MC_Reset) first; a test starts from Standstill",
                state_name(axis)?
            )))
        }
        other => {
            return Err(TestError::NotReady(format!(
                "axis {n} is in {other:?}: a test starts from Standstill"
            )))
        }
    }
    // The status shows the new state at the end of the tick that served the command.
    for _ in 0..1000 {
        let st = axis.status()?.state;
        if st == AxisState::Standstill {
            return Ok(());
        }
        if st != AxisState::Disabled {
            break;
        }
        pass(card, Duration::from_millis(1));
    }
    Err(TestError::NotReady(format!(
        "axis {n} did not come to Standstill after power on (it is in {:?})",
        axis.status()?.state
    )))
}

/// Run the test; see the [module](self).
pub fn run_test(card: &Card, scope: &Scope, spec: &TestSpec) -> Result<TestRun, TestError> {
    let rate_hz = card.info().servo_rate_hz;
    let rate = f64::from(rate_hz);
    spec.check(rate_hz)?;
    let ax = card.axis(spec.axis)?;
    ready(card, &ax, spec.enable)?;
    let p0 = ax.status()?.raw.cmd_pos;
    let d = spec.distance;
    let limits = match spec.kind {
        TestKind::Step => step_limits(rate_hz),
        TestKind::Move => spec.limits,
    };
    // Triggered as the command leaves p0 (a step: on its first tick; an S-curve: once it
    // has moved half a count, a few ms in): the pre-trigger samples hold the start.
    let level = p0 + d.signum() * (0.5_f64).min(d.abs() / 4.0);
    let settings = ScopeSettings {
        channels: CHANNELS
            .iter()
            .map(|&s| Source::axis(s, spec.axis))
            .collect(),
        divider: 1,
        trigger: ScopeTrigger::Level {
            channel: 0,
            level,
            edge: if d > 0.0 { Edge::Rising } else { Edge::Falling },
        },
        pre_trigger: PRE_TRIGGER,
        mode: ScopeMode::OneShot,
        post_trigger: (MAX_CAPTURE * rate) as u32,
    };
    scope.configure(&settings).map_err(|e| match e.kind() {
        crate::ErrorKind::ScopeState => TestError::NotReady(format!(
            "the card's scope is in use (armed by another host?): {e}"
        )),
        _ => TestError::Card(e),
    })?;
    scope.arm()?;
    let armed = Armed(Some(scope));
    // Let the history fill before the motion starts: counted in the card's own ticks (an
    // emulated card on a loaded machine runs behind the wall clock), plus a margin.
    pass_ticks(card, u64::from(PRE_TRIGGER) + u64::from(PRE_TRIGGER) / 2)?;
    let s = counts_per_unit(&ax);
    let lim = MoveLimits::new(
        limits.vmax / s.abs(),
        limits.amax / s.abs(),
        limits.jmax / s.abs(),
    );
    let motion = ax.move_relative(d / s, &lim)?;
    let mut raw: Vec<ScopeSample> = Vec::new();
    let wall = Instant::now();
    let wall_limit = Duration::from_secs_f64(MAX_CAPTURE + 10.0);
    let (mut done_tick, mut outcome) = (None::<u64>, None::<String>);
    let mut start_tick = None::<u64>;
    loop {
        scope.read(&mut raw)?;
        if start_tick.is_none() {
            start_tick = raw
                .first()
                .and_then(|f| raw.iter().find(|x| x.value[0] != f.value[0]))
                .map(|x| x.tick);
        }
        let st = scope.status()?;
        if !matches!(
            st.state,
            crate::ScopeState::Waiting | crate::ScopeState::Capturing
        ) {
            break; // the capture is full (MAX_CAPTURE)
        }
        match done_tick {
            None => match motion.wait(Duration::from_millis(5)) {
                Ok(_) => {
                    done_tick = Some(card.tick()?);
                    outcome = Some("in position".into());
                }
                Err(Error::Timeout(_)) => {}
                Err(e) => {
                    done_tick = Some(card.tick()?);
                    outcome = Some(e.to_string());
                }
            },
            Some(done) => {
                let began = start_tick.unwrap_or(done);
                let tail = (TAIL_MIN * rate).max(0.5 * done.saturating_sub(began) as f64);
                if card.tick()? as f64 >= done as f64 + tail {
                    break;
                }
                pass(card, Duration::from_millis(5));
            }
        }
        if wall.elapsed() > wall_limit {
            return Err(TestError::Capture(format!(
                "the capture did not end within {wall_limit:?} (the card's scope is in {:?})",
                st.state
            )));
        }
    }
    armed.stop()?;
    scope.read(&mut raw)?;
    let st = scope.status()?;
    if st.lost > 0 {
        return Err(TestError::Capture(format!(
            "the scope lost {} samples (this host read its ring too slowly): the figures \
             would be wrong; run the test again",
            st.lost
        )));
    }
    if raw.is_empty() {
        return Err(TestError::Capture(format!(
            "the scope never triggered: the commanded position did not cross {level} ({})",
            outcome.as_deref().unwrap_or("the motion did not finish")
        )));
    }
    if let Some(w) = raw.windows(2).find(|w| w[1].tick != w[0].tick + 1) {
        return Err(TestError::Capture(format!(
            "the capture has a gap from tick {} to {}",
            w[0].tick, w[1].tick
        )));
    }
    let start_tick = raw
        .iter()
        .find(|x| x.value[0] != raw[0].value[0])
        .map(|x| x.tick)
        .ok_or_else(|| {
            TestError::Capture("the commanded position did not move during the capture".into())
        })?;
    let col = |k: usize| raw.iter().map(|x| x.value[k]).collect::<Vec<f64>>();
    let samples = Samples {
        tick: raw.iter().map(|x| x.tick).collect(),
        t: raw
            .iter()
            .map(|x| (x.tick as f64 - start_tick as f64) / rate)
            .collect(),
        cmd: col(0),
        act: col(1),
        ferr: col(2),
        dac: col(3),
    };
    let end_state = state_name(&ax)?;
    let figures = figures(&samples.response(), Band::default()).map_err(|e| {
        match outcome.as_deref() {
            // The card ended the motion (a trip, a stop): that is the news, not the figures.
            Some(o) if o != "in position" => TestError::Aborted(format!(
                "the {} did not finish: {o}; axis {} is in {end_state}",
                spec.what(),
                spec.axis
            )),
            _ => TestError::Capture(e.to_string()),
        }
    })?;
    Ok(TestRun {
        kind: spec.kind,
        axis: spec.axis,
        distance: d,
        limits,
        servo_rate_hz: rate_hz,
        trigger_tick: st.trigger_tick,
        start_tick,
        in_position: outcome.as_deref() == Some("in position"),
        outcome: outcome
            .unwrap_or_else(|| format!("not in position after {MAX_CAPTURE} s of capture")),
        end_state,
        figures,
        samples,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stepped() -> Card {
        Card::open_sim(crate::SimOptions {
            clock: crate::Clock::Stepped,
            emu: Default::default(),
        })
        .unwrap()
    }

    fn spec(kind: TestKind, distance: f64) -> TestSpec {
        TestSpec {
            kind,
            axis: 0,
            distance,
            limits: Limits::default(),
            enable: true,
        }
    }

    #[test]
    fn a_step_jumps_in_one_tick_and_settles_on_the_default_axis() {
        let card = stepped();
        let scope = card.scope();
        let r = run_test(&card, &scope, &spec(TestKind::Step, 500.0)).unwrap();
        let f = &r.figures;
        let s = &r.samples;
        assert!(r.in_position, "{}", r.outcome);
        assert_eq!(r.end_state, "Standstill");
        // The command: p0 up to the start, p0 + 500 from the first moved sample on.
        assert_eq!(f.step, 500.0);
        assert_eq!(s.cmd[f.start_index], f.target, "one tick");
        assert_eq!(f.start_time, 0.0);
        assert!(
            f.start_index >= PRE_TRIGGER as usize - 1,
            "{}",
            f.start_index
        );
        // One sample per tick, no gap.
        assert!(s.tick.windows(2).all(|w| w[1] == w[0] + 1));
        assert!(s.t.windows(2).all(|w| (w[1] - w[0] - 1e-4).abs() < 1e-12));
        // The figures of the samples the run returned.
        assert_eq!(*f, figures(&s.response(), Band::default()).unwrap());
        // At the command's first tick the whole step is following error.
        assert!(f.peak_following_error >= 490.0, "{f:?}");
        assert!((f.final_actual - f.target).abs() <= f.band, "{f:?}");
        let (rise, settle) = (f.rise_time.unwrap(), f.settling_time.unwrap());
        assert!(rise > 0.0 && rise < settle, "{f:?}");
        assert!(settle < 0.1, "{f:?}");
        // The actual reaches the target within 1 count; the card's status agrees.
        let st = card.axis(0).unwrap().status().unwrap();
        assert_eq!(st.raw.cmd_pos, f.target);
        assert!((st.raw.act_pos - f.target).abs() <= 1.0);
        // The scope is free for the next test, which starts from where this one ended.
        let back = run_test(&card, &scope, &spec(TestKind::Step, -500.0)).unwrap();
        assert_eq!(back.figures.start, f.target);
        assert_eq!(back.figures.target, f.start);
        // Down as up, within the asymmetry Coulomb friction and the integrator give it.
        assert!(
            (back.figures.rise_time.unwrap() - rise).abs() < 1e-3,
            "{:?}",
            back.figures
        );
    }

    #[test]
    fn a_move_follows_its_s_curve_with_a_small_following_error() {
        let card = stepped();
        let scope = card.scope();
        let r = run_test(&card, &scope, &spec(TestKind::Move, 20_000.0)).unwrap();
        let f = &r.figures;
        assert!(r.in_position, "{}", r.outcome);
        assert_eq!(f.step, 20_000.0);
        // The planned duration: the command's end within a tick of the plan.
        let lim = crate::plan::Limits::symmetric(1e5, 1e6, 1e8);
        let plan = crate::plan::Profile::plan(0.0, 20_000.0, 0.0, 0.0, &lim).unwrap();
        assert!(
            (f.command_end_time - plan.duration()).abs() <= 2e-4,
            "{} vs {}",
            f.command_end_time,
            plan.duration()
        );
        // The default tuning follows within a couple of counts (README: 1.2 at most).
        assert!(f.peak_following_error < 2.0, "{f:?}");
        assert!(f.overshoot_pct < 0.05, "{f:?}");
        assert!(f.settling_time.unwrap() < plan.duration() + 0.01, "{f:?}");
    }

    #[test]
    fn distances_and_limits_are_counts_whatever_the_axis_scale() {
        let card = stepped();
        card.axis(0).unwrap().set_scale(-4.0).unwrap(); // counts per user unit, reversed
        let scope = card.scope();
        let r = run_test(&card, &scope, &spec(TestKind::Step, 300.0)).unwrap();
        assert_eq!(r.figures.step, 300.0);
        assert_eq!(card.axis(0).unwrap().status().unwrap().raw.cmd_pos, 300.0);
        let r = run_test(&card, &scope, &spec(TestKind::Move, -8000.0)).unwrap();
        assert_eq!(r.figures.target, -7700.0);
        let plan = crate::plan::Profile::plan(
            0.0,
            8000.0,
            0.0,
            0.0,
            &crate::plan::Limits::symmetric(1e5, 1e6, 1e8),
        )
        .unwrap();
        assert!((r.figures.command_end_time - plan.duration()).abs() <= 2e-4);
    }

    #[test]
    fn a_step_beyond_the_following_error_limit_is_reported_as_the_cards_trip() {
        let card = stepped();
        let scope = card.scope();
        // MIN_FERROR is 1000 counts: the step's first tick trips it.
        let e = run_test(&card, &scope, &spec(TestKind::Step, 2000.0)).unwrap_err();
        assert!(
            matches!(&e, TestError::Aborted(m) if m.contains("ErrorStop (FollowingError)")),
            "{e}"
        );
        let e = run_test(&card, &scope, &spec(TestKind::Step, 100.0)).unwrap_err();
        assert!(
            matches!(&e, TestError::NotReady(m) if m.contains("reset it")),
            "{e}"
        );
        // The scope was left free, and after MC_Reset the next test runs.
        card.axis(0).unwrap().reset().unwrap();
        card.sim().unwrap().step(10);
        let r = run_test(&card, &scope, &spec(TestKind::Step, 100.0)).unwrap();
        assert!(r.in_position, "{}", r.outcome);
    }

    #[test]
    fn bad_requests_and_unready_axes_are_refused_with_the_reason() {
        let card = stepped();
        let scope = card.scope();
        for (kind, d, lim, why) in [
            (TestKind::Step, 0.0, Limits::default(), "other than 0"),
            (TestKind::Step, f64::NAN, Limits::default(), "finite"),
            (
                TestKind::Move,
                100.0,
                Limits {
                    vmax: -1.0,
                    ..Limits::default()
                },
                "vmax must be between",
            ),
            (TestKind::Move, 1e7, Limits::default(), "the move takes"),
        ] {
            let e = run_test(
                &card,
                &scope,
                &TestSpec {
                    limits: lim,
                    ..spec(kind, d)
                },
            )
            .unwrap_err();
            assert!(
                matches!(&e, TestError::Request(m) if m.contains(why)),
                "{e}"
            );
        }
        let e = run_test(
            &card,
            &scope,
            &TestSpec {
                enable: false,
                ..spec(TestKind::Step, 10.0)
            },
        )
        .unwrap_err();
        assert!(
            matches!(&e, TestError::NotReady(m) if m.contains("disabled")),
            "{e}"
        );
        // A test on an axis the card has not.
        let e = run_test(
            &card,
            &scope,
            &TestSpec {
                axis: 99,
                ..spec(TestKind::Step, 10.0)
            },
        )
        .unwrap_err();
        assert!(
            matches!(&e, TestError::Card(e) if e.kind() == crate::ErrorKind::BadAxis),
            "{e}"
        );
    }
}

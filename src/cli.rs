//! `mcctl`'s subcommands, one module each: its arguments (a clap `Args` struct) and `run`,
//! which checks what clap cannot, opens the card when it needs one (`--card URI`), does the
//! work and gives the exit status. What they share is here: opening and closing the card around
//! a subcommand ([`on_card`]), the exit statuses, and the waits with their progress bar; the
//! argument groups and range-checking value parsers are in [`args`].
//!
//! Exit status: 0 done; 1 the card (or the SDK) refused or failed, with its message; 2 a bad
//! argument (clap's own refusals too); 128 + N when signal N ended it (see [`interrupt`]).
//! What a subcommand prints is a table, or one JSON object with `--json`.

use crate::proto::raw;
use crate::{AxisState, Card, Error, Motion, Result};
use std::process::ExitCode;
use std::time::{Duration, Instant};

pub mod args;
pub mod cam;
pub mod comp;
pub mod compare;
pub mod config;
pub mod freq;
pub mod gantry;
pub mod gcode;
pub mod gear;
pub mod group;
pub mod halt;
pub mod handwheel;
pub mod home;
pub mod info;
pub mod interrupt;
pub mod io;
pub mod jog;
pub mod list;
pub mod machine;
pub mod moves;
pub mod path_set;
pub mod plan;
pub mod power;
pub mod probe;
pub mod pvt;
pub mod replay;
pub mod reset;
pub mod rows;
pub mod run;
pub mod scope;
pub mod serve;
pub mod set_override;
pub mod status;
pub mod stop;

/// Groups on every card.
pub(crate) const MAX_GROUPS: usize = raw::MC_MAX_GROUPS as usize;

/// How long mcctl waits for a move to be done.
pub(crate) const WAIT: Duration = Duration::from_secs(600);

/// How often mcctl looks at the card while a move runs.
pub(crate) const POLL: Duration = Duration::from_millis(2);

/// A progress bar of `len` steps (a spinner without) on stderr, for what takes a while. It is
/// drawn only on a terminal (indicatif hides it when stderr is not one), so a script, a pipe or
/// `--json` output on stdout sees only the result.
pub fn progress(len: Option<u64>, what: &str) -> indicatif::ProgressBar {
    let (bar, template) = match len {
        Some(n) => (
            indicatif::ProgressBar::new(n),
            "{prefix} {bar:20} {pos}/{len} {msg}",
        ),
        None => (
            indicatif::ProgressBar::new_spinner(),
            "{prefix} {spinner} {msg}",
        ),
    };
    if let Ok(style) = indicatif::ProgressStyle::with_template(template) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.with_prefix(what.to_string())
}

/// Show the axis's state and actual position on `bar` (when it is drawn at all).
pub(crate) fn show_axis(card: &Card, axis: usize, bar: &indicatif::ProgressBar) -> Result<()> {
    if !bar.is_hidden() {
        let s = card.axis(axis)?.status()?;
        bar.set_message(format!(
            "axis {axis} {} at {:.3}",
            state_name(s.state),
            s.actual_position
        ));
        bar.tick();
    }
    Ok(())
}

/// Wait up to `WAIT` for `motion` of `axis` to be done, with a spinner showing where the
/// axis is (see [`progress`]). Returns where it ended.
pub fn wait_showing(card: &Card, axis: usize, motion: &Motion, what: &str) -> Result<f64> {
    let bar = progress(None, what);
    let start = Instant::now();
    let r = loop {
        match motion.wait(POLL) {
            Err(Error::Timeout(_)) if start.elapsed() < WAIT => {}
            Err(Error::Timeout(_)) => break Err(Error::Timeout(WAIT)),
            r => break r,
        }
        if let Err(e) = interrupt::check().and_then(|()| show_axis(card, axis, &bar)) {
            break Err(e);
        }
    };
    bar.finish_and_clear();
    r
}

/// Wait up to `limit` for what `wait` waits on (called with the time it may block). A stepped
/// card is stepped a hundredth of a second at a time while it is not done (Ctrl-C stops it);
/// a running one is waited on directly.
pub(crate) fn wait_stepping<T>(
    card: &Card,
    limit: Duration,
    mut wait: impl FnMut(Duration) -> Result<T>,
) -> Result<T> {
    let Some(sim) = card.sim() else {
        return wait(limit);
    };
    let rate = u64::from(card.info().servo_rate_hz);
    let mut waited = 0;
    loop {
        match wait(Duration::ZERO) {
            Err(Error::Timeout(_)) if waited < limit.as_secs() * rate => {
                sim.step(rate / 100);
                waited += rate / 100;
                interrupt::check()?;
            }
            r => return r,
        }
    }
}

pub(crate) fn state_name(s: AxisState) -> String {
    format!("{s:?}")
}

/// The axis's state once the card has published the effect of a command just acknowledged:
/// the ack comes within the tick, its status at the tick's end, so the first read may still
/// show the state before. Waits (up to a second) while `before` says it is the old one.
pub(crate) fn state_after(
    card: &Card,
    axis: usize,
    before: impl Fn(AxisState) -> bool,
) -> Result<AxisState> {
    let ax = card.axis(axis)?;
    for _ in 0..1000 {
        let s = ax.status()?.state;
        if !before(s) {
            return Ok(s);
        }
        hold_for(card, Duration::from_millis(1));
    }
    Ok(ax.status()?.state)
}

/// Power the axis on if it is disabled (`--enable`).
pub fn enable_if_needed(card: &Card, axis: usize) -> Result<()> {
    let ax = card.axis(axis)?;
    if ax.status()?.state == AxisState::Disabled {
        ax.enable()?;
    }
    Ok(())
}

/// Let `d` pass on the card: a stepped card's time moves only when asked, a real one's on its
/// own. A signal ([`interrupt`]) ends the wait early.
pub(crate) fn hold_for(card: &Card, d: Duration) {
    match card.sim() {
        Some(sim) => sim.step((d.as_secs_f64() * card.info().servo_rate_hz as f64).round() as u64),
        None => {
            let end = Instant::now() + d;
            while interrupt::signal().is_none() {
                let left = end.saturating_duration_since(Instant::now());
                if left.is_zero() {
                    break;
                }
                std::thread::sleep(left.min(Duration::from_millis(10)));
            }
        }
    }
}

/// [`hold_for`] `d` in steps of [`POLL`], with a bar of the time held and where the axis is.
pub(crate) fn hold_showing(card: &Card, axis: usize, d: Duration, what: &str) -> Result<()> {
    let bar = progress(Some(d.as_millis() as u64), what);
    bar.set_prefix(format!("{what} (ms)"));
    let mut held = Duration::ZERO;
    while held < d {
        let step = POLL.min(d - held);
        hold_for(card, step);
        interrupt::check()?;
        held += step;
        bar.set_position(held.as_millis() as u64);
        show_axis(card, axis, &bar)?;
    }
    bar.finish_and_clear();
    Ok(())
}

/// Open the card, run `f` on it and close it. A signal (SIGINT, SIGTERM, SIGHUP: see
/// [`interrupt`]) ends `f`'s waits; the close then ends the session cleanly, and the card
/// halts what mcctl started.
pub fn with_card<T>(uri: &str, f: impl FnOnce(&Card) -> Result<T>) -> Result<T> {
    let card = Card::open(uri)?;
    interrupt::watch(Some(&card));
    let out = match interrupt::check() {
        Ok(()) => f(&card),
        Err(e) => Err(e), // the signal came while the card was being opened
    };
    let closed = card.close();
    interrupt::watch(None);
    out.and_then(|o| closed.map(|()| o))
}

/// mcctl was interrupted by a signal: it closed the card (or never opened it) and says so;
/// the exit status is 128 + the signal's number, as a shell reports a process the signal
/// ended.
pub fn interrupted() -> Option<ExitCode> {
    let s = interrupt::signal()?;
    eprintln!("mcctl: {s}: stopped; the card halted what mcctl started and the session closed");
    Some(ExitCode::from(128u8.wrapping_add(s as i32 as u8)))
}

/// A subcommand that talks to the card: exit status 1 with the SDK's message on an error.
pub fn on_card(uri: &str, f: impl FnOnce(&Card) -> Result<String>) -> ExitCode {
    let r = with_card(uri, f);
    if let Some(code) = interrupted() {
        return code;
    }
    match r {
        Ok(text) => {
            print!("{text}");
            if !text.is_empty() && !text.ends_with('\n') {
                println!();
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("mcctl: {e}");
            ExitCode::from(1)
        }
    }
}

/// A bad argument: the message on stderr, exit status 2.
pub fn bad(msg: String) -> ExitCode {
    eprintln!("mcctl: {msg}");
    ExitCode::from(2)
}

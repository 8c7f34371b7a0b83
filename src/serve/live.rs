//! The live plots' stream: one thread that runs the card's scope continuously on the served
//! axis (commanded and actual position, following error, DAC) while someone watches, drains
//! its ring, decimates the samples for display and broadcasts them to every page
//! ([`LiveMsg`]).
//!
//! A test needs the scope for its own capture: [`Live::pause`] has the thread stop the
//! continuous capture and hands back a [`Lease`]; the stream resumes when the lease is
//! dropped, whatever way the test ended. The thread holds its state lock only while it talks
//! to the card (a command and a ring drain, milliseconds), never while it sleeps, and a pause
//! waits for it at most [`PAUSE_WAIT`].
//!
//! Decimation: the card samples every `divider` ticks for about [`CARD_HZ`] samples a second;
//! the host makes one display point of every [`GROUP`] samples: the group's last tick,
//! commanded and actual position, and its following error and DAC of the largest magnitude,
//! so a spike between two display points is never hidden.

use crate::{Card, Scope, ScopeMode, ScopeSample, ScopeSettings, ScopeTrigger, Signal, Source};
use serde::Serialize;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};
use tokio::sync::broadcast;

/// Samples per second the card's scope takes for the live plots (at most; the divider is a
/// whole number of ticks).
pub const CARD_HZ: u32 = 1000;
/// Card samples per display point.
pub const GROUP: usize = 5;
/// How often the ring is drained and a batch sent.
pub const PERIOD: Duration = Duration::from_millis(40);
/// The longest a test waits for the stream to let the scope go.
pub const PAUSE_WAIT: Duration = Duration::from_secs(3);
/// After a failure (the scope in use, the card not answering), the stream tries again after
/// this.
const RETRY: Duration = Duration::from_secs(1);
/// The live channels, in [`Batch`] order.
const CHANNELS: [Signal; 4] = [Signal::CmdPos, Signal::ActPos, Signal::Ferr, Signal::Dac];

/// What the stream sends to the pages.
#[derive(Debug, Clone, PartialEq)]
pub enum LiveMsg {
    /// A batch of display points ([`Batch`] as JSON).
    Samples(Arc<str>),
    /// The stream stopped because a test owns the scope (what for).
    Paused(Arc<str>),
    /// The stream runs again.
    Resumed,
    /// The stream cannot run (the reason); it tries again every second.
    Error(Arc<str>),
}

/// Display points, one entry per point.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Batch {
    /// The servo tick of the point (its group's last sample).
    pub tick: Vec<u64>,
    /// Commanded position, counts.
    pub cmd: Vec<f64>,
    /// Actual position, counts.
    pub act: Vec<f64>,
    /// Following error of the largest magnitude in the group, counts.
    pub ferr: Vec<f64>,
    /// DAC output of the largest magnitude in the group, V.
    pub dac: Vec<f64>,
    /// The axis's state when the batch was read.
    pub state: String,
    /// Samples the card lost since the stream started (its ring was full).
    pub lost: u64,
    /// Servo ticks per second.
    pub servo_rate_hz: u32,
}

/// Makes display points of [`GROUP`] samples each, across batches.
#[derive(Debug, Default)]
pub struct Decimator {
    group: Vec<ScopeSample>,
}

impl Decimator {
    /// Take `s`; a point goes to `out` each time a group is full.
    pub fn push(&mut self, s: &ScopeSample, out: &mut Batch) {
        self.group.push(*s);
        if self.group.len() < GROUP {
            return;
        }
        let last = self.group[GROUP - 1];
        let largest = |k: usize| {
            self.group.iter().map(|x| x.value[k]).fold(0.0_f64, |m, v| {
                if v.abs() > m.abs() {
                    v
                } else {
                    m
                }
            })
        };
        out.tick.push(last.tick);
        out.cmd.push(last.value[0]);
        out.act.push(last.value[1]);
        out.ferr.push(largest(2));
        out.dac.push(largest(3));
        self.group.clear();
    }
}

#[derive(Debug, Default)]
struct State {
    /// Tests holding a lease.
    paused: usize,
    /// The continuous capture is armed (the stream owns the scope).
    streaming: bool,
    /// The server is going down.
    shutdown: bool,
}

struct Shared {
    state: Mutex<State>,
    cond: Condvar,
    tx: broadcast::Sender<LiveMsg>,
}

impl Shared {
    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// The live stream; see the [module](self).
pub struct Live {
    shared: Arc<Shared>,
    thread: Mutex<Option<JoinHandle<()>>>,
}

/// A test's hold on the scope: the stream resumes when it is dropped.
pub struct Lease {
    shared: Arc<Shared>,
}

impl Drop for Lease {
    fn drop(&mut self) {
        let mut g = self.shared.lock();
        g.paused = g.paused.saturating_sub(1);
        if g.paused == 0 {
            let _ = self.shared.tx.send(LiveMsg::Resumed);
        }
        self.shared.cond.notify_all();
    }
}

impl Live {
    /// Start the stream's thread for `axis` of `card`, sharing `scope` with the tests.
    pub fn start(card: Card, scope: Arc<Scope>, axis: usize) -> std::io::Result<Self> {
        let (tx, _) = broadcast::channel(64);
        let shared = Arc::new(Shared {
            state: Mutex::new(State::default()),
            cond: Condvar::new(),
            tx,
        });
        let s = shared.clone();
        let thread = std::thread::Builder::new()
            .name("mcctl-live".into())
            .spawn(move || stream(&card, &scope, axis, &s))?;
        Ok(Self {
            shared,
            thread: Mutex::new(Some(thread)),
        })
    }

    /// A receiver of the stream's messages (a page that watches).
    pub fn subscribe(&self) -> broadcast::Receiver<LiveMsg> {
        let rx = self.shared.tx.subscribe();
        self.shared.cond.notify_all(); // someone watches: start now, not at the next poll
        rx
    }

    /// Stop the stream and take the scope for `what` (a test); waits until the stream has
    /// stopped its capture, at most [`PAUSE_WAIT`].
    pub fn pause(&self, what: &str) -> Result<Lease, String> {
        let mut g = self.shared.lock();
        g.paused += 1;
        let lease = Lease {
            shared: self.shared.clone(),
        };
        self.shared.cond.notify_all();
        let deadline = Instant::now() + PAUSE_WAIT;
        while g.streaming {
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                drop(g);
                return Err(format!(
                    "the live stream did not let the scope go within {PAUSE_WAIT:?}"
                ));
            }
            g = self
                .shared
                .cond
                .wait_timeout(g, left)
                .unwrap_or_else(|e| e.into_inner())
                .0;
        }
        let _ = self.shared.tx.send(LiveMsg::Paused(what.into()));
        Ok(lease)
    }

    /// Stop the thread (and the continuous capture); the pages' streams end.
    pub fn stop(&self) {
        self.shared.lock().shutdown = true;
        self.shared.cond.notify_all();
        let t = self.thread.lock().unwrap_or_else(|e| e.into_inner()).take();
        if let Some(t) = t {
            let _ = t.join();
        }
    }
}

impl Drop for Live {
    fn drop(&mut self) {
        self.stop();
    }
}

/// The scope's settings for the live plots at `rate_hz`.
fn settings(axis: usize, rate_hz: u32) -> ScopeSettings {
    ScopeSettings {
        channels: CHANNELS.iter().map(|&s| Source::axis(s, axis)).collect(),
        divider: (rate_hz / CARD_HZ).max(1),
        trigger: ScopeTrigger::Immediate,
        pre_trigger: 0,
        mode: ScopeMode::Continuous,
        post_trigger: 1,
    }
}

/// The stream's thread.
fn stream(card: &Card, scope: &Scope, axis: usize, shared: &Shared) {
    let rate_hz = card.info().servo_rate_hz;
    let mut dec = Decimator::default();
    let mut raw = Vec::new();
    let mut g = shared.lock();
    let mut retry_at: Option<Instant> = None;
    loop {
        if g.shutdown {
            break;
        }
        let watched = shared.tx.receiver_count() > 0;
        let may = retry_at.is_none_or(|t| Instant::now() >= t);
        if g.paused > 0 || !watched || !may {
            if g.streaming {
                let _ = scope.stop();
                g.streaming = false;
                dec = Decimator::default();
                shared.cond.notify_all();
            }
            g = shared
                .cond
                .wait_timeout(g, Duration::from_millis(100))
                .unwrap_or_else(|e| e.into_inner())
                .0;
            continue;
        }
        if !g.streaming {
            let started = scope
                .configure(&settings(axis, rate_hz))
                .and_then(|()| scope.arm());
            match started {
                Ok(_) => {
                    g.streaming = true;
                    retry_at = None;
                }
                Err(e) => {
                    let _ = shared.tx.send(LiveMsg::Error(
                        format!("the live plots cannot use the card's scope: {e}").into(),
                    ));
                    retry_at = Some(Instant::now() + RETRY);
                    continue;
                }
            }
        }
        raw.clear();
        let read = scope
            .read(&mut raw)
            .and_then(|_| Ok((scope.status()?, card.axis(axis)?.status()?)));
        match read {
            Ok((st, ax)) => {
                let mut batch = Batch {
                    state: format!("{:?}", ax.state),
                    lost: st.lost,
                    servo_rate_hz: rate_hz,
                    ..Batch::default()
                };
                for s in &raw {
                    dec.push(s, &mut batch);
                }
                if !batch.tick.is_empty() {
                    if let Ok(j) = serde_json::to_string(&batch) {
                        let _ = shared.tx.send(LiveMsg::Samples(j.into()));
                    }
                }
            }
            Err(e) => {
                let _ = shared
                    .tx
                    .send(LiveMsg::Error(format!("live plots: {e}").into()));
                let _ = scope.stop();
                g.streaming = false;
                shared.cond.notify_all();
                retry_at = Some(Instant::now() + RETRY);
            }
        }
        g = shared
            .cond
            .wait_timeout(g, PERIOD)
            .unwrap_or_else(|e| e.into_inner())
            .0;
    }
    if g.streaming {
        let _ = scope.stop();
        g.streaming = false;
    }
    shared.cond.notify_all();
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(tick: u64, v: [f64; 4]) -> ScopeSample {
        let mut s = ScopeSample {
            tick,
            ..Default::default()
        };
        s.value[..4].copy_from_slice(&v);
        s
    }

    #[test]
    fn a_display_point_keeps_the_groups_last_position_and_its_largest_error() {
        let mut d = Decimator::default();
        let mut b = Batch::default();
        // 12 samples: two full groups, two samples left over for the next batch.
        for k in 0..12u64 {
            let ferr = if k == 2 { -7.0 } else { k as f64 * 0.1 };
            let dac = if k == 6 { 9.5 } else { -0.5 };
            d.push(
                &sample(100 + k, [k as f64, k as f64 - 1.0, ferr, dac]),
                &mut b,
            );
        }
        assert_eq!(b.tick, vec![104, 109]);
        assert_eq!(b.cmd, vec![4.0, 9.0]);
        assert_eq!(b.act, vec![3.0, 8.0]);
        assert_eq!(b.ferr, vec![-7.0, 0.9]);
        assert_eq!(b.dac, vec![-0.5, 9.5]);
        let mut next = Batch::default();
        for k in 12..15u64 {
            d.push(&sample(100 + k, [k as f64, 0.0, 0.0, 0.0]), &mut next);
        }
        assert_eq!(next.tick, vec![114]);
    }

    #[test]
    fn a_test_pauses_the_stream_and_the_lease_resumes_it() {
        let card = Card::open("sim").unwrap();
        let scope = Arc::new(card.scope());
        let live = Live::start(card.clone(), scope.clone(), 0).unwrap();
        let mut rx = live.subscribe();
        // Samples arrive while someone watches.
        let deadline = Instant::now() + Duration::from_secs(5);
        let first = loop {
            match rx.try_recv() {
                Ok(LiveMsg::Samples(j)) => break j,
                Ok(other) => panic!("{other:?}"),
                Err(_) if Instant::now() < deadline => std::thread::sleep(PERIOD),
                Err(e) => panic!("no samples: {e:?}"),
            }
        };
        let b: serde_json::Value = serde_json::from_str(&first).unwrap();
        let ticks = b["tick"].as_array().unwrap();
        assert!(!ticks.is_empty());
        // Display points every GROUP card samples of `divider` ticks (10 at 10 kHz).
        let t: Vec<u64> = ticks.iter().map(|x| x.as_u64().unwrap()).collect();
        assert!(t.windows(2).all(|w| w[1] - w[0] == 50), "{t:?}");
        assert_eq!(b["state"], "Disabled");
        let lease = live.pause("step test").unwrap();
        // The scope is ours: a one-shot capture configures and arms.
        let cap = scope
            .capture(
                &ScopeSettings::new(&[Source::axis(Signal::CmdPos, 0)], 10),
                Duration::from_secs(2),
                |_| Ok(()),
            )
            .unwrap();
        assert_eq!(cap.samples.len(), 10);
        // The stream said it paused, and sends nothing while paused.
        let mut saw_pause = false;
        while let Ok(m) = rx.try_recv() {
            saw_pause |= m == LiveMsg::Paused("step test".into());
        }
        assert!(saw_pause);
        std::thread::sleep(PERIOD * 3);
        assert!(rx.try_recv().is_err());
        drop(lease);
        let deadline = Instant::now() + Duration::from_secs(5);
        let mut resumed = false;
        loop {
            match rx.try_recv() {
                Ok(LiveMsg::Resumed) => resumed = true,
                Ok(LiveMsg::Samples(_)) if resumed => break,
                Ok(m) => panic!("{m:?}"),
                Err(_) if Instant::now() < deadline => std::thread::sleep(PERIOD),
                Err(e) => panic!("not resumed: {e:?}"),
            }
        }
        live.stop();
        card.close().unwrap();
    }
}

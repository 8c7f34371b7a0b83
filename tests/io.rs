//! Digital I/O, position compare and touch probes on the stepped card and its plant
//! (deterministic): the inputs' polarity, debounce and edge events tick for tick; compare
//! pulses within ±1 count of their positions over thousands of fires at speeds up to 2·10⁶
//! counts/s (2 m/s on a 1 µm scale), measured where the shaft really was at each pulse; missed
//! positions counted and reported; a table of more than 4096 positions streamed in on low
//! water; probe captures within ±1 count of the sensor's true position at speed, in a window,
//! single shot and continuous, and on the index pulse.
//!
//! `cargo test --release --test io -- --nocapture` prints the accuracy tables
//! (BENCHMARKS.md, "Position compare and touch probe accuracy").
mod common;

use common::stepped_card_with;
use motioncard_sdk::{
    Card, CardEvent, Direction, EmuOptions, ErrorKind, EventKind, IoSettings, IoState,
    ProbeTrigger, Sensor, VelocityLimits, COMPARE_FIRED, COMPARE_LOW_WATER, COMPARE_MISSED,
    COMPARE_TABLE_LEN,
};
use std::time::Duration;

const RATE: u32 = 10_000;
const LONG: Duration = Duration::from_secs(60);

/// A one-axis stepped card, enabled.
fn card() -> Card {
    let card = stepped_card_with(EmuOptions::new(1, RATE));
    card.axis(0).unwrap().enable().unwrap();
    card
}

/// Run the axis at `v` counts/s (velocity mode) and wait until it is there.
fn run_at(card: &Card, v: f64) {
    let m = card
        .axis(0)
        .unwrap()
        .move_velocity(v, &VelocityLimits::new(5e6, 5e8))
        .unwrap();
    m.wait_in_velocity(LONG).unwrap();
}

/// Every event queued now.
fn events(card: &Card) -> Vec<CardEvent> {
    card.poll_events().unwrap();
    std::iter::from_fn(|| card.next_event(Duration::ZERO).unwrap()).collect()
}

fn position(card: &Card) -> f64 {
    card.axis(0).unwrap().status().unwrap().actual_position
}

/// The compare pulses' errors (shaft at the pulse − position programmed), counts.
struct Errors {
    fires: usize,
    max: f64,
    mean: f64,
    rms: f64,
}

fn errors(card: &Card) -> Errors {
    let rec = card.sim().unwrap().with_emulator(|e| e.take_fires());
    let errs: Vec<f64> = rec.iter().map(|f| f.shaft - f.position).collect();
    let n = errs.len().max(1) as f64;
    Errors {
        fires: errs.len(),
        max: errs.iter().fold(0.0f64, |m, e| m.max(e.abs())),
        mean: errs.iter().sum::<f64>() / n,
        rms: (errs.iter().map(|e| e * e).sum::<f64>() / n).sqrt(),
    }
}

/// A series of 1000 pulses at each speed (both directions), recorded where the shaft was at
/// each pulse's instant: all within ±1 count, none missed.
#[test]
fn compare_fires_within_one_count_up_to_two_million_counts_per_second() {
    println!("compare: 1000 pulses per row, error = shaft at the pulse - programmed position");
    println!("| speed, counts/s | direction | fires | missed | max abs error | mean | rms |");
    println!("|---:|---|---:|---:|---:|---:|---:|");
    for &v in &[1e3, 1e4, 1e5, 5e5, 1e6, 2e6] {
        for dir in [Direction::Positive, Direction::Negative] {
            let card = card();
            let sign = if dir == Direction::Positive {
                1.0
            } else {
                -1.0
            };
            run_at(&card, sign * v);
            card.sim().unwrap().with_emulator(|e| e.record_fires(true));
            // 1000 pulses over 0.5 s of travel (at least 5 counts apart), starting ahead.
            let pitch = (v * 5e-4).max(5.0).round();
            let start = (position(&card) + sign * 200.0).round();
            let ch = card.axis(0).unwrap().compare(1);
            ch.arm_series(4, 2, start, pitch, 1000, dir).unwrap();
            let ticks = ((1000.0 * pitch + 200.0) / v * RATE as f64) as u64 + 100;
            card.sim().unwrap().step(ticks);
            let st = ch.status().unwrap();
            let e = errors(&card);
            println!(
                "| {v:.0e} | {dir:?} | {} | {} | {:.3} | {:+.3} | {:.3} |",
                e.fires, st.missed, e.max, e.mean, e.rms
            );
            assert_eq!(
                (st.fires, st.missed, e.fires),
                (1000, 0, 1000),
                "{v} {dir:?}"
            );
            assert_eq!(st.state, IoState::Done);
            assert!(e.max <= 1.0, "{v} {dir:?}: {} counts", e.max);
        }
    }
}

/// Pulses while the axis accelerates hard (5·10⁶ counts/s² up to 2·10⁶ counts/s): still
/// within a count.
#[test]
fn compare_fires_within_one_count_while_accelerating() {
    let card = card();
    card.sim().unwrap().with_emulator(|e| e.record_fires(true));
    let ch = card.axis(0).unwrap().compare(0);
    ch.arm_series(0, 1, 100.0, 100.0, 4000, Direction::Positive)
        .unwrap();
    run_at(&card, 2e6);
    card.sim().unwrap().step(2000);
    let e = errors(&card);
    let st = ch.status().unwrap();
    println!(
        "accelerating to 2e6 counts/s at 5e6 counts/s^2: {} fires, max |error| {:.3}, mean {:+.3}",
        e.fires, e.max, e.mean
    );
    assert_eq!((st.fires, st.missed), (4000, 0));
    assert!(e.max <= 1.0, "{}", e.max);
}

/// Positions behind the axis at the arm, and positions inside the pulse before, are missed:
/// counted, reported by events, never fired; fires + missed = all.
#[test]
fn missed_positions_are_counted_and_reported() {
    let card = card();
    run_at(&card, 1e6);
    let x = position(&card);
    events(&card);
    // Behind: 10 positions already passed, then 10 ahead.
    let ch = card.axis(0).unwrap().compare(0);
    let start = (x - 1000.0).round();
    ch.arm_series(0, 1, start, 100.0, 20, Direction::Positive)
        .unwrap();
    card.sim().unwrap().step(100);
    let st = ch.status().unwrap();
    assert_eq!((st.missed, st.fires), (11, 9), "{st:?}"); // x is about start + 1000..1010
    let ev = events(&card);
    let missed: Vec<_> = ev
        .iter()
        .filter(|e| e.kind == EventKind::Compare && e.code == COMPARE_MISSED)
        .collect();
    assert_eq!(missed.len(), 1, "the passed ones in one tick: one event");
    assert_eq!(missed[0].value, st.last_missed);
    assert!(ev
        .iter()
        .any(|e| e.kind == EventKind::Compare && e.code == COMPARE_FIRED));
    // Inside the pulse: 100 µs pulses (100 counts at 10^6 counts/s), positions 60 apart.
    let ch = card.axis(0).unwrap().compare(1);
    let start = (position(&card) + 500.0).round();
    ch.arm_series(1, 100, start, 60.0, 100, Direction::Positive)
        .unwrap();
    card.sim().unwrap().step(200);
    let st = ch.status().unwrap();
    println!("pulse overlap: {} fired, {} missed", st.fires, st.missed);
    assert_eq!(st.fires + st.missed, 100);
    assert_eq!(st.fires, 50, "every other one: 120 counts apart > 100");
}

/// The shaft goes over a compare position and back within one tick (a knock against a hard
/// push back): neither end of the tick is past it, but the encoder interface's highest count
/// of the tick is, so the position is reported missed (it has no instant), not lost.
#[test]
fn a_position_crossed_and_crossed_back_within_a_tick_is_missed() {
    let card = card();
    let sim = card.sim().unwrap();
    sim.step(1000);
    let n = card.axis(0).unwrap().status().unwrap().raw.encoder;
    let ch = card.axis(0).unwrap().compare(0);
    ch.arm_single(0, 10, (n + 1) as f64, Direction::Positive)
        .unwrap();
    sim.step(1);
    assert_eq!(ch.status().unwrap().state, IoState::Armed);
    sim.with_emulator(|e| {
        let m = e.motor_mut(0).unwrap();
        let c = m.params.counts_per_rad();
        m.theta = (n as f64 + 0.998) / c; // the same count, just below the next
        m.omega = 300.0 / c;
        m.disturbance = 3.0;
    });
    sim.step(1);
    sim.with_emulator(|e| e.motor_mut(0).unwrap().disturbance = 0.0);
    let enc = card.axis(0).unwrap().status().unwrap().raw.encoder;
    sim.step(1);
    let st = ch.status().unwrap();
    assert_eq!(enc, n, "the count at the tick's end is where it was");
    assert_eq!((st.fires, st.missed), (0, 1), "{st:?}");
    assert_eq!(st.last_missed, (n + 1) as f64);
    let ev = events(&card);
    assert!(ev
        .iter()
        .any(|e| e.kind == EventKind::Compare && e.code == COMPARE_MISSED));
}

/// A table of 3 × 4096 positions streamed in while the axis runs at 10⁶ counts/s, topped up
/// on each low-water event: every position fires within a count, none is missed.
#[test]
fn a_table_longer_than_the_buffer_streams_on_low_water() {
    let card = card();
    card.sim().unwrap().with_emulator(|e| e.record_fires(true));
    let ch = card.axis(0).unwrap().compare(2);
    let total = 3 * COMPARE_TABLE_LEN;
    let start = 5_000.0;
    let pos = |k: usize| start + 37.0 * k as f64 + (k % 7) as f64; // uneven, increasing
    let first: Vec<f64> = (0..COMPARE_TABLE_LEN).map(pos).collect();
    assert_eq!(ch.push(Direction::Positive, &first).unwrap(), 0);
    assert_eq!(
        ch.push(Direction::Positive, &[1e9]).unwrap_err().kind(),
        ErrorKind::CompareFull
    );
    ch.arm_table(5, 5, 1024, Direction::Positive).unwrap();
    run_at(&card, 1e6);
    let mut sent = COMPARE_TABLE_LEN;
    let mut low_waters = 0;
    while sent < total {
        let ev = card.next_event(LONG).unwrap().unwrap();
        if ev.kind == EventKind::Compare && ev.code == COMPARE_LOW_WATER {
            low_waters += 1;
            let room = ch.room().unwrap();
            let n = room.min(total - sent);
            let next: Vec<f64> = (sent..sent + n).map(pos).collect();
            ch.push(Direction::Positive, &next).unwrap();
            sent += n;
        }
    }
    card.sim().unwrap().step(6000);
    let st = ch.status().unwrap();
    let e = errors(&card);
    println!(
        "table: {} positions, {low_waters} low-water refills, {} fired, max |error| {:.3}",
        total, e.fires, e.max
    );
    assert_eq!((st.fires as usize, st.missed, st.pending), (total, 0, 0));
    assert!(low_waters >= 2);
    assert!(e.max <= 1.0);
    // Queued behind the axis: missed at the next tick, reported.
    ch.push(Direction::Positive, &[0.0]).unwrap();
    card.sim().unwrap().step(1);
    assert_eq!(ch.status().unwrap().missed, 1);
    assert_eq!(
        ch.push(Direction::Positive, &[2e9, 1e9])
            .unwrap_err()
            .kind(),
        ErrorKind::CompareOrder
    );
}

/// The card checks every argument and changes nothing on a refusal.
#[test]
fn compare_and_probe_arguments_are_refused_with_their_own_codes() {
    let card = card();
    let ax = card.axis(0).unwrap();
    let kind = |r: motioncard_sdk::Result<()>| r.unwrap_err().kind();
    let c = ax.compare(0);
    assert_eq!(
        kind(ax.compare(4).arm_single(0, 1, 10.0, Direction::Positive)),
        ErrorKind::IoChannel
    );
    assert_eq!(
        kind(c.arm_single(16, 1, 10.0, Direction::Positive)),
        ErrorKind::CompareMode
    );
    assert_eq!(
        kind(c.arm_single(0, 0, 10.0, Direction::Positive)),
        ErrorKind::CompareMode
    );
    assert_eq!(
        kind(c.arm_single(0, 1, f64::NAN, Direction::Positive)),
        ErrorKind::NotFinite
    );
    assert_eq!(
        kind(c.arm_single(0, 1, 1e300, Direction::Positive)),
        ErrorKind::OutOfRange
    );
    assert_eq!(
        kind(c.arm_series(0, 1, 0.0, 1e-310, 10, Direction::Positive)),
        ErrorKind::CompareMode
    );
    assert_eq!(
        kind(c.arm_series(0, 1, 0.0, 1.0, 10, Direction::Either)),
        ErrorKind::CompareMode
    );
    assert_eq!(c.status().unwrap().state, IoState::Idle, "nothing changed");
    c.arm_single(0, 1, 1e6, Direction::Either).unwrap();
    assert_eq!(
        kind(c.arm_single(0, 1, 10.0, Direction::Positive)),
        ErrorKind::CompareBusy
    );
    assert_eq!(
        kind(ax.compare(1).arm_single(0, 1, 10.0, Direction::Positive)),
        ErrorKind::CompareBusy,
        "output 0 is channel 0's"
    );
    c.disarm().unwrap();
    let p = ax.touch_probe(0);
    let bad = ProbeTrigger {
        input: Some(17),
        ..ProbeTrigger::rising(0)
    };
    assert_eq!(kind(p.arm(&bad)), ErrorKind::ProbeInput);
    let none = ProbeTrigger {
        rising: false,
        ..ProbeTrigger::rising(0)
    };
    assert_eq!(kind(p.arm(&none)), ErrorKind::ProbeInput);
    let window = ProbeTrigger {
        window: Some((5.0, 4.0)),
        ..ProbeTrigger::rising(0)
    };
    assert_eq!(kind(p.arm(&window)), ErrorKind::ProbeInput);
    assert_eq!(kind(ax.touch_probe(4).abort()), ErrorKind::IoChannel);
    let mut s = IoSettings::default();
    s.debounce[3] = 10_001;
    assert_eq!(kind(card.configure_io(&s)), ErrorKind::IoConfig);
    assert_eq!(
        card.io_settings().unwrap(),
        IoSettings::default(),
        "put back"
    );
}

/// Polarity, debounce and edge events, tick for tick: a glitch shorter than the debounce never
/// shows; a level held shows exactly `debounce` ticks after it came; the events come on the
/// edges asked for, in that tick, with the debounced word.
#[test]
fn polarity_debounce_and_edge_events_are_exact() {
    let card = card();
    let sim = card.sim().unwrap();
    let mut s = IoSettings {
        polarity: 1 << 2,
        rise_events: 1 << 0 | 1 << 2,
        fall_events: 1 << 0,
        ..IoSettings::default()
    };
    s.debounce[0] = 5;
    card.configure_io(&s).unwrap();
    sim.step(1);
    assert_eq!(card.inputs().unwrap(), 1 << 2, "input 2 is active low");
    events(&card);
    let set = |i: usize, on: bool| sim.with_emulator(|e| e.inputs().set(i, on));
    // A 5-sample glitch on input 0 does not pass a debounce of 5.
    set(0, true);
    sim.step(5);
    set(0, false);
    sim.step(10);
    assert!(events(&card).is_empty());
    assert_eq!(card.inputs().unwrap() & 1, 0);
    // Held: the debounced bit rises 5 ticks after the first sample that saw it.
    set(0, true);
    let t0 = card.tick().unwrap() + 1; // the next tick samples it
    sim.step(10);
    let ev = events(&card);
    assert_eq!(ev.len(), 1, "{ev:?}");
    assert_eq!(
        (ev[0].kind, ev[0].axis, ev[0].code),
        (EventKind::Input, 0, 1)
    );
    assert_eq!(ev[0].tick, t0 + 5);
    assert_eq!(ev[0].value, f64::from(1 << 2 | 1));
    assert_eq!(card.inputs().unwrap(), 1 << 2 | 1);
    set(0, false);
    let t1 = card.tick().unwrap() + 1;
    sim.step(10);
    let ev = events(&card);
    assert_eq!((ev.len(), ev[0].code, ev[0].tick), (1, 0, t1 + 5));
    // Input 2 (active low, no debounce): the pin going high makes it inactive: no event (only
    // rising is asked for); going low again is its rising edge, in the next tick.
    set(2, true);
    sim.step(1);
    assert!(events(&card).is_empty());
    assert_eq!(card.inputs().unwrap() & 1 << 2, 0);
    set(2, false);
    let t2 = card.tick().unwrap() + 1;
    sim.step(1);
    let ev = events(&card);
    assert_eq!(
        (ev.len(), ev[0].axis, ev[0].code, ev[0].tick),
        (1, 2, 1, t2)
    );
    assert_eq!(card.inputs_raw().unwrap(), 1 << 2);
}

/// Outputs: set by the host, read back; a compare pulse ORs into them for its width.
#[test]
fn outputs_are_set_by_the_host_and_pulsed_by_compare() {
    let card = card();
    card.set_outputs(0b1010, 0b1000).unwrap();
    assert_eq!(card.outputs().unwrap(), 0b1000);
    run_at(&card, 1e5);
    let ch = card.axis(0).unwrap().compare(0);
    let at = (position(&card) + 50.0).round();
    // 250 µs: 3 ticks at 10 kHz.
    ch.arm_single(0, 250, at, Direction::Positive).unwrap();
    let sim = card.sim().unwrap();
    let mut on = 0;
    for _ in 0..20 {
        sim.step(1);
        let o = sim.with_emulator(|e| e.outputs());
        assert_eq!(o & 0b1000, 0b1000);
        on += o & 1;
    }
    assert_eq!(on, 3);
    assert_eq!(ch.status().unwrap().state, IoState::Done);
}

/// A touch probe hitting a part (a sensor at a shaft position) at speed: the capture is
/// within a count of the sensor's true position, both directions, at each speed.
#[test]
fn probe_captures_within_one_count_at_speed() {
    println!("touch probe: error = captured - true sensor position, 20 parts per row");
    println!("| speed, counts/s | max abs error | mean |");
    println!("|---:|---:|---:|");
    for &v in &[1e3, 1e4, 1e5, 1e6, 2e6] {
        let mut worst = 0.0f64;
        let mut sum = 0.0;
        let mut n = 0;
        for k in 0..20 {
            let card = card();
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            run_at(&card, sign * v);
            let x = position(&card);
            // A part a little ahead, at an odd fraction of a count.
            let part = x + sign * (20.0 + v * 3e-4 + 0.137 * k as f64);
            card.sim().unwrap().with_emulator(|e| {
                e.inputs().set_sensor(
                    3,
                    Some(Sensor {
                        axis: 0,
                        at: part,
                        active_above: sign > 0.0,
                    }),
                )
            });
            card.sim().unwrap().step(1);
            let p = card.axis(0).unwrap().touch_probe(k % 4);
            p.arm(&ProbeTrigger::rising(3)).unwrap();
            let got = p.wait_capture(1, LONG).unwrap();
            let err = got - part;
            worst = worst.max(err.abs());
            sum += err;
            n += 1;
            assert!(err.abs() <= 1.0, "{v}: {got} for {part}");
            let ev = events(&card);
            let cap: Vec<_> = ev.iter().filter(|e| e.kind == EventKind::Probe).collect();
            assert_eq!(cap.len(), 1);
            assert_eq!((cap[0].code, cap[0].value), (1, got));
            assert_eq!(p.status().unwrap().state, IoState::Done);
        }
        println!("| {v:.0e} | {worst:.3} | {:+.3} |", sum / n as f64);
    }
}

/// Continuous capture on the index pulse inside a window: each pulse's count (the cell's
/// middle), only those in the window, the ring of the last eight; MC_AbortTrigger stops it.
#[test]
fn continuous_index_probe_in_a_window() {
    let card = card();
    let ax = card.axis(0).unwrap();
    let p = ax.touch_probe(2);
    p.arm(&ProbeTrigger {
        continuous: true,
        window: Some((15_000.0, 95_000.0)),
        ..ProbeTrigger::index()
    })
    .unwrap();
    run_at(&card, 5e5);
    while position(&card) < 120_000.0 {
        card.sim().unwrap().step(100);
    }
    let st = p.status().unwrap();
    // Pulses at every 10,000 counts: 20,000 .. 90,000 inside, 10,000 and 100,000+ outside.
    assert_eq!(st.captures, 8, "{st:?}");
    assert_eq!(st.outside, 4);
    let want: Vec<f64> = (2..10).map(|k| 10_000.0 * k as f64 + 0.5).collect();
    assert_eq!(st.positions, want);
    p.abort().unwrap();
    assert_eq!(p.status().unwrap().state, IoState::Idle);
}

/// A probe armed with `halt` stops the axis's motion itself, in the tick it captures: the
/// velocity move is aborted, the axis comes to rest on its stop ramp just past the capture
/// (never short of it, never reversing) with stop reason `Probe`; the same probe without
/// `halt` leaves the axis running.
#[test]
fn a_halting_probe_stops_the_axis_on_the_capture() {
    for halt in [false, true] {
        let card = card();
        let ax = card.axis(0).unwrap();
        run_at(&card, 1e5);
        let part = position(&card) + 1234.567;
        card.sim().unwrap().with_emulator(|e| {
            e.inputs().set_sensor(
                3,
                Some(Sensor {
                    axis: 0,
                    at: part,
                    active_above: true,
                }),
            )
        });
        card.sim().unwrap().step(1);
        let p = ax.touch_probe(1);
        p.arm(&ProbeTrigger {
            halt,
            ..ProbeTrigger::rising(3)
        })
        .unwrap();
        let got = p.wait_capture(1, LONG).unwrap();
        assert!((got - part).abs() <= 1.0, "{got} for {part}");
        let t0 = card.tick().unwrap();
        card.sim().unwrap().step(2000); // 0.2 s
        let st = ax.status().unwrap();
        if !halt {
            assert_eq!(st.state, motioncard_sdk::AxisState::ContinuousMotion);
            assert!(st.actual_position > got + 1e4);
            continue;
        }
        assert_eq!(st.state, motioncard_sdk::AxisState::Standstill);
        assert_eq!(ax.stop_reason().unwrap(), motioncard_sdk::StopReason::Probe);
        let beyond = st.command_position - got;
        // 1e5 counts/s stopped on the stop ramp: the braking distance, never behind.
        assert!(
            beyond > 0.0 && beyond < 1e5 * 0.05,
            "{beyond} counts past the capture"
        );
        let ev = events(&card);
        assert!(
            ev.iter().any(|e| e.kind == EventKind::MotionAborted),
            "{ev:?}"
        );
        assert!(card.tick().unwrap() >= t0 + 2000);
    }
}

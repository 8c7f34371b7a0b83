//! Synchronised motion on the stepped card and its emulated plant (deterministic): electronic
//! gearing (MC_GearIn, MC_GearInPos, MC_GearOut), PT/PVT streaming and camming.
//!
//! - The ratio is exact: 10⁹ counts of an auxiliary encoder at 10⁸ counts/s, ratio 7/99991,
//!   leave the slave exactly where integer arithmetic puts it (0 error), where a float sum of
//!   the per-tick increments is off.
//! - Engaging holds the slave's limits: the finite differences of its commanded position per
//!   tick stay within 1.01 × its velocity, acceleration and jerk limits.
//! - MC_GearInPos meets its point: the slave is at the slave position when the master is at
//!   the master position.
//! - GearOut leaves the slave in velocity mode at its velocity; halt ends the coupling; a
//!   master that is disabled stops the slave on its stop ramp, reported.
//! - The card refuses bad ratios, masters and limits with their own nacks, changing nothing;
//!   an e-stop ends a coupling.
//! - PT/PVT: PVT and PT streams pass through every point at its time (1e-9 relative) with a
//!   continuous velocity; a point that breaks the limits is refused by name, the rest kept; a
//!   dry buffer stops, reported; 20,000 points go through the 4,096-point buffer on low water;
//!   two axes' streams start on one tick.
//! - Camming: a periodic cubic cam cycle is on its table at every tick and smooth; a second
//!   table takes over at the end of a cycle; a table that is not periodic ends.
//!
//! The figures: `cargo test --release --test sync -- --nocapture`.
mod common;

use common::stepped_card_with;
use motioncard_sdk::proto::{Command, Opcode};
use motioncard_sdk::{
    AxisState, Card, EmuOptions, ErrorKind, EventKind, GearRatio, Master, MoveLimits, NackCode,
    Status, SyncEvent, SyncLimits, VelocityLimits,
};
use std::time::Duration;

const RATE: u32 = 10_000;
const TS: f64 = 1.0 / RATE as f64;
const LONG: Duration = Duration::from_secs(60);

fn card(axes: usize) -> Card {
    let card = stepped_card_with(EmuOptions::new(axes, RATE));
    for a in 0..axes {
        card.axis(a).unwrap().enable().unwrap();
    }
    card
}

fn status(card: &Card, a: usize) -> Status {
    card.axis(a).unwrap().status().unwrap()
}

fn set_aux_velocity(card: &Card, k: usize, v: f64) {
    card.sim()
        .unwrap()
        .with_emulator(|e| e.aux_mut(k).unwrap().velocity = v);
}

/// The commanded positions of `axes` over `n` ticks (one row per tick).
fn record(card: &Card, axes: &[usize], n: u64) -> Vec<Vec<Status>> {
    let sim = card.sim().unwrap();
    (0..n)
        .map(|_| {
            sim.step(1);
            card.statuses(axes).unwrap()
        })
        .collect()
}

/// The largest |first|, |second| and |third| finite difference of `x` per tick, as velocity,
/// acceleration and jerk.
fn peaks(x: &[f64]) -> (f64, f64, f64) {
    let d1: Vec<f64> = x.windows(2).map(|w| (w[1] - w[0]) / TS).collect();
    let d2: Vec<f64> = d1.windows(2).map(|w| (w[1] - w[0]) / TS).collect();
    let d3: Vec<f64> = d2.windows(2).map(|w| (w[1] - w[0]) / TS).collect();
    let max = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    (max(&d1), max(&d2), max(&d3))
}

/// 10⁹ master counts: an auxiliary encoder at 10⁸ counts/s (10⁴ counts per tick) for 10⁵
/// ticks, the slave at 7/99991 (700 ≈ 7,000 counts/s). The slave's commanded position is
/// exactly `7 · 10⁹ / 99991` counts from where it engaged (quotient and remainder), and its
/// actual position in position there.
#[test]
fn gearing_is_exact_after_a_billion_master_counts() {
    let card = card(1);
    let x = card.axis(0).unwrap();
    let x0 = status(&card, 0).command_position;
    let m0 = card.aux_encoder(0).unwrap();
    let gear = x
        .gear_in(Master::Aux(0), 7, 99_991, &SyncLimits::new(2e4, 2e5, 2e7))
        .unwrap();
    let at = gear.wait_in_sync(LONG).unwrap();
    assert_eq!(at, x0, "at rest: in gear at once");
    assert!(status(&card, 0).in_sync());
    assert_eq!(x.gear_ratio(), Some(7.0 / 99_991.0));
    set_aux_velocity(&card, 0, 1e8);
    let sim = card.sim().unwrap();
    sim.step(100_000);
    set_aux_velocity(&card, 0, 0.0);
    sim.step(3_000); // let the servo settle (the count no longer moves)
    let dm = card.aux_encoder(0).unwrap() - m0;
    assert_eq!(dm, 1_000_000_000, "the master ran 10^9 counts");
    let ratio = GearRatio {
        num: 7,
        den: 99_991,
    };
    let (q, r) = ratio.divide(dm as i128, 1);
    assert_eq!((q, r), (70_006, 30_054));
    let expected = x0 + q as f64 + r as f64 / 99_991.0;
    let st = status(&card, 0);
    let err = st.command_position - expected;
    // What a float sum of the per-tick increments (10^4 counts · 7/99991) would give.
    let mut naive = x0;
    for _ in 0..100_000 {
        naive += 10_000.0 * ratio.as_f64();
    }
    println!(
        "gearing after 1e9 master counts at 7/99991: slave {} counts, error {err:e} counts \
         (float sum of the per-tick increments: error {:e} counts); actual {}",
        st.command_position,
        naive - expected,
        st.actual_position
    );
    assert_eq!(err, 0.0, "no drift");
    assert_ne!(naive, expected, "a float sum drifts");
    assert!((st.actual_position - expected).abs() <= 1.0);
    assert_eq!(st.state, AxisState::SynchronizedMotion);
}

/// The slave at rest engages on a master axis running at 20,000 counts/s at 1/2: it catches
/// up within its own limits (finite differences of its commanded position per tick within
/// 1.01 × vmax, amax, jerk), is in gear with the master's velocity × 1/2, then follows it
/// exactly (its increments half the master's of the same tick).
#[test]
fn engaging_holds_the_slave_limits() {
    let card = card(2);
    let (slave, master) = (card.axis(0).unwrap(), card.axis(1).unwrap());
    master
        .move_velocity(20_000.0, &VelocityLimits::new(2e5, 2e7))
        .unwrap()
        .wait_in_velocity(LONG)
        .unwrap();
    let lim = SyncLimits::new(15_000.0, 1e5, 1e7);
    let gear = slave.gear_in(Master::Commanded(1), 1, 2, &lim).unwrap();
    assert_eq!(status(&card, 0).state, AxisState::SynchronizedMotion);
    let rows = record(&card, &[0, 1], 6_000);
    let locked = rows.iter().position(|r| r[0].in_sync()).expect("in gear");
    let at = gear.wait_in_sync(LONG).unwrap();
    let xs: Vec<f64> = rows.iter().map(|r| r[0].command_position).collect();
    let (v, a, j) = peaks(&xs);
    println!(
        "engaging at 1/2 on a master at 20,000 counts/s: in gear after {:.4} s at {at}; peaks \
         {v:.1} counts/s ({:.4} of vmax), {a:.1} counts/s² ({:.4} of amax), {j:.4e} counts/s³ \
         ({:.4} of jerk)",
        locked as f64 * TS,
        v / lim.velocity,
        a / lim.acceleration,
        j / lim.jerk
    );
    assert!(v <= 1.01 * lim.velocity, "velocity {v}");
    assert!(a <= 1.01 * lim.acceleration, "acceleration {a}");
    assert!(j <= 1.01 * lim.jerk, "jerk {j}");
    // In gear: half the master's increments of the same tick (the master counts in 1/65536
    // count: the slave's increment is within half of that of half the master's).
    for k in locked + 2..rows.len() {
        let ds = rows[k][0].command_position - rows[k - 1][0].command_position;
        let dm = rows[k][1].command_position - rows[k - 1][1].command_position;
        assert!(
            (ds - dm / 2.0).abs() <= 1.0 / 65_536.0,
            "tick {k}: {ds} {dm}"
        );
    }
    let last = rows.last().unwrap();
    assert_eq!(last[0].command_velocity, 10_000.0);
    assert!(last[0].following_error.abs() < 5.0);
}

/// Issue 39: a slave geared at 3/2 to a commanded master follows the master's command of the
/// same tick. Both axes in mm (1000 counts/mm); the master at rest, then a line at 50 mm/s
/// (5 counts per tick) and back to rest: at every tick of it the slave's commanded position
/// is 3/2 of the master's travel from where it engaged, within the master's rounding to
/// 1/65536 count (one tick late it would trail by 7.5 counts while the master cruises).
#[test]
fn a_geared_slave_follows_a_commanded_master_in_the_same_tick() {
    let card = card(2);
    let (slave, master) = (card.axis(0).unwrap(), card.axis(1).unwrap());
    for a in [&slave, &master] {
        a.set_scale(1000.0).unwrap();
    }
    let lim = SyncLimits::new(1e3, 1e4, 1e6);
    slave
        .gear_in(Master::Commanded(1), 3, 2, &lim)
        .unwrap()
        .wait_in_sync(LONG)
        .unwrap();
    let (s0, m0) = (
        status(&card, 0).command_position,
        status(&card, 1).command_position,
    );
    let line = master
        .move_relative(100.0, &MoveLimits::new(50.0, 500.0, 5e4))
        .unwrap();
    let rows = record(&card, &[0, 1], 25_000);
    line.wait(Duration::ZERO).unwrap();
    let (mut worst, mut cruise) = (0.0f64, 0);
    for r in &rows {
        let want = s0 + 1.5 * (r[1].command_position - m0);
        worst = worst.max((r[0].command_position - want).abs());
        if (r[1].command_velocity - 50.0).abs() < 1e-9 {
            cruise += 1;
        }
    }
    println!(
        "gearing 3/2 on a commanded master line at 50 mm/s: largest deviation from the ratio line over {} ticks ({cruise} at cruise) {:.3e} counts",
        rows.len(),
        worst * 1000.0
    );
    assert!(cruise > 10_000, "{cruise} ticks at 50 mm/s");
    // 1.5 × half a 1/65536 count, and the float rounding of mm.
    assert!(
        worst * 1000.0 <= 1.5 / 65_536.0,
        "{} counts",
        worst * 1000.0
    );
    let last = rows.last().unwrap();
    assert!((last[1].command_position - (m0 + 100.0)).abs() < 1e-9);
}

/// Issue 39: an actual-position master is latched at the tick's start and the slave's servo
/// reaches its reference a tick later, so with `Master::Actual` the slave's reference of a
/// tick is 3/2 of where the master *was*: 7.5 counts behind 3/2 of the master's actual
/// position of the next tick at 50 mm/s (5 counts a tick). `Master::ActualLead` leads the
/// encoder by its velocity estimate over a period: the slave's reference meets the master's
/// next position, within the estimate's noise.
#[test]
fn an_actual_lead_master_takes_out_the_tick_of_lag() {
    let mut lags = Vec::new();
    for lead in [false, true] {
        let card = card(2);
        let (slave, master) = (card.axis(0).unwrap(), card.axis(1).unwrap());
        for a in [&slave, &master] {
            a.set_scale(1000.0).unwrap();
        }
        let m = if lead {
            Master::ActualLead(1)
        } else {
            Master::Actual(1)
        };
        slave
            .gear_in(m, 3, 2, &SyncLimits::new(1e3, 1e4, 1e6))
            .unwrap()
            .wait_in_sync(LONG)
            .unwrap();
        let (s0, m0) = (
            status(&card, 0).command_position,
            status(&card, 1).actual_position,
        );
        master
            .move_velocity(50.0, &VelocityLimits::new(500.0, 5e4))
            .unwrap()
            .wait_in_velocity(LONG)
            .unwrap();
        let rows = record(&card, &[0, 1], 5_000);
        // Counts: the slave's reference against 3/2 of the master's next actual position.
        let d: Vec<f64> = rows
            .windows(2)
            .skip(1_000)
            .map(|w| (w[0][0].command_position - s0 - 1.5 * (w[1][1].actual_position - m0)) * 1e3)
            .collect();
        let mean = d.iter().sum::<f64>() / d.len() as f64;
        let worst = d.iter().fold(0.0f64, |a, x| a.max((x - mean).abs()));
        println!(
            "gearing 3/2 on an {} master at 50 mm/s: the slave's reference {mean:+.3} counts from 3/2 of the master's next position (spread ±{worst:.3})",
            if lead { "actual-lead" } else { "actual" }
        );
        lags.push(mean);
    }
    assert!(
        (lags[0] + 7.5).abs() < 0.5,
        "actual master: {} counts",
        lags[0]
    );
    assert!(
        lags[1].abs() < 0.5,
        "actual-lead master: {} counts",
        lags[1]
    );
}

/// MC_GearInPos: the slave at rest at 0 is at 20,000 counts when the master (10,000 counts/s)
/// reaches 20,000 counts beyond where it is, ratio 1/1, within its limits on the way; a point too close for the limits
/// is refused (`Infeasible`), and so is a master at rest.
#[test]
fn gear_in_pos_meets_the_sync_point() {
    let card = card(2);
    let (slave, master) = (card.axis(0).unwrap(), card.axis(1).unwrap());
    let lim = SyncLimits::new(20_000.0, 1e5, 1e7);
    let e = slave
        .gear_in_pos(Master::Commanded(1), 1, 1, 60_000.0, 30_000.0, &lim)
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Infeasible, "master at rest: {e}");
    master
        .move_velocity(10_000.0, &VelocityLimits::new(1e5, 1e7))
        .unwrap()
        .wait_in_velocity(LONG)
        .unwrap();
    let m_now = status(&card, 1).command_position;
    let e = slave
        .gear_in_pos(Master::Commanded(1), 1, 1, m_now + 50.0, 30_000.0, &lim)
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Infeasible, "too close: {e}");
    assert_eq!(
        status(&card, 0).state,
        AxisState::Standstill,
        "nothing changed"
    );
    let (m_sync, s_sync) = ((m_now + 20_000.0).round(), 20_000.0);
    let gear = slave
        .gear_in_pos(Master::Commanded(1), 1, 1, m_sync, s_sync, &lim)
        .unwrap();
    let rows = record(&card, &[0, 1], 25_000);
    let locked = rows.iter().position(|r| r[0].in_sync()).expect("in sync");
    let at = gear.wait_in_sync(LONG).unwrap();
    // The slave follows the master's position of the same tick: at every tick in sync
    // x = S + (m − M) exactly; before, the master had not reached M.
    for (k, row) in rows.iter().enumerate().skip(locked) {
        let m = row[1].command_position;
        assert!(m >= m_sync, "tick {k}: master at {m}");
        let x = row[0].command_position;
        assert!(
            (x - (s_sync + (m - m_sync))).abs() <= 1.0 / 65_536.0,
            "tick {k}: {x}"
        );
    }
    assert!(rows[locked - 1][1].command_position < m_sync);
    let xs: Vec<f64> = rows.iter().map(|r| r[0].command_position).collect();
    let (v, a, j) = peaks(&xs);
    println!(
        "gear in at a point: the slave at {s_sync} when the master is at {m_sync}, in sync at \
         {at} after {:.4} s; peaks {v:.1} counts/s, {a:.1} counts/s², {j:.4e} counts/s³",
        locked as f64 * TS
    );
    assert!(v <= 1.01 * lim.velocity && a <= 1.01 * lim.acceleration);
    assert!(j <= 1.01 * lim.jerk, "jerk {j}");
}

/// GearOut: the slave keeps the velocity it had (velocity mode), the gear motion ends
/// aborted by GearOut; a halt then stops it. Halting a geared slave ends the coupling.
#[test]
fn gear_out_and_halt() {
    let card = card(2);
    let (slave, master) = (card.axis(0).unwrap(), card.axis(1).unwrap());
    master
        .move_velocity(-12_000.0, &VelocityLimits::new(2e5, 2e7))
        .unwrap()
        .wait_in_velocity(LONG)
        .unwrap();
    let lim = SyncLimits::new(20_000.0, 2e5, 2e7);
    let gear = slave.gear_in(Master::Actual(1), 3, 4, &lim).unwrap();
    gear.wait_in_sync(LONG).unwrap();
    let out = slave.gear_out().unwrap();
    let e = gear.wait(LONG).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Aborted, "{e}");
    let v = out.wait_in_velocity(LONG).unwrap();
    let st = status(&card, 0);
    // The master's actual velocity is its filtered encoder estimate (1.2 counts a tick).
    println!("gear out at {v} counts/s (the master's actual velocity × 3/4 ≈ -9000)");
    assert!((v + 9_000.0).abs() < 1_500.0, "{v}");
    assert_eq!(st.state, AxisState::ContinuousMotion);
    assert!(!st.in_sync());
    assert_eq!(slave.gear_ratio(), None);
    assert_eq!(
        slave.gear_out().unwrap_err().kind(),
        ErrorKind::InvalidState,
        "not geared"
    );
    slave.halt(2e5, 2e7).unwrap().wait(LONG).unwrap();
    // Gear in again, then halt: the coupling ends, the slave at rest.
    let gear = slave.gear_in(Master::Actual(1), 3, 4, &lim).unwrap();
    gear.wait_in_sync(LONG).unwrap();
    let halt = slave.halt(2e5, 2e7).unwrap();
    assert_eq!(gear.wait(LONG).unwrap_err().kind(), ErrorKind::Aborted);
    halt.wait(LONG).unwrap();
    let st = status(&card, 0);
    assert_eq!(st.state, AxisState::Standstill);
    assert_eq!(slave.gear_ratio(), None);
}

/// A master disabled while the slave follows it: the slave stops on its stop ramp (Stopping,
/// then Standstill at rest), the gear motion is aborted, and a sync event says why.
#[test]
fn a_lost_master_stops_the_slave() {
    let card = card(2);
    let (slave, master) = (card.axis(0).unwrap(), card.axis(1).unwrap());
    master
        .move_velocity(10_000.0, &VelocityLimits::new(2e5, 2e7))
        .unwrap()
        .wait_in_velocity(LONG)
        .unwrap();
    let gear = slave
        .gear_in(Master::Commanded(1), 1, 1, &SyncLimits::new(2e4, 2e5, 2e7))
        .unwrap();
    gear.wait_in_sync(LONG).unwrap();
    while card.next_event(Duration::ZERO).unwrap().is_some() {}
    master.disable().unwrap();
    assert_eq!(gear.wait(LONG).unwrap_err().kind(), ErrorKind::Aborted);
    assert_eq!(status(&card, 0).state, AxisState::Stopping);
    let mut lost = false;
    while let Some(e) = card.next_event(Duration::ZERO).unwrap() {
        lost |= e.kind == EventKind::Sync && e.code == SyncEvent::MasterLost as i32;
    }
    assert!(lost, "MasterLost reported");
    let sim = card.sim().unwrap();
    let mut t = 0;
    while status(&card, 0).state != AxisState::Standstill && t < 20_000 {
        sim.step(1);
        t += 1;
    }
    let st = status(&card, 0);
    println!(
        "master lost: the slave at rest after {:.4} s",
        t as f64 * TS
    );
    assert_eq!(st.state, AxisState::Standstill);
    assert_eq!(st.command_velocity, 0.0);
    // A disabled master is refused up front.
    let e = slave
        .gear_in(Master::Commanded(1), 1, 1, &SyncLimits::new(2e4, 2e5, 2e7))
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::SyncMaster);
}

/// Raw commands the SDK would not send: each gets its own nack and changes nothing.
#[test]
fn the_card_refuses_bad_gear_commands() {
    let card = card(2);
    let before = status(&card, 0);
    let ok = [1.0, 3.0, 7.0, 1e4, 1e5, 1e7, 0.0, 0.0];
    let cases: &[(usize, f64, u32, NackCode)] = &[
        (1, f64::NAN, 0, NackCode::NotFinite),
        (1, f64::INFINITY, 0, NackCode::NotFinite),
        (1, 1e300, 0, NackCode::GearRatio),
        (1, 2.5, 0, NackCode::GearRatio),
        (2, 0.0, 0, NackCode::GearRatio),
        (2, -7.0, 0, NackCode::GearRatio),
        (2, 1e-310, 0, NackCode::GearRatio),
        (0, 0.0, 0, NackCode::SyncMaster),
        (0, 5.0, 0, NackCode::SyncMaster),
        (0, 2.0, 2, NackCode::SyncMaster),
        (0, 1.0, 9, NackCode::SyncMaster),
        (3, -1.0, 0, NackCode::NonPositiveLimit),
        (4, 1e300, 0, NackCode::LimitRange),
        (5, 1e-320, 0, NackCode::LimitRange),
    ];
    for &(i, v, flags, code) in cases {
        let mut args = ok;
        args[i] = v;
        let mut cmd = Command::new(Opcode::GearIn, 0).with_args(&args);
        cmd.flags = flags;
        let seq = card.send_raw(cmd).unwrap();
        assert_eq!(
            card.wait_ack(seq).unwrap(),
            Err(code),
            "arg {i} = {v:e}, flags {flags}"
        );
    }
    let seq = card.send_raw(Command::new(Opcode::GearOut, 0)).unwrap();
    assert_eq!(card.wait_ack(seq).unwrap(), Err(NackCode::InvalidState));
    let after = status(&card, 0);
    assert_eq!(after.state, before.state);
    assert_eq!(after.raw.last_seq, before.raw.last_seq);
    assert_eq!(card.axis(0).unwrap().gear_ratio(), None);
    // The SDK refuses the same before sending.
    let slave = card.axis(0).unwrap();
    let lim = SyncLimits::new(1e4, 1e5, 1e7);
    assert_eq!(
        slave
            .gear_in(Master::Aux(0), 1, 0, &lim)
            .unwrap_err()
            .kind(),
        ErrorKind::GearRatio
    );
    assert_eq!(
        slave
            .gear_in(Master::Commanded(0), 1, 1, &lim)
            .unwrap_err()
            .kind(),
        ErrorKind::SyncMaster
    );
    assert_eq!(
        slave
            .gear_in(Master::Aux(0), 1, 1, &SyncLimits::new(f64::NAN, 1.0, 1.0))
            .unwrap_err()
            .kind(),
        ErrorKind::NotFinite
    );
}

// ---- PT/PVT streaming ----

use motioncard_sdk::{PvtEvent, PvtLimits, PvtMode, PvtPoint, PVT_LEN};

/// `n` points every `dt` s of `A (1 − cos 2π t)`, from rest at 0 back to rest at 0 (with their
/// velocities), the last at `n · dt`.
fn cosine_points(n: usize, dt: f64, amp: f64) -> Vec<PvtPoint> {
    let w = 2.0 * std::f64::consts::PI;
    (1..=n)
        .map(|k| {
            let t = k as f64 * dt;
            let v = if k == n { 0.0 } else { amp * w * (w * t).sin() };
            PvtPoint::new(t, amp * (1.0 - (w * t).cos()), v)
        })
        .collect()
}

/// Run a stream to its end, recording the commanded position after every tick (row `i` is
/// `t = (i + 1) · Ts`).
fn run_stream(card: &Card, n: u64) -> (Vec<Status>, f64) {
    let x = card.axis(0).unwrap();
    let m = x.pvt_start().unwrap();
    let rows: Vec<Status> = record(card, &[0], n).into_iter().map(|r| r[0]).collect();
    let done = m.wait(LONG).unwrap();
    (rows, done)
}

/// The stream passes exactly through every point at its time (1e-9 relative), with the
/// point's velocity, and its velocity is continuous (second differences of the commanded
/// position within the limit); PVT and PT both.
#[test]
fn pvt_and_pt_pass_through_every_point() {
    for mode in [PvtMode::Pvt, PvtMode::Pt] {
        let card = card(1);
        let x = card.axis(0).unwrap();
        let pts = cosine_points(200, 0.01, 5_000.0); // 2 s, 100 ticks a segment
        let lim = PvtLimits {
            velocity: 40_000.0,
            acceleration: 4e5,
        };
        x.pvt_begin(mode, &lim, 0).unwrap();
        let free = x.pvt_push(&pts, true).unwrap();
        assert_eq!(free, PVT_LEN - 200);
        card.sim().unwrap().step(1);
        assert_eq!(x.pvt_room(), (200, PVT_LEN - 200));
        let (rows, done) = run_stream(&card, 20_500);
        let mut worst = 0.0f64;
        for (k, p) in pts.iter().enumerate() {
            let i = (k + 1) * 100 - 1;
            let r = &rows[i];
            let err = (r.command_position - p.position).abs() / p.position.abs().max(1.0);
            worst = worst.max(err);
            assert!(
                err <= 1e-9,
                "{mode:?} point {k}: {} vs {}",
                r.command_position,
                p.position
            );
            if mode == PvtMode::Pvt && k + 1 < pts.len() {
                assert!((r.command_velocity - p.velocity).abs() <= 1e-9 * 40_000.0);
            }
        }
        let xs: Vec<f64> = rows.iter().map(|r| r.command_position).collect();
        let (v, a, _) = peaks(&xs[..20_000]);
        println!(
            "{mode:?}: 200 points, worst relative error at the points {worst:e}; peaks {v:.1} \
             counts/s, {a:.1} counts/s² (limits 40000, 4e5); done at {done}"
        );
        assert!(v <= 1.01 * lim.velocity && a <= 1.01 * lim.acceleration);
        assert_eq!(status(&card, 0).state, AxisState::Standstill);
        assert!(done.abs() <= 1.0);
    }
}

/// A point that breaks the limits is refused by name; the points before it stay queued, the
/// stream goes on. A stream that runs dry stops on the stop ramp, reported.
#[test]
fn pvt_refusals_and_a_dry_buffer() {
    let card = card(1);
    let x = card.axis(0).unwrap();
    let lim = PvtLimits {
        velocity: 10_000.0,
        acceleration: 1e5,
    };
    assert_eq!(
        x.pvt_push(&[PvtPoint::new(0.1, 1.0, 0.0)], false)
            .unwrap_err()
            .kind(),
        ErrorKind::PvtSequence,
        "no stream open"
    );
    x.pvt_begin(PvtMode::Pvt, &lim, 0).unwrap();
    let pts = [
        PvtPoint::new(0.1, 100.0, 2_000.0),
        PvtPoint::new(0.2, 400.0, 4_000.0),
        PvtPoint::new(0.3, 5_000.0, 4_000.0), // 46,000 counts/s on the way
        PvtPoint::new(0.4, 1_200.0, 4_000.0),
    ];
    let e = x.pvt_push(&pts, false).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::PvtLimit, "{e}");
    assert!(
        matches!(e, motioncard_sdk::Error::PvtPoint { index: 2, .. }),
        "{e}"
    );
    println!("refused: {e}");
    card.sim().unwrap().step(1);
    assert_eq!(x.pvt_room().0, 2, "the two before it are queued");
    for (bad, kind) in [
        (PvtPoint::new(0.2, 500.0, 0.0), ErrorKind::PvtTime),
        (PvtPoint::new(0.20001, 500.0, 0.0), ErrorKind::PvtTime),
        (PvtPoint::new(f64::NAN, 500.0, 0.0), ErrorKind::NotFinite),
        (PvtPoint::new(0.3, 1e300, 0.0), ErrorKind::OutOfRange),
    ] {
        let e = x.pvt_push(&[bad], false).unwrap_err();
        assert_eq!(e.kind(), kind, "{bad:?}: {e}");
    }
    // Raw: 1e300 reaches the card as a position out of range.
    let mut cmd = Command::new(Opcode::PvtPoints, 0).with_args(&[1.0, 0.3, 1e300, 0.0]);
    cmd.flags = 0;
    let seq = card.send_raw(cmd).unwrap();
    assert_eq!(card.wait_ack(seq).unwrap(), Err(NackCode::OutOfRange));
    let seq = card
        .send_raw(Command::new(Opcode::PvtPoints, 0).with_args(&[5.0]))
        .unwrap();
    assert_eq!(card.wait_ack(seq).unwrap(), Err(NackCode::OutOfRange));
    // Run dry: the last point passed at 0.2 s moving at 4000 counts/s.
    let m = x.pvt_start().unwrap();
    while card.next_event(Duration::ZERO).unwrap().is_some() {}
    let rows = record(&card, &[0], 2_100);
    assert_eq!(m.wait(LONG).unwrap_err().kind(), ErrorKind::Aborted);
    let mut starved = false;
    while let Some(e) = card.next_event(Duration::ZERO).unwrap() {
        starved |= e.kind == EventKind::Pvt && e.code == PvtEvent::Starved as i32;
    }
    assert!(starved, "starvation reported");
    // At 0.2 s the last point (400 at 4000 counts/s), and the stop's first tick from there.
    let at = rows[1_999][0].command_position;
    assert!((at - 400.4).abs() < 0.01, "{at}");
    let rest = rows
        .iter()
        .rposition(|r| r[0].command_velocity != 0.0)
        .unwrap();
    let st = status(&card, 0);
    println!(
        "dry at 0.2 s (4000 counts/s): at rest {:.4} s later at {}",
        (rest as f64 - 1_999.0) * TS,
        st.command_position
    );
    assert_eq!(st.state, AxisState::Standstill);
    assert_eq!(
        st.raw.stop_reason,
        motioncard_sdk::StopReason::Starvation as u32
    );
    // A time refusal says which bound when the point before is in the same push (too soon, or
    // later than the longest segment, 10⁶ s: the card's one nack for both); the first point
    // of a push names both.
    x.pvt_begin(PvtMode::Pvt, &lim, 0).unwrap();
    for (pts, index, reason) in [
        ([0.1, 0.1], 1, "at least one servo period after"),
        ([0.2, 1e9], 1, "at most 1e6 s (the longest move) after"),
        (
            [1e9, 2e9],
            0,
            "at least one servo period, and at most 1e6 s (the longest move), after",
        ),
    ] {
        // Held where the axis stands.
        let pts = pts.map(|t| PvtPoint::new(t, st.command_position, 0.0));
        let e = x.pvt_push(&pts, false).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::PvtTime, "{e}");
        let motioncard_sdk::Error::PvtPoint {
            index: i,
            reason: r,
            ..
        } = &e
        else {
            panic!("{e}")
        };
        assert_eq!(*i, index, "{e}");
        assert!(r.contains(reason), "{e}");
    }
}

/// 20,000 points (every ms for 20 s) through the 4,096-point buffer, refilled on the low-water
/// event: every point met exactly, no starvation; the rate of points accepted in-process.
#[test]
fn pvt_streams_more_than_the_buffer() {
    let card = card(1);
    let x = card.axis(0).unwrap();
    let n = 20_000;
    let pts = cosine_points(n, 0.001, 2_000.0);
    x.pvt_begin(
        PvtMode::Pvt,
        &PvtLimits {
            velocity: 20_000.0,
            acceleration: 2e5,
        },
        1_024,
    )
    .unwrap();
    let t0 = std::time::Instant::now();
    let mut sent = PVT_LEN;
    x.pvt_push(&pts[..sent], false).unwrap();
    let rate = sent as f64 / t0.elapsed().as_secs_f64();
    let m = x.pvt_start().unwrap();
    let sim = card.sim().unwrap();
    let mut lows = 0;
    let mut worst = 0.0f64;
    let mut tick = 0usize;
    while tick < n * 10 + 2_000 {
        sim.step(1);
        tick += 1;
        if tick.is_multiple_of(10) && tick / 10 <= n {
            let p = &pts[tick / 10 - 1];
            let err = (status(&card, 0).command_position - p.position).abs();
            worst = worst.max(err / p.position.abs().max(1.0));
        }
        while let Some(e) = card.next_event(Duration::ZERO).unwrap() {
            if e.kind == EventKind::Pvt && e.code == PvtEvent::LowWater as i32 {
                lows += 1;
                let take = x.pvt_free().min(n - sent);
                x.pvt_push(&pts[sent..sent + take], sent + take == n)
                    .unwrap();
                sent += take;
            }
            assert!(
                !(e.kind == EventKind::Pvt && e.code == PvtEvent::Starved as i32),
                "starved at tick {tick}"
            );
        }
    }
    m.wait(LONG).unwrap();
    println!(
        "streamed {n} points through {PVT_LEN}: {lows} low-water refills, worst relative \
         error at the points {worst:e}; {rate:.0} points/s accepted in-process (4 a command)"
    );
    assert_eq!(sent, n);
    assert!(lows >= 4);
    assert!(worst <= 1e-9);
}

// ---- Camming ----

use card_emu::motion::cam::CamTable;
use motioncard_sdk::CamSettings;

/// A rotary knife's cam over one sheet of `sheet` master counts: the knife turns `rev` counts
/// per sheet, at the conveyor's speed × `sync` at the cut (m = 0 mod sheet); `n` points.
fn knife_points(n: usize, sheet: f64, rev: f64, sync: f64) -> Vec<(f64, f64)> {
    let c = (sync - rev / sheet) * sheet / (2.0 * std::f64::consts::PI);
    (0..=n)
        .map(|i| {
            let m = sheet * i as f64 / n as f64;
            (
                m,
                rev / sheet * m + c * (2.0 * std::f64::consts::PI * m / sheet).sin(),
            )
        })
        .collect()
}

/// A periodic cubic cam of 65 points (a rotary knife, 20,000 counts of conveyor a sheet, 10,000
/// counts of knife a turn, at the conveyor's speed × 0.8 at the cut) behind a master axis at
/// 10,000 counts/s: on the cam the slave is the table at the master's position of the tick
/// before (within the master's 1/65536-count rounding times the slope), at every point and
/// between; velocity and acceleration continuous (finite differences), over two cycles; then a
/// second table (another path between the same cuts) takes over at the end of a cycle, the
/// motion smooth across it.
#[test]
fn a_cam_cycle_matches_its_table_and_switches_at_the_cycle_end() {
    let card = card(2);
    let (slave, master) = (card.axis(0).unwrap(), card.axis(1).unwrap());
    let (sheet, rev) = (20_000.0, 10_000.0);
    let pts = knife_points(64, sheet, rev, 0.8);
    card.load_cam_table(0, &pts, true, true).unwrap();
    // The second table: the same cut, another path between cuts (its slope and curvature at
    // the cut the first's, so the switch is smooth).
    let pts2: Vec<(f64, f64)> = pts
        .iter()
        .map(|&(m, s)| {
            let c = 1.0 - (2.0 * std::f64::consts::PI * m / sheet).cos();
            (m, s + 300.0 * c * c)
        })
        .collect();
    card.load_cam_table(1, &pts2, true, true).unwrap();
    let table = CamTable::new(&pts, true, true).unwrap();
    let table2 = CamTable::new(&pts2, true, true).unwrap();
    // Refusals: a table not loaded, a master that does not increase, a bad sequence.
    let lim = SyncLimits::new(30_000.0, 3e5, 3e7);
    assert_eq!(
        slave
            .cam_in(Master::Commanded(1), &CamSettings::new(2), &lim)
            .unwrap_err()
            .kind(),
        ErrorKind::CamTable
    );
    assert_eq!(
        card.load_cam_table(3, &[(0.0, 0.0), (0.0, 1.0)], false, false)
            .unwrap_err()
            .kind(),
        ErrorKind::CamTable
    );
    let seq = card
        .send_raw(Command::new(Opcode::CamData, 0).with_args(&[3.0, 5.0, 1.0, 0.0, 0.0]))
        .unwrap();
    assert_eq!(card.wait_ack(seq).unwrap(), Err(NackCode::CamSequence));
    master
        .move_velocity(10_000.0, &VelocityLimits::new(1e5, 1e7))
        .unwrap()
        .wait_in_velocity(LONG)
        .unwrap();
    let cam = CamSettings::new(0);
    let m = slave.cam_in(Master::Commanded(1), &cam, &lim).unwrap();
    m.wait_in_sync(LONG).unwrap();
    assert!(status(&card, 0).in_sync());
    // Two cycles: 4 s.
    let rows = record(&card, &[0, 1], 40_000);
    let mut worst = 0.0f64;
    for row in rows.iter().skip(1) {
        // The master's command of the same tick (issue 39: no tick of latency).
        let x_m = row[1].command_position;
        let want = table.eval(x_m).s;
        worst = worst.max((row[0].command_position - want).abs());
    }
    let xs: Vec<f64> = rows.iter().map(|r| r[0].command_position).collect();
    let (v, a, j) = peaks(&xs);
    // The cam's own peaks at 10,000 counts/s of master.
    let (mut fv, mut fa) = (0.0f64, 0.0f64);
    for i in 0..=20_000 {
        let e = table.eval(i as f64);
        fv = fv.max((e.ds * 1e4).abs());
        fa = fa.max((e.dds * 1e8).abs());
    }
    println!(
        "cam cycle (65-point cubic rotary knife, master 10,000 counts/s): worst |slave − \
         table(master)| {worst:e} counts over 2 cycles; peaks {v:.1} counts/s, {a:.1} counts/s² \
         (the table's: {fv:.1}, {fa:.1}), jerk {j:.3e} counts/s³"
    );
    assert!(worst <= 1e-3, "{worst}");
    assert!(v <= fv * 1.001 + 1.0 && a <= fa * 1.01 + 100.0, "{v} {a}");
    // The switch at the end of the cycle.
    let sw = slave
        .cam_switch(Master::Commanded(1), &CamSettings::new(1), &lim)
        .unwrap();
    let rows = record(&card, &[0, 1], 25_000);
    let at = sw.wait_cam_switch(LONG).unwrap();
    let dx: Vec<f64> = rows
        .windows(2)
        .map(|w| w[1][0].command_position - w[0][0].command_position)
        .collect();
    let jump = dx
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .fold(0.0, f64::max);
    println!("switched tables at the cycle end at {at}; largest change of the per-tick step {jump:e} counts");
    assert!(jump < 1e-3, "the position stays smooth: {jump}");
    // After the switch: the second table, shifted to continue from the boundary.
    let k = rows.len() - 1;
    let x_m = rows[k][1].command_position;
    let (d_now, d_ref) = (
        rows[k][0].command_position - rows[k - 100][0].command_position,
        table2.eval(x_m).s - table2.eval(rows[k - 100][1].command_position).s,
    );
    assert!((d_now - d_ref).abs() < 1e-3, "{d_now} {d_ref}");
    assert_eq!(
        card.load_cam_table(1, &pts2, true, true)
            .unwrap_err()
            .kind(),
        ErrorKind::CamTable,
        "in use"
    );
    slave.cam_out().unwrap().wait_in_velocity(LONG).unwrap();
    slave.halt(3e5, 3e7).unwrap().wait(LONG).unwrap();
}

// ---- Stops, groups of streams, the end of a cam ----

/// An e-stop on a geared slave: the gear motion is aborted, the slave stops in ErrorStop and
/// the coupling is gone.
#[test]
fn an_estop_ends_a_coupling() {
    let card = card(2);
    let (slave, master) = (card.axis(0).unwrap(), card.axis(1).unwrap());
    master
        .move_velocity(10_000.0, &VelocityLimits::new(2e5, 2e7))
        .unwrap()
        .wait_in_velocity(LONG)
        .unwrap();
    let gear = slave
        .gear_in(Master::Commanded(1), 1, 1, &SyncLimits::new(2e4, 2e5, 2e7))
        .unwrap();
    gear.wait_in_sync(LONG).unwrap();
    card.estop(motioncard_sdk::StopCategory::Cat1).unwrap();
    assert_eq!(gear.wait(LONG).unwrap_err().kind(), ErrorKind::Aborted);
    card.sim().unwrap().step(20_000);
    let st = status(&card, 0);
    assert_eq!(st.state, AxisState::ErrorStop);
    assert_eq!(st.command_velocity, 0.0);
    assert!(!st.in_sync());
    assert_eq!(slave.gear_ratio(), None);
}

/// Two axes' streams started on one tick (`Card::pvt_start`): each meets its points at the
/// same ticks.
#[test]
fn two_streams_start_together() {
    let card = card(2);
    let pts = cosine_points(100, 0.01, 3_000.0);
    let other: Vec<PvtPoint> = pts
        .iter()
        .map(|p| PvtPoint::new(p.time, -0.5 * p.position, -0.5 * p.velocity))
        .collect();
    let lim = PvtLimits {
        velocity: 40_000.0,
        acceleration: 4e5,
    };
    for (a, p) in [(0, &pts), (1, &other)] {
        let x = card.axis(a).unwrap();
        x.pvt_begin(PvtMode::Pvt, &lim, 0).unwrap();
        x.pvt_push(p, true).unwrap();
    }
    let motions = card.pvt_start(&[0, 1]).unwrap();
    assert_eq!(motions[0].seq(), motions[1].seq());
    let rows = record(&card, &[0, 1], 10_000);
    for k in 0..pts.len() {
        let r = &rows[(k + 1) * 100 - 1];
        assert!(
            (r[0].command_position - pts[k].position).abs() <= 1e-9 * 3e3,
            "point {k}"
        );
        assert!(
            (r[1].command_position - other[k].position).abs() <= 1e-9 * 3e3,
            "point {k}"
        );
    }
    for m in motions {
        m.wait(LONG).unwrap();
    }
    assert_eq!(
        card.pvt_start(&[]).unwrap_err().kind(),
        ErrorKind::PvtSequence
    );
}

/// A cam whose table is not periodic ends: the slave holds the table's end, reported.
#[test]
fn a_cam_that_is_not_periodic_ends() {
    let card = card(2);
    let (slave, master) = (card.axis(0).unwrap(), card.axis(1).unwrap());
    card.load_cam_table(
        2,
        &[(0.0, 0.0), (5_000.0, 2_000.0), (8_000.0, 2_500.0)],
        false,
        false,
    )
    .unwrap();
    let m = slave
        .cam_in(
            Master::Commanded(1),
            &CamSettings::new(2),
            &SyncLimits::new(2e4, 2e5, 2e7),
        )
        .unwrap();
    m.wait_in_sync(LONG).unwrap();
    while card.next_event(Duration::ZERO).unwrap().is_some() {}
    master
        .move_velocity(5_000.0, &VelocityLimits::new(1e5, 1e7))
        .unwrap();
    card.sim().unwrap().step(25_000);
    let mut ended = None;
    while let Some(e) = card.next_event(Duration::ZERO).unwrap() {
        if e.kind == EventKind::Sync && e.code == SyncEvent::CamEnd as i32 {
            ended = Some(e.value);
        }
    }
    assert_eq!(ended, Some(2_500.0), "CamEnd at the table's end");
    let st = status(&card, 0);
    assert_eq!(st.command_position, 2_500.0);
    assert_eq!(st.state, AxisState::SynchronizedMotion);
}

/// MC_CamIn's StartMode relative: the cam starts where the slave stands (no position
/// catch-up), and the slave then moves by the table's differences; absolute ramps the slave
/// onto the table.
#[test]
fn a_relative_cam_starts_where_the_slave_stands() {
    let card = card(2);
    let (slave, master) = (card.axis(0).unwrap(), card.axis(1).unwrap());
    let pts = [
        (0.0, 0.0),
        (4_000.0, 1_000.0),
        (8_000.0, 3_000.0),
        (12_000.0, 3_000.0),
    ];
    card.load_cam_table(1, &pts, true, false).unwrap();
    let lim = MoveLimits::new(5e4, 5e5, 5e7);
    slave
        .move_absolute(7_000.0, &lim)
        .unwrap()
        .wait(LONG)
        .unwrap();
    master
        .move_absolute(2_000.0, &lim)
        .unwrap()
        .wait(LONG)
        .unwrap();
    let table = card_emu::motion::cam::CamTable::new(&pts, true, false).unwrap();
    let cam = CamSettings {
        slave_offset: 100.0,
        slave_scale: 2.0,
        relative: true,
        ..CamSettings::new(1)
    };
    let at = slave
        .cam_in(Master::Commanded(1), &cam, &SyncLimits::new(2e4, 2e5, 2e7))
        .unwrap()
        .wait_in_sync(LONG)
        .unwrap();
    assert_eq!(at, 7_000.0, "in sync where it stood");
    let t0 = table.eval(2_000.0).s;
    master
        .move_absolute(9_000.0, &lim)
        .unwrap()
        .wait(LONG)
        .unwrap();
    card.sim().unwrap().step(2);
    let want = 7_000.0 + 2.0 * (table.eval(9_000.0).s - t0);
    let got = status(&card, 0).command_position;
    assert!((got - want).abs() < 1e-6, "relative: {got} vs {want}");
    // Absolute: from the same spot the slave ramps onto offset + scale · table.
    slave.cam_out().unwrap();
    slave.halt(2e5, 2e7).unwrap().wait(LONG).unwrap();
    let cam = CamSettings {
        relative: false,
        ..cam
    };
    let at = slave
        .cam_in(Master::Commanded(1), &cam, &SyncLimits::new(2e4, 2e5, 2e7))
        .unwrap()
        .wait_in_sync(LONG)
        .unwrap();
    let want = 100.0 + 2.0 * table.eval(9_000.0).s;
    assert!((at - want).abs() < 1e-6, "absolute: {at} vs {want}");
}

/// A PT/PVT stream and a coupling do not mix: MC_GearIn on a streaming axis is refused, and
/// the stream runs on to its end.
#[test]
fn a_stream_is_not_taken_over_by_a_coupling() {
    let card = card(1);
    let x = card.axis(0).unwrap();
    let lim = PvtLimits {
        velocity: 40_000.0,
        acceleration: 4e5,
    };
    x.pvt_begin(PvtMode::Pvt, &lim, 0).unwrap();
    x.pvt_push(&cosine_points(100, 0.01, 3_000.0), true)
        .unwrap();
    let m = x.pvt_start().unwrap();
    card.sim().unwrap().step(100);
    let e = x
        .gear_in(Master::Aux(0), 1, 1, &SyncLimits::new(2e4, 2e5, 2e7))
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidState, "{e}");
    m.wait(LONG).unwrap();
}

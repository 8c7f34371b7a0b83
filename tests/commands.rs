//! Every command gets exactly one ack or nack; each refusal has its own code; the PLCopen
//! state machine (Halt, Stop, Reset, Power) behaves as specified.
mod common;

use common::stepped_card;
use motioncard_sdk::proto::{Command, Opcode};
use motioncard_sdk::{AxisState, Card, ErrorKind, EventKind, MoveLimits, NackCode};
use std::time::Duration;

fn lim() -> MoveLimits {
    MoveLimits::new(100_000.0, 1e6, 5e7)
}

/// Send a raw command and return its nack code (or None when acked).
fn raw(card: &Card, cmd: Command) -> Option<NackCode> {
    let seq = card.send_raw(cmd).unwrap();
    card.wait_ack(seq).unwrap().err()
}

/// The host clock the card reads (`host.host_time_ms`), as the SDK last published it.
fn host_time(card: &Card) -> u32 {
    use firmware_proto::{layout, Mem};
    let sim = card.sim().expect("a stepped card");
    sim.with_emulator(|e| e.window().read32(layout::HOST_TIME_MS))
}

fn mv(axis: u16, args: &[f64]) -> Command {
    Command::new(Opcode::MoveAbsolute, axis).with_args(args)
}

#[test]
fn every_nack_code_is_provoked_by_its_own_fault() {
    let card = stepped_card();
    let good = [1000.0, 1e5, 1e6, 1e6, 1e7, 1e7, 1e7, 1e7];
    let mut seen = Vec::new();
    let mut expect = |code: NackCode, got: Option<NackCode>| {
        assert_eq!(got, Some(code));
        seen.push(code);
    };
    let mut unknown = Command::new(Opcode::Nop, 0);
    unknown.opcode = 0x7777;
    expect(NackCode::UnknownOpcode, raw(&card, unknown));
    expect(NackCode::BadAxis, raw(&card, mv(8, &good)));
    expect(NackCode::AxisDisabled, raw(&card, mv(0, &good)));
    assert_eq!(raw(&card, Command::new(Opcode::PowerOn, 0)), None);
    let mut nan = good;
    nan[0] = f64::NAN;
    expect(NackCode::NotFinite, raw(&card, mv(0, &nan)));
    let mut inf = good;
    inf[5] = f64::INFINITY;
    assert_eq!(raw(&card, mv(0, &inf)), Some(NackCode::NotFinite));
    let mut zero = good;
    zero[2] = 0.0;
    expect(NackCode::NonPositiveLimit, raw(&card, mv(0, &zero)));
    let mut neg = good;
    neg[7] = -1.0;
    assert_eq!(raw(&card, mv(0, &neg)), Some(NackCode::NonPositiveLimit));
    expect(
        NackCode::InvalidState,
        raw(&card, Command::new(Opcode::Reset, 0)),
    );
    let mut far = good;
    far[0] = 1e17;
    expect(NackCode::OutOfRange, raw(&card, mv(0, &far)));
    let mut crawl = good;
    crawl[4..8].copy_from_slice(&[1e-12; 4]);
    crawl[0] = 1e9;
    expect(NackCode::Infeasible, raw(&card, mv(0, &crawl)));
    // Limits outside the card's range (subnormal, absurdly small or large), for moves and
    // stops alike.
    for (i, x) in [(4, 1e-300), (2, 5e-324), (3, 1e-320), (1, 1e300), (7, 1e40)] {
        let mut bad = good;
        bad[i] = x;
        assert_eq!(
            raw(&card, mv(0, &bad)),
            Some(NackCode::LimitRange),
            "arg {i} = {x:e}"
        );
    }
    let halt = |d: f64, j: f64| Command::new(Opcode::Halt, 0).with_args(&[d, j]);
    expect(NackCode::LimitRange, raw(&card, halt(5e6, 1e-300)));
    assert_eq!(raw(&card, halt(1e-310, 1e8)), Some(NackCode::LimitRange));
    // An override beyond 200 % (or below 0 %).
    let ovr = |k: f64| Command::new(Opcode::SetOverride, 0).with_args(&[k]);
    expect(NackCode::OverrideRange, raw(&card, ovr(2.5)));
    assert_eq!(raw(&card, ovr(-0.1)), Some(NackCode::OverrideRange));
    assert_eq!(raw(&card, ovr(f64::NAN)), Some(NackCode::NotFinite));
    // A command the card takes after its deadline is refused, not executed.
    let mut late = mv(0, &good);
    late.deadline_ms = host_time(&card).wrapping_sub(10).max(1);
    expect(NackCode::Expired, raw(&card, late));
    // Card configuration: out of range, then in range but with an axis enabled.
    assert_eq!(
        card.set_servo_rate(50).unwrap_err().kind(),
        ErrorKind::BadConfig
    );
    seen.push(NackCode::BadConfig);
    assert_eq!(
        card.set_servo_rate(2000).unwrap_err().kind(),
        ErrorKind::AxesEnabled
    );
    seen.push(NackCode::AxesEnabled);
    // Axis and card codes here; the group codes (16..31, 48..63) in tests/groups.rs and
    // tests/nurbs.rs, the safety codes (32..47) in tests/safety.rs, the homing codes (64..79)
    // in tests/homing.rs. PlanCheck is the card's
    // check of its own plans: no input reaches it through a correct planner (the planner's
    // property tests in card-emu's scurve module hold it).
    for code in NackCode::ALL
        .iter()
        .filter(|c| (**c as i32) < 16 && **c != NackCode::PlanCheck)
    {
        assert!(seen.contains(code), "{code:?} never provoked");
    }
    // Nothing moved: every refused move left the axis where it was.
    let s = card.axis(0).unwrap().status().unwrap();
    assert_eq!((s.state, s.raw.move_count), (AxisState::Standstill, 0));
}

/// On the bare firmware, with the host's view of the event ring: 1,000 commands (valid,
/// refused, unknown opcodes, bad axes, NaN) sent in bursts that wrap both rings many times.
/// Every seq gets exactly one answer, an ack or a nack, and no answer names a seq that was not
/// sent.
#[test]
fn every_command_gets_exactly_one_answer() {
    use card_emu::Firmware;
    use firmware_proto::mem::HeapWindow;
    use firmware_proto::ring::{CmdProducer, EvtConsumer, CMD_RING, EVT_RING};
    use firmware_proto::{Event, MAX_AXES};
    use std::collections::HashMap;

    let w = std::sync::Arc::new(HeapWindow::new());
    let mut fw = Firmware::boot(w.clone(), 4, 10_000);
    let mut tx = CmdProducer::attach(w.clone(), CMD_RING);
    let mut rx = EvtConsumer::attach(w.clone(), EVT_RING);
    let ops = [
        Opcode::Nop,
        Opcode::PowerOn,
        Opcode::MoveAbsolute,
        Opcode::MoveRelative,
        Opcode::Halt,
        Opcode::Stop,
        Opcode::StopRelease,
        Opcode::Reset,
        Opcode::PowerOff,
    ];
    let mut rng = common::Rng::new(7);
    let mut answers: HashMap<u32, (u32, u32)> = HashMap::new(); // seq -> (acks, nacks)
    let take = |rx: &mut EvtConsumer<_>, answers: &mut HashMap<u32, (u32, u32)>| {
        while let Some(e) = rx.pop::<Event>().unwrap() {
            match e.kind() {
                Some(EventKind::Ack) => answers.entry(e.seq).or_default().0 += 1,
                Some(EventKind::Nack) => answers.entry(e.seq).or_default().1 += 1,
                _ => {}
            }
        }
    };
    let (enc, mut dac) = ([0i64; MAX_AXES], [0.0; MAX_AXES]);
    let mut sent = Vec::new();
    // A host in command (the session gate refuses motion and power without one), beating
    // before each tick.
    let mut attach = Command::new(Opcode::HostAttach, 0);
    attach.flags = 1;
    attach.seq = tx.head().wrapping_add(1);
    tx.push(&attach).unwrap();
    sent.push(attach.seq);
    let beat = || {
        use firmware_proto::{layout, Mem};
        w.write32(
            layout::HEARTBEAT,
            w.read32(layout::HEARTBEAT).wrapping_add(1),
        );
    };
    while sent.len() < 1000 {
        // A burst of up to a ring's worth, then the card serves and ticks.
        let burst = 1 + rng.next_u64() % CMD_RING.len as u64;
        for _ in 0..burst {
            let op = ops[(rng.next_u64() % ops.len() as u64) as usize];
            let axis = (rng.next_u64() % 6) as u16; // 4 and 5 do not exist
            let pick = |r: &mut common::Rng| match r.next_u64() % 8 {
                0 => f64::NAN,
                1 => -1.0,
                _ => r.log_uniform(1e2, 1e7),
            };
            let args: Vec<f64> = (0..8).map(|_| pick(&mut rng)).collect();
            let mut c = Command::new(op, axis).with_args(&args);
            if rng.next_u64().is_multiple_of(16) {
                c.opcode = 200 + (rng.next_u64() % 50) as u16; // unknown
            }
            c.seq = tx.head().wrapping_add(1);
            if tx.push(&c).is_err() {
                break; // full: the card has not taken them yet
            }
            sent.push(c.seq);
        }
        while fw.serve_commands() > 0 {
            take(&mut rx, &mut answers);
        }
        beat();
        fw.tick(&enc, &mut dac);
        take(&mut rx, &mut answers);
    }
    for _ in 0..10 {
        fw.serve_commands();
        beat();
        fw.tick(&enc, &mut dac);
    }
    take(&mut rx, &mut answers);
    let (mut acks, mut nacks) = (0, 0);
    for s in &sent {
        let (a, n) = answers.remove(s).unwrap_or_default();
        assert_eq!(a + n, 1, "seq {s}: {a} acks and {n} nacks");
        acks += a;
        nacks += n;
    }
    assert!(
        answers.is_empty(),
        "answers to seqs never sent: {answers:?}"
    );
    assert!(acks > 50 && nacks > 50, "{acks} acks, {nacks} nacks");
}

#[test]
fn sdk_refuses_bad_arguments_before_the_card_sees_them() {
    let card = stepped_card();
    let ax = card.axis(0).unwrap();
    assert_eq!(card.axis(8).err().unwrap().kind(), ErrorKind::BadAxis);
    ax.enable().unwrap();
    assert_eq!(
        ax.move_absolute(f64::NAN, &lim()).err().unwrap().kind(),
        ErrorKind::NotFinite
    );
    let mut l = lim();
    l.jerk[2] = f64::INFINITY;
    assert_eq!(
        ax.move_relative(1.0, &l).err().unwrap().kind(),
        ErrorKind::NotFinite
    );
    assert_eq!(
        ax.move_relative(1.0, &lim().deceleration(0.0))
            .err()
            .unwrap()
            .kind(),
        ErrorKind::NonPositiveLimit
    );
    assert_eq!(
        ax.halt(-1.0, 1e6).err().unwrap().kind(),
        ErrorKind::NonPositiveLimit
    );
    // Zero, subnormal and absurd scales are refused; a negative one is a direction.
    for bad in [0.0, 1e-320, 1e-300, -1e-12, 1e300] {
        assert_eq!(
            ax.set_scale(bad).unwrap_err().kind(),
            ErrorKind::BadConfig,
            "{bad:e}"
        );
    }
    ax.set_scale(-2.5).unwrap();
    ax.set_scale(1.0).unwrap();
    let mut cfg = motioncard_sdk::AxisSettings::default();
    cfg.ffpiv.kp = f64::NAN;
    assert_eq!(ax.configure(&cfg).unwrap_err().kind(), ErrorKind::NotFinite);
    cfg.ffpiv.kp = -3.0; // finite but out of range: the card refuses it
    assert_eq!(ax.configure(&cfg).unwrap_err().kind(), ErrorKind::BadConfig);
    // Nothing was sent for the host-side refusals: the card accepted only power-on and configure.
    assert_eq!(ax.status().unwrap().raw.move_count, 0);
}

#[test]
fn halt_decelerates_within_limits_then_standstill_and_aborts_the_move() {
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let ax = card.axis(2).unwrap();
    ax.enable().unwrap();
    let m = ax.move_absolute(1e6, &lim()).unwrap();
    sim.step(3000); // cruising at 1e5 counts/s
    assert_eq!(ax.status().unwrap().state, AxisState::DiscreteMotion);
    let h = ax.halt(5e5, 2e7).unwrap();
    assert_eq!(
        m.wait(Duration::ZERO).unwrap_err().kind(),
        ErrorKind::Aborted
    );
    let mut peak_dec: f64 = 0.0;
    sim.trace(2, 20_000, |s| {
        peak_dec = peak_dec.max(-s.command_acceleration);
        s.state == AxisState::DiscreteMotion
    })
    .unwrap();
    assert!(
        peak_dec <= 5e5 * (1.0 + 1e-9) && peak_dec > 4.9e5,
        "peak deceleration {peak_dec}"
    );
    let at = h.wait(Duration::from_secs(1)).unwrap();
    let s = ax.status().unwrap();
    assert_eq!(s.state, AxisState::Standstill);
    assert!((at - s.raw.target).abs() <= 1.0 && s.raw.target < 1e6);
    // Moves work again.
    ax.move_relative(-1000.0, &lim())
        .unwrap()
        .wait(Duration::from_secs(2))
        .unwrap();
}

#[test]
fn stop_holds_stopping_until_released_and_blocks_moves() {
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let ax = card.axis(0).unwrap();
    ax.enable().unwrap();
    ax.move_relative(5e5, &lim()).unwrap();
    sim.step(2000);
    let st = ax.stop(1e6, 5e7).unwrap();
    st.wait(Duration::from_secs(2)).unwrap();
    sim.step(1000);
    assert_eq!(ax.status().unwrap().state, AxisState::Stopping);
    assert_eq!(
        ax.move_relative(10.0, &lim()).err().unwrap().kind(),
        ErrorKind::InvalidState
    );
    assert_eq!(
        ax.halt(1e6, 1e7).err().unwrap().kind(),
        ErrorKind::InvalidState
    );
    ax.release_stop().unwrap();
    sim.step(1);
    assert_eq!(ax.status().unwrap().state, AxisState::Standstill);
    assert_eq!(
        ax.release_stop().unwrap_err().kind(),
        ErrorKind::InvalidState
    );
    ax.move_relative(10.0, &lim())
        .unwrap()
        .wait(Duration::from_secs(1))
        .unwrap();
}

#[test]
fn power_off_mid_move_aborts_and_disables() {
    let card = stepped_card();
    let sim = card.sim().unwrap();
    let ax = card.axis(4).unwrap();
    ax.enable().unwrap();
    let m = ax.move_relative(5e5, &lim()).unwrap();
    sim.step(500);
    ax.disable().unwrap();
    let err = m.wait(Duration::from_millis(10)).unwrap_err();
    assert_eq!(err.kind(), ErrorKind::Aborted);
    assert!(err.to_string().contains("PowerOff"), "{err}");
    sim.step(10);
    let s = ax.status().unwrap();
    assert_eq!((s.state, s.dac_volts), (AxisState::Disabled, 0.0));
    // State-change events were raised in order: Standstill, DiscreteMotion, Disabled.
    let states: Vec<i32> = std::iter::from_fn(|| card.next_event(Duration::ZERO).unwrap())
        .filter(|e| e.kind == EventKind::StateChanged && e.axis == 4)
        .map(|e| e.code)
        .collect();
    assert_eq!(
        states,
        vec![
            AxisState::Standstill as i32,
            AxisState::DiscreteMotion as i32,
            AxisState::Disabled as i32
        ]
    );
}

#[test]
fn servo_rate_is_configurable_between_1_and_20_khz() {
    let card = stepped_card();
    let sim = card.sim().unwrap();
    for hz in [1000, 20_000, 4000] {
        card.set_servo_rate(hz).unwrap();
        assert_eq!(card.info().servo_rate_hz, hz);
        let ax = card.axis(0).unwrap();
        ax.enable().unwrap();
        let t0 = sim.time();
        let pos = ax
            .move_relative(20_000.0, &lim())
            .unwrap()
            .wait(Duration::from_secs(3))
            .unwrap();
        let planned = ax.status().unwrap().raw.planned_time;
        assert!(
            sim.time() - t0 >= planned,
            "{hz} Hz: done before the profile ended"
        );
        assert!(
            (pos - ax.status().unwrap().raw.target).abs() <= 1.0,
            "{hz} Hz: done at {pos}"
        );
        ax.disable().unwrap();
    }
    assert_eq!(
        card.set_servo_rate(20_001).unwrap_err().kind(),
        ErrorKind::BadConfig
    );
    assert_eq!(
        card.set_servo_rate(999).unwrap_err().kind(),
        ErrorKind::BadConfig
    );
}

/// Issue 39: `Card::statuses` (C: `mc_get_statuses`) gives every axis of one servo tick, on a
/// card whose firmware publishes a tick every 100 µs while the host reads: 20,000 reads of all
/// 8 axes, each with one tick (two axes came from ticks 959653 and 959657 before).
#[test]
fn statuses_of_several_axes_are_of_one_tick() {
    let card = Card::open("sim").unwrap();
    let axes: Vec<usize> = (0..8).collect();
    let mut ticks = std::collections::BTreeSet::new();
    for _ in 0..20_000 {
        let s = card.statuses(&axes).unwrap();
        let t = s[0].raw.tick;
        assert!(
            s.iter().all(|st| st.raw.tick == t),
            "{:?}",
            s.iter().map(|st| st.raw.tick).collect::<Vec<_>>()
        );
        ticks.insert(t);
    }
    assert!(
        ticks.len() > 10,
        "the card ran while the host read ({} ticks)",
        ticks.len()
    );
}

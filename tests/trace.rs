//! API trace and replay: a recorded run replayed on an emulated card matches; a tampered trace
//! reports its first difference.
use motioncard::{Card, Clock, EmuOptions, ErrorKind, MoveLimits, SimOptions, TRACE_ENV};
use std::path::PathBuf;
use std::time::Duration;

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mc-trace-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// A run with configuration, moves, a refusal and a halt, recorded.
fn record(path: &std::path::Path, clock: Clock) {
    let card = Card::open_sim_traced(
        SimOptions {
            clock,
            emu: EmuOptions::new(3, 10_000),
        },
        path,
    )
    .unwrap();
    let (a0, a1) = (card.axis(0).unwrap(), card.axis(1).unwrap());
    a0.enable().unwrap();
    a1.enable().unwrap();
    a1.configure(&motioncard::AxisSettings {
        in_pos_window: 3.0,
        ..Default::default()
    })
    .unwrap();
    let lim = MoveLimits::new(2e4, 4e5, 2e7);
    let m = a0.move_absolute(3_000.0, &lim).unwrap();
    let m1 = a1.move_relative(-1_500.0, &lim).unwrap();
    m.wait(Duration::from_secs(10)).unwrap();
    assert_eq!(
        a0.move_absolute(f64::NAN, &lim).unwrap_err().kind(),
        ErrorKind::NotFinite
    );
    m1.wait(Duration::from_secs(10)).unwrap();
    a0.move_velocity(-5_000.0, &motioncard::VelocityLimits::new(4e5, 2e7))
        .unwrap();
    let h = a0.halt(4e5, 2e7).unwrap();
    h.wait(Duration::from_secs(10)).unwrap();
    card.close().unwrap();
}

#[test]
fn a_recorded_run_replays_without_a_difference() {
    let path = temp("stepped.trace");
    record(&path, Clock::Stepped);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.starts_with("# motioncard trace 1\nI "), "{text}");
    assert!(
        text.lines().any(|l| l.starts_with("W ")),
        "a block write is traced"
    );
    let r = motioncard::replay(&path).unwrap();
    assert_eq!(r.difference, None, "{r:?}");
    assert!(r.commands >= 7 && r.events >= 15, "{r:?}");
    assert_eq!(r.header.axes, 3);
}

#[test]
fn a_run_on_a_real_time_card_replays_too() {
    let path = temp("realtime.trace");
    record(&path, Clock::RealTime);
    let r = motioncard::replay(&path).unwrap();
    assert_eq!(r.difference, None, "{r:?}");
}

#[test]
fn a_tampered_trace_reports_its_first_difference() {
    let path = temp("tampered.trace");
    record(&path, Clock::Stepped);
    let text = std::fs::read_to_string(&path).unwrap();
    // The first move's target 3000 becomes 3001: its motion-done position differs first.
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let (i, line) = lines
        .iter()
        .enumerate()
        .find(|(_, l)| l.starts_with("C ") && l.split(' ').nth(6) == Some("3000.0"))
        .map(|(i, l)| (i, l.clone()))
        .expect("the move");
    let mut f: Vec<&str> = line.split(' ').collect();
    f[6] = "3001.0";
    lines[i] = f.join(" ");
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    let r = motioncard::replay(&path).unwrap();
    let (n, why) = r.difference.expect("a difference");
    assert!(n > i + 1, "after the tampered command: line {n}");
    assert!(why.contains("MotionDone") || why.contains("value"), "{why}");
    // Not a trace at all.
    std::fs::write(&path, "hello\n").unwrap();
    assert_eq!(
        motioncard::replay(&path).unwrap_err().kind(),
        ErrorKind::BadConfig
    );
}

#[test]
fn the_environment_turns_the_trace_on() {
    let path = temp("env.trace");
    // Only this test sets it, before its own open (the other tests open traced explicitly).
    std::env::set_var(TRACE_ENV, &path);
    let card = Card::open("sim").unwrap();
    std::env::remove_var(TRACE_ENV);
    card.axis(2).unwrap().enable().unwrap();
    card.close().unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\nI 1 "), "{text}");
    assert!(
        text.lines().filter(|l| l.starts_with("C ")).count() >= 3,
        "{text}"
    );
    let r = motioncard::replay(&path).unwrap();
    assert_eq!(r.difference, None, "{r:?}");
}

/// A run that ended its own session with a raw detach (and began it again with a raw attach)
/// replays as recorded: the moves refused outside the session are refused on the replaying
/// card too (its session ends where the traced one did), and the one after the attach runs.
#[test]
fn a_trace_that_detached_its_session_replays_its_refusals() {
    use motioncard::proto::{Command, Opcode};
    let path = temp("detached.trace");
    let card = Card::open_sim_traced(
        SimOptions {
            clock: Clock::Stepped,
            emu: EmuOptions::new(2, 10_000),
        },
        &path,
    )
    .unwrap();
    let ax = card.axis(0).unwrap();
    ax.enable().unwrap();
    let own = card.safety_status().unwrap().session;
    let session_op = |op: Opcode| {
        let mut c = Command::new(op, 0);
        c.flags = own;
        card.execute_raw(c)
    };
    session_op(Opcode::HostDetach).unwrap();
    let vel = motioncard::VelocityLimits::new(4e5, 2e7);
    assert_eq!(
        ax.move_velocity(5_000.0, &vel).unwrap_err().kind(),
        ErrorKind::NoSession
    );
    session_op(Opcode::HostAttach).unwrap();
    ax.move_relative(2_000.0, &MoveLimits::new(2e4, 4e5, 2e7))
        .unwrap()
        .wait(Duration::from_secs(10))
        .unwrap();
    card.close().unwrap();
    let r = motioncard::replay(&path).unwrap();
    assert_eq!(r.difference, None, "{r:?}");
    let text = std::fs::read_to_string(&path).unwrap();
    let detaches = text
        .lines()
        .filter(|l| l.starts_with("C ") && l.split(' ').nth(3) == Some("37"))
        .count();
    assert_eq!(detaches, 2, "the raw detach and the close's");
}

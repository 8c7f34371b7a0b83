//! API trace and replay: a recorded run replayed on an emulated card matches; a tampered trace
//! reports its first difference.
use motioncard_sdk::{Card, Clock, EmuOptions, ErrorKind, MoveLimits, SimOptions, TRACE_ENV};
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
    a1.configure(&motioncard_sdk::AxisSettings {
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
    a0.move_velocity(-5_000.0, &motioncard_sdk::VelocityLimits::new(4e5, 2e7))
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
    let r = motioncard_sdk::replay(&path).unwrap();
    assert_eq!(r.difference, None, "{r:?}");
    assert!(r.commands >= 7 && r.events >= 15, "{r:?}");
    assert_eq!(r.header.axes, 3);
}

#[test]
fn a_run_on_a_real_time_card_replays_too() {
    let path = temp("realtime.trace");
    record(&path, Clock::RealTime);
    let r = motioncard_sdk::replay(&path).unwrap();
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
    let r = motioncard_sdk::replay(&path).unwrap();
    let (n, why) = r.difference.expect("a difference");
    assert!(n > i + 1, "after the tampered command: line {n}");
    assert!(why.contains("MotionDone") || why.contains("value"), "{why}");
    // Not a trace at all.
    std::fs::write(&path, "hello\n").unwrap();
    assert_eq!(
        motioncard_sdk::replay(&path).unwrap_err().kind(),
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
    let r = motioncard_sdk::replay(&path).unwrap();
    assert_eq!(r.difference, None, "{r:?}");
}

/// The tick of the trace's last motion-done event set to `tick`.
fn with_last_motion_tick(text: &str, tick: &str) -> (String, usize) {
    let kind = (motioncard_sdk::EventKind::MotionDone as u16).to_string();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let i = lines
        .iter()
        .rposition(|l| l.starts_with("E ") && l.split(' ').nth(2) == Some(kind.as_str()))
        .expect("a motion-done event");
    let mut f: Vec<&str> = lines[i].split(' ').collect();
    f[6] = tick;
    lines[i] = f.join(" ");
    (lines.join("\n") + "\n", i + 1)
}

/// Replays in a thread of its own: `None` if still stepping after 30 s.
fn replay_within(
    path: &std::path::Path,
) -> Option<motioncard_sdk::Result<motioncard_sdk::ReplayReport>> {
    let (tx, rx) = std::sync::mpsc::channel();
    let p = path.to_path_buf();
    std::thread::spawn(move || tx.send(motioncard_sdk::replay(&p)));
    rx.recv_timeout(Duration::from_secs(30)).ok()
}

/// A recorded tick beyond the trace's own span (10¹⁵ or 2⁶³ in a trace of a fraction of a
/// second: decades of stepping at 3 s per 10⁶ ticks) or before the event before it is
/// refused before anything is replayed, naming its line.
#[test]
fn a_tick_beyond_the_traces_span_is_refused_before_the_replay() {
    let path = temp("far.trace");
    record(&path, Clock::Stepped);
    let text = std::fs::read_to_string(&path).unwrap();
    for tick in [
        "1000000000000000",
        "9223372036854775808",
        "18446744073709551615",
    ] {
        let (bad, line) = with_last_motion_tick(&text, tick);
        std::fs::write(&path, bad).unwrap();
        let t0 = std::time::Instant::now();
        let r = replay_within(&path).expect("refused at once, not stepped to the tick");
        let e = r.unwrap_err();
        assert_eq!(e.kind(), ErrorKind::BadConfig, "{e}");
        let msg = e.to_string();
        assert!(
            msg.contains(&format!("line {line}: tick {tick} is ")) && msg.contains("ticks after"),
            "{msg}"
        );
        assert!(t0.elapsed() < Duration::from_secs(5));
    }
    let (bad, line) = with_last_motion_tick(&text, "3");
    std::fs::write(&path, bad).unwrap();
    let e = motioncard_sdk::replay(&path).unwrap_err();
    assert!(
        e.to_string()
            .contains(&format!("line {line}: tick 3 is before")),
        "{e}"
    );
    // A later tick the trace's time allows (every tick from there on 500,000 later): the card's
    // own event is found where it comes, before that tick.
    let (_, line) = with_last_motion_tick(&text, "0");
    let shifted: Vec<String> = text
        .lines()
        .enumerate()
        .map(|(i, l)| {
            let mut f: Vec<String> = l.split(' ').map(String::from).collect();
            if i + 1 >= line && f[0] == "E" {
                f[6] = (f[6].parse::<u64>().unwrap() + 500_000).to_string();
            }
            f.join(" ")
        })
        .collect();
    std::fs::write(&path, shifted.join("\n") + "\n").unwrap();
    let r = replay_within(&path)
        .expect("found at the card's event")
        .unwrap();
    let (n, why) = r.difference.expect("a difference");
    assert_eq!(n, line, "{why}");
    assert!(
        why.contains("MotionDone") && why.contains("the card posted MotionDone"),
        "{why}"
    );
}

/// A run that ended its own session with a raw detach (and began it again with a raw attach)
/// replays as recorded: the moves refused outside the session are refused on the replaying
/// card too (its session ends where the traced one did), and the one after the attach runs.
#[test]
fn a_trace_that_detached_its_session_replays_its_refusals() {
    use motioncard_sdk::proto::{Command, Opcode};
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
    let vel = motioncard_sdk::VelocityLimits::new(4e5, 2e7);
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
    let r = motioncard_sdk::replay(&path).unwrap();
    assert_eq!(r.difference, None, "{r:?}");
    let text = std::fs::read_to_string(&path).unwrap();
    let detaches = text
        .lines()
        .filter(|l| l.starts_with("C ") && l.split(' ').nth(3) == Some("37"))
        .count();
    assert_eq!(detaches, 2, "the raw detach and the close's");
}

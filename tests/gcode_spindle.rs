//! The spindle on a card axis, coolant on card outputs, and G33/G33.1 on a stepped card, tick
//! by tick: the thread's lead against the spindle's encoder, the angle passes start at, a rigid
//! tap's way in and out, the spindle's speed, and the errors with their lines.
mod common;

use common::xyz_card;
use motioncard_sdk::gcode::run::{
    group_position, Hooks, RunSettings, RunState, Runner, SpindleSettings,
};
use motioncard_sdk::gcode::{Options, Program};
use motioncard_sdk::{AxisState, Card, Error, ErrorKind, Group};

/// The servo period of the stepped card, s.
const TS: f64 = 1e-4;
/// The spindle axis.
const SPINDLE: usize = 3;
/// Mist and flood outputs.
const MIST: u32 = 4;
const FLOOD: u32 = 5;

/// A stepped card: group 0 over X, Y, Z in mm (1000 counts a mm; 100 mm/s, 1000 mm/s², 10⁵
/// mm/s³), axis 3 the spindle in revolutions (its encoder's 10,000 counts a revolution).
fn spindle_card() -> (Card, Group) {
    let (card, g) = xyz_card();
    let sp = card.axis(SPINDLE).unwrap();
    sp.set_scale(10_000.0).unwrap();
    sp.enable().unwrap();
    (card, g)
}

/// Up to 3000 rpm, 100 rev/s², 2000 rev/s³; mist and flood on outputs 4 and 5.
fn settings() -> RunSettings {
    RunSettings {
        spindle: Some(SpindleSettings::new(SPINDLE, 3000.0, 100.0, 2000.0)),
        mist_output: Some(MIST),
        flood_output: Some(FLOOD),
        ..RunSettings::default()
    }
}

/// Messages, with their lines.
#[derive(Default)]
struct Msgs(Vec<(usize, String)>);

impl Hooks for Msgs {
    fn message(&mut self, line: usize, text: &str) {
        self.0.push((line, text.into()));
    }
}

/// One servo tick as the host reads it after the card ran it.
#[derive(Debug, Clone, Copy)]
struct Tick {
    /// The line whose segment the group runs (0: none).
    line: usize,
    x: f64,
    /// Z commanded and actual, mm.
    z: f64,
    z_act: f64,
    /// The spindle's encoder, revolutions; its commanded velocity, rev/s.
    turns: f64,
    rps_cmd: f64,
    spindle: AxisState,
    outputs: u32,
}

/// Runs `text` from where the group is, a tick at a time, reading the card after each tick.
fn run_sampled(
    card: &Card,
    g: &Group,
    text: &str,
    settings: RunSettings,
) -> (
    motioncard_sdk::Result<RunState>,
    Vec<Tick>,
    Vec<(usize, String)>,
) {
    let opts = Options {
        start: group_position(g, "XYZ").unwrap(),
        ..Options::default()
    };
    let program = Program::from_text(text, &opts);
    let mut r = Runner::new(g, program, settings, Msgs::default()).unwrap();
    let sim = card.sim().unwrap();
    let mut ticks = Vec::new();
    let result = loop {
        match r.poll() {
            Ok(RunState::Running | RunState::Draining) => {}
            other => break other,
        }
        assert!(ticks.len() < 400_000, "the program runs on");
        sim.step(1);
        let s = card.statuses(&[0, 1, 2, SPINDLE]).unwrap();
        ticks.push(Tick {
            line: r.running_line().unwrap(),
            x: s[0].command_position,
            z: s[2].command_position,
            z_act: s[2].actual_position,
            turns: s[3].actual_position,
            rps_cmd: s[3].command_velocity,
            spindle: s[3].state,
            outputs: card.outputs().unwrap(),
        });
    };
    let msgs = std::mem::take(&mut r.hooks_mut().0);
    (result, ticks, msgs)
}

/// How far `s` mm along a thread of `pitch` mm is from the helix through the spindle's index,
/// mm: `s = pitch · (turns − n)` for some whole `n`.
fn helix_error(s: f64, turns: f64, pitch: f64) -> f64 {
    let q = s / pitch - turns;
    pitch * (q - q.round())
}

/// The spindle's angle (revolutions, interpolated between ticks) where Z first crosses `z`
/// going down in `ticks`.
fn angle_at(ticks: &[Tick], z: f64) -> f64 {
    let i = ticks.iter().position(|t| t.z <= z).expect("Z gets there");
    let (a, b) = (&ticks[i - 1], &ticks[i]);
    a.turns + (b.turns - a.turns) * (a.z - z) / (a.z - b.z)
}

fn frac_diff(a: f64, b: f64) -> f64 {
    let d = a - b;
    (d - d.round()).abs()
}

/// Two passes of one G33 (1.5 mm at 600 rpm, Z1 to Z-20), the second after a longer wait:
/// on the thread Z stays on the helix through the spindle's index (commanded within 0.1 µm,
/// actual within 10 µm), and both passes reach 0.05 mm (on the ramp-in) and 1 mm (on the
/// thread) at the same spindle angle, within two encoder counts, though they began at
/// angles 0.1 revolution or more apart. Each pass ends at Z-20.
#[test]
fn g33_follows_the_spindle_and_passes_start_at_the_same_angle() {
    let (card, g) = spindle_card();
    let text = "\
G21 G90
S600 M3
G0 X1 Z1
G33 Z-20 K1.5
G0 X5
G0 Z1
G0 X1
G4 P0.37
G33 Z-20 K1.5
G0 X5
M5
M2
";
    let (r, ticks, _) = run_sampled(&card, &g, text, settings());
    assert_eq!(r.unwrap(), RunState::Done);
    // The passes: X at 1 and Z below its start.
    let mut passes: Vec<Vec<Tick>> = Vec::new();
    let mut before: Vec<f64> = Vec::new();
    let mut prev_in = false;
    for (i, t) in ticks.iter().enumerate() {
        let inside = (t.x - 1.0).abs() < 1e-9 && t.z < 1.0 - 1e-9;
        if inside && !prev_in {
            passes.push(Vec::new());
            // Where the spindle was when the group got to the start (the first tick there).
            let j = (0..i)
                .rev()
                .take_while(|&j| (ticks[j].x - 1.0).abs() < 1e-9)
                .last()
                .unwrap();
            before.push(ticks[j].turns);
        }
        if inside {
            passes.last_mut().unwrap().push(*t);
        }
        prev_in = inside;
    }
    assert_eq!(passes.len(), 2);
    let mut worst = (0.0f64, 0.0f64);
    for p in &passes {
        let mut n = 0;
        for t in p.iter().filter(|t| t.z < 0.5 && t.z > -19.5) {
            let s = 1.0 - t.z;
            worst.0 = worst.0.max(helix_error(s, t.turns, 1.5).abs());
            worst.1 = worst.1.max(helix_error(1.0 - t.z_act, t.turns, 1.5).abs());
            n += 1;
        }
        // 19 mm at 15 mm/s: about 12,700 ticks.
        assert!(n > 12_000, "{n} ticks on the thread");
        let last = p.last().unwrap();
        assert!((last.z + 20.0).abs() < 1e-6, "the pass ends at {}", last.z);
    }
    println!(
        "thread lead: commanded {:.2e} mm, actual {:.2e} mm from the helix",
        worst.0, worst.1
    );
    assert!(worst.0 < 1e-4, "commanded Z {} mm off the helix", worst.0);
    assert!(worst.1 < 0.01, "actual Z {} mm off the helix", worst.1);
    // The passes began at different angles...
    assert!(
        frac_diff(before[0], before[1]) > 0.1,
        "{before:?}: the test needs passes that start out of phase"
    );
    // ...and reach the ramp and the thread at the same angle.
    for depth in [0.05, 1.0] {
        let (a, b) = (
            angle_at(&passes[0], 1.0 - depth),
            angle_at(&passes[1], 1.0 - depth),
        );
        let d = frac_diff(a, b) * 10_000.0;
        println!("{depth} mm deep: passes {d:.3} counts apart ({a:.5}, {b:.5} rev)");
        assert!(d <= 2.0, "{depth} mm: {d} counts apart");
    }
}

/// G33.1 (1 mm at 600 rpm, Z2 to Z-10): the tap goes in and comes out on the same helix (the
/// spindle reversed between), past Z-10 by no more than the spindle takes to stop, and ends
/// at Z2 with the spindle turning forward at 600 rpm again.
#[test]
fn g33_1_taps_in_and_out_and_restores_the_spindle() {
    let (card, g) = spindle_card();
    let text = "G21 G90\nS600 M3\nG0 Z2\nG33.1 Z-10 K1\nM2\n";
    let (r, ticks, _) = run_sampled(&card, &g, text, settings());
    assert_eq!(r.unwrap(), RunState::Done);
    let deepest = ticks.iter().map(|t| t.z).fold(f64::MAX, f64::min);
    // The spindle stops from 10 rev/s within 100 rev/s² and 2000 rev/s³ in v²/2a + v·a/2j =
    // 0.75 revolutions: 0.75 mm past the end (and a tick's 0.01).
    assert!(
        (-10.76..=-10.7).contains(&deepest),
        "the tap reached {deepest}"
    );
    let reversed = ticks.iter().map(|t| t.rps_cmd).fold(f64::MAX, f64::min);
    assert_eq!(reversed, -10.0, "the spindle reversed");
    // In and out, after the rapid to Z2.
    let at_start = ticks.iter().position(|t| t.z >= 2.0 - 1e-9).unwrap();
    let mut worst = (0.0f64, 0.0f64);
    let mut n = 0;
    for t in ticks[at_start..].iter().filter(|t| t.z < 1.0 && t.z > -9.0) {
        worst.0 = worst.0.max(helix_error(2.0 - t.z, t.turns, 1.0).abs());
        worst.1 = worst.1.max(helix_error(2.0 - t.z_act, t.turns, 1.0).abs());
        n += 1;
    }
    println!(
        "tap: {deepest} deepest; commanded {:.2e} mm, actual {:.2e} mm from the helix",
        worst.0, worst.1
    );
    // 10 mm in and out at 10 mm/s: about 20,000 ticks.
    assert!(n > 19_000, "{n} ticks on the thread");
    assert!(worst.0 < 1e-4, "commanded Z {} mm off the helix", worst.0);
    assert!(worst.1 < 0.01, "actual Z {} mm off the helix", worst.1);
    let last = ticks.last().unwrap();
    assert!((last.z - 2.0).abs() < 1e-9, "the tap ends at {}", last.z);
    assert!(
        (last.z_act - 2.0).abs() < 0.005,
        "actually at {}",
        last.z_act
    );
    assert_eq!(last.spindle, AxisState::ContinuousMotion);
    assert_eq!(last.rps_cmd, 10.0);
    let st = card.axis(SPINDLE).unwrap().status().unwrap();
    assert!(st.motion.contains(motioncard_sdk::MotionFlags::IN_VELOCITY));
    assert_eq!(g.status().unwrap().0, motioncard_sdk::GroupState::Standby);
}

/// M3 S600 turns the spindle at 600 rpm (measured on its encoder over a dwell), S1200 at 1200,
/// an S above the largest runs at the largest with a message naming the line, M4 backward, M5
/// stops it; M8 sets the flood output, M7 the mist, M9 clears both.
#[test]
fn the_spindle_turns_at_its_speed_and_coolant_sets_its_outputs() {
    let (card, g) = spindle_card();
    let text = "\
M8
S600 M3
G4 P0.5
M7
S1200
G4 P0.5
S4000
G4 P0.2
M4 S300
G4 P0.5
M9 M5
G4 P0.1
M2
";
    let (r, ticks, msgs) = run_sampled(&card, &g, text, settings());
    assert_eq!(r.unwrap(), RunState::Done);
    let dwell =
        |line: usize| -> Vec<Tick> { ticks.iter().filter(|t| t.line == line).copied().collect() };
    let rpm = |d: &[Tick]| (d[d.len() - 1].turns - d[0].turns) / ((d.len() - 1) as f64 * TS) * 60.0;
    let flood = 1 << FLOOD;
    let mist = 1 << MIST;
    for (line, want, outputs) in [
        (3, 600.0, flood),
        (6, 1200.0, flood | mist),
        (8, 3000.0, flood | mist),
        (10, -300.0, flood | mist),
    ] {
        let d = dwell(line);
        assert!(d.len() > 1000, "line {line}: {} ticks", d.len());
        let got = rpm(&d);
        println!("line {line}: {got:.3} rpm");
        assert!(
            (got - want).abs() < 0.5,
            "line {line}: {got} rpm, want {want}"
        );
        assert!(d.iter().all(|t| t.rps_cmd == want / 60.0), "line {line}");
        assert!(
            d.iter().all(|t| t.outputs & (flood | mist) == outputs),
            "line {line}"
        );
    }
    let d = dwell(12);
    assert!(d.iter().all(|t| t.spindle == AxisState::Standstill));
    assert!(d.iter().all(|t| t.outputs & (flood | mist) == 0));
    assert_eq!(msgs.len(), 1, "{msgs:?}");
    assert_eq!(msgs[0].0, 7);
    assert!(msgs[0].1.contains("3000"), "{msgs:?}");
}

/// G33 without a spindle on the card, with the spindle stopped, too fast for the axes, and a
/// tap whose spindle reverses harder than Z may follow: `Error::Gcode` naming the line, Z not
/// moved. A spindle axis inside the group is refused.
#[test]
fn thread_errors_name_their_line() {
    let gcode_line = |e: Error| match e {
        Error::Gcode(g) => (g.line, g.message),
        e => panic!("not a G-code error: {e:?}"),
    };
    for (text, settings, line, what) in [
        (
            "G0 Z1\nS600 M3\nG33 Z-5 K1\nM2\n",
            RunSettings::default(),
            3,
            "no spindle",
        ),
        ("G0 Z1\nG33 Z-5 K1\nM2\n", settings(), 2, "stopped"),
        (
            "G0 Z1\nS600 M3\nM5\nG33.1 Z-5 K1\nM2\n",
            settings(),
            4,
            "stopped",
        ),
        (
            "S3000 M3\nG0 Z1\nG33 Z-5 K5\nM2\n",
            settings(),
            3,
            "above its limit",
        ),
        ("G0 Z1\nS600 M3\nG33 Z-5 K0\nM2\n", settings(), 3, "pitch"),
        (
            "S600 M3\nG33.1 Z-5 K4\nM2\n",
            RunSettings {
                spindle: Some(SpindleSettings::new(SPINDLE, 3000.0, 500.0, 2000.0)),
                ..settings()
            },
            2,
            "reversal",
        ),
    ] {
        let (card, g) = spindle_card();
        let (r, ticks, _) = run_sampled(&card, &g, text, settings);
        let (l, m) = gcode_line(r.unwrap_err());
        assert_eq!(l, line, "{text}: {m}");
        assert!(m.contains(what), "{text}: {m}");
        let z = ticks.last().map_or(0.0, |t| t.z);
        assert!(z >= 0.0, "{text}: Z moved to {z}");
    }
    let (_, g) = spindle_card();
    let bad = RunSettings {
        spindle: Some(SpindleSettings::new(2, 3000.0, 100.0, 2000.0)),
        ..RunSettings::default()
    };
    let p = Program::from_text("M2\n", &Options::default());
    let e = Runner::new(&g, p, bad, Msgs::default()).err().unwrap();
    assert_eq!(e.kind(), ErrorKind::BadConfig);
}

/// `mcctl run` with the spindle on axis 3: a tap comes back to its start (the JSON's end);
/// without `--spindle-axis` the same program is refused at the G33.1's line.
#[test]
fn mcctl_run_taps_with_the_spindle_on_a_card_axis() {
    let dir = std::env::temp_dir().join(format!("gcode-spindle-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("tap.ngc");
    std::fs::write(
        &file,
        "G21 G90\nS600 M3 M8\nG0 X5 Z2\nG33.1 Z-6 K1\nM9 M5\nM2\n",
    )
    .unwrap();
    let f = file.to_str().unwrap();
    let (code, out, err) = common::mcctl(&[
        "run",
        f,
        "--spindle-axis",
        "3",
        "--flood-output",
        "5",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    let end = &j["end"];
    assert!((end["x"].as_f64().unwrap() - 5.0).abs() < 1e-6, "{j}");
    assert!((end["z"].as_f64().unwrap() - 2.0).abs() < 1e-6, "{j}");
    let (code, _, err) = common::mcctl(&["run", f, "--json"]);
    assert_eq!(code, 1);
    assert!(
        err.contains("line 4") && err.contains("no spindle"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// An abort in the middle of a thread halts its axes within their limits (Z short of the end,
/// a few tenths of a millimetre past where the abort came), ends the run, and leaves the group
/// disabled with its axes at rest.
#[test]
fn an_abort_in_a_thread_halts_its_axes() {
    let (card, g) = spindle_card();
    let opts = Options {
        start: group_position(&g, "XYZ").unwrap(),
        ..Options::default()
    };
    let program = Program::from_text("S600 M3\nG33 Z-20 K1.5\nM2\n", &opts);
    let mut r = Runner::new(&g, program, settings(), Msgs::default()).unwrap();
    let sim = card.sim().unwrap();
    let z = || card.axis(2).unwrap().status().unwrap();
    let mut ticks = 0;
    while z().command_position > -5.0 {
        assert_eq!(r.poll().unwrap(), RunState::Draining);
        sim.step(1);
        ticks += 1;
        assert!(ticks < 100_000, "Z does not get to -5");
    }
    r.abort(1000.0, 1e5).unwrap();
    assert_eq!(r.poll().unwrap(), RunState::Aborted);
    sim.step(5000);
    let s = z();
    assert_eq!(s.state, AxisState::Standstill);
    // 15 mm/s stopped within 1000 mm/s² and 10⁵ mm/s³: v²/2a + v·a/2j = 0.19 mm.
    assert!(
        (-5.3..-5.0).contains(&s.command_position),
        "Z stopped at {}",
        s.command_position
    );
    assert_eq!(g.status().unwrap().0, motioncard_sdk::GroupState::Disabled);
}

/// With the spindle turning backward (M4) the axes follow it the same way: on the thread Z is
/// `pitch` per backward revolution from the helix through the index, and the pass ends at its
/// end.
#[test]
fn g33_with_m4_follows_the_spindle_backward() {
    let (card, g) = spindle_card();
    let text = "M4 S450\nG0 Z1\nG33 Z-9 K1.25\nM2\n";
    let (r, ticks, _) = run_sampled(&card, &g, text, settings());
    assert_eq!(r.unwrap(), RunState::Done);
    let at_start = ticks.iter().position(|t| t.z >= 1.0 - 1e-9).unwrap();
    let mut worst: f64 = 0.0;
    let mut n = 0;
    for t in ticks[at_start..].iter().filter(|t| t.z < 0.5 && t.z > -8.5) {
        // The spindle's revolutions counted backward.
        worst = worst.max(helix_error(1.0 - t.z, -t.turns, 1.25).abs());
        n += 1;
    }
    // 9 mm at 9.375 mm/s: about 9,600 ticks.
    assert!(n > 9_000, "{n} ticks on the thread");
    assert!(worst < 1e-4, "{worst} mm off the helix");
    let last = ticks.last().unwrap();
    assert!((last.z + 9.0).abs() < 1e-6, "the pass ends at {}", last.z);
    assert!(
        last.turns < -5.0,
        "the spindle turned backward: {}",
        last.turns
    );
}

/// M19 on the card: the turning spindle halts, then turns on to the angle (P0: forward, the
/// way M3 turns), and rests there; P1 goes back to it. G87 back bores with two oriented
/// stops: the spindle rests at its index each time the tool passes through the hole, and
/// turns again (M3's way) after.
#[test]
fn m19_orients_the_spindle_and_g87_back_bores_through_it() {
    let (card, g) = spindle_card();
    let text = "\
S600 M3
G4 P0.3
M19 R90
G4 P0.1
M19 R45 P1
G4 P0.1
G0 X0 Y0 Z5
M3
G98 G87 X2 Y3 Z-5 R1 I1 J-0.5 K-1 F600
G80
M2
";
    let (r, ticks, _) = run_sampled(&card, &g, text, settings());
    assert_eq!(r.unwrap(), RunState::Done);
    let on =
        |line: usize| -> Vec<Tick> { ticks.iter().filter(|t| t.line == line).copied().collect() };
    let frac = |turns: f64| turns.rem_euclid(1.0);
    // Line 4: at rest at 90° (a quarter turn), reached turning forward.
    let d = on(4);
    let before = on(2).last().unwrap().turns;
    assert!(d.iter().all(|t| t.spindle == AxisState::Standstill));
    let at = d.last().unwrap().turns;
    assert!((frac(at) - 0.25).abs() < 2e-4, "at {at}");
    assert!(at > before, "{at} after {before}: went back");
    // Line 6: back to 45°, less than a turn behind.
    let at6 = on(6).last().unwrap().turns;
    assert!((frac(at6) - 0.125).abs() < 2e-4, "at {at6}");
    assert!(at6 < at && at - at6 < 1.0, "{at6} after {at}");
    // G87: while the tool goes down through the hole at the offset point (X3 Y2.5) the
    // spindle rests at its index; over the back bore (X2 Y3) it turns.
    let g87 = on(9);
    let down: Vec<_> = g87
        .iter()
        .filter(|t| (t.x - 3.0).abs() < 1e-9 && t.z < 0.0)
        .collect();
    assert!(!down.is_empty());
    for t in &down {
        assert_eq!(t.spindle, AxisState::Standstill);
        let f = frac(t.turns);
        assert!(f.min(1.0 - f) < 2e-4, "through the hole at {} rev", t.turns);
    }
    assert!(g87
        .iter()
        .any(|t| (t.x - 2.0).abs() < 1e-9 && t.z > -1.5 && t.rps_cmd == 10.0));
    let last = ticks.last().unwrap();
    assert!((last.z - 5.0).abs() < 1e-9 && (last.x - 2.0).abs() < 1e-9);
    assert_eq!(last.rps_cmd, 10.0, "the spindle turns again after G87");
}

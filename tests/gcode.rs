//! RS274/NGC programs end to end: through the SDK's runner on a stepped card (machine
//! positions exact), through `mcctl gcode`'s dry run (the operations' JSON) and `mcctl run`
//! (blending measured), with answers worked out from the RS274/NGC rules, not from our output;
//! and the reader's memory on a million lines and on a 10 MB line.
mod common;

use common::{mcctl, mcctl_peak_rss, xyz_card};
use motioncard_sdk::gcode::run::{group_position, Hooks, NoHooks, RunSettings, RunState, Runner};
use motioncard_sdk::gcode::{Op, Options, Pos, Program};
use motioncard_sdk::Card;
use std::f64::consts::PI;
use std::time::Duration;

/// Every operation's end, as the runner reads them.
#[derive(Default)]
struct Ends(Vec<(usize, Pos)>);

impl Hooks for Ends {
    fn op(&mut self, op: &Op) {
        if let Some((_, e)) = op.kind.ends() {
            self.0.push((op.line, e));
        }
    }
}

/// Runs `text` on group 0 of a fresh stepped card to its end: the ends of its motions, and
/// the card's commanded X, Y, Z after it.
fn run_on_card(text: &str) -> (Vec<(usize, Pos)>, [f64; 3]) {
    let (card, g) = xyz_card();
    let opts = Options {
        start: group_position(&g, "XYZ").unwrap(),
        ..Options::default()
    };
    let program = Program::from_text(text, &opts);
    let mut r = Runner::new(&g, program, RunSettings::default(), Ends::default()).unwrap();
    assert_eq!(r.run(Duration::from_secs(600)).unwrap(), RunState::Done);
    let s = card.statuses(&[0, 1, 2]).unwrap();
    let at = [
        s[0].command_position,
        s[1].command_position,
        s[2].command_position,
    ];
    (std::mem::take(&mut r.hooks_mut().0), at)
}

fn near(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

/// A work offset set by G10 L2 and used, G92 then G92.1, G53, a subroutine whose #1 is
/// restored after the call, a while loop: each move's machine end, and the card there.
#[test]
fn offsets_subroutines_and_loops_end_where_the_rules_say() {
    let text = "\
G21 G90 G64 P0.01
G10 L2 P1 X10 Y5
G54 G0 X0 Y0
G92 X100 Y100
G0 X101
G92.1
G0 X1 Y1
G53 G0 X0 Y0 Z5
#1 = 7
o10 sub
  G0 Z[#1]
o10 endsub
o10 call [2]
G0 X#1
#2 = 0
o20 while [#2 LT 4]
  #2 = [#2 + 1]
  G91 G0 Y1
o20 endwhile
G90
M2
";
    let (ends, at) = run_on_card(text);
    let want: &[(usize, [f64; 3])] = &[
        // G54 at X10 Y5: the work origin.
        (3, [10.0, 5.0, 0.0]),
        // G92 makes here X100 Y100: X101 is one more.
        (5, [11.0, 5.0, 0.0]),
        // G92.1 cleared it: X1 Y1 in G54.
        (7, [11.0, 6.0, 0.0]),
        // G53: machine coordinates, this line only.
        (8, [0.0, 0.0, 5.0]),
        // the call's #1 is 2
        (11, [0.0, 0.0, 2.0]),
        // #1 is 7 again after the call: X7 in G54.
        (14, [17.0, 0.0, 2.0]),
        (18, [17.0, 1.0, 2.0]),
        (18, [17.0, 2.0, 2.0]),
        (18, [17.0, 3.0, 2.0]),
        (18, [17.0, 4.0, 2.0]),
    ];
    assert_eq!(ends.len(), want.len(), "{ends:?}");
    for ((line, e), (wline, w)) in ends.iter().zip(want) {
        assert_eq!(line, wline);
        assert!(near(&e[..3], w, 1e-12), "line {line}: {e:?}, want {w:?}");
    }
    assert!(near(&at, &[17.0, 4.0, 2.0], 1e-9), "the card at {at:?}");
}

/// G2 with P2 goes round twice: on the card it ends where it started its last turn, and the
/// dry run gives its length as 4π·r.
#[test]
fn g2_with_p2_turns_twice() {
    let text = "G0 X10\nG2 X10 Y0 I-10 P2 F1200\nM2\n";
    let (_, at) = run_on_card(text);
    assert!(near(&at, &[10.0, 0.0, 0.0], 1e-9), "{at:?}");
    let dir = tempdir("p2");
    let file = dir.join("p2.ngc");
    std::fs::write(&file, text).unwrap();
    let ops = dry_run(&[file.to_str().unwrap()]);
    let arc = &ops[1];
    assert_eq!(arc["kind"], "arc");
    assert_eq!(arc["line"], 2);
    let length = arc["length"].as_f64().unwrap();
    assert!((length - 4.0 * PI * 10.0).abs() < 1e-9, "{length}");
    std::fs::remove_dir_all(&dir).ok();
}

fn tempdir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("gcode-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `mcctl gcode FILE … --json`: one object a line.
fn dry_run(args: &[&str]) -> Vec<serde_json::Value> {
    let mut a = vec!["gcode"];
    a.extend_from_slice(args);
    a.push("--json");
    let (code, out, err) = mcctl(&a);
    assert_eq!(code, 0, "{err}");
    out.lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
        .collect()
}

fn end_of(op: &serde_json::Value) -> [f64; 3] {
    ["x", "y", "z"].map(|k| op["end"][k].as_f64().unwrap())
}

/// G81 with G98, in inches, under G43 with a tool 10 mm long (the tool table file): rapid
/// over the hole at the initial level, rapid to R, feed to the bottom, rapid back to the
/// initial level, every Z raised by the tool's length; the feed 10 in/min.
#[test]
fn a_drilling_cycle_in_inches_under_tool_length_compensation() {
    let dir = tempdir("g81");
    let tools = dir.join("tool.tbl");
    std::fs::write(&tools, "T1 P1 Z10 D6 ;6 mm drill\n").unwrap();
    let file = dir.join("g81.ngc");
    std::fs::write(
        &file,
        "G20 G90 G17\nT1 M6\nG43 H1\nG0 X0 Y0 Z1\nG98 G81 X1 Y0.5 Z-0.25 R0.1 F10\nG80\nM2\n",
    )
    .unwrap();
    let ops = dry_run(&[
        file.to_str().unwrap(),
        "--tool-table",
        tools.to_str().unwrap(),
    ]);
    let kinds: Vec<&str> = ops.iter().map(|o| o["kind"].as_str().unwrap()).collect();
    assert_eq!(
        kinds,
        [
            "tool_change",
            "rapid",
            "rapid",
            "rapid",
            "feed",
            "rapid",
            "end"
        ],
        "{ops:?}"
    );
    assert_eq!(ops[0]["tool"], 1);
    let initial = 25.4 + 10.0;
    let want = [
        [0.0, 0.0, initial],
        [25.4, 12.7, initial],
        [25.4, 12.7, 2.54 + 10.0],
        [25.4, 12.7, -6.35 + 10.0],
        [25.4, 12.7, initial],
    ];
    for (op, w) in ops[1..6].iter().zip(want) {
        assert!(near(&end_of(op), &w, 1e-9), "{op} want {w:?}");
        assert_eq!(op["line"], if w == [0.0, 0.0, initial] { 4 } else { 5 });
    }
    let feed = &ops[4];
    assert!((feed["feed"].as_f64().unwrap() - 254.0 / 60.0).abs() < 1e-12);
    assert!((feed["length"].as_f64().unwrap() - 8.89).abs() < 1e-9);
    std::fs::remove_dir_all(&dir).ok();
}

/// G41 around a 20 mm square with a 4 mm tool (radius 2), clockwise (the tool on the left is
/// outside): every side's end 2 mm outside the square, an arc of radius 2 round each convex
/// corner.
#[test]
fn g41_keeps_the_tool_outside_a_square() {
    let dir = tempdir("g41");
    let tools = dir.join("tool.tbl");
    std::fs::write(&tools, "T2 P2 D4\n").unwrap();
    let file = dir.join("g41.ngc");
    std::fs::write(
        &file,
        "T2 M6\nG0 X-10 Y-10\nG41 D2\nG1 X0 Y0 F600\nY20\nX20\nY0\nX0\nG40\nG0 X-10 Y-10\nM2\n",
    )
    .unwrap();
    let ops = dry_run(&[
        file.to_str().unwrap(),
        "--tool-table",
        tools.to_str().unwrap(),
    ]);
    // The sides (lines 5 to 8) and their corner arcs, after the entry move.
    let cut: Vec<&serde_json::Value> = ops
        .iter()
        .filter(|o| (5..=8).contains(&o["line"].as_u64().unwrap()))
        .collect();
    let feeds = cut.iter().filter(|o| o["kind"] == "feed").count();
    let arcs: Vec<_> = cut.iter().filter(|o| o["kind"] == "arc").collect();
    assert_eq!(feeds, 4, "{cut:?}");
    assert_eq!(
        arcs.len(),
        3,
        "three convex corners between the four sides: {cut:?}"
    );
    for a in &arcs {
        assert!((a["length"].as_f64().unwrap() - PI).abs() < 1e-9, "{a}");
    }
    // The distance of a point outside the square [0, 20]² from it.
    let outside = |p: [f64; 3]| {
        let dx = (-p[0]).max(p[0] - 20.0).max(0.0);
        let dy = (-p[1]).max(p[1] - 20.0).max(0.0);
        dx.hypot(dy)
    };
    for o in cut.iter().filter(|o| o["kind"] == "feed") {
        let d = outside(end_of(o));
        assert!((d - 2.0).abs() < 1e-9, "{o}: {d} from the square");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The same corners under G64 P0.05 and under G61 on the card (`mcctl run`, every tick
/// measured): a polyline of 7.07 mm sides turning 30° at each corner, as a CAM contour does.
/// The blends stay within 0.05 mm (and use it: more than `--tolerance`), G61 stops at every
/// corner and stays on the path, and blending is faster. (At 90° corners at these limits an
/// exact stop is as fast as any blend within 0.05 mm: the reversing axis's jerk and
/// acceleration leave no faster way round.)
#[test]
fn g64_p_blends_within_its_tolerance_and_g61_stops() {
    let dir = tempdir("g64");
    let (mut x, mut y) = (0.0f64, 0.0f64);
    let mut contour = String::new();
    for i in 1..=8 {
        let a = if i % 2 == 1 { 15f64 } else { -15.0 }.to_radians();
        x += 7.07 * a.cos();
        y += 7.07 * a.sin();
        contour += &format!("X{x:.4} Y{y:.4}\n");
    }
    let run = |mode: &str| {
        let file = dir.join(format!("{}.ngc", mode.replace(' ', "")));
        std::fs::write(&file, format!("{mode}\nG1 F3000\n{contour}M2\n")).unwrap();
        let (code, out, err) = mcctl(&[
            "run",
            file.to_str().unwrap(),
            "--tolerance",
            "0.001",
            "--json",
        ]);
        assert_eq!(code, 0, "{err}");
        serde_json::from_str::<serde_json::Value>(out.trim()).unwrap()
    };
    let (blend, exact) = (run("G64 P0.05"), run("G61"));
    let f = |j: &serde_json::Value, k: &str| j[k].as_f64().unwrap();
    let dev = f(&blend, "max_deviation");
    assert!(
        dev <= 0.05 * (1.0 + 1e-6),
        "G64 P0.05 went {dev} mm from the path"
    );
    assert!(
        dev > 0.01,
        "G64 P0.05 used only {dev} mm: the P is not in effect"
    );
    assert_eq!(blend["exact_stops"], 0, "{blend}");
    assert_eq!(exact["exact_stops"], 7, "{exact}");
    assert!(f(&exact, "max_deviation") < 1e-6, "{exact}");
    assert!(
        f(&blend, "path_time") < 0.9 * f(&exact, "path_time"),
        "G64 {blend} G61 {exact}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The reader's memory is bounded by its longest line: a million lines peak within 2 MB of
/// ten thousand, and a line of 10 MB is refused, naming its line, without holding it.
#[test]
fn a_million_lines_and_a_ten_megabyte_line_in_bounded_memory() {
    let dir = tempdir("memory");
    let write = |name: &str, n: usize| {
        let file = dir.join(name);
        let mut text = String::from("G1 F600\n");
        for i in 0..n {
            text += &format!("X{}.{:03} Y{}\n", i % 100, i % 1000, i % 7);
        }
        std::fs::write(&file, text).unwrap();
        file
    };
    let peak = |file: &std::path::Path| {
        let (code, out, err, peak) = mcctl_peak_rss(&["gcode", file.to_str().unwrap()]);
        assert_eq!(code, 0, "{err}");
        (out.lines().count(), peak)
    };
    let (small_ops, small) = peak(&write("small.ngc", 10_000));
    let (big_ops, big) = peak(&write("big.ngc", 1_000_000));
    assert_eq!((small_ops, big_ops), (10_000, 1_000_000));
    assert!(
        big < small + 2048,
        "{big} kB for 10^6 lines, {small} kB for 10^4"
    );
    let long = dir.join("long.ngc");
    std::fs::write(&long, format!("G0 X1\nG0 X2 ({})\n", "c".repeat(10 << 20))).unwrap();
    let (code, _, err, long_peak) = mcctl_peak_rss(&["gcode", long.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(err.contains("line 2: line longer than"), "{err}");
    assert!(long_peak < small + 2048, "{long_peak} kB for a 10 MB line");
    std::fs::remove_dir_all(&dir).ok();
}

/// A pause asked for while the program runs takes effect at the end of a block: under G61
/// (an exact stop at every corner) the end of the block running, at rest on its programmed
/// end; under G64 P0.05 the end of the first block the path can stop at, where the blend into
/// the next starts (within 0.05 mm of the block's end). What was queued stays queued, and
/// after `resume` the run ends where the program does. An abort halts along the path and
/// reads nothing more.
#[test]
fn pause_resume_and_abort_from_the_host() {
    let sides: String = (1..=20)
        .map(|i| format!("X{} Y{}\n", 10 * i, if i % 2 == 1 { 10 } else { 0 }))
        .collect();
    // line n + 1 ends side n
    let corner = |line: usize| {
        let i = line - 1;
        [10.0 * i as f64, if i % 2 == 1 { 10.0 } else { 0.0 }, 0.0]
    };
    let start = |mode: &str| {
        let text = format!("{mode} G1 F6000\n{sides}M2\n");
        let (card, g) = xyz_card();
        let opts = Options::default();
        let settings = RunSettings::default();
        let r = Runner::new(
            &g,
            Program::from_text(text, &opts),
            settings,
            Ends::default(),
        )
        .unwrap();
        (card, r)
    };
    let at = |card: &Card| {
        let s = card.statuses(&[0, 1, 2]).unwrap();
        [
            s[0].command_position,
            s[1].command_position,
            s[2].command_position,
        ]
    };
    for (mode, tol) in [("G61", 1e-9), ("G64 P0.05", 0.05 + 1e-9)] {
        let (card, mut r) = start(mode);
        // run until the fourth side (line 5) is running
        let mut k = 0;
        while r.running_line().unwrap() != 5 {
            r.poll().unwrap();
            r.idle().unwrap();
            k += 1;
            assert!(k < 100_000, "{mode}: line 5 never ran");
        }
        r.pause().unwrap();
        assert_eq!(r.run(Duration::from_secs(600)).unwrap(), RunState::Paused);
        let line = r.running_line().unwrap();
        if mode == "G61" {
            assert_eq!(line, 5, "{mode}: paused at the end of the block running");
        } else {
            assert!((5..=6).contains(&line), "{mode}: paused after line {line}");
        }
        let here = at(&card);
        assert!(
            near(&here, &corner(line), tol),
            "{mode}: at {here:?}, line {line} ends at {:?}",
            corner(line)
        );
        assert!(matches!(
            card.group(0).unwrap().path_pause_state().unwrap(),
            motioncard_sdk::PauseState::Paused { id } if id as usize == line
        ));
        for _ in 0..100 {
            assert_eq!(r.poll().unwrap(), RunState::Paused);
            r.idle().unwrap();
        }
        assert_eq!(at(&card), here, "{mode}: held");
        r.resume().unwrap();
        assert_eq!(r.run(Duration::from_secs(600)).unwrap(), RunState::Done);
        assert!(
            near(&at(&card), &[200.0, 0.0, 0.0], 1e-9),
            "{mode}: {:?}",
            at(&card)
        );
        // the path was the program's: within its tolerance all along
        let rep = r.report().unwrap().unwrap();
        assert!(rep.max_deviation <= tol.max(1e-6), "{mode}: {rep:?}");
    }

    // Aborted a second into the run: halted on the path, short of its end, nothing more read.
    let (card, mut r) = start("G61");
    for _ in 0..10_000 {
        r.poll().unwrap();
        r.idle().unwrap();
    }
    r.abort(1000.0, 1e5).unwrap();
    assert_eq!(r.poll().unwrap(), RunState::Aborted);
    for _ in 0..5_000 {
        r.idle().unwrap();
    }
    let end = at(&card);
    assert!(end[0] > 0.0 && end[0] < 200.0, "{end:?}");
    let g = card.group(0).unwrap();
    assert_eq!(g.status().unwrap().0, motioncard_sdk::GroupState::Standby);
}

/// The fuzzer's corpus for the reader and interpreter (`fuzz/corpus/gcode`, grown by `cargo
/// +nightly fuzz run gcode` from the example programs), replayed on stable: no input panics,
/// and none runs on (at most 100,000 operations are taken, as the fuzz target does).
#[test]
fn the_fuzz_corpus_reads_without_a_panic() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/fuzz/corpus/gcode");
    let mut inputs = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let data = std::fs::read(entry.unwrap().path()).unwrap();
        let text = String::from_utf8_lossy(&data).into_owned();
        for op in Program::from_text(text, &Options::default()).take(100_000) {
            if op.is_err() {
                break;
            }
        }
        inputs += 1;
    }
    assert!(inputs > 100, "{inputs} inputs in {dir}");
}

/// `(DEBUG, …)` texts, as the runner reads them.
#[derive(Default)]
struct Debug(Vec<String>);

impl Hooks for Debug {
    fn message(&mut self, _line: usize, text: &str) {
        self.0.push(text.to_string());
    }
}

/// G38.2–G38.5 on the card, a probe on input 5 switching as Z passes −3.217 mm (active
/// below): the card halts the group itself on the capture, #5063 holds the trip within a
/// count, the program goes on from where Z came to rest (just past the trip); G38.4/G38.5
/// find the same point from the other side (the probe opening); a G38.3 that touches nothing ends at its end with
/// #5070 = 0, a G38.2 that touches nothing is an error, and so is a probe already tripped.
/// `cargo test --release --test gcode g38 -- --nocapture` prints the trips.
#[test]
fn g38_probes_on_the_card_and_the_program_uses_the_result() {
    const TRIP: f64 = -3.217;
    let start = |text: &str, input: Option<u32>| {
        let (card, g) = xyz_card();
        card.sim().unwrap().with_emulator(|e| {
            e.inputs().set_sensor(
                5,
                Some(motioncard_sdk::Sensor {
                    axis: 2,
                    at: TRIP * 1000.0,
                    active_above: false,
                }),
            )
        });
        card.sim().unwrap().step(2);
        let settings = RunSettings {
            probe_input: input,
            ..RunSettings::default()
        };
        let program = Program::from_text(text.to_string(), &Options::default());
        let r = Runner::new(&g, program, settings, Debug::default()).unwrap();
        (card, r)
    };
    let z = |card: &Card| card.statuses(&[2]).unwrap()[0].command_position;
    let text = "\
G21 G90 G0 X1 Y2 Z0
G38.2 Z-10 F100
(DEBUG, #5063 #5070 #5422)
G38.4 Z5 F50
(DEBUG, #5063 #5070 #5422)
G38.3 Z-10 F50
(DEBUG, #5063 #5070 #5422)
G38.5 Z5 F20
(DEBUG, #5063 #5070 #5422)
G0 Z[#5063 + 1]
G38.3 Z[#5063 + 0.5] F100
(DEBUG, #5063 #5070 #5422)
M2
";
    let (card, mut r) = start(text, Some(5));
    assert_eq!(r.run(Duration::from_secs(600)).unwrap(), RunState::Done);
    let seen: Vec<Vec<f64>> = r
        .hooks_mut()
        .0
        .iter()
        .map(|t| t.split_whitespace().map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(seen.len(), 5, "{seen:?}");
    // G38.2 down, G38.4 up (until the probe opens), G38.3 down, G38.5 up: each trip within
    // a count (1 µm) of the switching point, and Z at rest just past it (#5422, the
    // program's position), never short of it.
    println!(
        "| probe | feed, mm/min | tripped at (#5063) | error, µm | came to rest past it, µm |"
    );
    println!("|---|---:|---:|---:|---:|");
    for (k, (s, down)) in seen[..4].iter().zip([true, false, true, false]).enumerate() {
        println!(
            "| {} | {} | {:.6} | {:+.1} | {:.1} |",
            ["G38.2 down", "G38.4 up", "G38.3 down", "G38.5 up"][k],
            [100, 50, 50, 20][k],
            s[0],
            (s[0] - TRIP) * 1e3,
            (s[0] - s[2]).abs() * 1e3
        );
        assert!(
            (s[0] - TRIP).abs() <= 0.0011,
            "probe {k}: tripped at {}",
            s[0]
        );
        assert_eq!(s[1], 1.0);
        let past = if down { s[0] - s[2] } else { s[2] - s[0] };
        assert!(
            past > 0.0 && past < 0.05,
            "probe {k}: rest {} mm past",
            past
        );
    }
    // The G0 to the trip + 1 mm from where the last probe stopped, then a G38.3 that
    // touches nothing: it ends at its end, #5070 = 0.
    // (the texts print 6 decimals)
    let tripped = seen[3][0];
    assert!((seen[4][0] - (tripped + 0.5)).abs() < 2e-6, "{seen:?}");
    assert_eq!(seen[4][1], 0.0);
    assert!(
        (z(&card) - (tripped + 0.5)).abs() < 2e-6,
        "{} {seen:?}",
        z(&card)
    );
    assert_eq!(
        card.axis(2).unwrap().touch_probe(0).status().unwrap().state,
        motioncard_sdk::IoState::Idle,
        "the probes are disarmed after the move"
    );

    // G38.2 that touches nothing: an error at the block after it, the machine at its end.
    let (card, mut r) = start("G0 Z0\nG38.2 Z-1 F100\nG0 Z1\n", Some(5));
    let e = r.run(Duration::from_secs(600)).unwrap_err();
    match e {
        motioncard_sdk::Error::Gcode(e) => {
            assert_eq!(e.line, 3);
            assert!(e.message.contains("line 2"), "{e}");
        }
        e => panic!("{e}"),
    }
    assert!((z(&card) + 1.0).abs() < 1e-9);
    // Already tripped; and no probe input set.
    for (text, input, line, says) in [
        ("G0 Z-5\nG38.2 Z-10 F100\n", Some(5), 2, "already tripped"),
        ("G0 Z0\nG38.4 Z-10 F100\n", Some(5), 2, "already open"),
        ("G38.2 Z-10 F100\n", None, 1, "no probe input"),
    ] {
        let (_card, mut r) = start(text, input);
        match r.run(Duration::from_secs(600)).unwrap_err() {
            motioncard_sdk::Error::Gcode(e) => {
                assert_eq!(e.line, line, "{text}: {e}");
                assert!(e.message.contains(says), "{text}: {e}");
            }
            e => panic!("{text}: {e}"),
        }
    }
}

/// G64 Q, LinuxCNC's "naive CAM" tolerance, is the chord fitter's: a circle of 10 mm radius
/// posted as 720 chords rounded to 3 decimals runs as the chords themselves under Q0 (every
/// one a segment on the card) and as a few fitted curves under Q0.005, each within its Q of
/// the points; without Q the fitter takes P's tolerance, as LinuxCNC does. The runner's own
/// report (`Runner::report`, every tick seen on the stepped card) measures each run.
#[test]
fn g64_q_is_the_chord_fitters_tolerance() {
    let mut chords = String::new();
    for k in 1..=720 {
        let a = (k as f64 * 0.5).to_radians();
        chords += &format!("X{:.3} Y{:.3}\n", 10.0 * a.cos() - 10.0, 10.0 * a.sin());
    }
    let run = |mode: &str| {
        let (card, g) = xyz_card();
        let opts = Options {
            start: group_position(&g, "XYZ").unwrap(),
            ..Options::default()
        };
        let text = format!("{mode}\nG1 F3000\n{chords}M2\n");
        let program = Program::from_text(&text, &opts);
        let mut r = Runner::new(&g, program, RunSettings::default(), Ends::default()).unwrap();
        assert_eq!(r.run(Duration::from_secs(600)).unwrap(), RunState::Done);
        let done = g.status().unwrap().1.path_done;
        let report = r.report().unwrap().unwrap();
        assert_eq!(report.ticks, report.ticks_seen, "{mode}: {report:?}");
        assert_eq!(report.segments, 720, "{mode}");
        drop(card);
        (done, report)
    };
    let (naive_off, off) = run("G64 P0.05 Q0");
    let (fitted, fit) = run("G64 P0.05 Q0.005");
    let (default, _) = run("G64 P0.05");
    // Finer than the coordinates' rounding: the fitter cannot hold the points so closely.
    let (fine, _) = run("G64 P0.05 Q0.0001");
    assert!(fine > 10 * fitted.max(1), "Q0.0001: {fine} segments");
    assert_eq!(naive_off, 720, "Q0: every chord a segment");
    assert!(fitted < 40, "Q0.005: {fitted} segments");
    assert!(
        default <= fitted,
        "no Q: P's tolerance ({default} vs {fitted})"
    );
    // Within Q of the points (and their 0.5 µm rounding) and the circle's 0.4 µm chord sag.
    assert!(fit.max_deviation < 0.005 + 1e-3, "{fit:?}");
    assert!(off.max_deviation < 0.05, "{off:?}");
    for r in [&off, &fit] {
        assert!(r.peak_vel_ratio <= 1.0 + 1e-9, "{r:?}");
        assert!(r.peak_accel_ratio <= 1.0 + 1e-6, "{r:?}");
        assert!(
            r.max_following_error > 0.0 && r.max_contour_error > 0.0,
            "{r:?}"
        );
    }
    eprintln!(
        "G64 Q: Q0 {naive_off} segments {:.4} s, Q0.005 {fitted} segments {:.4} s, no Q \
         {default} segments, Q0.0001 {fine} segments",
        off.path_time, fit.path_time
    );
    // A negative Q is refused, naming its line.
    let opts = Options::default();
    let err = Program::from_text("G1 X1 F100\nG64 P0.1 Q-1\n", &opts)
        .find_map(|op| op.err())
        .unwrap();
    assert_eq!(err.line, 2, "{err}");
    assert!(err.to_string().contains("G64 Q-1"), "{err}");
}

/// Subroutines in files (LinuxCNC's `SUBROUTINE_PATH`): `o<caller> call` runs `caller.ngc`
/// from the subroutine path, which calls `helper.ngc` from the program's own directory; #1
/// is the caller's again after the helper returns, and the caller's return value reaches the
/// program. As in LinuxCNC's `nested-sub-in-file-error` test, a second subroutine in a
/// subroutine file is not callable. Each error names its line and its file.
#[test]
fn subroutines_in_files_on_the_subroutine_path() {
    let dir = tempdir("subfiles");
    let subs = dir.join("subs");
    std::fs::create_dir_all(&subs).unwrap();
    let write = |path: std::path::PathBuf, text: &str| std::fs::write(path, text).unwrap();
    write(
        subs.join("caller.ngc"),
        "o<caller> sub\nG1 X#1 Y#2 Z#3 F600\no<helper> call [4] [5] [6]\nG1 X[#1*10]\n\
         o<caller> endsub [#1+#2+#3]\nM2\n",
    );
    write(
        dir.join("helper.ngc"),
        "o<helper> sub\nG1 X#1 Y#2 Z#3 F600\no<helper> endsub\nM2\n",
    );
    write(
        subs.join("sequential.ngc"),
        "o<sequential> sub\no200 call [4] [5] [6]\no<sequential> endsub\n\n\
         o200 sub\nG1 X#1\no200 endsub\nM2\n",
    );
    write(
        subs.join("other.ngc"),
        "o<another> sub\nG0 X1\no<another> endsub\n",
    );
    let opts = Options {
        subroutine_path: vec![subs.clone()],
        ..Options::default()
    };
    let run = |main: &str| {
        let file = dir.join("main.ngc");
        write(file.clone(), main);
        Program::open(&file, &opts)
            .unwrap()
            .collect::<Result<Vec<Op>, _>>()
    };
    let ops = run("G21 G90\no<caller> call [1] [2] [3]\nG0 Z[#<_value>*2]\nM2\n").unwrap();
    let ends: Vec<(usize, [f64; 3])> = ops
        .iter()
        .filter_map(|op| op.kind.ends().map(|(_, e)| (op.line, [e[0], e[1], e[2]])))
        .collect();
    assert_eq!(
        ends,
        vec![
            (2, [1.0, 2.0, 3.0]),   // caller.ngc line 2
            (2, [4.0, 5.0, 6.0]),   // helper.ngc line 2
            (4, [10.0, 5.0, 6.0]),  // caller.ngc line 4: #1 is 1 again
            (3, [10.0, 5.0, 12.0]), // main.ngc line 3: Z = 2 (1 + 2 + 3)
        ]
    );
    let err = run("o<sequential> call [7] [8] [9]\nM2\n").unwrap_err();
    assert_eq!(err.line, 2, "{err}");
    assert!(
        err.message.contains("no subroutine o200") && err.message.contains("sequential.ngc"),
        "{err}"
    );
    let err = run("G0 X1\no<missing> call\n").unwrap_err();
    assert_eq!(err.line, 2, "{err}");
    assert!(err.message.contains("no missing.ngc"), "{err}");
    let err = run("o<other> call\n").unwrap_err();
    assert!(
        err.message.contains("does not define o<other> sub"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A card with X, Y, Z and A (axes 0..3, 1000 counts a unit; Z's scale `z_scale`) in group 0,
/// and the group.
fn xyza_card(z_scale: f64) -> (Card, motioncard_sdk::Group) {
    let card = common::stepped_card();
    for a in 0..4 {
        let axis = card.axis(a).unwrap();
        axis.set_scale(if a == 2 { z_scale } else { 1000.0 })
            .unwrap();
        axis.enable().unwrap();
    }
    let g = card.group(0).unwrap();
    g.configure(&motioncard_sdk::GroupSettings::new(&[0, 1, 2, 3]))
        .unwrap();
    g.enable().unwrap();
    g.configure_path(&motioncard_sdk::PathSettings::uniform(
        4, 100.0, 1000.0, 1e5,
    ))
    .unwrap();
    (card, g)
}

/// A G18 helix in a coordinate system rotated 30° about Z (and moved to X3 Y−4): from work
/// X0 Z0 about X5 Z0, radius 5, clockwise in (Z, X) three quarters of a turn plus a whole one
/// (P2), rising 6 mm along the work Y axis while A turns 90°. On the card (one arc about
/// the rotated Y a turn, `MC_OP_PATH_ARC_NORMAL`) every tick's commanded point, taken back to
/// work coordinates, is on the cylinder of radius 5 about the work centre within 10⁻⁶ of the
/// radius, at the height and A the angle turned gives (within 10⁻⁶ relative), and the end is
/// the program's exactly; the report finds the commanded path on the programmed one; the dry
/// run gives it as `arc_normal` with its length √((r·θ)² + 6²). On a card whose Z has another
/// scale, the arc is refused with its line.
#[test]
fn a_helix_in_a_rotated_g18_plane_runs_on_its_helix() {
    let text = "G21 G90 G61\nG10 L2 P1 X3 Y-4 R30\nG0 X0 Y0 Z0 A0\n\
                G18 G2 X5 Z5 Y6 A90 I5 K0 P2 F1200\nG0 Y10\nM2\n";
    let (card, g) = xyza_card(1000.0);
    let opts = Options {
        start: group_position(&g, "XYZA").unwrap(),
        ..Options::default()
    };
    let settings = RunSettings {
        axes: "XYZA".into(),
        ..RunSettings::default()
    };
    let mut r = Runner::new(
        &g,
        Program::from_text(text, &opts),
        settings,
        Ends::default(),
    )
    .unwrap();
    let (s30, c30) = 30f64.to_radians().sin_cos();
    let work = |m: [f64; 4]| {
        let (x, y) = (m[0] - 3.0, m[1] + 4.0);
        [c30 * x + s30 * y, -s30 * x + c30 * y, m[2], m[3]]
    };
    let total = 1.75 * 2.0 * PI;
    let (mut turned, mut last_phi, mut ticks) = (0.0f64, None::<f64>, 0);
    let (mut worst_r, mut worst_h, mut worst_a) = (0.0f64, 0.0f64, 0.0f64);
    let mut state = RunState::Running;
    for _ in 0..2_000_000 {
        state = r.poll().unwrap();
        if state == RunState::Done {
            break;
        }
        let on_helix = r.running_line().unwrap() == 4;
        card.sim().unwrap().step(1);
        if !on_helix {
            continue;
        }
        let s = card.statuses(&[0, 1, 2, 3]).unwrap();
        let w = work([0, 1, 2, 3].map(|i| s[i].command_position));
        // in (Z, X) about (0, 5): the angle from the start's −π/2, clockwise
        let phi = (w[0] - 5.0).atan2(w[2]);
        if let Some(p) = last_phi {
            let mut d = p - phi;
            if d > PI {
                d -= 2.0 * PI;
            } else if d < -PI {
                d += 2.0 * PI;
            }
            turned += d;
        } else {
            turned = -PI / 2.0 - phi;
        }
        last_phi = Some(phi);
        let share = turned / total;
        worst_r = worst_r.max(((w[0] - 5.0).hypot(w[2]) - 5.0).abs() / 5.0);
        worst_h = worst_h.max((w[1] - 6.0 * share).abs() / 6.0);
        worst_a = worst_a.max((w[3] - 90.0 * share).abs() / 90.0);
        ticks += 1;
    }
    assert_eq!(state, RunState::Done);
    println!(
        "rotated helix: {ticks} ticks, worst radius {worst_r:.2e}, height {worst_h:.2e}, \
         A {worst_a:.2e} (relative)"
    );
    assert!(ticks > 1000, "{ticks}");
    assert!(
        (turned - total).abs() < 1e-6,
        "turned {turned}, want {total}"
    );
    assert!(worst_r <= 1e-6 && worst_h <= 1e-6 && worst_a <= 1e-6);
    // the helix's end, exactly (then the rapid along the work Y to Y10)
    let ends = std::mem::take(&mut r.hooks_mut().0);
    let (_, e) = ends.iter().find(|(l, _)| *l == 4).unwrap();
    let want = [
        3.0 + 5.0 * c30 - 6.0 * s30,
        -4.0 + 5.0 * s30 + 6.0 * c30,
        5.0,
        90.0,
    ];
    assert!(near(&e[..4], &want, 1e-12), "{e:?} vs {want:?}");
    let s = card.statuses(&[0, 1, 2, 3]).unwrap();
    let at = [0, 1, 2, 3].map(|i| s[i].command_position);
    let want = [
        3.0 + 5.0 * c30 - 10.0 * s30,
        -4.0 + 5.0 * s30 + 10.0 * c30,
        5.0,
        90.0,
    ];
    assert!(near(&at, &want, 1e-9), "{at:?} vs {want:?}");
    let rep = r.report().unwrap().unwrap();
    println!("rotated helix: report {rep:?}");
    assert!(rep.max_deviation <= 1e-6, "{rep:?}");

    let dir = tempdir("ghelix");
    let file = dir.join("helix.ngc");
    std::fs::write(&file, text).unwrap();
    let ops = dry_run(&[file.to_str().unwrap()]);
    let arc = ops.iter().find(|o| o["line"] == 4).unwrap();
    assert_eq!(arc["kind"], "arc_normal");
    let length = arc["length"].as_f64().unwrap();
    let want = (5.0 * total).hypot(6.0);
    assert!((length - want).abs() <= 1e-12 * want, "{length} vs {want}");
    let n = ["x", "y", "z"].map(|k| arc["normal"][k].as_f64().unwrap());
    assert!(near(&n, &[-s30, c30, 0.0], 1e-15), "{n:?}");
    std::fs::remove_dir_all(&dir).ok();

    // Z with another scale: refused with its line, the motion before it run
    let (_, g) = xyza_card(500.0);
    let settings = RunSettings {
        axes: "XYZA".into(),
        ..RunSettings::default()
    };
    let mut r = Runner::new(&g, Program::from_text(text, &opts), settings, NoHooks).unwrap();
    match r.run(Duration::from_secs(600)) {
        Err(motioncard_sdk::Error::Gcode(e)) => assert_eq!(e.line, 4, "{e}"),
        other => panic!("{other:?}"),
    }
}

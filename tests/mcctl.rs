//! `mcctl plan` from the outside: output, JSON, exit codes.
mod common;

/// An `emu:` card of `axes` axes served from this process on its real-time clock: it
/// outlives each mcctl process a test starts (named `<tag>-<pid>`).
struct EmuCard {
    uri: String,
    _server: card_emu::emu::server::Server,
    _runner: card_emu::Runner,
}

impl EmuCard {
    fn new(tag: &str, axes: usize) -> Self {
        use card_emu::{EmuOptions, Emulator, Runner};
        let name = format!("{tag}-{}", std::process::id());
        let emu = Emulator::create(&name, &EmuOptions::new(axes, 10_000)).unwrap();
        let _server = card_emu::emu::server::Server::start(&name, emu.lessor()).unwrap();
        let _runner = Runner::spawn(emu, card_emu::Clock::RealTime, false).unwrap();
        EmuCard {
            uri: format!("emu:{name}"),
            _server,
            _runner,
        }
    }

    /// mcctl on this card.
    fn on(&self, args: &[&str]) -> (i32, String, String) {
        let mut all = vec!["--card", self.uri.as_str()];
        all.extend_from_slice(args);
        mcctl(&all)
    }
}

use common::{mcctl, mcctl_peak_rss};
use std::process::Command;

#[test]
fn plan_json_matches_the_hand_computed_profile() {
    // vmax 1000, amax 1e4, jerk 1e6, distance 1e4: ramps of 0.01 + 0.09 + 0.01 s, cruise 9.89 s.
    let (code, out, _) = mcctl(&[
        "plan", "10000", "--vmax", "1000", "--amax", "1e4", "--jmax", "1e6", "--json",
    ]);
    assert_eq!(code, 0);
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    let phases: Vec<f64> = j["phases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let want = [0.01, 0.09, 0.01, 9.89, 0.01, 0.09, 0.01];
    for (p, w) in phases.iter().zip(want) {
        assert!((p - w).abs() < 1e-9, "{phases:?}");
    }
    assert!((j["duration"].as_f64().unwrap() - 10.11).abs() < 1e-9);
    assert!((j["peak_velocity"].as_f64().unwrap() - 1000.0).abs() < 1e-9);
}

#[test]
fn plan_table_and_asymmetric_limits() {
    let (code, out, _) = mcctl(&[
        "plan", "-5000", "--vmax", "2000", "--amax", "4e4", "--dmax", "1e4", "--jmax", "1e6",
        "--jdec", "2e5",
    ]);
    assert_eq!(code, 0);
    assert!(
        out.contains("phase 6 constant dec") && out.contains("total"),
        "{out}"
    );
}

#[test]
fn bad_arguments_exit_with_status_2_and_say_why() {
    for (args, why) in [
        (
            vec!["plan", "100", "--vmax", "0", "--amax", "1", "--jmax", "1"],
            "--vmax must be greater than zero",
        ),
        (
            vec!["plan", "100", "--vmax", "1", "--amax", "nan", "--jmax", "1"],
            "--amax must be a finite number",
        ),
        (
            vec![
                "plan", "100", "--vmax", "1", "--amax", "1", "--jmax", "1", "--v1", "5",
            ],
            "--v1 must be between 0 and --vmax",
        ),
        (
            vec![
                "plan", "1", "--vmax", "10", "--amax", "1", "--jmax", "1", "--v0", "10",
            ],
            "no S-curve satisfies",
        ),
    ] {
        let (code, _, err) = mcctl(&args);
        assert_eq!(code, 2, "{args:?}");
        assert!(err.contains(why), "{args:?}: {err}");
    }
    let (code, _, err) = mcctl(&["plan", "100", "--vmax", "abc"]);
    assert_eq!(code, 2);
    assert!(err.contains("invalid value"), "{err}");
}

/// Negative limits are values, refused for their sign, not taken for unknown flags.
#[test]
fn negative_limits_get_the_must_be_positive_message() {
    for (flag, value) in [
        ("--dmax", "-3"),
        ("--vmax", "-1000"),
        ("--amax", "-1e4"),
        ("--jmax", "-0.5"),
        ("--jdec", "-2e5"),
    ] {
        let mut args = vec![
            "plan", "100", "--vmax", "1000", "--amax", "1e4", "--jmax", "1e6",
        ];
        if let Some(i) = args.iter().position(|a| *a == flag) {
            args[i + 1] = value;
        } else {
            args.extend([flag, value]);
        }
        let (code, out, err) = mcctl(&args);
        assert_eq!(code, 2, "{args:?}: {out}");
        assert!(
            err.contains(&format!("{flag} must be greater than zero, got {value}"))
                || err.contains(&format!("{flag} must be greater than zero")),
            "{args:?}: {err}"
        );
        assert!(!err.contains("unexpected argument"), "{args:?}: {err}");
    }
    let (code, _, err) = mcctl(&[
        "plan", "100", "--vmax", "10", "--amax", "1", "--jmax", "1", "--v0", "-2",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("--v0 must be between 0 and --vmax"), "{err}");
    // A negative distance is a move backwards, as before.
    let (code, out, _) = mcctl(&[
        "plan", "-100", "--vmax", "10", "--amax", "100", "--jmax", "1e4",
    ]);
    assert_eq!(code, 0, "{out}");
}

/// Numbers outside their range are refused by clap as it parses (exit status 2, the argument
/// named, what it must be), before any card is opened: the card named here does not exist, so
/// a value that got past the parsing would fail opening it instead (exit status 1).
#[test]
fn values_out_of_range_are_refused_before_a_card_is_opened() {
    for (args, arg, why) in [
        (
            &["move", "0", "100", "--vmax", "-5"][..],
            "--vmax",
            "--vmax must be greater than zero, got -5",
        ),
        (
            &["halt", "0", "--dmax", "inf"],
            "--dmax",
            "--dmax must be a finite number, got inf",
        ),
        (
            &["jog", "0", "100", "--for", "-0.5"],
            "--for",
            "--for must be a number of seconds >= 0, got -0.5",
        ),
        (
            &["status", "--watch", "--interval", "0"],
            "--interval",
            "--interval must be a number of seconds > 0, got 0",
        ),
        (
            &["scope", "--divider", "0"],
            "--divider",
            "0 is not in 1..=65536",
        ),
        (
            &["scope", "--pre", "1025"],
            "--pre",
            "1025 is not in 0..=1024",
        ),
        (&["scope", "--samples", "0"], "--samples", "0 is not in 1.."),
        (
            &[
                "compare",
                "0",
                "--output",
                "3",
                "--at",
                "5",
                "--pulse-us",
                "0",
            ],
            "--pulse-us",
            "0 is not in 1..=1000000",
        ),
        (
            &["gear", "1", "--master", "0", "--slave-jmax", "0"],
            "--slave-jmax",
            "--slave-jmax must be greater than zero, got 0",
        ),
        (
            &["run", "part.ngc", "--tolerance", "-0.01"],
            "--tolerance",
            "--tolerance must be 0 or more, got -0.01",
        ),
        (
            &["run", "part.ngc", "--amax", "1000,0,1000"],
            "--amax",
            "--amax must be greater than zero, got 0",
        ),
        (
            &[
                "plan",
                "1",
                "--vmax",
                "1",
                "--amax",
                "1",
                "--jmax",
                "1",
                "--servo-rate",
                "0",
            ],
            "--servo-rate",
            "--servo-rate must be between 1000 and 20000 Hz, got 0",
        ),
    ] {
        let mut all = vec!["--card", "emu:no-such-card"];
        all.extend_from_slice(args);
        let (code, out, err) = mcctl(&all);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(&format!("for '{arg} <")), "{args:?}: {err}");
        assert!(err.contains(why), "{args:?}: {err}");
        assert!(out.is_empty(), "{args:?}: {out}");
    }
    // The same card, with the values in range: the open fails instead.
    let (code, _, err) = mcctl(&[
        "--card",
        "emu:no-such-card",
        "move",
        "0",
        "100",
        "--vmax",
        "5",
    ]);
    assert_eq!(code, 1, "{err}");
}

/// Distances and durations beyond what the card accepts are refused with the card's bound.
#[test]
fn distances_and_times_beyond_the_card_are_refused() {
    let lim = ["--vmax", "1e4", "--amax", "1e5", "--jmax", "1e7"];
    for d in ["1e300", "-1e300", "4503599627370497", "9e15"] {
        let mut args = vec!["plan", d];
        args.extend(lim);
        let (code, out, err) = mcctl(&args);
        assert_eq!(code, 2, "{d}: {out}");
        assert!(
            err.contains("distance must be at most 4503599627370496"),
            "{d}: {err}"
        );
    }
    // Within the position range, but at 1 count/s it would take 1e7 s.
    let (code, _, err) = mcctl(&[
        "plan", "1e7", "--vmax", "1", "--amax", "10", "--jmax", "100",
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("the card refuses moves longer than 1000000 s"),
        "{err}"
    );
    // The largest distance is fine with fast enough limits.
    let (code, out, err) = mcctl(&[
        "plan",
        "4503599627370496",
        "--vmax",
        "1e12",
        "--amax",
        "1e14",
        "--jmax",
        "1e16",
    ]);
    assert_eq!(code, 0, "{out}{err}");
}

/// Limits outside the range the card accepts at its servo rate (`firmware_proto::limit_range`)
/// are refused by name with the range, before any planning: they used to give zero-duration or
/// overshooting plans printed with exit 0.
#[test]
fn limits_outside_the_cards_range_are_refused() {
    let base = [
        "plan", "100000", "--vmax", "2e5", "--amax", "2e6", "--jmax", "1e8",
    ];
    let with = |flag: &'static str, value: &'static str| {
        let mut args = base.to_vec();
        match args.iter().position(|a| *a == flag) {
            Some(i) => args[i + 1] = value,
            None => args.extend([flag, value]),
        }
        args
    };
    for (args, why) in [
        (
            with("--jmax", "1e-300"),
            "--jmax must be between 1e-18 and 4.503599627370496e27 (the card's jerk range at \
             --servo-rate 10000 Hz), got 1e-300",
        ),
        (
            with("--amax", "1e-310"), // subnormal
            "--amax must be between 1e-12 and 4.503599627370496e23 (the card's acceleration \
             range at --servo-rate 10000 Hz), got 1e-310",
        ),
        (
            with("--dmax", "4e-320"), // subnormal
            "--dmax must be between 1e-12 and",
        ),
        (
            with("--vmax", "1e300"),
            "--vmax must be between 1e-6 and 4.503599627370496e19 (the card's velocity range \
             at --servo-rate 10000 Hz), got 1e300",
        ),
        (with("--jdec", "1e-320"), "--jdec must be between 1e-18 and"),
        // the range moves with the servo rate: 5e19 counts/s is 2^52 counts in 1/11102 s
        (
            with("--vmax", "5e19"),
            "--vmax must be between 1e-6 and 4.503599627370496e19",
        ),
        (
            with("--servo-rate", "999"),
            "--servo-rate must be between 1000 and 20000 Hz, got 999",
        ),
        (
            with("--servo-rate", "20001"),
            "--servo-rate must be between 1000 and 20000 Hz, got 20001",
        ),
    ] {
        let (code, out, err) = mcctl(&args);
        assert_eq!(code, 2, "{args:?}: {out}");
        assert!(err.contains(why), "{args:?}: {err}");
        assert!(out.is_empty(), "{args:?}: {out}");
    }
    // At 20 kHz 5e19 counts/s is inside, and the plan is printed.
    let mut args = with("--vmax", "5e19");
    args.extend(["--servo-rate", "20000", "--json"]);
    let (code, out, err) = mcctl(&args);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert!(j["duration"].as_f64().unwrap() > 0.0);
    // The ends of the range are inside.
    let (code, _, err) = mcctl(&[
        "plan", "1", "--vmax", "1e-6", "--amax", "1e-12", "--jmax", "1e-18",
    ]);
    assert_eq!(code, 2, "{err}"); // within range, but 1 count at these limits takes > 10^6 s
    assert!(err.contains("the card refuses moves longer than"), "{err}");
    let (code, _, err) = mcctl(&[
        "plan", "1e-3", "--vmax", "1e-6", "--amax", "1e-12", "--jmax", "1e-18",
    ]);
    assert_eq!(code, 0, "{err}");
}

/// Layout 1.10: `mcctl handwheel` selects the wheel, holds it, lets go (the wheel on a `sim`
/// card stands still: the axis stays); `--off` without a wheel, a bad input, ratio or detent
/// exit with status 1 and the card's reason.
#[test]
fn handwheel_selects_holds_and_lets_go() {
    let (code, out, err) = mcctl(&[
        "handwheel",
        "2",
        "--input",
        "1",
        "--ratio",
        "10",
        "--for",
        "0.1",
        "--enable",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(j["axis"], 2, "{out}");
    assert_eq!(j["ratio"], 10, "{out}");
    assert_eq!(j["detent"], 4, "{out}");
    assert_eq!(j["turned"], 0, "{out}");
    assert_eq!(j["moved"], 0.0, "{out}");
    for (args, why) in [
        (
            vec!["handwheel", "0", "--off"],
            "not allowed in the axis's current state",
        ),
        (
            vec!["handwheel", "0", "--input", "2", "--enable"],
            "no such handwheel",
        ),
        (
            vec!["handwheel", "0", "--ratio", "0", "--enable"],
            "bad handwheel ratio",
        ),
        (
            vec!["handwheel", "0", "--detent", "0", "--enable"],
            "bad handwheel ratio",
        ),
    ] {
        let (code, _, err) = mcctl(&args);
        assert_eq!(code, 1, "{args:?}: {err}");
        assert!(err.contains(why), "{args:?}: {err}");
    }
    let (code, _, err) = mcctl(&["handwheel", "0", "--off", "--ratio", "10"]);
    assert_eq!(code, 2, "{err}");
}

/// The card subcommands against an emulated card (`--card sim`, real time): a move waited for,
/// velocity mode for a while, jog, status as JSON; the card's refusals exit with status 1 and
/// its reason.
#[test]
fn card_commands_move_jog_override_and_status() {
    let (code, out, err) = mcctl(&["move", "0", "5000", "--enable", "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert!(
        (j["position"].as_f64().unwrap() - 5000.0).abs() <= 1.0,
        "{out}"
    );
    // Velocity mode for 0.2 s at -3000 counts/s, then the halt: about -600 counts.
    let (code, out, err) = mcctl(&[
        "move",
        "0",
        "-3000",
        "--velocity",
        "--for",
        "0.2",
        "--enable",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    let p = j["position"].as_f64().unwrap();
    // 0.2 s of wall time on a real-time card: under load the card's clock may fall behind
    // (the run under full CI load once gave -467), so only the order of magnitude is checked.
    assert!((-700.0..=-300.0).contains(&p), "{out}");
    let (code, out, err) = mcctl(&["jog", "1", "-20000", "--for", "0.1", "--enable"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("axis 1: jogged to -"), "{out}");
    let (code, out, _) = mcctl(&["status", "--json"]);
    assert_eq!(code, 0);
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(j["axes"].as_array().unwrap().len(), 8);
    assert_eq!(j["axes"][0]["state"], "Disabled");
    assert_eq!(j["groups"].as_array().unwrap().len(), 4);
    assert_eq!(j["groups"][0]["path_free"], 4096);
    for (args, why) in [
        (
            vec!["override", "0", "2.5"],
            "override factor is outside 0 to 2",
        ),
        (
            vec!["jog", "0", "1e6", "--enable"],
            "position or velocity out of range",
        ),
        (vec!["move", "0", "100"], "disabled"),
        (vec!["move", "9", "100"], "axis"),
    ] {
        let (code, _, err) = mcctl(&args);
        assert_eq!(code, 1, "{args:?}: {err}");
        assert!(err.contains(why), "{args:?}: {err}");
    }
    let (code, _, _) = mcctl(&["jog", "0", "100", "--for", "-1"]);
    assert_eq!(code, 2);
    // Homing: CiA 402 method 37 (the current position) makes it read --position.
    let (code, out, err) = mcctl(&[
        "home",
        "0",
        "--method",
        "37",
        "--position",
        "-250",
        "--enable",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(j["homed"], true, "{out}");
    assert!(
        (j["position"].as_f64().unwrap() + 250.0).abs() <= 1.0,
        "{out}"
    );
    let (code, _, err) = mcctl(&["home", "0", "--method", "99", "--enable"]);
    assert_eq!(code, 1);
    assert!(err.contains("cannot do this homing method"), "{err}");
}

/// `--a0` plans from any state (Ruckig's position interface): here a start at 1.5 vmax moving
/// away from the target, braked back to -vmax (reaching amax), then turned round; the same plan
/// as the library's.
#[test]
fn plan_from_any_state_above_vmax_moving_away() {
    use motioncard_sdk::plan::{OtgLimits, Trajectory};
    let (code, out, err) = mcctl(&[
        "plan", "100", "--vmax", "10", "--amax", "100", "--jmax", "1e3", "--v0", "-15", "--a0",
        "0", "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    let want = Trajectory::to_position(
        0.0,
        -15.0,
        0.0,
        100.0,
        0.0,
        &OtgLimits::symmetric(10.0, 100.0, 1e3),
    )
    .unwrap();
    let duration = j["duration"].as_f64().unwrap();
    assert_eq!(duration, want.duration());
    // The brake ramps the acceleration up at +J until the velocity is back at -vmax:
    // sqrt(2 * 5 / 1000) = 0.1 s.
    assert!((j["brake"].as_f64().unwrap() - 0.1).abs() < 1e-12, "{j}");
    let phases: Vec<f64> = j["phases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let jerks: Vec<f64> = j["jerks"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(phases, want.phases());
    assert_eq!(jerks[0], 1e3);
    assert!((phases.iter().sum::<f64>() - duration).abs() < 1e-12);
    assert!(
        (j["peak_velocity"].as_f64().unwrap() - 15.0).abs() < 1e-9,
        "{j}"
    );
    // It moves away first, so it takes longer than the 10 s at vmax the distance alone needs.
    assert!(duration > 10.0, "{duration}");
    // The table names the brake.
    let (code, out, _) = mcctl(&[
        "plan", "100", "--vmax", "10", "--amax", "100", "--jmax", "1e3", "--v0", "-15", "--a0", "0",
    ]);
    assert_eq!(code, 0);
    assert!(
        out.contains("brake 1 jerk +J") && out.contains("of which brake"),
        "{out}"
    );
    // Signed --v1 with --a0, refused beyond ±vmax; --a0 itself must be finite.
    let (code, out, err) = mcctl(&[
        "plan", "-50", "--vmax", "10", "--amax", "100", "--dmax", "50", "--jmax", "1e3", "--a0",
        "250", "--v1", "-4", "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert!(j["brake"].as_f64().unwrap() > 0.0); // a0 = 250 beyond the 50 allowed along -x
    assert_eq!(j["limits"]["amax"].as_f64(), Some(50.0));
    for (extra, why) in [
        (
            ["--a0", "0", "--v1", "-11"],
            "--v1 must be between -10 and --vmax (10), got -11",
        ),
        (["--a0", "nan", "--v1", "0"], "--a0 must be a finite number"),
    ] {
        let mut args = vec![
            "plan", "5", "--vmax", "10", "--amax", "100", "--jmax", "1e3",
        ];
        args.extend(extra);
        let (code, _, err) = mcctl(&args);
        assert_eq!(code, 2);
        assert!(err.contains(why), "{err}");
    }
}

/// `mcctl run` streams a G-code program through the path buffer of the stepped card and
/// reports what the commanded positions did: the square's corners blended within the
/// tolerance, every axis within its limits, no exact stop; with tolerance 0 every corner is
/// an exact stop, on the corner. Bad arguments are exit status 2.
#[test]
fn run_reports_a_blended_square_within_its_tolerance_and_limits() {
    let file = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/gcode/square.ngc");
    let report = |tol: &str| {
        let (code, out, err) = mcctl(&["run", file, "--tolerance", tol, "--json"]);
        assert_eq!(code, 0, "{err}");
        serde_json::from_str::<serde_json::Value>(out.trim()).unwrap()
    };
    let blended = report("0.05");
    let f = |j: &serde_json::Value, k: &str| j[k].as_f64().unwrap();
    assert_eq!(blended["segments"], 5);
    assert!(
        f(&blended, "max_deviation") <= 0.05 * (1.0 + 1e-9),
        "{blended}"
    );
    assert!(
        f(&blended, "max_deviation") > 0.005,
        "corners not blended: {blended}"
    );
    for k in ["peak_vel_ratio", "peak_accel_ratio", "peak_jerk_ratio"] {
        assert!(f(&blended, k) <= 1.01, "{k}: {blended}");
    }
    assert_eq!(blended["exact_stops"], 0);
    let exact = report("0");
    // Five moves: four corners, each an exact stop.
    assert_eq!(exact["exact_stops"], 4, "{exact}");
    assert!(f(&exact, "max_deviation") < 1e-6, "{exact}");
    let (code, _, _) = mcctl(&["run", file, "--tolerance", "-1"]);
    assert_eq!(code, 2);
    let (code, _, _) = mcctl(&["run", file, "--vmax", "1,2"]);
    assert_eq!(code, 2);
}

/// A stepped run sends when the card's buffer has room for a batch, not a segment or two a
/// tick: each send is a stream of its own, and the chord fitter fits within one. Behind 4,500
/// collinear pieces it cannot merge (their feeds alternate: a buffer full of single lines), a
/// circle of 2,000 chords runs about as fast as it does alone: it is sent as curves all the
/// same. (And the batch runs between two ticks: every tick is in the report.)
#[test]
fn chords_behind_a_full_buffer_are_still_fitted() {
    let dir = std::env::temp_dir().join(format!("mcctl-behind-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let pieces: String = (1..=4500)
        .map(|i| format!("G1 F{} X{:.3}\n", 6000 - 10 * (i % 2), 0.05 * i as f64))
        .collect();
    let circle: String = (1..=2000)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 2000.0;
            let (x, y) = (200.0 + 25.4 * a.cos(), 25.4 * a.sin());
            format!("G1 F6000 X{x:.3} Y{y:.3}\n")
        })
        .collect();
    let time = |name: &str, text: String| {
        let file = dir.join(name);
        std::fs::write(&file, text).unwrap();
        let j = json_of(&["run", file.to_str().unwrap(), "--json"]);
        for k in ["peak_vel_ratio", "peak_accel_ratio", "peak_jerk_ratio"] {
            assert!(j[k].as_f64().unwrap() <= 1.01, "{name} {k}: {j}");
        }
        j["path_time"].as_f64().unwrap()
    };
    // (the pieces end at X225, the circle's start, at rest: an exact stop before the circle)
    let start = "G1 F6000 X225.4\nG4 P0.01\n";
    let alone = time("pieces.ngc", pieces.clone() + start);
    let both = time("both.ngc", pieces + start + &circle);
    let circle_alone = time("circle.ngc", "G0 X225.4\n".to_string() + &circle);
    let extra = both - alone;
    assert!(
        extra <= 1.1 * circle_alone,
        "the circle took {extra} s behind the pieces, {circle_alone} s alone"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `mcctl run` in memory that does not grow with the run: a move and a dwell of 40 s
/// (400,000 ticks of 0.1 ms) peak within 2 MB of the same program with a dwell of 1 s.
/// Every tick was kept before (24 bytes a tick: 9 MB more), so a program running for hours
/// ran out of memory.
#[test]
fn run_memory_does_not_grow_with_the_run() {
    let dir = std::env::temp_dir().join(format!("mcctl-run-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |dwell: u32| {
        let file = dir.join(format!("dwell{dwell}.ngc"));
        std::fs::write(&file, format!("G1 X1 F600\nG4 P{dwell}\nX2\n")).unwrap();
        let (code, out, err, peak) = mcctl_peak_rss(&["run", file.to_str().unwrap(), "--json"]);
        assert_eq!(code, 0, "{err}");
        let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
        (j, peak)
    };
    let (short, short_peak) = run(1);
    let (long, long_peak) = run(40);
    let ticks = |j: &serde_json::Value| j["ticks_seen"].as_u64().unwrap();
    assert_eq!(ticks(&long) - ticks(&short), 390_000, "{short} {long}");
    assert_eq!(long["exact_stops"], 1);
    assert!(short_peak > 0);
    assert!(
        long_peak < short_peak + 2048,
        "peak {long_peak} kB over 400,000 ticks, {short_peak} kB over 10,000"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `mcctl run` reads the program a line at a time and checks all of it before anything
/// moves: an error on the last of 200,000 lines names its line and nothing ran; a line
/// longer than 64 KiB and a program without motion are refused before the card moves.
#[test]
fn run_checks_the_whole_program_first() {
    let dir = std::env::temp_dir().join(format!("mcctl-runcheck-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("long.ngc");
    let mut text = String::from("G1 F6000\n");
    for i in 1..200_000 {
        text += &format!("X{}\n", i % 2);
    }
    text += "G7\n";
    std::fs::write(&file, &text).unwrap();
    let t0 = std::time::Instant::now();
    let (code, _, err) = mcctl(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("line 200001: G7"), "{err}");
    // 200,000 moves of 1 mm would take over half an hour of card time.
    assert!(t0.elapsed() < std::time::Duration::from_secs(60));
    std::fs::write(&file, format!("G1 X1 F60 ({})\n", "c".repeat(70_000))).unwrap();
    let (code, _, err) = mcctl(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(
        err.contains("line 1: line longer than 65536 bytes"),
        "{err}"
    );
    std::fs::write(&file, "G4 P100\n").unwrap();
    let (code, _, err) = mcctl(&["run", file.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(err.contains("no motion to run"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `mcctl io` sets outputs and reads them back; `mcctl pvt` streams a PT file (a smooth move
/// of 1000 counts in 0.2 s) to its end on the emulated card; a malformed line is exit status
/// 2 naming the line.
#[test]
fn io_and_pvt_from_the_command_line() {
    let (code, out, err) = mcctl(&["io", "--set-outputs", "0x0F", "5", "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(j["outputs"], 5, "{out}");
    // Layout 1.11: a spare DAC set and read back, an analog input configured, the PSO's
    // refusals (a group not configured, a cut-off above Nyquist) each with its reason.
    let (code, out, err) = mcctl(&[
        "io",
        "--set-analog",
        "1",
        "-3.3",
        "--analog-input",
        "2",
        "50",
        "1.5",
        "0.25",
        "--events",
        "both",
        "--analog",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(j["analog"]["outputs"][1], -676.0 * 20.0 / 4096.0, "{out}");
    let a2 = &j["analog"]["inputs"][2];
    assert_eq!(
        (&a2["cutoff_hz"], &a2["threshold"], &a2["hysteresis"]),
        (
            &serde_json::json!(50.0),
            &serde_json::json!(1.5),
            &serde_json::json!(0.25)
        ),
        "{out}"
    );
    assert_eq!(
        (&a2["rise_event"], &a2["fall_event"]),
        (&serde_json::json!(true), &serde_json::json!(true))
    );
    assert_eq!(j["analog"]["pso"]["state"], "off", "{out}");
    let (code, _, err) = mcctl(&["io", "--pso", "0", "--pso-dac", "0", "--v-ref", "10"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("not configured"), "{err}");
    let (code, _, err) = mcctl(&["io", "--analog-input", "0", "1e6", "0", "0"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("half the servo rate"), "{err}");
    let (code, out, err) = mcctl(&["io", "--analog"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("analog inputs (V):") && out.contains("pso off"),
        "{out}"
    );
    let dir = std::env::temp_dir().join(format!("mcctl-pvt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("move.csv");
    let mut text = String::from("# time, position (PT)\n");
    for k in 1..=10 {
        let s = k as f64 / 10.0;
        text += &format!(
            "{}, {}\n",
            0.02 * k as f64,
            1000.0 * s * s * (3.0 - 2.0 * s)
        );
    }
    std::fs::write(&file, &text).unwrap();
    let f = file.to_str().unwrap();
    let (code, out, err) = mcctl(&["pvt", "0", f, "--enable", "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(j["points"], 10, "{out}");
    assert!(
        (j["position"].as_f64().unwrap() - 1000.0).abs() <= 1.0,
        "{out}"
    );
    std::fs::write(&file, "0.02, 1\n0.04, 2\n0.06 oops\n").unwrap();
    let (code, _, err) = mcctl(&["pvt", "0", f, "--enable"]);
    assert_eq!(code, 2);
    assert!(err.contains("line 3"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A point `mcctl pvt` refuses is named by its index in the file and its line, past the card's
/// 4096-point buffer too (it was the index within the refill, "point 4"), with the card's
/// true reason: a time not after the one before, or more than the longest segment (10⁶ s)
/// after it.
#[test]
fn a_refused_pvt_point_names_its_line_and_reason() {
    let dir = std::env::temp_dir().join(format!("mcctl-pvt-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("hold.csv");
    let f = file.to_str().unwrap();
    for (bad, at, reason) in [
        (
            4100,
            "0.5",
            "at least one servo period after the one before",
        ),
        (
            4500,
            "1e9",
            "at most 1e6 s (the longest move) after the one before",
        ),
        (
            0,
            "1e9",
            "at most 1e6 s (the longest move) after the one before",
        ),
    ] {
        // Point k at (k + 1) ms holds the axis where it is; the bad one's time is `at`.
        let mut text = String::from("# time, position\n");
        for k in 0..bad + 10 {
            if k == bad {
                text += &format!("{at}, 0\n");
            } else {
                text += &format!("{}, 0\n", (k + 1) as f64 * 1e-3);
            }
        }
        std::fs::write(&file, &text).unwrap();
        let (code, _, err) = mcctl(&["pvt", "0", f, "--enable"]);
        assert_eq!(code, 1, "{err}");
        let want = format!(
            "{f}:{}: PT/PVT point {bad} on axis 0 refused: a PT/PVT point must come {reason}",
            bad + 2
        );
        assert!(err.contains(&want), "{err}\nwanted {want}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--enable` powers only the axes a command moves, once what it arms or loads is accepted, and
/// powers them off again however it ends: a refused compare, probe or gear left the axes
/// powered, and a finished one too. On one `emu:` card that outlives each mcctl process.
#[test]
fn enable_powers_the_moved_axes_for_the_command_only() {
    let card = EmuCard::new("test-mcctl-power", 4);
    let on = |args: &[&str]| card.on(args);
    let states = || {
        let (code, out, err) = on(&["status", "--json"]);
        assert_eq!(code, 0, "{err}");
        let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
        (0..2)
            .map(|a| j["axes"][a]["state"].as_str().unwrap().to_string())
            .collect::<Vec<_>>()
    };
    let off = vec!["Disabled".to_string(); 2];
    let cases: [(&[&str], i32, &str); 5] = [
        // Refused by the card: nothing was powered for it.
        (
            &[
                "compare", "0", "--output", "99", "--at", "100", "--move", "900", "--enable",
            ],
            1,
            "refused compare_single",
        ),
        (
            &["probe", "0", "--channel", "9", "--move", "900", "--enable"],
            1,
            "no such compare or probe channel",
        ),
        (
            &[
                "gear", "1", "--master", "0", "--ratio", "1/0", "--move", "900", "--enable",
            ],
            1,
            "gear ratio",
        ),
        // Watching only: nothing to power.
        (
            &[
                "compare", "0", "--output", "3", "--at", "100", "--for", "0.05", "--enable",
            ],
            0,
            "0 fired",
        ),
        // A move: powered for it, off at the end.
        (
            &[
                "compare", "0", "--output", "3", "--at", "100", "--move", "900", "--enable",
            ],
            0,
            "1 fired",
        ),
    ];
    for (args, want, what) in cases {
        let (code, out, err) = on(args);
        assert_eq!(code, want, "{args:?}: {out}{err}");
        assert!(
            out.contains(what) || err.contains(what),
            "{args:?}: {out}{err}"
        );
        assert_eq!(states(), off, "{args:?}: powered after it");
    }
    let (code, out, err) = on(&["gear", "1", "--master", "0", "--move", "1500", "--enable"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("master moved 600"), "{out}");
    assert_eq!(states(), off, "powered after the gear");
}

/// `compare --table` checks its file a line at a time (a position out of order is refused
/// with its line before anything moves) and reads the positions as the channel's table
/// empties: a table of 10⁶ positions peaks within 4 MB of one of 10 (every position was read
/// into memory first: 10⁷ took 794 MB).
#[test]
fn a_compare_table_is_streamed_from_its_file() {
    let dir = std::env::temp_dir().join(format!("mcctl-cmp-big-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("table.txt");
    let f = file.to_str().unwrap();
    let run = |n: usize| {
        let text: String = (1..=n).map(|k| format!("{}\n", 100 + 10 * k)).collect();
        std::fs::write(&file, text).unwrap();
        let args = [
            "compare", "0", "--output", "3", "--table", f, "--move", "500", "--enable",
        ];
        let (code, out, err, peak) = mcctl_peak_rss(&args);
        assert_eq!(code, 0, "{err}");
        // 110 to 500: 40 fired on the way.
        assert!(out.contains(": 40 fired (110 .. 500), 0 missed"), "{out}");
        peak
    };
    let (small, big) = (run(10_000), run(1_000_000));
    assert!(
        big < small + 4096,
        "peak {big} kB for 10^6 positions, {small} kB for 10^4"
    );
    std::fs::write(&file, "100\n200\n# a comment\n150\n300\n").unwrap();
    let (code, _, err) = mcctl(&[
        "compare", "0", "--output", "3", "--table", f, "--move", "500",
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("line 4: position 150 does not come after 200 in the positive direction"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The one JSON object a subcommand printed, after checking it exited 0.
fn json_of(args: &[&str]) -> serde_json::Value {
    let (code, out, err) = mcctl(args);
    assert_eq!(code, 0, "{args:?}: {err}");
    serde_json::from_str(out.trim()).unwrap_or_else(|e| panic!("{args:?}: {e}: {out}"))
}

fn floats(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn compare_and_probe_from_the_command_line() {
    // A series fired on the way to 12,000: every position once, in order.
    let j = json_of(&[
        "compare",
        "0",
        "--output",
        "3",
        "--series",
        "1000,500,20",
        "--move",
        "12000",
        "--enable",
        "--json",
    ]);
    let want: Vec<f64> = (0..20).map(|k| 1000.0 + 500.0 * k as f64).collect();
    assert_eq!(floats(&j["fired_at"]), want, "{j}");
    assert_eq!(
        (j["fires"].as_u64(), j["missed"].as_u64()),
        (Some(20), Some(0))
    );
    // A table streamed from a file (more positions than one refill); a position already
    // behind the axis is missed. (Every run is a fresh emulated card, at 0.)
    let dir = std::env::temp_dir().join(format!("mcctl-cmp-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let table = dir.join("table.txt");
    let positions: Vec<f64> = (0..300).map(|k| -1000.0 - 30.0 * k as f64).collect();
    let text: String = positions.iter().map(|p| format!("{p}\n")).collect();
    std::fs::write(&table, text).unwrap();
    let t = table.to_str().unwrap();
    let j = json_of(&[
        "compare",
        "0",
        "--output",
        "4",
        "--table",
        t,
        "--direction",
        "negative",
        "--move",
        "-12000",
        "--enable",
        "--json",
    ]);
    assert_eq!(floats(&j["fired_at"]), positions, "{j}");
    let j = json_of(&[
        "compare", "0", "--output", "4", "--at", "-500", "--for", "0.05", "--json",
    ]);
    assert_eq!(
        (j["fires"].as_u64(), j["missed"].as_u64()),
        (Some(0), Some(1))
    );
    assert_eq!(floats(&j["missed_at"]), [-500.0], "{j}");
    // The index pulse, once per 10,000-count revolution, latched at speed on both edges.
    let j = json_of(&[
        "probe",
        "0",
        "--edge",
        "both",
        "--continuous",
        "--move",
        "35000",
        "--enable",
        "--json",
    ]);
    let got = floats(&j["positions"]);
    assert_eq!(got.len(), 3, "{j}");
    for (k, p) in got.iter().enumerate() {
        let rev = 10_000.0 * (k + 1) as f64;
        assert!((p - rev).abs() <= 1.0, "capture {k} at {p}: {j}");
    }
    // A window that holds the second pulse only; a single shot takes it.
    let j = json_of(&[
        "probe", "0", "--window", "-25000", "-15000", "--edge", "falling", "--move", "-40000",
        "--enable", "--json",
    ]);
    assert_eq!(j["captures"], 1, "{j}");
    assert!((floats(&j["positions"])[0] + 20_000.0).abs() <= 1.0, "{j}");
    for (args, why) in [
        (vec!["compare", "0", "--output", "1"], "exactly one of --at"),
        (
            vec![
                "compare", "0", "--output", "1", "--at", "1", "--series", "1,2,3",
            ],
            "exactly one of --at",
        ),
        (
            vec!["compare", "0", "--output", "1", "--series", "1,2,2.5"],
            "COUNT a whole number",
        ),
    ] {
        let (code, _, err) = mcctl(&args);
        assert_eq!(code, 2, "{args:?}");
        assert!(err.contains(why), "{args:?}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn gear_and_cam_from_the_command_line() {
    // An odd master travel at -3/2: the slave lands on the half count the ratio says.
    let j = json_of(&[
        "gear", "1", "--master", "0", "--ratio", "-3/2", "--move", "40001", "--enable", "--json",
    ]);
    assert_eq!(j["master_travel"], 40001.0, "{j}");
    assert_eq!(j["slave_travel"], -60001.5, "{j}");
    assert_eq!(j["error"], 0.0, "{j}");
    // A periodic cubic cam, the master through more than one cycle.
    let dir = std::env::temp_dir().join(format!("mcctl-cam-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("cam.csv");
    std::fs::write(
        &file,
        "# master, slave\n0, 0\n1000, 200\n2000, 1000\n3000, 1200\n3600, 1200\n",
    )
    .unwrap();
    let f = file.to_str().unwrap();
    let j = json_of(&[
        "cam",
        "1",
        f,
        "--master",
        "0",
        "--cubic",
        "--periodic",
        "--move",
        "5000",
        "--enable",
        "--json",
    ]);
    assert_eq!(j["master"], 5000.0, "{j}");
    assert!(j["error"].as_f64().unwrap().abs() < 1e-6, "{j}");
    // Past the cycle the slave has risen by one cycle's 1200 on top of the table at 1400.
    let s = j["slave_position"].as_f64().unwrap();
    assert!(s > 1200.0 + 200.0 && s < 1200.0 + 1000.0, "{j}");
    for (args, why) in [
        (
            vec!["gear", "1", "--master", "aux:0", "--move", "5"],
            "needs a master axis",
        ),
        (vec!["gear", "1", "--master", "x:1"], "is not a master"),
        (
            vec!["gear", "1", "--master", "0", "--ratio", "1.5/2"],
            "not a ratio",
        ),
        (
            vec!["cam", "1", "/nonexistent.csv", "--master", "0"],
            "/nonexistent.csv",
        ),
    ] {
        let (code, _, err) = mcctl(&args);
        assert_eq!(code, 2, "{args:?}");
        assert!(err.contains(why), "{args:?}: {err}");
    }
    // The card's own refusal: a zero denominator is a gear-ratio error, exit status 1.
    let (code, _, err) = mcctl(&["gear", "1", "--master", "0", "--ratio", "1/0", "--enable"]);
    assert_eq!(code, 1);
    assert!(err.contains("gear ratio"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The card commands one after another against one card that outlives each mcctl process (an
/// `emu:NAME` card served by this test): power, a move, a stop, status and its watch, info,
/// reset.
#[test]
fn one_card_across_mcctl_processes() {
    let card = EmuCard::new("test-mcctl", 4);
    let on = |args: &[&str]| card.on(args);
    let (code, out, err) = on(&["info", "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(j["axes"], 4, "{out}");
    assert_eq!(j["servo_rate_hz"], 10_000, "{out}");
    let (code, out, err) = on(&["enable", "0", "1"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out, "axis 0: Standstill\naxis 1: Standstill\n");
    // Enabled by one process, moved by the next.
    let (code, _, err) = on(&["move", "1", "-4000"]);
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = on(&["stop", "1", "--dmax", "2e6"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("Standstill"), "{out}");
    let (code, out, err) = on(&[
        "status",
        "--watch",
        "--count",
        "3",
        "--interval",
        "0.02",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let rows: Vec<serde_json::Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(rows.len(), 3, "{out}");
    assert!(
        rows.windows(2)
            .all(|w| w[1]["tick"].as_u64() > w[0]["tick"].as_u64()),
        "{out}"
    );
    let a1 = &rows[2]["axes"][1];
    assert_eq!(a1["state"], "Standstill");
    assert!(
        (a1["command_position"].as_f64().unwrap() + 4000.0).abs() <= 1.0,
        "{a1}"
    );
    let (code, out, _) = on(&["reset"]);
    assert_eq!((code, out.as_str()), (0, "no axis to reset\n"));
    let (code, out, err) = on(&["disable", "0"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out, "axis 0: Disabled\n");
    let (code, _, err) = on(&["stop", "0"]);
    assert_eq!(code, 1);
    assert!(err.contains("disabled"), "{err}");
    let (code, _, _) = on(&["status", "--watch", "--interval", "-1"]);
    assert_eq!(code, 2);
    // A G-code program on the real-time card: streamed by a thread of its own while the
    // positions are sampled; the report measures what it saw.
    let square = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/gcode/square.ngc");
    let (code, out, err) = on(&["run", square, "--tolerance", "0.05", "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(j["segments"], 5, "{j}");
    assert!(j["ticks_seen"].as_u64().unwrap() > 1_000, "{j}");
    assert!(
        j["max_deviation"].as_f64().unwrap() <= 0.05 * (1.0 + 1e-9),
        "{j}"
    );
}

/// An API trace of one mcctl run (by the environment), replayed by another; a tampered trace
/// reports its first difference with exit status 1.
#[test]
fn replay_a_trace_from_the_command_line() {
    let trace = std::env::temp_dir().join(format!("mcctl-trace-{}", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_mcctl"))
        .args(["move", "0", "5000", "--enable"])
        .env(motioncard_sdk::TRACE_ENV, &trace)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let t = trace.to_str().unwrap();
    let j = json_of(&["replay", t, "--json"]);
    assert_eq!(j["difference"], serde_json::Value::Null, "{j}");
    // The open reads back each of the 8 axes' settings (to adopt its scale), then the power,
    // the move and the close's detach (the open's attach is the replaying host's own).
    assert_eq!(j["commands"], 8 + 2 + 1, "{j}");
    let text = std::fs::read_to_string(&trace).unwrap();
    std::fs::write(&trace, text.replacen(" 5000.0 ", " 4999.0 ", 1)).unwrap();
    let (code, out, _) = mcctl(&["replay", t]);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("first difference at line") && out.contains("4999"),
        "{out}"
    );
    let (code, _, err) = mcctl(&["--card", "emu:x", "replay", t]);
    assert_eq!(code, 2, "{err}");
    let _ = std::fs::remove_file(&trace);
}

/// `mcctl scope`: a move captured from a level trigger with samples before it, to CSV and SVG;
/// bad channels and triggers are exit status 2.
#[test]
fn scope_from_the_command_line() {
    let dir = std::env::temp_dir().join(format!("mcctl-scope-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (csv, svg) = (dir.join("move.csv"), dir.join("move.svg"));
    let j = json_of(&[
        "scope",
        "--channel",
        "cmd_pos:1",
        "--channel",
        "cmd_vel:1",
        "--channel",
        "ferr:1",
        "--trigger",
        "level:1:-100:falling",
        "--pre",
        "10",
        "--samples",
        "1500",
        "--axis",
        "1",
        "--move",
        "-20000",
        "--enable",
        "--csv",
        csv.to_str().unwrap(),
        "--svg",
        svg.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(
        (j["samples"].as_u64(), j["pre_trigger"].as_u64()),
        (Some(1510), Some(10)),
        "{j}"
    );
    assert_eq!(j["lost"], 0, "{j}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("tick,time_s,cmd_pos:1,cmd_vel:1,ferr:1"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 1510);
    for w in rows.windows(2) {
        assert_eq!(w[1][0], w[0][0] + 1.0, "one sample a tick");
        assert!(w[1][2] <= w[0][2], "the commanded position falls: {w:?}");
    }
    // The trigger sample: the first at or below -100 counts/s, at time 0.
    let k = rows.iter().position(|r| r[1] == 0.0).unwrap();
    assert_eq!(k, 10);
    assert!(
        rows[9][3] > -100.0 && rows[10][3] <= -100.0,
        "{:?}",
        &rows[9..11]
    );
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
    for args in [
        vec!["scope", "--channel", "nothing:0"],
        vec!["scope", "--trigger", "level:x"],
        vec!["scope", "--trigger", "input:1:sideways"],
        vec!["scope", "--timeout", "0"],
    ] {
        let (code, _, err) = mcctl(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `mcctl config save|load|diff` against one `emu:` card served by this test (each mcctl
/// process opens it in turn): a changed file differs (exit 1, key by key, JSON too), loads, and
/// then the card saves the same bytes; a file with a bad value is exit 2 naming key and line,
/// and changes nothing.
#[test]
fn config_save_load_and_diff_from_the_command_line() {
    let card = EmuCard::new("test-config", 2);
    let uri = card.uri.clone();
    let dir = std::env::temp_dir().join(format!("mcctl-config-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = |f: &str| dir.join(f).display().to_string();

    let (code, out, err) = mcctl(&["--card", &uri, "config", "save", &path("a.toml")]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("saved"), "{out}");
    let a = std::fs::read_to_string(path("a.toml")).unwrap();
    let (code, out, _) = mcctl(&["--card", &uri, "config", "save", "-"]);
    assert_eq!(
        (code, out.as_str()),
        (0, a.as_str()),
        "save - prints the file"
    );
    let (code, out, err) = mcctl(&["--card", &uri, "config", "diff", &path("a.toml")]);
    assert_eq!((code, out.as_str()), (0, ""), "{err}");

    // One gain and the servo rate changed.
    let kp = a.lines().find(|l| l.starts_with("kp = ")).unwrap();
    let b = a
        .replacen(kp, "kp = 150.5", 1)
        .replace("servo_rate_hz = 10000", "servo_rate_hz = 8000");
    std::fs::write(path("b.toml"), &b).unwrap();
    let (code, out, err) = mcctl(&["--card", &uri, "config", "diff", &path("b.toml")]);
    assert_eq!(code, 1, "{err}");
    assert!(
        out.contains("card.servo_rate_hz: file 8000, card 10000"),
        "{out}"
    );
    assert!(out.contains("axis.0.ffpiv.kp: file 150.5, card "), "{out}");
    assert_eq!(out.lines().count(), 2, "{out}");
    let (code, out, _) = mcctl(&["--card", &uri, "config", "diff", &path("b.toml"), "--json"]);
    assert_eq!(code, 1);
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(j[0]["key"], "axis.0.ffpiv.kp", "{out}");
    assert_eq!(j[0]["file"], "150.5", "{out}");
    assert_eq!(j[1]["key"], "card.servo_rate_hz", "{out}");

    let (code, out, err) = mcctl(&["--card", &uri, "config", "load", &path("b.toml"), "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(j["applied"], serde_json::json!(["card", "axis.0"]), "{out}");
    let (code, _, err) = mcctl(&["--card", &uri, "config", "save", &path("c.toml")]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        std::fs::read_to_string(path("c.toml")).unwrap(),
        b,
        "load, save: same bytes"
    );
    let (code, _, _) = mcctl(&["--card", &uri, "config", "diff", &path("b.toml")]);
    assert_eq!(code, 0);

    // A bad value: exit 2, key and line named, nothing applied.
    let line = 1 + b.lines().position(|l| l.starts_with("kp = ")).unwrap();
    std::fs::write(path("bad.toml"), b.replacen("kp = 150.5", "kp = -1.0", 1)).unwrap();
    for action in ["load", "diff"] {
        let (code, _, err) = mcctl(&["--card", &uri, "config", action, &path("bad.toml")]);
        assert_eq!(code, 2, "{action}: {err}");
        assert!(
            err.contains(&format!("bad.toml:{line}: axis.0.ffpiv.kp: ")),
            "{action}: {err}"
        );
    }
    let (code, _, _) = mcctl(&["--card", &uri, "config", "diff", &path("b.toml")]);
    assert_eq!(code, 0, "the bad file changed nothing");
    // Bad arguments and a missing file.
    let (code, _, _) = mcctl(&["--card", &uri, "config", "frobnicate"]);
    assert_eq!(code, 2);
    let (code, _, err) = mcctl(&["--card", &uri, "config", "load", &path("none.toml")]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("cannot read"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Long operations draw a progress bar on a terminal (util-linux `script` gives mcctl one) and
/// nothing when stderr is a pipe: the pipe sees only the result.
#[test]
fn progress_is_drawn_on_a_terminal_only() {
    let bin = env!("CARGO_BIN_EXE_mcctl");
    let args = "--card sim jog 0 20000 --for 0.3 --enable";
    let typescript = std::env::temp_dir().join(format!("mcctl-tty-{}", std::process::id()));
    let out = Command::new("script")
        .args(["-qec", &format!("'{bin}' {args}")])
        .arg(&typescript)
        .output()
        .expect("util-linux script");
    assert!(out.status.success(), "{out:?}");
    let seen = String::from_utf8_lossy(&std::fs::read(&typescript).unwrap()).into_owned();
    let _ = std::fs::remove_file(&typescript);
    // The bar of the time the button is held, the axis on it, then the spinner of the release.
    assert!(seen.contains("jogging (ms)"), "{seen}");
    assert!(seen.contains("axis 0 ContinuousMotion at "), "{seen}");
    assert!(seen.contains("axis 0: jogged to "), "{seen}");
    let (code, out, err) = mcctl(&args.split(' ').collect::<Vec<_>>());
    assert_eq!(code, 0, "{err}");
    assert!(out.starts_with("axis 0: jogged to "), "{out}");
    assert_eq!(err, "", "nothing drawn on a pipe");
}

/// SIGTERM (systemd, `timeout`, a supervisor), SIGINT (Ctrl-C) and SIGHUP end mcctl the way
/// its own end would: the card halts what mcctl started (reason HostDetach: mcctl closed its
/// session), no watchdog trip latches, the axes mcctl never touched stay as they were, and
/// mcctl exits with 128 + the signal's number. Each signal is sent once the card shows the
/// motion under way (read from the card's window by this test, which serves the card), so
/// nothing depends on timing; a `status --watch` (which moves nothing) is interrupted the same
/// way.
#[test]
fn a_signal_halts_what_mcctl_started_and_closes_its_session() {
    use card_emu::emu::server::Server;
    use card_emu::{EmuOptions, Emulator, Runner};
    use firmware_proto::layout::safety_status as ss;
    use firmware_proto::{seqlock, AxisState, Mem, StopReason};
    use nix::sys::signal::{kill, Signal};
    use nix::unistd::Pid;
    use std::process::Stdio;
    use std::time::{Duration, Instant};
    let name = format!("test-mcctl-signal-{}", std::process::id());
    let emu = Emulator::create(&name, &EmuOptions::new(4, 10_000)).unwrap();
    let window = emu.window().clone();
    let _server = Server::start(&name, emu.lessor()).unwrap();
    let _runner = Runner::spawn(emu, card_emu::Clock::RealTime, false).unwrap();
    let uri = format!("emu:{name}");
    let status = |a: usize| seqlock::read_axis_status(&*window, a).unwrap();
    let state = |a: usize| AxisState::from_raw(status(a).state);
    let wait_for = |what: &str, done: &dyn Fn() -> bool| {
        let deadline = Instant::now() + Duration::from_secs(20);
        while !done() {
            assert!(Instant::now() < deadline, "never: {what}");
            std::thread::sleep(Duration::from_millis(1));
        }
    };
    let (code, _, err) = mcctl(&["--card", &uri, "enable", "0", "1", "2"]);
    assert_eq!(code, 0, "{err}");

    let cases: [(Signal, usize, &[&str]); 3] = [
        (Signal::SIGTERM, 0, &["jog", "0", "20000", "--for", "600"]),
        (
            Signal::SIGINT,
            1,
            &["move", "1", "-30000", "--velocity", "--for", "600"],
        ),
        (Signal::SIGHUP, 0, &["move", "0", "1e8", "--relative"]),
    ];
    for (sig, axis, args) in cases {
        let others: Vec<_> = (0..4)
            .filter(|&a| a != axis)
            .map(|a| (a, status(a)))
            .collect();
        let mut child = Command::new(env!("CARGO_BIN_EXE_mcctl"))
            .args(["--card", uri.as_str()])
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        wait_for(&format!("{sig}: axis {axis} moving"), &|| {
            status(axis).cmd_vel.abs() > 1000.0
        });
        kill(Pid::from_raw(child.id() as i32), sig).unwrap();
        let deadline = Instant::now() + Duration::from_secs(20);
        let exit = loop {
            if let Some(s) = child.try_wait().unwrap() {
                break s;
            }
            assert!(Instant::now() < deadline, "{sig}: mcctl did not exit");
            std::thread::sleep(Duration::from_millis(5));
        };
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(exit.code(), Some(128 + sig as i32), "{sig}: {exit:?} {err}");
        assert!(err.contains(sig.as_str()), "{sig}: {err}");
        // The session closed cleanly: nothing latched, nobody attached, the axis halting on
        // the detach's ramp and then at rest, in position.
        assert_eq!(window.read32(ss::FAULTS), 0, "{sig}: a fault latched");
        assert_eq!(window.read32(ss::SESSION), 0, "{sig}: still attached");
        assert_eq!(window.read32(ss::WATCHDOG_ARMED), 0, "{sig}");
        wait_for(&format!("{sig}: axis {axis} at rest"), &|| {
            state(axis) == Some(AxisState::Standstill) && status(axis).cmd_vel == 0.0
        });
        let s = status(axis);
        assert_eq!(
            StopReason::from_raw(s.stop_reason),
            Some(StopReason::HostDetach),
            "{sig}"
        );
        assert_eq!(window.read32(ss::FAULTS), 0, "{sig}: a fault latched");
        // The axes mcctl never touched: as they were (enabled ones still enabled, still).
        for (a, before) in &others {
            let now = status(*a);
            assert_eq!(now.state, before.state, "{sig}: axis {a}");
            assert_eq!(now.cmd_pos, before.cmd_pos, "{sig}: axis {a}");
            assert_eq!(now.stop_reason, before.stop_reason, "{sig}: axis {a}");
        }
        assert_eq!(state(2), Some(AxisState::Standstill), "{sig}: axis 2");
        assert_eq!(state(3), Some(AxisState::Disabled), "{sig}: axis 3");
    }

    // A watch moves nothing, and a signal ends it with the session closed too.
    let mut child = Command::new(env!("CARGO_BIN_EXE_mcctl"))
        .args([
            "--card",
            uri.as_str(),
            "status",
            "--watch",
            "--interval",
            "0.05",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_for("the watch attached", &|| window.read32(ss::SESSION) != 0);
    kill(Pid::from_raw(child.id() as i32), Signal::SIGTERM).unwrap();
    let deadline = Instant::now() + Duration::from_secs(20);
    let exit = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        assert!(Instant::now() < deadline, "the watch did not exit");
        std::thread::sleep(Duration::from_millis(5));
    };
    assert_eq!(exit.code(), Some(143));
    assert_eq!(window.read32(ss::SESSION), 0);
    assert_eq!(window.read32(ss::FAULTS), 0);
    for a in 0..3 {
        assert_eq!(state(a), Some(AxisState::Standstill), "axis {a}");
    }
}

/// Layout 1.10: a rotary axis from the command line against one `emu:` card served by this
/// test: `modulo` set with `mcctl config load` (and saved back), then `mcctl move
/// --direction`: to 9000 of a 10,000-count turn negatively from 0 goes back 1000 counts, to 500
/// positively goes forward 1500; a direction on a relative move is a usage error, a target
/// outside the turn the card's refusal.
#[test]
fn a_rotary_axis_from_the_command_line() {
    let card = EmuCard::new("test-rotary", 1);
    let uri = card.uri.clone();
    let dir = std::env::temp_dir().join(format!("mcctl-rotary-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = |f: &str| dir.join(f).display().to_string();
    let (code, _, err) = mcctl(&["--card", &uri, "config", "save", &path("a.toml")]);
    assert_eq!(code, 0, "{err}");
    let a = std::fs::read_to_string(path("a.toml")).unwrap();
    assert!(a.contains("\nmodulo = 0.0\n"), "{a}");
    std::fs::write(
        path("r.toml"),
        a.replace("\nmodulo = 0.0\n", "\nmodulo = 10000.0\n"),
    )
    .unwrap();
    let (code, out, err) = mcctl(&["--card", &uri, "config", "load", &path("r.toml"), "--json"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("axis.0.modulo"), "{out}");
    let (code, out, _) = mcctl(&["--card", &uri, "config", "save", "-"]);
    assert_eq!(code, 0);
    assert!(out.contains("\nmodulo = 10000.0\n"), "{out}");

    let enc = || {
        let (_, out, _) = mcctl(&["--card", &uri, "status", "--json"]);
        let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
        j["axes"][0]["encoder"].as_i64().unwrap()
    };
    let mv = |target: &str, dir: &str| {
        let (code, out, err) = mcctl(&[
            "--card",
            &uri,
            "move",
            "0",
            target,
            "--direction",
            dir,
            "--enable",
            "--json",
        ]);
        assert_eq!(code, 0, "{err}");
        let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
        j["position"].as_f64().unwrap()
    };
    let e0 = enc();
    let at = mv("9000", "negative");
    let e1 = enc();
    assert!(
        (at - 9000.0).abs() <= 1.0 && (e1 - e0 + 1000).abs() <= 2,
        "{at} {e0} {e1}"
    );
    let at = mv("500", "positive");
    let e2 = enc();
    assert!(
        (at - 500.0).abs() <= 1.0 && (e2 - e1 - 1500).abs() <= 2,
        "{at} {e1} {e2}"
    );

    // Layout 1.13: compare on the turn. Every 250 counts from 125, on every turn, crossed
    // downwards on the shortest way from 500 to 9000 (back over the wrap): each place once, in
    // the order the axis comes to them, the first the one it comes to first.
    let (code, out, err) = mcctl(&[
        "--card",
        &uri,
        "compare",
        "0",
        "--output",
        "3",
        "--series",
        "125,250,0",
        "--each-turn",
        "--direction",
        "negative",
        "--move",
        "9000",
        "--enable",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(
        floats(&j["fired_at"]),
        [375.0, 125.0, 9875.0, 9625.0, 9375.0, 9125.0],
        "{j}"
    );
    assert_eq!(j["missed"], 0, "{j}");
    // Off the turn: the card's refusal, exit 1 naming it; each turn with a table: usage.
    let (code, _, err) = mcctl(&[
        "--card",
        &uri,
        "compare",
        "0",
        "--output",
        "3",
        "--at",
        "10000",
        "--each-turn",
        "--for",
        "0.01",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("rotary axis"), "{err}");
    let (code, _, err) = mcctl(&[
        "--card",
        &uri,
        "compare",
        "0",
        "--output",
        "3",
        "--table",
        "t.txt",
        "--each-turn",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("not --table"), "{err}");

    let (code, _, err) = mcctl(&[
        "--card",
        &uri,
        "move",
        "0",
        "5",
        "--relative",
        "--direction",
        "positive",
    ]);
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = mcctl(&["--card", &uri, "move", "0", "10000", "--enable"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("modulo"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Layout 1.10: `mcctl gantry form|status|home|dissolve` on one `emu:` card that outlives each
/// mcctl process: formed (the slave coupled), listed with --json, homed (method 37 on each
/// side: square where they stand), dissolved (none listed); the card's refusals exit 1 with
/// its reason, a missing argument 2.
#[test]
fn gantry_forms_homes_shows_and_dissolves() {
    let card = EmuCard::new("test-mcctl-gantry", 3);
    let on = |args: &[&str]| card.on(args);
    let json = |args: &[&str]| {
        let (code, out, err) = on(args);
        assert_eq!(code, 0, "{args:?}: {err}");
        serde_json::from_str::<serde_json::Value>(out.trim()).unwrap()
    };
    let j = json(&[
        "gantry",
        "form",
        "0",
        "--slaves",
        "2",
        "--skew-limit",
        "150",
        "--offsets",
        "-25",
        "--ki",
        "1e7",
        "--index",
        "1",
        "--enable",
        "--json",
    ]);
    assert_eq!(j["index"], 1, "{j}");
    assert_eq!(j["master"], 0, "{j}");
    assert_eq!(j["slaves"][0]["axis"], 2, "{j}");
    assert_eq!(j["slaves"][0]["offset"], -25.0, "{j}");
    assert_eq!(j["kp"], 1e6, "{j}");
    assert_eq!(j["ki"], 1e7, "{j}");
    assert_eq!(j["skew_limit"], 150.0, "{j}");
    assert_eq!(j["squared"], false, "{j}");
    let st = json(&["status", "--json"]);
    assert_eq!(st["axes"][2]["state"], "SynchronizedMotion", "{st}");
    // A slave is in use; the slot is taken.
    for (args, why) in [
        (
            vec!["gantry", "form", "1", "--slaves", "2", "--skew-limit", "1"],
            "in use",
        ),
        (
            vec!["gantry", "form", "1", "--slaves", "1", "--skew-limit", "1"],
            "bad gantry axes",
        ),
        (vec!["gantry", "home", "0"], "not in a state"),
        (vec!["gantry", "dissolve", "3"], "not in a state"),
    ] {
        let (code, _, err) = on(&args);
        assert_eq!(code, 1, "{args:?}: {err}");
        assert!(err.contains(why), "{args:?}: {err}");
    }
    let j = json(&["gantry", "home", "1", "--json"]);
    assert_eq!(j["squared"], true, "{j}");
    assert_eq!(j["status"]["slaves"][0]["hold"], -25.0, "{j}");
    let (code, out, err) = on(&["gantry", "status", "1"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("gantry 1: coupled, master axis 0") && out.contains("squared"),
        "{out}"
    );
    let j = json(&["gantry", "dissolve", "1", "--json"]);
    assert_eq!(j["dissolved"], true, "{j}");
    let j = json(&["gantry", "status", "--json"]);
    assert_eq!(j["gantries"].as_array().unwrap().len(), 0, "{j}");
    let st = json(&["status", "--json"]);
    assert_eq!(st["axes"][2]["state"], "Standstill", "{st}");
    let (code, _, err) = on(&["gantry", "form", "0", "--skew-limit", "1"]);
    assert_eq!(code, 2, "{err}");
    let _ = on(&["disable", "0", "1", "2"]);
}

/// Layout 1.9: `mcctl comp AXIS load|show|clear` on one `emu:` card that outlives each mcctl
/// process: an interferometer's error columns loaded as corrections (negated, a column per
/// direction), shown in the file's format, a malformed file (exit 2, its line named) and a
/// table beyond its bound (exit 1, the card's reason) refused with the table kept, then cleared.
#[test]
fn comp_loads_shows_and_clears_a_table_file() {
    let card = EmuCard::new("test-mcctl-comp", 2);
    let on = |args: &[&str]| card.on(args);
    let dir = std::env::temp_dir().join(format!("mcctl-comp-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = |n: &str, text: &str| {
        let p = dir.join(n);
        std::fs::write(&p, text).unwrap();
        p.display().to_string()
    };
    let laser = file(
        "x.csv",
        "# axis X, errors (actual - target)\n# position, forward, reverse\n0, 0, 0\n5000, 6, 5.5\n10000, -10, -9\n",
    );
    let (code, out, err) = on(&[
        "comp",
        "1",
        "load",
        &laser,
        "--bound",
        "20",
        "--backlash",
        "4",
        "--errors",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(j["loaded"], 3, "{out}");
    assert_eq!(j["table"]["bidirectional"], true, "{out}");
    assert_eq!(
        j["table"]["points"][1],
        serde_json::json!([5000.0, -6.0, -5.5]),
        "{out}"
    );
    let shown = "# axis 1: backlash 4, bound 20, ramp 1000 /s, 1000000 /s²\n\
                 # position, correction, correction_negative\n\
                 0, 0, 0\n5000, -6, -5.5\n10000, 10, 9\n";
    let (code, out, err) = on(&["comp", "1", "show"]);
    assert_eq!((code, out.as_str()), (0, shown), "{err}");
    // What `show` prints loads back as the same table.
    let again = file("again.csv", &out);
    let (code, _, err) = on(&[
        "comp",
        "1",
        "load",
        &again,
        "--bound",
        "20",
        "--backlash",
        "4",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(on(&["comp", "1", "show"]).1, shown);
    for (text, code, why) in [
        ("0, 0\n5000, 6, 5\n", 2, "line 2: 3 columns, line 1 2"),
        ("0, 0\n0, 1\n", 2, "line 2: position 0 after 0"),
        (
            "0, 0\n5000, x\n",
            2,
            "line 2: expected `position, correction",
        ),
        ("# only a header\n", 2, "no points"),
        ("0, 0\n5000, 30\n", 1, "beyond the table's bound"),
    ] {
        let bad = file("bad.csv", text);
        let (c, _, err) = on(&["comp", "1", "load", &bad, "--bound", "20"]);
        assert_eq!(c, code, "{text}: {err}");
        assert!(err.contains(why), "{text}: {err}");
        assert_eq!(
            on(&["comp", "1", "show"]).1,
            shown,
            "{text}: the table kept"
        );
    }
    let (code, _, err) = on(&["comp", "1", "clear"]);
    assert_eq!(code, 0, "{err}");
    let (code, out, _) = on(&["comp", "1", "show", "--json"]);
    assert_eq!(code, 0);
    assert_eq!(out.trim(), r#"{"axis":1,"table":null}"#);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `mcctl list`: two `emu:` cards served from this process, one held by a host here: both are
/// listed with their names, serials, axes, rate and sync role, the held one busy (and the host
/// keeps it: it still answers afterwards); `--card name:NAME` opens a card by its name.
#[test]
fn list_shows_every_card_with_its_serial_sync_role_and_availability() {
    use card_emu::{EmuOptions, Emulator, Runner};
    let pid = std::process::id();
    let serve = |name: &str, axes: usize, serial: u64| {
        let opts = EmuOptions {
            serial,
            ..EmuOptions::new(axes, 10_000)
        };
        let emu = Emulator::create(name, &opts).unwrap();
        let server = card_emu::emu::server::Server::start(name, emu.lessor()).unwrap();
        (
            server,
            Runner::spawn(emu, card_emu::Clock::RealTime, false).unwrap(),
        )
    };
    let (a, b) = (format!("mcctl-list-a-{pid}"), format!("mcctl-list-b-{pid}"));
    let (sa, sb) = ((u64::from(pid) << 8) | 1, (u64::from(pid) << 8) | 2);
    let _a = serve(&a, 3, sa);
    let _b = serve(&b, 2, sb);
    let host = motioncard_sdk::Card::open(&format!("emu:{a}")).unwrap();
    let (code, out, err) = mcctl(&["list", "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    let card = |name: &str| {
        j["cards"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["uri"] == format!("emu:{name}"))
            .unwrap_or_else(|| panic!("emu:{name} not in {out}"))
            .clone()
    };
    let ca = card(&a);
    assert_eq!(ca["name"], a.as_str());
    assert_eq!(ca["serial"], sa);
    assert_eq!(ca["axes"], 3);
    assert_eq!(ca["servo_rate_hz"], 10_000);
    assert_eq!(ca["sync_role"], "alone");
    assert_eq!(ca["master"], "");
    assert_eq!(ca["available"], false, "held by this test: {ca}");
    assert_eq!(ca["open_here"], false, "mcctl is another process");
    assert!(ca["error"].is_null(), "{ca}");
    let cb = card(&b);
    assert_eq!((&cb["serial"], &cb["axes"]), (&sb.into(), &2.into()));
    assert_eq!(cb["available"], true, "{cb}");
    host.ping().unwrap();
    assert_eq!(host.inherited_stops(), 0);
    // The table: a line per card, the held one busy.
    let (code, out, _) = mcctl(&["list"]);
    assert_eq!(code, 0);
    assert!(out.starts_with("URI "), "{out}");
    let line = |name: &str| {
        out.lines()
            .find(|l| l.starts_with(&format!("emu:{name} ")))
            .unwrap_or_else(|| panic!("{out}"))
            .split_whitespace()
            .collect::<Vec<_>>()
    };
    let sa_text = sa.to_string();
    let sb_text = sb.to_string();
    assert_eq!(
        line(&a)[1..],
        [a.as_str(), &sa_text, "3", "10000", "Hz", "alone", "busy"]
    );
    assert_eq!(
        line(&b)[1..],
        [
            b.as_str(),
            &sb_text,
            "2",
            "10000",
            "Hz",
            "alone",
            "available"
        ]
    );
    // By name: the card of that name (b: a is held).
    let (code, out, err) = mcctl(&["--card", &format!("name:{b}"), "info", "--json"]);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(j["axes"], 2);
    let (code, _, err) = mcctl(&["--card", &format!("name:nobody-{pid}"), "info"]);
    assert_eq!(code, 1);
    assert!(
        err.contains(&format!("no card named 'nobody-{pid}'")),
        "{err}"
    );
}

/// Layout 1.11: `mcctl group home|status` on one `emu:` card whose three axes each have a home
/// switch (method 19) and whose group 0 (X, Y, Z = card axes 0, 1, 2) has the home order Z,
/// then X and Y, configured through `GroupSettings`: the status shows the order, `group home`
/// runs it (two stages, every axis homed), `--order` gives another; a bad order exits 1 with
/// the card's reason, a malformed one 2, and the group stays at rest in Standby.
#[test]
fn group_homes_in_its_configured_order_and_in_one_given() {
    use card_emu::{EmuOptions, Emulator, HomeSwitch, Runner, Switches};
    use motioncard_sdk::{GroupSettings, HomingSettings};
    let name = format!("test-mcctl-group-{}", std::process::id());
    let mut emu = Emulator::create(&name, &EmuOptions::new(3, 10_000)).unwrap();
    for (a, edge) in [2_000.0, 3_000.0, 1_500.0].into_iter().enumerate() {
        emu.faults().set_switches(
            a,
            Switches::limits(-1e7, 1e7).with_home(HomeSwitch::Above(edge)),
        );
    }
    let _server = card_emu::emu::server::Server::start(&name, emu.lessor()).unwrap();
    let _runner = Runner::spawn(emu, card_emu::Clock::RealTime, false).unwrap();
    let uri = format!("emu:{name}");
    {
        let host = motioncard_sdk::Card::open(&uri).unwrap();
        for a in 0..3 {
            let ax = host.axis(a).unwrap();
            ax.configure_homing(&HomingSettings {
                method: 19,
                search_vel: 40_000.0,
                creep_vel: 4_000.0,
                ..HomingSettings::default()
            })
            .unwrap();
            ax.enable().unwrap();
        }
        let g = host.group(0).unwrap();
        g.configure(&GroupSettings {
            home_order: vec![vec![2], vec![0, 1]],
            ..GroupSettings::new(&[0, 1, 2])
        })
        .unwrap();
        g.enable().unwrap();
    }
    let on = |args: &[&str]| {
        let mut all = vec!["--card", uri.as_str()];
        all.extend_from_slice(args);
        mcctl(&all)
    };
    let json = |args: &[&str]| {
        let (code, out, err) = on(args);
        assert_eq!(code, 0, "{args:?}: {err}");
        serde_json::from_str::<serde_json::Value>(out.trim()).unwrap()
    };
    let j = json(&["group", "status", "0", "--json"]);
    assert_eq!(j["state"], "Standby", "{j}");
    assert_eq!(j["axes"], serde_json::json!([0, 1, 2]), "{j}");
    assert_eq!(j["home_order"], serde_json::json!([[2], [0, 1]]), "{j}");
    let j = json(&["group", "home", "0", "--json"]);
    assert_eq!(j["stages"], 2, "{j}");
    for a in 0..3 {
        assert_eq!(j["axes"][a]["axis"], a, "{j}");
        assert_eq!(j["axes"][a]["homed"], true, "{j}");
    }
    let (code, out, err) = on(&["group", "home", "0", "--order", "1;2;0"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.starts_with("group 0: homed in 3 stages"), "{out}");
    for (order, why) in [
        ("0;0", "twice"),
        ("3", "does not have"),
        ("2;", "empty stage"),
    ] {
        let (code, _, err) = on(&["group", "home", "0", "--order", order]);
        assert_eq!(code, 1, "{order}: {err}");
        assert!(err.contains(why), "{order}: {err}");
    }
    let (code, _, err) = on(&["group", "home", "0", "--order", "2;x"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("`x`"), "{err}");
    let (code, out, err) = on(&["group", "status", "0"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        out, "group 0: Standby, card axes [0, 1, 2], home order 2;0,1\n",
        "{err}"
    );
}

/// Layout 1.13: `mcctl group arc` queues a move-queue arc in a plane given by a normal vector
/// and waits for it: a full turn about (1, 1, 1) from the origin with a turn added, the fourth
/// axis climbing 1,000, ends where it started (within 1e-6 counts) with the fourth axis at
/// 1,000; a refusal of the card (a zero normal) exits 1 with its reason, a malformed point 2.
#[test]
fn group_arc_runs_a_normal_vector_arc_and_reports_where_it_ended() {
    let card = EmuCard::new("test-mcctl-arc", 4);
    {
        let host = motioncard_sdk::Card::open(&card.uri).unwrap();
        for a in 0..4 {
            host.axis(a).unwrap().enable().unwrap();
        }
        let g = host.group(0).unwrap();
        g.configure(&motioncard_sdk::GroupSettings::new(&[0, 1, 2, 3]))
            .unwrap();
        g.enable().unwrap();
    }
    // the centre 2,000 from the origin in the plane normal to (1, 1, 1)
    let c = 2_000.0 / 2f64.sqrt();
    let centre = format!("{},{},0", -c, c);
    let args = [
        "group", "arc", "0", "--axes", "0,1,2", "--normal", "1,1,1", "--centre", &centre, "--end",
        "0,0,0", "--turns", "1", "--helix", "1000", "--feed", "40000", "--accel", "1e6", "--jerk",
        "1e8", "--json",
    ];
    let (code, out, err) = card.on(&args);
    assert_eq!(code, 0, "{err}");
    let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(j["axes"], serde_json::json!([0, 1, 2, 3]), "{j}");
    for a in 0..3 {
        let p = j["position"][a].as_f64().unwrap();
        assert!(p.abs() < 1e-6, "axis {a} at {p}: {j}");
    }
    assert_eq!(j["position"][3], 1000.0, "{j}");
    let mut zero = args.to_vec();
    zero[6] = "0,0,0";
    let (code, _, err) = card.on(&zero);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("normal"), "{err}");
    let mut bad = args.to_vec();
    bad[10] = "0,0";
    let (code, _, err) = card.on(&bad);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("three values"), "{err}");
}

/// Layout 1.14: `mcctl path-set` runs a 12-column file as one path across two stepped cards
/// of one bus: split 6 + 6 and 8 + 4, every card's axes end exactly on the last point (each
/// card holding its own dimensions), and the path takes the same card time whichever split
/// ran it (every card plans all twelve dimensions alike). A bad line, a split of more than 16
/// axes and a group of 9 are refused before any card is opened (status 2, naming what); a
/// line of zero length is the cards' refusal (status 1, their reason).
#[test]
fn path_set_runs_a_12_axis_file_over_two_cards() {
    let dir = std::env::temp_dir().join(format!("mcctl-path-set-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("p12.txt");
    let last: Vec<f64> = (0..12)
        .map(|d| 125.5 * (d as f64 + 1.0) * if d % 3 == 1 { -1.0 } else { 1.0 })
        .collect();
    let row = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let a: Vec<f64> = (0..12).map(|d| 1000.0 + 150.0 * d as f64).collect();
    let b: Vec<f64> = (0..12)
        .map(|d| if d % 2 == 0 { -800.0 } else { 2400.0 })
        .collect();
    std::fs::write(
        &file,
        format!(
            "# twelve dimensions\n{}\n{}, \ndwell 0.01  # a stop\n{}\n",
            row(&a),
            row(&b).replace(' ', ", "),
            row(&last)
        ),
    )
    .unwrap();
    let f = file.to_str().unwrap();
    let mut seconds = Vec::new();
    for split in ["6,6", "8,4"] {
        let (code, out, err) = mcctl(&[
            "path-set",
            f,
            "--split",
            split,
            "--tolerance",
            "5",
            "--json",
        ]);
        assert_eq!(code, 0, "{split}: {err}");
        let j: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
        assert_eq!(
            (j["dimensions"].as_u64(), j["done"].as_u64()),
            (Some(12), Some(4))
        );
        let mut at = Vec::new();
        for c in j["cards"].as_array().unwrap() {
            assert_eq!(c["state"], "Standby", "{j}");
            at.extend(
                c["positions"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|x| x.as_f64().unwrap()),
            );
        }
        assert_eq!(at, last, "{split}: {j}");
        seconds.push(j["seconds"].as_f64().unwrap());
    }
    assert_eq!(seconds[0], seconds[1], "the same path, the same time");
    assert!(seconds[0] > 0.1, "{seconds:?}");
    // the table names each card's dimensions
    let (code, out, _) = mcctl(&["path-set", f, "--split", "6,6"]);
    assert_eq!(code, 0);
    assert!(
        out.contains("card sim1: group 0 Standby, dimensions 6..11"),
        "{out}"
    );

    let bad = dir.join("bad.txt");
    std::fs::write(&bad, format!("{}\n\n{}\n", row(&a), row(&a[..11]))).unwrap();
    let (code, _, err) = mcctl(&["path-set", bad.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("line 3: expected 12 finite numbers"), "{err}");
    let (code, _, err) = mcctl(&["path-set", f, "--split", "8,8,1"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("at most 16 dimensions, got 17"), "{err}");
    let (code, _, err) = mcctl(&["path-set", f, "--split", "9,3"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("1 to 8 axes"), "{err}");
    // the same point twice: a line of zero length, refused by the cards
    let zero = dir.join("zero.txt");
    std::fs::write(&zero, format!("{}\n{}\n", row(&a), row(&a))).unwrap();
    let (code, out, err) = mcctl(&["path-set", zero.to_str().unwrap()]);
    assert_eq!(code, 1, "{out}{err}");
    assert!(err.contains("zero length"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

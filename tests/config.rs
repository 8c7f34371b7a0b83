//! Card configuration files (layout 1.8) on stepped cards: a non-default configuration saved
//! from one card, loaded on a fresh card and saved again gives the same bytes; a file with one
//! bad value (out of range, NaN, wrong type, unknown key, unknown axis) is refused naming its
//! key and line, and changes nothing on the card.
mod common;

use common::stepped_card_with;
use motioncard_sdk::{
    AccDec, AnalogInputSettings, BiquadSpec, Card, Config, EmuOptions, Error, ErrorKind,
    FilterKind, FilterSettings, GroupSettings, HomingFlags, HomingSettings, Interpolator,
    IoSettings, PathSettings, Pso, PsoOutput, PsoState, SafetySettings, StopCategory,
};
use std::time::Duration;

fn card() -> Card {
    stepped_card_with(EmuOptions::new(4, 10_000))
}

/// A card set up through the SDK's setters: nothing at its reset value.
fn configured() -> Card {
    let card = card();
    card.set_servo_rate(8_000).unwrap();
    card.set_watchdog_timeout(Duration::from_millis(250))
        .unwrap();
    card.set_estop_input_category(StopCategory::Cat2).unwrap();
    card.set_max_stop_time(Duration::from_secs(3)).unwrap();
    let mut io = IoSettings {
        polarity: 0b101,
        rise_events: 0b11,
        fall_events: 0b100,
        ..Default::default()
    };
    io.debounce[0] = 5;
    io.debounce[3] = 100;
    card.configure_io(&io).unwrap();
    let a0 = card.axis(0).unwrap();
    let mut s = motioncard_sdk::AxisSettings::default();
    s.ffpiv.kp *= 1.25;
    s.in_pos_window = 2.0;
    s.settle_time = 0.005;
    s.jog_max_vel = 30_000.0;
    a0.configure(&s).unwrap();
    a0.set_scale(1000.0).unwrap();
    let a1 = card.axis(1).unwrap();
    a1.configure_pdplus(&motioncard_sdk::die_bonder_pdplus(1))
        .unwrap();
    a1.set_scale(-2.5e-3).unwrap();
    let a2 = card.axis(2).unwrap();
    a2.set_filters(&FilterSettings {
        rapid: (FilterKind::Linear, 0.02),
        cutting: (FilterKind::Exponential, 0.015),
        jog: (FilterKind::None, 0.0),
    })
    .unwrap();
    a2.configure_safety(&SafetySettings {
        soft_limits: Some((-1e6, 2e6)),
        ferror: 5_000.0,
        ..SafetySettings::default()
    })
    .unwrap();
    a2.configure_homing(&HomingSettings {
        method: 17,
        flags: HomingFlags::MOVE_TO_HOME.bits(),
        search_vel: 10_000.0,
        home_offset: -12.5,
        ..HomingSettings::default()
    })
    .unwrap();
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings {
        axes: vec![2, 0],
        accdec: AccDec::Post,
        interpolator: Interpolator::ReferenceWord,
        tolerance: 1.5,
        home_order: Vec::new(),
    })
    .unwrap();
    g.configure_path(&PathSettings {
        lookahead: 64,
        low_water: 8,
        plan_period: 0.002,
        chord_fit: true,
        ..PathSettings::uniform(2, 1e5, 1e6, 1e8)
    })
    .unwrap();
    // Layout 1.11: servo-output filters, an analog input, the path-speed output on group 0.
    a0.set_servo_filter(1, &BiquadSpec::notch(24.0, 0.2, -20.0))
        .unwrap();
    a0.set_servo_filter(3, &BiquadSpec::low_pass(800.0, 0.7))
        .unwrap();
    a2.set_servo_filter(0, &BiquadSpec::lead_lag(30.0, 90.0))
        .unwrap();
    a2.set_servo_filter(2, &BiquadSpec::raw([0.2, 0.2, 0.0, -0.6, 0.0]))
        .unwrap();
    card.configure_analog_input(
        3,
        &AnalogInputSettings {
            cutoff_hz: 50.0,
            threshold: 2.5,
            hysteresis: 0.25,
            rise_event: true,
            fall_event: false,
        },
    )
    .unwrap();
    card.pso_counts(
        0,
        &Pso {
            output: PsoOutput::Pwm {
                output: 3,
                hz: 2000.0,
            },
            gate: 2,
            min: 0.1,
            max: 0.8,
            v_ref: 5e4,
            filter_hz: 100.0,
        },
    )
    .unwrap();
    card
}

#[test]
fn a_non_default_configuration_round_trips_byte_for_byte() {
    let fresh = card().save_config().unwrap();
    let a = configured();
    let saved = a.save_config().unwrap();
    println!("{saved}");
    assert_ne!(saved, fresh, "the configuration is not the card's reset");
    for needle in [
        "servo_rate_hz = 8000",
        "max_stop_time_us = 3000000",
        "servo_law = \"pdplus\"",
        "scale = -0.0025",
        "rapid_kind = \"linear\"",
        "method = 17",
        "interpolator = \"reference_word\"",
        "lookahead = 64",
        "[axis.0.biquad.1]\nkind = \"notch\"\nfreq_hz = 24.0\ndamping = 0.2\ndepth_db = -20.0\n",
        "[axis.0.biquad.2]\nkind = \"none\"\n",
        "[axis.2.biquad.0]\nkind = \"lead_lag\"\nfreq_hz = 30.0\nfreq2_hz = 90.0\n",
        "kind = \"raw\"\nb0 = 0.2\nb1 = 0.2\nb2 = 0.0\na1 = -0.6\na2 = 0.0\n",
        "[analog_input.3]\ncutoff_hz = 50.0\nthreshold = 2.5\nhysteresis = 0.25\nrise_event = true\n",
        "[pso]\noutput = \"pwm\"\ngroup = 0\nchannel = 3\npwm_hz = 2000.0\ngate = 2\n",
    ] {
        assert!(saved.contains(needle), "{needle}");
    }
    let b = card();
    let report = b.load_config(&saved, "a.toml").unwrap();
    assert!(report.applied.len() >= 10, "{:?}", report.applied);
    let again = b.save_config().unwrap();
    assert_eq!(
        again, saved,
        "save, load on a fresh card, save: the same bytes"
    );
    // Loading it again changes nothing, and the card's scale is this host's.
    assert!(b.load_config(&saved, "a.toml").unwrap().applied.is_empty());
    assert_eq!(b.axis(1).unwrap().scale_factor(), -2.5e-3);
    assert_eq!(
        Config::parse(&saved, "a.toml").unwrap(),
        b.read_config().unwrap()
    );
    assert!(b.diff_config(&saved, "a.toml").unwrap().is_empty());
    let d = b.diff_config(&fresh, "fresh.toml").unwrap();
    let keys: Vec<&str> = d.iter().map(|d| d.key.as_str()).collect();
    assert!(keys.contains(&"card.servo_rate_hz"), "{keys:?}");
    assert!(keys.contains(&"axis.0.ffpiv.kp"), "{keys:?}");
    assert!(keys.contains(&"io.debounce"), "{keys:?}");
    // The filters, the analog input and the PSO as the SDK reads them.
    let f = b.axis(2).unwrap().servo_filters().unwrap();
    assert_eq!(f[0].unwrap().spec, BiquadSpec::lead_lag(30.0, 90.0));
    assert_eq!(f[1], None);
    assert_eq!(
        f[2].unwrap().spec,
        BiquadSpec::raw([0.2, 0.2, 0.0, -0.6, 0.0])
    );
    assert_eq!(b.analog_input(3).unwrap().settings.cutoff_hz, 50.0);
    let pso = b.pso_status().unwrap();
    assert_eq!((pso.state, pso.group), (PsoState::Closed, 0));
    assert_eq!(pso.settings.unwrap().v_ref, 5e4);
    // A host opening the card later adopts its scales.
    let settings = b.axis(2).unwrap().safety_settings().unwrap();
    assert_eq!(settings.soft_limits, Some((-1e6, 2e6)));
    // A fresh card's file empties the slots, resets the input and stops the PSO.
    b.load_config(&fresh, "fresh.toml").unwrap();
    assert_eq!(b.axis(0).unwrap().servo_filters().unwrap(), [None; 4]);
    assert_eq!(b.pso_status().unwrap().state, PsoState::Off);
    assert_eq!(
        b.analog_input(3).unwrap().settings,
        AnalogInputSettings::default()
    );
}

/// The line (1-based) of the first line of `text` that starts with `prefix` after the line
/// `after`.
fn line_after(text: &str, after: &str, prefix: &str) -> usize {
    let start = text.lines().position(|l| l == after).expect(after);
    start
        + 1
        + text
            .lines()
            .skip(start)
            .position(|l| l.starts_with(prefix))
            .expect(prefix)
}

/// Replace the first line starting with `prefix` after the line `after`.
fn replace_after(text: &str, after: &str, prefix: &str, with: &str) -> String {
    let n = line_after(text, after, prefix);
    text.lines()
        .enumerate()
        .map(|(i, l)| if i + 1 == n { with } else { l })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

#[test]
fn a_file_with_one_bad_value_changes_nothing_and_names_key_and_line() {
    let saved = configured().save_config().unwrap();
    let b = card();
    let before = b.save_config().unwrap();
    let kp = line_after(&saved, "[axis.0.ffpiv]", "kp = ");
    let umax = line_after(&saved, "[axis.1.pdplus]", "umax = ");
    let cases: Vec<(String, &str, usize)> = vec![
        (
            replace_after(&saved, "[axis.0.ffpiv]", "kp = ", "kp = -5.0"),
            "axis.0.ffpiv.kp",
            kp,
        ),
        (
            replace_after(&saved, "[axis.0.ffpiv]", "kp = ", "kp = nan"),
            "axis.0.ffpiv.kp",
            kp,
        ),
        (
            replace_after(&saved, "[axis.0.ffpiv]", "kp = ", "kp = \"high\""),
            "axis.0.ffpiv.kp",
            kp,
        ),
        (
            replace_after(&saved, "[axis.0.ffpiv]", "kp = ", "kpp = 1.0"),
            "axis.0.ffpiv.kpp",
            kp,
        ),
        (
            replace_after(&saved, "[axis.1.pdplus]", "umax = ", "umax = 11.0"),
            "axis.1.pdplus.umax",
            umax,
        ),
        (
            saved.replace("[axis.3", "[axis.7"),
            "axis.7",
            line_after(&saved, "[axis.0]", "[axis.3]"),
        ),
        (
            replace_after(
                &saved,
                "[safety]",
                "max_stop_time_us",
                "max_stop_time_us = 5",
            ),
            "safety.max_stop_time_us",
            line_after(&saved, "[safety]", "max_stop_time_us"),
        ),
        (
            replace_after(&saved, "[axis.2.homing]", "method = ", "method = 15"),
            "axis.2.homing.method",
            line_after(&saved, "[axis.2.homing]", "method = "),
        ),
        // Layout 1.11: the filters, checked and designed at the file's rate (8 kHz).
        (
            replace_after(&saved, "[axis.0.biquad.1]", "freq_hz", "freq_hz = 4000.0"),
            "axis.0.biquad.1.freq_hz",
            line_after(&saved, "[axis.0.biquad.1]", "freq_hz"),
        ),
        (
            replace_after(&saved, "[axis.0.biquad.1]", "depth_db", "depth_db = 3.0"),
            "axis.0.biquad.1.depth_db",
            line_after(&saved, "[axis.0.biquad.1]", "depth_db"),
        ),
        (
            replace_after(&saved, "[axis.2.biquad.2]", "a1 = ", "a1 = -2.5"),
            "axis.2.biquad.2.a1",
            line_after(&saved, "[axis.2.biquad.2]", "a1 = "),
        ),
        (
            replace_after(&saved, "[axis.0.biquad.3]", "kind", "kind = \"lead_lag\""),
            "axis.0.biquad.3.damping",
            line_after(&saved, "[axis.0.biquad.3]", "damping"),
        ),
        (
            saved.replace("[axis.0.biquad.3]", "[axis.0.biquad.4]"),
            "axis.0.biquad.4",
            line_after(&saved, "[axis.0]", "[axis.0.biquad.3]"),
        ),
        (
            replace_after(&saved, "[analog_input.3]", "threshold", "threshold = 11.0"),
            "analog_input.3.threshold",
            line_after(&saved, "[analog_input.3]", "threshold"),
        ),
        (
            replace_after(
                &saved,
                "[analog_input.3]",
                "cutoff_hz",
                "cutoff_hz = 4001.0",
            ),
            "analog_input.3.cutoff_hz",
            line_after(&saved, "[analog_input.3]", "cutoff_hz"),
        ),
        (
            replace_after(&saved, "[pso]", "max = ", "max = 1.5"),
            "pso.max",
            line_after(&saved, "[pso]", "max = "),
        ),
        (
            replace_after(&saved, "[pso]", "group = ", "group = 3"),
            "pso.group",
            line_after(&saved, "[pso]", "group = "),
        ),
        (
            replace_after(&saved, "[pso]", "output = ", "output = \"dac\""),
            "pso.pwm_hz",
            line_after(&saved, "[pso]", "pwm_hz = "),
        ),
    ];
    for (text, key, line) in cases {
        let e = b.load_config(&text, "bad.toml").unwrap_err();
        println!("{e}");
        assert_eq!(e.kind(), ErrorKind::ConfigFile, "{e}");
        match &e {
            Error::ConfigFile {
                key: k, line: l, ..
            } => {
                assert_eq!((k.as_str(), *l), (key, line), "{e}")
            }
            _ => unreachable!(),
        }
        assert!(
            e.to_string()
                .starts_with(&format!("bad.toml:{line}: {key}")),
            "{e}"
        );
        assert_eq!(b.save_config().unwrap(), before, "{key}: nothing applied");
        assert!(b.diff_config(&text, "bad.toml").is_err());
    }
    // A syntax error: the line, no key.
    let e = b
        .load_config("[card\nservo_rate_hz = 1", "x.toml")
        .unwrap_err();
    assert!(matches!(e, Error::ConfigFile { line: 1, .. }), "{e}");
    assert_eq!(b.save_config().unwrap(), before);
}

/// A servo rate at which a filter the file leaves as the card holds it would not run (800 Hz
/// above 1 kHz's Nyquist) is refused naming the rate, nothing changed; the same rate with that
/// slot replaced by a filter that runs there loads (the old one emptied before the rate).
#[test]
fn a_servo_rate_the_held_filters_cannot_run_at_is_refused() {
    let c = configured();
    let before = c.save_config().unwrap();
    let text = "[card]\nservo_rate_hz = 1000\n";
    let e = c.load_config(text, "rate.toml").unwrap_err();
    println!("{e}");
    match &e {
        Error::ConfigFile {
            key, line, message, ..
        } => {
            assert_eq!((key.as_str(), *line), ("card.servo_rate_hz", 2));
            assert!(message.contains("axis 0's filter in slot 3"), "{message}");
            assert!(message.contains("FilterFreq"), "{message}");
        }
        _ => panic!("{e}"),
    }
    assert_eq!(c.save_config().unwrap(), before, "nothing applied");
    let text = replace_after(
        &before.replace("servo_rate_hz = 8000", "servo_rate_hz = 1000"),
        "[axis.0.biquad.3]",
        "freq_hz",
        "freq_hz = 200.0",
    );
    let text = &text;
    let report = c.load_config(text, "rate.toml").unwrap();
    assert_eq!(
        report.applied,
        ["axis.0.biquad.3", "card", "axis.0.biquad.3"],
        "emptied, the rate, set"
    );
    assert_eq!(c.servo_rate().unwrap(), 1000);
    let f = c.axis(0).unwrap().servo_filters().unwrap();
    assert_eq!(f[3].unwrap().spec, BiquadSpec::low_pass(200.0, 0.7));
    assert_eq!(f[1].unwrap().spec, BiquadSpec::notch(24.0, 0.2, -20.0));
    assert!(c.diff_config(text, "rate.toml").unwrap().is_empty());
}

/// The checked-in example (`examples/config/machine.toml`: the configuration above, on a
/// 4-axis card) loads on a fresh card and saves back to its own bytes.
#[test]
fn the_example_file_round_trips() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/config/machine.toml");
    let text = std::fs::read_to_string(path).unwrap();
    assert_eq!(
        text,
        configured().save_config().unwrap(),
        "regenerate the example"
    );
    let b = card();
    b.load_config_file(path).unwrap();
    assert_eq!(b.save_config().unwrap(), text);
    // a file saved before the planner's period existed loads, with the card's default
    let old: String = text
        .lines()
        .filter(|l| !l.starts_with("plan_period"))
        .map(|l| format!("{l}\n"))
        .collect();
    assert!(old.len() < text.len());
    let c = card();
    c.load_config(&old, "old.toml").unwrap();
    assert_eq!(
        c.save_config().unwrap(),
        text.replace("plan_period = 0.002", "plan_period = 0.0")
    );
}

/// What a host wrote into a block after the card applied it, or had refused, is not what the
/// getters give: they read the card back.
#[test]
fn the_getters_read_the_card_not_the_last_write() {
    let c = card();
    let a = c.axis(0).unwrap();
    let bad = motioncard_sdk::AxisSettings {
        dac_limit_v: 12.0,
        ..Default::default()
    };
    assert_eq!(a.configure(&bad).unwrap_err().kind(), ErrorKind::BadConfig);
    assert_eq!(a.settings().unwrap().dac_limit_v, 10.0);
    let io = IoSettings {
        polarity: 1 << 20, // beyond the inputs: refused
        ..Default::default()
    };
    assert!(c.configure_io(&io).is_err());
    assert_eq!(c.io_settings().unwrap().polarity, 0);
    assert_eq!(a.pdplus_settings().unwrap(), None);
    a.configure_pdplus(&motioncard_sdk::die_bonder_pdplus(0))
        .unwrap();
    let pd = a.pdplus_settings().unwrap().unwrap();
    assert_eq!(pd.gains, motioncard_sdk::die_bonder_pdplus(0).gains);
    assert!(c.group(1).unwrap().settings().unwrap().is_none());
    assert_eq!(c.servo_rate().unwrap(), 10_000);
    assert_eq!(c.safety_settings().unwrap().max_stop_time_us, 2_000_000);
    assert_eq!(a.filter_settings().unwrap(), FilterSettings::shin_table1());
}

/// Any one number of a saved configuration replaced by a value from the whole f64 range
/// (zero, subnormals, 1e-300, 1e300, infinities, NaN, either sign; a float where an integer
/// belongs too): the load either applies all of the file, so the card then holds exactly it
/// (no difference left), or refuses it as `ConfigFile` naming that key and line, and changes
/// nothing. Never a half-applied file, never a panic.
/// A modulo period the card cannot hold to the last bit (it holds 1/65536 count) loads and
/// reads back as the same period: the file's value as the card holds it, no difference left.
/// (Found by the sweep below: 144770.06379344547 read back as 144770.0638 and the load
/// called it a protocol violation.)
#[test]
fn a_modulo_finer_than_the_card_holds_loads_and_shows_no_difference() {
    let saved = configured().save_config().unwrap();
    for v in ["144770.06379344547", "360.0000000001", "12.345678901234567"] {
        // axis 2's (its scale is positive)
        let mut section = "";
        let text: String = saved
            .lines()
            .map(|l| {
                if l.starts_with('[') {
                    section = l;
                }
                if section == "[axis.2]" && l.starts_with("modulo = ") {
                    format!("modulo = {v}\n")
                } else {
                    format!("{l}\n")
                }
            })
            .collect();
        assert!(text.contains(&format!("modulo = {v}")), "no modulo key");
        let b = card();
        b.load_config(&text, "m.toml").unwrap();
        assert_eq!(b.diff_config(&text, "m.toml").unwrap(), vec![], "{v}");
    }
}

#[test]
fn any_number_anywhere_loads_whole_or_changes_nothing() {
    use proptest::prelude::*;
    use proptest::test_runner::{Config as PtConfig, TestRunner};
    let saved = configured().save_config().unwrap();
    let numbers: Vec<usize> = saved
        .lines()
        .enumerate()
        .filter(|(_, l)| {
            l.split_once(" = ")
                .is_some_and(|(_, v)| v.parse::<f64>().is_ok())
        })
        .map(|(i, _)| i)
        .collect();
    assert!(numbers.len() > 100, "{} numbers", numbers.len());
    // Layout 1.11's sections (the filters, the analog inputs, the PSO) get half the cases.
    let mut section = "";
    let newer: Vec<usize> = saved
        .lines()
        .enumerate()
        .filter(|(_, l)| {
            if l.starts_with('[') {
                section = l;
            }
            section.contains(".biquad.")
                || section.starts_with("[analog_input.")
                || section == "[pso]"
        })
        .map(|(i, _)| i)
        .filter(|i| numbers.contains(i))
        .collect();
    assert!(newer.len() > 20, "{} numbers", newer.len());
    let b = card();
    let value = prop_oneof![
        Just(0.0),
        Just(-0.0),
        Just(f64::MIN_POSITIVE / 4.0),
        Just(1e-300),
        Just(1e300),
        Just(-1e300),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(f64::NAN),
        (-1e6f64..1e6),
        any::<f64>(),
    ];
    let (applied, refused) = (std::cell::Cell::new(0), std::cell::Cell::new(0));
    let mut runner = TestRunner::new(PtConfig {
        cases: 200,
        failure_persistence: None,
        ..PtConfig::default()
    });
    runner
        .run(
            &(
                prop_oneof![
                    proptest::sample::select(numbers),
                    proptest::sample::select(newer)
                ],
                value,
            ),
            |(line, v)| {
                let mut lines: Vec<String> = saved.lines().map(String::from).collect();
                let (key, _) = lines[line].split_once(" = ").unwrap();
                // TOML spells the specials its own way.
                let text_v = match v {
                    v if v.is_nan() => "nan".to_string(),
                    v if v == f64::INFINITY => "inf".to_string(),
                    v if v == f64::NEG_INFINITY => "-inf".to_string(),
                    v => format!("{v:?}"),
                };
                lines[line] = format!("{key} = {text_v}");
                let text = lines.join("\n") + "\n";
                let before = b.save_config().unwrap();
                match b.load_config(&text, "p.toml") {
                    Ok(_) => {
                        applied.set(applied.get() + 1);
                        let diff = b.diff_config(&text, "p.toml").unwrap();
                        prop_assert!(diff.is_empty(), "line {}: {diff:?}", line + 1);
                    }
                    Err(e @ Error::ConfigFile { line: l, .. }) => {
                        refused.set(refused.get() + 1);
                        prop_assert_eq!(l, line + 1, "{}", e);
                        prop_assert_eq!(b.save_config().unwrap(), before, "{}", e);
                    }
                    Err(e) => prop_assert!(false, "line {}: {e}", line + 1),
                }
                Ok(())
            },
        )
        .unwrap();
    println!("{} files applied, {} refused", applied.get(), refused.get());
    assert!(applied.get() > 20 && refused.get() > 20);
}

/// A file larger than any configuration is refused before it is read (parsing took about 100
/// times a file's size in memory: 40 MB took 4.1 GB); text echoed from the file into an
/// error (a value, a key) is cut to 60 characters with an ellipsis.
#[test]
fn an_oversized_file_is_refused_unread_and_echoes_are_cut() {
    let card = card();
    let before = card.save_config().unwrap();
    let dir = std::env::temp_dir().join(format!("mc-config-size-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // A valid file padded with comments past the limit.
    let big = dir.join("big.toml");
    let pad = "# padding\n".repeat(motioncard_sdk::MAX_CONFIG_BYTES / 10 + 1);
    std::fs::write(&big, format!("{before}{pad}")).unwrap();
    let size = std::fs::metadata(&big).unwrap().len();
    for e in [
        card.load_config_file(&big).unwrap_err(),
        card.diff_config_file(&big).unwrap_err(),
    ] {
        assert_eq!(e.kind(), ErrorKind::ConfigFile, "{e}");
        let msg = e.to_string();
        assert!(
            msg.contains(&format!("{size} bytes is more than"))
                && msg.contains(&motioncard_sdk::MAX_CONFIG_BYTES.to_string()),
            "{msg}"
        );
    }
    // The same text given whole, and a pipe (no size) read no further than the limit.
    let text = std::fs::read_to_string(&big).unwrap();
    let e = card.load_config(&text, "text").unwrap_err();
    assert!(e.to_string().starts_with("text: "), "{e}");
    let e = card.load_config_file("/dev/zero").unwrap_err();
    assert!(
        e.to_string().contains(&format!(
            "more than {} bytes is more than",
            motioncard_sdk::MAX_CONFIG_BYTES
        )),
        "{e}"
    );
    // Just under the limit is read.
    let under = before.clone() + &"#".repeat(motioncard_sdk::MAX_CONFIG_BYTES - before.len() - 1);
    std::fs::write(&big, under + "\n").unwrap();
    card.load_config_file(&big).unwrap();
    // A long string where a number goes, and a long unknown key: cut.
    let long = "x".repeat(200_000);
    let value = replace_after(
        &before,
        "[axis.0.ffpiv]",
        "kp = ",
        &format!("kp = \"{long}\""),
    );
    let key = replace_after(&before, "[axis.0.ffpiv]", "kp = ", &format!("{long} = 1.0"));
    for (text, want_key) in [
        (value, "axis.0.ffpiv.kp".to_string()),
        (key, format!("axis.0.ffpiv.{}…", &long[..60])),
    ] {
        let e = card.load_config(&text, "f.toml").unwrap_err();
        let Error::ConfigFile { key, message, .. } = &e else {
            panic!("{e}")
        };
        assert_eq!(key, &want_key);
        assert!(message.contains(&format!("{}…", &long[..60])), "{message}");
        assert!(
            e.to_string().len() < 600,
            "{} bytes: {e}",
            e.to_string().len()
        );
    }
    assert_eq!(card.save_config().unwrap(), before, "nothing was applied");
    std::fs::remove_dir_all(&dir).ok();
}

/// The largest file `save_config` writes (8 axes, every section: scales, PID+FF gains, four
/// raw biquads, a bidirectional compensation table of the most points, soft limits, homing;
/// four groups with their path settings; every analog input and the PSO; numbers of 17
/// significant digits throughout) fits in `MAX_CONFIG_BYTES`, loads on a fresh card and saves
/// to the same bytes.
#[test]
fn the_largest_file_save_writes_loads_back() {
    use motioncard_sdk::{CompPoint, Compensation, PidffSettings, COMP_POINTS_MAX};
    let card = stepped_card_with(EmuOptions::new(8, 10_000));
    // Long numbers: 17 significant digits and an exponent.
    let long = |x: f64| x * (1.0 + std::f64::consts::PI * 1e-9);
    for a in 0..8 {
        let ax = card.axis(a).unwrap();
        ax.set_scale(long(-1000.0)).unwrap();
        ax.configure_pidff(&PidffSettings::for_drive(long(123_456.0), long(300.0)))
            .unwrap();
        for k in 0..4 {
            let c = long(0.1 + 0.01 * k as f64);
            ax.set_servo_filter(k, &BiquadSpec::raw([c, c, 0.0, -0.6, 0.0]))
                .unwrap();
        }
        let points = (0..COMP_POINTS_MAX)
            .map(|k| CompPoint {
                position: long(k as f64 * 97.0 - 12_000.0),
                forward: long(0.001 * (k % 17) as f64 - 0.007),
                reverse: long(0.001 * (k % 13) as f64 - 0.005),
            })
            .collect();
        ax.set_compensation(&Compensation {
            points,
            bidirectional: true,
            backlash: long(0.002),
            bound: long(0.05),
            ramp_velocity: long(2.0),
            ramp_acceleration: long(2e3),
        })
        .unwrap();
        ax.configure_safety(&SafetySettings {
            soft_limits: Some((long(-1e3), long(2e3))),
            ferror: long(5.0),
            ..ax.safety_settings().unwrap()
        })
        .unwrap();
        ax.configure_homing(&HomingSettings {
            method: 17,
            search_vel: long(10_000.0),
            home_offset: long(-12.5),
            ..ax.homing_settings().unwrap()
        })
        .unwrap();
    }
    for g in 0..4 {
        let grp = card.group(g).unwrap();
        grp.configure(&GroupSettings::new(&[2 * g, 2 * g + 1]))
            .unwrap();
        grp.configure_path(&PathSettings {
            lookahead: 64,
            plan_period: 0.002,
            ..PathSettings::uniform(2, long(100.0), long(1e3), long(1e5))
        })
        .unwrap();
    }
    for i in 0..8 {
        card.configure_analog_input(
            i,
            &AnalogInputSettings {
                cutoff_hz: long(50.0),
                threshold: long(2.5),
                hysteresis: long(0.25),
                rise_event: true,
                fall_event: true,
            },
        )
        .unwrap();
    }
    let text = card.save_config().unwrap();
    println!(
        "the largest configuration file: {} bytes (limit {})",
        text.len(),
        motioncard_sdk::MAX_CONFIG_BYTES
    );
    // Room left for comments: at least a third of the limit.
    assert!(
        text.len() <= motioncard_sdk::MAX_CONFIG_BYTES * 2 / 3,
        "{} bytes",
        text.len()
    );
    let fresh = stepped_card_with(EmuOptions::new(8, 10_000));
    fresh.load_config(&text, "largest.toml").unwrap();
    assert_eq!(fresh.save_config().unwrap(), text);
}

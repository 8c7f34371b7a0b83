//! Analog I/O and the path-speed output (layout 1.11) on the stepped card and its plant
//! (deterministic): the ADC's quantisation and saturation, the filter's step response against
//! the analytic first-order one, the threshold's event on the tick the analytic response
//! crosses it (and back with the hysteresis), the spare DACs' clamp and read-back, every
//! refusal changing nothing, and the PSO through a 90° blended corner.
//!
//! `cargo test --release --test analog -- --nocapture` prints the PSO's error through the
//! corner (BENCHMARKS.md, "Path-speed output through a 90° corner").
mod common;

use common::stepped_card_with;
use motioncard_sdk::{
    AnalogInputSettings, AnalogSource, Card, CardEvent, EmuOptions, ErrorKind, EventKind,
    GroupSettings, OutputAt, PathItem, PathSettings, Pso, PsoOutput, PsoState, Segment, ADC_LSB,
};
use std::time::Duration;

const RATE: u32 = 10_000;

fn card(axes: usize) -> Card {
    stepped_card_with(EmuOptions::new(axes, RATE))
}

/// Every event queued now.
fn events(card: &Card) -> Vec<CardEvent> {
    card.poll_events().unwrap();
    std::iter::from_fn(|| card.next_event(Duration::ZERO).unwrap()).collect()
}

fn set_pin(card: &Card, i: usize, s: AnalogSource) {
    card.sim().unwrap().with_emulator(|e| e.analog().set(i, s));
}

fn kind(r: motioncard_sdk::Result<impl std::fmt::Debug>) -> ErrorKind {
    r.expect_err("refused").kind()
}

/// The 16-bit ADC: round to the nearest 20/65536 V, saturate at -10 V and 10 V - 1 LSB.
#[test]
fn the_adc_quantises_to_16_bits_and_saturates() {
    let card = card(1);
    let sim = card.sim().unwrap();
    for (v, code) in [
        (0.0, 0.0),
        (1.0, 3277.0),   // 3276.8 codes
        (-2.5, -8192.0), // exact
        (0.000_15, 0.0), // under half an LSB (0.1526 mV)
        (0.000_16, 1.0),
        (12.0, 32767.0),
        (-12.0, -32768.0),
    ] {
        set_pin(&card, 0, AnalogSource::Constant(v));
        sim.step(1);
        let a = card.analog_input(0).unwrap();
        assert_eq!(a.sample, code * ADC_LSB, "{v} V");
        assert_eq!(a.value, a.sample, "no filter: the value is the sample");
    }
}

/// A 5 V step through a 20 Hz filter: the value is the continuous first-order response at
/// every tick (to rounding); the threshold at 3 V posts MC_EV_ANALOG on the tick the analytic
/// response first reaches it, and the fall comes only at 3 - 0.5 V.
#[test]
fn filter_step_response_and_threshold_event_are_exact() {
    let card = card(1);
    let sim = card.sim().unwrap();
    let fc = 20.0;
    let s = AnalogInputSettings {
        cutoff_hz: fc,
        threshold: 3.0,
        hysteresis: 0.5,
        rise_event: true,
        fall_event: true,
    };
    card.configure_analog_input(2, &s).unwrap();
    assert_eq!(card.analog_input(2).unwrap().settings, s);
    sim.step(10);
    events(&card);
    let t0 = card.tick().unwrap();
    set_pin(&card, 2, AnalogSource::Constant(5.0));
    let y = 16384.0 * ADC_LSB; // 5 V: code 16384 exactly
    let w = std::f64::consts::TAU * fc / f64::from(RATE);
    let analytic = |n: u64| y * (1.0 - (-w * n as f64).exp());
    let first = (1..).find(|&n| analytic(n) >= 3.0).unwrap();
    let mut worst = 0.0f64;
    let mut rose = Vec::new();
    for n in 1..=2000 {
        sim.step(1);
        let a = card.analog_input(2).unwrap();
        assert_eq!(a.sample, y);
        worst = worst.max((a.value - analytic(n)).abs());
        rose.extend(
            events(&card)
                .into_iter()
                .filter(|e| e.kind == EventKind::Analog),
        );
    }
    assert!(worst < 1e-12, "filter vs analytic: {worst:e} V");
    assert_eq!(rose.len(), 1, "{rose:?}");
    let e = &rose[0];
    assert_eq!((e.axis, e.code, e.tick), (2, 1, t0 + first));
    assert!(e.value >= 3.0 && e.value - 3.0 < y * w);
    assert!(card.analog_input(2).unwrap().above);
    // Down to 2.8 V: below the threshold, within the hysteresis: no event, still above.
    set_pin(&card, 2, AnalogSource::Constant(2.8));
    sim.step(3000);
    assert!(events(&card).iter().all(|e| e.kind != EventKind::Analog));
    assert!(card.analog_input(2).unwrap().above);
    // To 2 V: below at 2.5 V.
    set_pin(&card, 2, AnalogSource::Constant(2.0));
    let t1 = card.tick().unwrap();
    let y0 = card.analog_input(2).unwrap().value;
    let y1 = (2.0f64 / ADC_LSB).round() * ADC_LSB;
    let down = (1..)
        .find(|&n| y1 + (y0 - y1) * (-w * n as f64).exp() <= 2.5)
        .unwrap();
    sim.step(3000);
    let fell: Vec<_> = events(&card)
        .into_iter()
        .filter(|e| e.kind == EventKind::Analog)
        .collect();
    assert_eq!(fell.len(), 1, "{fell:?}");
    assert_eq!((fell[0].code, fell[0].tick), (0, t1 + down));
}

/// A new servo rate keeps an input filter's cut-off in Hz: the step response at 2 kHz is the
/// continuous one at the 2 kHz instants; a rate below twice the cut-off is refused
/// (`AnalogFilter`) and leaves the rate as it was.
#[test]
fn a_new_servo_rate_keeps_the_filters_cut_off() {
    let card = card(1);
    let sim = card.sim().unwrap();
    let s = AnalogInputSettings {
        cutoff_hz: 800.0,
        threshold: 0.0,
        hysteresis: 0.0,
        rise_event: false,
        fall_event: false,
    };
    card.configure_analog_input(1, &s).unwrap();
    assert_eq!(kind(card.set_servo_rate(1_500)), ErrorKind::AnalogFilter);
    assert_eq!(card.info().servo_rate_hz, RATE);
    card.configure_analog_input(
        1,
        &AnalogInputSettings {
            cutoff_hz: 20.0,
            ..s
        },
    )
    .unwrap();
    card.set_servo_rate(2_000).unwrap();
    sim.step(10);
    set_pin(&card, 1, AnalogSource::Constant(5.0));
    let y = 16384.0 * ADC_LSB;
    let w = std::f64::consts::TAU * 20.0 / 2_000.0;
    for n in 1..=400 {
        sim.step(1);
        let v = card.analog_input(1).unwrap().value;
        assert!(
            (v - y * (1.0 - (-w * n as f64).exp())).abs() < 1e-12,
            "tick {n}"
        );
    }
}

/// A height sensor: an input wired to an axis's position follows it.
#[test]
fn a_position_sensor_follows_its_axis() {
    let card = card(1);
    let sim = card.sim().unwrap();
    set_pin(
        &card,
        5,
        AnalogSource::Position {
            axis: 0,
            volts_per_count: 1e-4,
            offset: -1.0,
        },
    );
    let ax = card.axis(0).unwrap();
    ax.enable().unwrap();
    sim.step(2);
    let at_zero = (-1.0f64 / ADC_LSB).round() * ADC_LSB;
    assert_eq!(card.analog_input(5).unwrap().sample, at_zero);
    let m = ax
        .move_absolute(20_000.0, &motioncard_sdk::MoveLimits::new(1e5, 1e6, 1e8))
        .unwrap();
    m.wait(Duration::from_secs(60)).unwrap();
    sim.step(2000);
    let shaft = sim.with_emulator(|e| e.load_position(0).unwrap());
    let want = ((-1.0 + 1e-4 * shaft) / ADC_LSB).round() * ADC_LSB;
    assert_eq!(card.analog_input(5).unwrap().sample, want);
    assert!((want - 1.0).abs() < 0.01, "{want}");
}

/// The spare DACs: clamped to the 12-bit DAC's range and quantised, read back by the host
/// and seen by the plant; NaN and an output the card does not have refused, nothing changed.
#[test]
fn spare_dacs_clamp_quantise_and_read_back() {
    let card = card(1);
    let sim = card.sim().unwrap();
    let lsb = 20.0 / 4096.0;
    assert_eq!(card.set_analog_output(0, 1.0).unwrap(), 205.0 * lsb);
    assert_eq!(card.set_analog_output(1, 15.0).unwrap(), 10.0 - lsb);
    assert_eq!(card.set_analog_output(3, -15.0).unwrap(), -10.0);
    sim.step(1);
    assert_eq!(card.analog_output(0).unwrap(), 205.0 * lsb);
    assert_eq!(card.analog_output(1).unwrap(), 10.0 - lsb);
    assert_eq!(card.analog_output(2).unwrap(), 0.0);
    assert_eq!(
        sim.with_emulator(|e| e.analog_outputs()),
        [205.0 * lsb, 10.0 - lsb, 0.0, -10.0]
    );
    assert_eq!(
        kind(card.set_analog_output(0, f64::NAN)),
        ErrorKind::NotFinite
    );
    assert_eq!(
        kind(card.set_analog_output(4, 1.0)),
        ErrorKind::AnalogChannel
    );
    assert_eq!(kind(card.analog_output(4)), ErrorKind::AnalogChannel);
    assert_eq!(kind(card.analog_input(8)), ErrorKind::AnalogChannel);
    sim.step(1);
    assert_eq!(card.analog_output(0).unwrap(), 205.0 * lsb);
}

/// Every bad analog input setting and PSO is refused with its own error, and nothing changes.
#[test]
fn refusals_change_nothing() {
    let card = card(2);
    let sim = card.sim().unwrap();
    let good = AnalogInputSettings {
        cutoff_hz: 100.0,
        threshold: 1.0,
        hysteresis: 0.1,
        rise_event: true,
        fall_event: false,
    };
    card.configure_analog_input(0, &good).unwrap();
    let bad = |s: AnalogInputSettings| kind(card.configure_analog_input(0, &s));
    assert_eq!(
        bad(AnalogInputSettings {
            cutoff_hz: 5000.5, // above Nyquist at 10 kHz
            ..good
        }),
        ErrorKind::AnalogFilter
    );
    assert_eq!(
        bad(AnalogInputSettings {
            cutoff_hz: -1.0,
            ..good
        }),
        ErrorKind::AnalogFilter
    );
    assert_eq!(
        bad(AnalogInputSettings {
            threshold: 10.5,
            ..good
        }),
        ErrorKind::AnalogThreshold
    );
    assert_eq!(
        bad(AnalogInputSettings {
            hysteresis: -0.1,
            ..good
        }),
        ErrorKind::AnalogThreshold
    );
    assert_eq!(
        bad(AnalogInputSettings {
            threshold: f64::NAN,
            ..good
        }),
        ErrorKind::NotFinite
    );
    assert_eq!(
        kind(card.configure_analog_input(8, &good)),
        ErrorKind::AnalogChannel
    );
    // Nyquist itself is taken.
    card.configure_analog_input(
        1,
        &AnalogInputSettings {
            cutoff_hz: 5000.0,
            ..good
        },
    )
    .unwrap();
    sim.step(1);
    assert_eq!(card.analog_input(0).unwrap().settings, good);

    // The PSO: a group that does not exist or is not configured, then each bad argument.
    let pso = Pso {
        output: PsoOutput::Dac(0),
        gate: 3,
        min: 0.0,
        max: 5.0,
        v_ref: 10_000.0,
        filter_hz: 0.0,
    };
    assert_eq!(kind(card.group(1).unwrap().pso(&pso)), ErrorKind::PsoGroup);
    assert_eq!(kind(card.pso_counts(9, &pso)), ErrorKind::PsoGroup);
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings::new(&[0, 1])).unwrap();
    let refused = |p: Pso| kind(g.pso(&p));
    for (p, k) in [
        (Pso { min: 6.0, ..pso }, ErrorKind::PsoConfig), // min > max
        (Pso { max: 10.5, ..pso }, ErrorKind::PsoConfig),
        (Pso { v_ref: 0.0, ..pso }, ErrorKind::PsoConfig),
        (
            Pso {
                filter_hz: 5000.5, // above Nyquist at 10 kHz
                ..pso
            },
            ErrorKind::PsoConfig,
        ),
        (Pso { gate: 16, ..pso }, ErrorKind::PsoConfig),
        (
            Pso {
                output: PsoOutput::Dac(4),
                ..pso
            },
            ErrorKind::PsoConfig,
        ),
        (
            Pso {
                output: PsoOutput::Pwm { output: 2, hz: 0.5 },
                min: 0.0,
                max: 1.0,
                ..pso
            },
            ErrorKind::PsoConfig,
        ),
        (
            Pso {
                output: PsoOutput::Pwm { output: 3, hz: 1e3 },
                min: 0.0,
                max: 1.0,
                ..pso
            },
            ErrorKind::PsoConfig, // the gate is the PWM's own output
        ),
        (
            Pso {
                output: PsoOutput::Pwm { output: 2, hz: 1e3 },
                min: 0.0,
                max: 1.5,
                ..pso
            },
            ErrorKind::PsoConfig, // a duty above 1
        ),
        (
            Pso {
                min: f64::NAN,
                ..pso
            },
            ErrorKind::NotFinite,
        ),
    ] {
        assert_eq!(refused(p), k, "{p:?}");
    }
    sim.step(1);
    assert_eq!(card.pso_status().unwrap().state, PsoState::Off);
    // A PSO on DAC 0: that DAC is the PSO's until it stops.
    g.pso(&pso).unwrap();
    assert_eq!(
        kind(card.set_analog_output(0, 1.0)),
        ErrorKind::AnalogChannel
    );
    card.pso_off().unwrap();
    card.set_analog_output(0, 1.0).unwrap();
}

/// Layout 1.12: a compare channel is refused on the digital output the PSO's PWM holds
/// (`PsoOutput`), the channel left idle and the PSO running as before; another output is
/// taken, and once the PSO stops its output is free again. (The other way, a PWM on an output a
/// compare channel pulses, is `PsoConfig`: `refusals_change_nothing`.)
#[test]
fn a_compare_channel_is_refused_on_the_psos_pwm_output() {
    use motioncard_sdk::{Direction, IoState};
    let card = card(2);
    let sim = card.sim().unwrap();
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings::new(&[0, 1])).unwrap();
    let pwm = Pso {
        output: PsoOutput::Pwm { output: 6, hz: 1e3 },
        gate: 3,
        min: 0.1,
        max: 0.9,
        v_ref: 10_000.0,
        filter_hz: 0.0,
    };
    g.pso(&pwm).unwrap();
    sim.step(1);
    let before = card.pso_status().unwrap();
    let ch = card.axis(0).unwrap().compare(0);
    assert_eq!(
        kind(ch.arm_single(6, 100, 10.0, Direction::Positive)),
        ErrorKind::PsoOutput
    );
    let series = ch.arm_series(6, 100, 10.0, 5.0, 3, Direction::Positive);
    assert_eq!(kind(series), ErrorKind::PsoOutput);
    sim.step(1);
    assert_eq!(ch.status().unwrap().state, IoState::Idle, "nothing armed");
    assert_eq!(card.pso_status().unwrap(), before, "the PSO as it was");
    // Another output is taken.
    ch.arm_single(7, 100, 10.0, Direction::Positive).unwrap();
    ch.disarm().unwrap();
    // The PSO stopped: its output is free.
    card.pso_off().unwrap();
    ch.arm_single(6, 100, 10.0, Direction::Positive).unwrap();
    assert_eq!(ch.status().unwrap().state, IoState::Armed);
}

/// The PSO on a DAC through a 90° corner blended within 200 counts: laser power = 1 V + 7 V ·
/// v/v_ref, gated by output 3 that the path sets at its start and clears at its end, the speed
/// filtered at 200 Hz. Each tick's output is compared with the ideal output at the plant's
/// true tangential speed of that tick (what the laser really sees) and at the commanded path
/// speed (what the program means; the servo's own tracking lag adds to it).
///
/// The bound (against the true speed): the card's speed w is each axis's encoder difference
/// per tick through two first-order filters, the axis's velocity estimate (α, 1500 Hz) and the
/// PSO's (β, 200 Hz); their impulse response h is positive with unit sum. So (1) the lag: on a
/// velocity whose vector changes at most at a (the plant's largest acceleration of the run),
/// |v − h∗v| ≤ a·Σ h_j·(j Ts + Ts/2) = a·τ, τ = Ts/2 + Ts(1−α)/α + Ts(1−β)/β; (2) the encoder's
/// quantisation q ∈ [0, 1) count enters as (q_k − q_{k−1})/Ts, whose filtered sum is at most
/// (1/Ts)·Σ|h_j − h_{j−1}| = 2·max h/Ts ≤ 2β/Ts per axis, √2 times that for the vector of two.
/// ||w| − |v|| ≤ |w − v|, the clamp only shrinks an error, and the DAC rounds to half an LSB:
/// |error| ≤ k·(a·τ + 2√2·β/Ts) + LSB/2, k = (max − min)/v_ref.
#[test]
fn pso_follows_the_actual_speed_through_a_90_degree_corner() {
    const V: f64 = 50_000.0;
    const A: f64 = 1e6;
    const J: f64 = 1e8;
    const FC: f64 = 200.0;
    let card = card(2);
    let sim = card.sim().unwrap();
    for a in 0..2 {
        card.axis(a).unwrap().enable().unwrap();
    }
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings::new(&[0, 1])).unwrap();
    g.enable().unwrap();
    g.configure_path(&PathSettings::uniform(2, V, A, J))
        .unwrap();
    let (min, max) = (1.0, 8.0);
    g.pso(&Pso {
        output: PsoOutput::Dac(1),
        gate: 3,
        min,
        max,
        v_ref: V,
        filter_hz: FC,
    })
    .unwrap();
    sim.step(1);
    let st = card.pso_status().unwrap();
    assert_eq!((st.state, st.value), (PsoState::Closed, 0.0));
    let items: Vec<PathItem> = vec![
        PathItem::Output {
            output: 3,
            on: true,
            at: OutputAt::Start,
        },
        Segment::line(1, &[30_000.0, 0.0], V, 200.0).into(),
        PathItem::Output {
            output: 3,
            on: false,
            at: OutputAt::End,
        },
        Segment::line(2, &[30_000.0, 30_000.0], V, 200.0)
            .last()
            .into(),
    ];
    g.stream_path(items, |_| {}).unwrap();
    let k = (max - min) / V;
    let ideal = |v: f64| (min + k * v).clamp(min, max);
    let counts_per_rad = sim.with_emulator(|e| e.motor(0).unwrap().params.counts_per_rad());
    let (mut worst_cmd, mut worst_true, mut on_ticks, mut corner_min) = (0.0f64, 0.0f64, 0, V);
    let mut worst_at = 0.0;
    let ts = 1.0 / f64::from(RATE);
    let true_vel = || {
        sim.with_emulator(|e| {
            let w: Vec<f64> = (0..2).map(|a| e.motor(a).unwrap().omega).collect();
            [w[0] * counts_per_rad, w[1] * counts_per_rad]
        })
    };
    let mut last_true = true_vel();
    let mut a_max = 0.0f64;
    for _ in 0..200_000 {
        sim.step(1);
        let vt = true_vel();
        a_max = a_max.max((vt[0] - last_true[0]).hypot(vt[1] - last_true[1]) / ts);
        last_true = vt;
        let st = card.pso_status().unwrap();
        let dac = card.analog_output(1).unwrap();
        assert_eq!(dac, st.value);
        if st.state == PsoState::On {
            on_ticks += 1;
            let cmd: Vec<f64> = (0..2)
                .map(|a| card.axis(a).unwrap().status().unwrap().raw.cmd_vel)
                .collect();
            let v_cmd = cmd[0].hypot(cmd[1]);
            let v_true = vt[0].hypot(vt[1]);
            let (ec, et) = (st.value - ideal(v_cmd), st.value - ideal(v_true));
            if ec.abs() > worst_cmd {
                worst_cmd = ec.abs();
                worst_at = v_cmd;
            }
            worst_true = worst_true.max(et.abs());
            let p0 = card.axis(0).unwrap().status().unwrap().raw.cmd_pos;
            if (29_000.0..30_000.0).contains(&p0) {
                corner_min = corner_min.min(v_cmd);
            }
        } else if on_ticks > 0 {
            assert_eq!(st.value, 0.0, "the gate closed: 0 V");
            break;
        }
    }
    assert!(on_ticks > 1000, "{on_ticks} ticks on");
    assert!(
        corner_min < 0.9 * V,
        "the corner slows the path: {corner_min}"
    );
    let fs = 20.0;
    println!(
        "PSO through a 90° corner (feed {V} counts/s, blend 200 counts, 1 V + 7 V·v/v_ref): \
         worst error vs the commanded path speed {worst_cmd:.4} V ({:.3} % of the 20 V full \
         scale, at {worst_at:.0} counts/s), vs the plant's true speed {worst_true:.4} V \
         ({:.3} %), slowest commanded speed in the corner {corner_min:.0} counts/s",
        100.0 * worst_cmd / fs,
        100.0 * worst_true / fs,
    );
    let alpha = 1.0 - (-std::f64::consts::TAU * 1500.0 * ts).exp();
    let beta = 1.0 - (-std::f64::consts::TAU * FC * ts).exp();
    let tau = ts / 2.0 + ts * (1.0 - alpha) / alpha + ts * (1.0 - beta) / beta;
    let bound = k * (a_max * tau + 2.0 * 2f64.sqrt() * beta / ts) + 20.0 / 4096.0 / 2.0;
    println!(
        "bound {bound:.4} V ({:.3} %): a = {a_max:.0} counts/s², τ = {:.3} ms",
        100.0 * bound / fs,
        tau * 1e3
    );
    assert!(worst_true <= bound, "{worst_true} V > {bound} V");
}

/// The scope's analog signals (MC_SIG_AIN0..7 51..58, MC_SIG_AOUT0..3 59..62, MC_SIG_PSO 63):
/// each sample is the status of its tick.
#[test]
fn the_scope_samples_the_analog_signals() {
    use motioncard_sdk::{ScopeSettings, Signal, Source};
    let card = card(2);
    let sim = card.sim().unwrap();
    for i in 0..8 {
        set_pin(&card, i, AnalogSource::Constant(i as f64 - 3.5));
    }
    card.set_analog_output(3, -2.0).unwrap();
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings::new(&[0, 1])).unwrap();
    g.pso(&Pso {
        output: PsoOutput::Dac(0),
        gate: 3,
        min: 1.5,
        max: 5.0,
        v_ref: 1e4,
        filter_hz: 0.0,
    })
    .unwrap();
    card.set_outputs(8, 8).unwrap();
    sim.step(2);
    let signals = [
        Signal::Ain0,
        Signal::Ain1,
        Signal::Ain2,
        Signal::Ain3,
        Signal::Ain4,
        Signal::Ain5,
        Signal::Ain6,
        Signal::Ain7,
        Signal::Aout0,
        Signal::Aout1,
        Signal::Aout2,
        Signal::Aout3,
        Signal::Pso,
    ];
    assert_eq!(
        signals.map(|s| s as u32),
        core::array::from_fn(|k| 51 + k as u32)
    );
    let sources: Vec<Source> = signals.iter().map(|&s| Source::axis(s, 0)).collect();
    let cap = card
        .scope()
        .capture(
            &ScopeSettings::new(&sources, 1),
            Duration::from_secs(60),
            |_| Ok(()),
        )
        .unwrap();
    let v = &cap.samples[0].value;
    for (i, &x) in v.iter().enumerate().take(8) {
        assert_eq!(x, card.analog_input(i).unwrap().value, "ain{i}");
        assert_eq!(x, ((i as f64 - 3.5) / ADC_LSB).round() * ADC_LSB);
    }
    let pso = 1.5f64;
    let dac = |x: f64| (x / (20.0 / 4096.0)).round() * (20.0 / 4096.0);
    assert_eq!(&v[8..12], &[dac(pso), 0.0, 0.0, dac(-2.0)]);
    assert_eq!(v[12], dac(pso));
    assert_eq!(card.pso_status().unwrap().state, PsoState::On);
}

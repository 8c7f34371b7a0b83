//! The scope (layout 1.8) through the SDK: on a stepped `sim` card every sample is the status
//! of its tick, bit for bit; each trigger kind, pre-trigger samples, the divider, one-shot and
//! continuous capture, a ring nobody drains, the refusals; and across processes, a
//! `card-emu` process at 20 kHz captured on 16 channels during a move and drained by this
//! process, every sample there, in order, equal to the same capture on a stepped card.
mod common;

use common::{card_emu as start, open_when_ready};
use motioncard_sdk::{
    Card, Clock, Edge, EmuOptions, ErrorKind, EventKind, MoveLimits, ScopeEvent, ScopeMode,
    ScopeSample, ScopeSettings, ScopeState, ScopeTrigger, Signal, SimOptions, Source, StopCategory,
    SCOPE_RING_LEN,
};
use std::time::Duration;

fn stepped(axes: usize, rate: u32) -> Card {
    Card::open_sim(SimOptions {
        clock: Clock::Stepped,
        emu: EmuOptions {
            axes,
            servo_rate_hz: rate,
            ..EmuOptions::default()
        },
    })
    .unwrap()
}

/// 16 channels: 13 signals of axis 0, axis 1's commanded position, group 0's path speed and
/// the inputs.
fn sixteen() -> Vec<Source> {
    let mut v: Vec<Source> = [
        Signal::CmdPos,
        Signal::CmdVel,
        Signal::CmdAcc,
        Signal::ActPos,
        Signal::ActVel,
        Signal::Ferr,
        Signal::Dac,
        Signal::URequest,
        Signal::Encoder,
        Signal::ServoP,
        Signal::ServoI,
        Signal::ServoD,
        Signal::ServoFf,
    ]
    .iter()
    .map(|&s| Source::axis(s, 0))
    .collect();
    v.push(Source::axis(Signal::CmdPos, 1));
    v.push(Source {
        signal: Signal::PathSpeed,
        index: 0,
    });
    v.push(Source {
        signal: Signal::Inputs,
        index: 0,
    });
    v
}

const MOVE: f64 = 40_000.0;

fn limits() -> MoveLimits {
    MoveLimits::new(200_000.0, 4e6, 4e8)
}

fn scope_events(card: &Card) -> Vec<(i32, f64)> {
    let mut v = Vec::new();
    while let Some(e) = card.next_event(Duration::ZERO).unwrap() {
        if e.kind == EventKind::Scope {
            v.push((e.code, e.value));
        }
    }
    v
}

#[test]
fn every_sample_is_the_status_of_its_tick() {
    let card = stepped(2, 20_000);
    let sim = card.sim().unwrap();
    let ax = card.axis(0).unwrap();
    ax.enable().unwrap();
    let scope = card.scope();
    let settings = ScopeSettings {
        mode: ScopeMode::Continuous,
        ..ScopeSettings::new(&sixteen(), 0)
    };
    scope.configure(&settings).unwrap();
    scope.arm().unwrap();
    ax.move_relative(MOVE, &limits()).unwrap();
    let mut samples = Vec::new();
    let mut statuses = Vec::new();
    sim.trace(0, 6000, |s| {
        statuses.push(s.raw);
        scope.read(&mut samples).unwrap() == 1
    })
    .unwrap();
    assert_eq!(samples.len(), statuses.len());
    let mut moving = 0;
    for (s, st) in samples.iter().zip(&statuses) {
        assert_eq!(s.tick, st.tick);
        let want = [
            st.cmd_pos,
            st.cmd_vel,
            st.cmd_acc,
            st.act_pos,
            st.act_vel,
            st.ferr,
            st.dac_v,
            st.u_request,
            st.encoder as f64,
        ];
        for (k, w) in want.iter().enumerate() {
            assert_eq!(
                s.value[k].to_bits(),
                w.to_bits(),
                "tick {} channel {k}",
                s.tick
            );
        }
        // The servo terms add up to the output before the clamp.
        let sum: f64 = s.value[9..13].iter().sum();
        assert!((sum - st.u_request).abs() <= 1e-9 * (1.0 + st.u_request.abs()));
        assert_eq!(s.value[13], 0.0); // axis 1 at rest at 0
        assert_eq!(s.value[14], 0.0); // no group
        moving += (st.cmd_vel != 0.0) as usize;
    }
    assert!(
        moving > 1000,
        "the move was captured ({moving} samples moving)"
    );
    scope.stop().unwrap();
}

#[test]
fn level_trigger_keeps_pre_trigger_samples_at_the_divider() {
    let card = stepped(1, 10_000);
    let ax = card.axis(0).unwrap();
    ax.enable().unwrap();
    let scope = card.scope();
    let settings = ScopeSettings {
        channels: vec![
            Source::axis(Signal::CmdPos, 0),
            Source::axis(Signal::CmdVel, 0),
        ],
        divider: 3,
        trigger: ScopeTrigger::Level {
            channel: 1,
            level: 100_000.0,
            edge: Edge::Rising,
        },
        pre_trigger: 200,
        mode: ScopeMode::OneShot,
        post_trigger: 300,
    };
    let cap = scope
        .capture(&settings, Duration::from_secs(5), |_| {
            card.sim().unwrap().step(1000); // more than the pre-trigger history at rest
            ax.move_relative(MOVE, &limits()).map(|_| ())
        })
        .unwrap();
    assert_eq!((cap.samples.len(), cap.lost), (500, 0));
    let ticks: Vec<u64> = cap.samples.iter().map(|s| s.tick).collect();
    assert!(ticks.windows(2).all(|w| w[1] == w[0] + 3), "divider 3");
    let trig = &cap.samples[200];
    assert_eq!(trig.tick, cap.trigger_tick);
    assert!(trig.value[1] >= 100_000.0 && cap.samples[199].value[1] < 100_000.0);
    assert_eq!(
        cap.samples[0].value[1], 0.0,
        "pre-trigger samples from rest"
    );
    let ev = scope_events(&card);
    assert!(ev.contains(&(ScopeEvent::Triggered as i32, cap.trigger_tick as f64)));
    assert!(ev.contains(&(ScopeEvent::Done as i32, 500.0)));
    assert_eq!(scope.status().unwrap().state, ScopeState::Done);
}

#[test]
fn input_fault_and_command_triggers() {
    let card = stepped(1, 10_000);
    let sim = card.sim().unwrap();
    card.axis(0).unwrap().enable().unwrap();
    let scope = card.scope();
    let chans = [Source {
        signal: Signal::Inputs,
        index: 0,
    }];
    // An input edge: input 3 rises at some tick, the trigger sample is the first with it.
    let s = ScopeSettings {
        trigger: ScopeTrigger::Input {
            input: 3,
            edge: Edge::Rising,
        },
        pre_trigger: 5,
        ..ScopeSettings::new(&chans, 5)
    };
    let cap = scope
        .capture(&s, Duration::from_secs(1), |_| {
            sim.step(50);
            sim.set_input(3, true);
            Ok(())
        })
        .unwrap();
    let v: Vec<f64> = cap.samples.iter().map(|s| s.value[0]).collect();
    assert_eq!(v, [0.0, 0.0, 0.0, 0.0, 0.0, 8.0, 8.0, 8.0, 8.0, 8.0]);
    // A fault: an e-stop latches a fault on the axis.
    let s = ScopeSettings {
        trigger: ScopeTrigger::Fault,
        channels: vec![Source::axis(Signal::CmdVel, 0)],
        ..ScopeSettings::new(&chans, 3)
    };
    let cap = scope
        .capture(&s, Duration::from_secs(1), |_| {
            sim.step(20);
            assert_eq!(scope.status().unwrap().state, ScopeState::Waiting);
            card.estop(StopCategory::Cat0)
        })
        .unwrap();
    assert_eq!(cap.samples.len(), 3);
    // A command: nothing until MC_OP_SCOPE_TRIGGER, then the samples after it.
    let s = ScopeSettings {
        trigger: ScopeTrigger::Command,
        ..ScopeSettings::new(&chans, 4)
    };
    let cap = scope
        .capture(&s, Duration::from_secs(1), |sc| {
            sim.step(500);
            assert_eq!(sc.pending().unwrap(), 0);
            sc.trigger()
        })
        .unwrap();
    assert_eq!(cap.samples.len(), 4);
    assert!(cap.trigger_tick > 500);
}

#[test]
fn continuous_capture_runs_until_stopped_and_a_full_ring_counts_what_it_loses() {
    let card = stepped(1, 20_000);
    let sim = card.sim().unwrap();
    let scope = card.scope();
    let s = ScopeSettings {
        mode: ScopeMode::Continuous,
        ..ScopeSettings::new(&sixteen()[..1], 0)
    };
    scope.configure(&s).unwrap();
    scope.arm().unwrap();
    // Nobody drains: the ring fills, the rest is counted.
    sim.step(SCOPE_RING_LEN as u64 + 1000);
    let st = scope.status().unwrap();
    assert_eq!(st.state, ScopeState::Capturing);
    assert_eq!((st.samples, st.lost), (SCOPE_RING_LEN as u64, 1000));
    let ev = scope_events(&card);
    assert_eq!(
        ev.iter()
            .filter(|e| e.0 == ScopeEvent::Lost as i32)
            .collect::<Vec<_>>(),
        [&(ScopeEvent::Lost as i32, 1.0)]
    );
    let mut got: Vec<ScopeSample> = Vec::new();
    assert_eq!(scope.read(&mut got).unwrap(), SCOPE_RING_LEN);
    // Drained, it goes on without a gap from here.
    sim.step(100);
    got.clear();
    scope.read(&mut got).unwrap();
    assert_eq!(got.len(), 100);
    assert!(got.windows(2).all(|w| w[1].tick == w[0].tick + 1));
    scope.stop().unwrap();
    sim.step(100);
    assert_eq!(scope.pending().unwrap(), 0);
    assert_eq!(scope.status().unwrap().lost, 1000);
}

#[test]
fn refusals_name_their_fault_and_change_nothing() {
    let card = stepped(2, 10_000);
    let scope = card.scope();
    let kind = |s: &ScopeSettings| scope.configure(s).unwrap_err().kind();
    let good = ScopeSettings::new(&sixteen(), 10);
    // Before any configure, the card has nothing to arm.
    assert_eq!(scope.arm().unwrap_err().kind(), ErrorKind::ScopeState);
    let cases = [
        (
            ScopeSettings {
                channels: vec![],
                ..good.clone()
            },
            ErrorKind::ScopeChannels,
        ),
        (
            ScopeSettings {
                channels: [sixteen(), sixteen()].concat(),
                ..good.clone()
            },
            ErrorKind::ScopeChannels,
        ),
        (
            ScopeSettings {
                channels: vec![Source::axis(Signal::Ferr, 2)],
                ..good.clone()
            },
            ErrorKind::ScopeSignal,
        ),
        (
            ScopeSettings {
                channels: vec![Source {
                    signal: Signal::PathAcc,
                    index: 4,
                }],
                ..good.clone()
            },
            ErrorKind::ScopeSignal,
        ),
        (
            ScopeSettings {
                divider: 0,
                ..good.clone()
            },
            ErrorKind::ScopeDivider,
        ),
        (
            ScopeSettings {
                pre_trigger: 1025,
                ..good.clone()
            },
            ErrorKind::ScopePretrigger,
        ),
        (
            ScopeSettings {
                post_trigger: 0,
                ..good.clone()
            },
            ErrorKind::ScopeTrigger,
        ),
        (
            ScopeSettings {
                trigger: ScopeTrigger::Level {
                    channel: 0,
                    level: f64::NAN,
                    edge: Edge::Either,
                },
                ..good.clone()
            },
            ErrorKind::ScopeTrigger,
        ),
        (
            ScopeSettings {
                trigger: ScopeTrigger::Level {
                    channel: 16,
                    level: 0.0,
                    edge: Edge::Either,
                },
                ..good.clone()
            },
            ErrorKind::ScopeTrigger,
        ),
        (
            ScopeSettings {
                trigger: ScopeTrigger::Input {
                    input: 16,
                    edge: Edge::Falling,
                },
                ..good.clone()
            },
            ErrorKind::ScopeTrigger,
        ),
    ];
    for (s, want) in &cases {
        assert_eq!(kind(s), *want, "{s:?}");
    }
    // The state refusals are the card's.
    assert_eq!(scope.trigger().unwrap_err().kind(), ErrorKind::ScopeState);
    scope.configure(&good).unwrap();
    assert_eq!(scope.stop().unwrap_err().kind(), ErrorKind::ScopeState);
    let s = ScopeSettings {
        trigger: ScopeTrigger::Command,
        ..good.clone()
    };
    scope.configure(&s).unwrap();
    let seq = scope.arm().unwrap();
    assert_eq!(scope.arm().unwrap_err().kind(), ErrorKind::ScopeState);
    assert_eq!(kind(&good), ErrorKind::ScopeState);
    card.sim().unwrap().step(10);
    let st = scope.status().unwrap();
    assert_eq!(
        (st.state, st.arm_seq, st.channels),
        (ScopeState::Waiting, seq, 16)
    );
    scope.stop().unwrap();
}

/// Capture `post` samples from the start of a move of axis 0 (level trigger on the commanded
/// velocity leaving 0, 1000 samples before it) on `card`, 16 channels at every tick, draining as it runs.
fn capture_move(card: &Card, post: u32) -> motioncard_sdk::Capture {
    let ax = card.axis(0).unwrap();
    ax.enable().unwrap();
    let settings = ScopeSettings {
        trigger: ScopeTrigger::Level {
            channel: 1,
            level: 1e-6,
            edge: Edge::Rising,
        },
        pre_trigger: 1000,
        ..ScopeSettings::new(&sixteen(), post)
    };
    card.scope()
        .capture(&settings, Duration::from_secs(30), |_| {
            // Let the pre-trigger history fill with the axis at rest.
            let t0 = card.tick().unwrap();
            while card.tick().unwrap() < t0 + 1500 {
                match card.sim() {
                    Some(sim) => sim.step(100),
                    None => std::thread::sleep(Duration::from_millis(5)),
                }
            }
            // A known move, longer than the ring.
            ax.move_relative(MOVE, &limits())?;
            Ok(())
        })
        .unwrap()
}

/// The bar: a `card-emu` process at 20 kHz, 16 channels every tick during a move, drained
/// from this process. Every sample arrives, in order (one tick apart), none lost, and each is
/// the status of its tick: equal, bit for bit, to the same capture on a stepped card in this
/// process (the firmware and the plant are deterministic per tick, and the axis starts from
/// the same rest), aligned on the trigger tick. 1000 pre-trigger samples at rest come first.
#[test]
fn a_20_khz_16_channel_capture_across_processes_loses_nothing() {
    const POST: u32 = 3 * SCOPE_RING_LEN as u32; // 0.6 s: the ring turns three times
    let name = format!("scope-{}", std::process::id());
    let _emu = start(&name, &["--axes", "2", "--servo-rate", "20000"]);
    let card = open_when_ready(&format!("emu:{name}"));
    assert_eq!(card.info().servo_rate_hz, 20_000);
    let remote = capture_move(&card, POST);
    let local = capture_move(&stepped(2, 20_000), POST);
    println!(
        "scope across processes: {} samples x 16 channels at 20 kHz, {} lost",
        remote.samples.len(),
        remote.lost
    );
    assert_eq!(remote.lost, 0);
    assert_eq!(remote.samples.len(), 1000 + POST as usize);
    let r = &remote.samples;
    assert!(
        r.windows(2).all(|w| w[1].tick == w[0].tick + 1),
        "in order, no gap"
    );
    assert_eq!(r[1000].tick, remote.trigger_tick);
    assert_eq!(local.samples.len(), r.len());
    for (k, (a, b)) in r.iter().zip(&local.samples).enumerate() {
        // (samples before the trigger: signed)
        assert_eq!(
            a.tick as i64 - remote.trigger_tick as i64,
            b.tick as i64 - local.trigger_tick as i64
        );
        for c in 0..16 {
            assert_eq!(
                a.value[c].to_bits(),
                b.value[c].to_bits(),
                "sample {k} channel {c}: {} vs {}",
                a.value[c],
                b.value[c]
            );
        }
    }
    // The pre-trigger samples are the axis at rest, the trigger sample the first moving one.
    assert!(r[..1000].iter().all(|s| s.value[1] == 0.0));
    assert!(r[1000].value[1] > 0.0);
}

//! Layout 1.11: group homing (PLCopen Part 4 MC_GroupHome) on the stepped card. A group of
//! three axes (X, Y, Z = card axes 0, 1, 2), each homing on its own home switch (method 19):
//! the order observed tick by tick (Z homed and at rest before X or Y moved), the group's state
//! during and after, the group failing as a whole (the member and its error, the others halted
//! with their own stop reason, the later stages never started), a group halt ending it, every
//! refusal's code, and the order carried through the configuration file.
mod common;

use common::stepped_card_with;
use motioncard_sdk::{
    AxisState, Card, EmuOptions, Error, ErrorKind, EventKind, GroupSettings, GroupState,
    HomeSwitch, HomingError, HomingSettings, PathLimits, StopReason, Switches,
};
use std::time::Duration;

const RATE: u32 = 10_000;
const LONG: Duration = Duration::from_secs(60);
/// Each axis's home switch edge (counts): the axis starts at 0 below it.
const EDGE: [f64; 3] = [6_000.0, 9_000.0, 4_000.0];

/// Three axes, each with a home switch above its edge (`None`: axis `a` has none) and homing
/// method 19 within `max_distance`, enabled, in group 0 (enabled).
fn card_with(no_switch: Option<usize>, max_distance: f64) -> Card {
    let card = stepped_card_with(EmuOptions::new(3, RATE));
    let sim = card.sim().unwrap();
    for (a, &edge) in EDGE.iter().enumerate() {
        let home = if no_switch == Some(a) {
            HomeSwitch::None
        } else {
            HomeSwitch::Above(edge)
        };
        sim.with_emulator(|e| {
            e.faults()
                .set_switches(a, Switches::limits(-1e7, 1e7).with_home(home))
        });
        let ax = card.axis(a).unwrap();
        ax.configure_homing(&HomingSettings {
            method: 19,
            max_distance: if no_switch == Some(a) {
                max_distance
            } else {
                1e6
            },
            ..HomingSettings::default()
        })
        .unwrap();
        ax.enable().unwrap();
    }
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings::new(&[0, 1, 2])).unwrap();
    g.enable().unwrap();
    card
}

fn card() -> Card {
    card_with(None, 1e6)
}

/// Z first, then X and Y together: Z is homed and at rest before X or Y moves, on every tick;
/// the group is in GroupHoming throughout, then Standby with every axis homed; the group's
/// event comes once, with the command's seq and the stages run.
#[test]
fn z_homes_first_then_x_and_y_together_and_the_group_stands_by() {
    let card = card();
    let sim = card.sim().unwrap();
    let g = card.group(0).unwrap();
    while card.next_event(Duration::ZERO).unwrap().is_some() {}
    let homing = g.home(&[&[2], &[0, 1]]).unwrap();
    let (mut z_done_tick, mut xy_moved_tick) = (None, None);
    let mut homed_event = None;
    let mut ticks = 0u64;
    loop {
        sim.step(1);
        ticks += 1;
        let (state, _) = g.status().unwrap();
        let st: Vec<_> = (0..3)
            .map(|a| card.axis(a).unwrap().status().unwrap())
            .collect();
        while let Some(e) = card.next_event(Duration::ZERO).unwrap() {
            if e.kind == EventKind::GroupHomed {
                homed_event = Some(e);
            }
            assert_ne!(e.kind, EventKind::GroupHomingFailed, "{e:?}");
        }
        if homed_event.is_some() {
            assert_eq!(state, GroupState::Standby);
            break;
        }
        assert_eq!(state, GroupState::Homing, "tick {ticks}");
        if z_done_tick.is_none() && st[2].homed() && st[2].state == AxisState::Standstill {
            z_done_tick = Some(ticks);
        }
        // X and Y begin homing (their state) on the tick Z is done at the earliest, and
        // move after it.
        let xy_moved = st[..2].iter().any(|s| s.command_position != 0.0);
        if xy_moved && xy_moved_tick.is_none() {
            xy_moved_tick = Some(ticks);
        }
        if st[..2].iter().any(|s| s.state != AxisState::Standstill) {
            assert!(
                z_done_tick.is_some(),
                "X or Y homing at tick {ticks} before Z"
            );
        }
        assert!(ticks < 600_000, "group homing did not end");
    }
    let (z, xy) = (z_done_tick.unwrap(), xy_moved_tick.unwrap());
    println!("group homing: Z homed at tick {z}, X/Y first moved at tick {xy}, all homed at tick {ticks}");
    assert!(z < xy, "Z homed at tick {z}, X or Y moved at tick {xy}");
    let e = homed_event.unwrap();
    assert_eq!((e.axis, e.seq, e.code, e.value), (0, homing.seq(), 0, 2.0));
    for a in 0..3 {
        let st = card.axis(a).unwrap().status().unwrap();
        assert!(st.homed(), "axis {a}");
        assert_eq!(st.state, AxisState::Standstill, "axis {a}");
    }
    assert_eq!(homing.wait(LONG).unwrap(), 2);
}

/// A member whose homing fails ends it for the group: X (no home switch) runs out of its
/// maximum distance; Y, homing with it, halts with stop reason GroupHoming; Z's stage never
/// starts; the group ends at rest in Standby with the failure naming X and its error.
#[test]
fn a_member_that_fails_fails_the_group_as_a_whole() {
    let card = card_with(Some(0), 3_000.0);
    let sim = card.sim().unwrap();
    let g = card.group(0).unwrap();
    let err = g.home(&[&[0, 1], &[2]]).unwrap().wait(LONG).unwrap_err();
    assert_eq!(err.kind(), ErrorKind::HomingFailed);
    match err {
        Error::GroupHomingFailed { group, axis, error } => {
            assert_eq!((group, axis), (0, Some(0)));
            assert_eq!(error, Some(HomingError::DistanceExceeded));
        }
        e => panic!("{e}"),
    }
    assert_eq!(g.status().unwrap().0, GroupState::Standby);
    let y = card.axis(1).unwrap();
    assert_eq!(y.stop_reason().unwrap(), StopReason::GroupHoming);
    assert!(!y.status().unwrap().homed());
    assert_eq!(y.status().unwrap().state, AxisState::Standstill);
    assert_eq!(
        card.axis(0).unwrap().stop_reason().unwrap(),
        StopReason::HomingFailed
    );
    let z = card.axis(2).unwrap().status().unwrap();
    assert_eq!(
        (z.command_position, z.homed()),
        (0.0, false),
        "Z's stage never started"
    );
    // Nothing moves after it.
    let before: Vec<f64> = (0..3)
        .map(|a| card.axis(a).unwrap().status().unwrap().command_position)
        .collect();
    sim.step(2000);
    let after: Vec<f64> = (0..3)
        .map(|a| card.axis(a).unwrap().status().unwrap().command_position)
        .collect();
    assert_eq!(before, after);
}

/// MC_GroupHalt during group homing ends it as a whole: every member homing halts (stop
/// reason Halt), and the failure names no axis and no homing error.
#[test]
fn a_group_halt_ends_group_homing() {
    let card = card();
    let sim = card.sim().unwrap();
    let g = card.group(0).unwrap();
    let homing = g.home(&[&[0, 1, 2]]).unwrap();
    sim.step(500);
    assert_eq!(g.status().unwrap().0, GroupState::Homing);
    assert_eq!(
        card.axis(0).unwrap().status().unwrap().state,
        AxisState::Homing
    );
    g.halt(1e6, 1e8).unwrap();
    match homing.wait(LONG).unwrap_err() {
        Error::GroupHomingFailed { group, axis, error } => {
            assert_eq!((group, axis, error), (0, None, None))
        }
        e => panic!("{e}"),
    }
    assert_eq!(g.status().unwrap().0, GroupState::Standby);
    for a in 0..3 {
        let ax = card.axis(a).unwrap();
        assert_eq!(ax.stop_reason().unwrap(), StopReason::Halt, "axis {a}");
        assert_eq!(ax.status().unwrap().state, AxisState::Standstill);
    }
}

/// A member's safety stop during group homing stops the others (reason Group) and the group
/// goes to GroupErrorStop; the failure names the member.
#[test]
fn a_safety_stop_of_a_member_stops_the_group_homing() {
    let card = card();
    let sim = card.sim().unwrap();
    let g = card.group(0).unwrap();
    let homing = g.home(&[&[0, 1, 2]]).unwrap();
    sim.step(500);
    sim.with_emulator(|e| e.faults().set_alarm(1, true));
    match homing.wait(LONG).unwrap_err() {
        Error::GroupHomingFailed { group, axis, error } => {
            assert_eq!((group, axis, error), (0, Some(1), None))
        }
        e => panic!("{e}"),
    }
    assert_eq!(g.status().unwrap().0, GroupState::ErrorStop);
    for a in [0, 2] {
        let ax = card.axis(a).unwrap();
        assert_eq!(ax.stop_reason().unwrap(), StopReason::Group, "axis {a}");
    }
    assert_eq!(
        card.axis(1).unwrap().stop_reason().unwrap(),
        StopReason::AmpAlarm
    );
}

fn refused(r: motioncard_sdk::Result<motioncard_sdk::GroupHoming>) -> ErrorKind {
    match r {
        Ok(_) => panic!("accepted"),
        Err(e) => e.kind(),
    }
}

/// Every refusal has its own code, and a refused order moves nothing.
#[test]
fn every_refusal_has_its_code() {
    let card = card();
    let g = card.group(0).unwrap();
    assert_eq!(refused(g.home(&[&[3]])), ErrorKind::HomeAxis);
    assert_eq!(refused(g.home(&[&[8]])), ErrorKind::HomeAxis);
    assert_eq!(refused(g.home(&[&[0], &[1, 0]])), ErrorKind::HomeTwice);
    assert_eq!(refused(g.home(&[&[0, 0]])), ErrorKind::HomeTwice);
    assert_eq!(refused(g.home(&[&[0], &[]])), ErrorKind::HomeStage);
    // No order given and none configured.
    assert_eq!(refused(g.home(&[])), ErrorKind::HomeStage);
    let nine: Vec<&[usize]> = vec![&[0]; 9];
    assert_eq!(refused(g.home(&nine)), ErrorKind::BadConfig);
    // Not at rest: a move runs.
    let _m = g
        .move_linear(
            &[50_000.0, 0.0, 0.0],
            &PathLimits::new(1e4, 1e6, 1e8),
            Default::default(),
        )
        .unwrap();
    card.sim().unwrap().step(10);
    assert_eq!(refused(g.home(&[&[0]])), ErrorKind::InvalidState);
    g.halt(1e6, 1e8).unwrap().wait(LONG).unwrap();
    // Homing already.
    let h = g.home(&[&[0]]).unwrap();
    assert_eq!(refused(g.home(&[&[1]])), ErrorKind::InvalidState);
    h.wait(LONG).unwrap();
    // Disabled.
    g.disable().unwrap();
    assert_eq!(refused(g.home(&[&[0]])), ErrorKind::GroupDisabled);
    // Nothing moved: axis 1 and 2 never homed.
    for a in [1, 2] {
        let st = card.axis(a).unwrap().status().unwrap();
        assert!(!st.homed(), "axis {a}");
    }
}

/// `[group.N] home_order` goes through the configuration file: saved, loaded on a fresh card,
/// read back the same, and the order `Group::home(&[])` takes.
#[test]
fn the_home_order_round_trips_through_the_configuration_file() {
    let a = card();
    let saved = a.save_config().unwrap();
    assert!(!saved.contains("home_order"), "none configured");
    let with = saved.replace("[group.0]\n", "[group.0]\nhome_order = [[2], [0, 1]]\n");
    assert_ne!(with, saved, "{saved}");
    let b = card();
    b.group(0).unwrap().disable().unwrap();
    b.load_config(&with, "a.toml").unwrap();
    let again = b.save_config().unwrap();
    assert!(again.contains("home_order = [[2], [0, 1]]"), "{again}");
    assert_eq!(
        motioncard_sdk::Config::parse(&again, "b.toml").unwrap(),
        motioncard_sdk::Config::parse(&with, "a.toml").unwrap()
    );
    let g = b.group(0).unwrap();
    g.enable().unwrap();
    assert_eq!(g.home(&[]).unwrap().wait(LONG).unwrap(), 2);
    // A bad order in a file is refused by key, and nothing of the file applied.
    let bad = saved.replace("[group.0]\n", "[group.0]\nhome_order = [[2], [2, 1]]\n");
    let c = card();
    c.group(0).unwrap().disable().unwrap();
    let err = c.load_config(&bad, "c.toml").unwrap_err();
    assert_eq!(err.kind(), ErrorKind::ConfigFile, "{err}");
    assert!(err.to_string().contains("home_order"), "{err}");
}

/// `GroupSettings::home_order` goes through `Group::configure` and reads back from the card
/// through `Group::settings`; the configured order is what `Group::home(&[])` runs (Z first:
/// homed before X or Y moved). A bad order is refused with the home order's own codes and the
/// card keeps the configuration it had (axes, tolerance and order).
#[test]
fn the_home_order_round_trips_through_group_settings() {
    let card = card();
    let sim = card.sim().unwrap();
    let g = card.group(0).unwrap();
    g.disable().unwrap();
    assert_eq!(
        g.settings().unwrap().unwrap().home_order,
        Vec::<Vec<usize>>::new()
    );
    let set = GroupSettings {
        home_order: vec![vec![2], vec![0, 1]],
        tolerance: 3.0,
        ..GroupSettings::new(&[0, 1, 2])
    };
    g.configure(&set).unwrap();
    assert_eq!(g.settings().unwrap().unwrap(), set);
    for (order, code) in [
        (vec![vec![2], vec![2, 1]], ErrorKind::HomeTwice),
        (vec![vec![0, 0]], ErrorKind::HomeTwice),
        (vec![vec![3]], ErrorKind::HomeAxis),
        (vec![vec![8]], ErrorKind::HomeAxis),
        (vec![vec![0], vec![]], ErrorKind::HomeStage),
        (vec![vec![0]; 9], ErrorKind::BadConfig),
    ] {
        let bad = GroupSettings {
            home_order: order.clone(),
            tolerance: 5.0,
            ..GroupSettings::new(&[0, 1, 2])
        };
        let err = g.configure(&bad).unwrap_err();
        assert_eq!(err.kind(), code, "{order:?}: {err}");
        assert_eq!(g.settings().unwrap().unwrap(), set, "{order:?}: kept");
    }
    g.enable().unwrap();
    let homing = g.home(&[]).unwrap();
    let mut z_done = false;
    for _ in 0..(60 * RATE) {
        sim.step(10);
        let st: Vec<_> = (0..3)
            .map(|a| card.axis(a).unwrap().status().unwrap())
            .collect();
        if !z_done {
            z_done = st[2].homed() && st[2].state == AxisState::Standstill;
            for xy in st[..2].iter().filter(|_| !z_done) {
                assert_eq!(xy.command_position, 0.0, "X and Y wait for Z");
            }
        }
        if g.status().unwrap().0 == GroupState::Standby {
            break;
        }
    }
    assert!(z_done);
    assert_eq!(g.status().unwrap().0, GroupState::Standby);
    assert_eq!(homing.wait(LONG).unwrap(), 2);
    for a in 0..3 {
        assert!(card.axis(a).unwrap().status().unwrap().homed(), "axis {a}");
    }
}

/// A gantry's master in a stage homes its gantry, squaring included: card axes 0 (master) and
/// 1 (slave, square offset 40 counts) form gantry 0; group 0 is X = the gantry's master and
/// Y = axis 2. Y homes first, then the gantry; the group then stands by with the bridge
/// squared, and both stages' axes homed.
#[test]
fn a_gantry_master_in_a_stage_homes_its_gantry() {
    let card = stepped_card_with(EmuOptions::new(3, RATE));
    let sim = card.sim().unwrap();
    for (a, &edge) in EDGE.iter().enumerate() {
        sim.with_emulator(|e| {
            e.faults().set_switches(
                a,
                Switches::limits(-1e7, 1e7).with_home(HomeSwitch::Above(edge)),
            )
        });
        let ax = card.axis(a).unwrap();
        ax.configure_homing(&HomingSettings {
            method: 19,
            ..HomingSettings::default()
        })
        .unwrap();
        ax.enable().unwrap();
    }
    let gantry = card
        .gantry_at(
            0,
            0,
            &[1],
            &motioncard_sdk::GantryConfig {
                kp: 1e6,
                ki: 0.0,
                skew_limit: 500.0,
                offsets: vec![40.0],
            },
        )
        .unwrap();
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings::new(&[0, 2])).unwrap();
    g.enable().unwrap();
    let homing = g.home(&[&[1], &[0]]).unwrap();
    sim.step(100);
    assert_eq!(g.status().unwrap().0, GroupState::Homing);
    assert_eq!(
        card.axis(0).unwrap().status().unwrap().state,
        AxisState::Standstill
    );
    assert_eq!(homing.wait(LONG).unwrap(), 2);
    assert_eq!(g.status().unwrap().0, GroupState::Standby);
    let st = gantry.status().unwrap();
    assert!(st.squared, "the bridge is squared");
    assert_eq!(st.phase, motioncard_sdk::GantryPhase::Coupled);
    assert!((st.slaves[0].hold - 40.0).abs() < 1e-9);
    for a in 0..3 {
        assert!(card.axis(a).unwrap().status().unwrap().homed(), "axis {a}");
    }
}

/// MC_GroupStop during group homing: the group is in GroupStopping at once, the members halt
/// (stop reason Stop), the failure posts once they are at rest, and the group stays in
/// GroupStopping until released. MC_GroupDisable during group homing ends it at once.
#[test]
fn a_group_stop_holds_the_group_and_a_disable_ends_it() {
    let card = card();
    let sim = card.sim().unwrap();
    let g = card.group(0).unwrap();
    let homing = g.home(&[&[0, 1, 2]]).unwrap();
    sim.step(500);
    g.stop(1e6, 1e8).unwrap();
    assert_eq!(g.status().unwrap().0, GroupState::Stopping);
    match homing.wait(LONG).unwrap_err() {
        Error::GroupHomingFailed { axis, error, .. } => assert_eq!((axis, error), (None, None)),
        e => panic!("{e}"),
    }
    sim.step(100);
    assert_eq!(g.status().unwrap().0, GroupState::Stopping);
    for a in 0..3 {
        assert_eq!(
            card.axis(a).unwrap().stop_reason().unwrap(),
            StopReason::Stop
        );
    }
    g.release_stop().unwrap();
    sim.step(100);
    assert_eq!(g.status().unwrap().0, GroupState::Standby);

    let homing = g.home(&[&[0, 1, 2]]).unwrap();
    sim.step(500);
    g.disable().unwrap();
    assert_eq!(g.status().unwrap().0, GroupState::Disabled);
    assert!(matches!(
        homing.wait(LONG).unwrap_err(),
        Error::GroupHomingFailed { axis: None, .. }
    ));
    sim.step(5000);
    for a in 0..3 {
        let st = card.axis(a).unwrap().status().unwrap();
        assert_eq!(st.state, AxisState::Standstill, "axis {a}");
        assert_eq!(st.command_velocity, 0.0, "axis {a} at rest");
    }
}

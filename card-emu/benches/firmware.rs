//! Cost of one firmware tick with 8 axes moving, including the plant (the whole servo period
//! of the emulated card: command service, 8 profiles, 8 FFPIV loops, 8 motor models, status
//! publication under seqlocks).
//!
//! A second figure has three of the axes in a group running lines (S-curve feed and the
//! post-interpolation filters): the group's tick steps on top.
//!
//! A third has axes 0 and 1 a gantry (layout 1.10: axis 1 follows axis 0 with its yaw loop)
//! and the 7 other axes moving: the gantry's step on top of the 8 servo loops.
//!
//! Layout 1.11: the first figure again with every axis under PID+FF and four biquad filters on
//! its servo output (two notches, a low-pass and a lead/lag): the laws' and the filters' cost.
//!
//! Layout 1.14: group 0 over axes 0–5 running a continuous path of blended lines (the members'
//! `Path<8>`), and the same group as its card's part of a 12-axis path across cards (a
//! `Path<16>` planning all twelve, driving its six): what planning the other card's axes
//! costs a card. Axes 6 and 7 move on their own in both.
//!
//! A fourth is what a new `emu:` host costs card-emu: `Lessor::renew`, a new memfd (its 1 MiB
//! allocated), the window copied into it and mapped over the card's mapping in place, a new
//! eventfd, the old memfd freed. The card's thread waits only for the copy and the remap.
//!
//! `cargo bench -p card-emu --bench firmware`
use card_emu::{EmuOptions, Emulator};
use criterion::{criterion_group, criterion_main, Criterion};
use firmware_proto::ring::{CmdProducer, CMD_RING};
use firmware_proto::{AxisState, Command, Opcode};

fn moving_card() -> (
    Emulator,
    CmdProducer<std::sync::Arc<firmware_proto::window::MappedWindow>>,
) {
    let mut emu = Emulator::create("bench", &EmuOptions::default()).unwrap();
    let mut host = CmdProducer::attach(emu.window().clone(), CMD_RING);
    // A host in command: the session gate refuses power and motion without one.
    let mut attach = Command::new(Opcode::HostAttach, 0);
    attach.flags = 1;
    host.push(&attach).unwrap();
    for a in 0..8u16 {
        host.push(&Command::new(Opcode::PowerOn, a)).unwrap();
    }
    emu.serve();
    (emu, host)
}

/// Start a long move (to the other end of ±1e6 counts) on every axis standing still (a
/// gantry's slave is in SynchronizedMotion: never).
fn keep_moving(
    emu: &mut Emulator,
    host: &mut CmdProducer<std::sync::Arc<firmware_proto::window::MappedWindow>>,
) {
    for a in 0..8u16 {
        let Some(axis) = emu.firmware().axis(a as usize) else {
            continue;
        };
        if axis.state == AxisState::Standstill {
            let target = if axis.reference().pos > 0.0 {
                -1e6
            } else {
                1e6
            };
            let args = [target, 2e5, 2e6, 2e6, 1e8, 1e8, 1e8, 1e8];
            let _ = host.push(&Command::new(Opcode::MoveAbsolute, a).with_args(&args));
        }
    }
    emu.serve();
}

/// The host's heartbeat: the attach armed the watchdog (100 ms, 1,000 ticks), so the bench
/// beats every 256 ticks, outside what matters for the figure.
fn beat(emu: &Emulator) {
    use firmware_proto::Mem;
    let w = emu.window();
    w.write32(
        firmware_proto::layout::HEARTBEAT,
        w.read32(firmware_proto::layout::HEARTBEAT).wrapping_add(1),
    );
}

fn tick(c: &mut Criterion) {
    let (emu, host) = moving_card();
    bench_moving(c, "firmware tick, 8 moving axes + plant", emu, host, "");
}

/// Steps the card, keeping axis 7 moving, under `name`; prints how much of it axis 7 moved.
fn bench_moving(
    c: &mut Criterion,
    name: &str,
    mut emu: Emulator,
    mut host: CmdProducer<std::sync::Arc<firmware_proto::window::MappedWindow>>,
    what: &str,
) {
    keep_moving(&mut emu, &mut host);
    let mut n = 0u64;
    let mut moving_ticks = 0u64;
    // The host drains nothing here, so events pile up; the card keeps going (it counts what it
    // could not post). Drain by resetting the consumer index the way a host would.
    c.bench_function(name, |b| {
        b.iter(|| {
            emu.step();
            n += 1;
            if emu.firmware().axis(7).map(|x| x.state) == Some(AxisState::DiscreteMotion) {
                moving_ticks += 1;
            }
            if n.is_multiple_of(256) {
                beat(&emu);
            }
            if n.is_multiple_of(1024) {
                let w = emu.window();
                use firmware_proto::Mem;
                let head = w.read32(firmware_proto::layout::EVT_HEAD);
                w.write32(firmware_proto::layout::EVT_TAIL, head);
                keep_moving(&mut emu, &mut host);
            }
        })
    });
    eprintln!(
        "axis 7 was in DiscreteMotion on {:.1}% of the {n} ticks measured{what}",
        100.0 * moving_ticks as f64 / n.max(1) as f64
    );
}

/// Every axis under PID+FF (the default tuning) with four filters on its servo output.
fn filtered_card() -> (
    Emulator,
    CmdProducer<std::sync::Arc<firmware_proto::window::MappedWindow>>,
) {
    use firmware_proto::{layout, raw, AxisConfig, AxisPidff};
    let (mut emu, mut host) = moving_card();
    for a in 0..8u16 {
        let w = emu.window();
        layout::AXIS_PIDFF
            .at(a as usize)
            .write(w, &AxisPidff::default());
        let cfg = AxisConfig {
            servo_law: raw::MC_SERVO_PIDFF,
            ..AxisConfig::default()
        };
        layout::AXIS_CONFIG.at(a as usize).write(w, &cfg);
        host.push(&Command::new(Opcode::ApplyAxisConfig, a))
            .unwrap();
        let filters: [[f64; 6]; 4] = [
            [0.0, raw::MC_BIQUAD_NOTCH as f64, 300.0, 0.2, -20.0, 0.0],
            [1.0, raw::MC_BIQUAD_LOWPASS as f64, 2000.0, 0.7, 0.0, 0.0],
            [2.0, raw::MC_BIQUAD_LEAD_LAG as f64, 400.0, 0.0, 0.0, 600.0],
            [3.0, raw::MC_BIQUAD_NOTCH as f64, 1500.0, 0.3, -10.0, 0.0],
        ];
        for f in filters {
            host.push(&Command::new(Opcode::ServoFilterSet, a).with_args(&f))
                .unwrap();
        }
        emu.serve();
    }
    for a in 0..8 {
        let active = layout::SERVO_FILTERS.at(a).read(emu.window()).active;
        assert_eq!(active, 0xF, "axis {a}'s filters");
    }
    (emu, host)
}

fn filtered_tick(c: &mut Criterion) {
    let (emu, host) = filtered_card();
    bench_moving(
        c,
        "firmware tick, 8 moving axes PID+FF + 4 biquads + plant",
        emu,
        host,
        " (PID+FF, 4 biquads)",
    );
}

/// Group 0 over axes 0–2 (S-curve feed, post-interpolation filters), enabled.
fn group_card() -> (
    Emulator,
    CmdProducer<std::sync::Arc<firmware_proto::window::MappedWindow>>,
) {
    use firmware_proto::{layout, raw};
    let (mut emu, mut host) = moving_card();
    let block = raw::mc_group_config {
        naxes: 3,
        axes: [0, 1, 2, 0, 0, 0, 0, 0],
        accdec: raw::MC_ACCDEC_PRE | raw::MC_ACCDEC_POST,
        interpolator: raw::MC_INTERP_EXACT,
        tolerance: 1.0,
        ..Default::default()
    };
    layout::GROUP_CONFIG.at(0).write(emu.window(), &block);
    host.push(&Command::new(Opcode::GroupConfigure, 0)).unwrap();
    host.push(&Command::new(Opcode::GroupEnable, 0)).unwrap();
    emu.serve();
    (emu, host)
}

/// A line of the group to the other end (±2e5 counts on each axis) when it stands by, and
/// long moves on the single axes 3–7 standing still.
fn keep_group_moving(
    emu: &mut Emulator,
    host: &mut CmdProducer<std::sync::Arc<firmware_proto::window::MappedWindow>>,
) {
    use firmware_proto::GroupState;
    if emu.firmware().group(0).map(|g| g.state) == Some(GroupState::Standby) {
        let x = emu.firmware().axis(0).map_or(0.0, |a| a.reference().pos);
        let t = if x > 0.0 { -2e5 } else { 2e5 };
        let args = [2e5, 2e6, 2e6, 1e8, t, -t, 0.5 * t];
        let _ = host.push(&Command::new(Opcode::GroupMoveLinear, 0).with_args(&args));
    }
    keep_axes_moving(emu, host, 3..8);
}

/// Long moves (to the other end of ±1e6 counts) on the axes of `axes` standing still, served.
fn keep_axes_moving(
    emu: &mut Emulator,
    host: &mut CmdProducer<std::sync::Arc<firmware_proto::window::MappedWindow>>,
    axes: std::ops::Range<u16>,
) {
    for a in axes {
        if emu.firmware().axis(a as usize).map(|x| x.state) == Some(AxisState::Standstill) {
            let x = emu
                .firmware()
                .axis(a as usize)
                .map_or(0.0, |x| x.reference().pos);
            let target = if x > 0.0 { -1e6 } else { 1e6 };
            let args = [target, 2e5, 2e6, 2e6, 1e8, 1e8, 1e8, 1e8];
            let _ = host.push(&Command::new(Opcode::MoveAbsolute, a).with_args(&args));
        }
    }
    emu.serve();
}

fn group_tick(c: &mut Criterion) {
    let (mut emu, mut host) = group_card();
    keep_group_moving(&mut emu, &mut host);
    let (mut n, mut moving) = (0u64, 0u64);
    c.bench_function(
        "firmware tick, 3-axis group line + 5 moving axes + plant",
        |b| {
            b.iter(|| {
                emu.step();
                n += 1;
                if emu.firmware().axis(0).map(|x| x.state) == Some(AxisState::SynchronizedMotion) {
                    moving += 1;
                }
                if n.is_multiple_of(256) {
                    beat(&emu);
                    let w = emu.window();
                    use firmware_proto::Mem;
                    let head = w.read32(firmware_proto::layout::EVT_HEAD);
                    w.write32(firmware_proto::layout::EVT_TAIL, head);
                    keep_group_moving(&mut emu, &mut host);
                }
            })
        },
    );
    eprintln!(
        "the group was moving on {:.1}% of the {n} ticks measured",
        100.0 * moving as f64 / n.max(1) as f64
    );
}

fn renew(c: &mut Criterion) {
    let (emu, _host) = moving_card();
    let lessor = emu.lessor();
    c.bench_function(
        "a new lease: window copied and remapped, new eventfd",
        |b| b.iter(|| lessor.renew().unwrap()),
    );
}

/// Axes 0 and 1 a gantry (kp 10⁶/s², skew limit 10⁴ counts), every axis powered.
fn gantry_tick(c: &mut Criterion) {
    let (mut emu, mut host) = moving_card();
    let args = [0.0, 1.0, 1e6, 0.0, 1e4, 1.0, 0.0];
    host.push(&Command::new(Opcode::GantryForm, 0).with_args(&args))
        .unwrap();
    emu.serve();
    assert!(emu.firmware().gantry(0).is_some(), "the gantry is formed");
    keep_moving(&mut emu, &mut host);
    let mut n = 0u64;
    c.bench_function(
        "firmware tick, a gantry of 2 axes + 6 axes moving + plant",
        |b| {
            b.iter(|| {
                emu.step();
                n += 1;
                if n.is_multiple_of(256) {
                    beat(&emu);
                }
                if n.is_multiple_of(1024) {
                    let w = emu.window();
                    use firmware_proto::Mem;
                    let head = w.read32(firmware_proto::layout::EVT_HEAD);
                    w.write32(firmware_proto::layout::EVT_TAIL, head);
                    keep_moving(&mut emu, &mut host);
                }
            })
        },
    );
    let st = emu.firmware().axis(1).map(|x| x.state);
    assert_eq!(
        st,
        Some(AxisState::SynchronizedMotion),
        "the slave followed"
    );
}

/// Group 0 over axes 0–5 (no filters: a path), its path of `dims` dimensions (0: its
/// members'; 12: the first six its axes, the other six another card's), enabled.
fn path_card(
    dims: usize,
) -> (
    Emulator,
    CmdProducer<std::sync::Arc<firmware_proto::window::MappedWindow>>,
) {
    use firmware_proto::{layout, raw};
    let (mut emu, mut host) = moving_card();
    let block = raw::mc_group_config {
        naxes: 6,
        axes: [0, 1, 2, 3, 4, 5, 0, 0],
        accdec: raw::MC_ACCDEC_PRE,
        interpolator: raw::MC_INTERP_EXACT,
        tolerance: 1.0,
        ..Default::default()
    };
    layout::GROUP_CONFIG.at(0).write(emu.window(), &block);
    let mut d = raw::mc_group_dims {
        ndims: dims as u32,
        ..Default::default()
    };
    for k in 0..16 {
        d.axis[k] = if k < 6 { k as i32 } else { raw::MC_DIM_REMOTE };
        (d.vmax[k], d.amax[k], d.jmax[k]) = (1e5, 1e6, 1e8);
    }
    layout::GROUP_DIMS.at(0).write(emu.window(), &d);
    for op in [
        Opcode::GroupConfigure,
        Opcode::GroupEnable,
        Opcode::ApplyGroupDims,
    ] {
        host.push(&Command::new(op, 0)).unwrap();
    }
    emu.serve();
    assert_eq!(emu.firmware().group(0).map(|g| g.path_dims()), Some(dims));
    (emu, host)
}

/// Keep the path going: blended lines back and forth between two points 20,000 counts apart
/// on every dimension (four more whenever fewer than four are queued; with dimensions, each
/// with its `MC_OP_PATH_MORE`, then released), and axes 6 and 7 moving.
fn keep_path_moving(
    emu: &mut Emulator,
    host: &mut CmdProducer<std::sync::Arc<firmware_proto::window::MappedWindow>>,
    dims: usize,
    k: &mut u64,
) {
    use firmware_proto::path_flags;
    let st = emu.firmware().group(0).map(|g| g.status(0)).unwrap();
    if st.path_queued < 4 {
        let flags = (firmware_proto::raw::MC_PATH_BLEND_LOW << path_flags::BUFFER_SHIFT)
            | (firmware_proto::raw::MC_TM_MAX_DEVIATION << path_flags::TRANSITION_SHIFT);
        for _ in 0..4 {
            *k += 1;
            let x = if *k % 2 == 1 { 2e4 } else { 0.0 };
            let mut args = vec![*k as f64, 5e4, 5.0];
            args.extend((0..6).map(|d| x * (1.0 + 0.1 * d as f64)));
            let mut line = Command::new(Opcode::PathLine, 0).with_args(&args);
            line.flags = flags;
            if dims > 8 {
                let more: Vec<f64> = (8..dims).map(|d| x * (1.0 + 0.1 * d as f64)).collect();
                let mut l = line;
                l.args[9] = x * 1.6;
                l.args[10] = x * 1.7;
                host.push_all(&[l, Command::new(Opcode::PathMore, 0).with_args(&more)])
                    .unwrap();
            } else {
                host.push(&line).unwrap();
            }
        }
        if dims > 0 {
            host.push(&Command::new(Opcode::PathRelease, 0).with_args(&[4.0]))
                .unwrap();
        }
    }
    keep_axes_moving(emu, host, 6..8);
}

fn path_tick(c: &mut Criterion) {
    for (dims, name) in [
        (0, "firmware tick, 6-axis path + 2 moving axes + plant"),
        (
            12,
            "firmware tick, 6 axes of a 12-axis path across cards + 2 moving axes + plant",
        ),
    ] {
        let (mut emu, mut host) = path_card(dims);
        let (mut n, mut k, mut moving) = (0u64, 0u64, 0u64);
        keep_path_moving(&mut emu, &mut host, dims, &mut k);
        c.bench_function(name, |b| {
            b.iter(|| {
                emu.step();
                n += 1;
                if emu.firmware().axis(0).map(|x| x.state) == Some(AxisState::SynchronizedMotion) {
                    moving += 1;
                }
                if n.is_multiple_of(256) {
                    beat(&emu);
                    let w = emu.window();
                    use firmware_proto::Mem;
                    let head = w.read32(firmware_proto::layout::EVT_HEAD);
                    w.write32(firmware_proto::layout::EVT_TAIL, head);
                    keep_path_moving(&mut emu, &mut host, dims, &mut k);
                }
            })
        });
        eprintln!(
            "the path ran on {:.1}% of the {n} ticks measured, {k} segments",
            100.0 * moving as f64 / n.max(1) as f64
        );
    }
}

criterion_group!(
    benches,
    tick,
    filtered_tick,
    group_tick,
    path_tick,
    gantry_tick,
    renew
);
criterion_main!(benches);

//! Cost of one firmware tick with 8 axes moving, including the plant (the whole servo period
//! of the emulated card: command service, 8 profiles, 8 FFPIV loops, 8 motor models, status
//! publication under seqlocks).
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
    for a in 0..8u16 {
        host.push(&Command::new(Opcode::PowerOn, a)).unwrap();
    }
    emu.serve();
    (emu, host)
}

/// Start a long move (to the other end of ±1e6 counts) on every axis standing still.
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

fn tick(c: &mut Criterion) {
    let (mut emu, mut host) = moving_card();
    keep_moving(&mut emu, &mut host);
    let mut n = 0u64;
    let mut moving_ticks = 0u64;
    // The host drains nothing here, so events pile up; the card keeps going (it counts what it
    // could not post). Drain by resetting the consumer index the way a host would.
    c.bench_function("firmware tick, 8 moving axes + plant", |b| {
        b.iter(|| {
            emu.step();
            n += 1;
            if emu.firmware().axis(7).map(|x| x.state) == Some(AxisState::DiscreteMotion) {
                moving_ticks += 1;
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
        "axis 7 was in DiscreteMotion on {:.1}% of the {n} ticks measured",
        100.0 * moving_ticks as f64 / n.max(1) as f64
    );
}

criterion_group!(benches, tick);
criterion_main!(benches);

//! `card-emu`: serve an emulated motion card to other processes as `emu:NAME`.
use card_emu::{server::Server, Clock, EmuOptions, Emulator, Runner};
use clap::Parser;
use std::os::fd::AsFd;

/// Serve an emulated motion card. Hosts open it with the card URI `emu:NAME`.
#[derive(Parser, Debug)]
#[command(version, about)]
struct Args {
    /// The card's name (hosts open `emu:NAME`).
    #[arg(long, default_value = "card0")]
    name: String,
    /// Axes on the card (1..=8).
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u8).range(1..=8))]
    axes: u8,
    /// Servo rate in Hz (1000..=20000).
    #[arg(long, default_value_t = 10_000, value_parser = clap::value_parser!(u32).range(1000..=20000))]
    servo_rate: u32,
    /// realtime (paced to the servo rate) or free-running (as fast as possible).
    #[arg(long, default_value = "realtime")]
    clock: Clock,
    /// Busy-poll the command ring between ticks instead of sleeping (lowest latency, one core).
    #[arg(long)]
    busy_poll: bool,
}

fn main() -> std::process::ExitCode {
    let args = Args::parse();
    if args.clock == Clock::Stepped {
        eprintln!("card-emu: a served card needs a running clock (realtime or free-running)");
        return std::process::ExitCode::from(2);
    }
    let opts = EmuOptions {
        axes: args.axes as usize,
        servo_rate_hz: args.servo_rate,
        ..EmuOptions::default()
    };
    let run = || -> std::io::Result<(Server, Runner)> {
        let emu = Emulator::create(&args.name, &opts)?;
        let window = emu.window().fd().try_clone_to_owned()?;
        let irq = emu.irq_fd().as_fd().try_clone_to_owned()?;
        let server = Server::start(&args.name, window, irq).map_err(|e| {
            if e.kind() == std::io::ErrorKind::AddrInUse {
                std::io::Error::new(
                    e.kind(),
                    format!("a card named '{}' is already being served", args.name),
                )
            } else {
                e
            }
        })?;
        let runner = Runner::spawn(emu, args.clock, args.busy_poll)?;
        Ok((server, runner))
    };
    match run() {
        Ok((server, _runner)) => {
            println!(
                "card-emu: serving emu:{} ({} axes, {} Hz, {:?} clock{})",
                server.name(),
                opts.axes,
                opts.servo_rate_hz,
                args.clock,
                if args.busy_poll { ", busy-poll" } else { "" }
            );
            loop {
                std::thread::park();
            }
        }
        Err(e) => {
            eprintln!("card-emu: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}

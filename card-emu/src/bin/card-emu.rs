//! `card-emu`: serve an emulated motion card to other processes as `emu:NAME`.
use card_emu::emu::bus;
use card_emu::emu::server::{resolve_group, PeerPolicy, ServeOptions, Server};
use card_emu::{Clock, EmuOptions, Emulator, Runner};
use clap::Parser;

/// Serve an emulated motion card. Hosts open it with the card URI `emu:NAME`.
///
/// Access: the card is served on the abstract Unix socket @motioncard/NAME, which has no file
/// permissions, so card-emu checks who connects (the kernel's SO_PEERCRED/SO_PEERGROUPS
/// credentials of the connecting process). It admits its own user (effective uid), root, every
/// uid given with --allow-uid, and every process whose effective gid or one of whose
/// supplementary groups is given with --allow-group. Any other process is refused: its
/// `Card::open` fails with PermissionDenied (C: MC_ERR_PERMISSION_DENIED) and card-emu logs
/// each refused uid once on stderr. One admitted host at a time holds the card (the others get
/// "busy"), from its greeting (within 2 s of connecting, or the connection is dropped) until it
/// closes the connection. Each host gets a window of its own: what a past host writes into the
/// window it kept reaches no later host. This keeps other SDK hosts out, not a process of the
/// same user (or root) that maps the current window through /proc/PID/fd.
#[derive(Parser, Debug)]
#[command(version, about, long_about)]
struct Args {
    /// The card's name (hosts open `emu:NAME`).
    #[arg(long, default_value = "card0")]
    name: String,
    /// The board's serial number, as hosts read it (`mcctl list`; 0: none).
    #[arg(long, default_value_t = 0)]
    serial: u64,
    /// Axes on the card (1..=8).
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u8).range(1..=8))]
    axes: u8,
    /// Servo rate in Hz (1000..=20000).
    #[arg(long, default_value_t = 10_000, value_parser = clap::value_parser!(u32).range(1000..=20000))]
    servo_rate: u32,
    /// The watchdog timeout at boot in ms (until a host sets its own; default 100): a longer
    /// one to debug a host under gdb or valgrind (the watchdog stays armed).
    #[arg(long, value_name = "MS", value_parser = clap::value_parser!(u32).range(1..=3_600_000))]
    watchdog_timeout_ms: Option<u32>,
    /// realtime (paced to the servo rate) or free-running (as fast as possible).
    #[arg(long, default_value = "realtime")]
    clock: Clock,
    /// Run on the servo clock of the card-emu serving NAME (a sync cable between boards):
    /// this card takes its tick count and runs one tick per tick of it. Without it, this card
    /// serves its own clock to followers on @motioncard-bus/NAME (same access rules as hosts).
    #[arg(long, value_name = "NAME")]
    sync_from: Option<String>,
    /// Busy-poll the command ring between ticks instead of sleeping (lowest latency, one core).
    #[arg(long)]
    busy_poll: bool,
    /// Also admit hosts running as this user id (repeatable). Its own user and root are always
    /// admitted.
    #[arg(long = "allow-uid", value_name = "UID")]
    allow_uid: Vec<u32>,
    /// Also admit hosts in this group, by name or gid (repeatable): a process whose effective
    /// gid or one of whose supplementary groups it is.
    #[arg(long = "allow-group", value_name = "GROUP", value_parser = resolve_group)]
    allow_group: Vec<u32>,
}

/// Join the bus of `master`, waiting up to 5 s for it to serve (started at the same time).
fn connect_bus(master: &str) -> std::io::Result<bus::BusLink> {
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(5);
    loop {
        match bus::connect(master) {
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::ConnectionRefused | std::io::ErrorKind::NotFound
                ) && std::time::Instant::now() < deadline =>
            {
                std::thread::sleep(std::time::Duration::from_millis(5))
            }
            r => return r,
        }
    }
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
        watchdog_timeout_us: args
            .watchdog_timeout_ms
            .map_or(EmuOptions::default().watchdog_timeout_us, |ms| ms * 1000),
        serial: args.serial,
        ..EmuOptions::default()
    };
    let run = || -> std::io::Result<(Server, Runner, PeerPolicy)> {
        let mut emu = Emulator::create(&args.name, &opts)?;
        let policy = args
            .allow_uid
            .iter()
            .fold(PeerPolicy::this_user(), |p, &u| p.allow_uid(u));
        let policy = args.allow_group.iter().fold(policy, |p, &g| p.allow_gid(g));
        // A follower joins before any host can attach (only a card no host commands joins).
        if let Some(master) = &args.sync_from {
            emu.follow_bus(connect_bus(master)?)?;
        }
        let serve = ServeOptions::new(policy.clone());
        let server = Server::start_with(&args.name, emu.lessor(), serve).map_err(|e| {
            if e.kind() == std::io::ErrorKind::AddrInUse {
                std::io::Error::new(
                    e.kind(),
                    format!("a card named '{}' is already being served", args.name),
                )
            } else {
                e
            }
        })?;
        // After the host socket, whose bind says whether the name is taken.
        if args.sync_from.is_none() {
            bus::serve(emu.lead_bus()?, policy.clone())?;
        }
        let runner = Runner::spawn(emu, args.clock, args.busy_poll)?;
        Ok((server, runner, policy))
    };
    match run() {
        Ok((server, _runner, policy)) => {
            println!(
                "card-emu: serving emu:{} ({} axes, {} Hz, {:?} clock{}{}) to {policy}",
                server.name(),
                opts.axes,
                opts.servo_rate_hz,
                args.clock,
                if args.busy_poll { ", busy-poll" } else { "" },
                args.sync_from
                    .as_ref()
                    .map_or(String::new(), |m| format!(", on the sync bus of {m}"))
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

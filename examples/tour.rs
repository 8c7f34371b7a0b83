//! The tour: enable 8 axes, run S-curve moves with different limits on each, and print what
//! the card measured against what was asked.
//!
//! ```text
//! cargo run --release --example tour                       # the built-in emulated card
//! cargo run --release --example tour -- --card emu:NAME    # a card-emu process
//! ```
use clap::Parser;
use motioncard_sdk::{Card, Error, MoveLimits};
use std::time::Duration;

/// Run point-to-point S-curve moves on every axis of a card and report them.
#[derive(Parser)]
struct Args {
    /// Card URI: sim, emu:NAME, uio:/dev/uioN or pci:DDDD:BB:DD.F.
    #[arg(long, default_value = "sim")]
    card: String,
}

/// One move per axis: (what it shows, distance in counts, limits).
fn plan() -> Vec<(&'static str, f64, MoveLimits)> {
    vec![
        (
            "long, cruises",
            400_000.0,
            MoveLimits::new(200_000.0, 2e6, 1e8),
        ),
        (
            "long, asymmetric acc/dec",
            -300_000.0,
            MoveLimits::new(150_000.0, 3e6, 1e8)
                .deceleration(1e6)
                .decel_jerk(2e7),
        ),
        (
            "short, no cruise",
            20_000.0,
            MoveLimits::new(400_000.0, 2e6, 1e8),
        ),
        (
            "tiny, acc limit never hit",
            500.0,
            MoveLimits::new(100_000.0, 4e6, 5e7),
        ),
        (
            "soft jerk",
            100_000.0,
            MoveLimits::new(120_000.0, 1.5e6, 1e7),
        ),
        (
            "stiff jerk",
            -150_000.0,
            MoveLimits::new(250_000.0, 2.5e6, 5e8),
        ),
        (
            "slow and long",
            50_000.0,
            MoveLimits::new(25_000.0, 2e5, 2e6),
        ),
        (
            "quick decel",
            250_000.0,
            MoveLimits::new(300_000.0, 1e6, 5e7).deceleration(4e6),
        ),
    ]
}

fn main() -> Result<(), Error> {
    let args = Args::parse();
    let card = Card::open(&args.card)?;
    let info = card.info();
    println!(
        "card {}: firmware {}.{}.{}, layout {}.{}, {} axes, servo {} Hz",
        args.card,
        info.firmware_version >> 16,
        (info.firmware_version >> 8) & 0xff,
        info.firmware_version & 0xff,
        info.layout.0,
        info.layout.1,
        info.axes,
        info.servo_rate_hz
    );
    let moves: Vec<_> = plan().into_iter().take(info.axes).collect();
    let axes = card.axes();
    let mut motions = Vec::new();
    for (axis, (_, dist, lim)) in axes.iter().zip(&moves) {
        axis.enable()?;
        let start = axis.status()?.command_position;
        motions.push((start + dist, axis.move_relative(*dist, lim)?));
    }
    println!();
    println!(
        "{:<4} {:<26} {:>10} {:>10} {:>8} {:>8}  {:>19}  {:>19}  {:>19}  {:>19}  {:>7}",
        "axis",
        "move",
        "target",
        "final",
        "plan s",
        "exec s",
        "peak v / limit",
        "peak a / limit",
        "peak d / limit",
        "peak |j| / max j",
        "|ferr|"
    );
    let mut worst_miss: f64 = 0.0;
    for ((axis, (what, _, lim)), (target, motion)) in axes.iter().zip(&moves).zip(&motions) {
        let reached = motion.wait(Duration::from_secs(30))?;
        let s = axis.status()?.raw;
        let jmax = lim.jerk.iter().cloned().fold(0.0, f64::max);
        worst_miss = worst_miss.max((reached - target).abs());
        println!(
            "{:<4} {:<26} {:>10.0} {:>10.0} {:>8.4} {:>8.4}  {:>9.0}/{:<9.0}  {:>9.3e}/{:<9.3e}  {:>9.3e}/{:<9.3e}  {:>9.3e}/{:<9.3e}  {:>7.2}",
            axis.index(),
            what,
            target,
            reached,
            s.planned_time,
            s.move_time,
            s.peak_vel,
            lim.velocity,
            s.peak_acc,
            lim.acceleration,
            s.peak_dec,
            lim.deceleration,
            s.peak_jerk,
            jmax,
            s.max_ferr
        );
    }
    println!();
    println!("positions and following errors in encoder counts; exec = start to in-position (motion done)");
    println!(
        "peak |j| is the largest jerk of the move, against the largest of its four phase jerks"
    );
    println!("worst |final - target| = {worst_miss} counts");
    for axis in &axes {
        axis.disable()?;
    }
    Ok(())
}

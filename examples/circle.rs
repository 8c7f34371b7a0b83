//! A circle on the emulated card: S-curve feed along the path, then per-axis filters.
//! Prints a summary and writes SVG plots of the path and of the velocity profiles.
//!
//! `cargo run --release --example circle`
use clap::Parser;
use mcctl::plot::{lines, Series};
use motioncard_sdk::{
    AccDec, ArcSpec, Card, Clock, EmuOptions, GroupSettings, GroupState, MoveOptions, PathLimits,
    Plane, SimOptions,
};
use std::path::PathBuf;
use std::time::Duration;

/// Run a full circle on a 2-axis group and plot it.
#[derive(Parser)]
struct Args {
    /// Radius, counts.
    #[arg(long, default_value_t = 20_000.0)]
    radius: f64,
    /// Feed, counts/s.
    #[arg(long, default_value_t = 60_000.0)]
    feed: f64,
    /// Acc/dec: pre (S-curve along the path), post (filters), both.
    #[arg(long, default_value = "both")]
    accdec: String,
    /// Directory for the SVG plots.
    #[arg(long, default_value = "target/plots")]
    out: PathBuf,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a = Args::parse();
    let accdec = match a.accdec.as_str() {
        "pre" => AccDec::Pre,
        "post" => AccDec::Post,
        "both" => AccDec::Both,
        other => return Err(format!("--accdec {other}: expected pre, post or both").into()),
    };
    // Stepped: every tick is traced, and the result is the same on any machine.
    let card = Card::open_sim(SimOptions {
        clock: Clock::Stepped,
        emu: EmuOptions::new(2, 10_000),
    })?;
    let sim = card.sim().expect("stepped sim");
    let (x, y) = (card.axis(0)?, card.axis(1)?);
    x.enable()?;
    y.enable()?;
    let g = card.group(0)?;
    g.configure(&GroupSettings {
        accdec,
        ..GroupSettings::new(&[0, 1])
    })?;
    g.enable()?;
    let r = a.radius;
    // From the origin, a full circle around (r, 0).
    let mv = g.move_circular(
        &ArcSpec::Centre {
            end: [0.0, 0.0],
            centre: [r, 0.0],
            ccw: true,
        },
        Plane::XY,
        &[],
        &PathLimits::new(a.feed, 4.0 * a.feed, 100.0 * a.feed),
        MoveOptions::default(),
    )?;
    let (mut cmd_path, mut act_path, mut vx, mut vy, mut feed) =
        (vec![], vec![], vec![], vec![], vec![]);
    let (mut worst_cmd, mut worst_act, mut worst_ferr): (f64, f64, f64) = (0.0, 0.0, 0.0);
    while g.status()?.0 == GroupState::Moving {
        sim.step(1);
        let (sx, sy) = (x.status()?.raw, y.status()?.raw);
        let t = sim.time();
        cmd_path.push((sx.cmd_pos, sy.cmd_pos));
        act_path.push((sx.act_pos, sy.act_pos));
        vx.push((t, sx.cmd_vel));
        vy.push((t, sy.cmd_vel));
        feed.push((t, sx.cmd_vel.hypot(sy.cmd_vel)));
        worst_cmd = worst_cmd.max(((sx.cmd_pos - r).hypot(sy.cmd_pos) - r).abs());
        worst_act = worst_act.max(((sx.act_pos - r).hypot(sy.act_pos) - r).abs());
        worst_ferr = worst_ferr.max(sx.ferr.hypot(sy.ferr));
    }
    mv.wait(Duration::from_secs(10))?;
    println!(
        "circle R = {r} counts at {} counts/s, acc/dec {:?}",
        a.feed, accdec
    );
    println!("  time                       {:.4} s", sim.time());
    println!(
        "  peak tangential velocity   {:.1} counts/s",
        feed.iter().map(|p| p.1).fold(0.0, f64::max)
    );
    println!("  max |radius error|, command {worst_cmd:.3} counts (the post filters shrink a circle: Kim eq 28)");
    println!("  max |radius error|, encoder {worst_act:.3} counts");
    println!("  max |following error|       {worst_ferr:.3} counts");
    println!(
        "  final position              ({}, {})",
        x.status()?.actual_position,
        y.status()?.actual_position
    );
    lines(
        &a.out.join("circle_path.svg"),
        "circle: commanded and actual path",
        "x [counts]",
        "y [counts]",
        &[
            Series {
                name: "command",
                points: cmd_path,
            },
            Series {
                name: "encoder",
                points: act_path,
            },
        ],
        true,
    )?;
    lines(
        &a.out.join("circle_velocity.svg"),
        "circle: velocity profiles",
        "t [s]",
        "counts/s",
        &[
            Series {
                name: "vx",
                points: vx,
            },
            Series {
                name: "vy",
                points: vy,
            },
            Series {
                name: "feed",
                points: feed,
            },
        ],
        false,
    )?;
    println!("plots written to {}", a.out.display());
    Ok(())
}

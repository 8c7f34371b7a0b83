//! Yeh's die bonder on the emulated card: a NURBS path with two sharp corners, interpolated on
//! the card at 1 ms with PD+ axes, with and without the saturation-aware feed. Prints the drive
//! outputs against Umax, the contour error and the feed fluctuation; writes SVG plots of the
//! feed and of u against the bounds (like Yeh Fig 6 and 7).
//!
//! `cargo run --release --example nurbs`
use clap::Parser;
use motioncard::papers::{yeh_die_bonder, DIE_BONDER_FEED};
use motioncard::plot::{lines, Series};
use std::path::PathBuf;

/// Run the die-bonder path with and without the saturation-aware feed.
#[derive(Parser)]
struct Args {
    /// Directory for the SVG plots.
    #[arg(long, default_value = "target/plots")]
    out: PathBuf,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let with = yeh_die_bonder(true)?;
    let without = yeh_die_bonder(false)?;
    println!("Yeh die bonder (Table 1 plant and PD+ gains, 1 ms), feed {DIE_BONDER_FEED} counts/s, chord tolerance 1 count");
    println!(
        "drive output u in volts (1 DU = 10 V, Umax = {} V); positions in counts",
        with.umax
    );
    println!();
    println!("| feed                   | max |u| X | max |u| Y | Umax | ticks over Umax | max contour error | feed fluctuation | time s |");
    println!("|------------------------|-----------|-----------|------|-----------------|-------------------|------------------|--------|");
    for (name, r) in [
        ("saturation-aware", &with),
        ("plain (no awareness)", &without),
    ] {
        let fluct = format!("{:.1e}", r.feed_fluctuation);
        println!(
            "| {:<22} | {:>9.3} | {:>9.3} | {:>4} | {:>15} | {:>17.2} | {:>16} | {:>6.3} |",
            name, r.max_u[0], r.max_u[1], r.umax, r.ticks_over, r.contour, fluct, r.time
        );
    }
    println!();
    println!("without the saturation-aware feed the PD+ law asks for more than the drive can give; the DAC clips at ±{} V and the axes fall behind the path", with.umax);
    let feed = |r: &motioncard::papers::DieBonder| {
        r.feed
            .iter()
            .map(|p| (p.0 * 1e3, p.1 / 1e3))
            .collect::<Vec<_>>()
    };
    lines(
        &args.out.join("nurbs_feed.svg"),
        "die bonder: feed along the path",
        "t [ms]",
        "feed [counts/ms]",
        &[
            Series {
                name: "saturation-aware",
                points: feed(&with),
            },
            Series {
                name: "plain",
                points: feed(&without),
            },
        ],
        false,
    )?;
    for (axis, name) in [(0usize, "x"), (1, "y")] {
        let u = |r: &motioncard::papers::DieBonder| {
            r.u.iter()
                .map(|p| (p.0 * 1e3, if axis == 0 { p.1 } else { p.2 }))
                .collect::<Vec<_>>()
        };
        let t_end = with.time.max(without.time) * 1e3;
        let bound = |v: f64| vec![(0.0, v), (t_end, v)];
        let mut plain = u(&without);
        // Keep the plot readable: the plain run's requests go far beyond the bounds.
        for p in plain.iter_mut() {
            p.1 = p.1.clamp(-3.0 * with.umax, 3.0 * with.umax);
        }
        lines(
            &args.out.join(format!("nurbs_u_{name}.svg")),
            &format!("die bonder: drive output u of axis {name} (plain run clipped at ±3·Umax for display)"),
            "t [ms]",
            "u [V]",
            &[Series { name: "saturation-aware", points: u(&with) }, Series { name: "plain", points: plain }, Series { name: "+Umax", points: bound(with.umax) }, Series { name: "-Umax", points: bound(-with.umax) }],
            false,
        )?;
    }
    let path = |r: &motioncard::papers::DieBonder| r.path.iter().map(|p| p.1).collect::<Vec<_>>();
    let cmd: Vec<(f64, f64)> = with.path.iter().map(|p| p.0).collect();
    lines(
        &args.out.join("nurbs_path.svg"),
        "die bonder: path",
        "x [counts]",
        "y [counts]",
        &[
            Series {
                name: "command",
                points: cmd,
            },
            Series {
                name: "actual, saturation-aware",
                points: path(&with),
            },
            Series {
                name: "actual, plain",
                points: path(&without),
            },
        ],
        true,
    )?;
    println!("plots written to {}", args.out.display());
    Ok(())
}

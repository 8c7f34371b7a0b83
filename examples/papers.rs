//! The papers' experiments on the emulated card, as tables (and SVG plots in `--out`).
//!
//! `cargo run --release --example papers`
use clap::Parser;
use motioncard::papers::{
    kim_fig7, kim_sync_ptp, radial_error, shin_comparison, shin_corner, SyncShape, RADIAL_CASES,
    SYNC_TARGETS,
};
use motioncard::plot::{lines, Series};
use motioncard::{FilterKind, Interpolator, MotorParams};
use std::path::PathBuf;

/// Reproduce Kim 1991 Fig 7, eq 10–14 and §4, and Shin's corner test, on the emulated card.
#[derive(Parser)]
struct Args {
    /// Directory for the SVG plots.
    #[arg(long, default_value = "target/plots")]
    out: PathBuf,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();

    println!("Kim 1991 Fig 7: 81,920 pulses on X at 10 rev/s, 100 ms acc/dec, 1 kHz");
    println!(
        "| filter      | final command | final encoder | ramp to 99% feed | snap correction |"
    );
    println!(
        "|-------------|---------------|---------------|------------------|-----------------|"
    );
    let mut pos = Vec::new();
    let mut vel = Vec::new();
    for kind in [FilterKind::Linear, FilterKind::Exponential] {
        let r = kim_fig7(kind)?;
        let feed = motioncard::papers::KIM_FIG7_FEED;
        let ramp = r
            .vel
            .iter()
            .position(|v| *v >= 0.99 * feed)
            .map_or(f64::NAN, |k| r.t[k] - r.t[0]);
        println!(
            "| {:<11} | {:>13} | {:>13} | {:>14.3} s | {:>15.1e} |",
            format!("{kind:?}"),
            r.final_cmd,
            r.final_act,
            ramp,
            r.snap
        );
        let name = if kind == FilterKind::Linear {
            "linear"
        } else {
            "exponential"
        };
        pos.push(Series {
            name,
            points: r.t.iter().copied().zip(r.pos.iter().copied()).collect(),
        });
        vel.push(Series {
            name,
            points: r.t.iter().copied().zip(r.vel.iter().copied()).collect(),
        });
    }
    lines(
        &args.out.join("kim_fig7_position.svg"),
        "Kim Fig 7: position command",
        "t [s]",
        "pulses",
        &pos,
        false,
    )?;
    lines(
        &args.out.join("kim_fig7_velocity.svg"),
        "Kim Fig 7: velocity command",
        "t [s]",
        "pulses/s",
        &vel,
        false,
    )?;

    println!();
    println!(
        "Kim 1991 eq 10–14: synchronised point-to-point, axes x y z w to {SYNC_TARGETS:?} counts, 1 kHz"
    );
    println!("| shape                            | start tick (x y z w) | at rest on target from tick (x y z w) | time s | peak velocity x / z | snap correction |");
    println!("|----------------------------------|----------------------|---------------------------------------|--------|---------------------|-----------------|");
    for (name, shape) in [
        ("S-curve, common limits", SyncShape::SCurve),
        ("S-curve, z slow (own limits)", SyncShape::SCurveOwnLimits),
        ("linear filter 50 ms", SyncShape::Filter(FilterKind::Linear)),
        (
            "exponential filter 50 ms",
            SyncShape::Filter(FilterKind::Exponential),
        ),
        ("bell filter 50 ms", SyncShape::Filter(FilterKind::Bell)),
    ] {
        let r = kim_sync_ptp(shape)?;
        println!(
            "| {:<32} | {:>20} | {:>37} | {:>6.3} | {:>9.1} / {:>7.1} | {:>15.1e} |",
            name,
            format!("{:?}", r.start),
            format!("{:?}", r.end),
            r.duration(),
            r.peak_vel[0],
            r.peak_vel[2],
            r.snap
        );
    }

    println!();
    println!("Kim 1991 §4: steady-state radial error of a circle through the acc/dec filter, measured on the card");
    println!("| filter      | interpolator  |      R |    Ω | rate Hz |   τ ms |  ΔR measured |   ΔR formula | rel. diff |");
    println!("|-------------|---------------|--------|------|---------|--------|--------------|--------------|-----------|");
    let mut worst: f64 = 0.0;
    for kind in [FilterKind::Linear, FilterKind::Exponential] {
        for &(r, omega, rate, tau) in &RADIAL_CASES {
            for interp in [Interpolator::Exact, Interpolator::ReferenceWord] {
                let (m, f) = radial_error(kind, r, omega, rate, tau, interp)?;
                worst = worst.max((m - f).abs() / f);
                println!("| {:<11} | {:<13} | {:>6} | {:>4} | {:>7} | {:>6.1} | {:>12.6} | {:>12.6} | {:>9.1e} |", format!("{kind:?}"), format!("{interp:?}"), r, omega, rate, tau * 1e3, m, f, (m - f).abs() / f);
            }
        }
    }
    println!("formula: linear = corrected eq 28, exponential = eq 32; worst relative difference {worst:.1e}");

    println!();
    println!("Shin: 90° corner at 1 m/min (1 count = 1 µm), errors near the corner in µm");
    println!("| plant                     | filter      |   τ ms | command rounding | table tracking | table vs programmed corner |");
    println!("|---------------------------|-------------|--------|------------------|----------------|----------------------------|");
    let plants = [
        ("rigid (default)", MotorParams::default_servo()),
        (
            "two-mass, 33 Hz resonance",
            MotorParams::machine_table(33.0),
        ),
    ];
    let mut paths = Vec::new();
    let mut two_mass = Vec::new();
    for (pname, plant) in plants {
        for kind in [FilterKind::Linear, FilterKind::Exponential] {
            for tau in [0.015, 0.030] {
                let c = shin_corner(plant, kind, tau)?;
                println!(
                    "| {:<25} | {:<11} | {:>6.0} | {:>16.1} | {:>14.1} | {:>26.1} |",
                    pname,
                    format!("{kind:?}"),
                    tau * 1e3,
                    c.command_rounding,
                    c.tracking,
                    c.total
                );
                if pname.starts_with("two-mass") {
                    two_mass.push(c.clone());
                    if kind == FilterKind::Linear {
                        paths.push((tau, c));
                    }
                }
            }
        }
    }
    println!();
    println!("Against Shin (Fig 12, ± corner tracking error), two-mass plant:");
    let runs = [
        (two_mass[0].clone(), two_mass[1].clone()),
        (two_mass[2].clone(), two_mass[3].clone()),
    ];
    print!("{}", shin_comparison(&runs));
    let mut series = Vec::new();
    let names = [
        "command, 15 ms",
        "table, 15 ms",
        "command, 30 ms",
        "table, 30 ms",
    ];
    for (i, (_, c)) in paths.iter().enumerate() {
        series.push(Series {
            name: names[2 * i],
            points: c.command.clone(),
        });
        series.push(Series {
            name: names[2 * i + 1],
            points: c.table.clone(),
        });
    }
    lines(
        &args.out.join("shin_corner.svg"),
        "Shin corner, linear filter, two-mass table",
        "x [µm]",
        "y [µm]",
        &series,
        true,
    )?;
    println!();
    println!("plots written to {}", args.out.display());
    Ok(())
}

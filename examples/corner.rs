//! Shin's corner test on the emulated card: a 90° corner at 1 m/min through linear and
//! exponential filters of 15 and 30 ms, on a rigid axis and on Shin's two-mass table (as
//! fitted, `papers::SHIN_FIT`, or with another resonance and damping). Prints the corner
//! errors of all four filter/time-constant runs next to Shin's, and writes SVG plots of the
//! paths and velocities. The fit, the prediction and the why: `--example papers -- --only
//! shin`.
//!
//! `cargo run --release --example corner`
use card_emu::servo::ffpiv::FfpivGains;
use clap::Parser;
use mcctl::papers::{shin_corner, ShinMachine, SHIN_FIG12, SHIN_FIT};
use mcctl::plot::{lines, Series};
use motioncard_sdk::{FilterKind, MotorParams};
use std::path::PathBuf;

/// Run Shin's corner test.
#[derive(Parser)]
struct Args {
    /// Resonance of the table's coupling, Hz.
    #[arg(long, default_value_t = SHIN_FIT.resonance_hz)]
    resonance: f64,
    /// Damping ratio of the table's coupling.
    #[arg(long, default_value_t = SHIN_FIT.zeta)]
    zeta: f64,
    /// Directory for the SVG plots.
    #[arg(long, default_value = "target/plots")]
    out: PathBuf,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a = Args::parse();
    let table = ShinMachine {
        resonance_hz: a.resonance,
        zeta: a.zeta,
        ..SHIN_FIT
    };
    println!(
        "90° corner at 1 m/min; table with a {} Hz coupling resonance, ζ {}; errors in µm",
        a.resonance, a.zeta
    );
    println!(
        "| filter      | τ ms | command rounding | contour error | table vs programmed corner |"
    );
    println!(
        "|-------------|------|------------------|---------------|----------------------------|"
    );
    let mut paths = Vec::new();
    for kind in [FilterKind::Linear, FilterKind::Exponential] {
        for tau in [0.015, 0.030] {
            let c = table.corner(kind, tau)?;
            println!(
                "| {:<11} | {:>4.0} | {:>16.1} | {:>13.1} | {:>26.1} |",
                format!("{kind:?}"),
                tau * 1e3,
                c.command_rounding,
                c.contour,
                c.total
            );
            paths.push((format!("{kind:?} {:.0} ms", tau * 1e3), c));
        }
    }
    println!();
    println!("Against Shin (Fig 12, ± corner tracking error):");
    for (i, (kind, s15, s30)) in SHIN_FIG12.iter().enumerate() {
        let (short, long) = (&paths[2 * i].1, &paths[2 * i + 1].1);
        println!(
            "{kind:?}: Shin ±{s15} → ±{s30} µm ({:.1}×), here {:.1} → {:.1} µm ({:.2}×)",
            s15 / s30,
            short.contour,
            long.contour,
            short.contour / long.contour
        );
    }
    println!();
    let rigid = shin_corner(
        MotorParams::default_servo(),
        FfpivGains::default(),
        FilterKind::Linear,
        0.015,
    )?;
    println!("rigid axis, linear 15 ms: contour error {:.1} µm — without a resonance there is nothing to excite", rigid.contour);
    let series: Vec<Series> = paths
        .iter()
        .map(|(n, c)| Series {
            name: n,
            points: c.table.clone(),
        })
        .collect();
    lines(
        &a.out.join("corner_table_paths.svg"),
        "table path near the corner",
        "x [µm]",
        "y [µm]",
        &series,
        true,
    )?;
    let cmds: Vec<Series> = paths
        .iter()
        .map(|(n, c)| Series {
            name: n,
            points: c.command.clone(),
        })
        .collect();
    lines(
        &a.out.join("corner_command_paths.svg"),
        "commanded path near the corner",
        "x [µm]",
        "y [µm]",
        &cmds,
        true,
    )?;
    let (_, lin15) = &paths[0];
    let vx = Series {
        name: "vx (linear 15 ms)",
        points: lin15.velocity.iter().map(|v| (v.0, v.1)).collect(),
    };
    let vy = Series {
        name: "vy (linear 15 ms)",
        points: lin15.velocity.iter().map(|v| (v.0, v.2)).collect(),
    };
    let (_, exp30) = &paths[3];
    let ex = Series {
        name: "vx (exponential 30 ms)",
        points: exp30.velocity.iter().map(|v| (v.0, v.1)).collect(),
    };
    let ey = Series {
        name: "vy (exponential 30 ms)",
        points: exp30.velocity.iter().map(|v| (v.0, v.2)).collect(),
    };
    lines(
        &a.out.join("corner_velocity.svg"),
        "commanded velocities through the corner",
        "t [s]",
        "µm/s",
        &[vx, vy, ex, ey],
        false,
    )?;
    println!("plots written to {}", a.out.display());
    Ok(())
}

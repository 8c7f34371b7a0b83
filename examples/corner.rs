//! Shin's corner test on the emulated card: a 90° corner at 1 m/min through linear and
//! exponential filters of 15 and 30 ms, on a rigid axis and on a table with a 33 Hz coupling
//! resonance. Prints the corner errors of all four filter/time-constant runs, sets them next
//! to Shin's (what agrees, what does not, and why), and writes SVG plots of the paths and
//! velocities.
//!
//! `cargo run --release --example corner`
use clap::Parser;
use motioncard::papers::{shin_comparison, shin_corner};
use motioncard::plot::{lines, Series};
use motioncard::{FilterKind, MotorParams};
use std::path::PathBuf;

/// Run Shin's corner test.
#[derive(Parser)]
struct Args {
    /// Resonance of the table's coupling, Hz.
    #[arg(long, default_value_t = 33.0)]
    resonance: f64,
    /// Directory for the SVG plots.
    #[arg(long, default_value = "target/plots")]
    out: PathBuf,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a = Args::parse();
    let table = MotorParams::machine_table(a.resonance);
    println!(
        "90° corner at 1 m/min; table with a {} Hz coupling resonance; errors in µm",
        a.resonance
    );
    println!(
        "| filter      | τ ms | command rounding | table tracking | table vs programmed corner |"
    );
    println!(
        "|-------------|------|------------------|----------------|----------------------------|"
    );
    let mut paths = Vec::new();
    for kind in [FilterKind::Linear, FilterKind::Exponential] {
        for tau in [0.015, 0.030] {
            let c = shin_corner(table, kind, tau)?;
            println!(
                "| {:<11} | {:>4.0} | {:>16.1} | {:>14.1} | {:>26.1} |",
                format!("{kind:?}"),
                tau * 1e3,
                c.command_rounding,
                c.tracking,
                c.total
            );
            paths.push((format!("{kind:?} {:.0} ms", tau * 1e3), c));
        }
    }
    println!();
    println!("Against Shin (Fig 12, ± corner tracking error):");
    let runs = [
        (paths[0].1.clone(), paths[1].1.clone()),
        (paths[2].1.clone(), paths[3].1.clone()),
    ];
    print!("{}", shin_comparison(&runs));
    println!();
    let rigid = shin_corner(MotorParams::default_servo(), FilterKind::Linear, 0.015)?;
    println!("rigid axis, linear 15 ms: tracking {:.1} µm — without a resonance there is nothing to excite", rigid.tracking);
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

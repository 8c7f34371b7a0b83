//! Yeh's die bonder on the emulated card: a NURBS path with two sharp corners, interpolated on
//! the card at 1 ms with PD+ axes, with and without the saturation-aware feed. Prints the drive
//! outputs against Umax, the contour error and the feed fluctuation; writes SVG plots of the
//! feed between the speed bounds of Yeh eq 3.6–3.10 (like Fig 6) and of u against ±Umax (like
//! Fig 7).
//!
//! `cargo run --release --example nurbs`
use card_emu::motion::nurbs::Point;
use card_emu::motion::nurbs_interp::{InterpConfig, Interpolator};
use card_emu::motion::saturation::{AxisSample, SaturationAwareFeed};
use card_emu::presets::{die_bonder_path, die_bonder_volts};
use card_emu::servo::pdplus::{DriveModelExt, PdPlus};
use clap::Parser;
use mcctl::papers::{yeh_die_bonder, DIE_BONDER_FEED};
use mcctl::plot::{lines, Series};
use std::path::PathBuf;

/// One tick of the host model: time s, feed, and the feasible feed interval of eq 3.6–3.10
/// (both axes), counts/s.
struct Bounded {
    t: f64,
    feed: f64,
    v_min: f64,
    v_max: f64,
}

/// Yeh Fig 6 on the host: the card's interpolator (the same code) on the die-bonder plant model
/// (Yeh eq 2.2 in volts, exact zero-order hold) with the PD+ law and a drive that clips at
/// ±Umax, recording each tick's feed and the speed window of eq 3.6 mapped onto the path
/// (eq 3.7–3.10: the feeds that keep both axes' predicted |u| ≤ Umax). With `aware` the
/// interpolator applies it (§3.4); without, the window is only computed, along each step.
fn feed_bounds(aware: bool) -> Result<Vec<Bounded>, Box<dyn std::error::Error>> {
    let preset = die_bonder_volts();
    let ts = preset.ts;
    let sat = SaturationAwareFeed::new(&preset.axes, ts)?;
    let curve = die_bonder_path();
    let cfg = InterpConfig {
        ts,
        feed: DIE_BONDER_FEED,
        accel: 4e7,
        jerk: 4e10,
        chord_tol: 1.0,
        max_corrections: 3,
    };
    let mut ip = if aware {
        Interpolator::with_actuator_limits(curve, cfg, &sat, 0.8)?
    } else {
        Interpolator::new(curve, cfg)?
    };
    let start = ip.position();
    let (mut th, mut vel) = ([start[0], start[1]], [0.0f64; 2]);
    let mut th_prev = th;
    let mut pd = Vec::new();
    for (j, a) in preset.axes.iter().enumerate() {
        let mut c = PdPlus::new(a.gains, ts)?;
        c.reset(th[j]);
        pd.push(c);
    }
    let mut out = Vec::new();
    let mut k = 0;
    while !ip.is_done() && k < 100_000 {
        k += 1;
        let mut theta_a = Point::zeros();
        let mut w_a = Point::zeros();
        for j in 0..2 {
            theta_a[j] = th[j];
            w_a[j] = (th[j] - th_prev[j]) / ts;
        }
        let states: Vec<AxisSample> = (0..2)
            .map(|j| AxisSample {
                theta_d_prev: ip.position()[j],
                w_d_prev: ip.velocity()[j],
                theta_a: theta_a[j],
                w_a: w_a[j],
            })
            .collect();
        let (tick, v_min, v_max) = if aware {
            let (t, dec) = ip.tick_guarded(&sat, &theta_a, &w_a)?;
            (t, dec.v_min, dec.v_max)
        } else {
            let t = ip.tick()?;
            let n = t.vel.norm();
            let dir = if n > 0.0 { t.vel / n } else { Point::zeros() };
            let dec = sat.limit_feed(t.feed, t.feed, &dir, &states)?;
            (t, dec.v_min, dec.v_max)
        };
        out.push(Bounded {
            t: k as f64 * ts,
            feed: tick.feed,
            v_min,
            v_max,
        });
        th_prev = th;
        for j in 0..2 {
            let a = &preset.axes[j];
            let u = pd[j].update(tick.pos[j], tick.vel[j], tick.acc[j], th[j]);
            (th[j], vel[j]) = a.plant.step(ts, th[j], vel[j], u.clamp(-a.umax, a.umax));
        }
    }
    Ok(out)
}

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
    // Yeh Fig 6: the feed against the bounds of eq 3.6–3.10 (host model of the same interpolator)
    let shown = 1.5 * DIE_BONDER_FEED;
    for (aware, name, file) in [
        (true, "saturation-aware", "nurbs_feed_bounds_aware.svg"),
        (false, "plain", "nurbs_feed_bounds_plain.svg"),
    ] {
        let run = feed_bounds(aware)?;
        let outside = run
            .iter()
            .filter(|b| b.feed > b.v_max * (1.0 + 1e-9) || b.feed < b.v_min * (1.0 - 1e-9))
            .count();
        println!(
            "feed between the eq 3.6 bounds ({name}, host model): {} of {} ticks outside",
            outside,
            run.len()
        );
        let pts = |f: &dyn Fn(&Bounded) -> f64| {
            run.iter()
                .map(|b| (b.t * 1e3, f(b).clamp(0.0, shown) / 1e3))
                .collect::<Vec<_>>()
        };
        lines(
            &args.out.join(file),
            &format!(
                "die bonder, {name}: feed and its bounds (Yeh eq 3.6-3.10; shown up to 1.5 x feed)"
            ),
            "t [ms]",
            "feed [counts/ms]",
            &[
                Series {
                    name: "feed",
                    points: pts(&|b| b.feed),
                },
                Series {
                    name: "upper bound",
                    points: pts(&|b| b.v_max),
                },
                Series {
                    name: "lower bound",
                    points: pts(&|b| b.v_min),
                },
            ],
            false,
        )?;
    }
    let feed = |r: &mcctl::papers::DieBonder| {
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
        let u = |r: &mcctl::papers::DieBonder| {
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
    let path = |r: &mcctl::papers::DieBonder| r.path.iter().map(|p| p.1).collect::<Vec<_>>();
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

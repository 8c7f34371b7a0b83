//! The papers' experiments on the emulated card, as tables (and SVG plots in `--out`).
//!
//! `cargo run --release --example papers`
use card_emu::servo::ffpiv::FfpivGains;
use clap::Parser;
use mcctl::papers::{
    corner_boxes, mm_per_s, um, yeh_die_bonder, yeh_feed_fluctuation, yeh_test_circle,
    yeh_test_sine, yeh_umax_sweep, DieBonder, DIE_BONDER_BUDGET, DIE_BONDER_FEED,
    DIE_BONDER_UM_PER_COUNT, YEH_FLUCTUATION_FEEDS, YEH_FOLLOWING_BOUND_UM, YEH_UMAX_FRACTIONS,
};
use mcctl::papers::{
    cruise_error, estimator_lag_error, ff_speed_sweep_on, kim_fig7, kim_sync_ptp, radial_error,
    shin_comparison, shin_fit, shin_resonance_sweep, shin_runs, sweep_frequencies, thinh_fig10,
    thinh_fig11, thinh_fig5, thinh_fig9, thinh_plant, FeedForward, Fig5Axis, ShinMachine,
    SweepPoint, SyncShape, Tracking, FIG10_SEGMENTS, FIG5_LIMITS, FIG9_STEP, LIGHT_ZETA,
    RADIAL_CASES, SHIN_FIG12, SHIN_FIT, SWEEP_ACCEL, SWEEP_SPEEDS, SYNC_TARGETS,
    THINH_COUNTS_PER_REV, THINH_GAINS,
};
use mcctl::plot::{lines, lines_log_x, Series};
use motioncard_sdk::Transition;
use motioncard_sdk::{FilterKind, Interpolator, MotorParams};
use std::path::PathBuf;

/// Reproduce Kim 1991 Fig 7, eq 10–14 and §4, Shin's corner test, Thinh 2014 Figs 5, 9
/// and 11, and Yeh 2008's die bonder in µm (following error, Umax sweep, eq 3.1/3.2 against
/// the card's corrected step), on the emulated card.
#[derive(Parser)]
struct Args {
    /// Directory for the SVG plots.
    #[arg(long, default_value = "target/plots")]
    out: PathBuf,
    /// Only this paper's experiments: kim, shin, thinh or yeh.
    #[arg(long)]
    only: Option<String>,
    /// Refit Shin's machine to his 15 ms figures (`papers::shin_fit`) instead of using the
    /// fitted constants (`papers::SHIN_FIT`).
    #[arg(long)]
    refit: bool,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let run = |paper: &str| args.only.as_deref().is_none_or(|o| o == paper);
    if run("kim") {
        kim(&args)?;
    }
    if run("shin") {
        shin(&args)?;
    }
    if run("thinh") {
        thinh(&args)?;
    }
    if run("yeh") {
        yeh(&args)?;
    }
    println!();
    println!("plots written to {}", args.out.display());
    Ok(())
}

fn kim(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
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
        let feed = mcctl::papers::KIM_FIG7_FEED;
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
    Ok(())
}

fn shin(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
    println!();
    println!("Shin: 90° corner at 1 m/min (1 count = 1 µm), two-mass axes, errors in µm");
    let m = if args.refit {
        let t0 = std::time::Instant::now();
        let f = shin_fit()?;
        println!(
            "refitted in {} evaluations of two runs ({:.1} s): {:?}, 15 ms errors {:.2} / {:.2} µm \
             (constants: {:?})",
            f.evaluations,
            t0.elapsed().as_secs_f64(),
            f.machine,
            f.errors.0,
            f.errors.1,
            SHIN_FIT
        );
        f.machine
    } else {
        SHIN_FIT
    };
    let runs = shin_runs(&m)?;
    println!("| filter      | τ ms | command rounding | contour error (min, max) | table vs programmed |");
    println!("|-------------|------|------------------|--------------------------|---------------------|");
    for ((kind, _, _), (short, long)) in SHIN_FIG12.iter().zip(&runs) {
        for (tau, c) in [(15, short), (30, long)] {
            println!(
                "| {:<11} | {:>4} | {:>16.1} | {:>24} | {:>19.1} |",
                format!("{kind:?}"),
                tau,
                c.command_rounding,
                format!(
                    "{:.1} ({:.1}, {:.1})",
                    c.contour, c.contour_min, c.contour_max
                ),
                c.total
            );
        }
    }
    let bw: Vec<String> = [15.0, 60.0, 150.0]
        .iter()
        .map(|&b| {
            let c = ShinMachine {
                bandwidth_hz: b,
                ..m
            }
            .corner(FilterKind::Linear, 0.015)?;
            Ok(format!("{:.1} µm at {b:.0} Hz", c.contour))
        })
        .collect::<Result<_, motioncard_sdk::Error>>()?;
    println!(
        "servo bandwidth (held at {:.0} Hz), linear 15 ms: {}",
        m.bandwidth_hz,
        bw.join(", ")
    );
    let hz = sweep_frequencies();
    let sweep = shin_resonance_sweep(&m, &hz)?;
    let light = shin_resonance_sweep(
        &ShinMachine {
            zeta: LIGHT_ZETA,
            ..m
        },
        &hz,
    )?;
    println!();
    println!(
        "Resonance sweep (ζ {:.3} as fitted, and ζ {LIGHT_ZETA}): corner error µm, 15 → 30 ms",
        m.zeta
    );
    println!("|   Hz | linear                | exponential           | linear, ζ {LIGHT_ZETA}        | exponential, ζ {LIGHT_ZETA}   |");
    println!("|------|-----------------------|-----------------------|-----------------------|-----------------------|");
    let cell = |p: (f64, f64)| format!("{:.1} → {:.1} ({:.2}×)", p.0, p.1, p.0 / p.1);
    for (p, q) in sweep.iter().zip(&light) {
        println!(
            "| {:>4.0} | {:<21} | {:<21} | {:<21} | {:<21} |",
            p.hz,
            cell(p.linear),
            cell(p.exponential),
            cell(q.linear),
            cell(q.exponential)
        );
    }
    println!();
    println!("Against Shin (Fig 12, ± corner tracking error):");
    print!("{}", shin_comparison(&m, &runs, &sweep, &light));
    let ratio = |s: &[SweepPoint], f: fn(&SweepPoint) -> (f64, f64)| -> Vec<(f64, f64)> {
        s.iter().map(|p| (p.hz, f(p).0 / f(p).1)).collect()
    };
    let name_l = format!("linear, ζ {:.2}", m.zeta);
    let name_e = format!("exponential, ζ {:.2}", m.zeta);
    let name_ll = format!("linear, ζ {LIGHT_ZETA}");
    let name_le = format!("exponential, ζ {LIGHT_ZETA}");
    lines_log_x(
        &args.out.join("shin_resonance_sweep.svg"),
        "Shin corner: error at 15 ms over error at 30 ms vs resonance",
        "coupling resonance [Hz]",
        "15 ms / 30 ms",
        &[
            Series {
                name: &name_l,
                points: ratio(&sweep, |p| p.linear),
            },
            Series {
                name: &name_e,
                points: ratio(&sweep, |p| p.exponential),
            },
            Series {
                name: &name_ll,
                points: ratio(&light, |p| p.linear),
            },
            Series {
                name: &name_le,
                points: ratio(&light, |p| p.exponential),
            },
        ],
    )?;
    let error = |f: fn(&SweepPoint) -> f64| -> Vec<(f64, f64)> {
        sweep.iter().map(|p| (p.hz, f(p))).collect()
    };
    lines_log_x(
        &args.out.join("shin_resonance_errors.svg"),
        &format!(
            "Shin corner error vs resonance (ζ {:.2}, as fitted)",
            m.zeta
        ),
        "coupling resonance [Hz]",
        "corner error [µm]",
        &[
            Series {
                name: "linear 15 ms",
                points: error(|p| p.linear.0),
            },
            Series {
                name: "linear 30 ms",
                points: error(|p| p.linear.1),
            },
            Series {
                name: "exponential 15 ms",
                points: error(|p| p.exponential.0),
            },
            Series {
                name: "exponential 30 ms",
                points: error(|p| p.exponential.1),
            },
        ],
    )?;
    let names = [
        "command, 15 ms",
        "table, 15 ms",
        "command, 30 ms",
        "table, 30 ms",
    ];
    let (l15, l30) = &runs[0];
    let mut series = Vec::new();
    for (i, c) in [l15, l30].into_iter().enumerate() {
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
        "Shin corner, linear filter, fitted two-mass table",
        "x [µm]",
        "y [µm]",
        &series,
        true,
    )?;
    let mut traces = Vec::new();
    let tnames = [
        "linear 15 ms",
        "linear 30 ms",
        "exponential 15 ms",
        "exponential 30 ms",
    ];
    for (i, c) in runs.iter().flat_map(|(a, b)| [a, b]).enumerate() {
        let t0 = c.contour_trace.first().map_or(0.0, |p| p.0);
        traces.push(Series {
            name: tnames[i],
            points: c.contour_trace.iter().map(|&(t, e)| (t - t0, e)).collect(),
        });
    }
    lines(
        &args.out.join("shin_contour_error.svg"),
        "Shin corner: contour error of the table against its commanded path",
        "t from entering the corner window [s]",
        "contour error [µm] (+ outside the turn)",
        &traces,
        false,
    )?;
    Ok(())
}

/// A plot of a command and its actual value against time.
fn command_actual(
    file: &std::path::Path,
    title: &str,
    unit: &str,
    t: &[f64],
    (cmd, act): (&[f64], &[f64]),
) -> Result<(), Box<dyn std::error::Error>> {
    lines(
        file,
        title,
        "t [s]",
        unit,
        &[
            Series {
                name: "command",
                points: points(t, cmd),
            },
            Series {
                name: "actual",
                points: points(t, act),
            },
        ],
        false,
    )?;
    Ok(())
}

fn points(t: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    t.iter().copied().zip(y.iter().copied()).collect()
}

fn thinh(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
    let tg = THINH_GAINS.to_ffpiv();
    let tp = thinh_plant();
    println!();
    println!(
        "Thinh 2014: K_P {}, K_I {}, K_V {}, K_VFF {} read as rpm/pulse, 1/ms, mV/rpm, mV/rpm \
         on {THINH_COUNTS_PER_REV} counts/rev: kp {:.1} 1/s, ki {:.0} 1/s, kv {:.3e} V/(count/s), kvff {:.2}; \
         plant J {:.3e} kg·m², {:.3} N·m/V (velocity loop {:.0} rad/s)",
        THINH_GAINS.kp,
        THINH_GAINS.ki,
        THINH_GAINS.kv,
        THINH_GAINS.kvff,
        tg.kp,
        tg.ki,
        tg.kv,
        tg.kvff,
        tp.inertia,
        tp.kt * tp.amp_gain,
        tg.kv * tp.accel_per_volt(),
    );
    println!();
    println!(
        "Thinh Fig 5: the same S-curve ({} counts at ≤ {:.0e} counts/s, {:.0e} counts/s², {:.0e} counts/s³), 10 kHz; following error = command − encoder, counts",
        mcctl::papers::FIG5_DISTANCE,
        FIG5_LIMITS.velocity,
        FIG5_LIMITS.acceleration,
        FIG5_LIMITS.jerk[0]
    );
    println!("| axis    | feed-forward                   |    peak |     RMS | (1−K_VFF)·v/K_P |");
    println!("|---------|--------------------------------|---------|---------|-----------------|");
    for axis in [Fig5Axis::Default, Fig5Axis::Thinh] {
        let (plant, gains) = axis.setup();
        let mut series = Vec::new();
        let cases: &[(FeedForward, &str)] = match axis {
            Fig5Axis::Default => &[
                (FeedForward::Full, "full (velocity + acceleration)"),
                (FeedForward::Velocity, "velocity only"),
                (FeedForward::None, "none"),
            ],
            Fig5Axis::Thinh => &[
                (FeedForward::Full, "full (velocity + acceleration)"),
                (FeedForward::Velocity, "velocity only"),
                (FeedForward::Thinh, "Thinh's K_VFF 30 (0.6)"),
                (FeedForward::None, "none"),
            ],
        };
        for &(ff, name) in cases {
            let r = thinh_fig5(axis, ff)?;
            let g = ff.apply(gains, &plant);
            println!(
                "| {:<7} | {:<30} | {:>7.2} | {:>7.2} | {:>15.1} |",
                format!("{axis:?}"),
                name,
                r.peak,
                r.rms,
                cruise_error(&g, FIG5_LIMITS.velocity)
            );
            if ff != FeedForward::None {
                series.push(Series {
                    name,
                    points: points(&r.t, &r.ferr),
                });
            }
        }
        lines(
            &args
                .out
                .join(format!("thinh_fig5_{axis:?}.svg").to_lowercase()),
            &format!("Thinh Fig 5, {axis:?} axis: following error (none: see table)"),
            "t [s]",
            "counts",
            &series,
            false,
        )?;
    }

    println!();
    let v = FIG9_STEP.limits.velocity;
    println!(
        "Thinh Fig 9 (acceleration mode) on Thinh's axis: S-curve to {v} counts/s ({:.0} rpm), {:.0e} counts/s², {:.0e} counts/s³",
        v * 60.0 / THINH_COUNTS_PER_REV as f64,
        FIG9_STEP.limits.acceleration,
        FIG9_STEP.limits.jerk[0]
    );
    println!("| feed-forward           | peak |v_cmd − v| counts/s | at cruise | peak following error | peak torque N·m (1 ms) | beyond DAC | end − target |");
    println!("|------------------------|-----------------------|-----------|----------------------|------------------------|------------|--------------|");
    for (ff, name) in [
        (FeedForward::Thinh, "Thinh's K_VFF 30 (0.6)"),
        (FeedForward::Full, "full"),
    ] {
        let r = thinh_fig9(ff)?;
        let verr = r.velocity_error(false);
        let cruise = r.velocity_error(true);
        let torque = r.torque_1ms();
        let peak_torque = torque.iter().map(|t| t.abs()).fold(0.0, f64::max);
        println!(
            "| {:<22} | {:>13.0} ({:>4.2}%) | {:>8.2}% | {:>20.1} | {:>22.3} | {:>10} | {:>12.0} |",
            name,
            verr,
            100.0 * verr / v,
            100.0 * cruise / v,
            r.peak,
            peak_torque,
            r.saturated,
            r.end.0 - r.end.1
        );
        let tag = if ff == FeedForward::Thinh {
            ""
        } else {
            "_full"
        };
        command_actual(
            &args.out.join(format!("thinh_fig9_velocity{tag}.svg")),
            &format!("Thinh Fig 9: acceleration mode, velocity ({name})"),
            "counts/s",
            &r.t,
            (&r.cmd_vel, &r.act_vel),
        )?;
        lines(
            &args.out.join(format!("thinh_fig9_torque{tag}.svg")),
            &format!("Thinh Fig 9: acceleration mode, torque ({name})"),
            "t [s]",
            "N·m",
            &[Series {
                name: "torque (1 ms mean)",
                points: points(&r.t, &torque),
            }],
            false,
        )?;
    }

    println!();
    println!("Thinh Fig 11 (step mode) on Thinh's axis: quarter-turn steps (2048 counts), 20 ms at rest after each");
    println!("| feed-forward           | profile ms | motion done after ms (per step)            | peak following error | end − target |");
    println!("|------------------------|------------|--------------------------------------------|----------------------|--------------|");
    for (ff, name) in [
        (FeedForward::Thinh, "Thinh's K_VFF 30 (0.6)"),
        (FeedForward::Full, "full"),
    ] {
        let r = thinh_fig11(ff)?;
        let done: Vec<String> = r
            .step_times
            .iter()
            .map(|(_, d)| format!("{:.1}", d * 1e3))
            .collect();
        println!(
            "| {:<22} | {:>10.1} | {:<42} | {:>20.1} | {:>12.0} |",
            name,
            r.step_times.first().map_or(0.0, |s| s.0 * 1e3),
            done.join(" "),
            r.peak,
            r.end.0 - r.end.1
        );
        let tag = if ff == FeedForward::Thinh {
            ""
        } else {
            "_full"
        };
        command_actual(
            &args.out.join(format!("thinh_fig11_position{tag}.svg")),
            &format!("Thinh Fig 11: step mode, position ({name})"),
            "counts",
            &r.t,
            (&r.cmd_pos, &r.act_pos),
        )?;
        command_actual(
            &args.out.join(format!("thinh_fig11_velocity{tag}.svg")),
            &format!("Thinh Fig 11: step mode, velocity ({name})"),
            "counts/s",
            &r.t,
            (&r.cmd_vel, &r.act_vel),
        )?;
    }

    println!();
    println!(
        "Thinh Fig 10 (blending mode) on Thinh's axis, full feed-forward: {} (counts, counts/s) on a one-axis path",
        FIG10_SEGMENTS.map(|(d, f)| format!("{d:.0} at {f:.0}")).join(", ")
    );
    println!("| transition                           | motion done s | least speed between | peak following error | 1 ms torque step N·m |");
    println!("|--------------------------------------|---------------|---------------------|----------------------|----------------------|");
    for (tr, name, tag) in [
        (
            Transition::TimeShift(1.0),
            "time-shifted profiles (Thinh, TM 3)",
            "shifted",
        ),
        (
            Transition::MaxDeviation(1.0),
            "the card's look-ahead planner",
            "planner",
        ),
        (Transition::None, "rest to rest (exact stops)", "stops"),
    ] {
        let r = thinh_fig10(tr)?;
        println!(
            "| {name:<36} | {:>13.4} | {:>19.0} | {:>20.2} | {:>20.4} |",
            r.time, r.least_between, r.trace.peak, r.torque_step
        );
        command_actual(
            &args.out.join(format!("thinh_fig10_velocity_{tag}.svg")),
            &format!("Thinh Fig 10: blending mode, velocity ({name})"),
            "counts/s",
            &r.trace.t,
            (&r.trace.cmd_vel, &r.trace.act_vel),
        )?;
    }

    println!();
    let (a, j) = SWEEP_ACCEL;
    let lag = estimator_lag_error(&FfpivGains::default(), a, 1e-4);
    println!(
        "Beyond Thinh: the default axis, default tuning (full feed-forward matched to the plant), S-curves at {a:.0e} counts/s², {j:.0e} counts/s³, 100 ms at cruise; \
         following error = command − encoder, counts (the estimator's lag alone would cost a·lag/K_P = {lag:.2} counts at {a:.0e} counts/s²)"
    );
    println!("| plant               | v counts/s | peak   | RMS   | ticks > 1 count | shaft − command, least .. largest |");
    println!("|---------------------|------------|--------|-------|-----------------|-----------------------------------|");
    let names = [
        "2e4 counts/s",
        "1e5 counts/s",
        "2e5 counts/s",
        "4e5 counts/s",
        "5e5 counts/s",
    ];
    let mut series = Vec::new();
    let no_coulomb = MotorParams {
        coulomb: 0.0,
        ..MotorParams::default_servo()
    };
    for (pname, plant) in [
        ("default", MotorParams::default_servo()),
        ("default, no Coulomb", no_coulomb),
    ] {
        for (v, name) in SWEEP_SPEEDS.iter().zip(names) {
            let r: Tracking = ff_speed_sweep_on(plant, *v)?;
            println!(
                "| {:<19} | {:>10.0e} | {:>6.4} | {:>5.3} | {:>15} | {:>15.3} .. {:<15.3} |",
                pname,
                v,
                r.peak,
                r.rms,
                r.ticks_over(1.0 + 1e-9),
                r.shaft.0,
                r.shaft.1
            );
            if pname == "default" {
                let end = r.t.last().copied().unwrap_or(1.0);
                series.push(Series {
                    name,
                    points: r
                        .t
                        .iter()
                        .map(|t| t / end)
                        .zip(r.ferr.iter().copied())
                        .collect(),
                });
            }
        }
    }
    lines(
        &args.out.join("ff_speed_sweep.svg"),
        "Default axis, full feed-forward: following error over the move",
        "fraction of the move",
        "counts",
        &series,
        false,
    )?;
    Ok(())
}

fn yeh(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
    let curve = card_emu::presets::die_bonder_path();
    let end = curve.point(curve.domain().1)?;
    let top = curve.point(0.5)?;
    println!();
    println!(
        "Yeh 2008 die bonder (Table 1 plant and PD+ gains, 1 ms) at {DIE_BONDER_UM_PER_COUNT} µm/count \
         (10,000 counts/rev from K_e = 10000/2π, 10 mm lead assumed: the paper gives none): \
         path {:.0} mm up, {:.0} mm across, feed {:.0} mm/s ({DIE_BONDER_FEED} counts/s), \
         Umax 10 V = 1 DU, look-ahead budget {DIE_BONDER_BUDGET}·Umax",
        um(top[1]) / 1e3,
        um(end[0]) / 1e3,
        mm_per_s(DIE_BONDER_FEED)
    );
    let with = yeh_die_bonder(true)?;
    let without = yeh_die_bonder(false)?;
    println!();
    println!(
        "Following error per axis (command − encoder) against Yeh's {YEH_FOLLOWING_BOUND_UM} µm"
    );
    println!("| feed             | max |u| X V | max |u| Y V | ticks > Umax | following X µm | following Y µm | within {YEH_FOLLOWING_BOUND_UM} µm | contour µm | time s |");
    println!("|------------------|-------------|-------------|--------------|----------------|----------------|----------------|------------|--------|");
    for (name, r) in [("saturation-aware", &with), ("plain", &without)] {
        let within = r.following.iter().all(|f| um(*f) <= YEH_FOLLOWING_BOUND_UM);
        println!(
            "| {:<16} | {:>11.2} | {:>11.2} | {:>12} | {:>14.1} | {:>14.1} | {:>14} | {:>10.1} | {:>6.3} |",
            name,
            r.max_u[0],
            r.max_u[1],
            r.ticks_over,
            um(r.following[0]),
            um(r.following[1]),
            if within { "yes" } else { "no" },
            um(r.contour),
            r.time
        );
    }
    let worst = with.following[0].max(with.following[1]);
    println!(
        "with the saturation-aware feed the worst axis stays within {YEH_FOLLOWING_BOUND_UM} µm for any scale up to {:.1} µm/count (a {:.0} mm lead)",
        YEH_FOLLOWING_BOUND_UM / worst,
        YEH_FOLLOWING_BOUND_UM / worst * 10.0
    );
    // the plain run's lag is shown clipped at ±4·100 µm, so the bound stays readable
    let clip = 4.0 * YEH_FOLLOWING_BOUND_UM;
    let ferr = |r: &DieBonder, axis: usize| -> Vec<(f64, f64)> {
        r.u.iter()
            .zip(&r.path)
            .map(|(u, (c, a))| {
                let e = if axis == 0 { c.0 - a.0 } else { c.1 - a.1 };
                (u.0 * 1e3, um(e).clamp(-clip, clip))
            })
            .collect()
    };
    let t_end = with.time.max(without.time) * 1e3;
    lines(
        &args.out.join("yeh_following_error.svg"),
        "Yeh die bonder: following error per axis (plain run clipped at ±400 µm for display)",
        "t [ms]",
        "command − encoder [µm]",
        &[
            Series {
                name: "X, saturation-aware",
                points: ferr(&with, 0),
            },
            Series {
                name: "Y, saturation-aware",
                points: ferr(&with, 1),
            },
            Series {
                name: "X, plain",
                points: ferr(&without, 0),
            },
            Series {
                name: "Y, plain",
                points: ferr(&without, 1),
            },
            Series {
                name: "+100 µm",
                points: vec![
                    (0.0, YEH_FOLLOWING_BOUND_UM),
                    (t_end, YEH_FOLLOWING_BOUND_UM),
                ],
            },
            Series {
                name: "−100 µm",
                points: vec![
                    (0.0, -YEH_FOLLOWING_BOUND_UM),
                    (t_end, -YEH_FOLLOWING_BOUND_UM),
                ],
            },
        ],
        false,
    )?;

    println!();
    let b = corner_boxes();
    println!(
        "Umax swept, saturation-aware feed; corner feed over the two curved spans (x {:.1}–{:.1} mm and {:.1}–{:.1} mm, y ≥ {:.1} mm)",
        um(b[0].0) / 1e3,
        um(b[0].1) / 1e3,
        um(b[1].0) / 1e3,
        um(b[1].1) / 1e3,
        um(b[0].2) / 1e3
    );
    println!("| Umax V | time s | plan alone s | corner feed mean mm/s | corner feed min mm/s | max |u| X V | max |u| Y V | ticks > Umax | following X µm | following Y µm |");
    println!("|--------|--------|--------------|-----------------------|----------------------|-------------|-------------|--------------|----------------|----------------|");
    let sweep = yeh_umax_sweep(&YEH_UMAX_FRACTIONS)?;
    for r in &sweep {
        println!(
            "| {:>6.1} | {:>6.3} | {:>12.3} | {:>21.1} | {:>20.1} | {:>11.3} | {:>11.3} | {:>12} | {:>14.1} | {:>14.1} |",
            r.umax,
            r.time,
            r.planned_time.unwrap_or(f64::NAN),
            mm_per_s(r.corner_feed.0),
            mm_per_s(r.corner_feed.1),
            r.max_u[0],
            r.max_u[1],
            r.ticks_over,
            um(r.following[0]),
            um(r.following[1])
        );
    }
    let shown: Vec<&DieBonder> = sweep
        .iter()
        .filter(|r| {
            [3.0, 5.0, 7.0, 10.0]
                .iter()
                .any(|u| (r.umax - u).abs() < 1e-9)
        })
        .collect();
    let names: Vec<String> = shown
        .iter()
        .map(|r| format!("Umax {:.0} V", r.umax))
        .collect();
    let feed: Vec<Series> = shown
        .iter()
        .zip(&names)
        .map(|(r, name)| Series {
            name,
            points: r.feed.iter().map(|p| (p.0 * 1e3, mm_per_s(p.1))).collect(),
        })
        .collect();
    lines(
        &args.out.join("yeh_umax_sweep_feed.svg"),
        "Yeh die bonder, saturation-aware: feed for several Umax",
        "t [ms]",
        "feed [mm/s]",
        &feed,
        false,
    )?;
    let u: Vec<Series> = shown
        .iter()
        .zip(&names)
        .map(|(r, name)| Series {
            name,
            points: r
                .u
                .iter()
                .map(|p| (p.0 * 1e3, p.1.abs().max(p.2.abs())))
                .collect(),
        })
        .collect();
    lines(
        &args.out.join("yeh_umax_sweep_u.svg"),
        "Yeh die bonder, saturation-aware: max(|u_x|, |u_y|) for several Umax",
        "t [ms]",
        "|u| [V]",
        &u,
        false,
    )?;

    println!();
    println!(
        "Feed fluctuation |chord/Ts − V|/V at 1 ms: Yeh's plain parameter updates (offline, every step \
         but the last) against the card's eq 3.1 + Newton corrections (stepped card, cruise)"
    );
    println!("| curve                 | feed mm/s | eq 3.2 max | eq 3.2 RMS | eq 3.1 max | eq 3.1 RMS | card max | card RMS | eq 3.1 max / card max |");
    println!("|-----------------------|-----------|------------|------------|------------|------------|----------|----------|-----------------------|");
    for (name, curve) in [
        ("circle r 5 mm (C¹)", yeh_test_circle()),
        ("sine 5 mm × 4 mm (C²)", yeh_test_sine()),
    ] {
        for r in yeh_feed_fluctuation(&curve, &YEH_FLUCTUATION_FEEDS)? {
            println!(
                "| {:<21} | {:>9.0} | {:>10.2e} | {:>10.2e} | {:>10.2e} | {:>10.2e} | {:>8.1e} | {:>8.1e} | {:>21.1e} |",
                name,
                mm_per_s(r.feed),
                r.eq32.max,
                r.eq32.rms,
                r.eq31.max,
                r.eq31.rms,
                r.card.max,
                r.card.rms,
                r.eq31.max / r.card.max
            );
        }
    }
    Ok(())
}

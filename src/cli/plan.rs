//! `mcctl plan`: the seven-segment S-curve the card plans for one axis (Thinh eq 1–28), or with
//! --a0 the time-optimal trajectory from any state; offline, no card.

use super::args::{finite, positive};
use super::bad;
use crate::plan::{Limits, OtgLimits, PlanError, Profile, Trajectory};
use clap::Args as ClapArgs;
use std::process::ExitCode;

/// `mcctl plan`.
#[derive(ClapArgs)]
pub struct Args {
    /// Distance to travel (signed).
    #[arg(allow_hyphen_values = true, value_parser = finite("distance"))]
    pub distance: f64,
    // Negative numbers are values here, so `--dmax -3` gets "must be greater than zero"
    // rather than clap's "unexpected argument".
    /// Maximum velocity.
    #[arg(long, allow_negative_numbers = true, value_parser = positive("--vmax"))]
    pub vmax: f64,
    /// Maximum acceleration.
    #[arg(long, allow_negative_numbers = true, value_parser = positive("--amax"))]
    pub amax: f64,
    /// Maximum jerk (phases 1 and 3; also 5 and 7 unless --jdec).
    #[arg(long, allow_negative_numbers = true, value_parser = positive("--jmax"))]
    pub jmax: f64,
    /// Maximum deceleration (default: --amax).
    #[arg(long, allow_negative_numbers = true, value_parser = positive("--dmax"))]
    pub dmax: Option<f64>,
    /// Jerk of the deceleration phases 5 and 7 (default: --jmax).
    #[arg(long, allow_negative_numbers = true, value_parser = positive("--jdec"))]
    pub jdec: Option<f64>,
    /// Start velocity, along the direction of motion (0..=--vmax). With --a0: signed, in
    /// the world frame, any value (a start beyond --vmax is braked first).
    #[arg(
        long,
        default_value_t = 0.0,
        allow_negative_numbers = true,
        value_parser = finite("--v0")
    )]
    pub v0: f64,
    /// End velocity, along the direction of motion (0..=--vmax). With --a0: signed, in the
    /// world frame, within ±--vmax.
    #[arg(
        long,
        default_value_t = 0.0,
        allow_negative_numbers = true,
        value_parser = finite("--v1")
    )]
    pub v1: f64,
    /// Start acceleration, signed (world frame). Plans the time-optimal trajectory from
    /// any state (Ruckig's position interface, `motion::otg`) instead of the S-curve:
    /// --v0 and --v1 are then signed, --v0 may lie beyond --vmax and --a0 beyond the
    /// limits; the limits are --amax ahead, --dmax behind and the smaller jerk.
    #[arg(long, allow_negative_numbers = true, value_parser = finite("--a0"))]
    pub a0: Option<f64>,
    /// Servo rate of the card, Hz (1000..=20000): the range the card accepts for each limit
    /// depends on it.
    #[arg(long, default_value_t = 10_000, value_parser = servo_rate)]
    pub servo_rate: u32,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// `--servo-rate`: a rate the card runs at.
fn servo_rate(s: &str) -> Result<u32, String> {
    let rates = card_emu::SERVO_RATE_MIN_HZ..=card_emu::SERVO_RATE_MAX_HZ;
    match s.parse::<u32>() {
        Ok(r) if rates.contains(&r) => Ok(r),
        _ => Err(format!(
            "--servo-rate must be between {} and {} Hz, got {s}",
            rates.start(),
            rates.end()
        )),
    }
}

/// Plan and print; a plan the card would refuse is exit status 2, with the card's reason.
pub fn run(a: Args) -> ExitCode {
    let Args {
        distance,
        vmax,
        amax,
        jmax,
        dmax,
        jdec,
        v0,
        v1,
        a0,
        servo_rate,
        json,
    } = a;
    let dmax = dmax.unwrap_or(amax);
    let jdec = jdec.unwrap_or(jmax);
    let named = [
        ("--vmax", vmax),
        ("--amax", amax),
        ("--jmax", jmax),
        ("--dmax", dmax),
        ("--jdec", jdec),
        ("--v0", v0),
        ("--v1", v1),
    ];
    // Each is finite, the limits are greater than zero and the servo rate is one the card
    // runs at: clap's value parsers saw to it.
    //
    // The card's range for a limit of order k (1 velocity, 2 acceleration, 3 jerk):
    // from one count in the longest move to the whole position range in one tick.
    let (vel, acc, jerk) = ((1, "velocity"), (2, "acceleration"), (3, "jerk"));
    for ((what, v), (order, kind)) in named[..5].iter().zip([vel, acc, jerk, acc, jerk]) {
        let range = card_emu::limit_range(order, servo_rate);
        if !range.contains(v) {
            return bad(format!(
                "{what} must be between {:e} and {:e} (the card's {kind} range at \
                 --servo-rate {servo_rate} Hz), got {v:e}",
                range.start(),
                range.end()
            ));
        }
    }
    if a0.is_some() && v1.abs() > vmax {
        return bad(format!(
            "--v1 must be between -{vmax} and --vmax ({vmax}), got {v1}"
        ));
    }
    for (what, v) in &named[5..] {
        if a0.is_some() {
            break;
        }
        if *v < 0.0 || *v > vmax {
            return bad(format!(
                "{what} must be between 0 and --vmax ({vmax}), got {v}"
            ));
        }
    }
    // The card's own bounds: it refuses a target beyond ±MAX_POSITION counts and a
    // move longer than MAX_MOVE_TIME.
    let max_pos = card_emu::MAX_POSITION;
    if distance.abs() > max_pos {
        return bad(format!(
            "distance must be at most {max_pos} in magnitude (2^52, the card's position \
             range in counts), got {distance}"
        ));
    }
    let lim = Limits {
        vmax,
        amax,
        dmax,
        j1: jmax,
        j3: jmax,
        j5: jdec,
        j7: jdec,
    };
    if let Some(a0) = a0 {
        let dir = if distance < 0.0 { -1.0 } else { 1.0 };
        return from_any_state(distance, v0, a0, v1, &OtgLimits::along(dir, &lim), json);
    }
    let p = match Profile::plan(0.0, distance, v0, v1, &lim) {
        Ok(p) => p,
        Err(e) => return bad(format!("no S-curve satisfies these limits: {e}")),
    };
    // The card's own check of the plan before it runs it (Profile::plan_checked).
    match p.verify_plan(0.0, distance, v0, v1, &lim) {
        Ok(()) => {}
        Err(PlanError::Infeasible) => {
            return bad(format!(
                "the move would take {:.6e} s; the card refuses moves longer than {} s",
                p.duration(),
                card_emu::MAX_MOVE_TIME
            ))
        }
        Err(e) => {
            return bad(format!(
                "the card would refuse this plan ({e}: off its target, beyond a limit, \
                 backwards or shorter than |distance|/vmax)"
            ))
        }
    }
    let phases = p.phases();
    if json {
        let j = serde_json::json!({
            "distance": distance,
            "duration": p.duration(),
            "phases": phases,
            "peak_velocity": p.peak_velocity(),
            "peak_acceleration": p.peak_acceleration(),
            "peak_deceleration": p.peak_deceleration(),
            "limits": { "vmax": vmax, "amax": amax, "dmax": dmax, "jacc": jmax, "jdec": jdec, "v0": v0, "v1": v1 },
        });
        println!("{j}");
    } else {
        println!("S-curve for a distance of {distance} (v0 {v0}, v1 {v1})");
        let names = [
            "1 jerk +J1",
            "2 constant acc",
            "3 jerk -J3",
            "4 cruise",
            "5 jerk -J5",
            "6 constant dec",
            "7 jerk +J7",
        ];
        for (n, t) in names.iter().zip(phases) {
            println!("  phase {n:<16} {t:>14.9} s");
        }
        println!("  total                  {:>14.9} s", p.duration());
        println!(
            "  peak velocity          {:>14.6} (limit {vmax})",
            p.peak_velocity()
        );
        println!(
            "  peak acceleration      {:>14.6} (limit {amax})",
            p.peak_acceleration()
        );
        println!(
            "  peak deceleration      {:>14.6} (limit {dmax})",
            p.peak_deceleration()
        );
    }
    ExitCode::SUCCESS
}

/// `mcctl plan --a0 ...`: the time-optimal trajectory from `(0, v0, a0)` to `(distance, v1)`
/// (`Trajectory::to_position`, which runs the card's check on it), printed like the S-curve.
fn from_any_state(
    distance: f64,
    v0: f64,
    a0: f64,
    v1: f64,
    lim: &OtgLimits,
    json: bool,
) -> ExitCode {
    let tr = match Trajectory::to_position(0.0, v0, a0, distance, v1, lim) {
        Ok(t) => t,
        Err(e) => return bad(format!("no trajectory satisfies these limits: {e}")),
    };
    if tr.duration() > card_emu::MAX_MOVE_TIME {
        return bad(format!(
            "the move would take {:.6e} s; the card refuses moves longer than {} s",
            tr.duration(),
            card_emu::MAX_MOVE_TIME
        ));
    }
    let phases = tr.phases();
    let jerks = &tr.jerks()[..phases.len()];
    let (amin, amax) = tr.acceleration_range();
    // Each segment named by what it does: its jerk, or the acceleration it holds.
    let mut start = 0.0;
    let mut names = Vec::new();
    for (i, (t, j)) in phases.iter().zip(jerks).enumerate() {
        let acc = tr.sample(start + 0.5 * t).acc;
        start += t;
        let what = if *j > 0.0 {
            "jerk +J"
        } else if *j < 0.0 {
            "jerk -J"
        } else if acc == 0.0 {
            "cruise"
        } else {
            "constant acc"
        };
        let part = if i < tr.brake_segments() {
            "brake"
        } else {
            "phase"
        };
        names.push(format!("{part} {} {what}", i + 1));
    }
    if json {
        let j = serde_json::json!({
            "distance": distance,
            "duration": tr.duration(),
            "brake": tr.brake_duration(),
            "phases": phases,
            "jerks": jerks,
            "peak_velocity": tr.peak_velocity(),
            "peak_acceleration": amax,
            "peak_deceleration": -amin,
            "limits": { "vmax": lim.vmax, "vmin": lim.vmin, "amax": lim.amax, "amin": lim.amin, "jmax": lim.jmax, "v0": v0, "a0": a0, "v1": v1 },
        });
        println!("{j}");
    } else {
        println!(
            "Time-optimal trajectory for a distance of {distance} from any state (v0 {v0}, a0 \
             {a0}, v1 {v1})"
        );
        for (n, t) in names.iter().zip(phases) {
            println!("  {n:<22} {t:>14.9} s");
        }
        println!("  total                  {:>14.9} s", tr.duration());
        println!("  of which brake         {:>14.9} s", tr.brake_duration());
        println!(
            "  peak velocity          {:>14.6} (limits {} .. {})",
            tr.peak_velocity(),
            lim.vmin,
            lim.vmax
        );
        println!(
            "  acceleration           {:>14.6} .. {:.6} (limits {} .. {})",
            amin, amax, lim.amin, lim.amax
        );
    }
    ExitCode::SUCCESS
}

//! Unit tests of [`Axis::control`], the servo loop and motion bookkeeping of one tick, called
//! directly on an axis set up in-process (no card, no plant: the tests say where the shaft
//! is). The following-error and limit-switch trips are not `control`'s: the safety layer
//! (`safety.rs`) acts on the following error and the reference `control` leaves.

use super::*;
use crate::firmware::dac::Dac;
use crate::firmware::rate_hz;
use crate::math;
use crate::servo::pdplus::{DriveModel, PdPlusGains};
use firmware_proto::raw;

/// The tests' servo period, s (10 kHz).
const TS: f64 = 1e-4;

/// The limits of the tests' moves: 2·10⁵ counts/s, 2·10⁶ counts/s², 10⁸ counts/s³.
fn limits() -> Limits {
    Limits::symmetric(2e5, 2e6, 1e8)
}

/// A powered axis at rest at encoder count `at`, with the default configuration (FFPIV).
fn powered(at: i64) -> Axis {
    let mut ax = Axis::new();
    ax.sense(at, TS);
    assert_eq!(ax.power(true), Ok(Some(AxisState::Disabled)));
    ax
}

/// One tick with the shaft at count `enc`.
fn tick(ax: &mut Axis, enc: i64) -> (f64, TickReport) {
    ax.sense(enc, TS);
    ax.control(TS)
}

/// One tick of an ideal drive: the shaft on the last reference, rounded to a count.
fn tick_ideal(ax: &mut Axis) -> (f64, TickReport) {
    let enc = math::round(ax.reference().pos) as i64;
    tick(ax, enc)
}

/// Ideal ticks until a report satisfies `until` (at most `max`): that tick's number (from 1)
/// and report.
fn run_until(
    ax: &mut Axis,
    max: usize,
    until: impl Fn(&TickReport) -> bool,
) -> (usize, TickReport) {
    for k in 1..=max {
        let (_, report) = tick_ideal(ax);
        if until(&report) {
            return (k, report);
        }
    }
    panic!("no such report in {max} ticks");
}

fn faults(ax: &Axis) -> Faults {
    Faults::from_bits_retain(ax.status(0).faults)
}

/// Relative closeness, for outputs computed the way the law computes them.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1.0)
}

/// A disabled axis outputs 0 V whatever its reference says, and its reference is pulled onto
/// the shaft at rest (so that enabling never jumps): no following error, no terms, no report.
#[test]
fn a_disabled_axis_outputs_nothing_and_its_reference_follows_the_shaft() {
    let mut ax = Axis::new();
    ax.sense(500, TS);
    ax.drive(Reference {
        pos: 0.0,
        vel: 10.0,
        acc: 5.0,
    });
    let (volts, report) = ax.control(TS);
    assert_eq!(volts, 0.0);
    assert_eq!(report, TickReport::default());
    assert_eq!(ax.state, AxisState::Disabled);
    assert_eq!(
        ax.reference(),
        Reference {
            pos: 500.0,
            vel: 0.0,
            acc: 0.0
        }
    );
    let st = ax.status(0);
    assert_eq!((st.ferr, st.dac_v), (0.0, 0.0));
    assert_eq!(ax.servo_terms(), ServoTerms::default());
}

/// Powered at rest on its reference, the FFPIV law has nothing to do: 0 V, every tick, and a
/// reference between two counts at rest is taken as the nearest count (no hunting between the
/// two), though the following error published is the unrounded difference.
#[test]
fn at_rest_on_its_reference_the_output_is_zero() {
    let mut ax = powered(250);
    for _ in 0..100 {
        let (volts, report) = tick(&mut ax, 250);
        assert_eq!(volts, 0.0);
        assert_eq!(report, TickReport::default());
        assert_eq!(ax.status(0).u_request, 0.0);
    }
    ax.drive(Reference {
        pos: 250.4,
        vel: 0.0,
        acc: 0.0,
    });
    for _ in 0..100 {
        let (volts, _) = tick(&mut ax, 250);
        assert_eq!(volts, 0.0);
    }
    assert!(close(ax.status(0).ferr, 0.4));
    assert_eq!(ax.state, AxisState::Standstill);
}

/// A position error `e` at rest, with the shaft still, gives the FFPIV output of Thinh eq 29
/// with the configured gains: `v_cmd = kp·e`, `u = kv·(v_cmd + ki·∫v_cmd)`, of the error's sign,
/// its terms split as the law says; the DAC puts out that voltage to within half an LSB.
#[test]
fn a_position_error_gives_the_ffpiv_output_of_its_sign_and_size() {
    for e in [3.0, -3.0] {
        let mut ax = powered(0);
        let g = ax.config.ffpiv;
        ax.drive(Reference {
            pos: e,
            vel: 0.0,
            acc: 0.0,
        });
        let (volts, report) = tick(&mut ax, 0);
        let ev = g.kp * e;
        let integral = ev * TS;
        let expected = g.kv * (ev + g.ki * integral);
        assert!(
            expected.abs() < ax.config.dac_limit_v,
            "{expected} V saturates"
        );
        assert!(
            expected.abs() > 10.0 * Dac::LSB,
            "{expected} V is too small a test"
        );
        let st = ax.status(0);
        assert!(
            close(st.u_request, expected),
            "{} != {expected}",
            st.u_request
        );
        assert_eq!(volts.signum(), e.signum());
        assert!((volts - expected).abs() <= Dac::LSB / 2.0);
        assert_eq!((st.dac_v, st.ferr), (volts, e));
        let t = ax.servo_terms();
        assert!(close(t.p, g.kv * g.kp * e));
        assert!(close(t.i, g.kv * g.ki * integral));
        assert_eq!((t.d, t.ff), (0.0, 0.0));
        assert_eq!(report, TickReport::default());
        assert!(!faults(&ax).contains(Faults::DAC_SATURATED));
    }
}

/// A shaft moving with no position error meets the velocity loop: the output opposes the
/// motion, its `d` term is `−kv·v̂` of the filtered velocity estimate, and the terms add up to
/// the output.
#[test]
fn a_moving_shaft_without_position_error_is_damped() {
    for dir in [1i64, -1] {
        let mut ax = powered(0);
        let g = ax.config.ffpiv;
        let mut u = 0.0;
        for k in 1..=50 {
            ax.drive(Reference {
                pos: (dir * k) as f64,
                vel: 0.0,
                acc: 0.0,
            });
            u = tick(&mut ax, dir * k).0;
            assert_eq!(ax.status(0).ferr, 0.0);
        }
        let v = ax.velocity_estimate();
        assert!(v * dir as f64 > 0.5 / TS, "v̂ {v}");
        assert_eq!(u.signum(), -(dir as f64), "output {u} V at v̂ {v}");
        let t = ax.servo_terms();
        assert_eq!(t.p, 0.0);
        assert!(close(t.d, -g.kv * v));
        assert!(close(t.p + t.i + t.d + t.ff, ax.status(0).u_request));
    }
}

/// The output is clamped to the configured DAC range, and flagged `DAC_SATURATED` whenever the
/// law asks for the limit or more (the request is published unclamped); back within range the
/// flag clears (the integrator did not wind up meanwhile); a disabled axis clears it too.
#[test]
fn the_output_is_clamped_to_the_dac_range_and_saturation_flagged() {
    let mut ax = powered(0);
    let at = |ax: &mut Axis, pos: f64| {
        ax.drive(Reference {
            pos,
            vel: 0.0,
            acc: 0.0,
        });
        tick(ax, 0).0
    };
    assert_eq!(at(&mut ax, 1e6), Dac::output(10.0).0);
    assert!(ax.status(0).u_request > 10.0);
    assert!(faults(&ax).contains(Faults::DAC_SATURATED));
    assert_eq!(at(&mut ax, -1e6), -10.0);
    assert!(faults(&ax).contains(Faults::DAC_SATURATED));
    // A narrower range: the clamp follows the configuration.
    let cfg = AxisConfig {
        block: firmware_proto::AxisConfig {
            dac_limit_v: 2.0,
            ..Default::default()
        },
        pdplus: None,
        pidff: None,
    };
    ax.apply_config(cfg, TS);
    let volts = at(&mut ax, 1e6);
    assert!((volts - 2.0).abs() <= Dac::LSB / 2.0, "{volts} V");
    assert!(faults(&ax).contains(Faults::DAC_SATURATED));
    let volts = at(&mut ax, -1e6);
    assert!((volts + 2.0).abs() <= Dac::LSB / 2.0, "{volts} V");
    assert_eq!(at(&mut ax, 0.0), 0.0);
    assert!(!faults(&ax).contains(Faults::DAC_SATURATED));
    // Saturated, then disabled: the flag goes with the output.
    at(&mut ax, 1e6);
    assert!(faults(&ax).contains(Faults::DAC_SATURATED));
    ax.power(false).unwrap();
    assert_eq!(tick(&mut ax, 0).0, 0.0);
    assert!(!faults(&ax).contains(Faults::DAC_SATURATED));
}

/// With PD+ configured, the output is Yeh eq 2.12 with the configured gains,
/// `kp·(θ_d − θ) + kd·(θ̇_d − θ̇) + kv·θ̇_d + ka·θ̈_d`, the measured speed the backward difference
/// of the shaft (zero on the first tick after the law is selected).
#[test]
fn pdplus_configured_gives_yeh_eq_2_12() {
    let mut ax = powered(100);
    let gains = PdPlusGains {
        kp: 0.02,
        kd: 0.001,
        kv: 1e-4,
        ka: 1e-6,
    };
    let model = AxisModel {
        gains,
        plant: DriveModel {
            kc: 10.0,
            tau: 0.01,
            ke: 1591.5494,
        },
        umax: 10.0,
    };
    let cfg = AxisConfig {
        block: firmware_proto::AxisConfig {
            servo_law: raw::MC_SERVO_PDPLUS,
            ..Default::default()
        },
        pdplus: Some(model),
        pidff: None,
    };
    ax.apply_config(cfg, TS);
    let r = Reference {
        pos: 150.0,
        vel: 1000.0,
        acc: 1e5,
    };
    ax.drive(r);
    let law = |theta: f64, w: f64| {
        gains.kp * (r.pos - theta) + gains.kd * (r.vel - w) + gains.kv * r.vel + gains.ka * r.acc
    };
    let (volts, _) = tick(&mut ax, 100);
    let expected = law(100.0, 0.0);
    assert!(close(ax.status(0).u_request, expected));
    assert!(expected > 0.0 && (volts - expected).abs() <= Dac::LSB / 2.0);
    let t = ax.servo_terms();
    assert!(close(t.p, gains.kp * 50.0) && close(t.d, gains.kd * 1000.0));
    assert!(close(t.ff, gains.kv * 1000.0 + gains.ka * 1e5));
    assert_eq!(t.i, 0.0);
    // The shaft moved a count in the tick: 10⁴ counts/s, faster than the reference.
    let (volts, _) = tick(&mut ax, 101);
    let expected = law(101.0, 1.0 / TS);
    assert!(close(ax.status(0).u_request, expected));
    assert!(expected < 0.0 && (volts - expected).abs() <= Dac::LSB / 2.0);
}

/// A position move runs its planned trajectory (the reference never backwards, never past the
/// target, never over vmax), holds at its end, and reports done once, with its seq and the
/// shaft's position, after the settle time in position; the same tick it leaves DiscreteMotion
/// for Standstill, with the stop reason Done and the move's time published.
#[test]
fn a_move_runs_its_trajectory_and_reports_done_once_in_position() {
    let mut ax = powered(0);
    let lim = limits();
    let started = ax.start_move(7, MoveKind::Absolute, 1000.0, &lim, false, rate_hz(TS));
    assert_eq!(started, Ok((Some(AxisState::Standstill), Started::Now)));
    let planned = ax.status(0).planned_time;
    let settle = ax.config.settle_time;
    let mut prev = ax.reference();
    let mut done_at = None;
    for k in 1..=20_000 {
        let (_, report) = tick_ideal(&mut ax);
        let r = ax.reference();
        let backwards = r.pos < prev.pos - 1e-9;
        assert!(
            !backwards && r.pos <= 1000.0 + 1e-9,
            "{} after {}",
            r.pos,
            prev.pos
        );
        assert!(r.vel.abs() <= lim.vmax * (1.0 + 1e-9));
        prev = r;
        if report.done.is_some() {
            assert!(done_at.is_none(), "done twice");
            assert_eq!(report.done, Some((7, 1000.0)));
            assert_eq!(report.state_from, Some(AxisState::DiscreteMotion));
            assert_eq!((report.active, report.in_velocity), (None, None));
            assert!(report.dropped.is_empty());
            done_at = Some(k);
        } else {
            assert_eq!(report, TickReport::default());
        }
    }
    let k = done_at.expect("no motion done") as f64;
    assert!(k * TS >= planned + settle - TS, "done after {k} ticks");
    assert!(
        k * TS <= planned + settle + 20.0 * TS,
        "done after {k} ticks"
    );
    assert_eq!(ax.state, AxisState::Standstill);
    assert_eq!(ax.safety.stop_reason, StopReason::Done);
    let st = ax.status(0);
    assert_eq!((st.cmd_pos, st.cmd_vel, st.act_pos), (1000.0, 0.0, 1000.0));
    assert!(st.move_time >= planned && st.move_time <= k * TS + 1e-9);
    assert!(st.peak_vel > 0.0 && st.peak_vel <= lim.vmax * (1.0 + 1e-9));
}

/// PLCopen Buffered: the move queued behind another starts on the tick that one is done, the
/// same report giving both (done for the first, active for the second, its target counted from
/// the first one's); no state change between them, and Standstill after the second.
#[test]
fn a_buffered_move_starts_on_the_tick_the_one_before_is_done() {
    let mut ax = powered(0);
    let (lim, rate) = (limits(), rate_hz(TS));
    ax.start_move(1, MoveKind::Absolute, 1000.0, &lim, false, rate)
        .unwrap();
    let queued = ax.start_move(2, MoveKind::Relative, 500.0, &lim, true, rate);
    assert_eq!(queued, Ok((None, Started::Queued)));
    assert_eq!(ax.status(0).queued, 1);
    let (_, report) = run_until(&mut ax, 20_000, |r| r.done.is_some());
    assert_eq!(report.done, Some((1, 1000.0)));
    assert_eq!(report.active, Some((2, 1500.0)));
    assert_eq!(report.state_from, None);
    assert_eq!(ax.state, AxisState::DiscreteMotion);
    assert_eq!(ax.status(0).queued, 0);
    assert!(ax.motion_flags().contains(MotionFlags::BUFFERED_ACTIVE));
    let (_, report) = run_until(&mut ax, 20_000, |r| r.done.is_some());
    assert_eq!(report.done, Some((2, 1500.0)));
    assert_eq!(report.state_from, Some(AxisState::DiscreteMotion));
    assert_eq!(ax.state, AxisState::Standstill);
}

/// A buffered move that cannot be planned when its turn comes (its limits out of the card's
/// range) is dropped, and every move queued behind it with it, in order, in the report of the
/// tick the move before them is done; the axis goes to Standstill.
#[test]
fn a_buffered_move_that_cannot_be_planned_is_dropped_with_the_rest() {
    let mut ax = powered(0);
    let (lim, rate) = (limits(), rate_hz(TS));
    let bad = Limits {
        vmax: f64::MAX,
        ..lim
    };
    ax.start_move(1, MoveKind::Absolute, 1000.0, &lim, false, rate)
        .unwrap();
    ax.start_move(2, MoveKind::Absolute, 0.0, &bad, true, rate)
        .unwrap();
    ax.start_move(3, MoveKind::Absolute, 500.0, &lim, true, rate)
        .unwrap();
    let (_, report) = run_until(&mut ax, 20_000, |r| r.done.is_some());
    assert_eq!(report.done, Some((1, 1000.0)));
    assert_eq!(report.dropped.as_slice(), &[2, 3]);
    assert_eq!(report.active, None);
    assert_eq!(report.state_from, Some(AxisState::DiscreteMotion));
    assert_eq!(ax.state, AxisState::Standstill);
    assert_eq!(ax.status(0).queued, 0);
}

/// Velocity mode reports InVelocity once, with its seq and velocity, when its ramp ends (not
/// before); a move buffered behind it starts in that same report (ContinuousMotion to
/// DiscreteMotion). Velocity mode itself is never done.
#[test]
fn velocity_mode_reports_in_velocity_once_and_starts_the_move_behind_it() {
    let mut ax = powered(0);
    let (lim, rate) = (limits(), rate_hz(TS));
    assert_eq!(
        ax.start_velocity(3, 5000.0, &lim, rate),
        Ok(Some(AxisState::Standstill))
    );
    let ramp = ax.status(0).planned_time;
    let queued = ax.start_move(4, MoveKind::Absolute, 50_000.0, &lim, true, rate);
    assert_eq!(queued, Ok((None, Started::Queued)));
    let (k, report) = run_until(&mut ax, 20_000, |r| r.in_velocity.is_some());
    assert!(
        k as f64 * TS >= ramp - TS,
        "InVelocity after {k} ticks, ramp {ramp} s"
    );
    assert_eq!(report.in_velocity, Some((3, 5000.0)));
    assert_eq!(report.active, Some((4, 50_000.0)));
    assert_eq!(report.done, None);
    assert_eq!(report.state_from, Some(AxisState::ContinuousMotion));
    assert_eq!(ax.state, AxisState::DiscreteMotion);
    let (_, report) = run_until(&mut ax, 100_000, |r| {
        assert_eq!(r.in_velocity, None, "InVelocity twice");
        r.done.is_some()
    });
    assert_eq!(report.done, Some((4, 50_000.0)));
}

/// Homing's searches run in velocity mode without reporting InVelocity or done: homing says
/// itself when it is done (homing.rs).
#[test]
fn homing_velocity_reports_no_in_velocity() {
    let mut ax = powered(0);
    assert_eq!(
        ax.begin_homing(9, Io::empty()),
        Ok(Some(AxisState::Standstill))
    );
    ax.homing_velocity(2000.0, &limits(), rate_hz(TS)).unwrap();
    for _ in 0..3000 {
        let (_, report) = tick_ideal(&mut ax);
        assert_eq!(report, TickReport::default());
    }
    assert_eq!(ax.reference().vel, 2000.0);
    assert_eq!(ax.state, AxisState::Homing);
    assert!(!ax.motion_flags().contains(MotionFlags::IN_VELOCITY));
}

/// MC_Stop: the ramp runs to rest and the stop is done there, but the axis stays in Stopping
/// until the stop is released; the tick after the release leaves it for Standstill.
#[test]
fn a_stop_holds_stopping_until_released() {
    let mut ax = powered(0);
    ax.start_move(
        1,
        MoveKind::Absolute,
        100_000.0,
        &limits(),
        false,
        rate_hz(TS),
    )
    .unwrap();
    for _ in 0..200 {
        tick_ideal(&mut ax);
    }
    assert!(ax.reference().vel > 0.0);
    assert_eq!(
        ax.start_stop(5, true, 2e6, 1e8, 1.0),
        Ok(Some(AxisState::DiscreteMotion))
    );
    let mut done = None;
    for _ in 0..10_000 {
        let (_, report) = tick_ideal(&mut ax);
        assert_eq!(report.state_from, None);
        done = done.or(report.done);
    }
    assert_eq!(ax.state, AxisState::Stopping);
    let r = ax.reference();
    assert_eq!((r.vel, r.acc), (0.0, 0.0));
    assert_eq!(done, Some((5, math::round(r.pos))));
    ax.release_stop().unwrap();
    let (_, report) = tick_ideal(&mut ax);
    assert_eq!(report.state_from, Some(AxisState::Stopping));
    assert_eq!(ax.state, AxisState::Standstill);
}

/// The following error is the reference minus the shaft, every tick, and its peak over the
/// move is kept. With the shaft stalled it grows to the whole move; `control` keeps driving
/// (the output saturates and says so) and trips nothing itself: the following-error stop is
/// the safety layer's, on the error left here.
#[test]
fn following_error_is_the_reference_minus_the_shaft_and_its_peak_is_kept() {
    let mut ax = powered(0);
    ax.start_move(1, MoveKind::Absolute, 1000.0, &limits(), false, rate_hz(TS))
        .unwrap();
    let mut peak: f64 = 0.0;
    for _ in 0..2000 {
        let (_, report) = tick(&mut ax, 0);
        assert_eq!(report, TickReport::default());
        let st = ax.status(0);
        assert_eq!(st.ferr, st.cmd_pos - 0.0);
        assert_eq!(ax.following_error(), st.ferr);
        peak = peak.max(st.ferr.abs());
        assert_eq!(st.max_ferr, peak);
    }
    assert_eq!(peak, 1000.0);
    assert_eq!(ax.state, AxisState::DiscreteMotion);
    assert!(faults(&ax).contains(Faults::DAC_SATURATED));
    assert!(!faults(&ax).contains(Faults::FOLLOWING_ERROR));
}

/// In ErrorStop with the drive powered (a category 1 stop), the servo runs the stop ramp to
/// rest; once power is removed the output is 0 V whatever the error, and the reference follows
/// the shaft.
#[test]
fn error_stop_servoes_its_ramp_while_powered_and_outputs_nothing_unpowered() {
    let mut ax = powered(0);
    ax.start_velocity(1, 5000.0, &limits(), rate_hz(TS))
        .unwrap();
    run_until(&mut ax, 20_000, |r| r.in_velocity.is_some());
    let r = ax.reference();
    let ramp = plan_stop(r.pos, r.vel, r.acc, 5e6, 5e8).unwrap();
    assert_eq!(
        ax.enter_error_stop(Some(ramp)),
        Some(AxisState::ContinuousMotion)
    );
    let (mut prev_vel, mut driven) = (r.vel, false);
    for _ in 0..1000 {
        let (volts, report) = tick_ideal(&mut ax);
        assert_eq!(report, TickReport::default());
        let v = ax.reference().vel;
        assert!(v <= prev_vel && v >= 0.0);
        prev_vel = v;
        driven |= volts != 0.0;
    }
    assert!(driven, "the ramp was not servoed");
    assert_eq!(ax.reference().vel, 0.0);
    assert_eq!(ax.state, AxisState::ErrorStop);
    ax.remove_power();
    let enc = math::round(ax.reference().pos) as i64 + 300;
    let (volts, report) = tick(&mut ax, enc);
    assert_eq!(
        (volts, ax.status(0).dac_v, ax.status(0).ferr),
        (0.0, 0.0, 0.0)
    );
    assert_eq!(report, TickReport::default());
    assert_eq!(ax.reference().pos, enc as f64);
}

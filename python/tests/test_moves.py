"""Point-to-point, velocity and jog moves on the stepped card, against figures computed here."""

from __future__ import annotations

import math

import pytest

import motioncard as mc

# The card's in-position window is a few counts; a move ends within it of its target.
IN_POSITION = 2.0


def scurve_time(d: float, v: float, a: float, j: float) -> float:
    """Duration of a rest-to-rest S-curve move of distance d that reaches both the
    acceleration a (v >= a²/j) and the velocity v (d >= v²/a + v·a/j): d/v + v/a + a/j."""
    assert v >= a * a / j and d >= v * v / a + v * a / j
    return d / v + v / a + a / j


def test_move_absolute_reaches_its_target(card: mc.Card) -> None:
    x = card.axis(0)
    x.enable()
    assert x.status().state == mc.AxisState.STANDSTILL
    reached = x.move_absolute(10_000.0, mc.MoveLimits(50_000.0, 1e6, 5e7)).wait(5.0)
    assert abs(reached - 10_000.0) <= IN_POSITION
    st = x.status()
    assert st.state is mc.AxisState.STANDSTILL
    assert abs(st.position - 10_000.0) <= IN_POSITION
    assert st.command_position == pytest.approx(10_000.0, abs=1e-6)
    assert abs(st.following_error) <= IN_POSITION
    assert st.velocity == pytest.approx(0.0, abs=1.0)


def test_moves_take_the_planned_time(card: mc.Card) -> None:
    """The motion-done event comes the S-curve's duration after the move began (plus the
    settling into the in-position window), on every axis with its own limits."""
    rate = card.info.servo_rate_hz
    cases = [
        (0, 400_000.0, 200_000.0, 2e6, 1e8),
        (1, -300_000.0, 150_000.0, 3e6, 1e8),
        (2, 50_000.0, 25_000.0, 2e5, 2e6),
    ]
    for axis, d, v, a, j in cases:
        ax = card.axis(axis)
        ax.enable()
        t0 = card.tick()
        m = ax.move_relative(d, mc.MoveLimits(v, a, j))
        reached = m.wait(30.0)
        assert abs(reached - d) <= IN_POSITION
        done = [
            e
            for e in card.events(0.0)
            if e.kind == mc.EventKind.MOTION_DONE and e.seq == m.seq
        ]
        assert len(done) == 1 and done[0].axis == axis
        took = (done[0].tick - t0) / rate
        planned = scurve_time(abs(d), v, a, j)
        # begins within a tick or two; settles within 20 ms
        assert planned - 0.001 <= took <= planned + 0.02, (axis, took, planned)


def test_asymmetric_limits_by_keyword(card: mc.Card) -> None:
    lim = mc.MoveLimits(150_000.0, 3e6, 1e8, deceleration=1e6, decel_jerk=2e7)
    assert lim.deceleration == 1e6
    assert lim.jerks == (1e8, 1e8, 2e7, 2e7)
    four = mc.MoveLimits(1.0, 2.0, 3.0, jerks=(4.0, 5.0, 6.0, 7.0))
    assert four.jerks == (4.0, 5.0, 6.0, 7.0)
    x = card.axis(0)
    x.enable()
    reached = x.move_relative(-300_000.0, lim).wait(30.0)
    assert abs(reached + 300_000.0) <= IN_POSITION


def test_scale_user_units(card: mc.Card) -> None:
    x = card.axis(0)
    x.set_scale(1000.0)  # counts per mm
    assert x.scale == 1000.0
    x.enable()
    reached = x.move_absolute(12.5, mc.MoveLimits(100.0, 1000.0, 1e5)).wait(5.0)
    assert abs(reached - 12.5) <= IN_POSITION / 1000.0


def test_velocity_mode_then_halt(card: mc.Card) -> None:
    x = card.axis(0)
    x.enable()
    m = x.move_velocity(20_000.0, 1e6, 5e7)
    v = m.wait_in_velocity(2.0)
    assert v == pytest.approx(20_000.0)
    st = x.status()
    assert st.state == mc.AxisState.CONTINUOUS_MOTION
    assert st.command_velocity == pytest.approx(20_000.0, rel=1e-9)
    # the velocity move never completes: halting it aborts it
    before = x.status().command_position
    h = x.halt(1e6, 5e7)
    with pytest.raises(mc.AbortedError):
        m.wait(1.0)
    at = h.wait(2.0)
    st = x.status()
    assert st.state == mc.AxisState.STANDSTILL
    assert abs(at - st.position) <= IN_POSITION
    # braking from v at deceleration d and jerk j (v = d²/j here): v²/(2d) + v·d/(2j) = 400
    # counts, plus what it ran at v (2 counts a tick) before the card took the halt
    brake = 20_000.0**2 / (2 * 1e6) + 20_000.0 * 1e6 / (2 * 5e7)
    assert brake - 0.01 <= st.command_position - before <= brake + 2 * 2.0 + 0.01


def test_jog_and_release(card: mc.Card, sim: mc.Sim) -> None:
    x = card.axis(0)
    x.enable()
    x.jog(1_000.0)
    sim.step(5_000)
    st = x.status()
    assert st.state == mc.AxisState.CONTINUOUS_MOTION
    assert st.command_velocity == pytest.approx(1_000.0)
    x.jog_release().wait(2.0)
    assert x.status().state == mc.AxisState.STANDSTILL
    assert math.isfinite(x.status().position) and x.status().position > 0


def test_stop_holds_until_released(card: mc.Card, sim: mc.Sim) -> None:
    x = card.axis(0)
    x.enable()
    m = x.move_relative(100_000.0, mc.MoveLimits(50_000.0, 1e6, 5e7))
    sim.step(1_000)
    x.stop(1e6, 5e7).wait(2.0)
    with pytest.raises(mc.AbortedError) as e:
        m.wait(0.1)
    assert e.value.kind == "Aborted"
    assert x.status().state == mc.AxisState.STOPPING
    # refused while stopping
    with pytest.raises(mc.InvalidStateError):
        x.move_relative(10.0, mc.MoveLimits(50_000.0, 1e6, 5e7))
    x.release_stop()
    sim.step(1)
    assert x.status().state == mc.AxisState.STANDSTILL
    x.move_relative(10.0, mc.MoveLimits(50_000.0, 1e6, 5e7)).wait(1.0)


def test_await_a_motion(card: mc.Card) -> None:
    import asyncio

    x = card.axis(0)
    x.enable()

    async def go() -> float:
        return await x.move_absolute(-5_000.0, mc.MoveLimits(50_000.0, 1e6, 5e7))

    reached = asyncio.run(go())
    assert abs(reached + 5_000.0) <= IN_POSITION


def test_rotary_axis_wraps(card: mc.Card) -> None:
    x = card.axis(0)
    x.set_scale(100.0)  # counts per degree
    x.set_modulo(360.0)
    assert x.modulo() == 360.0
    x.enable()
    x.move_relative(400.0, mc.MoveLimits(3_600.0, 36_000.0, 3.6e6)).wait(5.0)
    assert x.status().position == pytest.approx(40.0, abs=0.05)
    with pytest.raises(mc.ModuloZeroError):
        x.set_modulo(0.0)


def test_buffered_and_additive_moves(card: mc.Card) -> None:
    x = card.axis(0)
    x.enable()
    lim = mc.MoveLimits(50_000.0, 1e6, 5e7)
    first = x.move_absolute(5_000.0, lim)
    second = x.move_relative(1_000.0, lim, buffered=True)
    assert second.wait_active(2.0) == pytest.approx(6_000.0)
    # the first ended in position before the buffered one began
    assert abs(first.wait(0.0) - 5_000.0) <= IN_POSITION
    assert abs(second.wait(2.0) - 6_000.0) <= IN_POSITION
    x.move_absolute(7_000.0, lim)
    reached = x.move_additive(500.0, lim).wait(2.0)
    assert abs(reached - 7_500.0) <= IN_POSITION


def test_servo_settings(card: mc.Card) -> None:
    x = card.axis(0)
    s = x.settings()
    assert set(s) >= {"kp", "ki", "kv", "in_pos_window", "jog_max_vel"}
    x.configure(in_pos_window=3.5, kp=s["kp"] * 1.5)
    t = x.settings()
    assert t["in_pos_window"] == 3.5 and t["kp"] == s["kp"] * 1.5
    assert {k: v for k, v in t.items() if k not in ("kp", "in_pos_window")} == {
        k: v for k, v in s.items() if k not in ("kp", "in_pos_window")
    }
    with pytest.raises(mc.BadConfigError):
        x.configure(in_pos_window=-1.0)
    with pytest.raises(TypeError):
        x.configure(gain=1.0)
    assert x.settings() == t

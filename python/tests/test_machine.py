"""Rotary moves with a direction, the handwheel, pitch-error and backlash compensation, on a
stepped card."""

from __future__ import annotations

import pytest

import motioncard as mc

COUNTS_PER_TURN = 10_000.0
SCALE = COUNTS_PER_TURN / 360.0
DEGREES = mc.MoveLimits(720.0, 36_000.0, 3.6e6)
COUNTS = mc.MoveLimits(50_000.0, 1e6, 5e7)


def settle(card: mc.Card, x: mc.Axis) -> float:
    """Step until the commanded position stood still for 100 ticks: it."""
    sim = card.sim
    assert sim is not None
    last, still = float("nan"), 0
    for _ in range(200_000):
        sim.step(1)
        p = x.status().command_position
        still = still + 1 if p == last else 0
        last = p
        if still == 100:
            return p
    raise AssertionError("never came to rest")


def test_rotary_moves_go_the_way_they_name(card: mc.Card) -> None:
    x = card.axis(0)
    x.enable()
    x.set_scale(SCALE)
    x.set_modulo(360.0)
    x.move_absolute(10.0, DEGREES).wait(5.0)
    cases: list[tuple[float, mc.MoveDirection, float]] = [
        (350.0, "shortest", -20.0),
        (340.0, "positive", 350.0),
        (20.0, "negative", -320.0),
        (10.0, "current", -10.0),  # the way it last moved: negative
        (20.0, "current", -350.0),
        (200.0, "shortest", 180.0),  # half a turn: positive
    ]
    for target, direction, way in cases:
        e0 = x.status().encoder
        done = x.move_absolute(target, DEGREES, direction=direction).wait(5.0)
        moved = (x.status().encoder - e0) / SCALE
        assert moved == pytest.approx(way, abs=2.0 / SCALE), (target, direction)
        assert done == pytest.approx(target, abs=2.0 / SCALE)
        assert 0.0 <= x.status().position < 360.0
    with pytest.raises(mc.ModuloMoveError):
        x.move_absolute(360.0, DEGREES)
    with pytest.raises(ValueError):
        x.move_absolute(10.0, DEGREES, direction="sideways")  # type: ignore[arg-type]
    x.clear_modulo()
    with pytest.raises(mc.ModuloMoveError):
        x.move_absolute(10.0, DEGREES, direction="positive")


def test_a_handwheel_detent_moves_the_axis_by_the_ratio(card: mc.Card, sim: mc.Sim) -> None:
    x = card.axis(0)
    x.enable()
    p0 = x.status().command_position
    m = x.handwheel(1, ratio=10)
    assert x.status().state == mc.AxisState.SYNCHRONIZED_MOTION
    sim.jump_aux(1, 28)  # 7 detents of 4 counts, x10
    assert settle(card, x) == p0 + 70.0
    sim.jump_aux(1, -2)  # half a detent: half the ratio
    assert settle(card, x) == p0 + 65.0
    x.handwheel(1, ratio=-100)  # the other way, x100, from the target it has
    sim.jump_aux(1, 8)
    assert settle(card, x) == p0 + 65.0 - 200.0
    # spinning: it follows within the jog limits and stops where the wheel put it
    sim.set_aux_velocity(1, -400.0)
    sim.step(5_000)
    sim.set_aux_velocity(1, 0.0)
    assert settle(card, x) == pytest.approx(p0 + 65.0 - 200.0 + 0.5 * 400 / 4 * 100, abs=100.0)
    x.handwheel_off()
    at = m.wait(5.0)
    assert x.status().state == mc.AxisState.STANDSTILL
    assert at == pytest.approx(x.status().command_position, abs=1.0)
    with pytest.raises(mc.InvalidStateError):
        x.handwheel_off()
    with pytest.raises(mc.HandwheelInputError):
        x.handwheel(99)
    with pytest.raises(mc.HandwheelRatioError):
        x.handwheel(1, ratio=0)


def test_compensation_moves_the_motor_by_the_table(card: mc.Card, sim: mc.Sim) -> None:
    x = card.axis(0)
    x.enable()
    table = mc.Compensation(
        [(0.0, 0.0), (1_000.0, 4.0), (2_000.0, -2.0)],
        backlash=2.0,
        bound=10.0,
        ramp_velocity=2_000.0,
        ramp_acceleration=2e6,
    )
    assert x.compensation() is None
    with pytest.raises(mc.CompOrderError):
        x.set_compensation(mc.Compensation([(0.0, 0.0), (0.0, 1.0)], bound=10.0))
    with pytest.raises(mc.CompBoundError):
        x.set_compensation(mc.Compensation([(0.0, 0.0), (1_000.0, 20.0)], bound=10.0))
    with pytest.raises(ValueError):
        mc.Compensation([(0.0,)], bound=10.0)  # type: ignore[list-item]
    assert x.compensation() is None
    x.set_compensation(table)
    back = x.compensation()
    assert back is not None
    assert back.points == [(0.0, 0.0, 0.0), (1_000.0, 4.0, 4.0), (2_000.0, -2.0, -2.0)]
    assert (back.backlash, back.bound, back.bidirectional) == (2.0, 10.0, False)
    # not homed: not used
    x.move_absolute(500.0, COUNTS).wait(2.0)
    st = x.status()
    assert st.compensated_position == st.command_position == 500.0
    x.set_position(500.0)  # homed here: the table is in force
    # (target, the correction there: the table interpolated, ±backlash/2 by direction)
    for target, correction in [(1_500.0, 1.0 + 1.0), (500.0, 2.0 - 1.0), (1_250.0, 2.5 + 1.0)]:
        x.move_absolute(target, COUNTS).wait(2.0)
        sim.step(200)  # the ramp
        st = x.status()
        assert st.command_position == target
        assert st.compensated_position == pytest.approx(target + correction, abs=1e-9)
        # the load (the encoder less the correction) is where it was sent
        assert st.position == pytest.approx(target, abs=1.5)
    x.clear_compensation()
    sim.step(200)
    st = x.status()
    assert x.compensation() is None and st.compensated_position == st.command_position


def test_the_path_speed_output_follows_the_groups_speed(card: mc.Card, sim: mc.Sim) -> None:
    for a in (0, 1):
        card.axis(a).enable()
    g = card.group(0)
    with pytest.raises(mc.PsoGroupError):
        g.pso(0, gate=3, min=0.0, max=10.0, v_ref=10_000.0)  # not configured
    g.configure([0, 1])
    g.enable()
    assert card.pso_status().state == "off"
    with pytest.raises(mc.PsoConfigError):
        g.pso(0, gate=3, min=0.0, max=10.0, v_ref=-1.0)
    g.pso(0, gate=3, min=0.0, max=10.0, v_ref=10_000.0, filter_hz=200.0)
    s = card.pso_status()
    assert (s.state, s.group, s.output, s.pwm_hz, s.gate) == ("closed", 0, 0, None, 3)
    assert (s.min, s.max, s.v_ref_counts, s.filter_hz, s.value) == (0.0, 10.0, 10_000.0, 200.0, 0.0)
    # the gate closed: nothing while it moves
    m = g.move_linear([20_000.0, 0.0], mc.PathLimits(5_000.0, 1e5, 1e7))
    sim.step(5_000)
    s = card.pso_status()
    assert s.state == "closed" and s.value == 0.0 and s.speed_counts == pytest.approx(5_000.0, rel=0.05)
    m.wait(30.0)
    card.set_output(3, True)
    sim.step(2)
    assert card.pso_status().state == "on"
    # at the feed: min + (max - min)·v/v_ref, v the speed it measured (a 12-bit DAC: 20 V/4096)
    m = g.move_linear([20_000.0 + 30_000.0, 40_000.0], mc.PathLimits(5_000.0, 1e5, 1e7))
    sim.step(5_000)
    s = card.pso_status()
    assert s.speed_counts == pytest.approx(5_000.0, rel=0.05)
    assert s.value == pytest.approx(10.0 * s.speed_counts / 10_000.0, abs=20.0 / 4096)
    m.wait(30.0)
    sim.step(5_000)
    s = card.pso_status()
    assert (s.state, s.speed_counts, s.value) == ("on", 0.0, 0.0)
    card.pso_off()
    assert card.pso_status().state == "off"

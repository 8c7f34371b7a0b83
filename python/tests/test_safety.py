"""The safety configuration: an axis's stop ramp, the e-stop input's category, the longest
stop, and the stop's reason and timing as the card measured them."""

from __future__ import annotations

import math

import pytest

import motioncard as mc

RATE = 10_000  # the sim's servo rate, Hz
V = 50_000.0  # cruise, counts/s
D = 5e5  # the stop's deceleration, counts/s^2
J = 5e7  # the stop's jerk, counts/s^3


def stop_time(v: float, d: float, j: float) -> float:
    """A jerk-limited stop from cruise at ``v``: the ramp reaches ``d`` (when ``v`` allows)."""
    if v >= d * d / j:
        return v / d + d / j
    return 2.0 * math.sqrt(v / j)


def test_settings_round_trip(card: mc.Card) -> None:
    x = card.axis(0)
    default = mc.SafetySettings()
    assert x.safety_settings() == default
    s = default.replace(soft_limits=(-1000.0, 2000.0), limit_stop=2, stop_deceleration=D,
                        stop_jerk=J, ferror=5000.0, max_velocity=2e5)
    assert s.soft_limits == (-1000.0, 2000.0) and s.limit_stop == mc.StopCategory.CAT2
    assert default.soft_limits is None and default.limit_stop == mc.StopCategory.CAT1
    x.configure_safety(s)
    assert x.safety_settings() == s
    # In user units: a scale of 10 counts per unit divides what is read back.
    x.set_scale(10.0)
    back = x.safety_settings()
    assert back.soft_limits == pytest.approx((-100.0, 200.0))
    assert back.stop_deceleration == pytest.approx(D / 10.0)
    x.set_scale(1.0)
    assert x.safety_settings().replace(soft_limits=None).soft_limits is None
    card.set_estop_input_category(0)
    card.set_max_stop_time(1.5)
    c = card.safety_settings()
    assert c.estop_input_category == mc.StopCategory.CAT0
    assert c.max_stop_time == pytest.approx(1.5)


def test_refusals_change_nothing(card: mc.Card) -> None:
    x = card.axis(0)
    before = x.safety_settings()
    with pytest.raises(TypeError):
        mc.SafetySettings(stop_decel=1.0)  # type: ignore[call-arg]
    with pytest.raises(mc.BadCategoryError):
        mc.SafetySettings(limit_stop=3)
    with pytest.raises(mc.BadConfigError):
        x.configure_safety(before.replace(soft_limits=(5.0, -5.0)))
    with pytest.raises(mc.NotFiniteError):
        x.configure_safety(before.replace(ferror=math.nan))
    # 10^6 counts/s (the default max velocity) at 10^5 counts/s^2 takes 10 s: over 2 s.
    with pytest.raises(mc.StopTooLongError):
        x.configure_safety(before.replace(stop_deceleration=1e5))
    assert x.safety_settings() == before
    with pytest.raises(mc.BadCategoryError):
        card.set_estop_input_category(3)
    # The default ramp from 10^6 counts/s takes 0.21 s: a 0.1 s bound cannot hold it.
    with pytest.raises(mc.StopTooLongError):
        card.set_max_stop_time(0.1)
    with pytest.raises(ValueError):
        card.set_max_stop_time(-1.0)
    c = card.safety_settings()
    assert c.estop_input_category == mc.StopCategory.CAT1
    assert c.max_stop_time == pytest.approx(2.0)


def test_estop_input_category_1_stops_within_its_ramp(card: mc.Card, sim: mc.Sim) -> None:
    x = card.axis(0)
    x.configure_safety(x.safety_settings().replace(stop_deceleration=D, stop_jerk=J,
                                                   max_velocity=2e5))
    card.set_estop_input_category(1)
    x.enable()
    m = x.move_relative(1e7, mc.MoveLimits(V, 1e6, 5e7))
    sim.step(2_000)  # at cruise
    s = x.status()
    assert s.command_velocity == pytest.approx(V)
    assert s.stop_reason == mc.StopReason.NONE
    t0 = card.tick()
    p0 = s.command_position
    sim.set_estop(True)
    sim.step(1)
    with pytest.raises(mc.AbortedError):
        m.wait(0.0)
    assert x.status().state == mc.AxisState.ERROR_STOP
    assert card.safety_status().estop_input
    t = stop_time(V, D, J)
    sim.step(int(t * RATE) + 500)
    info = x.stop_info()
    assert info.reason == mc.StopReason.E_STOP_INPUT
    assert x.stop_reason() == mc.StopReason.E_STOP_INPUT
    assert x.status().stop_reason == mc.StopReason.E_STOP_INPUT
    assert t0 <= info.stop_tick <= t0 + 2
    assert info.ramp_time == pytest.approx(t, abs=2.0 / RATE)
    assert info.rest_tick is not None
    # At rest within the configured ramp (plus the settle), not sooner: not a category 0.
    took = info.rest_tick - info.stop_tick
    assert t * RATE - 2 <= took <= t * RATE + 200
    # The ramp's distance: the mean of the velocity over it, V/2, for its duration.
    s = x.status()
    assert s.command_position - p0 == pytest.approx(V * t / 2.0, rel=0.01)
    assert s.command_velocity == 0.0
    # Category 1: the drive is off once at rest.
    assert s.state == mc.AxisState.ERROR_STOP
    with pytest.raises(mc.CauseActiveError):
        card.reset_faults()
    sim.set_estop(False)
    sim.step(1)
    card.reset_faults()
    assert x.status().state == mc.AxisState.DISABLED


def test_estop_input_category_0_cuts_power_at_once(card: mc.Card, sim: mc.Sim) -> None:
    x = card.axis(1)
    card.set_estop_input_category(0)
    x.enable()
    x.move_relative(1e7, mc.MoveLimits(V, 1e6, 5e7))
    sim.step(2_000)
    sim.set_estop(True)
    sim.step(1)
    info = x.stop_info()
    assert info.reason == mc.StopReason.E_STOP_INPUT
    assert info.ramp_time == 0.0
    assert x.status().dac_volts == 0.0

"""Servo tuning on a stepped card: the PID+FF and PD+ laws, the biquad filters on the servo
output (their coefficients checked against their design, computed here), the frequency
response as numpy arrays."""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np
import pytest

import motioncard as mc

LIMITS = mc.MoveLimits(50_000.0, 1e6, 5e7)
RATE = 10_000


def gain_db(coeffs: Sequence[float], hz: float, rate: float = RATE) -> float:
    """|H(e^{jωT})| of a biquad (b0, b1, b2, a1, a2), dB."""
    b0, b1, b2, a1, a2 = coeffs
    z = np.exp(-2j * np.pi * hz / rate)  # z^-1
    h = (b0 + b1 * z + b2 * z * z) / (1.0 + a1 * z + a2 * z * z)
    return float(20.0 * np.log10(abs(h)))


def test_pidff_law_round_trip_refusal_and_back_to_ffpiv(card: mc.Card) -> None:
    x = card.axis(0)
    x.enable()
    assert x.servo_law() == "ffpiv" and x.pidff_settings() is None
    gains = mc.pidff_for_drive(1e6, 2 * math.pi * 60)
    # the placement the SDK documents: kd = wc/A, kp = wc²/(4A), ki = kp·wc/10, kaff = 1/A
    wc = 2 * math.pi * 60
    assert gains["kd"] == pytest.approx(wc / 1e6)
    assert gains["kp"] == pytest.approx(wc * wc / 4e6)
    assert gains["ki"] == pytest.approx(gains["kp"] * wc / 10)
    assert gains["kaff"] == pytest.approx(1e-6)
    # no gains given: the card's default tuning under PID+FF
    x.configure_pidff()
    default = x.pidff_settings()
    assert x.servo_law() == "pidff" and default is not None
    placed = mc.pidff_for_drive(default["kaff"] ** -1, 4 * default["kp"] / default["kd"])
    assert default == pytest.approx(placed, rel=1e-12)
    x.configure_pidff(**gains)
    assert x.pidff_settings() == gains
    # one gain changed, the others stay
    x.configure_pidff(**default)
    x.configure_pidff(friction_deadband=200.0)
    assert x.pidff_settings() == {**default, "friction_deadband": 200.0}
    # refused: nothing changes
    with pytest.raises(mc.PidffGainsError):
        x.configure_pidff(kp=-1.0)
    with pytest.raises(mc.PidffGainsError):
        x.configure_pidff(d_filter_hz=0.0)
    with pytest.raises(TypeError):
        x.configure_pidff(kv=1.0)  # type: ignore[call-arg]
    assert x.pidff_settings() == {**default, "friction_deadband": 200.0}
    # it servos: a move under PID+FF ends on its target, the encoder with it
    assert x.move_absolute(2_000.0, LIMITS).wait(2.0) == 2_000.0
    sim = card.sim
    assert sim is not None
    sim.step(2_000)
    assert abs(x.status().position - 2_000.0) < 5.0
    # FFPIV again through configure
    x.configure(kp=x.settings()["kp"])
    assert x.servo_law() == "ffpiv" and x.pidff_settings() is None


def test_pdplus_law(card: mc.Card) -> None:
    x = card.axis(0)
    s = mc.die_bonder_pdplus(0)
    assert set(s) == {"kp", "kd", "kv", "ka", "kc", "tau", "ke", "umax"}
    with pytest.raises(TypeError, match="missing"):
        x.configure_pdplus(kp=1.0)  # from FFPIV every setting is needed
    assert x.servo_law() == "ffpiv"
    x.configure_pdplus(**s)
    assert x.servo_law() == "pdplus" and x.pdplus_settings() == s
    x.configure_pdplus(umax=5.0)
    assert x.pdplus_settings() == {**s, "umax": 5.0}
    assert x.pidff_settings() is None


def test_servo_filters_are_designed_as_asked(card: mc.Card) -> None:
    x = card.axis(1)
    assert x.servo_filters() == [None] * 4
    x.set_servo_filter(0, mc.ServoFilter.notch(200.0, 0.2, -20.0))
    x.set_servo_filter(2, mc.ServoFilter.low_pass(800.0, 0.7))
    x.set_servo_filter(3, mc.ServoFilter.raw(0.5, 0.5, 0.0, 0.0, 0.0))
    f = x.servo_filters()
    assert f[1] is None
    notch, lp, raw = f[0], f[2], f[3]
    assert notch is not None and lp is not None and raw is not None
    assert (notch.kind, notch.freq_hz, notch.damping, notch.depth_db) == ("notch", 200.0, 0.2, -20.0)
    assert (lp.kind, lp.freq_hz, lp.damping) == ("low_pass", 800.0, 0.7)
    assert notch.coeffs is not None and lp.coeffs is not None
    # the card's design: the notch's depth at its centre, unity at DC; the low-pass's
    # 1/(2ζ) at its corner (prewarped), unity at DC
    assert gain_db(notch.coeffs, 200.0) == pytest.approx(-20.0, abs=1e-6)
    assert gain_db(notch.coeffs, 1e-3) == pytest.approx(0.0, abs=1e-6)
    assert gain_db(lp.coeffs, 800.0) == pytest.approx(20 * math.log10(1 / 1.4), abs=1e-6)
    assert gain_db(lp.coeffs, 1e-3) == pytest.approx(0.0, abs=1e-6)
    assert raw.kind == "raw" and raw.coeffs == (0.5, 0.5, 0.0, 0.0, 0.0)
    # refusals change nothing
    with pytest.raises(mc.FilterKindError):
        x.set_servo_filter(4, mc.ServoFilter.low_pass(100.0, 0.7))
    with pytest.raises(mc.FilterFreqError):
        x.set_servo_filter(1, mc.ServoFilter.notch(RATE / 2 + 1.0, 0.2, -20.0))
    with pytest.raises(mc.FilterParamError):
        x.set_servo_filter(1, mc.ServoFilter.notch(100.0, 0.2, 6.0))
    with pytest.raises(mc.FilterUnstableError):
        x.set_servo_filter(1, mc.ServoFilter.raw(1.0, 0.0, 0.0, 0.0, 1.5))
    assert [g is None for g in x.servo_filters()] == [False, True, False, False]
    x.clear_servo_filter(0)
    assert [g is None for g in x.servo_filters()] == [True, True, False, False]
    x.clear_servo_filter()
    assert x.servo_filters() == [None] * 4


def test_frequency_response_as_numpy_arrays(card: mc.Card) -> None:
    x = card.axis(0)
    with pytest.raises(mc.AxisDisabledError):
        x.frequency_response(points=5, timeout=10.0)
    x.enable()
    with pytest.raises(ValueError):
        x.frequency_response(mode="sideways")  # type: ignore[arg-type]
    with pytest.raises(mc.FreqRangeError):
        x.frequency_response(from_hz=5.0, to_hz=RATE / 2, points=5, timeout=10.0)
    r = x.frequency_response(from_hz=5.0, to_hz=500.0, points=10, amplitude=100.0, timeout=30.0)
    assert (r.mode, r.complete, len(r)) == ("reference", True, 10)
    hz, db, deg = r.response()
    assert all(isinstance(a, np.ndarray) and a.dtype == np.float64 for a in (hz, db, deg))
    # log-spaced, each rounded to whole periods in whole ticks of the measured window
    np.testing.assert_allclose(hz, np.geomspace(5.0, 500.0, 10), rtol=1e-3)
    np.testing.assert_array_equal(hz, r.frequency)
    # the closed loop: follows at 5 Hz (about 0 dB, a little behind), far below it and
    # further behind at 500 Hz
    assert abs(db[0]) < 1.0 and -30.0 < deg[0] <= 0.0
    lag = np.degrees(np.unwrap(np.radians(deg)))
    assert db[-1] < -20.0 and lag[-1] < lag[0] - 90.0
    # the closed loop is the reference mode's response
    for a, b in zip(r.closed_loop(), (hz, db, deg)):
        np.testing.assert_array_equal(a, b)
    # on the servo output: the plant P and the open loop L, from which the closed loop
    # T = P / (1 + L) (position per volt of disturbance) must follow
    o = x.frequency_response(mode="output", from_hz=5.0, to_hz=100.0, points=6, amplitude=0.5, timeout=30.0)
    assert o.mode == "output" and o.complete

    def cplx(c: tuple[np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
        return np.asarray(10 ** (c[1] / 20) * np.exp(1j * np.radians(c[2])))

    p, l, t = cplx(o.plant()), cplx(o.open_loop()), cplx(o.closed_loop())
    np.testing.assert_allclose(t, p / (1 + l), rtol=1e-9)
    # the plant (an integrating motor) falls with frequency, by decades
    assert o.plant()[1][-1] < o.plant()[1][0] - 20.0

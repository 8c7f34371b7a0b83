"""Analog inputs: the ADC's quantisation, the filter against the analytic first-order step
response, the threshold's events on the tick the analytic response crosses it (and back only
past the hysteresis), and every refusal changing nothing."""

from __future__ import annotations

import itertools
import math

import pytest

import motioncard as mc

RATE = 10_000  # the stepped card's servo rate, Hz


def analog_events(card: mc.Card) -> list[mc.Event]:
    return [e for e in card.events(0.0) if e.kind == mc.EventKind.ANALOG]


def quantised(volts: float) -> float:
    """What the 16-bit ADC reads: the nearest step, saturated at -10 V and 10 V - 1 step."""
    code = max(-32768, min(32767, round(volts / mc.ADC_LSB)))
    return code * mc.ADC_LSB


def test_the_adc_quantises_and_saturates(card: mc.Card, sim: mc.Sim) -> None:
    assert mc.ANALOG_INPUTS == 8
    assert mc.ADC_LSB == 20.0 / 65536
    for v in [0.0, 1.0, -2.5, 0.000_15, 0.000_16, 7.3, 12.0, -12.0]:
        sim.set_analog_input(0, v)
        sim.step(1)
        a = card.analog_input_status(0)
        assert a.sample == quantised(v), v
        assert a.value == a.sample  # no filter
        assert card.analog_input(0) == a.value
    with pytest.raises(ValueError):
        sim.set_analog_input(mc.ANALOG_INPUTS, 1.0)


def test_a_threshold_crossing_raises_its_event_on_the_tick(card: mc.Card, sim: mc.Sim) -> None:
    fc = 20.0
    card.configure_analog_input(
        2, cutoff_hz=fc, threshold=3.0, hysteresis=0.5, rise_event=True, fall_event=True
    )
    s = card.analog_input_status(2)
    assert (s.cutoff_hz, s.threshold, s.hysteresis, s.rise_event, s.fall_event) == (
        fc,
        3.0,
        0.5,
        True,
        True,
    )
    assert not s.above
    sim.step(10)
    analog_events(card)
    t0 = card.tick()
    sim.set_analog_input(2, 5.0)
    y = quantised(5.0)
    w = 2 * math.pi * fc / RATE
    first = next(n for n in itertools.count(1) if y * (1 - math.exp(-w * n)) >= 3.0)
    worst = 0.0
    for n in range(1, 1001):
        sim.step(1)
        worst = max(worst, abs(card.analog_input_status(2).value - y * (1 - math.exp(-w * n))))
    assert worst < 1e-12
    rose = analog_events(card)
    assert len(rose) == 1, rose
    e = rose[0]
    assert (e.axis, e.code, e.tick) == (2, 1, t0 + first)
    assert 3.0 <= e.value < 3.0 + y * w  # the value of that tick: over by less than a tick's step
    assert card.analog_input_status(2).above
    # down to 2.8 V: under the threshold but within the hysteresis: no event, still above
    sim.set_analog_input(2, 2.8)
    sim.step(3000)
    assert analog_events(card) == []
    assert card.analog_input_status(2).above
    # down to 2 V: below again at 2.5 V, on the tick the analytic response gets there
    sim.set_analog_input(2, 2.0)
    t1 = card.tick()
    y0 = card.analog_input_status(2).value
    y1 = quantised(2.0)
    down = next(n for n in itertools.count(1) if y1 + (y0 - y1) * math.exp(-w * n) <= 2.5)
    sim.step(3000)
    fell = analog_events(card)
    assert [(e.axis, e.code, e.tick) for e in fell] == [(2, 0, t1 + down)]
    assert not card.analog_input_status(2).above


def test_events_only_where_asked(card: mc.Card, sim: mc.Sim) -> None:
    card.configure_analog_input(4, threshold=1.0, rise_event=False, fall_event=True)
    sim.step(2)
    analog_events(card)
    sim.set_analog_input(4, 2.0)
    sim.step(5)
    assert analog_events(card) == []
    assert card.analog_input_status(4).above
    sim.set_analog_input(4, 0.0)
    sim.step(5)
    assert [(e.axis, e.code) for e in analog_events(card)] == [(4, 0)]


def test_bad_settings_raise_their_kind_and_change_nothing(card: mc.Card, sim: mc.Sim) -> None:
    good = dict(cutoff_hz=100.0, threshold=1.0, hysteresis=0.1, rise_event=True)
    card.configure_analog_input(0, **good)  # type: ignore[arg-type]
    cases: list[tuple[dict[str, float], type[mc.Error]]] = [
        (dict(cutoff_hz=RATE / 2 + 0.5), mc.AnalogFilterError),
        (dict(cutoff_hz=-1.0), mc.AnalogFilterError),
        (dict(threshold=10.5), mc.AnalogThresholdError),
        (dict(hysteresis=-0.1), mc.AnalogThresholdError),
        (dict(threshold=math.nan), mc.NotFiniteError),
    ]
    for change, error in cases:
        with pytest.raises(error):
            card.configure_analog_input(0, **{**good, **change})  # type: ignore[arg-type]
    with pytest.raises(mc.AnalogChannelError):
        card.configure_analog_input(mc.ANALOG_INPUTS, **good)  # type: ignore[arg-type]
    with pytest.raises(mc.AnalogChannelError):
        card.analog_input_status(mc.ANALOG_INPUTS)
    card.configure_analog_input(1, cutoff_hz=RATE / 2)  # Nyquist itself is taken
    sim.step(1)
    s = card.analog_input_status(0)
    assert (s.cutoff_hz, s.threshold, s.hysteresis, s.rise_event, s.fall_event) == (
        100.0,
        1.0,
        0.1,
        True,
        False,
    )

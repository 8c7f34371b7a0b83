"""Compare tables (positions queued, fired in order, the low-water event) and series on every
turn of a rotary axis: each pulse where the emulator's shaft was, within the comparator's
bound, and each refusal its own error kind."""

from __future__ import annotations

import math

import pytest

import motioncard as mc

LIMITS = mc.MoveLimits(50_000.0, 1e6, 5e7)


def test_a_table_fires_each_position_in_order(card: mc.Card, sim: mc.Sim) -> None:
    x = card.axis(0)
    x.enable()
    sim.record_fires(True)
    ch = x.compare(0)
    assert ch.room() == mc.COMPARE_TABLE_LEN and ch.state() == "idle"
    positions = [1_000.0 + 250.0 * k for k in range(30)]  # three entries of the card's 12
    assert ch.push(positions) == mc.COMPARE_TABLE_LEN - 30
    ch.arm_table(4, 2, low_water=5)
    assert ch.state() == "armed"
    x.move_absolute(10_000.0, LIMITS).wait(2.0)
    fires, missed, pending, last = ch.status()
    assert (fires, missed, pending, last) == (30, 0, 0, positions[-1])
    rec = sim.take_fires()
    assert [r.position for r in rec] == positions
    assert all(r.output == 4 and r.channel == 0 for r in rec)
    # Each pulse within a count of the shaft's true position at its instant, in order.
    assert max(abs(r.shaft - r.position) for r in rec) <= 1.0
    assert all(a.time < b.time for a, b in zip(rec, rec[1:]))
    events = [e for e in card.events(0.0) if e.kind == mc.EventKind.COMPARE and e.axis == 0]
    fired = [e.value for e in events if e.code == mc.COMPARE_FIRED]
    assert fired == positions
    low = [e for e in events if e.code == mc.COMPARE_LOW_WATER]
    assert len(low) == 1
    # The refusals: out of order, a table both ways, a full table (nothing of that entry).
    with pytest.raises(mc.CompareOrderError):
        ch.push([20_000.0, 19_000.0])
    with pytest.raises(mc.CompareModeError):
        ch.push([20_000.0], "either")
    assert ch.room() == mc.COMPARE_TABLE_LEN
    far = [20_000.0 + k for k in range(mc.COMPARE_TABLE_LEN)]
    assert ch.push(far) == 0
    with pytest.raises(mc.CompareFullError):
        ch.push([1e6])
    ch.disarm()
    assert ch.room() == mc.COMPARE_TABLE_LEN and ch.state() == "idle"


def test_a_series_on_every_turn_fires_at_each_crossing(card: mc.Card, sim: mc.Sim) -> None:
    turn = 3_600.0  # counts
    x = card.axis(0)
    x.enable()
    x.set_modulo(turn)
    sim.record_fires(True)
    ch = x.compare(1)
    ch.arm_series_each_turn(5, 2, 450.0, 900.0)  # count 0: the whole turn, 4 places
    e0 = float(x.status().encoder)
    x.move_velocity(36_000.0, 1e6, 1e8)  # ten turns a second
    sim.step(2_500)
    x.halt(1e6, 1e8).wait(2.0)
    e1 = float(x.status().encoder)
    assert e1 - e0 > 2 * turn
    places = [450.0 + 900.0 * k for k in range(4)]
    # The crossings of each place between where the axis started and where it stopped.
    expected = sum(math.floor((e1 - q) / turn) - math.floor((e0 - q) / turn) for q in places)
    fires, missed, pending, _ = ch.status()
    assert (fires, missed, pending) == (expected, 0, 4)
    assert ch.state() == "armed"
    rec = sim.take_fires()
    assert len(rec) == expected
    assert {r.position for r in rec} == set(places)
    for r in rec:
        err = (r.shaft - r.position) % turn
        err = err - turn if err >= turn / 2 else err
        assert abs(err) <= 0.5 + 1e-6, "the comparator's bound: half a count"
    with pytest.raises(mc.CompareTurnError):
        card.axis(1).compare(2).arm_series_each_turn(5, 2, 0.0, 900.0)
    with pytest.raises(mc.CompareTurnError):
        x.compare(2).arm_single_each_turn(6, 2, turn + 1.0)

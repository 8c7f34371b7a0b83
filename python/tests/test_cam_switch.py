"""A cam's table switched at the end of its cycle (MC_CamTableSelect): the slave follows the
first table up to the cycle's end, then the second, continuing from where the first left it."""

from __future__ import annotations

import pytest

import motioncard as mc

CYCLE = 10_000.0  # the master's counts per cycle
FIRST = [(0.0, 0.0), (5_000.0, 2_000.0), (CYCLE, 0.0)]
SECOND = [(0.0, 0.0), (5_000.0, -1_000.0), (CYCLE, 0.0)]


def linear(table: list[tuple[float, float]], master: float) -> float:
    """The periodic linear table at `master`."""
    m = master % CYCLE
    for (x0, y0), (x1, y1) in zip(table, table[1:]):
        if x0 <= m <= x1:
            return y0 + (y1 - y0) * (m - x0) / (x1 - x0)
    raise AssertionError(m)


def test_a_cam_switches_tables_at_the_end_of_its_cycle(card: mc.Card, sim: mc.Sim) -> None:
    slave, master = card.axis(0), card.axis(1)
    slave.enable()
    master.enable()
    card.load_cam_table(0, FIRST, periodic=True)
    card.load_cam_table(1, SECOND, periodic=True)
    with pytest.raises(mc.InvalidStateError):
        slave.cam_switch(1, 1, 1e5, 1e6, 1e8)  # not camming yet
    master.move_velocity(10_000.0, 1e5, 1e7).wait_in_velocity(5.0)
    slave.cam_in(1, 0, 1e5, 1e6, 1e8).wait_in_sync(5.0)
    sim.step(2_000)
    assert master.status().command_position < CYCLE - 3_000.0, "the switch is a cycle ahead"
    with pytest.raises(mc.CamTableError):
        slave.cam_switch(1, 5, 1e5, 1e6, 1e8)  # table 5 is not loaded
    sw = slave.cam_switch(1, 1, 1e5, 1e6, 1e8)
    rows = []
    for _ in range(15_000):  # most of a cycle past the switch
        sim.step(1)
        rows.append((slave.status().command_position, master.status().command_position))
    at = sw.wait_cam_switch(1.0)
    # It switched where the first table ends its cycle, continuing the slave from there.
    assert at == pytest.approx(linear(FIRST, CYCLE), abs=1e-6)
    before = [(s, m) for s, m in rows if m < CYCLE]
    after = [(s, m) for s, m in rows if m > CYCLE]
    assert len(before) > 1_000 and len(after) > 5_000
    # The master's command of the same tick: no tick of latency.
    assert max(abs(s - linear(FIRST, m)) for s, m in before) < 1e-6
    assert max(abs(s - (at + linear(SECOND, m) - SECOND[0][1])) for s, m in after) < 1e-6
    with pytest.raises(mc.CamTableError):
        card.load_cam_table(1, SECOND, periodic=True)  # in use

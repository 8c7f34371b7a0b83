"""A gantry on a stepped card: a slave that follows its master tick by tick, refuses commands
of its own, is squared to its offset by the gantry's homing, and is its own axis again once
the gantry is dissolved."""

from __future__ import annotations

import pytest

import motioncard as mc

LIMITS = mc.MoveLimits(50_000.0, 1e6, 5e7)


def test_a_gantry_moves_its_slave_with_its_master(card: mc.Card, sim: mc.Sim) -> None:
    m, s = card.axis(0), card.axis(1)
    m.enable()
    s.enable()
    s.move_absolute(30.0, LIMITS).wait(2.0)  # the slave coupled where it stands: 30 ahead
    with pytest.raises(mc.GantryAxesError):
        card.gantry(0, [0], skew_limit=50.0)
    with pytest.raises(mc.GantryGainsError):
        card.gantry(0, [1], skew_limit=-1.0)
    assert card.gantries() == []
    g = card.gantry(0, [1], skew_limit=50.0, offsets=[5.0])
    st = g.status()
    assert (st.index, st.phase, st.master, st.skew_limit, st.squared) == (g.index, "coupled", 0, 50.0, False)
    [side] = st.slaves
    assert (side.axis, side.offset) == (1, 5.0) and side.hold == pytest.approx(30.0, abs=1.0)
    assert s.status().state == mc.AxisState.SYNCHRONIZED_MOTION
    with pytest.raises(mc.GantrySlaveError):
        s.move_absolute(0.0, LIMITS)
    # the master's move drives the slave: its commanded position is the master's plus 30,
    # tick by tick
    motion = g.master().move_absolute(10_000.0, LIMITS)
    for _ in range(40):
        sim.step(50)
        cm, cs = m.status().command_position, s.status().command_position
        assert cs - cm == pytest.approx(side.hold, abs=1e-9)
    assert motion.wait(2.0) == 10_000.0
    side = g.status().slaves[0]
    assert abs(side.skew) < 2.0 and side.max_skew < 10.0
    # homing: each side homes on the current position (method 37), then the slave squares
    # to its offset: slave - master = 5
    m.configure_homing(37)
    s.configure_homing(37)
    g.home().wait(10.0)
    sim.step(1_000)
    st = g.status()
    assert st.squared and st.phase == "coupled" and st.slaves[0].hold == pytest.approx(5.0)
    assert s.status().position - m.status().position == pytest.approx(5.0, abs=1.0)
    [listed] = card.gantries()
    assert listed.index == g.index and card.gantry_handle(g.index).index == g.index
    g.dissolve()
    assert card.gantries() == []
    with pytest.raises(mc.GantryStateError):
        g.status()
    assert s.status().state == mc.AxisState.STANDSTILL
    s.move_relative(100.0, LIMITS).wait(2.0)  # its own axis again

"""Homing, gearing, camming, PT/PVT streams, compare and touch probes, safety."""

from __future__ import annotations

import pytest

import motioncard as mc

LIMITS = mc.MoveLimits(50_000.0, 1e6, 5e7)


def test_home_on_the_current_position(card: mc.Card) -> None:
    x = card.axis(0)
    x.enable()
    x.move_absolute(1_234.0, LIMITS).wait(2.0)
    assert not x.status().homed
    x.configure_homing(37)
    x.home(10.0).wait(5.0)
    st = x.status()
    assert st.homed and st.position == pytest.approx(10.0, abs=2.0)
    x.set_position(5.0, relative=True)
    assert x.status().position == pytest.approx(15.0, abs=2.0)
    with pytest.raises(mc.HomingMethodError):
        x.configure_homing(99)


def test_gear_follows_its_master(card: mc.Card) -> None:
    master, slave = card.axis(0), card.axis(1)
    master.enable()
    slave.enable()
    g = slave.gear_in(0, 2, 1, 200_000.0, 4e6, 1e9)
    g.wait_in_sync(1.0)
    before = slave.status().command_position
    master.move_relative(1_000.0, LIMITS).wait(2.0)
    st = slave.status()
    assert st.in_sync and st.state == mc.AxisState.SYNCHRONIZED_MOTION
    assert st.command_position - before == pytest.approx(2_000.0, abs=1e-6)
    slave.gear_out()
    with pytest.raises(mc.GearRatioError):
        slave.gear_in(0, 1, 0, 1.0, 1.0, 1.0)
    with pytest.raises(mc.SyncMasterError):
        slave.gear_in(1, 1, 1, 1.0, 1.0, 1.0)


def test_cam_table(card: mc.Card, sim: mc.Sim) -> None:
    card.load_cam_table(0, [(0.0, 0.0), (1_000.0, 500.0), (2_000.0, 0.0)])
    with pytest.raises(mc.CamTableError):
        card.load_cam_table(1, [(0.0, 0.0), (0.0, 1.0)])
    master, slave = card.axis(0), card.axis(1)
    master.enable()
    slave.enable()
    slave.cam_in(0, 0, 200_000.0, 4e6, 1e9).wait_in_sync(1.0)
    master.move_absolute(1_000.0, LIMITS).wait(2.0)
    # linear table: at master 1000 the slave is at 500
    assert slave.status().command_position == pytest.approx(500.0, abs=1e-6)
    master.move_absolute(1_500.0, LIMITS).wait(2.0)
    assert slave.status().command_position == pytest.approx(250.0, abs=1e-6)


def test_pvt_stream_passes_its_points(card: mc.Card) -> None:
    x = card.axis(0)
    x.enable()
    m = x.pvt([(0.1, 500.0, 7_500.0), (0.2, 1_000.0, 0.0)], 20_000.0, 1e6)
    assert abs(m.wait(2.0) - 1_000.0) <= 2.0
    with pytest.raises(mc.PvtTimeError):
        x.pvt([(0.1, 1_100.0, 0.0), (0.05, 1_200.0, 0.0)], 20_000.0, 1e6)
    with pytest.raises(ValueError):
        x.pvt([(0.1, 0.0, 0.0)], 1.0, 1.0, mode="spline")  # type: ignore[arg-type]


def test_compare_fires_at_its_positions(card: mc.Card) -> None:
    x = card.axis(0)
    x.enable()
    c = x.compare(0)
    assert c.channel == 0
    c.arm_series(output=4, pulse_us=100, start=100.0, pitch=100.0, count=5)
    x.move_absolute(1_000.0, LIMITS).wait(2.0)
    fires, missed, pending, last = c.status()
    assert (fires, missed, pending) == (5, 0, 0)
    assert last == pytest.approx(500.0, abs=1.0)
    with pytest.raises(mc.IoChannelError):
        x.compare(99).arm_single(4, 100, 0.0)


def test_probe_latches_the_position(card: mc.Card, sim: mc.Sim) -> None:
    x = card.axis(0)
    x.enable()
    p = x.touch_probe(0)
    p.arm(3)
    x.move_velocity(10_000.0, 1e6, 5e7)
    sim.step(1_000)
    before = x.status().position
    sim.set_input(3, True)
    at = p.wait_capture(1, 1.0)
    now = x.status().position
    # latched between the status before the edge and the one after (within a tick's travel)
    assert before <= at <= now + 1.0
    assert p.positions() == [at]
    x.halt(1e6, 5e7).wait(1.0)
    with pytest.raises(mc.ProbeInputError):
        p.arm(99)


def test_estop_and_reset(card: mc.Card, sim: mc.Sim) -> None:
    x = card.axis(0)
    x.enable()
    card.estop(1)
    s = card.safety_status()
    assert s.estop_command
    assert x.status().state == mc.AxisState.ERROR_STOP
    with pytest.raises(mc.EStopActiveError):
        card.axis(1).enable()
    with pytest.raises(mc.InvalidStateError):
        card.reset_faults()  # not before the stopped axis is at rest
    sim.step(100)
    card.reset_faults()
    assert not card.safety_status().estop_command
    # category 1: the drive was disabled
    assert x.status().state == mc.AxisState.DISABLED
    x.enable()
    x.move_relative(100.0, LIMITS).wait(1.0)

"""A scope capture gives numpy arrays equal to the axis's status at the same ticks."""

from __future__ import annotations

import numpy as np

import motioncard as mc


def test_capture_equals_the_status_at_its_ticks(card: mc.Card, sim: mc.Sim) -> None:
    x = card.axis(0)
    x.enable()
    n = 400
    statuses: dict[int, mc.Status] = {}

    def while_armed() -> None:
        # start a move, then run the card a tick at a time reading the status after each
        x.move_relative(2_000.0, mc.MoveLimits(50_000.0, 1e6, 5e7))
        for _ in range(n + 10):
            sim.step(1)
            st = x.status()
            statuses[st.tick] = st

    cap = card.scope.capture(
        [(mc.Signal.CMD_POS, 0), ("act_pos", 0), ("FERR", 0), (mc.Signal.CMD_VEL, 0)],
        n,
        while_armed=while_armed,
    )
    assert len(cap) == 4
    assert cap.sources == [("cmd_pos", 0), ("act_pos", 0), ("ferr", 0), ("cmd_vel", 0)]
    cmd, act, ferr, vel = cap  # one array per channel
    for a in (cmd, act, ferr, vel, cap.time):
        assert isinstance(a, np.ndarray) and a.dtype == np.float64 and a.shape == (n,)
    assert cap.ticks.dtype == np.uint64 and cap.lost == 0
    # consecutive ticks, the time in seconds from the trigger at the servo rate
    assert np.all(np.diff(cap.ticks.astype(np.int64)) == 1)
    rate = card.info.servo_rate_hz
    expected_time = (cap.ticks.astype(np.float64) - cap.trigger_tick) / rate
    assert np.array_equal(cap.time, expected_time)
    # every sample is the status the card published on that tick (scale 1: counts)
    matched = 0
    for k, tick in enumerate(cap.ticks.tolist()):
        st = statuses.get(tick)
        if st is None:
            continue
        matched += 1
        assert cmd[k] == st.command_position
        assert act[k] == st.position
        assert ferr[k] == st.following_error
        assert vel[k] == st.command_velocity
    assert matched >= n - 2
    # and the move is in it: the commanded position rises from 0 towards 2000
    assert cmd[0] < 1.0 and cmd[-1] > 100.0 and np.all(np.diff(cmd) >= 0)


def test_capture_by_command_trigger_and_channel_indexing(card: mc.Card) -> None:
    scope = card.scope
    cap = scope.capture(
        [("cmd_pos", 1)], 50, divider=2, trigger="command", while_armed=scope.trigger
    )
    assert len(cap) == 1 and cap[0].shape == (50,) and cap[-1] is not None
    assert np.all(np.diff(cap.ticks.astype(np.int64)) == 2)
    assert cap.channels[0].tolist() == cap[0].tolist()


def test_bad_scope_settings(card: mc.Card) -> None:
    import pytest

    with pytest.raises(mc.ScopeSignalError):
        card.scope.capture([("cmd_pos", 50)], 10)
    with pytest.raises(mc.ScopeChannelsError):
        card.scope.capture([], 10)
    with pytest.raises(ValueError):
        card.scope.capture([("no_such_signal", 0)], 10)
    with pytest.raises(ZeroDivisionError):
        card.scope.capture([("cmd_pos", 0)], 10, while_armed=lambda: 1 / 0)

"""Commands timed to a tick on one card (`with card.timed(tick)`): they start on that tick,
not before; with a key all of them or none; each refusal its own error kind."""

from __future__ import annotations

import pytest

import motioncard as mc

RATE = 10_000
LIMITS = mc.MoveLimits(50_000.0, 1e6, 5e7)


def step_to(card: mc.Card, sim: mc.Sim, tick: int) -> None:
    now = card.tick()
    assert now <= tick
    sim.step(tick - now)
    assert card.tick() == tick


def test_a_move_timed_to_a_tick_starts_on_that_tick(card: mc.Card, sim: mc.Sim) -> None:
    x = card.axis(0)
    x.enable()
    t = card.tick() + 200
    with card.timed(t) as s:
        m = x.move_relative(1_000.0, LIMITS)
    assert (s.tick, s.key, s.held, s.ended) == (t, 0, 1, True)
    step_to(card, sim, t - 1)
    st = x.status()
    assert st.state == mc.AxisState.STANDSTILL and st.command_position == 0.0
    sim.step(1)
    st = x.status()
    assert st.state == mc.AxisState.DISCRETE_MOTION
    # One tick of the jerk-limited start: j dt^3 / 6.
    assert st.command_position == pytest.approx(5e7 / RATE**3 / 6, rel=1e-9)
    timed = [e for e in card.events(0.0) if e.kind == mc.EventKind.TIMED]
    assert [(e.seq, e.tick) for e in timed] == [(m.seq, t)]
    s.wait(1.0)
    assert m.wait(1.0) == 1_000.0
    # It ran its profile from the tick: done a planned time (and a settle) after it.
    done = x.status()
    assert done.tick >= t + int(done.planned_time * RATE)


def test_a_key_starts_every_move_on_one_tick_or_none(card: mc.Card, sim: mc.Sim) -> None:
    x, y = card.axis(0), card.axis(1)
    x.enable()
    y.enable()
    t = card.tick() + 100
    with card.timed(t, key=7) as s:
        mx = x.move_relative(1_000.0, LIMITS)
        my = y.move_relative(-500.0, LIMITS)
    assert s.held == 2
    step_to(card, sim, t - 1)
    assert (x.status().command_position, y.status().command_position) == (0.0, 0.0)
    sim.step(1)
    assert x.status().command_position > 0.0 and y.status().command_position < 0.0
    s.wait(1.0)
    assert (mx.wait(1.0), my.wait(1.0)) == (1_000.0, -500.0)
    # Leaving by an exception cancels the key: nothing moves.
    t2 = card.tick() + 100
    with pytest.raises(RuntimeError):
        with card.timed(t2, key=9) as c:
            x.move_relative(1_000.0, LIMITS)
            raise RuntimeError("abandoned")
    before = x.status().command_position
    step_to(card, sim, t2 + 50)
    assert x.status().command_position == before
    with pytest.raises(mc.TimedCancelledError):
        c.wait(1.0)
    # A key never committed: refused on its tick, not run.
    t3 = card.tick() + 100
    s3 = card.timed(t3, key=11)
    x.move_relative(1_000.0, LIMITS)
    assert s3.end() == 1
    with pytest.raises(mc.NotCommittedError):
        s3.wait(1.0)
    assert x.status().command_position == before


def test_refusals(card: mc.Card, sim: mc.Sim) -> None:
    x = card.axis(0)
    x.enable()
    sim.step(10)
    now = card.tick()
    with pytest.raises(mc.TickPassedError):
        with card.timed(now):
            x.move_relative(1_000.0, LIMITS)
    with pytest.raises(mc.TickFarError):
        with card.timed(now + 600_001):
            x.move_relative(1_000.0, LIMITS)
    # The card holds 16 timed commands; the 17th is refused.
    with pytest.raises(mc.TimedFullError):
        with card.timed(now + 1_000, key=5):
            for _ in range(17):
                x.set_override(1.0)
    assert card.cancel_timed(5) == 0, "leaving by the refusal cancelled the 16 held"
    with pytest.raises(mc.CommitLateError):
        card.sync_commit(3, card.tick())
    # The timing ends with the block: a command after it runs at once.
    m = x.move_relative(10.0, LIMITS)
    assert m.wait(1.0) == 10.0

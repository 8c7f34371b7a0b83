"""Several cards on one sync bus (``CardSet``), stepped in this process: commands timed to one
tick with ``with cards.sync()``, a synchronised hold and halt, and a path across cards whose
every axis moves on every tick as the same path split differently over the cards."""

from __future__ import annotations

import pytest

import motioncard as mc

LIMITS = mc.MoveLimits(50_000.0, 1e6, 5e7)
RATE = 10_000


def enabled_set(n: int, axes: int) -> mc.CardSet:
    s = mc.CardSet.sim(n, axes=axes, servo_rate_hz=RATE)
    for c in s.cards:
        for a in range(axes):
            c.axis(a).enable()
    return s


def step(s: mc.CardSet, n: int) -> None:
    sim = s.cards[0].sim
    assert sim is not None
    sim.step(n)


def timed_ticks(card: mc.Card) -> list[int]:
    return [e.tick for e in card.events(timeout=0.0) if e.kind == mc.EventKind.TIMED]


def positions(s: mc.CardSet, axes: int) -> list[float]:
    return [c.axis(a).status().command_position for c in s.cards for a in range(axes)]


def test_the_cards_of_a_set_share_one_clock() -> None:
    s = mc.CardSet.sim(3, axes=2, servo_rate_hz=RATE)
    assert len(s) == 3 and [c.info.axes for c in s.cards] == [2, 2, 2]
    t0 = s.tick()
    step(s, 123)
    assert [c.tick() for c in s.cards] == [t0 + 123] * 3
    with pytest.raises(mc.BadConfigError):
        mc.CardSet.sim(0)


def test_a_synchronised_start_runs_every_move_of_both_cards_on_one_tick() -> None:
    s = enabled_set(2, 4)
    for c in s.cards:
        timed_ticks(c)  # drain the enables' events
    before = s.tick()
    with s.sync() as scope:
        motions = [c.axis(a).move_absolute(5_000.0, LIMITS) for c in s.cards for a in range(4)]
        # held, not run: nothing moved yet
        assert positions(s, 4) == [0.0] * 8
    assert scope.committed and scope.tick > before
    for c in s.cards:
        assert timed_ticks(c) == [scope.tick] * 4
    # tick by tick, every axis of both cards is where every other one is, to the last bit
    trace = []
    while True:
        p = positions(s, 4)
        assert p == [p[0]] * 8, p
        trace.append(p[0])
        if p[0] == 5_000.0:
            break
        step(s, 1)
    assert len(trace) > 50 and 0.0 < trace[0] < trace[1] < 1.0
    assert [m.wait(5.0) for m in motions] == [5_000.0] * 8


def test_a_sync_block_left_by_an_exception_moves_nothing_anywhere() -> None:
    s = enabled_set(2, 2)
    for c in s.cards:
        timed_ticks(c)
    with pytest.raises(RuntimeError):
        with s.sync() as scope:
            for c in s.cards:
                c.axis(0).move_absolute(1_000.0, LIMITS)
            raise RuntimeError("changed my mind")
    assert not scope.committed
    step(s, 2_000)
    assert positions(s, 2) == [0.0] * 4
    for c in s.cards:
        assert timed_ticks(c) == []
        assert c.axis(0).status().state == mc.AxisState.STANDSTILL
    with pytest.raises(mc.InvalidStateError):
        scope.commit()


def test_a_synchronised_hold_and_halt_act_on_every_card() -> None:
    s = enabled_set(2, 1)
    with s.sync():
        for c in s.cards:
            c.axis(0).move_absolute(100_000.0, LIMITS)
    step(s, 500)
    held = s.hold()
    step(s, 3_000)
    a = positions(s, 1)
    step(s, 1_000)
    # held: at rest, still in their motion, both at the same place short of the target
    assert positions(s, 1) == a and a[0] == a[1] and 0.0 < a[0] < 100_000.0
    assert [c.axis(0).status().state for c in s.cards] == [mc.AxisState.DISCRETE_MOTION] * 2
    assert held <= s.tick()
    s.set_override(1.0)
    step(s, 200)
    b = positions(s, 1)
    assert b[0] == b[1] and b[0] > a[0]
    s.halt(1e6, 5e7)
    step(s, 3_000)
    h = positions(s, 1)
    assert h[0] == h[1] and b[0] < h[0] < 100_000.0
    assert [x.axis(0).status().state for x in s.cards] == [mc.AxisState.STANDSTILL] * 2


# --- a path across cards -------------------------------------------------------------------

N = 12


def pt(k: float) -> list[float]:
    return [k * (1_000.0 + 137.0 * d) * (1.0 if d % 2 == 0 else -0.5) for d in range(N)]


def program() -> list[mc.Segment]:
    a, b = pt(1.0), pt(2.0)
    helix = [3.0 * a[d] - 400.0 * d for d in range(2, N)]
    return [
        mc.Segment.line(1, a, 3e4, 5.0),
        mc.Segment.line(2, b, 2e4, 5.0),
        mc.Segment.arc(3, (b[0] + 8_000.0, b[1]), (b[0] + 4_000.0, b[1]), 2.5e4, 2.0, helix=helix),
        mc.Segment.dwell(4, 0.002),
        mc.Segment.line(5, pt(-1.0), 3e4, 0.0),
        mc.Segment.line(6, [0.0] * N, 3e4, 0.0, last=True),
    ]


def settings() -> mc.PathSettings:
    return mc.PathSettings(
        [4e4 + 1e3 * d for d in range(N)],
        [1e6 - 2e4 * d for d in range(N)],
        [1e8] * N,
    )


def run_split(split: list[int]) -> dict[int, list[float]]:
    """The program over cards of 8 axes, card k's group 0 over its first split[k] axes: every
    axis's commanded position every 20 ticks from the start, by tick since the start."""
    s = mc.CardSet.sim(len(split), axes=8, servo_rate_hz=RATE)
    for c, n in zip(s.cards, split):
        for a in range(n):
            c.axis(a).enable()
        g = c.group(0)
        g.configure(list(range(n)))
        g.enable()
    path = s.path([(k, 0) for k in range(len(split))], settings())
    assert path.dims == N
    prog = program()
    # the first two segments, then the rest while it runs
    for seg in prog[:2]:
        path.push(seg)
    assert path.progress().staged == 2
    start = path.release()
    got: dict[int, list[float]] = {}

    def sample() -> None:
        got[s.tick() - start] = [
            c.axis(a).status().command_position for c, n in zip(s.cards, split) for a in range(n)
        ]

    sample()
    for _ in range(10):
        step(s, 20)
        sample()
    assert path.run(prog[2:]) > start
    sample()
    for _ in range(2_000):
        st = [c.group(0).status() for c in s.cards]
        if all(x.state == mc.GroupState.STANDBY and x.queued == 0 for x in st) and got[
            max(got)
        ] == [0.0] * N:
            break
        step(s, 20)
        sample()
    path.wait(5.0)
    pr = path.progress()
    assert (pr.staged, pr.queued, pr.done) == (0, 0, len(prog))
    return got


def test_a_12_axis_path_over_two_cards_moves_as_the_same_path_split_otherwise() -> None:
    six = run_split([6, 6])
    eight = run_split([8, 4])
    # every axis ends exactly on its final target, the origin
    assert six[max(six)] == [0.0] * N and eight[max(eight)] == [0.0] * N
    common = sorted(set(six) & set(eight))
    assert len(common) > 100
    for t in common:
        assert six[t] == eight[t], t
    # and it went somewhere on the way: through pt(2) and the arc
    far = max(max(abs(x) for x in six[t]) for t in common)
    assert far >= max(abs(x) for x in pt(2.0))


def test_what_a_path_across_cards_refuses() -> None:
    s = mc.CardSet.sim(2, axes=8, servo_rate_hz=RATE)
    for c in s.cards:
        for a in range(8):
            c.axis(a).enable()
        c.group(0).configure(list(range(8)))
        c.group(0).enable()
    with pytest.raises(mc.BadConfigError):
        s.path([(2, 0)], mc.PathSettings.uniform(16, 5e4, 1e6, 1e8))
    with pytest.raises(mc.BadConfigError):
        s.path([(0, 0), (0, 0)], mc.PathSettings.uniform(16, 5e4, 1e6, 1e8))
    with pytest.raises(mc.BadAxisError):
        s.path([(0, 0), (1, 0)], mc.PathSettings.uniform(12, 5e4, 1e6, 1e8))
    path = s.path([(0, 0), (1, 0)], mc.PathSettings.uniform(16, 5e4, 1e6, 1e8))
    with pytest.raises(mc.BadAxisError):
        path.push(mc.Segment.line(1, [1.0] * 12, 1e4))
    with pytest.raises(mc.PathZeroLengthError):
        path.push(mc.Segment.line(1, [0.0] * 16, 1e4))
    assert path.progress().staged == 0
    path.push(mc.Segment.line(1, [10.0 * (d + 1) for d in range(16)], 1e4))
    path.release()
    path.wait(5.0)
    assert [c.axis(a).status().command_position for c in s.cards for a in range(8)] == [
        10.0 * (d + 1) for d in range(16)
    ]

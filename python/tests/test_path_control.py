"""A path's control beyond streaming: a pause at a segment's end and the resume, outputs
along the path, Aborting, buffer modes, transitions and the chord fitter's tolerance."""

from __future__ import annotations

import math

import pytest

import motioncard as mc

V, A, J = 1e5, 1e6, 1e8  # every axis's limits, counts
RATE = 10_000  # the sim's servo rate, Hz
SQUARE = [(0.0, 0.0), (50_000.0, 0.0), (50_000.0, 50_000.0), (0.0, 50_000.0), (0.0, 0.0)]


def xy(card: mc.Card) -> mc.Group:
    for a in (0, 1):
        card.axis(a).enable()
    g = card.group(0)
    g.configure([0, 1])
    g.enable()
    g.configure_path(V, A, J)
    return g


def commanded(card: mc.Card) -> tuple[float, float]:
    return (card.axis(0).status().command_position, card.axis(1).status().command_position)


def square(buffer: mc.BufferMode = "blending_low", tolerance: float = 100.0) -> list[mc.Segment]:
    return [
        mc.Segment.line(i, p, 80_000.0, tolerance, last=i == 4).with_buffer(buffer)
        for i, p in enumerate(SQUARE[1:], start=1)
    ]


def run_to_rest(card: mc.Card, sim: mc.Sim, g: mc.Group, every: int = 1) -> list[tuple[float, float]]:
    """Step until the group stops moving: X and Y every `every` ticks."""
    trace = [commanded(card)]
    for _ in range(400_000 // every):
        sim.step(every)
        trace.append(commanded(card))
        if g.status().state != mc.GroupState.MOVING:
            return trace
    raise AssertionError("the path never ended")


def within_limits(trace: list[tuple[float, float]], dt: float) -> None:
    """Every axis's speed between samples `dt` apart at most V (a count of rounding)."""
    for (x0, y0), (x1, y1) in zip(trace, trace[1:]):
        assert abs(x1 - x0) <= V * dt + 1e-6 and abs(y1 - y0) <= V * dt + 1e-6


def ids(events: list[mc.Event], kind: mc.EventKind) -> list[int]:
    return [int(e.value) for e in events if e.kind == kind and e.axis == 0]


def test_segment_options_and_refusals() -> None:
    s = mc.Segment.line(1, (10.0, 0.0), 100.0, 2.0)
    assert s.buffer == "blending_low" and s.transition == ("max_deviation", 2.0)
    assert s.fit_tolerance is None
    t = s.with_buffer("aborting").with_transition("corner_distance", 5.0).fit_within(0.5)
    assert (t.buffer, t.transition, t.fit_tolerance) == ("aborting", ("corner_distance", 5.0), 0.5)
    assert s.buffer == "blending_low", "a copy: the segment itself stays"
    with pytest.raises(ValueError):
        s.with_buffer("blending")  # type: ignore[arg-type]
    with pytest.raises(ValueError):
        s.with_transition("round", 1.0)  # type: ignore[arg-type]
    with pytest.raises(ValueError):
        mc.PathOutput(3, True, at="middle")  # type: ignore[arg-type]
    o = mc.PathOutput(3, True, at=250.0)
    assert (o.output, o.on, o.at) == (3, True, 250.0)
    assert mc.PathOutput(2, False).at == "start"


def test_a_pause_rests_at_a_segment_end_and_a_resume_runs_to_the_end(
    card: mc.Card, sim: mc.Sim
) -> None:
    g = xy(card)
    m = g.stream_path(square())
    assert m is not None
    sim.step(3_000)
    assert g.path_pause_state() == ("none", None)
    g.path_pause()
    assert g.path_pause_state() == ("pausing", None)
    trace = [commanded(card)]
    for _ in range(100_000):
        sim.step(1)
        trace.append(commanded(card))
        if g.path_pause_state()[0] == "paused":
            break
    state, seg = g.path_pause_state()
    assert state == "paused" and seg is not None and 1 <= seg <= 3
    here = commanded(card)
    # At the end of segment `seg`: within the blend's tolerance of its corner.
    cx, cy = SQUARE[seg]
    assert math.hypot(here[0] - cx, here[1] - cy) <= 100.0 + 1e-6
    paused = [e for e in card.events(0.0) if e.kind == mc.EventKind.PATH_PAUSED]
    assert [int(e.value) for e in paused] == [seg]
    # Held there, the rest still queued.
    sim.step(500)
    assert commanded(card) == here
    assert g.status().state == mc.GroupState.MOVING
    g.path_resume()
    assert g.path_pause_state() == ("none", None)
    trace += run_to_rest(card, sim, g)
    m.wait(1.0)
    assert trace[-1] == (0.0, 0.0)
    within_limits(trace, 1.0 / RATE)
    ends = ids(list(card.events(0.0)), mc.EventKind.SEGMENT_END)
    assert ends[-1] == 4


def test_an_output_set_at_a_segment_s_start_is_on_at_that_tick(card: mc.Card, sim: mc.Sim) -> None:
    g = xy(card)
    items: list[mc.Segment | mc.PathOutput] = [
        mc.Segment.line(1, (20_000.0, 0.0), 50_000.0),
        mc.PathOutput(3, True, at="start"),
        mc.Segment.line(2, (20_000.0, 20_000.0), 50_000.0),
        mc.PathOutput(3, False, at=5_000.0),
        mc.Segment.line(3, (0.0, 20_000.0), 50_000.0, last=True),
    ]
    g.stream_path(items)
    on_tick = off_at = None
    for _ in range(100_000):
        sim.step(1)
        out = card.outputs() & (1 << 3)
        if out and on_tick is None:
            on_tick = card.tick()
            on_at = commanded(card)
        if on_tick is not None and not out and off_at is None:
            off_at = commanded(card)
        if g.status().state != mc.GroupState.MOVING:
            break
    assert on_tick is not None and off_at is not None
    starts = {int(e.value): e.tick for e in card.events(0.0)
              if e.kind == mc.EventKind.SEGMENT_START and e.axis == 0}
    assert on_tick == starts[2]
    # An exact stop at the corner (tolerance 0): segment 2 starts from (20000, 0).
    assert on_at[0] == 20_000.0 and on_at[1] == pytest.approx(0.0, abs=V / RATE)
    # Cleared 5000 counts into segment 3 (within a tick's travel).
    assert off_at[1] == 20_000.0 and off_at[0] == pytest.approx(15_000.0, abs=50_000.0 / RATE)


def test_aborting_replaces_the_queue(card: mc.Card, sim: mc.Sim) -> None:
    g = xy(card)
    m = g.stream_path(square())
    assert m is not None
    sim.step(3_000)  # on segment 1 (50000 counts at 80000 counts/s take over 6000 ticks)
    new = g.path_push(
        mc.Segment.line(7, (-10_000.0, -10_000.0), 50_000.0, last=True).with_buffer("aborting")
    )
    assert new is not None
    trace = run_to_rest(card, sim, g)
    new.wait(1.0)
    with pytest.raises(mc.AbortedError):
        m.wait(0.0)
    assert trace[-1] == (-10_000.0, -10_000.0)
    within_limits(trace, 1.0 / RATE)
    events = list(card.events(0.0))
    # Segments 2 to 4 never ran: the Aborting segment replaced them.
    assert ids(events, mc.EventKind.SEGMENT_START) == [1, 7]
    assert any(e.kind == mc.EventKind.GROUP_MOTION_ABORTED for e in events)
    # The stop on segment 1 stayed on its line (y = 0) until segment 7 began.
    assert all(abs(y) < 1e-6 for x, y in trace if x > 0.0 and y >= 0.0)


def test_buffered_stops_exactly_at_each_corner_blending_cuts_it(card: mc.Card, sim: mc.Sim) -> None:
    g = xy(card)

    def nearest(trace: list[tuple[float, float]], corner: tuple[float, float]) -> float:
        return min(math.hypot(x - corner[0], y - corner[1]) for x, y in trace)

    g.stream_path(square("buffered"))
    exact = run_to_rest(card, sim, g)
    g.stream_path(square("blending_low", 100.0))
    blended = run_to_rest(card, sim, g)
    g.stream_path(
        [s.with_transition("corner_distance", 2_000.0) for s in square("blending_low", 0.0)]
    )
    corner = run_to_rest(card, sim, g)
    # The ticks straddle the blend's nearest point: one half a tick's travel (at most
    # V / RATE / 2) along the path from it is at most that squared over twice 100 farther.
    slack = (V / RATE / 2) ** 2 / 200.0
    for c in SQUARE[1:4]:
        assert nearest(exact, c) == 0.0
        # Blended within 100 counts of the corner, never through it.
        assert 0.0 < nearest(blended, c) <= 100.0 + slack
        # A blend begun 2000 counts before the corner passes farther from it than that one.
        assert 100.0 < nearest(corner, c) < 2_000.0


def test_fit_within_zero_sends_each_line_as_it_is(card: mc.Card, sim: mc.Sim) -> None:
    g = xy(card)
    # 100 points on a quarter circle of radius 20000 around (0, 20000), from the origin:
    # chords 314 counts long, 0.6 counts from the circle.
    n = 100
    pts = [(20_000.0 * math.sin(k * math.pi / (2 * n)),
            20_000.0 * (1 - math.cos(k * math.pi / (2 * n))))
           for k in range(1, n + 1)]

    def run(fit: float | None) -> list[int]:
        segs = [mc.Segment.line(i, p, 50_000.0, 10.0, last=i == len(pts))
                for i, p in enumerate(pts, start=1)]
        if fit is not None:
            segs = [s.fit_within(fit) for s in segs]
        g.stream_path(segs)
        run_to_rest(card, sim, g, every=10)
        assert commanded(card) == pts[-1]
        started = ids(list(card.events(0.0)), mc.EventKind.SEGMENT_START)
        g.stream_path([mc.Segment.line(99, (0.0, 0.0), 50_000.0, last=True)])
        run_to_rest(card, sim, g, every=10)
        list(card.events(0.0))
        return started

    assert run(0.0) == list(range(1, n + 1))
    fitted = run(None)
    # The chord fitter sent the run as a curve: fewer segments, the last line's id last.
    assert len(fitted) < n / 2 and fitted[-1] == n

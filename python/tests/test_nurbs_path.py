"""NURBS curves as objects, cut into pieces, and paths of several pieces: where they end, where
they pass, and each bad curve's own error kind."""

from __future__ import annotations

import math

import pytest

import motioncard as mc

FEED = dict(feed=50_000.0, acceleration=1e6, jerk=5e7)


def xy(card: mc.Card) -> mc.Group:
    for a in (0, 1):
        card.axis(a).enable()
    g = card.group(0)
    g.configure([0, 1])
    g.enable()
    return g


def commanded(card: mc.Card) -> tuple[float, float]:
    return (card.axis(0).status().command_position, card.axis(1).status().command_position)


def run_to_rest(card: mc.Card, sim: mc.Sim, g: mc.Group) -> list[tuple[float, float]]:
    """Step the card until the group stops moving: where X and Y were every 10 ticks."""
    trace = []
    for _ in range(100_000):
        sim.step(10)
        trace.append(commanded(card))
        if g.status().state != mc.GroupState.MOVING:
            break
    return trace


def distance_to_polyline(p: list[float], pts: list[tuple[float, float]]) -> float:
    best = math.inf
    for (ax, ay), (bx, by) in zip(pts, pts[1:]):
        dx, dy = bx - ax, by - ay
        L = dx * dx + dy * dy
        t = 0.0 if L == 0.0 else max(0.0, min(1.0, ((p[0] - ax) * dx + (p[1] - ay) * dy) / L))
        best = min(best, math.hypot(ax + t * dx - p[0], ay + t * dy - p[1]))
    return best


def test_a_curve_is_what_it_was_made_of() -> None:
    pts = [[0.0, 0.0], [1000.0, 2000.0], [3000.0, 2000.0], [4000.0, 0.0]]
    c = mc.Nurbs(pts, degree=3)
    assert c.degree == 3
    assert c.control_points == pts
    assert c.weights == [1.0] * 4
    assert c.knots == [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0]
    # a cubic Bézier: at u = 1/2 the point is (P0 + 3 P1 + 3 P2 + P3) / 8
    assert c.point(0.5) == pytest.approx([2000.0, 1500.0], abs=1e-9)
    assert c.point(1.0) == pytest.approx(pts[-1], abs=1e-9)
    with pytest.raises(mc.Error):
        c.point(1.5)


def test_a_bad_curve_raises_its_kind() -> None:
    pts = [[0.0, 0.0], [1.0, 2.0], [3.0, 2.0], [4.0, 0.0], [5.0, 1.0]]
    cases: list[tuple[dict[str, object], type[mc.Error]]] = [
        (dict(knots=[0.0, 0.0, 0.0, 0.7, 0.5, 1.0, 1.0, 1.0]), mc.NurbsKnotsDecreasingError),
        (dict(knots=[0.0, 0.0, 0.2, 0.4, 0.6, 1.0, 1.0, 1.0]), mc.NurbsNotClampedError),
        (dict(knots=[0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0]), mc.NurbsKnotCountError),
        (dict(degree=1, knots=[0.0, 0.0, 0.5, 0.5, 0.7, 1.0, 1.0]), mc.NurbsKnotMultiplicityError),
        (dict(weights=[1.0, 1.0, 0.0, 1.0, 1.0]), mc.NurbsWeightError),
        (dict(degree=6), mc.NurbsDegreeError),
        (dict(degree=5), mc.NurbsCtrlCountError),
    ]
    for kwargs, error in cases:
        args: dict[str, object] = {"degree": 2, **kwargs}
        with pytest.raises(error):
            mc.Nurbs(pts, **args)  # type: ignore[arg-type]
    with pytest.raises(ValueError):
        mc.Nurbs([[0.0, 0.0], [1.0], [2.0, 2.0]], degree=1)


def test_a_split_curve_is_the_curve() -> None:
    n = 40
    pts = [[i * 1000.0, 3000.0 * math.sin(i * 0.4)] for i in range(n)]
    whole = mc.Nurbs.split(pts, degree=3, max_ctrl=1024)
    assert len(whole) == 1
    curve = whole[0]
    pieces = mc.Nurbs.split(pts, degree=3, max_ctrl=6)
    assert len(pieces) > 1
    assert all(len(p.control_points) <= 6 for p in pieces)
    # each piece keeps the curve's parameter: its points are the curve's
    for p in pieces:
        lo, hi = p.knots[0], p.knots[-1]
        for k in range(5):
            u = lo + (hi - lo) * k / 4
            assert p.point(u) == pytest.approx(curve.point(u), abs=1e-6)
    # one after another, each starting where the one before ends
    for a, b in zip(pieces, pieces[1:]):
        assert a.control_points[-1] == pytest.approx(b.control_points[0], abs=1e-9)
    assert pieces[0].control_points[0] == pts[0]
    assert pieces[-1].control_points[-1] == pytest.approx(pts[-1], abs=1e-9)


def test_a_path_of_two_pieces_ends_on_the_last_control_point(card: mc.Card, sim: mc.Sim) -> None:
    g = xy(card)
    first = mc.Nurbs([[0.0, 0.0], [5000.0, 10_000.0], [10_000.0, 10_000.0], [15_000.0, 0.0]])
    second = mc.Nurbs(
        [[15_000.0, 0.0], [20_000.0, -10_000.0], [25_000.0, -10_000.0], [30_000.0, 5_000.0]],
        degree=2,
        knots=[0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0],
    )
    m = g.move_nurbs_path([first, second], **FEED)
    trace = run_to_rest(card, sim, g)
    m.wait(5.0)
    assert commanded(card) == (30_000.0, 5_000.0)
    # it passed both curves' middles (within a count: the feed keeps the chord error there)
    for c in (first, second):
        assert distance_to_polyline(c.point(0.5), trace) < 1.0
    # the second piece did not start before the first ended: the joint is on the way
    assert distance_to_polyline([15_000.0, 0.0], trace) < 1.0


def test_a_long_path_waits_for_room_and_runs_to_its_end(card: mc.Card) -> None:
    g = xy(card)
    n = 200
    pts = [[i * 500.0, 2000.0 * math.sin(i * 0.3)] for i in range(n)]
    pieces = mc.Nurbs.split(pts, degree=3, max_ctrl=4)
    # more pieces than the group's queue holds: move_nurbs_path waits for room
    assert len(pieces) > 64
    m = g.move_nurbs_path(pieces, **FEED, timeout=30.0)
    m.wait(30.0)
    assert commanded(card) == pytest.approx((pts[-1][0], pts[-1][1]), abs=1e-6)
    assert g.status().queued == 0


def test_a_path_that_does_not_join_is_refused_at_the_piece(card: mc.Card, sim: mc.Sim) -> None:
    g = xy(card)
    a = mc.Nurbs([[0.0, 0.0], [1000.0, 1000.0], [2000.0, 0.0]], degree=2)
    b = mc.Nurbs([[2500.0, 0.0], [3000.0, 1000.0], [4000.0, 0.0]], degree=2)
    with pytest.raises(mc.NurbsStartError):
        g.move_nurbs_path([a, b], **FEED)
    # the piece before it was queued and runs to its end
    g.wait_done(5.0)
    assert commanded(card) == (2000.0, 0.0)
    with pytest.raises(mc.UnsupportedError):
        g.move_nurbs_path([], **FEED)
    three = mc.Nurbs([[2000.0, 0.0, 0.0], [3000.0, 1.0, 0.0]], degree=1)
    with pytest.raises(mc.NurbsDimensionError):
        g.move_nurbs_path([three], **FEED)


def test_a_nurbs_segment_between_lines_of_a_path(card: mc.Card, sim: mc.Sim) -> None:
    g = xy(card)
    g.configure_path(60_000.0, 1e6, 5e7)
    # a rational cubic from (20000, 0) with a double knot, ending at (70000, 20000)
    pts = [(0, 0), (10e3, 0), (15e3, 10e3), (25e3, 15e3), (30e3, 5e3), (40e3, 0), (45e3, 10e3), (50e3, 20e3)]
    curve = mc.Nurbs(
        [[20_000.0 + x, y] for x, y in pts],
        weights=[1.0, 1.0, 2.0, 1.0, 0.5, 1.0, 1.0, 1.0],
        knots=[0.0, 0.0, 0.0, 0.0, 0.2, 0.4, 0.4, 0.7, 1.0, 1.0, 1.0, 1.0],
    )
    fit = 1.0
    path = [
        mc.Segment.line(1, [20_000.0, 0.0], 60_000.0),
        mc.Segment.nurbs(2, curve, 60_000.0, fit_tolerance=fit),
        mc.Segment.line(3, [80_000.0, 40_000.0], 60_000.0, last=True),
    ]
    m = g.stream_path(path)
    assert m is not None
    trace = run_to_rest(card, sim, g)
    m.wait(5.0)
    assert commanded(card) == (80_000.0, 40_000.0)
    # the curve's points are on the way, within its fit tolerance (and the chord between
    # samples ten ticks apart)
    for k in range(1, 10):
        assert distance_to_polyline(curve.point(k / 10), trace) < fit + 1.0
    ends = [e.value for e in card.events(0.0) if e.kind == mc.EventKind.SEGMENT_END and e.axis == 0]
    assert ends == [1.0, 2.0, 3.0]

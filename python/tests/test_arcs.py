"""Arcs in every form: by centre, by radius, through a point on them, in any plane, as group
moves and as path segments; each traced tick by tick on the stepped card against the circle
the test computes from the arguments."""

from __future__ import annotations

import math
from typing import Sequence
import pytest

import motioncard as mc

COUNT = 0.001  # mm: the axes run at 1000 counts/mm
LIM = mc.PathLimits(50.0, 500.0, 1e4)


def xyz(card: mc.Card) -> mc.Group:
    for a in range(3):
        ax = card.axis(a)
        ax.set_scale(1000.0)
        ax.enable()
    g = card.group(0)
    # the card's geometry tolerance (radius against chord, centre equidistance): 2 counts
    g.configure([0, 1, 2], tolerance=2 * COUNT)
    g.enable()
    g.configure_path(100.0, 1000.0, 1e5)
    return g


def commanded(card: mc.Card) -> tuple[float, float, float]:
    x, y, z = (card.axis(a).status().command_position for a in range(3))
    return (x, y, z)


def trace(card: mc.Card, sim: mc.Sim, g: mc.Group) -> list[tuple[float, float, float]]:
    """The commanded X, Y, Z of every tick until the group stops moving."""
    pts = []
    for _ in range(200_000):
        sim.step(1)
        pts.append(commanded(card))
        if g.status().state != mc.GroupState.MOVING:
            return pts
    raise AssertionError("the group did not stop")


def distance_to_polyline(p: Sequence[float], pts: Sequence[Sequence[float]]) -> float:
    """The distance from `p` to the polyline through `pts` (points of any dimension)."""
    best = math.inf
    for a, b in zip(pts, pts[1:]):
        d = [bi - ai for ai, bi in zip(a, b)]
        L = sum(x * x for x in d)
        t = 0.0
        if L > 0.0:
            t = max(0.0, min(1.0, sum((pi - ai) * di for pi, ai, di in zip(p, a, d)) / L))
        best = min(best, math.dist(p, [ai + t * di for ai, di in zip(a, d)]))
    return best


def radius_centre(
    start: tuple[float, float], end: tuple[float, float], r: float, ccw: bool
) -> tuple[float, float]:
    """The centre of the arc of radius `r` from `start` to `end` (G-code's rule: the centre on
    the left of the chord for a clockwise arc shorter than half a turn, a negative radius
    the long way round)."""
    mx, my = (start[0] + end[0]) / 2, (start[1] + end[1]) / 2
    dx, dy = end[0] - start[0], end[1] - start[1]
    c = math.hypot(dx, dy)
    h = math.sqrt(max(0.0, r * r - c * c / 4))
    # unit normal to the left of the chord
    nx, ny = -dy / c, dx / c
    side = 1.0 if ccw else -1.0
    if r < 0:
        side = -side
    return (mx + side * h * nx, my + side * h * ny)


# A half circle from (0, 0) to (20, 0): its centre is (10, 0) whichever way it is given;
# counter-clockwise it passes the bottom (10, -10), clockwise the top (10, 10).
HALF = [
    pytest.param(dict(radius=10.0), (10.0, -10.0), id="radius-ccw"),
    pytest.param(dict(radius=10.0, ccw=False), (10.0, 10.0), id="radius-cw"),
    pytest.param(dict(via=(10.0, -10.0)), (10.0, -10.0), id="via-bottom"),
    pytest.param(dict(via=(10.0 + 6.0, 8.0)), (10.0, 10.0), id="via-top"),
    pytest.param(dict(centre=(10.0, 0.0), ccw=False), (10.0, 10.0), id="centre-cw"),
]


@pytest.mark.parametrize("form, apex", HALF)
def test_a_half_circle_in_every_form_stays_on_its_circle(
    card: mc.Card, sim: mc.Sim, form: dict[str, object], apex: tuple[float, float]
) -> None:
    g = xyz(card)
    end = (20.0, 0.0)
    m = g.move_circular(end, limits=LIM, **form)  # type: ignore[call-overload]
    pts = trace(card, sim, g)
    m.wait(5.0)
    centre = (10.0, 0.0)
    worst = max(abs(math.hypot(x - centre[0], y - centre[1]) - 10.0) for x, y, _ in pts)
    assert worst < COUNT / 100, f"off the circle by {worst} mm"
    assert pts[-1][:2] == pytest.approx(end, abs=COUNT / 100)
    xy = [(x, y) for x, y, _ in pts]
    assert distance_to_polyline(apex, xy) < COUNT
    assert all(z == 0.0 for _, _, z in pts)
    via = form.get("via")
    if isinstance(via, tuple):
        assert distance_to_polyline(via, xy) < COUNT


@pytest.mark.parametrize("r, ccw", [(13.0, True), (13.0, False), (-13.0, True), (-13.0, False)])
def test_an_arc_by_radius_turns_around_the_centre_the_geometry_gives(
    card: mc.Card, sim: mc.Sim, r: float, ccw: bool
) -> None:
    g = xyz(card)
    g.move_linear([2.0, 3.0, 0.0], LIM).wait(5.0)
    start, end = (2.0, 3.0), (12.0, -7.0)
    c = radius_centre(start, end, r, ccw)
    m = g.move_circular(end, limits=LIM, radius=r, ccw=ccw)
    pts = trace(card, sim, g)
    m.wait(5.0)
    worst = max(abs(math.hypot(x - c[0], y - c[1]) - abs(r)) for x, y, _ in pts)
    assert worst < COUNT / 100, f"centre {c}: off the circle by {worst} mm"
    assert pts[-1][:2] == pytest.approx(end, abs=COUNT / 100)
    # the swept angle, summed tick by tick: under half a turn for r > 0, over for r < 0,
    # positive counter-clockwise
    swept = 0.0
    for (ax, ay, _), (bx, by, _) in zip(pts, pts[1:]):
        a0 = math.atan2(ay - c[1], ax - c[0])
        a1 = math.atan2(by - c[1], bx - c[0])
        swept += (a1 - a0 + math.pi) % (2 * math.pi) - math.pi
    chord_angle = 2 * math.asin(math.hypot(10.0, 10.0) / 2 / abs(r))
    expected = chord_angle if r > 0 else 2 * math.pi - chord_angle
    assert swept == pytest.approx(expected if ccw else -expected, abs=1e-6)


@pytest.mark.parametrize(
    "plane, end, centre, z_sign",
    [
        # "XZ": (u, v) = (X, Z), counter-clockwise from X towards Z: from X = 0 round through
        # Z = -10 to X = 20
        pytest.param("XZ", (20.0, 0.0), (10.0, 0.0), -1.0, id="XZ"),
        pytest.param((0, 2), (20.0, 0.0), (10.0, 0.0), -1.0, id="axes-0-2"),
        # "ZX" (G18): (u, v) = (Z, X), counter-clockwise from Z towards X: the other way round
        pytest.param("ZX", (0.0, 20.0), (0.0, 10.0), 1.0, id="ZX"),
    ],
)
def test_an_arc_in_the_xz_plane_moves_x_and_z_and_not_y(
    card: mc.Card,
    sim: mc.Sim,
    plane: mc.Plane,
    end: tuple[float, float],
    centre: tuple[float, float],
    z_sign: float,
) -> None:
    g = xyz(card)
    m = g.move_circular(end, centre, LIM, plane=plane)
    pts = trace(card, sim, g)
    m.wait(5.0)
    assert all(y == 0.0 for _, y, _ in pts)
    worst = max(abs(math.hypot(x - 10.0, z) - 10.0) for x, _, z in pts)
    assert worst < COUNT / 100
    assert pts[-1] == pytest.approx((20.0, 0.0, 0.0), abs=COUNT / 100)
    apex = max(pts, key=lambda p: abs(p[2]))
    assert apex[2] == pytest.approx(10.0 * z_sign, abs=COUNT)


def test_an_arc_in_the_yz_plane_and_a_helix(card: mc.Card, sim: mc.Sim) -> None:
    g = xyz(card)
    # YZ (G19): (u, v) = (Y, Z); a quarter turn around (0, 5) from (0, 0) to (5, 5)... with
    # X climbing to 4 along it
    m = g.move_circular((5.0, 5.0), radius=5.0, limits=LIM, plane="YZ", helix=[4.0])
    pts = trace(card, sim, g)
    m.wait(5.0)
    worst = max(abs(math.hypot(y - 0.0, z - 5.0) - 5.0) for _, y, z in pts)
    assert worst < COUNT / 100
    # X climbs linearly with the angle: at each tick X / 4 = angle / (π/2)
    for x, y, z in pts:
        angle = math.atan2(z - 5.0, y) + math.pi / 2
        assert x == pytest.approx(4.0 * angle / (math.pi / 2), abs=COUNT)
    assert pts[-1] == pytest.approx((4.0, 5.0, 5.0), abs=COUNT / 100)


def test_arcs_the_card_refuses_raise_their_kind(card: mc.Card) -> None:
    g = xyz(card)
    with pytest.raises(mc.RadiusTooSmallError):
        g.move_circular((10.0, 0.0), radius=4.0, limits=LIM)
    with pytest.raises(mc.RadiusTooSmallError):
        g.move_circular((0.0, 10.0), radius=-4.99, limits=LIM, plane="ZX")
    with pytest.raises(mc.CollinearPointsError):
        g.move_circular((10.0, 0.0), via=(5.0, 0.0), limits=LIM)
    with pytest.raises(mc.CentreNotEquidistantError):
        g.move_circular((10.0, 0.0), (3.0, 0.0), LIM, plane="XZ")
    with pytest.raises(mc.PlaneAxesError):
        g.move_circular((10.0, 0.0), (5.0, 0.0), LIM, plane=(1, 1))
    with pytest.raises(mc.BadAxisError):
        g.move_circular((10.0, 0.0), (5.0, 0.0), LIM, plane=(0, 3))
    # the binding's own checks: one way to give the arc, a plane it can name
    for bad in [
        dict(centre=(5.0, 0.0), radius=5.0),
        dict(),
        dict(via=(5.0, 5.0), ccw=True),
    ]:
        with pytest.raises(ValueError):
            g.move_circular((10.0, 0.0), limits=LIM, **bad)  # type: ignore[call-overload]
    for plane in ["XX", "XA", "XYZ", ""]:
        with pytest.raises(ValueError):
            g.move_circular((10.0, 0.0), (5.0, 0.0), LIM, plane=plane)
    with pytest.raises(TypeError):
        g.move_circular((10.0, 0.0), radius=5.0)  # type: ignore[call-overload]
    # nothing was queued: the group is where it was, at rest
    assert g.status().state == mc.GroupState.STANDBY
    assert commanded(card) == (0.0, 0.0, 0.0)


def test_a_path_of_arcs_in_every_form(card: mc.Card, sim: mc.Sim) -> None:
    g = xyz(card)
    path = [
        # XY by radius: (0, 0) to (10, 10) a quarter turn around (10, 0)
        mc.Segment.arc(1, (10.0, 10.0), feed=40.0, radius=10.0, ccw=False),
        # ZX through a point: (z, x) from (0, 10) to (0, 30) through (10, 20) (+Z side)
        mc.Segment.arc(2, (0.0, 30.0), feed=40.0, via=(10.0, 20.0), plane="ZX"),
        # XZ around a centre, relative: half a turn clockwise back to X = 10 by the -Z side
        mc.Segment.arc(3, (-20.0, 0.0), (-10.0, 0.0), 40.0, ccw=False, plane="XZ", relative=True),
        # YZ: (y, z) from (10, 0) half a turn by radius to (0, 0), X climbing to 12
        mc.Segment.arc(4, (0.0, 0.0), feed=40.0, radius=5.0, plane="YZ", helix=[12.0], last=True),
    ]
    m = g.stream_path(path)
    assert m is not None
    pts = trace(card, sim, g)
    m.wait(10.0)
    assert pts[-1] == pytest.approx((12.0, 0.0, 0.0), abs=COUNT / 100)
    xz = [(x, z) for x, _, z in pts]
    assert distance_to_polyline((20.0, 10.0), xz) < COUNT  # segment 2's via point
    assert distance_to_polyline((20.0, -10.0), xz) < COUNT  # segment 3's far side
    started = [
        e.value for e in card.events(0.0) if e.kind == mc.EventKind.SEGMENT_START and e.axis == 0
    ]
    assert started == [1.0, 2.0, 3.0, 4.0]


def test_a_path_arc_the_card_refuses_names_its_index(card: mc.Card) -> None:
    g = xyz(card)
    path = [
        mc.Segment.arc(1, (10.0, 10.0), feed=40.0, radius=10.0),
        mc.Segment.arc(2, (30.0, 10.0), feed=40.0, radius=2.0, plane="XY", last=True),
    ]
    with pytest.raises(mc.RadiusTooSmallError) as e:
        g.stream_path(path)
    assert getattr(e.value, "index") == 1
    with pytest.raises(ValueError):
        mc.Segment.arc(3, (1.0, 1.0), (0.0, 1.0), 40.0, radius=1.0)  # type: ignore[call-overload]
    with pytest.raises(TypeError):
        mc.Segment.arc(3, (1.0, 1.0), radius=1.0)  # type: ignore[call-overload]


def cross(a: tuple[float, float, float], b: tuple[float, float, float]) -> tuple[float, float, float]:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_an_arc_about_a_normal_vector_turns_in_its_tilted_plane(
    card: mc.Card, sim: mc.Sim, sign: float
) -> None:
    g = xyz(card)
    # half a turn in the plane through the origin normal to (1, 1, 1), around (5, -5, 0)
    k = 1 / math.sqrt(3)
    n = (sign * k, sign * k, sign * k)
    c = (5.0, -5.0, 0.0)
    r = math.hypot(5.0, 5.0)
    m = g.move_circular_normal((10.0, -10.0, 0.0), c, LIM, normal=(sign, sign, sign))
    pts = trace(card, sim, g)
    m.wait(5.0)
    worst_r = max(abs(math.dist(p, c) - r) for p in pts)
    worst_plane = max(abs(p[0] + p[1] + p[2]) * k for p in pts)
    assert worst_r < COUNT / 100 and worst_plane < COUNT / 100, (worst_r, worst_plane)
    assert pts[-1] == pytest.approx((10.0, -10.0, 0.0), abs=COUNT / 100)
    # a quarter turn counter-clockwise about the normal: the start's radius turned by n ×
    r0 = (-c[0], -c[1], -c[2])
    q = cross(n, r0)
    quarter = (c[0] + q[0], c[1] + q[1], c[2] + q[2])
    assert distance_to_polyline(quarter, pts) < COUNT
    # a full turn more: the same end, the length of three half turns
    ticks = len(pts)
    g.move_linear([0.0, 0.0, 0.0], LIM).wait(5.0)
    m = g.move_circular_normal((10.0, -10.0, 0.0), c, LIM, normal=(sign, sign, sign), turns=1)
    longer = trace(card, sim, g)
    m.wait(5.0)
    assert longer[-1] == pytest.approx((10.0, -10.0, 0.0), abs=COUNT / 100)
    assert len(longer) > 2 * ticks


def test_normal_vector_arcs_the_card_refuses(card: mc.Card) -> None:
    g = xyz(card)
    end, c = (10.0, -10.0, 0.0), (5.0, -5.0, 0.0)
    cases: list[tuple[dict[str, object], type[mc.Error]]] = [
        (dict(normal=(0.0, 0.0, 0.0)), mc.ArcNormalError),
        (dict(normal=(1.0, 1.0, 1.0), axes=(0, 1, 1)), mc.ArcAxesError),
        (dict(normal=(1.0, 1.0, 1.0), axes=(0, 1, 3)), mc.BadAxisError),
    ]
    for kwargs, error in cases:
        with pytest.raises(error):
            g.move_circular_normal(end, c, LIM, **kwargs)  # type: ignore[arg-type]
    with pytest.raises(mc.ArcOffPlaneError):
        g.move_circular_normal(end, (5.0, -5.0, 1.0), LIM, normal=(1.0, 1.0, 1.0))
    with pytest.raises(mc.CentreNotEquidistantError):
        g.move_circular_normal((10.0, -9.0, -1.0), c, LIM, normal=(1.0, 1.0, 1.0))
    assert g.status().state == mc.GroupState.STANDBY
    assert commanded(card) == (0.0, 0.0, 0.0)


def test_a_path_arc_about_a_normal_vector(card: mc.Card, sim: mc.Sim) -> None:
    g = xyz(card)
    path = [
        mc.Segment.arc_normal(2, (10.0, -10.0, 0.0), (5.0, -5.0, 0.0), 40.0, normal=(1.0, 1.0, 1.0)),
        mc.Segment.arc_normal(
            3, (-10.0, 10.0, 0.0), (-5.0, 5.0, 0.0), 40.0, normal=(0.0, 0.0, 1.0),
            relative=True, last=True,
        ),
    ]
    m = g.stream_path(path)
    assert m is not None
    pts = trace(card, sim, g)
    m.wait(10.0)
    assert pts[-1] == pytest.approx((0.0, 0.0, 0.0), abs=COUNT / 100)
    k = 1 / math.sqrt(3)
    quarter = (5.0 - 5.0 * k, -5.0 - 5.0 * k, 10.0 * k)
    assert distance_to_polyline(quarter, pts) < COUNT
    # the second, in XY counter-clockwise from (10, -10) around (5, -5): by (10, 0)
    assert distance_to_polyline((10.0, 0.0, 0.0), pts) < COUNT


@pytest.mark.parametrize("as_segment", [False, True], ids=["move", "segment"])
def test_a_rise_along_the_normal_is_a_helix(card: mc.Card, sim: mc.Sim, as_segment: bool) -> None:
    g = xyz(card)
    # a full turn about +Z around (5, 0, 0), rising 4 along the normal
    end, c = (0.0, 0.0, 4.0), (5.0, 0.0, 0.0)
    if as_segment:
        seg = mc.Segment.arc_normal(1, end, c, 40.0, normal=(0.0, 0.0, 1.0), rise=True, last=True)
        m = g.stream_path([seg])
        assert m is not None
    else:
        m = g.move_circular_normal(end, c, LIM, normal=(0.0, 0.0, 1.0), rise=True)
    pts = trace(card, sim, g)
    m.wait(10.0)
    assert pts[-1] == pytest.approx(end, abs=COUNT / 100)
    assert max(abs(math.hypot(x - 5.0, y) - 5.0) for x, y, _ in pts) < COUNT / 100
    # Z climbs with the angle swept about +Z (counter-clockwise: from π on through 3π/2)
    for x, y, z in pts:
        swept = (math.atan2(y, x - 5.0) - math.pi) % (2 * math.pi)
        if z > 0.1 and z < 3.9:
            assert z == pytest.approx(4.0 * swept / (2 * math.pi), abs=COUNT)
    assert distance_to_polyline((5.0, -5.0, 1.0), pts) < COUNT


def test_arcs_by_radius_and_through_a_point_on_a_path_across_two_cards() -> None:
    # two cards of 4 axes, their groups the path's 8 dimensions (counts): card 1's axis a is
    # dimension 4 + a
    s = mc.CardSet.sim(2, axes=4, servo_rate_hz=10_000)
    for c in s.cards:
        for a in range(4):
            c.axis(a).enable()
        c.group(0).configure([0, 1, 2, 3], tolerance=2.0)
        c.group(0).enable()
    path = s.path([(0, 0), (1, 0)], mc.PathSettings.uniform(8, 5e4, 1e6, 1e8))
    program = [
        # dimensions 1 and 5, one on each card: half a turn by radius, below the chord
        mc.Segment.arc(1, (20_000.0, 0.0), feed=2e4, radius=10_000.0, plane=(1, 5)),
        # "ZX": (z, x) = dimensions (2, 0), through (10000, 10000) to (0, 20000)
        mc.Segment.arc(2, (0.0, 20_000.0), feed=2e4, via=(10_000.0, 10_000.0), plane="ZX", last=True),
    ]
    sim = s.cards[0].sim
    assert sim is not None

    def dims() -> list[float]:
        return [c.axis(a).status().command_position for c in s.cards for a in range(4)]

    path.run(program)
    pts = [dims()]
    for _ in range(100_000):
        sim.step(5)
        pts.append(dims())
        if path.progress().done == len(program):
            break
    path.wait(5.0)
    assert dims() == pytest.approx([20_000.0, 20_000.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], abs=1e-6)
    d15 = [(p[1], p[5]) for p in pts]
    assert max(abs(math.hypot(u - 10_000.0, v) - 10_000.0) for u, v in d15[: len(d15) // 2]) < 1e-3
    assert distance_to_polyline((10_000.0, -10_000.0), d15) < 1.0
    d20 = [(p[2], p[0]) for p in pts]
    assert distance_to_polyline((10_000.0, 10_000.0), d20) < 1.0
    assert all(p[3] == 0.0 and p[4] == 0.0 and p[6] == 0.0 and p[7] == 0.0 for p in pts)

"""Groups: coordinated lines, arcs and G-code, ending where they were sent."""

from __future__ import annotations

import math

import pytest

import motioncard as mc

TOL = 0.005  # mm: 5 counts at 1000 counts/mm


def xyz(card: mc.Card) -> mc.Group:
    for a in range(3):
        ax = card.axis(a)
        ax.set_scale(1000.0)
        ax.enable()
    g = card.group(0)
    g.configure([0, 1, 2])
    g.enable()
    g.configure_path(100.0, 1000.0, 1e5)
    return g


def positions(card: mc.Card) -> list[float]:
    return [card.axis(a).status().position for a in range(3)]


def test_line_and_arc(card: mc.Card) -> None:
    g = xyz(card)
    assert g.axes() == [0, 1, 2]
    lim = mc.PathLimits(50.0, 500.0, 1e4)
    g.move_linear([10.0, 5.0, -2.0], lim).wait(10.0)
    assert positions(card) == pytest.approx([10.0, 5.0, -2.0], abs=TOL)
    assert g.status().state == mc.GroupState.STANDBY
    # a half circle around (10, 0) from (10, 5) to (10, -5), then a relative line, queued
    g.move_circular((10.0, -5.0), (10.0, 0.0), lim, ccw=True, buffered=True)
    g.move_linear([1.0, 1.0, 1.0], lim, relative=True, buffered=True)
    g.wait_done(20.0)
    assert positions(card) == pytest.approx([11.0, -4.0, -1.0], abs=TOL)


def test_ptp_and_await(card: mc.Card) -> None:
    import asyncio

    g = xyz(card)

    async def go() -> None:
        await g.move_ptp([3.0, 4.0, 0.0], mc.PathLimits(50.0, 500.0, 1e4))

    asyncio.run(go())
    assert positions(card) == pytest.approx([3.0, 4.0, 0.0], abs=TOL)


def test_gcode_program_runs_to_its_end(card: mc.Card) -> None:
    g = xyz(card)
    program = """
        G21 G90 G17
        G0 X5 Y0
        G1 X5 Y5 F600
        G2 X10 Y10 I5 J0
        G1 Z-1
        M2
    """
    assert g.run_gcode(program, timeout=60.0) == "done"
    assert positions(card) == pytest.approx([10.0, 10.0, -1.0], abs=TOL)
    # the arc's centre (10, 5): the radius is 5 at its end
    x, y, _ = positions(card)
    assert math.hypot(x - 10.0, y - 5.0) == pytest.approx(5.0, abs=TOL)


def test_stream_a_path(card: mc.Card) -> None:
    g = xyz(card)
    square = [
        mc.Segment.line(1, [10.0, 0.0, 0.0], 50.0, 0.01),
        mc.Segment.line(2, [10.0, 10.0, 0.0], 50.0, 0.01),
        mc.Segment.arc(3, (0.0, 10.0), (5.0, 10.0), 50.0, 0.01),
        mc.Segment.dwell(4, 0.05),
        mc.Segment.line(5, [-1.0, -10.0, 2.0], 50.0, 0.0, relative=True, last=True),
    ]
    assert [s.id for s in square] == [1, 2, 3, 4, 5]
    m = g.stream_path(square)
    assert m is not None
    m.wait(30.0)
    assert positions(card) == pytest.approx([-1.0, 0.0, 2.0], abs=TOL)
    started = [
        e.value for e in card.events(0.0) if e.kind == mc.EventKind.SEGMENT_START and e.axis == 0
    ]
    assert started == [1.0, 2.0, 3.0, 4.0, 5.0]


def test_a_refused_segment_names_its_index(card: mc.Card) -> None:
    g = xyz(card)
    bad = [
        mc.Segment.line(1, [1.0, 0.0, 0.0], 50.0),
        mc.Segment.line(2, [1.0, float("nan"), 0.0], 50.0),
    ]
    with pytest.raises(mc.NotFiniteError) as e:
        g.stream_path(bad)
    assert getattr(e.value, "index") == 1


def test_group_homing_runs_its_stages_in_order() -> None:
    with mc.Card.open_sim(axes=3) as card:
        for a in range(3):
            card.axis(a).enable()
            card.axis(a).configure_homing(37)  # on the current position: one stage's time
        g = card.group(0)
        g.configure([0, 1, 2])
        g.enable()
        for bad, error in [
            ([[3]], mc.HomeAxisError),
            ([[0], [0, 1]], mc.HomeTwiceError),
            ([[2], []], mc.HomeStageError),
        ]:
            with pytest.raises(error):
                g.home(bad)
        while card.next_event(0.0) is not None:
            pass
        h = g.home([[2], [0, 1]])  # Z first, then X and Y together
        assert h.wait(5.0) == 2
        done = {
            e.axis: e.tick
            for e in card.events(timeout=0.0)
            if e.kind == mc.EventKind.MOTION_DONE and e.seq == h.seq
        }
        assert done[2] < done[0] == done[1]
        assert all(card.axis(a).status().homed for a in range(3))
        assert g.status().state == mc.GroupState.STANDBY


def test_a_nurbs_quarter_circle_is_followed_on_the_circle(card: mc.Card, sim: mc.Sim) -> None:
    for a in (0, 1):
        card.axis(a).enable()
    g = card.group(0)
    g.configure([0, 1])
    g.enable()
    r = 10_000.0
    g.move_linear([r, 0.0], mc.PathLimits(50_000.0, 1e6, 5e7)).wait(5.0)
    # the exact rational quadratic quarter circle: weights 1, √2/2, 1
    m = g.move_nurbs(
        [[r, 0.0], [r, r], [0.0, r]],
        degree=2,
        weights=[1.0, math.sqrt(0.5), 1.0],
        feed=20_000.0,
        acceleration=1e6,
        jerk=5e7,
    )
    samples = 0
    while True:
        sim.step(20)
        x, y = (card.axis(a).status().command_position for a in (0, 1))
        assert math.hypot(x, y) == pytest.approx(r, abs=1e-6), (x, y)
        samples += 1
        if (x, y) == (0.0, r):
            break
        assert samples < 5_000
    # a quarter turn of 10,000 at 20,000/s: about 0.79 s, 400 samples of 20 ticks
    assert samples > 300
    m.wait(5.0)
    with pytest.raises(mc.NurbsCtrlCountError):
        g.move_nurbs([[0.0, r], [1.0, 2.0]], degree=3, feed=1e4, acceleration=1e6, jerk=1e8)
    with pytest.raises(mc.NurbsWeightError):
        g.move_nurbs([[0.0, r], [1.0, 2.0], [3.0, 4.0]], degree=2, weights=[1.0, -1.0, 1.0], feed=1e4, acceleration=1e6, jerk=1e8)
    with pytest.raises(mc.NurbsStartError):
        g.move_nurbs([[5.0, r], [1.0, 2.0], [3.0, 4.0]], degree=2, feed=1e4, acceleration=1e6, jerk=1e8)
    with pytest.raises(ValueError):
        g.move_nurbs([[0.0, r], [1.0]], degree=1, feed=1e4, acceleration=1e6, jerk=1e8)
    assert (card.axis(0).status().command_position, card.axis(1).status().command_position) == (0.0, r)

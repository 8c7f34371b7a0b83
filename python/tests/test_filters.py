"""The post-interpolation acc/dec filters (Shin): a group with `accdec="post"` runs its line at
constant feed and each axis's filter of the move's feed type shapes it: a moving average of
`tau` ramps the velocity over `tau`, so the move takes L/F + tau and accelerates at F/tau."""

from __future__ import annotations

import math

import pytest

import motioncard as mc

RATE = 10_000
F = 50_000.0  # feed, counts/s
L = 10_000.0  # the line, counts


def line(
    card: mc.Card, sim: mc.Sim, g: mc.Group, target: list[float], feed_type: mc.FeedType
) -> list[float]:
    """X's commanded position every tick of the line, from where it stands to rest."""
    x = card.axis(0)
    m = g.move_linear(target, mc.PathLimits(F, 1e6, 1e8), feed_type=feed_type)
    xs = [x.status().command_position]
    for _ in range(4_000):
        sim.step(1)
        xs.append(x.status().command_position)
    m.wait(1.0)
    return xs


def shape(xs: list[float]) -> tuple[int, float]:
    """(ticks the axis moved, its peak |acceleration| counts/s^2)."""
    moving = [i for i in range(1, len(xs)) if xs[i] != xs[i - 1]]
    v = [(b - a) * RATE for a, b in zip(xs, xs[1:])]
    acc = max(abs(b - a) * RATE for a, b in zip(v, v[1:]))
    return moving[-1] - moving[0] + 1, acc


def test_each_feed_type_runs_its_own_filter(card: mc.Card, sim: mc.Sim) -> None:
    x, y = card.axis(0), card.axis(1)
    for a in (x, y):
        a.enable()
        a.set_filters(cutting=("linear", 0.02), rapid=("linear", 0.05))
    f = x.filter_settings()
    assert f["cutting"][0] == "linear" and f["cutting"][1] == pytest.approx(0.02)
    assert f["rapid"][0] == "linear" and f["rapid"][1] == pytest.approx(0.05)
    assert f["jog"][0] == "exponential", "the one not given stays"
    g = card.group(0)
    g.configure([0, 1], accdec="post")
    g.enable()
    runs: list[tuple[list[float], mc.FeedType, float]] = [
        ([L, 0.0], "cutting", 0.02),
        ([0.0, 0.0], "rapid", 0.05),
    ]
    for target, feed_type, tau in runs:
        xs = line(card, sim, g, target, feed_type)
        ticks, acc = shape(xs)
        assert xs[-1] == target[0]
        assert abs(ticks - (L / F + tau) * RATE) <= 2, (feed_type, ticks)
        assert acc == pytest.approx(F / tau, rel=1e-3), feed_type


def test_bad_filters_are_refused_and_change_nothing(card: mc.Card) -> None:
    x = card.axis(0)
    before = x.filter_settings()
    with pytest.raises(ValueError):
        x.set_filters(cutting=("gauss", 0.03))  # type: ignore[arg-type]
    with pytest.raises(mc.NotFiniteError):
        x.set_filters(cutting=("linear", math.nan))
    with pytest.raises(mc.BadConfigError):
        x.set_filters(cutting=("linear", -1.0))
    assert x.filter_settings() == before
    with pytest.raises(ValueError):
        card.group(0).configure([0, 1], accdec="late")  # type: ignore[arg-type]

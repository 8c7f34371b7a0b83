"""Every test runs on a stepped emulated card (time advances only when the test steps it or
waits), so the figures are the same on any machine, however loaded."""

from __future__ import annotations

from typing import Iterator

import pytest

import motioncard as mc


@pytest.fixture
def card() -> Iterator[mc.Card]:
    with mc.Card.open_sim("stepped") as c:
        yield c


@pytest.fixture
def sim(card: mc.Card) -> mc.Sim:
    s = card.sim
    assert s is not None
    return s

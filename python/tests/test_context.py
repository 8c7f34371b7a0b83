"""Cards are context managers: leaving the block closes the card."""

from __future__ import annotations

import pytest

import motioncard as mc


def test_with_closes() -> None:
    with mc.Card.open_sim() as card:
        x = card.axis(0)
        x.enable()
        x.move_relative(1_000.0, mc.MoveLimits(50_000.0, 1e6, 5e7)).wait(1.0)
    with pytest.raises(mc.ClosedError):
        x.status()
    with pytest.raises(mc.ClosedError):
        card.tick()


def test_with_closes_on_an_exception_and_lets_it_through() -> None:
    with pytest.raises(KeyError):
        with mc.Card.open_sim() as card:
            raise KeyError("inside")
    with pytest.raises(mc.ClosedError):
        card.ping()


def test_close_ends_a_wait_in_another_thread() -> None:
    import threading

    with mc.Card.open_sim("realtime") as card:
        x = card.axis(0)
        x.enable()
        m = x.move_velocity(1_000.0, 1e5, 1e7)
        got: list[BaseException] = []

        def waiter() -> None:
            try:
                m.wait(30.0)
            except mc.Error as e:
                got.append(e)

        t = threading.Thread(target=waiter)
        t.start()
        card.tick()
        card.close()
        t.join(10.0)
        assert not t.is_alive()
        assert len(got) == 1 and isinstance(got[0], (mc.ClosedError, mc.AbortedError))


def test_a_realtime_sim_reopens_after_close() -> None:
    for _ in range(2):
        with mc.Card.open("sim") as card:
            assert card.info.axes == 8
            card.ping()

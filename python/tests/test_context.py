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


def test_open_sim_options() -> None:
    with mc.Card.open_sim("stepped", axes=3, servo_rate_hz=5_000) as card:
        assert card.info.axes == 3 and card.info.servo_rate_hz == 5_000
        assert card.uri == "sim"
        sim = card.sim
        assert sim is not None
        t0 = sim.time
        sim.step(500)
        assert sim.time - t0 == pytest.approx(0.1)
        with pytest.raises(mc.BadAxisError):
            card.axis(3)
    with mc.Card.open_sim("realtime") as card:
        assert card.sim is None
    with pytest.raises(ValueError):
        mc.Card.open_sim("sundial")  # type: ignore[arg-type]
    with pytest.raises(mc.BadConfigError):
        mc.Card.open_sim(axes=0)

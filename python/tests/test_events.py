"""Events: an iterator with a timeout, and awaitable from asyncio."""

from __future__ import annotations

import asyncio

import pytest

import motioncard as mc

LIMITS = mc.MoveLimits(50_000.0, 1e6, 5e7)


def drain(card: mc.Card) -> None:
    while card.next_event(0.0) is not None:
        pass


def test_events_iterate_until_none_comes(card: mc.Card) -> None:
    x = card.axis(0)
    x.enable()
    drain(card)
    m = x.move_absolute(3_000.0, LIMITS)
    got = list(card.events(0.5))  # ends 0.5 s (emulated) after the last one
    done = [e for e in got if e.kind == mc.EventKind.MOTION_DONE]
    assert len(done) == 1
    assert done[0].seq == m.seq and done[0].axis == 0
    assert abs(done[0].value - 3_000.0) <= 2.0
    states = [mc.AxisState(e.code) for e in got if e.kind == mc.EventKind.STATE_CHANGED]
    assert states == [mc.AxisState.DISCRETE_MOTION, mc.AxisState.STANDSTILL]
    ticks = [e.tick for e in got]
    assert ticks == sorted(ticks)
    assert card.next_event(0.0) is None


def test_inputs_and_outputs(card: mc.Card, sim: mc.Sim) -> None:
    card.configure_io(rise_events=1 << 5, debounce=[10] * mc.INPUTS)
    drain(card)
    assert card.inputs() & (1 << 5) == 0
    sim.set_input(5, True)
    sim.step(5)
    assert card.inputs() & (1 << 5) == 0  # not yet: debounced over 10 ticks
    sim.step(100)
    assert card.inputs() & (1 << 5)
    edges = [e for e in card.events(0.0) if e.kind == mc.EventKind.INPUT]
    assert [(e.axis, e.code) for e in edges] == [(5, 1)]
    with pytest.raises(ValueError):
        card.configure_io(debounce=[1, 2])
    card.set_output(3, True)
    card.set_outputs(0b110000, 0b100000)
    assert card.outputs() & 0b111000 == 0b101000
    card.set_output(3, False)
    assert card.outputs() & 0b1000 == 0


def test_events_from_asyncio(card: mc.Card) -> None:
    x = card.axis(0)
    x.enable()
    drain(card)

    async def main() -> tuple[float, list[mc.Event], list[mc.Event]]:
        m = x.move_absolute(-2_000.0, LIMITS)
        reached = await m
        first = await mc.next_event_async(card, 1.0)
        assert first is not None
        rest = [e async for e in card.events(0.2)]
        none = await mc.next_event_async(card, 0.1)
        assert none is None
        m2 = x.move_absolute(0.0, LIMITS)
        more = [e async for e in mc.events_async(card, 0.5)]
        assert any(e.kind == mc.EventKind.MOTION_DONE and e.seq == m2.seq for e in more)
        return reached, [first, *rest], more

    reached, got, _ = asyncio.run(main())
    assert abs(reached + 2_000.0) <= 2.0
    kinds = [e.kind for e in got]
    assert mc.EventKind.MOTION_DONE in kinds


def test_an_asyncio_wait_is_cancelled_promptly(card: mc.Card) -> None:
    x = card.axis(0)
    x.enable()
    m = x.move_velocity(1_000.0, 1e5, 1e7)

    async def main() -> None:
        task = asyncio.ensure_future(mc.wait_async(m))
        await asyncio.sleep(0.05)
        task.cancel()
        try:
            await task
        except asyncio.CancelledError:
            return
        raise AssertionError("not cancelled")

    asyncio.run(main())
    x.halt(1e5, 1e7).wait(1.0)

"""Ctrl-C ends a wait: the waits run without the GIL in short slices and look for signals
between them, so a SIGINT (here raised from another thread) ends them with
KeyboardInterrupt, promptly, and the card stays usable."""

from __future__ import annotations

import _thread
import signal
import threading
import time
from typing import Callable

import pytest

import motioncard as mc


def interrupt_later(how: Callable[[], None], after: float = 0.2) -> threading.Thread:
    t = threading.Timer(after, how)
    t.start()
    return t


@pytest.mark.parametrize(
    "how",
    [_thread.interrupt_main, lambda: signal.raise_signal(signal.SIGINT)],
    ids=["interrupt_main", "raise_signal"],
)
def test_ctrl_c_ends_a_motion_wait(card: mc.Card, how: Callable[[], None]) -> None:
    x = card.axis(0)
    x.enable()
    m = x.move_velocity(1_000.0, 1e5, 1e7)  # never done
    t = interrupt_later(how)
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        m.wait(None)
    took = time.monotonic() - start
    t.join()
    assert took < 10.0
    # the card goes on: the motion still runs and can be halted
    assert x.status().state == mc.AxisState.CONTINUOUS_MOTION
    x.halt(1e5, 1e7).wait(1.0)


def test_ctrl_c_ends_an_event_wait() -> None:
    with mc.Card.open_sim("realtime") as card:
        while card.next_event(0.0) is not None:
            pass
        t = interrupt_later(_thread.interrupt_main)
        with pytest.raises(KeyboardInterrupt):
            for _ev in card.events(None):
                pass
        t.join()


def test_other_threads_run_while_a_wait_blocks(card: mc.Card) -> None:
    """The wait releases the GIL: a Python thread makes progress meanwhile."""
    x = card.axis(0)
    x.enable()
    counted = [0]
    stop = threading.Event()

    def count() -> None:
        while not stop.is_set():
            counted[0] += 1

    t = threading.Thread(target=count)
    t.start()
    x.move_relative(400_000.0, mc.MoveLimits(100_000.0, 1e6, 1e8)).wait(30.0)
    stop.set()
    t.join()
    assert counted[0] > 0


def test_ctrl_c_ends_a_nurbs_path_waiting_for_room(card: mc.Card) -> None:
    """`move_nurbs_path` waits for the queue's room in slices too; what it had queued runs on."""
    import math

    for a in (0, 1):
        card.axis(a).enable()
    g = card.group(0)
    g.configure([0, 1])
    g.enable()
    pts = [[i * 500.0, 2000.0 * math.sin(i * 0.3)] for i in range(200)]
    pieces = mc.Nurbs.split(pts, degree=3, max_ctrl=4)
    t = interrupt_later(_thread.interrupt_main)
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        # slow: 100,000 counts at 500 counts/s, minutes of the card's time
        g.move_nurbs_path(pieces, feed=500.0, acceleration=1e5, jerk=1e7)
    took = time.monotonic() - start
    t.join()
    assert took < 10.0
    st = g.status()
    assert st.state == mc.GroupState.MOVING and st.queued > 0
    g.halt(1e5, 1e7).wait(5.0)
    assert g.status().state == mc.GroupState.STANDBY

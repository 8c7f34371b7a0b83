"""Cards served by other processes: ``Card.list()`` sees them with their fields, and
``CardSet.open`` drives a master and its follower on one sync bus. The cards are served by
the workspace's ``card-emu`` (``MOTIONCARD_EMU``: its path; else ``target/release/card-emu``
of this repository; CI builds it and sets the variable, so these tests run there)."""

from __future__ import annotations

import os
import pathlib
import subprocess
import time
from typing import Iterator

import pytest

import motioncard as mc

REPO = pathlib.Path(__file__).resolve().parents[2]


def emu_binary() -> str:
    path = os.environ.get("MOTIONCARD_EMU")
    if path:
        assert pathlib.Path(path).is_file(), f"MOTIONCARD_EMU={path}: no such file"
        return path
    built = REPO / "target" / "release" / "card-emu"
    if not built.is_file():
        pytest.skip("no card-emu: `cargo build --release -p card-emu`, or set MOTIONCARD_EMU")
    return str(built)


def listed(name: str) -> mc.CardListing | None:
    return next((c for c in mc.Card.list() if c.uri == f"emu:{name}"), None)


class Served:
    """`card-emu` processes, ended (by their own handles) when the test ends."""

    def __init__(self) -> None:
        self.procs: list[subprocess.Popen[bytes]] = []

    def start(self, name: str, *args: str) -> None:
        p = subprocess.Popen([emu_binary(), "--name", name, *args], stderr=subprocess.PIPE)
        self.procs.append(p)
        # served once it is listed (and the followers locked to their master)
        deadline = time.monotonic() + 20.0
        while time.monotonic() < deadline:
            c = listed(name)
            if c is not None and c.error is None and c.sync_state != "lost":
                if "--sync-from" not in args or c.sync_state == "locked":
                    return
            assert p.poll() is None, p.stderr.read().decode() if p.stderr else ""
            time.sleep(0.05)
        raise AssertionError(f"card-emu {name} was never listed")

    def stop(self) -> None:
        for p in reversed(self.procs):
            p.terminate()
            p.wait(10)


@pytest.fixture
def served() -> Iterator[Served]:
    s = Served()
    try:
        yield s
    finally:
        s.stop()


def test_list_shows_every_card_with_its_fields(served: Served) -> None:
    pid = os.getpid()
    a, b = f"py-list-a-{pid}", f"py-list-b-{pid}"
    served.start(a, "--axes", "3", "--serial", str(pid * 256 + 1))
    served.start(b, "--axes", "2", "--serial", str(pid * 256 + 2), "--servo-rate", "4000")
    ca, cb = listed(a), listed(b)
    assert ca is not None and cb is not None
    assert (ca.name, ca.serial, ca.axes, ca.servo_rate_hz) == (a, pid * 256 + 1, 3, 10_000)
    assert (cb.name, cb.serial, cb.axes, cb.servo_rate_hz) == (b, pid * 256 + 2, 2, 4_000)
    for c in (ca, cb):
        assert (c.sync_role, c.sync_state, c.master) == ("alone", "free", "")
        assert c.available and not c.open_here
        assert c.error is None and c.error_kind is None
        assert c.layout[0] == 1 and c.layout[1] >= 12 and c.firmware_version > 0
    with mc.Card.open(f"emu:{a}") as card:
        assert card.info.axes == 3
        now = listed(a)
        assert now is not None and not now.available and now.open_here
        other = listed(b)
        assert other is not None and other.available and not other.open_here
    # closed: the server has it back; this process holds it until the last handle goes
    again = listed(a)
    assert again is not None and again.available
    del card
    gone = listed(a)
    assert gone is not None and gone.available and not gone.open_here
    # a sim card of this process is no listed card
    with mc.Card.open_sim():
        assert all(c.uri.startswith(("emu:", "uio:", "pci:")) for c in mc.Card.list())


def test_a_card_set_of_served_cards_starts_axes_on_one_tick(served: Served) -> None:
    pid = os.getpid()
    m, f = f"py-bus-m-{pid}", f"py-bus-f-{pid}"
    served.start(m, "--axes", "2")
    served.start(f, "--axes", "2", "--sync-from", m)
    lm, lf = listed(m), listed(f)
    assert lm is not None and lf is not None
    assert (lm.sync_role, lf.sync_role, lf.sync_state, lf.master) == (
        "master",
        "follower",
        "locked",
        m,
    )
    with pytest.raises(mc.BadConfigError):
        mc.CardSet.open([f"emu:{f}", f"emu:{m}"])  # the master first
    # a margin for a loaded machine: every command and the commit in before the tick
    s = mc.CardSet.open([f"emu:{m}", f"emu:{f}"], margin=0.5)
    try:
        assert [c.uri for c in s.cards] == [f"emu:{m}", f"emu:{f}"]
        limits = mc.MoveLimits(20_000.0, 1e6, 5e7)
        for c in s.cards:
            c.axis(0).enable()
            while c.next_event(0.0) is not None:
                pass
        with s.sync() as scope:
            motions = [c.axis(0).move_absolute(2_000.0, limits) for c in s.cards]
        assert [m.wait(5.0) for m in motions] == [2_000.0, 2_000.0]
        for c in s.cards:
            timed = [e.tick for e in c.events(timeout=0.0) if e.kind == mc.EventKind.TIMED]
            assert timed == [scope.tick]
    finally:
        for c in s.cards:
            c.close()

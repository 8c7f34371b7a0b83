"""API traces and replay: a run recorded from Python replays on a fresh emulated card without
a difference, counting what the file holds; a tampered trace names its first difference."""

from __future__ import annotations

import pathlib

import pytest

import motioncard as mc


def record(path: pathlib.Path) -> None:
    """A run with configuration, moves, a refusal and a halt, recorded."""
    with mc.Card.open_sim(axes=3, trace=path) as card:
        a0, a1 = card.axis(0), card.axis(1)
        a0.enable()
        a1.enable()
        lim = mc.MoveLimits(2e4, 4e5, 2e7)
        m = a0.move_absolute(3000.0, lim)
        m1 = a1.move_relative(-1500.0, lim)
        m.wait(10.0)
        with pytest.raises(mc.NotFiniteError):
            a0.move_absolute(float("nan"), lim)
        m1.wait(10.0)
        a0.move_velocity(-5000.0, 4e5, 2e7)
        a0.halt(4e5, 2e7).wait(10.0)


def lines(path: pathlib.Path, kind: str) -> list[str]:
    return [line for line in path.read_text().splitlines() if line.startswith(kind + " ")]


def test_a_recorded_run_replays_without_a_difference(tmp_path: pathlib.Path) -> None:
    path = tmp_path / "run.trace"
    record(path)
    text = path.read_text()
    assert text.startswith("# motioncard trace 1\nI ")
    r = mc.replay(str(path))
    assert r.difference is None, r
    assert (r.axes, r.servo_rate_hz, r.uri) == (3, 10_000, "sim")
    assert r.layout == mc.Card.open_sim(axes=1).info.layout
    # every command but the open's attach is sent again, every event but its answer compared
    commands, events = lines(path, "C"), lines(path, "E")
    attach = commands[0].split(" ")[2]  # its seq
    answers = [e for e in events if e.split(" ")[2] in ("1", "2") and e.split(" ")[4] == attach]
    assert len(answers) == 1
    assert r.commands == len(commands) - 1
    assert r.events == len(events) - 1
    assert r.commands >= 7


def test_a_tampered_trace_names_its_first_difference(tmp_path: pathlib.Path) -> None:
    path = tmp_path / "tampered.trace"
    record(path)
    text = path.read_text().splitlines()
    # the first move's target 3000 becomes 3001: its motion-done position differs first
    i = next(
        k for k, line in enumerate(text) if line.startswith("C ") and line.split(" ")[6] == "3000.0"
    )
    f = text[i].split(" ")
    f[6] = "3001.0"
    text[i] = " ".join(f)
    path.write_text("\n".join(text) + "\n")
    r = mc.replay(path)
    assert r.difference is not None
    line, why = r.difference
    assert line > i + 1, (line, why)
    assert text[line - 1].startswith("E "), text[line - 1]
    assert "MotionDone" in why or "value" in why, why


def test_what_is_not_a_trace_is_refused(tmp_path: pathlib.Path) -> None:
    path = tmp_path / "not.trace"
    path.write_text("hello\n")
    with pytest.raises(mc.BadConfigError):
        mc.replay(path)
    with pytest.raises(mc.IoError):
        mc.replay(tmp_path / "missing.trace")
    other = tmp_path / "other-layout.trace"
    record(other)
    t = other.read_text().splitlines()
    f = t[1].split(" ")
    f[2] = str(int(f[2]) + 1)  # the minor layout
    t[1] = " ".join(f)
    other.write_text("\n".join(t) + "\n")
    with pytest.raises(mc.VersionMismatchError):
        mc.replay(other)


def test_the_environment_turns_the_trace_on(
    tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "env.trace"
    # only this test sets it, for its own open
    monkeypatch.setenv(mc.TRACE_ENV, str(path))
    card = mc.Card.open_sim(axes=2)
    monkeypatch.delenv(mc.TRACE_ENV)
    with card:
        card.axis(1).enable()
    assert len(lines(path, "C")) >= 3
    r = mc.replay(path)
    assert r.difference is None, r
    assert r.axes == 2

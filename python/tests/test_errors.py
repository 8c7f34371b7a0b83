"""Every ErrorKind of the SDK has its class, and a representative set is provoked for real."""

from __future__ import annotations

import pathlib
import re

import pytest

import motioncard as mc

LIMITS = mc.MoveLimits(50_000.0, 1e6, 5e7)
ERROR_RS = pathlib.Path(__file__).resolve().parents[2] / "sdk" / "src" / "error.rs"


def kinds_in_sdk_source() -> list[str]:
    """The kinds of the SDK's `error_kinds!` table, read from its source (not from the
    built module), in order."""
    text = ERROR_RS.read_text()
    table = text[text.index("error_kinds! {") :]
    return re.findall(r"^\s+([A-Z][A-Za-z0-9]*) = -\d+, MC_ERR_", table, re.M)


def test_every_kind_has_its_class() -> None:
    kinds = kinds_in_sdk_source()
    assert len(kinds) > 100
    assert [k for k, _cls, _code, _desc in mc.ERROR_KINDS] == kinds
    codes = set()
    for kind, cls_name, code, desc in mc.ERROR_KINDS:
        cls = getattr(mc, cls_name)
        assert cls_name == kind + "Error"
        assert issubclass(cls, mc.Error) and cls is not mc.Error
        assert cls.kind == kind and cls.code == code and cls.description == desc
        assert mc.ERROR_CLASSES[kind] is cls
        assert code < 0
        codes.add(code)
    assert len(codes) == len(kinds)
    assert mc.Error.kind is None
    assert issubclass(mc.Error, Exception)


def test_every_kind_raises_its_own_class() -> None:
    """Every kind, raised as an SDK error is (through the one conversion all of them take),
    is its own class, a `motioncard.Error`, with its kind, code and description."""
    for kind, cls_name, code, desc in mc.ERROR_KINDS:
        cls = getattr(mc, cls_name)
        with pytest.raises(cls) as e:
            mc._raise_kind(kind)
        assert type(e.value) is cls
        assert isinstance(e.value, mc.Error)
        assert (e.value.kind, e.value.code) == (kind, code)
        assert desc in str(e.value)
    with pytest.raises(ValueError):
        mc._raise_kind("NoSuchKind")


def test_nan_target_is_not_finite(card: mc.Card) -> None:
    x = card.axis(0)
    x.enable()
    with pytest.raises(mc.NotFiniteError) as e:
        x.move_absolute(float("nan"), LIMITS)
    assert e.value.kind == "NotFinite" and e.value.code == -11
    assert "NaN" in str(e.value)
    with pytest.raises(mc.NonPositiveLimitError):
        x.move_absolute(1.0, mc.MoveLimits(0.0, 1e6, 5e7))
    # nothing moved
    assert x.status().command_position == 0.0


def test_unknown_axis_and_group(card: mc.Card) -> None:
    with pytest.raises(mc.BadAxisError) as e:
        card.axis(99)
    assert isinstance(e.value, mc.Error)
    with pytest.raises(mc.BadGroupError):
        card.group(99)


def test_refused_moves(card: mc.Card) -> None:
    x = card.axis(0)
    with pytest.raises(mc.AxisDisabledError):
        x.move_relative(100.0, LIMITS)
    x.enable()
    card.estop(1)
    with pytest.raises(mc.EStopActiveError):
        x.move_relative(100.0, LIMITS)
    with pytest.raises(mc.BadCategoryError):
        card.estop(7)


def test_waits(card: mc.Card) -> None:
    x = card.axis(0)
    x.enable()
    with pytest.raises(mc.NoMotionError):
        x.wait_done(0.1)
    m = x.move_relative(1_000_000.0, mc.MoveLimits(10_000.0, 1e5, 1e7))
    with pytest.raises(mc.TimeoutError) as e:
        m.wait(0.2)
    assert e.value.kind == "Timeout"
    x.halt(1e5, 1e7)
    with pytest.raises(mc.AbortedError):
        m.wait(1.0)
    with pytest.raises(ValueError):
        m.wait(-1.0)


def test_bad_uri_and_missing_card() -> None:
    with pytest.raises(mc.BadUriError):
        mc.Card.open("floppy:a")
    with pytest.raises(mc.NotFoundError):
        mc.Card.open("emu:no-such-card-here")


def test_gcode_error_names_its_line(card: mc.Card) -> None:
    g = card.group(0)
    for a in range(3):
        card.axis(a).enable()
    g.configure([0, 1, 2])
    g.enable()
    g.configure_path(100.0, 1000.0, 1e5)
    with pytest.raises(mc.GcodeError) as e:
        g.run_gcode("G0 X1\nG1 X2 F100\nG77 X3\n")
    assert "line 3" in str(e.value)
    # nothing moved: the program is checked whole first
    assert card.axis(0).status().command_position == 0.0


def test_closed_card_refuses(card: mc.Card) -> None:
    x = card.axis(0)
    card.close()
    with pytest.raises(mc.ClosedError):
        x.enable()
    card.close()  # twice is harmless

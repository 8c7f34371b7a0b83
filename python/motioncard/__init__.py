"""The motion card's SDK for Python.

Open a card by URI (or an emulated one in this process), take its axes, move them, read
their status, wait for the card's events, capture its scope as numpy arrays::

    import motioncard as mc

    with mc.Card.open_sim() as card:          # stepped emulated card; or mc.Card.open("sim")
        x = card.axis(0)
        x.enable()
        reached = x.move_absolute(10_000, mc.MoveLimits(50_000, 1e6, 5e7)).wait(5.0)
        print(reached, x.status().state)

Every error is a ``motioncard.Error`` whose ``kind`` names the SDK's ``ErrorKind``; each kind
has its own subclass (``BadAxisError``, ``TimeoutError``, ...). Waits release the GIL and
Ctrl-C ends them with ``KeyboardInterrupt``.
"""

from __future__ import annotations

import asyncio
import enum
from typing import AsyncIterator, Callable, Optional, TypeVar, Union

from . import _motioncard
from ._motioncard import *  # noqa: F401,F403 (the classes and the error subclasses)
from ._motioncard import _raise_kind  # noqa: F401 (for the tests)
from ._motioncard import (
    ADC_LSB,
    ANALOG_INPUTS,
    AXIS_STATES,
    COMPARE_FIRED,
    COMPARE_LOW_WATER,
    COMPARE_MISSED,
    COMPARE_TABLE_LEN,
    ERROR_KINDS,
    EVENT_KINDS,
    GROUP_STATES,
    INPUTS,
    NURBS_MAX_CTRL,
    SCOPE_CHANNELS,
    SIGNALS,
    STOP_CATEGORIES,
    STOP_REASONS,
    TRACE_ENV,
    Card,
    CardInfo,
    CardListing,
    CardSafetySettings,
    CardSet,
    Capture,
    Compare,
    Compensation,
    Error,
    Event,
    Events,
    FireRecord,
    FreqResponse,
    Gantry,
    GantryHoming,
    GantrySide,
    GantryStatus,
    Group,
    GroupHoming,
    GroupMotion,
    GroupStatus,
    Motion,
    MoveLimits,
    Nurbs,
    PathLimits,
    PathOutput,
    PathSettings,
    Probe,
    PsoStatus,
    ReplayReport,
    SafetySettings,
    SafetyStatus,
    Scope,
    Segment,
    ServoFilter,
    SetPath,
    SetPathProgress,
    Sim,
    Status,
    StopInfo,
    SyncScope,
    TimedScope,
    Axis,
    AnalogInput,
    die_bonder_pdplus,
    pidff_for_drive,
    replay,
)

#: PLCopen axis states (``Status.state``).
AxisState = enum.IntEnum("AxisState", AXIS_STATES, module=__name__)  # type: ignore[misc]
#: PLCopen group states (``GroupStatus.state``).
GroupState = enum.IntEnum("GroupState", GROUP_STATES, module=__name__)  # type: ignore[misc]
#: Event kinds (``Event.kind``).
EventKind = enum.IntEnum("EventKind", EVENT_KINDS, module=__name__)  # type: ignore[misc]
#: Scope signals (``Scope.capture``'s channels).
Signal = enum.IntEnum("Signal", SIGNALS, module=__name__)  # type: ignore[misc]
#: Stop categories of an e-stop (IEC 60204-1).
StopCategory = enum.IntEnum("StopCategory", STOP_CATEGORIES, module=__name__)  # type: ignore[misc]
#: Why an axis's last motion ended (``Axis.stop_reason()``, ``Status.stop_reason``).
StopReason = enum.IntEnum("StopReason", STOP_REASONS, module=__name__)  # type: ignore[misc]

#: The error class of each kind, by the kind's name (``"BadAxis"`` → ``BadAxisError``).
ERROR_CLASSES: dict[str, type[Error]] = {
    kind: getattr(_motioncard, cls) for kind, cls, _code, _desc in ERROR_KINDS
}

# How long one executor call of the asyncio functions waits: a cancelled task leaves a thread
# waiting at most this long.
_ASYNC_SLICE = 0.05


_T = TypeVar("_T")


async def _wait_sliced(wait: Callable[[float], _T], timeout: Optional[float]) -> _T:
    """``wait(timeout)`` from asyncio: in the loop's default executor, in short slices (a
    slice that times out is waited again until ``timeout`` is spent), so that cancelling the
    task ends it promptly."""
    loop = asyncio.get_running_loop()
    left = timeout
    while True:
        s = _ASYNC_SLICE if left is None else min(_ASYNC_SLICE, left)
        try:
            return await loop.run_in_executor(None, wait, s)
        except _motioncard.TimeoutError:
            if left is not None:
                left -= s
                if left <= 0:
                    raise


async def wait_async(motion: Motion, timeout: Optional[float] = None) -> float:
    """``motion.wait(timeout)`` from asyncio (``await motion`` is this without a timeout):
    the final position. The wait runs in the loop's default executor in short slices, so
    cancelling the task ends it promptly."""
    return await _wait_sliced(motion.wait, timeout)


async def next_event_async(
    card: Union[Card, Events], timeout: Optional[float] = None
) -> Optional[Event]:
    """``card.next_event(timeout)`` from asyncio: the next event, or None when none came
    within ``timeout`` seconds (None: wait until one comes)."""
    loop = asyncio.get_running_loop()
    left = timeout
    while True:
        s = _ASYNC_SLICE if left is None else min(_ASYNC_SLICE, left)
        ev = await loop.run_in_executor(None, card.next_event, s)
        if ev is not None:
            return ev
        if left is not None:
            left -= s
            if left <= 0:
                return None


async def events_async(card: Union[Card, Events], timeout: Optional[float] = 1.0) -> AsyncIterator[Event]:
    """The card's events as an async iterator (``async for ev in events_async(card)``, or
    ``async for ev in card.events(timeout)``); it ends when none comes within ``timeout``
    seconds."""
    while True:
        ev = await next_event_async(card, timeout)
        if ev is None:
            return
        yield ev


async def group_wait_async(motion: GroupMotion, timeout: Optional[float] = None) -> None:
    """``motion.wait(timeout)`` of a group's move from asyncio (``await motion``)."""
    await _wait_sliced(motion.wait, timeout)

__all__ = [
    "ADC_LSB",
    "ANALOG_INPUTS",
    "AXIS_STATES",
    "COMPARE_FIRED",
    "COMPARE_LOW_WATER",
    "COMPARE_MISSED",
    "COMPARE_TABLE_LEN",
    "ERROR_CLASSES",
    "ERROR_KINDS",
    "EVENT_KINDS",
    "GROUP_STATES",
    "INPUTS",
    "NURBS_MAX_CTRL",
    "SCOPE_CHANNELS",
    "SIGNALS",
    "STOP_CATEGORIES",
    "STOP_REASONS",
    "TRACE_ENV",
    "AnalogInput",
    "Axis",
    "AxisState",
    "Capture",
    "Card",
    "CardInfo",
    "CardListing",
    "CardSafetySettings",
    "CardSet",
    "Compare",
    "Compensation",
    "Error",
    "Event",
    "EventKind",
    "Events",
    "FireRecord",
    "FreqResponse",
    "Gantry",
    "GantryHoming",
    "GantrySide",
    "GantryStatus",
    "Group",
    "GroupHoming",
    "GroupMotion",
    "GroupState",
    "GroupStatus",
    "Motion",
    "MoveLimits",
    "Nurbs",
    "PathLimits",
    "PathOutput",
    "PathSettings",
    "Probe",
    "PsoStatus",
    "ReplayReport",
    "SafetySettings",
    "SafetyStatus",
    "Scope",
    "Segment",
    "ServoFilter",
    "SetPath",
    "SetPathProgress",
    "Signal",
    "Sim",
    "Status",
    "StopCategory",
    "StopInfo",
    "StopReason",
    "SyncScope",
    "TimedScope",
    "die_bonder_pdplus",
    "events_async",
    "group_wait_async",
    "next_event_async",
    "pidff_for_drive",
    "replay",
    "wait_async",
] + [cls for _kind, cls, _code, _desc in ERROR_KINDS]

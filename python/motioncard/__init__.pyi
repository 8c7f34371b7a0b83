# Type stubs of the package motioncard (the compiled motioncard._motioncard and the Python
# around it). The sections between the GENERATED markers are written by
# `python tools/stubs.py` from the built module; tests/test_stubs.py checks they match it.
import builtins
import enum
from os import PathLike
from types import TracebackType
from typing import (
    Any,
    AsyncIterator,
    Callable,
    Generator,
    Iterator,
    Literal,
    NoReturn,
    Optional,
    Sequence,
    Tuple,
    Union,
    overload,
)

import numpy as np
import numpy.typing as npt

AXIS_STATES: list[tuple[str, int]]
GROUP_STATES: list[tuple[str, int]]
EVENT_KINDS: list[tuple[str, int]]
SIGNALS: list[tuple[str, int]]
STOP_CATEGORIES: list[tuple[str, int]]
STOP_REASONS: list[tuple[str, int]]
#: (kind, class name, C code, description) of every ErrorKind.
ERROR_KINDS: list[tuple[str, str, int, str]]
ERROR_CLASSES: dict[str, type[Error]]
SCOPE_CHANNELS: int
__all__: list[str]
INPUTS: int
#: The environment variable that records every card a program opens to a trace file.
TRACE_ENV: str
#: The card's analog inputs.
ANALOG_INPUTS: int
#: The ADC's step, V (20 V / 65536).
ADC_LSB: float
#: `EventKind.COMPARE` codes: a position fired, a position missed, a table's low water.
COMPARE_FIRED: int
COMPARE_MISSED: int
COMPARE_LOW_WATER: int
#: The positions a compare channel's table holds.
COMPARE_TABLE_LEN: int
#: The most control points the card takes in one curve (`Nurbs.split` cuts longer ones).
NURBS_MAX_CTRL: int

Clock = Literal["stepped", "realtime", "free"]
Trigger = Literal["immediate", "command", "fault", "level", "input"]
Edge = Literal["rising", "falling", "either"]
Direction = Literal["positive", "negative", "either"]
#: An arc's plane: "XY" (G17), "ZX" (G18), "YZ" (G19), any other two of X, Y, Z ("XZ": from X
#: towards Z), or a pair (u, v) of group axes.
Plane = Union[str, Tuple[int, int]]
MasterSource = Literal["commanded", "actual", "actual_lead", "aux"]
ServoLaw = Literal["ffpiv", "pdplus", "pidff"]
MoveDirection = Literal["shortest", "positive", "negative", "current"]
#: How a path segment joins the one before it (PLCopen BufferMode).
BufferMode = Literal[
    "aborting", "buffered", "blending_low", "blending_previous", "blending_next", "blending_high"
]
#: How a blend is sized (PLCopen TransitionMode).
TransitionKind = Literal["none", "max_deviation", "corner_distance", "time_shift"]
PauseState = Literal["none", "pausing", "paused"]
#: An axis's post-interpolation acc/dec filter (`Axis.set_filters`).
FilterKind = Literal["none", "linear", "exponential", "bell"]
#: A group move's feed type: which of each axis's filters shapes it.
FeedType = Literal["rapid", "cutting", "jog"]

class Error(Exception):
    """An error of the card or the SDK; each ErrorKind has its own subclass."""

    #: The SDK's ErrorKind name ("BadAxis"); None on the base class.
    kind: Optional[str]
    #: The C ABI's MC_ERR_* code.
    code: Optional[int]
    description: Optional[str]

class CardInfo:
    firmware_version: int
    layout: Tuple[int, int]
    axes: int
    servo_rate_hz: int

class CardListing:
    """One card found by Card.list()."""

    uri: str
    name: str
    serial: int
    axes: int
    servo_rate_hz: int
    layout: Tuple[int, int]
    firmware_version: int
    sync_role: Literal["alone", "master", "follower"]
    sync_state: Literal["free", "locked", "lost"]
    master: str
    available: bool
    open_here: bool
    #: The ErrorKind's name when the card could not be read.
    error_kind: Optional[str]
    error: Optional[str]

class SafetyStatus:
    watchdog_tripped: bool
    estop_command: bool
    estop_input: bool
    watchdog_armed: bool
    protocol_errors: int
    session: int

class SafetySettings:
    """An axis's safety configuration, in user units; keywords not given: the card's
    defaults."""

    def __init__(
        self,
        *,
        soft_limits: Optional[Tuple[float, float]] = ...,
        hard_limits: bool = ...,
        amp_alarm: bool = ...,
        encoder_checks: bool = ...,
        limit_stop: int = ...,
        ferror: float = ...,
        min_ferror: float = ...,
        max_velocity: float = ...,
        stop_deceleration: float = ...,
        stop_jerk: float = ...,
        encoder_max_velocity: float = ...,
    ) -> None: ...
    def replace(
        self,
        *,
        soft_limits: Optional[Tuple[float, float]] = ...,
        hard_limits: bool = ...,
        amp_alarm: bool = ...,
        encoder_checks: bool = ...,
        limit_stop: int = ...,
        ferror: float = ...,
        min_ferror: float = ...,
        max_velocity: float = ...,
        stop_deceleration: float = ...,
        stop_jerk: float = ...,
        encoder_max_velocity: float = ...,
    ) -> SafetySettings: ...
    @property
    def soft_limits(self) -> Optional[Tuple[float, float]]: ...
    @property
    def hard_limits(self) -> bool: ...
    @property
    def amp_alarm(self) -> bool: ...
    @property
    def encoder_checks(self) -> bool: ...
    @property
    def limit_stop(self) -> StopCategory: ...
    @property
    def ferror(self) -> float: ...
    @property
    def min_ferror(self) -> float: ...
    @property
    def max_velocity(self) -> float: ...
    @property
    def stop_deceleration(self) -> float: ...
    @property
    def stop_jerk(self) -> float: ...
    @property
    def encoder_max_velocity(self) -> float: ...

class CardSafetySettings:
    """The card-wide safety settings as the card holds them."""

    @property
    def watchdog_timeout(self) -> float: ...
    @property
    def estop_input_category(self) -> StopCategory: ...
    @property
    def max_stop_time(self) -> float: ...

class StopInfo:
    """How an axis's last safety stop went, measured by the card."""

    @property
    def reason(self) -> StopReason: ...
    stop_tick: int
    rest_tick: Optional[int]
    ramp_time: float

class AnalogInput:
    """An analog input as the card sampled it at its last tick."""

    sample: float
    value: float
    above: bool
    cutoff_hz: float
    threshold: float
    hysteresis: float
    rise_event: bool
    fall_event: bool

class FireRecord:
    """A compare pulse the emulator recorded (``Sim.record_fires``), in counts."""

    channel: int
    output: int
    axis: int
    position: float
    time: float
    shaft: float
    velocity: float

class Sim:
    """Stepping control of a stepped emulated card."""

    def step(self, n: int) -> None: ...
    @property
    def time(self) -> float: ...
    def set_input(self, input: int, high: bool) -> None: ...
    def set_estop(self, pressed: bool) -> None: ...
    def record_fires(self, on: bool) -> None: ...
    def take_fires(self) -> list[FireRecord]: ...
    def jump_aux(self, input: int, counts: int) -> None: ...
    def set_aux_velocity(self, input: int, counts_per_s: float) -> None: ...
    def set_analog_input(self, input: int, volts: float) -> None: ...

class Event:
    @property
    def kind(self) -> EventKind: ...
    axis: int
    seq: int
    code: int
    tick: int
    value: float

class Events:
    """The card's events: `for ev in card.events(timeout)` or `async for ...`."""

    def __iter__(self) -> Iterator[Event]: ...
    def __next__(self) -> Event: ...
    def __aiter__(self) -> AsyncIterator[Event]: ...
    def next_event(self, timeout: Optional[float] = 0.0) -> Optional[Event]: ...
    @property
    def timeout(self) -> Optional[float]: ...

class Card:
    """A motion card opened by URI; a context manager that closes it."""

    @staticmethod
    def open(uri: str, *, trace: Optional[Union[str, PathLike[str]]] = None) -> Card: ...
    @staticmethod
    def open_sim(
        clock: Clock = "stepped",
        axes: int = 8,
        servo_rate_hz: int = 10000,
        *,
        trace: Optional[Union[str, PathLike[str]]] = None,
    ) -> Card: ...
    @staticmethod
    def list() -> builtins.list[CardListing]: ...
    @property
    def uri(self) -> str: ...
    @property
    def info(self) -> CardInfo: ...
    def tick(self) -> int: ...
    def timed(self, tick: int, *, key: int = 0) -> TimedScope: ...
    def sync_commit(self, key: int, tick: int) -> None: ...
    def cancel_timed(self, key: int = 0) -> int: ...
    def axis(self, index: int) -> Axis: ...
    def axes(self) -> builtins.list[Axis]: ...
    def group(self, index: int) -> Group: ...
    def pso_off(self) -> None: ...
    def pso_status(self) -> PsoStatus: ...
    def gantry(
        self,
        master: int,
        slaves: Sequence[int],
        *,
        skew_limit: float,
        kp: float = 1e6,
        ki: float = 0.0,
        offsets: Optional[Sequence[float]] = None,
        index: Optional[int] = None,
    ) -> Gantry: ...
    def gantry_handle(self, index: int) -> Gantry: ...
    def gantries(self) -> builtins.list[GantryStatus]: ...
    @property
    def sim(self) -> Optional[Sim]: ...
    @property
    def scope(self) -> Scope: ...
    def ping(self) -> None: ...
    def close(self) -> None: ...
    def __enter__(self) -> Card: ...
    def __exit__(
        self,
        exc_type: Optional[type[BaseException]],
        exc: Optional[BaseException],
        tb: Optional[TracebackType],
    ) -> bool: ...
    def cancel_waits(self) -> None: ...
    def next_event(self, timeout: Optional[float] = 0.0) -> Optional[Event]: ...
    def events(self, timeout: Optional[float] = 1.0) -> Events: ...
    def events_lost(self) -> Tuple[int, int]: ...
    def inputs(self) -> int: ...
    def outputs(self) -> int: ...
    def set_outputs(self, mask: int, value: int) -> None: ...
    def set_output(self, output: int, high: bool) -> None: ...
    def configure_io(
        self,
        *,
        polarity: Optional[int] = None,
        rise_events: Optional[int] = None,
        fall_events: Optional[int] = None,
        debounce: Optional[Sequence[int]] = None,
    ) -> None: ...
    def analog_input(self, input: int) -> float: ...
    def analog_input_status(self, input: int) -> AnalogInput: ...
    def configure_analog_input(
        self,
        input: int,
        *,
        cutoff_hz: float = 0.0,
        threshold: float = 0.0,
        hysteresis: float = 0.0,
        rise_event: bool = False,
        fall_event: bool = False,
    ) -> None: ...
    def set_analog_output(self, output: int, volts: float) -> float: ...
    def estop(self, category: int = 1) -> None: ...
    def reset_faults(self) -> None: ...
    def safety_status(self) -> SafetyStatus: ...
    def set_watchdog_timeout(self, timeout: float) -> None: ...
    def set_estop_input_category(self, category: int) -> None: ...
    def set_max_stop_time(self, seconds: float) -> None: ...
    def safety_settings(self) -> CardSafetySettings: ...
    def load_cam_table(
        self,
        table: int,
        points: Sequence[Tuple[float, float]],
        *,
        cubic: bool = False,
        periodic: bool = False,
    ) -> None: ...
    def set_servo_rate(self, hz: int) -> None: ...
    def save_config(self) -> str: ...
    def load_config(self, text: str, origin: str = "<string>") -> builtins.list[str]: ...
    def save_config_file(self, path: Union[str, PathLike[str]]) -> None: ...
    def load_config_file(self, path: Union[str, PathLike[str]]) -> builtins.list[str]: ...

class MoveLimits:
    def __init__(
        self,
        velocity: float,
        acceleration: float,
        jerk: float,
        *,
        deceleration: Optional[float] = None,
        decel_jerk: Optional[float] = None,
        jerks: Optional[Tuple[float, float, float, float]] = None,
    ) -> None: ...
    @property
    def velocity(self) -> float: ...
    @property
    def acceleration(self) -> float: ...
    @property
    def deceleration(self) -> float: ...
    @property
    def jerks(self) -> Tuple[float, float, float, float]: ...

class Status:
    @property
    def state(self) -> AxisState: ...
    position: float
    velocity: float
    following_error: float
    command_position: float
    compensated_position: float
    command_velocity: float
    command_acceleration: float
    dac_volts: float
    faults: int
    queued: int
    override_factor: float
    tick: int
    peak_velocity: float
    peak_acceleration: float
    peak_deceleration: float
    peak_jerk: float
    max_following_error: float
    planned_time: float
    move_time: float
    move_count: int
    encoder: int
    homed: bool
    in_sync: bool
    @property
    def stop_reason(self) -> StopReason: ...

class Motion:
    @property
    def seq(self) -> int: ...
    @property
    def axis(self) -> int: ...
    def wait(self, timeout: Optional[float] = None) -> float: ...
    def wait_in_velocity(self, timeout: Optional[float] = None) -> float: ...
    def wait_in_sync(self, timeout: Optional[float] = None) -> float: ...
    def wait_cam_switch(self, timeout: Optional[float] = None) -> float: ...
    def wait_active(self, timeout: Optional[float] = None) -> float: ...
    def __await__(self) -> Generator[Any, None, float]: ...

class Axis:
    @property
    def index(self) -> int: ...
    def enable(self) -> None: ...
    def disable(self) -> None: ...
    def set_scale(self, counts_per_unit: float) -> None: ...
    @property
    def scale(self) -> float: ...
    def set_modulo(self, period: float) -> None: ...
    def clear_modulo(self) -> None: ...
    def modulo(self) -> float: ...
    def move_absolute(
        self,
        target: float,
        limits: MoveLimits,
        *,
        buffered: bool = False,
        direction: MoveDirection = "shortest",
    ) -> Motion: ...
    def move_relative(
        self, distance: float, limits: MoveLimits, *, buffered: bool = False
    ) -> Motion: ...
    def move_additive(
        self, distance: float, limits: MoveLimits, *, buffered: bool = False
    ) -> Motion: ...
    def settings(self) -> dict[str, float]: ...
    def configure(self, **changes: float) -> None: ...
    def move_velocity(
        self,
        velocity: float,
        acceleration: float,
        jerk: float,
        *,
        deceleration: Optional[float] = None,
    ) -> Motion: ...
    def jog(self, velocity: float) -> Motion: ...
    def jog_release(self) -> Motion: ...
    def halt(self, deceleration: float, jerk: float) -> Motion: ...
    def stop(self, deceleration: float, jerk: float) -> Motion: ...
    def release_stop(self) -> None: ...
    def safety_settings(self) -> SafetySettings: ...
    def configure_safety(self, settings: SafetySettings) -> None: ...
    def stop_reason(self) -> StopReason: ...
    def stop_info(self) -> StopInfo: ...
    def reset(self) -> None: ...
    def set_override(self, factor: float) -> None: ...
    def wait_done(self, timeout: Optional[float] = None) -> float: ...
    def status(self) -> Status: ...
    def configure_homing(
        self,
        method: int,
        *,
        search_velocity: Optional[float] = None,
        creep_velocity: Optional[float] = None,
        acceleration: Optional[float] = None,
        jerk: Optional[float] = None,
        offset: Optional[float] = None,
        timeout: Optional[float] = None,
        max_distance: Optional[float] = None,
        index: Optional[bool] = None,
    ) -> None: ...
    def home(self, position: float = 0.0) -> Motion: ...
    def set_position(self, position: float, relative: bool = False) -> None: ...
    def gear_in(
        self,
        master: int,
        numerator: int,
        denominator: int,
        velocity: float,
        acceleration: float,
        jerk: float,
        *,
        source: MasterSource = "commanded",
    ) -> Motion: ...
    def gear_out(self) -> Motion: ...
    def cam_in(
        self,
        master: int,
        table: int,
        velocity: float,
        acceleration: float,
        jerk: float,
        *,
        source: MasterSource = "commanded",
        relative: bool = False,
    ) -> Motion: ...
    def set_filters(
        self,
        *,
        rapid: Optional[Tuple[FilterKind, float]] = None,
        cutting: Optional[Tuple[FilterKind, float]] = None,
        jog: Optional[Tuple[FilterKind, float]] = None,
    ) -> None: ...
    def filter_settings(self) -> dict[str, Tuple[FilterKind, float]]: ...
    def cam_switch(
        self,
        master: int,
        table: int,
        velocity: float,
        acceleration: float,
        jerk: float,
        *,
        source: MasterSource = "commanded",
    ) -> Motion: ...
    def cam_out(self) -> Motion: ...
    def pvt(
        self,
        points: Sequence[Tuple[float, float, float]],
        velocity: float,
        acceleration: float,
        *,
        mode: Literal["pvt", "pt"] = "pvt",
    ) -> Motion: ...
    def compare(self, channel: int) -> Compare: ...
    def touch_probe(self, channel: int) -> Probe: ...
    def servo_law(self) -> ServoLaw: ...
    def configure_pidff(
        self,
        *,
        kp: float = ...,
        ki: float = ...,
        kd: float = ...,
        kvff: float = ...,
        kaff: float = ...,
        friction: float = ...,
        friction_deadband: float = ...,
        d_filter_hz: float = ...,
    ) -> None: ...
    def pidff_settings(self) -> Optional[dict[str, float]]: ...
    def configure_pdplus(
        self,
        *,
        kp: float = ...,
        kd: float = ...,
        kv: float = ...,
        ka: float = ...,
        kc: float = ...,
        tau: float = ...,
        ke: float = ...,
        umax: float = ...,
    ) -> None: ...
    def pdplus_settings(self) -> Optional[dict[str, float]]: ...
    def set_servo_filter(self, slot: int, filter: ServoFilter) -> None: ...
    def clear_servo_filter(self, slot: Optional[int] = None) -> None: ...
    def servo_filters(self) -> list[Optional[ServoFilter]]: ...
    def frequency_response(
        self,
        *,
        mode: Literal["reference", "output"] = "reference",
        from_hz: float = 5.0,
        to_hz: float = 1000.0,
        points: int = 40,
        amplitude: float = 100.0,
        cycles: int = 4,
        settle_s: float = 0.2,
        timeout: Optional[float] = None,
    ) -> FreqResponse: ...
    def set_compensation(self, table: Compensation) -> None: ...
    def clear_compensation(self) -> None: ...
    def compensation(self) -> Optional[Compensation]: ...
    def handwheel(self, input: int, *, ratio: int = 1, detent: int = 4) -> Motion: ...
    def handwheel_off(self) -> None: ...

class Compensation:
    """An axis's pitch-error and backlash compensation table, user units."""

    def __init__(
        self,
        points: Sequence[Union[Tuple[float, float], Tuple[float, float, float]]],
        *,
        backlash: float = 0.0,
        bound: float,
        ramp_velocity: float = 1000.0,
        ramp_acceleration: float = 1e6,
    ) -> None: ...
    @property
    def points(self) -> list[Tuple[float, float, float]]: ...
    @property
    def bidirectional(self) -> bool: ...
    @property
    def backlash(self) -> float: ...
    @property
    def bound(self) -> float: ...
    @property
    def ramp_velocity(self) -> float: ...
    @property
    def ramp_acceleration(self) -> float: ...

class PsoStatus:
    """The path-speed output as the card ran it at its last tick."""

    state: Literal["off", "closed", "on"]
    group: int
    output: Optional[int]
    pwm_hz: Optional[float]
    gate: Optional[int]
    min: float
    max: float
    v_ref_counts: float
    filter_hz: float
    speed_counts: float
    value: float

class GantrySide:
    """One slave of a gantry (the master's user units)."""

    axis: int
    offset: float
    hold: float
    skew: float
    correction: float
    max_skew: float

class GantryStatus:
    index: int
    phase: Literal["coupled", "homing", "squaring"]
    master: int
    slaves: list[GantrySide]
    kp: float
    ki: float
    skew_limit: float
    squared: bool

class GantryHoming:
    @property
    def seq(self) -> int: ...
    def wait(self, timeout: Optional[float] = None) -> float: ...

class Gantry:
    """A gantry of the card: commanded through its master."""

    @property
    def index(self) -> int: ...
    def status(self) -> GantryStatus: ...
    def master(self) -> Axis: ...
    def home(self) -> GantryHoming: ...
    def dissolve(self) -> None: ...

class ServoFilter:
    """A biquad filter on an axis's servo output."""

    @staticmethod
    def notch(hz: float, damping: float, depth_db: float) -> ServoFilter: ...
    @staticmethod
    def low_pass(hz: float, damping: float) -> ServoFilter: ...
    @staticmethod
    def lead_lag(zero_hz: float, pole_hz: float) -> ServoFilter: ...
    @staticmethod
    def raw(b0: float, b1: float, b2: float, a1: float, a2: float) -> ServoFilter: ...
    @property
    def kind(self) -> Literal["notch", "low_pass", "lead_lag", "raw"]: ...
    @property
    def freq_hz(self) -> float: ...
    @property
    def damping(self) -> float: ...
    @property
    def depth_db(self) -> float: ...
    @property
    def freq2_hz(self) -> float: ...
    #: The card's coefficients (b0, b1, b2, a1, a2) of a filter read back; None for one made
    #: here (but a raw one).
    @property
    def coeffs(self) -> Optional[Tuple[float, float, float, float, float]]: ...

#: (frequency Hz, gain dB, phase degrees), one value per point.
Curve = Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]

class FreqResponse:
    """A frequency sweep's result; each response is (frequency, gain dB, phase deg) arrays."""

    @property
    def mode(self) -> Literal["reference", "output"]: ...
    @property
    def complete(self) -> bool: ...
    @property
    def frequency(self) -> npt.NDArray[np.float64]: ...
    def response(self) -> Curve: ...
    def closed_loop(self) -> Curve: ...
    def plant(self) -> Curve: ...
    def open_loop(self) -> Curve: ...
    def resonances(self) -> list[Tuple[float, float, float, bool]]: ...
    def __len__(self) -> int: ...

def _raise_kind(kind: str) -> NoReturn:
    """Raise the error of `kind` as every SDK error is raised (for the tests)."""

def pidff_for_drive(accel_per_volt: float, wc: float) -> dict[str, float]: ...

class ReplayReport:
    """What `replay` found."""

    layout: tuple[int, int]
    axes: int
    servo_rate_hz: int
    uri: str
    commands: int
    events: int
    #: (the trace's line, what differs); None: the card answered as recorded.
    difference: Optional[tuple[int, str]]

def replay(path: Union[str, PathLike[str]]) -> ReplayReport: ...
def die_bonder_pdplus(axis: int) -> dict[str, float]: ...

class Compare:
    """A position-compare channel of an axis."""

    @property
    def channel(self) -> int: ...
    def arm_single(
        self, output: int, pulse_us: int, position: float, direction: Direction = "either"
    ) -> None: ...
    def arm_series(
        self,
        output: int,
        pulse_us: int,
        start: float,
        pitch: float,
        count: int,
        direction: Direction = "positive",
    ) -> None: ...
    def arm_single_each_turn(
        self, output: int, pulse_us: int, position: float, direction: Direction = "either"
    ) -> None: ...
    def arm_series_each_turn(
        self,
        output: int,
        pulse_us: int,
        start: float,
        pitch: float,
        count: int = 0,
        direction: Direction = "positive",
    ) -> None: ...
    def arm_table(
        self, output: int, pulse_us: int, *, low_water: int = 0, direction: Direction = "positive"
    ) -> None: ...
    def push(self, positions: Sequence[float], direction: Direction = "positive") -> int: ...
    def room(self) -> int: ...
    def state(self) -> Literal["idle", "armed", "done"]: ...
    def disarm(self) -> None: ...
    def status(self) -> Tuple[int, int, int, float]: ...

class Probe:
    """A touch probe of an axis."""

    def arm(
        self,
        input: Optional[int],
        *,
        rising: bool = True,
        falling: bool = False,
        continuous: bool = False,
        window: Optional[Tuple[float, float]] = None,
    ) -> None: ...
    def abort(self) -> None: ...
    def positions(self) -> list[float]: ...
    def wait_capture(self, n: int = 1, timeout: Optional[float] = None) -> float: ...

class PathLimits:
    def __init__(
        self,
        velocity: float,
        acceleration: float,
        jerk: float,
        *,
        deceleration: Optional[float] = None,
    ) -> None: ...
    @property
    def velocity(self) -> float: ...
    @property
    def acceleration(self) -> float: ...
    @property
    def deceleration(self) -> float: ...
    @property
    def jerk(self) -> float: ...

class Segment:
    """One segment of a group's path."""

    @staticmethod
    def line(
        id: int,
        target: Sequence[float],
        feed: float,
        tolerance: float = 0.0,
        *,
        relative: bool = False,
        last: bool = False,
    ) -> Segment: ...
    @overload
    @staticmethod
    def arc(
        id: int,
        end: Tuple[float, float],
        centre: Tuple[float, float],
        feed: float,
        tolerance: float = 0.0,
        *,
        ccw: Optional[bool] = None,
        plane: Optional[Plane] = None,
        helix: Sequence[float] = ...,
        relative: bool = False,
        last: bool = False,
    ) -> Segment: ...
    @overload
    @staticmethod
    def arc(
        id: int,
        end: Tuple[float, float],
        *,
        feed: float,
        radius: float,
        tolerance: float = 0.0,
        ccw: Optional[bool] = None,
        plane: Optional[Plane] = None,
        helix: Sequence[float] = ...,
        relative: bool = False,
        last: bool = False,
    ) -> Segment: ...
    @overload
    @staticmethod
    def arc(
        id: int,
        end: Tuple[float, float],
        *,
        feed: float,
        via: Tuple[float, float],
        tolerance: float = 0.0,
        plane: Optional[Plane] = None,
        helix: Sequence[float] = ...,
        relative: bool = False,
        last: bool = False,
    ) -> Segment: ...
    @staticmethod
    def arc_normal(
        id: int,
        end: Tuple[float, float, float],
        centre: Tuple[float, float, float],
        feed: float,
        tolerance: float = 0.0,
        *,
        normal: Tuple[float, float, float],
        axes: Tuple[int, int, int] = (0, 1, 2),
        rise: bool = False,
        helix: Sequence[float] = ...,
        relative: bool = False,
        last: bool = False,
    ) -> Segment: ...
    @staticmethod
    def nurbs(
        id: int,
        curve: Nurbs,
        feed: float,
        tolerance: float = 0.0,
        *,
        fit_tolerance: float,
        relative: bool = False,
        last: bool = False,
    ) -> Segment: ...
    @staticmethod
    def dwell(id: int, seconds: float, *, last: bool = False) -> Segment: ...
    @property
    def id(self) -> int: ...
    def with_buffer(self, mode: BufferMode) -> Segment: ...
    def with_transition(self, kind: TransitionKind, distance: float = 0.0) -> Segment: ...
    def fit_within(self, tolerance: float) -> Segment: ...
    @property
    def buffer(self) -> BufferMode: ...
    @property
    def transition(self) -> Tuple[TransitionKind, float]: ...
    @property
    def fit_tolerance(self) -> Optional[float]: ...

class PathOutput:
    """Set or clear a digital output at a point of the next motion segment of a path."""

    def __init__(
        self, output: int, on: bool, at: Union[Literal["start", "end"], float] = "start"
    ) -> None: ...
    @property
    def output(self) -> int: ...
    @property
    def on(self) -> bool: ...
    @property
    def at(self) -> Union[Literal["start", "end"], float]: ...

class Nurbs:
    """A NURBS curve, checked when made."""

    def __init__(
        self,
        control_points: Sequence[Sequence[float]],
        *,
        degree: int = 3,
        weights: Optional[Sequence[float]] = None,
        knots: Optional[Sequence[float]] = None,
    ) -> None: ...
    @staticmethod
    def split(
        control_points: Sequence[Sequence[float]],
        *,
        degree: int = 3,
        weights: Optional[Sequence[float]] = None,
        knots: Optional[Sequence[float]] = None,
        max_ctrl: int = ...,
    ) -> list[Nurbs]: ...
    @property
    def degree(self) -> int: ...
    @property
    def control_points(self) -> list[list[float]]: ...
    @property
    def weights(self) -> list[float]: ...
    @property
    def knots(self) -> list[float]: ...
    def point(self, u: float) -> list[float]: ...

class GroupMotion:
    @property
    def seq(self) -> int: ...
    def wait(self, timeout: Optional[float] = None) -> None: ...
    def __await__(self) -> Generator[Any, None, None]: ...

class GroupHoming:
    @property
    def seq(self) -> int: ...
    def wait(self, timeout: Optional[float] = None) -> int: ...

class GroupStatus:
    @property
    def state(self) -> GroupState: ...
    queued: int

class Group:
    @property
    def index(self) -> int: ...
    def configure(
        self,
        axes: Sequence[int],
        *,
        tolerance: Optional[float] = None,
        accdec: Literal["pre", "post", "both"] = "pre",
    ) -> None: ...
    def configure_path(self, velocity: float, acceleration: float, jerk: float) -> None: ...
    def axes(self) -> list[int]: ...
    def enable(self) -> None: ...
    def disable(self) -> None: ...
    def move_linear(
        self,
        target: Sequence[float],
        limits: PathLimits,
        *,
        relative: bool = False,
        buffered: bool = False,
        feed_type: FeedType = "cutting",
    ) -> GroupMotion: ...
    def move_ptp(
        self,
        target: Sequence[float],
        limits: PathLimits,
        *,
        relative: bool = False,
        buffered: bool = False,
    ) -> GroupMotion: ...
    @overload
    def move_circular(
        self,
        end: Tuple[float, float],
        centre: Tuple[float, float],
        limits: PathLimits,
        *,
        ccw: Optional[bool] = None,
        plane: Optional[Plane] = None,
        helix: Sequence[float] = ...,
        relative: bool = False,
        buffered: bool = False,
    ) -> GroupMotion: ...
    @overload
    def move_circular(
        self,
        end: Tuple[float, float],
        *,
        limits: PathLimits,
        radius: float,
        ccw: Optional[bool] = None,
        plane: Optional[Plane] = None,
        helix: Sequence[float] = ...,
        relative: bool = False,
        buffered: bool = False,
    ) -> GroupMotion: ...
    @overload
    def move_circular(
        self,
        end: Tuple[float, float],
        *,
        limits: PathLimits,
        via: Tuple[float, float],
        plane: Optional[Plane] = None,
        helix: Sequence[float] = ...,
        relative: bool = False,
        buffered: bool = False,
    ) -> GroupMotion: ...
    def move_circular_normal(
        self,
        end: Tuple[float, float, float],
        centre: Tuple[float, float, float],
        limits: PathLimits,
        *,
        normal: Tuple[float, float, float],
        axes: Tuple[int, int, int] = (0, 1, 2),
        rise: bool = False,
        turns: int = 0,
        helix: Sequence[float] = ...,
        relative: bool = False,
        buffered: bool = False,
    ) -> GroupMotion: ...
    def halt(self, deceleration: float, jerk: float) -> GroupMotion: ...
    def stop(self, deceleration: float, jerk: float) -> GroupMotion: ...
    def release_stop(self) -> None: ...
    def reset(self) -> None: ...
    def set_override(self, feed: float, rapid: float) -> None: ...
    def wait_done(self, timeout: Optional[float] = None) -> None: ...
    def status(self) -> GroupStatus: ...
    def home(self, order: Sequence[Sequence[int]] = ...) -> GroupHoming: ...
    def move_nurbs(
        self,
        control_points: Sequence[Sequence[float]],
        *,
        degree: int,
        feed: float,
        acceleration: float,
        jerk: float,
        weights: Optional[Sequence[float]] = None,
        knots: Optional[Sequence[float]] = None,
        chord_tolerance: Optional[float] = None,
        saturation: Optional[float] = None,
        buffered: bool = False,
    ) -> GroupMotion: ...
    def move_nurbs_path(
        self,
        pieces: Sequence[Nurbs],
        *,
        feed: float,
        acceleration: float,
        jerk: float,
        chord_tolerance: Optional[float] = None,
        saturation: Optional[float] = None,
        timeout: Optional[float] = None,
    ) -> GroupMotion: ...
    def pso(
        self,
        output: int,
        *,
        gate: int,
        min: float,
        max: float,
        v_ref: float,
        pwm_hz: Optional[float] = None,
        filter_hz: float = 0.0,
    ) -> None: ...
    def stream_path(
        self, segments: Sequence[Union[Segment, PathOutput]]
    ) -> Optional[GroupMotion]: ...
    @overload
    def path_push(self, item: Segment) -> GroupMotion: ...
    @overload
    def path_push(self, item: PathOutput) -> None: ...
    def path_pause(self) -> None: ...
    def path_resume(self) -> None: ...
    def path_pause_state(self) -> Tuple[PauseState, Optional[int]]: ...
    def path_free(self) -> int: ...
    def run_gcode(
        self,
        text: str,
        *,
        axes: str = "XYZ",
        rapid_feed: Optional[float] = None,
        max_feed: Optional[float] = None,
        timeout: Optional[float] = None,
    ) -> Literal["done", "paused", "aborted", "running"]: ...

class PathSettings:
    """The limits of a path across cards: per dimension (in its axis's units), the look-ahead,
    the tangential limits (the first dimension's units; 0: from the axes) and the planner
    period (s; 0: the card's default)."""

    def __init__(
        self,
        vmax: Sequence[float],
        amax: Sequence[float],
        jmax: Sequence[float],
        *,
        lookahead: int = 256,
        accel: float = 0.0,
        jerk: float = 0.0,
        plan_period: float = 0.0,
    ) -> None: ...
    @staticmethod
    def uniform(n: int, velocity: float, acceleration: float, jerk: float) -> PathSettings: ...
    @property
    def vmax(self) -> list[float]: ...
    @property
    def amax(self) -> list[float]: ...
    @property
    def jmax(self) -> list[float]: ...
    @property
    def lookahead(self) -> int: ...

class SetPathProgress:
    staged: int
    queued: int
    done: int

class SetPath:
    """A path across the cards of a CardSet (CardSet.path)."""

    @property
    def dims(self) -> int: ...
    def push(self, segment: Segment) -> None: ...
    def release(self) -> int: ...
    def run(self, segments: Sequence[Segment]) -> int: ...
    def progress(self) -> SetPathProgress: ...
    def wait(self, timeout: Optional[float] = None) -> None: ...
    def halt(self, deceleration: float, jerk: float) -> int: ...
    def hold(self) -> int: ...
    def set_override(self, factor: float) -> int: ...
    def pause(self, on: bool = True) -> int: ...

class TimedScope:
    """Commands timed to one tick (``with card.timed(tick, key=...) as t``)."""

    @property
    def tick(self) -> int: ...
    @property
    def key(self) -> int: ...
    @property
    def held(self) -> int: ...
    @property
    def ended(self) -> bool: ...
    def end(self) -> int: ...
    def wait(self, timeout: float = 5.0) -> None: ...
    def __enter__(self) -> TimedScope: ...
    def __exit__(
        self,
        exc_type: Optional[type[BaseException]],
        exc: Optional[BaseException] = None,
        tb: Optional[TracebackType] = None,
    ) -> bool: ...

class SyncScope:
    """Commands timed to one tick on the cards of a set (``with cards.sync() as s``)."""

    @property
    def tick(self) -> int: ...
    @property
    def committed(self) -> bool: ...
    def commit(self) -> int: ...
    def cancel(self) -> None: ...
    def __enter__(self) -> SyncScope: ...
    def __exit__(
        self,
        exc_type: Optional[type[BaseException]],
        exc: Optional[BaseException] = None,
        tb: Optional[TracebackType] = None,
    ) -> bool: ...

class CardSet:
    """Cards on one sync bus, the master first, driven as one."""

    @staticmethod
    def sim(
        n: int,
        *,
        clock: Clock = "stepped",
        axes: int = 8,
        servo_rate_hz: int = 10_000,
        margin: Optional[float] = None,
    ) -> CardSet: ...
    @staticmethod
    def open(uris: Sequence[str], *, margin: Optional[float] = None) -> CardSet: ...
    @property
    def cards(self) -> list[Card]: ...
    def __len__(self) -> int: ...
    def tick(self) -> int: ...
    def sync(self) -> SyncScope: ...
    def halt(self, deceleration: float, jerk: float) -> int: ...
    def hold(self) -> int: ...
    def set_override(self, factor: float) -> int: ...
    def path(self, parts: Sequence[Tuple[int, int]], settings: PathSettings) -> SetPath: ...

class Capture:
    """A finished capture: `time` (s from the trigger) and one array per channel."""

    @property
    def time(self) -> npt.NDArray[np.float64]: ...
    @property
    def ticks(self) -> npt.NDArray[np.uint64]: ...
    @property
    def channels(self) -> list[npt.NDArray[np.float64]]: ...
    @property
    def sources(self) -> list[Tuple[str, int]]: ...
    trigger_tick: int
    lost: int
    def __getitem__(self, k: int) -> npt.NDArray[np.float64]: ...
    def __len__(self) -> int: ...
    def __iter__(self) -> Iterator[npt.NDArray[np.float64]]: ...

class Scope:
    def capture(
        self,
        channels: Sequence[Tuple[Union[Signal, int, str], int]],
        samples: int,
        *,
        divider: int = 1,
        pre_trigger: int = 0,
        trigger: Trigger = "immediate",
        trigger_channel: int = 0,
        level: float = 0.0,
        trigger_input: int = 0,
        edge: Edge = "rising",
        timeout: float = 10.0,
        while_armed: Optional[Callable[[], object]] = None,
    ) -> Capture: ...
    def trigger(self) -> None: ...

async def wait_async(motion: Motion, timeout: Optional[float] = None) -> float: ...
async def group_wait_async(motion: GroupMotion, timeout: Optional[float] = None) -> None: ...
async def next_event_async(
    card: Union[Card, Events], timeout: Optional[float] = None
) -> Optional[Event]: ...
def events_async(
    card: Union[Card, Events], timeout: Optional[float] = 1.0
) -> AsyncIterator[Event]: ...

# BEGIN GENERATED
class AxisState(enum.IntEnum):
    """PLCopen axis states."""

    DISABLED = 0
    STANDSTILL = 1
    HOMING = 2
    DISCRETE_MOTION = 3
    CONTINUOUS_MOTION = 4
    SYNCHRONIZED_MOTION = 5
    STOPPING = 6
    ERROR_STOP = 7

class GroupState(enum.IntEnum):
    """PLCopen group states."""

    DISABLED = 0
    STANDBY = 1
    MOVING = 2
    HOMING = 3
    STOPPING = 4
    ERROR_STOP = 5

class EventKind(enum.IntEnum):
    """Event kinds."""

    ACK = 1
    NACK = 2
    MOTION_DONE = 3
    STATE_CHANGED = 4
    FAULT = 5
    MOTION_ABORTED = 6
    GROUP_MOTION_DONE = 8
    GROUP_STATE_CHANGED = 9
    GROUP_MOTION_ABORTED = 10
    MOTION_ACTIVE = 11
    IN_VELOCITY = 12
    HOMING_FAILED = 13
    SAFETY_STOP = 16
    AT_REST = 17
    PROTOCOL_ERROR = 18
    SEGMENT_START = 20
    SEGMENT_END = 21
    PATH_LOW_WATER = 22
    PATH_STARVED = 23
    INPUT = 24
    COMPARE = 25
    PROBE = 26
    SYNC = 27
    PVT = 28
    SCOPE = 29
    GROUP_HOMED = 30
    GROUP_HOMING_FAILED = 31
    GANTRY_FAULT = 32
    GANTRY_HOMED = 33
    ANALOG = 34
    PATH_PAUSED = 36
    FREQ_DONE = 37
    SYNC_BUS = 38
    TIMED = 39

class Signal(enum.IntEnum):
    """Scope signals."""

    CMD_POS = 1
    CMD_VEL = 2
    CMD_ACC = 3
    ACT_POS = 4
    ACT_VEL = 5
    FERR = 6
    DAC = 7
    U_REQUEST = 8
    ENCODER = 9
    SERVO_P = 10
    SERVO_I = 11
    SERVO_D = 12
    SERVO_FF = 13
    GANTRY_SKEW = 14
    COMP_POS = 15
    FILTER_IN = 16
    FILTER_OUT = 17
    SERVO_FRICTION = 18
    FREQ_INJECT = 19
    FREQ_HZ = 20
    PATH_SPEED = 32
    PATH_ACC = 33
    PATH_POS = 34
    INPUTS = 48
    OUTPUTS = 49
    INPUTS_RAW = 50
    AIN0 = 51
    AIN1 = 52
    AIN2 = 53
    AIN3 = 54
    AIN4 = 55
    AIN5 = 56
    AIN6 = 57
    AIN7 = 58
    AOUT0 = 59
    AOUT1 = 60
    AOUT2 = 61
    AOUT3 = 62
    PSO = 63

class StopCategory(enum.IntEnum):
    """Stop categories."""

    CAT0 = 0
    CAT1 = 1
    CAT2 = 2

class StopReason(enum.IntEnum):
    """Why an axis's last motion ended."""

    NONE = 0
    DONE = 1
    HALT = 2
    STOP = 3
    POWER_OFF = 4
    HOST_DETACH = 5
    HOMING_FAILED = 6
    PROBE = 7
    GROUP_HOMING = 8
    SYNC_LOST = 9
    WATCHDOG = 16
    E_STOP_COMMAND = 17
    E_STOP_INPUT = 18
    HARD_LIMIT_POS = 19
    HARD_LIMIT_NEG = 20
    SOFT_LIMIT_POS = 21
    SOFT_LIMIT_NEG = 22
    FOLLOWING_ERROR = 23
    AMP_ALARM = 24
    ENCODER_LOSS = 25
    ENCODER_JUMP = 26
    STARVATION = 27
    CMD_RING = 28
    EVT_RING = 29
    GROUP = 30
    STOP_TIMEOUT = 31
    HOST_CHANGED = 32
    NO_SESSION = 33
    GANTRY_SKEW = 34
    GANTRY = 35

class BadUriError(Error):
    """BadUri (-1): bad card URI"""

class NotFoundError(Error):
    """NotFound (-2): no card at that URI"""

class BusyError(Error):
    """Busy (-3): the card is already open (by another process, or by this one)"""

class VersionMismatchError(Error):
    """VersionMismatch (-4): the card's DPRAM layout version differs from the library's"""

class NotRespondingError(Error):
    """NotResponding (-5): the card does not respond"""

class ProtocolError(Error):
    """Protocol (-6): the card broke the protocol"""

class RingFullError(Error):
    """RingFull (-7): the command ring is full"""

class TimeoutError(Error):
    """Timeout (-8): timed out"""

class AbortedError(Error):
    """Aborted (-9): the motion was aborted"""

class BadAxisError(Error):
    """BadAxis (-10): no such axis"""

class NotFiniteError(Error):
    """NotFinite (-11): an argument is NaN or infinite"""

class NonPositiveLimitError(Error):
    """NonPositiveLimit (-12): a limit is zero or negative"""

class AxisDisabledError(Error):
    """AxisDisabled (-13): the axis is disabled"""

class InvalidStateError(Error):
    """InvalidState (-14): not allowed in the axis's current state"""

class BadConfigError(Error):
    """BadConfig (-15): a configuration value is out of range"""

class InfeasibleError(Error):
    """Infeasible (-16): no profile satisfies the request"""

class OutOfRangeError(Error):
    """OutOfRange (-17): a position or velocity out of range"""

class AxesEnabledError(Error):
    """AxesEnabled (-18): all axes must be disabled first"""

class UnknownCommandError(Error):
    """UnknownCommand (-19): unknown command"""

class BadGroupError(Error):
    """BadGroup (-22): no such group"""

class AxisInOtherGroupError(Error):
    """AxisInOtherGroup (-23): an axis already belongs to another group"""

class AxisNotInGroupError(Error):
    """AxisNotInGroup (-24): the move needs an axis the group does not have"""

class AxisBusyError(Error):
    """AxisBusy (-25): an axis of the group is moving on its own"""

class AxisGroupedError(Error):
    """AxisGrouped (-26): the axis belongs to an enabled group"""

class ZeroLengthArcError(Error):
    """ZeroLengthArc (-27): the arc has zero length or zero radius"""

class CentreNotEquidistantError(Error):
    """CentreNotEquidistant (-28): the centre is not equidistant from start and end"""

class RadiusTooSmallError(Error):
    """RadiusTooSmall (-29): the radius is shorter than half the chord"""

class CollinearPointsError(Error):
    """CollinearPoints (-30): the three points are on one line"""

class QueueFullError(Error):
    """QueueFull (-31): the move queue (the group's or the axis's) is full"""

class IncompatibleModeError(Error):
    """IncompatibleMode (-32): the interpolator cannot run with this acc/dec mode"""

class GroupDisabledError(Error):
    """GroupDisabled (-33): the group is disabled"""

class FilterBusyError(Error):
    """FilterBusy (-34): the filter still holds distance"""

class NurbsSequenceError(Error):
    """NurbsSequence (-35): NURBS data out of sequence (no begin, a gap, or missing data)"""

class NurbsDegreeError(Error):
    """NurbsDegree (-36): NURBS degree outside 1..5"""

class NurbsDimensionError(Error):
    """NurbsDimension (-37): NURBS curves need a group of at least 2 axes"""

class NurbsCtrlCountError(Error):
    """NurbsCtrlCount (-38): too few or too many NURBS control points"""

class NurbsKnotCountError(Error):
    """NurbsKnotCount (-39): the knot count must be control points + degree + 1"""

class NurbsKnotsDecreasingError(Error):
    """NurbsKnotsDecreasing (-40): the knots decrease"""

class NurbsKnotMultiplicityError(Error):
    """NurbsKnotMultiplicity (-41): an interior knot is repeated more than degree times"""

class NurbsNotClampedError(Error):
    """NurbsNotClamped (-42): the knot vector is not clamped"""

class NurbsWeightError(Error):
    """NurbsWeight (-43): a weight is not finite and positive"""

class NurbsPointError(Error):
    """NurbsPoint (-44): a control point is not finite"""

class NurbsStartError(Error):
    """NurbsStart (-45): the curve does not start where the group is"""

class NurbsZeroLengthError(Error):
    """NurbsZeroLength (-46): the curve has zero length"""

class NurbsKnotError(Error):
    """NurbsKnot (-54): a knot is not finite"""

class IoError(Error):
    """Io (-20): an operating-system call failed"""

class UnsupportedError(Error):
    """Unsupported (-21): not supported by this card"""

class WatchdogTrippedError(Error):
    """WatchdogTripped (-47): the host watchdog tripped: reset the card's faults first"""

class EStopActiveError(Error):
    """EStopActive (-48): an e-stop is latched: reset the card's faults first"""

class HardLimitError(Error):
    """HardLimit (-49): the move goes further into an active limit switch"""

class SoftLimitError(Error):
    """SoftLimit (-50): the move goes further beyond a soft limit"""

class CauseActiveError(Error):
    """CauseActive (-51): the cause of the fault is still present"""

class WatchdogTimeoutError(Error):
    """WatchdogTimeout (-52): watchdog timeout is zero or under 1.5 x the host's heartbeat period"""

class BadCategoryError(Error):
    """BadCategory (-53): stop category must be 0, 1 or 2"""

class LimitRangeError(Error):
    """LimitRange (-55): a limit is outside the range the card accepts (one count in 1e6 s to the whole position range in one servo tick)"""

class PlanCheckError(Error):
    """PlanCheck (-56): the planned profile failed the card's check; nothing moved"""

class ExpiredError(Error):
    """Expired (-57): the card served the command after its deadline; it was not executed"""

class StopTooLongError(Error):
    """StopTooLong (-58): the stop ramp from max velocity is longer than the card's maximum stop time"""

class SessionError(Error):
    """Session (-59): another host's session is attached"""

class NoSessionError(Error):
    """NoSession (-108): no host session is attached: the card refuses motion, power, outputs and configuration until a host attaches"""

class CardGoneError(Error):
    """CardGone (-60): the card went away"""

class ClosedError(Error):
    """Closed (-61): the card was closed"""

class CancelledError(Error):
    """Cancelled (-62): the wait was cancelled"""

class PermissionDeniedError(Error):
    """PermissionDenied (-63): the card's server refused this user"""

class OverrideRangeError(Error):
    """OverrideRange (-64): the override factor is outside 0 to 2 (0 % to 200 %)"""

class HomingMethodError(Error):
    """HomingMethod (-65): the axis cannot do this homing method"""

class AxisHomingError(Error):
    """AxisHoming (-66): the axis is homing"""

class HomingFailedError(Error):
    """HomingFailed (-67): homing failed: the axis stopped, not homed"""

class PathModeError(Error):
    """PathMode (-68): unknown path buffer or transition mode"""

class PathZeroLengthError(Error):
    """PathZeroLength (-69): the path line has zero length"""

class PathOutputError(Error):
    """PathOutput (-70): bad output number, or too many output actions before a segment"""

class PathBusyError(Error):
    """PathBusy (-71): the group's path and its move queue do not mix: wait for the other to finish"""

class PathIdError(Error):
    """PathId (-72): a segment id must be an integer in 0..2^32-1"""

class PathCurveError(Error):
    """PathCurve (-73): the NURBS path segment has a cusp or needs more pieces than the path buffer holds"""

class IoConfigError(Error):
    """IoConfig (-90): bad digital input configuration (input number or debounce)"""

class IoChannelError(Error):
    """IoChannel (-91): no such compare or probe channel"""

class CompareModeError(Error):
    """CompareMode (-92): bad compare mode, direction, output, pulse width, pitch or count"""

class CompareFullError(Error):
    """CompareFull (-93): the compare table is full"""

class CompareOrderError(Error):
    """CompareOrder (-94): compare positions must be strictly monotonic in the direction"""

class CompareBusyError(Error):
    """CompareBusy (-95): the compare channel or its output is in use"""

class ProbeInputError(Error):
    """ProbeInput (-96): bad probe input, edge or window"""

class GearRatioError(Error):
    """GearRatio (-74): a gear ratio must be integer numerator / positive integer denominator, each of magnitude 1..2^31-1"""

class SyncMasterError(Error):
    """SyncMaster (-75): no such master, the slave itself, or a master axis disabled or in ErrorStop"""

class PvtTimeError(Error):
    """PvtTime (-76): a PT/PVT point must come at least one servo period, and at most 1e6 s (the longest move), after the one before"""

class PvtLimitError(Error):
    """PvtLimit (-77): the PT/PVT segment into this point breaks the velocity or acceleration limit"""

class PvtSequenceError(Error):
    """PvtSequence (-78): PT/PVT commands out of sequence"""

class CamTableError(Error):
    """CamTable (-79): bad cam table: number, points (master strictly increasing, finite), not loaded, or in use"""

class CamSequenceError(Error):
    """CamSequence (-80): cam table data out of sequence"""

class ScopeSignalError(Error):
    """ScopeSignal (-81): unknown scope signal, or no such axis or group"""

class ScopeChannelsError(Error):
    """ScopeChannels (-82): a scope samples 1 to 16 channels"""

class ScopeDividerError(Error):
    """ScopeDivider (-83): the scope divider must be 1..65536"""

class ScopeTriggerError(Error):
    """ScopeTrigger (-84): bad scope mode or trigger (kind, edge, channel, input, level, or no samples after it)"""

class ScopePretriggerError(Error):
    """ScopePretrigger (-85): more pre-trigger samples than the card keeps (1024)"""

class ScopeStateError(Error):
    """ScopeState (-86): the scope's state does not allow this (configure or arm while armed, trigger while not waiting, stop while idle, arm before configure)"""

class ConfigKindError(Error):
    """ConfigKind (-106): the card does not know that configuration block"""

class CompTableError(Error):
    """CompTable (-110): bad compensation table: point count, bound, backlash or ramp limits out of range"""

class CompSequenceError(Error):
    """CompSequence (-111): compensation table data out of sequence"""

class CompOrderError(Error):
    """CompOrder (-112): compensation positions must be strictly increasing"""

class CompBoundError(Error):
    """CompBound (-113): a compensation correction is beyond the table's bound"""

class CompBusyError(Error):
    """CompBusy (-114): the axis is not at rest: its compensation cannot change"""

class ModuloZeroError(Error):
    """ModuloZero (-116): a modulo period of zero: use clear_modulo to make the axis linear"""

class ModuloRangeError(Error):
    """ModuloRange (-117): modulo period out of range (negative, not finite, under 1 count or over 1e11 counts)"""

class ModuloBusyError(Error):
    """ModuloBusy (-118): the axis is not at rest: its modulo period cannot change"""

class ModuloMoveError(Error):
    """ModuloMove (-119): the move does not fit the axis: a modulo axis takes targets in [0, modulo), a linear axis no direction"""

class HandwheelInputError(Error):
    """HandwheelInput (-120): the card has no such handwheel (auxiliary encoder) input"""

class HandwheelRatioError(Error):
    """HandwheelRatio (-121): bad handwheel ratio (0 or beyond 10000 counts per detent) or detent (1 to 1024 counts)"""

class ConfigFileError(Error):
    """ConfigFile (-107): the configuration file does not parse or validate"""

class GcodeError(Error):
    """Gcode (-109): the G-code program has an error (see the error's line)"""

class NoMotionError(Error):
    """NoMotion (-115): no motion to wait for: none was started there by this process since the card was opened"""

class GantrySlaveError(Error):
    """GantrySlave (-125): the axis is a gantry's slave: command its master"""

class GantryInUseError(Error):
    """GantryInUse (-126): a gantry axis is already in use (another gantry, a group, gearing or a stream)"""

class GantryAxesError(Error):
    """GantryAxes (-127): bad gantry axes: out of range, master among the slaves, a slave twice, or a bad count"""

class GantryGainsError(Error):
    """GantryGains (-128): gantry kp, ki, skew limit or offset out of range"""

class GantryStateError(Error):
    """GantryState (-129): the gantry or its axes are not in a state that takes this"""

class HomeAxisError(Error):
    """HomeAxis (-122): the home order names an axis the group does not have"""

class HomeTwiceError(Error):
    """HomeTwice (-123): the home order names an axis twice"""

class HomeStageError(Error):
    """HomeStage (-124): the home order has an empty stage (or no stages, and the group has none configured)"""

class PlaneAxesError(Error):
    """PlaneAxes (-130): an arc's plane names one group axis twice"""

class FilterKindError(Error):
    """FilterKind (-131): bad servo filter slot (0..3) or kind"""

class FilterFreqError(Error):
    """FilterFreq (-132): servo filter frequency must be above 0 and below half the servo rate"""

class FilterParamError(Error):
    """FilterParam (-133): servo filter damping (0..10], depth (-120..0 dB) or raw coefficient out of range"""

class FilterUnstableError(Error):
    """FilterUnstable (-134): unstable servo filter: a pole is not inside the unit circle"""

class PidffGainsError(Error):
    """PidffGains (-135): bad PID+FF gains: every gain >= 0, derivative cut-off and friction deadband > 0"""

class AnalogChannelError(Error):
    """AnalogChannel (-136): no such analog input or output (inputs 0..7, outputs 0..3), or a DAC the PSO drives"""

class AnalogFilterError(Error):
    """AnalogFilter (-137): an analog filter cut-off below 0 or above half the servo rate"""

class AnalogThresholdError(Error):
    """AnalogThreshold (-138): an analog threshold beyond +-10 V or a hysteresis outside 0..20 V"""

class PsoConfigError(Error):
    """PsoConfig (-139): bad path-speed output: output, gate, min > max, range, reference speed or PWM frequency"""

class PsoGroupError(Error):
    """PsoGroup (-140): the path-speed output's group does not exist or is not configured"""

class AmbiguousError(Error):
    """Ambiguous (-150): more than one card has that name or serial: open it by its URI"""

class TickPassedError(Error):
    """TickPassed (-152): the tick of the timed command has passed on the card"""

class TimedFullError(Error):
    """TimedFull (-153): the card holds 16 timed commands already"""

class TimedAloneError(Error):
    """TimedAlone (-154): a timed command without its command, or of one that cannot be timed"""

class TickFarError(Error):
    """TickFar (-155): the tick is too far ahead (600000 ticks at most), or not a whole number"""

class CommitLateError(Error):
    """CommitLate (-156): the commit arrived on or after its tick: nothing of it runs on any card"""

class NotMasterError(Error):
    """NotMaster (-157): this card follows the sync bus: commit on its master"""

class NotCommittedError(Error):
    """NotCommitted (-158): the timed command's commit did not come before its tick: not run"""

class SyncLostError(Error):
    """SyncLost (-159): the card lost the sync bus's master"""

class TimedRefusedError(Error):
    """TimedRefused (-160): its timing was refused: the command does not run"""

class TimedCancelledError(Error):
    """TimedCancelled (-161): the timed command was cancelled before its tick"""

class ArcNormalError(Error):
    """ArcNormal (-147): an arc's normal vector is zero (or no normal plane was set)"""

class ArcAxesError(Error):
    """ArcAxes (-148): an arc's plane of three group axes names one axis twice"""

class ArcOffPlaneError(Error):
    """ArcOffPlane (-149): the arc's centre or end is off its plane by more than the group's tolerance"""

class ArcPieceError(Error):
    """ArcPiece (-151): a piece of a normal-vector arc move came alone or out of order (its two entries go together)"""

class FreqRangeError(Error):
    """FreqRange (-141): sweep frequencies must be 0.1 Hz <= from <= to <= a quarter of the servo rate, with 1..256 points, 1..1000 cycles and 0..60 s settling"""

class FreqAmplitudeError(Error):
    """FreqAmplitude (-142): sweep amplitude must be above 0 (and within the DAC limit on the servo output)"""

class FreqLimitsError(Error):
    """FreqLimits (-143): the sweep's sine would exceed the axis's velocity, acceleration, following error or soft limits"""

class FreqBusyError(Error):
    """FreqBusy (-144): a frequency sweep is running (stop it first)"""

class PsoOutputError(Error):
    """PsoOutput (-145): the output is the path-speed output's PWM: no compare channel on it"""

class CompareTurnError(Error):
    """CompareTurn (-146): compare on a rotary axis: positions must lie in [0, modulo) and a series within one turn (each turn: rotary axes only; no period change while a channel watches the axis)"""

class PathDimsError(Error):
    """PathDims (-162): the path's dimensions must name each axis of the group exactly once (at most 16 dimensions)"""

class PathMoreError(Error):
    """PathMore (-163): a segment of more than 8 dimensions came without its second entry (its two entries go together)"""

class PathReleaseError(Error):
    """PathRelease (-164): the release names more segments than are staged (or the group moved since they were staged)"""

# END GENERATED

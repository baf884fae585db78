"""The stated ranges of rlff's inputs, checked up front with messages that carry the numbers.

Sizes are checked before anything is allocated, so that a typo (``angle=0:2:100000000``,
``densify step = 1e-9``) is one line and exit 2 instead of tens of gigabytes and a killed process.
Physical quantities are checked against ranges that hold for a throwing arm of the size rlff
models (the Comau Smart5 SiX: about 1.4 m of reach) with a wide margin. A single name given
where the public functions take several (joints, columns) is that one name (:func:`as_names`).

The numbers:

- :data:`MAX_GRID_POINTS`: points of a generated path. ``rlff generate`` peaks at about 0.9 kB a
  point (1.1 GB for 1,000,000 points, measured), so the maximum needs about 2 GB; a 100,000,000
  point grid asked for about 90 GB and was killed.
- :data:`MAX_GENERATE_BYTES`: what the climbs of a generated path may hold. Each point keeps
  every start's end point: 8 bytes x (K (1 + 2 O) + 3) starts x (O + 2) values for K components
  and O outputs, 4.5 kB for a whole-arm model of K = 7 and 5 outputs (4.6 kB measured), so such
  a model is held to about 450,000 points where a one-output model keeps the 2,000,000 (a
  1,000,000-point path of a K = 8 whole-arm model grew past 3.3 GB and ran for hours).
- :data:`MAX_DENSIFY_SAMPLES`: samples a resampling step (``densify``) may make, all trajectories
  together (8 bytes a value, a few columns and spline copies: about 1 GB at the maximum).
- :data:`MAX_MAGNITUDE`: the largest magnitude of a data value or a model parameter. Mixtures
  square and sum values; with ``|x| <= 1e100`` every square and sum of squares of up to 1e100
  samples stays finite, where 1e308 overflows to inf and ends in a division by zero.
- :data:`DISTANCE_RANGE`: basket distances (m) from the robot's base or the thrower: from just
  outside the base (0.3 m) to 20 m, far beyond what a person or this arm throws.
- :data:`PEDESTAL_RANGE`: height (m) of the robot's base above the ground.
- :data:`FRAME_RATE_RANGE`: the frame rate (Hz) of a recording without time stamps: depth cameras
  and skeleton trackers record at 4 to 120 Hz, motion capture up to a few hundred; 1 to 1000 Hz
  holds them all with a margin. 1e300 Hz made every time step 0 and a singular matrix.
- :data:`MAX_JOINT_ANGLE`: the largest human joint angle (rad) a path or a dataset may hold, two
  turns (:func:`require_radians`). An elbow's included angle lies within 0 to pi; beyond two turns
  the angles are degrees (40-170), which had gone through cleaning, fitting and generating to a
  robot limit error that pointed at --clip and the robot file.
- :data:`MIN_PERIOD`: the shortest controller period (s) a trajectory is planned at. Arm
  controllers run at 100 Hz to 1 kHz (rlff plans at 2 ms or 10 ms, :data:`CONTROLLER_PERIODS`
  of :mod:`rlff.trajectory.resample`); 10 kHz leaves a margin. ``--period 0.000001`` wrote a 130 MB
  file of a throw of 0.85 s, 1e-9 ran out of memory. :data:`MAX_PERIOD` the longest, 1 s: no arm
  controller samples a motion so coarsely, and ``--period 10`` (milliseconds meant) was taken as
  10 s, refused as a throw too short to wind up for, or, for an approach, planned over 10 s.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping

import numpy as np

from rlff.errors import InputError

MAX_GRID_POINTS = 2_000_000
MAX_GENERATE_BYTES = 2_000_000_000
MAX_DENSIFY_SAMPLES = 20_000_000
MAX_MAGNITUDE = 1e100
DISTANCE_RANGE = (0.3, 20.0)
PEDESTAL_RANGE = (0.0, 5.0)
FRAME_RATE_RANGE = (1.0, 1000.0)
MIN_PERIOD, MAX_PERIOD = 1e-4, 1.0
MAX_JOINT_ANGLE = 4.0 * math.pi


def check_count(what: str, count: float, maximum: int, hint: str = "") -> int:
    """``count`` as an int, or an :class:`InputError` when it is above ``maximum``.

    Parameters
    ----------
    what : str
        What is counted and where it comes from, e.g. ``"--grid angle=0:2:100000000: points"``.
    count : float
        The requested count (a float when computed from a range and a step; inf allowed).
    maximum : int
    hint : str
        How to stay below it, appended to the message.
    """
    if not math.isfinite(count) or count > maximum:
        shown = f"{count:,.0f}" if math.isfinite(count) else str(count)
        raise InputError(f"{what}: {shown} is more than the {maximum:,} allowed" + (f" ({hint})" if hint else ""))
    return int(count)


def parse_number(text: str, what: str) -> float:
    """``text`` as a finite float, or an :class:`InputError` naming ``what`` it came from."""
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"{what}: {text!r} is not a number") from None
    if not math.isfinite(value):
        raise InputError(f"{what}: {text!r} is not a finite number")
    return value


def is_number(text: str) -> bool:
    """Whether ``text`` reads as a float (``nan`` and ``inf`` too): a cell or token of numbers,
    not of names."""
    try:
        float(text)
    except ValueError:
        return False
    return True


def check_range(name: str, value: float, bounds: tuple[float, float], unit: str = "m",
                hint: Callable[[float], str] | None = None) -> float:
    """``value`` as a float within ``bounds`` (inclusive), or an :class:`InputError` naming it,
    ended by ``hint(value)`` (:func:`centimetres_hint`)."""
    low, high = bounds
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: {value!r} is not a number") from None
    if math.isnan(number):
        raise InputError(f"{name}: {value!r} is not a number")
    if not low <= number <= high:
        raise InputError(f"{name}: {value:g} {unit} is outside the range {low:g} to {high:g} {unit}"
                         + (hint(number) if hint else ""))
    return number


def centimetres_hint(distance: float, bounds: tuple[float, float] = DISTANCE_RANGE, what: str = "distance",
                     nearest: float | None = None) -> str:
    """`` (centimetres? the distance is in metres)`` after a length (m) beyond ``bounds`` (default
    :data:`DISTANCE_RANGE`) that is within them in centimetres, `` (millimetres? ...)`` in
    millimetres, `` (centimetres or millimetres? ...)`` in either, else ``""``; ``what`` names the
    length, and ``nearest`` (default ``distance``) the shortest of several, which must fit too. (A
    basket of 1750 was asked about centimetres alone, 17.5 m, where 1.75 m in millimetres is the
    likelier; distances of 750 to 2750 got no hint.)"""
    low, high = bounds
    nearest = distance if nearest is None else nearest
    units = [unit for unit, per_metre in (("centimetres", 100), ("millimetres", 1000))
             if distance > high and low <= nearest / per_metre and distance / per_metre <= high]
    return f" ({' or '.join(units)}? the {what} is in metres)" if units else ""


def check_distance(name: str, value: float) -> float:
    """A basket distance (m) within :data:`DISTANCE_RANGE`; the message asks whether one is in
    centimetres or millimetres (:func:`centimetres_hint`)."""
    return check_range(name, value, DISTANCE_RANGE, hint=centimetres_hint)


def check_pedestal(value: float, name: str = "pedestal") -> float:
    """A pedestal height (m) within :data:`PEDESTAL_RANGE`; the message asks whether one is in
    centimetres or millimetres (:func:`centimetres_hint`)."""
    return check_range(name, value, PEDESTAL_RANGE,
                       hint=lambda height: centimetres_hint(height, PEDESTAL_RANGE, "height"))


def check_frame_rate(value: float, name: str = "frame rate") -> float:
    """A recording's frame rate (Hz) within :data:`FRAME_RATE_RANGE`."""
    return check_range(name, value, FRAME_RATE_RANGE, "Hz")


def check_period(value: float, name: str = "period") -> float:
    """A controller period (s): finite, at least :data:`MIN_PERIOD` and at most :data:`MAX_PERIOD`;
    ``name``: what the message calls it (``--period`` on the command line)."""
    if value is None or not (math.isfinite(value) and value > 0):
        raise InputError(f"{name} must be a positive controller period (s), got {value!r}: "
                         "the points of a path are not a trajectory a controller can follow")
    if value < MIN_PERIOD:
        raise InputError(f"{name} {value:g} s is shorter than {MIN_PERIOD:g} s (a {1 / MIN_PERIOD / 1000:g} kHz "
                         "controller): arm controllers run at 1 kHz or slower; give their period, e.g. 0.002")
    if value > MAX_PERIOD:
        raise InputError(f"{name} {value:g} s is longer than {MAX_PERIOD:g} s: a controller period is in seconds "
                         "(milliseconds? 2 ms is 0.002), and arm controllers run at 100 Hz to 1 kHz")
    return float(value)


def require_radians(values: np.ndarray, what: str) -> None:
    """:class:`InputError` when ``values`` (a human joint's angles, any shape) reach beyond
    :data:`MAX_JOINT_ANGLE`: degrees where rlff reads radians."""
    values = np.asarray(values, dtype=float)
    if values.size and float(np.nanmax(np.abs(values))) > MAX_JOINT_ANGLE:
        raise InputError(f"{what} reaches {float(np.nanmax(np.abs(values))):.4g}, beyond two turns in radians: "
                         "degrees? joint angles are in rad (an elbow's from 0, folded, to about 3.1, straight)")


def as_names(names: str | Iterable[str]) -> tuple[str, ...]:
    """``names`` (joints, columns) as a tuple; a single str is one name, ``"elbow"`` ->
    ``("elbow",)``, not the characters it is made of (``joints="elbow"`` had asked for the joints
    'e', 'l', 'b', ...)."""
    return (names,) if isinstance(names, str) else tuple(names)


def check_magnitudes(where: str, columns: Mapping[str, np.ndarray]) -> None:
    """Refuse a non-finite value or one beyond :data:`MAX_MAGNITUDE` in any column.

    Parameters
    ----------
    where : str
        The file or object the columns come from, for the message.
    columns : mapping of str to ndarray
        Named arrays of any shape.
    """
    for name, values in columns.items():
        array = np.asarray(values, dtype=float)
        bad = ~(np.abs(array) <= MAX_MAGNITUDE)  # nan compares False: caught too
        if bad.any():
            index = np.unravel_index(int(np.flatnonzero(bad)[0]), array.shape) if array.ndim else ()
            at = f" at {list(map(int, index))}" if array.ndim > 1 else (f" at row {int(index[0]) + 1}" if array.ndim else "")
            raise InputError(
                f"{where}: {name} holds {float(array[index]):g}{at}; values must be finite and within "
                f"±{MAX_MAGNITUDE:g}"
            )


def apart(value: float, limit: float, digits: int = 6) -> tuple[str, str]:
    """``value`` and ``limit`` formatted with the fewest digits (at least ``digits``) that tell them apart.

    So that a message never reads "2.792 rad/s beyond the limit 2.792 rad/s".
    """
    for precision in range(digits, 18):
        first, second = f"{value:.{precision}g}", f"{limit:.{precision}g}"
        if first != second:
            return first, second
    return repr(float(value)), repr(float(limit))


__all__ = [
    "DISTANCE_RANGE",
    "FRAME_RATE_RANGE",
    "MAX_DENSIFY_SAMPLES",
    "MAX_GENERATE_BYTES",
    "MAX_GRID_POINTS",
    "MAX_JOINT_ANGLE",
    "MAX_MAGNITUDE",
    "MAX_PERIOD",
    "MIN_PERIOD",
    "PEDESTAL_RANGE",
    "apart",
    "as_names",
    "centimetres_hint",
    "check_count",
    "check_distance",
    "check_frame_rate",
    "check_magnitudes",
    "check_pedestal",
    "check_period",
    "check_range",
    "require_radians",
]

"""What every simulated person shares: minimum-jerk moves, the camera that records them, the aim.

The one-joint people of :mod:`rlff.synthetic.throws` and the whole-arm people of
:mod:`rlff.synthetic.whole_arm` move their joints along minimum-jerk profiles, are recorded by
the same depth camera (thesis section 4.2.1: 15-30 Hz, measurement noise, dropped frames and
"second skeleton" glitches: a frame where the tracker follows someone else and every joint angle
jumps to that person's) and aim by the ball speed a parabola needs to reach the basket's rim.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from rlff.ballistics import GRAVITY
from rlff.dataset import Dataset
from rlff.errors import InputError
from rlff.limits import as_names

#: One simulated throw: its id, its columns (each of shape (T,)) and its metadata.
Throw = tuple[str, dict[str, np.ndarray], dict[str, object]]

#: The thesis' basket distances (m), section 4.2 (the three 2 m baskets of other heights left out).
THESIS_DISTANCES = (1.0, 1.5, 2.0, 2.25, 2.5, 2.75, 3.0, 3.25, 3.5, 4.0)
#: Upper arm length, shoulder to elbow (m), of every simulated person.
UPPER_ARM = 0.30
#: Height of the default basket's rim (m).
RIM_HEIGHT = 0.3
#: Fastest elbow extension a simulated person makes (rad/s; about 10 m/s at the ball).
MAX_ELBOW_SPEED = 30.0

#: The frame rates (Hz) of a depth camera, lowest and highest (thesis 4.2.1).
CAMERA_RATES = (15.0, 30.0)
#: The largest angle noise (rad, standard deviation) the camera takes: a skeleton tracker's elbow
#: angle is off by a few hundredths of a radian (the default 0.03); 0.5 rad (29 degrees) is a
#: quarter of the extension itself (0.6-0.9 rad to 2.8-3.1 rad), so more is a mistake (degrees?).
MAX_NOISE = 0.5
#: Dropped frames and glitches are probabilities per frame below this: with half the frames gone
#: or a second skeleton's, there is hardly a throw left to see.
MAX_FRAME_FAULT = 0.5

#: Where a glitch puts each joint angle (rad, uniform between the bounds): the second skeleton
#: stands idle, its elbow folded near zero (thesis 4.3.6.1), its arm down, its hand straight.
_GLITCH_RANGE = {"angle": (0.0, 0.15), "shoulder": (0.0, 0.3), "wrist": (2.9, np.pi)}
#: Measurement noise of each joint angle relative to the elbow's: the hand's segment is short, so
#: the same error in the tracked points turns the wrist's angle more.
_NOISE_SCALE = {"angle": 1.0, "shoulder": 1.0, "wrist": 2.0}


def minimum_jerk(s: np.ndarray) -> np.ndarray:
    """Position fraction of a minimum-jerk move at time fraction ``s`` in [0, 1]."""
    return s**3 * (10.0 - 15.0 * s + 6.0 * s**2)


def minimum_jerk_speed(s: np.ndarray | float) -> np.ndarray:
    """d(position fraction)/d(time fraction) of a minimum-jerk move: 30 s^2 (1 - s)^2."""
    return 30.0 * np.asarray(s) ** 2 * (1.0 - np.asarray(s)) ** 2


def needed_speed(x0: float, z0: float, launch: float, landing: float, rim_height: float) -> float | None:
    """Ball speed (m/s) that carries a ball released at ``(x0, z0)`` (m) at elevation ``launch``
    (rad) down to ``rim_height`` (m) at horizontal distance ``landing`` (m); None when no speed
    does (the basket behind the hand, or the launch line passing below the rim).

    From the parabola through the release point: z = z0 + d tan(a) - g d^2 / (2 v^2 cos^2 a),
    set to the rim height at horizontal offset d = landing - x0.
    """
    offset = landing - x0
    drop = z0 - rim_height + offset * np.tan(launch)
    if offset <= 0 or drop <= 0:
        return None
    return float(np.sqrt(GRAVITY * offset**2 / (2.0 * np.cos(launch) ** 2 * drop)))


def record(
    rng: np.random.Generator,
    positions_of_time: Callable[[np.ndarray], dict[str, np.ndarray]],
    duration: float,
    rate_hz: float,
    noise: float,
    dropped_frames: float,
    glitches: float,
) -> tuple[np.ndarray, dict[str, np.ndarray], int]:
    """Sample a throw as the camera does.

    Parameters
    ----------
    rng : numpy.random.Generator
    positions_of_time : callable
        Maps times (s), shape (T,), to the true joint angles (rad), ``{"angle": (T,), ...}``
        (joints among ``angle``, ``shoulder``, ``wrist``).
    duration : float
        Length of the recording (s).
    rate_hz, noise, dropped_frames, glitches : float
        Frame rate, elbow angle noise (rad, sd; other joints scaled by their segment), probability
        of a dropped frame, probability per frame that a glitch starts (1 frame, sometimes 2).

    Returns
    -------
    time : array of shape (T,)
        Frame times (s), from a random phase of the first frame.
    angles : dict of str to array of shape (T,)
        The recorded joint angles (rad), in the order ``positions_of_time`` gives them.
    glitches : int
        Number of glitches; every joint of a glitch frame jumps to the second skeleton's angle.
    """
    period = 1.0 / rate_hz
    time = rng.uniform(0.0, period) + np.arange(0.0, duration, period)
    angles = positions_of_time(time)
    if noise:
        angles = {
            name: values + rng.normal(0.0, noise * _NOISE_SCALE[name], time.size)
            for name, values in angles.items()
        }
    keep = rng.random(time.size) >= dropped_frames
    keep[[0, -1]] = True
    time = time[keep]
    angles = {name: values[keep] for name, values in angles.items()}
    count = 0
    if glitches:
        # the second skeleton: isolated samples (1 or 2 frames), not at the ends
        starts = np.flatnonzero(rng.random(time.size) < glitches)
        starts = starts[(starts >= 2) & (starts <= time.size - 4)]
        starts = starts[np.concatenate([[True], np.diff(starts) > 3])] if starts.size else starts
        for start in starts:
            width = 2 if rng.random() < 0.2 else 1
            for name, values in angles.items():
                values[start : start + width] = rng.uniform(*_GLITCH_RANGE[name], width)
        count = int(starts.size)
    return time, angles, count


def subject_names(subjects: int | Sequence[str]) -> list[str]:
    """The people's names: ``s01``, ``s02``, ... for a count, else the names given."""
    return [f"s{i + 1:02d}" for i in range(subjects)] if isinstance(subjects, int) else list(as_names(subjects))


def check_recording(rate_hz: float, **amounts: float) -> None:
    """Refuse a camera rate outside :data:`CAMERA_RATES`, a noise beyond :data:`MAX_NOISE`, a
    probability (``dropped_frames``, ``glitches``) outside [0, :data:`MAX_FRAME_FAULT`), and any
    other amount (bias, scatter; sign of ``bias`` ignored) that is negative or not finite; each
    named by its parameter."""
    check_rate(rate_hz)
    for name, value in amounts.items():
        if name == "noise":
            check_noise(value)
        elif name in ("dropped_frames", "glitches"):
            check_frame_fault(value, name)
        elif not (math.isfinite(value) and (abs(value) if name == "bias" else value) >= 0):
            raise InputError(f"{name} {value:g}: out of range (a finite amount >= 0)")


def check_rate(value: float, name: str = "rate_hz") -> None:
    """A depth camera's frame rate (Hz) within :data:`CAMERA_RATES`."""
    low, high = CAMERA_RATES
    if not low <= value <= high:
        raise InputError(f"{name} {value:g}: a depth camera records at {low:g} to {high:g} Hz")


def check_noise(value: float, name: str = "noise") -> None:
    """An angle noise (rad, standard deviation) from 0 to :data:`MAX_NOISE`."""
    if not 0.0 <= value <= MAX_NOISE:
        raise InputError(f"{name} {value:g}: the angle noise is a standard deviation in rad, from 0 to {MAX_NOISE:g} "
                         "(a tracker's is a few hundredths of a rad; the default 0.03)")


def check_frame_fault(value: float, name: str) -> None:
    """A probability per frame (a dropped frame, a glitch) in [0, :data:`MAX_FRAME_FAULT`)."""
    if not 0.0 <= value < MAX_FRAME_FAULT:
        raise InputError(f"{name} {value:g}: a probability per frame, from 0 to below {MAX_FRAME_FAULT:g}")


def check_distinct(name: str, values: Sequence[float], unit: str) -> None:
    """Refuse a value ``values`` holds twice (``--distances 1,1``): each value makes baskets of its
    own, whose throws' ids, which write it with 6 digits, would repeat."""
    seen: set[str] = set()
    for value in values:
        shown = f"{value:g}"
        if shown in seen:
            raise InputError(f"{name}: {shown} {unit} is given twice; give each once")
        seen.add(shown)


def throw_meta(subject: str, target: float, landing: float, hit_radius: float, release_angle: float,
               release_time: float, glitches: int) -> dict[str, object]:
    """A simulated throw's metadata: who threw at which basket (m), where the ball came down (m)
    and whether within ``hit_radius`` (m) of it, the release's elbow angle (rad) and time (s, on
    the recording's clock) and the glitches recorded."""
    return {
        "subject": subject,
        "source": "simulated",
        "target": target,
        "landing": landing,
        "hit": bool(abs(landing - target) <= hit_radius),
        "release_angle": release_angle,
        "release_time": release_time,
        "glitches": glitches,
    }


def throws_dataset(throws: Sequence[Throw], columns: Sequence[str], context: tuple[str, ...]) -> Dataset:
    """The throws as one :class:`~rlff.dataset.Dataset` with ``columns`` in that order."""
    return Dataset.from_columns(
        {name: np.concatenate([data[name] for _, data, _ in throws]) for name in columns},
        [name for name, _, _ in throws], [data["time"].size for _, data, _ in throws],
        [meta for _, _, meta in throws], context=context,
    )

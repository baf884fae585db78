"""Cutting a long recording into single throws: wind-up, extension, follow-through.

The thesis cut its bags by hand (rqt_bag). Here a throw is found from the elbow angle alone:

1. a median filter (0.15 s) removes tracking glitches of one or two frames, which would
   otherwise look like very fast extensions;
2. every peak of the angular velocity above ``min_peak_velocity`` marks an extension; it runs
   from the angle's minimum before the peak (wound up) to its maximum after it (arm straight),
   and it counts only if the angle rises by at least ``min_extension`` on the way;
3. the throw starts where the wind-up starts: going back from the minimum through holds of at
   most ``max_hold`` and the stretch where the arm flexes faster than ``rest_velocity``, up to
   ``max_wind_up`` before the minimum;
4. it ends where the follow-through settles: going forward from the maximum, the last sample
   moving faster than ``rest_velocity`` before a pause longer than ``settle`` (at most
   ``max_follow_through`` later).

In both walks, motion after a pause counts only when it lasts ``min_motion``: tracker noise in
a rest makes one- or two-sample blips above ``rest_velocity``.

Consecutive throws never overlap: a follow-through ends at the latest where the next wind-up
begins. Stretches of lost tracking split the recording; a throw never spans one.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.ndimage import median_filter
from scipy.signal import find_peaks

from rlff.capture.angles import ArmMotion, savgol_derivative


@dataclass(frozen=True)
class SegmentSettings:
    """Thresholds of the throw finder (angles in rad, velocities in rad/s, durations in s)."""

    min_peak_velocity: float = 3.0
    min_extension: float = 0.6
    rest_velocity: float = 0.5
    min_separation: float = 0.5
    max_hold: float = 0.5
    max_wind_up: float = 1.5
    max_follow_through: float = 0.6
    settle: float = 0.25
    min_motion: float = 0.1
    glitch_filter: float = 0.15


@dataclass(frozen=True)
class ThrowCut:
    """One throw as sample indices into an :class:`ArmMotion` grid.

    Attributes
    ----------
    start, stop : int
        The throw is ``motion.time[start:stop]`` (wind-up start to follow-through end).
    extension_start, extension_end : int
        Indices of the angle's minimum (wound up) and maximum (straight) around the extension.
    peak : int
        Index of the peak angular velocity of the extension.
    """

    start: int
    stop: int
    extension_start: int
    extension_end: int
    peak: int


def find_throws(motion: ArmMotion, settings: SegmentSettings | None = None) -> tuple[list[ThrowCut], list[str]]:
    """Find the throws in an arm's motion.

    Parameters
    ----------
    motion : ArmMotion
        The arm on a uniform grid.
    settings : SegmentSettings, optional

    Returns
    -------
    throws : list of ThrowCut
        In time order, not overlapping.
    notes : list of str
        Candidate extensions that were rejected, and why.
    """
    settings = settings or SegmentSettings()
    throws: list[ThrowCut] = []
    notes: list[str] = []
    for run in motion.runs():
        found, rejected = _throws_in_run(motion.angle[run], 1.0 / motion.rate_hz, settings)
        throws.extend(_shift(cut, run.start) for cut in found)
        notes.extend(
            f"{motion.arm.label}: movement at t={motion.time[run.start + index]:.2f} s is not a throw ({why})"
            for index, why in rejected
        )
    return throws, notes


def _shift(cut: ThrowCut, offset: int) -> ThrowCut:
    return ThrowCut(*(value + offset for value in (cut.start, cut.stop, cut.extension_start, cut.extension_end, cut.peak)))


def _throws_in_run(angle: np.ndarray, dt: float, settings: SegmentSettings) -> tuple[list[ThrowCut], list[tuple[int, str]]]:
    """Throws within one run of valid samples; indices relative to the run."""
    n = angle.size
    kernel = max(3, int(round(settings.glitch_filter / dt)) | 1)
    if n < kernel + 2:
        return [], []
    smooth = median_filter(angle, size=kernel, mode="nearest")
    velocity = savgol_derivative(smooth, dt)
    peaks, _ = find_peaks(velocity, height=settings.min_peak_velocity, distance=max(1, int(round(settings.min_separation / dt))))
    extensions: dict[tuple[int, int], int] = {}
    rejected: list[tuple[int, str]] = []
    for peak in peaks:
        low = int(peak)
        while low > 0 and velocity[low - 1] > 0:
            low -= 1
        high = int(peak)
        while high < n - 1 and velocity[high + 1] > 0:
            high += 1
        rise = smooth[high] - smooth[low]
        if rise < settings.min_extension:
            rejected.append((int(peak), f"the angle rises by {rise:.2f} rad, less than {settings.min_extension:.2f}"))
            continue
        key = (low, high)
        if key not in extensions or velocity[peak] > velocity[extensions[key]]:
            extensions[key] = int(peak)
    cuts = []
    for (low, high), peak in sorted(extensions.items()):
        start = _wind_up_start(velocity, low, dt, settings)
        stop = _follow_through_end(velocity, high, dt, settings) + 1
        cuts.append(ThrowCut(start, stop, low, high, peak))
    return _without_overlap(cuts), rejected


def _wind_up_start(velocity: np.ndarray, low: int, dt: float, settings: SegmentSettings) -> int:
    """Index where the flexion before the extension starting at ``low`` begins.

    Walks back through flexion (velocity <= -rest) and holds (|velocity| < rest), stopping at a
    rise (the previous movement), at a hold longer than ``max_hold`` (the rest before the throw)
    or ``max_wind_up`` before ``low``.
    """
    walk = _Walk(settings.max_wind_up / dt, settings.max_hold / dt, settings.rest_velocity, _min_run(settings, dt))
    return low - walk.last_motion(velocity[: low + 1][::-1], stop_at_rise=True)


def _follow_through_end(velocity: np.ndarray, high: int, dt: float, settings: SegmentSettings) -> int:
    """Index where the motion after the extension ending at ``high`` comes to rest.

    Walks forward while the arm moves (|velocity| >= rest), through pauses of at most ``settle``,
    for at most ``max_follow_through``.
    """
    walk = _Walk(settings.max_follow_through / dt, settings.settle / dt, settings.rest_velocity, _min_run(settings, dt))
    return high + walk.last_motion(velocity[high:], stop_at_rise=False)


def _min_run(settings: SegmentSettings, dt: float) -> int:
    return max(2, int(round(settings.min_motion / dt)))


@dataclass(frozen=True)
class _Walk:
    """A walk away from an extension along the velocity, in samples."""

    longest: float
    pause: float
    rest: float
    min_run: int

    def last_motion(self, velocity: np.ndarray, stop_at_rise: bool) -> int:
        """Steps from ``velocity[0]`` to the last sample moving faster than ``rest``.

        Stops at a pause longer than ``pause``, after ``longest`` steps or, with
        ``stop_at_rise``, where the angle rises (the movement before). Motion separated from what
        was already taken by a pause counts only when it lasts ``min_run`` samples: tracker noise
        in a rest makes blips of a sample or two.
        """
        last = quiet = run = 0
        for step in range(1, min(velocity.size, int(round(self.longest)) + 1)):
            value = velocity[step]
            if stop_at_rise and value >= self.rest:
                break
            if abs(value) >= self.rest:
                run += 1
                quiet = 0
                if run >= self.min_run or step - run == last:
                    last = step
            else:
                run = 0
                quiet += 1
                if quiet > self.pause:
                    break
        return last


def _without_overlap(cuts: list[ThrowCut]) -> list[ThrowCut]:
    """Where a follow-through runs into the next wind-up, end the one where the other begins."""
    result: list[ThrowCut] = []
    for cut in cuts:
        if result and result[-1].stop > cut.start:
            boundary = max(cut.start, result[-1].extension_end + 1)
            result[-1] = replace(result[-1], stop=boundary)
            cut = replace(cut, start=boundary)
        result.append(cut)
    return result

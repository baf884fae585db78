"""Cutting a recording into single throws (wind-up, extension, follow-through) on its own samples.

The thesis cut its bags by hand (rqt_bag). Here a throw is found from the elbow angle alone, on the
samples as the tracker gave them (even or not, 4 to 30 Hz), with every threshold an angle or a
time, never a number of samples:

1. the angle's rises and falls are followed with a hysteresis of ``reversal`` (dips smaller than
   that within a rise are jitter); every rise of at least ``min_candidate`` is a candidate;
2. a candidate is an extension when the angle rises by at least ``min_extension`` in all, and by
   at least that much within ``extension_window`` at its steepest (measured on the straight lines
   between samples, so a gap through the extension still counts with the rate it implies);
3. the throw starts where the wind-up starts: going back from the extension's start through
   holds of at most ``max_hold`` and flexion faster than ``rest_velocity``, up to ``max_wind_up``;
4. it ends where the follow-through settles: going forward from the extension's end, the last
   sample moving faster than ``rest_velocity`` before a pause longer than ``settle`` (at most
   ``max_follow_through`` later).

In both walks, motion after a pause counts only when it lasts ``min_motion`` (tracker noise in a
rest makes blips), and a blip does not restart the pause's clock; a rise within the wind-up's
hold ends the walk only when it lasts ``min_motion`` too. A sample stands for the time half-way
to each neighbour, so a single sample of a sparse recording can be enough. The follow-through's
velocity is a local fit over ``settle_window`` (the wind-up's, over the output's 0.25 s but a
quadratic where it holds fewer than 6 samples, stops where the extension begins). Every candidate not taken comes back as a :class:`Rejection` with
its time, the rule that stopped it and why. Consecutive throws never overlap; a throw never spans
lost tracking (:meth:`ArmMotion.runs`), and a rise across lost tracking is reported too.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from rlff.capture.angles import (
    ArmMotion,
    derivative_window,
    fewest_in_window,
    local_derivative,
    time_tolerance,
)

#: Fewest samples for the cubic fit of the wind-up walk's velocity (see :func:`local_derivative`).
WIND_UP_CUBIC_FROM = 6


@dataclass(frozen=True)
class SegmentSettings:
    """Thresholds of the throw finder (angles in rad, velocities in rad/s, durations in s)."""

    min_extension: float = 0.6
    extension_window: float = 0.5
    min_candidate: float = 0.3
    reversal: float = 0.1
    rest_velocity: float = 0.5
    max_hold: float = 0.5
    max_wind_up: float = 1.5
    max_follow_through: float = 0.6
    settle: float = 0.25
    min_motion: float = 0.1
    steepest_window: float = 0.28
    settle_window: float = 0.4


@dataclass(frozen=True)
class ThrowCut:
    """One throw as sample indices into an :class:`ArmMotion`.

    Attributes
    ----------
    start, stop : int
        The throw is ``motion.time[start:stop]`` (wind-up start to follow-through end).
    extension_start, extension_end : int
        Indices of the angle's minimum (wound up) and maximum (straight) around the extension.
    peak : int
        Index of the sample nearest to the middle of the stretch where the elbow extends fastest.
    fastest : tuple of float
        That stretch (s, on the motion's clock): the ``steepest_window`` over which the angle
        rises most. The release is measured over it (:func:`rlff.capture.label.estimate_release`).
    """

    start: int
    stop: int
    extension_start: int
    extension_end: int
    peak: int
    fastest: tuple[float, float]


@dataclass(frozen=True)
class Rejection:
    """A candidate movement that was not taken as a throw.

    Attributes
    ----------
    time : float
        Where it happened (s, on the recording's clock): the middle of its steepest stretch.
    rule : str
        The rule that stopped it (a setting's name, such as ``min_extension``).
    reason : str
        Why, with the numbers.
    rise : float
        How far the elbow angle rose (rad); ranks the candidates when none is taken.
    """

    time: float
    rule: str
    reason: str
    rise: float


def steepest_rise(time: np.ndarray, values: np.ndarray, width: float) -> tuple[float, float]:
    """The stretch of ``width`` seconds over which ``values`` rise most, on the lines between samples.

    Parameters
    ----------
    time : array of shape (T,), increasing (s)
    values : array of shape (T,)
    width : float (s)

    Returns
    -------
    begin : float
        Start (s) of the stretch; when the samples span less than ``width``, the stretch is
        centred on them, and when several stretches rise as much (one long chord between two
        samples), it is the middle one.
    rise : float
        ``values`` at ``begin + width`` minus at ``begin`` (linear interpolation; values held
        outside the samples).
    """
    if time[-1] - time[0] <= width:
        return float((time[0] + time[-1] - width) / 2), float(values[-1] - values[0])
    # on a piecewise-linear curve the best window has one of its ends on a sample
    begins = np.concatenate([time[time + width <= time[-1]], time[time - width >= time[0]] - width])
    rises = np.interp(begins + width, time, values) - np.interp(begins, time, values)
    best = float(rises.max())
    # along one straight chord (a gap in sparse sampling) every window rises as much: take the middle
    tied = begins[rises >= best - 1e-9 * max(1.0, abs(best))]
    return float((tied.min() + tied.max()) / 2), best


def find_throws(motion: ArmMotion, settings: SegmentSettings | None = None) -> tuple[list[ThrowCut], list[Rejection]]:
    """Find the throws in an arm's motion.

    Parameters
    ----------
    motion : ArmMotion
        The arm on its own samples.
    settings : SegmentSettings, optional

    Returns
    -------
    throws : list of ThrowCut
        In time order, not overlapping.
    rejections : list of Rejection
        Every candidate movement not taken, and why, in time order.
    """
    settings = settings or SegmentSettings()
    throws: list[ThrowCut] = []
    rejections: list[Rejection] = []
    runs = motion.runs()
    tolerance = time_tolerance(motion.time)  # 3 samples at 30 Hz last min_motion, 0.1 s, whatever the clock
    for run in runs:
        time, angle = motion.time[run], motion.angle[run]
        # the wind-up's hold compares tracker jitter with rest_velocity: a fit that smooths more
        # than the output's where samples are few (a quadratic up to 5 samples, as at 15 Hz); where
        # every window holds more, the two fits are one and the output's is taken as it is
        window = derivative_window(motion.time)
        velocity = (motion.velocity[run] if fewest_in_window(time, window) >= WIND_UP_CUBIC_FROM
                    else local_derivative(time, angle, window, cubic_from=WIND_UP_CUBIC_FROM))
        # the follow-through compares a slow speed with rest_velocity: a wider fit than the output's
        # keeps tracker jitter from crossing it (the chord when sparse anyway)
        settling = local_derivative(time, angle, settings.settle_window)
        found, rejected = _throws_in_run(time, angle, velocity, settling, settings, tolerance)
        throws.extend(_shift(cut, run.start) for cut in found)
        rejections.extend(rejected)
    for before, after in zip(runs, runs[1:], strict=False):
        rise = float(motion.angle[after.start] - motion.angle[before.stop - 1])
        if rise >= settings.min_extension:
            begin, end = float(motion.time[before.stop - 1]), float(motion.time[after.start])
            rejections.append(Rejection(
                (begin + end) / 2, "lost tracking",
                f"the angle rises by {rise:.2f} rad across {end - begin:.2f} s without tracking; the extension is not measured",
                rise,
            ))
    return throws, sorted(rejections, key=lambda rejection: rejection.time)


def _shift(cut: ThrowCut, offset: int) -> ThrowCut:
    return replace(
        cut, start=cut.start + offset, stop=cut.stop + offset, extension_start=cut.extension_start + offset,
        extension_end=cut.extension_end + offset, peak=cut.peak + offset,
    )


def _swings(angle: np.ndarray, reversal: float) -> list[tuple[int, int]]:
    """(low, high) sample indices of every rise of the angle, with dips under ``reversal`` ignored."""
    pivots: list[int] = []
    trend, low, high = 0, 0, 0
    for index in range(1, angle.size):
        value = angle[index]
        if trend == 0:
            low = index if value < angle[low] else low
            high = index if value > angle[high] else high
            if value - angle[low] >= reversal:
                pivots, trend, high = [low], 1, index
            elif angle[high] - value >= reversal:
                pivots, trend, low = [high], -1, index
        elif trend == 1:
            if value > angle[high]:
                high = index
            elif angle[high] - value >= reversal:
                pivots.append(high)
                trend, low = -1, index
        else:
            if value < angle[low]:
                low = index
            elif value - angle[low] >= reversal:
                pivots.append(low)
                trend, high = 1, index
    if trend:
        pivots.append(high if trend == 1 else low)
    return [(a, b) for a, b in zip(pivots, pivots[1:], strict=False) if angle[b] > angle[a]]


def _throws_in_run(
    time: np.ndarray, angle: np.ndarray, velocity: np.ndarray, settling: np.ndarray, settings: SegmentSettings,
    tolerance: float,
) -> tuple[list[ThrowCut], list[Rejection]]:
    """Throws within one run of tracked samples; indices relative to the run; ``tolerance`` (s) for the walks."""
    if time.size < 2:
        return [], []
    cuts: list[ThrowCut] = []
    rejected: list[Rejection] = []
    for low, high in _swings(angle, settings.reversal):
        rise = float(angle[high] - angle[low])
        if rise < settings.min_candidate:
            continue
        stretch = slice(low, high + 1)
        begin, fastest = steepest_rise(time[stretch], angle[stretch], settings.extension_window)
        middle = begin + settings.extension_window / 2
        if rise < settings.min_extension:
            rejected.append(Rejection(
                middle, "min_extension", f"the angle rises by {rise:.2f} rad, less than {settings.min_extension:.2f}", rise
            ))
            continue
        if fastest < settings.min_extension - 1e-9:
            rejected.append(Rejection(
                middle, "extension_window",
                f"the angle rises by {rise:.2f} rad, but by at most {fastest:.2f} rad within "
                f"{settings.extension_window:g} s (slower than a throw, which needs {settings.min_extension:.2f})",
                rise,
            ))
            continue
        begin, _ = steepest_rise(time[stretch], angle[stretch], settings.steepest_window)
        fastest = (begin, begin + settings.steepest_window)
        peak = low + int(np.argmin(np.abs(time[stretch] - (begin + settings.steepest_window / 2))))
        start = low - _Walk(settings.max_wind_up, settings.max_hold, settings, tolerance, stop_at_rise=True).last_motion(
            time[: low + 1][::-1], velocity[: low + 1][::-1]
        )
        stop = high + 1 + _Walk(settings.max_follow_through, settings.settle, settings, tolerance, stop_at_rise=False).last_motion(
            time[high:], settling[high:]
        )
        cuts.append(ThrowCut(start, stop, low, high, peak, fastest))
    return _without_overlap(cuts), rejected


@dataclass(frozen=True)
class _Walk:
    """A walk away from an extension along the velocity, in time; durations within ``tolerance`` (s)
    of a setting count as equal to it (:func:`time_tolerance`)."""

    longest: float
    pause: float
    settings: SegmentSettings
    tolerance: float
    stop_at_rise: bool

    def last_motion(self, time: np.ndarray, velocity: np.ndarray) -> int:
        """Steps from sample 0 to the last sample moving faster than ``rest_velocity``.

        ``time`` and ``velocity`` are in walking order (``time`` backwards for the wind-up).
        Stops at a pause longer than ``pause``, beyond ``longest`` or, with ``stop_at_rise``,
        where the angle rises (the movement before). Each sample stands for the time half-way to
        its neighbours, and motion or a rise shorter than ``min_motion`` is tracker jitter:

        - motion separated from what was already taken by a pause counts only when it lasts
          ``min_motion``, and a pause is timed from the last motion taken (a blip of jitter does
          not restart it);
        - until motion lasting ``min_motion`` has been taken, a rise ends the walk only when it
          lasts ``min_motion`` too (a blip in the hold at the bottom of the wind-up is not the
          movement before); after it, any rise does.
        """
        distance = np.abs(time - time[0])
        edges = np.concatenate([[0.0], (distance[1:] + distance[:-1]) / 2, [distance[-1]]])
        rest = self.settings.rest_velocity

        def lasts(first: int, step: int) -> bool:
            return bool(edges[step + 1] - edges[first] >= self.settings.min_motion - self.tolerance)

        last = 0
        run_start: int | None = None  # the motion (or rise) the walk is in
        rise_start: int | None = None
        moved = False  # motion lasting min_motion has been taken
        for step in range(1, distance.size):
            if distance[step] > self.longest + self.tolerance:
                break
            value = velocity[step]
            if self.stop_at_rise and value >= rest:
                rise_start = step if rise_start is None else rise_start
                if moved or lasts(rise_start, step):
                    break
                run_start = None
                continue
            rise_start = None
            if abs(value) >= rest:
                run_start = step if run_start is None else run_start
                if lasts(run_start, step) or run_start == last + 1:
                    last = step
                    moved = moved or lasts(run_start, step)
            else:
                run_start = None
                if distance[step] - distance[last] > self.pause + self.tolerance:
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

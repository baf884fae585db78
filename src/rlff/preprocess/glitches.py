"""Step 1 (thesis 4.2.1.1, "second skeleton filter"): drop tracking glitches.

A glitch is a sample (or a short run of samples) where the tracker followed a second skeleton:
the angle jumps away (near zero, thesis 4.3.6.1) and comes straight back. In velocity terms it is
a discontinuity: a fast move out, a fast move back, and the angle after the glitch close to the
angle before it. Real motion never does that within one or two frames, however fast the throw,
and an abrupt stop is a fast move that does not come back, so neither is taken for a glitch.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from rlff.dataset import ARM_JOINT_COLUMNS, Dataset
from rlff.dataset import velocity_column as velocity_of
from rlff.errors import InputError
from rlff.preprocess.report import StepReport

#: After a glitch the angle comes back to within this many times the smaller jump of where it
#: was: the motion goes on during the glitch (a fast throw moves up to 1.5 rad in two frames at
#: 15 Hz), but a glitch's excursion is of the same size as that motion or larger.
_RETURN_RATIO = 3.0
#: A glitch at either end of a trajectory is a jump faster than this many times every other step.
_END_FACTOR = 2.0
#: Consistency constant of the median absolute deviation for a normal distribution.
_MAD_TO_SIGMA = 1.4826


def spike_filter(
    dataset: Dataset,
    *,
    column: str = "angle",
    threshold: float | Literal["auto"] = "auto",
    k: float = 3.0,
    max_width: int = 2,
    recompute_velocity: bool = True,
    velocity_column: str = "velocity",
) -> tuple[Dataset, StepReport]:
    """Remove samples that make an out-and-back velocity discontinuity (tracking glitches).

    Parameters
    ----------
    dataset : Dataset
    column : str
        The column a glitch disturbs (the joint angle, rad).
    threshold : float or "auto"
        Speed (column units per second; per sample without a ``time`` column) that both the jump
        out and the jump back must exceed. ``"auto"``: ``k`` robust standard deviations of the
        change of speed from one step to the next, pooled over the whole dataset. A speed must
        be 0 or more.
    k : float
        Multiplier of the automatic threshold; positive.
    max_width : int
        Longest run of consecutive glitch samples looked for (1 or 2 frames on a Kinect); at
        least 1.
    recompute_velocity : bool
        When the data has a ``time`` column, recompute ``velocity_column`` of the trajectories
        that lost samples as the finite difference of ``column`` over time (``numpy.gradient``),
        since a glitch also corrupts the velocities of its neighbours; so too every other joint's
        velocity (``shoulder_velocity``, ``wrist_velocity``) from its angle: a glitch frame is the
        tracker following another skeleton, every joint of it is wrong and goes.
    velocity_column : str

    Returns
    -------
    Dataset, StepReport
        A glitch at the first or last sample is a jump faster than twice every other step of the
        trajectory (and above the threshold).
    """
    dataset.require([column])
    _check_glitch_params(threshold, k, max_width)
    report = StepReport("spike_filter", {}, dataset)
    timed = "time" in dataset.columns
    if threshold == "auto":
        threshold = _auto_threshold(dataset, column, k, timed)
    report.params = {
        "column": column, "threshold": float(threshold), "k": k, "max_width": max_width,
        "recompute_velocity": recompute_velocity, "velocity_column": velocity_column,
    }
    recompute = recompute_velocity and timed and velocity_column in dataset.columns
    pairs = [(column, velocity_column)] + [
        (joint, velocity_of(joint)) for joint in ARM_JOINT_COLUMNS
        if joint != column and joint in dataset.columns and velocity_of(joint) in dataset.columns
    ]
    unit = "/s" if timed else " per sample"
    found = glitch_samples(dataset, column, threshold=float(threshold), max_width=max_width)
    out = []
    for trajectory in dataset:
        spikes = found.get(trajectory.id)
        if spikes is None:
            out.append(trajectory)
            continue
        kept = trajectory.take(np.setdiff1d(np.arange(len(trajectory)), spikes))
        if recompute and len(kept) > 1:
            kept = kept.with_columns(
                **{velocity: np.gradient(kept[position], kept["time"]) for position, velocity in pairs}
            )
        out.append(kept)
        report.change_samples(
            trajectory.id, spikes.size, 0,
            f"glitch sample{'s' if spikes.size > 1 else ''} {', '.join(map(str, spikes))}: "
            f"{column} jumps out and back faster than {float(threshold):.3g}{unit}",
        )
    if recompute and report.samples:
        velocities = ", ".join(velocity for _, velocity in pairs)
        positions = ", ".join(position for position, _ in pairs)
        report.notes.append(f"{velocities} recomputed from {positions} and time where samples were removed")
    report.after = dataset.replace(out)
    return report.after, report


def glitch_samples(dataset: Dataset, column: str = "angle", *, threshold: float | Literal["auto"] = "auto",
                   k: float = 3.0, max_width: int = 2) -> dict[str, np.ndarray]:
    """The glitch samples :func:`spike_filter` removes with these settings (see there), by
    trajectory id: indices ascending, only for trajectories that have any. Also for drawing raw
    data without the lines a glitch throws across a figure."""
    _check_glitch_params(threshold, k, max_width)
    timed = "time" in dataset.columns
    if threshold == "auto":
        threshold = _auto_threshold(dataset, column, k, timed)
    found = {t.id: find_spikes(t[column], t["time"] if timed else None, float(threshold), max_width)
             for t in dataset}
    return {name: spikes for name, spikes in found.items() if spikes.size}


def _check_glitch_params(threshold: float | str, k: float, max_width: int) -> None:
    """Refuse settings that would take ordinary motion for glitches (or none at all)."""
    if threshold != "auto" and not threshold >= 0:
        raise InputError(f'threshold {threshold}: must be "auto" or a speed of 0 or more (column units per second)')
    if not k > 0:
        raise InputError(f"k {k}: must be positive (robust standard deviations of the automatic threshold; 3 in the preset)")
    if max_width < 1:
        raise InputError(f"max_width {max_width}: must be at least 1")


def _frame(time: np.ndarray | None) -> float | None:
    """The camera's frame period (s): the median time step (an upper median, cheap on short arrays)."""
    if time is None or time.size < 2:
        return None
    steps = np.sort(np.diff(time))
    return float(steps[steps.size // 2])


def _speeds(values: np.ndarray, time: np.ndarray | None, frame: float | None) -> np.ndarray:
    """Speed of each step; a gap of dropped frames counts as one frame, so that a glitch beside a
    dropped frame is as fast as any other."""
    steps = np.diff(values)
    if time is None:
        return steps
    return steps / np.minimum(np.diff(time), frame)


def _auto_threshold(dataset: Dataset, column: str, k: float, timed: bool) -> float:
    changes = [
        np.diff(_speeds(t[column], time, _frame(time)))
        for t in dataset if len(t) > 2
        for time in [t["time"] if timed else None]
    ]
    if not changes:
        return float("inf")
    scale = _MAD_TO_SIGMA * float(np.median(np.abs(np.concatenate(changes))))
    return k * scale


def find_spikes(
    values: np.ndarray, time: np.ndarray | None, threshold: float, max_width: int = 2
) -> np.ndarray:
    """Indices of the glitch samples of one trajectory, ascending.

    Parameters
    ----------
    values : array of shape (T,)
    time : array of shape (T,) or None
        Time stamps (s); without them speeds are per sample.
    threshold : float
        Speed both the jump out and the jump back must exceed.
    max_width : int
        Longest run of glitch samples.

    Returns
    -------
    ndarray of int
        Runs of up to ``max_width`` samples entered and left by jumps of opposite signs faster
        than ``threshold`` after which the value comes back to within three times the smaller
        jump of where it was, the deepest first; then a first or last sample reached by a jump
        faster than the threshold and than twice any other step. Removal is repeated until
        nothing changes.
    """
    index = np.arange(values.size)
    frame = _frame(time)
    spikes: list[np.ndarray] = []
    while index.size > 2:
        at = None if time is None else time[index]
        found = _interior_spikes(values[index], at, frame, threshold, max_width)
        if not found.size:
            found = _end_spikes(values[index], at, frame, threshold)
        if not found.size:
            break
        spikes.append(index[found])
        index = np.delete(index, found)
    return np.sort(np.concatenate(spikes)) if spikes else np.empty(0, dtype=int)


def _interior_spikes(
    values: np.ndarray, time: np.ndarray | None, frame: float | None, threshold: float, max_width: int
) -> np.ndarray:
    """The deepest glitch run, as indices (empty when there is none).

    One run at a time: beside a glitch, a good sample can look like an out-and-back too (its
    jump back is the jump into the glitch), but less deep; the glitch goes first.
    """
    speed = _speeds(values, time, frame)
    if not np.any(np.abs(speed) > threshold):
        return np.empty(0, dtype=int)
    size = values.size
    best, best_depth = np.empty(0, dtype=int), 0.0
    for width in range(1, max_width + 1):
        first = np.arange(1, size - width)  # run first..first+width-1, neighbours on both sides
        if not first.size:
            break
        into = speed[first - 1]
        back = speed[first + width - 1]
        jump_in = np.abs(values[first] - values[first - 1])
        jump_back = np.abs(values[first + width] - values[first + width - 1])
        depth = np.minimum(jump_in, jump_back)
        miss = np.abs(values[first + width] - values[first - 1])
        hit = (
            (np.sign(into) * np.sign(back) < 0)
            & (np.abs(into) > threshold)
            & (np.abs(back) > threshold)
            & (miss <= _RETURN_RATIO * depth)
        )
        if hit.any():
            candidate = int(np.argmax(np.where(hit, depth, -np.inf)))
            if depth[candidate] > best_depth:
                best = np.arange(first[candidate], first[candidate] + width)
                best_depth = float(depth[candidate])
    return best


def _end_spikes(
    values: np.ndarray, time: np.ndarray | None, frame: float | None, threshold: float
) -> np.ndarray:
    speed = np.abs(_speeds(values, time, frame))
    found = []
    for end, others in ((0, speed[1:]), (values.size - 1, speed[:-1])):
        jump = speed[0] if end == 0 else speed[-1]
        if jump > threshold and jump > _END_FACTOR * float(np.max(others)):
            found.append(end)
    return np.array(found, dtype=int)

"""Steps 2-5 (thesis 4.2.1.1): isolate the throw in each recording and keep the usable ones.

2. crop to the largest rise of the angle, from the wind-up's minimum to the extension's maximum
   (spurious motion before and after);
3. keep the longest monotonic interval between local extrema (fluctuations inside the crop);
4. drop trajectories with too few points (too sparse to model);
5. balance: at most a number of trajectories per context (the thesis kept ten per basket).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Literal

import numpy as np

from rlff.dataset import Dataset, velocity_column
from rlff.errors import InputError
from rlff.preprocess.report import StepReport
from rlff.wording import plural


def crop(
    dataset: Dataset,
    *,
    column: str = "angle",
    direction: Literal["any", "increasing", "decreasing"] = "any",
) -> tuple[Dataset, StepReport]:
    """Keep each trajectory's largest change of ``column``: from where it starts to where it ends.

    Parameters
    ----------
    dataset : Dataset
    column : str
    direction : {"any", "increasing", "decreasing"}
        "increasing": the largest rise, from the lowest sample to the highest one after it (the
        thesis' "from the minimal to the maximal extension of the arm", rlff's elbow angle growing
        as the arm extends). A recording that starts with the arm already stretched at rest has
        its global maximum before the wind-up's minimum; the rise that follows the wind-up is
        still the largest one, so the rest before it is cut away. "decreasing": the largest fall.
        "any": from the global minimum to the global maximum, in the recorded order (from the
        maximum to the minimum when the maximum comes first), the largest change either way.

    The first occurrence of each extreme is used. A trajectory that never moves in
    ``direction`` is removed with that reason (a single sample is no motion).
    """
    out, report = _keep_interval(
        "crop", dataset, column, direction, largest_change,
        f"the largest {_CHANGE[direction]} of {column}",
    )
    against = _against_their_fastest_motion(dataset, column, direction)
    if against:
        report.warnings.append(
            f"{against} of {len(dataset)} throws move their {column} the other way at their fastest sample: it is "
            f"kept where it {'rises' if direction == 'increasing' else 'falls'}, their wind-up; rlff's elbow angle "
            "grows as the arm extends (0 folded, pi straight), so flexion angles (0 straight) go in as pi - angle, "
            "with the velocity negated")
    return out, report


def _against_their_fastest_motion(dataset: Dataset, column: str, direction: str) -> int:
    """How many trajectories' ``column`` moves against ``direction`` at their fastest sample (by
    its velocity column), when most of them do; 0 otherwise, or without a velocity column or a
    direction. The thesis preset keeps the rise of a flexion angle, which falls as the arm extends:
    the wind-up, its velocities a third of the throw's, and nothing said so."""
    speed = velocity_column(column)
    if direction == "any" or speed not in dataset.columns or not len(dataset):
        return 0
    sign = 1.0 if direction == "increasing" else -1.0
    against = sum(float(t[speed][int(np.argmax(np.abs(t[speed])))]) * sign < 0 for t in dataset)
    return against if 2 * against > len(dataset) else 0


_CHANGE = {"any": "change (global minimum to maximum)", "increasing": "rise", "decreasing": "fall"}


def largest_change(values: np.ndarray, direction: str = "any") -> tuple[int, int]:
    """First and last index (inclusive) of the largest change of ``values`` in ``direction``.

    Parameters
    ----------
    values : array of shape (T,)
    direction : {"any", "increasing", "decreasing"}
        "increasing": the pair ``i <= j`` with the largest ``values[j] - values[i]``;
        "decreasing": with the largest ``values[i] - values[j]``; "any": the global minimum and
        maximum, in their recorded order.

    Returns
    -------
    (int, int)
        ``(0, 0)`` when ``values`` never moves in ``direction``.
    """
    if direction == "any":
        low, high = int(np.argmin(values)), int(np.argmax(values))
        return min(low, high), max(low, high)
    signed = values if direction == "increasing" else -values
    # the rise to each sample from the lowest sample before it; its largest value ends the change
    rise = signed - np.minimum.accumulate(signed)
    last = int(np.argmax(rise))
    if rise[last] <= 0:
        return 0, 0
    return int(np.argmin(signed[: last + 1])), last


def longest_monotonic(
    dataset: Dataset,
    *,
    column: str = "angle",
    direction: Literal["any", "increasing", "decreasing"] = "any",
) -> tuple[Dataset, StepReport]:
    """Keep each trajectory's longest strictly monotonic run of ``column``.

    The local extrema split a trajectory into strictly monotonic runs (two equal consecutive
    values end a run); the run with the most samples is kept, the earliest on a tie.

    Parameters
    ----------
    dataset : Dataset
    column : str
    direction : {"any", "increasing", "decreasing"}
        Only runs in this direction qualify ("increasing" for the throw's extension in rlff's
        angle convention). A trajectory without such a run is removed with that reason.
    """
    return _keep_interval(
        "longest_monotonic", dataset, column, direction, monotonic_run,
        f"the longest {'' if direction == 'any' else direction + ' '}monotonic run of {column}",
    )


def _keep_interval(
    step: str,
    dataset: Dataset,
    column: str,
    direction: str,
    find: Callable[[np.ndarray, str], tuple[int, int]],
    what: str,
) -> tuple[Dataset, StepReport]:
    """Keep in every trajectory the samples ``find(values, direction)`` bounds (inclusive)."""
    dataset.require([column])
    report = StepReport(step, {"column": column, "direction": direction}, dataset)
    out = []
    for trajectory in dataset:
        first, last = find(trajectory[column], direction)
        if last == first:
            report.remove(trajectory.id, f"{what} is a single sample: no motion to keep")
            continue
        out.append(trajectory.take(slice(first, last + 1)))
        report.change_samples(
            trajectory.id, len(trajectory) - (last - first + 1), 0, f"kept samples {first}-{last}, {what}"
        )
    report.after = dataset.replace(out)
    return report.after, report


def monotonic_run(values: np.ndarray, direction: str = "any") -> tuple[int, int]:
    """First and last index (inclusive) of the longest strictly monotonic run of ``values``.

    Parameters
    ----------
    values : array of shape (T,)
    direction : {"any", "increasing", "decreasing"}

    Returns
    -------
    (int, int)
        ``(0, 0)`` when no step qualifies (a single sample, or no step in ``direction``).
    """
    signs = np.sign(np.diff(values))
    wanted = {"any": (1.0, -1.0), "increasing": (1.0,), "decreasing": (-1.0,)}[direction]
    if not signs.size:
        return 0, 0
    # runs of equal step signs: boundaries where the sign changes
    change = np.flatnonzero(np.diff(signs) != 0) + 1
    starts = np.concatenate([[0], change])
    ends = np.concatenate([change, [signs.size]])  # exclusive, in steps
    good = np.isin(signs[starts], wanted)
    if not good.any():
        return 0, 0
    lengths = np.where(good, ends - starts, -1)
    best = int(np.argmax(lengths))
    return int(starts[best]), int(ends[best])


def min_points(dataset: Dataset, *, min_points: int = 5) -> tuple[Dataset, StepReport]:
    """Drop the trajectories with fewer than ``min_points`` samples."""
    if min_points < 1:
        raise InputError(f"min_points {min_points}: must be at least 1")
    report = StepReport("min_points", {"min_points": min_points}, dataset)
    out = []
    for trajectory in dataset:
        if len(trajectory) < min_points:
            report.remove(trajectory.id, f"{len(trajectory)} samples, fewer than {min_points}")
        else:
            out.append(trajectory)
    report.after = dataset.replace(out)
    return report.after, report


def balance(
    dataset: Dataset,
    *,
    max_per_context: int = 10,
    order: Literal["first", "random"] = "first",
    seed: int = 0,
) -> tuple[Dataset, StepReport]:
    """Keep at most ``max_per_context`` trajectories per context value.

    Parameters
    ----------
    dataset : Dataset
    max_per_context : int
        The thesis kept ten per basket distance.
    order : {"first", "random"}
        Which to keep: the first ones in the dataset's order, or a random choice drawn with
        ``seed`` (deterministic). The kept trajectories stay in the dataset's order.
    seed : int
    """
    if max_per_context < 1:
        raise InputError(f"max_per_context {max_per_context}: must be at least 1")
    if seed < 0:
        raise InputError(f"seed {seed}: must be 0 or more (a seed of numpy's random generator)")
    report = StepReport(
        "balance", {"max_per_context": max_per_context, "order": order, "seed": seed}, dataset
    )
    rng = np.random.default_rng(seed)
    dropped: set[str] = set()
    for context, group in dataset.by_context().items():
        if len(group) <= max_per_context:
            continue
        if order == "first":
            chosen = set(range(max_per_context))
        else:
            chosen = set(rng.choice(len(group), max_per_context, replace=False).tolist())
        label = ", ".join(f"{n}={v:g}" for n, v in zip(dataset.context, context, strict=True))
        for position, trajectory in enumerate(group):
            if position not in chosen:
                dropped.add(trajectory.id)
                report.remove(
                    trajectory.id,
                    f"context {label} has {len(group)} trajectories, keeping {max_per_context} ({order})",
                )
    report.after = dataset.replace(t for t in dataset if t.id not in dropped)
    lost = _subjects(dataset) - _subjects(report.after)
    if lost:
        names = sorted(lost)
        shown = ", ".join(names[:6]) + (f" and {len(names) - 6} more" if len(names) > 6 else "")
        report.warnings.append(
            f"every throw of {plural(len(names), 'subject')} ({shown}) was left out: order '{order}' keeps "
            + ("the first of each basket in the data's order; order 'random' draws from every subject"
               if order == "first" else "a random draw of each basket"))
    return report.after, report


def _subjects(dataset: Dataset) -> set[str]:
    """The ``subject`` metadata of the trajectories that have it."""
    return {str(t.meta["subject"]) for t in dataset if t.meta.get("subject") is not None}

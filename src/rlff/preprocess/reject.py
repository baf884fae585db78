"""Steps 10-11 (thesis 4.3.3, 4.3.6.2): reject what the thesis removed by hand, automatically.

10. contexts (basket distances) whose throws break the monotone trend of velocity against
    distance (2.75 m in the thesis: too slow for its place between 2.5 and 3 m), or whose throws
    scatter far more than those of the other contexts (1.0, 1.5 and 4.0 m in the thesis: hard to
    make a full movement so close to the basket);
11. trajectories whose shape differs from the common shape of their context (two kinds of
    throws recorded for one basket, thesis figure 4.54).

Both compare velocity curves sampled on a common grid: the level of a throw is its mean velocity
over the angle band most throws cover; its shape is its velocity against its own progress from
first to last angle, divided by its mean speed.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from rlff.dataset import Dataset, Trajectory
from rlff.errors import InputError
from rlff.limits import apart
from rlff.preprocess.report import StepReport

#: Consistency constant of the median absolute deviation for a normal distribution.
_MAD_TO_SIGMA = 1.4826


def _progress(values: np.ndarray) -> np.ndarray:
    """Fraction of the path covered at each sample, from 0 to 1 (path length of ``values``)."""
    travelled = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(values)))])
    return travelled / travelled[-1] if travelled[-1] > 0 else np.linspace(0.0, 1.0, values.size)


def _shape(trajectory: Trajectory, column: str, velocity_column: str, points: int) -> np.ndarray:
    """Velocity against progress on ``points`` evenly spaced fractions, over its mean speed."""
    curve = np.interp(np.linspace(0.0, 1.0, points), _progress(trajectory[column]), trajectory[velocity_column])
    mean_speed = float(np.mean(np.abs(curve)))
    return curve / mean_speed if mean_speed > 0 else curve


def reject_shapes(
    dataset: Dataset,
    *,
    column: str = "angle",
    velocity_column: str = "velocity",
    k: float = 4.0,
    min_trajectories: int = 3,
    points: int = 50,
) -> tuple[Dataset, StepReport]:
    """Remove trajectories whose velocity shape is far from the common shape of their context.

    Parameters
    ----------
    dataset : Dataset
    column, velocity_column : str
    k : float
        A trajectory is rejected when its distance to its context's common shape exceeds the
        median distance over the dataset by ``k`` robust standard deviations (MAD); positive.
    min_trajectories : int
        Contexts with fewer trajectories have no common shape to compare with; they are kept
        (at least 1).
    points : int
        Samples of a shape (at least 2).

    The common shape is the pointwise median of the context's shapes (velocity against progress,
    over the mean speed); the distance is the root mean square difference.
    """
    dataset.require([column, velocity_column])
    if not k > 0:
        raise InputError(f"k {k}: must be positive (robust standard deviations above the median distance; 4 in the preset)")
    if min_trajectories < 1:
        raise InputError(f"min_trajectories {min_trajectories}: must be at least 1")
    if points < 2:
        raise InputError(f"points {points}: must be at least 2 (samples of a shape; 50 by default)")
    params = {"column": column, "velocity_column": velocity_column, "k": k,
              "min_trajectories": min_trajectories, "points": points}
    report = StepReport("reject_shapes", params, dataset)
    distances: dict[str, float] = {}
    small = []
    for context, group in dataset.by_context().items():
        if len(group) < min_trajectories:
            small.append(context)
            continue
        shapes = np.stack([_shape(t, column, velocity_column, points) for t in group])
        common = np.median(shapes, axis=0)
        rms = np.sqrt(np.mean((shapes - common) ** 2, axis=1))
        distances.update(zip((t.id for t in group), rms.tolist(), strict=True))
    if small:
        report.notes.append(
            f"{len(small)} context(s) with fewer than {min_trajectories} trajectories not compared"
        )
    if distances:
        values = np.array(list(distances.values()))
        centre = float(np.median(values))
        limit = centre + k * _MAD_TO_SIGMA * float(np.median(np.abs(values - centre)))
        report.params["limit"] = limit
        for trajectory_id, distance in distances.items():
            if distance > limit:
                shown, edge = apart(distance, limit, 3)  # as many digits as tell them apart
                report.remove(trajectory_id, f"shape differs from its context's common shape (distance {shown} > {edge})")
    removed = {r.trajectory for r in report.removed}
    report.after = dataset.replace(t for t in dataset if t.id not in removed)
    return report.after, report


def reject_contexts(
    dataset: Dataset,
    *,
    column: str = "distance",
    angle_column: str = "angle",
    velocity_column: str = "velocity",
    trend: Literal["increasing", "decreasing", "none"] = "increasing",
    tolerance: float = 0.10,
    z: float = 2.0,
    by_subject: bool = True,
    max_spread_ratio: float = 3.0,
    min_contexts: int = 3,
    min_trajectories: int = 2,
    bin_width: float = 0.0,
) -> tuple[Dataset, StepReport]:
    """Reject contexts that break the trend of velocity against ``column`` or stand apart.

    Parameters
    ----------
    dataset : Dataset
    column : str
        The context column the velocity should follow (the basket distance, m).
    angle_column, velocity_column : str
    trend : {"increasing", "decreasing", "none"}
        How the level (the median over a context's trajectories of their mean velocity over the
        common angle band) should change with ``column``. A context breaks the trend when it is
        out of order with a neighbouring context and deviates from the value interpolated
        between its two neighbours by more than ``tolerance`` (a fraction of that value). The
        worst offender (the largest gap to that value) is rejected first, then the trend is
        checked again, so the neighbours of a bad context are not blamed for it. "none" skips
        the check.
    tolerance : float
        Relative deviation allowed (0.10: 10 %); 0 or more.
    z : float
        The deviation must also exceed ``z`` standard errors of the levels compared (a level's
        standard error: 1.4826 MAD of its trajectories' mean velocities over the square root of
        their number), so that sparse, noisy recordings do not lose good contexts to chance; 0
        or more.
    by_subject : bool
        When every trajectory has a ``subject``, divide each trajectory's mean velocity by its
        subject's median (times the overall median, to stay in rad/s) before comparing contexts,
        and its velocity curve by the same factor: a fast thrower then does not lift a basket's
        level, a basket thrown by a fast and a slow subject does not look scattered, and the
        levels' standard errors measure throw-to-throw variation only (the thesis' plan: every
        subject at every basket).
    max_spread_ratio : float
        A context stands apart when its trajectories scatter more than this many times the
        median scatter of the contexts (scatter: the median RMS distance of a context's
        velocity curves from their pointwise median, over the context's level). 0 skips it;
        otherwise at least 1.
    min_contexts : int
        With fewer contexts (per value of the other context columns) nothing is rejected.
    min_trajectories : int
        Contexts with fewer trajectories are neither judged nor used to judge others: one throw
        does not tell a basket's level (recordings labelled with an estimated, continuous
        distance have one throw per value; give ``bin_width`` for them).
    bin_width : float
        When positive, ``column`` is grouped into bins of this width (m) centred on multiples of
        it, and a whole bin is judged and rejected as one context; 0 (default) or positive.

    With several context columns, the trend is checked along ``column`` within each group of
    contexts sharing the other columns' values.
    """
    dataset.require([angle_column, velocity_column])
    if column not in dataset.context:
        raise InputError(f"{column!r} is not a context column (context: {', '.join(dataset.context) or 'none'})")
    _check_context_params(tolerance, z, max_spread_ratio, min_contexts, min_trajectories, bin_width)
    params = {"column": column, "angle_column": angle_column, "velocity_column": velocity_column,
              "trend": trend, "tolerance": tolerance, "z": z, "by_subject": by_subject,
              "max_spread_ratio": max_spread_ratio,
              "min_contexts": min_contexts, "min_trajectories": min_trajectories, "bin_width": bin_width}
    report = StepReport("reject_contexts", params, dataset)
    names = dataset.context
    axis = names.index(column)
    groups = _grouped(dataset, axis, bin_width)
    few = [c for c, g in groups.items() if len(g) < min_trajectories]
    if few:
        report.notes.append(
            f"{len(few)} context(s) with fewer than {min_trajectories} trajectories not judged"
            + ("" if bin_width else " (bin_width groups nearby values)")
        )
        groups = {c: g for c, g in groups.items() if len(g) >= min_trajectories}
    if len(groups) < min_contexts:
        report.notes.append(f"{len(groups)} context(s), fewer than {min_contexts}: nothing checked")
        report.after = dataset
        return dataset, report
    grid = _band(dataset, angle_column)
    curves = {c: np.stack([_on_band(t, angle_column, velocity_column, grid) for t in g]) for c, g in groups.items()}
    means = {c: np.mean(v, axis=1) for c, v in curves.items()}
    if by_subject:
        factors = _subject_factors(means, {c: [t.meta.get("subject") for t in g] for c, g in groups.items()})
        means = {c: m * factors[c] for c, m in means.items()}
        curves = {c: v * factors[c][:, None] for c, v in curves.items()}
    levels = {c: float(np.median(m)) for c, m in means.items()}
    errors = {
        c: _MAD_TO_SIGMA * float(np.median(np.abs(m - levels[c]))) / np.sqrt(m.size) for c, m in means.items()
    }
    rejected: dict[tuple[float, ...], str] = {}
    if max_spread_ratio > 0:
        rejected.update(_apart(curves, levels, max_spread_ratio, velocity_column))
    if trend != "none":
        sign = 1.0 if trend == "increasing" else -1.0
        by_rest: dict[tuple[float, ...], list[tuple[float, ...]]] = {}
        for context in groups:
            if context not in rejected:
                by_rest.setdefault(context[:axis] + context[axis + 1 :], []).append(context)
        for members in by_rest.values():
            if len(members) >= min_contexts:
                rejected.update(
                    _off_trend(members, levels, errors, axis, sign, (tolerance, z), column, velocity_column)
                )
    for context, reason in rejected.items():
        report.reject_context(dict(zip(names, context, strict=True)), [t.id for t in groups[context]], reason)
    report.params["levels"] = {
        ", ".join(f"{v:g}" for v in context): round(level, 6) for context, level in levels.items()
    }
    dropped = {t.id for context in rejected for t in groups[context]}
    report.after = dataset.replace(t for t in dataset if t.id not in dropped)
    return report.after, report


def _check_context_params(tolerance: float, z: float, max_spread_ratio: float, min_contexts: int,
                          min_trajectories: int, bin_width: float) -> None:
    """Refuse settings outside the ranges :func:`reject_contexts` documents."""
    for name, value in (("tolerance", tolerance), ("z", z)):
        if not value >= 0:
            raise InputError(f"{name} {value}: must be 0 or more")
    if not (max_spread_ratio == 0 or max_spread_ratio >= 1):
        raise InputError(
            f"max_spread_ratio {max_spread_ratio}: must be 0 (off) or at least 1 (below 1, a context "
            "that scatters less than the typical one would stand apart)"
        )
    for name, count in (("min_contexts", min_contexts), ("min_trajectories", min_trajectories)):
        if count < 1:
            raise InputError(f"{name} {count}: must be at least 1")
    if not bin_width >= 0:
        raise InputError(f"bin_width {bin_width}: must be 0 (off) or positive (m)")


def _grouped(dataset: Dataset, axis: int, bin_width: float) -> dict[tuple[float, ...], list[Trajectory]]:
    """Trajectories by context, ``column`` (at ``axis``) rounded to bins when ``bin_width`` > 0."""
    if bin_width <= 0:
        return dataset.by_context()
    groups: dict[tuple[float, ...], list[Trajectory]] = {}
    for context, members in dataset.by_context().items():
        centre = round(context[axis] / bin_width) * bin_width
        groups.setdefault(context[:axis] + (centre,) + context[axis + 1 :], []).extend(members)
    return dict(sorted(groups.items()))


def _subject_factors(means: dict, subjects: dict) -> dict:
    """Per context, each trajectory's factor that brings its subject's median mean velocity to the
    overall median (all ones when a trajectory has no subject or a median is not positive)."""
    ones = {c: np.ones(m.size) for c, m in means.items()}
    every = [s for names in subjects.values() for s in names]
    if any(s is None for s in every):
        return ones
    values = np.concatenate(list(means.values()))
    labels = np.array([str(s) for s in every])
    overall = float(np.median(values))
    medians = {name: float(np.median(values[labels == name])) for name in set(labels.tolist())}
    if any(m <= 0 for m in medians.values()) or overall <= 0:
        return ones
    return {c: overall / np.array([medians[str(s)] for s in subjects[c]]) for c in means}


def _band(dataset: Dataset, angle_column: str, points: int = 50) -> np.ndarray:
    """The angle band most trajectories cover: from the median start to the median end."""
    starts = np.array([min(t[angle_column][0], t[angle_column][-1]) for t in dataset])
    ends = np.array([max(t[angle_column][0], t[angle_column][-1]) for t in dataset])
    low, high = float(np.median(starts)), float(np.median(ends))
    return np.linspace(low, high, points) if high > low else np.array([low])


def _on_band(trajectory: Trajectory, angle_column: str, velocity_column: str, grid: np.ndarray) -> np.ndarray:
    """Velocity on the band's grid (held at the end values outside the trajectory's range)."""
    angle, velocity = trajectory[angle_column], trajectory[velocity_column]
    if angle[-1] < angle[0]:
        angle, velocity = angle[::-1], velocity[::-1]
    if np.any(np.diff(angle) <= 0):
        # not monotonic: the mean of the samples inside the band stands for the whole band
        inside = (angle >= grid[0]) & (angle <= grid[-1])
        return np.full(grid.size, float(np.mean(velocity[inside] if inside.any() else velocity)))
    return np.interp(grid, angle, velocity)


def _apart(curves: dict, levels: dict, ratio: float, velocity_column: str) -> dict:
    scatter = {}
    for context, stack in curves.items():
        common = np.median(stack, axis=0)
        rms = np.sqrt(np.mean((stack - common) ** 2, axis=1))
        scatter[context] = float(np.median(rms)) / max(abs(levels[context]), 1e-12)
    typical = float(np.median(list(scatter.values())))
    return {
        context: (
            f"its trajectories scatter {value / typical:.1f} times more than a typical context's "
            f"({velocity_column} spread {100 * value:.0f} % of its level, typical {100 * typical:.0f} %)"
        )
        for context, value in scatter.items()
        if typical > 0 and value > ratio * typical
    }


def _off_trend(
    members: list[tuple[float, ...]], levels: dict, errors: dict, axis: int, sign: float,
    limits: tuple[float, float], column: str, velocity_column: str,
) -> dict:
    tolerance, z = limits
    active = sorted(members, key=lambda c: c[axis])
    rejected = {}
    while len(active) >= 3:
        # the worst offender is the one farthest from its neighbours in absolute terms: beside a
        # dip, a good neighbour looks off too, but by about half as much
        worst, worst_gap, worst_reason = None, 0.0, ""
        for i, context in enumerate(active):
            level = levels[context]
            before = active[i - 1] if i > 0 else None
            after = active[i + 1] if i + 1 < len(active) else None
            too_low = before is not None and sign * (level - levels[before]) < 0
            too_high = after is not None and sign * (levels[after] - level) < 0
            if not (too_low or too_high):
                continue
            expected, error = _expected(context, before, after, levels, errors, axis)
            deviation = (level - expected) / max(abs(expected), 1e-12)
            significant = abs(level - expected) > z * error
            if significant and (sign * deviation < -tolerance and too_low or sign * deviation > tolerance and too_high):
                if abs(level - expected) > worst_gap:
                    worst, worst_gap = context, abs(level - expected)
                    worst_reason = (
                        f"breaks the {'increasing' if sign > 0 else 'decreasing'} trend of "
                        f"{velocity_column} with {column}: level {level:.3g}, "
                        f"{100 * abs(deviation):.0f} % {'below' if deviation < 0 else 'above'} the "
                        f"{expected:.3g} its neighbours {_label(before, after, axis)} suggest"
                    )
        if worst is None:
            break
        rejected[worst] = worst_reason
        active.remove(worst)
    return rejected


def _expected(context, before, after, levels: dict, errors: dict, axis: int) -> tuple[float, float]:
    """The level interpolated between the neighbouring contexts (or the single neighbour's), and
    the standard error of the difference between it and the context's own level."""
    if before is None or after is None:
        neighbour = after if before is None else before
        return levels[neighbour], float(np.hypot(errors[context], errors[neighbour]))
    x0, x1 = before[axis], after[axis]
    weight = (context[axis] - x0) / (x1 - x0)
    expected = (1 - weight) * levels[before] + weight * levels[after]
    error = np.sqrt(errors[context] ** 2 + ((1 - weight) * errors[before]) ** 2 + (weight * errors[after]) ** 2)
    return expected, float(error)


def _label(before, after, axis: int) -> str:
    return " and ".join(f"{c[axis]:g}" for c in (before, after) if c is not None)

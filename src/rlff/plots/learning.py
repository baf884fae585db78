"""Learning from failure: the miss of every attempt, per method, until the first hit.

Every method has its own colour and marker in every figure (:func:`method_style`): the demo's
learning figure and ``rlff plot learning`` of its logs draw calibrate alike. Which logs may
share a figure and how their curves are named is :mod:`rlff.plots.learning_logs`'.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
from matplotlib.lines import Line2D
from matplotlib.ticker import MaxNLocator

from rlff.errors import InputError
from rlff.plots._figure import HIT_COLOUR, SavedFigure, figure_style, new_figure, save
from rlff.plots.learning_logs import (
    LoggedRun,
    curve_names,
    read_learning_log,
    require_one_task,
    shared_settings,
)
from rlff.wording import plural

__all__ = ["LoggedRun", "learning_curves", "learning_curves_from_logs", "method_style", "read_learning_log"]

_MARKERS = "osD^vP<>Xh"
#: The learning methods in the order of their colours (matplotlib's C0, C1, ...) and markers: a
#: method is drawn alike in every figure. Its ablations (``calibrate:gmr-mean``) take its colour
#: and marker, dashed or dotted.
METHOD_ORDER = ("calibrate", "hindsight", "failure", "secant", "imitation", "donut", "random", "sweep", "gp-bo", "cma")
_ABLATION_LINES = {"no-exploration": "--", "gmr-mean": ":"}


def method_style(method: str) -> tuple[str, str, str] | None:
    """The colour, marker and line style of a learning method's curve in every figure, or None for
    a method rlff does not know (:data:`METHOD_ORDER`)."""
    base, _, ablation = method.partition(":")
    if base not in METHOD_ORDER:
        return None
    index = METHOD_ORDER.index(base)
    return f"C{index}", _MARKERS[index], _ABLATION_LINES.get(ablation, "-")


def _styles(methods: Sequence[str]) -> list[tuple[str, str, str]]:
    """Colour, marker and line style of each curve: its method's (:func:`method_style`); a method
    rlff does not know takes a colour no known method of the figure has, and a method drawn
    again another marker and line style for each later curve."""
    known = {method: method_style(method) for method in methods}
    taken = {style[0] for style in known.values() if style}
    free = [f"C{i}" for i in range(10) if f"C{i}" not in taken] or [f"C{i}" for i in range(10)]
    unknown = [method for method, style in known.items() if style is None]
    for index, method in enumerate(unknown):
        known[method] = (free[index % len(free)], "o", "-")
    styles, drawn = [], dict.fromkeys(methods, 0)
    for method in methods:
        colour, marker, line = known[method]
        times = drawn[method]
        drawn[method] += 1
        if times:
            marker, line = _MARKERS[(_MARKERS.index(marker) + times) % len(_MARKERS)], ("--", ":", "-.")[(times - 1) % 3]
        styles.append((colour, marker, line))
    return styles


def learning_curves(
    misses: Mapping[str, Sequence[float]],
    out: str | Path,
    *,
    tolerance: float | None = None,
    hits: Mapping[str, Sequence[bool]] | None = None,
    basket: float | None = None,
    methods: Mapping[str, str] | None = None,
    band: str | None = None,
    settings: Sequence[str] = (),
) -> SavedFigure:
    """Signed miss (m) against attempt number, one line per method.

    Parameters
    ----------
    misses : mapping of curve name to sequence of float
        Signed miss of each attempt in m (negative: short of the basket, positive: long);
        NaN for an attempt without a landing point. The name is the legend's.
    out : path
        File stem of the PNG and SVG.
    tolerance : float, optional
        Half the width (m) of a band around the basket's centre, shaded (|miss| <= tolerance; a
        ball landing in the loop's hit window may still bounce off the rim, so ``hits`` decides
        the stars).
    hits : mapping of curve name to sequence of bool, optional
        Which attempts hit (default: |miss| <= tolerance when a tolerance is given). The first hit
        of each curve is marked with a star.
    basket : float, optional
        The basket distance (m), for the title.
    methods : mapping of curve name to method, optional
        The learning method of each curve, which gives its colour and marker
        (:func:`method_style`); default the curve's name.
    band : str, optional
        What the shaded band is, for the legend; default ``|miss| <= {tolerance} m``.
    settings : sequence of str
        What every curve shares, in a few words each, added to the title (``arm speed:0.9``).
    """
    if not misses:
        raise InputError("no learning curves to plot")
    names = list(misses)
    styles = _styles([(methods or {}).get(name, name) for name in names])
    with figure_style():
        figure = new_figure(10.5, 4.6)
        axes = figure.add_subplot()
        axes.axhline(0.0, color="black", linewidth=0.8)
        if tolerance is not None:
            axes.axhspan(-tolerance, tolerance, color=HIT_COLOUR, alpha=0.12,
                         label=band or f"|miss| ≤ {tolerance:.3g} m")
        blind = False  # whether some miss has no measured landing
        stars: dict[tuple[int, int | None], int] = {}  # first hits drawn at (attempt, miss in cm; None: no landing)
        for (method, values), (colour, marker, line) in zip(misses.items(), styles, strict=True):
            miss = np.asarray(values, dtype=float)
            attempts = np.arange(1, miss.size + 1)
            axes.plot(
                attempts, miss, marker=marker, markersize=5, linestyle=line,
                color=colour, linewidth=1.4, label=f"{method} ({plural(miss.size, 'attempt')})",
            )
            if hits is not None and method in hits:
                hit = np.asarray(hits[method], dtype=bool)
            elif tolerance is not None:
                hit = np.abs(miss) <= tolerance
            else:
                hit = np.zeros(miss.size, dtype=bool)
            unmeasured = ~np.isfinite(miss) & ~hit  # a miss seen but not measured (typed "miss" on a live arm)
            if unmeasured.any():
                axes.plot(attempts[unmeasured], np.zeros(unmeasured.sum()), marker="x", markersize=8, color=colour,
                          linestyle="none")
                blind = True
            if hit.any():
                first = int(np.flatnonzero(hit)[0])
                # a star on another method's (same attempt, same cm) is drawn smaller on top of it
                point = (first, round(float(miss[first]) * 100) if np.isfinite(miss[first]) else None)
                below = stars.get(point, 0)
                stars[point] = below + 1
                blind |= not np.isfinite(miss[first])  # a typed hit: drawn at 0 like an unmeasured miss
                axes.plot(
                    attempts[first], np.nan_to_num(miss[first]), marker="*", markersize=max(17 - 6 * below, 6),
                    color=colour,
                    markeredgecolor="black", linestyle="none", zorder=5 + below,
                )
        axes.xaxis.set_major_locator(MaxNLocator(integer=True, min_n_ticks=1))
        longest = max((len(values) for values in misses.values()), default=1)
        axes.set_xlim(0.5, longest + 0.5)
        axes.set_xlabel("attempt")
        axes.set_ylabel("miss (m): < 0 short, > 0 long")
        handles, labels = axes.get_legend_handles_labels()
        if stars:
            handles.append(Line2D([], [], marker="*", markersize=12, color="grey", markeredgecolor="black",
                                  linestyle="none"))
            labels.append("first hit")
        if blind:
            handles.append(Line2D([], [], marker="x", markersize=8, color="grey", linestyle="none"))
            labels.append("landing not measured (drawn at 0)")
        figure.legend(handles, labels, loc="outside right upper")
        where = f" for a basket at {basket:g} m" if basket is not None else ""
        axes.set_title(f"Learning from failure{where}" + "".join(f", {words}" for words in settings), wrap=True)
    return save(figure, out)


def learning_curves_from_logs(logs: Sequence[str | Path], out: str | Path, *, tolerance: float | None = None) -> SavedFigure:
    """:func:`learning_curves` of one or more attempts logs of one task (one line per log).

    Logs of different tasks (another basket, bearing, rim height, robot, pedestal or joints) are
    refused (:func:`rlff.plots.learning_logs.require_one_task`), and so is a log without an attempt. Each curve is named by its method
    and what else tells it from the other logs' (:func:`rlff.plots.learning_logs.curve_names`),
    what all share goes into the title. Without ``tolerance`` (m) the shaded band is the loop's
    hit window for the logs' basket when they share an opening
    (:func:`rlff.learn.loop.hit_tolerance`: half the opening less the ball's radius, a landing
    clear of the rim); a ``tolerance`` is checked (:func:`check_tolerance`) and shaded as itself.
    """
    if not logs:
        raise InputError("no attempts logs given")
    runs = [read_learning_log(path) for path in logs]
    require_one_task(runs)
    # a header alone (a run stopped before its first throw) had drawn an empty axis, exit 0
    if (empty := next((path for path, run in zip(logs, runs, strict=True) if not len(run.misses)), None)) is not None:
        raise InputError(f"{empty} holds no attempt (its run stopped before its first throw): no curve to draw; "
                         "leave it out")
    basket = runs[0].basket
    band = None
    openings = {run.opening for run in runs}
    if tolerance is not None:
        tolerance = check_tolerance(tolerance, basket)
    elif len(openings) == 1:  # the band the loop counts as a hit, as the demo's
        from rlff.learn.loop import hit_tolerance
        from rlff.sim import Basket

        tolerance = hit_tolerance(Basket(basket, opening=openings.pop()))
        band = f"lands clear of the rim (|miss| ≤ {tolerance:.3g} m)"
    names = curve_names(runs)
    return learning_curves(dict(zip(names, (run.misses for run in runs), strict=True)), out, tolerance=tolerance,
                           hits=dict(zip(names, (run.hits for run in runs), strict=True)), basket=basket,
                           methods=dict(zip(names, (run.method for run in runs), strict=True)), band=band,
                           settings=shared_settings(runs))


def check_tolerance(tolerance: float, basket: float) -> float:
    """A band's half-width ``tolerance`` (m) around a basket ``basket`` m away: a positive number of
    metres no larger than the distance (a band reaching back past the robot is no landing window;
    one of centimetres is asked about).

    Raises
    ------
    InputError
        Starting ``tolerance:``, naming the value.
    """
    if not (math.isfinite(tolerance) and tolerance > 0):
        raise InputError(f"tolerance: {tolerance:g} m is no half-width of a band: give a positive number of metres, "
                         "e.g. 0.15")
    if tolerance > basket:
        hint = f" (centimetres? the tolerance is in metres: {tolerance / 100:g})" if tolerance / 100 <= basket else ""
        raise InputError(f"tolerance: {tolerance:g} m is wider than the basket is far ({basket:g} m){hint}")
    return float(tolerance)

"""Learning from failure: the miss of every attempt, per method, until the first hit."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.lines import Line2D
from matplotlib.ticker import MaxNLocator

from rlff.errors import InputError
from rlff.plots._figure import HIT_COLOUR, SavedFigure, figure_style, new_figure, save
from rlff.wording import plural

_MARKERS = "osD^vP<>Xh"


def learning_curves(
    misses: Mapping[str, Sequence[float]],
    out: str | Path,
    *,
    tolerance: float | None = None,
    hits: Mapping[str, Sequence[bool]] | None = None,
    basket: float | None = None,
) -> SavedFigure:
    """Signed miss (m) against attempt number, one line per method.

    Parameters
    ----------
    misses : mapping of method name to sequence of float
        Signed miss of each attempt in m (negative: short of the basket, positive: long);
        NaN for an attempt without a landing point.
    out : path
        File stem of the PNG and SVG.
    tolerance : float, optional
        Half the width (m) of the landing window of a hit: the band |miss| <= tolerance is shaded
        (a ball landing there may still bounce off the rim, so ``hits`` decides the stars).
    hits : mapping of method name to sequence of bool, optional
        Which attempts hit (default: |miss| <= tolerance when a tolerance is given). The first hit
        of each method is marked with a star.
    basket : float, optional
        The basket distance (m), for the title.
    """
    if not misses:
        raise InputError("no learning curves to plot")
    with figure_style():
        figure = new_figure(10.5, 4.6)
        axes = figure.add_subplot()
        axes.axhline(0.0, color="black", linewidth=0.8)
        if tolerance is not None:
            axes.axhspan(-tolerance, tolerance, color=HIT_COLOUR, alpha=0.12, label="lands clear of the rim")
        colours = [f"C{i}" for i in range(10)]
        blind = False  # whether some miss has no measured landing
        stars: dict[tuple[int, int | None], int] = {}  # first hits drawn at (attempt, miss in cm; None: no landing)
        for index, (method, values) in enumerate(misses.items()):
            miss = np.asarray(values, dtype=float)
            attempts = np.arange(1, miss.size + 1)
            colour = colours[index % len(colours)]
            axes.plot(
                attempts, miss, marker=_MARKERS[index % len(_MARKERS)], markersize=5,
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
        axes.set_title(f"Learning from failure{where}")
    return save(figure, out)


@dataclass(frozen=True)
class LoggedRun:
    """What a learning curve needs of one attempts log.

    Attributes
    ----------
    method : str
        The run's update strategy or baseline.
    feedback : str
    basket : float
        Basket distance (m).
    misses : list of float
        Signed miss of every attempt (m).
    hits : list of bool
    robot : str or None
        The robot the run threw with (its robot file's ``name``), None in a log that does not say.
    digest : str or None
        The digest of the robot's description and mapping the log records (two robot files of
        one name differ in it).
    joints : tuple of str
        The robot joints the throws drove (``joint_2``; a whole-arm run's several), empty when the
        log does not say.
    bearing : float
        The basket's bearing (degrees from the robot's forward axis, positive to the left).
    opening : float
        The basket's inner width (m; 0.35 in a log that does not say).
    gap : str
        How the simulated arm differed from its robot file (``none``, ``speed:0.9``, ...).
    """

    method: str
    feedback: str
    basket: float
    misses: list[float]
    hits: list[bool]
    robot: str | None = None
    digest: str | None = None
    joints: tuple[str, ...] = ()
    bearing: float = 0.0
    opening: float = 0.35
    gap: str = "none"


def read_learning_log(path: str | Path) -> LoggedRun:
    """Read an attempts log of ``rlff learn`` (JSONL) for plotting, without changing the file.

    A last line cut short by a crash is ignored (the loop itself drops it on resume).

    Raises
    ------
    InputError
        No such file, not an rlff attempts log, or a damaged line before the last one.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such attempts log")
    lines = [line for line in path.read_text(encoding="utf-8", errors="replace").splitlines() if line.strip()]
    records = []
    for number, line in enumerate(lines, start=1):
        try:
            record = json.loads(line)
        except json.JSONDecodeError:
            if number == len(lines):
                break  # a partial last line
            raise InputError(f"{path}, line {number}: not JSON") from None
        if not isinstance(record, dict):
            raise InputError(f"{path}, line {number}: not a JSON object")
        records.append(record)
    if not records or records[0].get("format") != "rlff-attempts":
        raise InputError(f"{path}: not an rlff attempts log (no 'rlff-attempts' header line)")
    run = records[0].get("run", {})
    try:
        # a miss nobody measured (typed "miss" on a live arm) is logged as null
        misses = [math.nan if r["miss"] is None else float(r["miss"]) for r in records[1:]]
        hits = [bool(r["hit"]) for r in records[1:]]
        basket = float(run["basket"]["distance"])
    except KeyError as exc:
        raise InputError(f"{path}: attempt or run record without {exc}") from None
    except (TypeError, ValueError, OverflowError, AttributeError):
        raise InputError(f"{path}: an attempt's miss or the run's basket distance is not a number") from None
    try:
        bearing = float(run["basket"].get("bearing", 0.0))  # left out for a basket straight ahead
        opening = float(run["basket"].get("opening", 0.35))
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{path}: the run's basket bearing or opening is not a number") from None
    robot = run.get("robot") if isinstance(run.get("robot"), dict) else {}
    name, digest = robot.get("name"), robot.get("digest")
    return LoggedRun(str(run.get("update", path.stem)), str(run.get("feedback", "")), basket, misses, hits,
                     None if name is None else str(name), None if digest is None else str(digest),
                     _thrown_joints(run), bearing, opening, str(run.get("gap", "none")))


def _thrown_joints(run: dict) -> tuple[str, ...]:
    """The robot joints an attempts log's run drove: its ``joints`` (a whole-arm run), else the
    joint of the one-joint mapping its robot record holds, else none known."""
    joints = run.get("joints")
    if isinstance(joints, list) and all(isinstance(j, str) for j in joints):
        return tuple(sorted(joints))
    mapping = _at(run, "robot", "description", "mapping")
    if isinstance(mapping, dict):
        if isinstance(mapping.get("joint"), str):
            return (mapping["joint"],)
        if isinstance(mapping.get("driven"), dict):
            return tuple(sorted(map(str, mapping["driven"])))
    return ()


def _at(record: object, *keys: str) -> object:
    """The value at ``keys`` of nested dicts, or None where a part is absent."""
    for key in keys:
        record = record.get(key) if isinstance(record, dict) else None
    return record


def learning_curves_from_logs(logs: Sequence[str | Path], out: str | Path, *, tolerance: float | None = None) -> SavedFigure:
    """:func:`learning_curves` of one or more attempts logs (one line per log).

    The logs must be for one basket distance; a run on a simulated arm unlike its robot file has
    its gap added to its name (``calibrate, arm speed:0.9``), and a name seen twice then its
    feedback (``hindsight, distance feedback``) and then a number. ``tolerance`` (m) defaults to
    the loop's hit window for the logs' basket when they share an opening
    (:func:`rlff.learn.loop.hit_tolerance`: half the opening less the ball's radius).
    """
    if not logs:
        raise InputError("no attempts logs given")
    runs = [read_learning_log(path) for path in logs]
    baskets = sorted({run.basket for run in runs})
    if len(baskets) > 1:
        raise InputError(f"the logs are for different baskets ({', '.join(f'{b:g} m' for b in baskets)}); plot them separately")
    openings = {run.opening for run in runs}
    if tolerance is None and len(openings) == 1:  # the band the loop counts as a hit, as the demo's
        from rlff.learn.loop import hit_tolerance
        from rlff.sim import Basket

        tolerance = hit_tolerance(Basket(baskets[0], opening=openings.pop()))
    misses: dict[str, list[float]] = {}
    hits: dict[str, list[bool]] = {}
    for run in runs:
        name = run.method if run.gap == "none" else f"{run.method}, arm {run.gap}"
        if name in misses:
            name = f"{run.method}, {run.feedback} feedback"
        suffix = 2
        while name in misses:
            name, suffix = f"{run.method} ({suffix})", suffix + 1
        misses[name] = run.misses
        hits[name] = run.hits
    return learning_curves(misses, out, tolerance=tolerance, hits=hits, basket=baskets[0])

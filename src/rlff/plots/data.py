"""Figures of a dataset: the demonstrations in 3-D and as 2-D slices per basket distance.

Thesis figures 4.1 and 4.16-4.17 (the dataset in (angle, distance, velocity)) and 4.44 (the data
split by distance).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.cm import ScalarMappable
from matplotlib.colors import to_rgba
from matplotlib.lines import Line2D
from matplotlib.ticker import MaxNLocator
from mpl_toolkits.mplot3d.art3d import Line3DCollection

from rlff.dataset import JOINT_COLUMNS, Dataset, Trajectory
from rlff.errors import InputError
from rlff.plots._figure import (
    HIT_COLOUR,
    MISS_COLOUR,
    RASTERIZE_ABOVE,
    SavedFigure,
    add_curves,
    axis_label,
    distance_colours,
    figure_style,
    format_distance,
    grid_shape,
    new_figure,
    robust_limits,
    save,
)
from rlff.preprocess.glitches import glitch_samples
from rlff.wording import plural

#: Two viewpoints of the 3-D figure (elevation, azimuth in degrees), as in thesis figure 4.17.
_VIEWS = ((22.0, -60.0), (14.0, -30.0))
#: Tracking glitches' samples, drawn as dots apart from the lines.
_GLITCH_COLOUR = "#7f7f7f"


def _check_columns(dataset: Dataset, columns: Sequence[str]) -> None:
    if len(dataset) == 0:
        raise InputError("the dataset is empty: nothing to plot")
    dataset.require(columns)


#: Up to this many lines in a panel, hits and misses are two layers, the fewer on top where they stand out.
LAYERED_UP_TO = 60


@dataclass(frozen=True)
class OutcomeDrawing:
    """How a panel draws its hits and misses.

    Attributes
    ----------
    order : ndarray of int, shape (N,)
        The lines' indices in drawing order (the last on top).
    colours : ndarray, shape (N, 4)
        RGBA of the lines in drawing order (``colours[k]`` is line ``order[k]``'s): hit or miss
        colour, with its alpha.
    linewidth : float
        Line width (points).
    """

    order: np.ndarray
    colours: np.ndarray
    linewidth: float


#: The shuffle of a panel of many lines (:func:`outcome_drawing`) is this seed's: a figure drawn
#: again from the same data is the same picture.
_SHUFFLE_SEED = 0


def outcome_drawing(hit: Sequence[bool]) -> OutcomeDrawing:
    """Draw order, alpha and line width that keep each outcome's colour mass true to its count.

    Up to :data:`LAYERED_UP_TO` lines the larger group is drawn first and the smaller on top
    (misses at alpha 0.7, hits at 0.8, width 1): a few hits among many misses stand out, and a
    few misses among many hits too. Above it, a group drawn on top would paint over the other
    (166 hits over 631 misses looked green): the lines are drawn in one shuffled order (the same
    for the same number of lines) with an alpha and a width that fall with the square root of
    their number, so a region reads as the mix of the lines that pass through it.

    Parameters
    ----------
    hit : sequence of bool, shape (N,)
        Whether each line hit the basket.

    Returns
    -------
    OutcomeDrawing
        The lines' indices in drawing order and their colours in that order.
    """
    hit = np.asarray(hit, dtype=bool)
    count = hit.size
    if count <= LAYERED_UP_TO:
        larger_first = hit.sum() > count - hit.sum()  # ties: the hits on top, as a few hits among misses
        order = np.concatenate([np.flatnonzero(hit == larger_first), np.flatnonzero(hit != larger_first)])
        alphas, linewidth = np.where(hit, 0.8, 0.7), 1.0
    else:
        order = np.random.default_rng(_SHUFFLE_SEED).permutation(count)
        scale = float(np.sqrt(LAYERED_UP_TO / count))
        alphas, linewidth = np.full(count, max(0.1, 0.75 * scale)), max(0.4, scale)
    order = order.astype(int)
    colours = np.array([to_rgba(HIT_COLOUR if hit[i] else MISS_COLOUR, alphas[i]) for i in order])
    return OutcomeDrawing(order, colours.reshape(count, 4), linewidth)


def _outcome_counts(trajectories: Sequence[Trajectory]) -> str:
    hits = sum(1 for t in trajectories if t.meta.get("hit") is True)
    misses = sum(1 for t in trajectories if t.meta.get("hit") is False)
    if hits + misses == 0:
        return plural(len(trajectories), "throw")
    return f"{hits} hit, {misses} missed"


def dataset_3d(
    dataset: Dataset,
    out: str | Path,
    *,
    columns: tuple[str, str, str] = ("angle", "distance", "velocity"),
    title: str | None = None,
) -> SavedFigure:
    """The demonstrations as lines in 3-D, seen from two viewpoints, coloured by distance.

    Parameters
    ----------
    dataset : Dataset
        Trajectories with the three ``columns``; the second is the context (one value per
        trajectory) that sets the colour.
    out : path
        File stem of the PNG and SVG.
    columns : (x, y, z) column names
        Default (angle rad, distance m, velocity rad/s), the axes of thesis figure 4.1.
    title : str, optional
        Figure title; default names the number of trajectories.
    """
    _check_columns(dataset, columns)
    x_name, c_name, y_name = columns
    contexts = [float(t[c_name][0]) for t in dataset]
    colours, norm, cmap = distance_colours(contexts)
    # tracking glitches (rare samples far off) are clipped instead of setting the scale
    z_limits = robust_limits([(0.5, [t[y_name] for t in dataset])])
    with figure_style():
        figure = new_figure(12.0, 5.2)
        for index, (elevation, azimuth) in enumerate(_VIEWS):
            axes = figure.add_subplot(1, 2, index + 1, projection="3d")
            lines = Line3DCollection(
                [t.to_array((x_name, c_name, y_name)) for t in dataset],
                colors=[colours[c] for c in contexts], linewidths=1.1, alpha=0.85,
                rasterized=dataset.n_samples > RASTERIZE_ABOVE, axlim_clip=True,
            )
            axes.add_collection3d(lines)
            points = dataset.to_array((x_name, c_name, y_name))
            axes.auto_scale_xyz(points[:, 0], points[:, 1], points[:, 2])
            axes.set_zlim(*z_limits)
            axes.set_xlabel(axis_label(x_name), labelpad=6)
            axes.set_ylabel(axis_label(c_name), labelpad=6)
            axes.set_zlabel(axis_label(y_name), labelpad=6)
            for axis in (axes.xaxis, axes.yaxis, axes.zaxis):
                axis.set_major_locator(MaxNLocator(5))
            axes.view_init(elev=elevation, azim=azimuth)
            axes.set_title(f"view {index + 1}: elevation {elevation:g}°, azimuth {azimuth:g}°")
        colour_bar = figure.colorbar(
            ScalarMappable(norm=norm, cmap=cmap), ax=figure.axes, shrink=0.7, pad=0.04
        )
        colour_bar.set_label(axis_label(c_name))
        figure.suptitle(title or f"Demonstrations: {plural(len(dataset), 'trajectory', 'trajectories')}, "
                                 f"{plural(dataset.n_samples, 'sample')}")
    return save(figure, out)


def dataset_slices(
    dataset: Dataset,
    out: str | Path,
    *,
    x: str = "angle",
    y: str = "velocity",
    context: str = "distance",
    title: str | None = None,
) -> SavedFigure:
    """One panel per basket distance with the demonstrations on the (x, y) plane.

    Successful throws are green, failed ones red when the trajectories carry a ``hit`` outcome,
    drawn so that each colour's mass follows its count (:func:`outcome_drawing`); otherwise every
    line takes its distance's colour. Panels share their axes so that the
    distances compare at a glance (thesis figure 4.44).

    Parameters
    ----------
    dataset : Dataset
    out : path
        File stem of the PNG and SVG.
    x, y : str
        Columns on the horizontal and vertical axes (default angle rad, velocity rad/s).
    context : str
        The column that splits the panels (default the basket distance, m).
    title : str, optional
    """
    _check_columns(dataset, (x, y, context))
    groups: dict[float, list[Trajectory]] = {}
    for trajectory in dataset:
        groups.setdefault(float(trajectory[context][0]), []).append(trajectory)
    groups = dict(sorted(groups.items()))
    colours, _, _ = distance_colours(list(groups))
    has_outcome = any("hit" in t.meta for t in dataset)
    rows, columns = grid_shape(len(groups))
    with figure_style():
        figure = new_figure(3.4 * columns, 2.8 * rows + 0.6)
        panels = figure.subplots(rows, columns, sharex=True, sharey=True, squeeze=False)
        # a tracking glitch's sample, joined into the line, throws strokes across the whole panel:
        # the lines skip them, and they are drawn as dots (rlff data preprocess removes them)
        glitches = glitch_samples(dataset, x) if len(dataset) and x in JOINT_COLUMNS else {}

        def curve(t: Trajectory) -> tuple[np.ndarray, np.ndarray]:
            """The line without the glitch samples, nor their neighbours, whose velocities the
            glitch corrupts (a finite difference across it)."""
            xs, ys = np.array(t[x], dtype=float), np.array(t[y], dtype=float)
            spikes = glitches.get(t.id, np.empty(0, dtype=int))
            near = np.unique(np.clip(np.concatenate([spikes - 1, spikes, spikes + 1]), 0, len(t) - 1))
            xs[near] = np.nan
            return xs, ys

        for axes, (value, trajectories) in zip(panels.flat, groups.items(), strict=False):
            if has_outcome:
                drawing = outcome_drawing([t.meta.get("hit") is True for t in trajectories])
                add_curves(axes, [curve(trajectories[i]) for i in drawing.order], drawing.colours,
                           linewidth=drawing.linewidth, alpha=None)
            else:
                add_curves(axes, [curve(t) for t in trajectories], colours[value], linewidth=1.0, alpha=0.8)
            stray = [(t[x][glitches[t.id]], t[y][glitches[t.id]]) for t in trajectories if t.id in glitches]
            if stray:
                axes.plot(np.concatenate([a for a, _ in stray]), np.concatenate([b for _, b in stray]), ".",
                          color=_GLITCH_COLOUR, markersize=2.5, label="tracking glitch (sample)", zorder=2)
            label = format_distance(value) if context == "distance" else f"{context} = {value:g}"
            axes.set_title(f"{label} · {_outcome_counts(trajectories)}", fontsize=10)
        y_limits = robust_limits([(0.5, [t[y] for t in dataset])])
        panels[0, 0].set_ylim(*y_limits)  # shared: tracking glitches run off the panels
        for axes in panels.flat[len(groups):]:
            axes.set_visible(False)
        for column in range(columns):
            # the lowest visible panel of each column carries the x labels
            lowest = panels[(len(groups) - 1 - column) // columns, column] if column < len(groups) else None
            if lowest is not None:
                lowest.xaxis.set_tick_params(labelbottom=True)
                lowest.set_xlabel(axis_label(x))
        for axes in panels[:, 0]:
            axes.set_ylabel(axis_label(y))
        handles = ([Line2D([], [], color=HIT_COLOUR, label="hit the basket"),
                    Line2D([], [], color=MISS_COLOUR, label="missed")] if has_outcome else [])
        if glitches:
            handles.append(Line2D([], [], color=_GLITCH_COLOUR, marker=".", linestyle="none",
                                  label=f"tracking glitch ({sum(map(len, glitches.values()))} samples, left out of the lines)"))
        if handles:
            figure.legend(handles=handles, loc="outside lower center", ncols=len(handles))
        count = plural(len(dataset), "trajectory", "trajectories")
        # wrapped: one or two panels are narrower than the title
        figure.suptitle(title or f"Demonstrations per basket distance ({count})", wrap=True)
    return save(figure, out)

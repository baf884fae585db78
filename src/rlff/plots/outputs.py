"""The generated throws: the DMM output for several basket distances, demonstrated and new
(thesis figures 4.5-4.7, 4.40-4.41 and 4.49-4.50).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Protocol

import numpy as np
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from rlff.dataset import Dataset
from rlff.errors import InputError
from rlff.plots._figure import (
    SavedFigure,
    add_curves,
    axis_label,
    distance_colours,
    figure_style,
    format_distance,
    grid_shape,
    new_figure,
    save,
)

_DEMO_COLOUR = "#a0a0a0"

#: Title of the panel that overlays every output (tests and readers look it up by this title).
SUMMARY_TITLE = "Generated throws, one per basket distance"


class GeneratedPathLike(Protocol):
    """What the figure needs of a generated throw (``rlff.model.GeneratedPath`` is one).

    Every attribute is an array of shape (T,): joint angle (rad), the DMM's velocity (rad/s), the
    GMR mean and standard deviation of the velocity (rad/s), and the exploration factor (0-1).
    A path may also carry ``cautions`` (tuple of str), what its generation warned of in a few
    words (``GeneratedPath.cautions``: "extrapolated", ...): its curve is labelled with them.
    """

    angle: np.ndarray
    velocity: np.ndarray
    gmr_mean: np.ndarray
    gmr_std: np.ndarray
    exploration: np.ndarray


def _label(distance: float, demonstrated: bool | None, cautions: Sequence[str] = ()) -> str:
    """The distance, whether it was demonstrated when that is known (None: not known) and what
    its generation warned of: ``z = 8 m (new; extrapolated)``."""
    said = ([] if demonstrated is None else ["demonstrated" if demonstrated else "new"])
    if cautions:
        said.append(", ".join(cautions))
    return format_distance(distance) + (f" ({'; '.join(said)})" if said else "")


def output_trajectories(
    paths: Mapping[float, GeneratedPathLike],
    out: str | Path,
    *,
    dataset: Dataset | None = None,
    x: str = "angle",
    y: str = "velocity",
    context: str = "distance",
) -> SavedFigure:
    """The DMM's throw for every distance: all together, then one panel each with its data.

    The top panel overlays the outputs, coloured by distance; with a dataset, distances without
    demonstrations are dashed and the labels say "demonstrated" or "new" (without one, which
    distances were demonstrated is not known, and neither is said); a throw whose generation
    warned (its ``cautions``: extrapolated, ...) says so in its label. Below, one panel per
    distance shows the demonstrations at that distance (grey), the GMR mean with its ±2σ band
    and the DMM output, which leaves the mean where the demonstrations disagree (thesis figure
    4.7).

    Parameters
    ----------
    paths : mapping of float to generated path
        Basket distance (m) → generated throw (see :class:`GeneratedPathLike`).
    out : path
        File stem of the PNG and SVG.
    dataset : Dataset, optional
        The demonstrations, drawn behind each panel's output; they also decide which distances
        count as demonstrated.
    x, y, context : str
        Column names of the dataset (angle rad, velocity rad/s, distance m).

    Returns
    -------
    SavedFigure
        Its ``warnings`` are the paths' own (``GeneratedPath.warnings``), each after its distance.
    """
    if not paths:
        raise InputError("no generated trajectories to plot")
    by_distance = {float(d): path for d, path in paths.items()}
    distances = sorted(by_distance)
    demonstrated_values: set[float] = set()
    if dataset is not None and len(dataset):
        dataset.require((x, y, context))
        demonstrated_values = {float(t[context][0]) for t in dataset}

    def is_demonstrated(distance: float) -> bool | None:
        if dataset is None:
            return None
        return any(abs(distance - value) < 1e-9 for value in demonstrated_values)

    warnings = [f"{format_distance(distance)}: {warning}" for distance in distances
                for warning in getattr(by_distance[distance], "warnings", ())]
    colours, _, _ = distance_colours(distances)
    rows, columns = grid_shape(len(distances), 4)
    with figure_style():
        figure = new_figure(max(3.6 * columns, 8.0), 4.2 + 3.0 * rows)
        top, bottom = figure.subfigures(2, 1, height_ratios=[4.2, 3.0 * rows])
        summary = top.subplots()
        for distance in distances:
            path = by_distance[distance]
            summary.plot(
                path.angle, path.velocity, color=colours[distance], linewidth=2.0,
                linestyle="--" if is_demonstrated(distance) is False else "-",
                label=_label(distance, is_demonstrated(distance), getattr(path, "cautions", ())),
            )
        summary.set_xlabel(axis_label(x))
        summary.set_ylabel(axis_label(y))
        summary.set_title(SUMMARY_TITLE)
        summary.legend(loc="best", ncols=1 if len(distances) < 6 else 2)
        panels = bottom.subplots(rows, columns, sharex=True, sharey=True, squeeze=False)
        any_demos = False  # whether some panel draws demonstrations (the legend then names them)
        for axes, distance in zip(panels.flat, distances, strict=False):
            path = by_distance[distance]
            if dataset is not None:
                demos = [t for t in dataset if abs(float(t[context][0]) - distance) < 1e-9]
                any_demos |= bool(demos)
                add_curves(axes, [(t[x], t[y]) for t in demos], _DEMO_COLOUR, linewidth=0.7, alpha=0.7, zorder=1)
            mean = np.asarray(path.gmr_mean, dtype=float)
            spread = 2.0 * np.asarray(path.gmr_std, dtype=float)
            axes.fill_between(path.angle, mean - spread, mean + spread, color="black", alpha=0.08, linewidth=0)
            axes.plot(path.angle, mean, color="black", linestyle="--", linewidth=1.1)
            axes.plot(path.angle, path.velocity, color=colours[distance], linewidth=2.0)
            axes.set_title(
                f"{_label(distance, is_demonstrated(distance), getattr(path, 'cautions', ()))}\nmean exploration ε = "
                f"{float(np.mean(path.exploration)):.2f}",
                fontsize=10, wrap=True,
            )
        for axes in panels.flat[len(distances):]:
            axes.set_visible(False)
        for column in range(columns):
            if column < len(distances):
                lowest = panels[(len(distances) - 1 - column) // columns, column]
                lowest.xaxis.set_tick_params(labelbottom=True)
                lowest.set_xlabel(axis_label(x))
        for axes in panels[:, 0]:
            axes.set_ylabel(axis_label(y))
        handles = [
            Line2D([], [], color="black", linestyle="--", label="GMR mean"),
            Patch(color="black", alpha=0.08, label="GMR ±2σ"),
            Line2D([], [], color=colours[distances[0]], linewidth=2.0,
                   label="DMM output (colour: distance; the robot keeps its first pose and release)"),
        ]
        if any_demos:
            handles.insert(0, Line2D([], [], color=_DEMO_COLOUR, linewidth=0.7, label="demonstrations at this distance"))
        # one row fits from three panels across (10.8 in); a narrower figure takes two rows
        bottom.legend(handles=handles, loc="outside lower center", ncols=len(handles) if columns >= 3 else 2)
    return save(figure, out, warnings)


def model_outputs(
    model: Any,
    distances: Sequence[float],
    out: str | Path,
    *,
    dataset: Dataset | None = None,
    angles: np.ndarray | None = None,
    continuity: bool = True,
) -> SavedFigure:
    """:func:`output_trajectories` of a model's throws for several basket distances.

    Parameters
    ----------
    model : rlff.model.Model
        A model with one context input (the distance) and one output (the velocity) or several
        (a whole-arm model: the first, the elbow's velocity, is drawn).
    distances : sequence of float
        Basket distances (m); distances outside the data are welcome (extrapolation).
    out : path
        File stem of the PNG and SVG.
    dataset : Dataset, optional
        The demonstrations, drawn behind the outputs.
    angles : array of shape (T,), optional
        Angle grid (rad); default ``Model.generate``'s (up to the demonstrations' release).
    continuity : bool
        Keep each throw continuous where two modes are nearly as high (see ``Model.generate``);
        on by default, as ``rlff generate`` writes the throw.
    """
    if len(model.context_names) != 1:
        raise InputError(
            f"the outputs figure needs a model with one context input (the distance), this one has "
            f"context {list(model.context_names)}"
        )
    if not distances:
        raise InputError("no distances to generate throws for")
    (context,) = model.context_names
    paths = {float(d): model.generate({context: float(d)}, angles, continuity=continuity) for d in distances}
    return output_trajectories(paths, out, dataset=dataset, x=model.inputs[0], y=model.outputs[0], context=context)

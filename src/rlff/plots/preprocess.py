"""Each preprocessing step before and after (thesis figures 4.16, 4.22, 4.26, 4.30-4.31, 4.36, 4.43).

The thesis shows the dataset after every refinement it applied by hand; here one panel per step of
the pipeline overlays the data before the step (grey) and after it (coloured by distance).
"""

from __future__ import annotations

import textwrap
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.cm import ScalarMappable
from matplotlib.lines import Line2D

from rlff.dataset import Dataset
from rlff.errors import InputError
from rlff.plots._figure import (
    SavedFigure,
    add_curves,
    axis_label,
    distance_colours,
    figure_style,
    grid_shape,
    new_figure,
    save,
)

_BEFORE_COLOUR = "#b0b0b0"


def _change(before: Dataset, after: Dataset) -> str:
    if len(before) == len(after) and before.n_samples == after.n_samples:
        return f"{len(after)} traj., {after.n_samples} samples"
    return (
        f"{len(before)} → {len(after)} traj., "
        f"{before.n_samples} → {after.n_samples} samples"
    )


def _robust_limits(after: list[np.ndarray], before: list[np.ndarray]) -> tuple[float, float] | None:
    """Axis limits holding nearly all the data after the step and the bulk of the data before it
    (2nd to 98th percentile), with a margin: rare tracking glitches far outside do not squash the
    throws into a line, they run off the panel."""
    ranges = [np.percentile(np.concatenate(v), q) for v, q in ((after, [0.2, 99.8]), (before, [2.0, 98.0])) if v]
    if not ranges:
        return None
    low = min(r[0] for r in ranges)
    high = max(r[1] for r in ranges)
    margin = 0.08 * max(high - low, 1e-9)
    return float(low - margin), float(high + margin)


def preprocessing_steps(
    steps: Sequence[tuple[str, Dataset, Dataset] | tuple[str, Dataset, Dataset, str]],
    out: str | Path,
    *,
    x: str = "angle",
    y: str = "velocity",
    context: str = "distance",
    max_columns: int = 3,
) -> SavedFigure:
    """One panel per step: the data before it in grey, after it coloured by basket distance.

    Each panel is scaled to the bulk of its data (1st to 99th percentile), so that the few
    tracking glitches the first step removes do not flatten everything else.

    Parameters
    ----------
    steps : sequence of (name, before, after) or (name, before, after, note)
        Step name, the datasets before and after it, and an optional one-line note (what the
        step reported), in pipeline order. For a pipeline report:
        ``[(s.step, s.before, s.after, s.summary()) for s in report.steps]``.
    out : path
        File stem of the PNG and SVG.
    x, y : str
        Columns on the axes (default angle rad, velocity rad/s).
    context : str
        Column that sets the colour (default the basket distance, m).
    max_columns : int
        Panels per row.
    """
    if not steps:
        raise InputError("no preprocessing steps to plot")
    contexts: set[float] = set()
    for _name, before, after, *_ in steps:
        for dataset in (before, after):
            if len(dataset):
                dataset.require((x, y, context))
                contexts.update(float(t[context][0]) for t in dataset)
    colours, norm, cmap = distance_colours(sorted(contexts))
    rows, columns = grid_shape(len(steps), max_columns)
    with figure_style():
        figure = new_figure(max(4.2 * columns, 8.0), 3.4 * rows + 0.7)
        panels = figure.subplots(rows, columns, squeeze=False)
        for index, (axes, (name, before, after, *note)) in enumerate(zip(panels.flat, steps, strict=False)):
            add_curves(axes, [(t[x], t[y]) for t in before], _BEFORE_COLOUR, linewidth=0.8, alpha=0.7,
                       label="before", zorder=1)
            add_curves(axes, [(t[x], t[y]) for t in after],
                       [colours[float(t[context][0])] for t in after], linewidth=1.0, alpha=0.85,
                       label="after", zorder=2)
            for limits, setter in (
                (_robust_limits([t[x] for t in after], [t[x] for t in before]), axes.set_xlim),
                (_robust_limits([t[y] for t in after], [t[y] for t in before]), axes.set_ylim),
            ):
                if limits is not None:
                    setter(*limits)
            title = f"{index + 1}. {name}\n{_change(before, after)}"
            if note and note[0]:
                title += "\n" + textwrap.shorten(note[0], 52, placeholder=" …")
            axes.set_title(title, fontsize=9.5)
            if index % columns == 0:
                axes.set_ylabel(axis_label(y))
            axes.set_xlabel(axis_label(x))
        for axes in panels.flat[len(steps):]:
            axes.set_visible(False)
        figure.legend(
            handles=[
                Line2D([], [], color=_BEFORE_COLOUR, label="before the step"),
                Line2D([], [], color=cmap(0.5), label="after the step (colour: distance)"),
            ],
            loc="outside upper right",
            ncols=2,
        )
        colour_bar = figure.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=figure.axes, shrink=0.6)
        colour_bar.set_label(axis_label(context))
        figure.suptitle("Preprocessing, step by step", x=0.02, horizontalalignment="left")
    return save(figure, out)


def pipeline_steps(
    dataset: Dataset,
    out: str | Path,
    *,
    preset: str | None = None,
    config: str | Path | None = None,
) -> SavedFigure:
    """Run a preprocessing pipeline on ``dataset`` and plot :func:`preprocessing_steps` of it.

    Parameters
    ----------
    dataset : Dataset
        Raw demonstrations.
    out : path
        File stem of the PNG and SVG.
    preset : str, optional
        A packaged pipeline (default ``"thesis"`` when no ``config`` is given).
    config : path, optional
        A pipeline TOML file.
    """
    from rlff.preprocess import Pipeline

    pipeline = Pipeline.from_toml(config) if config is not None else Pipeline.preset(preset or "thesis")
    _, report = pipeline.run(dataset)
    return preprocessing_steps(
        [
            (step.step, step.before, step.after if step.after is not None else step.before, step.summary())
            for step in report.steps
        ],
        out,
    )

"""Each preprocessing step before and after (thesis figures 4.16, 4.22, 4.26, 4.30-4.31, 4.36, 4.43).

The thesis shows the dataset after every refinement it applied by hand; here one panel per step of
the pipeline overlays the data before the step (grey) and after it (coloured by distance).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from matplotlib.cm import ScalarMappable
from matplotlib.lines import Line2D

from rlff.dataset import Dataset
from rlff.errors import InputError
from rlff.plots._figure import (
    SavedFigure,
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


def preprocessing_steps(
    steps: Sequence[tuple[str, Dataset, Dataset]],
    out: str | Path,
    *,
    x: str = "angle",
    y: str = "velocity",
    context: str = "distance",
    max_columns: int = 3,
) -> SavedFigure:
    """One panel per step: the data before it in grey, after it coloured by basket distance.

    Parameters
    ----------
    steps : sequence of (name, before, after)
        Step name and the datasets before and after it, in pipeline order (for a pipeline
        report: ``[(s.name, s.before, s.after) for s in report.steps]``).
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
    for _name, before, after in steps:
        for dataset in (before, after):
            if len(dataset):
                dataset.require((x, y, context))
                contexts.update(float(t[context][0]) for t in dataset)
    colours, norm, cmap = distance_colours(sorted(contexts))
    rows, columns = grid_shape(len(steps), max_columns)
    with figure_style():
        figure = new_figure(max(4.2 * columns, 8.0), 3.3 * rows + 0.7)
        panels = figure.subplots(rows, columns, sharex=True, sharey=True, squeeze=False)
        for index, (axes, (name, before, after)) in enumerate(zip(panels.flat, steps, strict=False)):
            for trajectory in before:
                axes.plot(trajectory[x], trajectory[y], color=_BEFORE_COLOUR, linewidth=0.8, alpha=0.7)
            for trajectory in after:
                axes.plot(
                    trajectory[x], trajectory[y],
                    color=colours[float(trajectory[context][0])], linewidth=1.0, alpha=0.85,
                )
            axes.set_title(f"{index + 1}. {name}\n{_change(before, after)}", fontsize=10)
        for axes in panels.flat[len(steps):]:
            axes.set_visible(False)
        for column in range(columns):
            if column < len(steps):
                lowest = panels[(len(steps) - 1 - column) // columns, column]
                lowest.xaxis.set_tick_params(labelbottom=True)
                lowest.set_xlabel(axis_label(x))
        for axes in panels[:, 0]:
            axes.set_ylabel(axis_label(y))
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

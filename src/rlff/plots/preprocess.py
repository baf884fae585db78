"""Each preprocessing step before and after (thesis figures 4.16, 4.22, 4.26, 4.30-4.31, 4.36, 4.43).

The thesis shows the dataset after every refinement it applied by hand; here one panel per step of
the pipeline overlays the data before the step (grey) and after it (coloured by distance).
"""

from __future__ import annotations

import textwrap
from collections.abc import Sequence
from pathlib import Path

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
    robust_limits,
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
            # nearly all the data after the step, the bulk of the data before it
            for column, setter in ((x, axes.set_xlim), (y, axes.set_ylim)):
                limits = robust_limits([(0.2, [t[column] for t in after]), (2.0, [t[column] for t in before])])
                if limits is not None:
                    setter(*limits)
            title = f"{index + 1}. {name}\n{_change(before, after)}"
            if note and note[0]:  # wrapped to the panel's width, cut only past three lines
                title += "\n" + "\n".join(textwrap.wrap(note[0], 52, max_lines=3, placeholder=" …"))
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

"""What every figure shares: one style, colours per basket distance, saving as PNG and SVG.

Figures are built with matplotlib's object API (``Figure`` without pyplot), so no global figure
state is kept between calls and any number of figures can be made in a loop or in parallel
processes. PNG is written through the Agg renderer; the SVG keeps text as text.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.colors import Colormap, ListedColormap, Normalize
from matplotlib.figure import Figure

from rlff.fileio import atomic_path

#: Resolution of the PNG files (dots per inch).
PNG_DPI = 110
#: Curves with more points than this in all are drawn as an image inside the SVG (the file stays
#: small; axes, labels and text stay vector).
RASTERIZE_ABOVE = 20_000

#: Readable sizes for a figure shown at page width in a report or a paper.
_STYLE = {
    "font.size": 11,
    "axes.titlesize": 12,
    "axes.labelsize": 11,
    "legend.fontsize": 9,
    "xtick.labelsize": 10,
    "ytick.labelsize": 10,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "svg.fonttype": "none",
    "figure.constrained_layout.use": True,
}

#: Axis labels with units for the throwing task's columns.
AXIS_LABELS = {
    "angle": "joint angle ξ (rad)",
    "distance": "basket distance z (m)",
    "velocity": "joint velocity ξ̇ (rad/s)",
    "time": "time t (s)",
}

#: Colours of successful and failed demonstrations.
HIT_COLOUR = "#1a9850"
MISS_COLOUR = "#d73027"


def axis_label(column: str) -> str:
    """Axis label with its unit for a column name (the name itself for unknown columns)."""
    return AXIS_LABELS.get(column, column)


@dataclass(frozen=True)
class SavedFigure:
    """A figure and the files it was written to.

    Attributes
    ----------
    figure : matplotlib.figure.Figure
        The figure object, for inspection (tests check its axes, lines and labels).
    png, svg : Path
        The written files.
    warnings : tuple of str
        What may make what the figure draws wrong (a generated throw past the data, ...), for the
        caller to say (``rlff plot`` prints them on stderr); the figure marks it too.
    """

    figure: Figure
    png: Path
    svg: Path
    warnings: tuple[str, ...] = ()

    @property
    def paths(self) -> tuple[Path, Path]:
        """The PNG and the SVG path."""
        return (self.png, self.svg)


@contextmanager
def figure_style() -> Iterator[None]:
    """Apply the rlff style to the artists created inside the block."""
    with matplotlib.rc_context(_STYLE):
        yield


def new_figure(width: float, height: float) -> Figure:
    """An empty figure of ``width`` x ``height`` inches, outside pyplot's global state."""
    return Figure(figsize=(width, height))


def save(figure: Figure, out: str | Path, warnings: Sequence[str] = ()) -> SavedFigure:
    """Write ``figure`` as ``OUT.png`` and ``OUT.svg``.

    Parameters
    ----------
    figure : Figure
    out : path
        File stem; a ``.png`` or ``.svg`` suffix is replaced. Missing folders are created.
    warnings : sequence of str
        What the caller should say of the figure (:attr:`SavedFigure.warnings`).
    """
    out = Path(out)
    if out.suffix.lower() in (".png", ".svg"):
        out = out.with_suffix("")
    png = out.with_name(out.name + ".png")
    svg = out.with_name(out.name + ".svg")
    with figure_style():
        with atomic_path(png) as temp:
            figure.savefig(temp, dpi=PNG_DPI, format="png")
        # the layout is settled by the PNG's drawing; keep it instead of solving it again
        engine = figure.get_layout_engine()
        figure.set_layout_engine("none")
        with atomic_path(svg) as temp:
            figure.savefig(temp, format="svg")
        figure.set_layout_engine(engine)
    return SavedFigure(figure, png, svg, tuple(warnings))


def distance_colours(
    distances: Sequence[float], cmap: str = "viridis"
) -> tuple[dict[float, tuple[float, float, float, float]], Normalize, Colormap]:
    """One colour per basket distance on a sequential colour map, so near distances look alike.

    Returns
    -------
    colours : dict of float to RGBA
    norm : Normalize
        Maps a distance (m) to [0, 1]; use with ``cmap`` for a colour bar.
    cmap : Colormap
    """
    values = np.asarray(sorted({float(d) for d in distances}), dtype=float)
    # viridis' pale yellow end vanishes on white: use the first 90 % of the map
    colour_map = ListedColormap(matplotlib.colormaps[cmap](np.linspace(0.0, 0.9, 256)), name=cmap)
    if values.size == 0:
        return {}, Normalize(0.0, 1.0), colour_map
    low, high = float(values.min()), float(values.max())
    if high - low < 1e-12:
        low, high = low - 0.5, high + 0.5
    norm = Normalize(low, high)
    colours = {float(d): colour_map(norm(d)) for d in values}
    return colours, norm, colour_map


def grid_shape(n: int, max_columns: int = 4) -> tuple[int, int]:
    """Rows and columns of a panel grid for ``n`` panels, at most ``max_columns`` wide."""
    n = max(n, 1)
    rows = -(-n // max_columns)
    columns = -(-n // rows)  # balance the rows: 5 panels as 3 + 2, not 4 + 1
    return rows, columns


def format_distance(distance: float) -> str:
    """A basket distance for a legend or a title, e.g. ``z = 2.5 m``."""
    return f"z = {distance:g} m"


def add_curves(
    axes: Axes,
    curves: Sequence[tuple[np.ndarray, np.ndarray]],
    colours: Sequence[Any] | Any,
    *,
    linewidth: float = 1.0,
    alpha: float | None = 0.8,
    label: str | None = None,
    zorder: float = 2.0,
) -> LineCollection:
    """Draw many (x, y) curves as one LineCollection (one artist: fast to draw and to save).

    Parameters
    ----------
    curves : sequence of (x, y) pairs of arrays of shape (T_i,)
    colours : one colour, or one per curve
    alpha : float, or None for the colours' own alpha (RGBA)
    """
    segments = [np.column_stack([x, y]) for x, y in curves]
    collection = LineCollection(
        segments, colors=colours, linewidths=linewidth, alpha=alpha, label=label, zorder=zorder,
        rasterized=sum(len(s) for s in segments) > RASTERIZE_ABOVE,
    )
    axes.add_collection(collection)
    axes.autoscale_view()
    return collection


def robust_limits(groups: Sequence[tuple[float, Sequence[np.ndarray]]], margin: float = 0.08) -> tuple[float, float] | None:
    """Axis limits that hold the bulk of the data, so rare tracking glitches far outside do not
    squash everything else into a line (they run off the axes instead).

    Parameters
    ----------
    groups : sequence of (tail, arrays)
        Each group of arrays is covered from its ``tail``-th to its (100 - ``tail``)-th
        percentile (e.g. 0.2 for nearly all of it, 2 for its bulk).
    margin : float
        Share of the range added on both sides.

    Returns
    -------
    (low, high), or None when there is no data.
    """
    ranges = [np.percentile(np.concatenate(arrays), [tail, 100.0 - tail]) for tail, arrays in groups if len(arrays)]
    if not ranges:
        return None
    low = min(float(r[0]) for r in ranges)
    high = max(float(r[1]) for r in ranges)
    pad = margin * max(high - low, 1e-9)
    return low - pad, high + pad

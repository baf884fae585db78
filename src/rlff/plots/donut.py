"""Figures of the Donut Mixture Model: a Gaussian beside its donuts for several exploration factors
(thesis figure 2.5), and the DMM density over (angle, velocity) seen from above with the chosen
throw and the GMR mean (figures 2.7 and 4.4).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
from matplotlib.colors import PowerNorm

from rlff.dataset import Dataset
from rlff.errors import InputError
from rlff.plots._figure import (
    SavedFigure,
    add_curves,
    axis_label,
    figure_style,
    format_distance,
    new_figure,
    save,
)

#: Points of the density grid along each axis.
_GRID = 220


def donut_family(
    out: str | Path,
    *,
    eps: Sequence[float] = (0.0, 0.25, 0.5, 0.75, 1.0),
    gamma: float | None = None,
) -> SavedFigure:
    """A standard Gaussian and the donuts made of it for several exploration factors ε.

    Parameters
    ----------
    out : path
        File stem of the PNG and SVG.
    eps : sequence of float
        Exploration factors in [0, 1]; ε = 0 is the Gaussian itself, ε = 1 has zero density at
        the mean.
    gamma : float, optional
        The donut's weight γ > 1 (default :data:`rlff.model.donut.GAMMA`, the thesis' 2).
    """
    from rlff.model.donut import GAMMA, donut_pdf

    gamma = GAMMA if gamma is None else gamma
    values = [float(e) for e in eps]
    if not values:
        raise InputError("no exploration factors to plot")
    bad = [e for e in values if not (0.0 <= e <= 1.0)]
    if bad:
        raise InputError(f"exploration factor {bad[0]:g} is outside [0, 1]")
    y = np.linspace(-4.0, 4.0, 801)
    gaussian = np.exp(-0.5 * y**2) / np.sqrt(2.0 * np.pi)
    colour_map = matplotlib.colormaps["plasma"]
    with figure_style():
        figure = new_figure(7.6, 4.6)
        axes = figure.add_subplot()
        for e in values:
            density = donut_pdf(y[:, None], np.zeros(1), np.eye(1), e, gamma)
            axes.plot(y, density, color=colour_map(0.85 * e), linewidth=1.8, label=f"donut, ε = {e:g}")
        axes.plot(y, gaussian, color="black", linestyle="--", linewidth=1.6, label="Gaussian N(0, 1)")
        axes.set_xlabel("output y − μ (in standard deviations σ)")
        axes.set_ylabel("density (1/σ)")
        axes.set_title(f"A Gaussian and its donuts (γ = {gamma:g}): the hole grows with ε")
        axes.legend(loc="upper right")
    return save(figure, out)


def _up_to_release(model: Any, angles: np.ndarray) -> np.ndarray:
    """Mask (T,) of the ``angles`` a generated throw covers: from the start of
    :meth:`rlff.model.Model.default_path` to its end, the demonstrations' release."""
    path = model.default_path()
    low, high = sorted((float(path[0]), float(path[-1])))
    return (angles >= low - 1e-12) & (angles <= high + 1e-12)


def dmm_heatmap(
    model: Any,
    distance: float,
    out: str | Path,
    *,
    dataset: Dataset | None = None,
    angles: np.ndarray | None = None,
    exploration: str | float = "auto",
    exploration_scale: float = 1.0,
) -> SavedFigure:
    """The DMM density P(velocity | angle, distance) as a heat map, the throw the model chooses
    (highest density at every angle) and the GMR mean; below it the exploration factor ε.

    With several outputs (a whole-arm model: velocity, shoulder, ...) the map is the density of
    the first output with the others integrated out (:func:`rlff.model.donut.dmm_marginal_pdf`),
    and the throw drawn is the first output of the joint mode, which need not sit on the
    marginal's ridge.

    Parameters
    ----------
    model : rlff.model.Model
        A fitted model with inputs (angle, distance) and one output (velocity) or several (the
        first is drawn).
    distance : float
        Basket distance (m).
    out : path
        File stem of the PNG and SVG.
    dataset : Dataset, optional
        Demonstrations; those at ``distance`` are drawn over the density.
    angles : array of shape (T,), optional
        Angle grid (rad); default the model's fitted range.
    exploration, exploration_scale
        As for :meth:`rlff.model.Model.generate`.

    Returns
    -------
    SavedFigure
        Its ``warnings`` are what :meth:`rlff.model.Model.generate` warns of the throw drawn (a
        distance past the data, ...); the title names them in a few words.
    """
    from rlff.model.donut import dmm_marginal_pdf

    if len(model.inputs) != 2:
        raise InputError(
            f"the density map needs a model with 2 inputs (the path variable and the distance), this one has "
            f"inputs {list(model.inputs)}"
        )
    x_name, context = model.inputs
    y_name = model.outputs[0]
    if angles is None:
        angles = np.linspace(*model.input_range[x_name], _GRID)
    path = model.generate({context: distance}, angles, exploration=exploration, exploration_scale=exploration_scale)
    low = float(min(np.min(path.gmr_mean - 3.5 * path.gmr_std), np.min(path.velocity)))
    high = float(max(np.max(path.gmr_mean + 3.5 * path.gmr_std), np.max(path.velocity)))
    margin = 0.05 * (high - low)
    velocities = np.linspace(low - margin, high + margin, _GRID)
    conditional = model.condition(np.column_stack([path.angle, np.full(path.angle.size, distance)]))
    grid = np.broadcast_to(velocities[None, :], (path.angle.size, velocities.size))
    density = dmm_marginal_pdf(conditional, grid, path.exploration)  # (T, M)
    with figure_style():
        figure = new_figure(9.0, 6.4)
        top, bottom = figure.subplots(2, 1, sharex=True, height_ratios=[3.2, 1.0])
        # a square-root colour scale: the narrow, tall components would otherwise hide the wide ones
        mesh = top.pcolormesh(path.angle, velocities, density.T, cmap="inferno", shading="auto",
                              norm=PowerNorm(0.5, vmin=0.0), rasterized=True)
        if dataset is not None and len(dataset):
            dataset.require((x_name, y_name, context))
            demos = [t for t in dataset if abs(float(t[context][0]) - distance) < 1e-9]
            add_curves(top, [(t[x_name], t[y_name]) for t in demos], "#d0d0d0", linewidth=0.6, alpha=0.6,
                       label=f"demonstrations at {format_distance(distance)}" if demos else None, zorder=2)
        # the throw up to the release, where `rlff generate` ends it (the density goes on beyond:
        # drawn on to the range's end, the chosen throw had run to 13 rad/s where the generated
        # throw let go at 7.3)
        thrown = _up_to_release(model, path.angle)
        # what generate warns of the throw drawn (up to the release: past it, a pose no arm
        # takes is no warning about this throw)
        drawn = path if thrown.all() else model.generate({context: distance}, path.angle[thrown],
                                                          exploration=exploration, exploration_scale=exploration_scale)
        top.plot(path.angle[thrown], path.gmr_mean[thrown], color="white", linestyle="--", linewidth=1.5,
                 label="GMR mean")
        top.plot(path.angle[thrown], path.velocity[thrown], color="#22d3ee", linewidth=2.2,
                 label="chosen throw (highest density)")
        if not thrown.all():
            release = float(model.default_path()[-1])
            for axes in (top, bottom):
                axes.axvline(release, color="#a3a3a3", linestyle=":", linewidth=1.2,
                             label="release (the generated throw ends)" if axes is top else None)
        top.set_xlim(path.angle[0], path.angle[-1])
        top.set_ylim(velocities[0], velocities[-1])
        top.set_ylabel(axis_label(y_name))
        cautions = f" ({', '.join(drawn.cautions)})" if drawn.cautions else ""
        top.set_title(f"DMM density at {format_distance(distance)}{cautions}, seen from above", wrap=True)
        legend = top.legend(loc="upper left", fontsize=8, facecolor="#333333", labelcolor="white", framealpha=0.8)
        legend.get_frame().set_edgecolor("none")
        top.grid(False)
        # the colour bar sits in an inset so that both panels keep one width and their angles align
        colour_bar = figure.colorbar(mesh, cax=top.inset_axes([1.02, 0.0, 0.025, 1.0]))
        colour_bar.set_label("P_DMM(ξ̇ | ξ, z) (s/rad)" + (", other outputs integrated out" if len(model.outputs) > 1 else ""))
        bottom.plot(path.angle, path.exploration, color="#7c3aed", linewidth=1.8)
        bottom.set_ylim(0.0, 1.0)
        bottom.set_ylabel("exploration ε")
        bottom.set_xlabel(axis_label(x_name))
    return save(figure, out, drawn.warnings)

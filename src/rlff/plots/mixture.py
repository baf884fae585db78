"""Figures of the Gaussian mixture: k-means and EM for several K (thesis figures 2.3-2.4), the
BIC against K (eq. 2.2), and the components as ellipses on the (angle, velocity) plane for one
basket distance (figures 4.2-4.3, 4.19-4.20, 4.47-4.48).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
from matplotlib.axes import Axes
from matplotlib.colors import to_hex
from matplotlib.lines import Line2D
from matplotlib.patches import Ellipse
from matplotlib.ticker import MaxNLocator
from scipy.cluster.vq import kmeans2

from rlff.dataset import Dataset
from rlff.errors import InputError
from rlff.model.mixture import GaussianMixture
from rlff.plots._figure import (
    SavedFigure,
    add_curves,
    axis_label,
    figure_style,
    format_distance,
    new_figure,
    save,
)

#: Ellipses drawn at these Mahalanobis radii (1 and 2 standard deviations).
_SIGMAS = (1.0, 2.0)
_DATA_COLOUR = "#9a9a9a"
#: The criteria's names in titles.
_CRITERIA = {"bic": "Bayesian information criterion", "aic": "Akaike information criterion"}
#: Components whose weight at the shown distance is below this are left out of the drawing.
MIN_SHOWN_WEIGHT = 0.01


#: Colours of the components past the tenth (matplotlib's C0-C9 first): tab20b's, none of C0-C9.
_MORE_COLOURS = tuple(to_hex(colour) for colour in matplotlib.colormaps["tab20b"].colors)


def component_colour(k: int) -> str:
    """Colour of component ``k`` (the same in every mixture figure): 30 colours apart before they
    repeat (C0-C9 had a 12th component drawn in the 2nd's colour)."""
    return f"C{k}" if k < 10 else _MORE_COLOURS[(k - 10) % len(_MORE_COLOURS)]


def draw_ellipses(
    axes: Axes, mean: np.ndarray, covariance: np.ndarray, colour: str, *, alpha: float = 0.25, label: str | None = None
) -> None:
    """Draw the 1- and 2-sigma ellipses of a 2-D Gaussian on ``axes``.

    Parameters
    ----------
    mean : array of shape (2,)
    covariance : array of shape (2, 2)
        Symmetric positive definite, in the squared units of the axes.
    """
    values, vectors = np.linalg.eigh(covariance)
    values = np.clip(values, 0.0, None)
    angle = float(np.degrees(np.arctan2(vectors[1, -1], vectors[0, -1])))
    for n_sigma in _SIGMAS:
        width, height = 2.0 * n_sigma * np.sqrt(values[::-1])
        axes.add_patch(
            Ellipse(
                tuple(mean), width, height, angle=angle, facecolor=colour,
                alpha=alpha / n_sigma, edgecolor=colour, linewidth=1.5,
            )
        )
    axes.plot(*mean, marker="x", color=colour, markersize=9, markeredgewidth=2, linestyle="none", label=label)


def kmeans_em_steps(
    points: np.ndarray,
    out: str | Path,
    *,
    ks: Sequence[int] = (2, 3, 4),
    columns: tuple[str, str] = ("angle", "velocity"),
    seed: int = 0,
    max_points: int = 3000,
    effective_samples: float | None = None,
) -> SavedFigure:
    """k-means clusters (top row) and the Gaussian mixture EM makes of them (bottom row), per K.

    k-means (scipy's, with k-means++ seeding, on standardised columns) gives the first placement
    of the components; EM (:class:`rlff.model.mixture.GaussianMixture`) refines it into weights, means
    and covariances (thesis section 2.2.1).

    Parameters
    ----------
    points : array of shape (N, 2)
        Samples on the plotted plane, e.g. ``dataset.to_array(["angle", "velocity"])``.
    out : path
        File stem of the PNG and SVG.
    ks : sequence of int
        Numbers of components, one column each.
    columns : (x, y) column names, for the axis labels.
    seed : int
        Seed of k-means, EM and the subset.
    max_points : int
        Larger sets are shown (and clustered) through a random subset of this size, said in the title.
    effective_samples : float, optional
        How many independent samples the N points stand for, for the BIC in the titles, as
        ``Model.fit`` counts them (:func:`rlff.model.model.effective_sample_count`); None: every
        point counts. A random subset stands for its share of them.
    """
    points = np.asarray(points, dtype=float)
    if points.ndim != 2 or points.shape[1] != 2:
        raise InputError(f"points must have shape (N, 2), got {points.shape}")
    if not np.all(np.isfinite(points)):
        raise InputError("points hold NaN or inf")
    if not ks:
        raise InputError("no number of components: give one or more, e.g. 2,3,4")
    bad = [k for k in ks if not 1 <= k <= points.shape[0]]
    if bad:  # only the bad ones: "[0, 1] must be between 1 and ..." read as if 1 were wrong too
        raise InputError(f"{'number' if len(bad) == 1 else 'numbers'} of components {', '.join(map(str, bad))} "
                         f"must be between 1 and the {points.shape[0]} points")
    n_points = points.shape[0]
    if n_points > max_points:  # an illustration of the algorithms: a random subset reads as well
        points = points[np.sort(np.random.default_rng(seed).choice(n_points, max_points, replace=False))]
    counted = None if effective_samples is None else effective_samples * points.shape[0] / n_points
    scale = points.std(axis=0)
    scale[scale == 0] = 1.0
    centre = points.mean(axis=0)
    standard = (points - centre) / scale
    with figure_style():
        figure = new_figure(3.9 * len(ks), 7.0)
        panels = figure.subplots(2, len(ks), sharex=True, sharey=True, squeeze=False)
        for column, k in enumerate(ks):
            centroids, labels = kmeans2(standard, k, minit="++", seed=seed)
            centroids = centroids * scale + centre
            top = panels[0, column]
            # colours follow the order along the x axis, so that k-means and EM colours match
            for rank, j in enumerate(np.argsort(centroids[:, 0])):
                members = labels == j
                colour = component_colour(rank)
                top.scatter(points[members, 0], points[members, 1], s=6, color=colour, alpha=0.6, rasterized=True)
                top.plot(*centroids[j], marker="X", markersize=11, color=colour, markeredgecolor="black")
            top.set_title(f"k-means, K = {k}")
            mixture = GaussianMixture(k, random_state=seed).fit(points)
            bottom = panels[1, column]
            bottom.scatter(points[:, 0], points[:, 1], s=4, color=_DATA_COLOUR, alpha=0.5, rasterized=True)
            for rank, j in enumerate(np.argsort(mixture.means_[:, 0])):
                draw_ellipses(bottom, mixture.means_[j], mixture.covariances_[j], component_colour(rank))
            bottom.set_title(f"EM, K = {k} (BIC {mixture.bic(points, effective_samples=counted):.4g} of this plane)")
            bottom.set_xlabel(axis_label(columns[0]))
        for row in range(2):
            panels[row, 0].set_ylabel(axis_label(columns[1]))
        figure.legend(
            handles=[
                Line2D([], [], marker="X", color="grey", markeredgecolor="black", linestyle="none", label="k-means centre"),
                Line2D([], [], marker="x", color="grey", linestyle="none", label="Gaussian mean, 1σ and 2σ ellipses"),
            ],
            loc="outside lower center",
            ncols=2 if len(ks) > 1 else 1,  # one K is too narrow for both in a row
        )
        shown = f" ({points.shape[0]} of {n_points} samples, drawn at random)" if n_points > points.shape[0] else ""
        bic = _counted("BIC", points.shape[0], counted)
        plane = f"the ({columns[0]}, {columns[1]}) plane: its BIC is not rlff fit's, which fits every column"
        figure.suptitle(f"Placing the components: k-means, then EM, on {plane}{shown}\n{bic}", x=0.02,
                        horizontalalignment="left",
                        wrap=True)  # one K is narrower than the title
    return save(figure, out)


def selection_curve(
    table: Sequence[Mapping[str, Any]],
    out: str | Path,
    *,
    criterion: str = "bic",
    n_samples: int | None = None,
    effective_samples: float | None = None,
) -> SavedFigure:
    """BIC and AIC against the number of components K, the chosen K marked.

    Parameters
    ----------
    table : sequence of mapping
        One row per K with ``n_components``, ``bic`` and ``aic`` (``Selection.table``).
    out : path
        File stem of the PNG and SVG.
    criterion : {"bic", "aic"}
        The criterion that chose K (its minimum is marked).
    n_samples : int, optional
        The samples the mixtures were fitted to; with it the title says what n the criteria count.
    effective_samples : float, optional
        The independent samples the criteria counted in place of ``n_samples``
        (``model.fit_info["effective_samples"]``); None: every sample.
    """
    if not table:
        raise InputError("the model-selection table is empty")
    for name in ("n_components", "bic", "aic"):
        if name not in table[0]:
            raise InputError(f"the model-selection table has no {name!r} column")
    if criterion not in ("bic", "aic"):
        raise InputError(f"criterion must be 'bic' or 'aic', got {criterion!r}")
    ks = np.array([row["n_components"] for row in table], dtype=int)
    scores = {name: np.array([row[name] for row in table], dtype=float) for name in ("bic", "aic")}
    chosen = int(np.argmin(scores[criterion]))
    with figure_style():
        figure = new_figure(6.4, 4.2)
        axes = figure.add_subplot()
        axes.plot(ks, scores["bic"], marker="o", color="C0", label="BIC = −2 ln L + p ln n")
        axes.plot(ks, scores["aic"], marker="s", color="C1", linestyle="--", label="AIC = −2 ln L + 2p")
        axes.plot(
            ks[chosen], scores[criterion][chosen], marker="o", markersize=16, markerfacecolor="none",
            markeredgecolor="black", markeredgewidth=2, linestyle="none",
            label=f"chosen: K = {ks[chosen]} (lowest {criterion.upper()})",
        )
        # whole K only, also for one K (its axis spanned 0.945-1.055 in fractional ticks)
        axes.xaxis.set_major_locator(MaxNLocator(integer=True, min_n_ticks=1))
        axes.set_xlim(ks.min() - 0.5, ks.max() + 0.5)
        axes.set_xlabel("number of Gaussian components K")
        axes.set_ylabel("criterion (lower is better)")
        axes.legend()
        title = f"Choosing K by the {_CRITERIA[criterion]}"
        if n_samples is not None:
            title += "\n" + _counted("BIC and AIC", n_samples, effective_samples)
        axes.set_title(title)
    return save(figure, out)


def _counted(criteria: str, n_samples: int, effective_samples: float | None) -> str:
    """What n the information ``criteria`` count, in words for a title."""
    if effective_samples is None:
        return f"{criteria} over all {n_samples} samples"
    return f"{criteria} over {effective_samples:.0f} effective samples (of {n_samples})"


def components_at_distance(
    weights: np.ndarray,
    means: np.ndarray,
    covariances: np.ndarray,
    dataset: Dataset,
    distance: float,
    out: str | Path,
    *,
    columns: tuple[str, str] = ("angle", "velocity"),
    context: str = "distance",
    title: str | None = None,
) -> SavedFigure:
    """The mixture's components on the (angle, velocity) plane for one basket distance.

    Each component is drawn as its 1- and 2-sigma ellipses, shaded by its weight at that
    distance; the demonstrations of that distance are drawn over it and the others faintly
    (thesis figures 4.2-4.3).

    Parameters
    ----------
    weights : array of shape (K,)
        Component weights at the distance (the joint mixture conditioned on it).
    means : array of shape (K, 2)
        Component means on the plane (columns ``columns``), at the distance.
    covariances : array of shape (K, 2, 2)
        Component covariances on the plane, at the distance.
    dataset : Dataset
        The data the mixture was fitted to.
    distance : float
        The basket distance (m).
    out : path
        File stem of the PNG and SVG.
    """
    weights = np.asarray(weights, dtype=float)
    means = np.asarray(means, dtype=float)
    covariances = np.asarray(covariances, dtype=float)
    k = weights.size
    if means.shape != (k, 2) or covariances.shape != (k, 2, 2):
        raise InputError(
            f"components must have shapes (K,), (K, 2), (K, 2, 2); got {weights.shape}, {means.shape}, {covariances.shape}"
        )
    dataset.require((*columns, context))
    with figure_style():
        figure = new_figure(10.0, 5.2)
        axes = figure.add_subplot()
        nearest = None
        if len(dataset):
            values = np.array(sorted({float(t[context][0]) for t in dataset}))
            nearest = float(values[np.argmin(np.abs(values - distance))])
        here = [t for t in dataset if abs(float(t[context][0]) - distance) < 1e-9]
        elsewhere = [t for t in dataset if abs(float(t[context][0]) - distance) >= 1e-9]
        add_curves(axes, [(t[columns[0]], t[columns[1]]) for t in elsewhere], _DATA_COLOUR,
                   linewidth=0.6, alpha=0.35, zorder=1)
        add_curves(axes, [(t[columns[0]], t[columns[1]]) for t in here], "black", linewidth=0.9, alpha=0.8, zorder=3)
        order = [j for j in np.argsort(means[:, 0]) if weights[j] >= MIN_SHOWN_WEIGHT]
        for rank, j in enumerate(order):
            draw_ellipses(
                axes, means[j], covariances[j], component_colour(rank),
                alpha=0.15 + 0.45 * float(weights[j] / weights.max()),
                label=f"component {rank + 1}: weight {weights[j]:.2f}",
            )
        handles, labels = axes.get_legend_handles_labels()
        demonstrated = nearest is not None and abs(nearest - distance) < 1e-9
        if demonstrated:
            handles.append(Line2D([], [], color="black", linewidth=0.9))
            labels.append(f"demonstrations at {format_distance(distance)}")
        if elsewhere:
            handles.append(Line2D([], [], color=_DATA_COLOUR, linewidth=0.6))
            labels.append("demonstrations at other distances")
        hidden = k - len(order)
        if hidden:
            handles.append(Line2D([], [], linestyle="none"))
            labels.append(f"{hidden} more with weight < {MIN_SHOWN_WEIGHT:.0%} here (not drawn)")
        figure.legend(handles, labels, loc="outside right upper")
        axes.autoscale_view()
        axes.set_xlabel(axis_label(columns[0]))
        axes.set_ylabel(axis_label(columns[1]))
        axes.set_title(title or f"{k} Gaussian components at {format_distance(distance)} (1σ and 2σ ellipses)")
    return save(figure, out)


def _at_distance(dataset: Dataset, distance: float, context: str = "distance") -> Dataset:
    """The trajectories of ``dataset`` at one context value; :class:`InputError` listing the values if none."""
    dataset.require((context,))
    chosen = [t for t in dataset if abs(float(t[context][0]) - distance) < 1e-9]
    if not chosen:
        values = sorted({float(t[context][0]) for t in dataset})
        raise InputError(f"no trajectories at {context} = {distance:g} (values: {', '.join(f'{v:g}' for v in values)})")
    return dataset.replace(chosen)


def kmeans_em_for_dataset(
    dataset: Dataset,
    out: str | Path,
    *,
    ks: Sequence[int] = (2, 3, 4),
    distance: float | None = None,
    columns: tuple[str, str] = ("angle", "velocity"),
    seed: int = 0,
    effective_samples: str | float | None = "auto",
) -> SavedFigure:
    """:func:`kmeans_em_steps` on a dataset's (angle, velocity) samples, all or at one distance (m).

    ``effective_samples`` is the samples the BIC in the titles counts, as ``Model.fit`` takes it:
    "auto" (the measured share of densified samples), None (every sample) or a number.
    """
    from rlff.model.model import effective_sample_count

    if len(dataset) == 0:
        raise InputError("the dataset is empty: nothing to cluster")
    subset = dataset if distance is None else _at_distance(dataset, distance)
    effective = effective_sample_count(subset, np.ones(subset.n_samples), effective_samples)
    return kmeans_em_steps(subset.to_array(columns), out, ks=ks, columns=columns, seed=seed, effective_samples=effective)


def selection_for_dataset(
    dataset: Dataset,
    out: str | Path,
    *,
    max_components: int = 8,
    criterion: str = "bic",
    seed: int = 0,
    effective_samples: str | float | None = "auto",
) -> SavedFigure:
    """Choose K as ``rlff fit`` does and plot :func:`selection_curve`: ``Model.fit`` with K = 1 ..
    ``max_components`` on the throw's columns (:func:`rlff.model.model.throw_roles`), its
    defaults otherwise; ``effective_samples`` as in ``Model.fit`` ("auto", None or a number)."""
    from rlff.model.model import Model, throw_roles

    if criterion not in ("bic", "aic"):
        raise InputError(f"criterion must be 'bic' or 'aic', got {criterion!r}")
    inputs, outputs = throw_roles(dataset.columns)
    model = Model.fit(dataset, inputs=inputs, outputs=outputs, max_components=max_components, criterion=criterion,
                      seed=seed, effective_samples=effective_samples)
    return selection_curve(model.selection.table, out, criterion=criterion, n_samples=model.fit_info["n_samples"],
                           effective_samples=model.fit_info["effective_samples"])


def model_components(
    model: Any,
    dataset: Dataset,
    distance: float,
    out: str | Path,
    *,
    columns: tuple[str, str] = ("angle", "velocity"),
) -> SavedFigure:
    """:func:`components_at_distance` of a fitted model: its joint mixture conditioned on the
    context column (the basket distance) at ``distance``, shown on the ``columns`` plane.

    Parameters
    ----------
    model : rlff.model.Model
        A model with one context input (e.g. inputs angle, distance; output velocity).
    dataset : Dataset
        The data the model was fitted to.
    distance : float
        The context value (m).
    out : path
        File stem of the PNG and SVG.
    columns : (x, y) column names of the plane.
    """
    from rlff.model.regression import condition

    if len(model.context_names) != 1:
        raise InputError(
            f"the components figure needs a model with one context input, this one has {list(model.context_names)}"
        )
    (context,) = model.context_names
    missing = [c for c in columns if c not in model.columns]
    if missing:
        raise InputError(f"the model has no column {missing[0]!r} (columns: {', '.join(model.columns)})")
    names = list(model.columns)
    conditional = condition(
        model.mixture, [names.index(context)], [names.index(c) for c in columns], np.array([[float(distance)]])
    )
    return components_at_distance(
        conditional.weights[0], conditional.means[0], conditional.covariances, dataset, distance, out,
        columns=columns, context=context,
    )

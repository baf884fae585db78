"""The learnt model: a Gaussian mixture over named columns, its file, and the paths it generates.

:class:`Model` ties a :class:`rlff.model.mixture.GaussianMixture` to column names and roles: the
*inputs* (the first one is the path variable, ``angle``; the others are the *context*, such as the
basket ``distance``) and the *outputs* (``velocity``). It fits itself to a dataset (K by BIC),
saves to and loads from ``model.json`` (no pickle; validated on load), conditions on inputs
(GMR) and generates a path: for every angle the DMM's global mode at a fixed context.

Where the generated velocity is <= 0 (the thesis' demonstrations start and end at rest, and the
DMM may dip just below 0 there) the ``velocity`` column keeps the model's value, and the ``time``
column is computed from the velocity clipped at 0 in the direction of the path: a stop is crossed
at the floor speed of :func:`rlff.timing.time_along_path` (1 % of the peak speed), so
the time is always finite and increasing. Should the model give no forward velocity anywhere on
the path, the time uses |velocity| (or a unit speed if that is zero too), and a note says so.
"""

from __future__ import annotations

import json
import math
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rlff import __version__
from rlff.dataset import (
    ARM_JOINT_COLUMNS,
    ID_COLUMN,
    THROW_CONTEXT,
    THROW_INPUTS,
    THROW_OUTPUTS,
    Dataset,
    Trajectory,
    check_column_units,
    check_velocity_units,
    velocity_column,
)
from rlff.errors import InputError
from rlff.fileio import write_text
from rlff.jsonfile import read_json_object
from rlff.limits import (
    MAX_GENERATE_BYTES,
    MAX_GRID_POINTS,
    MAX_MAGNITUDE,
    as_names,
    check_count,
    check_distance,
    check_magnitudes,
)
from rlff.model.climb import starts_per_input
from rlff.model.donut import dmm_mode
from rlff.model.mixture import (
    GaussianMixture,
    check_samples,
    check_weights,
    frame_columns,
    information_criteria,
    is_frame,
    select_components,
)
from rlff.model.regression import Conditional, condition, predict
from rlff.timing import first_reversal, time_along_path
from rlff.wording import plural

FORMAT = "rlff-model"
VERSION = 1
#: Points of a generated path when no angles are given.
DEFAULT_POINTS = 100
#: Restarts of EM per candidate K (k-means++ seeds).
DEFAULT_N_INIT = 3
#: Peak speed below which a path does not move (output units).
_STILL = 1e-9
#: The other joints' outputs of a whole-arm model, in order: each position, then its velocity.
WHOLE_ARM_JOINT_OUTPUTS = tuple(c for joint in ARM_JOINT_COLUMNS for c in (joint, velocity_column(joint)))


def throw_roles(columns: Sequence[str]) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The inputs and outputs of a throwing model for a dataset with these columns.

    Inputs: ``angle`` (the elbow's, the phase) and every context column present (distance,
    bearing, height); outputs: ``velocity`` and every other joint's column present (shoulder,
    shoulder_velocity, wrist, wrist_velocity): the other joints' positions are outputs because
    the phase is the elbow's angle, not theirs. A one-joint dataset gives (angle, distance) ->
    velocity, the model of the thesis.
    """
    present = set(columns)
    inputs = ("angle", *(name for name in THROW_CONTEXT if name in present))
    outputs = ("velocity", *(name for name in WHOLE_ARM_JOINT_OUTPUTS if name in present))
    return inputs, outputs


def check_throw_context(columns: Sequence[str], where: str) -> None:
    """:class:`InputError` when ``columns`` hold none of the throw's context columns
    (:data:`rlff.dataset.THROW_CONTEXT`), ``where`` naming the data.

    :func:`throw_roles` would give the inputs ``angle`` alone, and the model the same throw for
    every basket; a model without context is still fitted when its inputs are named (``rlff fit
    --inputs angle``, ``Model.fit(inputs=("angle",))``).
    """
    if any(name in columns for name in THROW_CONTEXT):
        return
    raise InputError(
        f"{where}: no column 'distance', the basket distance each throw aimed at (m): without it the model "
        "gives the same throw for every basket; import the recordings with their baskets (`rlff data import "
        "RECORDINGS --manifest baskets.csv`, docs/capture.md) or add a distance column (--inputs angle fits a "
        "model without context on purpose)"
    )


def uncut_throws_note(dataset: Dataset, where: str) -> str | None:
    """A warning when throws of ``dataset`` (``where`` naming it) are not cut to one sweep of the
    elbow up to the release (``angle`` not strictly monotonic), None when all are or there is no
    ``angle``.

    The mixture's path variable is the angle: a recorded throw still holding its wind-up and
    follow-through passes the same angles two or three times, and the regression averages those
    slow phases into the throw (an uncleaned real recording gave a generated throw of 64 s at a
    peak of 1.2 rad/s). Fitting such data is not refused (a model of anything can be asked for).
    """
    if "angle" not in dataset.columns:
        return None
    reversals = ((trajectory.id, first_reversal(trajectory["angle"])) for trajectory in dataset)
    uncut = [(name, sample) for name, sample in reversals if sample is not None]
    if not uncut:
        return None
    name, sample = uncut[0]
    return (f"{where}: {len(uncut)} of {plural(len(dataset), 'throw')} are not cut to the elbow's one sweep up to "
            f"the release (their angle goes back; the first, {name!r}, at sample {sample}): the wind-up and "
            "follow-through of a recording are averaged into the model's throw; clean them first (rlff data "
            f"preprocess {where} --preset thesis -o clean.csv)")


@dataclass(frozen=True)
class ComponentSelection:
    """How K was chosen: the criterion and one row per candidate (see :func:`select_components`)."""

    criterion: str
    table: list[dict[str, Any]]

    @property
    def chosen(self) -> int:
        """K of the row with the lowest criterion."""
        return int(min(self.table, key=lambda row: row[self.criterion])["n_components"])


@dataclass(frozen=True)
class GeneratedPath:
    """A path generated by the model at a fixed context, one row per angle (T rows).

    Attributes
    ----------
    angle : ndarray of shape (T,)
        The path variable (first input; rad for throws).
    velocity : ndarray of shape (T,)
        DMM output of the first output column (rad/s for throws).
    pdf : ndarray of shape (T,)
        P_DMM at the chosen output.
    exploration : ndarray of shape (T,)
        Exploration factor eps used at each angle.
    gmr_mean, gmr_std : ndarray of shape (T,)
        GMR mean and standard deviation of the first output.
    time : ndarray of shape (T,)
        Cumulative time (s) along the path from the velocity clipped at 0 (see module notes).
    outputs : ndarray of shape (T, O)
        DMM output of every output column (``velocity`` is the first column).
    gmr_means, gmr_stds : ndarray of shape (T, O)
        GMR mean and standard deviation of every output column.
    density_traded : ndarray of shape (T,)
        Share of density given up for continuity (0 without it).
    input_name : str
    output_names : tuple of str
    context : dict of str to float
    notes : tuple of str
        What the user should know of how the time was made (clipped velocities).
    warnings : tuple of str
        What may make the path wrong: a context or the path variable outside the fitted range, a
        joint angle outside 0 to pi, a throw past the data that turns back (extrapolation).
    cautions : tuple of str
        The same in a few words each, for a figure's legend or title (``"extrapolated"``,
        ``"the regression turns back"``, ``"no arm takes this pose"``, ``"only distance 1.75 in
        the data"``), each once.
    """

    angle: np.ndarray
    velocity: np.ndarray
    pdf: np.ndarray
    exploration: np.ndarray
    gmr_mean: np.ndarray
    gmr_std: np.ndarray
    time: np.ndarray
    outputs: np.ndarray
    gmr_means: np.ndarray
    gmr_stds: np.ndarray
    density_traded: np.ndarray
    input_name: str = "angle"
    output_names: tuple[str, ...] = ("velocity",)
    context: dict[str, float] = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    warnings: tuple[str, ...] = ()
    cautions: tuple[str, ...] = ()

    def __len__(self) -> int:
        return self.angle.size

    def __repr__(self) -> str:
        """One line, as :class:`Model` and :class:`Dataset` print: the points, the path variable's
        span, the duration, every output at the release (the last point), the context and the
        cautions; not the arrays (the dataclass printed kilobytes of them)."""
        context = ", ".join(f"{name}={value:g}" for name, value in self.context.items()) or "none"
        cautions = f", cautions={list(self.cautions)}" if self.cautions else ""
        if not len(self):
            return f"GeneratedPath(0 points, context {context}{cautions})"
        release = ", ".join(f"{name}={value:.4g}" for name, value in zip(self.output_names, self.outputs[-1], strict=True))
        return (f"GeneratedPath({len(self)} points, {self.input_name} {self.angle[0]:.4g} to {self.angle[-1]:.4g}, "
                f"{self.time[-1]:.4g} s, release {release}, context {context}{cautions})")

    def to_frame(self) -> Any:
        """The path as a pandas DataFrame: the input, every output, time, pdf, exploration,
        gmr_mean, gmr_std (the first output's; ``gmr_mean_<name>``, ``gmr_std_<name>`` for every
        further output), density_traded, the context."""
        import pandas as pd

        columns: dict[str, np.ndarray] = {self.input_name: self.angle}
        for j, name in enumerate(self.output_names):
            columns[name] = self.outputs[:, j]
        if "velocity" not in columns:
            columns["velocity"] = self.velocity
        columns.update(
            time=self.time, pdf=self.pdf, exploration=self.exploration, gmr_mean=self.gmr_mean, gmr_std=self.gmr_std
        )
        for j, name in enumerate(self.output_names[1:], start=1):  # the first output's are gmr_mean, gmr_std
            columns[f"gmr_mean_{name}"] = self.gmr_means[:, j]
            columns[f"gmr_std_{name}"] = self.gmr_stds[:, j]
        columns["density_traded"] = self.density_traded
        for name, value in self.context.items():
            columns[name] = np.full(self.angle.size, value)
        return pd.DataFrame(columns)

    def write_csv(self, path: str | Path) -> None:
        """Write :meth:`to_frame`'s columns as CSV (round-trip float precision, atomically).

        A path with a non-finite value (a context far outside the data) is an
        :class:`InputError`, and nothing is written."""
        from rlff.csvtable import write_csv_columns

        frame = self.to_frame()
        columns = {name: frame[name].to_numpy() for name in frame.columns}
        context = ", ".join(f"{name}={value:g}" for name, value in self.context.items())
        check_magnitudes(f"the path generated at {context or 'no context'} ({path} not written)", columns)
        write_csv_columns(path, columns)


class Model:
    """A Gaussian mixture over named columns with input and output roles.

    Parameters
    ----------
    mixture : GaussianMixture
        Fitted on the columns ``inputs + outputs`` in that order.
    inputs, outputs : sequence of str
        Column names; the first input is the path variable, the other inputs the context.
    input_range : mapping of str to (float, float)
        Minimum and maximum of every input in the fitted data.
    selection : ComponentSelection, optional
        The BIC/AIC table when K was chosen automatically.
    fit_info : mapping, optional
        Fit settings and results kept in the file (seed, n_init, log-likelihood...).
    """

    def __init__(
        self,
        mixture: GaussianMixture,
        inputs: Sequence[str],
        outputs: Sequence[str],
        input_range: Mapping[str, tuple[float, float]],
        selection: ComponentSelection | None = None,
        fit_info: Mapping[str, Any] | None = None,
    ) -> None:
        self.inputs = tuple(inputs)
        self.outputs = tuple(outputs)
        _check_roles(self.inputs, self.outputs)
        names = getattr(mixture, "feature_names_in_", None)
        if names is not None and tuple(names) != self.columns:
            raise InputError(
                f"the mixture was fitted on columns {list(names)}, not the inputs and outputs "
                f"{list(self.columns)}"
            )
        # The mixture's columns are the inputs then the outputs: named so that the mixture and
        # rlff.condition / rlff.predict take a DataFrame's columns by name too.
        mixture.feature_names_in_ = np.array(self.columns, dtype=object)
        self.mixture = mixture
        self.input_range = {name: (float(lo), float(hi)) for name, (lo, hi) in input_range.items()}
        self.selection = selection
        self.fit_info = dict(fit_info or {})

    @property
    def columns(self) -> tuple[str, ...]:
        """Columns of the mixture, in order: the inputs, then the outputs."""
        return self.inputs + self.outputs

    @property
    def context_names(self) -> tuple[str, ...]:
        """Inputs other than the path variable."""
        return self.inputs[1:]

    @property
    def n_components(self) -> int:
        return int(self.mixture.weights_.size)

    def selection_notes(self) -> list[str]:
        """What a reader of a K chosen by the criterion should know: that K is the largest tried (a
        larger one may fit better; not when K is as large as the samples allow), and that the
        criterion rests on fewer (effective) samples than the chosen K's parameters (the data
        hardly decide K). A K given outright gets the last note only, in its own words: its
        components fit the noise of a few samples."""
        n_samples = self.fit_info.get("n_samples", math.inf)
        effective, parameters = self.fit_info.get("effective_samples"), self.mixture.n_parameters()
        counted, what = (effective, "effective samples") if effective else (n_samples, "samples")  # None: every one
        if self.selection is None:
            if counted >= parameters:
                return []
            return [f"the given K = {self.n_components} has {parameters} parameters, more than the {counted:.0f} "
                    f"{what} BIC counts: its components fit the noise of a few samples (fewer components, or "
                    "leave K to BIC: components=\"auto\", rlff fit -k auto)"]
        notes = []
        tried = max(int(row["n_components"]) for row in self.selection.table)
        # K at component_bound: no larger K to try
        if self.n_components == tried > 1 and (math.isinf(counted) or tried < component_bound(counted, None, len(self.columns))):
            notes.append(f"{self.selection.criterion.upper()} chose K = {self.n_components}, the largest tried: "
                         "a larger K may fit better (raise max_components, rlff fit --max-components)")
        fallen = _fallen_likelihood(self.selection.table, self.n_components)
        share = effective / n_samples if effective else 1.0  # ln L as the criterion counts it (rlff fit's table)
        if fallen is not None and _fall_may_have_decided(self.selection, self.n_components, *fallen, share):
            larger, smaller = fallen
            notes.append(f"ln L falls from K = {smaller['n_components']} to K = {larger['n_components']} "
                         f"({smaller['log_likelihood'] * share:.2f} to {larger['log_likelihood'] * share:.2f}), "
                         "though a mixture of "
                         f"{larger['n_components']} can fit as well as one of {smaller['n_components']}: EM's "
                         f"{self.fit_info.get('n_init', DEFAULT_N_INIT)} starts found a poorer optimum there, so "
                         f"K = {larger['n_components']} may have lost to K = {self.n_components} for its fit, not "
                         "its size (more starts: n_init, rlff fit --n-init)")
        if counted < parameters:
            notes.append(f"{self.selection.criterion.upper()} rests on {counted:.0f} {what}, fewer than "
                         f"the {parameters} parameters of K = {self.n_components}: the data hardly decide K (record "
                         "more throws, or fix K: components, rlff fit --components)")
        return notes

    def __repr__(self) -> str:
        return f"Model(K={self.n_components}, inputs={list(self.inputs)}, outputs={list(self.outputs)})"

    # -- fitting ---------------------------------------------------------------------------
    @classmethod
    def fit(
        cls,
        data: Dataset | np.ndarray | Any,
        *,
        columns: Sequence[str] | None = None,
        inputs: Sequence[str] = THROW_INPUTS,
        outputs: Sequence[str] = THROW_OUTPUTS,
        components: str | int = "auto",
        max_components: int = 8,
        criterion: str = "bic",
        seed: int | None = 0,
        sample_weight: np.ndarray | None = None,
        n_init: int = DEFAULT_N_INIT,
        reg_covar: float = 1e-6,
        context_resolution: str | float | None = "auto",
        effective_samples: str | float | None = "auto",
        progress: Callable[[int, int], None] | None = None,
    ) -> Model:
        """Fit a mixture to the input and output columns of a dataset or an array.

        Parameters
        ----------
        data : Dataset, pandas DataFrame or array of shape (N, C)
            Samples. A DataFrame gives its columns by name (the inputs and outputs must be among
            them; others are left out, with a warning for a ``trajectory`` column or throw
            metadata such as ``measured_share`` and ``cut_angle``, which only a Dataset carries
            into the fit). An array needs ``columns`` (C names) unless it holds exactly the
            inputs and outputs in that order. Anything else (a path, a dict, a list of
            trajectories) is an :class:`InputError` naming its type.
        columns : sequence of str, optional
            Names of the array's columns (not with a DataFrame, which names its own).
        inputs, outputs : sequence of str
            Column roles (default: angle, distance -> velocity).
        components : "auto" or int
            K, or "auto" to pick it by ``criterion`` over 1..``max_components``.
        max_components : int
            Largest K tried with "auto", capped at :func:`component_bound` (one component per
            D + 1 of the samples BIC counts, D the inputs and outputs).
        criterion : {"bic", "aic"}
        seed : int or None
            Seed of the k-means++ initialisations.
        sample_weight : array of shape (N,), optional
            Weight of every sample (weighted EM).
        n_init : int
            EM restarts per K; the best log-likelihood is kept.
        reg_covar : float
            Covariance regularisation on the standardised scale.
        context_resolution : "auto", float or None
            How finely the context inputs (every input but the first, e.g. the basket distance)
            are known, in their units: each is taken as uniform within +-resolution / 2 of its
            recorded value, so every component gets resolution^2 / 12 added to its variance in
            that input. Without it a component can sit on a single basket with almost no
            variance in the distance, a likelihood without bound (which BIC rewards) and nothing
            to say between the baskets. "auto": the median gap between the distinct recorded
            values of an input that takes few values (at most a tenth as many as there are
            samples), else 0; a number: that resolution for every context input; None or 0: none.
        effective_samples : "auto", float or None
            How many independent samples the data stand for, for BIC and AIC (see
            :func:`rlff.model.mixture.information_criteria`). "auto" (default): each trajectory's
            samples times its ``measured_share`` metadata (the share of measured samples, which
            ``densify`` records; 1 when absent), summed (weighted by ``sample_weight``), so that
            samples interpolated between measurements do not count as independent evidence for
            more components; data without that metadata count every sample. None: every sample
            (the count before densified data were told apart); or a number.
        progress : callable(done, total), optional
            Called after each candidate K.

        Returns
        -------
        Model

        Raises
        ------
        InputError
            Among others, a ``distance`` of 0 m or less or beyond the farthest basket
            (centimetres?) or a joint angle (``angle``, ``shoulder``, ``wrist``) beyond two turns
            (degrees?), as :func:`rlff.dataset.check_column_units` words them. A distance nearer
            than any basket is taken: a learning method labels a throw with where it came down.
        """
        inputs, outputs = as_names(inputs), as_names(outputs)
        _check_roles(inputs, outputs)
        names = inputs + outputs
        X = _columns_of(data, columns, names)
        # degrees and centimetres fitted as they were, and every path generated from them went wrong
        check_column_units({name: X[:, j] for j, name in enumerate(names)}, landings=True)
        _check_velocities(data, names)
        weights = check_weights(sample_weight, X.shape[0])
        _warn_constant(X, names)
        if 1 < X.shape[0] <= len(names):  # one sample is refused by the fit
            warnings.warn(
                f"{plural(X.shape[0], 'sample')} over {len(names)} columns, fewer than the {len(names) + 1} a "
                "covariance needs: the model's variances come from the regularisation alone (record more throws)",
                stacklevel=2,
            )
        resolution = {name: _resolution(X[:, j], context_resolution, name) for j, name in enumerate(inputs) if j > 0}
        column_variance = np.array([resolution.get(name, 0.0) ** 2 / 12.0 for name in names])
        settings = {"random_state": seed, "n_init": n_init, "reg_covar": reg_covar, "column_variance": column_variance}
        effective = effective_sample_count(data, weights, effective_samples)
        if components == "auto":
            if not isinstance(max_components, (int, np.integer)) or max_components < 1:
                raise InputError(f"max_components must be an integer >= 1, got {max_components!r}")
            largest = min(max_components, component_bound(X.shape[0], effective, len(names)))
            found = select_components(
                X, range(1, largest + 1), criterion=criterion, sample_weight=sample_weight,
                effective_samples=effective, progress=progress, **settings,
            )
            mixture = found.model
            selection = ComponentSelection(found.criterion, found.table)
        else:
            k = _component_count(components)
            mixture = GaussianMixture(k, **settings).fit(X, sample_weight=sample_weight)
            selection = None
            if progress is not None:
                progress(1, 1)
        log_likelihood, n = mixture._total_log_likelihood(X, weights)
        bic, aic = information_criteria(log_likelihood, mixture.n_parameters(), n, effective)
        fit_info = {
            "n_samples": int(X.shape[0]),
            "effective_samples": effective,
            "weighted": sample_weight is not None,
            "log_likelihood": log_likelihood,
            "bic": bic,
            "aic": aic,
            "converged": bool(mixture.converged_),
            "n_iter": int(mixture.n_iter_),
            "seed": seed,
            "n_init": n_init,
            "reg_covar": reg_covar,
            "context_resolution": resolution,
            "release": _typical_release(data, inputs[0]),
        }
        input_range = {name: (float(X[:, j].min()), float(X[:, j].max())) for j, name in enumerate(inputs)}
        return cls(mixture, inputs, outputs, input_range, selection, fit_info)

    # -- use ---------------------------------------------------------------------------------
    def condition(self, X_in: np.ndarray | Any) -> Conditional:
        """GMR of the outputs at inputs ``X_in``.

        ``X_in`` is an array of shape (N, I), columns in the order of ``inputs``, or a pandas
        DataFrame holding (at least) the input columns by name, in any order.
        """
        return condition(self.mixture, *self._roles(), self._inputs_array(X_in))

    def predict(self, X_in: np.ndarray | Any) -> tuple[np.ndarray, np.ndarray]:
        """GMR mean (N, O) and total covariance (N, O, O) of the outputs at inputs ``X_in``
        (as in :meth:`condition`), without the per-component arrays of :meth:`condition`."""
        return predict(self.mixture, *self._roles(), self._inputs_array(X_in))

    def _roles(self) -> tuple[range, range]:
        """Mixture columns of the inputs and of the outputs."""
        n_in = len(self.inputs)
        return range(n_in), range(n_in, n_in + len(self.outputs))

    def _inputs_array(self, X_in: np.ndarray | Any) -> np.ndarray:
        """``X_in`` as floats: a DataFrame's input columns by name, an array as it is (with one
        input a plain (N,) array is taken as (N, 1))."""
        if is_frame(X_in):
            return frame_columns(X_in, self.inputs, "inputs")
        X_in = np.asarray(X_in, dtype=float)
        return X_in[:, None] if X_in.ndim == 1 and len(self.inputs) == 1 else X_in

    def generate(
        self,
        context: Mapping[str, float],
        angles: np.ndarray | None = None,
        *,
        exploration: str | float | np.ndarray = "auto",
        exploration_scale: float = 1.0,
        continuity: bool | float = False,
        progress: Callable[[int, int], None] | None = None,
    ) -> GeneratedPath:
        """The DMM path at a fixed context: for every angle, the output of highest density.

        Parameters
        ----------
        context : mapping of str to float, or float
            A value for every input but the first (e.g. ``{"distance": 2.5}``); a ``distance``
            is the basket's in m, within :data:`rlff.limits.DISTANCE_RANGE` (0.3 to 20 m). A
            model of one context column also takes its value alone (``2.5``).
        angles : array of shape (T,), optional
            Values of the first input, monotonic; default 100 points from the data's range end
            farthest from the demonstrations' typical release to that release (``fit_info
            ["release"]``, see :func:`_typical_release`), or over the data's whole range when
            the model does not know it (fitted to an array, or an older model.json).
        exploration : "auto", float or array of shape (T,)
            See :func:`rlff.model.donut.dmm_mode`.
        exploration_scale : float
            Exploration scale sigma in output units (with "auto").
        continuity : bool or float
            Keep the output continuous along the path where modes are nearly equally high.
        progress : callable, optional
            ``progress(done, total)`` as the climb of a several-output model goes through the
            points (see :func:`rlff.model.donut.dmm_mode`).

        Returns
        -------
        GeneratedPath
        """
        values = _context_values(context, self.context_names, self.input_range)
        first = self.inputs[0]
        if angles is None:
            angles = self.default_path()
        angles = np.asarray(angles, dtype=float)
        if sum(length > 1 for length in angles.shape) > 1:  # reshaped, a (T, 2) had read as a zigzag path
            raise InputError(f"{first} values to generate at of shape {angles.shape}: give one array of shape (T,)")
        angles = angles.reshape(-1)
        if angles.size == 0:
            raise InputError(f"no {first} values to generate at")
        check_count(f"{first} values to generate at", angles.size, MAX_GRID_POINTS, "use fewer points")
        per_point = 8 * starts_per_input(self.n_components, len(self.outputs)) * (len(self.outputs) + 2)
        check_count(f"{first} values to generate at with this model ({self.n_components} components, "
                    f"{len(self.outputs)} outputs: about {per_point / 1000:.2g} kB a point)", angles.size,
                    MAX_GENERATE_BYTES // per_point, "use fewer points")
        if not np.all(np.isfinite(angles)):
            raise InputError(f"{first} values hold NaN or inf")
        # degrees had been generated at as a far extrapolation (velocities of 193 and a caution)
        check_column_units({first: angles}, lambda name: f"{name} values to generate at")
        X_in = np.column_stack([angles, *(np.full(angles.size, v) for v in values)])
        conditional = self.condition(X_in)
        mode = dmm_mode(conditional, exploration, exploration_scale, continuity, progress=progress)
        # (caution, warning): a few words for a figure beside each full sentence
        cautioned = [
            ("extrapolated", f"{name} = {value:g} is outside the fitted range [{lo:g}, {hi:g}]: extrapolating")
            if hi > lo else
            (f"only {name} {lo:g} in the data",
             f"{name} = {value:g}: every demonstration had {name} {lo:g}, so the model cannot tell one {name} "
             f"from another and gives the throw for {lo:g}")
            for name, value in zip(self.context_names, values, strict=True)
            for lo, hi in [self.input_range[name]]
            if not lo <= value <= hi
        ]
        lo, hi = self.input_range[first]
        if angles.min() < lo or angles.max() > hi:
            cautioned.append(("extrapolated", f"{first} values {angles.min():g} to {angles.max():g} leave the fitted "
                                              f"range [{lo:g}, {hi:g}]: extrapolating"))
        cautioned.extend(("the regression turns back", warning)
                         for warning in self._speed_reversal(angles, values, conditional.mean[:, 0]))
        cautioned.extend(("no arm takes this pose", warning) for warning in _impossible_angles(mode.output, self.outputs))
        if first == "angle" and (angles.min() < lo or angles.max() > hi):
            # the elbow's grid itself, past its data (--grid angle=0.7:10:100 had only "extrapolating")
            cautioned.extend(("no arm takes this pose", warning) for warning in _impossible_angles(angles[:, None], [first]))
        warnings = [warning for _, warning in cautioned]
        velocity = mode.output[:, 0]
        time, notes = _path_time(angles, velocity, self.outputs[0])
        notes.extend(_steps(angles, velocity, first, self.outputs[0]))
        std = np.sqrt(np.maximum(conditional.variance, 0.0))
        return GeneratedPath(
            angle=angles,
            velocity=velocity,
            pdf=mode.pdf,
            exploration=mode.exploration,
            gmr_mean=conditional.mean[:, 0],
            gmr_std=std[:, 0],
            time=time,
            outputs=mode.output,
            gmr_means=conditional.mean,
            gmr_stds=std,
            density_traded=mode.density_traded,
            input_name=first,
            output_names=self.outputs,
            context=dict(zip(self.context_names, values, strict=True)),
            notes=tuple(notes),
            warnings=tuple(warnings),
            cautions=tuple(dict.fromkeys(caution for caution, _ in cautioned)),
        )

    def _speed_reversal(self, angles: np.ndarray, values: Sequence[float], mean: np.ndarray) -> list[str]:
        """A note when a distance beyond the fitted range gets a slower throw than the range's
        edge (or, below it, a faster one): the GMR mean (``mean``, shape (T,), of the first output
        along ``angles``) past the data follows the edge component's local slope, which in noisy
        demonstrations may point the wrong way, so the throw lands on the wrong side of the
        edge's. Compared by the peak of the first output's magnitude (its speed)."""
        if "distance" not in self.context_names:
            return []
        index = self.context_names.index("distance")
        value = float(values[index])
        lo, hi = self.input_range["distance"]
        if lo <= value <= hi:
            return []
        edge = hi if value > hi else lo
        edge_values = [edge if i == index else v for i, v in enumerate(values)]
        X_edge = np.column_stack([angles, *(np.full(angles.size, v) for v in edge_values)])
        peak, edge_peak = float(np.max(np.abs(mean))), float(np.max(np.abs(self.predict(X_edge)[0][:, 0])))
        farther = value > hi
        if (peak < 0.98 * edge_peak) if farther else (peak > 1.02 * edge_peak):
            return [f"the regression's (GMR mean) {self.outputs[0]} for distance {value:.3g} peaks at {peak:.3g}, "
                    f"{'below' if farther else 'above'} the {edge_peak:.3g} for {edge:.3g} (the fitted range's "
                    f"{'top' if farther else 'bottom'}): past the data the regression turns back, and this throw "
                    f"would land {'shorter' if farther else 'farther'} than the one for {edge:.3g}; ask within "
                    f"[{lo:.3g}, {hi:.3g}], or let rlff learn calibrate the speed for this distance"]
        return []

    def default_path(self) -> np.ndarray:
        """The default values (T,) of the path variable :meth:`generate` uses: up to the release.

        From the end of the fitted range farthest from the demonstrations' typical release to
        that release, :data:`DEFAULT_POINTS` points (the whole range without a known release):
        a generated throw then ends where the demonstrations let go of the ball, not beyond.
        """
        lo, hi = self.input_range[self.inputs[0]]
        release = self.fit_info.get("release") or {}
        end = release.get("value")
        if not isinstance(end, int | float) or not lo < end <= hi or isinstance(end, bool):
            return np.linspace(lo, hi, DEFAULT_POINTS)
        start = lo if end - lo >= hi - end else hi
        return np.linspace(start, float(end), DEFAULT_POINTS)

    # -- persistence -------------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """The model.json document (see docs/models.md)."""
        mixture = self.mixture
        return {
            "format": FORMAT,
            "version": VERSION,
            "columns": list(self.columns),
            "inputs": list(self.inputs),
            "outputs": list(self.outputs),
            "weights": mixture.weights_.tolist(),
            "means": mixture.means_.tolist(),
            "covariances": mixture.covariances_.tolist(),
            "scale": {"center": mixture.center_.tolist(), "std": mixture.scale_.tolist()},
            "input_range": {name: list(bounds) for name, bounds in self.input_range.items()},
            "selection": None
            if self.selection is None
            else {"criterion": self.selection.criterion, "table": self.selection.table},
            "fit": self.fit_info,
            "software": {"rlff": __version__},
        }

    def save(self, path: str | Path) -> None:
        """Write ``model.json`` (floats at full precision: loading gives the same model)."""
        write_text(path, json.dumps(self.to_dict(), indent=1, allow_nan=False) + "\n")

    @classmethod
    def from_dict(cls, document: Any, source: str = "model") -> Model:
        """A model from a model.json document; :class:`InputError` naming the bad field."""
        return _parse(document, source)

    @classmethod
    def load(cls, path: str | Path) -> Model:
        """Read and validate ``model.json``; a dataset given in its place is said to be one, and any
        other file that is no JSON object what it is (an attempts log, a recording, a path)."""
        try:
            document = read_json_object(path)
        except InputError:
            path = Path(path)
            if _looks_like_dataset(path):
                raise InputError(f"{path}: a dataset, not a model (model.json): fit one first, "
                                 f"rlff fit {path} -o model.json") from None
            if (kind := _other_kind(path)) is not None:
                raise InputError(f"{path} is {kind}, not a model (model.json, which rlff fit writes)") from None
            raise
        return _parse(document, str(path))


def _looks_like_dataset(path: Path) -> bool:
    """Whether ``path``, which does not hold a JSON object, is a dataset file: a Parquet or NPZ file
    by its extension (:data:`rlff.formats.FORMATS`), a long-format table or a thesis matrix by its
    header (:func:`rlff.kinds.csv_kind`). (A generated path's CSV and a skeleton recording's text
    had been called datasets by their extension alone, and told to be fitted, which fit refuses.)"""
    from rlff.formats import FORMATS
    from rlff.kinds import DATASET, csv_kind, header_names

    if not path.is_file():  # missing: read_json_object's "no such file" says it
        return False
    if path.suffix.lower() in FORMATS["npz"] + FORMATS["parquet"]:
        return True
    return csv_kind(header_names(path)) == DATASET


def _other_kind(path: Path) -> str | None:
    """What ``path``, a file that holds no JSON object, is instead (:func:`rlff.kinds.file_kind`:
    an attempts log, text with its first line quoted, ...), or None where it looks like JSON
    (a damaged model.json: the JSON error says where) or is no file."""
    from rlff.kinds import file_kind

    if not path.is_file():
        return None
    try:
        with path.open("rb") as file:
            if file.read(64).lstrip(b"\xef\xbb\xbf").lstrip().startswith((b"{", b"[")) and path.suffix != ".jsonl":
                return None
    except OSError:
        return None
    return file_kind(path)


# -- helpers -------------------------------------------------------------------------------------


#: A step of the first output between two neighbouring points larger than this share of its range
#: along the path is said (a mode of the DMM ends, and the path goes on from another).
STEP_SHARE = 0.1


def _steps(angles: np.ndarray, output: np.ndarray, input_name: str, output_name: str) -> list[str]:
    """A note on the largest step of ``output`` (T,) between neighbouring points of ``angles``
    (T,) when it is above :data:`STEP_SHARE` of the output's range along the path: where the mode
    followed ends (or the next is more than the continuity's 5 % higher) the path jumps to another,
    and a robot cannot follow a step; the robot step plans a smooth swing to the release."""
    if output.size < 3:
        return []
    steps = np.abs(np.diff(output))
    i = int(np.argmax(steps))
    large = int(np.count_nonzero(steps > STEP_SHARE * float(np.ptp(output))))
    if not large:
        return []
    others = f" (and {large - 1} more step{'s' if large > 2 else ''} above a tenth of its range)" if large > 1 else ""
    return [f"{output_name} steps by {steps[i]:.3g} between {input_name} {angles[i]:.4g} and {angles[i + 1]:.4g} "
            f"({output[i]:.4g} -> {output[i + 1]:.4g}){others}: the density's mode followed ends there and the path "
            "goes on from another (rlff robot export plans a smooth swing to the release)"]


#: How far (rad) a generated joint angle may pass 0 or pi before it is said to be impossible: the
#: regression smooths a wrist held straight (about pi) a little past it inside the data.
ANGLE_SLACK = 0.05


def _impossible_angles(outputs: np.ndarray, names: Sequence[str]) -> list[str]:
    """A warning for each joint angle (``angle``, the elbow's, ``shoulder``, ``wrist``: angles
    between two limbs, 0 to pi) among ``names`` that leaves 0 to pi by more than
    :data:`ANGLE_SLACK` somewhere in ``outputs`` (T, O): no arm takes that pose, so the model was
    asked far past its data."""
    found = []
    for j, name in enumerate(names):
        if name == "angle" or name in ARM_JOINT_COLUMNS:
            low, high = float(outputs[:, j].min()), float(outputs[:, j].max())
            if low < -ANGLE_SLACK or high > math.pi + ANGLE_SLACK:
                found.append(f"{name} goes {low:.3g} to {high:.3g} rad, outside 0 to pi (the angle between two "
                             "limbs): no arm takes that pose; the model is asked far past its data")
    return found


def compile_kernels() -> None:
    """Compile the compiled loops of GMR and the DMM mode (one output and several), or load them
    from numba's cache.

    The first call after installing compiles them (a minute and a half of CPU: 86-90 s, 2.2 min
    of wall time, measured on a cold ``NUMBA_CACHE_DIR`` on a shared 2-core machine under a load
    average of 4-6) and stores the machine code beside the sources; later processes load it in
    well under a second. ``scripts/setup.sh`` calls this
    so that the first ``rlff`` command does not wait for the compiler.
    """
    mixture = GaussianMixture.from_parameters(np.array([0.5, 0.5]), np.array([[0.0, 0.0], [1.0, 2.0]]), np.array([np.eye(2)] * 2))
    dmm_mode(condition(mixture, [0], [1], np.array([[0.5]])))
    several = GaussianMixture.from_parameters(  # the several-output kernel (whole-arm models)
        np.array([0.5, 0.5]), np.array([[0.0, 0.0, 0.0], [1.0, 2.0, 1.0]]), np.array([np.eye(3)] * 2)
    )
    dmm_mode(condition(several, [0], [1, 2], np.array([[0.5]])))


def _release_of(trajectory, column: str) -> tuple[float, str]:
    """One demonstration's release value of ``column`` and where it comes from.

    In order: ``cut_angle`` metadata (the preprocessing cut the throw at its release), the value
    at the ``release_time`` metadata along the ``time`` column, ``release_angle`` metadata
    within the samples, else the last sample (a segmented throw ends at its release).
    """
    values = trajectory[column]
    meta = trajectory.meta
    if column == "angle" and isinstance(meta.get("cut_angle"), int | float):
        return float(meta["cut_angle"]), "cut_angle"
    release_time = meta.get("release_time")
    if isinstance(release_time, int | float) and "time" in trajectory.columns:
        time = trajectory["time"]
        if values.size > 1 and np.all(np.diff(time) > 0) and time[0] <= release_time <= time[-1]:
            return float(np.interp(release_time, time, values)), "release_time"
    release_angle = meta.get("release_angle")
    if column == "angle" and isinstance(release_angle, int | float) and values.min() <= release_angle <= values.max():
        return float(release_angle), "release_angle"
    return float(values[-1]), "last sample"


def _typical_release(data: Dataset | np.ndarray, column: str) -> dict[str, Any] | None:
    """The demonstrations' typical release of the path variable: the median over the throws.

    ``{"value": median, "sources": {source: count}}`` (see :func:`_release_of`), or None for an
    array (no throws to tell apart). The median, not the mean: a few throws segmented late (a
    follow-through kept) must not carry the generated throw past where most let go.
    """
    if not isinstance(data, Dataset) or len(data) == 0:
        return None
    found = [_release_of(trajectory, column) for trajectory in data]
    sources: dict[str, int] = {}
    for _, source in found:
        sources[source] = sources.get(source, 0) + 1
    return {"value": float(np.median([value for value, _ in found])), "sources": sources}


#: How far (in ln L) a larger K's fit may fall below a smaller K's before :meth:`Model.selection_notes`
#: says so: half a unit of BIC, below which the fall cannot change a choice by the criterion.
LIKELIHOOD_FALL = 0.25


def _fallen_likelihood(table: Sequence[dict[str, Any]], chosen: int) -> tuple[dict, dict] | None:
    """The first row of a K above ``chosen`` whose ln L is more than :data:`LIKELIHOOD_FALL`
    below that of a smaller K (EM short of the larger mixture's best fit), and that smaller K's
    row (the best ln L below it); None when no such K."""
    best: dict | None = None
    for row in sorted(table, key=lambda r: r["n_components"]):
        if (best is not None and row["n_components"] > chosen
                and row["log_likelihood"] < best["log_likelihood"] - LIKELIHOOD_FALL):
            return row, best
        if best is None or row["log_likelihood"] > best["log_likelihood"]:
            best = row
    return None


def _fall_may_have_decided(selection: ComponentSelection, chosen: int, larger: dict, smaller: dict,
                           share: float) -> bool:
    """Whether the ``larger`` K's poor fit (its ln L below the ``smaller`` K's) may have decided the
    choice of the ``chosen`` K: it fell below the chosen K's own ln L, or, fitted as well as the
    smaller K, it would have beaten the chosen one on the criterion. A fall between two Ks that
    lost anyway (K = 20 to 21, when BIC chose K = 1 far below both) decided nothing."""
    if smaller["n_components"] == chosen:
        return True
    criterion = selection.criterion
    chosen_row = next(row for row in selection.table if row["n_components"] == chosen)
    better = larger[criterion] - 2.0 * share * (smaller["log_likelihood"] - larger["log_likelihood"])
    return better < chosen_row[criterion]


def component_bound(n_samples: float, effective_samples: float | None, n_features: int) -> int:
    """The most components ``components="auto"`` tries whatever ``max_components`` says: one per
    ``n_features`` + 1 of the samples BIC counts (``effective_samples``, else all ``n_samples``),
    at least 1. A full covariance over D columns needs D + 1 samples not to be singular: a
    component with fewer stands on the regularisation alone, a likelihood BIC rewards and a
    predicted variance of nothing (until 2026-12-07 the bound was one component per sample: 3
    samples of angle, distance and velocity got K = 3 and a variance of 7e-7). With more
    components than that the fits of large K also took hours."""
    counted = n_samples if effective_samples is None else effective_samples
    return max(1, math.floor(counted / (n_features + 1)))


def effective_sample_count(data: Dataset | np.ndarray, weights: np.ndarray, setting: str | float | None) -> float | None:
    """The number of independent samples BIC counts, see ``Model.fit(effective_samples=)``;
    None for every sample. ``weights`` (N,) are the samples' weights (ones when unweighted)."""
    if setting is None:
        return None
    if isinstance(setting, str):
        if setting != "auto":
            raise InputError(f"effective_samples must be 'auto', a number or None, got {setting!r}")
        if not isinstance(data, Dataset) or not any("measured_share" in t.meta for t in data):
            return None
        share = np.concatenate([np.full(len(t), float(t.meta.get("measured_share", 1.0))) for t in data])
        return float(weights @ share)
    return float(setting)


def _resolution(values: np.ndarray, setting: str | float | None, name: str) -> float:
    """The resolution (input units) of one context input, see ``Model.fit(context_resolution=)``."""
    if setting is None:
        return 0.0
    if isinstance(setting, str):
        if setting != "auto":
            raise InputError(f"context_resolution must be 'auto', a number >= 0 or None, got {setting!r}")
        distinct = np.unique(values)
        if distinct.size < 2 or distinct.size > values.size / 10:
            return 0.0
        return float(np.median(np.diff(distinct)))  # the grid's step, even with a few values off it
    resolution = float(setting)
    if not (math.isfinite(resolution) and resolution >= 0):
        raise InputError(f"context_resolution for {name} must be a number >= 0, got {setting!r}")
    return resolution


def _check_roles(inputs: tuple[str, ...], outputs: tuple[str, ...]) -> None:
    if not inputs:
        raise InputError("a model needs at least one input column")
    if not outputs:
        raise InputError("a model needs at least one output column")
    names = inputs + outputs
    for name in names:
        if not isinstance(name, str) or not name:
            raise InputError(f"column names must be non-empty strings, got {name!r}")
    repeated = sorted({name for name in names if names.count(name) > 1})
    if repeated:
        raise InputError(f"column {repeated[0]!r} is given more than once among the inputs and outputs")


def _columns_of(data: Dataset | np.ndarray | Any, columns: Sequence[str] | None, names: tuple[str, ...]) -> np.ndarray:
    """The samples (N, len(names)) of the named columns."""
    if isinstance(data, Dataset):
        if len(data) == 0:
            raise InputError("the dataset is empty: no trajectories")
        return check_samples(data.to_array(names), "data")
    if is_frame(data):
        if columns is not None:
            raise InputError("columns= names the columns of an array; a DataFrame names its own")
        _warn_frame_metadata(data)
        return frame_columns(data, names, "data")
    if isinstance(data, (str, Path)):
        raise InputError(f"data is the path {str(data)!r}, not the samples: read it first, "
                         f"Model.fit(rlff.formats.read_dataset({str(data)!r}))")
    if isinstance(data, (list, tuple)) and data and all(isinstance(t, Trajectory) for t in data):
        raise InputError(f"data is a {type(data).__name__} of Trajectory: make a Dataset of them, "
                         "Model.fit(rlff.Dataset(trajectories))")
    array = check_samples(data, "data", FIT_DATA)
    if columns is None:
        if array.shape[1] != len(names):
            raise InputError(
                f"the array has {array.shape[1]} columns: name them with columns= "
                f"(inputs and outputs are {list(names)})"
            )
        return array
    columns = tuple(columns)
    if len(columns) != array.shape[1]:
        raise InputError(f"{len(columns)} column names for an array of {array.shape[1]} columns")
    missing = [name for name in names if name not in columns]
    if missing:
        raise InputError(f"no column {missing[0]!r} in the data (columns: {', '.join(columns)})")
    return array[:, [columns.index(name) for name in names]]


def _check_velocities(data: Dataset | np.ndarray | Any, names: tuple[str, ...]) -> None:
    """:func:`rlff.dataset.check_velocity_units` of the velocity columns among ``names`` (the
    inputs and outputs fitted), over the throws of ``data``: a Dataset's, or a DataFrame's by its
    ``trajectory`` column (the time and the angle, where it holds them, to integrate the elbow's
    velocity over). An array, or a frame without throws, tells none apart: not checked."""
    if isinstance(data, Dataset):
        columns = [*names, *(name for name in ("time", "angle") if name in data.columns and name not in names)]
        check_velocity_units(data, columns)
    elif is_frame(data) and ID_COLUMN in data.columns:
        columns = [*names, *(name for name in ("time", "angle") if name in data.columns and name not in names
                             and data[name].dtype.kind in "fiu")]
        throws = [{name: group[name].to_numpy(float) for name in columns}
                  for _, group in data.groupby(ID_COLUMN, sort=False)]
        check_velocity_units(throws, columns)


#: What Model.fit takes, for errors.
FIT_DATA = ("a Dataset (rlff.formats.read_dataset reads one from a file), a pandas DataFrame or a numeric "
            "array of shape (N, C)")
#: Per-trajectory metadata the fit reads from a Dataset (effective samples, the release).
_FIT_METADATA = ("measured_share", "cut_angle", "release_time", "release_angle")


def _warn_frame_metadata(frame: Any) -> None:
    """Warn when a DataFrame looks like a dataset's samples (a ``trajectory`` column or the
    metadata :data:`_FIT_METADATA`): a frame is read as rows, without its throws' metadata, so BIC
    counts every sample and the release is unknown (a model of clean.csv read by pandas chose
    another K and generated throws past the release)."""
    lost = [name for name in (ID_COLUMN, *_FIT_METADATA) if name in frame.columns]
    if lost:
        warnings.warn(
            f"the DataFrame's columns {', '.join(lost)} are not read: a DataFrame is rows, not throws with "
            "their metadata, so BIC counts every sample (no measured_share) and the release is unknown "
            "(fit_info['release'] None, generate runs over the whole angle range): fit a Dataset, "
            "Model.fit(rlff.formats.read_dataset(path))",
            stacklevel=4,
        )


def _warn_constant(X: np.ndarray, names: tuple[str, ...]) -> None:
    for j, name in enumerate(names):
        if np.ptp(X[:, j]) <= 1e-12 * max(1.0, float(np.abs(X[:, j]).max())):
            warnings.warn(
                f"column {name!r} is constant ({X[0, j]:g}): its variance comes from the regularisation "
                "alone, so the model cannot tell its values apart",
                stacklevel=3,
            )


def _component_count(components: Any) -> int:
    if isinstance(components, (int, np.integer)) and not isinstance(components, bool):
        k = int(components)
    elif isinstance(components, str) and components.strip().isdigit():
        k = int(components)
    else:
        raise InputError(f"components must be 'auto' or an integer >= 1, got {components!r}")
    if k < 1:
        raise InputError(f"components must be 'auto' or an integer >= 1, got {components!r}")
    return k


def _context_values(
    context: Mapping[str, float], names: tuple[str, ...], ranges: Mapping[str, tuple[float, float]]
) -> list[float]:
    """The context's values in ``names``' order; :class:`InputError` for an unknown, missing (with
    the model's demonstrated range of it) or non-finite value, or a ``distance`` outside the basket
    distances rlff takes (:data:`rlff.limits.DISTANCE_RANGE`, m), as ``rlff generate`` refuses it.
    A number alone is the value of a model's one context column; anything else that is no mapping
    is refused saying what a context is (``model.generate(2.0)`` had been a TypeError)."""
    if not isinstance(context, Mapping):
        if isinstance(context, int | float | np.integer | np.floating) and not isinstance(context, bool) \
                and len(names) == 1:
            context = {names[0]: context}
        else:
            example = ", ".join(f"{name!r}: {sum(ranges[name]) / 2:.3g}" for name in names)
            raise InputError(f"the context is a mapping of the model's context columns to their values, e.g. "
                             f"{{{example}}}, got {type(context).__name__} {context!r}"
                             + ("" if len(names) != 1 else f" (or the {names[0]} alone, a number)"))
    unknown = [name for name in context if name not in names]
    if unknown:
        expected = ", ".join(names) if names else "none"
        raise InputError(f"unknown context {unknown[0]!r} (the model's context: {expected})")
    missing = [name for name in names if name not in context]
    if missing:  # every one named at once, not one per try

        def example(name: str) -> str:
            lo, hi = ranges[name]
            return f"{name}={(lo + hi) / 2:.3g} (demonstrated: {lo:g} to {hi:g})"

        raise InputError(f"missing context {', '.join(map(repr, missing))}: give "
                         f"{' and '.join(map(example, missing))}")
    values = []
    for name in names:
        try:
            value = float(context[name])
        except (TypeError, ValueError):
            raise InputError(f"context {name!r} must be a number, got {context[name]!r}") from None
        if not math.isfinite(value):
            raise InputError(f"context {name!r} must be finite, got {value}")
        if name == "distance":  # the throwing task's basket, in m: 175 (cm) gave a path of -285 rad/s
            value = check_distance("context 'distance'", value)
        values.append(value)
    return values


def _path_time(angles: np.ndarray, velocity: np.ndarray, output: str) -> tuple[np.ndarray, list[str]]:
    """Time along the path (T,) from the velocity clipped at 0, and notes on what was done."""
    if angles.size == 1:
        return np.zeros(1), []
    direction = math.copysign(1.0, float(angles[-1] - angles[0]))
    forward = direction * velocity
    notes = []
    clipped = int(np.count_nonzero(forward <= 0))
    if clipped:
        notes.append(
            f"{clipped} of {angles.size} points have {output} <= 0 along the path: "
            "timed as rest (time uses the velocity clipped at 0)"
        )
    speed = np.maximum(forward, 0.0)
    if speed.max() <= _STILL:
        speed = np.abs(velocity)
        notes.append(f"the model gives no forward {output} along this path: time uses |{output}|")
        if speed.max() <= _STILL:
            speed = np.ones_like(velocity)
            notes.append(f"{output} is zero all along: time assumes a unit speed")
    return time_along_path(angles, direction * speed, min_speed=0.01 * float(speed.max())), notes


# -- model.json validation ---------------------------------------------------------------------


def _parse(document: Any, source: str) -> Model:
    def fail(field_name: str, problem: str) -> InputError:
        return InputError(f"{source}: field {field_name!r} {problem}")

    if not isinstance(document, dict):
        raise InputError(f"{source}: not a model.json document (expected a JSON object)")
    if document.get("format") != FORMAT:
        raise fail("format", f"must be {FORMAT!r}, got {document.get('format')!r}")
    version = document.get("version")
    if version != VERSION:
        raise fail("version", f"is {version!r}; this rlff reads version {VERSION}")
    names = {}
    for key in ("columns", "inputs", "outputs"):
        value = document.get(key)
        if not isinstance(value, list) or not value or not all(isinstance(v, str) and v for v in value):
            raise fail(key, "must be a non-empty list of column names")
        names[key] = tuple(value)
    try:
        _check_roles(names["inputs"], names["outputs"])
    except InputError as exc:
        raise fail("inputs", f"and 'outputs' are inconsistent: {exc}") from None
    if names["columns"] != names["inputs"] + names["outputs"]:
        raise fail("columns", "must be the inputs followed by the outputs")
    d = len(names["columns"])

    def array(key: str, shape: tuple[int, ...], value: Any = None, bound: float = MAX_MAGNITUDE) -> np.ndarray:
        raw = document.get(key) if value is None else value
        try:
            result = np.asarray(raw, dtype=float)
        except (TypeError, ValueError):
            raise fail(key, "must hold numbers only") from None
        if raw is None or result.shape != shape:
            raise fail(key, f"must have shape {list(shape)}, got {list(result.shape) if raw is not None else 'nothing'}")
        if not np.all(np.isfinite(result)):
            raise fail(key, "holds a non-finite number")
        if np.any(np.abs(result) > bound):  # data values are within ±MAX_MAGNITUDE, so are these
            raise fail(key, f"holds {result.flat[int(np.argmax(np.abs(result)))]:g}, beyond ±{bound:g}")
        return result

    weights_raw = document.get("weights")
    if not isinstance(weights_raw, list) or not weights_raw:
        raise fail("weights", "must be a non-empty list")
    k = len(weights_raw)
    weights = array("weights", (k,))
    if np.any(weights < 0) or abs(weights.sum() - 1.0) > 1e-6:
        raise fail("weights", f"must be >= 0 and sum to 1 (sum {weights.sum():.9g})")
    means = array("means", (k, d))
    covariances = array("covariances", (k, d, d), bound=MAX_MAGNITUDE**2)
    for j, covariance in enumerate(covariances):
        if not np.allclose(covariance, covariance.T, rtol=1e-9, atol=1e-12 * np.abs(covariance).max()):
            raise fail(f"covariances[{j}]", "is not symmetric")
        try:
            np.linalg.cholesky(covariance)
        except np.linalg.LinAlgError:
            raise fail(f"covariances[{j}]", "is not positive definite") from None
    scale = document.get("scale")
    if not isinstance(scale, dict):
        raise fail("scale", "must be an object with 'center' and 'std'")
    center = array("scale.center", (d,), scale.get("center", []))
    std = array("scale.std", (d,), scale.get("std", []))
    if np.any(std <= 0):
        raise fail("scale.std", "must be > 0")
    ranges = document.get("input_range")
    if not isinstance(ranges, dict) or set(ranges) != set(names["inputs"]):
        raise fail("input_range", f"must give [min, max] for each input {list(names['inputs'])}")
    input_range = {}
    for name in names["inputs"]:
        lo, hi = array(f"input_range.{name}", (2,), ranges[name])
        if lo > hi:
            raise fail(f"input_range.{name}", f"has min {lo} > max {hi}")
        input_range[name] = (lo, hi)
    selection = document.get("selection")
    if selection is not None:
        if not isinstance(selection, dict) or selection.get("criterion") not in ("bic", "aic"):
            raise fail("selection", "must be null or hold 'criterion' (bic or aic) and 'table'")
        table = selection.get("table")
        needed = ("n_components", selection["criterion"])
        if not isinstance(table, list) or not table or not all(
            isinstance(row, dict) and all(isinstance(row.get(key), (int, float)) for key in needed) for row in table
        ):
            raise fail("selection.table", "must be a list of rows with n_components and the criterion")
        selection = ComponentSelection(selection["criterion"], table)
    fit_info = document.get("fit", {})
    if not isinstance(fit_info, dict):
        raise fail("fit", "must be an object")
    try:
        mixture = GaussianMixture.from_parameters(weights, means, covariances, center=center, scale=std)
    except InputError as exc:
        raise InputError(f"{source}: {exc}") from None
    return Model(mixture, names["inputs"], names["outputs"], input_range, selection, fit_info)

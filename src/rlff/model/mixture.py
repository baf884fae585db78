"""Gaussian Mixture Models with full covariances: k-means++ initialisation, EM, BIC/AIC selection.

Fitting happens on standardised columns (mean 0, standard deviation 1) for numerical health;
every attribute the user sees is in the data's units. ``reg_covar`` is added to the diagonal of
every covariance on the standardised scale, so it is relative to each column's variance.

Why EM is written here rather than taken from scikit-learn: the model needs weighted EM (the
learning loop weights the robot's own attempts above the human demonstrations), fitting on
standardised columns with results in data units, and a fast E/M step. Both steps go through one
matrix of quadratic features ``[1, z, z_i z_j]`` per sample: the log-density of every component
is one matrix product with per-component coefficients, and the sufficient statistics of the M
step are one matrix product with the responsibilities. No (N, K, D) temporary is ever built.
"""

from __future__ import annotations

import functools
import inspect
import math
import sys
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from threadpoolctl import ThreadpoolController

from rlff.errors import InputError
from rlff.limits import MAX_MAGNITUDE

_LOG_2PI = math.log(2.0 * math.pi)
_INITS = ("kmeans++", "random")
#: Relative tolerance of k-means on the standardised scale (as scikit-learn's KMeans).
_KMEANS_TOL = 1e-4
_KMEANS_MAX_ITER = 300
#: k-means++ seedings tried per initialisation, and the most samples they are refined on.
_KMEANS_TRIALS = 3
_KMEANS_SUBSET = 20_000


# -- validation --------------------------------------------------------------------------------


def check_samples(X: Any, name: str = "X", accepted: str = "a numeric array") -> np.ndarray:
    """``X`` as a finite float array of shape (N, D) with N >= 1, else :class:`InputError`.

    A 1-D array is one column (N,) -> (N, 1). Sparse matrices and complex numbers are refused.
    ``accepted`` says, in the error for something that is no numbers, what the caller takes
    (the error names the type it got).
    """
    if hasattr(X, "tocsr"):  # a scipy.sparse matrix or array, without importing scipy
        raise InputError(f"{name} is a sparse matrix: give a dense array (e.g. X.toarray())")
    try:
        array = np.asarray(X)
        complex_values = array.dtype.kind == "c"
        if not complex_values:
            array = array.astype(float, copy=False)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be {accepted}, got {type_of(X)}") from None
    if complex_values:
        raise InputError(f"Complex data not supported: {name} holds complex numbers")
    if array.ndim == 1:
        array = array[:, None]
    if array.ndim != 2:
        raise InputError(f"{name} must have shape (n_samples, n_features), got {array.shape}")
    if array.shape[0] == 0:
        raise InputError(f"{name} is empty: no samples")
    if array.shape[1] == 0:
        raise InputError(
            f"{name} has no columns (0 feature(s) (shape={array.shape}) while a minimum of 1 is required)"
        )
    if not np.all(np.isfinite(array)):
        row, column = np.argwhere(~np.isfinite(array))[0]
        value = "NaN" if np.isnan(array[row, column]) else f"{array[row, column]:+}"
        raise InputError(f"{name} has a non-finite value ({value}) at row {row}, column {column}")
    if np.abs(array).max() > MAX_MAGNITUDE:  # squares and sums of squares would overflow
        row, column = np.argwhere(np.abs(array) > MAX_MAGNITUDE)[0]
        raise InputError(
            f"{name} has the value {array[row, column]:g} at row {row}, column {column}: values must be "
            f"within ±{MAX_MAGNITUDE:g}"
        )
    return array


def type_of(value: Any) -> str:
    """``value``'s type for an error: ``dict``, ``list of Trajectory``, ``ndarray of object``."""
    name = type(value).__name__
    if isinstance(value, np.ndarray):
        return f"{name} of {value.dtype}"
    if isinstance(value, (list, tuple)) and value:
        return f"{name} of {type(value[0]).__name__}"
    return name


#: Why a DataFrame cannot be read by name.
NO_NAMES = (
    "X is a DataFrame, but the mixture has no column names (it was fitted on an array): pass an "
    "array with the columns in the mixture's order, or fit the mixture on a DataFrame"
)


def is_frame(data: Any) -> bool:
    """Whether ``data`` is a pandas DataFrame (without importing pandas: if pandas is not loaded,
    nothing is a DataFrame)."""
    pandas = sys.modules.get("pandas")
    return pandas is not None and isinstance(data, pandas.DataFrame)


def by_name(X: Any, names: Sequence[str] | None, what: str = "X") -> Any:
    """``X`` unchanged, or for a pandas DataFrame with string column names its columns
    ``names`` by name (:func:`frame_columns`). A DataFrame whose columns are not named (integer
    labels) is taken by position, as an array.

    Raises
    ------
    InputError
        ``names`` is None (the model has no column names) for a DataFrame with named columns, or
        the DataFrame lacks some of ``names``.
    """
    if not is_frame(X) or not all(isinstance(column, str) for column in X.columns):
        return X
    if names is None:
        raise InputError(NO_NAMES)
    return frame_columns(X, names, what)


def frame_columns(frame: Any, names: Sequence[str], what: str = "data") -> np.ndarray:
    """The named columns of a pandas DataFrame as a float array (N, len(names)), by name.

    Raises
    ------
    InputError
        A named column is missing (the message lists the missing and the present columns),
        appears more than once, is not numeric or holds NaN or inf (naming the column and row).
    """
    present = [str(column) for column in frame.columns]
    missing = [name for name in names if name not in present]
    if missing:
        raise InputError(
            f"{what}: the DataFrame has no column{'s' if len(missing) > 1 else ''} "
            f"{', '.join(map(repr, missing))} (columns present: {', '.join(present) if present else 'none'})"
        )
    if len(frame) == 0:
        raise InputError(f"{what}: the DataFrame has no rows")
    values = np.empty((len(frame), len(names)))
    for j, name in enumerate(names):
        if present.count(name) > 1:
            raise InputError(f"{what}: the DataFrame has column {name!r} {present.count(name)} times")
        column = frame.iloc[:, present.index(name)]
        try:
            values[:, j] = column.to_numpy(dtype=float)
        except (TypeError, ValueError):
            raise InputError(f"{what}: column {name!r} is not numeric (dtype {column.dtype})") from None
        bad = np.flatnonzero(~np.isfinite(values[:, j]))
        if bad.size:
            raise InputError(
                f"{what}: column {name!r} has a non-finite value ({values[bad[0], j]}) at row {bad[0]}"
            )
    return values


def check_weights(sample_weight: Any, n_samples: int) -> np.ndarray:
    """Sample weights of shape (N,), finite, >= 0, not all 0; ones when ``None``."""
    if sample_weight is None:
        return np.ones(n_samples)
    weights = np.asarray(sample_weight, dtype=float)
    if weights.shape != (n_samples,):
        raise InputError(f"sample_weight must have shape ({n_samples},), got {weights.shape}")
    if not np.all(np.isfinite(weights)) or np.any(weights < 0):
        bad = int(np.flatnonzero(~np.isfinite(weights) | (weights < 0))[0])
        raise InputError(f"sample_weight[{bad}] = {weights[bad]} is not a finite weight >= 0")
    if not np.any(weights > 0):
        raise InputError("sample_weight is zero everywhere")
    return weights


def _n_parameters(n_components: int, n_features: int) -> int:
    """Free parameters of a full-covariance mixture: weights, means and covariances."""
    return (n_components - 1) + n_components * n_features + n_components * n_features * (n_features + 1) // 2


# -- the numerical core on standardised data -------------------------------------------------


@functools.lru_cache(maxsize=1)
def _threadpools() -> ThreadpoolController:
    return ThreadpoolController()


def single_threaded_blas() -> Any:
    """Context manager running BLAS on one thread.

    The matrix products of EM and GMR are thin (samples x a few columns): BLAS threads cost more
    in start-up and contention than they save (tenfold on a busy machine).
    """
    return _threadpools().limit(limits=1, user_api="blas")


@functools.lru_cache(maxsize=16)
def upper_triangle(d: int) -> tuple[np.ndarray, np.ndarray]:
    """Row and column indices (i <= j) of the upper triangle of a (d, d) matrix (cached)."""
    rows, cols = np.triu_indices(d)
    rows.setflags(write=False)
    cols.setflags(write=False)
    return rows, cols


def quadratic_features(Z: np.ndarray, transposed: bool = False) -> np.ndarray:
    """Features ``[1, z_1..z_D, z_i z_j for i <= j]`` of every sample.

    ``Z`` has shape (N, D) and the result (N, 1 + D + D(D+1)/2); with ``transposed`` both are
    given with the samples last, ``Z`` (D, N) and the result (F, N), for products with arrays laid
    out that way.
    """
    d = Z.shape[0] if transposed else Z.shape[1]
    rows, cols = upper_triangle(d)
    if transposed:
        phi = np.empty((1 + d + rows.size, Z.shape[1]))
        phi[0] = 1.0
        phi[1 : d + 1] = Z
        for row, (i, j) in enumerate(zip(rows, cols, strict=True), start=d + 1):
            np.multiply(Z[i], Z[j], out=phi[row])
        return phi
    phi = np.empty((Z.shape[0], 1 + d + rows.size))
    phi[:, 0] = 1.0
    phi[:, 1 : d + 1] = Z
    for column, (i, j) in enumerate(zip(rows, cols, strict=True), start=d + 1):
        np.multiply(Z[:, i], Z[:, j], out=phi[:, column])
    return phi


def _cholesky(covariances: np.ndarray) -> np.ndarray:
    """Batched lower Cholesky factors (K, D, D); raises InputError naming the component."""
    try:
        return np.linalg.cholesky(covariances)
    except np.linalg.LinAlgError:
        for k, covariance in enumerate(covariances):
            try:
                np.linalg.cholesky(covariance)
            except np.linalg.LinAlgError:
                raise InputError(
                    f"covariance of component {k} is not positive definite; increase reg_covar"
                ) from None
        raise


def log_density_coefficients(weights: np.ndarray, means: np.ndarray, covariances: np.ndarray) -> np.ndarray:
    """Coefficients (F, K) such that ``quadratic_features(Z) @ coef`` = log w_k N(z | mu_k, S_k).

    Uses (z - mu)^T P (z - mu) = z^T P z - 2 mu^T P z + mu^T P mu with the precision P from the
    Cholesky factor; the data are standardised, so the terms stay of moderate size.
    """
    chol = _cholesky(covariances)
    chol_inv = np.linalg.inv(chol)  # triangular, (K, D, D)
    precision = np.swapaxes(chol_inv, 1, 2) @ chol_inv
    log_det = 2.0 * np.log(np.diagonal(chol, axis1=1, axis2=2)).sum(axis=1)
    return gaussian_log_coefficients(weights, means, precision, log_det)


def gaussian_log_coefficients(
    weights: np.ndarray, means: np.ndarray, precision: np.ndarray, log_det: np.ndarray
) -> np.ndarray:
    """:func:`log_density_coefficients` from the precisions (K, D, D) and ln |S_k| (K,)."""
    n_components, d = means.shape
    p_mu = (precision @ means[:, :, None])[:, :, 0]
    log_weights = np.log(weights, out=np.full(n_components, -np.inf), where=weights > 0)
    rows, cols = upper_triangle(d)
    coef = np.empty((1 + d + rows.size, n_components))
    coef[0] = log_weights - 0.5 * (d * _LOG_2PI + log_det + (means * p_mu).sum(axis=1))
    coef[1 : d + 1] = p_mu.T
    quad = -precision[:, rows, cols]
    quad[:, rows == cols] *= 0.5
    coef[d + 1 :] = quad.T
    return coef


#: Lowest log-responsibility relative to the largest (see :func:`normalise_log_weights`).
_LOG_FLOOR = -700.0
#: Rows per block of the E/M pass: keeps the (K, rows) work arrays in the CPU cache.
_BLOCK = 8192


def normalise_log_weights(log_prob: np.ndarray, log_density: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
    """In place: ``log_prob`` (K, N) becomes the responsibilities; returns them and ln p (N,).

    Components run along the first axis so that the reductions over K are elementwise
    operations on contiguous rows. With ``log_density=False`` ln p is not computed (None).
    Log-weights more than 700 below the largest are raised to that floor (a responsibility of
    1e-304 instead of less): ``exp`` is ten times slower where its result underflows to
    subnormal numbers or zero, and far from a component most values would.
    """
    peak = log_prob.max(axis=0)
    peak[~np.isfinite(peak)] = 0.0
    log_prob -= peak
    np.maximum(log_prob, _LOG_FLOOR, out=log_prob)
    np.exp(log_prob, out=log_prob)
    total = log_prob.sum(axis=0)
    log_prob /= total
    if not log_density:
        return log_prob, None
    with np.errstate(divide="ignore"):
        return log_prob, peak + np.log(total)


def _e_m_pass(phi: np.ndarray, coef: np.ndarray, weights: np.ndarray) -> tuple[float, np.ndarray]:
    """One E step and the sufficient statistics of the next M step, block by block.

    Returns the weighted total log-likelihood and the statistics (K, F): weighted sums of the
    responsibilities times ``[1, z, z_i z_j]``.
    """
    stats = np.zeros((coef.shape[1], phi.shape[1]))
    log_likelihood = 0.0
    coef_t = np.ascontiguousarray(coef.T)
    for start in range(0, phi.shape[0], _BLOCK):  # blocks of rows, not single samples
        block = phi[start : start + _BLOCK]
        w = weights[start : start + _BLOCK]
        resp, log_density = normalise_log_weights(coef_t @ block.T)
        log_likelihood += float(w @ log_density)
        resp *= w
        stats += resp @ block
    return log_likelihood, stats


def _parameters_from_statistics(
    stats: np.ndarray, diagonal: np.ndarray, d: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Weights (K,), means (K, D) and covariances (K, D, D) from the statistics (K, F); the
    covariances get ``diagonal`` (D,) added (the regularisation)."""
    counts = stats[:, 0] + 10.0 * np.finfo(float).eps
    means = stats[:, 1 : d + 1] / counts[:, None]
    rows, cols = upper_triangle(d)
    second = np.empty((counts.size, d, d))
    second[:, rows, cols] = stats[:, d + 1 :] / counts[:, None]
    second[:, cols, rows] = second[:, rows, cols]
    covariances = second - means[:, :, None] * means[:, None, :]
    covariances[:, np.arange(d), np.arange(d)] += diagonal
    return counts / counts.sum(), means, covariances


def _kmeans_plus_plus(Z: np.ndarray, weights: np.ndarray, k: int, rng: np.random.Generator) -> np.ndarray:
    """Greedy k-means++ seeding (Arthur & Vassilvitskii, 2007).

    Each next centre is drawn with probability proportional to the weight times the squared
    distance to the *nearest* centre chosen so far; 2 + ln k such draws are tried and the one that
    lowers the total squared distance most is kept, which avoids two seeds in one cluster.
    """
    n = Z.shape[0]
    trials = 2 + int(math.log(k))
    sq_norms = (Z**2).sum(axis=1)
    centres = np.empty((k, Z.shape[1]))
    centres[0] = Z[rng.choice(n, p=weights / weights.sum())]
    nearest = ((Z - centres[0]) ** 2).sum(axis=1)
    for j in range(1, k):
        cumulative = np.cumsum(weights * nearest)
        if cumulative[-1] <= 0:  # every sample sits on a centre: duplicated points
            cumulative = np.cumsum(weights)
        draws = rng.random(trials) * cumulative[-1]
        candidates = np.minimum(np.searchsorted(cumulative, draws, side="right"), n - 1)
        distances = sq_norms[:, None] - 2.0 * Z @ Z[candidates].T + sq_norms[candidates]
        np.maximum(distances, 0.0, out=distances)
        np.minimum(distances, nearest[:, None], out=distances)
        best = int(np.argmin(weights @ distances))
        centres[j] = Z[candidates[best]]
        nearest = distances[:, best]
    return centres


def _assign(Z: np.ndarray, sq_norms: np.ndarray, centres: np.ndarray) -> tuple[np.ndarray, float]:
    """Index of the nearest centre for every sample (N,), and the squared distances' sum."""
    distances = Z @ (-2.0 * centres.T)
    distances += (centres**2).sum(axis=1)
    labels = distances.argmin(axis=1)
    nearest = distances[np.arange(Z.shape[0]), labels]
    return labels, float((nearest + sq_norms).sum())


def _lloyd(Z: np.ndarray, weights: np.ndarray, centres: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Refine centres by weighted k-means (Lloyd); returns the centres (K, D), the final labels
    (N,) and the (unweighted) sum of squared distances to the nearest centre."""
    k, d = centres.shape
    sq_norms = (Z**2).sum(axis=1)
    labels, inertia = _assign(Z, sq_norms, centres)
    for _ in range(_KMEANS_MAX_ITER):
        mass = np.bincount(labels, weights=weights, minlength=k)
        new = np.empty_like(centres)
        for j in range(d):  # loop over the few columns, not the samples
            new[:, j] = np.bincount(labels, weights=weights * Z[:, j], minlength=k)
        filled = mass > 0
        new[filled] /= mass[filled, None]
        new[~filled] = centres[~filled]
        shift = ((new - centres) ** 2).sum()
        centres = new
        labels, inertia = _assign(Z, sq_norms, centres)
        if shift <= _KMEANS_TOL:  # the columns are standardised: mean variance 1
            break
    return centres, labels, inertia


def _kmeans(Z: np.ndarray, weights: np.ndarray, k: int, rng: np.random.Generator) -> np.ndarray:
    """Labels (N,) of k-means from the best of several k-means++ seedings.

    Each of ``_KMEANS_TRIALS`` greedy k-means++ seedings is refined by k-means on at most
    ``_KMEANS_SUBSET`` samples (drawn with probability proportional to the weights); the centres
    with the least sum of squared distances start the final k-means on all samples. One seeding
    alone lands two centres in one cluster now and then, and EM rarely recovers from that.
    """
    n = Z.shape[0]
    if n > _KMEANS_SUBSET:
        subset = rng.choice(n, size=_KMEANS_SUBSET, p=weights / weights.sum())
        Z_s, w_s = Z[subset], np.ones(_KMEANS_SUBSET)
    else:
        Z_s, w_s = Z, weights
    best_centres, best_inertia = None, np.inf
    for _ in range(_KMEANS_TRIALS):
        centres, _, inertia = _lloyd(Z_s, w_s, _kmeans_plus_plus(Z_s, w_s, k, rng))
        if inertia < best_inertia:
            best_centres, best_inertia = centres, inertia
    return _lloyd(Z, weights, best_centres)[1]


def _initial_responsibilities(
    Z: np.ndarray, weights: np.ndarray, k: int, init: str, rng: np.random.Generator
) -> np.ndarray:
    """Hard responsibilities (N, K) from k-means++ + k-means, or from random centres."""
    if init == "kmeans++":
        labels = _kmeans(Z, weights, k, rng)
    else:
        positive = np.flatnonzero(weights > 0)
        chosen = rng.choice(positive, size=k, replace=False)
        labels, _ = _assign(Z, (Z**2).sum(axis=1), Z[chosen])
    resp = np.zeros((Z.shape[0], k))
    resp[np.arange(Z.shape[0]), labels] = 1.0
    return resp


# -- the estimator -----------------------------------------------------------------------------


class GaussianMixture:
    """Gaussian Mixture Model with full covariances, fitted by EM in log space.

    A scikit-learn estimator: ``__init__`` stores its arguments unchanged, :meth:`fit` validates
    them and sets the fitted state (names ending in ``_``), :meth:`get_params` /
    :meth:`set_params` read and change the settings, so ``sklearn.base.clone``, pipelines and
    ``GridSearchCV`` (which ranks by :meth:`score`, the mean log-likelihood) work.

    Parameters
    ----------
    n_components : int
        Number of Gaussian components K.
    reg_covar : float
        Added to the diagonal of every covariance on the standardised scale (>= 0).
    column_variance : array of shape (D,), optional
        Variance in the data's units added to the diagonal of every covariance, on top of
        ``reg_covar``: the resolution of a column recorded on a grid. A basket distance known to
        0.25 m is uniform within +-0.125 m of its value, variance 0.25^2 / 12; without it a
        component can sit on a single basket with a variance of almost 0 in the distance and a
        likelihood that grows without bound.
    tol : float
        EM stops when the mean log-likelihood per sample changes by less than ``tol``.
    max_iter : int
        Maximum number of EM iterations per initialisation.
    n_init : int
        Number of initialisations; the one with the highest final log-likelihood is kept.
    init : {"kmeans++", "random"}
        k-means++ seeding refined by k-means, or centres drawn at random among the samples.
    random_state : int, numpy Generator or None
        Seed of the initialisations and of :meth:`sample`.
    weights_init, means_init, covariances_init : arrays of shape (K,), (K, D), (K, D, D), optional
        Initial parameters in the data's units; when given, ``init`` is not used and ``n_init``
        is 1.

    Attributes
    ----------
    weights_ : ndarray of shape (K,)
    means_ : ndarray of shape (K, D)
        In the data's units.
    covariances_ : ndarray of shape (K, D, D)
        In the data's units (squared).
    center_, scale_ : ndarray of shape (D,)
        Standardisation used for fitting: z = (x - center_) / scale_.
    n_features_in_ : int
        D, the number of columns seen by :meth:`fit`.
    feature_names_in_ : ndarray of shape (D,), dtype object
        The column names, when fitted on a pandas DataFrame with string column names (or
        given by :class:`rlff.Model`); the methods then take a DataFrame's columns by name.
    converged_ : bool
    n_iter_ : int
        EM iterations of the kept initialisation.
    lower_bound_ : float
        Mean log-likelihood per sample (standardised scale) at the last E step.
    lower_bounds_ : list of float
        Mean log-likelihood per sample at every E step of the kept initialisation.
    """

    def __init__(
        self,
        n_components: int = 1,
        *,
        reg_covar: float = 1e-6,
        column_variance: np.ndarray | None = None,
        tol: float = 1e-3,
        max_iter: int = 100,
        n_init: int = 1,
        init: str = "kmeans++",
        random_state: int | np.random.Generator | None = None,
        weights_init: np.ndarray | None = None,
        means_init: np.ndarray | None = None,
        covariances_init: np.ndarray | None = None,
    ) -> None:
        self.n_components = n_components
        self.reg_covar = reg_covar
        self.column_variance = column_variance
        self.tol = tol
        self.max_iter = max_iter
        self.n_init = n_init
        self.init = init
        self.random_state = random_state
        self.weights_init = weights_init
        self.means_init = means_init
        self.covariances_init = covariances_init

    # -- the scikit-learn estimator protocol ------------------------------------------------
    # Implemented here rather than inherited from sklearn.base.BaseEstimator: importing
    # sklearn.base loads pandas, pyarrow and most of scipy (about 1,100 modules, +1 s on every
    # rlff command that touches a model), and scikit-learn is only needed by those who use it.
    # The protocol is small: the settings are exactly the keyword arguments of __init__.

    @classmethod
    def _get_param_names(cls) -> list[str]:
        """Names of the settings: the parameters of ``__init__``, in order."""
        return [name for name in inspect.signature(cls.__init__).parameters if name != "self"]

    def get_params(self, deep: bool = True) -> dict[str, Any]:
        """The settings as given to ``__init__`` (``deep`` is accepted for scikit-learn; no
        setting is itself an estimator)."""
        return {name: getattr(self, name) for name in self._get_param_names()}

    def set_params(self, **params: Any) -> GaussianMixture:
        """Change settings (validated at the next :meth:`fit`); returns ``self``.

        Raises
        ------
        InputError
            A name that is not a setting (the settings are listed).
        """
        valid = self._get_param_names()
        for name, value in params.items():
            if name not in valid:
                raise InputError(
                    f"GaussianMixture has no parameter {name!r} (parameters: {', '.join(valid)})"
                )
            setattr(self, name, value)
        return self

    def __sklearn_tags__(self) -> Any:
        """scikit-learn's default estimator tags with the type of a density estimator (as its
        DensityMixin sets it). Only scikit-learn calls this, so scikit-learn is importable here.
        """
        from sklearn.base import BaseEstimator

        tags = BaseEstimator.__sklearn_tags__(self)
        tags.estimator_type = "density_estimator"
        return tags

    def __repr__(self) -> str:
        defaults = {
            name: parameter.default
            for name, parameter in inspect.signature(type(self).__init__).parameters.items()
        }
        changed = [
            f"{name}={value!r}"
            for name, value in self.get_params().items()
            if not (value is defaults[name] or (_is_plain(value) and value == defaults[name]))
        ]
        return f"GaussianMixture({', '.join(changed)})"

    # -- construction ----------------------------------------------------------------------
    def _check_parameters(self) -> None:
        if not isinstance(self.n_components, (int, np.integer)) or self.n_components < 1:
            raise InputError(f"n_components must be an integer >= 1, got {self.n_components!r}")
        if not (np.isfinite(self.reg_covar) and self.reg_covar >= 0):
            raise InputError(f"reg_covar must be >= 0, got {self.reg_covar!r}")
        if not (np.isfinite(self.tol) and self.tol >= 0):
            raise InputError(f"tol must be >= 0, got {self.tol!r}")
        if not isinstance(self.max_iter, (int, np.integer)) or self.max_iter < 1:
            raise InputError(f"max_iter must be an integer >= 1, got {self.max_iter!r}")
        if not isinstance(self.n_init, (int, np.integer)) or self.n_init < 1:
            raise InputError(f"n_init must be an integer >= 1, got {self.n_init!r}")
        if self.init not in _INITS:
            raise InputError(f"init must be one of {', '.join(_INITS)}, got {self.init!r}")

    @classmethod
    def from_parameters(
        cls,
        weights: np.ndarray,
        means: np.ndarray,
        covariances: np.ndarray,
        *,
        center: np.ndarray | None = None,
        scale: np.ndarray | None = None,
        **kwargs: Any,
    ) -> GaussianMixture:
        """A fitted mixture from its parameters in the data's units (no fitting).

        ``center`` and ``scale`` (D,) are the standardisation to keep for later use; defaults
        0 and 1.
        """
        weights = np.asarray(weights, dtype=float)
        means = np.asarray(means, dtype=float)
        covariances = np.asarray(covariances, dtype=float)
        k, d = means.shape
        if weights.shape != (k,) or covariances.shape != (k, d, d):
            raise InputError(
                f"inconsistent shapes: weights {weights.shape}, means {means.shape}, covariances {covariances.shape}"
            )
        mixture = cls(n_components=k, **kwargs)
        mixture.center_ = np.zeros(d) if center is None else np.asarray(center, dtype=float)
        mixture.scale_ = np.ones(d) if scale is None else np.asarray(scale, dtype=float)
        mixture.weights_ = weights
        mixture.means_ = means
        mixture.covariances_ = covariances
        mixture.n_features_in_ = d
        mixture.converged_ = True
        mixture.n_iter_ = 0
        mixture.lower_bound_ = -np.inf
        mixture.lower_bounds_ = []
        mixture._refresh()
        return mixture

    def _refresh(self) -> None:
        """Derived quantities on the standardised scale, from the public attributes.

        Raises InputError when they overflow (parameters near 1e308, or a scale that makes a
        covariance vanish): such a mixture cannot be evaluated.
        """
        self._cholesky_data = _cholesky(self.covariances_)
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            z_means = (self.means_ - self.center_) / self.scale_
            z_cov = self.covariances_ / np.outer(self.scale_, self.scale_)
            coef = log_density_coefficients(self.weights_, z_means, z_cov) if np.all(np.isfinite(z_cov)) else None
        # row 0 holds ln w_k + constants: -inf for a weight of 0; everything else must be finite
        usable = (
            coef is not None
            and np.all(np.isfinite(coef[1:]))
            and np.all(np.isfinite(coef[0]) | ((self.weights_ == 0) & (coef[0] == -np.inf)))
        )
        if not usable:
            raise InputError(
                "the mixture's parameters overflow on its standardised scale (means, covariances "
                "or scale too large or too small to evaluate)"
            )
        self._coef = coef

    def _check_fitted(self) -> None:
        if not hasattr(self, "weights_"):
            raise InputError("this GaussianMixture is not fitted yet: call fit first")

    # -- fitting ---------------------------------------------------------------------------
    def fit(self, X: np.ndarray, y: None = None, sample_weight: np.ndarray | None = None) -> GaussianMixture:
        """Fit the mixture to samples by EM.

        Parameters
        ----------
        X : array of shape (N, D)
            Samples in the data's units; finite.
        y : ignored
            For scikit-learn compatibility.
        sample_weight : array of shape (N,), optional
            Non-negative weight of each sample (weighted EM); a weight acts as a repeat count.

        Returns
        -------
        self
        """
        self._check_parameters()
        self.__dict__.pop("feature_names_in_", None)
        if is_frame(X) and all(isinstance(name, str) for name in X.columns):
            names = np.array(X.columns, dtype=object)
            X = frame_columns(X, names.tolist(), "X")
            self.feature_names_in_ = names
        X = check_samples(X)
        weights = check_weights(sample_weight, X.shape[0])
        n_used = int(np.count_nonzero(weights))
        if n_used < 2:
            raise InputError(
                f"need at least 2 samples (with weight > 0) to fit a mixture, got {n_used} sample"
                + ("s" if n_used != 1 else "")
            )
        if self.n_components > n_used:
            raise InputError(
                f"n_components = {self.n_components} is more than the {n_used} samples"
            )
        self.center_, self.scale_ = _standardisation(X, weights)
        Z = (X - self.center_) / self.scale_
        phi = quadratic_features(Z)
        w = weights / weights.mean()
        rng = np.random.default_rng(self.random_state)
        diagonal = self._diagonal(X.shape[1])
        best = None
        with single_threaded_blas():
            for start in self._initial_parameters(Z, phi, w, rng, diagonal):
                result = self._em(phi, w, start, diagonal)
                if best is None or result[0] > best[0]:
                    best = result
        lower_bound, params, converged, n_iter, history = best
        z_weights, z_means, z_cov = params
        self.weights_ = z_weights
        self.means_ = z_means * self.scale_ + self.center_
        self.covariances_ = z_cov * np.outer(self.scale_, self.scale_)
        self.n_features_in_ = X.shape[1]
        self.converged_ = converged
        self.n_iter_ = n_iter
        self.lower_bound_ = lower_bound
        self.lower_bounds_ = history
        self._refresh()
        return self

    def _diagonal(self, d: int) -> np.ndarray:
        """What every covariance gets on its diagonal, (D,) on the standardised scale."""
        if self.column_variance is None:
            return np.full(d, float(self.reg_covar))
        extra = np.asarray(self.column_variance, dtype=float)
        if extra.shape != (d,) or not np.all(np.isfinite(extra)) or np.any(extra < 0):
            raise InputError(f"column_variance must hold {d} finite values >= 0, got {extra.tolist()}")
        return self.reg_covar + extra / self.scale_**2

    def _initial_parameters(
        self, Z: np.ndarray, phi: np.ndarray, w: np.ndarray, rng: np.random.Generator, diagonal: np.ndarray
    ) -> Iterable[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        d = Z.shape[1]
        if self.means_init is not None:
            weights = np.asarray(
                np.full(self.n_components, 1.0 / self.n_components) if self.weights_init is None else self.weights_init,
                dtype=float,
            )
            means = (np.asarray(self.means_init, dtype=float) - self.center_) / self.scale_
            if self.covariances_init is None:
                covariances = np.broadcast_to(np.eye(d), (self.n_components, d, d)).copy()
            else:
                covariances = np.asarray(self.covariances_init, dtype=float) / np.outer(self.scale_, self.scale_)
            if means.shape != (self.n_components, d) or covariances.shape != (self.n_components, d, d):
                raise InputError("means_init / covariances_init do not match n_components and the data's columns")
            return [(weights, means, covariances)]
        return (
            _parameters_from_statistics(
                _initial_responsibilities(Z, w, self.n_components, self.init, rng).T @ (phi * w[:, None]),
                diagonal,
                d,
            )
            for _ in range(self.n_init)
        )

    def _em(
        self,
        phi: np.ndarray,
        w: np.ndarray,
        params: tuple[np.ndarray, np.ndarray, np.ndarray],
        diagonal: np.ndarray,
    ) -> tuple[float, tuple[np.ndarray, np.ndarray, np.ndarray], bool, int, list[float]]:
        """EM from initial standardised parameters; returns (mean LL, params, converged, iterations, history)."""
        lower_bound = -np.inf
        history: list[float] = []
        converged = False
        total_weight = w.sum()
        while len(history) < self.max_iter:
            previous = lower_bound
            log_likelihood, stats = _e_m_pass(phi, log_density_coefficients(*params), w)
            lower_bound = log_likelihood / total_weight
            history.append(lower_bound)
            params = _parameters_from_statistics(stats, diagonal, diagonal.size)
            if abs(lower_bound - previous) < self.tol:
                converged = True
                break
        return lower_bound, params, converged, len(history), history

    # -- evaluation --------------------------------------------------------------------------
    def _log_prob_z(self, X: np.ndarray) -> np.ndarray:
        """Weighted log-densities log w_k N(z | mu_k, S_k) (N, K) on the standardised scale."""
        self._check_fitted()
        X = check_samples(self._named_columns(X, range(self.means_.shape[1])))
        if X.shape[1] != self.means_.shape[1]:
            raise InputError(
                f"X has {X.shape[1]} features, but GaussianMixture is expecting "
                f"{self.means_.shape[1]} features as input (one per column it was fitted on)"
            )
        return quadratic_features((X - self.center_) / self.scale_) @ self._coef

    def _named_columns(self, X: Any, columns: Iterable[int]) -> Any:
        """``X`` through :func:`by_name` with the names of the mixture's ``columns`` (indices)."""
        names = getattr(self, "feature_names_in_", None)
        return by_name(X, None if names is None else [str(names[j]) for j in columns])

    def score_samples(self, X: np.ndarray) -> np.ndarray:
        """Log-density ln p(x) of every sample (N,), in the data's units."""
        log_prob = self._log_prob_z(X)
        peak = log_prob.max(axis=1)
        total = np.log(np.exp(log_prob - peak[:, None]).sum(axis=1))
        return peak + total - np.log(self.scale_).sum()

    def score(self, X: np.ndarray, y: None = None, sample_weight: np.ndarray | None = None) -> float:
        """Mean (weighted) log-likelihood per sample of ``X`` (N, D), in the data's units."""
        log_density = self.score_samples(X)
        weights = check_weights(sample_weight, log_density.size)
        return float(weights @ log_density / weights.sum())

    def predict_proba(self, X: np.ndarray) -> np.ndarray:
        """Responsibilities (N, K): posterior probability of each component for each sample."""
        return _softmax(self._log_prob_z(X))

    def predict(self, X: np.ndarray) -> np.ndarray:
        """Most probable component of each sample (N,)."""
        return self._log_prob_z(X).argmax(axis=1)

    def n_parameters(self) -> int:
        """Number of free parameters p of the model."""
        self._check_fitted()
        return _n_parameters(*self.means_.shape)

    def bic(self, X: np.ndarray, sample_weight: np.ndarray | None = None, effective_samples: float | None = None) -> float:
        """Bayesian information criterion -2 ln L + p ln n of ``X`` (N, D) (lower is better).

        With ``sample_weight``, ln L is the weighted sum and n the sum of the weights; with
        ``effective_samples``, n is that many independent samples (:func:`information_criteria`).
        """
        log_likelihood, n = self._total_log_likelihood(X, sample_weight)
        return information_criteria(log_likelihood, self.n_parameters(), n, effective_samples)[0]

    def aic(self, X: np.ndarray, sample_weight: np.ndarray | None = None) -> float:
        """Akaike information criterion -2 ln L + 2 p of ``X`` (N, D) (lower is better)."""
        log_likelihood, n = self._total_log_likelihood(X, sample_weight)
        return information_criteria(log_likelihood, self.n_parameters(), n)[1]

    def _total_log_likelihood(self, X: np.ndarray, sample_weight: np.ndarray | None) -> tuple[float, float]:
        log_density = self.score_samples(X)
        weights = check_weights(sample_weight, log_density.size)
        return float(weights @ log_density), float(weights.sum())

    def sample(self, n_samples: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """Draw samples (n, D) in the data's units and their component labels (n,)."""
        self._check_fitted()
        if n_samples < 1:
            raise InputError(f"n_samples must be >= 1, got {n_samples}")
        rng = np.random.default_rng(self.random_state)
        labels = rng.choice(self.weights_.size, size=n_samples, p=self.weights_ / self.weights_.sum())
        noise = rng.standard_normal((n_samples, self.means_.shape[1]))
        samples = self.means_[labels] + np.einsum("nij,nj->ni", self._cholesky_data[labels], noise)
        return samples, labels


def _is_plain(value: Any) -> bool:
    """A setting compared by value in the repr (numbers, strings, None), not an array."""
    return value is None or isinstance(value, (int, float, str, np.integer, np.floating))


def _softmax(log_prob: np.ndarray) -> np.ndarray:
    log_prob = log_prob - log_prob.max(axis=1, keepdims=True)
    prob = np.exp(log_prob)
    return prob / prob.sum(axis=1, keepdims=True)


def _standardisation(X: np.ndarray, weights: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Weighted column means (D,) and standard deviations (D,); a constant column gets scale 1."""
    center = weights @ X / weights.sum()
    scale = np.sqrt(weights @ (X - center) ** 2 / weights.sum())
    constant = scale <= 1e-12 * np.maximum(1.0, np.abs(center))
    scale[constant] = 1.0
    return center, scale


# -- component selection ----------------------------------------------------------------------


@dataclass
class Selection:
    """Result of :func:`select_components`.

    Attributes
    ----------
    model : GaussianMixture
        The fitted mixture with the lowest criterion.
    table : list of dict
        One row per candidate K: ``n_components``, ``bic``, ``aic``, ``log_likelihood`` (total
        ln L in the data's units), ``n_parameters``, ``converged``, ``n_iter``.
    criterion : str
        ``"bic"`` or ``"aic"``.
    """

    model: GaussianMixture
    table: list[dict[str, Any]] = field(default_factory=list)
    criterion: str = "bic"

    @property
    def n_components(self) -> int:
        return self.model.n_components


def information_criteria(
    log_likelihood: float, n_parameters: int, n_samples: float, effective_samples: float | None = None
) -> tuple[float, float]:
    """BIC = -2 ln L + p ln n and AIC = -2 ln L + 2 p (lower is better).

    Both assume n independent samples. Samples interpolated between measurements (a densified
    trajectory holds 10-40 samples per camera frame) are not: ln L grows with every one of them
    while the penalty grows with ln n only, so BIC keeps falling with K. With
    ``effective_samples`` = n_e < n, each sample counts for n_e / n of one: ln L is scaled by
    n_e / n and n is n_e.
    """
    if effective_samples is None:
        return -2.0 * log_likelihood + n_parameters * math.log(n_samples), -2.0 * log_likelihood + 2.0 * n_parameters
    if not (math.isfinite(effective_samples) and 0 < effective_samples <= n_samples * (1 + 1e-12)):
        raise InputError(f"effective_samples must be in (0, {n_samples:g}], got {effective_samples!r}")
    scaled = log_likelihood * effective_samples / n_samples
    return -2.0 * scaled + n_parameters * math.log(effective_samples), -2.0 * scaled + 2.0 * n_parameters


def select_components(
    X: np.ndarray,
    components: Iterable[int] = range(1, 9),
    *,
    criterion: str = "bic",
    sample_weight: np.ndarray | None = None,
    effective_samples: float | None = None,
    progress: Callable[[int, int], None] | None = None,
    **gm_kwargs: Any,
) -> Selection:
    """Fit one mixture per candidate number of components and keep the lowest BIC (or AIC).

    Parameters
    ----------
    X : array of shape (N, D)
        Samples in the data's units.
    components : iterable of int
        Candidate K; candidates above the number of samples are left out.
    criterion : {"bic", "aic"}
        BIC = -2 ln L + p ln n (the thesis' choice), AIC = -2 ln L + 2 p. Ties go to the smaller K.
    sample_weight : array of shape (N,), optional
        Weights of the samples (weighted EM; ln L weighted, n = sum of weights).
    effective_samples : float, optional
        How many independent samples the data stand for, when fewer than n (see
        :func:`information_criteria`).
    progress : callable(done, total), optional
        Called after each candidate.
    **gm_kwargs
        Passed to :class:`GaussianMixture` (reg_covar, tol, max_iter, n_init, init, random_state).

    Returns
    -------
    Selection
    """
    if criterion not in ("bic", "aic"):
        raise InputError(f"criterion must be 'bic' or 'aic', got {criterion!r}")
    X = check_samples(X)
    weights = check_weights(sample_weight, X.shape[0])
    n_used = int(np.count_nonzero(weights))
    candidates = sorted({int(k) for k in components})
    if not candidates or candidates[0] < 1:
        raise InputError(f"component candidates must be integers >= 1, got {candidates}")
    usable = [k for k in candidates if k <= n_used]
    if not usable:
        raise InputError(f"every candidate number of components {candidates} exceeds the {n_used} samples")
    table = []
    best: tuple[float, GaussianMixture] | None = None
    for done, k in enumerate(usable, start=1):
        model = GaussianMixture(k, **gm_kwargs).fit(X, sample_weight=sample_weight)
        log_likelihood, n = model._total_log_likelihood(X, sample_weight)
        p = model.n_parameters()
        bic, aic = information_criteria(log_likelihood, p, n, effective_samples)
        row = {
            "n_components": k,
            "bic": bic,
            "aic": aic,
            "log_likelihood": log_likelihood,
            "n_parameters": p,
            "converged": bool(model.converged_),
            "n_iter": int(model.n_iter_),
        }
        table.append(row)
        if best is None or row[criterion] < best[0]:
            best = (row[criterion], model)
        if progress is not None:
            progress(done, len(usable))
    assert best is not None
    return Selection(model=best[1], table=table, criterion=criterion)

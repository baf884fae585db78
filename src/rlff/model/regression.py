"""Gaussian Mixture Regression: a fitted mixture conditioned on some of its columns (thesis eq. 2.3-2.6).

For inputs x (columns ``inputs``) and outputs y (columns ``outputs``), every component k gives

- the weight h_k(x) = w_k N(x | mu_in, S_ii) / sum_j w_j N(x | mu_in_j, S_ii_j), computed in log
  space so that it stays finite far from every component;
- the mean m_k(x) = mu_out + S_oi S_ii^-1 (x - mu_in);
- the covariance S_k = S_oo - S_oi S_ii^-1 S_io (independent of x);

and the mixture's conditional mean and total covariance follow from the law of total variance:
m(x) = sum_k h_k m_k and V(x) = sum_k h_k (S_k + (m_k - m)(m_k - m)^T).

Everything is batched over the N inputs and the K components; S_ii is only ever used through its
Cholesky factor.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numba
import numpy as np

from rlff.errors import InputError
from rlff.model.fastexp import exp_relative
from rlff.model.mixture import by_name, gaussian_log_coefficients

#: Samples per block of the compiled pass: keeps the (K, block) work arrays in the CPU cache.
_BLOCK = 1024


@dataclass(frozen=True)
class Conditional:
    """The mixture of Gaussians p(y | x) for a batch of N inputs.

    Attributes
    ----------
    weights : ndarray of shape (N, K)
        Component weights h_k(x), each row sums to 1.
    means : ndarray of shape (N, K, O)
        Component means m_k(x), in the output's units.
    covariances : ndarray of shape (K, O, O)
        Component covariances S_k (the same for every input).
    mean : ndarray of shape (N, O)
        Conditional mean E[y | x] (the GMR prediction).
    covariance : ndarray of shape (N, O, O)
        Total conditional covariance V[y | x] (law of total variance).

    The batch arrays may be transposed views of arrays laid out with the samples last.
    """

    weights: np.ndarray
    means: np.ndarray
    covariances: np.ndarray
    mean: np.ndarray
    covariance: np.ndarray

    @property
    def variance(self) -> np.ndarray:
        """Diagonal of :attr:`covariance`, shape (N, O)."""
        return np.diagonal(self.covariance, axis1=1, axis2=2).copy()

    def __len__(self) -> int:
        return self.weights.shape[0]


def _column_indices(indices: Sequence[int], n_features: int, name: str) -> np.ndarray:
    given = np.asarray(list(indices)).reshape(-1).tolist()
    if not all(isinstance(i, int) and not isinstance(i, bool) for i in given):
        raise InputError(f"{name} {given} must be column positions (integers from 0 to {n_features - 1}), "
                         "e.g. inputs=[0, 1], outputs=[2]; Model.condition takes the inputs by name")
    columns = [int(i) for i in given]
    if not columns:
        raise InputError(f"{name} must name at least one column")
    if any(c < 0 or c >= n_features for c in columns):
        raise InputError(f"{name} {columns} out of range for a mixture of {n_features} columns")
    if len(set(columns)) != len(columns):
        raise InputError(f"{name} {columns} repeats a column")
    return np.array(columns)


def condition(mixture: Any, inputs: Sequence[int], outputs: Sequence[int], X: np.ndarray) -> Conditional:
    """Condition a fitted mixture on input columns for a batch of inputs.

    Parameters
    ----------
    mixture : GaussianMixture or any object with ``weights_`` (K,), ``means_`` (K, D) and
        ``covariances_`` (K, D, D)
        The joint model, in the data's units.
    inputs : sequence of int, length I
        Columns conditioned on.
    outputs : sequence of int, length O
        Columns predicted; disjoint from ``inputs``.
    X : array of shape (N, I) (or (I,) for one input)
        Input values, in the data's units.

    Returns
    -------
    Conditional
        Weights (N, K), means (N, K, O), covariances (K, O, O), and the mixture mean (N, O) and
        total covariance (N, O, O).

    See :func:`predict` for the mean and total covariance alone (without writing N x K weights
    and N x K x O means).
    """
    regression = _Regression(mixture, inputs, outputs)
    X = regression.checked_inputs(X)
    n = X.shape[0]
    h = np.empty((regression.n_components, n))
    component_means = np.empty((regression.n_components, regression.n_out, n))
    mean, covariance = regression.run(X, h, component_means)
    return Conditional(
        weights=h.T,
        means=component_means.transpose(2, 0, 1),
        covariances=regression.cond_cov,
        mean=mean,
        covariance=covariance,
    )


def predict(
    mixture: Any, inputs: Sequence[int], outputs: Sequence[int], X: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The GMR prediction alone: conditional mean (N, O) and total covariance (N, O, O).

    Same parameters and numbers as :func:`condition`, without storing the per-component weights
    and means (N x K values each) that only the DMM needs.
    """
    regression = _Regression(mixture, inputs, outputs)
    X = regression.checked_inputs(X)
    no_store = np.empty((regression.n_components, 0))
    return regression.run(X, no_store, no_store.reshape(regression.n_components, 1, 0))


class _Regression:
    """The per-component constants of one conditioning (inputs, outputs) of a mixture."""

    def __init__(self, mixture: Any, inputs: Sequence[int], outputs: Sequence[int]):
        missing = [name for name in ("weights_", "means_", "covariances_") if not hasattr(mixture, name)]
        if missing:
            raise InputError(f"this {type(mixture).__name__} is not fitted yet (no {', '.join(missing)}): "
                             "call fit first")
        weights = np.asarray(mixture.weights_, dtype=float)
        means = np.asarray(mixture.means_, dtype=float)
        covariances = np.asarray(mixture.covariances_, dtype=float)
        n_features = means.shape[1]
        i_in = _column_indices(inputs, n_features, "inputs")
        i_out = _column_indices(outputs, n_features, "outputs")
        if set(i_in.tolist()) & set(i_out.tolist()):
            raise InputError(f"inputs {i_in.tolist()} and outputs {i_out.tolist()} share a column")
        s_ii = covariances[:, i_in[:, None], i_in]  # (K, I, I)
        s_oi = covariances[:, i_out[:, None], i_in]  # (K, O, I)
        s_oo = covariances[:, i_out[:, None], i_out]  # (K, O, O)
        try:
            chol = np.linalg.cholesky(s_ii)
        except np.linalg.LinAlgError:
            raise InputError("the input block of a component covariance is not positive definite") from None
        chol_inv = np.linalg.inv(chol)  # L^-1, (K, I, I)
        precision = np.swapaxes(chol_inv, 1, 2) @ chol_inv  # S_ii^-1
        regression = s_oi @ precision  # A_k = S_oi S_ii^-1, (K, O, I)
        cond_cov = s_oo - regression @ np.swapaxes(s_oi, 1, 2)
        self.cond_cov = np.ascontiguousarray(0.5 * (cond_cov + np.swapaxes(cond_cov, 1, 2)))
        names = getattr(mixture, "feature_names_in_", None)
        self.input_names = None if names is None else [str(names[j]) for j in i_in]
        self.n_components, self.n_out, self.n_in = regression.shape
        # Inputs centred on the components' mean input, so the quadratic expansion of the
        # Mahalanobis distance works on moderate numbers. log w_k N(x | mu_in, S_ii) is linear in
        # the features [1, x, x_i x_j] of x (see rlff.model.mixture.gaussian_log_coefficients), and so
        # is the component mean m_k(x) = (mu_out - A_k mu_in) + A_k x.
        self.center = weights @ means[:, i_in]
        mu_in = means[:, i_in] - self.center
        log_det = 2.0 * np.log(np.diagonal(chol, axis1=1, axis2=2)).sum(axis=1)
        self.coef_log = np.ascontiguousarray(gaussian_log_coefficients(weights, mu_in, precision, log_det).T)  # (K, F)
        self.coef_mean = np.empty((self.n_components, self.n_out, 1 + self.n_in))
        self.coef_mean[:, :, 0] = means[:, i_out] - (regression @ mu_in[:, :, None])[:, :, 0]
        self.coef_mean[:, :, 1:] = regression

    def checked_inputs(self, X: np.ndarray) -> np.ndarray:
        """Checked inputs X (N, I) (or (I,) for one input) as a C-ordered (N, I) array; a
        DataFrame's input columns by name (the mixture's ``feature_names_in_``)."""
        X = np.asarray(by_name(X, self.input_names), dtype=float)
        given = X.shape
        if X.ndim == 1:
            X = X.reshape(1, -1) if X.size == self.n_in else X[:, None]
        if X.ndim != 2 or X.shape[1] != self.n_in:
            one = f" (or ({self.n_in},) for one row)" if self.n_in > 1 else " (or (n,))"
            raise InputError(f"X must have shape (n, {self.n_in}){one}, got {given}")
        X = np.ascontiguousarray(X)
        if not X.flags.writeable:  # e.g. DataFrame.to_numpy(): numba would compile a second version
            X = X.copy()
        # a finite sum proves every value finite (one pass, no temporary); else look closer
        if not (np.isfinite(X.sum()) or np.isfinite(X).all()):
            row = int(np.flatnonzero(~np.all(np.isfinite(X), axis=1))[0])
            raise InputError(f"input row {row} holds NaN or inf: {X[row].tolist()}")
        return X

    def run(self, X: np.ndarray, h: np.ndarray, component_means: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Mean (N, O) and total covariance (N, O, O) at inputs X (N, I); fills ``h`` (K, N) and
        ``component_means`` (K, O, N) unless their last axis is empty."""
        n = X.shape[0]
        mean = np.empty((self.n_out, n))
        covariance = np.empty((self.n_out, self.n_out, n))
        _conditional_kernel(X, self.center, self.coef_log, self.coef_mean, self.cond_cov, h, component_means, mean, covariance)
        return mean.T, covariance.transpose(2, 0, 1)


@numba.njit(cache=True, nogil=True, fastmath={"contract"})
def _affine(coef: np.ndarray, features: np.ndarray, out: np.ndarray, size: int) -> None:
    """out[:size] = coef[0] + sum_f coef[f + 1] features[f, :size], with coef (1 + F,) and
    features (F, B): up to three features per pass over the block."""
    n_features = features.shape[0]
    c0 = coef[0]
    if n_features == 0:
        out[:size] = c0
        return
    f = min(n_features, 3)
    if f == 1:
        c1, x1 = coef[1], features[0]
        for b in range(size):
            out[b] = c0 + c1 * x1[b]
    elif f == 2:
        c1, c2, x1, x2 = coef[1], coef[2], features[0], features[1]
        for b in range(size):
            out[b] = c0 + c1 * x1[b] + c2 * x2[b]
    else:
        c1, c2, c3, x1, x2, x3 = coef[1], coef[2], coef[3], features[0], features[1], features[2]
        for b in range(size):
            out[b] = c0 + c1 * x1[b] + c2 * x2[b] + c3 * x3[b]
    while f < n_features:
        if f + 1 < n_features:
            c1, c2, x1, x2 = coef[f + 1], coef[f + 2], features[f], features[f + 1]
            for b in range(size):
                out[b] += c1 * x1[b] + c2 * x2[b]
            f += 2
        else:
            c1, x1 = coef[f + 1], features[f]
            for b in range(size):
                out[b] += c1 * x1[b]
            f += 1


@numba.njit(cache=True, nogil=True, fastmath={"contract"})
def _conditional_kernel(
    X: np.ndarray,
    center: np.ndarray,
    coef_log: np.ndarray,
    coef_mean: np.ndarray,
    cond_cov: np.ndarray,
    h_out: np.ndarray,
    means_out: np.ndarray,
    mean: np.ndarray,
    covariance: np.ndarray,
) -> None:
    """The GMR of N inputs, block by block of samples.

    Inputs: X (N, I) inputs and the centre (I,) subtracted from them; coef_log (K, F) with
    log w_k N(x | mu_k, S_k) = coef_log[k] . [1, x, x_i x_j (i <= j)] on centred x; coef_mean
    (K, O, 1 + I) with m_k(x) = coef_mean[k] . [1, x]; cond_cov (K, O, O). Outputs: mean (O, N),
    covariance (O, O, N), and when their last axis is N (not 0), the weights h_out (K, N) and the
    component means means_out (K, O, N).

    Why compiled (numba): every quantity is a short sum over K components per input. As NumPy
    array expressions that is some forty passes over (K, N) temporaries; here the work arrays are
    one block of samples that stays in the CPU cache, and every loop runs along the block (SIMD).
    """
    n, n_in = X.shape
    n_components, n_features = coef_log.shape
    n_out = coef_mean.shape[1]
    store = h_out.shape[1] == n
    phi = np.empty((n_features - 1, _BLOCK))  # features [x, x_i x_j] of a block
    h = np.empty((n_components, _BLOCK))
    m = np.empty((n_components, n_out, _BLOCK))
    peak = np.empty(_BLOCK)
    total = np.empty(_BLOCK)
    for start in range(0, n, _BLOCK):
        stop = min(start + _BLOCK, n)
        size = stop - start
        for i in range(n_in):
            row, c = phi[i], center[i]
            for b in range(size):
                row[b] = X[start + b, i] - c
        if n_in != 2:
            f = n_in
            for i in range(n_in):
                for j in range(i, n_in):
                    row_i, row_j, row_f = phi[i], phi[j], phi[f]
                    for b in range(size):
                        row_f[b] = row_i[b] * row_j[b]
                    f += 1
        # log-weights l_k and their largest per sample
        for k in range(n_components):
            row = h[k]
            if n_in == 2:  # the throwing model's case: coefficients of [1, x, y, x^2, xy, y^2], one pass
                c, x, y = coef_log[k], phi[0], phi[1]
                for b in range(size):
                    row[b] = c[0] + x[b] * (c[1] + c[3] * x[b] + c[4] * y[b]) + y[b] * (c[2] + c[5] * y[b])
            else:
                _affine(coef_log[k], phi, row, size)
            if k == 0:
                peak[:size] = row[:size]
            else:
                for b in range(size):
                    peak[b] = row[b] if row[b] > peak[b] else peak[b]
        # weights h_k = e_k / sum_j e_j with e_k = exp(l_k - peak) (normalised at the end)
        total[:size] = 0.0
        for k in range(n_components):
            exp_relative(h[k, :size], peak[:size], total[:size])
        for b in range(size):
            total[b] = 1.0 / total[b]
        # component means m_k(x) and the mixture mean
        for o in range(n_out):
            mean_o = mean[o, start:stop]
            mean_o[:] = 0.0
            for k in range(n_components):
                m_ko, weight = m[k, o], h[k]
                _affine(coef_mean[k, o], phi[:n_in], m_ko, size)
                for b in range(size):
                    mean_o[b] += weight[b] * m_ko[b]
            for b in range(size):
                mean_o[b] *= total[b]
        # total covariance sum_k h_k (S_k + (m_k - m)(m_k - m)^T)
        for o in range(n_out):
            for p in range(o + 1):
                cov = covariance[o, p, start:stop]
                cov[:] = 0.0
                mean_o, mean_p = mean[o, start:stop], mean[p, start:stop]
                for k in range(n_components):
                    weight, m_ko, m_kp, s = h[k], m[k, o], m[k, p], cond_cov[k, o, p]
                    for b in range(size):
                        cov[b] += weight[b] * (s + (m_ko[b] - mean_o[b]) * (m_kp[b] - mean_p[b]))
                for b in range(size):
                    cov[b] *= total[b]
                if p != o:
                    covariance[p, o, start:stop] = cov
        if store:
            for k in range(n_components):
                for b in range(size):
                    h_out[k, start + b] = h[k, b] * total[b]
            means_out[:, :, start:stop] = m[:, :, :size]

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

import numpy as np

from rlff.errors import InputError
from rlff.mixture import (
    log_density_coefficients,
    normalise_log_weights,
    quadratic_features,
    single_threaded_blas,
)

#: Samples per block: keeps the (K, block) work arrays in the CPU cache.
_BLOCK = 8192


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
    array = np.asarray(list(indices), dtype=int).reshape(-1)
    if array.size == 0:
        raise InputError(f"{name} must name at least one column")
    if np.any(array < 0) or np.any(array >= n_features):
        raise InputError(f"{name} {array.tolist()} out of range for a mixture of {n_features} columns")
    if np.unique(array).size != array.size:
        raise InputError(f"{name} {array.tolist()} repeats a column")
    return array


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
    """
    weights = np.asarray(mixture.weights_, dtype=float)
    means = np.asarray(mixture.means_, dtype=float)
    covariances = np.asarray(mixture.covariances_, dtype=float)
    n_features = means.shape[1]
    i_in = _column_indices(inputs, n_features, "inputs")
    i_out = _column_indices(outputs, n_features, "outputs")
    if np.intersect1d(i_in, i_out).size:
        raise InputError(f"inputs {i_in.tolist()} and outputs {i_out.tolist()} share a column")
    X = np.asarray(X, dtype=float)
    if X.ndim == 1:
        X = X.reshape(1, -1) if X.size == i_in.size else X[:, None]
    if X.ndim != 2 or X.shape[1] != i_in.size:
        raise InputError(f"X must have shape (n, {i_in.size}), got {X.shape}")
    if not np.all(np.isfinite(X)):
        row = int(np.flatnonzero(~np.all(np.isfinite(X), axis=1))[0])
        raise InputError(f"input row {row} holds NaN or inf: {X[row].tolist()}")

    s_ii = covariances[:, i_in[:, None], i_in]  # (K, I, I)
    s_oi = covariances[:, i_out[:, None], i_in]  # (K, O, I)
    s_oo = covariances[:, i_out[:, None], i_out]  # (K, O, O)
    try:
        chol = np.linalg.cholesky(s_ii)
    except np.linalg.LinAlgError:
        raise InputError("the input block of a component covariance is not positive definite") from None
    identity = np.broadcast_to(np.eye(i_in.size), chol.shape)
    chol_inv = np.linalg.solve(chol, identity)  # L^-1 from the triangular factor, (K, I, I)
    # Regression matrices A_k = S_oi S_ii^-1 = (S_oi L^-T) L^-1, (K, O, I).
    whitened_oi = s_oi @ np.swapaxes(chol_inv, 1, 2)
    regression = whitened_oi @ chol_inv
    cond_cov = s_oo - whitened_oi @ np.swapaxes(whitened_oi, 1, 2)
    cond_cov = 0.5 * (cond_cov + np.swapaxes(cond_cov, 1, 2))

    # Inputs centred on the components' mean input, so the quadratic expansion of the
    # Mahalanobis distance works on moderate numbers.
    center = weights @ means[:, i_in]
    mu_in = means[:, i_in] - center
    # log w_k N(x | mu_in, S_ii) for every (k, n) is one matrix product with quadratic features
    # of x (see rlff.mixture.log_density_coefficients), then normalised in log space.
    n_components, n_out = regression.shape[:2]
    n_in = i_in.size
    # One matrix product per block gives both, from the features [1, x, x_i x_j]:
    # rows 0..K-1: log w_k N(x | mu_in, S_ii) (see rlff.mixture.log_density_coefficients);
    # rows K..: the component means m_k(x) = (mu_out - A_k mu_in) + A_k x, component-major.
    coef_log = log_density_coefficients(weights, mu_in, s_ii).T  # (K, F)
    coef_mean = np.zeros((n_components * n_out, coef_log.shape[1]))
    coef_mean[:, 0] = (means[:, i_out] - np.einsum("koi,ki->ko", regression, mu_in)).reshape(-1)
    coef_mean[:, 1 : n_in + 1] = regression.reshape(-1, n_in)
    coef = np.concatenate([coef_log, coef_mean])
    # Batch arrays are laid out with the samples last, (K, N) and (K, O, N), and filled block by
    # block so that the work arrays stay in the CPU cache.
    n = X.shape[0]
    X_t = (X - center).T.copy()  # (I, N)
    h = np.empty((n_components, n))
    component_means = np.empty((n_components * n_out, n))
    mean = np.empty((n_out, n))
    covariance = np.empty((n, n_out, n_out))
    with single_threaded_blas():
        for start in range(0, n, _BLOCK):  # blocks of samples, not single samples
            block = slice(start, start + _BLOCK)
            product = coef @ quadratic_features(X_t[:, block], transposed=True)
            h_b, _ = normalise_log_weights(product[:n_components], log_density=False)
            m_b = product[n_components:]
            h[:, block] = h_b
            component_means[:, block] = m_b
            if n_out == 1:  # one output: plain (K, B) products, no small matrices
                weighted = h_b * m_b
                mean_b = weighted.sum(axis=0)
                mean[0, block] = mean_b
                m_b -= mean_b  # V = sum_k h_k (S_k + (m_k - m)^2)
                np.multiply(h_b, m_b, out=weighted)
                weighted *= m_b
                covariance[block, 0, 0] = weighted.sum(axis=0) + cond_cov[:, 0, 0] @ h_b
            else:
                m_b = m_b.reshape(n_components, n_out, -1)
                mean_b = (h_b[:, None, :] * m_b).sum(axis=0)  # (O, B)
                mean[:, block] = mean_b
                spread = m_b - mean_b
                covariance[block] = np.einsum("kn,kop->nop", h_b, cond_cov) + np.einsum(
                    "kn,kon,kpn->nop", h_b, spread, spread
                )
    return Conditional(
        weights=h.T,
        means=component_means.reshape(n_components, n_out, n).transpose(2, 0, 1),
        covariances=cond_cov,
        mean=mean.T,
        covariance=covariance,
    )

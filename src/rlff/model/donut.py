"""The Donut Mixture Model (thesis eq. 2.7-2.11, after Grollman & Billard 2011) and its global mode.

A donut is the difference of two Gaussians with one mean,

    D(y | m, S, r_a, r_b, gamma) = gamma N(y | m, S / r_a^2) - (gamma - 1) N(y | m, S / r_b^2),

and the DMM swaps every component of the GMR conditional p(y | x) for a donut,
P_DMM(y | x) = sum_k h_k(x) D(y | m_k(x), S_k, eps(x)). The exploration factor eps in [0, 1] sets
how deep the hole at the mean is: eps = 0 gives back the Gaussian, eps = 1 puts zero density at
the mean. By default eps(x) = 1 - 1 / (1 + ||V(x)|| / sigma^2) with V the GMR total covariance
and sigma the *exploration scale* in output units (sigma = 1 reproduces the thesis).

The radii come from eps through :func:`donut_radii` (one small function, to swap for another
parametrisation): with d output dimensions, rho = r_b / r_a = 1 + eps ((gamma / (gamma - 1))^(1/d) - 1)
and the donut keeps the covariance S of its Gaussian, gamma / r_a^2 - (gamma - 1) / r_b^2 = 1.
Then every donut is non-negative and integrates to 1, and at eps = 1 its density at the mean is 0.

The output for an input is the *global* maximiser of P_DMM (thesis section 2.4). Instead of one
BFGS run per input from the GMR mean (which stops at the hole of a donut), :func:`dmm_mode` starts
from every component's mean and from its ring of highest density along each principal axis, plus
the GMR mean, and runs safeguarded Newton steps on all starts of all inputs: one compiled loop
(numba) over the inputs and their starts, one version for one output and one for several
(:mod:`rlff.model.climb`).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numba
import numpy as np

from rlff.errors import InputError
from rlff.model import climb
from rlff.model.regression import Conditional

#: Donut weight gamma of the thesis.
GAMMA = 2.0
#: Relative pdf tolerance within which two modes count as equally high (continuity option).
CONTINUITY_TOLERANCE = 0.05
#: Inputs the several-output climb takes in one compiled call. Between calls Ctrl-C is answered
#: and progress told: a whole-arm model fitted to an hour of throws takes up to 26 ms a point, and
#: 10,000 points in one call answered neither for 4 minutes. Each call climbs its first and last
#: input afresh (:func:`rlff.model.climb._modes_nd_kernel`), a few more of the 30-60 fresh climbs
#: of 1,000 points, in the same time (10,000 points of the real MSR model: 7.3 s either way).
#: Paths up to this length are climbed as before; on longer ones every point is as high to the
#: climbs' precision (1e-8), and where the top is a flat ridge the point on it may differ (221
#: of those 10,000 points, by up to 0.17 rad/s, at densities equal to 6e-9).
CLIMB_CHUNK = 500


# -- exploration and radii -------------------------------------------------------------------


def exploration_factor(covariance: np.ndarray, scale: float = 1.0) -> np.ndarray:
    """Exploration factor eps = 1 - 1 / (1 + ||V|| / scale^2) for every input (thesis eq. 2.10).

    Parameters
    ----------
    covariance : array of shape (N, O, O)
        GMR total covariance V of the output (output units squared).
    scale : float
        Exploration scale sigma in output units: the spread of the demonstrations that counts as
        large (eps = 1/2 where ||V|| = sigma^2). The thesis uses 1.

    Returns
    -------
    ndarray of shape (N,)
        eps in [0, 1); ||V|| is the spectral norm (the variance itself for one output).
    """
    covariance = np.asarray(covariance, dtype=float)
    if covariance.ndim != 3 or covariance.shape[1] != covariance.shape[2]:
        raise InputError(f"covariance must have shape (N, O, O), got {covariance.shape}")
    if not (np.isfinite(scale) and scale > 0):
        raise InputError(f"exploration scale must be > 0, got {scale!r}")
    if covariance.shape[1] == 1:
        norm = covariance[:, 0, 0]
    else:
        norm = np.empty(len(covariance))
        _largest_eigenvalues(np.ascontiguousarray(covariance), norm)
    norm = np.maximum(norm, 0.0)
    return norm / (norm + scale**2)


@numba.njit(cache=True, nogil=True)
def _largest_eigenvalues(matrices: np.ndarray, out: np.ndarray) -> None:
    """The largest eigenvalue of each symmetric matrix (N, O, O) into ``out`` (N,): in closed form
    for O = 2 and 3 (the 3x3 by the trigonometric solution of the characteristic cubic, unless its
    two largest eigenvalues nearly coincide), else by cyclic Jacobi rotations.

    Why by hand (numba): np.linalg.eigvalsh makes one LAPACK call per matrix, and for the 2-5
    outputs of a throw the call costs more than the arithmetic: 0.5 us for a 3x3 matrix, where a
    whole GMR pass takes 0.2 us per point.
    """
    n, o, _ = matrices.shape
    a = np.empty((o, o))
    for i in range(n):
        m = matrices[i]
        if o == 2:
            half = 0.5 * (m[0, 0] - m[1, 1])
            out[i] = 0.5 * (m[0, 0] + m[1, 1]) + math.sqrt(half * half + m[0, 1] * m[0, 1])
        elif o == 3:
            off = m[0, 1] * m[0, 1] + m[0, 2] * m[0, 2] + m[1, 2] * m[1, 2]
            mean = (m[0, 0] + m[1, 1] + m[2, 2]) / 3.0
            d0, d1, d2 = m[0, 0] - mean, m[1, 1] - mean, m[2, 2] - mean
            p = math.sqrt((d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * off) / 6.0)
            if off == 0.0 or p == 0.0:
                out[i] = max(m[0, 0], m[1, 1], m[2, 2])
                continue
            # det((A - mean I) / p) / 2 = cos(3 phi): the largest root is mean + 2 p cos(phi)
            det = d0 * (d1 * d2 - m[1, 2] * m[1, 2]) - m[0, 1] * (m[0, 1] * d2 - m[1, 2] * m[0, 2]) + m[0, 2] * (
                m[0, 1] * m[1, 2] - d1 * m[0, 2]
            )
            r = 0.5 * det / (p * p * p)
            if r > -0.999:
                out[i] = mean + 2.0 * p * math.cos(math.acos(min(1.0, r)) / 3.0)
                continue
            a[:, :] = m  # the two largest nearly equal: acos loses digits there (1e-8), Jacobi does not
            out[i] = _jacobi_largest(a)
        else:
            a[:, :] = m
            out[i] = _jacobi_largest(a)


@numba.njit(cache=True, nogil=True)
def _jacobi_largest(a: np.ndarray) -> float:
    """The largest eigenvalue of a symmetric matrix (O, O), overwritten: cyclic Jacobi rotations
    until the off-diagonal part is below 1e-30 of the diagonal (squared sums)."""
    o = a.shape[0]
    for _ in range(50):
        off = diagonal = 0.0
        for p in range(o):
            diagonal += a[p, p] * a[p, p]
            for q in range(p + 1, o):
                off += a[p, q] * a[p, q]
        if not off > 1e-30 * diagonal:
            break
        for p in range(o - 1):
            for q in range(p + 1, o):
                if a[p, q] == 0.0:
                    continue
                theta = (a[q, q] - a[p, p]) / (2.0 * a[p, q])
                t = (1.0 if theta >= 0.0 else -1.0) / (abs(theta) + math.sqrt(theta * theta + 1.0))
                c = 1.0 / math.sqrt(t * t + 1.0)
                s = t * c
                for k in range(o):  # A J, then J^T (A J): zeroes a[p, q]
                    left, right = a[k, p], a[k, q]
                    a[k, p] = c * left - s * right
                    a[k, q] = s * left + c * right
                for k in range(o):
                    upper, lower = a[p, k], a[q, k]
                    a[p, k] = c * upper - s * lower
                    a[q, k] = s * upper + c * lower
    largest = a[0, 0]
    for p in range(1, o):
        largest = max(largest, a[p, p])
    return largest


def donut_radii(exploration: np.ndarray, n_dims: int, gamma: float = GAMMA) -> tuple[np.ndarray, np.ndarray]:
    """Squared precision radii (r_a^2, r_b^2) of the donut for exploration factors in [0, 1].

    rho = r_b / r_a = 1 + eps ((gamma / (gamma - 1))^(1/d) - 1) and gamma / r_a^2 - (gamma - 1) /
    r_b^2 = 1 (the donut keeps the covariance of its Gaussian), so r_a^2 = gamma - (gamma - 1) /
    rho^2. eps = 0 gives r_a = r_b = 1 (the Gaussian); eps = 1 gives rho^d = gamma / (gamma - 1),
    where the two terms cancel at the mean. Returns two arrays shaped like ``exploration``.
    """
    eps = np.asarray(exploration, dtype=float)
    rho = 1.0 + eps * ((gamma / (gamma - 1.0)) ** (1.0 / n_dims) - 1.0)
    r_a2 = gamma - (gamma - 1.0) / rho**2
    return r_a2, r_a2 * rho**2


def _check_exploration(exploration: Any, n: int) -> np.ndarray:
    eps = np.broadcast_to(np.asarray(exploration, dtype=float), (n,)).copy() if np.ndim(exploration) == 0 else np.asarray(exploration, dtype=float)
    if eps.shape != (n,):
        raise InputError(f"exploration must be a number or have shape ({n},), got {eps.shape}")
    if not np.all(np.isfinite(eps)) or np.any(eps < 0) or np.any(eps > 1):
        bad = eps[~(np.isfinite(eps) & (eps >= 0) & (eps <= 1))][0]
        raise InputError(f"exploration factor must be in [0, 1], got {bad}")
    return eps


def _check_gamma(gamma: float) -> None:
    if not (np.isfinite(gamma) and gamma > 1):
        raise InputError(f"gamma must be > 1, got {gamma!r}")


# -- densities -------------------------------------------------------------------------------


def donut_pdf(
    y: np.ndarray, mean: np.ndarray, covariance: np.ndarray, exploration: float | np.ndarray, gamma: float = GAMMA
) -> np.ndarray:
    """Density of one donut (thesis eq. 2.8), broadcast over leading axes.

    Parameters
    ----------
    y : array of shape (..., O)
        Points, output units.
    mean : array of shape (..., O)
        Donut centre m.
    covariance : array of shape (..., O, O)
        Covariance S of the underlying Gaussian (the donut's own covariance).
    exploration : float or array of shape (...)
        eps in [0, 1].
    gamma : float
        Donut weight (> 1).

    Returns
    -------
    ndarray of shape (...)
    """
    _check_gamma(gamma)
    y = np.asarray(y, dtype=float)
    mean = np.asarray(mean, dtype=float)
    covariance = np.asarray(covariance, dtype=float)
    d = y.shape[-1]
    chol = np.linalg.cholesky(covariance)
    diff = np.broadcast_to(y - mean, np.broadcast_shapes(y.shape, mean.shape, covariance.shape[:-1]))
    whitened = np.linalg.solve(np.broadcast_to(chol, diff.shape + (d,)), diff[..., None])[..., 0]
    q = (whitened**2).sum(axis=-1)
    log_norm = -0.5 * d * math.log(2 * math.pi) - np.log(np.diagonal(chol, axis1=-2, axis2=-1)).sum(axis=-1)
    r_a2, r_b2 = donut_radii(np.asarray(exploration, dtype=float), d, gamma)
    return np.exp(log_norm) * (
        gamma * r_a2 ** (d / 2) * np.exp(-0.5 * r_a2 * q) - (gamma - 1.0) * r_b2 ** (d / 2) * np.exp(-0.5 * r_b2 * q)
    )


class _Donuts:
    """The DMM of a batch of conditionals: the per-component constants the density and the climbs use."""

    def __init__(self, conditional: Conditional, exploration: np.ndarray, gamma: float):
        _check_gamma(gamma)
        self.h = np.asarray(conditional.weights, dtype=float)  # (N, K)
        self.m = np.asarray(conditional.means, dtype=float)  # (N, K, O)
        cov = np.asarray(conditional.covariances, dtype=float)  # (K, O, O)
        self.n, self.k, self.o = self.m.shape
        self.gamma = gamma
        self.covariances = cov
        try:
            chol = np.linalg.cholesky(cov)
        except np.linalg.LinAlgError:
            raise InputError("a conditional covariance is not positive definite") from None
        identity = np.broadcast_to(np.eye(self.o), chol.shape)
        chol_inv = np.linalg.solve(chol, identity)
        self.precision = np.swapaxes(chol_inv, 1, 2) @ chol_inv  # (K, O, O)
        log_det = 2.0 * np.log(np.diagonal(chol, axis1=1, axis2=2)).sum(axis=1)
        self.eigenvalues, self.eigenvectors = np.linalg.eigh(cov)  # (K, O), (K, O, O)
        self.eps = exploration
        self.r_a2, self.r_b2 = donut_radii(exploration, self.o, gamma)  # (N,)
        # Per (n, k) factors of the two Gaussian terms: h_k (2 pi)^-d/2 |S_k|^-1/2 r^d (gamma or gamma-1).
        base = self.h * np.exp(-0.5 * (self.o * math.log(2 * math.pi) + log_det))
        self.w_a = base * (gamma * self.r_a2 ** (self.o / 2))[:, None]  # (N, K)
        self.w_b = base * ((gamma - 1.0) * self.r_b2 ** (self.o / 2))[:, None]

    def rows(self, part: slice) -> _Donuts:
        """The donuts of the inputs in ``part`` (the per-component constants shared)."""
        chosen = copy.copy(self)
        for name in ("h", "m", "eps", "r_a2", "r_b2", "w_a", "w_b"):
            setattr(chosen, name, getattr(self, name)[part])
        chosen.n = chosen.m.shape[0]
        return chosen

    def ring_radius2(self) -> np.ndarray:
        """Squared Mahalanobis radius (N,) where one donut is highest (0: peak at the mean).

        Setting the derivative of gamma r_a^d e^(-r_a^2 q/2) - (gamma-1) r_b^d e^(-r_b^2 q/2) in q
        to zero gives q* = 2 ln((gamma-1) r_b^(d+2) / (gamma r_a^(d+2))) / (r_b^2 - r_a^2).
        """
        gap = self.r_b2 - self.r_a2
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.log((self.gamma - 1.0) / self.gamma) + 0.5 * (self.o + 2) * np.log(self.r_b2 / self.r_a2)
            q = np.where(gap > 1e-12, 2.0 * ratio / np.where(gap > 1e-12, gap, 1.0), 0.0)
        return np.maximum(q, 0.0)

    def evaluate(self, y: np.ndarray) -> np.ndarray:
        """P_DMM (N, S) at points y (N, S, O)."""
        diff = y[:, :, None, :] - self.m[:, None, :, :]  # (N, S, K, O)
        if self.o == 1:
            q = (diff * (diff * self.precision[:, 0, 0][:, None]))[..., 0]
        else:
            q = (diff * np.einsum("nsko,kop->nskp", diff, self.precision)).sum(axis=-1)
        a = np.exp(q * (-0.5 * self.r_a2)[:, None, None])
        a *= self.w_a[:, None, :]
        b = np.exp(q * (-0.5 * self.r_b2)[:, None, None])
        b *= self.w_b[:, None, :]
        return (a - b).sum(axis=2)


def dmm_pdf(
    conditional: Conditional, y: np.ndarray, exploration: float | np.ndarray, gamma: float = GAMMA
) -> np.ndarray:
    """P_DMM(y | x) for every input of a conditional (thesis eq. 2.9).

    Parameters
    ----------
    conditional : Conditional
        GMR of N inputs (see :func:`rlff.model.regression.condition`).
    y : array of shape (N, O) or (N, M, O)
        One or M output points per input.
    exploration : float or array of shape (N,)
        eps in [0, 1] per input.
    gamma : float
        Donut weight (> 1).

    Returns
    -------
    ndarray of shape (N,) or (N, M)
    """
    n, _, o = np.shape(conditional.means)
    y = np.asarray(y, dtype=float)
    single = y.ndim == 2
    points = y[:, None, :] if single else y
    if points.ndim != 3 or points.shape[0] != n or points.shape[2] != o:
        raise InputError(f"y must have shape ({n}, {o}) or ({n}, M, {o}), got {y.shape}")
    donuts = _Donuts(conditional, _check_exploration(exploration, n), gamma)
    pdf = donuts.evaluate(points)
    return pdf[:, 0] if single else pdf


def dmm_marginal_pdf(
    conditional: Conditional, y: np.ndarray, exploration: float | np.ndarray, output: int = 0, gamma: float = GAMMA
) -> np.ndarray:
    """The density of one output of the DMM, the other outputs integrated out.

    A donut of d outputs is gamma N(m, S / r_a^2) - (gamma - 1) N(m, S / r_b^2), so its marginal
    on output j is the same difference of the two Gaussians' marginals: the 1-D donut of mean
    m_j and variance S_jj with the radii of the d-output donut (not those of a 1-D donut with
    the same eps). With one output this is :func:`dmm_pdf`.

    Parameters
    ----------
    conditional : Conditional
        GMR of N inputs, O outputs.
    y : array of shape (N, M)
        M values of the output per input.
    exploration : float or array of shape (N,)
        eps in [0, 1] per input.
    output : int
        Which output (column of the conditional's outputs).
    gamma : float
        Donut weight (> 1).

    Returns
    -------
    ndarray of shape (N, M)
    """
    _check_gamma(gamma)
    n, _, o = np.shape(conditional.means)
    if not 0 <= output < o:
        raise InputError(f"output {output} out of range for {o} outputs")
    y = np.asarray(y, dtype=float)
    if y.ndim != 2 or y.shape[0] != n:
        raise InputError(f"y must have shape ({n}, M), got {y.shape}")
    r_a2, r_b2 = donut_radii(_check_exploration(exploration, n), o, gamma)
    variance = np.asarray(conditional.covariances, dtype=float)[:, output, output]  # (K,)
    q = (y[:, :, None] - np.asarray(conditional.means, dtype=float)[:, None, :, output]) ** 2 / variance  # (N, M, K)
    base = np.asarray(conditional.weights, dtype=float)[:, None, :] / np.sqrt(2 * math.pi * variance)
    a = gamma * np.sqrt(r_a2)[:, None, None] * np.exp(-0.5 * r_a2[:, None, None] * q)
    b = (gamma - 1.0) * np.sqrt(r_b2)[:, None, None] * np.exp(-0.5 * r_b2[:, None, None] * q)
    return (base * (a - b)).sum(axis=2)


# -- the global mode --------------------------------------------------------------------------


@dataclass(frozen=True)
class DonutMode:
    """The DMM output for a batch of N inputs.

    Attributes
    ----------
    output : ndarray of shape (N, O)
        The chosen output (the global maximiser of P_DMM, unless continuity traded it).
    pdf : ndarray of shape (N,)
        P_DMM at ``output``.
    exploration : ndarray of shape (N,)
        The exploration factor used.
    max_pdf : ndarray of shape (N,)
        The global maximum of P_DMM (equal to ``pdf`` without continuity).
    density_traded : ndarray of shape (N,)
        1 - pdf / max_pdf: the share of density given up for continuity (0 without it).
    """

    output: np.ndarray
    pdf: np.ndarray
    exploration: np.ndarray
    max_pdf: np.ndarray
    density_traded: np.ndarray


def dmm_mode(
    conditional: Conditional,
    exploration: str | float | np.ndarray = "auto",
    scale: float = 1.0,
    continuity: bool | float = False,
    *,
    gamma: float = GAMMA,
    tol: float = 1e-5,
    progress: Callable[[int, int], None] | None = None,
) -> DonutMode:
    """The output of highest P_DMM density for every input, found for all inputs at once.

    Parameters
    ----------
    conditional : Conditional
        GMR of N inputs.
    exploration : "auto", float or array of shape (N,)
        ``"auto"``: eps from the GMR total covariance (:func:`exploration_factor` with ``scale``);
        a number or array: a fixed eps in [0, 1] (0 gives the GMR density).
    scale : float
        Exploration scale sigma in output units (only with ``"auto"``).
    continuity : bool or float
        When the inputs are consecutive points of a path, choose among the modes whose density is
        within a relative tolerance of the highest (``True``: 5 %, or the float given) the chain
        that keeps the output continuous (least sum of squared jumps, by dynamic programming),
        for one output or several.
        What it costs is reported in ``density_traded``.
    gamma : float
        Donut weight (> 1).
    tol : float
        A start stops when its step is below ``tol`` times the largest component standard
        deviation (the density is then within about tol^2 of the top: far below the 1e-6 asked for).
    progress : callable, optional
        ``progress(done, total)`` after each :data:`CLIMB_CHUNK` inputs of a several-output climb.

    Returns
    -------
    DonutMode

    Notes
    -----
    Starts: every component's mean, its ring of highest donut density on each principal axis (both
    sides), and the GMR mean. Each start climbs by Newton steps on ln P_DMM inside a trust radius
    (where ln P is not concave, a step of the radius uphill: along the gradient for one output,
    along the Newton direction of the Hessian shifted to definite for several); a step that does
    not raise the density is refused and the radius shrinks, so every start only climbs. The
    highest end point wins; ties within a relative 1e-9 go to the larger first output coordinate.
    With several outputs the continuity option measures each output's jumps in units of its own
    mean GMR variance, so that outputs in different units (rad, rad/s) weigh alike.

    With several outputs and inputs that are consecutive points of a path, the tops are followed
    from one input to the next, and all starts are climbed only where the mixture has changed
    enough since the last such input (57 of a throw's 1,000 phase points, 46 of 150) and where a
    followed top is lost; a top that a fresh climb finds and the following missed is followed
    back (see :func:`rlff.model.climb._modes_nd_kernel`). The result is that of climbing every input alone, but
    for a top born and gone again between two fresh inputs, and about 4x faster on 1,000 path
    points. Inputs that are not a path (random queries) are each climbed alone.
    """
    n = len(conditional)
    if isinstance(exploration, str):
        if exploration != "auto":
            raise InputError(f"exploration must be 'auto' or a number in [0, 1], got {exploration!r}")
        eps = exploration_factor(conditional.covariance, scale)
    else:
        eps = _check_exploration(exploration, n)
    donuts = _Donuts(conditional, eps, gamma)
    if donuts.o == 1:
        y, pdf, best = climb.modes_1d(donuts, np.asarray(conditional.mean, dtype=float)[:, 0], tol)
        y = y[:, :, None]
    else:
        mean = np.asarray(conditional.mean, dtype=float)
        holes = bool(np.any(donuts.ring_radius2() > 1e-12))  # the same starts in every call
        parts = []
        for first in range(0, n, CLIMB_CHUNK):
            part = slice(first, min(first + CLIMB_CHUNK, n))
            parts.append(climb.modes_nd(donuts.rows(part), mean[part], tol, holes=holes))
            if progress is not None:
                progress(part.stop, n)
        y, pdf, best = (np.concatenate(arrays) for arrays in zip(*parts, strict=True))
    rows = np.arange(n)
    output, best_pdf = y[rows, best], pdf[rows, best]
    chosen_pdf = best_pdf
    if continuity:
        tolerance = CONTINUITY_TOLERANCE if continuity is True else float(continuity)
        if not 0 < tolerance < 1:
            raise InputError(f"continuity tolerance must be in (0, 1), got {tolerance}")
        # per output, so that outputs in different units (rad, rad/s) weigh alike in the jumps
        spread = np.mean(np.diagonal(conditional.covariance, axis1=1, axis2=2), axis=0)
        chain = _continuous_chain(y, pdf, best_pdf, tolerance, np.maximum(spread, 1e-300))
        output, chosen_pdf = y[rows, chain], pdf[rows, chain]
    with np.errstate(invalid="ignore", divide="ignore"):
        traded = np.where(best_pdf > 0, 1.0 - chosen_pdf / best_pdf, 0.0)
    return DonutMode(
        output=output, pdf=chosen_pdf, exploration=eps, max_pdf=best_pdf, density_traded=np.maximum(traded, 0.0)
    )


def _continuous_chain(
    y: np.ndarray, pdf: np.ndarray, best_pdf: np.ndarray, tolerance: float, spread: np.ndarray
) -> np.ndarray:
    """Index (N,) of the mode chosen for each consecutive input: among the modes y (N, S, O)
    within ``tolerance`` of the highest density, the chain with the least sum of squared jumps
    (each output in units of its mean GMR variance, ``spread`` (O,)), by dynamic programming."""
    allowed = pdf >= best_pdf[:, None] * (1.0 - tolerance)
    cost = np.where(allowed[0], 0.0, np.inf)
    back = np.zeros(pdf.shape, dtype=int)
    for t in range(1, y.shape[0]):  # along the path: each step depends on the one before
        jump = (((y[t][:, None, :] - y[t - 1][None, :, :]) ** 2) / spread).sum(axis=-1)  # (S_t, S_t-1)
        total = cost[None, :] + jump
        back[t] = total.argmin(axis=1)
        cost = np.where(allowed[t], total[np.arange(total.shape[0]), back[t]], np.inf)
    chain = np.empty(y.shape[0], dtype=int)
    chain[-1] = int(np.argmin(cost))
    for t in range(y.shape[0] - 1, 0, -1):
        chain[t - 1] = back[t, chain[t]]
    return chain

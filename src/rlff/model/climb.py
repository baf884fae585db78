"""The DMM's global mode, compiled: every start of every input climbed to its top (numba).

:func:`rlff.model.donut.dmm_mode` hands over the donuts of a batch of inputs (one output or
several) and gets back every start's end point and density; it then chooses the highest, or the
continuous chain. With one output the starts are each component's mean, its two ring points and
the GMR mean; with several, the same on every principal axis, and along a path the tops are
followed from one input to the next (:func:`modes_nd`, :func:`_modes_nd_kernel`).

Why by hand: the search is the project's own (the thesis runs BFGS from the GMR mean, which
stops at a donut's hole). scipy's BFGS, one run per input, is 270-1,000 times slower and ends
lower wherever it stops in a hole (benchmarks/models.py, sections (c) and (d)).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numba
import numpy as np

from rlff.model.fastexp import LOWEST, exp_nonpositive

if TYPE_CHECKING:
    from rlff.model.donut import _Donuts

_MAX_NEWTON = 60
#: The one-output climb skips a donut term below e^-46 (1e-20) times the highest peak of a single
#: donut: P_DMM is at least that peak somewhere (all terms are >= 0), so the K terms skipped move
#: the density by less than K 1e-20 of its maximum, while most terms far from a start cost no exp.
_NEGLIGIBLE = -46.0
#: Following along a path (see :func:`_modes_nd_kernel`): inputs climbed afresh, with the tops
#: followed between them, wherever the mixture has changed by this much since the last (see
#: :func:`_fresh_inputs`), and at least every ``_TRACK_LONGEST`` inputs.
_TRACK_CHANGE = 2.0
_TRACK_LONGEST = 32
#: Input i continues input i-1 when no component of relative weight above e^-7 (1e-3) at either
#: changes its log-weight by more than ``_TRACK_LOG_WEIGHT`` and the donut radii change by less
#: than ``_TRACK_RADII`` (relative). (Not the means' steps: a narrow component's mean can slide
#: by more than its width from one phase point to the next while its top is followed well.)
_TRACK_RELEVANT = -7.0
_TRACK_LOG_WEIGHT = 1.0
_TRACK_RADII = 0.05
#: A followed top whose climb ends farther than this (scaled outputs: widest standard
#: deviations) from where it was predicted is lost (it vanished, or jumped to another top): the
#: input is climbed afresh instead, and what that finds is followed back.
_TRACK_JUMP = 0.15
#: ... and so is one whose density fell below this share of what it was at the input before (a
#: path too coarse for following: the top has left the reach of its climb).
_TRACK_DROP = 0.5
#: Two end points this close (scaled outputs) are one top: followed once.
_SAME_TOP = 1e-3
#: Tops below this share of the highest at an input are not followed to the next (until the
#: block's next fresh climb); the block's last input checks for tops above ``_TOP_SHARE``.
_FOLLOW_SHARE = 0.1
#: Tops below this share of the highest are not checked for (continuity tolerances up to 0.9
#: choose only among higher ones).
_TOP_SHARE = 0.1
#: A fresh climb's top is among the followed ones when one of them ended this close to it.
_FOUND_TOP = 1e-2
#: How the climbs' helpers compile: without numba's reference counting (its ``_nrt=False``
#: option, which numba's own tests use but does not document). They only read and write arrays
#: that the kernels (:func:`_modes_1d_kernel`, :func:`_modes_nd_kernel`) allocated and hold while
#: they run, and with the counting every array argument, view and tuple element of each call cost
#: an atomic increment and decrement: perf put half the several-output kernel's time in them
#: (NRT_incref, NRT_decref), and without them it takes half the time on 1,000 path points (the
#: one-output kernel 10-20 % less). What would need the runtime (an allocation, a slice
#: assignment, ndarray.max) does not compile under this option, so it cannot slip in; the
#: kernels themselves, which allocate, keep it.
_UNCOUNTED = {"cache": True, "nogil": True, "_nrt": False}
#: Up to ``_LATE_SLOTS`` tops a block's last input finds and the following missed are followed
#: back through the block into slots of their own; more than that, and the block is climbed afresh.
_LATE_SLOTS = 2


def modes_1d(donuts: _Donuts, gmr_mean: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The climb for one output, compiled: end points (N, S) and their pdf (N, S) for the starts of
    :func:`_modes_1d_kernel` (pdf -inf for those left out), and the index (N,) of the highest (see
    :func:`_highest`)."""
    with np.errstate(divide="ignore"):  # a weight of 0 is a log-weight of -inf: a term of 0
        log_a, log_b = np.log(donuts.w_a), np.log(donuts.w_b)
    n_starts = donuts.k * 3 + 1
    ends = np.empty((donuts.n, n_starts))
    pdf = np.empty((donuts.n, n_starts))
    best = np.empty(donuts.n, dtype=np.int64)
    # C-ordered float64 arrays only: another memory layout would compile (and cache) another
    # version of the kernel, seconds each
    inputs = [gmr_mean, donuts.m[:, :, 0], log_a, log_b, donuts.precision[:, 0, 0], donuts.r_a2, donuts.r_b2, donuts.ring_radius2()]
    _modes_1d_kernel(*(np.ascontiguousarray(a, dtype=float) for a in inputs), float(tol), ends, pdf, best)
    return ends, pdf, best


@numba.njit(**_UNCOUNTED)
def _density_1d(
    y: float,
    means: np.ndarray,
    log_a: np.ndarray,
    log_b: np.ndarray,
    half_precision: np.ndarray,
    r_a2: float,
    r_b2: float,
    floor: float,
) -> tuple[float, float, float]:
    """P_DMM and its first two derivatives at y for one input: (P, P', P'').

    means, log_a, log_b (K,): component means and the log-weights of the two Gaussian terms;
    half_precision (K,): 1 / (2 S_k); terms with exponent below ``floor`` are skipped. With
    d = y - m_k, a = w_a exp(-r_a^2 d^2 / (2 S_k)), b likewise: P = sum (a - b),
    P' = -sum (d / S_k)(r_a^2 a - r_b^2 b), P'' = sum (d / S_k)^2 (r_a^4 a - r_b^4 b) - (r_a^2 a - r_b^2 b) / S_k.
    """
    pdf = grad = hess = 0.0
    for k in range(means.size):
        d = y - means[k]
        quad = half_precision[k] * d * d
        exponent_a = log_a[k] - r_a2 * quad
        if exponent_a < floor:  # b <= a: both negligible
            continue
        a = math.exp(exponent_a)
        b = math.exp(log_b[k] - r_b2 * quad)
        u = 2.0 * half_precision[k] * d  # d / S_k
        slope = r_a2 * a - r_b2 * b
        pdf += a - b
        grad -= u * slope
        hess += u * u * (r_a2 * r_a2 * a - r_b2 * r_b2 * b) - 2.0 * half_precision[k] * slope
    return pdf, grad, hess


@numba.njit(cache=True, nogil=True)
def _modes_1d_kernel(
    gmr_mean: np.ndarray,
    means: np.ndarray,
    log_a: np.ndarray,
    log_b: np.ndarray,
    precision: np.ndarray,
    r_a2: np.ndarray,
    r_b2: np.ndarray,
    ring: np.ndarray,
    tol: float,
    ends: np.ndarray,
    pdf: np.ndarray,
    best: np.ndarray,
) -> None:
    """Every start of every input climbed to its top, and the highest per input.

    Inputs: gmr_mean (N,); means, log_a, log_b (N, K): component means and log-weights of the
    two Gaussian terms; precision (K,) = 1 / S_k; r_a2, r_b2, ring (N,): squared radii and the
    squared Mahalanobis radius of the donuts' highest ring. Outputs: ends and pdf (N, 3 K + 1),
    in this order: each component's mean and its ring point above and
    below, then the GMR mean; pdf -inf for starts left out; best (N,): the highest (see
    :func:`_highest`).

    Starts left out: P_DMM is at least h_j max D_j for every j (all terms are >= 0), so a
    component whose h_k max D_k is below 1e-7 of the largest adds less than 1e-7 of the maximum
    anywhere: its starts could only find the modes of other components, which their own starts
    find. A donut with a hole is lowest at its mean, whose climb only reaches its ring, whose
    points are starts: each component climbs either its mean (no hole) or its ring points.

    Why compiled (numba): each input has a handful of starts, each a few Newton steps of a sum
    over K terms; as NumPy array operations the climb was bound by their number per step.
    """
    n, n_components = means.shape
    half_precision = 0.5 * precision
    sigma = math.sqrt(1.0 / precision.min())  # the widest component's standard deviation
    narrowest_variance = 1.0 / precision.max()
    peaks = np.empty(n_components)
    for i in range(n):
        m_i, a_i, b_i, ra2, rb2, q = means[i], log_a[i], log_b[i], r_a2[i], r_b2[i], ring[i]
        hole = q > 1e-12
        for k in range(n_components):  # each donut's highest density h_k max D_k
            peaks[k] = math.exp(a_i[k] - 0.5 * ra2 * q) - math.exp(b_i[k] - 0.5 * rb2 * q)
        top = peaks.max()
        # terms below e^-46 of the highest peak are skipped (see _NEGLIGIBLE)
        floor = math.log(top) + _NEGLIGIBLE if top > 0 else -np.inf
        first_radius = math.sqrt(narrowest_variance / rb2)
        for s in range(3 * n_components + 1):
            k, slot = divmod(s, 3)
            if k == n_components:
                start, climb = gmr_mean[i], True
            else:
                offset = math.sqrt(q / precision[k])
                start = m_i[k] + (0.0 if slot == 0 else offset if slot == 1 else -offset)
                climb = peaks[k] >= 1e-7 * top and (slot == 0) != hole
            ends[i, s] = start
            pdf[i, s] = -np.inf
            if climb:
                ends[i, s], pdf[i, s] = _climb_start(
                    start, s == 3 * n_components, m_i, a_i, b_i, half_precision, ra2, rb2, floor, first_radius, sigma, tol
                )
        best[i] = _highest(ends[i], pdf[i])


@numba.njit(**_UNCOUNTED)
def _climb_start(
    start: float,
    gmr_start: bool,
    means: np.ndarray,
    log_a: np.ndarray,
    log_b: np.ndarray,
    half_precision: np.ndarray,
    r_a2: float,
    r_b2: float,
    floor: float,
    first_radius: float,
    sigma: float,
    tol: float,
) -> tuple[float, float]:
    """One start's climb (see _modes_1d_kernel): returns the end point and its density.

    Newton steps on ln P (a peak of a sum of Gaussians is nearly quadratic in the log) inside a
    trust radius, a step of the radius uphill where ln P is not concave; a step that does not
    raise P is refused and the radius shrinks to a quarter of it, so a start only climbs. The
    first radius is the narrowest donut's standard deviation for a Newton step and a tenth of it
    for a gradient step, so that a start climbs its own hill rather than leaping a valley.
    """
    point = start
    p, g, h = _density_1d(point, means, log_a, log_b, half_precision, r_a2, r_b2, floor)
    bend = g * g - h * p  # -P^2 (ln P)'': > 0 where ln P is concave
    # The GMR mean where ln P is not concave sits in a hole or a valley: its climb would end on
    # the side of a neighbouring ring or peak, which the components' own starts climb.
    if gmr_start and bend <= 0:
        return point, p
    radius = (1.0 if h < 0 else 0.1) * first_radius
    for _ in range(_MAX_NEWTON):
        # The rise of ln P a Newton step promises is 0.5 P'^2 / bend: below 1e-14 the start is
        # at its top (about 1e-7 standard deviations away)
        if bend > 0 and g * g <= 2e-14 * bend:
            break
        newton = bend > 0
        step = g * p / bend if newton else math.copysign(radius, g)
        if not math.isfinite(step):
            step = math.copysign(radius, g)
        length = abs(step)
        # a whole Newton step promising a rise of ln P below 1e-8 ends the climb: Newton
        # converges quadratically, so the point reached is far closer still to the top
        last = newton and length <= radius and g * g <= 2e-8 * bend
        length = min(length, radius)
        trial = point + math.copysign(length, step)
        p_t, g_t, h_t = _density_1d(trial, means, log_a, log_b, half_precision, r_a2, r_b2, floor)
        # a short step changing the density by less than 1e-10 of itself: at the top
        flat = abs(p_t - p) <= 1e-10 * p and length <= 1e-3 * sigma
        if p_t > p:
            point, p, g, h = trial, p_t, g_t, h_t
            bend = g * g - h * p
            radius = max(radius, 4.0 * length)
        else:
            radius = 0.25 * length
        if length <= tol * sigma or radius <= tol * sigma or flat or last:
            break
    return point, p


def starts_per_input(k: int, o: int, holes: bool = True) -> int:
    """The climbs' slots per input of :func:`modes_nd` (K components, O outputs): each component's
    mean, with ``holes`` its 2 O ring points, the GMR mean and the late slots."""
    return k * ((1 + 2 * o) if holes else 1) + 1 + _LATE_SLOTS


def modes_nd(donuts: _Donuts, gmr_mean: np.ndarray, tol: float,
             holes: bool | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The climb for several outputs, compiled: end points (N, S, O) and their pdf (N, S) for the
    starts of :func:`_modes_nd_kernel` (pdf -inf for those left out), and the index (N,) of the
    highest. ``holes``: whether any donut has a hole, so the ring points are starts (default:
    whether one of these inputs' has; a path climbed in parts passes the whole path's, so every
    part has the same S).

    The climb runs on outputs divided by their widest component standard deviation, so that
    outputs in different units (rad and rad/s) get trust radii and gradient steps of one scale;
    the density is the same function of the scaled point (the quadratic forms do not change), so
    only the end points are scaled back.
    """
    with np.errstate(divide="ignore"):  # a weight of 0 is a log-weight of -inf: a term of 0
        log_a, log_b = np.log(donuts.w_a), np.log(donuts.w_b)
    unit = np.sqrt(np.diagonal(donuts.covariances, axis1=1, axis2=2).max(axis=0))  # (O,)
    precision = donuts.precision * unit[:, None] * unit[None, :]  # of the scaled outputs
    # ring offsets per unit Mahalanobis radius along each principal axis: (K, O axes, O coords)
    axes = np.swapaxes(donuts.eigenvectors, 1, 2) * np.sqrt(donuts.eigenvalues)[:, :, None] / unit
    ring = donuts.ring_radius2()
    # the ring points are starts only where a donut has a hole: without any, one start per component
    n_starts = starts_per_input(donuts.k, donuts.o, holes=bool(np.any(ring > 1e-12)) if holes is None else holes)
    ends = np.empty((donuts.n, n_starts, donuts.o))
    pdf = np.empty((donuts.n, n_starts))
    best = np.empty(donuts.n, dtype=np.int64)
    # C-ordered float64 arrays only: one compiled (and cached) version of the kernel
    inputs = [gmr_mean, donuts.m, log_a, log_b, precision, axes, donuts.r_a2, donuts.r_b2, ring, unit]
    _modes_nd_kernel(*(np.ascontiguousarray(a, dtype=float) for a in inputs), float(tol), ends, pdf, best)
    return ends, pdf, best


@numba.njit(**_UNCOUNTED)
def _density_nd(
    y: np.ndarray,
    means: np.ndarray,
    log_a: np.ndarray,
    log_b: np.ndarray,
    precision: np.ndarray,
    low: np.ndarray,
    used: np.ndarray,
    r_a2: float,
    r_b2: float,
    floor: float,
    diff: np.ndarray,
    u: np.ndarray,
    grad: np.ndarray,
    hess: np.ndarray,
    derivatives: bool = True,
) -> float:
    """P_DMM at y (O,) for one input, its gradient into ``grad`` (O,) and Hessian into ``hess`` (O, O)
    (left as they are when ``derivatives`` is False: a climb's last point needs only P).

    means (K, O), log_a, log_b (K,): component means and log-weights of the two Gaussian terms;
    precision (K, O, O) = S_k^-1 and low (K,) its smallest eigenvalue; used: the components
    summed (the others are negligible everywhere); diff, u (O,): work space. Terms with exponent
    below ``floor`` are skipped, most of them before their quadratic form, from its lower bound
    low_k |d|^2. With d = y - m_k, u = S_k^-1 d, q = d.u, a = w_a exp(-r_a^2 q / 2) and b likewise:
    P = sum (a - b), grad = -sum (r_a^2 a - r_b^2 b) u,
    hess = sum (r_a^4 a - r_b^4 b) u u^T - (r_a^2 a - r_b^2 b) S_k^-1.
    """
    n_out = means.shape[1]
    pdf = 0.0
    grad[:] = 0.0
    hess[:, :] = 0.0
    for k in used:
        distance2 = 0.0
        for o in range(n_out):
            diff[o] = y[o] - means[k, o]
            distance2 += diff[o] * diff[o]
        if log_a[k] - 0.5 * r_a2 * low[k] * distance2 < floor:  # far: negligible
            continue
        quad = 0.0
        for o in range(n_out):
            total = 0.0
            for p in range(n_out):
                total += precision[k, o, p] * diff[p]
            u[o] = total
            quad += diff[o] * total
        exponent_a = log_a[k] - 0.5 * r_a2 * quad
        if exponent_a < floor:  # b <= a: both negligible
            continue
        exponent_b = log_b[k] - 0.5 * r_b2 * quad
        a = exp_nonpositive(exponent_a if exponent_a > LOWEST else LOWEST)
        b = exp_nonpositive(exponent_b if exponent_b > LOWEST else LOWEST)
        slope = r_a2 * a - r_b2 * b
        bend = r_a2 * r_a2 * a - r_b2 * r_b2 * b
        pdf += a - b
        if not derivatives:
            continue
        for o in range(n_out):
            grad[o] -= slope * u[o]
            for p in range(o + 1):
                hess[o, p] += bend * u[o] * u[p] - slope * precision[k, o, p]
    for o in range(n_out):
        for p in range(o):
            hess[p, o] = hess[o, p]
    return pdf


@numba.njit(**_UNCOUNTED)
def _newton_direction(pdf: float, grad: np.ndarray, hess: np.ndarray, factor: np.ndarray, out: np.ndarray) -> int:
    """The Newton step on ln P into ``out`` (O,): 0 where ln P is concave (the step itself), 1
    where it is not (a direction only: the step with M shifted to positive definite), -1 if
    there is none (a zero gradient where ln P is not concave).

    With M = g g^T - P H = -P^2 (ln P)'' (positive definite where ln P is concave), the step is
    P M^-1 g (the one-output climb's g P / bend). Where M is not positive definite, the smallest
    of the shifts M + mu I (mu = 1e-6 ... 1e2 times M's largest diagonal) that is gives a
    direction that follows the curvature across a curved ridge of P, where a gradient step
    would zig-zag. M is factored by Cholesky into ``factor`` (a hand-written loop: O is 2 to 5,
    far below what a LAPACK call is worth).
    """
    n = grad.size
    scale = 0.0
    for i in range(n):
        scale = max(scale, abs(grad[i] * grad[i] - pdf * hess[i, i]))
    for attempt in range(6):
        shift = 0.0 if attempt == 0 else scale * 10.0 ** (2 * attempt - 8)
        if attempt > 0 and not shift > 0.0:
            return -1
        if _cholesky_shifted(pdf, grad, hess, shift, factor):
            break
    else:
        return -1
    for i in range(n):  # forward then back substitution: out = P M^-1 g
        total = grad[i]
        for m in range(i):
            total -= factor[i, m] * out[m]
        out[i] = total / factor[i, i]
    for i in range(n - 1, -1, -1):
        total = out[i]
        for m in range(i + 1, n):
            total -= factor[m, i] * out[m]
        out[i] = total / factor[i, i]
    for i in range(n):
        out[i] *= pdf
    return 0 if shift == 0.0 else 1


@numba.njit(**_UNCOUNTED)
def _cholesky_shifted(pdf: float, grad: np.ndarray, hess: np.ndarray, shift: float, factor: np.ndarray) -> bool:
    """Cholesky factor of g g^T - P H + shift I into ``factor``; False if not positive definite."""
    n = grad.size
    for i in range(n):
        for j in range(i + 1):
            total = grad[i] * grad[j] - pdf * hess[i, j] + (shift if i == j else 0.0)
            for m in range(j):
                total -= factor[i, m] * factor[j, m]
            if i == j:
                if not total > 0.0:
                    return False
                factor[i, i] = math.sqrt(total)
            else:
                factor[i, j] = total / factor[j, j]
    return True


@numba.njit(cache=True, nogil=True)
def _modes_nd_kernel(
    gmr_mean: np.ndarray,
    means: np.ndarray,
    log_a: np.ndarray,
    log_b: np.ndarray,
    precision: np.ndarray,
    axes: np.ndarray,
    r_a2: np.ndarray,
    r_b2: np.ndarray,
    ring: np.ndarray,
    unit: np.ndarray,
    tol: float,
    ends: np.ndarray,
    pdf: np.ndarray,
    best: np.ndarray,
) -> None:
    """Every start of every input climbed to its top, and the highest per input: several outputs.

    Inputs: gmr_mean (N, O); means (N, K, O); log_a, log_b (N, K): log-weights of the two
    Gaussian terms; precision (K, O, O) = S_k^-1; axes (K, O, O): row j the offset of one
    Mahalanobis unit along S_k's j-th principal axis; r_a2, r_b2, ring (N,): squared radii and
    the squared Mahalanobis radius of the donuts' highest ring; unit (O,): the scale of each
    output (the means, the axes and the precisions are of the outputs divided by it, see
    :func:`modes_nd`; gmr_mean and means are divided here). Outputs: ends (N, S, O) and pdf
    (N, S) with S = K (1 + 2 O) + 1 + ``_LATE_SLOTS``, in this order: each component's mean, its
    ring points on its O principal axes (+), the same (-), the GMR mean, then the slots of tops
    followed back (below); without a hole in any donut, S = K + 1 + ``_LATE_SLOTS`` (no ring
    points); pdf -inf for starts left out and slots unused; best (N,): the highest (see
    :func:`_highest`).

    Starts as in :func:`_modes_1d_kernel`: components whose h_k max D_k is below 1e-7 of the
    largest are left out (they add less than that anywhere); a donut without a hole climbs from
    its mean. A donut with a hole climbs from its ring points *and* its mean: with several
    outputs the ring is a shell, not two points, and the climb from the hole follows the other
    components' pull to the part of the shell they raise (what BFGS from that mean does). The
    GMR mean is always climbed (the thesis' start). Climbed so at every input, the result is not
    below BFGS from the GMR mean or from any component mean (tested on random mixtures, to the
    climbs' precision).

    Along a path the tops are followed instead. The inputs of :func:`_fresh_inputs` (the first,
    the last, and one wherever the mixture has changed by ``_TRACK_CHANGE``) climb all their
    starts afresh; in between, each start climbs from where it ended at i-1, carried on along the
    parabola through its last ends (:func:`_follow_point`, :func:`_predict`): starts that ended
    on one top climb once, tops below ``_FOLLOW_SHARE`` of the highest are let go, and a climb
    takes one or two density evaluations instead of the five or so from a component mean. An
    input where a followed top is lost (``_TRACK_JUMP``, ``_TRACK_DROP``: it vanished under its
    climb) is climbed afresh. At each fresh input the tops above ``_TOP_SHARE`` of the highest
    that the following did not reach (born, or risen from a top let go, inside the block) are
    followed back through the block into late slots of their own (:func:`_follow_back`, which
    climbs a row afresh where such a top moved too far to follow); when there are more of them
    than late slots, the block is climbed afresh. What this can miss is a top born and gone
    again between two fresh inputs.

    (Both cores with numba's prange took the time down by 1.3-1.6x on an idle machine and up
    by about 3x on a busy one, where a thread waits for the other at every join: left out.)

    Each climb is :func:`_climb_start_nd`; only the components whose log-weight is above the
    floor of negligible terms enter its density sums. (Stopping a climb whose Newton step lands
    on a top already found saved a tenth of the evaluations and now and then stopped one short
    of a higher top close by on the same ring: left out.)

    Why compiled (numba): as for one output, each input has a handful of starts of a few Newton
    steps over K terms each; NumPy array operations over all starts at once were bound by their
    number per step (tens of microseconds each) and by evaluating every start to the last step.
    """
    n, n_components, n_out = means.shape
    gmr_mean = gmr_mean / unit  # the outputs scaled (see modes_nd), the end points scaled back below
    means = means / unit
    narrowest = np.inf
    sigma = 0.0
    for k in range(n_components):  # the scaled components' extreme standard deviations
        for j in range(n_out):
            length = math.sqrt(_dot(axes[k, j], axes[k, j]))
            narrowest = min(narrowest, length)
            sigma = max(sigma, length)
    low = np.empty(n_components)  # the smallest eigenvalue of each precision: 1 / largest variance
    for k in range(n_components):
        widest = 0.0
        for j in range(n_out):
            widest = max(widest, _dot(axes[k, j], axes[k, j]))
        low[k] = 1.0 / widest
    context = (gmr_mean, means, log_a, log_b, precision, axes, r_a2, r_b2, ring, low, narrowest, sigma, tol)
    n_starts = pdf.shape[1]
    fresh = _fresh_inputs(means, log_a, r_a2, r_b2)  # block b: inputs fresh[b] .. fresh[b + 1]
    n_blocks = fresh.size - 1
    fresh_ends = np.empty((fresh.size, n_starts, n_out))
    fresh_pdf = np.empty((fresh.size, n_starts))
    scratch = _scratch(n_components, n_out, n_starts)
    for j in range(fresh.size):
        _fresh_point(fresh[j], j, context, scratch, fresh_ends, fresh_pdf)
    ends[n - 1] = fresh_ends[n_blocks]
    pdf[n - 1] = fresh_pdf[n_blocks]
    block_ends = np.empty((_TRACK_LONGEST + 1, n_starts, n_out))
    block_pdf = np.empty((_TRACK_LONGEST + 1, n_starts))
    missed = np.empty(_LATE_SLOTS, dtype=np.int64)
    for b in range(n_blocks):  # the blocks between them
        first, last = fresh[b], fresh[b + 1]
        _follow_block(first, last, fresh_ends[b], fresh_pdf[b], fresh_ends[b + 1], fresh_pdf[b + 1], context,
                      scratch, block_ends, block_pdf, missed)
        ends[first:last] = block_ends[: last - first]
        pdf[first:last] = block_pdf[: last - first]
    for i in range(n):
        best[i] = _highest(ends[i, :, 0], pdf[i])
        for s in range(n_starts):
            for o in range(n_out):
                ends[i, s, o] *= unit[o]


@numba.njit(cache=True, nogil=True)
def _fresh_inputs(means: np.ndarray, log_a: np.ndarray, r_a2: np.ndarray, r_b2: np.ndarray) -> np.ndarray:
    """The inputs (F,) climbed afresh along a path of N inputs: the first, the last, and between
    them each where the mixture has changed by ``_TRACK_CHANGE`` since the fresh one before, or
    ``_TRACK_LONGEST`` inputs after it, or that does not continue the one before (see
    :func:`_change`). The change sums over a throw's phase path to about 100-130 whatever the number of
    points, so the benchmark's path has 57 fresh inputs at 1,000 points and 46 at 150 (with
    blocks of a fixed 8 inputs they were 126 and 19: the short paths, where the mixture changes
    most from one point to the next, now get more of them). With ``_TRACK_CHANGE`` = 2 every point
    of 162 whole-arm paths (seeds 0-7 and the benchmark's, 2 and 3 outputs, 1.5-3.5 m, 150-1,000
    points) got the mode of climbing it alone, to a relative 1e-8; with 3, one point was 1.3e-8
    lower, and with 4 and 6 one point kept a top 0.4 % lower. (4 would save about 5 %.)
    """
    n = means.shape[0]
    fresh = np.empty(n, dtype=np.int64)
    fresh[0] = 0
    count = 1
    change = 0.0
    for i in range(1, n):
        change += _change(i, means, log_a, r_a2, r_b2)
        if i == n - 1 or change >= _TRACK_CHANGE or i - fresh[count - 1] >= _TRACK_LONGEST:
            fresh[count] = i
            count += 1
            change = 0.0
    return fresh[:count]


@numba.njit(**_UNCOUNTED)
def _follow_block(
    first: int,
    last: int,
    first_ends: np.ndarray,
    first_pdf: np.ndarray,
    last_ends: np.ndarray,
    last_pdf: np.ndarray,
    context: tuple,
    scratch: tuple,
    block_ends: np.ndarray,
    block_pdf: np.ndarray,
    missed: np.ndarray,
) -> None:
    """Inputs first .. last - 1 into rows 0 .. last - first - 1 of block_ends (R, S, O) and
    block_pdf (R, S), from the fresh climbs at ``first`` and ``last`` (S, O) and (S,) (see
    :func:`_modes_nd_kernel`); row last - first is work space."""
    gmr_mean, means, log_a, log_b, precision, axes, r_a2, r_b2, ring, low, narrowest, sigma, tol = context
    rows = last - first
    _copy(block_ends[0], first_ends)
    _copy(block_pdf[0], first_pdf)
    _release(scratch)
    for row in range(1, rows + 1):
        i = first + row
        # (every input inside a block continues the one before: see _fresh_inputs)
        if (row < rows or _change(i, means, log_a, r_a2, r_b2) < np.inf) and _follow_point(i, row, context, scratch, block_ends, block_pdf):
            continue
        # a top lost: climb this input afresh, and follow back what it finds that was not followed
        if row < rows:
            _refollow(i, row, context, scratch, block_ends, block_pdf)
            _find_back(block_ends[row], block_pdf[row], block_ends[row - 1], block_pdf[row - 1], first, row, context, scratch, block_ends, block_pdf, missed)
        else:
            _find_back(last_ends, last_pdf, block_ends[row - 1], block_pdf[row - 1], first, row, context, scratch, block_ends, block_pdf, missed)
            return
    _find_back(last_ends, last_pdf, block_ends[rows], block_pdf[rows], first, rows, context, scratch, block_ends, block_pdf, missed)


@numba.njit(**_UNCOUNTED)
def _refollow(i: int, row: int, context: tuple, scratch: tuple, ends: np.ndarray, pdf: np.ndarray) -> None:
    """Input i, where following lost a top, climbed afresh into ends[row], pdf[row]; a start whose
    fresh climb ends on the top its followed climb reached (a top that moved by more than
    ``_TRACK_JUMP`` from where it was, with nothing to predict the move by) counts as followed
    for one step, so that the next input predicts it along the line through its last two ends
    (else a top that moves that fast is lost at every input)."""
    a_i, b_i, peaks, active, start, point, work, square, tracked, dropped, kept_ends, kept_pdf, moved, followed = scratch
    _copy(kept_ends, ends[row])  # the followed climbs up to the lost one
    _copy(kept_pdf, pdf[row])
    _fresh_point(i, row, context, scratch, ends, pdf)
    for s in range(pdf.shape[1]):
        if kept_pdf[s] > -np.inf and pdf[row, s] > -np.inf and _distance2(kept_ends[s], ends[row, s]) <= _FOUND_TOP**2:
            followed[s] = 1


@numba.njit(**_UNCOUNTED)
def _find_back(
    fresh_ends: np.ndarray,
    fresh_pdf: np.ndarray,
    followed_ends: np.ndarray,
    followed_pdf: np.ndarray,
    first: int,
    row: int,
    context: tuple,
    scratch: tuple,
    block_ends: np.ndarray,
    block_pdf: np.ndarray,
    missed: np.ndarray,
) -> None:
    """The tops of a fresh climb of input first + row (S, O) and (S,) that the followed climbs
    (S, O) and (S,) did not reach (:func:`_missed_tops`), followed back through rows row - 1 .. 1
    (:func:`_follow_back`); when there are more than ``_LATE_SLOTS`` of them, those rows are
    climbed afresh instead."""
    n_missed = _missed_tops(fresh_ends, fresh_pdf, followed_ends, followed_pdf, missed)
    if n_missed > _LATE_SLOTS:
        _climb_rows_afresh(first, 1, row, context, scratch, block_ends, block_pdf)
        return
    for j in range(n_missed):
        _follow_back(fresh_ends[missed[j]], first, row, context, scratch, block_ends, block_pdf)


@numba.njit(cache=True, nogil=True)
def _scratch(n_components: int, n_out: int, n_starts: int) -> tuple:
    """Work space of :func:`_modes_nd_kernel`: per-input log-weights, peaks and
    the active components, a start and an end point, the climb's vectors and matrices, the
    starts climbed at the current input, the starts let go in the current block, a row's
    followed climbs with the tops a fresh climb of it adds (:func:`_follow_back`), and how many
    steps each start has been followed for (:func:`_predict`)."""
    return (
        np.empty(n_components), np.empty(n_components), np.empty(n_components), np.empty(n_components, dtype=np.int64),
        np.empty(n_out), np.empty(n_out), np.empty((8, n_out)), np.empty((3, n_out, n_out)),
        np.empty(n_starts, dtype=np.int64), np.zeros(n_starts, dtype=np.bool_),
        np.empty((n_starts, n_out)), np.empty(n_starts), np.empty(2, dtype=np.int64), np.zeros(n_starts, dtype=np.int64),
    )


@numba.njit(**_UNCOUNTED)
def _release(scratch: tuple) -> None:
    """No start let go, none followed (at a fresh input or a block's start)."""
    scratch[9][:] = False
    scratch[13][:] = 0


@numba.njit(**_UNCOUNTED)
def _weigh_point(i: int, context: tuple, scratch: tuple) -> tuple[float, float, int, float]:
    """Input i's log-weights relative to the largest into the scratch (the climbs see P / e^M with
    M the largest log-weight: every exponent is then <= 0, for the compiled exp of
    rlff.model.fastexp), each donut's peak h_k max D_k and the components above the floor of
    negligible terms. Returns (e^M, the floor, the number of active components, the largest peak)."""
    gmr_mean, means, log_a, log_b, precision, axes, r_a2, r_b2, ring, low, narrowest, sigma, tol = context
    a_i, b_i, peaks, active, start, point, work, square, tracked, dropped, kept_ends, kept_pdf, moved, followed = scratch
    ra2, rb2, q = r_a2[i], r_b2[i], ring[i]
    highest = _largest(log_a[i])
    for k in range(a_i.size):
        a_i[k] = log_a[i, k] - highest
        b_i[k] = log_b[i, k] - highest
        exponent_a, exponent_b = a_i[k] - 0.5 * ra2 * q, b_i[k] - 0.5 * rb2 * q  # both <= 0
        peaks[k] = exp_nonpositive(max(exponent_a, LOWEST)) - exp_nonpositive(max(exponent_b, LOWEST))
    top = _largest(peaks)
    floor = math.log(top) + _NEGLIGIBLE if top > 0 else -np.inf
    n_active = 0
    for k in range(a_i.size):  # a term's exponent is at most its log-weight
        if a_i[k] >= floor:
            active[n_active] = k
            n_active += 1
    return math.exp(highest), floor, n_active, top


@numba.njit(**_UNCOUNTED, inline="always")
def _slots(pdf: np.ndarray, n_components: int) -> int:
    """Starts per component in the layout of ``pdf`` (N, S): 1 + 2 O with ring points, else 1."""
    return (pdf.shape[1] - 1 - _LATE_SLOTS) // n_components


@numba.njit(**_UNCOUNTED)
def _prepare_point(
    i: int, row: int, context: tuple, scratch: tuple, ends: np.ndarray, pdf: np.ndarray
) -> tuple[float, float, int, float, int]:
    """:func:`_weigh_point` of input i, and the starts it climbs (see :func:`_modes_nd_kernel`)
    into the scratch's list; in ends[row], pdf[row] the starts left out get pdf -inf and their
    component's mean, the late slots pdf -inf and the GMR mean. Returns :func:`_weigh_point`'s
    and the number of starts."""
    gmr_mean, means, log_a, log_b, precision, axes, r_a2, r_b2, ring, low, narrowest, sigma, tol = context
    a_i, b_i, peaks, active, start, point, work, square, tracked, dropped, kept_ends, kept_pdf, moved, followed = scratch
    scale, floor, n_active, top = _weigh_point(i, context, scratch)
    n_components, n_out = means.shape[1], means.shape[2]
    slots = _slots(pdf, n_components)
    n_slots = 0
    hole = ring[i] > 1e-12
    for k in range(n_components):
        kept = peaks[k] >= 1e-7 * top
        for slot in range(slots):
            s = k * slots + slot
            if kept and (slot == 0 or hole):
                tracked[n_slots] = s
                n_slots += 1
            else:
                pdf[row, s] = -np.inf
                for o in range(n_out):
                    ends[row, s, o] = means[i, k, o]
    tracked[n_slots] = n_components * slots  # the GMR mean
    for s in range(n_components * slots + 1, pdf.shape[1]):
        pdf[row, s] = -np.inf
        _copy(ends[row, s], gmr_mean[i])
    return scale, floor, n_active, top, n_slots + 1


@numba.njit(**_UNCOUNTED)
def _fresh_point(i: int, row: int, context: tuple, scratch: tuple, ends: np.ndarray, pdf: np.ndarray) -> None:
    """Input i: every start climbed from where :func:`_modes_nd_kernel` says, into ends[row], pdf[row]."""
    a_i, b_i, peaks, active, start, point, work, square, tracked, dropped, kept_ends, kept_pdf, moved, followed = scratch
    scale, floor, n_active, top, n_slots = _prepare_point(i, row, context, scratch, ends, pdf)
    _release(scratch)
    for t in range(n_slots):
        s = tracked[t]
        k, slot = divmod(s, _slots(pdf, peaks.size))
        pdf[row, s] = _climb_fresh(i, k, slot, context, scratch, active[:n_active], floor) * scale
        _copy(ends[row, s], point)


@numba.njit(**_UNCOUNTED)
def _climb_fresh(i: int, k: int, slot: int, context: tuple, scratch: tuple, used: np.ndarray, floor: float) -> float:
    """One start of input i climbed from component k's mean (slot 0), its ring point on a
    principal axis (slots 1 to 2 O) or, for k = K, the GMR mean; end point into the scratch's
    point, its density (relative to e^M, see :func:`_weigh_point`) returned."""
    gmr_mean, means, log_a, log_b, precision, axes, r_a2, r_b2, ring, low, narrowest, sigma, tol = context
    a_i, b_i, peaks, active, start, point, work, square, tracked, dropped, kept_ends, kept_pdf, moved, followed = scratch
    n_out = means.shape[2]
    if k == means.shape[1]:
        _copy(start, gmr_mean[i])
    else:
        _copy(start, means[i, k])
        if slot > 0:  # on the ring, along a principal axis
            sign = 1.0 if slot <= n_out else -1.0
            axis = axes[k, (slot - 1) % n_out]
            for o in range(n_out):
                start[o] += sign * math.sqrt(ring[i]) * axis[o]
    return _climb_from(i, start, context, scratch, used, floor)


@numba.njit(**_UNCOUNTED)
def _climb_from(i: int, begin: np.ndarray, context: tuple, scratch: tuple, used: np.ndarray, floor: float) -> float:
    """:func:`_climb_start_nd` of input i from ``begin`` (O,) over the components ``used``, with the
    first trust radius of the narrowest donut; end point into the scratch's point, its density
    (relative to e^M, see :func:`_weigh_point`) returned."""
    gmr_mean, means, log_a, log_b, precision, axes, r_a2, r_b2, ring, low, narrowest, sigma, tol = context
    a_i, b_i, peaks, active, start, point, work, square, tracked, dropped, kept_ends, kept_pdf, moved, followed = scratch
    return _climb_start_nd(
        begin, means[i], a_i, b_i, precision, low, used, r_a2[i], r_b2[i], floor, narrowest / math.sqrt(r_b2[i]), sigma,
        tol, point, work, square,
    )


@numba.njit(**_UNCOUNTED)
def _follow_point(i: int, row: int, context: tuple, scratch: tuple, ends: np.ndarray, pdf: np.ndarray) -> bool:
    """Input i into ends[row], pdf[row] from the previous input in row - 1: each start that
    climbed there climbs from where it ended (once per top, see :func:`_predict`), a start new
    at i afresh, a top below ``_FOLLOW_SHARE`` of the highest is let go. False when a followed
    top is lost (``_TRACK_JUMP``; the row is then incomplete)."""
    gmr_mean, means, log_a, log_b, precision, axes, r_a2, r_b2, ring, low, narrowest, sigma, tol = context
    a_i, b_i, peaks, active, start, point, work, square, tracked, dropped, kept_ends, kept_pdf, moved, followed = scratch
    scale, floor, n_active, top, n_slots = _prepare_point(i, row, context, scratch, ends, pdf)
    used = active[:n_active]
    slots = _slots(pdf, means.shape[1])
    lowest_followed = _FOLLOW_SHARE * _largest(pdf[row - 1])
    for t in range(n_slots):
        s = tracked[t]
        k, slot = divmod(s, slots)
        if not dropped[s] and pdf[row - 1, s] == -np.inf:  # a start new at this input
            pdf[row, s] = _climb_fresh(i, k, slot, context, scratch, used, floor) * scale
            _copy(ends[row, s], point)
            followed[s] = 0
            continue
        if dropped[s] or pdf[row - 1, s] < lowest_followed:  # a low top: let go
            dropped[s] = True
            followed[s] = 0
            pdf[row, s] = -np.inf
            _copy(ends[row, s], ends[row - 1, s])
            continue
        same = -1
        for other in tracked[:t]:  # a start that ended on the same top was followed already
            if pdf[row - 1, other] > -np.inf and _distance2(ends[row - 1, s], ends[row - 1, other]) <= _SAME_TOP**2:
                same = other
                break
        if same >= 0:
            pdf[row, s] = pdf[row, same]
            _copy(ends[row, s], ends[row, same])
            followed[s] += 1
            continue
        _predict(ends, row, s, followed[s], start)
        climbed = _climb_from(i, start, context, scratch, used, floor)
        pdf[row, s] = climbed * scale
        _copy(ends[row, s], point)
        if _distance2(point, start) > _TRACK_JUMP**2 or not climbed * scale > _TRACK_DROP * pdf[row - 1, s]:
            return False  # not where it was headed, or far lower than it was: lost
        followed[s] += 1
    return True


@numba.njit(**_UNCOUNTED)
def _predict(ends: np.ndarray, row: int, s: int, followed: int, start: np.ndarray) -> None:
    """Where start s's top is expected in ``row``, into ``start`` (O,), from its ends in the rows
    before and the number of steps ``followed`` that led to its end in row - 1 by following (a
    fresh climb can put a start on another top): the parabola through the last three ends when
    two steps were followed, the line through the last two after one, else where it was (a
    predictor for the climb, which then corrects; a top that moves by more than a component's
    width from one input to the next is then still found in a step or two)."""
    _copy(start, ends[row - 1, s])
    if followed >= 2 and row >= 3:
        for o in range(start.size):
            start[o] += 2.0 * ends[row - 1, s, o] - 3.0 * ends[row - 2, s, o] + ends[row - 3, s, o]
    elif followed >= 1 and row >= 2:
        for o in range(start.size):
            start[o] += ends[row - 1, s, o] - ends[row - 2, s, o]


@numba.njit(**_UNCOUNTED)
def _change(i: int, means: np.ndarray, log_a: np.ndarray, r_a2: np.ndarray, r_b2: np.ndarray) -> float:
    """How much the mixture changed from input i-1 to input i (scaled outputs): the largest, over
    the components of relative weight above e^-7 (``_TRACK_RELEVANT``) at either, of the step of
    the mean plus that of the relative log-weight; inf where input i does not continue input i-1
    along a path (a relevant log-weight changes by more than ``_TRACK_LOG_WEIGHT``, or the donut
    radii by more than ``_TRACK_RADII``)."""
    if abs(r_a2[i] - r_a2[i - 1]) > _TRACK_RADII * r_a2[i - 1] or abs(r_b2[i] - r_b2[i - 1]) > _TRACK_RADII * r_b2[i - 1]:
        return np.inf
    highest, highest_before = _largest(log_a[i]), _largest(log_a[i - 1])
    step = 0.0
    for k in range(log_a.shape[1]):
        weight, weight_before = log_a[i, k] - highest, log_a[i - 1, k] - highest_before
        if weight < _TRACK_RELEVANT and weight_before < _TRACK_RELEVANT:
            continue
        if abs(weight - weight_before) > _TRACK_LOG_WEIGHT:
            return np.inf
        step = max(step, math.sqrt(_distance2(means[i, k], means[i - 1, k])) + abs(weight - weight_before))
    return step


@numba.njit(**_UNCOUNTED)
def _missed_tops(
    fresh_ends: np.ndarray, fresh_pdf: np.ndarray, followed_ends: np.ndarray, followed_pdf: np.ndarray, missed: np.ndarray
) -> int:
    """The tops of a fresh climb (S, O) with a pdf above ``_TOP_SHARE`` of the highest that no
    followed climb (S, O) of the same input reached: their starts into ``missed`` (as many as it
    holds, one per top), their number returned."""
    top = _largest(fresh_pdf)
    n_missed = 0
    for s in range(fresh_pdf.size):
        if not fresh_pdf[s] >= _TOP_SHARE * top:
            continue
        found = False
        for other in range(followed_pdf.size):
            if followed_pdf[other] > -np.inf and _distance2(fresh_ends[s], followed_ends[other]) <= _FOUND_TOP**2:
                found = True
                break
        for j in range(min(n_missed, missed.size)):  # another start of the same missed top
            if _distance2(fresh_ends[s], fresh_ends[missed[j]]) <= _FOUND_TOP**2:
                found = True
                break
        if not found:
            if n_missed < missed.size:
                missed[n_missed] = s
            n_missed += 1
    return n_missed


@numba.njit(**_UNCOUNTED)
def _follow_back(
    top_end: np.ndarray, first: int, rows: int, context: tuple, scratch: tuple, ends: np.ndarray, pdf: np.ndarray
) -> None:
    """A top ``top_end`` (O,) that a fresh climb at input first + rows found and the following
    missed, followed back through rows rows - 1 .. 1 (inputs first + row) into a late slot free in
    each, until it meets a top there or its climb jumps. A jump is a top born at the row after, or
    one that moved farther in a step than a climb follows (a component whose weight changes fast
    carries its top along): that row is climbed afresh, and a top there that the followed climbs
    had not reached (the same top, moved) is followed on from there. Where no late slot is free,
    or the fresh row holds more than one such top, the rows left are climbed afresh."""
    gmr_mean, means, log_a, log_b, precision, axes, r_a2, r_b2, ring, low, narrowest, sigma, tol = context
    a_i, b_i, peaks, active, begin, point, work, square, tracked, dropped, kept_ends, kept_pdf, moved, followed = scratch
    previous = top_end
    older = top_end  # the top two rows on, for the predictor (none yet)
    for row in range(rows - 1, 0, -1):
        i = first + row
        late = pdf.shape[1] - _LATE_SLOTS
        while late < pdf.shape[1] and pdf[row, late] > -np.inf:
            late += 1
        if late == pdf.shape[1]:
            _climb_rows_afresh(first, 1, row + 1, context, scratch, ends, pdf)
            return
        scale, floor, n_active, top = _weigh_point(i, context, scratch)
        _copy(begin, previous)
        if row + 2 <= rows:  # the line through the two tops before
            for o in range(begin.size):
                begin[o] += previous[o] - older[o]
        climbed = _climb_from(i, begin, context, scratch, active[:n_active], floor)
        if _distance2(point, begin) <= _TRACK_JUMP**2 and climbed > 0.0:
            for other in range(pdf.shape[1]):
                if pdf[row, other] > -np.inf and _distance2(point, ends[row, other]) <= _FOUND_TOP**2:
                    return
            pdf[row, late] = climbed * scale
            _copy(ends[row, late], point)
            older, previous = previous, ends[row, late]
            continue
        _copy(kept_ends, ends[row])  # jumped: this row afresh, against what was followed there
        _copy(kept_pdf, pdf[row])
        _fresh_point(i, row, context, scratch, ends, pdf)
        n_moved = _missed_tops(ends[row], pdf[row], kept_ends, kept_pdf, moved)
        if n_moved == 0:  # born at the row after
            return
        if n_moved > 1:
            _climb_rows_afresh(first, 1, row, context, scratch, ends, pdf)
            return
        older = previous = ends[row, moved[0]]


@numba.njit(**_UNCOUNTED)
def _climb_rows_afresh(
    first: int, start: int, stop: int, context: tuple, scratch: tuple, ends: np.ndarray, pdf: np.ndarray
) -> None:
    """Rows start .. stop - 1 (inputs first + row) of ends (R, S, O), pdf (R, S) climbed afresh."""
    for row in range(start, stop):
        _fresh_point(first + row, row, context, scratch, ends, pdf)


@numba.njit(**_UNCOUNTED, inline="always")
def _copy(destination: np.ndarray, source: np.ndarray) -> None:
    """destination[...] = source for two arrays of one shape, as a loop (a slice assignment needs
    numba's runtime: see :data:`_UNCOUNTED`)."""
    for index in np.ndindex(destination.shape):
        destination[index] = source[index]


@numba.njit(**_UNCOUNTED, inline="always")
def _largest(x: np.ndarray) -> float:
    """max(x) of a (S,) vector (-inf if empty), as a loop (ndarray.max needs numba's runtime)."""
    top = -np.inf
    for value in x:
        top = max(top, value)
    return top


@numba.njit(**_UNCOUNTED, inline="always")
def _distance2(x: np.ndarray, y: np.ndarray) -> float:
    """|x - y|^2 of two (O,) vectors."""
    total = 0.0
    for o in range(x.size):
        total += (x[o] - y[o]) * (x[o] - y[o])
    return total


@numba.njit(**_UNCOUNTED)
def _climb_start_nd(
    start: np.ndarray,
    means: np.ndarray,
    log_a: np.ndarray,
    log_b: np.ndarray,
    precision: np.ndarray,
    low: np.ndarray,
    used: np.ndarray,
    r_a2: float,
    r_b2: float,
    floor: float,
    first_radius: float,
    sigma: float,
    tol: float,
    point: np.ndarray,
    work: np.ndarray,
    square: np.ndarray,
) -> float:
    """One start's climb in O dimensions (see :func:`_modes_nd_kernel`): the end point into
    ``point`` (O,), its density returned; ``work`` (8, O) and ``square`` (3, O, O) are work space.

    Where ln P is not concave the step goes the radius along the direction of
    :func:`_newton_direction`. The stops are :func:`_climb_start`'s: the rise of ln P a Newton
    step promises, 0.5 g.M^-1 g, below 1e-14, a whole Newton step promising below 1e-8, or a step
    or radius below ``tol`` standard deviations (not the 1-D climb's "short step changing P by
    less than 1e-10": along the flat top of a ring that is no sign of the top).
    """
    diff, u, grad, step, trial, grad_t = work[0], work[1], work[2], work[3], work[4], work[5]
    hess, hess_t, factor = square[0], square[1], square[2]
    _copy(point, start)
    p = _density_nd(point, means, log_a, log_b, precision, low, used, r_a2, r_b2, floor, diff, u, grad, hess)
    kind = _newton_direction(p, grad, hess, factor, step)
    radius = (1.0 if kind == 0 else 0.1) * first_radius
    for _ in range(_MAX_NEWTON):
        if kind < 0:
            break
        length = math.sqrt(_dot(step, step))
        if not (math.isfinite(length) and length > 0.0):
            break
        last = False
        if kind == 0:
            rise = 0.5 * _dot(grad, step) / p
            if rise <= tol * tol:  # ln P within tol^2 of the top: as close as a step of tol
                break
            last = length <= radius and rise <= 1e-8
        if kind == 1 or length > radius:  # a direction only, or a Newton step beyond the radius
            step *= radius / length
            length = radius
        for o in range(point.size):
            trial[o] = point[o] + step[o]
        p_t = _density_nd(trial, means, log_a, log_b, precision, low, used, r_a2, r_b2, floor, diff, u, grad_t, hess_t,
                          not last)
        if p_t > p:
            _copy(point, trial)
            p = p_t
            _copy(grad, grad_t)
            _copy(hess, hess_t)
            radius = max(radius, 4.0 * length)
        else:
            radius = 0.25 * length
        if length <= tol * sigma or radius <= tol * sigma or last:
            break
        kind = _newton_direction(p, grad, hess, factor, step)
    return p


@numba.njit(**_UNCOUNTED, inline="always")
def _dot(x: np.ndarray, y: np.ndarray) -> float:
    """x . y of two (O,) vectors, as a loop (an array expression would allocate a temporary)."""
    total = 0.0
    for o in range(x.size):
        total += x[o] * y[o]
    return total


@numba.njit(**_UNCOUNTED)
def _highest(first: np.ndarray, pdf: np.ndarray) -> int:
    """Index of the highest of S end points, from their densities (S,) and first coordinates (S,):
    ties within a relative 1e-9 go to the larger first coordinate (the first such on an exact tie)."""
    tied = _largest(pdf) * (1.0 - 1e-9)
    choice = -1
    for s in range(pdf.size):
        if pdf[s] >= tied and (choice < 0 or first[s] > first[choice]):
            choice = s
    return choice

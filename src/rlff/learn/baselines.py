"""Baselines in the same harness as the update strategies.

All of them start from the Gaussian Mixture Regression mean for the target distance (the GMR
fitted once to the demonstrations labelled as every method sees them, :func:`known_labels`: with
the landings where they are known, else with the targets; no exploration), change only the speed
that decides the throw, and never ask for more than the joint's speed limit (``limit``, the
largest factor that keeps the GMR mean within it):

``imitation``
    The GMR mean, every time: pure imitation of the demonstrations.
``random``
    The GMR mean with its velocity scaled by a random factor exp(N(0, 0.15^2)) from the second
    attempt on: random perturbation around the demonstrations.
``sweep`` (binary feedback)
    A deterministic bracketing sweep of one speed factor: log factors 0, +w, -w, +2w, -2w, ...
    where w is the hit window's width in log speed (the window 2 x tolerance / Z in log
    distance over the range's elasticity 1.6, the prior that ``calibrate`` also has), one side
    only once the other reaches the speed limit. What an engineer does who is told only hit
    or miss.
``cma`` (distance feedback)
    CMA-ES (pycma) over two log speed factors, at the first and at the release angle, linearly
    blended along the path, fitness the absolute miss. Not run with binary feedback, where its
    0/1 fitness carries no direction and CMA-ES is a random search.
``secant`` (distance feedback)
    The plain engineering answer: a root search on one speed factor s of the GMR mean for
    miss(s) = 0. The first step uses that a projectile's range grows with the square of its
    speed, s1 = s0 sqrt(Z / L0); then secant steps, regula falsi (Illinois) once the hit is
    bracketed; never beyond the speed limit.
``gp-bo`` (distance feedback)
    Bayesian optimisation of the log speed factor x: a Gaussian process (scikit-learn's
    GaussianProcessRegressor, RBF plus white noise, hyper-parameters by maximum likelihood) of
    the signed miss about the range law through the first attempt, (Z + m0) exp(1.6 x) - Z, and
    the next x where the expected improvement of the absolute miss over the best so far is
    largest (in closed form, :func:`expected_improvement_of_abs`).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import replace
from functools import cached_property

import numpy as np
from scipy.stats import norm

from rlff.learn.attempt import Attempt
from rlff.learn.method import (
    Method,
    Problem,
    Proposal,
    finite_miss,
    release_speed,
    scale_speed,
)
from rlff.learn.windows import (  # the sweep's windows are the window search's, unordered by a prior
    LOWEST,
    RANGE_ELASTICITY,
    half_shifted,
    lattice,
    limit_band,
    lowest_for,
    reachable_top,
    window_width,
)

#: Largest change of the speed factor in one secant step (a factor, > 1).
_MAX_STEP = 1.5


class GmrBaseline(Method):
    """A baseline that scales the GMR mean for the target distance."""

    carries = True  # it starts at :attr:`start`, where carried hits point
    def __init__(self, problem: Problem):
        super().__init__(problem)
        model = problem.demonstrations_model()
        path = model.generate({"distance": problem.target}, problem.angles, exploration=0.0)
        #: The GMR mean's throw (every joint of it) for the target.
        self.throw = Proposal.of_outputs(path.angle, path.gmr_means, path.output_names, problem.target)
        self.angle, self.mean = self.throw.angle, self.throw.velocity
        fastest = float(np.max(np.abs(self.mean)))
        #: Largest speed factor that keeps the GMR mean within the joint's speed limit.
        self.limit = problem.max_speed / fastest if fastest > 0 else np.inf
        #: The run's own u0 as a speed factor on the GMR mean: 1, or where the arm's kinematics send
        #: its throw (``Problem.aim``). Attempts log their ``log_factor`` over it, as ``calibrate``
        #: logs over its u0: what a later basket carries (every baseline's; ``imitation``,
        #: ``random`` and ``cma`` logged none until 2026-12-07, and their hits carried nothing).
        self.aimed = problem.aim(self.throw) if problem.aim is not None else 1.0
        #: Speed factor the baseline's factors are relative to: u0 shifted to where earlier
        #: baskets' hits point (:mod:`rlff.learn.carry`): the same information ``calibrate`` gets.
        self.start = self.aimed * math.exp(problem.carried_shift)

    @cached_property
    def lowest(self) -> float:
        """Slowest log speed factor over :attr:`start` a search goes down to: as slow as a near
        basket needs by the arm's kinematics, as calibrate's (:func:`rlff.learn.windows.lowest_for`)."""
        problem = self.problem
        return lowest_for(problem.landing, self.start * release_speed(self.angle, self.mean), problem.target,
                          problem.tolerance, window_width(problem.target, problem.tolerance))

    def scaled(self, factor: np.ndarray | float, info: dict) -> Proposal:
        """The GMR mean with every velocity times ``start * factor`` (``factor`` scalar or shape
        (T,)), within the limit. A scalar factor beyond the limit is thrown at the limit, and
        ``info["log_factor"]`` says so: it had logged the factor asked for, so GP-BO fitted a
        throw at the limit as one at its start, and a hit at the limit carried an offset beyond it."""
        asked = np.asarray(factor, dtype=float)
        if asked.ndim == 0 and "log_factor" in info and asked > self.limit / self.start:
            info = {**info, "log_factor": round(math.log(self.limit / self.start) + self.problem.carried_shift, 4)}
        return replace(scale_speed(self.throw, np.minimum(self.start * asked, self.limit)), info=info)


class Imitation(GmrBaseline):
    """The GMR mean without exploration, every attempt."""

    name = "imitation"

    def propose(self, history: Sequence[Attempt]) -> Proposal:
        return self.scaled(1.0, {"log_factor": round(self.problem.carried_shift, 4)})


class RandomPerturbation(GmrBaseline):
    """The GMR mean times a random speed factor (log-normal, 15 %)."""

    name = "random"
    spread = 0.15

    def propose(self, history: Sequence[Attempt]) -> Proposal:
        factor = 1.0
        if history:
            rng = np.random.default_rng([self.problem.seed, len(history)])
            factor = float(np.exp(self.spread * rng.standard_normal()))
        return self.scaled(factor, {"factor": factor,
                                    "log_factor": round(math.log(factor) + self.problem.carried_shift, 4)})


class BracketingSweep(GmrBaseline):
    """Log speed factors 0, +w, -w, +2w, ... in steps w of the hit window (binary feedback).

    The windows are :class:`rlff.learn.windows.WindowSearch`'s (the lattice, one at the speed
    limit where the lattice's top window ends more than half a window below it, then the pass
    shifted by w / 2), thrown nearest the GMR mean's speed first, the faster of two equally near
    first, instead of in the order of a prior; after both passes, the last again.
    """

    name = "sweep"
    feedbacks = ("binary",)

    def __init__(self, problem: Problem):
        super().__init__(problem)
        width = window_width(problem.target, problem.tolerance)
        highest = reachable_top(float(np.log(self.limit / self.start)), width)
        centres = lattice(width, highest, self.lowest)
        if limit_band(centres, width, highest):
            centres = np.r_[centres, highest]
        first = _nearest_first(centres)
        #: The log speed factors in the order thrown, shape (N,).
        self.offsets = np.r_[first, _nearest_first(half_shifted(first, width, highest))]

    def propose(self, history: Sequence[Attempt]) -> Proposal:
        x = float(self.offsets[min(len(history), self.offsets.size - 1)])  # swept everything: stay at the end
        return self.scaled(float(np.exp(x)), {"log_factor": round(x + self.problem.carried_shift, 4)})


def _nearest_first(offsets: np.ndarray) -> np.ndarray:
    """``offsets`` by distance from 0, the larger of +-x first (the sweep's order)."""
    return np.asarray(sorted(offsets, key=lambda x: (abs(x), -x)), dtype=float)


class CmaSearch(GmrBaseline):
    """CMA-ES over the log speed factors at the first and the release angle."""

    name = "cma"
    feedbacks = ("distance",)
    sigma0 = 0.15

    def __init__(self, problem: Problem):
        super().__init__(problem)
        import cma

        # CMA-ES takes a seed of 0 for "from the clock" and seeds numpy with it (at most 2**32 - 1)
        seed = problem.seed % (2**32 - 1) + 1
        self.es = cma.CMAEvolutionStrategy([0.0, 0.0], self.sigma0, {"seed": seed, "verbose": -9, "verb_log": 0})
        self.pending: list[np.ndarray] = []  # candidates of the current generation, asked order
        self.fitness: list[float] = []
        self.seen = 0

    def propose(self, history: Sequence[Attempt]) -> Proposal:
        # Replay what this instance has not seen (after a resume it has seen nothing).
        while self.seen < len(history):
            if not self.pending or len(self.fitness) == len(self.pending):
                self._ask()
            self.fitness.append(self._fitness(history[self.seen]))
            self.seen += 1
            self._tell_if_complete()
        if not self.pending or len(self.fitness) == len(self.pending):
            self._ask()
        x = self.pending[len(self.fitness)]
        blend = np.linspace(0.0, 1.0, self.angle.size)
        factor = np.exp(x[0] + (x[1] - x[0]) * blend)
        # the log factor at the release, which decides where the ball goes, is what a later basket carries
        return self.scaled(factor, {"x": [float(v) for v in x],
                                    "log_factor": round(float(x[1]) + self.problem.carried_shift, 4)})

    def _ask(self) -> None:
        self.pending = [np.asarray(x, dtype=float) for x in self.es.ask()]
        self.fitness = []

    def _tell_if_complete(self) -> None:
        if len(self.fitness) == len(self.pending):
            self.es.tell(self.pending, self.fitness)
            self.pending = []
            self.fitness = []

    def _fitness(self, attempt: Attempt) -> float:
        return abs(finite_miss(attempt))


class SecantSearch(GmrBaseline):
    """Root search on one speed factor of the GMR mean within the speed limit (distance feedback)."""

    name = "secant"
    feedbacks = ("distance",)

    def propose(self, history: Sequence[Attempt]) -> Proposal:
        # the first throw at its start, or at the limit where the start lies beyond it: the
        # factor the secant steps from is the one thrown (it had stepped from 1.0, beyond the
        # limit, and after a long throw at the limit asked for the limit again until the run stopped)
        factors = [min(1.0, self.limit / self.start)]
        misses: list[float] = []
        for attempt in history:
            misses.append(finite_miss(attempt))
            factors.append(min(self._next(factors, misses), self.limit / self.start))
        factor = factors[len(history)]
        return self.scaled(factor, {"factor": factor,
                                    "log_factor": round(math.log(factor) + self.problem.carried_shift, 4)})

    def _next(self, factors: list[float], misses: list[float]) -> float:
        s = np.asarray(factors[: len(misses)])
        m = np.asarray(misses)
        target = self.problem.target
        if s.size == 1:
            ratio = target / max(target + m[0], 0.05 * target)
            step = float(np.sqrt(ratio))
        else:
            short, long = m < 0, m > 0
            if short.any() and long.any():
                # Illinois regula falsi on the closest bracket (halve the stale end's weight)
                i = int(np.flatnonzero(short)[np.argmax(m[short])])
                j = int(np.flatnonzero(long)[np.argmin(m[long])])
                mi, mj = m[i], m[j]
                if len(m) >= 3 and np.sign(m[-1]) == np.sign(m[-2]):
                    if m[-1] < 0:
                        mj = 0.5 * mj
                    else:
                        mi = 0.5 * mi
                return float(s[i] - mi * (s[j] - s[i]) / (mj - mi))
            a, b = s[-2], s[-1]
            ma, mb = m[-2], m[-1]
            step = 1.0 if mb == ma else float((b - mb * (b - a) / (mb - ma)) / b)
            if not np.isfinite(step) or step <= 0:
                step = _MAX_STEP if mb < 0 else 1.0 / _MAX_STEP
        step = float(np.clip(step, 1.0 / _MAX_STEP, _MAX_STEP))
        return float(s[-1] * step)


class GpSearch(GmrBaseline):
    """Bayesian optimisation of one log speed factor: a GP of the miss, expected improvement."""

    name = "gp-bo"
    feedbacks = ("distance",)

    def propose(self, history: Sequence[Attempt]) -> Proposal:
        from sklearn.gaussian_process import GaussianProcessRegressor
        from sklearn.gaussian_process.kernels import RBF, ConstantKernel, WhiteKernel

        shift = self.problem.carried_shift  # its log factors are logged over the run's u0
        if not history:
            return self.scaled(1.0, {"log_factor": round(shift, 4)})
        target = self.problem.target
        x = np.array([a.info["log_factor"] for a in history]) - shift
        miss = np.array([finite_miss(a) for a in history])
        reach = max(target + miss[0], 0.05 * target)  # the range law through the first attempt

        def prior(v: np.ndarray) -> np.ndarray:
            return reach * np.exp(RANGE_ELASTICITY * (v - x[0])) - target

        kernel = ConstantKernel(0.1, (1e-3, 10.0)) * RBF(0.3, (0.05, 3.0)) + WhiteKernel(1e-4, (1e-6, 1e-2))
        gp = GaussianProcessRegressor(kernel, random_state=self.problem.seed, n_restarts_optimizer=0)
        with warnings.catch_warnings():  # a bound reached on a handful of points is no news
            warnings.simplefilter("ignore")
            gp.fit(x[:, None], miss - prior(x))
        highest = min(float(np.log(self.limit / self.start)), -LOWEST)
        grid = np.linspace(self.lowest, highest, 481)
        mean, std = gp.predict(grid[:, None], return_std=True)
        gain = expected_improvement_of_abs(mean + prior(grid), std, float(np.min(np.abs(miss))))
        best = float(grid[int(np.argmax(gain))])
        return self.scaled(float(np.exp(best)), {"log_factor": best + shift})


def expected_improvement_of_abs(mean: np.ndarray, std: np.ndarray, best: float) -> np.ndarray:
    """E[max(best - |m|, 0)] for m ~ N(mean, std^2), shape of ``mean``.

    The improvement is best - |m| on -best < m < best: split at 0, each half is
    E[(c - X) 1{l < X < u}] = (c - mu) (Phi(beta) - Phi(alpha)) + s (phi(beta) - phi(alpha)), with
    alpha, beta the standardised ends; the negative half is the positive one of -m.
    """
    std = np.maximum(std, 1e-12)

    def half(mu: np.ndarray) -> np.ndarray:
        alpha, beta = (0.0 - mu) / std, (best - mu) / std
        return (best - mu) * (norm.cdf(beta) - norm.cdf(alpha)) + std * (norm.pdf(beta) - norm.pdf(alpha))

    return half(mean) + half(-mean)


BASELINES: dict[str, type[GmrBaseline]] = {
    cls.name: cls
    for cls in (Imitation, RandomPerturbation, BracketingSweep, SecantSearch, GpSearch, CmaSearch)
}

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

import warnings
from collections.abc import Sequence
from dataclasses import replace

import numpy as np
from scipy.stats import norm

from rlff.learn.attempt import Attempt
from rlff.learn.method import (
    Method,
    Problem,
    Proposal,
    finite_miss,
    labelled_demos,
    scale_speed,
    training_set,
)

#: Largest change of the speed factor in one secant step (a factor, > 1).
_MAX_STEP = 1.5
#: Elasticity of the landing distance in the release speed that the baselines assume (the prior
#: of ``calibrate``'s speed calibration: range ~ speed^2, brought down by the release height).
RANGE_ELASTICITY = 1.6
#: Smallest log speed factor any search tries (a throw at 30 % of the demonstrations' speed).
_LOWEST = -1.2


class GmrBaseline(Method):
    """A baseline that scales the GMR mean for the target distance."""

    def __init__(self, problem: Problem):
        super().__init__(problem)
        data, _ = training_set(labelled_demos(problem.demos), [1.0] * len(problem.demos))
        model = problem.fit(data)
        path = model.generate({"distance": problem.target}, problem.angles, exploration=0.0)
        #: The GMR mean's throw (every joint of it) for the target.
        self.throw = Proposal.of_outputs(path.angle, path.gmr_means, path.output_names, problem.target)
        self.angle, self.mean = self.throw.angle, self.throw.velocity
        fastest = float(np.max(np.abs(self.mean)))
        #: Largest speed factor that keeps the GMR mean within the joint's speed limit.
        self.limit = problem.max_speed / fastest if fastest > 0 else np.inf

    def scaled(self, factor: np.ndarray | float, info: dict) -> Proposal:
        """The GMR mean with every velocity times ``factor`` (scalar or shape (T,)), within the limit."""
        factor = np.minimum(factor, self.limit)
        return replace(scale_speed(self.throw, factor), info=info)


class Imitation(GmrBaseline):
    """The GMR mean without exploration, every attempt."""

    name = "imitation"

    def propose(self, history: Sequence[Attempt]) -> Proposal:
        return self.scaled(1.0, {})


class RandomPerturbation(GmrBaseline):
    """The GMR mean times a random speed factor (log-normal, 15 %)."""

    name = "random"
    spread = 0.15

    def propose(self, history: Sequence[Attempt]) -> Proposal:
        if not history:
            return self.scaled(1.0, {"factor": 1.0})
        rng = np.random.default_rng([self.problem.seed, len(history)])
        factor = float(np.exp(self.spread * rng.standard_normal()))
        return self.scaled(factor, {"factor": factor})


class BracketingSweep(GmrBaseline):
    """Log speed factors 0, +w, -w, +2w, ... in steps w of the hit window (binary feedback).

    The upward side ends with a throw at the speed limit when the last step below it leaves
    more than half a window uncovered (a hit there, at the edge of the reach, would otherwise
    be stepped over); after the whole range, the same order shifted by w / 2 (the gaps a range
    law steeper than :data:`RANGE_ELASTICITY` leaves between the windows), then the end again.
    """

    name = "sweep"
    feedbacks = ("binary",)

    def __init__(self, problem: Problem):
        super().__init__(problem)
        step = 2.0 * problem.tolerance / (RANGE_ELASTICITY * problem.target)
        highest = min(float(np.log(self.limit)), -_LOWEST)
        #: The log speed factors in the order thrown.
        self.offsets = self._pass(step, 0.0, highest) + self._pass(step, 0.5, highest)

    @staticmethod
    def _pass(step: float, shift: float, highest: float) -> list[float]:
        rings = int(np.ceil(-_LOWEST / step)) + 2
        ups = [(k + shift) * step for k in range(rings) if (k + shift) * step <= highest + 1e-12]
        if not ups or highest - ups[-1] > 0.5 * step + 1e-12:  # the band below the limit uncovered
            ups.append(highest)
        downs = [-(k + shift) * step for k in range(rings)]
        downs = [x for x in downs if _LOWEST <= x <= highest and min(abs(x - u) for u in ups) > 0.5 * step - 1e-12]
        order = ups[:1] if shift == 0.0 else []  # the GMR mean's own speed once, first
        rest = ups[1:] if shift == 0.0 else ups
        for k in range(max(len(rest), len(downs))):
            order += rest[k:k + 1] + downs[k:k + 1]
        return order

    def propose(self, history: Sequence[Attempt]) -> Proposal:
        x = self.offsets[min(len(history), len(self.offsets) - 1)]  # swept everything: stay at the end
        return self.scaled(float(np.exp(x)), {"log_factor": round(x, 4)})


class CmaSearch(GmrBaseline):
    """CMA-ES over the log speed factors at the first and the release angle."""

    name = "cma"
    feedbacks = ("distance",)
    sigma0 = 0.15

    def __init__(self, problem: Problem):
        super().__init__(problem)
        import cma

        self.es = cma.CMAEvolutionStrategy(
            [0.0, 0.0], self.sigma0, {"seed": problem.seed + 1, "verbose": -9, "verb_log": 0}
        )
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
        return self.scaled(factor, {"x": [float(v) for v in x]})

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
        factors = [1.0]
        misses: list[float] = []
        for attempt in history:
            misses.append(finite_miss(attempt))
            factors.append(min(self._next(factors, misses), self.limit))
        factor = factors[len(history)]
        return self.scaled(factor, {"factor": factor})

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

        if not history:
            return self.scaled(1.0, {"log_factor": 0.0})
        target = self.problem.target
        x = np.array([a.info["log_factor"] for a in history])
        miss = np.array([finite_miss(a) for a in history])
        reach = max(target + miss[0], 0.05 * target)  # the range law through the first attempt

        def prior(v: np.ndarray) -> np.ndarray:
            return reach * np.exp(RANGE_ELASTICITY * (v - x[0])) - target

        kernel = ConstantKernel(0.1, (1e-3, 10.0)) * RBF(0.3, (0.05, 3.0)) + WhiteKernel(1e-4, (1e-6, 1e-2))
        gp = GaussianProcessRegressor(kernel, random_state=self.problem.seed, n_restarts_optimizer=0)
        with warnings.catch_warnings():  # a bound reached on a handful of points is no news
            warnings.simplefilter("ignore")
            gp.fit(x[:, None], miss - prior(x))
        highest = min(float(np.log(self.limit)), -_LOWEST)
        grid = np.linspace(_LOWEST, highest, 481)
        mean, std = gp.predict(grid[:, None], return_std=True)
        gain = expected_improvement_of_abs(mean + prior(grid), std, float(np.min(np.abs(miss))))
        best = float(grid[int(np.argmax(gain))])
        return self.scaled(float(np.exp(best)), {"log_factor": best})


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

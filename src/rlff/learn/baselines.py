"""Baselines in the same harness as the update strategies.

All of them start from the Gaussian Mixture Regression mean for the target distance (the GMR
fitted once to the demonstrations, no exploration) and change only what decides the throw:

``imitation``
    The GMR mean, every time: pure imitation of the demonstrations.
``random``
    The GMR mean with its velocity scaled by a random factor exp(N(0, 0.15^2)) from the second
    attempt on: random perturbation around the demonstrations.
``cma``
    CMA-ES (pycma) over two log speed factors, at the first and at the release angle, linearly
    blended along the path. Fitness: the absolute miss (distance feedback) or 0 for a hit and
    1 for a miss (binary feedback, where CMA-ES has nothing but the hit to go on).
``secant`` (distance feedback)
    The plain engineering answer: a root search on one speed factor s of the GMR mean for
    miss(s) = 0. The first step uses that a projectile's range grows with the square of its
    speed, s1 = s0 sqrt(Z / L0); then secant steps, regula falsi (Illinois) once the hit is
    bracketed.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from rlff.learn.attempt import Attempt
from rlff.learn.method import Method, Problem, Proposal, finite_miss

#: Largest change of the speed factor in one secant step (a factor, > 1).
_MAX_STEP = 1.5


class GmrBaseline(Method):
    """A baseline that perturbs the GMR mean for the target distance."""

    def __init__(self, problem: Problem):
        super().__init__(problem)
        from rlff.model import Model

        model = Model.fit(
            problem.demos,
            inputs=("angle", "distance"),
            outputs=("velocity",),
            components=problem.components,
            seed=problem.seed,
        )
        path = model.generate({"distance": problem.target}, problem.angles, exploration=0.0)
        self.angle = np.asarray(path.angle, dtype=float)
        self.mean = np.asarray(path.gmr_mean, dtype=float).reshape(-1)

    def scaled(self, factor: np.ndarray | float, info: dict) -> Proposal:
        """The GMR mean with its velocity times ``factor`` (scalar or shape (T,))."""
        return Proposal(self.angle, self.mean * factor, query=self.problem.target, info=info)


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


class CmaSearch(GmrBaseline):
    """CMA-ES over the log speed factors at the first and the release angle."""

    name = "cma"
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
        if self.problem.feedback == "distance":
            return abs(finite_miss(attempt))
        return 0.0 if attempt.hit else 1.0


class SecantSearch(GmrBaseline):
    """Root search on one speed factor of the GMR mean (distance feedback only)."""

    name = "secant"
    feedbacks = ("distance",)

    def propose(self, history: Sequence[Attempt]) -> Proposal:
        factors = [1.0]
        misses: list[float] = []
        for attempt in history:
            misses.append(finite_miss(attempt))
            factors.append(self._next(factors, misses))
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


BASELINES: dict[str, type[GmrBaseline]] = {
    cls.name: cls for cls in (Imitation, RandomPerturbation, CmaSearch, SecantSearch)
}

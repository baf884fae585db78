"""Update strategies: how the robot's attempts change the Donut Mixture Model between attempts.

Every strategy refits the mixture to the demonstrations plus what the attempts taught, and asks
the DMM for a throw (the mode of the donut density at every angle, thesis section 2.4). They
differ in how the attempts join the data, with what weight, and which distance is asked for.

``failure`` (Grollman & Billard 2011)
    Each failed attempt joins the data labelled with the target distance. Attempts that disagree
    with the demonstrations widen the conditional variance there, so the exploration factor
    grows and the donut pushes the next throw away from what failed. Works with both feedback
    kinds; slow when the demonstrations agree, because the exploration then starts small.
``hindsight``
    Each attempt joins the data labelled with the distance it actually reached (a throw for 3 m
    that landed at 2.6 m becomes a demonstration for 2.6 m). Needs distance feedback.
``calibrate`` (this project's strategy)
    The demonstrations' distance labels are where the *human's* throws went; the robot, driven
    through the human-to-robot mapping, lands elsewhere, but in the same order: a faster
    demonstration still throws farther. So the labels are right up to a monotone recalibration
    g (label -> robot landing), and finding the throw for the target Z is finding the label
    c = g^-1(Z) to ask the DMM for. The strategy keeps a posterior over g, modelled locally as a
    power law log(L / Z) = a + b log(c / Z), on a grid, prior a ~ N(0, 0.4), b ~ N(1, 0.3):

    - distance feedback: each landing L_j at label c_j is a noisy observation of g;
    - binary feedback: each miss at c_j rules out the recalibrations under which c_j would have
      hit (the window Z +- tolerance), so the posterior mass moves to both sides of what
      failed, and the next query goes where most of it is: a search that brackets the hit
      without ever being told short or long.

    The next label is the one with the highest posterior probability of a hit. The data the DMM
    is refitted to: the demonstrations relabelled with where they landed when that is known (a
    miss still says which distance a throw is good for), plus, with distance feedback, every
    attempt labelled at g^-1(landing) (hindsight in the demonstrations' units) and weighted
    above the demonstrations, so the robot's own throws outweigh the human ones near them. The
    DMM's exploration stays on: where the demonstrations disagree it still explores.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from scipy.special import logsumexp, ndtr

from rlff.dataset import Dataset
from rlff.errors import InputError
from rlff.learn.attempt import Attempt
from rlff.learn.method import (
    Method,
    Proposal,
    attempt_trajectory,
    demo_labels,
    training_set,
    with_labels,
)


class DmmStrategy(Method):
    """A strategy that refits the DMM to weighted data and asks it for a distance."""

    #: Weight of a robot attempt relative to a demonstration.
    robot_weight: float = 1.0

    def generate(self, data: Dataset, sample_weight: np.ndarray, query: float, info: dict) -> Proposal:
        """Fit the mixture to ``data`` and return the DMM's throw for distance ``query`` (m)."""
        from rlff.model import Model

        problem = self.problem
        model = Model.fit(
            data,
            inputs=("angle", "distance"),
            outputs=("velocity",),
            components=problem.components,
            seed=problem.seed,
            sample_weight=sample_weight,
        )
        path = model.generate({"distance": query}, problem.angles, exploration="auto")
        return Proposal(
            angle=np.asarray(path.angle, dtype=float),
            velocity=np.asarray(path.velocity, dtype=float).reshape(-1),
            query=float(query),
            exploration=float(np.mean(path.exploration)),
            info=info,
        )


class FailureUpdate(DmmStrategy):
    """Grollman & Billard: attempts join the data labelled with the target distance."""

    name = "failure"

    def propose(self, history: Sequence[Attempt]) -> Proposal:
        problem = self.problem
        trajectories = list(problem.demos) + [attempt_trajectory(a, problem.target) for a in history]
        weights = [1.0] * len(problem.demos) + [self.robot_weight] * len(history)
        data, sample_weight = training_set(trajectories, weights)
        return self.generate(data, sample_weight, problem.target, {})


class HindsightUpdate(DmmStrategy):
    """Attempts join the data labelled with the distance they reached (needs distance feedback)."""

    name = "hindsight"
    feedbacks = ("distance",)

    def propose(self, history: Sequence[Attempt]) -> Proposal:
        problem = self.problem
        trajectories = list(problem.demos) + [attempt_trajectory(a, a.landing) for a in history]
        weights = [1.0] * len(problem.demos) + [self.robot_weight] * len(history)
        data, sample_weight = training_set(trajectories, weights)
        return self.generate(data, sample_weight, problem.target, {})


class CalibrationPosterior:
    """Posterior over the recalibration log(L / Z) = a + b log(c / Z) on a grid.

    Parameters
    ----------
    target : float
        Basket distance Z (m).
    tolerance : float
        Half-width of the hit window around Z (m).
    prior_scale : float
        Prior standard deviation of a (log units): how far the robot's landing may be from the
        demonstrations' labels before any attempt.
    noise : float
        Standard deviation (log units) of a landing about the power law: execution noise and
        the law's own error.
    """

    def __init__(
        self,
        target: float,
        tolerance: float,
        *,
        prior_scale: float = 0.4,
        slope_scale: float = 0.3,
        noise: float = 0.05,
    ):
        self.target = float(target)
        self.tolerance = float(tolerance)
        self.noise = float(noise)
        self.offset = np.linspace(-4.0 * prior_scale, 4.0 * prior_scale, 241)  # a, shape (A,)
        self.slope = np.linspace(0.3, 2.5, 45)  # b, shape (B,)
        # log prior on the (A, B) grid
        self.log_p = (
            -0.5 * (self.offset[:, None] / prior_scale) ** 2
            - 0.5 * ((self.slope[None, :] - 1.0) / slope_scale) ** 2
        )
        # candidate labels c / Z, log-spaced, shape (C,)
        self.ratios = np.exp(np.linspace(-1.6, 1.6, 321))

    def predicted_log_ratio(self, log_c_ratio: np.ndarray | float) -> np.ndarray:
        """log(L / Z) of every grid point for labels with log(c / Z) given; shape (A, B, ...)."""
        x = np.asarray(log_c_ratio, dtype=float)
        extra = (1,) * x.ndim
        return self.offset.reshape((-1, 1, *extra)) + self.slope.reshape((1, -1, *extra)) * x

    def hit_probability(self, log_c_ratio: np.ndarray | float, spread: float) -> np.ndarray:
        """P(|L - Z| <= tolerance) at every grid point, landing noise ``spread`` (log units)."""
        log_l = self.predicted_log_ratio(log_c_ratio)
        half = self.tolerance / self.target  # window in log units, to first order
        return ndtr((half - log_l) / spread) - ndtr((-half - log_l) / spread)

    def observe_landing(self, label: float, landing: float) -> None:
        """Distance feedback: the throw asked for label c (m) landed at ``landing`` (m)."""
        if not landing > 0:
            return  # a throw that never reached forward carries no scale information
        residual = np.log(landing / self.target) - self.predicted_log_ratio(np.log(label / self.target))
        self.log_p = self.log_p - 0.5 * (residual / self.noise) ** 2

    def observe_miss(self, label: float, *, trust: float = 0.9) -> None:
        """Binary feedback: the throw asked for label c (m) missed.

        ``trust`` < 1 keeps a little mass where the model says it should have hit, so one
        misleading miss (a bounce off the rim, a model error) cannot rule a region out for good.
        """
        p_hit = self.hit_probability(np.log(label / self.target), self.noise)
        self.log_p = self.log_p + np.log1p(-trust * p_hit)

    def posterior(self) -> np.ndarray:
        """Normalised posterior on the grid, shape (A, B)."""
        return np.exp(self.log_p - logsumexp(self.log_p))

    def best_label(self) -> tuple[float, float]:
        """The label (m) with the highest posterior probability of a hit, and that probability."""
        weights = self.posterior()
        p_hit = self.hit_probability(np.log(self.ratios), self.noise)  # (A, B, C)
        expected = np.tensordot(weights, p_hit, axes=([0, 1], [0, 1]))  # (C,)
        best = int(np.argmax(expected))
        return float(self.ratios[best] * self.target), float(expected[best])

    def inverse(self, landing: float) -> float:
        """Posterior-mean label c (m) whose throw lands at ``landing`` (m)."""
        weights = self.posterior()
        log_c = (np.log(landing / self.target) - self.offset[:, None]) / self.slope[None, :]
        return float(self.target * np.exp(np.sum(weights * log_c)))


class CalibrateUpdate(DmmStrategy):
    """This project's strategy: recalibrate the demonstrations' labels from the attempts."""

    name = "calibrate"
    robot_weight = 3.0

    def propose(self, history: Sequence[Attempt]) -> Proposal:
        problem = self.problem
        posterior = CalibrationPosterior(problem.target, problem.tolerance)
        for attempt in history:
            if problem.feedback == "distance":
                posterior.observe_landing(attempt.query, attempt.landing)
            elif not attempt.hit:
                posterior.observe_miss(attempt.query)
        query, p_hit = posterior.best_label()
        labels = _hindsight_labels(problem.demos)
        trajectories = with_labels(problem.demos, labels)
        weights = [1.0] * len(trajectories)
        if problem.feedback == "distance":
            for attempt in history:
                trajectories.append(attempt_trajectory(attempt, posterior.inverse(attempt.landing)))
                weights.append(self.robot_weight)
        data, sample_weight = training_set(trajectories, weights)
        return self.generate(data, sample_weight, query, {"p_hit": round(p_hit, 4)})


def _hindsight_labels(demos: Dataset) -> np.ndarray:
    """Each demonstration's label: where its throw landed when recorded, else its target (m)."""
    labels = demo_labels(demos)
    landed = np.array([float(t.meta.get("landing", np.nan)) for t in demos])
    usable = np.isfinite(landed) & (landed > 0)
    return np.where(usable, landed, labels)


STRATEGIES: dict[str, type[DmmStrategy]] = {
    cls.name: cls for cls in (FailureUpdate, HindsightUpdate, CalibrateUpdate)
}


def strategy(name: str) -> type[DmmStrategy]:
    """The strategy class called ``name``; :class:`InputError` listing the known ones otherwise."""
    try:
        return STRATEGIES[name]
    except KeyError:
        raise InputError(f"unknown update strategy {name!r} (known: {', '.join(STRATEGIES)})") from None


"""What every learning method shares: the problem it sees, what it proposes, the data it joins.

A *method* proposes the next throw from the demonstrations and the attempts so far. The update
strategies (:mod:`rlff.learn.strategies`) do it by refitting the Donut Mixture Model; the
baselines (:mod:`rlff.learn.baselines`) by imitation, random or CMA-ES search, or a secant
search. All run in the same harness (:func:`rlff.learn.loop.learn`), so their attempt counts
compare directly.

Methods see attempts only through the feedback they are given: with binary feedback the
landing point and the miss of every attempt are NaN, so a method cannot use them by mistake.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rlff.dataset import Dataset, Trajectory
from rlff.learn.attempt import Attempt

FEEDBACKS = ("binary", "distance")
#: The dataset columns the loop learns from (the throwing task).
COLUMNS = ("angle", "distance", "velocity")


@dataclass(frozen=True)
class Problem:
    """What a method knows before its first attempt.

    Parameters
    ----------
    demos : Dataset
        Demonstrations with columns ``angle`` (rad), ``distance`` (m), ``velocity`` (rad/s), in
        the units the robot mapping takes.
    target : float
        Basket distance (m).
    feedback : {"binary", "distance"}
        What each attempt reports: hit or miss only, or also the signed miss.
    tolerance : float
        Half-width (m) of the landing window that counts as a hit (from the basket's opening
        and the ball's radius); methods may use it to size their steps.
    angles : array of shape (T,)
        Angle grid (rad) of every generated throw; its last angle is the release.
    components : int
        Number of mixture components, chosen once by BIC on the demonstrations.
    seed : int
        Seed of every random choice of the run.
    max_speed : float
        Fastest speed of the driven joint in the demonstrations' units (rad/s).
    """

    demos: Dataset
    target: float
    feedback: str
    tolerance: float
    angles: np.ndarray
    components: int
    seed: int
    max_speed: float = float("inf")


@dataclass(frozen=True)
class Proposal:
    """The next throw a method asks for.

    Parameters
    ----------
    angle, velocity : array of shape (T,)
        The throw in the demonstrations' units (rad, rad/s).
    query : float
        Distance the model was asked for (m); NaN when no model was queried.
    exploration : float
        Mean DMM exploration factor along the path (0 without one).
    info : dict
        JSON-serialisable details kept in the attempts log.
    """

    angle: np.ndarray
    velocity: np.ndarray
    query: float = float("nan")
    exploration: float = 0.0
    info: dict[str, Any] = field(default_factory=dict)


class Method(ABC):
    """A way of choosing the next throw from what happened so far.

    ``propose`` receives the whole history each time, so a method rebuilt after a crash picks
    up from the attempts log. Stateful methods (CMA-ES) replay the history they have not seen.
    """

    #: Name used on the command line and in the benchmark table.
    name: str = ""
    #: Feedback kinds the method can work with.
    feedbacks: tuple[str, ...] = FEEDBACKS

    def __init__(self, problem: Problem):
        self.problem = problem

    @abstractmethod
    def propose(self, history: Sequence[Attempt]) -> Proposal:
        """The next throw, given every attempt so far (as the feedback reports them)."""


def attempt_trajectory(attempt: Attempt, label: float, *, source: str = "robot") -> Trajectory:
    """An attempt as a training trajectory labelled with distance ``label`` (m)."""
    return Trajectory(
        f"attempt-{attempt.index}",
        {
            "angle": attempt.angle,
            "distance": np.full(attempt.angle.size, float(label)),
            "velocity": attempt.velocity,
        },
        {"source": source, "target": attempt.target, "hit": attempt.hit},
    )


def with_labels(demos: Dataset, labels: np.ndarray) -> list[Trajectory]:
    """The demonstrations with their distance column set to ``labels`` (one per trajectory, m)."""
    return [
        demo.with_columns(distance=np.full(len(demo), float(label)))
        for demo, label in zip(demos, labels, strict=True)
    ]


def training_set(
    trajectories: Sequence[Trajectory], weights: Sequence[float]
) -> tuple[Dataset, np.ndarray]:
    """Stack trajectories into a dataset and expand per-trajectory weights to samples.

    Returns
    -------
    dataset : Dataset
    sample_weight : ndarray of shape (N,)
        Weight of each sample, N the total number of samples.
    """
    dataset = Dataset(trajectories, context=("distance",))
    sample_weight = np.concatenate(
        [np.full(len(t), float(w)) for t, w in zip(trajectories, weights, strict=True)]
    )
    return dataset, sample_weight


def demo_labels(demos: Dataset) -> np.ndarray:
    """Distance each demonstration is labelled with (m), shape (S,)."""
    return np.array([float(t["distance"][0]) for t in demos])


def known_labels(demos: Dataset) -> np.ndarray:
    """Each demonstration's best distance label (m), shape (S,): where its throw landed when
    that is recorded (``landing`` metadata; a failed throw still shows which distance it is
    good for), else the basket it aimed at. Every method starts from these labels, so that all
    see the same information."""
    labels = demo_labels(demos)
    landed = np.array([float(t.meta.get("landing", np.nan)) for t in demos])
    usable = np.isfinite(landed) & (landed > 0)
    return np.where(usable, landed, labels)


def labelled_demos(demos: Dataset) -> list[Trajectory]:
    """The demonstrations with their distance column set to :func:`known_labels`."""
    return with_labels(demos, known_labels(demos))


def finite_miss(attempt: Attempt) -> float:
    """The attempt's signed miss (m); a throw that never came down through the rim's height
    (no landing point) counts as falling at the robot's base, ``-target``."""
    return attempt.miss if np.isfinite(attempt.miss) else -attempt.target

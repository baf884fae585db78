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
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import Any

import numpy as np

from rlff.dataset import Dataset, Trajectory
from rlff.learn.attempt import Attempt
from rlff.learn.memo import ByContent, content_digest
from rlff.learn.windows import MISREPORT

FEEDBACKS = ("binary", "distance")
#: The dataset columns the loop learns from (the throwing task).
COLUMNS = ("angle", "distance", "velocity")
#: Outputs of the one-joint model: the elbow's velocity along its angle.
ONE_JOINT_OUTPUTS = ("velocity",)
#: The last mixtures :meth:`Problem.demonstrations_model` made, by the demonstrations' content.
_DEMONSTRATIONS_MODELS = ByContent()


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
        Fastest speed of the elbow's joint in the demonstrations' units (rad/s). A proposal
        scaled beyond another driven joint's limit has that joint saturate there, as the robot
        does; the landing still grows with the speed.
    outputs : tuple of str
        The model's outputs: ``("velocity",)`` for a one-joint throw, with the other joints'
        positions and velocities for a whole-arm one (:func:`joint_outputs`).
    elasticity : float
        Where the speed calibration's prior centres the elasticity of the landing in the release
        speed: 1.6 for a one-joint throw, from the arm's kinematics for a whole-arm one
        (:func:`rlff.learn.reach.release_elasticity`).
    saturation : callable, optional
        ``saturation(proposal) -> factor``: for a whole-arm throw, the factor on every velocity
        beyond which no driven joint goes faster at the release (each saturates at its limit, the
        elbow's too, :func:`rlff.learn.reach.saturation_factor`); a speed calibration searches up
        to it, in the commanded speed (the executed elbow speed stops growing where the elbow
        saturates, the landing does not). None: :attr:`max_speed` bounds the executed speed.
    aim : callable, optional
        ``aim(proposal) -> factor``: the factor on every velocity of a proposal that sends the
        ball to the target by the arm's kinematics and the free flight from its release (a
        whole-arm throw, :func:`rlff.learn.reach.aimed_factor`); None: the demonstrations' own
        speed is where the calibration's prior puts the basket.
    carried : tuple of float
        Log speed factors of earlier runs' hits over their own start (:mod:`rlff.learn.carry`):
        where this run's search centres, when given.
    misreport : float
        With binary feedback, the probability that a hit is reported as a miss, which the window
        search gives a window that missed (:func:`rlff.learn.windows.with_retries`).
    landing : callable, optional
        ``landing(u) -> m``: where the demonstrations' typical throw released at speed u (rad/s,
        as :func:`release_speed` measures it) comes down by the arm's kinematics
        (:func:`rlff.learn.reach.typical_landing`); the speed searches go as slow as a near
        basket needs by it (:func:`rlff.learn.windows.lowest_for`). None: no robot known.
    """

    demos: Dataset
    target: float
    feedback: str
    tolerance: float
    angles: np.ndarray
    components: int
    seed: int
    max_speed: float = float("inf")
    outputs: tuple[str, ...] = ONE_JOINT_OUTPUTS
    elasticity: float = 1.6
    saturation: Callable[[Proposal], float] | None = None
    aim: Callable[[Proposal], float] | None = None
    carried: tuple[float, ...] = ()
    misreport: float = MISREPORT
    landing: Callable[[float], float] | None = None

    def __repr__(self) -> str:
        """One line: the basket, the feedback, the grid's length T, the top speed and the
        outputs; not the demonstrations' or the grid's arrays, nor the robot mapping inside
        :attr:`saturation` (the dataclass printed kilobytes of them)."""
        return (f"Problem(target={self.target:g}, feedback={self.feedback!r}, T={np.size(self.angles)}, "
                f"max_speed={self.max_speed:.4g}, outputs={self.outputs!r})")

    @property
    def carried_shift(self) -> float:
        """Log speed factor the carried hits point to (their mean; 0 without any)."""
        return float(np.mean(self.carried)) if self.carried else 0.0

    def fit(self, data: Dataset, sample_weight: np.ndarray | None = None, n_init: int | None = None):
        """The mixture over (angle, distance) -> :attr:`outputs` of ``data`` (an
        :class:`rlff.model.Model`), with the run's number of components and seed, ``n_init`` EM
        starts (default: the model's)."""
        from rlff.model import Model

        starts = {} if n_init is None else {"n_init": n_init}
        return Model.fit(data, inputs=("angle", "distance"), outputs=self.outputs, components=self.components,
                         seed=self.seed, sample_weight=sample_weight, **starts)

    def demonstrations_model(self):
        """:meth:`fit` of the demonstrations alone, labelled as every method labels them
        (:func:`labelled_demos`), with the model's restarts: what every method starts from.
        Kept by content (:mod:`rlff.learn.memo`), so the methods of a benchmark and a whole-arm
        run's reach checks share one fit; the refits at every attempt (:meth:`fit`) are not kept,
        none of them comes twice."""
        def fit():
            data, _ = training_set(labelled_demos(self.demos), [1.0] * len(self.demos))
            return self.fit(data)

        return _DEMONSTRATIONS_MODELS.get((content_digest(self.demos), self.outputs, self.components, self.seed), fit)


@dataclass(frozen=True)
class Proposal:
    """The next throw a method asks for.

    Parameters
    ----------
    angle, velocity : array of shape (T,)
        The elbow's path in the demonstrations' units (rad, rad/s): the throw's phase.
    query : float
        Distance the model was asked for (m); NaN when no model was queried.
    exploration : float
        Mean DMM exploration factor along the path (0 without one).
    info : dict
        JSON-serialisable details kept in the attempts log.
    arm : mapping of str to array of shape (T,)
        The other driven joints along the same samples: ``shoulder`` (rad),
        ``shoulder_velocity`` (rad/s), ``wrist``, ``wrist_velocity``; empty for a one-joint throw.
    """

    angle: np.ndarray
    velocity: np.ndarray
    query: float = float("nan")
    exploration: float = 0.0
    info: dict[str, Any] = field(default_factory=dict)
    arm: Mapping[str, np.ndarray] = field(default_factory=lambda: MappingProxyType({}))

    @property
    def path(self) -> dict[str, np.ndarray]:
        """The whole human path (``rlff.robot.mapping.HumanPath``): angle, velocity and :attr:`arm`."""
        return {"angle": self.angle, "velocity": self.velocity, **self.arm}

    @classmethod
    def of_outputs(cls, angle: np.ndarray, outputs: np.ndarray, names: Sequence[str], query: float,
                   exploration: float = 0.0, info: dict[str, Any] | None = None) -> Proposal:
        """The proposal of a model's outputs (T, O) named ``names`` (``velocity`` among them)."""
        columns = {name: np.asarray(outputs[:, j], dtype=float) for j, name in enumerate(names)}
        velocity = columns.pop("velocity")
        return cls(np.asarray(angle, dtype=float), velocity, float(query), float(exploration), info or {}, columns)


def release_samples(count: int) -> int:
    """How many of a path's ``count`` samples are its release part: the last tenth, at least 2."""
    return max(2, count // 10)


def release_speed(angles: np.ndarray, velocity: np.ndarray) -> float:
    """Mean speed (rad/s) over the release part of the path (:func:`release_samples`): what
    decides where the ball goes. ``angles`` (T,) are the path's positions (only their number T
    counts) and ``velocity`` (T,) its velocities (rad/s) at them."""
    return float(np.mean(np.abs(velocity[-release_samples(angles.size):])))


def scale_speed(proposal: Proposal, factor: np.ndarray | float) -> Proposal:
    """``proposal`` with every velocity column times ``factor`` (scalar, or (T,) per sample).

    The positions along the path stay; only the time it takes changes (by 1 / ``factor``): the
    coordinated throw sped up or slowed down as a whole, every joint by the same time scale.
    """
    arm = {name: values * factor if name.endswith("_velocity") else values for name, values in proposal.arm.items()}
    return replace(proposal, velocity=proposal.velocity * factor, arm=arm)



class Method(ABC):
    """A way of choosing the next throw from what happened so far.

    ``propose`` receives the whole history each time, so a method rebuilt after a crash picks
    up from the attempts log. Stateful methods (CMA-ES) replay the history they have not seen.
    """

    #: Name used on the command line and in the benchmark table.
    name: str = ""
    #: Feedback kinds the method can work with.
    feedbacks: tuple[str, ...] = FEEDBACKS
    #: Whether a run of it can carry earlier runs' hits (``learn(carry_from=...)``, ``rlff learn
    #: --carry``): its throws start where ``Problem.carried`` points, and each proposal's ``info``
    #: holds ``log_factor``, its log speed factor over the method's own start, which a later run
    #: carries (:mod:`rlff.learn.carry`). A method that does neither is refused a carry: its log
    #: would carry nothing, and nothing carried would move it.
    carries: bool = False

    def __init__(self, problem: Problem):
        self.problem = problem

    @abstractmethod
    def propose(self, history: Sequence[Attempt]) -> Proposal:
        """The next throw, given every attempt so far (as the feedback reports them)."""


def attempt_trajectory(attempt: Attempt, label: float, *, source: str = "robot") -> Trajectory:
    """An attempt as a training trajectory labelled with distance ``label`` (m): every column
    it drove (the elbow's angle and velocity, and the other joints' of a whole-arm throw)."""
    return Trajectory(
        f"attempt-{attempt.index}",
        {
            "angle": attempt.angle,
            "distance": np.full(attempt.angle.size, float(label)),
            "velocity": attempt.velocity,
            **attempt.arm,
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
    landed = recorded_landings(demos)
    return np.where(np.isfinite(landed), landed, demo_labels(demos))


def recorded_landings(demos: Dataset) -> np.ndarray:
    """Where each demonstration's ball came down (m, its ``landing`` metadata), shape (S,); NaN
    where that is not known: absent, not a number, or 0 m or nearer (the placeholder a table
    writes for "not measured"; no basket is nearer than 0.3 m)."""
    landed = np.array([float(t.meta.get("landing", np.nan)) for t in demos])
    return np.where(landed > 0, landed, np.nan)


def labelled_demos(demos: Dataset) -> list[Trajectory]:
    """The demonstrations with their distance column set to :func:`known_labels`."""
    return with_labels(demos, known_labels(demos))


def finite_miss(attempt: Attempt) -> float:
    """The attempt's signed miss (m); one not measured (NaN) counts as falling at the robot's
    base, ``-target``. (A ball that never came down through the rim's height is reported where
    it first touched, :func:`rlff.learn.loop.reported_outcome`.)"""
    return attempt.miss if np.isfinite(attempt.miss) else -attempt.target

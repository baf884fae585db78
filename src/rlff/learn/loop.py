"""The closed learning-from-failure loop (thesis 1.1.2 and chapter 5's open last step).

fit -> generate the DMM's throw for the basket distance -> map it to the robot -> execute ->
record the attempt -> update -> repeat, until a hit (or, with ``until="centred"``, a hit near the
basket's centre) or the budget is spent.

The loop works on what the robot does. The demonstrations are checked against the robot
through the human-to-robot mapping before anything runs; every proposed throw is mapped to the
robot and saturated at the joint limits if it goes beyond them (the robot never exceeds a
limit, and the attempt says how many values were clipped); what the robot executed is mapped
back to the demonstrations' units and that is what joins the data. Every attempt goes to the
attempts log the moment it ends, and a run started again with the same log continues after
the last recorded attempt, exactly as the uninterrupted run would have.
"""

from __future__ import annotations

import hashlib
import math
import time as clock
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from rlff.dataset import Dataset
from rlff.errors import InputError
from rlff.learn.attempt import Attempt
from rlff.learn.baselines import BASELINES
from rlff.learn.log import AttemptLog, robot_record
from rlff.learn.method import COLUMNS, FEEDBACKS, Method, Problem
from rlff.learn.strategies import STRATEGIES
from rlff.limits import check_pedestal
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.timing import time_along_path

#: Quantile of the demonstrations' last angles where generated throws release.
RELEASE_QUANTILE = 0.25
#: Most mixture components the loop uses.
MAX_COMPONENTS = 4
#: Fewest points of a generated throw.
MIN_POINTS = 30
#: Most demonstration samples the mixture is refitted to at every attempt.
MAX_SAMPLES = 600
#: Every method the loop can run, by name: update strategies first, then baselines.
METHODS: dict[str, type[Method]] = {**STRATEGIES, **BASELINES}
#: When a run stops: at the first hit, or at the first hit within the centre share of the opening.
UNTILS = ("hit", "centred")
#: Default share of the opening (centre to rim) a centred hit lands within.
CENTRE_SHARE = 0.5


class Outcome(Protocol):
    """What an executor reports about one throw (``rlff.sim``'s ThrowOutcome is one)."""

    hit: bool
    landing_x: float
    miss: float


#: Runs one robot trajectory and reports its outcome.
Executor = Callable[[JointTrajectory], Outcome]


@dataclass(frozen=True)
class LearningResult:
    """The end of a run.

    Parameters
    ----------
    hit : bool
        The last attempt hit the basket.
    attempts : int
        Attempts made, including those resumed from the log.
    misses : list of float
        Signed miss (m) of every attempt: the landing's distance from the basket's centre,
        negative short, positive long, hits included; NaN where the ball never came down.
    history : list of Attempt
    target : float
        Basket distance (m).
    feedback, update : str
    resumed : int
        Attempts taken from the log rather than executed by this call.
    dropped_partial_line : bool
        The log ended in a line cut short by a crash; it was dropped.
    until : {"hit", "centred"}
        The stopping rule of the run.
    centred : bool
        The last attempt hit within the centre share of the opening (``centre_window``).
    centre_window : float
        Largest ``abs(miss)`` (m) of a centred hit; ``inf`` when the run stops at any hit.
    """

    hit: bool
    attempts: int
    misses: list[float]
    history: list[Attempt]
    target: float
    feedback: str
    update: str
    resumed: int = 0
    dropped_partial_line: bool = False
    notes: list[str] = field(default_factory=list)
    until: str = "hit"
    centred: bool = False
    centre_window: float = math.inf

    @property
    def best(self) -> Attempt | None:
        """The throw to keep: the last hit, else the attempt that came down nearest the centre,
        else None (no attempt, or none came down)."""
        hits = [a for a in self.history if a.hit]
        if hits:
            return hits[-1]
        landed = [a for a in self.history if math.isfinite(a.miss)]
        return min(landed, key=lambda a: abs(a.miss)) if landed else None

    def to_json(self) -> dict[str, Any]:
        """The result as plain values (no trajectories)."""
        return {
            "hit": self.hit,
            "attempts": self.attempts,
            "misses": [_json_number(m) for m in self.misses],
            "hits": [a.hit for a in self.history],
            "landings": [_json_number(a.landing) for a in self.history],
            "exploration": [a.exploration for a in self.history],
            "target": self.target,
            "feedback": self.feedback,
            "update": self.update,
            "resumed": self.resumed,
            "dropped_partial_line": self.dropped_partial_line,
            "until": self.until,
            "centred": self.centred,
            "centre_window": _json_number(self.centre_window),
            "notes": self.notes,
        }


def learn(
    demos: Dataset,
    basket: float,
    *,
    budget: int = 20,
    feedback: str = "binary",
    update: str = "calibrate",
    seed: int = 0,
    log_path: str | Path | None = None,
    executor: Executor | None = None,
    progress: Callable[[Attempt], None] | None = None,
    robot: str = "comau_smart5_six",
    pedestal: float = 0.0,
    rim_height: float = 0.3,
    opening: float = 0.35,
    until: str = "hit",
    centre_share: float = CENTRE_SHARE,
    executed_on: str = "sim",
) -> LearningResult:
    """Learn to hit a basket at distance ``basket`` from (possibly failed) demonstrations.

    Parameters
    ----------
    demos : Dataset
        Demonstrations with columns ``angle`` (rad), ``distance`` (m: the basket aimed at) and
        ``velocity`` (rad/s), one throw per trajectory up to its release, in the human units the
        robot mapping takes. Metadata ``landing`` (m), where known, is used by ``calibrate``.
    basket : float
        Distance of the basket's centre from the robot's base axis (m).
    budget : int
        Largest number of attempts, counting those resumed from the log.
    feedback : {"binary", "distance"}
        What an attempt reports to the method: hit or miss only, or the signed miss as well.
    update : str
        An update strategy (``failure``, ``hindsight``, ``calibrate``) or a baseline
        (``imitation``, ``random``, ``cma``, ``secant``); see :data:`METHODS`.
    seed : int
        Seed of every random choice; a run is reproducible from it.
    log_path : str or Path, optional
        Attempts log (JSONL); resumed when it exists.
    executor : callable, optional
        ``executor(joint_trajectory) -> outcome`` with ``hit``, ``landing_x`` and ``miss``;
        default: the MuJoCo simulation of :mod:`rlff.sim` for this basket.
    progress : callable, optional
        Called with every attempt as it ends (also those resumed from the log).
    robot : str
        Robot name or robot file; its ``[throwing]`` table is the mapping.
    pedestal, rim_height, opening : float
        Height of the robot's base, of the basket's rim, and the basket's inner width (m).
    until : {"hit", "centred"}
        Stop at the first hit, or keep refining after hits near the rim until a throw lands
        within ``centre_share`` of the opening: ``abs(miss) <= centre_share * opening / 2``.
        Methods are then told "hit" only for such throws (and size their steps by that
        narrower window), so every method and both feedbacks work unchanged.
    centre_share : float
        In (0, 1]: the share of the half-opening a centred hit lands within.
    executed_on : str
        What ``executor`` runs the throws on (``sim``, ``ros1``, ``ros2``): a log resumes only
        on the same (a run in simulation writes no such field, so older logs resume).

    Returns
    -------
    LearningResult

    Raises
    ------
    InputError
        Unknown method or feedback, a method that needs other feedback, a basket out of the
        robot's reach, demonstrations beyond the joint limits, or a corrupt or foreign log.
    """
    from rlff.robot import RobotMapping, load_robot
    from rlff.sim import Basket

    if update not in METHODS:
        raise InputError(f"unknown update {update!r} (known: {', '.join(METHODS)})")
    if feedback not in FEEDBACKS:
        raise InputError(f"unknown feedback {feedback!r} (known: {', '.join(FEEDBACKS)})")
    method_class = METHODS[update]
    if feedback not in method_class.feedbacks:
        raise InputError(f"update {update!r} needs {' or '.join(method_class.feedbacks)} feedback, "
                         f"not {feedback!r}")
    if not (isinstance(budget, int) and budget >= 1):
        raise InputError(f"budget must be a positive whole number of attempts, got {budget!r}")
    if until not in UNTILS:
        raise InputError(f"unknown until {until!r} (known: {', '.join(UNTILS)})")
    if not 0 < centre_share <= 1:
        raise InputError(f"centre share must be in (0, 1] of the half-opening, got {centre_share!r}")
    robot_model = load_robot(robot)
    mapping = RobotMapping.for_robot(robot_model)
    target = Basket(float(basket), rim_height=rim_height, opening=opening)  # checks the stated range
    pedestal = check_pedestal(pedestal)
    _require_reach(robot_model, target, pedestal)
    demos = _learning_demos(demos)
    _require_demos_within_limits(demos, mapping)
    _require_executable(mapping, target, pedestal, _angle_grid(demos))
    if executor is None:
        executor = _simulator(robot_model, target, pedestal)

    run = {
        "basket": target.to_dict(),
        "feedback": feedback,
        "update": update,
        "seed": seed,
        "robot": robot_record(mapping),
        "pedestal": pedestal,
        "demos": fingerprint(demos),
        "until": until,
    }
    centre_window = math.inf
    if until == "centred":
        centre_window = 0.5 * centre_share * target.opening
        run["centre_share"] = centre_share
    if executed_on != "sim":
        run["executor"] = executed_on
    log = AttemptLog(log_path, run) if log_path is not None else None
    try:
        return _run(log, method_class, demos, target, feedback, update, seed, budget, mapping, executor,
                    progress, until, centre_window)
    finally:
        if log:
            log.close()


def _run(log, method_class, demos, target, feedback, update, seed, budget, mapping, executor, progress,
         until, centre_window) -> LearningResult:
    """The attempts of :func:`learn` after its checks, with the log (or None) held."""
    history = list(log.contents.attempts) if log else []
    resumed = len(history)
    for attempt in history:
        if progress:
            progress(attempt)

    problem = Problem(
        demos=demos,
        target=target.distance,
        feedback=feedback,
        tolerance=min(_hit_tolerance(target), centre_window),
        angles=_angle_grid(demos),
        components=_components(demos, seed),
        seed=seed,
        max_speed=mapping.robot.joint(mapping.joint).max_velocity / abs(mapping.velocity_scale),
    )

    def done(attempt: Attempt) -> bool:
        return attempt.hit and abs(attempt.miss) <= centre_window

    method = method_class(problem) if not (history and done(history[-1])) else None
    while method is not None and len(history) < budget and not (history and done(history[-1])):
        start = clock.perf_counter()
        proposal = method.propose([_as_reported(a, feedback, centre_window) for a in history])
        attempt = _execute(proposal, len(history) + 1, target.distance, mapping, executor, start)
        if log:
            log.append(attempt)
        history.append(attempt)
        if progress:
            progress(attempt)

    notes = []
    if log and log.contents.dropped_partial_line:
        notes.append(f"{log.path}: dropped a partial last line (a run interrupted mid-write)")
    return LearningResult(
        hit=bool(history and history[-1].hit),
        attempts=len(history),
        misses=[a.miss for a in history],
        history=history,
        target=target.distance,
        feedback=feedback,
        update=update,
        resumed=resumed,
        dropped_partial_line=bool(log and log.contents.dropped_partial_line),
        notes=notes,
        until=until,
        centred=bool(history and done(history[-1])),
        centre_window=centre_window,
    )


def _execute(proposal, index: int, target: float, mapping, executor: Executor, start: float) -> Attempt:
    """Map a proposal to the robot (saturating at its limits), execute it, record what it did."""
    from rlff.robot.plan import plan

    velocity = _forward_velocity(proposal.angle, proposal.velocity)
    planned = plan(mapping, proposal.angle, velocity, time_along_path(proposal.angle, velocity), clip=True)
    trajectory, clip_report = planned.points, planned.clipped_points
    outcome = executor(planned.trajectory)
    angle, executed = mapping.from_robot(trajectory)
    return Attempt(
        index=index,
        target=target,
        query=proposal.query,
        angle=angle,
        velocity=executed,
        time=trajectory.time / mapping.time_scale,
        hit=bool(outcome.hit),
        landing=float(outcome.landing_x),
        miss=float(outcome.miss),
        exploration=proposal.exploration,
        clipped=len(clip_report),
        seconds=clock.perf_counter() - start,
        info=proposal.info,
    )


def fingerprint(demos: Dataset) -> str:
    """Short hash of the demonstrations' samples and labels: a log resumes only for the same data."""
    digest = hashlib.sha256()
    for trajectory in demos:
        digest.update(trajectory.id.encode())
        digest.update(np.ascontiguousarray(trajectory.to_array(COLUMNS)).tobytes())
        digest.update(repr(trajectory.meta.get("landing")).encode())
    return digest.hexdigest()[:16]


def _learning_demos(demos: Dataset, max_samples: int = MAX_SAMPLES) -> Dataset:
    """The demonstrations reduced to the columns the loop learns from, thinned if dense.

    Densified demonstrations (a sample every 0.01 rad) repeat themselves; the mixture is
    refitted at every attempt, so every k-th sample of each throw is kept (its release sample
    always) until the set has at most ``max_samples`` samples. A throw's ``measured_share`` (the
    share of its samples that stand for a measurement, which BIC counts) grows by what thinning
    dropped: the kept samples still rest on the same measurements, up to one each.
    """
    demos.require(COLUMNS)
    if len(demos) < 2:
        raise InputError(f"learning needs at least 2 demonstrations, got {len(demos)}")
    step = max(1, math.ceil(demos.n_samples / max_samples))
    thinned = []
    for t in demos:
        keep = np.unique(np.r_[np.arange(0, len(t), step), len(t) - 1])
        meta = dict(t.meta)
        if "measured_share" in meta:
            meta["measured_share"] = min(1.0, float(meta["measured_share"]) * len(t) / keep.size)
        thinned.append(t.replace(data={c: t[c][keep] for c in COLUMNS}, meta=meta))
    return Dataset(thinned, context=("distance",))


def _require_reach(robot, basket, pedestal: float) -> None:
    from rlff.sim import require_reachable

    require_reachable(basket, robot, pedestal)


def learnable_basket(demos: Dataset, mapping, basket, pedestal: float = 0.0) -> float:
    """Farthest basket centre (m) of ``basket``'s shape that :func:`learn` accepts from ``demos``:
    what the throws of its angle grid reach (see :func:`_require_executable`)."""
    from rlff.sim.reach import executable_reach, farthest_basket

    start, release = mapping.angle_offset + mapping.angle_scale * _angle_grid(_learning_demos(demos))[[0, -1]]
    reach = executable_reach(mapping, basket.rim_height, pedestal, release, swing_from=start)
    return farthest_basket(reach.distance, basket.opening)


def _require_executable(mapping, basket, pedestal: float, angles: np.ndarray) -> None:
    """Refuse a basket that no throw of this loop can reach, before the first throw.

    Every method throws along the same angle grid (rad, shape (T,)), so the driven joint swings
    from its mapped first angle and lets go at the mapped last one, at most at its speed limit
    (and what its acceleration and jerk limits allow over that swing), the other joints at the
    start pose.
    """
    from rlff.sim.reach import require_executable

    start, release = mapping.angle_offset + mapping.angle_scale * angles[[0, -1]]
    require_executable(basket, mapping, pedestal, release, swing_from=start,
                       release_source="where the demonstrations let go")


def _require_demos_within_limits(demos: Dataset, mapping) -> None:
    """Every demonstration's path must map inside the driven joint's position range.

    Speeds beyond the robot's limits are allowed (the robot saturates when it executes a throw
    that fast), but a path outside the joint's range means the mapping does not fit the data.
    """
    for demo in demos:
        angle = demo["angle"]
        try:
            _, report = mapping.to_robot(angle, _forward_velocity(angle, demo["velocity"]), clip=True)
        except InputError as exc:
            raise InputError(
                f"demonstration {demo.id!r} is not one throw up to its release ({exc}); clean "
                "the demonstrations first (rlff data preprocess --preset thesis, or --preset)"
            ) from None
        if report.count("position"):
            positions = mapping.angle_offset + mapping.angle_scale * angle[[0, -1]]
            raise InputError(
                f"demonstration {demo.id!r} is beyond the robot's joint limits: its path maps to "
                f"{mapping.joint} positions {positions[0]:.3f} .. {positions[1]:.3f} rad "
                f"({report.summary()}); check the robot file's [throwing] mapping"
            )


def _simulator(robot, basket, pedestal: float) -> Executor:
    from rlff.sim import simulate_throw

    def execute(trajectory: JointTrajectory) -> Outcome:
        return simulate_throw(trajectory, basket, robot=robot, pedestal=pedestal)

    return execute


def _hit_tolerance(basket) -> float:
    """Half-width (m) of the landing window of a hit: half the opening less the ball's radius."""
    from rlff.sim.arm import BALL_RADIUS

    return max(0.5 * basket.opening - BALL_RADIUS, 0.25 * basket.opening)


def _angle_grid(demos: Dataset) -> np.ndarray:
    """The angle grid (rad) of generated throws, shape (T,).

    From the median first angle to the release angle, with the median number of samples of a
    demonstration (at least ``MIN_POINTS``). The release is the ``RELEASE_QUANTILE`` quantile of the demonstrations' last
    angles: early enough that most demonstrations cover the whole path, so the mixture's
    velocity at the release rests on most of them rather than on the few that went farthest.
    """
    first = float(np.median([t["angle"][0] for t in demos]))
    last = float(np.quantile([t["angle"][-1] for t in demos], RELEASE_QUANTILE))
    count = int(np.median([len(t) for t in demos]))
    if first == last:
        raise InputError("the demonstrations do not move: first and last angles coincide")
    return np.linspace(first, last, max(count, MIN_POINTS))


def _components(demos: Dataset, seed: int) -> int:
    """Number of mixture components, chosen once by BIC on the demonstrations.

    At most ``MAX_COMPONENTS``: the loop asks the mixture for distances beyond the
    demonstrations, where many small components make the regression wiggle.
    """
    from rlff.model import Model

    model = Model.fit(demos, inputs=("angle", "distance"), outputs=("velocity",),
                      components="auto", max_components=MAX_COMPONENTS, seed=seed)
    return int(model.n_components)


def _forward_velocity(angle: np.ndarray, velocity: np.ndarray, crawl: float = 0.1) -> np.ndarray:
    """Velocity (rad/s), shape (T,), with any sample against the direction of motion set to 0.

    A mixture's output may dip just below zero where a throw starts from rest; a joint cannot
    move backwards along a path that goes forwards. A proposal with no forward motion at all
    (a DMM mode on the wrong side of zero everywhere) is executed as a crawl at ``crawl``
    rad/s: the robot moves along the path and the ball drops, a miss like any other.
    """
    direction = math.copysign(1.0, float(angle[-1] - angle[0]))
    speed = np.maximum(direction * np.asarray(velocity, dtype=float), 0.0)
    if not np.any(speed > 0):
        speed = np.full(speed.shape, crawl)
    return direction * speed


def _as_reported(attempt: Attempt, feedback: str, centre_window: float = math.inf) -> Attempt:
    """The attempt as the feedback reports it: without landing and miss for binary feedback, and
    a hit only within ``centre_window`` (m) of the centre (``until="centred"``)."""
    hit = attempt.hit and abs(attempt.miss) <= centre_window
    if feedback == "distance":
        return attempt if hit == attempt.hit else replace(attempt, hit=hit)
    return replace(attempt, hit=hit, landing=math.nan, miss=math.nan)


def _json_number(value: float) -> float | None:
    """None for NaN (a throw with no landing point), which JSON cannot hold."""
    return float(value) if math.isfinite(value) else None

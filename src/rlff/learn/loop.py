"""The closed learning-from-failure loop (thesis 1.1.2 and chapter 5's open last step).

fit -> generate the DMM's throw for the basket distance -> map it to the robot -> execute ->
record the attempt -> update -> repeat, until a hit (or, with ``until="centred"``, a hit near the
basket's centre) or the budget is spent.

One joint or the whole arm: by default the human elbow's angle drives one robot joint (the
robot file's ``[throwing]`` table). With ``joints`` (e.g. joint_2, joint_3[, joint_5]) the
``[whole_arm]`` table maps the human shoulder, elbow (and wrist) to them: the elbow's angle stays
the throw's phase, the model's outputs become the elbow's velocity and the other joints'
positions and velocities along it (:func:`rlff.dataset.joint_outputs`), and every proposal,
attempt and log line carries all of them. The basket may stand at a ``bearing`` (joint 1 turns
the arm to face it; people face the basket they throw at, so the arm's motion in its plane does
not depend on the bearing and every demonstration is used whatever its bearing) and at a rim
``height``: demonstrations labelled with rim heights learn from those at the height nearest the
basket's (a throw that drops into a 1 m rim is not one that drops into a 0.3 m rim).

The loop works on what the robot does. The demonstrations are checked against the robot
through the human-to-robot mapping before anything runs; every proposed throw is mapped to the
robot and saturated at the joint limits if it goes beyond them (the robot never exceeds a
limit, and the attempt says how many values were clipped); that saturated path, the one the
motion planner is given, is mapped back to the demonstrations' units and joins the data (the
planner keeps its first pose and its release, where the ball's flight is decided, exactly, and
replaying the attempt plans the same trajectory again). Every attempt goes to the
attempts log the moment it ends, and a run started again with the same log continues after
the last recorded attempt, exactly as the uninterrupted run would have.
"""

from __future__ import annotations

import math
import numbers
import re
import time as clock
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from functools import partial
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from rlff.dataset import Dataset, joint_outputs, velocity_column
from rlff.errors import InputError, RlffError
from rlff.learn.aim_hint import aim_hint
from rlff.learn.attempt import Attempt
from rlff.learn.baselines import BASELINES
from rlff.learn.carry import carried_offsets
from rlff.learn.demos import (
    RELEASE_QUANTILE,
    RELEASE_QUANTILES,
    RELEASE_WORDS,
    angle_grid,
    drives_whole_arm,
    fingerprint,
    forward_velocity,
    loop_components,
    require_units,
    typical_throw,
    usable_demos,
)
from rlff.learn.log import AttemptLog, require_log_file, robot_record
from rlff.learn.method import FEEDBACKS, Method, Problem
from rlff.learn.method_import import EXAMPLE, import_method
from rlff.learn.proposal_check import changed_words, proposed, short_repr
from rlff.learn.reach import (
    SAME_REPORTED,
    aimed_factor,
    arm_reach,
    beyond_reach,
    more_joints_words,
    release_elasticity,
    same_throw_at_the_limit,
    same_throw_reported_the_same,
    saturation_factor,
    typical_landing,
)
from rlff.learn.strategies import STRATEGIES
from rlff.learn.windows import MISREPORT
from rlff.limits import DISTANCE_RANGE, as_names, check_pedestal
from rlff.timing import time_along_path
from rlff.trajectory.joint import JointTrajectory
from rlff.wording import numbered

#: Every method the loop can run, by name: update strategies first, then baselines.
METHODS: dict[str, type[Method]] = {**STRATEGIES, **BASELINES}


def method_of(update: str | type[Method]) -> type[Method]:
    """The method ``update`` names (:data:`METHODS`), or ``update`` itself: a subclass of
    :class:`rlff.learn.Method` of the caller's (docs/learn.md, "Writing your own method"),
    given as the class or as ``"MODULE:CLASS"`` (:func:`rlff.learn.method_import.import_method`).

    Raises
    ------
    InputError
        An unknown name; a MODULE:CLASS that does not import; a class that is no method, has no
        ``name`` of its own (the attempts log and the benchmark's table know a method by it) or
        takes a built-in method's, or names a feedback the loop does not give.
    """
    known = ", ".join(METHODS)
    if isinstance(update, str):
        if update in METHODS:
            return METHODS[update]
        if ":" not in update or update.partition(":")[0] in METHODS:  # calibrate:typo is no module's
            raise InputError(f"unknown update {update!r} (known: {known}); a method of your own is MODULE:CLASS, "
                             f"e.g. {EXAMPLE}; a log it wrote names it by its class's name and resumes with it")
        update = import_method(update)
    if not (isinstance(update, type) and issubclass(update, Method)):
        raise InputError(f"update must be a method's name ({known}) or a subclass of rlff.learn.Method, "
                         f"got {short_repr(update)} ({type(update).__name__})")
    title = update.__qualname__
    if not (isinstance(update.name, str) and update.name.strip()):
        raise InputError(f"method {title} has no name: set its class attribute name (the attempts log and the "
                         "benchmark's table know it by that)")
    if METHODS.get(update.name, update) is not update:
        raise InputError(f"method {title} is named {update.name!r}, as a built-in method is: give it a name of its "
                         "own (a log resumes only with the method its header names)")
    unknown = [kind for kind in update.feedbacks if kind not in FEEDBACKS]
    if unknown or not update.feedbacks:
        raise InputError(f"method {title} has feedbacks {update.feedbacks!r}: a tuple of "
                         f"{' and '.join(repr(kind) for kind in FEEDBACKS)}, those it can work with")
    if getattr(update.propose, "__isabstractmethod__", False):
        raise InputError(f"method {title} has no propose(history): it returns the next throw, an "
                         "rlff.learn.Proposal")
    return update


def require_carrying(method: type[Method]) -> None:
    """Refuse to carry earlier runs' hits (:mod:`rlff.learn.carry`) into a run of ``method``, a
    method that does not carry (:attr:`rlff.learn.Method.carries`), naming the built-in methods
    (:data:`METHODS`) that do.

    Raises
    ------
    InputError
        ``method`` does not carry: what a carry is, why this method has none, which methods do.
    """
    if method.carries:
        return
    carrying = [name for name, known in METHODS.items() if known.carries]
    whole = [name for name in carrying if ":" not in name]
    ablated = [name for name in whole if any(other.startswith(f"{name}:") for other in carrying)]
    named = ", ".join(whole) + (f" (and the ablations of {' and '.join(ablated)})" if ablated else "")
    if METHODS.get(method.name) is method:
        why = (f"{method.name} learns by refitting the DMM to its attempts, not by a speed over a start of its own, so "
               "its attempts log no such offset and a carried one would not move its throws")
    else:
        why = (f"{method.name} does not say it carries (a method of one's own that starts at problem.carried_shift "
               "and logs each attempt's info['log_factor'] sets its class attribute carries = True)")
    raise InputError(f"update {method.name!r} cannot carry earlier runs' hits (--carry): a hit is carried as the "
                     f"speed offset at which it hit, in log speed over its method's start, and {why}. The methods "
                     f"that carry: {named}; or learn without --carry")



#: When a run stops: at the first hit, or at the first hit within the centre share of the opening.
UNTILS = ("hit", "centred")
#: Default share of the opening (centre to rim) a centred hit lands within.
CENTRE_SHARE = 0.5
#: Where the speed search of ``calibrate`` (and the GMR baselines' start) puts the basket: where
#: the robot file's kinematics send the throw (``kinematics``), or at the demonstrations' own
#: speed (``demonstrations``); ``auto``: the kinematics for a whole-arm throw, the
#: demonstrations for a one-joint one (see :func:`learn`).
AIMS = ("auto", "kinematics", "demonstrations")
#: The log header's keys a user sets with an option of ``rlff learn``: (the option, how a header
#: without the key reads). A resumed log that differs in one names it, in this order, first.
RUN_OPTIONS: dict[str, tuple[str, str | None]] = {
    "joints": ("--joints", "one joint (the [throwing] table's)"),
    "until": ("--until", None),
    "basket.distance": ("--basket", None),
    "basket.rim_height": ("--height", None),
    "basket.bearing": ("--bearing", "0.0"),
    "feedback": ("--feedback", None),
    "update": ("--update", None),
    "seed": ("--seed", None),
    "robot": ("--robot", None),
    "pedestal": ("--pedestal", None),
    "executor": ("--executor", "'sim'"),
    "gap": ("--gap", "'none'"),
    "misreport": ("--misreport", repr(MISREPORT)),
    "centre_share": ("--centre-share", None),
    "carried": ("--carry", "none"),
    "aim": ("--aim", "'auto'"),
}
#: :func:`learn`'s parameter that sets each key of :data:`RUN_OPTIONS` whose name it does not have.
RUN_PARAMETERS = {"basket.distance": "basket", "basket.rim_height": "height", "basket.bearing": "bearing",
                  "executor": "executor or executed_on", "carried": "carry_from"}


def log_options() -> dict[str, tuple[str, str | None]]:
    """:data:`RUN_OPTIONS` as the attempts log names them when a resumed log differs: the
    parameter of :func:`learn`, then the option of ``rlff learn`` (``executor or executed_on
    (--executor)``). A log a Python executor wrote, resumed without one, had been said to differ
    "from --executor", which no library call has."""
    return {key: (f"{RUN_PARAMETERS.get(key, key)} ({option})", absent) for key, (option, absent) in RUN_OPTIONS.items()}


def run_options(feedback: str = "binary", until: str = "hit", centre_share: float | None = None,
                misreport: float | None = None, *, update: str | type[Method] = "calibrate",
                carry_from: Sequence[str | Path] = (), log_path: str | Path | None = None, aim: str = "auto",
                as_options: bool = False) -> tuple[type[Method], float, float]:
    """``(method class, centre_share, misreport)`` of a run of :func:`learn` with these options,
    checked before anything is read: the class ``update`` names (:func:`method_of`), None
    standing for the defaults (:data:`CENTRE_SHARE`, :data:`rlff.learn.windows.MISREPORT`).
    Messages name :func:`learn`'s parameters (``until='centred'``); with ``as_options``, ``rlff
    learn``'s options (``--until centred``, ``--log``; :func:`options_words`).

    Raises
    ------
    InputError
        A ``log_path`` that is no regular file (:func:`rlff.learn.log.require_log_file`), an
        unknown ``aim``, an unknown ``update`` (:func:`method_of`), ``carry_from`` into a method
        that does not carry (:func:`require_carrying`), an unknown ``feedback`` or ``until``, a
        value out of its range, or an option given where it changes nothing: ``centre_share``
        without ``until='centred'``, ``misreport`` with distance feedback (it went into the log's
        header, and the command line could then never resume that log).
    """
    if log_path is not None:  # a device or a FIFO is no log, and it would be read first
        try:
            require_log_file(log_path)
        except InputError as exc:
            if not as_options:
                raise
            raise InputError(f"--log {exc}") from None
    if aim not in AIMS:
        raise InputError(f"unknown {'--aim' if as_options else 'aim'} {aim!r} (known: {', '.join(AIMS)})")
    method_class = method_of(update)  # a MODULE:CLASS imported once
    if carry_from:
        require_carrying(method_class)
    try:
        return (method_class, *_shares(feedback, until, centre_share, misreport))
    except InputError as exc:
        if not as_options:
            raise
        raise InputError(options_words(str(exc))) from None


def _shares(feedback: str, until: str, centre_share: float | None, misreport: float | None) -> tuple[float, float]:
    """``(centre_share, misreport)`` of :func:`run_options`, checked with ``feedback`` and ``until``."""
    if feedback not in FEEDBACKS:
        raise InputError(f"unknown feedback {feedback!r} (known: {', '.join(FEEDBACKS)})")
    if until not in UNTILS:
        raise InputError(f"unknown until {until!r} (known: {', '.join(UNTILS)})")
    if centre_share is not None and until != "centred":
        raise InputError("centre_share is how near the centre a hit must land to stop a run until='centred'; "
                         "until='hit' (the default) stops at the first hit: add until='centred', or drop centre_share")
    if misreport is not None and feedback != "binary":
        raise InputError("misreport is the chance that a hit is reported as a miss: it goes with feedback='binary' "
                         "(add it, or drop misreport)")
    centre_share = CENTRE_SHARE if centre_share is None else centre_share
    misreport = MISREPORT if misreport is None else misreport
    if not (_is_number(centre_share) and 0 < centre_share <= 1):
        raise InputError(f"centre_share must be in (0, 1] of the half-opening, got {centre_share!r}")
    if not (_is_number(misreport) and 0 <= misreport < 1):
        raise InputError(f"misreport is the probability that a hit is reported as a miss, in [0, 1); got {misreport!r}")
    return float(centre_share), float(misreport)


def options_words(text: str) -> str:
    """A message of :func:`learn`'s, which names its parameters, with ``rlff learn``'s options:
    ``until='centred'`` as ``--until centred``, ``centre_share`` as ``--centre-share`` (the
    options of :data:`RUN_OPTIONS`)."""
    options = {key: option for key, (option, _) in RUN_OPTIONS.items() if key.isidentifier()}
    text = re.sub(r"\b(\w+)='([^']*)'", lambda m: f"{options[m[1]]} {m[2]}" if m[1] in options else m[0], text)
    return re.sub(r"(?<![\w-])(centre_share|misreport)(?![\w-])", lambda m: options[m[1]], text)


def _is_number(value) -> bool:
    """A real number, not a bool."""
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


class Outcome(Protocol):
    """What an executor reports about one throw (``rlff.sim``'s ThrowOutcome is one): ``hit``
    (a bool), ``landing_x`` (m from the robot's base along the basket's line, finite: for a ball
    that never came down through the rim's height, where it first touched, as ``rlff.sim``
    reports it; NaN or None where not measured) and ``miss`` (``landing_x`` less the basket's
    distance, m, negative short; NaN where not measured), checked as :func:`reported_outcome`
    says: with distance feedback a miss, with ``until="centred"`` a hit, must be measured."""

    hit: bool
    landing_x: float
    miss: float


#: Runs one robot trajectory and reports its outcome. The trajectory is the attempt's throw as the
#: loop planned it: from rest at the throw's own first pose, through its release, braked to rest.
#: An arm stands where its last throw braked it (about a radian away on the Comau's joint_2 from
#: the second attempt on): an executor that drives an arm sends
#: ``rlff.learn.plan_from_pose(trajectory, robot, pose)``, the same throw after an approach from
#: the arm's pose at rest, as the ROS executors do, never the trajectory as it comes.
Executor = Callable[[JointTrajectory], Outcome]


def best_attempt(history: Sequence[Attempt]) -> Attempt | None:
    """The throw of ``history`` to keep (what ``rlff learn --out`` writes, and what a stopped run
    says to export): the last hit, else the attempt that came down nearest the basket's centre
    (smallest ``abs(miss)``, m; the first of equals), else None (no attempt, or no landing measured)."""
    hits = [a for a in history if a.hit]
    if hits:
        return hits[-1]
    landed = [a for a in history if math.isfinite(a.miss)]
    return min(landed, key=lambda a: abs(a.miss)) if landed else None


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
        negative short, positive long, hits included; NaN where not measured (binary feedback
        does not need it).
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
    out_of_reach : bool
        The basket is beyond the arm: the last :data:`~rlff.learn.reach.SHORT_AT_THE_LIMIT`
        throws came down short of it by more than the fastest release the joints allow would
        make up (see :func:`rlff.learn.reach.shortfall_at_the_limit`), and the run stopped there
        (before its budget, unless they were its last); a note says by how much. With
        ``until="centred"``: short of the centre window (``centre_out_of_reach`` says whether
        only that window is beyond the arm).
    centre_out_of_reach : bool
        A run ``until="centred"`` stopped out of reach (``out_of_reach``) where the basket is not
        shown to be: it was hit, or the fastest release would still reach its rim; only the
        centre window is beyond the arm's fastest throws.
    repeated : bool
        The last :data:`~rlff.learn.reach.SAME_AT_THE_LIMIT` throws let go the same way at the
        fastest release the joints allow (:func:`rlff.learn.reach.same_throw_at_the_limit`): the
        method asked for more speed than the arm has, and the run stopped there; a note says
        where they came down.
    unchanged : bool
        The last :data:`~rlff.learn.reach.SAME_REPORTED` throws let go the same way, below the
        fastest release (else ``repeated`` stops the run first), and each was reported to the
        method the same (:func:`rlff.learn.reach.same_throw_reported_the_same`): the method is
        not changing its throw, and the run stopped there; a note says what they were told.
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
    out_of_reach: bool = False
    centre_out_of_reach: bool = False
    repeated: bool = False
    unchanged: bool = False

    @property
    def best(self) -> Attempt | None:
        """The throw to keep: :func:`best_attempt` of the history."""
        return best_attempt(self.history)

    def __repr__(self) -> str:
        """One line: the outcome, the attempts, every signed miss (m, to the millimetre), the
        basket, the feedback and the method; not the attempts' arrays (the dataclass printed
        kilobytes of them)."""
        misses = ", ".join(f"{miss:.3f}" for miss in self.misses)
        return (f"LearningResult(hit={self.hit}, attempts={self.attempts}, misses=[{misses}], target={self.target:g}, "
                f"feedback={self.feedback!r}, update={self.update!r})")

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
            # a run that stops at any hit has no centre window to say anything about
            **({"centred": self.centred, "centre_window": self.centre_window,
                "centre_out_of_reach": self.centre_out_of_reach} if self.until == "centred" else {}),
            "out_of_reach": self.out_of_reach,
            "repeated": self.repeated,
            "unchanged": self.unchanged,
            "notes": self.notes,
        }


def learn(
    demos: Dataset | str | Path,
    basket: float,
    *,
    budget: int = 20,
    feedback: str = "binary",
    update: str | type[Method] = "calibrate",
    seed: int = 0,
    log_path: str | Path | None = None,
    executor: Executor | None = None,
    progress: Callable[[Attempt], None] | None = None,
    resuming: Callable[[int], None] | None = None,
    robot: str | Any = "comau_smart5_six",
    pedestal: float = 0.0,
    rim_height: float = 0.3,
    opening: float = 0.35,
    until: str = "hit",
    centre_share: float | None = None,
    executed_on: str | None = None,
    joints: Sequence[str] | None = None,
    bearing: float = 0.0,
    height: float | None = None,
    carry_from: Sequence[str | Path] = (),
    gap: str = "none",
    misreport: float | None = None,
    aim: str = "auto",
) -> LearningResult:
    """Learn to hit a basket at distance ``basket`` from (possibly failed) demonstrations.

    Parameters
    ----------
    demos : Dataset or path
        Demonstrations (or the file that holds them, read by :func:`rlff.formats.read_dataset`:
        CSV, NPZ, Parquet or the thesis' matrix) with columns ``angle`` (rad), ``distance`` (m:
        the basket aimed at) and ``velocity`` (rad/s), one throw per trajectory up to its
        release, in the human units the robot mapping takes; for a whole-arm throw also the
        driven joints' columns (``shoulder``, ``shoulder_velocity``, ``wrist``,
        ``wrist_velocity``), and optionally ``height`` (m).
        Metadata ``landing`` (m), where known, is used by ``calibrate``.
    basket : float
        Distance of the basket's centre from the robot's base axis (m).
    budget : int
        Largest number of attempts, counting those resumed from the log.
    feedback : {"binary", "distance"}
        What an attempt reports to the method: hit or miss only, or the signed miss as well.
    update : str or Method subclass
        An update strategy (``calibrate``, the default; ``donut``, ``failure``, ``hindsight``),
        each also as its ablations ``NAME:no-exploration`` and ``NAME:gmr-mean``, or a baseline
        (``sweep``, ``secant``, ``gp-bo``, ``cma``, ``random``, ``imitation``); see :data:`METHODS`.
        Or a method of one's own: a subclass of :class:`rlff.learn.Method`, the class or
        ``"MODULE:CLASS"`` (:func:`method_of`; docs/learn.md, "Writing your own method"), known in
        the log and the result by its ``name``.
    seed : int
        Seed of every random choice; a run is reproducible from it.
    log_path : str or Path, optional
        Attempts log (JSONL); resumed when it exists. Its header records ``budget`` (a run
        resumed with another one writes its own there with its first attempt).
    executor : callable, optional
        ``executor(joint_trajectory) -> outcome`` with ``hit``, ``landing_x`` and ``miss``;
        default: the MuJoCo simulation of :mod:`rlff.sim` for this basket. The trajectory starts
        at rest at the throw's first pose, not where the arm is: an executor that drives an arm
        sends :func:`rlff.learn.plan_from_pose` of it from the arm's pose (see :data:`Executor`).
    progress : callable, optional
        Called with every attempt as it ends, the attempts resumed from the log first.
    resuming : callable, optional
        ``resuming(count)``, called once before ``progress`` is given any attempt and before the
        first throw, with how many attempts were taken from the log (0 without one): the first
        ``count`` attempts ``progress`` is given come from the log, and the first throw of this
        call is attempt ``count + 1`` (what :meth:`rlff.learn.robot.RobotExecutor.resume` takes).
    robot : str or Robot
        Robot name, robot file or description; its ``[throwing]`` table is the one-joint
        mapping, its ``[whole_arm]`` table the whole arm's. One without ``[geometry]`` cannot be
        simulated, but an ``executor`` throws with it: the reach checks before the first throw,
        the stop at a basket beyond the arm and the searches' landing law need the geometry and
        are left out, and the kinematics' ``aim`` is refused.
    pedestal, rim_height, opening : float
        Height of the robot's base, of the basket's rim, and the basket's inner width (m).
    until : {"hit", "centred"}
        Stop at the first hit, or keep refining after hits near the rim until a throw lands
        within ``centre_share`` of the opening: ``abs(miss) <= centre_share * opening / 2``.
        Methods are then told "hit" only for such throws (and size their steps by that
        narrower window), so every method and both feedbacks work unchanged.
    centre_share : float, optional
        In (0, 1]: the share of the half-opening a centred hit lands within; with
        ``until="centred"`` only (it would change nothing else, and is refused); None:
        :data:`CENTRE_SHARE`.
    executed_on : str, optional
        What ``executor`` runs the throws on (``sim``, ``ros1``, ``ros2``, or a name of the
        caller's): a log resumes only on the same (a run in simulation writes no such field, so
        older logs resume). None: ``sim`` without an executor, ``python`` with one (the caller's
        own arm; its log had said it was a simulation's, and resumed in one).
    joints : sequence of str, optional
        Robot joints the throw drives (``joint_2``, ``joint_3`` [, ``joint_5``]) through the
        robot file's ``[whole_arm]`` table; None (or ``("joint_2",)``) is the one-joint throw.
    bearing : float
        Direction of the basket (deg, 0 straight ahead, positive to the left): joint 1 turns
        the arm to it before the throw.
    height : float, optional
        The basket rim's height (m); default ``rim_height``.
    carry_from : sequence of paths
        Attempts logs of earlier runs at other baskets (the same method, demonstrations, robot,
        joints and pedestal): the speed offsets of their hits centre this run's search
        (:mod:`rlff.learn.carry`). Only methods that carry (:attr:`rlff.learn.Method.carries`:
        ``calibrate``, ``donut`` and the GMR baselines) take them; the ``failure`` and
        ``hindsight`` updates, which move the DMM rather than a speed, are refused before
        anything is read. The offsets go into this run's log header, so it resumes only with the
        same.
    gap : str
        How the simulated arm differs from its robot file: ``none``, ``speed:G`` (it reaches G
        of the commanded joint speeds) or ``delay:S`` (it lets go S s late;
        :func:`rlff.sim.gap.parse_gap`). The loop plans and aims with the file; the
        simulation executes every throw as that arm would. Only with the default executor; the
        log's header records it, so a run resumes only on the same arm.
    misreport : float, optional
        In [0, 1): with binary feedback, the probability that a hit is reported as a miss (a
        ball that rattles out, a sensor that misses it). ``calibrate`` throws a likely window
        that missed once more where a misreported hit there is likelier than a hit in the
        windows left (:func:`rlff.learn.windows.with_retries`); 0: no window twice before the
        second pass. A value other than the default goes into the log's header. Refused with
        distance feedback (it had gone into the header there too, and ``rlff learn`` could never
        resume that log); None: :data:`rlff.learn.windows.MISREPORT`.
    aim : {"auto", "kinematics", "demonstrations"}
        Where the speed search starts (:data:`AIMS`). ``kinematics``: at the speed at which the
        robot file's geometry and the free flight from the release send the method's first
        throw to the basket (:func:`rlff.learn.reach.aimed_factor`), with the narrow prior
        :data:`rlff.learn.strategies.AIM_SCALE` about it; the GMR baselines start there too
        (the same information), and ``failure`` and ``hindsight`` throw the DMM's throw sped up
        or slowed down to it (:class:`rlff.learn.strategies.RefitUpdate`). ``demonstrations``:
        where the demonstrations' speeds (their landings, their labels' range law, or the GMR
        mean) put it. ``auto`` (default): the
        kinematics for a whole-arm throw, whose mapping moves a human throw's landing far; the
        demonstrations for a one-joint throw, the benchmark's setting, where the mapping kept
        the simulated people's landings close. On real recordings the one-joint mapping need not
        (the MSR throws' speeds map to the speed limit at every basket), and ``kinematics``
        starts there. An aim other than the default goes into the log's header.

    Returns
    -------
    LearningResult
        Also when the run stops before its budget because the basket is beyond the arm's reach
        (``out_of_reach``: the executor reported :data:`~rlff.learn.reach.SHORT_AT_THE_LIMIT`
        landings in a row that no faster release could bring to the basket; an arm slower than
        its robot file, a late release or a heavier ball does that), or because the method asks
        for the same throw at the arm's limit again (``repeated``), or throws the same throw below
        it, reported the same each time, :data:`~rlff.learn.reach.SAME_REPORTED` times in a row
        (``unchanged``), with a note that says so.

    Raises
    ------
    InputError
        Unknown method or feedback, a method that needs other feedback, an executor that is not
        callable, a carry into a method that does not carry (:func:`require_carrying`), a basket
        out of the robot's reach, a robot file without ``[geometry]`` in simulation or aimed by
        its kinematics, demonstrations beyond the joint limits, a log path that is no regular file
        (a device, a FIFO), or a corrupt or foreign log. A
        method's proposal that is no :class:`~rlff.learn.method.Proposal` or does not follow
        ``problem.angles`` (:func:`rlff.learn.proposal_check.proposed`), stopping the run at that
        attempt; an error that stops an attempt and names it ends "(the log keeps the attempts
        before)" where there is a log and attempts in it.
    """
    from rlff.robot import Robot, load_robot, mapping_for
    from rlff.robot.mapping import require_bearing
    from rlff.sim import Basket

    # one path given where several may be: that one, not its letters (joints: as_names)
    carry_from = (carry_from,) if isinstance(carry_from, str | Path) else carry_from
    method_class, centre_share, misreport = run_options(feedback, until, centre_share, misreport, update=update,
                                                        carry_from=carry_from, log_path=log_path, aim=aim)
    update = method_class.name  # what the log and the result know it by
    if feedback not in method_class.feedbacks:
        raise InputError(f"update {update!r} needs {' or '.join(method_class.feedbacks)} feedback, "
                         f"not {feedback!r}")
    if not (isinstance(budget, numbers.Integral) and not isinstance(budget, bool) and budget >= 1):
        raise InputError(f"budget must be a positive whole number of attempts, got {budget!r}")
    budget = int(budget)
    if not (isinstance(seed, numbers.Integral) and not isinstance(seed, bool) and seed >= 0):
        raise InputError(f"seed must be a whole number >= 0, got {seed!r}")
    seed = int(seed)
    if executor is not None and not callable(executor):
        raise InputError(f"executor must be a callable, executor(joint_trajectory) -> outcome with hit, landing_x "
                         f"and miss; got {type(executor).__name__} {short_repr(executor)}")
    demos = _demonstrations(demos)
    require_units(demos)  # before anything is judged in them (a unit slip is the likeliest fault)
    from rlff.sim.gap import parse_gap

    arm_gap = parse_gap(gap)
    if executor is not None and not arm_gap.none:
        raise InputError(f"gap {arm_gap.name!r} is how the simulated arm differs from its robot file: it goes "
                         "with the simulation, not with another executor")
    if executed_on is None:
        executed_on = "sim" if executor is None else "python"
    robot_model = robot if isinstance(robot, Robot) else load_robot(robot)
    mapping = mapping_for(robot_model, None if joints is None else as_names(joints))
    # for a new one-joint run aimed by the demonstrations where the kinematics would likely do better
    hint = aim_hint(robot_model, demos) if aim == "auto" and not drives_whole_arm(mapping) else None
    rim = rim_height if height is None else height
    # checks the stated range
    target = Basket(float(basket), rim_height=rim, opening=opening, bearing=float(bearing))
    require_bearing(mapping, target.bearing)  # before the log opens: a run refused by it leaves none
    pedestal = check_pedestal(pedestal)
    kinematic = drives_whole_arm(mapping) if aim == "auto" else aim == "kinematics"
    # without [geometry] nothing says where a throw goes: the simulation refuses (its own message),
    # a live arm throws with the reach checks left out, but the kinematics' aim cannot start anywhere
    reckoned = robot_model.geometry is not None or executor is None
    if not reckoned and kinematic:
        which = ("aim='auto' (--aim auto) of a whole-arm throw, the kinematics," if aim == "auto"
                 else "aim='kinematics' (--aim kinematics)")
        raise InputError(f"{robot_model.source}: the robot has no [geometry] table, and {which} starts where the "
                         "arm's geometry sends the throw; give the robot file a [geometry] table, or "
                         "aim='demonstrations' (--aim demonstrations)")
    if reckoned:
        try:
            _require_reach(robot_model, target, pedestal, mapping.driven_joints, demos.columns)
        except InputError as exc:
            raise InputError(f"{exc}{_executed_reach_words(demos, mapping, target, pedestal)}") from None
    demos, limit_notes = usable_demos(demos, mapping, target.rim_height)
    components = loop_components(demos, seed, joint_outputs(mapping.human_columns))
    release = release_quantile(demos, mapping, target, pedestal) if reckoned else RELEASE_QUANTILE
    if reckoned:
        _require_executable(mapping, target, pedestal, demos, components, seed, method_class, release)
    if executor is None:
        executor = _simulator(robot_model, target, pedestal, arm_gap)

    basket_record = target.to_dict()
    if not basket_record.get("bearing"):  # straight ahead: the header older versions wrote
        basket_record.pop("bearing", None)
    run = {
        "basket": basket_record,
        "feedback": feedback,
        "update": update,
        "seed": seed,
        "robot": robot_record(mapping),
        "pedestal": pedestal,
        "demos": fingerprint(demos),
        "until": until,
    }
    if until == "centred":
        run["centre_share"] = centre_share
    if executed_on != "sim":
        run["executor"] = executed_on
    if not arm_gap.none:  # a run without one writes no such field, so older logs resume
        run["gap"] = arm_gap.name
    if misreport != MISREPORT:  # the default writes no such field, so older logs resume
        run["misreport"] = misreport
    if drives_whole_arm(mapping):
        run["joints"] = list(mapping.driven_joints)
    if kinematic != drives_whole_arm(mapping):  # the default writes no such field, so older logs resume
        run["aim"] = "kinematics" if kinematic else "demonstrations"
    if release != RELEASE_QUANTILE:  # the default writes no such field, so older logs resume
        run["release_quantile"] = release
    carried, carry_notes = carried_offsets(carry_from, run) if carry_from else ((), [])
    if carried:
        run["carried"] = [round(x, 4) for x in carried]
    log = AttemptLog(log_path, run, log_options(), budget=budget) if log_path is not None else None
    try:
        result = _run(log, method_class, demos, target, feedback, update, seed, budget, mapping, executor,
                      progress, until, centre_window(until, centre_share, target.opening), pedestal, components,
                      tuple(run.get("carried", ())), misreport, kinematic, release, resuming=resuming)
        later = release_note(demos, mapping, target, pedestal, release)
        result.notes[:0] = [hint] * bool(hint and not result.resumed) + limit_notes + [later] * bool(later) + carry_notes
        return result
    finally:
        if log:
            log.close()


def _demonstrations(demos) -> Dataset:
    """``demos`` as :func:`learn` takes them: a :class:`Dataset`, or one read from a path."""
    if isinstance(demos, Dataset):
        return demos
    if isinstance(demos, str | Path):
        from rlff.formats import read_dataset

        return read_dataset(demos)
    raise InputError(f"demos must be a Dataset of demonstrations or the path of a file of them (rlff.formats."
                     f"read_dataset reads .csv, .npz, .parquet and the thesis' .txt), got {type(demos).__name__} "
                     f"{short_repr(demos)}")


def _run(log, method_class, demos, target, feedback, update, seed, budget, mapping, executor, progress,
         until, centre_window, pedestal, components, carried, misreport, kinematic, release, *,
         resuming=None) -> LearningResult:
    """The attempts of :func:`learn` after its checks, with the log (or None) held."""
    history = list(log.contents.attempts) if log else []
    # the attempts as the method is told them, kept beside history (not made again per attempt)
    reported = [_as_reported(a, feedback, centre_window) for a in history]
    resumed = len(history)
    if resuming:
        resuming(resumed)
    for attempt in history:
        if progress:
            progress(attempt)

    problem = _problem(demos, target, feedback, seed, mapping, pedestal, components,
                       tolerance=min(hit_tolerance(target), centre_window), carried=carried, misreport=misreport,
                       aim=kinematic, release=release)

    def done(attempt: Attempt) -> bool:
        return counts_as_hit(attempt, centre_window)

    def out_of_reach_note() -> tuple[str, bool] | None:
        """Judged once after every attempt (and on the attempts resumed from the log): the note,
        and whether only the centre window is beyond the arm (:func:`beyond_reach`); never on a
        robot file without ``[geometry]``, whose fastest release's gain is unknown."""
        if (history and done(history[-1])) or mapping.robot.geometry is None:
            return None
        return beyond_reach(history, mapping, target, pedestal, centre_window)

    def repeated_note() -> str | None:
        """Judged as :func:`out_of_reach_note` is, when that says nothing."""
        if history and done(history[-1]):
            return None
        return same_throw_at_the_limit(history, mapping, aimed=problem.aim is not None)

    def unchanged_note() -> str | None:
        """Judged as :func:`repeated_note` is, when neither rule before says anything: on the
        attempts as the method was told them."""
        if history and done(history[-1]):
            return None
        return same_throw_reported_the_same(reported[-SAME_REPORTED:], mapping)

    def stop_notes() -> tuple[tuple[str, bool] | None, str | None, str | None]:
        """What stops the run after the attempts so far, the first rule that says anything:
        the basket (or the centre window) out of reach, the same throw at the limit, the same
        throw reported the same."""
        out_of_reach = out_of_reach_note()
        repeated = None if out_of_reach else repeated_note()
        unchanged = None if out_of_reach or repeated else unchanged_note()
        return out_of_reach, repeated, unchanged

    out_of_reach, repeated, unchanged = stop_notes()
    method = None  # made at the first attempt this call throws: a finished log needs none
    changed: dict[str, tuple[int, str, list[int]]] = {}  # what the loop changed of a proposal: first, words, attempts
    while (len(history) < budget and not (history and done(history[-1])) and out_of_reach is None
           and repeated is None and unchanged is None):
        method = method or method_class(problem)
        start = clock.perf_counter()
        index = len(history) + 1
        try:
            proposal = proposed(method, problem, list(reported), index)  # a copy: the method may keep or change it
            for kind, words in changed_words(proposal, problem).items():
                changed.setdefault(kind, (index, words, []))[2].append(index)
            attempt = _execute(proposal, index, target, mapping, executor, start,
                               distance_needed=feedback == "distance", hit_distance_needed=until == "centred",
                               method=update)
        except RlffError as exc:
            _tell_what_the_log_keeps(exc, index, log, history)
            raise
        if log:
            log.append(attempt)
        history.append(attempt)
        reported.append(_as_reported(attempt, feedback, centre_window))
        if progress:
            progress(attempt)
        out_of_reach, repeated, unchanged = stop_notes()

    notes = []
    if log and log.contents.dropped_partial_line:
        notes.append(f"{log.path}: dropped a partial last line (a run interrupted mid-write)")
    notes.extend(_changed_note(update, first, words, attempts) for first, words, attempts in changed.values())
    notes.extend(note for note in (out_of_reach and out_of_reach[0], repeated, unchanged) if note)
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
        out_of_reach=bool(out_of_reach),
        centre_out_of_reach=bool(out_of_reach and out_of_reach[1]),
        repeated=bool(repeated),
        unchanged=bool(unchanged),
    )


def _changed_note(method: str, first: int, words: str, attempts: Sequence[int]) -> str:
    """A note that the loop changed the throws ``method`` proposed at ``attempts`` as
    :func:`rlff.learn.proposal_check.changed_words` says (``words``, of attempt ``first``)."""
    which = f"attempt {first}" if len(attempts) == 1 else f"attempts {numbered(attempts)}"
    at = "" if len(attempts) == 1 else f" (at attempt {first})"
    return f"{which}: the throw {method} proposed was changed before it was thrown{at}: {words}"


def _tell_what_the_log_keeps(exc: RlffError, index: int, log: AttemptLog | None, history: Sequence[Attempt]) -> None:
    """End the message of ``exc``, an error that stopped attempt ``index`` and names it
    (``attempt 3: ...``: its proposal, its plan, its outcome, or the robot executor's goal or
    landing), with what the log keeps where that is something: a log, and attempts in it before
    this one. It had said "(the log keeps the attempts before)" of a run without a log, and at
    the first attempt of a fresh log. An error of the caller's own that does not name the
    attempt says what it says (``rlff learn``'s closed stdin speaks of the log itself)."""
    if log is not None and history and str(exc).startswith(f"attempt {index}: "):
        exc.args = (f"{exc} (the log keeps the attempts before)",)


def _problem(demos: Dataset, target, feedback: str, seed: int, mapping, pedestal: float, components: int, *,
             tolerance: float, carried: tuple[float, ...] = (), misreport: float = MISREPORT,
             aim: bool | None = None, release: float = RELEASE_QUANTILE) -> Problem:
    """What a method of :func:`learn` knows before its first attempt at basket ``target``
    (:class:`rlff.sim.Basket`), the demonstrations prepared (:func:`rlff.learn.demos.usable_demos`),
    its throws let go at the ``release`` quantile of their last angles (:func:`release_quantile`);
    a whole-arm throw also the arm's saturation and landing elasticity, and with ``aim`` (None:
    for a whole-arm throw) the kinematics' aim, and their elasticity for a one-joint throw. A
    robot file without ``[geometry]`` (a live arm's) says nothing of where a throw comes down: no
    elasticity of its kinematics (the default's), no landing law, no aim (:func:`learn` refuses it)."""
    whole_arm = drives_whole_arm(mapping)
    aim = whole_arm if aim is None else aim
    typical = typical_throw(mapping, demos, release)
    known = {}
    kinematics = mapping.robot.geometry is not None
    if (whole_arm or aim) and kinematics:
        known["elasticity"] = release_elasticity(mapping, typical, target.distance, target.rim_height, pedestal)
    if aim:
        known["aim"] = partial(aimed_factor, mapping, target.distance, target.rim_height, pedestal)
    if whole_arm:
        known["saturation"] = partial(saturation_factor, mapping)
    return Problem(
        demos=demos,
        target=target.distance,
        feedback=feedback,
        tolerance=tolerance,
        angles=angle_grid(demos, release),
        components=components,
        seed=seed,
        max_speed=mapping.max_human_speeds()["velocity"],
        outputs=joint_outputs(mapping.human_columns),
        carried=carried,
        misreport=misreport,
        landing=partial(typical_landing, mapping, typical, target.rim_height, pedestal) if kinematics else None,
        **known,
    )


def _first_shape(method_class: type[Method], demos: Dataset, mapping, basket, pedestal: float, components: int,
                 seed: int) -> dict[str, np.ndarray]:
    """The path (columns of shape (T,)) of the first throw ``method_class`` makes for ``basket``
    with nothing tried yet: the shape its later throws speed up or slow down, whose reach at the
    joints' limits decides whether a whole-arm basket is within the loop's reach. (The check used
    the GMR mean's shape before, which is not what ``calibrate`` throws: on the real MSR throws
    cut at the middle of the velocity's top its DMM shape reached 3.87 m where the GMR mean's
    reached 4.29 m, and the check accepted baskets 0.4 m beyond the run's throws.)"""
    feedback = "binary" if "binary" in method_class.feedbacks else method_class.feedbacks[0]
    problem = _problem(demos, basket, feedback, seed, mapping, pedestal, components, tolerance=hit_tolerance(basket))
    proposal = proposed(method_class(problem), problem, [], 1)
    path = dict(proposal.path)
    path["velocity"] = forward_velocity(proposal.angle, proposal.velocity)
    return path


def _execute(proposal, index: int, target, mapping, executor: Executor, start: float, *,
             distance_needed: bool = False, hit_distance_needed: bool = False, method: str = "the method") -> Attempt:
    """Map a proposal of ``method`` (its name; checked by
    :func:`rlff.learn.proposal_check.proposed`) to the robot (saturating at its limits), execute
    it, record what it did; its outcome checked by :func:`reported_outcome` (with
    ``distance_needed`` and ``hit_distance_needed``). A proposal that cannot be planned
    (degrees, a path the arm cannot make), such an outcome, or a simulated arm that did not
    follow the throw (:class:`ArmNotFollowed`, from the loop's simulator or an executor's
    :func:`rlff.sim.simulate_throw` outcome): an :class:`InputError` naming attempt ``index``
    (and ``method``)."""
    try:
        path = dict(proposal.path)
        path["velocity"] = forward_velocity(proposal.angle, proposal.velocity)
        path["time"] = time_along_path(proposal.angle, path["velocity"])
        points, trajectory, clip_report = _plan(mapping, path, target.bearing)
    except InputError as exc:
        raise type(exc)(f"attempt {index}: the throw {method} proposed: {exc}") from None
    try:
        outcome = executor(trajectory)
        require_followed(outcome)  # an executor of the caller's may simulate the throw with rlff.sim too
    except ArmNotFollowed as exc:  # the simulator knows no attempt: its error had named none
        raise ArmNotFollowed(f"attempt {index}: {exc}") from None
    try:
        hit, landing, miss = reported_outcome(outcome, target, distance_needed=distance_needed,
                                              hit_distance_needed=hit_distance_needed)
    except InputError as exc:
        raise InputError(f"attempt {index}: {exc}") from None
    executed = mapping.path_from_robot(points)
    return Attempt(
        index=index,
        target=target.distance,
        query=proposal.query,
        angle=executed["angle"],
        velocity=executed["velocity"],
        time=executed["time"],
        hit=hit,
        landing=landing,
        miss=miss,
        exploration=proposal.exploration,
        clipped=len(clip_report),
        seconds=clock.perf_counter() - start,
        info=proposal.info,
        arm={name: executed[name] for name in joint_outputs(mapping.human_columns)[1:]},
    )


def reported_outcome(outcome, basket, *, distance_needed: bool = False,
                     hit_distance_needed: bool = False) -> tuple[bool, float, float]:
    """``(hit, landing, miss)`` of what an executor returned for a throw at ``basket``
    (:class:`rlff.sim.Basket`), checked: the :class:`Outcome` protocol's ``hit`` a bool,
    ``landing_x`` (m along the basket's line from the robot's base; None or NaN: not measured)
    no farther than the farthest basket rlff takes either way, ``miss`` (m, negative short)
    ``landing_x - basket.distance`` where both are known. (A hit far from the basket is not
    refused: a measurement as noisy as ``noisy-distance:0.5`` gives one.)

    A ball that never came down through the rim's height has a landing all the same: where it
    first touched the ground (or the basket), as :func:`rlff.sim.simulate_throw` reports it, and
    every method learns from that point as it does in simulation. +-inf is refused, saying so:
    it had been written into the data as a demonstration's distance (``calibrate``, ``donut``
    and ``hindsight`` stopped at the next attempt on a non-finite ``distance``) or read as a
    throw short at the robot's base (+inf: the secant's next throw was at the speed limit),
    and the loop's own message advised it until 2026-12-07.

    As a person's typed outcome (:func:`rlff.learn.robot.parse_answer`): with
    ``distance_needed`` (distance feedback) a miss must say where the ball came down, with
    ``hit_distance_needed`` (``until="centred"``) a hit must. A miss not measured had been
    taken by the baselines for a ball at the robot's base (the secant then threw at the speed
    limit); a hit not measured, under ``until="centred"``, for no centred hit, and the run threw
    on past its hits to the end of its budget.

    An executor stands for the user's own arm, camera or person, so a unit slip or a slip of
    the protocol comes in here: a landing in centimetres had been learned from (and a resumed
    run then threw behind the arm), ``hit="False"`` counted as a hit.

    Raises
    ------
    InputError
        One line naming the field, what came and what is expected.
    """
    fields = ("hit", "landing_x", "miss")
    if not all(hasattr(outcome, name) for name in fields):
        raise InputError(f"the executor returned {type(outcome).__name__} {short_repr(outcome)}: it must return an "
                         "object with hit (bool), landing_x and miss (m), as rlff.sim.simulate_throw's outcome has")
    hit = outcome.hit
    if not isinstance(hit, bool | np.bool_):
        raise InputError(f"the executor's outcome has hit = {hit!r} ({type(hit).__name__}): give True or False")
    landing, miss = (_metres(getattr(outcome, name), name) for name in ("landing_x", "miss"))
    for name, value in (("landing_x", landing), ("miss", miss)):
        if math.isinf(value):
            raise InputError(f"the executor's outcome has {name} = {value:g}: for a ball that never came down "
                             "through the rim's height, report where it first touched the ground or the basket "
                             "(m along the basket's line), as rlff.sim.simulate_throw does; None or NaN where not "
                             "measured")
    far = DISTANCE_RANGE[1]
    for name, value in (("landing_x", landing), ("miss", miss)):
        if abs(value) > far:
            raise InputError(f"the executor's outcome has {name} = {value:g} m, beyond {far:g} m either way "
                             "(a unit slip? landing_x and miss are in metres)")
    if math.isfinite(landing) and math.isfinite(miss) and abs(miss - (landing - basket.distance)) > 1e-6:
        raise InputError(f"the executor's outcome has miss = {miss:g} m with landing_x = {landing:g} m: the miss "
                         f"is landing_x - the basket's distance ({landing - basket.distance:+g} m for the basket "
                         f"at {basket.distance:g} m)")
    if math.isnan(landing) and math.isnan(miss):  # not measured
        if distance_needed and not hit:
            raise InputError("the executor reported a miss without where the ball came down (landing_x and miss "
                             "None or NaN): distance feedback learns from the signed miss; report landing_x and "
                             "miss in m (where the ball first touched, if it never came down through the rim's "
                             "height), or learn with feedback='binary'")
        if hit_distance_needed and hit:
            raise InputError("the executor reported a hit without where the ball came down (landing_x and miss "
                             "None or NaN): until='centred' judges a hit by its distance from the basket's centre; "
                             "report landing_x and miss in m, or stop at any hit with until='hit'")
    return bool(hit), landing, miss


def _metres(value, name: str) -> float:
    """``value`` as a float (None: NaN, not measured), or :class:`InputError` naming ``name``."""
    if value is None:
        return math.nan
    if isinstance(value, bool | np.bool_ | str) or not isinstance(value, numbers.Real):
        raise InputError(f"the executor's outcome has {name} = {value!r} ({type(value).__name__}): give a "
                         "number in metres (NaN or None where not measured)")
    return float(value)


#: Bisection steps of :func:`_plan`'s search for the fastest throw of a shape the arm can make:
#: the speed found is within 2^-12 of the asked one below it.
SATURATION_STEPS = 12


def _plan(mapping, path, bearing: float):
    """The mapped throw at the path's samples, the planned trajectory to execute and what was
    clipped: :func:`rlff.robot.plan.plan_path` with clipping (a proposal beyond a limit
    saturates there, as the robot would).

    A throw the arm cannot make as fast as asked, though every value is within the limits (a
    release speed whose run-up from rest needs a wind-up past a position limit, or whose
    braking runs past one), saturates too: the whole path slowed by one factor, the largest
    (to 2^-:data:`SATURATION_STEPS`) the arm can make, its release velocities counted as clipped.
    Before, such a proposal ended the run with the planner's error at that attempt, and at every
    resumption (a tester's UR file with joint_2's lower limit at -1.25 rad, distance feedback).
    Where no slower throw fits either, the error is the asked throw's.
    """
    from rlff.robot.plan import plan_path
    from rlff.trajectory.check import MotionLimitError
    from rlff.trajectory.limits import ClipReport, LimitChange

    def slowed(factor: float):
        scaled = {name: column * factor if name in velocities else column for name, column in path.items()}
        scaled["time"] = time_along_path(scaled["angle"], scaled["velocity"])
        return plan_path(mapping, scaled, bearing=bearing, clip=True)

    velocities = [name for name in path if name == "velocity" or name.endswith("_velocity")]
    try:
        planned = plan_path(mapping, path, bearing=bearing, clip=True)
        return planned.points, planned.trajectory, planned.clipped_points
    except MotionLimitError as exc:
        asked = exc
    low, high = 0.0, 1.0
    fitting = None
    for _ in range(SATURATION_STEPS):
        middle = 0.5 * (low + high)
        try:
            fitting, low = slowed(middle), middle
        except MotionLimitError:
            high = middle
    if fitting is None:
        raise asked
    wanted = mapping.path_to_robot(path, bearing=bearing, clip=True)[0].velocities[-1]
    made = fitting.points.velocities[-1]
    last = len(fitting.points) - 1
    slower = tuple(LimitChange(last, name, "velocity", float(before), float(after))
                   for name, before, after in zip(fitting.points.joint_names, wanted, made, strict=True)
                   if before != after)
    return fitting.points, fitting.trajectory, ClipReport(fitting.clipped_points.changes + slower)


def _require_reach(robot, basket, pedestal: float, joints: Sequence[str] = ("joint_2",),
                   columns: Sequence[str] = ()) -> None:
    """:func:`rlff.sim.require_reachable`; where its hint names a joint the run does not drive,
    it says too what that run needs of the demonstrations (``columns``) when they lack it."""
    from rlff.robot import mapping_for
    from rlff.sim import require_reachable
    from rlff.sim.reach import PLANE_JOINTS, next_throwing_joint

    plane = tuple(j for j in joints if j in PLANE_JOINTS) or ("joint_2",)
    try:
        require_reachable(basket, robot, pedestal, plane)
    except InputError as exc:
        more = next_throwing_joint(plane)  # the joint the error's hint names
        if more is None or not robot.whole_arm:
            raise
        wanted = (*sorted(plane), more)
        try:
            needed = mapping_for(robot, wanted).human_columns
        except InputError:  # the robot file's [whole_arm] does not drive that joint
            raise exc from None
        lacking = [column for name in needed for column in (name, velocity_column(name)) if column not in columns]
        if not lacking:
            raise
        raise InputError(f"{exc}; with {more} the throw is --joints {','.join(wanted)}, which needs "
                         f"{' and '.join(lacking)} columns in the demonstrations, and these lack them (rlff data "
                         "import keeps the shoulder and wrist unless --joints elbow)") from None


def learnable_basket(demos: Dataset, mapping, basket, pedestal: float = 0.0, *, seed: int = 0,
                     headroom: float = 0.0, update: str | type[Method] = "calibrate") -> float:
    """Farthest basket centre (m) of ``basket``'s shape (its rim height and opening) that
    :func:`learn` accepts from ``demos`` through ``mapping`` (see :func:`_require_executable`):
    what a one-joint run's throws reach let go at the release that reaches farthest
    (:func:`release_quantile`: a basket beyond the default release's reach is thrown at with a
    later one), or a whole-arm throw's, what the first throw of
    ``update`` (a method's name or a :class:`Method` subclass, as :func:`learn` takes it:
    :func:`method_of`) for ``basket``'s distance (with ``seed``) reaches.

    ``headroom`` (whole-arm throws): the share of the joints' speed limits kept in reserve, so that
    the basket is reached at ``1 - headroom`` of the fastest throw the arm executes (0.1: at 90 %),
    as a choice of joints for an arm that may be slower than its robot file wants it. That choice
    takes the nearer of two reaches: the first throw of ``update`` and the demonstrations' GMR
    mean (``imitation``'s throw, what the baselines scale). The headroom was measured with the
    GMR mean's shape (``benchmarks/whole_arm_gap.py``); with ``calibrate``'s shape alone, seed
    6's people at 4 m kept joints 2 and 3 by 4 cm, and an arm that lets go 20 ms late missed there.
    """
    from rlff.sim.reach import farthest_basket

    method_class = method_of(update)
    demos, _ = usable_demos(demos, mapping, basket.rim_height)
    if drives_whole_arm(mapping):
        components = loop_components(demos, seed, joint_outputs(mapping.human_columns))
        methods = {method_class, METHODS["imitation"]} if headroom else {method_class}
        reach = min(arm_reach(mapping, _first_shape(method, demos, mapping, basket, pedestal, components, seed),
                              basket.rim_height, pedestal, headroom=headroom).distance
                    for method in sorted(methods, key=lambda method: method.name))
        return farthest_basket(reach, basket.opening)
    if headroom:
        raise InputError("a speed headroom is a choice among the joints of a whole-arm throw; a one-joint "
                         "throw's reach is at its joint's speed limit")
    return max(release_reaches(demos, mapping, basket, pedestal).values())


def _swing_ends(demos: Dataset, mapping, release: float) -> tuple[float, float]:
    """Where (rad of ``mapping``'s driven joint) a one-joint throw of the loop starts its swing
    and lets go: the ends of the demonstrations' angle grid to the ``release`` quantile of their
    last angles (:func:`angle_grid`), mapped."""
    start, end = mapping.angle_offset + mapping.angle_scale * angle_grid(demos, release)[[0, -1]]
    return float(start), float(end)


def release_reaches(demos: Dataset, mapping, basket, pedestal: float) -> dict[float, float]:
    """The farthest basket centre (m) of ``basket``'s shape that a one-joint run's throws reach
    when they let go at each of :data:`~rlff.learn.demos.RELEASE_QUANTILES` of the demonstrations'
    last angles: the joint at its speed limit (and what its acceleration and jerk limits allow
    over the swing), the others at the start pose."""
    from rlff.sim.reach import executable_reach, farthest_basket

    reaches = {}
    for quantile in RELEASE_QUANTILES:
        start, release = _swing_ends(demos, mapping, quantile)
        reach = executable_reach(mapping, basket.rim_height, pedestal, release, swing_from=start)
        reaches[quantile] = farthest_basket(reach.distance, basket.opening)
    return reaches


#: Room (m) a one-joint run's default release must leave beyond the basket (its throws' farthest
#: basket less the basket's distance) to be kept (:func:`release_quantile`). A basket at the edge of
#: a release's reach is hit only by its joint's fastest throws, the window the speed search comes
#: to last; the window below it lands about 0.09 m shorter. At baskets of 2.1-2.3 m ``calibrate``
#: took a mean of 1.1-4.9 attempts letting go at the first release that reached them and 1.0-1.6
#: at the farthest-reaching one, the sweep 3.6-10.0 against 1.3-7.1 (held-out seeds 84000-84007,
#: binary feedback, no labels; docs/learn.md).
RELEASE_ROOM = 0.1


def release_quantile(demos: Dataset, mapping, basket, pedestal: float = 0.0) -> float:
    """Where the throws of a run of :func:`learn` at ``basket`` let go: a quantile of the
    demonstrations' last angles (``demos`` as the run learns from them,
    :func:`rlff.learn.demos.usable_demos`).

    :data:`~rlff.learn.demos.RELEASE_QUANTILE` (their first quartile, where most demonstrations
    still cover the whole path) wherever its throws reach the basket with :data:`RELEASE_ROOM` to
    spare; nearer its edge or beyond, a one-joint run lets go later, where the demonstrations
    disagree: at the one of :data:`~rlff.learn.demos.RELEASE_QUANTILES` whose throws reach
    farthest (0.1-0.2 m farther than the default on the Comau, docs/learn.md), so that the hit
    lies below the joint's speed limit rather than at it; :func:`learn` refuses a basket beyond
    that one's reach, naming it. Chosen once, before the first throw: every throw of a run
    follows one angle grid (:mod:`rlff.learn.proposal_check`). A whole-arm run, whose reach is its
    first throw's (:func:`_require_executable`), and a robot file without ``[geometry]``, whose
    reach is unknown, let go at the default.
    """
    if drives_whole_arm(mapping) or mapping.robot.geometry is None:
        return RELEASE_QUANTILE
    reaches = release_reaches(demos, mapping, basket, pedestal)
    if reaches[RELEASE_QUANTILE] >= basket.distance + RELEASE_ROOM:
        return RELEASE_QUANTILE
    return max(reaches, key=reaches.get)


def release_note(demos: Dataset, mapping, basket, pedestal: float = 0.0, release: float | None = None) -> str:
    """The note of a run of :func:`learn` at ``basket`` that lets go later than the default: where,
    and what the default's throws and these reach; "" for a run that lets go at the default, and
    for a basket beyond every release's reach (:func:`learn` refuses it). ``release``: the quantile
    it lets go at (default :func:`release_quantile`'s); ``demos`` as the run learns from them
    (:func:`rlff.learn.demos.usable_demos`)."""
    release = release_quantile(demos, mapping, basket, pedestal) if release is None else release
    if release == RELEASE_QUANTILE:
        return ""
    from rlff.sim.reach import basket_metres, centimetres_below

    reaches = release_reaches(demos, mapping, basket, pedestal)
    if basket.distance > max(reaches.values()):
        return ""
    default, later = (_swing_ends(demos, mapping, quantile)[1] for quantile in (RELEASE_QUANTILE, release))
    where = ("beyond the reach" if basket.distance > reaches[RELEASE_QUANTILE]
             else f"within {RELEASE_ROOM:g} m of the edge of the reach")
    return (f"the basket at {basket_metres(basket.distance)} m is {where} of throws let go "
            f"{RELEASE_WORDS[RELEASE_QUANTILE]} ({mapping.joint} at {default:.2f} rad, the first quartile of their "
            f"last angles: a basket at {centimetres_below(reaches[RELEASE_QUANTILE])} m at most); this run lets go "
            f"later, {RELEASE_WORDS[release]} ({later:.2f} rad), and its throws reach a basket at "
            f"{centimetres_below(reaches[release])} m at most")


def planned_release_note(demos: Dataset, basket: float, robot, pedestal: float = 0.0,
                         rim_height: float = 0.3) -> str:
    """:func:`release_note` of a one-joint run of :func:`learn` at ``basket`` (m) from ``demos``
    (as :func:`learn` takes them, before its preparation) on ``robot`` (a :class:`rlff.robot.Robot`),
    known before the run starts: what the run will say of where its throws let go; "" where they
    let go at the default, and where the run will refuse the robot, the basket or the
    demonstrations (its own error says why, and this says nothing first)."""
    from rlff.robot import mapping_for
    from rlff.sim import Basket

    try:
        mapping = mapping_for(robot, None)
        target = Basket(float(basket), rim_height=rim_height)
        usable, _ = usable_demos(_demonstrations(demos), mapping, target.rim_height)
        return release_note(usable, mapping, target, pedestal)
    except InputError:
        return ""


def _executed_reach_words(demos: Dataset, mapping, basket, pedestal: float) -> str:
    """For a one-joint run refused by :func:`_require_reach` (the arm's reach at its best release),
    what this run's own throws reach, which :func:`_require_executable` holds it to next: "; this
    run's throws (joint_2 let go where the demonstrations let go, -0.35 rad) reach a basket at
    2.32 m at most"; "" for a whole-arm run (its first throw needs the model) or demonstrations
    the loop cannot use (their own error comes next)."""
    from rlff.sim.reach import centimetres_below

    if drives_whole_arm(mapping):
        return ""

    try:
        usable, _ = usable_demos(demos, mapping, basket.rim_height)
        reaches = release_reaches(usable, mapping, basket, pedestal)
        earliest, latest = (_swing_ends(usable, mapping, q)[1] for q in (RELEASE_QUANTILES[0], RELEASE_QUANTILES[-1]))
    except InputError:
        return ""
    farthest = max(reaches.values())
    reached = "no basket" if not math.isfinite(farthest) else f"a basket at {centimetres_below(farthest)} m at most"
    return (f"; this run's throws ({mapping.joint} let go where the demonstrations let go, {earliest:.2f} to "
            f"{latest:.2f} rad) reach {reached}")


def _require_executable(mapping, basket, pedestal: float, demos: Dataset, components: int = 1,
                        seed: int = 0, method_class: type[Method] | None = None,
                        release: float = RELEASE_QUANTILE) -> None:
    """Refuse a basket that no throw of this loop can reach, before the first throw.

    Every method throws along the same angle grid (rad, shape (T,); to the ``release`` quantile
    of the demonstrations' last angles, :func:`release_quantile`), so the driven joint swings
    from its mapped first angle and lets go at the mapped last one, at most at its speed limit
    (and what its acceleration and jerk limits allow over that swing), the other joints at the
    start pose. A whole-arm throw: the first throw of ``method_class`` (default ``calibrate``)
    for the basket (:func:`_first_shape`, with ``components`` and ``seed``) at the fastest the
    arm executes it (:func:`arm_reach`).
    """
    from rlff.sim.reach import (
        basket_metres,
        came_down_words,
        farthest_basket,
        farthest_words,
        require_executable,
    )

    if not drives_whole_arm(mapping):
        start, end = _swing_ends(demos, mapping, release)
        source = RELEASE_WORDS[release]
        if basket.distance > max(release_reaches(demos, mapping, basket, pedestal).values()):
            source += (": of the releases a run takes, from where most of them let go to the last, the one that "
                       "reaches farthest")
        require_executable(basket, mapping, pedestal, end, swing_from=start, release_source=source)
        return
    method_class = method_class or METHODS["calibrate"]
    shape = _first_shape(method_class, demos, mapping, basket, pedestal, components, seed)
    reach = arm_reach(mapping, shape, basket.rim_height, pedestal)
    farthest = farthest_basket(reach.distance, basket.opening)
    if basket.distance <= farthest:
        return
    hint = f"; {more}" if (more := more_joints_words(mapping)) else ""
    if reach.distance < 0:  # no speed helps, nor more joints: the shape throws backwards
        hint = ("; at every speed its ball flies backwards, over or behind the robot: the shape the "
                "demonstrations give these joints for a basket this near does not throw forward; fewer joints "
                "(--joints joint_3, or one joint without --joints) throw nearer")
    raise InputError(
        f"basket at {basket_metres(basket.distance)} m is out of reach of the whole-arm throws this robot executes: the "
        f"first throw of {method_class.name} for it with {', '.join(sorted(mapping.driven_joints))}, sped "
        f"up until {reach.limiting}: the ball {came_down_words(reach.distance, basket.rim_height)}, so "
        f"{farthest_words(farthest, basket.opening)} (pedestal {pedestal:.2f} m){hint}"
    )


def _simulator(robot, basket, pedestal: float, gap=None) -> Executor:
    """The MuJoCo simulation of ``basket``, every throw executed as an arm that differs from
    ``robot`` by ``gap`` would (:class:`rlff.sim.gap.Gap`; None: the robot file's); a throw its
    arm did not follow raises :class:`ArmNotFollowed` (:func:`require_followed`)."""
    from rlff.sim import simulate_throw

    def execute(trajectory: JointTrajectory) -> Outcome:
        executed = trajectory if gap is None else gap.executed(trajectory)
        # planned by plan_path, which ran the motion check on it: not run again for every throw
        outcome = simulate_throw(executed, basket, robot=robot, pedestal=pedestal, check_motion=False)
        require_followed(outcome)
        return outcome

    return execute


class ArmNotFollowed(InputError):
    """The simulated arm did not follow a throw's trajectory: something struck or held it."""


def require_followed(outcome) -> None:
    """Raise :class:`ArmNotFollowed` for an outcome of :func:`rlff.sim.simulate_throw` whose arm did
    not follow its trajectory (:attr:`rlff.sim.ThrowOutcome.followed`): learning from it would
    learn what the plan does not do, so the run stops. Any other outcome passes (an executor of
    the caller's reports what its own arm did)."""
    from rlff.sim.throw import ThrowOutcome, not_followed

    if isinstance(outcome, ThrowOutcome) and not outcome.followed:
        raise ArmNotFollowed(f"{not_followed(outcome)}; the run stops")


def hit_tolerance(basket) -> float:
    """Half-width (m) of the landing window the loop counts as a hit (its searches' window, the
    learning curves' shaded band): half the opening less the ball's radius, a landing clear of
    the rim; a ball that lands on the rim may still bounce in (the simulation's hit decides)."""
    from rlff.sim.arm import BALL_RADIUS

    return max(0.5 * basket.opening - BALL_RADIUS, 0.25 * basket.opening)


def centre_window(until: str, centre_share: float, opening: float) -> float:
    """How far from the basket's centre (m) a hit must land to stop a run of :func:`learn` that
    stops ``until`` (``"hit"`` or ``"centred"``): ``centre_share`` times half the basket's
    ``opening`` (m) for one ``until="centred"``, infinite (any hit) otherwise."""
    return 0.5 * centre_share * opening if until == "centred" else math.inf


def counts_as_hit(attempt: Attempt, centre_window: float = math.inf) -> bool:
    """Whether ``attempt`` is a hit within ``centre_window`` (m) of the centre; every hit when the
    window is infinite, one whose landing was not measured (a typed hit) too."""
    return attempt.hit and (math.isinf(centre_window) or abs(attempt.miss) <= centre_window)


def _as_reported(attempt: Attempt, feedback: str, centre_window: float = math.inf) -> Attempt:
    """The attempt as the feedback reports it: without landing and miss for binary feedback, and
    a hit only within ``centre_window`` (m) of the centre (``until="centred"``)."""
    hit = counts_as_hit(attempt, centre_window)
    if feedback == "distance":
        return attempt if hit == attempt.hit else replace(attempt, hit=hit)
    return replace(attempt, hit=hit, landing=math.nan, miss=math.nan)


def _json_number(value: float) -> float | None:
    """None for NaN (a throw with no landing point), which JSON cannot hold."""
    return float(value) if math.isfinite(value) else None

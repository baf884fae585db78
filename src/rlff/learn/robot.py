"""Learning through a robot: every attempt runs through the FollowJointTrajectory action.

The loop (:func:`rlff.learn.learn`) hands an executor the robot trajectory of each proposed
throw. :class:`RobotExecutor` plans it from the arm's pose (read from the robot file's joint
states topic, ``[ros] joint_states``) with the approach (at ``approach_speed`` of the limits),
the same throw and its braking tail (:func:`rlff.learn.from_pose.plan_from_pose`), sends it as a
goal to the robot file's ``[ros] action`` (ROS 1 or ROS 2, whichever transport it is given) and
waits for its end, then takes the outcome from whoever watched the throw:

- a person (``ask``): "hit", "miss", or the signed miss in metres (negative short of the
  basket), typed at a prompt; see :func:`parse_answer`;
- a vision system (``topic``): the landing point it publishes, a geometry_msgs/PointStamped whose
  ``point.x`` is the landing distance (m) along the throwing direction from the robot's base
  axis, stamped after the planned release (and not in the future), in the robot's base frame
  (``header.frame_id`` empty or one of :data:`LANDING_FRAMES`); see :class:`Landings`.

A landing, typed or measured, is a hit within the basket's hit window, the same as in the
simulation, and keeps its measured miss (``--until centred`` judges hits by it). A landing
outside :data:`LANDING_RANGE` (behind the base, or beyond 20 m: a unit slip, a vision system's
glitch) is never learned from: a typed one is asked again, a published one stops the run.

The outcome joins the attempts log like a simulated one (hit, landing, signed miss), so a run
resumes the same way. A goal that does not succeed stops the run with an error naming the
attempt: the log keeps the attempts before it. Each throw's approach (the move to its start pose)
is announced (``tell``) before its goal is sent; an attempt interrupted mid-throw or at its
outcome is not logged (a resumed run throws it again): the interrupt is marked with its number.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from rlff.errors import InputError, RlffError
from rlff.learn.from_pose import LIVE_PERIOD, plan_from_pose
from rlff.limits import DISTANCE_RANGE
from rlff.robot.description import Robot
from rlff.robot.send import (
    ArmStateError,
    SendResult,
    approach_line,
    require_at_rest,
)
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.planner import APPROACH_SPEED, check_approach_speed

#: Topic a vision system publishes the measured landing on (geometry_msgs/PointStamped).
LANDING_TOPIC = "/rlff/landing"
#: Planning period (s) of the executed throws (``rlff robot send``'s default): a live goal's points
#: are interpolated by the controller, so 10 ms, where files are sampled at 2 ms (docs/cli.md).
PERIOD = LIVE_PERIOD
#: Seconds to wait at the start for the vision system's landing publisher to be discovered
#: (ROS 2); without one the throws go ahead and each waits for its landing as before.
LANDING_DISCOVERY = 10.0
#: Seconds to wait for a landing after the goal ended.
OUTCOME_TIMEOUT = 60.0
#: The frames a landing may be given in (``header.frame_id``): none (taken as the robot's base
#: frame) or the robot's base link, as ``rlff robot urdf`` names it. ``point.x`` is measured along
#: the throwing direction from the base axis; a camera's frame is not converted.
LANDING_FRAMES = ("", "base_link")
#: Seconds a landing's stamp may lie ahead of this host's ROS clock (clocks a little out of step).
LANDING_FUTURE = 0.5
#: Where a ball can come down (m from the robot's base axis): not behind it, and no farther than
#: the farthest basket rlff takes (``rlff.limits.DISTANCE_RANGE``).
LANDING_RANGE = (0.0, DISTANCE_RANGE[1])


@dataclass(frozen=True)
class ReportedOutcome:
    """What whoever watched reports: ``hit``, ``landing_x`` (m; NaN if not measured) and
    ``miss`` (m, ``landing_x`` less the basket's distance; NaN if not measured, a typed ``hit``
    too: in the basket is not a landing at its centre)."""

    hit: bool
    landing_x: float
    miss: float


class RobotFailed(RlffError):
    """A goal of the learning run did not succeed (rejected, aborted, timed out)."""


#: What a landing outside :data:`LANDING_RANGE` may be, by where it came from.
_UNIT_SLIPS = {
    "typed": "a unit slip? the miss is in metres: -0.3 for 30 cm short",
    "topic": "a unit slip? point.x is in metres from the robot's base along the basket's line: 1.75, not 1750",
}


def outcome_of_landing(landing: float, basket: float, tolerance: float, source: str = "typed") -> ReportedOutcome:
    """The outcome of a ball landing at ``landing`` (m) for a basket at ``basket`` (m): a hit
    when within ``tolerance`` (m) of the basket's centre; the miss is kept for a hit too.
    ``source`` (``typed`` or ``topic``) words the hint of the error.

    Raises
    ------
    InputError
        ``landing`` is not a number within :data:`LANDING_RANGE`.
    """
    low, high = LANDING_RANGE
    if not low <= landing <= high:  # also NaN
        where = "behind the robot's base" if landing < low else f"beyond {high:g} m" if landing > high else "not a number"
        raise InputError(f"a landing at {landing:g} m ({landing - basket:+g} m from the basket at {basket:g} m) is "
                         f"{where}: a ball comes down {low:g} to {high:g} m from the base ({_UNIT_SLIPS[source]})")
    miss = float(landing) - float(basket)
    return ReportedOutcome(abs(miss) <= tolerance, float(landing), miss)


def parse_answer(text: str, basket: float, tolerance: float, distance_needed: bool,
                 hit_distance_needed: bool = False) -> ReportedOutcome:
    """The outcome a person typed.

    ``hit`` (or ``h``, ``y``): in the basket, where not measured (landing and miss NaN; only
    when ``hit_distance_needed`` is False); ``miss`` (or ``m``, ``n``): out, not measured (only when
    ``distance_needed`` is False); a number: the signed miss (m, negative short), a hit within
    ``tolerance`` (m) of the centre, as :func:`outcome_of_landing` judges a measured landing.

    Raises
    ------
    InputError
        Anything else, or a miss that puts the landing outside :data:`LANDING_RANGE`, naming what
        was typed and what is expected.
    """
    answer = text.strip().lower()
    if answer in ("hit", "h", "y", "yes"):
        if hit_distance_needed:
            raise InputError("--until centred needs a hit's signed miss in m (e.g. 0.05 for 5 cm long), "
                             "not just 'hit'")
        return ReportedOutcome(True, math.nan, math.nan)
    if answer in ("miss", "m", "n", "no"):
        if distance_needed:
            raise InputError("distance feedback needs the signed miss in m (e.g. -0.3 for 30 cm short), "
                             "not just 'miss'")
        return ReportedOutcome(False, math.nan, math.nan)
    try:
        miss = float(answer)
    except ValueError:
        raise InputError(f"answer {text.strip()!r}: type hit, miss, or the signed miss in m "
                         "(negative short of the basket)") from None
    if not math.isfinite(miss):
        raise InputError(f"answer {text.strip()!r}: the miss must be a finite number of metres")
    return outcome_of_landing(float(basket) + miss, basket, tolerance)


class Landings:
    """The landing points a vision system publishes, kept as they arrive.

    ``subscribe(callback)`` connects the topic; the transport calls ``callback(stamp, x, frame)``
    with each message's header stamp (s), ``point.x`` (m) and ``header.frame_id``. ``now()``
    is the ROS time (s), against which a stamp in the future is refused. ``published()``, when
    the transport can ask its graph, lists the topics on which geometry_msgs/PointStamped is
    published: a wait that found nothing names them (a vision system on another topic).
    """

    def __init__(self, subscribe: Callable[[Callable[..., None]], None],
                 now: Callable[[], float] = time.time,
                 published: Callable[[], Sequence[str]] | None = None) -> None:
        self._seen: list[tuple[float, float, str]] = []
        self._arrived = threading.Condition()
        self._now = now
        self._published = published
        subscribe(self._on_landing)

    def _on_landing(self, stamp: float, x: float, frame: str = "") -> None:
        with self._arrived:
            self._seen.append((stamp, x, frame))
            self._arrived.notify_all()

    def after(self, start: float, timeout: float, topic: str = LANDING_TOPIC) -> float:
        """The first landing (m) stamped at or after ``start`` (s, the throw's release), waiting up
        to ``timeout`` s. Landings stamped earlier are older than the throw and passed over (the
        error on a timeout counts them). The landing may not be a number: the caller judges it.

        Raises
        ------
        RobotFailed
            None arrived in time; the landing is stamped in the future (beyond
            :data:`LANDING_FUTURE`) or given in a frame not of :data:`LANDING_FRAMES`.
        """
        deadline = time.monotonic() + timeout
        older: list[tuple[float, float]] = []
        with self._arrived:
            while True:
                while self._seen:
                    stamp, x, frame = self._seen.pop(0)
                    if stamp < start:
                        older.append((stamp, x))
                        continue
                    now = self._now()
                    if stamp > now + LANDING_FUTURE:
                        raise RobotFailed(
                            f"{topic}: the landing ({x:g} m) is stamped {stamp - now:.3g} s in the future "
                            f"({stamp:.3f} s, ROS time {now:.3f} s): stamp each landing with the ROS time the ball "
                            "came down, on a clock in step with this host's")
                    if frame not in LANDING_FRAMES:
                        raise RobotFailed(
                            f"{topic}: the landing ({x:g} m) is in frame {frame!r}, not the robot's base frame: "
                            f"publish point.x along the throwing direction from the robot's base axis, frame_id "
                            f"{' or '.join(repr(f) for f in LANDING_FRAMES)}")
                    return x
                left = deadline - time.monotonic()
                if left <= 0:
                    if older:
                        last_stamp, last_x = older[-1]
                        raise RobotFailed(
                            f"no landing on {topic} stamped after the throw's release within {timeout:g} s: "
                            f"{len(older)} arrived, all stamped before it (the last {last_x:g} m at "
                            f"{last_stamp:.3f} s, the release at {start:.3f} s): set each landing's header.stamp "
                            "to the ROS time now (ROS 1's rostopic pub: `header: {stamp: now}`; a ROS 2 node: "
                            "`node.get_clock().now().to_msg()`), on a clock in step with this host's")
                    break
                self._arrived.wait(left)
        # asked of the ROS graph (the master, or discovery) outside the lock the landings come under
        raise RobotFailed(f"no landing on {topic} within {timeout:g} s of the throw ({self._elsewhere(topic)})")

    def _elsewhere(self, topic: str) -> str:
        """What to check when nothing came on ``topic``: the other topics the graph has landings
        on, when there are any."""
        others: list[str] = []
        if self._published is not None:
            try:
                others = sorted(name for name in self._published() if name != topic)
            except Exception:  # noqa: BLE001 - a graph that cannot be asked only loses the hint
                others = []
        if not others:
            return "is the vision system publishing geometry_msgs/PointStamped?"
        return (f"geometry_msgs/PointStamped is published on {', '.join(others)}: if that is the vision system, "
                f"give --landing-topic {others[0]}")


def measured_outcome(landings: Landings, attempt: int, release: float, basket: float, tolerance: float,
                     topic: str = LANDING_TOPIC, timeout: float = OUTCOME_TIMEOUT) -> ReportedOutcome:
    """The outcome of ``attempt`` from the first landing on ``topic`` after its ``release`` (s).

    Raises
    ------
    RobotFailed
        No landing (:meth:`Landings.after`), or one that is not a number or not within
        :data:`LANDING_RANGE`: one line naming the attempt and what to check (the loop adds
        what its log keeps, :func:`rlff.learn.learn`).
    """
    try:
        landing = landings.after(release, timeout, topic)
    except RobotFailed as exc:
        raise RobotFailed(f"attempt {attempt}: {exc}") from None
    if not math.isfinite(landing):
        raise RobotFailed(f"attempt {attempt}: {topic}: the landing is not a number ({landing}): check the vision "
                          "system's output")
    try:
        return outcome_of_landing(landing, basket, tolerance, source="topic")
    except InputError as exc:
        raise RobotFailed(f"attempt {attempt}: {topic}: {exc}; check the vision system's frame and units") from None


class LiveArm(Protocol):
    """A transport to the arm: :class:`rlff.robot.ros2.client.Connection`, or ROS 1's client."""

    def arm_state(self, robot: Robot, timeout: float | None = None) -> tuple[np.ndarray, np.ndarray]: ...

    def send_goal(self, robot: Robot, traj: JointTrajectory, pose: np.ndarray, timeout: float | None = None,
                  on_feedback: Callable[[float], None] | None = None) -> SendResult: ...


class RobotExecutor:
    """Runs each attempt's throw on the arm and returns what was seen of it.

    Parameters
    ----------
    arm : LiveArm
    robot : Robot
    outcome : callable
        ``outcome(attempt, release)`` -> :class:`ReportedOutcome` for the attempt (1, 2, ...) whose
        ball left the hand at ROS time ``release`` (s, as planned): a prompt, or ``Landings.after``.
    period : float
        Planning period (s) of the executed motion.
    tell : callable, optional
        ``tell(line)``: each throw's approach, announced before its goal is sent.
    approach_speed : float
        Share of the joints' limits each throw's approach uses
        (:data:`rlff.trajectory.planner.APPROACH_SPEED`).
    ready : callable, optional
        ``ready(attempt)`` returns when the throw may go (a person said so); None: at once.

    The first throw is attempt 1 until :meth:`resume` says how many the run's log holds.
    """

    def __init__(self, arm: LiveArm, robot: Robot, outcome: Callable[[int, float], ReportedOutcome],
                 period: float = PERIOD, tell: Callable[[str], None] | None = None,
                 ready: Callable[[int], None] | None = None, approach_speed: float = APPROACH_SPEED) -> None:
        self.arm = arm
        self.robot = robot
        self.outcome = outcome
        self.period = period
        self.approach_speed = check_approach_speed(approach_speed)
        self.tell = tell
        self.ready = ready
        self.attempts = 0

    def resume(self, attempts: int) -> None:
        """Number the next throw ``attempts + 1``, as a log that holds ``attempts`` does: the
        ``resuming`` of :func:`rlff.learn.learn`, which says how many it took from its log before
        the first throw (known only once the log is read)."""
        self.attempts = attempts

    def __call__(self, trajectory: JointTrajectory) -> ReportedOutcome:
        self.attempts += 1
        pose, planned = self._plan(trajectory)
        while self.ready is not None:
            self.ready(self.attempts)
            before = pose
            pose, planned = self._plan(trajectory, announce=False)
            if np.allclose(pose, before, rtol=0.0, atol=MOVED_WHILE_WAITING):
                break
            # someone moved the arm while the throw waited: plan again, say so, and ask again
            self._announce(planned, "the arm moved while the throw waited: ")
        try:
            sent = self.arm.send_goal(self.robot, planned, pose)
        except KeyboardInterrupt as exc:  # the client cancelled the goal, if one went out
            exc.rlff_attempt = self.attempts  # type: ignore[attr-defined]
            raise
        except RlffError as exc:  # no server, no master: said with the attempt, as a goal that failed
            if isinstance(exc, InputError) or str(exc).startswith(f"attempt {self.attempts}: "):
                raise
            raise type(exc)(f"attempt {self.attempts}: {exc}") from None
        if not sent.succeeded:
            detail = f" ({sent.error_name})" if sent.error_name else ""
            raise RobotFailed(f"attempt {self.attempts}: goal {sent.status}{detail}: {sent.error_string}")
        release = sent.start + float(planned.release_time or 0.0)
        try:
            return self.outcome(self.attempts, release)
        except KeyboardInterrupt as exc:  # thrown, but no outcome: not logged either
            exc.rlff_attempt = self.attempts  # type: ignore[attr-defined]
            exc.rlff_outcome_missing = True  # type: ignore[attr-defined]
            raise

    def _plan(self, trajectory: JointTrajectory, announce: bool = True) -> tuple[np.ndarray, JointTrajectory]:
        """The arm's pose (J,) and the throw planned from it (:func:`plan_from_pose`), checked as
        the goal to send; the approach is announced unless ``announce`` is False.
        :class:`RobotFailed` for an arm not at rest.

        (``trajectory`` is planned already, from rest at its first pose through its braking: it
        had been planned again as if it were the throw up to its release, so the arm let go at
        the end of the braking, at rest, and the ball fell at its base.)"""
        try:
            pose, velocity = self.arm.arm_state(self.robot)
            require_at_rest(self.robot, velocity)  # before planning from rest
            planned = plan_from_pose(trajectory, self.robot, pose, period=self.period,
                                     approach_speed=self.approach_speed)
        except ArmStateError as exc:
            raise RobotFailed(f"attempt {self.attempts}: {exc}") from None
        if announce:
            self._announce(planned)
        return pose, planned

    def _announce(self, goal: JointTrajectory, why: str = "") -> None:
        announced = approach_line(goal, joints=self.robot.ros.joints)
        if announced and self.tell is not None:
            self.tell(f"attempt {self.attempts}: {why}{announced}")


#: How far (rad, any joint) the arm may have moved while a throw waited for its go before the
#: throw is planned again from where it is.
MOVED_WHILE_WAITING = 1e-3


#: The executors of ``rlff learn --executor`` and the outcome sources of ``--outcome``.
EXECUTORS = ("sim", "ros1", "ros2")
OUTCOMES = ("ask", "topic")


@contextmanager
def robot_executor(
    kind: str,
    outcome: str,
    robot: str | Robot,
    basket: float,
    feedback: str,
    until: str = "hit",
    ask: Callable[[str], str] | None = None,
    landing_topic: str = LANDING_TOPIC,
    outcome_timeout: float = OUTCOME_TIMEOUT,
    network: bool = False,
    tell: Callable[[str], None] | None = None,
    approach_speed: float = APPROACH_SPEED,
) -> Iterator[RobotExecutor]:
    """A :class:`RobotExecutor` on a live arm, for the time of the ``with`` block.

    Parameters
    ----------
    kind : {"ros1", "ros2"}
    outcome : {"ask", "topic"}
    robot : str or Robot
        Robot name, robot file or description (as ``rlff.learn.learn`` takes it).
    basket : float
        Basket distance (m), for the hit window of a measured landing and a typed miss.
    feedback : {"binary", "distance"}
        With distance feedback a typed miss must be a number.
    until : {"hit", "centred"}
        With ``centred`` a typed hit must be a number too: its distance from the centre decides.
    ask : callable, optional
        ``ask(question) -> answer`` for ``outcome="ask"`` (the command line's prompt); asked
        again after an answer it cannot read.
    landing_topic : str
        Where the vision system publishes for ``outcome="topic"``.
    outcome_timeout : float
        Seconds to wait for a landing after the goal started.
    network : bool
        Open the nodes to the network (default: this host only).
    tell : callable, optional
        ``tell(line)``: each throw's approach, announced before its goal is sent.
    approach_speed : float
        Share of the joints' limits each throw's approach uses. The throws are numbered from 1
        until the executor's :meth:`RobotExecutor.resume` says how many the run's log holds.

    Raises
    ------
    InputError
        Unknown kind or outcome, ``ask`` missing.
    """
    from rlff.learn.loop import hit_tolerance
    from rlff.robot.description import load_robot
    from rlff.sim import Basket

    if kind not in EXECUTORS[1:]:
        raise InputError(f"unknown robot executor {kind!r} (ros1 or ros2; sim is the simulation)")
    if outcome not in OUTCOMES:
        raise InputError(f"--outcome must be one of {', '.join(OUTCOMES)} with --executor {kind}, got {outcome!r}")
    if outcome == "ask" and ask is None:
        raise InputError("--outcome ask needs someone to ask")
    model = robot if isinstance(robot, Robot) else load_robot(robot)
    tolerance = hit_tolerance(Basket(float(basket)))

    def asked(attempt: int, release: float) -> ReportedOutcome:
        if until == "centred":
            question = f"attempt {attempt}: the signed miss in m (negative short; 0 the centre){'' if feedback == 'distance' else ', or miss'}? "
        elif feedback == "distance":
            question = f"attempt {attempt}: the signed miss in m (negative short; 0 or hit)? "
        else:
            question = f"attempt {attempt}: hit, miss, or the signed miss in m (negative short)? "
        while True:
            answer = ask(question)  # an error here (no one to answer) ends the run
            try:
                return parse_answer(answer, basket, tolerance, feedback == "distance", until == "centred")
            except InputError as exc:
                question = f"{exc}; attempt {attempt}? "

    def confirmed(attempt: int) -> None:
        # whoever answers may stand where the ball lands: each throw waits for an empty line, and
        # an answer typed ahead is not taken for one
        question = f"attempt {attempt}: the arm is about to throw: Enter to throw, Ctrl-C to stop "
        while ask(question).strip():
            question = (f"attempt {attempt}: not thrown yet, so nothing to answer: an empty line (Enter) throws, "
                        "Ctrl-C stops ")

    with ExitStack() as stack:
        if kind == "ros2":
            arm, subscribe, now, published = _ros2_arm(stack, landing_topic, network)
        else:
            arm, subscribe, now, published = _ros1_arm(model, landing_topic, network)
        if outcome == "topic":
            landings = Landings(subscribe, now, published)

            def measured(attempt: int, release: float) -> ReportedOutcome:
                return measured_outcome(landings, attempt, release, basket, tolerance, landing_topic,
                                        outcome_timeout)

            yield RobotExecutor(arm, model, measured, tell=tell, approach_speed=approach_speed)
        else:
            yield RobotExecutor(arm, model, asked, tell=tell, ready=confirmed, approach_speed=approach_speed)


def _ros2_arm(stack: ExitStack, topic: str, network: bool):
    from rlff.robot import ros2

    problem = ros2.missing()
    if problem:
        raise RobotFailed(problem)
    from rlff.robot.ros2.network import limit_discovery

    limit_discovery(network)
    from geometry_msgs.msg import PointStamped

    from rlff.robot.ros2.client import Connection

    connection = stack.enter_context(Connection("rlff_learn"))

    def subscribe(callback: Callable[[float, float, str], None]) -> None:
        # a vision system already running is matched before the first throw, so that its first
        # landing is not published before discovery joined the two
        connection.subscribe(PointStamped, topic, lambda msg: callback(
            msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9, msg.point.x, msg.header.frame_id),
            wait_for_publisher=LANDING_DISCOVERY)

    def published() -> list[str]:
        return [name for name, kinds in connection.node.get_topic_names_and_types()
                if "geometry_msgs/msg/PointStamped" in kinds]

    return connection, subscribe, connection.now, published


def _ros1_arm(robot: Robot, topic: str, network: bool):
    from rlff.robot import ros1

    problem = ros1.missing()
    if problem:
        raise RobotFailed(problem)
    from rlff.robot.ros1.network import limit_to_loopback

    limit_to_loopback(network)
    import rospy
    from geometry_msgs.msg import PointStamped

    from rlff.robot.ros1 import client

    client.arm_state(robot)  # starts the node (and checks the arm answers) before subscribing

    def subscribe(callback: Callable[[float, float, str], None]) -> None:
        rospy.Subscriber(topic, PointStamped, lambda msg: callback(msg.header.stamp.to_sec(), msg.point.x,
                                                                   msg.header.frame_id))

    def published() -> list[str]:
        return [name for name, kind in rospy.get_published_topics() if kind == "geometry_msgs/PointStamped"]

    return client, subscribe, lambda: rospy.get_rostime().to_sec(), published

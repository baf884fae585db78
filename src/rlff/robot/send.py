"""What sending a FollowJointTrajectory goal shares across transports (ROS 1, ROS 2).

The arm's state taken from its joint states (the robot file's ``[ros] joint_states``,
``/joint_states`` by default; :class:`StateWatch`: only fresh, stamped messages whose poses
are within the robot's limits and agree with each other), the refusal to plan from rest for an
arm that moves (:func:`require_at_rest`), the goal checked from that state (:func:`check_goal_for_arm`), the line
announcing the approach before anything moves (:func:`approach_line`), and the report of what
became of a goal; the transports (:mod:`rlff.robot.ros1.client`, :mod:`rlff.robot.ros2.client`)
only move messages.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass

import numpy as np

from rlff.errors import InputError, RlffError
from rlff.robot.controller import ResultCode, in_controller_words
from rlff.robot.description import Robot
from rlff.robot.goal import InvalidJoints, check_goal
from rlff.robot.joint_map import JointMap
from rlff.robot.messages import arm_state_of, missing_joints
from rlff.trajectory.joint import JointTrajectory

#: How far (s) a joint state's header stamp may be from the ROS clock, behind or ahead, for the
#: message to be taken as the arm's state now; an older one (a latched message, a driver that
#: stopped, a clock out of step) is waited past, and refused when no fresh one comes.
STATE_MAX_AGE = 1.0
#: The arm's state is taken from fresh messages spanning at least this long (s) by their stamps,
#: each agreeing with the one before (:class:`StateWatch`): a second node publishing the arm's
#: joints at 10 Hz or more (a simulator's joint_state_controller at its default 50 Hz, a bag) shows
#: among them, whatever the driver's rate; without velocities in the messages, the arm's speed is
#: the position change over this span. It delays the state by 0.1 s, or by one message of a
#: driver slower than 10 Hz.
STATE_SPAN = 0.1
#: How long (s) to keep waiting, after a joint states message that leaves out joints of the robot,
#: for one that names them all. Several drivers may publish on one joint states topic (the arm's,
#: a gripper's with only its fingers: robot_state_publisher merges them); a message of another
#: device is passed over, and only when none of the robot's comes does its absence become the
#: error (a robot file whose joint names are not the arm's).
PARTIAL_GRACE = 2.0
#: How far (rad) a joint may move between two fresh states beyond what its max velocity allows over
#: their stamps' difference, and the two still count as one arm's (:class:`StateWatch`): encoder
#: noise and a driver's rounding (an industrial arm's encoders resolve microradians), with room for
#: a stamp taken a little after its measurement. It equals the motion check's start tolerance
#: (:data:`rlff.trajectory.check.POSITION_TOLERANCE`): a pose off by less is one a goal may start
#: from anyway; two poses further apart than the joints can move are not one arm's.
STATE_NOISE = 1e-3
#: Above this speed (rad/s) on any joint the arm counts as moving: no goal planned from rest is sent.
MOVING_SPEED = 0.01
#: Seconds between sending a goal and its start (its header stamp), so the server is ready.
START_LEAD = 0.2
#: Default seconds to wait for the ROS master (ROS 1) and the action server when no timeout is given.
CONNECT_TIMEOUT = 10.0
#: Seconds to wait for the server to confirm a cancel (it answers once the arm has braked to rest).
CANCEL_WAIT = 10.0
#: What a goal came to when the command was interrupted: cancelled (the server confirmed the
#: goal's end), a cancel sent but not confirmed, or a cancel sent whose confirmation a second
#: interrupt stopped the wait for; see :func:`mark_goal`.
GOAL_CANCELLED, CANCEL_UNCONFIRMED, CANCEL_NOT_AWAITED = "cancelled", "unconfirmed", "not awaited"
#: The result codes' names by value.
ERROR_NAMES = {code.value: code.name for code in ResultCode}


class ArmStateError(RlffError):
    """The joint states cannot be taken as the arm's state (stale, unstamped, not a number, beyond a
    limit), or the arm is moving: nothing is sent."""


def mark_goal(exc: BaseException, fate: str) -> BaseException:
    """``exc`` (an interrupt) marked with what became of the goal it interrupted (:data:`GOAL_CANCELLED`,
    :data:`CANCEL_UNCONFIRMED` or :data:`CANCEL_NOT_AWAITED`); an interrupt without the mark came
    before any goal was sent."""
    exc.rlff_goal = fate  # type: ignore[attr-defined]
    return exc


def goal_fate(exc: BaseException) -> str | None:
    """What :func:`mark_goal` recorded on ``exc``; None: no goal was sent."""
    return getattr(exc, "rlff_goal", None)


def cancel_unconfirmed(wait: float | None = CANCEL_WAIT) -> str:
    """The words for a cancel the server did not confirm within ``wait`` s (None: the server is gone)."""
    why = "no server is left to answer it" if wait is None else f"no answer from the server within {wait:g} s"
    return f"the cancel was not confirmed ({why}): the arm's state is unknown; check the arm (e-stop it if it moves)"


def interrupted_goal(exc: BaseException) -> str | None:
    """What became of the goal an interrupt (Ctrl-C, SIGTERM) stopped, in words (its
    :func:`goal_fate`): None when none was sent."""
    fate = goal_fate(exc)
    if fate == GOAL_CANCELLED:
        return "goal cancelled"
    if fate == CANCEL_UNCONFIRMED:
        return f"goal interrupted: {cancel_unconfirmed()}"
    if fate == CANCEL_NOT_AWAITED:
        return ("goal interrupted: the cancel went out, and a second interrupt stopped the wait for the server to "
                "confirm it: the arm's state is unknown; check the arm (e-stop it if it moves)")
    return None


def _span(seconds: float) -> str:
    """``seconds`` in words: 0.312 s, 2.5 min, 56 years."""
    for unit, size in (("years", 365.25 * 86400), ("days", 86400), ("h", 3600), ("min", 60)):
        if seconds >= 2 * size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.3g} s"


class StateWatch:
    """The arm's state from the JointState messages (on the robot's ``ros.joint_states``) a
    transport hands to :meth:`offer`.

    A message is taken only when its header stamp is within :data:`STATE_MAX_AGE` of the ROS
    clock (``now()``); an unstamped one (stamp 0) has no age and is never taken. A fresh pose that
    is not a number, or beyond a joint's limit, is refused naming the topic. A message that leaves
    out joints of the robot (another device's on the same topic) is passed over; when none names
    them all within :data:`PARTIAL_GRACE` s of the first such message, that is the error.

    The state is that of the first fresh message naming every joint at least :data:`STATE_SPAN`
    s (by the stamps) after the earliest one, each such message agreeing with the one before it:
    no joint moved more than its max velocity allows over their stamps' difference (plus
    :data:`STATE_NOISE`). Two nodes publishing the arm's joints on the topic (a simulator left
    running beside the arm's driver, a bag played) give poses that jump between their messages;
    taking the first message would plan from whichever came first. Two that do not agree are
    refused at once: waiting for a pair that does could take it from the wrong publisher. A
    second publisher slower than one message per :data:`STATE_SPAN` may go unseen (``rostopic
    info`` / ``ros2 topic info`` lists them all), and so may one whose messages reach the
    subscription only later: a transport whose subscription reaches publishers one by one (ROS 2
    discovery) holds the state (:meth:`hold`) until the others are likely heard. A message without
    velocities gives the velocity of the change over that span.

    ``info``: the command that lists a topic's publishers, for the error (``rostopic info``,
    ``ros2 topic info``).
    """

    def __init__(self, robot: Robot, now: Callable[[], float], info: str = "rostopic info") -> None:
        self.robot = robot
        self.now = now
        self.info = info
        self.topic = robot.ros.joint_states
        self._max_velocity = robot.limits()[2]  # (J,) rad/s, for every message's agreement check
        self._arrived = threading.Condition()
        self._state: tuple[np.ndarray, np.ndarray] | None = None
        self._problem: Exception | None = None
        self._untrusted: str | None = None  # why the last message was passed over
        #: the fresh messages naming every joint: how many, the earliest and the last (stamp, pose)
        #: (the next must agree with the last), and whether the last carried no velocities
        self._fresh = 0
        self._earliest: tuple[float, np.ndarray] | None = None
        self._last: tuple[float, np.ndarray] | None = None
        self._without_velocity = False
        #: when (monotonic s) a message leaving out joints of the robot first came, and what it named
        self._partial: tuple[float, str] | None = None
        self._not_before = 0.0  # no state is taken before this monotonic time (:meth:`hold`)

    def hold(self, seconds: float) -> None:
        """Take no state for ``seconds`` from now (0: take it as soon as the messages allow):
        other publishers may not have reached the subscription yet. Messages go on being checked
        meanwhile, and :meth:`wait` waits a hold out once messages come, past its deadline if
        need be."""
        with self._arrived:
            self._not_before = time.monotonic() + seconds

    def offer(self, stamp: float, names: Sequence[str], positions: Sequence[float],
              velocities: Sequence[float]) -> None:
        """One message's header stamp (s of ROS time) and fields (from the transport's thread)."""
        with self._arrived:
            if self._state is not None or self._problem is not None:
                return
            now = self.now()
            try:
                self._take(stamp, now, names, positions, velocities)
            except (ArmStateError, InputError) as exc:
                self._problem = exc
            self._arrived.notify_all()

    def _take(self, stamp: float, now: float, names, positions, velocities) -> None:
        age = now - stamp
        if stamp <= 0:
            self._untrusted = "its messages are unstamped (header.stamp 0), so their age is unknown"
            return
        if abs(age) > STATE_MAX_AGE:
            when = (f"{_span(age)} old" if age > 0 else f"{_span(-age)} ahead of this host's ROS clock")
            self._untrusted = f"the last is stamped {stamp:.3f} s, {when} (ROS time {now:.3f} s)"
            return
        missing = missing_joints(self.robot, names)
        if missing:  # another device's message, or a robot file that names other joints
            if self._partial is None:
                self._partial = (time.monotonic(), f"{self.topic} has no position of {', '.join(missing)} (it names "
                                                   f"{', '.join(names) or 'no joint'})")
            return
        pose, velocity = arm_state_of(self.robot, self.topic, names, positions, velocities)
        self._check_pose(pose)
        if velocity is not None and not np.all(np.isfinite(velocity)):
            j = int(np.argmin(np.isfinite(velocity)))
            raise ArmStateError(f"{self.topic} reports {self.robot.ros.joints.label(self.robot.joint_names[j])} moving "
                                f"at {velocity[j]} rad/s: "
                                "the arm's state is unknown; check the arm's driver")
        last, self._last = self._last, (stamp, pose)
        self._fresh += 1
        self._without_velocity = velocity is None
        if last is not None:
            self._check_agree(last, (stamp, pose))
        earliest = self._earliest
        if earliest is None or stamp < earliest[0]:
            self._earliest = (stamp, pose)
            return
        if stamp - earliest[0] < STATE_SPAN or time.monotonic() < self._not_before:
            return
        span = stamp - earliest[0]
        if velocity is None:
            velocity = (pose - earliest[1]) / span
        else:
            self._check_still(pose - earliest[1], span, velocity)
        self._state = (pose, velocity)

    def _check_still(self, moved: np.ndarray, span: float, velocity: np.ndarray) -> None:
        """Refuse a state whose velocities say a joint rests (:data:`MOVING_SPEED` or less) while
        its positions moved faster than that over the ``span`` s they were taken over (beyond
        :data:`STATE_NOISE`): a driver that fills velocities with zeros reports a moving arm at
        rest, and a goal planned from rest would be sent to it."""
        speed = np.abs(moved) / span
        unreported = np.flatnonzero((np.abs(velocity) <= MOVING_SPEED) & (speed > MOVING_SPEED + STATE_NOISE / span))
        if unreported.size == 0:
            return
        j = int(unreported[np.argmax(speed[unreported])])
        raise ArmStateError(
            f"{self.topic} reports {self.robot.ros.joints.label(self.robot.joint_names[j])} at {velocity[j]:.3g} "
            f"rad/s, but its position moved {moved[j]:+.4g} rad in {span:.3f} s ({speed[j]:.3g} rad/s): the arm is "
            "moving, or its driver's velocities are not its motion; wait until it rests, then send again")

    def _check_agree(self, first: tuple[float, np.ndarray], second: tuple[float, np.ndarray]) -> None:
        """Refuse two fresh poses (stamp, pose) no arm can take in turn: a joint changed by more
        than its max velocity allows over the stamps' difference, plus :data:`STATE_NOISE`."""
        span = abs(second[0] - first[0])
        change = np.abs(second[1] - first[1])
        allowed = self._max_velocity * span + STATE_NOISE
        jumped = np.flatnonzero(change > allowed)
        if jumped.size == 0:
            return
        j = int(jumped[np.argmax((change - allowed)[jumped])])
        names = [self.robot.ros.joints.label(name) for name in self.robot.joint_names]
        others = [names[k] for k in jumped if k != j]
        also = f" (and {', '.join(others)})" if others else ""
        raise ArmStateError(
            f"two fresh states on {self.topic} disagree: {names[j]} at {first[1][j]:.6g} rad, then at "
            f"{second[1][j]:.6g} rad {span:.3g} s later by their stamps, {change[j]:.3g} rad where its max velocity "
            f"({self.robot.joints[j].max_velocity:g} rad/s) allows {allowed[j]:.3g}{also}: the arm's pose is "
            f"unknown; two nodes likely publish the arm's joints on {self.topic} (a simulator or a bag beside the "
            f"arm's driver): `{self.info} {self.topic}` lists them; stop all but the arm's driver")

    def _check_pose(self, pose: np.ndarray) -> None:
        joints = self.robot.ros.joints
        for joint, value in zip(self.robot.joints, pose, strict=True):
            if not math.isfinite(value):
                raise ArmStateError(f"{self.topic} reports {joints.label(joint.name)} at {value} rad: the arm's pose "
                                    "is unknown; check the arm's driver")
            for beyond, side, limit in ((value > joint.upper, "upper", joint.upper),
                                        (value < joint.lower, "lower", joint.lower)):
                if beyond:
                    mapped = f", its [ros.joints.{joint.name}]" if joint.name in joints.joints else ""
                    raise ArmStateError(
                        f"{self.topic} reports {joints.label(joint.name)} at {value:.6g} rad"
                        f"{_as_counted(self.robot, joint.name, value)}, beyond its {side} limit {limit:.6g} "
                        f"rad in the robot file ({self.robot.name}): move the arm inside its limits, or check the "
                        f"robot file's limits{mapped} and the driver's joint offsets against the arm's")

    def wait(self, deadline: float, waited: float) -> tuple[np.ndarray, np.ndarray] | None:
        """The arm's (pose, velocity), each (J,) in ``robot``'s order, waiting up to the monotonic
        ``deadline``; None when nothing came at all (``waited``: the seconds allowed, for the message).

        Raises
        ------
        ArmStateError
            Messages came, but none fresh, or fresh ones spanning less than :data:`STATE_SPAN` s;
            or a fresh one's pose is not a number or beyond a limit; or two fresh poses disagree.
        InputError
            Fresh messages came, but none within :data:`PARTIAL_GRACE` s named every joint of the robot.
        """
        with self._arrived:
            while self._state is None and self._problem is None:
                grace = self._partial is not None and self._last is None
                end = min(deadline, self._partial[0] + PARTIAL_GRACE) if grace else deadline
                if self._last is not None:  # the state comes with the first message after a hold
                    end = max(end, self._not_before + STATE_SPAN)
                left = end - time.monotonic()
                if left <= 0:
                    break
                self._arrived.wait(left)
            if self._problem is not None:
                raise self._problem
            if self._state is not None:
                return self._state
            if self._last is not None:
                if self._fresh == 1:
                    came = f"one fresh state on {self.topic} within {waited:g} s, and none {STATE_SPAN:g} s after it"
                else:
                    span = self._last[0] - self._earliest[0]
                    came = (f"{self._fresh} fresh states on {self.topic} within {waited:g} s, their stamps within "
                            f"{span:.3g} s")
                moves = " and whether it moves (they carry no velocities)" if self._without_velocity else ""
                raise ArmStateError(
                    f"{came}: states {STATE_SPAN:g} s apart that agree tell one arm's pose from two publishers'"
                    f"{moves}; have the arm's driver publish continuously"
                    + (", with velocities" if self._without_velocity else ""))
            if self._partial is not None:
                raise InputError(f"{self._partial[1]}, and no message on it within {PARTIAL_GRACE:g} s named every "
                                 f"joint of {self.robot.name}: check the robot file's joint names against the arm's, or map "
                                 "them to the arm's in [ros.joints] (docs/robot.md)")
            if self._untrusted is not None:
                raise ArmStateError(
                    f"no fresh state on {self.topic} within {waited:g} s: {self._untrusted}; the arm's pose is "
                    f"unknown: check that its driver publishes, stamping each state with the time it was measured, "
                    "and that its host's clock agrees with this one's")
            return None


def _as_counted(robot: Robot, joint: str, value: float) -> str:
    """For a message: what the controller reads of rlff's ``joint`` at ``value`` (rad), when its
    robot file's ``[ros.joints]`` counts it otherwise (`` (rlff's convention; the controller's
    -2.07 rad)``); empty when the controller counts it as rlff does."""
    if not robot.ros.joints.counts_otherwise(joint):
        return ""
    counted = robot.ros.joints.positions_to_controller([joint], [value])[0]
    return f" (rlff's convention; the controller's {counted:.6g} rad)"


def pose_line(robot: Robot, pose: np.ndarray) -> str:
    """The arm's ``pose`` (J,) rad (rlff's convention, ``robot``'s joints) in words, each joint the
    robot file's ``[ros.joints]`` renames or counts otherwise also as the controller has it:
    ``arm's pose (rad): shoulder_lift_joint -1.571 = joint_2 0, ...``."""
    joints = robot.ros.joints
    counted = joints.positions_to_controller(robot.joint_names, pose)
    parts = []
    for name, value, theirs in zip(robot.joint_names, pose, counted, strict=True):
        own = f"{name} {value + 0.0:.4g}"  # + 0.0: a -0.0 the controller reports reads 0
        controller = joints.controller_name(name)
        parts.append(own if controller == name and theirs == value else f"{controller} {theirs + 0.0:.4g} = {own}")
    return f"arm's pose read (rad; the controller's = rlff's): {', '.join(parts)}"


def require_at_rest(robot: Robot, velocity: np.ndarray) -> None:
    """Refuse (:class:`ArmStateError`) an arm moving faster than :data:`MOVING_SPEED` on a joint.

    Goals are planned from the arm at rest; a controller that receives one while the arm moves
    splices it in from the moving state (ros_control) over whatever time the goal gives, which
    may take more than the arm's limits allow.
    """
    speed = np.abs(np.asarray(velocity, dtype=float))
    if speed.size and speed.max() > MOVING_SPEED:
        j = int(np.argmax(speed))
        raise ArmStateError(f"the arm is moving ({speed[j]:.3g} rad/s on {robot.ros.joints.label(robot.joint_names[j])}): "
                            "wait until it "
                            "rests, then send again")


def approach_line(traj: JointTrajectory, what: str = "the throw", joints: JointMap | None = None) -> str | None:
    """One line on the move that comes before ``what`` in ``traj``: which joints move how far (deg)
    and for how long; None when there is none.

    The approach is ``traj``'s motion up to its first point after 0 s where every joint is at rest,
    when that point is not its last (a planned throw: the transition to its start pose; a
    trajectory sent with ``--approach``: the move to its first point). With the robot file's
    ``[ros.joints]`` map ``joints``, each joint it renames or counts otherwise is named as the
    controller names it and moves as the controller counts it (what the arm's pendant shows),
    rlff's name beside it: ``shoulder_lift_joint (joint_2) -30.0 deg``.
    """
    still = np.all(np.abs(traj.velocities) <= 1e-6, axis=1)
    inner = np.flatnonzero(still[1:-1])
    if inner.size == 0:
        return None
    end = int(inner[0]) + 1
    moved = traj.positions[end] - traj.positions[0]
    names = list(traj.joint_names)
    if joints is not None:
        moved = joints.rates_to_controller(traj.joint_names, moved)  # a change of position turns as a rate does
        names = [joints.label(name) for name in traj.joint_names]
    parts = [f"{name} {delta:+.1f} deg" for name, delta in zip(names, np.degrees(moved), strict=True)
             if abs(delta) >= 0.05]
    if not parts:
        return None
    duration = float(traj.time[end] - traj.time[0])
    return f"approach first: {', '.join(parts)} in {duration:.2f} s, to the start of {what}"


def fastest_joint_line(robot: Robot, traj: JointTrajectory) -> str:
    """The joint of ``traj`` that comes nearest its speed limit, in words (``fastest: joint_2 at
    100% of its 2.792 rad/s``): what a dry run of ``rlff robot send`` says last."""
    joints = [joint for joint in robot.joints if joint.name in traj.joint_names]
    shares = [float(np.max(np.abs(traj.velocities[:, traj.joint_index(joint.name)]))) / joint.max_velocity
              for joint in joints]
    top = int(np.argmax(shares))
    return (f"fastest: {robot.ros.joints.label(joints[top].name)} at {shares[top]:.0%} of its "
            f"{joints[top].max_velocity:g} rad/s")


@dataclass(frozen=True)
class SendResult:
    """What became of a goal.

    ``status``: succeeded, rejected, aborted, preempted (by another goal), cancelled, lost or
    timed out; ``error_code``: the action result's code (e.g. -1); ``error_name`` its name
    (INVALID_GOAL), None for the 0 of a goal that did not succeed (FollowJointTrajectory has no
    code for a preemption or a cancel); ``start``: the goal's start (ROS time, s);
    ``duration``: the trajectory's (s); ``feedback``: messages received.
    """

    status: str
    error_code: int | None
    error_name: str | None
    error_string: str
    start: float
    duration: float
    feedback: int

    @property
    def succeeded(self) -> bool:
        return self.status == "succeeded" and self.error_code == ResultCode.SUCCESSFUL

    def to_dict(self) -> dict:
        return asdict(self) | {"succeeded": self.succeeded}


def unfinished(gone: str | None, confirmed: bool, action: str, start: float, duration: float, feedback: int,
               detail: str = "") -> SendResult:
    """The :class:`SendResult` of a goal that ran out of time (``gone`` None) or whose server went
    silent (``gone``: how it was noticed), after a cancel the server ``confirmed`` or not;
    ``detail``: the server's text of a confirmed cancel (its result's error_string: how the arm
    braked), if any. ROS 1 and ROS 2 word a goal's end alike through it."""
    cancel = "goal cancelled" if confirmed else cancel_unconfirmed(CANCEL_WAIT if gone is None else None)
    detail = f"; {detail}" if confirmed and detail else ""
    if gone is not None:
        return SendResult("lost", None, None, f"the server at {action} stopped answering ({gone}); {cancel}{detail}",
                          start, duration, feedback)
    return SendResult("timed out", None, None, f"timed out; {cancel}{detail}", start, duration, feedback)


def check_timeout(timeout: float | None, name: str = "timeout") -> None:
    """Refuse a ``timeout`` (s) that is not a finite number above 0, before anything connects: nan,
    0 or -1 passed on to the transports as a wait that ends at once (the send then blamed the arm's
    driver) or a warning about a motion it is shorter than. ``name``: what the message calls it
    (``--timeout`` on the command line)."""
    if timeout is not None and not (math.isfinite(timeout) and timeout > 0):
        raise InputError(f"{name} {timeout:g}: give a finite number of seconds above 0, or leave {name} out "
                         "(10 s to connect, and the whole motion)")


def short_timeout(timeout: float | None, traj: JointTrajectory) -> str | None:
    """What a ``timeout`` (s, ``--timeout``) shorter than ``traj``'s motion does, said before the
    goal goes out (it cancels the goal mid-motion: the arm starts and is braked); None when it
    covers the motion or none is given."""
    if timeout is None or timeout >= traj.duration:
        return None
    return (f"timeout (--timeout) {timeout:g} s is shorter than the motion ({traj.duration:.3f} s): the goal will be cancelled "
            "mid-motion and the arm braked to rest (leave the timeout out to wait for the whole motion)")


def goal_start(robot: Robot, traj: JointTrajectory, pose: np.ndarray) -> np.ndarray:
    """The arm's ``pose`` (J,) in ``robot``'s joint order, restricted to ``traj``'s joints."""
    return np.asarray(pose, dtype=float)[[robot.index(name) for name in traj.joint_names]]


def check_goal_for_arm(robot: Robot, traj: JointTrajectory, pose: np.ndarray, velocity: np.ndarray) -> None:
    """Check ``traj`` as a goal for the arm in its state: at rest (:func:`require_at_rest`) and
    passing the motion check from ``pose`` (nothing is sent otherwise).

    Parameters
    ----------
    robot : Robot
    traj : JointTrajectory
        The motion, its first point where the arm is (e.g. planned from ``pose``).
    pose, velocity : arrays of shape (J,)
        The arm's state (rad, rad/s; every joint of ``robot``, e.g. from :class:`StateWatch`).

    Raises
    ------
    ArmStateError
        The arm is moving: a goal planned from rest is not sent to it.
    InputError
        ``traj`` fails the motion check from ``pose``.
    """
    require_at_rest(robot, velocity)
    try:
        check_goal(robot, traj, goal_start(robot, traj, pose))
    except InvalidJoints:
        raise
    except InputError as exc:  # worded as the controller's refusals are (a [ros.joints] map's joints both ways)
        raise type(exc)(in_controller_words(robot, f"from the arm's pose on {robot.ros.joint_states}: {exc}")) from None

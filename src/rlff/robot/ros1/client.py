"""Sending a trajectory to a FollowJointTrajectory server (``rlff robot send``), or on a topic.

The trajectory is checked against the robot's limits before any connection is made, and again
with the arm's current pose (read from /joint_states) as its start before it is sent
(:func:`rlff.trajectory.check.check_trajectory`). A timeout or Ctrl-C cancels the goal on the
server (the arm brakes to rest) before returning or re-raising.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import asdict, dataclass

import actionlib
import numpy as np
import rospy
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import (
    FollowJointTrajectoryAction,
    FollowJointTrajectoryGoal,
    FollowJointTrajectoryResult,
)
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory as TrajectoryMsg

from rlff.errors import InputError
from rlff.robot.controller import START_VELOCITY_TOLERANCE
from rlff.robot.description import Robot
from rlff.robot.goal import InvalidJoints, check_goal
from rlff.robot.ros1.convert import to_msg
from rlff.robot.ros1.master import RosUnavailable, wait_for_master
from rlff.robot.ros1.server import ACTION_NAMESPACE, JOINT_STATES, TOPIC
from rlff.trajectory.joint import JointTrajectory

#: Seconds between sending a goal and its start (its header stamp), so the server is ready.
START_LEAD = 0.2
#: Default seconds to wait for the master and the server when no timeout is given.
CONNECT_TIMEOUT = 10.0
#: Seconds after its start at which a goal sent to a moving arm has its first point.
APPROACH_LEAD = 0.1
#: Seconds to wait for the server to acknowledge a cancel (it answers once the arm has braked).
CANCEL_WAIT = 10.0

_ERROR_NAMES = {getattr(FollowJointTrajectoryResult, name): name for name in (
    "SUCCESSFUL", "INVALID_GOAL", "INVALID_JOINTS", "OLD_HEADER_TIMESTAMP", "PATH_TOLERANCE_VIOLATED",
    "GOAL_TOLERANCE_VIOLATED")}
# PREEMPTED is a goal cancelled while it ran: by us ("cancelled") or by a newer goal ("preempted")
_STATES = {GoalStatus.SUCCEEDED: "succeeded", GoalStatus.REJECTED: "rejected", GoalStatus.ABORTED: "aborted",
           GoalStatus.PREEMPTED: "preempted", GoalStatus.RECALLED: "cancelled", GoalStatus.LOST: "lost"}


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
        return self.status == "succeeded" and self.error_code == FollowJointTrajectoryResult.SUCCESSFUL

    def to_dict(self) -> dict:
        return asdict(self) | {"succeeded": self.succeeded}


def _connect(deadline: float, node: str) -> None:
    wait_for_master(max(0.0, deadline - time.monotonic()))
    if not rospy.core.is_initialized():
        rospy.init_node(node, anonymous=True, disable_signals=True)


def goal_start(robot: Robot, traj: JointTrajectory, pose: np.ndarray) -> np.ndarray:
    """The arm's ``pose`` (J,) in ``robot``'s joint order, restricted to ``traj``'s joints."""
    return np.asarray(pose, dtype=float)[[robot.index(name) for name in traj.joint_names]]


def arm_state(robot: Robot, timeout: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The arm's joint positions (rad) and velocities (rad/s), each (J,) in ``robot``'s order,
    from one /joint_states message.

    Raises
    ------
    RosUnavailable
        No master, or nothing on /joint_states, within ``timeout`` s (default 10).
    InputError
        The message leaves out a joint of ``robot``.
    """
    deadline = time.monotonic() + (timeout if timeout is not None else CONNECT_TIMEOUT)
    _connect(deadline, "rlff_send")
    try:
        msg = rospy.wait_for_message(JOINT_STATES, JointState, max(0.01, deadline - time.monotonic()))
    except rospy.ROSException:
        raise RosUnavailable(f"nothing on {JOINT_STATES}: the arm's pose is unknown "
                             "(is `rlff robot serve` running?)") from None
    names = list(msg.name)
    missing = [name for name in robot.joint_names if name not in names]
    if missing:
        raise InputError(f"{JOINT_STATES} has no position of {', '.join(missing)} (it names {', '.join(names)})")
    index = [names.index(name) for name in robot.joint_names]
    velocities = np.asarray(msg.velocity, dtype=float)
    return (np.asarray(msg.position, dtype=float)[index],
            velocities[index] if velocities.size == len(names) else np.zeros(len(index)))


def goal_for_arm(robot: Robot, traj: JointTrajectory, pose: np.ndarray, velocity: np.ndarray) -> JointTrajectory:
    """``traj`` checked as a goal from the arm's state, ready to send.

    Parameters
    ----------
    robot : Robot
    traj : JointTrajectory
        The motion, its first point where the arm is (e.g. planned from ``pose``).
    pose, velocity : arrays of shape (J,)
        The arm's state (rad, rad/s; every joint of ``robot``, e.g. :func:`arm_state`).

    Returns
    -------
    JointTrajectory
        ``traj`` itself for an arm at rest; for a moving arm (a running goal), whose pose is
        stale by the time the goal arrives, ``traj`` with every point :data:`APPROACH_LEAD` s
        later, so that the server approaches its first point from wherever the arm then is.

    Raises
    ------
    InputError
        ``traj`` fails the motion check from ``pose`` (nothing is sent).
    """
    try:
        check_goal(robot, traj, goal_start(robot, traj, pose))
    except InvalidJoints:
        raise
    except InputError as exc:
        raise type(exc)(f"from the arm's pose on {JOINT_STATES}: {exc}") from None
    if np.abs(velocity).max() <= START_VELOCITY_TOLERANCE:
        return traj
    return JointTrajectory(traj.joint_names, traj.time + APPROACH_LEAD, traj.positions, traj.velocities,
                           traj.accelerations)


def send_goal(
    robot: Robot,
    traj: JointTrajectory,
    pose: np.ndarray,
    timeout: float | None = None,
    on_feedback: Callable[[float], None] | None = None,
) -> SendResult:
    """Send ``traj`` as a FollowJointTrajectory goal and wait for its result.

    Parameters
    ----------
    robot : Robot
        The goal is checked against its joints and limits first.
    traj : JointTrajectory
    pose : array of shape (J,)
        The arm's pose (rad, every joint of ``robot``, e.g. :func:`arm_pose`): where the goal
        must start.
    timeout : float, optional
        Seconds for everything (connecting, executing); default: 10 s to connect, then the
        trajectory's duration plus 10 s. When it runs out the goal is cancelled.
    on_feedback : callable, optional
        Called with the elapsed trajectory time (s) of each feedback message.

    Raises
    ------
    InputError
        The trajectory does not fit the robot or does not start at ``pose`` (nothing is sent).
    RosUnavailable
        No master or no action server answered in time.
    KeyboardInterrupt
        After cancelling the goal.
    """
    check_goal(robot, traj, goal_start(robot, traj, pose))
    started = time.monotonic()
    deadline = started + (timeout if timeout is not None else CONNECT_TIMEOUT)
    _connect(deadline, "rlff_send")
    client = actionlib.SimpleActionClient(ACTION_NAMESPACE, FollowJointTrajectoryAction)
    if not client.wait_for_server(rospy.Duration.from_sec(max(0.01, deadline - time.monotonic()))):
        raise RosUnavailable(f"no action server at {ACTION_NAMESPACE} (is `rlff robot serve` running?)")
    if timeout is None:
        deadline = time.monotonic() + START_LEAD + traj.duration + CONNECT_TIMEOUT
    received = 0

    def feedback(message) -> None:
        nonlocal received
        received += 1
        if on_feedback:
            on_feedback(message.desired.time_from_start.to_sec())

    start = rospy.Time.now() + rospy.Duration.from_sec(START_LEAD)
    client.send_goal(FollowJointTrajectoryGoal(trajectory=to_msg(traj, start)), feedback_cb=feedback)
    try:
        finished = client.wait_for_result(rospy.Duration.from_sec(max(0.01, deadline - time.monotonic())))
    except (KeyboardInterrupt, rospy.ROSInterruptException):
        _cancel(client)
        raise KeyboardInterrupt from None
    if not finished:
        _cancel(client)
        result = client.get_result()
        text = f"; {result.error_string}" if result is not None and result.error_string else ""
        return SendResult("timed out", None, None, f"timed out; goal cancelled{text}", start.to_sec(),
                          traj.duration, received)
    result = client.get_result()
    status = _STATES.get(client.get_state(), "unknown")
    code = None if result is None else int(result.error_code)
    name = None if code == FollowJointTrajectoryResult.SUCCESSFUL and status != "succeeded" else _ERROR_NAMES.get(code)
    return SendResult(status, code, name, (result.error_string if result else "") or client.get_goal_status_text(),
                      start.to_sec(), traj.duration, received)


def _cancel(client: actionlib.SimpleActionClient) -> None:
    client.cancel_goal()
    client.wait_for_result(rospy.Duration.from_sec(CANCEL_WAIT))


def publish_trajectory(robot: Robot, traj: JointTrajectory, pose: np.ndarray,
                       timeout: float | None = None) -> int:
    """Publish ``traj`` once on the topic of the original driver; returns the subscriber count.

    Checked like :func:`send_goal` (starting at ``pose``); waits for a subscriber (the
    controller) up to the timeout, then lets the message go out.
    """
    check_goal(robot, traj, goal_start(robot, traj, pose))
    deadline = time.monotonic() + (timeout if timeout is not None else CONNECT_TIMEOUT)
    _connect(deadline, "rlff_publish")
    publisher = rospy.Publisher(TOPIC, TrajectoryMsg, queue_size=1, latch=True)
    while publisher.get_num_connections() == 0:
        if time.monotonic() >= deadline:
            raise RosUnavailable(f"nobody subscribes to {TOPIC} (is `rlff robot serve` running?)")
        time.sleep(0.05)
    publisher.publish(to_msg(traj))
    time.sleep(0.5)  # latched: let the subscriber fetch it before the node goes away
    return publisher.get_num_connections()

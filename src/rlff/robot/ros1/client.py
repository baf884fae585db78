"""Sending a trajectory to a FollowJointTrajectory server (``rlff robot send``), or on a topic.

The trajectory is checked against the robot before any connection is made. A timeout or Ctrl-C
cancels the goal on the server (the arm stops) before returning or re-raising.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import asdict, dataclass

import actionlib
import rospy
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import (
    FollowJointTrajectoryAction,
    FollowJointTrajectoryGoal,
    FollowJointTrajectoryResult,
)
from trajectory_msgs.msg import JointTrajectory as TrajectoryMsg

from rlff.robot.description import Robot
from rlff.robot.goal import check_goal
from rlff.robot.ros1.convert import to_msg
from rlff.robot.ros1.master import RosUnavailable, wait_for_master
from rlff.robot.ros1.server import ACTION_NAMESPACE, TOPIC
from rlff.trajectory.joint import JointTrajectory

#: Seconds between sending a goal and its start (its header stamp), so the server is ready.
START_LEAD = 0.2
#: Default seconds to wait for the master and the server when no timeout is given.
CONNECT_TIMEOUT = 10.0
#: Seconds to wait for the server to acknowledge a cancel.
CANCEL_WAIT = 10.0

_ERROR_NAMES = {getattr(FollowJointTrajectoryResult, name): name for name in (
    "SUCCESSFUL", "INVALID_GOAL", "INVALID_JOINTS", "OLD_HEADER_TIMESTAMP", "PATH_TOLERANCE_VIOLATED",
    "GOAL_TOLERANCE_VIOLATED")}
_STATES = {GoalStatus.SUCCEEDED: "succeeded", GoalStatus.REJECTED: "rejected", GoalStatus.ABORTED: "aborted",
           GoalStatus.PREEMPTED: "cancelled", GoalStatus.RECALLED: "cancelled", GoalStatus.LOST: "lost"}


@dataclass(frozen=True)
class SendResult:
    """What became of a goal.

    ``status``: succeeded, rejected, aborted, cancelled, lost or timed out; ``error_code`` and
    ``error_name``: the action result's code (e.g. -1, INVALID_GOAL); ``start``: the goal's
    start (ROS time, s); ``duration``: the trajectory's (s); ``feedback``: messages received.
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


def send_goal(
    robot: Robot,
    traj: JointTrajectory,
    timeout: float | None = None,
    on_feedback: Callable[[float], None] | None = None,
) -> SendResult:
    """Send ``traj`` as a FollowJointTrajectory goal and wait for its result.

    Parameters
    ----------
    robot : Robot
        The goal is checked against its joints and limits first.
    traj : JointTrajectory
    timeout : float, optional
        Seconds for everything (connecting, executing); default: 10 s to connect, then the
        trajectory's duration plus 10 s. When it runs out the goal is cancelled.
    on_feedback : callable, optional
        Called with the elapsed trajectory time (s) of each feedback message.

    Raises
    ------
    InputError
        The trajectory does not fit the robot (nothing is sent).
    RosUnavailable
        No master or no action server answered in time.
    KeyboardInterrupt
        After cancelling the goal.
    """
    check_goal(robot, traj)
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
        return SendResult("timed out", None, None, "timed out; goal cancelled", start.to_sec(),
                          traj.duration, received)
    result = client.get_result()
    code = None if result is None else int(result.error_code)
    return SendResult(_STATES.get(client.get_state(), "unknown"), code, _ERROR_NAMES.get(code),
                      (result.error_string if result else "") or client.get_goal_status_text(),
                      start.to_sec(), traj.duration, received)


def _cancel(client: actionlib.SimpleActionClient) -> None:
    client.cancel_goal()
    client.wait_for_result(rospy.Duration.from_sec(CANCEL_WAIT))


def publish_trajectory(robot: Robot, traj: JointTrajectory, timeout: float | None = None) -> int:
    """Publish ``traj`` once on the topic of the original driver; returns the subscriber count.

    Waits for a subscriber (the controller) up to the timeout, then lets the message go out.
    """
    check_goal(robot, traj)
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

"""Sending a trajectory to a FollowJointTrajectory server (``rlff robot send``), or on a topic.

The trajectory is checked against the robot's limits before any connection is made, and again
with the arm's current pose (read from /joint_states) as its start before it is sent
(:func:`rlff.trajectory.check.check_trajectory`). A timeout or Ctrl-C cancels the goal on the
server (the arm brakes to rest) before returning or re-raising.
"""

from __future__ import annotations

import time
from collections.abc import Callable

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

from rlff.errors import Interrupted
from rlff.robot.description import Robot
from rlff.robot.goal import check_goal
from rlff.robot.messages import arm_state_of
from rlff.robot.ros1.convert import to_msg
from rlff.robot.ros1.master import RosUnavailable, wait_for_master
from rlff.robot.ros1.server import ACTION_NAMESPACE, JOINT_STATES, TOPIC
from rlff.robot.send import ERROR_NAMES, SendResult, goal_start
from rlff.trajectory.joint import JointTrajectory

#: Seconds between sending a goal and its start (its header stamp), so the server is ready.
START_LEAD = 0.2
#: Default seconds to wait for the master and the server when no timeout is given.
CONNECT_TIMEOUT = 10.0
#: Seconds to wait for the server to acknowledge a cancel (it answers once the arm has braked).
CANCEL_WAIT = 10.0

# PREEMPTED is a goal cancelled while it ran: by us ("cancelled") or by a newer goal ("preempted")
_STATES = {GoalStatus.SUCCEEDED: "succeeded", GoalStatus.REJECTED: "rejected", GoalStatus.ABORTED: "aborted",
           GoalStatus.PREEMPTED: "preempted", GoalStatus.RECALLED: "cancelled", GoalStatus.LOST: "lost"}


def _connect(deadline: float, node: str) -> None:
    wait_for_master(max(0.0, deadline - time.monotonic()))
    if not rospy.core.is_initialized():
        rospy.init_node(node, anonymous=True, disable_signals=True)


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
    return arm_state_of(robot, JOINT_STATES, msg.name, msg.position, msg.velocity)


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
        After cancelling the goal (re-raised as it came: :class:`rlff.errors.Terminated` for
        the SIGTERM the command line turns into it; rospy's own shutdown as
        :class:`rlff.errors.Interrupted`).
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
    except (KeyboardInterrupt, rospy.ROSInterruptException) as exc:
        _cancel(client)
        raise (exc if isinstance(exc, KeyboardInterrupt) else Interrupted()) from None  # Terminated stays
    if not finished:
        _cancel(client)
        result = client.get_result()
        text = f"; {result.error_string}" if result is not None and result.error_string else ""
        return SendResult("timed out", None, None, f"timed out; goal cancelled{text}", start.to_sec(),
                          traj.duration, received)
    result = client.get_result()
    status = _STATES.get(client.get_state(), "unknown")
    code = None if result is None else int(result.error_code)
    name = None if code == FollowJointTrajectoryResult.SUCCESSFUL and status != "succeeded" else ERROR_NAMES.get(code)
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

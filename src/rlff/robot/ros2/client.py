"""Sending a trajectory to a ROS 2 FollowJointTrajectory server (``rlff robot send --ros 2``).

The trajectory is checked against the robot's limits, and with the arm's pose (read from
/joint_states by :func:`arm_state`) as its start, before it is sent. A timeout or Ctrl-C
cancels the goal on the server (the arm brakes to rest) before returning or re-raising. The
server's answer is reported as ROS 2 gives it: a goal the server refuses after accepting it (as
rlff's and ros2_control's servers do, so that the error code reaches the client) is "aborted"
with its code, one it does not accept at all is "rejected".
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

import numpy as np
import rclpy
from action_msgs.msg import GoalStatus
from control_msgs.action import FollowJointTrajectory
from rclpy.action import ActionClient
from rclpy.executors import SingleThreadedExecutor
from sensor_msgs.msg import JointState

from rlff.errors import RlffError
from rlff.robot.description import Robot
from rlff.robot.goal import check_goal
from rlff.robot.messages import arm_state_of
from rlff.robot.ros2.convert import seconds, to_msg
from rlff.robot.ros2.network import make_node
from rlff.robot.ros2.server import ACTION_NAME, JOINT_STATES
from rlff.robot.send import ERROR_NAMES, SendResult, goal_start
from rlff.trajectory.joint import JointTrajectory

#: Seconds between sending a goal and its start (its header stamp), so the server is ready.
START_LEAD = 0.2
#: Default seconds to wait for the server when no timeout is given.
CONNECT_TIMEOUT = 10.0
#: Seconds to wait for the server to answer a cancel (it does once the arm has braked).
CANCEL_WAIT = 10.0

_STATES = {GoalStatus.STATUS_SUCCEEDED: "succeeded", GoalStatus.STATUS_ABORTED: "aborted",
           GoalStatus.STATUS_CANCELED: "cancelled"}


class ServerUnavailable(RlffError):
    """No FollowJointTrajectory server answered in time."""


class Connection:
    """A node of its own (context, node, executor spinning in a thread) that talks to the arm.

    One call of :func:`arm_state` or :func:`send_goal` opens one; the learning loop keeps one for
    a whole run (it also listens for the landings a vision system publishes).
    """

    def __init__(self, name: str = "rlff_send", action: str = ACTION_NAME) -> None:
        self.action = action
        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.node = make_node(name, self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self._client: ActionClient | None = None
        self._thread = threading.Thread(target=self._spin, daemon=True)
        self._thread.start()

    def _spin(self) -> None:
        try:
            self.executor.spin()
        except Exception:  # noqa: BLE001 - the context was shut down under the spin
            pass

    def now(self) -> float:
        """ROS time (s)."""
        return self.node.get_clock().now().nanoseconds * 1e-9

    def subscribe(self, msg_type, topic: str, callback: Callable, wait_for_publisher: float = 0.0) -> bool:
        """Call ``callback(message)`` for every message on ``topic`` (from the executor's thread).

        With ``wait_for_publisher`` (s), wait that long at most for a publisher to be matched:
        a message published before discovery matched the two is lost to this subscription
        (volatile durability), and discovery can take seconds on a loaded machine. Returns
        whether a publisher is matched.
        """
        subscription = self.node.create_subscription(msg_type, topic, callback, 10)
        deadline = time.monotonic() + wait_for_publisher
        while subscription.get_publisher_count() == 0 and time.monotonic() < deadline:
            time.sleep(0.05)
        return subscription.get_publisher_count() > 0

    def close(self) -> None:
        # the spin ends before the node goes, so no callback runs on a destroyed node
        self.executor.shutdown(timeout_sec=1.0)
        self._thread.join(timeout=2.0)
        self.node.destroy_node()
        if self.context.ok():
            rclpy.shutdown(context=self.context)

    def __enter__(self) -> Connection:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def arm_state(self, robot: Robot, timeout: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The arm's joint positions (rad) and velocities (rad/s), each (J,) in ``robot``'s order,
        from the next /joint_states message.

        Raises
        ------
        ServerUnavailable
            Nothing on /joint_states within ``timeout`` s (default 10).
        InputError
            The message leaves out a joint of ``robot``.
        """
        deadline = time.monotonic() + (timeout if timeout is not None else CONNECT_TIMEOUT)
        received: list[JointState] = []
        subscription = self.node.create_subscription(JointState, JOINT_STATES, received.append, 1)
        try:
            while not received:
                if time.monotonic() >= deadline:
                    raise ServerUnavailable(f"nothing on {JOINT_STATES}: the arm's pose is unknown (is `rlff robot "
                                            "serve --ros 2` running, with the same ROS_DOMAIN_ID?)")
                time.sleep(0.01)
        finally:
            self.node.destroy_subscription(subscription)
        msg = received[0]
        return arm_state_of(robot, JOINT_STATES, msg.name, msg.position, msg.velocity)

    def send_goal(self, robot: Robot, traj: JointTrajectory, pose: np.ndarray, timeout: float | None = None,
                  on_feedback: Callable[[float], None] | None = None) -> SendResult:
        """:func:`send_goal` on this connection."""
        check_goal(robot, traj, goal_start(robot, traj, pose))
        deadline = time.monotonic() + (timeout if timeout is not None else CONNECT_TIMEOUT)
        if self._client is None:
            self._client = ActionClient(self.node, FollowJointTrajectory, self.action)
        client = self._client
        if not client.wait_for_server(timeout_sec=max(0.01, deadline - time.monotonic())):
            raise ServerUnavailable(f"no action server at {self.action} (is `rlff robot serve --ros 2` running, "
                                    "with the same ROS_DOMAIN_ID and discovery range?)")
        if timeout is None:
            deadline = time.monotonic() + START_LEAD + traj.duration + CONNECT_TIMEOUT
        received = 0

        def feedback(message) -> None:
            nonlocal received
            received += 1
            if on_feedback:
                on_feedback(seconds(message.feedback.desired.time_from_start))

        start = self.now() + START_LEAD
        goal = FollowJointTrajectory.Goal(trajectory=to_msg(traj, start))
        handle = sent = None
        try:
            sent = client.send_goal_async(goal, feedback_callback=feedback)
            if not _wait(sent, deadline):
                _cancel_when_accepted(sent)
                return SendResult("timed out", None, None, "timed out before the server accepted the goal", start,
                                  traj.duration, received)
            handle = sent.result()
            if not handle.accepted:
                return SendResult("rejected", None, None, "the server rejected the goal", start, traj.duration,
                                  received)
            answer = handle.get_result_async()
            if not _wait(answer, deadline):
                _cancel(handle)
                return SendResult("timed out", None, None, "timed out; goal cancelled", start, traj.duration,
                                  received)
        except KeyboardInterrupt:
            if handle is not None and handle.accepted:
                _cancel(handle)
            elif handle is None and sent is not None:  # sent, its acceptance not yet heard
                _cancel_when_accepted(sent)
            raise
        outcome = answer.result()
        code = int(outcome.result.error_code)
        status = _STATES.get(outcome.status, "lost")
        name = None if code == 0 and status != "succeeded" else ERROR_NAMES.get(code)
        return SendResult(status, code, name, outcome.result.error_string, start, traj.duration, received)


def _wait(future, deadline: float) -> bool:
    while not future.done():
        if time.monotonic() >= deadline:
            return False
        time.sleep(0.01)
    return True


def arm_state(robot: Robot, timeout: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The arm's joint positions (rad) and velocities (rad/s), each (J,) in ``robot``'s order, from
    one /joint_states message (:meth:`Connection.arm_state` on a connection of its own)."""
    with Connection("rlff_arm_state") as connection:
        return connection.arm_state(robot, timeout)


def send_goal(
    robot: Robot,
    traj: JointTrajectory,
    pose: np.ndarray,
    timeout: float | None = None,
    on_feedback: Callable[[float], None] | None = None,
    action: str = ACTION_NAME,
) -> SendResult:
    """Send ``traj`` as a FollowJointTrajectory goal and wait for its result.

    Parameters
    ----------
    robot : Robot
        The goal is checked against its joints and limits first.
    traj : JointTrajectory
    pose : array of shape (J,)
        The arm's pose (rad, every joint of ``robot``, e.g. from :func:`arm_state`): where the
        goal must start.
    timeout : float, optional
        Seconds for everything (connecting, executing); default: 10 s to connect, then the
        trajectory's duration plus 10 s. When it runs out the goal is cancelled.
    on_feedback : callable, optional
        Called with the elapsed trajectory time (s) of each feedback message.
    action : str
        The action's name.

    Raises
    ------
    InputError
        The trajectory does not fit the robot or does not start at ``pose`` (nothing is sent).
    ServerUnavailable
        No action server answered in time.
    KeyboardInterrupt
        After cancelling the goal (re-raised as it came: :class:`rlff.errors.Terminated` for
        the SIGTERM the command line turns into it).
    """
    check_goal(robot, traj, goal_start(robot, traj, pose))
    with Connection("rlff_send", action) as connection:
        return connection.send_goal(robot, traj, pose, timeout, on_feedback)


def _cancel_when_accepted(sent) -> None:
    """Cancel a goal whose acceptance had not arrived when the client gave up on it: an
    acceptance on its way would otherwise start the arm with nobody left to stop it."""
    if _wait(sent, time.monotonic() + CANCEL_WAIT) and sent.result().accepted:
        _cancel(sent.result())


def _cancel(handle) -> None:
    """Ask the server to cancel and wait for the goal's end (the arm braked to rest)."""
    deadline = time.monotonic() + CANCEL_WAIT
    _wait(handle.cancel_goal_async(), deadline)
    _wait(handle.get_result_async(), deadline)

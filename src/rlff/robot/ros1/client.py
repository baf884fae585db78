"""Sending a trajectory to a FollowJointTrajectory server (``rlff robot send``), or on a topic.

The action, the joint states and the topic are the robot's (``robot.ros``, the robot file's
``[ros]`` table). The trajectory is checked against the robot's limits before any connection is
made, and again with the arm's current pose (fresh joint state messages that agree,
:class:`rlff.robot.send.StateWatch`) as its start before it is sent (:func:`rlff.trajectory.check.check_trajectory`). A timeout or
Ctrl-C cancels the goal on the server (the arm brakes to rest) before returning or re-raising;
a cancel the server does not confirm within :data:`CANCEL_WAIT` s, or a server that goes silent
(its status topic stops), is reported as such: the arm's state is then unknown. Every goal of a
process goes through one actionlib client (:func:`_client`), its answers to callbacks of its own
(:class:`_Goal`).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

import actionlib
import numpy as np
import rospy
from actionlib.action_client import CommState
from actionlib_msgs.msg import GoalStatus, GoalStatusArray
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
from rlff.robot.ros1.convert import to_msg
from rlff.robot.ros1.master import RosUnavailable, publishers_of, wait_for_master
from rlff.robot.send import (
    CANCEL_NOT_AWAITED,
    CANCEL_UNCONFIRMED,
    CANCEL_WAIT,
    CONNECT_TIMEOUT,
    ERROR_NAMES,
    GOAL_CANCELLED,
    START_LEAD,
    SendResult,
    StateWatch,
    check_timeout,
    goal_fate,
    goal_start,
    mark_goal,
    unfinished,
)
from rlff.robot.unreachable import action_topic_hint, ros1_no_joint_states
from rlff.trajectory.joint import JointTrajectory

#: Seconds without a status message from the server (actionlib publishes one at 5 Hz) after
#: which it counts as gone; one second once its status connection has closed too.
SERVER_SILENCE = 5.0

# PREEMPTED is a goal cancelled while it ran: by us ("cancelled") or by a newer goal ("preempted")
_STATES = {GoalStatus.SUCCEEDED: "succeeded", GoalStatus.REJECTED: "rejected", GoalStatus.ABORTED: "aborted",
           GoalStatus.PREEMPTED: "preempted", GoalStatus.RECALLED: "cancelled", GoalStatus.LOST: "lost"}


def _connect(deadline: float, node: str) -> None:
    wait_for_master(max(0.0, deadline - time.monotonic()))
    if not rospy.core.is_initialized():
        rospy.init_node(node, anonymous=True, disable_signals=True)


def arm_state(robot: Robot, timeout: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The arm's joint positions (rad) and velocities (rad/s), each (J,) in ``robot``'s order,
    from fresh messages on its joint states topic (``robot.ros.joint_states``; see
    :class:`rlff.robot.send.StateWatch`).

    Raises
    ------
    RosUnavailable
        No master, or nothing on the joint states topic, within ``timeout`` s (default 10); the
        message says whether the master lists a publisher of it
        (:func:`rlff.robot.unreachable.ros1_no_joint_states`).
    ArmStateError
        Only stale or unstamped messages came, or the pose is not a number or beyond a limit, or
        two fresh poses disagree (two publishers of the arm's joints).
    InputError
        ``timeout`` is not a finite number above 0 (nothing connects), or the message leaves out a
        joint of ``robot``.
    """
    check_timeout(timeout)
    waited = timeout if timeout is not None else CONNECT_TIMEOUT
    deadline = time.monotonic() + waited
    _connect(deadline, "rlff_send")
    topic = robot.ros.joint_states
    # the master lists every publisher of the topic at once, and rospy connects to them together
    # (within some ms here): unlike ROS 2's discovery, no publisher comes late (StateWatch.hold)
    watch = StateWatch(robot, lambda: rospy.get_rostime().to_sec(), "rostopic info")
    subscriber = rospy.Subscriber(topic, JointState, lambda msg: watch.offer(
        msg.header.stamp.to_sec(), msg.name, msg.position, msg.velocity))
    try:
        state = watch.wait(deadline, waited)
    finally:
        subscriber.unregister()
    if state is None:
        raise RosUnavailable(ros1_no_joint_states(robot, waited, publishers_of(topic)))
    return state


#: The process's one client of each action (:func:`_client`).
_CLIENTS: dict[str, actionlib.ActionClient] = {}


def _client(action: str) -> actionlib.ActionClient:
    """The one client of ``action`` in this process, made on its first goal and kept for every later
    one (the learning loop sends one per attempt): rospy never drops a client's subscribers, so a
    client made per goal left its own behind each time, every one of them still fed each status."""
    if action not in _CLIENTS:
        _CLIENTS[action] = actionlib.ActionClient(action, FollowJointTrajectoryAction)
    return _CLIENTS[action]


class _Goal:
    """One goal sent on ``client``: its handle, whether it ended, and its callbacks.

    Its transitions come to callbacks of its own, bound before it is sent. actionlib's
    SimpleActionClient took them only once it had recorded the handle, which it does after the
    goal is out: a status or result that rospy's thread took first was dropped ("Got a transition
    callback on a goal handle that we're not tracking", about one goal in 25), and with it the
    goal's acceptance, or the end of a goal rejected at once, which was then waited for until the
    timeout.
    """

    def __init__(self, client: actionlib.ActionClient, goal: FollowJointTrajectoryGoal,
                 on_feedback: Callable[[float], None] | None, on_accepted: Callable[[], None] | None) -> None:
        self._ended = threading.Event()
        self._on_feedback, self._on_accepted = on_feedback, on_accepted
        self.received = 0  # feedback messages
        self.handle = client.send_goal(goal, self._transition, self._feedback)

    def _transition(self, handle) -> None:
        state = handle.get_comm_state()
        if state in (CommState.ACTIVE, CommState.PREEMPTING) and self._on_accepted is not None:
            accepted, self._on_accepted = self._on_accepted, None  # once
            accepted()
        elif state == CommState.DONE:
            self._ended.set()

    def _feedback(self, _handle, message) -> None:
        self.received += 1
        if self._on_feedback:
            self._on_feedback(message.desired.time_from_start.to_sec())

    def wait(self, timeout: float) -> bool:
        """Whether the goal ended (the server's last word on it, or actionlib's LOST), waiting up to ``timeout`` s."""
        return self._ended.wait(timeout)

    def status(self) -> int:
        """Its GoalStatus code, the server's latest."""
        return self.handle.get_goal_status()

    def result(self) -> FollowJointTrajectoryResult | None:
        return self.handle.get_result()


class _Status:
    """When the server of ``action`` last published its status, and whether its status connection is up."""

    def __init__(self, action: str) -> None:
        self.last = time.monotonic()
        self.subscriber = rospy.Subscriber(f"{action}/status", GoalStatusArray, self._heard)
        self.connected = False

    def _heard(self, _msg) -> None:
        self.last = time.monotonic()

    def silence(self) -> float | None:
        """Seconds the server has been silent, once it counts as gone; None while it answers."""
        quiet = time.monotonic() - self.last
        connected = self.subscriber.get_num_connections() > 0
        self.connected = self.connected or connected
        if quiet > SERVER_SILENCE or (self.connected and not connected and quiet > 1.0):
            return quiet
        return None

    def close(self) -> None:
        self.subscriber.unregister()


def send_goal(
    robot: Robot,
    traj: JointTrajectory,
    pose: np.ndarray,
    timeout: float | None = None,
    on_feedback: Callable[[float], None] | None = None,
    on_accepted: Callable[[], None] | None = None,
) -> SendResult:
    """Send ``traj`` as a FollowJointTrajectory goal and wait for its result.

    Parameters
    ----------
    robot : Robot
        The goal is checked against its joints and limits first, and goes to its action
        (``robot.ros.action``).
    traj : JointTrajectory
    pose : array of shape (J,)
        The arm's pose (rad, every joint of ``robot``, e.g. :func:`arm_state`): where the goal
        must start.
    timeout : float, optional
        Seconds for connecting and executing; default: 10 s to connect, then the trajectory's
        duration plus 10 s. When it runs out the goal is cancelled, and the server gets up to
        :data:`CANCEL_WAIT` s more to confirm it (the arm braked to rest).
    on_feedback : callable, optional
        Called with the elapsed trajectory time (s) of each feedback message.
    on_accepted : callable, optional
        Called once the server accepted the goal (from rospy's thread).

    Returns
    -------
    SendResult
        Its status "timed out" (or "lost": the server went silent) says in its text whether the
        cancel was confirmed.

    Raises
    ------
    InputError
        ``timeout`` is not a finite number above 0, or the trajectory does not fit the robot or
        does not start at ``pose`` (nothing connects or is sent).
    RosUnavailable
        No master or no action server answered in time.
    KeyboardInterrupt
        After cancelling the goal (re-raised as it came: :class:`rlff.errors.Terminated` for
        the SIGTERM the command line turns into it; rospy's own shutdown as
        :class:`rlff.errors.Interrupted`), marked (:func:`rlff.robot.send.goal_fate`) with whether
        the server confirmed the cancel.
    """
    check_timeout(timeout)
    check_goal(robot, traj, goal_start(robot, traj, pose))
    started = time.monotonic()
    deadline = started + (timeout if timeout is not None else CONNECT_TIMEOUT)
    _connect(deadline, "rlff_send")
    action = robot.ros.action
    client = _client(action)
    if not client.wait_for_server(rospy.Duration.from_sec(max(0.01, deadline - time.monotonic()))):
        raise RosUnavailable(f"no action server at {action} ({robot.ros_origin('action')}): "
                             f"{action_topic_hint(action)}is `rlff robot serve` "
                             "running, or does the arm's controller use another name? "
                             "(`rostopic list | grep follow_joint_trajectory`)")
    if timeout is None:
        deadline = time.monotonic() + START_LEAD + traj.duration + CONNECT_TIMEOUT
    status = _Status(action)
    start = rospy.Time.now() + rospy.Duration.from_sec(START_LEAD)
    sent, sending = None, False
    try:
        try:
            # in the controller's joint names and convention (the robot file's [ros.joints])
            goal = FollowJointTrajectoryGoal(trajectory=to_msg(robot.ros.joints.to_controller(traj), start))
            sending = True
            sent = _Goal(client, goal, on_feedback, on_accepted)
            ended = _wait(sent, status, deadline)
        except (KeyboardInterrupt, rospy.ROSInterruptException) as exc:
            interrupt = exc if isinstance(exc, KeyboardInterrupt) else Interrupted()  # Terminated stays
            if not sending:  # stopped while the goal was being made: nothing went out, unmarked
                raise interrupt from None
            try:
                # interrupted while sending: the goal may be out, with no handle to cancel it by
                fate = CANCEL_UNCONFIRMED if sent is None or not _cancel(sent, status) else GOAL_CANCELLED
            except KeyboardInterrupt:  # a second one while cancelling: the cancel went out, not awaited
                fate = CANCEL_NOT_AWAITED
            raise mark_goal(interrupt, fate) from None
        if ended != "ended":
            gone = None if ended == "timed out" else ended
            confirmed = _cancel(sent, status, lost=gone is not None)
            result = sent.result()
            text = result.error_string if result is not None else ""
            return unfinished(gone, confirmed, action, start.to_sec(), traj.duration, sent.received, text)
    except KeyboardInterrupt as exc:  # a second Ctrl-C while cancelling: the cancel was sent, not confirmed
        if sending and goal_fate(exc) is None:
            mark_goal(exc, CANCEL_UNCONFIRMED)
        raise
    finally:
        status.close()
    result = sent.result()
    state = _STATES.get(sent.status(), "unknown")
    code = None if result is None else int(result.error_code)
    name = None if code == FollowJointTrajectoryResult.SUCCESSFUL and state != "succeeded" else ERROR_NAMES.get(code)
    return SendResult(state, code, name, (result.error_string if result else "") or sent.handle.get_goal_status_text(),
                      start.to_sec(), traj.duration, sent.received)


def _wait(sent: _Goal, status: _Status, deadline: float) -> str:
    """Wait for the goal's end: "ended", "timed out", or why the server counts as gone."""
    while True:
        left = deadline - time.monotonic()
        if left <= 0:
            return "timed out"
        if sent.wait(min(0.2, left)):
            # a server restarted mid-goal lists no such goal, and actionlib ends it LOST: no end
            # the server gave, and nothing braked the arm
            return "it lists the goal no more: restarted?" if sent.status() == GoalStatus.LOST else "ended"
        quiet = status.silence()
        if quiet is not None:
            return f"no status for {quiet:.1f} s"


def _cancel(sent: _Goal, status: _Status, lost: bool = False) -> bool:
    """Ask the server to cancel; whether it confirmed the goal's end (the arm braked to rest) within
    :data:`CANCEL_WAIT` s. A server already gone gets the cancel (should it come back) and a
    second to answer it. A goal actionlib ends as LOST (a server restarted after a crash lists no
    such goal) is no confirmation: nothing braked it, and "cancelled" had been said of it."""
    sent.handle.cancel()
    deadline = time.monotonic() + (1.0 if lost else CANCEL_WAIT)
    while time.monotonic() < deadline:
        if sent.wait(0.2):
            return sent.status() != GoalStatus.LOST
        if not lost and status.silence() is not None:
            return False
    return False


def publish_trajectory(robot: Robot, traj: JointTrajectory, pose: np.ndarray,
                       timeout: float | None = None) -> int:
    """Publish ``traj`` once on the topic of the original driver (``robot.ros.trajectory_topic``);
    returns the subscriber count.

    Checked like :func:`send_goal` (its ``timeout`` and ``traj``, starting at ``pose``); waits for
    a subscriber (the controller) up to the timeout, then lets the message go out.
    """
    check_timeout(timeout)
    check_goal(robot, traj, goal_start(robot, traj, pose))
    deadline = time.monotonic() + (timeout if timeout is not None else CONNECT_TIMEOUT)
    _connect(deadline, "rlff_publish")
    topic = robot.ros.trajectory_topic
    publisher = rospy.Publisher(topic, TrajectoryMsg, queue_size=1, latch=True)
    while publisher.get_num_connections() == 0:
        if time.monotonic() >= deadline:
            raise RosUnavailable(f"nobody subscribes to {topic} ({robot.ros_origin('trajectory_topic')}): is "
                                 "`rlff robot serve` running, or does the arm's driver listen on another topic?")
        time.sleep(0.05)
    publisher.publish(to_msg(robot.ros.joints.to_controller(traj)))
    time.sleep(0.5)  # latched: let the subscriber fetch it before the node goes away
    return publisher.get_num_connections()

"""Sending a trajectory to a ROS 2 FollowJointTrajectory server (``rlff robot send --ros 2``).

The action and the joint states are the robot's (``robot.ros``, the robot file's ``[ros]``
table). The trajectory is checked against the robot's limits, and with the arm's pose (fresh
joint state messages that agree, read by :func:`arm_state`; see :class:`rlff.robot.send.StateWatch`) as its
start, before it is sent. A timeout or Ctrl-C cancels the goal on the server (the arm brakes
to rest) before returning or re-raising; a cancel the server does not confirm within
:data:`CANCEL_WAIT` s, or a server that goes away mid-goal (it leaves the graph, its feedback
stops, or, before any feedback, it answers no ping: :class:`_Ping`), is reported as such: the
arm's state is then unknown. The
server's answer is reported as ROS 2 gives it: a goal the server refuses after accepting it (as
rlff's and ros2_control's servers do, so that the error code reaches the client) is "aborted"
with its code, one it does not accept at all is "rejected".
"""

from __future__ import annotations

import threading
import time
import uuid
from collections.abc import Callable

import numpy as np
import rclpy
from action_msgs.msg import GoalStatus
from action_msgs.srv import CancelGoal
from control_msgs.action import FollowJointTrajectory
from rclpy.action import ActionClient
from rclpy.action.client import ClientGoalHandle
from rclpy.client import Client
from rclpy.executors import SingleThreadedExecutor
from sensor_msgs.msg import JointState
from unique_identifier_msgs.msg import UUID

from rlff.errors import RlffError
from rlff.robot.description import Robot
from rlff.robot.goal import check_goal
from rlff.robot.ros2.convert import seconds, to_msg
from rlff.robot.ros2.network import make_node
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
    cancel_unconfirmed,
    check_timeout,
    goal_fate,
    goal_start,
    mark_goal,
    unfinished,
)
from rlff.robot.unreachable import action_topic_hint, ros2_no_joint_states
from rlff.trajectory.joint import JointTrajectory

_STATES = {GoalStatus.STATUS_SUCCEEDED: "succeeded", GoalStatus.STATUS_ABORTED: "aborted",
           GoalStatus.STATUS_CANCELED: "cancelled"}


#: Seconds without feedback, once the server sent some, after which it counts as gone (servers
#: that send feedback send it every control cycle; a server that crashed is seen no other way
#: until discovery's lease of some 20 s runs out). Before its first feedback, seconds without an
#: answer to a ping (:class:`_Ping`) after which it counts as gone.
FEEDBACK_SILENCE = 3.0
#: Seconds between pings of a server that sent no feedback since it accepted the goal.
PING_PERIOD = 1.0
#: Seconds the goal's status may say it ended (the server's status topic) without its result
#: coming, before the result is asked for again (:class:`_Result`).
RESULT_GRACE = 2.0


#: Seconds from the first joint states message a subscription hears before the arm's state may be
#: taken (:meth:`rlff.robot.send.StateWatch.hold`; the messages meanwhile are compared): discovery
#: connects a new subscription to a topic's publishers one by one, and a second publisher of the
#: arm's joints must be heard before the state is taken. Measured here (two publishers, nodes of
#: their own, and a new process subscribing): the second's first message came 0 to 0.12 s after
#: the first's, once 0.75 s, and more than a second later in one run of twelve of the live test;
#: a publisher whose messages come later than this is not seen. (Waiting besides for a message of
#: every publisher the graph knows, read in the subscription's callback, made the live tests'
#: own discovery fail now and then, unexplained: left out.)
DISCOVERY_WINDOW = 1.0
#: Seconds a new action client waits for the server's feedback and status publishers to appear in
#: the graph once its services answer, and then seconds more before its first goal. Discovery is
#: mutual only eventually: a client that sends as soon as it sees the server's services can have
#: the goal's response (and the first feedback) lost, because the server has not matched the
#: client's readers yet ("timed out waiting for the goal response", once in CI, with an rclpy
#: ActionClient that sent at once; the arm would have thrown while rlff reported a timeout).
ACTION_DISCOVERY = 3.0
ACTION_SETTLE = 1.0


class ServerUnavailable(RlffError):
    """No FollowJointTrajectory server answered in time."""


class Connection:
    """A node of its own (context, node, executor spinning in a thread) that talks to the arm.

    One call of :func:`arm_state` or :func:`send_goal` opens one; ``rlff robot send`` keeps one
    to read the arm's state and send the goal, the learning loop one for a whole run (it also
    listens for the landings a vision system publishes). The topics and the
    action are those of the robot each call is given (its ``ros``).
    """

    def __init__(self, name: str = "rlff_send") -> None:
        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.node = make_node(name, self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self._clients: dict[str, ActionClient] = {}  # by action name
        self._pings: dict[str, Client] = {}  # the action's cancel service, to ping its server (_Ping)
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
        from fresh messages on its joint states topic (``robot.ros.joint_states``; see
        :class:`rlff.robot.send.StateWatch`).

        Raises
        ------
        ServerUnavailable
            Nothing on the joint states topic within ``timeout`` s (default 10; discovery counts
            against it); the message says whether discovery found a publisher of it
            (:func:`rlff.robot.unreachable.ros2_no_joint_states`).
        ArmStateError
            Only stale or unstamped messages came, or the pose is not a number or beyond a limit,
            or two fresh poses disagree (two publishers of the arm's joints).
        InputError
            ``timeout`` is not a finite number above 0 (nothing is subscribed), or the message leaves
            out a joint of ``robot``.
        """
        check_timeout(timeout)
        waited = timeout if timeout is not None else CONNECT_TIMEOUT
        deadline = time.monotonic() + waited
        topic = robot.ros.joint_states
        watch = StateWatch(robot, self.now, "ros2 topic info")
        heard = threading.Event()

        def offer(msg) -> None:
            if not heard.is_set():  # the first message: other publishers may not have reached this one yet
                heard.set()
                watch.hold(DISCOVERY_WINDOW)
            watch.offer(msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9, msg.name, msg.position, msg.velocity)

        subscription = self.node.create_subscription(JointState, topic, offer, 10)
        try:
            state = watch.wait(deadline, waited)
        finally:
            self.node.destroy_subscription(subscription)
        if state is None:  # no publisher discovered, or publishers that sent nothing it took
            raise ServerUnavailable(ros2_no_joint_states(robot, waited, self.node.count_publishers(topic)))
        return state

    def _settle(self, action: str, deadline: float) -> None:
        """Give a new action client's discovery time to become mutual before its first goal: wait
        (at most :data:`ACTION_DISCOVERY` s) for the server's feedback and status publishers, then
        :data:`ACTION_SETTLE` s; each wait takes at most half of what is left before ``deadline``
        (monotonic s), so the goal keeps its chance."""
        topics = (f"{action}/_action/feedback", f"{action}/_action/status")
        began = time.monotonic()
        until = began + min(ACTION_DISCOVERY, (deadline - began) / 2)
        while time.monotonic() < until and any(self.node.count_publishers(topic) == 0 for topic in topics):
            time.sleep(0.05)
        time.sleep(max(0.0, min(ACTION_SETTLE, (deadline - time.monotonic()) / 2)))

    def send_goal(self, robot: Robot, traj: JointTrajectory, pose: np.ndarray, timeout: float | None = None,
                  on_feedback: Callable[[float], None] | None = None,
                  on_accepted: Callable[[], None] | None = None) -> SendResult:
        """:func:`send_goal` on this connection."""
        check_timeout(timeout)
        check_goal(robot, traj, goal_start(robot, traj, pose))
        deadline = time.monotonic() + (timeout if timeout is not None else CONNECT_TIMEOUT)
        action = robot.ros.action
        fresh = action not in self._clients
        if fresh:
            self._clients[action] = ActionClient(self.node, FollowJointTrajectory, action)
            self._pings[action] = self.node.create_client(CancelGoal, f"{action}/_action/cancel_goal")
        client = self._clients[action]
        if not client.wait_for_server(timeout_sec=max(0.01, deadline - time.monotonic())):
            raise ServerUnavailable(f"no action server at {action} ({robot.ros_origin('action')}): "
                                    f"{action_topic_hint(action)}is `rlff robot "
                                    "serve --ros 2` running, with the same ROS_DOMAIN_ID and discovery range, or "
                                    "does the arm's controller use another name? (`ros2 action list -t`)")
        if fresh:
            self._settle(action, deadline)
        if timeout is None:
            deadline = time.monotonic() + START_LEAD + traj.duration + CONNECT_TIMEOUT
        received = 0
        heard: list[float] = []

        def feedback(message) -> None:
            nonlocal received
            received += 1
            heard[:] = [time.monotonic()]
            if on_feedback:
                on_feedback(seconds(message.feedback.desired.time_from_start))

        start = self.now() + START_LEAD
        goal = FollowJointTrajectory.Goal(trajectory=to_msg(robot.ros.joints.to_controller(traj), start))
        # the goal's id is the client's to choose: it can cancel the goal by it before it heard the acceptance
        goal_id = UUID(uuid=list(uuid.uuid4().bytes))
        handle = sent = None
        try:
            sent = client.send_goal_async(goal, feedback_callback=feedback, goal_uuid=goal_id)
            if not _wait(sent, deadline):
                fate, said = _cancel_when_accepted(sent, client, goal_id)
                text = (f"goal cancelled{f'; {said}' if said else ''}" if fate == GOAL_CANCELLED
                        else cancel_unconfirmed(CANCEL_WAIT) if fate == CANCEL_UNCONFIRMED
                        else said or "the goal was not accepted")
                return SendResult("timed out", None, None, f"timed out before the server accepted the goal; {text}",
                                  start, traj.duration, received)
            handle = sent.result()
            if not handle.accepted:
                return SendResult("rejected", None, None, "the server rejected the goal", start, traj.duration,
                                  received)
            if on_accepted:
                try:
                    on_accepted()
                except Exception:
                    _cancel(handle)  # accepted: it must not run on with nobody left to stop it
                    raise
            answer = _Result(handle)
            ended = _wait(answer, deadline, client, lambda: heard[0] if heard else None,
                          _Ping(self._pings[action]))
            if ended is not True:
                gone = ended if isinstance(ended, str) else None
                confirmed, said = _cancel(handle, lost=gone is not None, answer=answer)
                return unfinished(gone, confirmed, action, start, traj.duration, received, said)
        except KeyboardInterrupt as exc:
            if goal_fate(exc) is not None:  # a second Ctrl-C while cancelling
                raise
            try:
                if handle is not None and handle.accepted:
                    fate = GOAL_CANCELLED if _cancel(handle)[0] else CANCEL_UNCONFIRMED
                elif handle is None and sent is not None:  # sent, its acceptance not yet heard
                    fate = _cancel_when_accepted(sent, client, goal_id)[0]
                else:
                    fate = None  # refused, or never sent: nothing runs
            except KeyboardInterrupt:  # a second one while cancelling: the cancel went out, not awaited
                fate = CANCEL_NOT_AWAITED
            if fate is not None:
                mark_goal(exc, fate)
            raise
        outcome = answer.result()
        code = int(outcome.result.error_code)
        status = _STATES.get(outcome.status, "lost")
        name = None if code == 0 and status != "succeeded" else ERROR_NAMES.get(code)
        return SendResult(status, code, name, outcome.result.error_string, start, traj.duration, received)


class _Result:
    """The result of an accepted goal, as a future (``done()``, ``result()``), asked for again
    whenever the goal's status (the server's status topic, which rclpy keeps on the handle) has
    said for :data:`RESULT_GRACE` s that the goal ended and no answer came: a response the server
    sends before discovery has matched it to this client's reader is lost, and the server keeps
    the result to give again. Once in CI a goal the server aborted at once was reported "timed
    out" after the whole 60 s timeout, its result never heard."""

    def __init__(self, handle) -> None:
        self.handle = handle
        self.asked = [handle.get_result_async()]
        self.ended = None  # monotonic s when the status was first seen to say the goal ended

    def done(self) -> bool:
        if any(answer.done() for answer in self.asked):
            return True
        if self.handle.status in _STATES:
            now = time.monotonic()
            if self.ended is None:
                self.ended = now
            elif now - self.ended >= RESULT_GRACE:
                self.asked.append(self.handle.get_result_async())
                self.ended = now
        return False

    def result(self):
        return next(answer for answer in self.asked if answer.done()).result()


class _Ping:
    """Whether the server of an accepted goal that sends no feedback is still there.

    A server process that dies (killed, crashed) stays in the ROS graph until discovery's lease
    runs out, some 20 s; one that sends feedback is seen gone when it stops. One that sent none
    yet is pinged every :data:`PING_PERIOD` s: asked, on the action's own cancel service, to
    cancel a goal it never had (a random goal id, stamp 0, which cancels that goal alone: the
    server answers ERROR_UNKNOWN_GOAL_ID and nothing else happens). A server that answers none
    for :data:`FEEDBACK_SILENCE` s counts as gone; one whose cancel service this client has not
    been matched to yet is not asked, and not counted against it.
    """

    def __init__(self, service) -> None:
        self.service = service
        self.answered = time.monotonic()  # the goal was just accepted
        self.pending = None
        self.request = CancelGoal.Request()
        self.request.goal_info.goal_id.uuid = list(uuid.uuid4().bytes)

    def silence(self) -> float | None:
        """Seconds without an answer, once the server counts as gone; None while it answers."""
        now = time.monotonic()
        if self.pending is not None and self.pending.done():
            self.pending = None
            self.answered = now
        if self.pending is None and now - self.answered >= PING_PERIOD:
            if not self.service.service_is_ready():
                self.answered = now  # not asked: no answer missing
                return None
            self.pending = self.service.call_async(self.request)
        quiet = now - self.answered
        return quiet if quiet > FEEDBACK_SILENCE else None


def _wait(future, deadline: float, client: ActionClient | None = None,
          heard: Callable[[], float | None] | None = None, ping: _Ping | None = None) -> bool | str:
    """Whether ``future`` is done by ``deadline``; or why ``client``'s server counts as gone before
    that: it left the ROS graph for a second, or its feedback (``heard()``: when the last came,
    monotonic s; None before the first) stopped for :data:`FEEDBACK_SILENCE` s, or, before any
    feedback, it answered no ``ping`` for as long."""
    gone = None
    checked = 0.0
    while not future.done():
        now = time.monotonic()
        if now >= deadline:
            return False
        if client is not None and now - checked >= 0.1:
            checked = now
            gone = None if client.server_is_ready() else (gone or now)
            if gone is not None and now - gone > 1.0:
                return "it left the ROS graph"
            last = heard() if heard is not None else None
            if last is not None and now - last > FEEDBACK_SILENCE:
                return f"its feedback stopped {now - last:.1f} s ago"
            quiet = ping.silence() if last is None and ping is not None else None
            if quiet is not None:
                return f"no feedback since it accepted the goal, and no answer for {quiet:.1f} s"
        time.sleep(0.01)
    return True


def arm_state(robot: Robot, timeout: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The arm's joint positions (rad) and velocities (rad/s), each (J,) in ``robot``'s order, from
    fresh messages on its joint states topic (:meth:`Connection.arm_state` on a connection of its
    own). A ``timeout`` that is not a finite number above 0 is an :class:`InputError` before any
    node starts."""
    check_timeout(timeout)
    with Connection("rlff_arm_state") as connection:
        return connection.arm_state(robot, timeout)


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
        The arm's pose (rad, every joint of ``robot``, e.g. from :func:`arm_state`): where the
        goal must start.
    timeout : float, optional
        Seconds for connecting and executing; default: 10 s to connect, then the trajectory's
        duration plus 10 s. When it runs out the goal is cancelled, and the server gets up to
        :data:`CANCEL_WAIT` s more to confirm it (the arm braked to rest).
    on_feedback : callable, optional
        Called with the elapsed trajectory time (s) of each feedback message (from the
        connection's thread).
    on_accepted : callable, optional
        Called once the server accepted the goal.

    Raises
    ------
    InputError
        ``timeout`` is not a finite number above 0, or the trajectory does not fit the robot or
        does not start at ``pose`` (no node starts, nothing is sent).
    ServerUnavailable
        No action server answered in time.
    KeyboardInterrupt
        After cancelling the goal (re-raised as it came: :class:`rlff.errors.Terminated` for
        the SIGTERM the command line turns into it), marked (:func:`rlff.robot.send.goal_fate`)
        with whether the server confirmed the cancel; unmarked when no goal was sent.
    """
    check_timeout(timeout)
    check_goal(robot, traj, goal_start(robot, traj, pose))
    with Connection("rlff_send") as connection:
        return connection.send_goal(robot, traj, pose, timeout, on_feedback, on_accepted)


def _cancel_when_accepted(sent, client: ActionClient, goal_id: UUID) -> tuple[str | None, str]:
    """Cancel a goal whose acceptance had not arrived when the client gave up on it: an
    acceptance on its way would otherwise start the arm with nobody left to stop it. Where no
    acceptance comes within :data:`CANCEL_WAIT` s either, the goal is cancelled by its id
    (``goal_id``, the one ``sent`` went out with): the server's answer to its goal may have been
    lost (a response sent before discovery matched the two), the arm running a goal the client
    never heard was accepted. Returns what became of it: None (never accepted, or a server that
    knows no such goal: nothing runs, though it may have run and ended, which the second value
    says), :data:`GOAL_CANCELLED` or :data:`CANCEL_UNCONFIRMED` (accepted, or no answer at all);
    and the server's text of the goal's end (:func:`_cancel`)."""
    if _wait(sent, time.monotonic() + CANCEL_WAIT):
        if not sent.result().accepted:
            return None, ""
        handle = sent.result()
    else:  # a handle of the goal by its id, as if its acceptance had come
        handle = ClientGoalHandle(client, goal_id, FollowJointTrajectory.Impl.SendGoalService.Response(accepted=True))
    confirmed, said = _cancel(handle, unknown_is_none=True)
    if confirmed is None:  # the server keeps an ended goal only for its result timeout (rclpy: 10 s)
        return None, ("the server knows no such goal: it never had it, or had it and it ended (a server keeps an "
                      "ended goal for a few seconds only)")
    return (GOAL_CANCELLED if confirmed else CANCEL_UNCONFIRMED), said


def _cancel(handle, lost: bool = False, answer=None, unknown_is_none: bool = False) -> tuple[bool | None, str]:
    """Ask the server to cancel and wait for the goal's end (the arm braked to rest), on ``answer``
    (the goal's result future, when one was asked for already): whether it came within
    :data:`CANCEL_WAIT` s (a second for a server that left the graph), and the server's text of
    it, as ROS 1's result carries it too (rlff's servers: ``cancelled after 1.000 s of 2.100 s;
    braked to rest from 2.574 rad/s in 0.336 s``; empty when it did not come or said nothing).
    With ``unknown_is_none``: None where the server answers that it knows no such goal, to the
    cancel or with the result's status (a goal whose acceptance was never heard, which it never
    had)."""
    deadline = time.monotonic() + (1.0 if lost else CANCEL_WAIT)
    asked = handle.cancel_goal_async()
    if (_wait(asked, deadline) is True and unknown_is_none
            and asked.result().return_code == CancelGoal.Response.ERROR_UNKNOWN_GOAL_ID):
        return None, ""
    answer = answer if answer is not None else handle.get_result_async()
    if _wait(answer, deadline) is not True:
        return False, ""
    if unknown_is_none and answer.result().status == GoalStatus.STATUS_UNKNOWN:
        return None, ""
    return True, answer.result().result.error_string

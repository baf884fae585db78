"""The ROS 2 FollowJointTrajectory action server of a simulated arm (``rlff robot serve --ros 2``).

The second thin transport over :class:`rlff.robot.controller.TrajectoryController` (the ROS 1
one is :mod:`rlff.robot.ros1.server`): goals of ``control_msgs/action/FollowJointTrajectory`` and
trajectories on the topic, under the names of the robot file's ``[ros]`` table
(:class:`rlff.robot.description.RosNames`; by default the action
``/comau_controller/follow_joint_trajectory``, the topic ``/comau/joint_trajectory`` and
``/joint_states``), become the controller's calls; a timer ticks it at a fixed rate, every tick
publishing the joint states and the active goal's feedback. What a goal does (checks and result codes,
approach, braking on cancel, preemption) is the controller's; only the mapping to ROS 2's goal
states is this module's:

- rclpy cannot attach a result to a rejected goal, so a goal the controller refuses is accepted
  and at once aborted with the controller's code (INVALID_GOAL, INVALID_JOINTS, ...) and reason,
  as ros2_control's joint_trajectory_controller answers a goal that fails on its first sample;
  nothing moves.
- A goal that a newer one preempts is aborted with the controller's text ("preempted by a newer
  goal ..."): ROS 2 has no PREEMPTED state, and only a client's cancel request leads to CANCELED.
- A cancel request for the running goal is accepted; the goal ends CANCELED once the arm has
  braked to rest.
- Tolerances: the goal's ``path_tolerance``/``goal_tolerance`` entries must name joints of the
  robot (else INVALID_JOINTS) with finite values (else INVALID_GOAL); the kinematic arm follows
  its trajectory exactly, so the actual state is the desired one and no tolerance can be
  exceeded. A goal for multi-DOF joints is refused with INVALID_JOINTS (the arm has none).
- SIGTERM or Ctrl-C stops the server safely (:mod:`rlff.robot.stopping`): the executor turns
  on, ticking, while the arm brakes to rest and the goal is answered ABORTED (``the server was
  stopped by SIGTERM after ...; braked to rest from ...``); then the node shuts down. (A goal's
  execute callback waits for the goal's end in an executor thread: once the executor stopped
  turning, nothing ticked to end it, and the process hung on that thread.)
"""

from __future__ import annotations

import math
import os
import tempfile
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import rclpy
from control_msgs.action import FollowJointTrajectory
from filelock import lock_descriptor
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.action.server import ServerGoalHandle
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory as TrajectoryMsg
from trajectory_msgs.msg import JointTrajectoryPoint

from rlff.errors import InputError
from rlff.robot.controller import (
    CompletionHook,
    GoalRejected,
    Outcome,
    ResultCode,
    TrajectoryController,
    check_rate,
    completion_text,
    goal_in_rlff,
    in_controller_words,
    state_for_controller,
)
from rlff.robot.description import Robot
from rlff.robot.kinematic import ArmState
from rlff.robot.ros2.convert import duration, from_msg, start_of
from rlff.robot.ros2.network import make_node
from rlff.robot.stopping import StopRequest, run_until_stopped
from rlff.trajectory.joint import JointTrajectory

NODE_NAME = "rlff_comau_controller"
#: Threads of the executor: goals wait for their end in one each, besides the tick and callbacks.
THREADS = 8
#: Seconds a stopping server leaves its executor's threads to start the callbacks handed to them.
HANDOVER = 0.2
#: Seconds a starting server listens for another server of the action (discovery on this host
#: takes a fraction of a second when idle, more on a loaded machine).
DISCOVERY_WAIT = 3.0


class ServerRunning(InputError):
    """Another server already serves the action in this ROS domain."""



@dataclass
class _Goal:
    """A goal the server answered: its handle, its trajectory, and its result once it ended."""

    handle: ServerGoalHandle
    trajectory: JointTrajectory | None  # the goal's points; None: refused
    executed: JointTrajectory | None = None  # what the arm follows for it (approach included)
    ended: threading.Event = field(default_factory=threading.Event)
    status: str = ""  # succeeded, aborted, cancelled
    code: int = ResultCode.SUCCESSFUL
    text: str = ""

    def end(self, status: str, code: int, text: str) -> None:
        self.status, self.code, self.text = status, int(code), text
        self.ended.set()


def _goal_key(handle: ServerGoalHandle) -> bytes:
    return bytes(handle.goal_id.uuid)


class TrajectoryServer:
    """The ROS 2 transport of a :class:`TrajectoryController` of ``robot`` on ``node``, under the
    names of ``robot.ros``.

    Parameters
    ----------
    node : rclpy.node.Node
    robot : Robot
    initial : array of shape (J,)
        Starting joint positions (rad), within the limits.
    rate : float
        Ticks per second: state, joint states and feedback are computed and published this often.
    on_complete : callable, optional
        Called with every trajectory that ran to its end (e.g. a MuJoCo throw).
    """

    def __init__(self, node: Node, robot: Robot, initial: np.ndarray, rate: float = 100.0,
                 on_complete: CompletionHook | None = None) -> None:
        check_rate(rate)
        self.node = node
        self.robot = robot
        self.on_complete = on_complete
        self.controller = TrajectoryController(robot, initial)
        self._lock = threading.Lock()  # guards the controller and the goals
        self._goals: dict[bytes, _Goal] = {}
        callbacks = ReentrantCallbackGroup()
        names = robot.ros
        self._topic_name = names.trajectory_topic
        self._states = node.create_publisher(JointState, names.joint_states, 10)
        self._server = ActionServer(node, FollowJointTrajectory, names.action, execute_callback=self._execute,
                                    goal_callback=lambda request: GoalResponse.ACCEPT,
                                    handle_accepted_callback=self._on_accepted, cancel_callback=self._on_cancel,
                                    callback_group=callbacks)
        self._topic = node.create_subscription(TrajectoryMsg, names.trajectory_topic, self._on_topic, 1,
                                               callback_group=callbacks)
        self._timer = node.create_timer(1.0 / rate, self.tick, callback_group=MutuallyExclusiveCallbackGroup())

    def _now(self) -> float:
        return self.node.get_clock().now().nanoseconds * 1e-9

    # -- callbacks (executor threads) --------------------------------------------------------
    def _on_accepted(self, handle: ServerGoalHandle) -> None:
        request = handle.request
        key = _goal_key(handle)
        log = self.node.get_logger()
        with self._lock:
            try:
                self._check_extras(request)
                traj = goal_in_rlff(self.robot, from_msg(request.trajectory))
                executed, ended = self.controller.submit(key, traj, self._now(), start_of(request.trajectory))
            except InputError as exc:
                code = exc.code if isinstance(exc, GoalRejected) else ResultCode.INVALID_GOAL
                text = in_controller_words(self.robot, str(exc))
                goal = self._goals[key] = _Goal(handle, None)
                goal.end("aborted", code, text)
                log.warning(f"goal {key.hex()} refused ({ResultCode(code).name}): {text}")
            else:
                self._goals[key] = _Goal(handle, traj, executed)
                self._report(ended)
                log.info(f"goal {key.hex()} accepted: {len(traj)} points, {traj.duration:.3f} s "
                         f"(executed: {executed.duration:.3f} s)")
        handle.execute()

    def _check_extras(self, request: FollowJointTrajectory.Goal) -> None:
        """The parts of a goal the controller does not see: multi-DOF joints and tolerances."""
        if request.multi_dof_trajectory.joint_names or request.multi_dof_trajectory.points:
            raise GoalRejected(ResultCode.INVALID_JOINTS,
                               f"the goal has a multi-DOF trajectory ({list(request.multi_dof_trajectory.joint_names)}); "
                               f"robot {self.robot.name} has single-axis joints only")
        if request.component_path_tolerance or request.component_goal_tolerance:
            raise GoalRejected(ResultCode.INVALID_JOINTS,
                               "the goal has component tolerances, which are for multi-DOF joints")
        # the controller's names (the robot file's [ros.joints]), as the goal's
        known = self.robot.ros.joints.controller_names(self.robot.joint_names)
        for kind in ("path_tolerance", "goal_tolerance"):
            for tolerance in getattr(request, kind):
                if tolerance.name not in known:
                    raise GoalRejected(ResultCode.INVALID_JOINTS,
                                       f"{kind} names joint {tolerance.name!r}, which robot {self.robot.name} "
                                       f"does not have ({', '.join(known)})")
                for quantity in ("position", "velocity", "acceleration"):
                    value = getattr(tolerance, quantity)
                    if not math.isfinite(value):
                        raise GoalRejected(ResultCode.INVALID_GOAL,
                                           f"{kind} of {tolerance.name}: {quantity} {value} is not a number")

    def _on_topic(self, msg: TrajectoryMsg) -> None:
        log = self.node.get_logger()
        with self._lock:
            try:
                traj = goal_in_rlff(self.robot, from_msg(msg))
                executed, ended = self.controller.submit(None, traj, self._now(), start_of(msg))
            except InputError as exc:
                code = exc.code if isinstance(exc, GoalRejected) else ResultCode.INVALID_GOAL
                log.error(f"trajectory on {self._topic_name} refused ({ResultCode(code).name}): "
                          f"{in_controller_words(self.robot, str(exc))}")
                return
            self._report(ended)
        log.info(f"trajectory on {self._topic_name}: {len(traj)} points, {traj.duration:.3f} s "
                 f"(executed: {executed.duration:.3f} s)")

    def _on_cancel(self, handle: ServerGoalHandle) -> CancelResponse:
        key = _goal_key(handle)
        with self._lock:
            goal = self._goals.get(key)
            if goal is None or goal.ended.is_set():
                return CancelResponse.REJECT
            if key == self.controller.active_goal:
                self._report(self.controller.cancel(key, self._now()))  # or once braked, by the tick
                self.node.get_logger().info(f"goal {key.hex()} cancelled: braking to rest")
            else:  # accepted but not (or no longer) the controller's: nothing moves for it
                goal.end("cancelled", ResultCode.SUCCESSFUL, "cancelled")
        return CancelResponse.ACCEPT

    def _execute(self, handle: ServerGoalHandle) -> FollowJointTrajectory.Result:
        """Wait for the goal's end (reported by the tick or a callback) and answer with it."""
        goal = self._goals[_goal_key(handle)]
        while not goal.ended.wait(0.1):
            if not rclpy.ok(context=self.node.context):
                goal.end("aborted", ResultCode.SUCCESSFUL, "the server shut down")
        try:
            self._answer(handle, goal)
        finally:
            with self._lock:  # answered: a stopping server may shut down (:meth:`settled`)
                self._goals.pop(_goal_key(handle), None)
        return FollowJointTrajectory.Result(error_code=goal.code, error_string=goal.text)

    @staticmethod
    def _answer(handle: ServerGoalHandle, goal: _Goal) -> None:
        """Move the goal to the ROS 2 state of how it ended."""
        if goal.status == "cancelled":
            # a cancel of an arm at rest ends the goal inside the cancel callback, before rclpy
            # has moved the goal to CANCELING: give it that moment
            deadline = time.monotonic() + 1.0
            while not handle.is_cancel_requested and time.monotonic() < deadline:
                time.sleep(0.005)
        if goal.status == "succeeded":
            handle.succeed()
        elif goal.status == "cancelled" and handle.is_cancel_requested:
            handle.canceled()
        else:
            handle.abort()

    # -- stopping (the main thread) ----------------------------------------------------------
    def stop(self, by: str) -> bool:
        """Brake the arm to rest and take no new goal: the server was stopped by ``by`` (a signal's
        name); whether anything is left to finish (a motion, a goal to answer)."""
        with self._lock:
            self._report(self.controller.stop(self._now(), by))
        return not self.settled()

    def settled(self) -> bool:
        """Whether the arm stands still and every goal has been answered."""
        with self._lock:
            return self.controller.idle and not self._goals

    def abandon(self, text: str) -> None:
        """End every goal not yet ended with ``text`` (ABORTED), so that the executor threads
        waiting for their ends return: the server exits without waiting for the arm."""
        with self._lock:
            for goal in self._goals.values():
                if not goal.ended.is_set():
                    goal.end("aborted", ResultCode.SUCCESSFUL, text)

    # -- helpers (called with the lock held) -------------------------------------------------
    def _report(self, outcomes: list[Outcome]) -> None:
        """End the goals that were cancelled, preempted or braked because the server stops
        (successes go through :meth:`tick`)."""
        for outcome in outcomes:
            self.node.get_logger().info(
                f"{'topic trajectory' if outcome.goal is None else 'goal ' + outcome.goal.hex()}: {outcome.text}")
            goal = self._goals.get(outcome.goal) if outcome.goal is not None else None
            if goal is not None:
                status = "cancelled" if outcome.status == "cancelled" else "aborted"
                goal.end(status, outcome.code, outcome.text)

    # -- the fixed-rate loop -----------------------------------------------------------------
    def tick(self) -> None:
        """Advance the arm to now, publish the joint states and feedback, end goals that finished."""
        with self._lock:
            now = self.node.get_clock().now()  # under the lock, as in the ROS 1 server's tick
            state, ended = self.controller.update(now.nanoseconds * 1e-9)
            self._publish_state(now.to_msg(), state)
            active = self._goals.get(self.controller.active_goal)
            if active is not None and active.executed is not None:
                self._publish_feedback(active, now.to_msg(), state)
            finished = [outcome for outcome in ended if outcome.status == "succeeded"]
            self._report([outcome for outcome in ended if outcome.status != "succeeded"])
        for outcome in finished:
            self._succeed(outcome)

    def _succeed(self, outcome: Outcome) -> None:
        # the completion hook (a MuJoCo throw) may take a while: not under the lock
        text, failed = completion_text(self.on_complete, outcome)
        if failed:
            self.node.get_logger().error(text)
        self.node.get_logger().info(text)
        if outcome.goal is None:
            return
        with self._lock:
            goal = self._goals.get(outcome.goal)
            if goal is not None and not goal.ended.is_set():
                goal.end("succeeded", ResultCode.SUCCESSFUL, text)

    def _publish_state(self, stamp, state: ArmState) -> None:
        names, positions, velocities = state_for_controller(self.robot, state)[:3]
        msg = JointState(name=names, position=positions.tolist(), velocity=velocities.tolist())
        msg.header.stamp = stamp
        self._states.publish(msg)

    def _publish_feedback(self, goal: _Goal, stamp, state: ArmState) -> None:
        traj, executed = goal.trajectory, goal.executed
        # the goal's own point being executed: its times sit at the end of what the arm executes
        # (after an approach, if any)
        goal_time = state.elapsed - (executed.duration - traj.duration)
        index = int(np.clip(np.searchsorted(traj.time, goal_time, side="right") - 1, 0, len(traj) - 1))
        names, positions, velocities, accelerations = state_for_controller(self.robot, state)
        point = JointTrajectoryPoint(positions=positions.tolist(), velocities=velocities.tolist(),
                                     accelerations=accelerations.tolist(),
                                     time_from_start=duration(max(0.0, state.elapsed)))
        zeros = JointTrajectoryPoint(positions=[0.0] * len(state.positions), velocities=[0.0] * len(state.positions),
                                     accelerations=[0.0] * len(state.positions),
                                     time_from_start=point.time_from_start)
        feedback = FollowJointTrajectory.Feedback(joint_names=names, desired=point,
                                                  actual=point, error=zeros, index=index)
        feedback.header.stamp = stamp
        goal.handle.publish_feedback(feedback)


def _claim_on_this_host(node_name: str, action: str) -> int | None:
    """Lock this host's claim on ``action`` in this ROS domain; the locked descriptor, held until
    the process ends (the kernel frees it if the process dies).

    Discovery alone can miss a server on this host for seconds on a loaded machine; this lock
    cannot. Servers on other hosts are still found by :func:`_require_no_server`. None when the
    lock file cannot be opened (another user's): then discovery alone decides.

    Raises
    ------
    ServerRunning
        Another ``rlff robot serve --ros 2`` of this domain runs on this host.
    """
    domain = os.environ.get("ROS_DOMAIN_ID", "0")
    path = Path(tempfile.gettempdir()) / f"rlff-ros2-domain{domain}{action.replace('/', '-')}.lock"
    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError:
        return None
    if not lock_descriptor(fd, blocking=False):
        holder, _, pid = os.pread(fd, 200, 0).decode("utf-8", errors="replace").strip().partition("\n")
        os.close(fd)
        raise ServerRunning(f"{holder or 'another rlff server'} already serves {action} on this host "
                            f"({pid or 'pid unknown'}, ROS_DOMAIN_ID {domain}): stop it first; a second server "
                            "would compete for the goals")
    os.ftruncate(fd, 0)
    os.pwrite(fd, f"node /{node_name}\npid {os.getpid()}".encode(), 0)
    return fd


def _require_no_server(node: Node, action: str) -> None:
    """:class:`ServerRunning` if another node serves ``action`` (publishes its status) in reach.

    Two ROS 2 servers of one action would both take every goal (ROS 2 allows it, with nodes of
    the same name too), so a second ``rlff robot serve --ros 2`` is refused and the first goes on.
    """
    status = f"{action}/_action/status"
    deadline = time.monotonic() + DISCOVERY_WAIT
    found = None
    while time.monotonic() < deadline:
        # an endpoint may be discovered before its node's name (then "_NODE_NAME_UNKNOWN_")
        servers = node.get_publishers_info_by_topic(status)
        named = [info for info in servers if not info.node_name.startswith("_NODE_NAME_UNKNOWN")]
        found = named[0] if named else found or (servers[0] if servers else None)
        if named:
            break
        time.sleep(0.05)
    if found is not None:
        who = ("another node" if found.node_name.startswith("_NODE_NAME_UNKNOWN")
               else f"node {found.node_namespace.rstrip('/')}/{found.node_name}")
        raise ServerRunning(f"{who} already serves {action} (ROS_DOMAIN_ID "
                            f"{os.environ.get('ROS_DOMAIN_ID', '0')}): stop it first; a second server would "
                            "compete for the goals")


def serve(robot: Robot, initial: np.ndarray, rate: float = 100.0, on_complete: CompletionHook | None = None,
          node_name: str = NODE_NAME, on_ready: Callable[[], None] | None = None) -> None:
    """Start a ROS 2 node with a :class:`TrajectoryServer` of ``robot``'s ROS names (its ``ros``)
    and run it until Ctrl-C or SIGTERM, which brake a moving arm to rest and answer its goal first
    (a second one ends the process at once).

    Call :func:`rlff.robot.ros2.network.limit_discovery` first (the CLI does).

    Raises
    ------
    InputError
        ``rate`` is not a positive number, or the initial pose is beyond the limits.
    ServerRunning
        Another server of the action answers (checked before this one starts serving).
    """
    check_rate(rate)
    TrajectoryController(robot, initial)  # the initial pose within the limits, before any node
    _claim_on_this_host(node_name, robot.ros.action)  # held until the process ends
    context = rclpy.Context()
    rclpy.init(context=context)
    try:
        node = make_node(node_name, context)
        try:
            _require_no_server(node, robot.ros.action)
        except ServerRunning:
            node.destroy_node()
            raise
        server = TrajectoryServer(node, robot, initial, rate, on_complete)
        executor = MultiThreadedExecutor(num_threads=THREADS, context=context)
        executor.add_node(node)
        log = node.get_logger()

        def turn() -> bool:
            executor.spin_once(timeout_sec=0.1)
            return context.ok()

        stop = StopRequest()
        try:
            with stop.caught():
                if on_ready:
                    on_ready()
                run_until_stopped(turn, stop, server.stop, server.settled, log.info, log.warning)
        finally:
            # a second signal (or ROS shut down) ends it here before the goals' ends: their threads
            # must return for the executor, and the process, to end
            server.abandon("the server exited at once, before the arm was at rest")
            # rclpy (9.1) destroys the executor's guard condition without waiting for the callbacks
            # last handed to its threads, which then fail ("cannot use Destroyable because
            # destruction was requested", printed at exit); none is handed over once the executor
            # no longer turns: give those a moment to start
            time.sleep(HANDOVER)
            executor.shutdown(timeout_sec=1.0)
            node.destroy_node()
    finally:
        if context.ok():
            rclpy.shutdown(context=context)

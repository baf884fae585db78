"""The FollowJointTrajectory action server of a simulated arm (``rlff robot serve``).

It stands in for the thesis' controller plug-in, under the names of the robot file's ``[ros]``
table (:class:`rlff.robot.description.RosNames`; by default the action
``/comau_controller/follow_joint_trajectory``, the topic ``/comau/joint_trajectory`` of the
original driver's topic mode and ``/joint_states``): goals and topic trajectories go to the
transport-independent :class:`rlff.robot.controller.TrajectoryController`, which decides what the
arm does (goal checks and result codes, approaches, braking on cancel, preemption); this module
only turns messages into its calls and its outcomes into action results, and ticks it at a fixed
rate, every tick publishing the joint states and the active goal's feedback. A trajectory on the topic obeys the
same rules as a goal; a refused one is logged and nothing moves. A goal starts at its header
stamp (or on receipt when the stamp is 0 or the arm is moving).

SIGTERM or Ctrl-C stops the server safely (:mod:`rlff.robot.stopping`): rospy's own handlers,
which shut the node down at once (the arm left mid-motion, the goal unanswered), are not
installed; the arm brakes to rest, the goal is answered ABORTED (``the server was stopped by
SIGTERM after ...; braked to rest from ...``), then the node shuts down.
"""

from __future__ import annotations

from collections.abc import Callable

import actionlib
import numpy as np
import rospy
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import (
    FollowJointTrajectoryAction,
    FollowJointTrajectoryFeedback,
    FollowJointTrajectoryResult,
)
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
from rlff.robot.ros1.convert import from_msg
from rlff.robot.ros1.master import require_no_server, wait_for_master
from rlff.robot.stopping import StopRequest, run_until_stopped

NODE_NAME = "rlff_comau_controller"


class TrajectoryServer:
    """The ROS 1 transport of a :class:`TrajectoryController` (needs an initialised node), under the
    names of its robot's ``ros``.

    Parameters
    ----------
    controller : TrajectoryController
        Decides what every goal, cancel and tick does.
    rate : float
        Ticks per second: state, joint states and feedback are computed and published this often.
    on_complete : callable, optional
        Called with every trajectory that ran to its end (e.g. a MuJoCo throw).
    """

    def __init__(self, controller: TrajectoryController, rate: float = 100.0,
                 on_complete: CompletionHook | None = None) -> None:
        check_rate(rate)
        self.controller = controller
        self.robot = controller.robot
        self.rate = rate
        self.on_complete = on_complete
        self._handles: dict[str, actionlib.ServerGoalHandle] = {}
        names = self.robot.ros
        self._topic_name = names.trajectory_topic
        self._states = rospy.Publisher(names.joint_states, JointState, queue_size=10)
        self._server = actionlib.ActionServer(names.action, FollowJointTrajectoryAction,
                                              goal_cb=self._on_goal, cancel_cb=self._on_cancel,
                                              auto_start=False)
        # One lock guards the controller and the handles: the action server's own (re-entrant)
        # lock, which actionlib already holds when it calls the goal and cancel callbacks. A second
        # lock of ours would be taken in the opposite order by the tick (feedback) and deadlock.
        self._lock = self._server.lock
        self._topic = rospy.Subscriber(names.trajectory_topic, TrajectoryMsg, self._on_topic, queue_size=1)
        self._server.start()

    # -- callbacks (subscriber threads) ------------------------------------------------------
    def _on_goal(self, handle: actionlib.ServerGoalHandle) -> None:
        msg = handle.get_goal().trajectory
        goal = handle.get_goal_id().id
        with self._lock:
            now, start = rospy.get_time(), _start(msg)
            try:
                traj = goal_in_rlff(self.robot, from_msg(msg))
                executed, ended = self.controller.submit(goal, traj, now, start)
            except GoalRejected as exc:
                self._reject(handle, exc.code, in_controller_words(self.robot, str(exc)))
                return
            except InputError as exc:
                self._reject(handle, ResultCode.INVALID_GOAL, in_controller_words(self.robot, str(exc)))
                return
            handle.set_accepted("executing")
            self._handles[goal] = handle
            self._report(ended)
        rospy.loginfo("goal %s accepted: %d points, %.3f s (executed: %.3f s)", goal, len(traj),
                      traj.duration, executed.duration)
        if start is not None and start < now:
            rospy.logwarn("goal %s arrived %.3f s after its header stamp: started on receipt", goal, now - start)

    def _on_topic(self, msg: TrajectoryMsg) -> None:
        with self._lock:
            try:
                traj = goal_in_rlff(self.robot, from_msg(msg))
                executed, ended = self.controller.submit(None, traj, rospy.get_time(), _start(msg))
            except InputError as exc:
                code = exc.code.name if isinstance(exc, GoalRejected) else ResultCode.INVALID_GOAL.name
                rospy.logerr("trajectory on %s refused (%s): %s", self._topic_name, code,
                             in_controller_words(self.robot, str(exc)))
                return
            self._report(ended)
        rospy.loginfo("trajectory on %s: %d points, %.3f s (executed: %.3f s)", self._topic_name, len(traj),
                      traj.duration, executed.duration)

    def _on_cancel(self, handle: actionlib.ServerGoalHandle) -> None:
        goal = handle.get_goal_id().id
        with self._lock:
            if goal == self.controller.active_goal:
                self._report(self.controller.cancel(goal, rospy.get_time()))  # or once braked
                rospy.loginfo("goal %s cancelled: braking to rest", goal)
                return
            status = handle.get_goal_status().status
            if status in (GoalStatus.PENDING, GoalStatus.ACTIVE, GoalStatus.RECALLING, GoalStatus.PREEMPTING):
                handle.set_canceled(FollowJointTrajectoryResult(error_string="cancelled"), "cancelled")

    # -- helpers (called with the lock held) -------------------------------------------------
    def _reject(self, handle: actionlib.ServerGoalHandle, code: int, text: str) -> None:
        rospy.logwarn("goal %s rejected (%s): %s", handle.get_goal_id().id, ResultCode(code).name, text)
        handle.set_rejected(FollowJointTrajectoryResult(error_code=code, error_string=text), text)

    def _report(self, outcomes: list[Outcome]) -> None:
        """Answer the goals that ended cancelled or preempted (PREEMPTED), or braked because the
        server stops (ABORTED); successes go through :meth:`tick`."""
        for outcome in outcomes:
            rospy.loginfo("%s: %s", "topic trajectory" if outcome.goal is None else f"goal {outcome.goal}",
                          outcome.text)
            handle = self._handles.pop(outcome.goal, None) if outcome.goal is not None else None
            if handle is None or handle.get_goal_status().status not in (GoalStatus.ACTIVE, GoalStatus.PREEMPTING):
                continue
            result = FollowJointTrajectoryResult(error_code=outcome.code, error_string=outcome.text)
            if outcome.status == "aborted":
                handle.set_aborted(result, outcome.text)
            else:
                handle.set_canceled(result, outcome.text)

    def stop(self, by: str) -> bool:
        """Brake the arm to rest and take no new goal: the server was stopped by ``by`` (a signal's
        name); whether anything is left to finish (a motion, a goal to answer)."""
        with self._lock:
            self._report(self.controller.stop(rospy.get_time(), by))
        return not self.settled()

    def settled(self) -> bool:
        """Whether the arm stands still and every goal has been answered."""
        with self._lock:
            return self.controller.idle and not self._handles

    # -- the fixed-rate loop -----------------------------------------------------------------
    def tick(self) -> None:
        """Advance the arm to now, publish the joint states and feedback, answer goals that ended."""
        with self._lock:
            # the clock is read under the lock: a goal or cancel that took the lock in between
            # (with its own, later now) must not see the arm advanced to an earlier time, nor a
            # state be published stamped before the motion it was computed from
            now_time = rospy.Time.now()
            state, ended = self.controller.update(now_time.to_sec())
            self._publish_state(now_time, state)
            active = self._handles.get(self.controller.active_goal)
            if active is not None:
                self._publish_feedback(active, now_time, state)
            finished = [outcome for outcome in ended if outcome.status == "succeeded"]
            self._report([outcome for outcome in ended if outcome.status != "succeeded"])
        for outcome in finished:
            self._succeed(outcome)

    def _succeed(self, outcome: Outcome) -> None:
        # the completion hook (a MuJoCo throw) may take a while: not under the lock
        text, failed = completion_text(self.on_complete, outcome)
        if failed:
            rospy.logerr(text)
        rospy.loginfo(text)
        if outcome.goal is None:
            return
        with self._lock:
            handle = self._handles.pop(outcome.goal, None)
            if handle is not None and handle.get_goal_status().status == GoalStatus.ACTIVE:
                handle.set_succeeded(FollowJointTrajectoryResult(error_code=ResultCode.SUCCESSFUL,
                                                                 error_string=text), text)

    def _publish_state(self, stamp: rospy.Time, state: ArmState) -> None:
        names, positions, velocities = state_for_controller(self.robot, state)[:3]
        msg = JointState(name=names, position=positions.tolist(), velocity=velocities.tolist())
        msg.header.stamp = stamp
        self._states.publish(msg)

    def _publish_feedback(self, handle: actionlib.ServerGoalHandle, stamp: rospy.Time, state: ArmState) -> None:
        names, positions, velocities, accelerations = state_for_controller(self.robot, state)
        point = JointTrajectoryPoint(positions=positions.tolist(), velocities=velocities.tolist(),
                                     accelerations=accelerations.tolist(),
                                     time_from_start=rospy.Duration.from_sec(state.elapsed))
        zeros = JointTrajectoryPoint(positions=[0.0] * len(state.positions), velocities=[0.0] * len(state.positions),
                                     time_from_start=point.time_from_start)
        feedback = FollowJointTrajectoryFeedback(joint_names=names, desired=point, actual=point, error=zeros)
        feedback.header.stamp = stamp
        handle.publish_feedback(feedback)

    def spin(self, stop: StopRequest) -> None:
        """Tick at :attr:`rate` until ROS shuts down, or ``stop`` is requested and the arm has
        braked to rest and its goal been answered (:func:`rlff.robot.stopping.run_until_stopped`)."""
        clock = rospy.Rate(self.rate)

        def step() -> bool:
            self.tick()
            try:
                clock.sleep()
            except rospy.ROSInterruptException:
                return False
            return not rospy.is_shutdown()

        run_until_stopped(step, stop, self.stop, self.settled, rospy.loginfo, rospy.logwarn)


def _start(msg: TrajectoryMsg) -> float | None:
    """Clock time (s) the trajectory's time 0 refers to: its header stamp, None when 0."""
    return None if msg.header.stamp.is_zero() else msg.header.stamp.to_sec()


def serve(robot: Robot, initial: np.ndarray, rate: float = 100.0, on_complete: CompletionHook | None = None,
          node_name: str = NODE_NAME, on_ready: Callable[[], None] | None = None) -> None:
    """Start a ROS node with a :class:`TrajectoryServer` of ``robot``'s ROS names (its ``ros``) and
    run it until Ctrl-C or SIGTERM, which brake a moving arm to rest and answer its goal first
    (a second one ends the process at once), or ROS shuts down.

    The options are checked and the master asked for a running server (the node, or any
    publisher of the action's status topic) before the node registers, so a bad option or a
    second ``serve`` never disturbs the server already running.

    Raises
    ------
    InputError
        ``rate`` is not a positive number.
    ServerRunning
        A server of the same node name or action is already running.
    RosUnavailable
        No master answers within 10 s.
    """
    check_rate(rate)
    controller = TrajectoryController(robot, initial)  # the initial pose within the limits
    wait_for_master(10.0)
    require_no_server(node_name, robot.ros.action + "/status")
    stop = StopRequest()
    with stop.caught():
        rospy.init_node(node_name, disable_signals=True)  # the stop is ours: rospy's leaves the arm moving
        server = TrajectoryServer(controller, rate, on_complete)
        if on_ready:
            on_ready()
        server.spin(stop)
    rospy.signal_shutdown(f"stopped by {stop.by}" if stop.by else "ROS shut down")

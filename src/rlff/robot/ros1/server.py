"""The FollowJointTrajectory action server of a simulated arm (``rlff robot serve``).

It stands in for the thesis' controller plug-in: goals on
``/comau_controller/follow_joint_trajectory`` (and trajectories on the topic
``/comau/joint_trajectory``, the original driver's topic mode) are executed on a
:class:`rlff.robot.kinematic.KinematicArm` ticked at a fixed rate; every tick publishes
``/joint_states`` and the goal's feedback. A goal is checked before anything moves: unknown
joints are rejected with INVALID_JOINTS, anything else wrong (limits, times, sizes) with
INVALID_GOAL. A newer goal preempts the running one; a cancel stops the arm where it is.
A goal starts at its header stamp (or on receipt when the stamp is 0).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

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
from rlff.robot.description import Robot
from rlff.robot.goal import InvalidJoints, check_goal, check_joint_names
from rlff.robot.kinematic import ArmState, KinematicArm
from rlff.robot.ros1.convert import from_msg
from rlff.robot.ros1.master import wait_for_master
from rlff.trajectory.joint import JointTrajectory

ACTION_NAMESPACE = "/comau_controller/follow_joint_trajectory"
TOPIC = "/comau/joint_trajectory"
JOINT_STATES = "/joint_states"

#: Called with each completed trajectory; its text goes to the log and the result's error_string.
CompletionHook = Callable[[JointTrajectory], str]


@dataclass
class _Active:
    handle: actionlib.ServerGoalHandle | None  # None for a trajectory from the topic
    trajectory: JointTrajectory


class TrajectoryServer:
    """Executes trajectory goals on a kinematic arm of ``robot``.

    Parameters
    ----------
    robot : Robot
    initial : array of shape (J,)
        Starting joint positions (rad), within the limits.
    rate : float
        Ticks per second: state, /joint_states and feedback are computed and published this often.
    on_complete : callable, optional
        Called with every trajectory that ran to its end (e.g. a MuJoCo throw).
    """

    def __init__(self, robot: Robot, initial: np.ndarray, rate: float = 100.0,
                 on_complete: CompletionHook | None = None) -> None:
        if not rate > 0:
            raise InputError(f"rate must be positive, got {rate} Hz")
        self.robot = robot
        self.rate = rate
        self.on_complete = on_complete
        self.arm = KinematicArm(robot.joint_names, initial)
        self._active: _Active | None = None
        self._states = rospy.Publisher(JOINT_STATES, JointState, queue_size=10)
        self._server = actionlib.ActionServer(ACTION_NAMESPACE, FollowJointTrajectoryAction,
                                              goal_cb=self._on_goal, cancel_cb=self._on_cancel,
                                              auto_start=False)
        # One lock guards the arm and the active goal: the action server's own (re-entrant) lock,
        # which actionlib already holds when it calls the goal and cancel callbacks. A second lock
        # of ours would be taken in the opposite order by the tick (feedback) and deadlock.
        self._lock = self._server.lock
        self._topic = rospy.Subscriber(TOPIC, TrajectoryMsg, self._on_topic, queue_size=1)
        self._server.start()

    # -- callbacks (subscriber threads) ------------------------------------------------------
    def _on_goal(self, handle: actionlib.ServerGoalHandle) -> None:
        msg = handle.get_goal().trajectory
        try:
            check_joint_names(self.robot, list(msg.joint_names))
            traj = from_msg(msg)
            check_goal(self.robot, traj)
        except InvalidJoints as exc:
            self._reject(handle, FollowJointTrajectoryResult.INVALID_JOINTS, str(exc))
            return
        except InputError as exc:
            self._reject(handle, FollowJointTrajectoryResult.INVALID_GOAL, str(exc))
            return
        with self._lock:
            self._preempt("preempted by a newer goal")
            handle.set_accepted("executing")
            self._start(handle, traj, msg.header.stamp)
        rospy.loginfo("goal %s accepted: %d points, %.3f s", handle.get_goal_id().id, len(traj), traj.duration)

    def _on_topic(self, msg: TrajectoryMsg) -> None:
        try:
            check_joint_names(self.robot, list(msg.joint_names))
            traj = from_msg(msg)
            check_goal(self.robot, traj)
        except InputError as exc:
            rospy.logerr("trajectory on %s ignored: %s", TOPIC, exc)
            return
        with self._lock:
            self._preempt("preempted by a trajectory on the topic")
            self._start(None, traj, msg.header.stamp)
        rospy.loginfo("trajectory on %s: %d points, %.3f s", TOPIC, len(traj), traj.duration)

    def _on_cancel(self, handle: actionlib.ServerGoalHandle) -> None:
        with self._lock:
            if self._active is not None and self._active.handle is not None and \
                    self._active.handle.get_goal_id().id == handle.get_goal_id().id:
                self.arm.stop(rospy.get_time())
                self._active = None
                rospy.loginfo("goal %s cancelled: arm stopped", handle.get_goal_id().id)
            status = handle.get_goal_status().status
            if status in (GoalStatus.PENDING, GoalStatus.ACTIVE, GoalStatus.RECALLING, GoalStatus.PREEMPTING):
                handle.set_canceled(FollowJointTrajectoryResult(error_string="cancelled"), "cancelled")

    # -- helpers (called with the lock held) -------------------------------------------------
    def _reject(self, handle: actionlib.ServerGoalHandle, code: int, text: str) -> None:
        rospy.logwarn("goal %s rejected (%d): %s", handle.get_goal_id().id, code, text)
        handle.set_rejected(FollowJointTrajectoryResult(error_code=code, error_string=text), text)

    def _preempt(self, reason: str) -> None:
        if self._active is None:
            return
        if self._active.handle is not None:
            self._active.handle.set_canceled(FollowJointTrajectoryResult(error_string=reason), reason)
        self._active = None

    def _start(self, handle: actionlib.ServerGoalHandle | None, traj: JointTrajectory, stamp: rospy.Time) -> None:
        now = rospy.get_time()
        start = now if stamp.is_zero() else max(stamp.to_sec(), now)
        full = self.arm.follow(traj, start, now)
        self._active = _Active(handle, full)

    # -- the fixed-rate loop -----------------------------------------------------------------
    def tick(self) -> None:
        """Advance the arm to now, publish /joint_states and feedback, finish a completed goal."""
        now_time = rospy.Time.now()
        now = now_time.to_sec()
        with self._lock:
            state = self.arm.state(now)
            self._publish_state(now_time, state)
            active = self._active
            if active is None:
                return
            if active.handle is not None:
                self._publish_feedback(active.handle, now_time, state)
            if not self.arm.finished(now):
                return
            self._active = None
        # the completion hook (a MuJoCo throw) may take a while: not under the lock
        text = "trajectory completed"
        if self.on_complete:
            try:
                text = self.on_complete(active.trajectory)
            except Exception as exc:  # noqa: BLE001 - the arm did finish; the server must go on
                text = f"trajectory completed; the completion hook failed: {exc}"
                rospy.logerr(text)
        rospy.loginfo(text)
        if active.handle is None:
            return
        with self._lock:
            if active.handle.get_goal_status().status == GoalStatus.ACTIVE:  # not cancelled meanwhile
                active.handle.set_succeeded(FollowJointTrajectoryResult(
                    error_code=FollowJointTrajectoryResult.SUCCESSFUL, error_string=text), text)

    def _publish_state(self, stamp: rospy.Time, state: ArmState) -> None:
        msg = JointState(name=list(self.robot.joint_names), position=state.positions.tolist(),
                         velocity=state.velocities.tolist())
        msg.header.stamp = stamp
        self._states.publish(msg)

    def _publish_feedback(self, handle: actionlib.ServerGoalHandle, stamp: rospy.Time, state: ArmState) -> None:
        point = JointTrajectoryPoint(positions=state.positions.tolist(), velocities=state.velocities.tolist(),
                                     accelerations=state.accelerations.tolist(),
                                     time_from_start=rospy.Duration.from_sec(state.elapsed))
        zeros = JointTrajectoryPoint(positions=[0.0] * len(state.positions), velocities=[0.0] * len(state.positions),
                                     time_from_start=point.time_from_start)
        feedback = FollowJointTrajectoryFeedback(joint_names=list(self.robot.joint_names),
                                                 desired=point, actual=point, error=zeros)
        feedback.header.stamp = stamp
        handle.publish_feedback(feedback)

    def spin(self) -> None:
        """Tick at :attr:`rate` until ROS shuts down."""
        clock = rospy.Rate(self.rate)
        while not rospy.is_shutdown():
            self.tick()
            try:
                clock.sleep()
            except rospy.ROSInterruptException:
                break


def serve(robot: Robot, initial: np.ndarray, rate: float = 100.0, on_complete: CompletionHook | None = None,
          node_name: str = "rlff_comau_controller", on_ready: Callable[[], None] | None = None) -> None:
    """Start a ROS node with a :class:`TrajectoryServer` and run it until shut down (Ctrl-C).

    Raises :class:`rlff.robot.ros1.master.RosUnavailable` if no master answers within 10 s.
    """
    wait_for_master(10.0)
    rospy.init_node(node_name)
    server = TrajectoryServer(robot, initial, rate, on_complete)
    if on_ready:
        on_ready()
    server.spin()

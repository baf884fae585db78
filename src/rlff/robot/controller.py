"""The FollowJointTrajectory controller of the simulated arm, free of any ROS transport.

What a goal does follows ros2_control's joint_trajectory_controller (and ROS 1's before it), the
contract every FollowJointTrajectory client expects; the ROS 1 server
(:mod:`rlff.robot.ros1.server`) and the ROS 2 one are thin transports over this core:

- A goal naming joints the robot does not have is rejected with INVALID_JOINTS; one beyond the
  robot's limits (:func:`rlff.trajectory.check.check_trajectory`), or not ending at rest, with
  INVALID_GOAL (joint_trajectory_controller refuses a non-zero end velocity by default too).
- A goal whose first point is at ``time_from_start`` 0 is the motion from where the arm is. If
  that point is not the arm's state (position within :data:`START_POSITION_TOLERANCE`, velocity
  within :data:`START_VELOCITY_TOLERANCE`, the motion check's own tolerances; acceleration within
  what the joint's ``max_jerk`` changes in one controller period) the goal is refused with
  PATH_TOLERANCE_VIOLATED, the numbers and what to do: wait until the arm rests and send again
  when another goal under way moved it after the client (``rlff robot send``) read the state it
  planned from, or start the goal later than 0 s; joint_trajectory_controller answers such a
  goal with the same code when its first sample fails the state tolerance ("Aborted due to path tolerance
  violation"), here the arm does not move at all. Within the tolerance the first point is
  replaced by the arm's state, so the executed motion is continuous.
- A goal whose first point is later than 0 s is approached: the controller plans a jerk-limited
  transition (:func:`rlff.trajectory.planner.plan_transition`, ruckig) from the arm's position,
  velocity and acceleration to the first point's position, velocity and acceleration (0 where the
  goal gives none), so that a goal already accelerating at its first point goes on without a
  step in acceleration. Where the ROS controllers interpolate one spline over
  ``time_from_start`` whatever the distance (a 1 rad jump in 10 ms for a one-point goal), the
  approach here takes the time the limits need; an arm at rest waits so that the first point is
  reached at its ``time_from_start`` when the limits allow it sooner.
- A newer goal preempts the running one ("preempted by a newer goal": the old goal ends
  PREEMPTED, not succeeded); the newer one starts from the arm's state at its receipt, moving or
  not. A rejected goal leaves the running one alone.
- A cancel brakes to rest within the acceleration and jerk limits
  (:func:`rlff.trajectory.planner.plan_stop`) instead of stopping dead; the goal is reported
  cancelled once the arm stands still. Should the shortest brake overrun a position limit
  (moving fast towards it), the goal's own motion, which is checked to stop in time, runs on
  to its end instead.
- A stop of the server (:meth:`TrajectoryController.stop`: SIGTERM, Ctrl-C; FollowJointTrajectory
  has no word for it) brakes the running goal as a cancel does and ends it ABORTED once the arm
  stands still, saying that the server was stopped; from then on every goal is rejected with
  INVALID_GOAL, as joint_trajectory_controller rejects goals while it is not running. A brake
  under way (a cancel's) goes on and ends its goal cancelled.
- FollowJointTrajectory carries no release: the executed trajectory of a goal marks as its
  ``release_time`` its last point where the arm moves at zero acceleration (:func:`release_time`),
  which for a throw planned by :func:`rlff.trajectory.planner.plan_throw` is its release (the
  throw ends there at zero acceleration, the braking after it never has one), so that a
  completion hook (``serve --sim mujoco``) releases the ball where the model asked.
- Every motion the arm executes (approach and goal, or a brake) passes
  :func:`rlff.trajectory.check.check_trajectory` with the arm's pose as its start, under the
  arm's own interpolation (quintic, :mod:`rlff.robot.kinematic`), from the arm's position and
  velocity.

The controller is not thread-safe: a transport calls it under one lock of its own. Clock times
``now`` are in seconds of whatever clock the transport ticks with (ROS time).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Hashable
from dataclasses import dataclass
from enum import IntEnum

import numpy as np

from rlff.errors import InputError
from rlff.robot.description import Robot
from rlff.robot.goal import InvalidJoints, check_joint_names
from rlff.robot.kinematic import ArmState, KinematicArm
from rlff.trajectory.check import POSITION_TOLERANCE, VELOCITY_TOLERANCE, check_trajectory
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.planner import plan_stop, plan_transition

#: How far (rad) a first point at time_from_start 0 may lie from the arm's position.
START_POSITION_TOLERANCE = POSITION_TOLERANCE
#: How far (rad/s) its velocity may differ from the arm's (the arm may be moving when preempted).
START_VELOCITY_TOLERANCE = VELOCITY_TOLERANCE
#: Below this speed (rad/s) on every joint the arm counts as at rest.
AT_REST = 1e-9
#: Below this acceleration (rad/s^2) on every joint a moving point may be a throw's release.
RELEASE_ACCELERATION = 1e-6


def check_rate(rate: float) -> None:
    """:class:`InputError` unless ``rate`` (ticks per second of a transport) is positive and finite."""
    if not (math.isfinite(rate) and rate > 0):
        raise InputError(f"rate (--rate) must be a positive number of ticks per second, got {rate:g} Hz")


def release_time(traj: JointTrajectory) -> float | None:
    """Time (s) of the last point of ``traj`` moving (a speed above :data:`VELOCITY_TOLERANCE`)
    with every acceleration below :data:`RELEASE_ACCELERATION`; None if no point is."""
    moving = np.any(np.abs(traj.velocities) > VELOCITY_TOLERANCE, axis=1)
    coasting = np.all(np.abs(traj.accelerations) <= RELEASE_ACCELERATION, axis=1)
    candidates = np.flatnonzero(moving & coasting)
    return float(traj.time[candidates[-1]]) if candidates.size else None


class ResultCode(IntEnum):
    """FollowJointTrajectory's result codes (control_msgs, ROS 1 and ROS 2 alike)."""

    SUCCESSFUL = 0
    INVALID_GOAL = -1
    INVALID_JOINTS = -2
    OLD_HEADER_TIMESTAMP = -3
    PATH_TOLERANCE_VIOLATED = -4
    GOAL_TOLERANCE_VIOLATED = -5


class GoalRejected(InputError):
    """A goal the controller refuses; ``code`` is the :class:`ResultCode` to answer with."""

    def __init__(self, code: ResultCode, text: str) -> None:
        super().__init__(text)
        self.code = code


@dataclass(frozen=True)
class Outcome:
    """How a goal ended, for the transport to report.

    ``goal`` is the transport's token of the goal (None for a trajectory from the topic);
    ``status`` is ``"succeeded"``, ``"preempted"``, ``"cancelled"`` or ``"aborted"`` (braked to rest
    because the server was stopped); ``code`` the result code (SUCCESSFUL but for a success is no
    error code: FollowJointTrajectory has none for a preemption, a cancel or a stop); ``text`` says
    what happened with the numbers; ``trajectory`` is what the arm executed for this goal
    (approach included).
    """

    goal: Hashable | None
    status: str
    code: ResultCode
    text: str
    trajectory: JointTrajectory


def goal_in_rlff(robot: Robot, traj: JointTrajectory) -> JointTrajectory:
    """A goal (or topic trajectory) as it came from the ROS graph, in the controller's joint names
    and convention (``robot.ros.joints``, the robot file's ``[ros.joints]``), in rlff's: what
    :meth:`TrajectoryController.submit` takes. ``traj`` itself without a map.

    Raises
    ------
    GoalRejected
        INVALID_JOINTS: it names a joint the controller does not have (rlff's own name of a joint
        the map renames among them).
    """
    joints = robot.ros.joints
    if joints.identity:
        return traj
    known = joints.controller_names(robot.joint_names)
    unknown = [name for name in traj.joint_names if name not in known]
    if unknown:
        raise GoalRejected(ResultCode.INVALID_JOINTS, f"unknown joints {unknown} (the controller of robot "
                                                      f"{robot.name} has {', '.join(known)})")
    return joints.from_controller(traj)


def in_controller_words(robot: Robot, text: str) -> str:
    """The controller's ``text`` (a refusal, an outcome) as a client of the controller reads it.

    The controller checks and words goals in rlff's joint names and convention; a client of a
    robot file with a ``[ros.joints]`` map talks the controller's. So the map of every joint the
    text names is appended (``...; in rlff's names and convention: joint_2 as shoulder_lift_joint
    = -1.571 + joint_2``). ``text`` itself when it names none, or the map renames nothing.
    """
    joints = robot.ros.joints
    mapped = [joint for joint in robot.joint_names
              if not joints.keeps(joint) and re.search(rf"(?<!\w){re.escape(joint)}(?!\w)", text)]
    if not mapped:
        return text
    return f"{text}; in rlff's names and convention: {joints.words(mapped)}"


def state_for_controller(robot: Robot, state: ArmState) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray]:
    """The arm's ``state`` as its controller publishes it (joint states, feedback): the joint names,
    positions (J,) rad, velocities (J,) rad/s and accelerations (J,) rad/s^2 in the controller's
    names and convention (``robot.ros.joints``, the robot file's ``[ros.joints]``)."""
    joints, names = robot.ros.joints, robot.joint_names
    return (*joints.state_to_controller(names, state.positions, state.velocities),
            joints.rates_to_controller(names, state.accelerations))


#: Called with each completed trajectory (e.g. to throw it in MuJoCo); its text is the goal's result.
CompletionHook = Callable[[JointTrajectory], str]


def completion_text(hook: CompletionHook | None, outcome: Outcome) -> tuple[str, bool]:
    """The result text of a goal that succeeded, and whether ``hook`` failed.

    The hook's text when there is one; the controller's when there is none, or with the hook's
    error appended when it raised (the arm did finish: a server reports that and goes on).
    """
    if hook is None:
        return outcome.text, False
    try:
        return hook(outcome.trajectory), False
    except Exception as exc:  # noqa: BLE001 - the arm did finish; the server must go on
        return f"{outcome.text}; the completion hook failed: {exc}", True


@dataclass
class _Motion:
    goal: Hashable | None  # None: a trajectory from the topic
    trajectory: JointTrajectory  # what the arm follows, every joint, from time 0
    braking: str = ""  # after a cancel or a stop: what the brake does (the goal's outcome text)
    braked: str = "cancelled"  # the goal's status once the brake ends: cancelled, or aborted (a stop)


class TrajectoryController:
    """Goals, cancels and preemptions of FollowJointTrajectory on a kinematic arm of ``robot``.

    Parameters
    ----------
    robot : Robot
    initial : array of shape (J,)
        Starting joint positions (rad), one per joint of ``robot``.
    period : float
        Sampling period (s) of the planned approaches and brakes.
    """

    def __init__(self, robot: Robot, initial: np.ndarray, period: float = 0.002) -> None:
        if not period > 0:
            raise InputError(f"period must be positive, got {period} s")
        self.robot = robot
        self.period = period
        self.joints = [robot.joint(name) for name in robot.joint_names]
        self.arm = KinematicArm(robot.joint_names, initial)
        check_trajectory(JointTrajectory(robot.joint_names, [0.0], [self.arm.state(0.0).positions],
                                         [np.zeros(len(self.joints))]), self.joints)
        self._motion: _Motion | None = None
        self._stopped_by = ""  # once the server is stopped: by what (it takes no new goal)

    @property
    def active_goal(self) -> Hashable | None:
        """The token of the goal being executed (or braked after its cancel), if any."""
        return None if self._motion is None else self._motion.goal

    @property
    def idle(self) -> bool:
        """Whether the arm follows no goal, topic trajectory or brake (it stands still)."""
        return self._motion is None

    def state(self, now: float) -> ArmState:
        """The arm's state at clock time ``now``."""
        return self.arm.state(now)

    # -- goals -------------------------------------------------------------------------------
    def submit(self, goal: Hashable | None, traj: JointTrajectory, now: float,
               start: float | None = None) -> tuple[JointTrajectory, list[Outcome]]:
        """Accept ``traj`` as the arm's next motion, or raise :class:`GoalRejected`.

        Parameters
        ----------
        goal : hashable or None
            The transport's token for the goal (None: a trajectory from the topic).
        traj : JointTrajectory
            The goal's points, ``time`` being each point's time_from_start (s); joints it leaves
            out hold their positions (they must be at rest).
        now : float
            Clock time of the receipt (s).
        start : float, optional
            Clock time the goal's time 0 refers to (its header stamp); None or a time not later
            than ``now``: on receipt. Honoured only when the arm is at rest.

        Returns
        -------
        executed : JointTrajectory
            What the arm will follow from its state at ``now`` (every joint, time from 0).
        outcomes : list of Outcome
            The goal this one preempts, if any.
        """
        if self._stopped_by:
            raise GoalRejected(ResultCode.INVALID_GOAL, f"the server is stopping (stopped by {self._stopped_by}): "
                                                        "it takes no new goal")
        try:
            check_joint_names(self.robot, traj.joint_names)
        except InvalidJoints as exc:
            raise GoalRejected(ResultCode.INVALID_JOINTS, str(exc)) from None
        state = self.arm.state(now)
        at_rest = bool(np.all(np.abs(state.velocities) <= AT_REST))
        begin = now if start is None or start <= now or not at_rest else start
        if start is not None and start + traj.duration < now:
            raise GoalRejected(ResultCode.OLD_HEADER_TIMESTAMP,
                               f"the goal ended at {start + traj.duration:.3f} s, before its receipt at "
                               f"{now:.3f} s (header stamp {start:.3f} s + {traj.duration:.3f} s)")
        full = self._all_joints(traj, state)
        try:
            check_trajectory(full, self.joints)
        except InputError as exc:
            raise GoalRejected(ResultCode.INVALID_GOAL, str(exc)) from None
        try:
            if full.time[0] == 0.0:
                executed = self._from_here(full, state)
            else:
                executed, wait = self._approach(full, state)
                if at_rest:
                    begin += wait
            check_trajectory(executed, self.joints, start=state.positions, start_velocity=state.velocities)
        except GoalRejected:
            raise
        except InputError as exc:
            raise GoalRejected(ResultCode.INVALID_GOAL, f"from the arm's state: {exc}") from None
        executed = JointTrajectory(executed.joint_names, executed.time, executed.positions,
                                   executed.velocities, executed.accelerations, release_time(executed))
        outcomes = self._preempt(state)
        self.arm.follow(executed, begin)
        self._motion = _Motion(goal, executed)
        return executed, outcomes

    def _preempt(self, state: ArmState) -> list[Outcome]:
        """End the running goal because a newer one takes the arm over from ``state``."""
        if self._motion is None:
            return []
        if self._motion.braking:
            return self._end(self._motion.braked, f"{self._motion.braking}; the brake was taken over by a newer goal")
        return self._end("preempted", f"preempted by a newer goal after {state.elapsed:.3f} s of "
                                      f"{self._motion.trajectory.duration:.3f} s")

    def _all_joints(self, traj: JointTrajectory, state: ArmState) -> JointTrajectory:
        index = [self.robot.joint_names.index(name) for name in traj.joint_names]
        left_out = np.setdiff1d(np.arange(len(self.joints)), index)
        moving = [int(j) for j in left_out if abs(state.velocities[j]) > START_VELOCITY_TOLERANCE]
        if moving:
            j = moving[0]
            raise GoalRejected(ResultCode.INVALID_GOAL,
                               f"the goal leaves out {self.robot.joint_names[j]}, which is moving at "
                               f"{state.velocities[j]:.4g} rad/s: name every moving joint")
        positions = np.tile(state.positions, (len(traj), 1))
        velocities = np.zeros_like(positions)
        accelerations = np.zeros_like(positions)
        positions[:, index] = traj.positions
        velocities[:, index] = traj.velocities
        accelerations[:, index] = traj.accelerations
        return JointTrajectory(self.robot.joint_names, traj.time, positions, velocities, accelerations)

    def _from_here(self, traj: JointTrajectory, state: ArmState) -> JointTrajectory:
        """A goal starting at 0 s: its first point must be the arm's state, and becomes it exactly.

        Its acceleration may differ from the arm's by what the jerk limit changes in one
        controller period (``max_jerk * period``): the goal's own motion goes on from the arm's
        acceleration, and a larger step (a goal starting to accelerate where the arm is at rest)
        is a jerk no arm follows.
        """
        jerk = np.array([joint.max_jerk for joint in self.joints])
        for quantity, unit, goal, arm, tolerance in (
                ("position", "rad", traj.positions[0], state.positions, START_POSITION_TOLERANCE),
                ("velocity", "rad/s", traj.velocities[0], state.velocities, START_VELOCITY_TOLERANCE),
                ("acceleration", "rad/s^2", traj.accelerations[0], state.accelerations, jerk * self.period)):
            excess = np.abs(goal - arm) - tolerance
            j = int(np.argmax(excess))
            if excess[j] > 0:
                allowed = (f"tolerance {tolerance:g} {unit}" if np.ndim(tolerance) == 0 else
                           f"its max_jerk {jerk[j]:g} rad/s^3 changes it by {tolerance[j]:.4g} {unit} in the "
                           f"controller's {self.period:g} s period")
                raise GoalRejected(
                    ResultCode.PATH_TOLERANCE_VIOLATED,
                    f"the goal's first point (time_from_start 0) is not the arm's state: "
                    f"{self.robot.joint_names[j]} {quantity} {goal[j]:.6g} {unit}, the arm's {arm[j]:.6g} "
                    f"{unit} ({abs(goal[j] - arm[j]):.4g} {unit} apart, {allowed}){self._not_there(state)}")
        positions = traj.positions.copy()
        velocities = traj.velocities.copy()
        accelerations = traj.accelerations.copy()
        positions[0], velocities[0], accelerations[0] = state.positions, state.velocities, state.accelerations
        return JointTrajectory(traj.joint_names, traj.time, positions, velocities, accelerations)

    def _not_there(self, state: ArmState) -> str:
        """What to do of a goal from 0 s that is not the arm's ``state``, for both of its senders.

        A client that reads the arm's state and sends a goal from it (``rlff robot send``) misses
        the arm when another goal moved it in between: it waits until the arm rests and sends
        again, read from there. A goal of one's own may start later than 0 s, to be approached
        (preempting the running goal).
        """
        later = "start the goal later than 0 s to have the controller approach its first point"
        motion = self._motion
        if motion is None:
            # the arm at rest may never have moved: the goal may be planned from another pose
            return (f"; {later} (a goal planned from the arm's state read before, as rlff robot send plans it, "
                    "misses only if the arm moved since: read it again and send; otherwise the goal's first point is "
                    "not where the arm is)")
        what = ("the brake of a cancelled goal" if motion.braking else
                "another goal" if motion.goal is not None else "a trajectory from the topic")
        speed = float(np.max(np.abs(state.velocities)))
        moving = f", the arm moving at {speed:.4g} rad/s" if speed > AT_REST else ""
        return (f": {what} is under way{moving}, and moved the arm after this goal's start was read; wait until "
                "the arm rests and send the goal again from its state then (rlff robot send reads it anew), "
                f"or, to preempt it, {later}")

    def _approach(self, traj: JointTrajectory, state: ArmState) -> tuple[JointTrajectory, float]:
        """The planned approach to the first point, then the goal; and how long an arm at rest
        waits first (s) so that the first point comes at its time_from_start."""
        approach = plan_transition(state.positions, state.velocities, state.accelerations,
                                   traj.positions[0], traj.velocities[0], self.joints, period=self.period,
                                   target_acceleration=traj.accelerations[0])
        taken = approach.duration
        time = np.concatenate([approach.time, taken + traj.time[1:] - traj.time[0]])
        # the approach's last sample is the goal's first point (ruckig reaches it up to rounding)
        stack = [np.vstack([a[:-1], b]) for a, b in ((approach.positions, traj.positions),
                                                    (approach.velocities, traj.velocities),
                                                    (approach.accelerations, traj.accelerations))]
        executed = JointTrajectory(traj.joint_names, time, *stack)
        return executed, max(0.0, float(traj.time[0]) - taken)

    # -- cancel, stop and ticks --------------------------------------------------------------
    def cancel(self, goal: Hashable | None, now: float) -> list[Outcome]:
        """Brake the arm to rest if ``goal`` is the one it executes.

        Returns the outcome at once when the arm already stands still (else :meth:`update`
        reports it when the brake ends); an empty list when ``goal`` is not being executed.
        """
        motion = self._motion
        if motion is None or motion.goal != goal or motion.braking:
            return []
        return self._brake(now, "cancelled", "cancelled")

    def stop(self, now: float, by: str) -> list[Outcome]:
        """Brake the arm to rest for good: the server was stopped (``by`` says how, e.g. ``"SIGTERM"``).

        The running goal (or topic trajectory) is braked as :meth:`cancel` brakes it and ends
        ``"aborted"``, ``the server was stopped by SIGTERM after 1.000 s of 2.100 s; braked to
        rest from 2.574 rad/s in 0.336 s``: at once when the arm already stands still (returned
        here), else from :meth:`update` when the brake ends. A brake under way goes on. From now
        on :meth:`submit` rejects every goal (INVALID_GOAL). Stopping again changes nothing.
        """
        if self._stopped_by:
            return []
        self._stopped_by = by
        if self._motion is None or self._motion.braking:
            return []
        return self._brake(now, "aborted", f"the server was stopped by {by}")

    def _brake(self, now: float, status: str, why: str) -> list[Outcome]:
        """Brake the running motion to rest (``why``: what asked for it), to end it with ``status``."""
        motion = self._motion
        state = self.arm.state(now)
        when = f"{why} after {state.elapsed:.3f} s of {motion.trajectory.duration:.3f} s"
        if np.all(np.abs(state.velocities) <= AT_REST) and np.all(np.abs(state.accelerations) <= AT_REST):
            # hold the pose: the arm may be waiting at rest for the goal's start, and must not go on to it
            rest = np.zeros_like(state.positions)
            self.arm.follow(JointTrajectory(self.arm.joint_names, np.zeros(1), state.positions[None],
                                            rest[None], rest[None]), now)
            return self._end(status, f"{when}; the arm was at rest")
        peak = float(np.max(np.abs(state.velocities)))
        try:
            brake = plan_stop(state.positions, state.velocities, state.accelerations, self.joints,
                              period=self.period)
            check_trajectory(brake, self.joints, start=state.positions, start_velocity=state.velocities)
        except InputError as exc:  # no room to brake: the goal's own checked motion stops in time
            self._motion = _Motion(motion.goal, motion.trajectory, braked=status, braking=(
                f"{when} at {peak:.4g} rad/s, too fast to brake before a limit ({exc}); the goal ran to its end"))
            return []
        self.arm.follow(brake, now)
        self._motion = _Motion(motion.goal, motion.trajectory, braked=status, braking=(
            f"{when}; braked to rest from {peak:.4g} rad/s in {brake.duration:.3f} s"))
        return []

    def update(self, now: float) -> tuple[ArmState, list[Outcome]]:
        """The arm's state at ``now`` and the goal that ended by then, if any."""
        state = self.arm.state(now)
        if self._motion is None or not self.arm.finished(now):
            return state, []
        if self._motion.braking:
            return state, self._end(self._motion.braked, self._motion.braking)
        return state, self._end("succeeded", "trajectory completed")

    def _end(self, status: str, text: str) -> list[Outcome]:
        motion, self._motion = self._motion, None
        if motion is None:
            return []
        return [Outcome(motion.goal, status, ResultCode.SUCCESSFUL, text, motion.trajectory)]

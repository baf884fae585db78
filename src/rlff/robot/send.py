"""What sending a FollowJointTrajectory goal shares across transports (ROS 1, ROS 2).

The goal for the arm's state (checked from the pose /joint_states reports, delayed a little
when the arm is moving) and the report of what became of it; the transports
(:mod:`rlff.robot.ros1.client`, :mod:`rlff.robot.ros2.client`) only move messages.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from rlff.errors import InputError
from rlff.robot.controller import START_VELOCITY_TOLERANCE, ResultCode
from rlff.robot.description import Robot
from rlff.robot.goal import InvalidJoints, check_goal
from rlff.trajectory.joint import JointTrajectory

#: Seconds after its start at which a goal sent to a moving arm has its first point.
APPROACH_LEAD = 0.1
#: The result codes' names by value.
ERROR_NAMES = {code.value: code.name for code in ResultCode}


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
        return self.status == "succeeded" and self.error_code == ResultCode.SUCCESSFUL

    def to_dict(self) -> dict:
        return asdict(self) | {"succeeded": self.succeeded}


def goal_start(robot: Robot, traj: JointTrajectory, pose: np.ndarray) -> np.ndarray:
    """The arm's ``pose`` (J,) in ``robot``'s joint order, restricted to ``traj``'s joints."""
    return np.asarray(pose, dtype=float)[[robot.index(name) for name in traj.joint_names]]


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
        raise type(exc)(f"from the arm's pose on /joint_states: {exc}") from None
    if np.abs(velocity).max() <= START_VELOCITY_TOLERANCE:
        return traj
    return JointTrajectory(traj.joint_names, traj.time + APPROACH_LEAD, traj.positions, traj.velocities,
                           traj.accelerations)

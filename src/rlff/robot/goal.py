"""Checking a trajectory goal against a robot before it moves anything (the one motion check).

The FollowJointTrajectory server and client both run these checks; they split the failures the
way the action's standard error codes do: joints the robot does not have (INVALID_JOINTS) and
every other problem, limits included (INVALID_GOAL).
"""

from __future__ import annotations

import numpy as np

from rlff.errors import InputError
from rlff.robot.description import Robot
from rlff.trajectory.check import check_trajectory
from rlff.trajectory.joint import JointTrajectory


class InvalidJoints(InputError):
    """The goal names joints the robot does not have (or names one twice)."""


def check_joint_names(robot: Robot, names: list[str] | tuple[str, ...]) -> None:
    """Raise :class:`InvalidJoints` for an empty, repeated or unknown joint name."""
    if not names:
        raise InvalidJoints("the goal names no joints")
    if len(set(names)) != len(names):
        raise InvalidJoints(f"the goal names a joint twice: {list(names)}")
    unknown = [name for name in names if name not in robot.joint_names]
    if unknown:
        raise InvalidJoints(f"unknown joints {unknown} (robot {robot.name} has {', '.join(robot.joint_names)})")


def check_goal(robot: Robot, traj: JointTrajectory, start: np.ndarray | None = None) -> None:
    """Raise :class:`InvalidJoints` or :class:`InputError` unless ``traj`` is safe to execute.

    The goal passes :func:`rlff.trajectory.check.check_trajectory` against ``robot``'s limits:
    every point and the controller's quintic interpolation between points within the position,
    velocity and acceleration limits, time agreeing with positions and velocities, and the end
    at rest; with ``start`` (the arm's pose, joints in ``traj`` order), the first point within
    tolerance of it.
    """
    check_joint_names(robot, traj.joint_names)
    check_trajectory(traj, robot.joints, start=start)

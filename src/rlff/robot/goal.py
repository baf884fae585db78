"""Checking a trajectory goal against a robot before it moves anything.

The FollowJointTrajectory server and client both run these checks; they split the failures the
way the action's standard error codes do: joints the robot does not have (INVALID_JOINTS) and
every other problem, limits included (INVALID_GOAL).
"""

from __future__ import annotations

from rlff.errors import InputError
from rlff.robot.description import Robot
from rlff.trajectory.joint import JointTrajectory
from rlff.trajectory.limits import require_within_limits
from rlff.trajectory.resample import resample

#: Period (s) at which the interpolated path between points is checked against the limits.
CHECK_PERIOD = 0.002


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


def check_goal(robot: Robot, traj: JointTrajectory) -> None:
    """Raise :class:`InvalidJoints` or :class:`InputError` unless ``traj`` is safe to execute.

    Every point and the interpolated path between points (cubic Hermite, checked every
    :data:`CHECK_PERIOD` s) must lie within the position and speed limits.
    """
    check_joint_names(robot, traj.joint_names)
    joints = [robot.joint(name) for name in traj.joint_names]
    require_within_limits(traj, joints)
    if len(traj) > 1:
        try:
            require_within_limits(resample(traj, CHECK_PERIOD), joints)
        except InputError as exc:
            raise InputError(f"between the points, the interpolated path leaves the limits: {exc}") from None

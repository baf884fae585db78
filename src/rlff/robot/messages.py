"""The fields of trajectory_msgs/JointTrajectory and sensor_msgs/JointState as rlff's types.

ROS 1 and ROS 2 messages carry the same fields and differ only in how a duration is read; each
transport's ``convert`` module reads its durations and passes the fields here, so that what a
message may hold, and the errors for what it may not, are written once.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from rlff.errors import InputError
from rlff.robot.description import Robot
from rlff.trajectory.joint import JointTrajectory


def trajectory_from_points(joint_names: Sequence[str], points: Sequence[Any],
                           seconds: Callable[[Any], float]) -> JointTrajectory:
    """The trajectory of a message's joint names and points; :class:`InputError` naming the point at fault.

    Parameters
    ----------
    joint_names : sequence of str, length J
    points : sequence of JointTrajectoryPoint (ROS 1 or ROS 2)
        Each with ``positions`` (J,), ``velocities`` (J,) or empty, ``accelerations`` and
        ``time_from_start``.
    seconds : callable
        A point's ``time_from_start`` in seconds (the transport's duration type).

    Missing velocities are zeros; accelerations are taken if every point has them.
    """
    if not points:
        raise InputError("the trajectory has no points")
    joints = len(joint_names)
    for index, point in enumerate(points):
        if len(point.positions) != joints:
            raise InputError(f"point {index} has {len(point.positions)} positions for {joints} joints")
        if len(point.velocities) not in (0, joints):
            raise InputError(f"point {index} has {len(point.velocities)} velocities for {joints} joints")
    time = np.array([seconds(point.time_from_start) for point in points])
    if np.any(np.diff(time) <= 0) or time[0] < 0:
        raise InputError("time_from_start must start at 0 or later and increase strictly from point to point")
    positions = np.array([point.positions for point in points], dtype=float)
    velocities = np.array([point.velocities if len(point.velocities) else [0.0] * joints for point in points],
                          dtype=float)
    with_accelerations = all(len(point.accelerations) == joints for point in points)
    accelerations = (np.array([point.accelerations for point in points], dtype=float)
                     if with_accelerations else None)
    return JointTrajectory(tuple(joint_names), time, positions, velocities, accelerations)


def missing_joints(robot: Robot, names: Sequence[str]) -> list[str]:
    """The joints of ``robot`` a JointState message naming ``names`` (the controller's, see
    :class:`rlff.robot.joint_map.JointMap`) leaves out, in words (``shoulder_lift_joint (joint_2)``
    for a joint the robot file's ``[ros.joints]`` renames): another device's message on the same
    topic, or a robot file whose joint names are not the arm's."""
    joints = robot.ros.joints
    return [joints.label(name) for name in robot.joint_names if joints.controller_name(name) not in names]


def arm_state_of(robot: Robot, topic: str, names: Sequence[str], positions: Sequence[float],
                 velocities: Sequence[float]) -> tuple[np.ndarray, np.ndarray | None]:
    """The arm's pose and velocity (each (J,), rad and rad/s, ``robot``'s joints in order, in rlff's
    convention) from a JointState message's fields, which name every joint of ``robot`` by the
    controller's names (:func:`missing_joints` is empty) and give the controller's positions
    (converted by ``robot.ros.joints``); the velocity is None when the message has none (or not
    one per name): the arm's speed is then unknown, never taken as 0.

    Raises
    ------
    InputError
        The message (on ``topic``) has not one position per name.
    """
    names = list(names)
    if len(positions) != len(names):
        raise InputError(f"{topic} has {len(positions)} positions for {len(names)} joint names")
    return robot.ros.joints.state_from_controller(robot.joint_names, names, positions, velocities)

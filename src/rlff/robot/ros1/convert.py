"""Between :class:`rlff.trajectory.JointTrajectory` and ROS 1's trajectory_msgs/JointTrajectory."""

from __future__ import annotations

import numpy as np
import rospy
from trajectory_msgs.msg import JointTrajectory as TrajectoryMsg
from trajectory_msgs.msg import JointTrajectoryPoint

from rlff.errors import InputError
from rlff.trajectory.joint import JointTrajectory


def to_msg(traj: JointTrajectory, stamp: rospy.Time | None = None) -> TrajectoryMsg:
    """A JointTrajectory message of ``traj``; ``stamp`` is when it starts (None: on receipt)."""
    msg = TrajectoryMsg()
    msg.header.stamp = stamp if stamp is not None else rospy.Time(0)
    msg.joint_names = list(traj.joint_names)
    msg.points = [
        JointTrajectoryPoint(positions=traj.positions[i].tolist(), velocities=traj.velocities[i].tolist(),
                             accelerations=traj.accelerations[i].tolist(),
                             time_from_start=rospy.Duration.from_sec(float(traj.time[i])))
        for i in range(len(traj))
    ]
    return msg


def from_msg(msg: TrajectoryMsg) -> JointTrajectory:
    """The trajectory of a message; :class:`InputError` naming the point at fault.

    Missing velocities are zeros; accelerations are taken if every point has them.
    """
    if not msg.points:
        raise InputError("the trajectory has no points")
    joints = len(msg.joint_names)
    for index, point in enumerate(msg.points):
        if len(point.positions) != joints:
            raise InputError(f"point {index} has {len(point.positions)} positions for {joints} joints")
        if len(point.velocities) not in (0, joints):
            raise InputError(f"point {index} has {len(point.velocities)} velocities for {joints} joints")
    time = np.array([point.time_from_start.to_sec() for point in msg.points])
    if np.any(np.diff(time) <= 0) or time[0] < 0:
        raise InputError("time_from_start must start at 0 or later and increase strictly from point to point")
    positions = np.array([point.positions for point in msg.points], dtype=float)
    velocities = np.array([point.velocities or [0.0] * joints for point in msg.points], dtype=float)
    with_accelerations = all(len(point.accelerations) == joints for point in msg.points)
    accelerations = (np.array([point.accelerations for point in msg.points], dtype=float)
                     if with_accelerations else None)
    return JointTrajectory(tuple(msg.joint_names), time, positions, velocities, accelerations)

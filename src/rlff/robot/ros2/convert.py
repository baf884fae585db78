"""Between :class:`rlff.trajectory.JointTrajectory` and ROS 2's trajectory_msgs/msg/JointTrajectory."""

from __future__ import annotations

import numpy as np
from builtin_interfaces.msg import Duration, Time
from trajectory_msgs.msg import JointTrajectory as TrajectoryMsg
from trajectory_msgs.msg import JointTrajectoryPoint

from rlff.errors import InputError
from rlff.trajectory.joint import JointTrajectory


def duration(seconds: float) -> Duration:
    """A builtin_interfaces Duration of ``seconds`` (>= 0)."""
    whole = int(np.floor(seconds))
    return Duration(sec=whole, nanosec=min(999_999_999, int(round((seconds - whole) * 1e9))))


def seconds(stamp: Duration | Time) -> float:
    """Seconds of a Duration or Time message."""
    return stamp.sec + stamp.nanosec * 1e-9


def stamp(seconds_: float) -> Time:
    """A builtin_interfaces Time of ``seconds_`` since the epoch (0: "on receipt")."""
    whole = int(np.floor(seconds_))
    return Time(sec=whole, nanosec=min(999_999_999, int(round((seconds_ - whole) * 1e9))))


def to_msg(traj: JointTrajectory, start: float | None = None) -> TrajectoryMsg:
    """A JointTrajectory message of ``traj``; ``start`` (s, ROS time) is when it starts (None: on receipt)."""
    msg = TrajectoryMsg()
    msg.header.stamp = stamp(start) if start is not None else Time()
    msg.joint_names = list(traj.joint_names)
    msg.points = [
        JointTrajectoryPoint(positions=traj.positions[i].tolist(), velocities=traj.velocities[i].tolist(),
                             accelerations=traj.accelerations[i].tolist(),
                             time_from_start=duration(float(traj.time[i])))
        for i in range(len(traj))
    ]
    return msg


def start_of(msg: TrajectoryMsg) -> float | None:
    """Clock time (s) the trajectory's time 0 refers to: its header stamp, None when 0."""
    value = seconds(msg.header.stamp)
    return None if value == 0 else value


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
    time = np.array([seconds(point.time_from_start) for point in msg.points])
    if np.any(np.diff(time) <= 0) or time[0] < 0:
        raise InputError("time_from_start must start at 0 or later and increase strictly from point to point")
    positions = np.array([point.positions for point in msg.points], dtype=float)
    velocities = np.array([point.velocities if len(point.velocities) else [0.0] * joints for point in msg.points],
                          dtype=float)
    with_accelerations = all(len(point.accelerations) == joints for point in msg.points)
    accelerations = (np.array([point.accelerations for point in msg.points], dtype=float)
                     if with_accelerations else None)
    return JointTrajectory(tuple(msg.joint_names), time, positions, velocities, accelerations)

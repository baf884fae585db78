"""Between :class:`rlff.trajectory.JointTrajectory` and ROS 2's trajectory_msgs/msg/JointTrajectory."""

from __future__ import annotations

import numpy as np
from builtin_interfaces.msg import Duration, Time
from trajectory_msgs.msg import JointTrajectory as TrajectoryMsg
from trajectory_msgs.msg import JointTrajectoryPoint

from rlff.robot.messages import trajectory_from_points
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
    """The trajectory of a message (:func:`rlff.robot.messages.trajectory_from_points`)."""
    return trajectory_from_points(msg.joint_names, msg.points, seconds)

"""Between :class:`rlff.trajectory.JointTrajectory` and ROS 1's trajectory_msgs/JointTrajectory."""

from __future__ import annotations

import rospy
from trajectory_msgs.msg import JointTrajectory as TrajectoryMsg
from trajectory_msgs.msg import JointTrajectoryPoint

from rlff.robot.messages import trajectory_from_points
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
    """The trajectory of a message (:func:`rlff.robot.messages.trajectory_from_points`)."""
    return trajectory_from_points(msg.joint_names, msg.points, lambda duration: duration.to_sec())

"""Live ROS 1: the FollowJointTrajectory action server and client, and the topic mode.

These modules need Debian's ROS 1 Python packages, reachable from the venv, and the control_msgs
messages built for them: ``python -m rlff.robot.ros1.install`` does both (:mod:`rlff.robot.ros1.install`;
``scripts/setup.sh --test`` runs it for a clone).
"""

from __future__ import annotations

from rlff.robot.rospath import prefer

# Debian's ROS 1 before the ROS 2 wheels' packages of the same names: every ROS 1 module of rlff
# imports this package first
prefer(1)


def missing() -> str | None:
    """Why live ROS 1 cannot run here (a message naming the fix), or None when it can."""
    prefer(1)
    try:
        import actionlib  # noqa: F401
        import rospy  # noqa: F401
        from control_msgs.msg import FollowJointTrajectoryAction  # noqa: F401
    except ImportError as exc:
        from rlff.robot.ros1.install import apt_command

        return (f"ROS 1 is not reachable ({exc}): install Debian's ROS 1 packages ({apt_command()}), "
                "then run `python -m rlff.robot.ros1.install` with this venv's Python (it makes them "
                "importable here and builds the control_msgs messages); from a clone of rlff, "
                "scripts/setup.sh --test does both")
    return None

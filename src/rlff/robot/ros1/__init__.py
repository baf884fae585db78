"""Live ROS 1: the FollowJointTrajectory action server and client, and the topic mode.

These modules need Debian's ROS 1 Python packages and the control_msgs messages that
``scripts/setup.d/10-ros.sh`` builds (see :mod:`rlff.robot.ros1.msgs`).
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
        return (f"ROS 1 is not reachable ({exc}): install it with scripts/setup.sh --test "
                "(Debian's ROS 1 packages and the control_msgs messages)")
    return None

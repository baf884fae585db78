"""Live ROS 1: the FollowJointTrajectory action server and client, and the topic mode.

These modules need Debian's ROS 1 Python packages and the control_msgs messages that
``scripts/setup.d/10-ros.sh`` builds (see :mod:`rlff.robot.ros1.msgs`).
"""

from __future__ import annotations

import sys
from pathlib import Path


def _ros1_first() -> None:
    """Put the venv's ROS 1 folder (``.venv/ros1``) before site-packages on ``sys.path``.

    The ROS 2 wheels of the ``ros2`` extra install packages of the same names (std_msgs,
    trajectory_msgs, control_msgs, ...) into site-packages; a process that drives ROS 1 must
    import Debian's. Every ROS 1 module of rlff imports this package first.
    """
    folder = str(Path(sys.prefix) / "ros1")
    if folder in sys.path:
        sys.path.remove(folder)
        sys.path.insert(0, folder)


_ros1_first()


def missing() -> str | None:
    """Why live ROS 1 cannot run here (a message naming the fix), or None when it can."""
    try:
        import actionlib  # noqa: F401
        import rospy  # noqa: F401
        from control_msgs.msg import FollowJointTrajectoryAction  # noqa: F401
    except ImportError as exc:
        return (f"ROS 1 is not reachable ({exc}): install it with scripts/setup.sh --test "
                "(Debian's ROS 1 packages and the control_msgs messages)")
    return None

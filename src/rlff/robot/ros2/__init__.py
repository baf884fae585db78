"""Live ROS 2: the FollowJointTrajectory action server and client over rclpy.

These modules need the ``ros2`` extra (the ROS 2 Kilted wheels, ``pip install 'rlff[ros2]'``) and
the control_msgs interface that ``python -m rlff.robot.ros2.install`` builds against them (see
:mod:`rlff.robot.ros2.install`; ``scripts/setup.d/20-ros2.sh`` runs both for a clone).
"""

from __future__ import annotations

from rlff.robot.rospath import prefer

# the ROS 2 wheels before Debian's ROS 1 packages of the same names (see rlff.robot.rospath)
prefer(2)


def missing() -> str | None:
    """Why live ROS 2 cannot run here (a message naming the fix), or None when it can."""
    prefer(2)
    try:
        import control_msgs.action  # noqa: F401
        import rclpy  # noqa: F401
        from control_msgs.action import FollowJointTrajectory  # noqa: F401
    except ImportError as exc:
        return (f"ROS 2 is not reachable ({exc}): install the ROS 2 wheels with `pip install "
                "'rlff[ros2]'`, then run `python -m rlff.robot.ros2.install` with this venv's Python "
                "(it builds the control_msgs interface, with cmake, g++ and the Python headers: "
                "sudo apt install cmake g++ python3-dev); from a clone of rlff, "
                "scripts/setup.sh --test does both")
    return None

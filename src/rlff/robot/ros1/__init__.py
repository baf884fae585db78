"""Live ROS 1: the FollowJointTrajectory action server and client, and the topic mode.

These modules need Debian's ROS 1 Python packages and the control_msgs messages that
``scripts/setup.d/10-ros.sh`` builds (see :mod:`rlff.robot.ros1.msgs`).
"""

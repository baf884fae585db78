"""The robot side: robot description, human-to-robot mapping, exports, ROS 1 client and server."""

from rlff.robot.description import Geometry, Joint, Robot, available_robots, load_robot
from rlff.robot.mapping import RobotMapping

__all__ = ["Geometry", "Joint", "Robot", "RobotMapping", "available_robots", "load_robot"]

"""The robot side: robot description, URDF, human-to-robot mapping, exports, live ROS 1 and ROS 2.

The public names are imported on first use (PEP 562) so that importing a submodule such as
``rlff.robot.description`` does not load the mapping's SciPy dependencies.
"""

from __future__ import annotations

from rlff._lazy import lazy_exports

# public name -> module that defines it
_EXPORTS = {
    "Geometry": "rlff.robot.description",
    "Joint": "rlff.robot.description",
    "Robot": "rlff.robot.description",
    "available_robots": "rlff.robot.description",
    "load_robot": "rlff.robot.description",
    "ArmMapping": "rlff.robot.mapping",
    "HumanPath": "rlff.robot.mapping",
    "RobotMapping": "rlff.robot.mapping",
    "mapping_for": "rlff.robot.mapping",
}

__all__ = sorted(_EXPORTS)


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

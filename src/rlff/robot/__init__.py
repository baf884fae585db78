"""The robot side: robot description, URDF, human-to-robot mapping, exports, live ROS 1 and ROS 2.

The public names are imported on first use (PEP 562) so that importing a submodule such as
``rlff.robot.description`` does not load the mapping's SciPy dependencies.
"""

from __future__ import annotations

import importlib
from typing import Any

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


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'rlff.robot' has no attribute {name!r}")
    return getattr(importlib.import_module(module), name)


def __dir__() -> list[str]:
    """The module's own names and the public ones :func:`__getattr__` loads on first use: without
    it ``dir()``, tab completion and ``help()`` missed those (``'Model' in dir(rlff)`` was False)."""
    return sorted({*globals(), *_EXPORTS})

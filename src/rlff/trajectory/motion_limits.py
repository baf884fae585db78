"""The limits of a list of joints as arrays, for the planner and the motion check.

A joint without an acceleration or jerk limit (one built in code, since a robot file must state
them) can be neither planned nor checked: it is refused here, by name.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from rlff.errors import InputError
from rlff.trajectory.limits import JointLimits


@dataclass(frozen=True)
class MotionLimits:
    """Per-joint limits, each an array of shape (J,) in the order of ``names``.

    ``lower``/``upper`` (rad), ``velocity`` (rad/s), ``acceleration`` (rad/s^2) and ``jerk``
    (rad/s^3); the last three are magnitudes allowed in either direction.
    """

    names: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray


def motion_limits(joints: Sequence[JointLimits], names: Sequence[str] | None = None) -> MotionLimits:
    """The limits of ``joints`` (or of those called ``names``, in that order) as arrays.

    Raises
    ------
    InputError
        A name not among ``joints``, or a joint without ``max_acceleration`` or ``max_jerk``.
    """
    by_name = {joint.name: joint for joint in joints}
    names = tuple(by_name) if names is None else tuple(names)
    unknown = [name for name in names if name not in by_name]
    if unknown:
        raise InputError(f"unknown joint names {unknown} (the robot has {', '.join(by_name)})")
    ordered = [by_name[name] for name in names]
    for joint in ordered:
        for field in ("max_acceleration", "max_jerk"):
            if getattr(joint, field, None) is None:
                raise InputError(f"joint {joint.name} has no {field}: motion cannot be planned or "
                                 "checked without it (state it in the robot file)")
    return MotionLimits(names, *(np.array([float(getattr(joint, field)) for joint in ordered])
                                 for field in ("lower", "upper", "max_velocity", "max_acceleration",
                                               "max_jerk")))

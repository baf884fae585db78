"""Every export format of ``rlff robot export`` by name, and the one call that writes them."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from rlff.errors import InputError
from rlff.robot.comau import write_comau_program
from rlff.robot.export import write_csv, write_json, write_ros1_bag, write_ros2_bag
from rlff.robot.mapping import RobotMapping
from rlff.trajectory.joint import JointTrajectory

_WRITERS: dict[str, Callable[[JointTrajectory, Path], None]] = {
    "json": write_json,
    "csv": write_csv,
    "ros1-bag": write_ros1_bag,
    "ros2-bag": write_ros2_bag,
}
FORMATS = (*_WRITERS, "comau")


def export_trajectory(traj: JointTrajectory, mapping: RobotMapping, fmt: str, path: Path) -> None:
    """Write ``traj`` (a trajectory of ``mapping.robot``) to ``path`` in format ``fmt``."""
    if fmt == "comau":
        write_comau_program(traj, mapping, path)
    elif fmt in _WRITERS:
        _WRITERS[fmt](traj, path)
    else:
        raise InputError(f"unknown format {fmt!r} (known: {', '.join(FORMATS)})")

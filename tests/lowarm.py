"""An arm whose joint_2 stops at 1.3 rad, and a throw that crosses that limit at speed: what the
``--clip`` tests of every command that takes it (export, sim throw, send) refuse, since 2026-12-07:
clipped, its release is held at the limit, at rest, and the ball would not be thrown.

The throw drives joint_2 from 0 to :data:`UPPER` + :data:`BEYOND` rad at :data:`SPEED` rad/s
(the built-in Comau's own joint_2 cannot go there: its forearm would reach into the floor first).
The throw that still throws (:func:`windup_arm_files`) winds up :data:`BEYOND` rad below
joint_2's :data:`LOWER` limit of another robot file: clipped, its start is held inside the limit
and its release still moves, which the same tests measure.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import numpy as np

UPPER = 1.3  # rad, joint_2's upper limit in this robot file
LOWER = -0.5  # rad, joint_2's lower limit in the windup's robot file (below the whole-arm start pose)
BEYOND = 0.2  # rad, how far past it the throw goes, at SPEED
SPEED = 2.0  # rad/s
#: The least (rad) a joint clipped at a limit must keep from it: more than twice the simulated
#: servo's largest tracking error in a throw (2 mrad).
INSIDE = 0.005


def low_arm_files(folder: Path) -> tuple[Path, Path]:
    """The robot file and the generated path CSV of the throw past its limit, written into ``folder``."""
    # 0.05 rad apart: points 27-30 beyond the limit
    return _arm_files(folder, "upper = 2.71\n", f"upper = {UPPER}\n", np.linspace(0.0, UPPER + BEYOND, 31), "past")


def windup_arm_files(folder: Path) -> tuple[Path, Path]:
    """The robot file and the generated path CSV of the throw that winds up :data:`BEYOND` rad below
    joint_2's :data:`LOWER` limit (points 0-3) and releases at 0.8 rad, moving, written into ``folder``."""
    positions = np.linspace(LOWER - BEYOND, LOWER - BEYOND + 1.5, 31)
    return _arm_files(folder, "lower = -1.48\n", f"lower = {LOWER}\n", positions, "windup")


def _arm_files(folder: Path, line: str, limited: str, positions: np.ndarray, name: str) -> tuple[Path, Path]:
    """The built-in Comau's file with its joint_2 ``line`` made ``limited``, and the path of joint_2
    through ``positions`` (rad) at :data:`SPEED`, as ``name``.toml and ``name``.csv in ``folder``."""
    from rlff.robot import RobotMapping, load_robot

    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    assert line in text
    robot = folder / f"{name}.toml"
    robot.write_text(text.replace(line, limited, 1))
    mapping = RobotMapping.for_robot(load_robot(robot))
    angle = (positions - mapping.angle_offset) / mapping.angle_scale
    throw = folder / f"{name}.csv"
    rows = ["angle,velocity,pdf,exploration,gmr_mean"] + [
        f"{a:.17g},{SPEED / mapping.velocity_scale:.17g},1,0,0" for a in angle]
    throw.write_text("\n".join(rows) + "\n")
    return robot, throw

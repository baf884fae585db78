"""An arm whose joint_2 stops at 1.3 rad, and a throw that crosses that limit at speed: what the
``--clip`` tests of every command that takes it (export, sim throw, send) measure.

The throw drives joint_2 from 0 to :data:`UPPER` + :data:`BEYOND` rad at :data:`SPEED` rad/s
(the built-in Comau's own joint_2 cannot go there: its forearm would reach into the floor first).
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import numpy as np

UPPER = 1.3  # rad, joint_2's upper limit in this robot file
BEYOND = 0.2  # rad, how far past it the throw goes, at SPEED
SPEED = 2.0  # rad/s
#: The least (rad) a joint clipped at a limit must keep from it: more than twice the simulated
#: servo's largest tracking error in a throw (2 mrad).
INSIDE = 0.005


def low_arm_files(folder: Path) -> tuple[Path, Path]:
    """The robot file and the generated path CSV of the throw past its limit, written into ``folder``."""
    from rlff.robot import RobotMapping, load_robot

    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    robot = folder / "low.toml"
    robot.write_text(text.replace("upper = 2.71\n", f"upper = {UPPER}\n", 1))
    mapping = RobotMapping.for_robot(load_robot(robot))
    positions = np.linspace(0.0, UPPER + BEYOND, 31)  # 0.05 rad apart: points 27-30 beyond the limit
    angle = (positions - mapping.angle_offset) / mapping.angle_scale
    throw = folder / "past.csv"
    rows = ["angle,velocity,pdf,exploration,gmr_mean"] + [
        f"{a:.17g},{SPEED / mapping.velocity_scale:.17g},1,0,0" for a in angle]
    throw.write_text("\n".join(rows) + "\n")
    return robot, throw

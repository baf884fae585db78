"""The whole-arm mapping the learning tests use: the Comau's, with offsets and scales of their own.

The loop's mechanics are tested on this mapping, not on the tuning of the robot file's defaults:
joint 2 follows the shoulder, joint 3 the elbow, released near the pose of the arm's farthest
throw, so that the simulated whole-arm people's throws reach about 3 m.
"""

from __future__ import annotations

import re
from dataclasses import replace
from importlib import resources
from pathlib import Path

#: time_scale and (human joint, offset, scale) of each driven robot joint.
TIME_SCALE = 1.33
JOINTS = {"joint_2": ("shoulder", -3.077, 1.3), "joint_3": ("angle", -2.193, 0.37)}


def arm_robot():
    """The Comau Smart5 SiX (a :class:`rlff.robot.Robot`) with this mapping as its [whole_arm] table."""
    from rlff.robot import load_robot

    comau = load_robot()
    table = dict(comau.whole_arm)
    joints = {**table["joints"], **{name: {"human": human, "offset": offset, "scale": scale}
                                    for name, (human, offset, scale) in JOINTS.items()}}
    return replace(comau, whole_arm={**table, "time_scale": TIME_SCALE, "joints": joints})


def arm_robot_file(folder: Path) -> Path:
    """The Comau robot file with this mapping, written into ``folder`` (for the command line)."""
    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    for joint, (human, offset, scale) in JOINTS.items():
        text, count = re.subn(rf'(\[whole_arm\.joints\.{joint}\]\s*human = "{human}"\s*offset = )\S+(\s*scale = )\S+',
                              rf"\g<1>{offset}\g<2>{scale}", text)
        assert count == 1, f"the robot file has no [whole_arm.joints.{joint}] table to edit"
    text, count = re.subn(r"(\[whole_arm\]\s*time_scale = )\S+", rf"\g<1>{TIME_SCALE}", text)
    assert count == 1, "the robot file has no [whole_arm] time_scale to edit"
    path = folder / "whole-arm-comau.toml"
    path.write_text(text)
    return path

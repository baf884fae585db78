"""``rlff robot send --clip`` of a throw that crosses a position limit at speed, on a live arm: a
real roscore and ``rlff robot serve`` of the same robot file (tests/rosrig.py), the arm's motion
recorded on /joint_states. The throw and the arm: tests/lowarm.py's windup below a lower limit (its
throw past the upper limit, whose release clipping would hold at rest, is refused since 2026-12-07:
tests/test_robot_clip.py); export and sim throw: tests/test_robot_clip.py."""

from __future__ import annotations

import json

import pytest

from lowarm import INSIDE, LOWER, windup_arm_files
from rlff.trajectory import limits
from rosrig import Ros, ros_installed, states, stop, wait

pytestmark = [pytest.mark.ros, pytest.mark.integration, pytest.mark.slow]
_ros_installed = ros_installed


def test_send_holds_a_clipped_joint_inside_its_limit_on_the_arm(tmp_path):
    robot_file, throw = windup_arm_files(tmp_path)
    rig = Ros(tmp_path, "--robot", str(robot_file))
    try:
        recorder = rig.record(tmp_path / "states.csv")
        result = rig.rlff("robot", "send", str(throw), "--robot", str(robot_file), "--clip", "--json",
                          "--timeout", "60")
        assert result.returncode == 0, result.stderr
        outcome = json.loads(result.stdout)
        assert outcome["status"] == "succeeded"
        end = outcome["start"] + outcome["duration"]
        wait(lambda: states(tmp_path / "states.csv")[0][-1] > end + 0.5, 120, "states after the end")
        stop(recorder)
    finally:
        rig.close()
    _, positions = states(tmp_path / "states.csv")
    assert positions[:, 1].min() - LOWER > INSIDE  # it was 0: on the limit
    # held at the clip point, never below it; the arm leaves it as it starts, /joint_states catching
    # it there within a few urad
    lowest = positions[:, 1].min()
    assert LOWER + limits.CLIP_CLEARANCE - 1e-9 <= lowest <= LOWER + limits.CLIP_CLEARANCE + 1e-5

"""Live ROS 1 with a whole-arm throw: ``rlff robot send --joints joint_2,joint_3 --bearing`` to a
real ``rlff robot serve`` on its own roscore; the arm's /joint_states are recorded by Debian's
``rostopic echo``. The executed motion must follow the coordinated plan of every joint within
the tolerance of tests/test_ros1_live.py.

Without Debian's ROS 1 packages these tests skip locally and FAIL in CI (CI=true).
"""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from rlff.robot.plan import load_for_robot
from rosrig import ROBOT, execution_error, ros_fixture, ros_installed, states, stop, wait
from wholearm import human_throw

pytestmark = [pytest.mark.ros, pytest.mark.integration, pytest.mark.slow]
_ros_installed = ros_installed
ros = pytest.fixture(scope="module")(ros_fixture)

EXECUTION_TOLERANCE = 1e-3  # rad, as tests/test_ros1_live.py
PERIOD = 0.01  # s, robot send's default
JOINTS = ("joint_2", "joint_3")


def test_a_two_joint_throw_at_a_bearing_is_executed_as_planned(ros, tmp_path):
    path = tmp_path / "throw.csv"
    pd.DataFrame(human_throw(7.7, wrist=False)).to_csv(path, index=False)
    pose = ros.pose(tmp_path)
    sent = load_for_robot(path, ROBOT, PERIOD, start=pose, joints=JOINTS, bearing=30.0)[1].trajectory
    recorder = ros.record(tmp_path / "states.csv")
    result = ros.rlff("robot", "send", str(path), "--joints", ",".join(JOINTS), "--bearing", "30", "--json",
                      "--timeout", "60")
    assert result.returncode == 0, result.stderr
    outcome = json.loads(result.stdout)
    assert outcome["status"] == "succeeded" and outcome["duration"] == pytest.approx(sent.duration)
    wait(lambda: states(tmp_path / "states.csv")[0][-1] > outcome["start"] + sent.duration + 0.5, 120,
         "states after the end")
    stop(recorder)
    stamps, positions = states(tmp_path / "states.csv")
    delay, worst = execution_error(stamps, positions, sent, outcome["start"])
    assert worst < EXECUTION_TOLERANCE, (delay, worst)
    # every driven joint swung, joint_1 turned to the bearing, and all came to rest where planned
    moving = (stamps >= outcome["start"] + delay) & (stamps <= outcome["start"] + delay + sent.duration)
    travel = np.ptp(positions[moving], axis=0)
    for joint in (*JOINTS, "joint_1"):
        assert travel[ROBOT.index(joint)] > 0.3, (joint, travel)
    np.testing.assert_allclose(positions[-1], sent.positions[-1], atol=1e-9)
    assert positions[-1][ROBOT.index("joint_1")] == pytest.approx(np.radians(30.0))

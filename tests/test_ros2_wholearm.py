"""Live ROS 2 with a whole-arm throw: ``rlff robot send --ros 2 --joints joint_2,joint_3 --bearing``
to a real ``rlff robot serve --ros 2``; the test's own rclpy node records /joint_states. The
executed motion must follow the coordinated plan of every joint within the tolerance of
tests/test_ros1_live.py.

Without the ROS 2 wheels these tests skip locally and FAIL in CI (CI=true).
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from rlff.robot import load_robot
from rlff.robot.plan import load_for_robot
from ros2rig import RosNode, Server, free_domain, require_ros2, ros2_env, wait_until
from rosrig import execution_error
from wholearm import human_throw

pytestmark = [pytest.mark.ros2, pytest.mark.integration, pytest.mark.slow]

EXECUTION_TOLERANCE = 1e-3  # rad, as tests/test_ros1_live.py
PERIOD = 0.01  # s, robot send's default
JOINTS = ("joint_2", "joint_3")


@pytest.fixture(scope="module")
def rig(tmp_path_factory):
    require_ros2()
    domain = free_domain()
    folder = tmp_path_factory.mktemp("ros2")
    env = ros2_env(domain, folder)
    server = Server(env, folder / "serve.log")
    node = RosNode(domain)
    yield env, node
    node.close()
    server.close()


def test_a_two_joint_throw_at_a_bearing_is_executed_as_planned_over_ros2(rig, tmp_path):
    env, node = rig
    robot = load_robot()
    path = tmp_path / "throw.csv"
    pd.DataFrame(human_throw(7.7, wrist=False)).to_csv(path, index=False)
    _, pose = node.latest()
    sent = load_for_robot(path, robot, PERIOD, start=pose, joints=JOINTS, bearing=30.0)[1].trajectory
    result = subprocess.run([sys.executable, "-m", "rlff", "robot", "send", str(path), "--ros", "2", "--joints",
                             ",".join(JOINTS), "--bearing", "30", "--json", "--timeout", "60"],
                            env=env, capture_output=True, text=True, timeout=180)
    assert result.returncode == 0, result.stderr
    outcome = json.loads(result.stdout)
    assert outcome["status"] == "succeeded" and outcome["duration"] == pytest.approx(sent.duration)
    end = outcome["start"] + sent.duration
    wait_until(lambda: node.states()[0].size and node.states()[0][-1] > end + 0.5, 120, "states after the end")
    stamps, positions = node.states(since=outcome["start"] - 1.0)
    delay, worst = execution_error(stamps, positions, sent, outcome["start"])
    assert worst < EXECUTION_TOLERANCE, (delay, worst)
    moving = (stamps >= outcome["start"] + delay) & (stamps <= end + delay)
    travel = np.ptp(positions[moving], axis=0)
    for joint in (*JOINTS, "joint_1"):
        assert travel[robot.index(joint)] > 0.3, (joint, travel)
    np.testing.assert_allclose(positions[-1], sent.positions[-1], atol=1e-9)

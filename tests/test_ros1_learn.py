"""Learning through a ROS 1 robot: ``rlff learn --executor ros1`` against ``rlff robot serve``.

A real roscore and server (tests/rosrig.py); the "vision system" is Debian's ``rostopic pub`` of a
geometry_msgs/PointStamped on /rlff/landing each time the server reports a completed throw.
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from armrobot import arm_robot_file
from rosrig import ros_fixture, ros_installed, wait

pytestmark = [pytest.mark.ros, pytest.mark.integration, pytest.mark.slow]
_ros_installed = ros_installed
ros = pytest.fixture(scope="module")(ros_fixture)

BASKET = 2.0  # m
LANDINGS = [1.5, 2.05]  # a miss 0.5 m short, then a hit (within the basket's opening)


def report_landings(ros, learner: subprocess.Popen, landings: list[float], what: str) -> None:
    """The vision system: after each throw the server completes, publish its landing (m) on
    /rlff/landing with rostopic, while the learner keeps running."""
    before = ros.log().count("trajectory completed")
    for number, landing in enumerate(landings, start=1):
        wait(lambda n=number: ros.log().count("trajectory completed") >= before + n or learner.poll() is not None,
             300, f"{what} {number} on the arm")
        assert learner.poll() is None, learner.communicate()[1]
        subprocess.run(["rostopic", "pub", "-1", "/rlff/landing", "geometry_msgs/PointStamped",
                        f"{{header: {{stamp: now}}, point: {{x: {landing}}}}}"], env=ros.env, check=True,
                       capture_output=True, timeout=60)


def test_attempts_run_on_the_arm_with_landings_from_rostopic(ros, tmp_path):
    demos = tmp_path / "demos.csv"
    made = ros.rlff("data", "synth", "throws", "-o", str(demos), "--seed", "4", timeout=300)
    assert made.returncode == 0, made.stderr
    log = tmp_path / "attempts.jsonl"
    learner = subprocess.Popen([sys.executable, "-m", "rlff", "learn", str(demos), "--preset", "thesis", "--basket",
                                str(BASKET), "--executor", "ros1", "--outcome", "topic", "--budget", "4", "--log",
                                str(log), "--json"], env=ros.env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True)
    report_landings(ros, learner, LANDINGS, "throw")
    out, err = learner.communicate(timeout=300)
    assert learner.returncode == 0, err
    result = json.loads(out)
    assert (result["attempts"], result["hit"]) == (2, True)
    assert result["landings"] == pytest.approx(LANDINGS)
    lines = [json.loads(line) for line in log.read_text().splitlines()]
    assert lines[0]["run"]["executor"] == "ros1"
    # a hit keeps its measured miss (it was logged as 0.0: --until centred took every hit as centred)
    assert [a["miss"] for a in lines[1:]] == pytest.approx([LANDINGS[0] - BASKET, LANDINGS[1] - BASKET])


def test_whole_arm_attempts_run_on_the_arm_at_a_bearing(ros, tmp_path):
    demos = tmp_path / "arm-demos.csv"
    made = ros.rlff("data", "synth", "throws", "--whole-arm", "--subjects", "3", "--distances", "1,1.5,2",
                    "--bearings", "0,60", "--heights", "0.3", "-o", str(demos), "--seed", "4", timeout=300)
    assert made.returncode == 0, made.stderr
    robot = arm_robot_file(tmp_path)
    log = tmp_path / "arm-attempts.jsonl"
    learner = subprocess.Popen([sys.executable, "-m", "rlff", "learn", str(demos), "--preset", "thesis", "--basket",
                                "1.5", "--joints", "joint_2,joint_3", "--bearing", "30", "--robot", str(robot),
                                "--executor", "ros1", "--outcome", "topic", "--budget", "3", "--log", str(log),
                                "--json"], env=ros.env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    report_landings(ros, learner, [1.1, 1.52], "whole-arm throw")  # along the bearing line: short, then a hit
    out, err = learner.communicate(timeout=300)
    assert learner.returncode == 0, err
    result = json.loads(out)
    assert (result["attempts"], result["hit"]) == (2, True)
    lines = [json.loads(line) for line in log.read_text().splitlines()]
    assert lines[0]["run"]["joints"] == ["joint_3", "joint_2"] and lines[0]["run"]["basket"]["bearing"] == 30.0
    for attempt in lines[1:]:  # the executed shoulder rode along with the elbow
        assert len(attempt["arm"]["shoulder"]) == len(attempt["angle"]) and max(attempt["arm"]["shoulder"]) > min(
            attempt["arm"]["shoulder"]) + 0.05
    pose = ros.pose(tmp_path)  # the arm came to rest facing the basket
    assert pose[0] == pytest.approx(np.radians(30.0), abs=1e-6)

"""Live ROS 1 safety: what issue 12 found the server doing, tried again on a real roscore.

A real roscore (own free port), ``rlff robot serve``, raw FollowJointTrajectory goals from a
separate rospy process (tests/ros1_goal.py, bypassing rlff's client and its checks) and
``rlff robot send``; /joint_states recorded by ``rostopic echo``. Every goal is refused with the
numbers, or executed without a jump: the recorded motion's divided differences (see
:func:`rosrig.peaks`) stay within the speed and acceleration limits, with no allowance but the
motion check's relative slack for rounding (LIMIT_SLACK).
"""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from rlff.trajectory.check import LIMIT_SLACK
from rosrig import (
    AMAX,
    DRIVEN,
    ROBOT,
    VMAX,
    peaks,
    ros_fixture,
    ros_installed,
    states,
    stop,
    throw_csv,
    wait,
)

pytestmark = [pytest.mark.ros, pytest.mark.integration, pytest.mark.slow]
_ros_installed = ros_installed
ros = pytest.fixture(scope="module")(ros_fixture)
NAMES = list(ROBOT.joint_names)


def _within_limits(path) -> tuple[np.ndarray, np.ndarray]:
    stamps, positions = states(path)
    velocity, acceleration = peaks(stamps, positions)
    assert np.all(velocity <= VMAX * (1 + LIMIT_SLACK)), (velocity, VMAX)
    assert np.all(acceleration <= AMAX * (1 + LIMIT_SLACK)), (acceleration, AMAX)
    return velocity, acceleration


def _spec(time_from_start, positions) -> dict:
    return {"joint_names": NAMES, "time": list(time_from_start),
            "positions": [list(map(float, p)) for p in positions]}


def test_a_goal_starting_at_zero_away_from_the_arm_is_rejected_and_nothing_moves(ros, tmp_path):
    here = ros.pose(tmp_path)
    away = here.copy()
    away[DRIVEN] -= 0.613
    recorder = ros.record(tmp_path / "states.csv")
    result = ros.goal(tmp_path, _spec([0.0, 1.0], [away, away]))
    time.sleep(0.5)
    stop(recorder)
    assert result["status"] == "rejected" and result["error_code"] == -4  # PATH_TOLERANCE_VIOLATED
    assert (f"joint_2 position {away[DRIVEN]:.6g} rad, the arm's {here[DRIVEN]:.6g} rad (0.613 rad apart, "
            "tolerance 0.001 rad)") in result["error_string"]
    _, positions = states(tmp_path / "states.csv")
    assert np.ptp(positions, axis=0).max() == 0.0


def test_a_one_point_goal_1_rad_away_is_approached_not_jumped(ros, tmp_path):
    here = ros.pose(tmp_path)
    target = here.copy()
    target[DRIVEN] += 1.0 if here[DRIVEN] < 1.0 else -1.0
    recorder = ros.record(tmp_path / "states.csv")
    result = ros.goal(tmp_path, _spec([0.01], [target]))
    time.sleep(0.3)
    stop(recorder)
    assert result["status"] == "succeeded" and result["error_code"] == 0
    velocity, _ = _within_limits(tmp_path / "states.csv")
    assert velocity[DRIVEN] > 0.9 * VMAX[DRIVEN]  # it did move, fast, not in one tick
    stamps, positions = states(tmp_path / "states.csv")
    np.testing.assert_allclose(positions[-1], target, atol=1e-9)
    moving = np.flatnonzero(np.abs(np.diff(positions[:, DRIVEN])) > 0)
    assert stamps[moving[-1] + 1] - stamps[moving[0]] > 1.0 / VMAX[DRIVEN]  # at least 1 rad at full speed


def test_cancel_brakes_within_the_limits(ros, tmp_path):
    here = ros.pose(tmp_path)
    far = here.copy()
    far[DRIVEN] = 2.0 if here[DRIVEN] < 0.5 else -1.0
    recorder = ros.record(tmp_path / "states.csv")
    result = ros.goal(tmp_path, _spec([0.01], [far]), "--cancel-after", "0.5")
    time.sleep(0.5)
    stop(recorder)
    assert result["status"] == "preempted"  # actionlib's state of a goal cancelled while running
    assert "braked to rest from" in result["error_string"]
    speed = float(result["error_string"].split("braked to rest from ")[1].split(" rad/s")[0])
    assert speed > 1.0  # it was moving fast, and did not stop dead
    _within_limits(tmp_path / "states.csv")
    stamps, positions = states(tmp_path / "states.csv")
    after = stamps > stamps[-1] - 0.3
    assert np.ptp(positions[after], axis=0).max() == 0.0  # at rest, short of the goal
    assert abs(positions[-1, DRIVEN] - far[DRIVEN]) > 0.2


def test_a_preempted_throw_hands_over_without_a_step(ros, tmp_path):
    slow = throw_csv(tmp_path, "slow.csv", -1.2, 2.4, 0.6)
    quick = throw_csv(tmp_path, "quick.csv", 0.3, -0.3, 1.0)
    recorder = ros.record(tmp_path / "states.csv")
    first = subprocess.Popen([sys.executable, "-m", "rlff", "robot", "send", str(slow), "--json"], env=ros.env,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def fast() -> bool:
        stamps, positions = states(tmp_path / "states.csv")
        return len(stamps) > 3 and np.abs(np.diff(positions[-3:, DRIVEN])).max() / 0.01 > 1.0

    wait(fast, 120, "the first throw to move the arm fast")
    second = ros.rlff("robot", "send", str(quick), "--json", "--timeout", "60")
    out, _ = first.communicate(timeout=60)
    time.sleep(0.3)
    stop(recorder)
    assert second.returncode == 0, second.stderr
    assert "the arm is moving" in second.stderr
    assert json.loads(second.stdout)["status"] == "succeeded"
    preempted = json.loads(out)
    assert first.returncode == 1
    assert (preempted["status"], preempted["error_code"], preempted["error_name"]) == ("preempted", 0, None)
    assert preempted["error_string"].startswith("preempted by a newer goal after")
    _within_limits(tmp_path / "states.csv")


def test_serve_checks_its_options_and_never_replaces_a_running_server(ros, tmp_path):
    for args, message in ((("--rate", "0"), "--rate must be a positive number of ticks per second, got 0 Hz"),
                          ((), "a node /rlff_comau_controller is already running")):
        result = ros.rlff("robot", "serve", *args, timeout=60)
        assert result.returncode == 2, result.stderr
        assert result.stderr.count("\n") == 1 and message in result.stderr
    # the first server still serves: its node answers and a goal still moves the arm
    code, _, uri = ros.master.lookupNode("/test", "/rlff_comau_controller")
    assert code == 1 and uri
    here = ros.pose(tmp_path)
    target = here.copy()
    target[DRIVEN] += 0.1
    assert ros.goal(tmp_path, _spec([0.5], [target]))["status"] == "succeeded"


def test_ctrl_c_of_send_brakes_and_the_client_waits_for_rest(ros, tmp_path):
    slow = throw_csv(tmp_path, "slow.csv", -1.2, 2.4, 0.6)
    recorder = ros.record(tmp_path / "states.csv")
    sender = subprocess.Popen([sys.executable, "-m", "rlff", "robot", "send", str(slow)], env=ros.env,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def fast() -> bool:
        stamps, positions = states(tmp_path / "states.csv")
        return len(stamps) > 3 and np.abs(np.diff(positions[-3:, DRIVEN])).max() / 0.01 > 1.0

    wait(fast, 120, "the throw to move the arm fast")
    sender.send_signal(signal.SIGINT)
    _, err = sender.communicate(timeout=60)
    exited = time.time()
    wait(lambda: states(tmp_path / "states.csv")[0][-1] > exited + 0.5, 60, "states after the exit")
    stop(recorder)
    assert sender.returncode == 130 and "interrupted: goal cancelled" in err
    _within_limits(tmp_path / "states.csv")
    stamps, positions = states(tmp_path / "states.csv")
    assert np.ptp(positions[stamps > exited], axis=0).max() == 0.0  # at rest once the client is gone
    assert "braked to rest from" in ros.log()

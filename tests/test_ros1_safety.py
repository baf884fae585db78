"""Live ROS 1 safety: what issue 12 found the server doing, tried again on a real roscore.

A real roscore (own free port), ``rlff robot serve``, raw FollowJointTrajectory goals from a
separate rospy process (tests/ros1_goal.py, bypassing rlff's client and its checks) and
``rlff robot send``; /joint_states recorded by ``rostopic echo``. Every goal is refused with the
numbers, or executed without a jump: the recorded positions stay within the position limits and
their divided differences (see :func:`rosrig.peaks`) within the speed and acceleration limits,
with no allowance but the motion check's relative slack for rounding (LIMIT_SLACK).
"""

from __future__ import annotations

import json
import re
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from rlff.robot.sendfile import load_for_sending
from rlff.trajectory.check import LIMIT_SLACK
from rosrig import (
    AMAX,
    DRIVEN,
    ROBOT,
    VMAX,
    human_csv,
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
    lower, upper = (np.array([getattr(joint, side) for joint in ROBOT.joints]) for side in ("lower", "upper"))
    assert np.all((positions >= lower) & (positions <= upper))
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


def test_a_moving_arm_is_refused_and_a_raw_goal_preempts_without_a_step(ros, tmp_path):
    slow = throw_csv(tmp_path, "slow.csv", -1.2, 1.5, 0.0)  # several seconds: still running when preempted
    quick = throw_csv(tmp_path, "quick.csv", 0.3, -0.3, 1.0)
    recorder = ros.record(tmp_path / "states.csv")
    first = subprocess.Popen([sys.executable, "-m", "rlff", "robot", "send", str(slow), "--json"], env=ros.env,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def moving() -> bool:
        stamps, positions = states(tmp_path / "states.csv")
        return len(stamps) > 3 and np.abs(np.diff(positions[-3:, DRIVEN])).max() / 0.01 > 0.2

    wait(moving, 120, "the first throw to move the arm")
    # rlff plans from rest: a throw for a moving arm is not sent (a controller splicing it in from
    # the moving state, as ros_control does, would take the time the goal gives, not the limits')
    second = ros.rlff("robot", "send", str(quick), "--json", "--timeout", "60")
    assert second.returncode == 1, second.stderr
    assert second.stderr.strip().splitlines() == [second.stderr.strip()]
    assert second.stderr.startswith("rlff: error: the arm is moving (") and "rad/s on joint_2): wait until it rests" \
        in second.stderr
    # a goal of another client, its first point 1 s on, preempts: the server approaches it from the moving arm
    stamps, positions = states(tmp_path / "states.csv")
    raw = ros.goal(tmp_path, _spec([1.0], [positions[-1]]))
    out, _ = first.communicate(timeout=60)
    time.sleep(0.3)
    stop(recorder)
    assert raw["status"] == "succeeded", raw
    preempted = json.loads(out)
    assert first.returncode == 1
    assert (preempted["status"], preempted["error_code"], preempted["error_name"]) == ("preempted", 0, None)
    assert preempted["error_string"].startswith("preempted by a newer goal after")
    _within_limits(tmp_path / "states.csv")


def test_serve_checks_its_options_and_never_replaces_a_running_server(ros, tmp_path):
    elsewhere = dict(ros.env, ROS_NAMESPACE="/other")  # another node name, the same action
    for args, env, message in (
            (("--rate", "0"), ros.env, "rate (--rate) must be a positive number of ticks per second, got 0 Hz"),
            (("--rate", "nan"), ros.env, "rate (--rate) must be a positive number of ticks per second, got nan Hz"),
            ((), ros.env, "a node /rlff_comau_controller is already running"),
            ((), elsewhere, "/rlff_comau_controller already serves the action of "
                            "/comau_controller/follow_joint_trajectory/status")):
        result = ros.rlff("robot", "serve", *args, timeout=60, env=env)
        assert result.returncode == 2, result.stderr
        assert result.stderr.count("\n") == 1 and message in result.stderr
    # the first server still serves: its node answers and a goal still moves the arm
    code, _, uri = ros.master.lookupNode("/test", "/rlff_comau_controller")
    assert code == 1 and uri
    here = ros.pose(tmp_path)
    target = here.copy()
    target[DRIVEN] += 0.1
    assert ros.goal(tmp_path, _spec([0.5], [target]))["status"] == "succeeded"


@pytest.mark.parametrize(("stop_signal", "code", "word"), [(signal.SIGINT, 130, "interrupted"),
                                                           (signal.SIGTERM, 143, "terminated")],
                         ids=["ctrl-c", "sigterm"])
def test_stopping_send_brakes_and_the_client_waits_for_rest(ros, tmp_path, stop_signal, code, word):
    # Ctrl-C, or the SIGTERM of a supervisor (kill, systemd, a launch file): the goal is cancelled
    slow = throw_csv(tmp_path, "slow.csv", -1.2, 1.5, 0.0)  # several seconds: still running at the Ctrl-C
    recorder = ros.record(tmp_path / "states.csv")
    # Ctrl-C as a terminal gives it: a suite started in the background of a shell (`.ci/run &`)
    # inherits SIGINT ignored, and Python then never turns it into KeyboardInterrupt
    sender = subprocess.Popen([sys.executable, "-m", "rlff", "robot", "send", str(slow)], env=ros.env,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                              preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))

    def moving() -> bool:
        stamps, positions = states(tmp_path / "states.csv")
        return len(stamps) > 3 and np.abs(np.diff(positions[-3:, DRIVEN])).max() / 0.01 > 0.2

    wait(moving, 120, "the throw to move the arm")
    sender.send_signal(stop_signal)
    _, err = sender.communicate(timeout=60)
    exited = time.time()
    wait(lambda: states(tmp_path / "states.csv")[0][-1] > exited + 0.5, 60, "states after the exit")
    stop(recorder)
    assert sender.returncode == code and err.strip().endswith(f"rlff: goal cancelled\nrlff: {word}"), err
    _within_limits(tmp_path / "states.csv")
    stamps, positions = states(tmp_path / "states.csv")
    assert np.ptp(positions[stamps > exited], axis=0).max() == 0.0  # at rest once the client is gone
    assert "braked to rest from" in ros.log().split("cancelled: braking to rest")[-1]


def test_goals_of_other_joints_or_beyond_the_limits_are_rejected_with_their_codes(ros, tmp_path):
    here = ros.pose(tmp_path)
    beyond = here.copy()
    beyond[DRIVEN] = 3.0
    unknown = {"joint_names": ["axis_1"], "time": [1.0], "positions": [[0.0]]}
    rejected = ros.goal(tmp_path, unknown)
    assert (rejected["status"], rejected["error_code"]) == ("rejected", -2)  # INVALID_JOINTS
    assert "unknown joints ['axis_1']" in rejected["error_string"]
    rejected = ros.goal(tmp_path, _spec([1.0], [beyond]))
    assert (rejected["status"], rejected["error_code"]) == ("rejected", -1)  # INVALID_GOAL
    assert "joint_2 position 3 rad beyond the limit 2.71 rad" in rejected["error_string"]
    np.testing.assert_array_equal(ros.pose(tmp_path), here)


def test_a_throw_sent_by_rlff_stays_within_the_limits_and_ends_at_rest(ros, tmp_path):
    # the model asks for a release at 0.6 rad and 2.6 rad/s, 93 % of joint_2's speed limit (braking
    # from a release at 1.6 rad took the arm into the floor)
    path = human_csv(tmp_path / "throw.csv", np.linspace(-0.8, 0.6, 30), np.linspace(0.5, 2.6, 30))
    recorder = ros.record(tmp_path / "states.csv")
    result = ros.rlff("robot", "send", str(path), "--json", "--timeout", "60")
    time.sleep(0.3)
    stop(recorder)
    assert result.returncode == 0, result.stderr
    velocity, acceleration = _within_limits(tmp_path / "states.csv")
    assert velocity[DRIVEN] > 2.5 and acceleration[DRIVEN] > 0.9 * AMAX[DRIVEN]  # a real throw, at the limits
    stamps, positions = states(tmp_path / "states.csv")
    assert np.ptp(positions[stamps > stamps[-1] - 0.2], axis=0).max() == 0.0


def test_an_exported_trajectory_is_sent_only_from_its_start(ros, tmp_path):
    path = throw_csv(tmp_path, "throw.csv", 0.2, -0.6, 1.0)
    assert ros.rlff("robot", "export", str(path), "-f", "json", "-o", str(tmp_path / "throw.json")).returncode == 0
    exported = json.loads((tmp_path / "throw.json").read_text())
    first = np.array(exported["positions"][0])
    here = ros.pose(tmp_path)
    if abs(here[DRIVEN] - first[DRIVEN]) < 0.1:  # make sure the arm is elsewhere
        elsewhere = here.copy()
        elsewhere[DRIVEN] += 0.5
        assert ros.goal(tmp_path, _spec([0.5], [elsewhere]))["status"] == "succeeded"
        here = elsewhere
    refused = ros.rlff("robot", "send", str(tmp_path / "throw.json"), "--timeout", "30")
    assert refused.returncode == 2 and refused.stderr.count("\n") == 1
    assert (f"throw.json: point 0 (t = 0.000000 s): joint_2 position {first[DRIVEN]:.6g} rad is not where the arm "
            f"is ({here[DRIVEN]:.6g} rad") in refused.stderr
    assert "send the generated trajectory CSV" in refused.stderr
    assert ros.goal(tmp_path, _spec([0.5], [first]))["status"] == "succeeded"  # to its start
    sent = ros.rlff("robot", "send", str(tmp_path / "throw.json"), "--json", "--timeout", "30")
    assert sent.returncode == 0, sent.stderr
    np.testing.assert_allclose(ros.pose(tmp_path), exported["positions"][-1], atol=1e-9)


def test_rosbag_play_of_an_export_obeys_the_goal_rules(ros, tmp_path):
    path = throw_csv(tmp_path, "throw.csv", 0.4, -0.4, 1.0)
    bag = tmp_path / "throw.bag"
    assert ros.rlff("robot", "export", str(path), "-f", "ros1-bag", "-o", str(bag)).returncode == 0
    exported = load_for_sending(bag, ROBOT, None)[1].trajectory
    here = ros.pose(tmp_path)
    away = here.copy()
    away[DRIVEN] = exported.positions[0, DRIVEN] + 0.7  # the arm 0.7 rad from the bag's start
    assert ros.goal(tmp_path, _spec([0.5], [away]))["status"] == "succeeded"

    def play() -> None:
        subprocess.run(["rosbag", "play", "--quiet", "--wait-for-subscribers", str(bag)], env=ros.env,
                       check=True, timeout=120, capture_output=True)

    recorder = ros.record(tmp_path / "refused.csv")
    logged = len(ros.log())
    play()
    wait(lambda: "refused" in ros.log()[logged:], 30, "the server to refuse the bag")
    time.sleep(0.3)
    stop(recorder)
    refusal = ros.log()[logged:]
    assert "trajectory on /comau/joint_trajectory refused (PATH_TOLERANCE_VIOLATED)" in refusal
    assert "(0.7 rad apart, tolerance 0.001 rad)" in refusal
    _, positions = states(tmp_path / "refused.csv")
    assert np.ptp(positions, axis=0).max() == 0.0  # no jump, no motion

    assert ros.goal(tmp_path, _spec([0.5], [exported.positions[0]]))["status"] == "succeeded"
    recorder = ros.record(tmp_path / "played.csv")
    play()

    def arrived() -> bool:
        return np.abs(states(tmp_path / "played.csv")[1][-1] - exported.positions[-1]).max() < 1e-9

    wait(arrived, 60, "the bag's trajectory to be executed")
    stop(recorder)
    _within_limits(tmp_path / "played.csv")


def test_a_second_publisher_of_the_arm_s_joints_is_refused_naming_the_jump(ros, tmp_path):
    # a simulator left running beside the arm's driver (here rlff robot serve, 100 Hz): Debian's
    # `rostopic pub` at 20 Hz, stamped now, 0.3 rad elsewhere on joint_2
    here = ros.pose(tmp_path)
    elsewhere = here.copy()
    elsewhere[DRIVEN] += 0.3 if here[DRIVEN] < 2.0 else -0.3
    message = (f"{{header: {{stamp: now}}, name: [{', '.join(NAMES)}], position: {elsewhere.tolist()}, "
               "velocity: [0, 0, 0, 0, 0, 0]}")
    path = throw_csv(tmp_path, "throw.csv", -0.5, 0.5, 0.5)
    logged = len(ros.log())
    simulator = subprocess.Popen(["rostopic", "pub", "-s", "-r", "20", "/joint_states", "sensor_msgs/JointState",
                                  message], env=ros.env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        recorder = ros.record(tmp_path / "both.csv")  # both publish now
        wait(lambda: np.abs(states(tmp_path / "both.csv")[1][:, DRIVEN] - elsewhere[DRIVEN]).min() < 1e-9, 60,
             "the second publisher's states")
        stop(recorder)
        refused = ros.rlff("robot", "send", str(path), "--timeout", "30")
    finally:
        stop(simulator)
    assert refused.returncode == 1, refused.stderr
    line = refused.stderr.strip()
    assert line.count("\n") == 0, refused.stderr
    assert line.startswith("rlff: error: two fresh states on /joint_states disagree: joint_2 at "), line
    jumped = sorted(f"{value:.6g}" for value in (here[DRIVEN], elsewhere[DRIVEN]))
    assert sorted(re.search(r"joint_2 at (\S+) rad, then at (\S+) rad", line).groups()) == jumped, line
    assert re.search(r" rad [\d.e-]+ s later by their stamps, 0\.3 rad where its max velocity \(2\.792 rad/s\) "
                     r"allows [\d.e-]+: the arm's pose is unknown; ", line), line
    assert line.endswith("two nodes likely publish the arm's joints on /joint_states (a simulator or a bag beside "
                         "the arm's driver): `rostopic info /joint_states` lists them; stop all but the arm's driver")
    assert "accepted" not in ros.log()[logged:]  # nothing was sent
    # the driver alone again: sent as before
    sent = ros.rlff("robot", "send", str(path), "--json", "--timeout", "60")
    assert sent.returncode == 0, sent.stderr

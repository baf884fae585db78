"""Live ROS 1: a real roscore, ``rlff robot serve`` and ``rlff robot send`` as separate processes.

The executed path is what the server publishes on /joint_states, recorded by Debian's own
``rostopic echo`` (a third process). Stated tolerance: the recorded positions match the sent
trajectory (its points joined by quintic segments through their positions, velocities and
accelerations, as the server interpolates; scipy's own quintic Hermite here) within
EXECUTION_TOLERANCE rad at every recorded instant of the motion. The safety cases (jumps,
approaches, cancels, preemptions, bags) are in tests/test_ros1_safety.py.

Without Debian's ROS 1 packages these tests skip locally and FAIL in CI (CI=true).
"""

from __future__ import annotations

import json
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy.interpolate import BPoly

from rlff.robot.plan import load_for_robot
from rlff.robot.send import approach_line
from rlff.trajectory.check import LIMIT_SLACK
from robotfiles import unnamed_arm
from rosrig import (
    AMAX,
    ARM_NAMES,
    DRIVEN,
    ROBOT,
    UR_NAMES,
    VMAX,
    Ros,
    execution_error,
    free_port,
    named_robot_file,
    peaks,
    robot_file,
    ros_env,
    ros_fixture,
    ros_installed,
    states,
    stop,
    throw_csv,
    ur_file,
    wait,
)

pytestmark = [pytest.mark.ros, pytest.mark.integration, pytest.mark.slow]
_ros_installed = ros_installed
ros = pytest.fixture(scope="module")(ros_fixture)

EXECUTION_TOLERANCE = 1e-3  # rad
PERIOD = 0.01  # s, robot send's default


def completed_after(log: str, marker: str) -> bool:
    """Whether the server's ``log`` says a trajectory completed after its line with ``marker``:
    an earlier goal's "trajectory completed" before that line does not count, nor does any before
    the line was logged at all (the whole log then stands after no marker)."""
    return marker in log and "trajectory completed" in log.split(marker)[-1]


def _planned(path, pose):
    """What ``rlff robot send`` sends for the generated ``path`` to an arm at ``pose``."""
    return load_for_robot(path, ROBOT, PERIOD, start=pose)[1].trajectory


def test_executed_path_matches_the_sent_trajectory(ros, tmp_path):
    path = throw_csv(tmp_path, "throw.csv", -0.8, 1.6, 1.5)
    sent = _planned(path, ros.pose(tmp_path))
    recorder = ros.record(tmp_path / "states.csv")
    result = ros.rlff("robot", "send", str(path), "--json", "--timeout", "60")
    assert result.returncode == 0, result.stderr
    outcome = json.loads(result.stdout)
    assert outcome["status"] == "succeeded" and outcome["error_name"] == "SUCCESSFUL"
    assert outcome["feedback"] > 0 and outcome["duration"] == pytest.approx(sent.duration)
    end = outcome["start"] + sent.duration
    wait(lambda: states(tmp_path / "states.csv")[0][-1] > end + 0.5, 120, "states after the end")
    stop(recorder)

    stamps, positions = states(tmp_path / "states.csv")
    delay, worst = execution_error(stamps, positions, sent, outcome["start"])
    assert worst < EXECUTION_TOLERANCE, (delay, worst)
    after = stamps - outcome["start"] - delay > sent.duration + 0.05
    assert after.sum() > 0
    np.testing.assert_allclose(positions[after], np.tile(sent.positions[-1], (after.sum(), 1)), atol=1e-9)


def test_the_approach_goes_at_the_share_of_the_limits_asked_for(ros, tmp_path):
    """The move to the throw's start is planned at --approach-speed of the limits (a quarter by
    default) and announced with its duration; the server executes what was planned."""
    path = throw_csv(tmp_path, "throw.csv", 0.9, 1.5, 1.0)
    # each send leaves joint_2 about 0.45 rad past the throw's start, so each approaches it anew
    assert ros.rlff("robot", "send", str(path), "--timeout", "60").returncode == 0
    for share in (1.0, 0.5):
        pose = ros.pose(tmp_path)
        planned = load_for_robot(path, ROBOT, PERIOD, start=pose, approach_speed=share)[1].trajectory
        assert _planned(path, pose).duration > planned.duration + 0.2  # a quarter is slower
        result = ros.rlff("robot", "send", str(path), "--approach-speed", str(share), "--json", "--timeout", "60")
        assert result.returncode == 0, result.stderr
        assert approach_line(planned) in result.stderr
        assert json.loads(result.stdout)["duration"] == pytest.approx(planned.duration)


def test_a_dry_run_plans_from_the_live_pose_and_sends_nothing(ros, tmp_path):
    # checking before the arm moves: the pose read, the plan and its checks, the approach said
    path = throw_csv(tmp_path, "throw.csv", 0.9, 1.5, 1.0)
    pose = ros.pose(tmp_path)
    planned = _planned(path, pose)
    recorder = ros.record(tmp_path / "states.csv")
    result = ros.rlff("robot", "send", str(path), "--dry-run", "--json", "--timeout", "60")
    assert result.returncode == 0, result.stderr
    outcome = json.loads(result.stdout)
    assert outcome["status"] == "dry-run" and outcome["duration"] == pytest.approx(planned.duration)
    assert outcome["points"] == len(planned) and outcome["approach"] == approach_line(planned)
    assert "dry run, nothing sent:" in result.stderr and "fastest: joint_2 at" in result.stderr
    time.sleep(1.0)  # had a goal gone out, the arm would be moving now
    stop(recorder)
    _, positions = states(tmp_path / "states.csv")
    assert len(positions) > 10 and np.ptp(positions, axis=0).max() == 0.0
    np.testing.assert_allclose(ros.pose(tmp_path), pose, atol=0.0)


def test_goal_beyond_the_limits_is_rejected_and_nothing_moves(ros, tmp_path):
    # the client believes joint_2 tilts back to -1.9 rad; the server's robot stops at -1.48 (forward,
    # past 1.85 rad, the arm would reach into the floor, which the client refuses itself)
    wide = robot_file(tmp_path, "wide.toml", lambda t: t.replace("lower = -1.48", "lower = -1.9"))
    path = throw_csv(tmp_path, "far.csv", -0.5, -1.7, 0.5)
    recorder = ros.record(tmp_path / "states.csv")
    result = ros.rlff("robot", "send", str(path), "--robot", str(wide), "--json", "--timeout", "60")
    answered = time.time()
    wait(lambda: states(tmp_path / "states.csv")[0][-1] > answered + 1.0, 120, "states after the answer")
    stop(recorder)
    assert result.returncode == 1
    outcome = json.loads(result.stdout)
    assert outcome["status"] == "rejected" and outcome["error_code"] == -1
    assert outcome["error_name"] == "INVALID_GOAL"
    assert "joint_2 position" in outcome["error_string"] and "beyond the limit -1.48 rad" in outcome["error_string"]
    assert "executing" not in result.stderr, result.stderr  # no progress bar of a goal that never ran
    _, positions = states(tmp_path / "states.csv")
    assert np.ptp(positions, axis=0).max() == 0.0


def test_a_robot_the_arm_does_not_have_is_refused_before_sending(ros, tmp_path):
    def rename(text: str) -> str:  # the joints, not the [ros] names (joint_states, follow_joint_trajectory)
        joints, names = text.split("\n[ros]\n")
        # [geometry] is rlff's chain of joint_1..joint_6: a file of other names goes without it
        joints = re.sub(r"\n\[geometry\]\n(?:[^\[\n][^\n]*\n|\n)*", "\n", joints)
        return joints.replace("joint_", "axis_") + "\n[ros]\n" + names

    other = robot_file(tmp_path, "other.toml", rename)
    path = throw_csv(tmp_path, "throw.csv", -0.5, 0.5, 0.5)
    result = ros.rlff("robot", "send", str(path), "--robot", str(other), "--json", "--timeout", "60")
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1
    assert "/joint_states has no position of axis_1, axis_2" in result.stderr


def test_timeout_cancels_the_goal_and_the_arm_brakes(ros, tmp_path):
    path = throw_csv(tmp_path, "slower.csv", -1.4, 1.5, 0.0)  # within what keeps the arm above the floor
    sent = _planned(path, ros.pose(tmp_path))
    assert sent.duration > 12

    def brakes() -> int:
        return ros.log().count("braked to rest from")

    before = brakes()
    result = ros.rlff("robot", "send", str(path), "--timeout", "8", "--json")
    assert result.returncode == 1, result.stderr
    outcome = json.loads(result.stdout)
    assert outcome["status"] == "timed out" and outcome["duration"] == pytest.approx(sent.duration)
    assert "goal timed out: timed out; goal cancelled; cancelled after" in result.stderr
    assert brakes() == before + 1  # the server braked the arm to rest


def test_topic_mode_plans_from_the_arm_and_drives_it(ros, tmp_path):
    path = throw_csv(tmp_path, "throw.csv", 0.5, -0.5, 1.0)
    sent = _planned(path, ros.pose(tmp_path))
    result = ros.rlff("robot", "send", str(path), "--topic-mode", "--timeout", "60")
    assert result.returncode == 0, result.stderr
    assert f"published {len(sent)} points" in result.stderr
    wait(lambda: completed_after(ros.log(), f"/comau/joint_trajectory: {len(sent)} points"),
         60, "the topic trajectory to complete")
    np.testing.assert_allclose(ros.pose(tmp_path), sent.positions[-1], atol=1e-9)
    assert np.ptp(sent.positions[:, DRIVEN]) > 0.5  # it drove the arm (where it ends depends on where it was)


def test_serve_sim_mujoco_throws_where_sim_throw_does(tmp_path):
    # FollowJointTrajectory carries no release: the server finds it in the planned points
    rig = Ros(tmp_path / "mujoco", "--sim", "mujoco", "--basket", "2.0")
    try:
        path = throw_csv(tmp_path, "throw.csv", -0.8, 1.6, 1.5)
        result = rig.rlff("robot", "send", str(path), "--json", "--timeout", "120")
        assert result.returncode == 0, result.stderr
        text = json.loads(result.stdout)["error_string"]
    finally:
        rig.close()
    simulated = rig.rlff("sim", "throw", str(path), "--basket", "2.0", "--json")
    assert simulated.returncode == 0, simulated.stderr
    landing = json.loads(simulated.stdout)["landing_x"]
    assert text.startswith("MuJoCo throw: miss, landed at ")
    assert float(text.split("landed at ")[1].split(" m")[0]) == pytest.approx(landing, abs=1e-3)


def test_client_without_master_exits_with_a_clear_error(tmp_path):
    path = throw_csv(tmp_path, "throw.csv", -0.5, 0.5, 0.5)
    env = ros_env(free_port(), tmp_path)
    proc = subprocess.run([sys.executable, "-m", "rlff", "robot", "send", str(path), "--timeout", "2"], env=env,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1
    assert f"no ROS master at {env['ROS_MASTER_URI']} after 2 s" in proc.stderr


def test_a_learned_throw_is_sent_as_rlff_learn_out_wrote_it(tmp_path):
    """`rlff learn ... --out learned.json` then `rlff robot send learned.json`: refused while the
    arm (a fresh server, joint_2 at 0) is away from the throw's first pose, then with --approach
    the arm moves there within the limits and executes the learned throw, the file's points joined
    by the server's quintic interpolation."""
    from rlff.dataset import write_csv
    from rlff.preprocess import Pipeline
    from rlff.robot.export import read_json
    from rlff.robot.sendfile import with_approach
    from rlff.synthetic.throws import simulate_throws

    demos = tmp_path / "demos.csv"
    clean, _ = Pipeline.preset("thesis").run(simulate_throws(2, subjects=3, distances=(1.0, 1.25, 1.5),
                                                             throws_per_distance=2))
    write_csv(clean, demos)
    learned = tmp_path / "learned.json"
    rig = Ros(tmp_path)
    try:
        result = rig.rlff("learn", str(demos), "--basket", "1.4", "--feedback", "distance", "--out", str(learned),
                          "--json", timeout=300)
        assert result.returncode == 0, result.stderr
        assert json.loads(result.stdout)["hit"]
        pose = rig.pose(tmp_path)
        refused = rig.rlff("robot", "send", str(learned), "--timeout", "60")
        assert refused.returncode == 2 and "is not where the arm is" in refused.stderr, refused.stderr
        assert "--approach" in refused.stderr
        recorder = rig.record(tmp_path / "states.csv")
        sent = rig.rlff("robot", "send", str(learned), "--approach", "--json", "--timeout", "60")
        assert sent.returncode == 0, sent.stderr
        outcome = json.loads(sent.stdout)
        assert outcome["status"] == "succeeded" and outcome["error_name"] == "SUCCESSFUL"
        trajectory = with_approach(ROBOT, read_json(learned), pose, PERIOD)
        assert trajectory.duration > read_json(learned).duration  # the approach came first
        end = outcome["start"] + trajectory.duration
        wait(lambda: states(tmp_path / "states.csv")[0][-1] > end + 0.5, 120, "states after the end")
        stop(recorder)
    finally:
        rig.close()
    quintic = BPoly.from_derivatives(trajectory.time, np.stack([trajectory.positions, trajectory.velocities,
                                                                trajectory.accelerations], axis=1))
    stamps, positions = states(tmp_path / "states.csv")

    def error(delay: float) -> float:  # the goal starts on receipt when it arrives late (a loaded machine)
        elapsed = stamps - outcome["start"] - delay
        moving = (elapsed >= 0) & (elapsed <= trajectory.duration)
        return float(np.abs(positions[moving] - quintic(elapsed[moving])).max()) if moving.sum() >= 20 else np.inf

    assert min(error(delay) for delay in np.arange(0.0, 0.5, 0.001)) < EXECUTION_TOLERANCE


def test_a_stale_latched_state_is_not_taken_as_the_arm_s_pose(tmp_path):
    """A driver that published once, latched, stamped t = 1 s (or not at all): its pose is no
    longer the arm's; the client waits for a fresh state, then refuses, nothing sent."""
    rig = Ros(tmp_path, serve=False)
    try:
        names = "[" + ", ".join(ROBOT.joint_names) + "]"
        path = throw_csv(tmp_path, "throw.csv", -0.5, 0.5, 0.5)
        for stamp, said in (("{secs: 1}", "the last is stamped 1.000 s, 56"),
                            ("{secs: 0}", "its messages are unstamped (header.stamp 0)")):
            latched = subprocess.Popen(["rostopic", "pub", "-l", "/joint_states", "sensor_msgs/JointState",
                                        f"{{header: {{stamp: {stamp}}}, name: {names}, "
                                        "position: [0, 0, -1.373, 0, -0.198, 0], velocity: [0, 0, 0, 0, 0, 0]}"],
                                       env=rig.env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            try:
                time.sleep(3)  # registered and latched
                result = rig.rlff("robot", "send", str(path), "--timeout", "4")
            finally:
                stop(latched)
            assert result.returncode == 1, result.stderr
            assert result.stderr.count("\n") == 1, result.stderr
            assert result.stderr.startswith("rlff: error: no fresh state on /joint_states within 4 s: "), result.stderr
            assert said in result.stderr and "the arm's pose is unknown" in result.stderr
    finally:
        rig.close()


def test_stopping_send_before_any_goal_says_no_cancel(tmp_path):
    rig = Ros(tmp_path, serve=False)  # nothing on /joint_states: the client waits for the arm's pose
    try:
        path = throw_csv(tmp_path, "throw.csv", -0.5, 0.5, 0.5)
        sender = subprocess.Popen([sys.executable, "-m", "rlff", "robot", "send", str(path)], env=rig.env,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        time.sleep(5)
        sender.send_signal(signal.SIGTERM)
        _, err = sender.communicate(timeout=60)
    finally:
        rig.close()
    assert sender.returncode == 143 and err.strip() == "rlff: terminated", err


def test_goals_in_a_row_go_through_one_client_and_lose_no_answer(ros, tmp_path):
    """rlff's client made an actionlib SimpleActionClient per goal, which records a goal's handle
    only after the goal is out: an answer that came first was dropped ("Got a transition callback
    on a goal handle that we're not tracking", about one goal in 25), and with it the goal's
    acceptance, or the end of a goal rejected at once, waited for until the timeout ("timed out").
    tests/ros1_goals_in_a_row.py holds each send at that moment, where it always happens."""
    script = Path(__file__).with_name("ros1_goals_in_a_row.py")
    done = subprocess.run([sys.executable, str(script)], env=ros.env, capture_output=True, text=True, timeout=180)
    assert done.returncode == 0, done.stdout + done.stderr
    said = json.loads(done.stdout.strip().splitlines()[-1])
    assert said["goals"] == [{"status": "succeeded", "accepted": True}] * 3, said
    assert (said["rejected"], said["rejected_code"]) == ("rejected", "PATH_TOLERANCE_VIOLATED"), said
    assert said["clients"] == 1, said
    assert "not tracking" not in done.stderr and "[ERROR]" not in done.stderr, done.stderr


def test_an_interrupt_before_the_goal_goes_out_says_no_goal_was_sent(ros, tmp_path):
    """A Ctrl-C while the goal message was made (before anything was published) was marked as a
    cancel not confirmed ("check the arm (e-stop it if it moves)", goal_sent true) though the
    server never saw a goal; it is unmarked: nothing was sent (tests/ros1_interrupted_before_sending.py)."""
    before = ros.log()
    script = Path(__file__).with_name("ros1_interrupted_before_sending.py")
    done = subprocess.run([sys.executable, str(script)], env=ros.env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    assert json.loads(done.stdout.strip().splitlines()[-1]) == {"interrupted": True, "fate": None}
    assert ros.log() == before  # the server heard of no goal


def _send_slow_throw(rig: Ros, folder) -> subprocess.Popen:
    """``rlff robot send --json`` of a throw of several seconds, returned once its goal is accepted."""
    slow = throw_csv(folder, "slow.csv", -1.2, 1.5, 0.0)
    sender = subprocess.Popen([sys.executable, "-m", "rlff", "robot", "send", str(slow), "--json"],
                              env=rig.env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wait(lambda: "accepted" in rig.log() or sender.poll() is not None, 120, "the goal to be accepted")
    return sender


def test_a_server_that_dies_mid_goal_is_reported_lost_not_cancelled(tmp_path):
    rig = Ros(tmp_path)
    try:
        sender = _send_slow_throw(rig, tmp_path)
        rig.server.kill()  # the driver crashes: no result, no answer to the cancel
        killed = time.monotonic()
        out, err = sender.communicate(timeout=60)
        took = time.monotonic() - killed
    finally:
        rig.close()
    assert sender.returncode == 1, err
    outcome = json.loads(out)
    assert outcome["status"] == "lost" and "goal cancelled" not in err
    assert outcome["error_string"].startswith("the server at /comau_controller/follow_joint_trajectory stopped "
                                              "answering (no status for ")
    assert "the cancel was not confirmed (no server is left to answer it): the arm's state is unknown" in err
    assert took < 12  # seen within seconds (5 s of silence and the cancel's 1 s; 8.1 s on a loaded machine), not after the throw's duration + 10 s + the cancel's 10 s


def test_a_server_restarted_after_a_crash_mid_goal_confirms_no_cancel(tmp_path):
    # a supervisor (roslaunch respawn, systemd) starts the driver again at once: the new server
    # lists no such goal, actionlib ends it LOST, and "goal cancelled" had been said of it
    rig = Ros(tmp_path)
    try:
        sender = _send_slow_throw(rig, tmp_path)
        rig.server.kill()
        rig.server.wait()
        with open(tmp_path / "serve2.log", "w") as log:  # respawned
            rig.server = subprocess.Popen([sys.executable, "-m", "rlff", "robot", "serve"], env=rig.env,
                                          stdout=log, stderr=subprocess.STDOUT)
        out, err = sender.communicate(timeout=120)
    finally:
        rig.close()
    assert sender.returncode == 1, err
    assert json.loads(out)["status"] == "lost" and "goal cancelled" not in err, err
    assert "the cancel was not confirmed" in err, err


def test_a_server_stopped_mid_goal_brakes_the_arm_answers_the_goal_and_exits_0(tmp_path):
    """SIGTERM (a supervisor's stop) while the arm moves: the server brakes it to rest within the
    limits, publishing the joint states as it brakes, answers the goal ABORTED with the reason,
    and exits 0 (it once shut its node down at once: the arm left moving, the goal unanswered)."""
    rig = Ros(tmp_path)
    recorder = sender = None
    try:
        recorder = rig.record(tmp_path / "states.csv")
        sender = _send_slow_throw(rig, tmp_path)
        wait(lambda: np.ptp(states(tmp_path / "states.csv")[1][:, DRIVEN]) > 0.05, 60, "the arm to move")
        signalled = time.time()  # the server's ROS time is this wall clock
        rig.server.send_signal(signal.SIGTERM)
        try:
            code = rig.server.wait(timeout=30)
        except subprocess.TimeoutExpired:
            code = None  # still running
        took = time.time() - signalled
        out, err = sender.communicate(timeout=60)
    finally:
        for proc in (sender, recorder):
            if proc is not None:
                stop(proc)
        rig.close()
    assert sender.returncode == 1, err
    outcome = json.loads(out)
    assert outcome["status"] == "aborted", outcome
    assert outcome["error_string"].startswith("the server was stopped by SIGTERM after "), outcome
    assert "; braked to rest from " in outcome["error_string"], outcome
    assert "goal aborted: the server was stopped by SIGTERM" in err, err
    assert code == 0 and took < 5, (code, took, rig.log())
    assert "stopped by SIGTERM: braking the arm to rest and answering its goal" in rig.log()

    stamps, positions = states(tmp_path / "states.csv")
    velocities = pd.read_csv(tmp_path / "states.csv")[[f"field.velocity{i}" for i in range(6)]].to_numpy(float)
    velocity, acceleration = peaks(stamps, positions)
    assert np.all(velocity <= VMAX * (1 + LIMIT_SLACK)), (velocity, VMAX)
    assert np.all(acceleration <= AMAX * (1 + LIMIT_SLACK)), (acceleration, AMAX)
    braking = velocities[stamps > signalled]
    assert abs(braking[0, DRIVEN]) > 0.05  # published while it braked
    np.testing.assert_array_equal(braking[-1], np.zeros(6))  # and at rest at the end


def test_serve_and_send_under_the_robot_file_s_ros_names(tmp_path):
    """An arm whose controller lives under /arm: `robot serve` and `robot send` with a robot file
    whose [ros] table says so drive it (a goal, then topic mode), and rlff's default names find
    nothing."""
    from rlff.robot import RobotMapping, load_robot

    arm = named_robot_file(tmp_path, "arm.toml", **ARM_NAMES)
    robot = load_robot(arm)
    rig = Ros(tmp_path, "--robot", str(arm))
    try:
        assert ("serving /arm/follow_joint_trajectory and /arm/joint_trajectory, publishing /arm/joint_states, "
                "for comau_smart5_six") in rig.log()
        path, back = throw_csv(tmp_path, "throw.csv", 0.0, 0.3, 0.5), throw_csv(tmp_path, "back.csv", 0.3, 0.0, 0.5)
        sent = load_for_robot(path, robot, PERIOD, start=RobotMapping.for_robot(robot).pose(0.0))[1].trajectory
        returned = load_for_robot(back, robot, PERIOD, start=sent.positions[-1])[1].trajectory
        result = rig.rlff("robot", "send", str(path), "--robot", str(arm), "--json", "--timeout", "60")
        assert result.returncode == 0, result.stderr
        outcome = json.loads(result.stdout)
        assert outcome["status"] == "succeeded" and outcome["duration"] == pytest.approx(sent.duration)
        assert "\nexecuting " in result.stderr  # the progress bar, from the goal's first feedback

        published = rig.rlff("robot", "send", str(back), "--robot", str(arm), "--topic-mode", "--timeout", "60")
        assert published.returncode == 0, published.stderr
        assert f"published {len(returned)} points on /arm/joint_trajectory to 1 subscriber(s)" in published.stderr
        wait(lambda: completed_after(rig.log(), "trajectory on /arm/joint_trajectory: "),
             60, "the topic trajectory to complete")
        np.testing.assert_allclose(rig.pose(tmp_path, "/arm/joint_states"), returned.positions[-1], atol=1e-9)

        default = rig.rlff("robot", "send", str(path), "--timeout", "1")
    finally:
        rig.close()
    assert default.returncode == 1
    assert default.stderr.startswith("rlff: error: nothing on /joint_states within 1 s (the [ros] joint_states of "
                                     "built-in robot comau_smart5_six): the arm's pose is unknown; no node publishes "
                                     "it (the master lists none): is the arm's driver, or `rlff robot serve`, "
                                     "running, "), default.stderr


def test_serve_and_send_of_a_robot_file_without_a_ros_table_say_the_names_they_use(ros, tmp_path):
    """A robot file without [ros] drove goals to the Comau driver's action under the file's joint
    names without a word (only `robot show` said so): `serve` and `send` say it once, before any
    node registers or connects, and go on (a rehearsal of the file meets on the same names)."""
    plain = unnamed_arm(tmp_path)
    rig = Ros(tmp_path, "--robot", str(plain))
    try:
        served = rig.log()
        path = throw_csv(tmp_path, "throw.csv", 0.0, 0.3, 0.5)
        goal = rig.rlff("robot", "send", str(path), "--robot", str(plain), "--dry-run", "--timeout", "60")
        topic = rig.rlff("robot", "send", str(path), "--robot", str(plain), "--topic-mode", "--dry-run",
                         "--timeout", "60")
    finally:
        rig.close()
    joints = "the robot file's joint names (joint_1, joint_2, joint_3, joint_4, joint_5, joint_6)"
    assert served.count("has no [ros] table") == 1 and (
        f"warning: {plain} has no [ros] table: the simulated arm is served with rlff's defaults, the Comau driver's "
        "action /comau_controller/follow_joint_trajectory, joint_states /joint_states, trajectory_topic "
        f"/comau/joint_trajectory, and {joints}; if your arm's controller has other names, give them in a [ros] "
        "table (action, joint_states") in served, served
    assert served.index("has no [ros] table") < served.index("serving /")
    assert goal.returncode == 0 and "dry run, nothing sent" in goal.stderr, goal.stderr
    assert goal.stderr.count("has no [ros] table") == 1 and (
        "the goal is sent with rlff's defaults, the Comau driver's joint_states /joint_states, action "
        f"/comau_controller/follow_joint_trajectory, and {joints}") in goal.stderr, goal.stderr
    assert topic.returncode == 0 and topic.stderr.count("has no [ros] table") == 1 and (
        "the trajectory is published with rlff's defaults, the Comau driver's joint_states /joint_states, "
        "trajectory_topic /comau/joint_trajectory") in topic.stderr, topic.stderr
    # the built-in robot's file states the defaults: nothing to say
    builtin = ros.rlff("robot", "send", str(path), "--dry-run", "--timeout", "60")
    assert builtin.returncode == 0 and "[ros]" not in builtin.stderr, builtin.stderr


#: A driver whose publisher of the joint states (the topic its first argument) sends nothing.
SILENT_DRIVER = ("import sys\nimport rlff.robot.ros1\nimport rospy\nfrom sensor_msgs.msg import JointState\n"
                 "rospy.init_node('silent_driver')\nstates = rospy.Publisher(sys.argv[1], JointState, queue_size=1)\n"
                 "rospy.spin()")


def test_a_driver_that_publishes_nothing_is_told_from_none(ros, tmp_path):
    # its publisher registered with the master, its messages absent: not "is the arm's driver running"
    silent = named_robot_file(tmp_path, "silent.toml", joint_states="/silent/joint_states")
    driver = subprocess.Popen([sys.executable, "-c", SILENT_DRIVER, "/silent/joint_states"], env=ros.env)
    try:
        wait(lambda: any(topic == "/silent/joint_states" for topic, _ in ros.master.getSystemState("/test")[2][0]),
             60, "the silent driver's publisher")
        path = throw_csv(tmp_path, "throw.csv", -0.5, 0.5, 0.5)
        result = ros.rlff("robot", "send", str(path), "--robot", str(silent), "--timeout", "2")
    finally:
        stop(driver)
    assert result.returncode == 1
    assert result.stderr.splitlines()[-1] == (
        f"rlff: error: nothing on /silent/joint_states within 2 s (the [ros] joint_states of {silent}): the arm's "
        "pose is unknown; the master lists a publisher of it, and nothing came from it: does the arm's driver "
        "publish its state, and can this host reach the driver's (ROS_IP or ROS_HOSTNAME on both)? (`rostopic hz "
        "/silent/joint_states`, `rostopic info /silent/joint_states`)"), result.stderr


def test_an_action_nobody_serves_is_named_with_the_robot_file_s_ros_table(ros, tmp_path):
    nobody = named_robot_file(tmp_path, "nobody.toml", action="/nobody/follow_joint_trajectory")
    path = throw_csv(tmp_path, "throw.csv", -0.8, 0.6, 0.0)  # 7 s at 0.2 rad/s: longer than the 4 s timeout
    result = ros.rlff("robot", "send", str(path), "--robot", str(nobody), "--timeout", "4")
    assert result.returncode == 1
    assert result.stderr.splitlines()[-1] == (
        f"rlff: error: no action server at /nobody/follow_joint_trajectory (the [ros] action of {nobody}): is `rlff "
        "robot serve` running, or does the arm's controller use another name? "
        "(`rostopic list | grep follow_joint_trajectory`)"), result.stderr
    # before it: the plan, the approach and the too short --timeout announced, no progress bar of
    # a goal that never went out
    before = result.stderr.splitlines()[:-1]
    assert [line.split(" ")[0] for line in before] == ["planned", "approach", "warning:", "sending"], result.stderr
    assert before[-2].startswith("warning: timeout (--timeout) ") and "shorter than the motion" in before[-2]
    # the wait for the server said before it (it was 4 s of silence)
    assert before[-1] == "sending the goal to /nobody/follow_joint_trajectory: waiting up to 4 s for its action server"


def test_an_action_s_topic_given_for_the_action_is_named_as_such(ros, tmp_path):
    # `rostopic list | grep follow_joint_trajectory` lists the action's topics: a user copied one
    typed = named_robot_file(tmp_path, "typed.toml", action="/comau_controller/follow_joint_trajectory/goal")
    path = throw_csv(tmp_path, "throw.csv", -0.5, 0.5, 0.5)
    result = ros.rlff("robot", "send", str(path), "--robot", str(typed), "--timeout", "2")
    assert result.returncode == 1
    assert result.stderr.splitlines()[-1] == (
        f"rlff: error: no action server at /comau_controller/follow_joint_trajectory/goal (the [ros] action of "
        f"{typed}): the action is the part before /goal, /comau_controller/follow_joint_trajectory (/goal names one "
        "of its topics): name that in [ros] action; or is `rlff robot serve` running, or does the arm's controller "
        "use another name? (`rostopic list | grep follow_joint_trajectory`)"), result.stderr


def test_serve_and_send_a_throw_to_a_ur_named_controller_in_its_own_convention(tmp_path):
    """A robot file of rlff's joints with [geometry] and [ros.joints] of a UR-named controller:
    `robot serve` plays that controller (its joint states carry the UR's names and positions
    offset + sign * rlff's), `robot send` reads them back into rlff's convention, plans from there
    and sends the throw in the controller's; the arm ends where rlff planned. A file without the
    map finds none of its joints on the topic."""
    import pandas as pd

    from rlff.robot import RobotMapping, load_robot

    mapped = ur_file(tmp_path / "ur.toml")
    robot = load_robot(mapped)
    joints = robot.ros.joints
    rig = Ros(tmp_path, "--robot", str(mapped))
    try:
        path = throw_csv(tmp_path, "throw.csv", 0.0, 0.3, 0.5)
        start = RobotMapping.for_robot(robot).pose(0.0)  # where serve starts the arm, rlff's convention
        sent = load_for_robot(path, robot, PERIOD, start=start)[1].trajectory
        dry = rig.rlff("robot", "send", str(path), "--robot", str(mapped), "--dry-run", "--timeout", "60")
        assert dry.returncode == 0, dry.stderr
        lift = joints.positions_to_controller(["joint_2"], [start[1]])[0]
        assert (f"arm's pose read (rad; the controller's = rlff's): shoulder_pan_joint 0 = joint_1 0, "
                f"shoulder_lift_joint {lift:.4g} = joint_2 {start[1]:.4g}, ") in dry.stderr, dry.stderr

        result = rig.rlff("robot", "send", str(path), "--robot", str(mapped), "--json", "--timeout", "60")
        assert result.returncode == 0, result.stderr
        outcome = json.loads(result.stdout)
        assert outcome["status"] == "succeeded" and outcome["duration"] == pytest.approx(sent.duration)
        assert outcome["feedback"] > 0

        recorder = rig.record(tmp_path / "states.csv")
        stop(recorder)
        table = pd.read_csv(tmp_path / "states.csv")
        assert [table[f"field.name{i}"].iloc[-1] for i in range(6)] == list(UR_NAMES)
        np.testing.assert_allclose(states(tmp_path / "states.csv")[1][-1],
                                   joints.positions_to_controller(robot.joint_names, sent.positions[-1]), atol=1e-9)
        assert abs(sent.positions[-1][4] - start[4]) < 1e-12  # joint_5 held: 0.25 - its rlff angle on the topic
        np.testing.assert_allclose(table["field.position4"].iloc[-1], 0.25 - start[4], atol=1e-12)

        # topic mode goes out in the controller's names and convention too
        back = throw_csv(tmp_path, "back.csv", 0.3, 0.0, 0.5)
        returned = load_for_robot(back, robot, PERIOD, start=sent.positions[-1])[1].trajectory
        published = rig.rlff("robot", "send", str(back), "--robot", str(mapped), "--topic-mode", "--timeout", "60")
        assert published.returncode == 0, published.stderr
        wait(lambda: completed_after(rig.log(), "trajectory on /comau/joint_trajectory: "), 60,
             "the topic trajectory to complete")
        np.testing.assert_allclose(rig.pose(tmp_path), joints.positions_to_controller(
            robot.joint_names, returned.positions[-1]), atol=1e-9)

        # a goal beyond a limit in the controller's names: refused in rlff's words, with the map
        beyond = rig.pose(tmp_path)
        beyond[1] = joints.positions_to_controller(["joint_2"], [robot.joint("joint_2").upper + 0.3])[0]
        rejected = rig.goal(tmp_path, {"joint_names": list(UR_NAMES), "time": [4.0],
                                       "positions": [list(map(float, beyond))]})
        assert (rejected["status"], rejected["error_code"]) == ("rejected", -1), rejected  # INVALID_GOAL
        assert rejected["error_string"].endswith(
            "; in rlff's names and convention: joint_2 as shoulder_lift_joint = -1.5708 + joint_2"), rejected

        # another program's goal in the controller's names: its feedback in those names too
        moved = rig.pose(tmp_path)
        moved[4] += 0.2
        done = rig.goal(tmp_path, {"joint_names": list(UR_NAMES), "time": [2.0],
                                   "positions": [list(map(float, moved))]})
        assert done["status"] == "succeeded" and done["feedback_joint_names"] == [list(UR_NAMES)], done
        np.testing.assert_allclose(rig.pose(tmp_path), moved, atol=1e-9)

        plain = rig.rlff("robot", "send", str(path), "--timeout", "5")
    finally:
        rig.close()
    assert plain.returncode == 2, plain.stderr
    assert plain.stderr.splitlines()[-1] == (
        "rlff: error: /joint_states has no position of joint_1, joint_2, joint_3, joint_4, joint_5, joint_6 (it names "
        f"{', '.join(UR_NAMES)}), and no message on it within 2 s named every joint of comau_smart5_six: check the "
        "robot file's joint names against the arm's, or map them to the arm's in [ros.joints] (docs/robot.md)"), \
        plain.stderr

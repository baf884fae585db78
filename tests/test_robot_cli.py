"""``rlff robot show / export / send``: outputs, and bad input refused before anything is sent."""

from __future__ import annotations

import json
import re
from importlib import resources

import numpy as np
import pandas as pd
import pytest

from rlff.cli import main
from rlff.robot import RobotMapping, load_robot
from rlff.robot.export import read_json
from rlff.timing import time_along_path
from robotfiles import slow_arm, unnamed_arm


def human_csv(path, robot_positions, robot_speed, **extra):
    """A generated-trajectory CSV whose mapped joint_2 path is ``robot_positions`` (rad)."""
    mapping = RobotMapping.for_robot(load_robot())
    columns = {"angle": (np.asarray(robot_positions) - mapping.angle_offset) / mapping.angle_scale,
               "velocity": np.asarray(robot_speed) / mapping.velocity_scale, "pdf": 1.0,
               "exploration": 0.0, "gmr_mean": 0.0}
    columns.update(extra)
    pd.DataFrame(columns).to_csv(path, index=False)
    return path


@pytest.fixture
def throw(tmp_path):
    return human_csv(tmp_path / "throw.csv", np.linspace(-0.5, 1.5, 21), np.full(21, 2.0))


def run(capsys, *args):
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_show_lists_the_limits(cli):
    result = cli("robot", "show", "--json")
    assert result.code == 0, result.stderr
    shown = json.loads(result.stdout)
    assert shown["joints"][1] == {"name": "joint_2", "lower": -1.48, "upper": 2.71, "max_velocity": 2.792,
                                  "max_acceleration": 11.0, "max_jerk": 110.0}
    assert shown["throwing"]["joint"] == "joint_2"


def test_export_writes_the_comau_program_ending_at_rest(cli, throw, tmp_path):
    result = cli("robot", "export", str(throw), "--format", "comau", "-o", str(tmp_path / "p.txt"), "--period", "0.01")
    assert result.code == 0, result.stderr
    lines = (tmp_path / "p.txt").read_text().splitlines()
    rows = np.array([[float(v.strip("')")) for v in line.split(",")[1:]] for line in lines[1:]])
    assert lines[0] == 'coord_type = "-j"' and len(rows) > 50
    assert rows[0, 2] == pytest.approx(np.degrees(-0.5), abs=1e-4)  # joint_2's start in slot 3
    speed = rows[:, 5]  # slot 6: % of joint_2's 2.792 rad/s
    release = int(np.flatnonzero(speed > speed.max() - 1e-3)[-1])  # the last point at full speed
    assert speed[release] == pytest.approx(100 * 2.0 / 2.792, abs=1e-3)  # the release, as the model asked
    assert rows[release, 2] == pytest.approx(np.degrees(1.5), abs=1e-3)
    assert lines[-1].split(",")[6] == "'0')"  # ends at rest, not at 90 % speed
    assert np.all(speed <= 100.0)
    # the joints whose slots the throw takes are not in the program: the operator is told
    assert ("note: the Comau program holds in slot 3 joint_2's position and slot 6 its speed: joint_3 (start pose "
            "-78.67 deg) and joint_6 (start pose 0 deg) are in no slot and stay where the main program placed the "
            "arm") in " ".join(result.stderr.split())


def test_export_samples_the_plan_at_the_period(capsys, throw, tmp_path):
    code, _, err = run(capsys, "robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "t.json"),
                       "--period", "0.01", "--json")
    assert code == 0, err
    traj = read_json(tmp_path / "t.json")
    steps = np.diff(traj.time)
    assert np.all(steps <= 0.01 + 1e-12) and np.median(steps) == pytest.approx(0.01)
    release = int(np.flatnonzero(traj.time == traj.release_time)[0])
    assert traj.positions[release, 1] == pytest.approx(1.5, abs=1e-12)
    assert traj.velocities[release, 1] == pytest.approx(2.0, abs=1e-12)
    assert np.all(traj.velocities[-1] == 0) and np.all(traj.accelerations[-1] == 0)
    assert np.abs(traj.accelerations[:, 1]).max() <= 11.0


def test_a_bag_of_a_robot_file_without_a_ros_table_says_the_names_it_carries(capsys, throw, tmp_path):
    """A tester's UR5e file without [ros] exported its bag on the Comau driver's topic without a word:
    only `robot show` said so. Each bag says it once; a file of another format carries no ROS names."""
    plain = unnamed_arm(tmp_path)
    said = (f"warning: {plain} has no [ros] table: the bag is written with rlff's defaults, the Comau driver's "
            "trajectory_topic /comau/joint_trajectory, and the robot file's joint names (joint_1, joint_2, joint_3, "
            "joint_4, joint_5, joint_6); if your arm's controller has other names, give them in a [ros] table "
            "(action, joint_states, trajectory_topic; a [ros.joints.<joint>] table of name, offset and sign for "
            "each joint it names or counts otherwise; docs/robot.md)")
    for fmt, name in (("ros1-bag", "t.bag"), ("ros2-bag", "t2")):
        code, _, err = run(capsys, "robot", "export", str(throw), "--robot", str(plain), "-f", fmt, "-o",
                           str(tmp_path / name))
        assert code == 0 and err.count("has no [ros] table") == 1 and said in err, err
        # the built-in robot's file writes the defaults out: nothing to say
        code, _, err = run(capsys, "robot", "export", str(throw), "-f", fmt, "-o", str(tmp_path / f"builtin-{name}"))
        assert code == 0 and "[ros]" not in err, err
    code, _, err = run(capsys, "robot", "export", str(throw), "--robot", str(plain), "-o", str(tmp_path / "t.json"))
    assert code == 0 and "[ros]" not in err, err


def test_period_zero_is_refused(capsys, throw, tmp_path):
    for fmt in ("json", "ros1-bag"):
        code, _, err = run(capsys, "robot", "export", str(throw), "-f", fmt, "-o", str(tmp_path / f"t.{fmt}"),
                           "--period", "0")
        assert code == 2 and "--period must be a positive controller period (s), got 0.0" in err
        assert len(err.strip().splitlines()) == 1 and not (tmp_path / f"t.{fmt}").exists()


@pytest.mark.parametrize("period", ["1e-6", "5e-05"])
def test_a_period_below_a_controllers_is_refused(capsys, monkeypatch, throw, tmp_path, period):
    """1e-6 s wrote 130 MB for a throw of 0.85 s, 1e-9 ran out of memory; an exported trajectory,
    which is not planned again, is refused too: a --period is checked wherever it is given."""
    said = f"--period {float(period):g} s is shorter than 0.0001 s (a 10 kHz controller)"
    for fmt in ("json", "comau"):
        code, _, err = run(capsys, "robot", "export", str(throw), "-f", fmt, "-o", str(tmp_path / f"t.{fmt}"),
                           "--period", period)
        assert code == 2 and said in err and len(err.strip().splitlines()) == 1, err
        assert not (tmp_path / f"t.{fmt}").exists()
    assert run(capsys, "robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "t.json"))[0] == 0
    code, _, err = run(capsys, "robot", "export", str(tmp_path / "t.json"), "-f", "csv", "-o", str(tmp_path / "t.csv"),
                       "--period", period)
    assert code == 2 and said in err and not (tmp_path / "t.csv").exists()
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:9")  # nothing there, should the check let it through
    code, _, err = run(capsys, "robot", "send", str(tmp_path / "t.json"), "--period", period, "--timeout", "1")
    assert code == 2 and said in err


def test_clip_reports_every_change(capsys, tmp_path):
    path = human_csv(tmp_path / "far.csv", np.linspace(2.0, 2.8, 9), np.full(9, 1.0))
    code, _, err = run(capsys, "robot", "export", str(path), "-f", "csv", "-o", str(tmp_path / "o.csv"))
    # a release clipping would hold at the limit, at rest: no throw (until 2026-12-07 offered the clip)
    assert code == 2 and "the release (joint_2 at 2.8 rad, beyond its limit 2.71 rad) is beyond a position limit" in err
    fast = human_csv(tmp_path / "fast.csv", np.linspace(-1.0, 0.5, 9), np.linspace(0.5, 3.0, 9))
    code, _, err = run(capsys, "robot", "export", str(fast), "-f", "csv", "-o", str(tmp_path / "o.csv"))
    assert code == 2 and "point 8: joint_2 velocity 3 rad/s beyond the limit 2.792 rad/s (the release)" in err
    code, _, err = run(capsys, "robot", "export", str(fast), "-f", "csv", "-o", str(tmp_path / "o.csv"), "--clip")
    assert code == 0, err
    assert "clipped: point 8: joint_2 velocity 3 rad/s -> 2.792 rad/s" in err
    traj = pd.read_csv(tmp_path / "o.csv")
    assert traj["joint_2_velocity"].abs().max() == pytest.approx(2.792)  # the clipped release, kept


def test_a_path_in_degrees_is_said_so_not_offered_a_clip(capsys, tmp_path):
    """A path whose velocities are deg/s released joint_2 at 136 rad/s against its limit 2.792, and
    the refusal said "clip (--clip) clips it": a unit slip, which clipping would have thrown."""
    path = human_csv(tmp_path / "deg.csv", np.linspace(-1.0, 0.5, 9), np.degrees(np.linspace(0.5, 2.37, 9)))
    code, _, err = run(capsys, "robot", "export", str(path), "-f", "csv", "-o", str(tmp_path / "o.csv"))
    assert code == 2 and "point 8: joint_2 velocity 135.791 rad/s beyond the limit 2.792 rad/s (the release)" in err
    assert ("the path's velocities look like deg/s, not rad/s (49 times the limit; as deg/s 2.37 rad/s, within it)"
            in err and "clip (--clip) clips" not in err and len(err.splitlines()) == 1)


def test_no_room_to_brake_is_refused_by_every_format(capsys, tmp_path):
    """The issue's path ending 0.01 rad from a limit at 2.7 rad/s: no format writes it."""
    path = human_csv(tmp_path / "edge.csv", np.linspace(1.5, 2.70, 13), np.full(13, 2.7))
    for fmt in ("json", "csv", "ros1-bag", "ros2-bag", "comau"):
        out = tmp_path / f"o-{fmt}"
        code, _, err = run(capsys, "robot", "export", str(path), "-f", fmt, "-o", str(out))
        assert code == 2 and not out.exists(), fmt
        assert "no room to brake after the release: joint_2 would reach" in err
        assert "beyond its upper limit 2.71 rad" in err and "the limit is 0.01 rad away" in err


def test_a_robot_trajectory_that_disagrees_with_its_time_is_refused(capsys, throw, tmp_path):
    code, _, err = run(capsys, "robot", "export", str(throw), "-f", "csv", "-o", str(tmp_path / "t.csv"))
    assert code == 0, err
    table = pd.read_csv(tmp_path / "t.csv")
    for name, edit, message in (
            ("stretched", lambda t: t.assign(time=t.time * 20), "disagree by more than the acceleration limit"),
            ("slowed", lambda t: t.assign(joint_2_velocity=t.joint_2_velocity * 0.8), "but its velocities say"),
    ):
        edit(table).to_csv(tmp_path / f"{name}.csv", index=False)
        code, _, err = run(capsys, "robot", "export", str(tmp_path / f"{name}.csv"), "-f", "json",
                           "-o", str(tmp_path / f"{name}.json"))
        assert code == 2 and message in err and f"{name}.csv: point " in err and "joint_2" in err
        assert len(err.strip().splitlines()) == 1 and not (tmp_path / f"{name}.json").exists()
    # the checked file itself exports again, unchanged
    code, _, err = run(capsys, "robot", "export", str(tmp_path / "t.csv"), "-f", "json", "-o", str(tmp_path / "t.json"))
    assert code == 0, err
    np.testing.assert_array_equal(read_json(tmp_path / "t.json").positions[:, 1], table["joint_2_position"])


def test_a_robot_trajectory_released_where_its_throw_is_not_is_refused(rlff, throw, tmp_path):
    """An edited release_time off the samples, or in the braking, was taken (tester H): sim throw let
    go there. What rlff wrote is taken, and so is its release rounded to a microsecond."""
    assert rlff("robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "t.json")).code == 0
    document = json.loads((tmp_path / "t.json").read_text())
    release = document["time"].index(document["release_time"])
    for edited, said in ((document["time"][release] + 0.001, "is not one of the trajectory's sample times"),
                         (document["time"][release + 5], "falls where the arm slows down: joint_2 moves at")):
        (tmp_path / "edited.json").write_text(json.dumps(document | {"release_time": edited}))
        result = rlff("robot", "export", str(tmp_path / "edited.json"), "-f", "csv", "-o", str(tmp_path / "t.csv"))
        assert result.code == 2 and f"edited.json: release_time {edited:.10g} s {said}" in result.stderr, result.stderr
        assert not (tmp_path / "t.csv").exists()
    (tmp_path / "edited.json").write_text(json.dumps(document | {"release_time": round(document["release_time"], 6)}))
    assert rlff("robot", "export", str(tmp_path / "edited.json"), "-f", "csv", "-o", str(tmp_path / "t.csv")).code == 0
    assert pd.read_csv(tmp_path / "t.csv")["release_time"].iloc[0] == document["release_time"]


@pytest.mark.parametrize("fmt", ["json", "csv", "ros1-bag", "comau"])
def test_a_trajectory_of_one_point_is_not_exported(rlff, throw, tmp_path, fmt):
    """One point was written to csv, bags and Comau as `1 points, 0.000 s` (tester H)."""
    assert rlff("robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "t.json")).code == 0
    document = json.loads((tmp_path / "t.json").read_text())
    one = {key: document[key][:1] for key in ("time", "positions", "velocities", "accelerations")}
    (tmp_path / "one.json").write_text(json.dumps(document | one | {"release_time": None}))
    out = tmp_path / f"out.{fmt}"
    result = rlff("robot", "export", str(tmp_path / "one.json"), "-f", fmt, "-o", str(out))
    assert result.code == 2 and "checked as it is: 1 point, 0.000 s" in result.stderr, result.stderr
    assert result.stderr.endswith(f"rlff: error: {out}: not written: a trajectory of 1 point (0 s) is no motion, a "
                                  "controller runs from one point to the next; export one of 2 points or more, e.g. "
                                  "the throw planned from its generated path\n")
    assert not out.exists()


def test_show_names_the_arm_s_controller_on_the_ros_graph(capsys, tmp_path):
    text = resources.files("rlff").joinpath("robots", "comau_smart5_six.toml").read_text()
    arm = tmp_path / "arm.toml"
    arm.write_text(text.replace('joint_states = "/joint_states"', 'joint_states = "/arm/joint_states"'))
    code, out, _ = run(capsys, "robot", "show", "--robot", str(arm))
    assert code == 0
    assert ("ros: action /comau_controller/follow_joint_trajectory, joint states /arm/joint_states, trajectory "
            "topic /comau/joint_trajectory\n") in out
    code, out, _ = run(capsys, "robot", "show", "--robot", str(arm), "--json")
    assert json.loads(out)["ros"] == {"action": "/comau_controller/follow_joint_trajectory",
                                      "joint_states": "/arm/joint_states",
                                      "trajectory_topic": "/comau/joint_trajectory"}


def test_show_prints_every_limit(capsys):
    code, out, _ = run(capsys, "robot", "show")
    assert code == 0 and "max accel. (rad/s^2)" in out and "max jerk (rad/s^3)" in out
    row = next(line for line in out.splitlines() if line.startswith("joint_2"))
    assert row.split() == ["joint_2", "-1.48", "2.71", "2.792", "11", "110"]


def test_send_takes_what_export_json_writes(rlff, monkeypatch, throw, tmp_path):
    """Planned and checked before connecting: the exported file gets as far as the (absent) master,
    the same file with its time stretched is refused first, with exit 2."""
    assert rlff("robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "t.json")).code == 0
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:9")  # nothing there
    monkeypatch.setenv("ROS_IP", "127.0.0.1")
    result = rlff("robot", "send", str(tmp_path / "t.json"), "--timeout", "1")
    assert result.code == 1 and "no ROS master" in result.stderr, result.stderr
    document = json.loads((tmp_path / "t.json").read_text())
    document["time"] = [20 * t for t in document["time"]]
    (tmp_path / "slow.json").write_text(json.dumps(document))
    result = rlff("robot", "send", str(tmp_path / "slow.json"), "--timeout", "1")
    assert result.code == 2 and "slow.json: point " in result.stderr and "disagree" in result.stderr
    assert "master" not in result.stderr


@pytest.mark.parametrize("options", [["--bearing", "30"], ["--period", "0.01"], ["--clip"],
                                     ["--bearing", "0", "--period", "0.002"]])
def test_options_that_shape_a_plan_are_refused_for_a_robot_trajectory(rlff, monkeypatch, throw, tmp_path, options):
    """A robot trajectory is taken as it is: --bearing 30 --period 0.01 wrote it unchanged (at its own
    period, joint_1 not turned), without a word. Given at their defaults' values too, they are the
    user's; left out, the file is exported and sent as before, and a generated path takes them."""
    assert rlff("robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "t.json"), *options).code == 0
    given = ", ".join(option for option in options if option.startswith("--"))
    refusal = f"{given}: {tmp_path / 't.json'} is a robot trajectory, which is checked and taken as it is, not planned"
    result = rlff("robot", "export", str(tmp_path / "t.json"), "-f", "csv", "-o", str(tmp_path / "t.csv"), *options)
    assert result.code == 2 and result.stderr.startswith(f"rlff: error: {refusal}"), result.stderr
    assert "generated path (rlff generate)" in result.stderr and not (tmp_path / "t.csv").exists()
    assert rlff("robot", "export", str(tmp_path / "t.json"), "-f", "csv", "-o", str(tmp_path / "t.csv")).code == 0
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:9")  # nothing there, should the refusal let it through
    result = rlff("robot", "send", str(tmp_path / "t.csv"), *options, "--timeout", "1")
    assert result.code == 2 and refusal.replace("t.json", "t.csv") in result.stderr, result.stderr


def test_send_refuses_joints_for_a_robot_trajectory_it_sends_as_it_is(rlff, monkeypatch, throw, tmp_path):
    """--joints joint_2,joint_3 chose nothing: the trajectory's own joints went out, without a word."""
    assert rlff("robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "t.json")).code == 0
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:9")  # nothing there, should the refusal let it through
    result = rlff("robot", "send", str(tmp_path / "t.json"), "--joints", "joint_2,joint_3", "--timeout", "1")
    assert result.code == 2, result.stderr
    assert result.stderr.startswith(f"rlff: error: --joints: {tmp_path / 't.json'} is a robot trajectory, which is "
                                    "checked and taken as it is, not planned again"), result.stderr


def test_export_and_sim_throw_refuse_options_a_robot_trajectory_ignores(rlff, throw, tmp_path):
    """export --joints to a CSV, and sim throw --joints or --clip, of a robot trajectory changed
    nothing, without a word; --joints lays out a Comau program's slots, so it is taken there."""
    robot_trajectory = tmp_path / "t.json"
    assert rlff("robot", "export", str(throw), "-f", "json", "-o", str(robot_trajectory)).code == 0
    refusal = f"{robot_trajectory} is a robot trajectory, which is checked and taken as it is, not planned again"
    exported = rlff("robot", "export", str(robot_trajectory), "-f", "csv", "-o", str(tmp_path / "t.csv"),
                    "--joints", "joint_2")
    assert exported.code == 2 and exported.stderr.startswith(f"rlff: error: --joints: {refusal}"), exported.stderr
    assert not (tmp_path / "t.csv").exists()
    program = rlff("robot", "export", str(robot_trajectory), "-f", "comau", "-o", str(tmp_path / "t.txt"),
                   "--joints", "joint_2")
    assert program.code == 0, program.stderr
    for options in (["--clip"], ["--joints", "joint_2"], ["--clip", "--joints", "joint_2"]):
        simulated = rlff("sim", "throw", str(robot_trajectory), "--basket", "1.5", *options)
        named = ", ".join(option for option in options if option.startswith("--"))
        assert simulated.code == 2 and simulated.stderr.startswith(f"rlff: error: {named}: {refusal}"), simulated.stderr
    assert rlff("sim", "throw", str(robot_trajectory), "--basket", "1.5", "--bearing", "0").code == 0  # the basket's


def test_send_refuses_an_approach_speed_without_the_approach_it_paces(rlff, monkeypatch, throw, tmp_path):
    """A robot trajectory is sent from where the arm stands unless --approach plans a move to its
    start: --approach-speed 0.5 alone paced nothing, without a word."""
    assert rlff("robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "t.json")).code == 0
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:9")  # nothing there, should the refusal let it through
    monkeypatch.setenv("ROS_IP", "127.0.0.1")
    result = rlff("robot", "send", str(tmp_path / "t.json"), "--approach-speed", "0.5", "--timeout", "1")
    assert result.code == 2, result.stderr
    said = " ".join(result.stderr.split())
    assert said.startswith(f"rlff: error: --approach-speed paces the move --approach plans to the start of "
                           f"{tmp_path / 't.json'}, a robot trajectory sent as it is: add --approach to move there "
                           "first, or drop --approach-speed"), said
    # with --approach it paces that move: accepted, and the send goes on to look for the ROS master
    sent = rlff("robot", "send", str(tmp_path / "t.json"), "--approach", "--approach-speed", "0.5", "--timeout", "1")
    assert sent.code == 1 and "no ROS master" in sent.stderr, sent.stderr


def test_a_period_in_milliseconds_is_refused_for_a_plan_and_an_approach(rlff, monkeypatch, throw, tmp_path):
    # 10 (ms meant) was planned at a 10 s period: refused as a throw too short to wind up for, and
    # an exported trajectory's approach was planned over 10 s
    said = "--period 10 s is longer than 1 s: a controller period is in seconds (milliseconds? 2 ms is 0.002)"
    exported = rlff("robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "t.json"), "--period", "10")
    assert exported.code == 2 and said in exported.stderr and not (tmp_path / "t.json").exists()
    assert rlff("robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "t.json")).code == 0
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:9")  # nothing there
    monkeypatch.setenv("ROS_IP", "127.0.0.1")
    sent = rlff("robot", "send", str(tmp_path / "t.json"), "--approach", "--period", "10", "--timeout", "1")
    assert sent.code == 2 and said in sent.stderr, sent.stderr


def test_send_takes_a_period_for_the_approach_of_a_robot_trajectory(rlff, monkeypatch, throw, tmp_path):
    """With --approach, --period samples the approach planned to a robot trajectory's start: not refused."""
    assert rlff("robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "t.json")).code == 0
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:9")  # nothing there
    monkeypatch.setenv("ROS_IP", "127.0.0.1")
    result = rlff("robot", "send", str(tmp_path / "t.json"), "--approach", "--period", "0.01", "--timeout", "1")
    assert result.code == 1 and "no ROS master" in result.stderr, result.stderr


@pytest.mark.timeout(60)  # a timeout let through would wait for the absent master
@pytest.mark.parametrize("timeout", ["nan", "0", "-1", "inf"])
def test_send_refuses_a_timeout_that_is_no_time_before_connecting(rlff, monkeypatch, throw, timeout):
    """nan was taken (a warning that it is shorter than the motion, then the goal went out), -1
    blamed the arm's driver after waiting for nothing (exit 1)."""
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:9")  # nothing there
    monkeypatch.setenv("ROS_IP", "127.0.0.1")
    result = rlff("robot", "send", str(throw), "--timeout", timeout)
    assert result.code == 2, result.stderr
    assert result.stderr.startswith(f"rlff: error: --timeout {float(timeout):g}: give a finite number of seconds "
                                    "above 0"), result.stderr
    assert "master" not in result.stderr and len(result.stderr.strip().splitlines()) == 1


def test_bags_stamp_now_only_when_asked(capsys, throw, tmp_path):
    from rosbags.rosbag1 import Reader
    from rosbags.typesys import Stores, get_typestore

    typestore = get_typestore(Stores.ROS1_NOETIC)
    for flags, zero in (((), True), (("--stamp-now",), False)):
        out = tmp_path / f"t{len(flags)}.bag"
        code, _, err = run(capsys, "robot", "export", str(throw), "-f", "ros1-bag", "-o", str(out), *flags)
        assert code == 0, err
        with Reader(out) as reader:
            (connection, _, raw), = reader.messages()
            stamp = typestore.deserialize_ros1(raw, connection.msgtype).header.stamp
        assert (stamp.sec == 0 and stamp.nanosec == 0) == zero


@pytest.mark.parametrize(("suffix", "fmt"), [(".json", "json"), (".csv", "csv"), (".txt", "comau")])
def test_stamp_now_is_refused_for_a_file_without_a_stamp(capsys, throw, tmp_path, suffix, fmt):
    """It was ignored (until 2026-12-07): the file was written as without it."""
    out = tmp_path / f"exported{suffix}"
    code, _, err = run(capsys, "robot", "export", str(throw), "-o", str(out), "--stamp-now")
    assert code == 2, err
    assert err.strip() == (f"rlff: error: --stamp-now sets a ROS bag's header.stamp: a {fmt} file has none, so it "
                           "would change nothing; leave it out, or export a bag (-f ros1-bag or ros2-bag)")
    assert not out.exists()


@pytest.mark.parametrize(("edit", "ratio"), [(lambda t: t.assign(time=t.time * 20), "20 times as long"),
                                             (lambda t: t.assign(velocity=t.velocity * 0.8), "0.8 times as long")])
def test_a_generated_path_whose_time_disagrees_is_refused(capsys, tmp_path, edit, ratio):
    angle = np.linspace(0.7, 1.9, 30)
    velocity = np.linspace(2.0, 9.0, 30)
    path = tmp_path / "timed.csv"
    pd.DataFrame({"angle": angle, "velocity": velocity, "time": time_along_path(angle, velocity)}).to_csv(path, index=False)
    code, _, err = run(capsys, "robot", "export", str(path), "-f", "json", "-o", str(tmp_path / "ok.json"))
    assert code == 0, err
    edit(pd.read_csv(path)).to_csv(path, index=False)
    code, _, err = run(capsys, "robot", "export", str(path), "-f", "json", "-o", str(tmp_path / "bad.json"))
    assert code == 2 and len(err.strip().splitlines()) == 1 and not (tmp_path / "bad.json").exists()
    assert "timed.csv: rows 1 to 2: the time column takes" in err and ratio in err



@pytest.mark.parametrize(("edit", "hint"), [
    (lambda t: t.assign(time=t.time * 1000), "; is the time column in milliseconds? rlff reads seconds: divide it by 1000"),
    (lambda t: t.round(3), "; the file looks rounded to 3 decimals (a spreadsheet?), which explains the disagreement; "
                           "rlff generate writes full precision: generate the path again, or keep full precision where "
                           "it is saved"),
    (lambda t: t.round({"angle": 3, "velocity": 3, "time": 4}), "; the file looks rounded to angle 3, velocity 3, time 4 "
                                                                 "decimals (a spreadsheet?)"),
    (lambda t: t.assign(velocity=t.velocity * 0.8).round(3), None),  # rounding does not explain 0.8
    (lambda t: t.assign(time=t.time * 20), None),
])
def test_a_time_in_milliseconds_or_a_rounded_path_is_named_as_such(capsys, tmp_path, edit, hint):
    """A time column in ms, or a path saved by a spreadsheet at 3 decimals, was refused as time, angle
    and velocity that "do not belong together", with no word of what parted them (until 2026-12-07)."""
    angle = np.linspace(0.7, 1.9, 30)
    velocity = np.linspace(2.0, 9.0, 30)
    path = tmp_path / "timed.csv"
    edit(pd.DataFrame({"angle": angle, "velocity": velocity, "time": time_along_path(angle, velocity)})).to_csv(
        path, index=False)
    code, _, err = run(capsys, "robot", "export", str(path), "-f", "json", "-o", str(tmp_path / "bad.json"))
    assert code == 2 and len(err.strip().splitlines()) == 1 and not (tmp_path / "bad.json").exists()
    said = " ".join(err.split())
    assert "time, angle and velocity do not belong together" in said
    if hint is None:
        assert said.endswith("do not belong together"), said
    else:
        assert f"do not belong together{hint}" in said, said

def test_a_file_of_the_wrong_kind_is_one_line(capsys, tmp_path):
    other = tmp_path / "other.bag"
    other.write_bytes(b"#ROSBAG V2.0\n\x00\x01")
    program = tmp_path / "throw.txt"
    program.write_text('coord_type = "-j"\n')
    folder = tmp_path / "bag2"
    folder.mkdir()
    disguised = tmp_path / "throw.csv"  # a robot trajectory JSON saved as .csv: 50 kB of "columns"
    disguised.write_text('{"format": "rlff-joint-trajectory", "time": [' + ", ".join(["0.002"] * 10000) + "]}\n")
    wide = tmp_path / "wide.csv"
    wide.write_text(",".join(f"column_{i}_" + "x" * 60 for i in range(30)) + "\n")
    cut = tmp_path / "cut.jsonl"  # an attempts log whose header line was cut short
    cut.write_text('{"format":"rlff-attempts","version":1,"run":{"basket":{"dist')
    for command, message in (
            (("robot", "export", str(other), "-f", "json", "-o", str(tmp_path / "o.json")),
             "other.bag is a ROS 1 bag: give a generated path CSV or a robot trajectory JSON/CSV"),
            (("sim", "throw", str(other)), "`rlff robot send` takes the bag itself"),
            (("robot", "export", str(disguised), "-f", "json", "-o", str(tmp_path / "o.json")),
             "throw.csv: holds JSON, not CSV: a robot trajectory JSON needs the .json suffix"),
            (("robot", "export", str(wide), "-f", "json", "-o", str(tmp_path / "o.json")), "... and 22 more"),
            (("robot", "export", str(cut), "-f", "json", "-o", str(tmp_path / "o.json")),
             "cut.jsonl: corrupt attempts log (no complete header line)"),
            (("robot", "export", str(folder), "-f", "json", "-o", str(tmp_path / "o.json")),
             "bag2 is a folder (a ROS 2 bag?)"),
            (("robot", "send", str(other)), "other.bag: not a readable"),  # send reads bags
            (("robot", "send", str(folder)), "bag2: a folder, but not a ROS 2 bag (no metadata.yaml)"),
            (("robot", "send", str(program)), "throw.txt: a Comau program, which runs on the Comau controller"),
            (("sim", "throw", str(program)), "throw.txt is a Comau program (`rlff robot export -f comau` writes it)")):
        code, _, err = run(capsys, *command)
        assert code == 2 and message in err
        assert len(err.strip().splitlines()) == 1 and len(err) < 600


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda t: t.assign(angle=t.angle.to_numpy()[[0, 2, 1, *range(3, 21)]]), "not strictly monotonic at sample 2"),
        (lambda t: t.assign(velocity=[*t.velocity[:5], np.nan, *t.velocity[6:]]), "column 'velocity' row 6"),
        (lambda t: t.drop(columns="velocity"), "missing columns ['velocity']"),
    ],
)
def test_bad_trajectories_are_refused(capsys, throw, tmp_path, edit, message):
    edit(pd.read_csv(throw)).to_csv(throw, index=False)
    code, _, err = run(capsys, "robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "o.json"))
    assert code == 2 and message in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o.json").exists()


def test_robot_file_with_a_missing_limit_is_refused(capsys, throw, tmp_path):
    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    broken = tmp_path / "broken.toml"
    broken.write_text(text.replace("max_velocity = 2.967\n", "\n"))
    code, _, err = run(capsys, "robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "o.json"),
                       "--robot", str(broken))
    assert code == 2 and "broken.toml: joint 3 (joint_3): missing field 'max_velocity'" in err
    code, _, err = run(capsys, "robot", "export", str(throw), "-f", "yaml", "-o", str(tmp_path / "o.yaml"))
    assert code == 2 and "unknown --format 'yaml'" in err


def test_send_refuses_bad_input_before_connecting(rlff, monkeypatch, tmp_path):
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:9")  # nothing there
    monkeypatch.setenv("ROS_IP", "127.0.0.1")
    path = human_csv(tmp_path / "far.csv", np.linspace(2.0, 2.8, 9), np.full(9, 1.0))
    result = rlff("robot", "send", str(path), "--timeout", "1")
    assert result.code == 2
    assert "beyond its limit 2.71 rad" in result.stderr and "master" not in result.stderr
    # the path ending 0.01 rad from the limit at 2.7 rad/s: no room to brake, nothing sent
    edge = human_csv(tmp_path / "edge.csv", np.linspace(1.5, 2.70, 13), np.full(13, 2.7))
    result = rlff("robot", "send", str(edge), "--timeout", "1")
    assert result.code == 2 and "no room to brake after the release" in result.stderr
    assert "master" not in result.stderr


def test_the_format_and_the_output_are_checked_before_any_planning(capsys, tmp_path):
    """A path far beyond joint 2's limits would be refused by the planning; a bad --format, a
    suffix of another format or a folder that is no bag for a ROS 2 bag is refused first, and nothing written."""
    beyond = human_csv(tmp_path / "beyond.csv", np.linspace(-0.5, 4.0, 21), np.full(21, 2.0))
    (tmp_path / "bag").mkdir()
    for args, message in (
            (("-f", "JSON", "-o", str(tmp_path / "t.json")), "unknown --format 'JSON'"),
            (("-f", "json", "-o", str(tmp_path / "t.csv")),
             "t.csv: --format json under the suffix .csv of the csv format"),
            (("-f", "ros2-bag", "-o", str(tmp_path / "bag")), "bag: a folder, and not a ROS 2 bag of robot trajectories"),
            # a ROS 1 bag named .txt read as a Comau program (learn --out x.txt writes one)
            (("-f", "ros1-bag", "-o", str(tmp_path / "x.txt")), "x.txt: --format ros1-bag (binary) under the suffix .txt of the comau format")):
        code, _, err = run(capsys, "robot", "export", str(beyond), *args)
        assert code == 2 and message in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bag", "beyond.csv"]
    code, _, err = run(capsys, "robot", "export", str(beyond), "-f", "json", "-o", str(tmp_path / "t.json"))
    # what the planning says, once the rest is right (its release held at the limit is no throw)
    assert code == 2 and "the ball would not be thrown: the release (joint_2 at 4 rad, beyond its limit 2.71 rad)" in err


def test_live_goals_and_files_each_have_their_period_and_the_help_says_why():
    # send's 0.01 beside the 0.002 of export and learn read as a slip: each help now says which it is and why
    from rlff.cli import _command
    from rlff.learn.robot import PERIOD
    from rlff.trajectory.resample import CONTROLLER_PERIODS

    def period(*names):
        command = _command()
        for name in names:
            command = command.commands[name]
        return next(param for param in command.params if param.name == "period")

    send, export, learn = period("robot", "send"), period("robot", "export"), period("learn")
    assert send.default == PERIOD == CONTROLLER_PERIODS[1]  # a goal of send's as learn's live throws
    assert export.default == learn.default == CONTROLLER_PERIODS[0]
    assert "0.01 for a live goal" in send.help and "the controller interpolates between a goal's points" in send.help
    assert "0.002 for a file" in export.help and "live goals (robot send) are planned at 0.01" in export.help
    assert "the live throws of --executor ros1|ros2 are planned at 0.01" in learn.help


def test_the_approach_speed_option_defaults_to_the_planners_share(rlff, throw, tmp_path):
    from rlff.cli._common import APPROACH_SPEED_OPTION
    from rlff.trajectory.planner import APPROACH_SPEED

    assert APPROACH_SPEED_OPTION.default == APPROACH_SPEED
    for bad in ("0", "1e-06", "1.0000001", "nan", "-0.2"):  # refused before anything connects
        result = rlff("robot", "send", str(throw), "--approach-speed", bad)
        assert result.code == 2 and f"--approach-speed {bad}: the approach speed is a share" in result.stderr


def test_a_release_against_the_paths_direction_is_said_so_not_compared_with_a_limit_of_0(rlff, tmp_path):
    path = tmp_path / "turned.csv"
    velocity = np.full(30, 6.0)
    velocity[-1] = -4.0  # the last sample swings back
    pd.DataFrame({"angle": np.linspace(0.4, 2.2, 30), "velocity": velocity}).to_csv(path, index=False)
    result = rlff("robot", "export", str(path), "-f", "json", "-o", str(tmp_path / "out.json"))
    assert result.code == 2 and "the ball would not be thrown: the release (joint_2 velocity -1 rad/s) moves " \
        "against the path's direction" in result.stderr
    assert "beyond the limit 0" not in result.stderr


def test_a_release_clipping_would_stop_is_no_throw_with_or_without_clip(rlff, monkeypatch, tmp_path):
    """A path generated from uncleaned demonstrations released joint_2 backwards: the refusal offered
    "clip (--clip) stops (0 rad/s)", and with --clip export and send went ahead with exit 0, a
    release at rest; only sim throw said the ball was not thrown."""
    path = tmp_path / "raw.csv"
    velocity = np.linspace(6.0, -5.6, 30)  # the model's velocity crosses 0 before the release
    pd.DataFrame({"angle": np.linspace(0.4, 2.2, 30), "velocity": velocity}).to_csv(path, index=False)
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:9")  # nothing there, should the refusal let it through
    out = tmp_path / "out.json"
    for command in (("robot", "export", str(path), "-o", str(out)), ("robot", "export", str(path), "-o", str(out), "--clip"),
                    ("robot", "export", str(path), "-f", "comau", "-o", str(tmp_path / "o.pdl"), "--clip"),
                    ("robot", "send", str(path), "--clip", "--timeout", "1")):
        result = rlff(*command)
        said = " ".join(result.stderr.split())
        assert result.code == 2 and not out.exists() and not (tmp_path / "o.pdl").exists(), command
        assert ("the ball would not be thrown: the release (joint_2 velocity -1.4 rad/s) moves against the path's "
                "direction, and stopped (0 rad/s) it leaves every driven joint at rest there; a path from uncleaned "
                "demonstrations? clean them (rlff data preprocess --preset thesis)") in said, command
        assert "--clip" not in said and "master" not in said and len(result.stderr.splitlines()) == 1


@pytest.mark.parametrize(("edit", "said"), [
    (("velocity_scale = 0.25", "velocity_scale = 25"),
     "1 value far beyond the robot's limits, a unit or scale slip, not a throw to clip: point 20: joint_2 velocity "
     "200 rad/s at the release, 72 times the limit 2.792 rad/s; check the path's units (rlff reads rad and rad/s, "
     "as rlff generate writes them; read as deg/s, 200 is 3.491 rad/s) and {robot}'s [throwing] mapping (joint_2: "
     "angle_offset -1.65, angle_scale 0.71, velocity_scale 25), through which the path was mapped"),
    (("angle_offset = -1.65", "angle_offset = -94.5"),
     "21 values far beyond the robot's limits, a unit or scale slip, not a throw to clip: point 0: joint_2 position "
     "-93.35 rad, 91.9 rad beyond the limit -1.48 rad;"),
])
def test_a_unit_or_scale_slip_is_refused_with_or_without_clip(rlff, monkeypatch, throw, tmp_path, edit, said):
    """A robot file's velocity_scale 25 for 0.25, or an angle_offset in degrees: the refusal offered
    "clip (--clip) clips it", and with --clip export wrote a throw at the speed limit (exit 0)
    and send sent it. 72 times the limit, or a position 92 rad beyond it, is a slip, not a throw
    for a basket a little beyond reach."""
    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    robot = tmp_path / "slip.toml"
    robot.write_text(text.replace(*edit, 1))
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:9")  # nothing there, should the refusal let it through
    out = tmp_path / "out.json"
    for command in (("robot", "export", str(throw), "-o", str(out)), ("robot", "export", str(throw), "-o", str(out), "--clip"),
                    ("robot", "export", str(throw), "-f", "comau", "-o", str(tmp_path / "o.pdl"), "--clip"),
                    ("robot", "send", str(throw), "--clip", "--timeout", "1")):
        result = rlff(*command, "--robot", str(robot))
        text = " ".join(result.stderr.split())
        assert result.code == 2 and not out.exists() and not (tmp_path / "o.pdl").exists(), command
        assert said.format(robot=robot) in text and "(--clip)" not in text and "master" not in text, command
        assert f"{robot}'s [throwing] mapping" in text and len(result.stderr.splitlines()) == 1



def test_export_takes_the_format_from_the_suffix_as_learn_out_does(capsys, throw, tmp_path):
    # export required --format where learn --out x.json took it from the suffix
    from rlff.learn.replay import SUFFIX_FORMATS

    for suffix, fmt in SUFFIX_FORMATS.items():
        code, out, err = run(capsys, "robot", "export", str(throw), "-o", str(tmp_path / f"t{suffix}"), "--json")
        assert code == 0, err
        assert json.loads(out)["format"] == fmt
    assert read_json(tmp_path / "t.json").positions.shape[1] == 6
    assert list(pd.read_csv(tmp_path / "t.csv").columns)[0] == "time"
    assert (tmp_path / "t.txt").read_text().startswith('coord_type = "-j"')
    assert (tmp_path / "t" / "metadata.yaml").is_file()  # no suffix: a ROS 2 bag folder
    assert (tmp_path / "t.bag").read_bytes().startswith(b"#ROSBAG V2.0")
    # --format still overrides where the suffix names no format, and is refused under another's
    code, out, err = run(capsys, "robot", "export", str(throw), "-f", "comau", "-o", str(tmp_path / "p.prg"), "--json")
    assert code == 0 and json.loads(out)["format"] == "comau", err
    code, _, err = run(capsys, "robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "u.csv"))
    assert code == 2 and "u.csv: --format json under the suffix .csv of the csv format" in err
    code, _, err = run(capsys, "robot", "export", str(throw), "-o", str(tmp_path / "u.dat"))
    assert code == 2 and "u.dat: no export format for the suffix '.dat'" in err and "give --format" in err
    assert not (tmp_path / "u.csv").exists() and not (tmp_path / "u.dat").exists()


def test_show_prints_the_controller_s_joint_map(capsys, tmp_path):
    from rosrig import UR_NAMES, ur_file

    mapped = ur_file(tmp_path / "ur.toml")
    code, out, _ = run(capsys, "robot", "show", "--robot", str(mapped))
    assert code == 0
    assert ("ros joints (goals, joint states, feedback and bags; controller = offset + sign * rlff, rad): joint_1 as "
            "shoulder_pan_joint, joint_2 as shoulder_lift_joint = -1.5708 + joint_2, joint_3 as elbow_joint = 1.5708 + "
            "joint_3, joint_4 as wrist_1_joint, joint_5 as wrist_2_joint = 0.25 - joint_5, joint_6 as wrist_3_joint\n"
            ) in out
    code, out, _ = run(capsys, "robot", "show", "--robot", str(mapped), "--json")
    joints = json.loads(out)["ros"]["joints"]
    assert [joints[f"joint_{k}"]["name"] for k in range(1, 7)] == list(UR_NAMES)
    assert joints["joint_5"] == {"name": "wrist_2_joint", "offset": 0.25, "sign": -1}
    code, out, _ = run(capsys, "robot", "show")  # no map: no line, no key
    assert "ros joints" not in out
    code, out, _ = run(capsys, "robot", "show", "--json")
    assert "joints" not in json.loads(out)["ros"]


def moving_start(document: dict, first: int) -> dict:
    """A robot trajectory JSON ``document`` cut before its point ``first``, time from 0 there: it
    starts where the throw moves."""
    start = document["time"][first]
    cut = {key: document[key][first:] for key in ("positions", "velocities", "accelerations")}
    return document | cut | {"time": [t - start for t in document["time"][first:]],
                             "release_time": document["release_time"] - start}


@pytest.mark.parametrize("fmt", ["json", "csv", "ros1-bag", "comau"])
def test_a_robot_trajectory_that_starts_moving_is_refused_by_every_output(rlff, throw, tmp_path, fmt):
    """A trajectory starting at speed (a tester's joint_2 at 1 rad/s slowing to rest) was written to
    every format, the Comau program's first row at 36 % speed, and simulated, without a word: the
    check looked at the start only where the arm's pose was given."""
    assert rlff("robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "t.json")).code == 0
    document = json.loads((tmp_path / "t.json").read_text())
    first = document["time"].index(document["release_time"]) - 20  # 20 samples before the release, at speed
    (tmp_path / "moving.json").write_text(json.dumps(moving_start(document, first)))
    out = tmp_path / f"out.{fmt}"
    result = rlff("robot", "export", str(tmp_path / "moving.json"), "-f", fmt, "-o", str(out))
    assert result.code == 2 and not out.exists(), result.stderr
    speed = document["velocities"][first][1]
    said = " ".join(result.stderr.split())
    assert (f"moving.json: point 0 (t = 0.000000 s): the trajectory starts with joint_2 velocity {speed:.6g} rad/s, "
            "not at rest (tolerance 0.001 rad/s): a controller starts a trajectory from the arm at rest") in said, said
    assert "rlff robot export plans one from the generated path or attempts log" in said
    if fmt == "json":  # and the simulation, which executed it, refuses it the same way
        simulated = rlff("sim", "throw", str(tmp_path / "moving.json"), "--basket", "1.5")
        assert simulated.code == 2 and "the trajectory starts with joint_2 velocity" in simulated.stderr


def comau_speeds(path) -> np.ndarray:
    """The speed slot (6) of a Comau program's rows (% of the driven joint's maximum)."""
    return np.array([float(line.split(",")[6].strip("')")) for line in path.read_text().splitlines()[1:]])


@pytest.mark.parametrize("suffix", ["json", "csv"])
def test_a_robot_trajectory_is_converted_only_for_the_robot_it_was_planned_for(rlff, tmp_path, suffix):
    """A throw exported for a slow arm and converted without its --robot became a Comau program at
    a share of the built-in Comau's speed (78 % -> 42 % for a tester's arm): the slow arm would have
    thrown at half the planned speed. The file now says whose it is."""
    slow = str(slow_arm(tmp_path))
    path = human_csv(tmp_path / "throw.csv", np.linspace(-0.5, 1.5, 21), np.full(21, 1.2))
    planned = tmp_path / f"slow.{suffix}"
    assert rlff("robot", "export", str(path), "--robot", slow, "-o", str(planned)).code == 0
    result = rlff("robot", "export", str(planned), "-o", str(tmp_path / "comau.txt"))
    assert result.code == 2 and not (tmp_path / "comau.txt").exists()
    said = " ".join(result.stderr.split())
    assert re.search(rf"error: {re.escape(str(planned))} was planned for another robot \(slow_arm, digest [0-9a-f]{{16}} "
                     r"in the file; comau_smart5_six, digest [0-9a-f]{16}, with built-in robot comau_smart5_six\): its "
                     r"limits and speeds are that robot's; give its robot file as robot \(--robot\)", said), said
    simulated = rlff("sim", "throw", str(planned), "--basket", "1.5")
    assert simulated.code == 2 and "was planned for another robot (slow_arm" in simulated.stderr
    assert rlff("robot", "export", str(planned), "--robot", slow, "-o", str(tmp_path / "slow.txt")).code == 0
    assert comau_speeds(tmp_path / "slow.txt").max() == pytest.approx(100 * 1.2 / 1.6, abs=1e-3)  # of its own arm
    # converted for its own robot, the file keeps the record
    again = tmp_path / f"again.{'csv' if suffix == 'json' else 'json'}"
    converted = rlff("robot", "export", str(planned), "--robot", slow, "-o", str(again))
    assert converted.code == 0 and "warning" not in converted.stderr, converted.stderr
    assert rlff("robot", "export", str(again), "-o", str(tmp_path / "again.txt")).code == 2


def test_a_robot_trajectory_that_does_not_say_whose_it_is_is_read_with_a_warning(rlff, throw, tmp_path):
    """Files written before the record (or by hand) keep working, checked against the robot given."""
    assert rlff("robot", "export", str(throw), "-o", str(tmp_path / "t.json")).code == 0
    document = json.loads((tmp_path / "t.json").read_text())
    assert set(document["robot"]) == {"name", "digest"} and document["robot"]["name"] == "comau_smart5_six"
    del document["robot"]
    (tmp_path / "old.json").write_text(json.dumps(document))
    result = rlff("robot", "export", str(tmp_path / "old.json"), "-o", str(tmp_path / "old.txt"))
    assert result.code == 0, result.stderr
    said = " ".join(result.stderr.split())
    assert (f"warning: {tmp_path / 'old.json'} does not say which robot it was planned for (written before rlff "
            "recorded it, by hand or by another tool): checked and converted for comau_smart5_six (built-in robot comau_smart5_six); "
            "if it was planned for another robot, give that robot's file as robot (--robot)") in said, said
    assert rlff("robot", "export", str(throw), "-o", str(tmp_path / "t.csv")).code == 0
    pd.read_csv(tmp_path / "t.csv").drop(columns=["robot", "robot_digest"]).to_csv(tmp_path / "old.csv", index=False)
    result = rlff("sim", "throw", str(tmp_path / "old.csv"), "--basket", "1.5")
    assert result.code == 0 and "old.csv does not say which robot it was planned for" in result.stderr


def test_a_comau_program_is_planned_at_a_controller_period_or_refused(rlff, throw, tmp_path):
    """At --period 0.02 the rows of a program followed 20 ms apart, which its speeds do not time."""
    out = tmp_path / "p.txt"
    result = rlff("robot", "export", str(throw), "-f", "comau", "-o", str(out), "--period", "0.02")
    assert result.code == 2 and not out.exists()
    said = " ".join(result.stderr.split())
    assert (f"{out}: not written: points 0 and 1 are 0.02 s apart" in said and "the Comau program holds no time" in said
            and "as a Comau program with a period (--period) of 0.01 s or less (0.002 by default)" in said), said
    assert rlff("robot", "export", str(throw), "-f", "json", "-o", str(tmp_path / "p.json"), "--period", "0.02").code == 0


def test_clip_slows_a_whole_arm_throw_as_a_whole(rlff, tmp_path):
    """--clip clipped each joint's release on its own (a tester's throw: joint_2 x0.38, joint_3 x0.61,
    joint_5 unchanged), so the ball left in another direction than the model's; the whole throw is
    now slowed by one factor, as the learning loop scales a throw."""
    from rlff.dataset import velocity_column
    from rlff.robot import mapping_for
    from wholearm import human_throw

    joints = ("joint_2", "joint_3", "joint_5")
    mapping = mapping_for(load_robot(), joints)
    path = human_throw(20.0)  # joint_2 asked 4.05 rad/s (limit 2.792), joint_3 3.71 (2.967), joint_5 4.01 (6.545)
    asked = {m.joint: m.scale * path[velocity_column(m.human)][-1] / mapping.time_scale for m in mapping.joints}
    pd.DataFrame(path).to_csv(tmp_path / "fast.csv", index=False)
    result = rlff("robot", "export", str(tmp_path / "fast.csv"), "--joints", ",".join(joints), "--clip", "-o",
                  str(tmp_path / "t.json"))
    assert result.code == 0, result.stderr
    factor = 2.792 / asked["joint_2"]
    assert f"the whole throw slowed to {factor:.3g} of its speed, one factor for every joint" in result.stderr
    traj = read_json(tmp_path / "t.json")
    release = int(np.flatnonzero(traj.time == traj.release_time)[0])
    for name in joints:  # every joint's release the model's times one factor: its direction kept
        assert traj.velocities[release, traj.joint_index(name)] == pytest.approx(factor * asked[name], rel=1e-9), name
    assert "clipped: point 59:" not in result.stderr  # the release, within its limits, is not clipped
    refused = rlff("robot", "export", str(tmp_path / "fast.csv"), "--joints", ",".join(joints), "-o",
                   str(tmp_path / "t.json"))
    assert refused.code == 2 and ("clip (--clip) slows the whole throw, every joint by one factor, until its release is "
                                  "within the speed limits") in " ".join(refused.stderr.split()), refused.stderr


def test_clip_does_not_slow_a_whole_arm_slip_into_a_throw(rlff, tmp_path):
    """A robot file's [whole_arm] time_scale 0.0056 for 0.56 asks joint_2 100 times its speed:
    --clip slowed the whole throw to 0.0094 of its speed and wrote it (exit 0)."""
    from wholearm import human_throw

    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    robot = tmp_path / "slip.toml"
    robot.write_text(text.replace("time_scale = 0.56", "time_scale = 0.0056", 1))
    pd.DataFrame(human_throw(20.0)).to_csv(tmp_path / "fast.csv", index=False)
    result = rlff("robot", "export", str(tmp_path / "fast.csv"), "--joints", "joint_2,joint_3,joint_5", "--clip",
                  "--robot", str(robot), "-o", str(tmp_path / "t.json"))
    said = " ".join(result.stderr.split())
    assert result.code == 2 and not (tmp_path / "t.json").exists(), result.stderr
    assert "far beyond the robot's limits, a unit or scale slip, not a throw to clip: point 59: joint_2 velocity" in said
    assert f"{robot}'s [whole_arm] mapping (" in said and "time_scale 0.0056)" in said and "slowed" not in said


def test_the_one_joint_summary_says_when_the_release_was_clipped(rlff, tmp_path):
    """Listed point by point, the release's clipped speed was among "... and 22 more"."""
    path = human_csv(tmp_path / "fast.csv", np.linspace(-1.0, 0.5, 30), np.linspace(2.9, 3.3, 30))
    result = rlff("robot", "export", str(path), "--clip", "-o", str(tmp_path / "t.json"))
    assert result.code == 0, result.stderr
    said = " ".join(result.stderr.split())
    assert "... and 20 more" in said and "clipped: point 29" not in said
    assert ("clipped 0 positions and 30 velocities at 30 points, the release's among them (joint_2 velocity 3.3 "
            "rad/s -> 2.792 rad/s)") in said, said


def test_a_path_whose_names_a_spreadsheet_put_in_capitals_is_told_what_to_rename(tmp_path):
    # "missing columns ['angle', 'velocity'] (has ANGLE, VELOCITY, TIME)" and nothing more, though
    # the file has them in capitals (rlff.kinds takes it for a generated path by them)
    from rlff.errors import InputError
    from rlff.trajectory.path_csv import read_generated_path

    path = tmp_path / "caps.csv"
    path.write_text("ANGLE, Velocity ,TIME\n0.1,1.0,0.0\n0.2,2.0,0.1\n")
    with pytest.raises(InputError) as refused:
        read_generated_path(path)
    assert str(refused.value) == (
        f"{path}: missing columns ['angle', 'velocity'] (has ANGLE,  Velocity , TIME); rlff reads the names as "
        "rlff generate writes them, lower case without spaces: rename 'ANGLE' to 'angle', ' Velocity ' to 'velocity'")
    path.write_text("angle,speed\n0.1,1.0\n0.2,2.0\n")  # a name of its own: nothing to rename
    with pytest.raises(InputError) as refused:
        read_generated_path(path)
    assert str(refused.value) == f"{path}: missing columns ['velocity'] (has angle, speed)"

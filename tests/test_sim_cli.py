"""``rlff sim throw`` and ``rlff sim reach`` through the real entry point, and rendered frames."""

from __future__ import annotations

import json

import numpy as np
import pytest
from PIL import Image

from generated_paths import generated_path
from rlff.robot import RobotMapping, load_robot
from rlff.robot.plan import plan
from rlff.sim import Basket, simulate_throw


def test_sim_throw_prints_the_outcome_as_json(cli, tmp_path):
    path = generated_path(tmp_path / "traj.csv")
    result = cli("sim", "throw", str(path), "--basket", "1.9", "--json")
    assert result.code == 0, result.stderr
    payload = json.loads(result.stdout)
    assert {"hit", "landing_x", "miss", "release"} <= set(payload)
    assert payload["miss"] == pytest.approx(payload["landing_x"] - 1.9)
    assert abs(payload["landing_x"] - payload["predicted_landing_x"]) < 0.02
    # the same throw planned in the library gives the same numbers: the CLI adds nothing of its own
    robot = load_robot()
    table = np.genfromtxt(path, delimiter=",", names=True)
    mapping = RobotMapping.for_robot(robot)
    planned = plan(mapping, table["angle"], table["velocity"], table["time"]).trajectory
    outcome = simulate_throw(planned, Basket(1.9), robot=robot)
    assert payload["landing_x"] == pytest.approx(outcome.landing_x, abs=1e-9)
    assert payload["hit"] == outcome.hit
    assert payload["release"]["time"] == pytest.approx(planned.release_time, abs=0.002)
    # and lands where the unplanned throw (released at its end) lands, within 2 cm
    unplanned, _ = mapping.to_robot(table["angle"], table["velocity"], table["time"])
    assert abs(simulate_throw(unplanned, Basket(1.9), robot=robot, check_motion=False).landing_x - outcome.landing_x) < 0.02
    # the mapped throw swings joint 2 forward and lets go forward and upward
    release = payload["release"]
    assert release["velocity"][0] > 0 and release["velocity"][2] > 0


def test_a_ball_that_never_comes_down_through_the_rims_height_is_said_to(rlff, tmp_path):
    # a 1.9 m rim above every ball: it read "the ball came down to the 1.9 m rim's height at 1.782 m"
    path = generated_path(tmp_path / "traj.csv")
    high = rlff("sim", "throw", str(path), "--basket", "1.9", "--height", "1.9")
    assert high.code == 0, high.stderr
    assert "the ball never came down through the 1.9 m rim's height; it first touched the" in high.stdout
    assert "came down to the" not in high.stdout
    low = rlff("sim", "throw", str(path), "--basket", "1.9")
    assert "the ball came down to the 0.3 m rim's height at" in low.stdout


def test_a_robot_trajectory_without_a_release_time_is_said_to_drop_the_ball(rlff, tmp_path):
    # let go at its end, at rest: the only warning had blamed the robot file's signs
    exported = tmp_path / "robot.json"
    assert rlff("robot", "export", str(generated_path(tmp_path / "traj.csv")), "-o", str(exported)).code == 0
    document = json.loads(exported.read_text())
    document["release_time"] = None
    exported.write_text(json.dumps(document))
    result = rlff("sim", "throw", str(exported), "--basket", "1.9")
    assert result.code == 0, result.stderr
    assert "holds no release time: the ball is let go at its last point, at rest" in result.stderr
    assert "left the hand backwards" not in result.stderr


def test_an_exported_throw_lands_where_its_generated_path_does(rlff, tmp_path):
    path = generated_path(tmp_path / "traj.csv")
    direct = rlff("sim", "throw", str(path), "--basket", "1.9", "--json")
    assert direct.code == 0, direct.stderr
    for fmt in ("json", "csv"):
        exported = tmp_path / f"robot.{fmt}"
        assert rlff("robot", "export", str(path), "-f", fmt, "-o", str(exported)).code == 0
        again = rlff("sim", "throw", str(exported), "--basket", "1.9", "--json")
        assert again.code == 0, again.stderr
        assert json.loads(again.stdout)["landing_x"] == pytest.approx(json.loads(direct.stdout)["landing_x"], abs=1e-9)


def test_an_exported_throw_at_a_bearing_is_scored_on_its_line(rlff, tmp_path):
    # an export keeps no bearing: sim throw put the basket at 0 deg, and a hit at 60 deg was "1.4 m
    # short, 3.2 m left of the line"
    path = generated_path(tmp_path / "traj.csv")
    direct = rlff("sim", "throw", str(path), "--basket", "1.9", "--bearing", "40", "--json")
    assert direct.code == 0, direct.stderr
    exported = tmp_path / "robot.json"
    assert rlff("robot", "export", str(path), "--bearing", "40", "-f", "json", "-o", str(exported)).code == 0
    again = rlff("sim", "throw", str(exported), "--basket", "1.9", "--json")
    assert again.code == 0, again.stderr
    assert "basket bearing 40 deg, where the trajectory's joint_1 stands at the release" in again.stderr
    for key in ("landing_x", "miss", "lateral"):
        assert json.loads(again.stdout)[key] == pytest.approx(json.loads(direct.stdout)[key], abs=1e-9)
    # a bearing given is taken as given
    aside = rlff("sim", "throw", str(exported), "--basket", "1.9", "--bearing", "0", "--json")
    assert aside.code == 0 and abs(json.loads(aside.stdout)["lateral"]) > 0.5


def test_sim_throw_refuses_bad_input_in_one_line(rlff, tmp_path):
    fast = generated_path(tmp_path / "fast.csv", peak=20.0)
    result = rlff("sim", "throw", str(fast), "--basket", "2.0")
    assert result.code == 2
    assert "joint_2 velocity" in result.stderr and "limit" in result.stderr
    # a basket beyond the reach: where the throw lands is still worth knowing, with a warning
    far = rlff("sim", "throw", str(generated_path(tmp_path / "traj.csv")), "--basket", "3.5", "--json")
    assert far.code == 0, far.stderr
    assert "warning: the basket at 3.5 m is beyond the reach of comau_smart5_six" in far.stderr
    outcome = json.loads(far.stdout)
    assert not outcome["reachable"] and not outcome["hit"] and outcome["miss"] < -1.0


def test_sim_reach_reports_the_reach(rlff):
    result = rlff("sim", "reach", "--json")
    assert result.code == 0, result.stderr
    payload = json.loads(result.stdout)
    assert payload["reach"] == pytest.approx(2.30, abs=0.01)
    assert payload["farthest_basket"] == pytest.approx(payload["reach"] + 0.175 - 0.033)
    text = rlff("sim", "reach").stdout  # plain text (no rich markup): the table name as in the robot file
    assert "throws of the [throwing] mapping" in text and "\\" not in text
    assert "for comparison" not in text
    # beside the whole arm's reach, the one-joint line says it is a comparison
    both = rlff("sim", "reach", "--joints", "joint_2,joint_3").stdout
    assert "for comparison, one joint: throws of the [throwing] mapping (joint_2 alone" in both
    # an opening in centimetres had given "farthest basket 19.768 m"
    wide = rlff("sim", "reach", "--opening", "35")
    assert wide.code == 2 and "--opening 35 m reaches back past the robot" in wide.stderr
    # the basket's own check names its parameter; the command adds the option the user typed
    low = rlff("sim", "reach", "--height", "0.01")
    assert low.code == 2 and "rlff: error: basket rim_height (--height) 0.01 m is no higher than" in low.stderr


def test_sim_reach_of_an_arm_it_cannot_simulate_says_why(rlff, tmp_path):
    # a 7-joint arm got "unknown joint 'joint_1' on robot seven"; sim throw said it needs 6 joints
    lines = ["name = 'seven'"]
    for k in range(1, 8):
        lines += ["[[joints]]", f"name = 'a{k}'", "lower = -2.0", "upper = 2.0", "max_velocity = 1.5",
                  "max_acceleration = 5.0", "max_jerk = 40.0"]
    robot = tmp_path / "seven.toml"
    robot.write_text("\n".join(lines) + "\n")
    result = rlff("sim", "reach", "--robot", str(robot))
    assert result.code == 2 and "cannot be simulated" in result.stderr and "unknown joint" not in result.stderr


def test_sim_reach_throws_with_the_robot_file_s_throwing_joint_unless_told(rlff, tmp_path):
    # a file that throws with joint_3 was given joint_2's reach first (and its farthest basket)
    from importlib import resources

    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    assert text.count('joint = "joint_2"') == 1
    robot = tmp_path / "elbow.toml"
    robot.write_text(text.replace('joint = "joint_2"', 'joint = "joint_3"').replace("joint_3 = -1.373\n", "joint_2 = 0.2\n"))
    default = json.loads(rlff("sim", "reach", "--robot", str(robot), "--json").stdout)
    told = json.loads(rlff("sim", "reach", "--robot", str(robot), "--json", "--joints", "joint_3").stdout)
    assert default["joints"] == ["joint_3"] and default["reach"] == told["reach"]
    assert json.loads(rlff("sim", "reach", "--json").stdout)["joints"] == ["joint_2"]  # the built-in's


@pytest.mark.slow
def test_frames_are_written_as_png_and_gif(tmp_path):
    robot = load_robot()
    table = np.genfromtxt(generated_path(tmp_path / "traj.csv"), delimiter=",", names=True)
    trajectory, _ = RobotMapping.for_robot(robot).to_robot(table["angle"], table["velocity"], table["time"])
    outcome = simulate_throw(trajectory, Basket(1.9), robot=robot, frames_dir=tmp_path / "frames", check_motion=False)
    if not outcome.frames:
        assert any("frames skipped" in note for note in outcome.notes)
        pytest.skip(outcome.notes[0])
    pngs = [p for p in outcome.frames if p.suffix == ".png"]
    gif = outcome.frames[-1]
    assert gif.suffix == ".gif" and gif.is_file()
    # about 30 frames per simulated second
    assert abs(len(pngs) - 30 * outcome.simulated_time) <= 3
    with Image.open(gif) as animation:  # Pillow merges identical frames (the arm at rest)
        assert len(pngs) / 2 < animation.n_frames <= len(pngs)
    with Image.open(pngs[len(pngs) // 2]) as picture:
        pixels = np.asarray(picture.convert("RGB"), dtype=float)
    assert pixels.shape == (360, 480, 3)
    assert pixels.std() > 10  # a picture, not a blank


@pytest.mark.parametrize(("backend", "message"), [
    ("bogus", "MUJOCO_GL='bogus' is no backend MuJoCo knows (egl, osmesa, glfw)"),
    ("osmesa", "MUJOCO_GL=osmesa: libOSMesa is not installed"),
])
def test_a_mujoco_gl_that_cannot_load_is_one_line(tmp_path, backend, message):
    # MuJoCo's import failed with "internal error: AttributeError: 'NoneType' object has no
    # attribute 'glGetError'", and every throw with it, frames or not
    import ctypes.util
    import os
    import subprocess
    import sys

    if backend == "osmesa" and ctypes.util.find_library("OSMesa"):
        pytest.skip("libOSMesa is installed here: the backend loads")
    path = generated_path(tmp_path / "traj.csv")
    done = subprocess.run([sys.executable, "-m", "rlff", "sim", "throw", str(path), "--basket", "1.9"],
                          env={**os.environ, "MUJOCO_GL": backend}, capture_output=True, text=True, timeout=300)
    assert done.returncode == 2
    (line,) = done.stderr.strip().splitlines()
    assert line.startswith(f"rlff: error: {message}")

"""Where the arm's links are (rlff.robot.links): the chain agrees with the MuJoCo scene, and no
planned or sent motion takes a link into the plane the base stands on."""

from __future__ import annotations

from importlib import resources

import mujoco
import numpy as np
import pandas as pd
import pytest

from rlff.robot import RobotMapping, load_robot
from rlff.robot.links import FLOOR_CLEARANCE, chain_points, require_above_base
from rlff.robot.plan import plan
from rlff.sim.arm import Arm
from rlff.sim.basket import Basket
from rlff.sim.scene import build_scene
from rlff.trajectory.check import MotionLimitError
from rlff.trajectory.joint import JointTrajectory

ROBOT = load_robot()


def test_the_chain_is_where_the_mujoco_scene_puts_the_links():
    scene = build_scene(Arm.from_robot(ROBOT), Basket(2.0))
    data = mujoco.MjData(scene.model)
    poses = np.random.default_rng(3).uniform(-2.5, 2.5, (40, 6))  # every joint, joint 4's roll too
    points = chain_points(ROBOT.geometry, poses)
    for row, pose in enumerate(poses):
        data.qpos[scene.joint_qpos] = pose
        mujoco.mj_kinematics(scene.model, data)
        for body, name in (("link_2", "shoulder"), ("link_3", "elbow"), ("link_5", "wrist")):
            np.testing.assert_allclose(points[name][row], data.body(body).xpos, atol=1e-12)
        np.testing.assert_allclose(points["flange"][row], data.site_xpos[scene.flange_site], atol=1e-12)


def _joint_2_sweep(upper: float) -> JointTrajectory:
    """The start pose with joint_2 swept from 0 to ``upper`` (rad) over 1 s."""
    mapping = RobotMapping.for_robot(ROBOT)
    positions = np.tile(mapping.pose(), (101, 1))
    positions[:, 1] = np.linspace(0.0, upper, 101)
    return JointTrajectory(ROBOT.joint_names, np.linspace(0.0, 1.0, 101), positions, np.zeros_like(positions))


def test_a_motion_into_the_floor_is_refused_naming_the_link_and_the_moment():
    require_above_base(ROBOT, _joint_2_sweep(1.0))  # tilted forward 57 deg: the hand stays high
    with pytest.raises(MotionLimitError) as refused:
        require_above_base(ROBOT, _joint_2_sweep(2.5), "the sweep")
    text = str(refused.value)
    assert text.startswith("the sweep takes the arm's flange ") and " below the plane its base stands on" in text
    assert "t = 1.000 s" in text and "joint_2 2.5" in text and "[geometry]" in text


def test_the_shipped_robots_throws_stay_clear_of_the_floor():
    mapping = RobotMapping.for_robot(ROBOT)
    for top in (1.6, 2.0, 2.4):  # slow to fast releases; each brakes forward after its release
        angle = np.linspace(0.4, top, 40)
        velocity = 2.0 + 10.0 * np.sin(np.linspace(0.0, np.pi / 2, 40))
        planned = plan(mapping, angle, velocity, clip=True).trajectory
        heights = chain_points(ROBOT.geometry, planned.positions)["flange"][:, 2]
        assert heights.min() > FLOOR_CLEARANCE


@pytest.fixture
def lowered(tmp_path):
    """A robot file whose throwing table sends joint_2 forward past 2.4 rad, and a slow generated
    throw that goes there: the forearm points at the floor."""
    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    robot = tmp_path / "lowered.toml"
    robot.write_text(text.replace("angle_offset = -1.65", "angle_offset = 0.9"))
    path = tmp_path / "throw.csv"
    pd.DataFrame({"angle": np.linspace(1.0, 2.2, 30), "velocity": np.full(30, 2.0)}).to_csv(path, index=False)
    return robot, path


def test_export_and_the_simulation_refuse_a_throw_into_the_floor(rlff, lowered, tmp_path):
    robot, path = lowered
    for command in (("robot", "export", str(path), "-f", "json", "-o", str(tmp_path / "out.json")),
                    ("sim", "throw", str(path), "--basket", "1.5")):
        result = rlff(*command, "--robot", str(robot))
        assert result.code == 2, result.stderr
        assert "below the plane its base stands on" in result.stderr and result.stderr.count("\n") == 1
    assert not (tmp_path / "out.json").exists()


def test_send_refuses_an_exported_trajectory_into_the_floor_before_connecting(rlff, monkeypatch, tmp_path):
    from rlff.robot.export import write_json

    write_json(_into_the_floor(), tmp_path / "low.json")  # as another tool could write it
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:9")  # nothing there, should the refusal let it through
    result = rlff("robot", "send", str(tmp_path / "low.json"), "--timeout", "1")
    assert result.code == 2, result.stderr
    assert "low.json: the trajectory takes the arm's flange" in result.stderr


def _into_the_floor() -> JointTrajectory:
    """joint_2 from upright to 2.5 rad forward, within every joint limit: the forearm meets the floor."""
    from rlff.trajectory import plan_transition

    start = RobotMapping.for_robot(ROBOT).pose()
    target, rest = start.copy(), np.zeros(6)
    start[1], target[1] = 0.0, 2.5
    return plan_transition(start, rest, rest, target, rest, ROBOT.joints)


def test_a_simulated_arm_that_strikes_the_ground_says_its_outcome_is_not_the_plans():
    from rlff.sim import simulate_throw

    struck = simulate_throw(_into_the_floor(), Basket(2.0), robot=ROBOT, check_reach=False)
    assert not struck.followed and struck.tracking_error > 0.5
    assert struck.notes[-1].startswith("the simulated arm did not follow its trajectory: up to ")
    mapping = RobotMapping.for_robot(ROBOT)
    free = plan(mapping, np.linspace(0.4, 2.2, 40), 2.0 + 8.0 * np.sin(np.linspace(0.0, np.pi / 2, 40))).trajectory
    thrown = simulate_throw(free, Basket(2.0), robot=ROBOT, check_reach=False)
    assert thrown.followed and thrown.tracking_error < 0.01 and not thrown.notes


def test_the_learning_loop_stops_rather_than_learn_from_a_throw_its_arm_did_not_make():
    from rlff.errors import InputError
    from rlff.learn.loop import _simulator

    with pytest.raises(InputError, match="did not follow its trajectory.*; the run stops"):
        _simulator(ROBOT, Basket(2.0), 0.0)(_into_the_floor())


def test_sim_throw_warns_of_a_ball_that_leaves_backwards(rlff, tmp_path):
    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    robot = tmp_path / "backwards.toml"
    robot.write_text(text.replace("angle_offset = -1.65", "angle_offset = 1.65")
                     .replace("angle_scale = 0.71", "angle_scale = -0.71")
                     .replace("velocity_scale = 0.25", "velocity_scale = -0.25"))
    path = tmp_path / "throw.csv"
    pd.DataFrame({"angle": np.linspace(0.4, 2.2, 40),
                  "velocity": 2.0 + 8.0 * np.sin(np.linspace(0.0, np.pi / 2, 40))}).to_csv(path, index=False)
    result = rlff("sim", "throw", str(path), "--basket", "1.5", "--robot", str(robot))
    assert result.code == 0, result.stderr
    assert "warning: the ball left the hand backwards" in result.stderr and "[throwing] angle_scale" in result.stderr
    assert "backwards" not in rlff("sim", "throw", str(path), "--basket", "1.5").stderr


def test_a_trajectory_of_some_joints_is_checked_with_the_others_held():
    """A controller holds the joints a goal leaves out: where they are (the arm's pose for a
    send) decides where the links go (a re-tester's joint_2-only goal reached 0.25 m below)."""
    alone = _into_the_floor().select(["joint_2"])
    with pytest.raises(MotionLimitError, match="flange .* below the plane"):
        require_above_base(ROBOT, alone)  # the others at the start pose
    upright = np.zeros(6)  # forearm forward instead of up: at 2.5 rad still into the floor
    with pytest.raises(MotionLimitError, match="below the plane"):
        require_above_base(ROBOT, alone, held=upright)
    low = _joint_2_sweep(1.5).select(["joint_2"])  # upper arm horizontal: clear with the forearm up,
    require_above_base(ROBOT, low)
    straight = RobotMapping.for_robot(ROBOT).pose()
    straight[2] = 0.0  # not with the forearm straight on, which then points at the floor
    with pytest.raises(MotionLimitError, match="flange .* below the plane"):
        require_above_base(ROBOT, low, held=straight)


def test_send_checks_a_partial_trajectory_with_the_joints_it_leaves_out_held(rlff, monkeypatch, tmp_path):
    from rlff.robot.export import write_json

    write_json(_into_the_floor().select(["joint_2"]), tmp_path / "low.json")
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:9")  # nothing there, should the refusal let it through
    result = rlff("robot", "send", str(tmp_path / "low.json"), "--timeout", "1")
    assert result.code == 2 and "low.json: the trajectory takes the arm's flange" in result.stderr

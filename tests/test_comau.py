"""The Comau text program of thesis 4.4 against a hand-computed file."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rlff.errors import InputError
from rlff.robot import Robot, RobotMapping, load_robot, mapping_for
from rlff.robot.comau import comau_rows, joints_left_out, write_comau_program
from rlff.trajectory import JointTrajectory

EXPECTED = Path(__file__).parent / "data" / "comau_program_expected.txt"
START = {"joint_1": 0.0, "joint_3": -0.5, "joint_4": 0.0, "joint_5": np.pi / 2, "joint_6": 0.0}


def known_trajectory() -> tuple[JointTrajectory, RobotMapping]:
    """joint_2 at -1, 0, 0.5 rad moving at 0, 1.396 (half of its 2.792 rad/s) and 2.792 rad/s."""
    mapping = RobotMapping(load_robot(), "joint_2", START, 0.0, 1.0, 1.0)
    positions = np.tile(mapping.pose(), (3, 1))
    positions[:, 1] = [-1.0, 0.0, 0.5]
    velocities = np.zeros((3, 6))
    velocities[:, 1] = [0.0, 1.396, 2.792]
    return JointTrajectory(load_robot().joint_names, [0.0, 0.9, 1.2], positions, velocities), mapping


def test_program_matches_the_hand_computed_file(tmp_path):
    # By hand: -1 rad = -57.2958 deg (slot 2 holds joint_2's start, slot 3 its position),
    # 0.5 rad = 28.6479 deg, pi/2 = 90 deg for joint_5, and the speed slot 6 holds
    # 100 * |v| / 2.792: 0, 50 and 100 %.
    traj, mapping = known_trajectory()
    out = tmp_path / "throw.txt"
    write_comau_program(traj, mapping, out)
    assert out.read_text() == EXPECTED.read_text()


def test_rows_are_in_degrees_and_percent():
    traj, mapping = known_trajectory()
    rows = comau_rows(traj, mapping)
    np.testing.assert_allclose(rows[:, 2], np.degrees([-1.0, 0.0, 0.5]))
    np.testing.assert_allclose(rows[:, 5], [0.0, 50.0, 100.0])
    np.testing.assert_allclose(rows[:, [0, 3, 4]], [[0.0, 0.0, 90.0]] * 3)


def test_moving_backwards_gives_a_positive_percentage():
    traj, mapping = known_trajectory()
    backwards = JointTrajectory(traj.joint_names, traj.time, traj.positions[::-1], -traj.velocities[::-1])
    np.testing.assert_allclose(comau_rows(backwards, mapping)[:, 5], [100.0, 50.0, 0.0])


def test_bad_layouts_are_refused():
    traj, mapping = known_trajectory()
    robot = mapping.robot
    same = Robot(robot.name, robot.joints, robot.geometry, robot.throwing,
                 {"position_slot": 6, "velocity_slot": 6}, "same.toml")
    with pytest.raises(InputError, match="position_slot and velocity_slot are both 6"):
        comau_rows(traj, RobotMapping(same, "joint_2", START, 0.0, 1.0, 1.0))
    wrong = Robot(robot.name, robot.joints, robot.geometry, robot.throwing, {"position_slot": 7}, "wrong.toml")
    with pytest.raises(InputError, match="position_slot must be a slot number 1..6, got 7"):
        comau_rows(traj, RobotMapping(wrong, "joint_2", START, 0.0, 1.0, 1.0))
    five = Robot("five", robot.joints[:5], None, {}, {}, "five.toml")
    pose = {k: v for k, v in START.items() if k != "joint_6"}
    with pytest.raises(InputError, match="six slots; robot five has 5 joints"):
        comau_rows(traj.select(five.joint_names), RobotMapping(five, "joint_2", pose, 0.0, 1.0, 1.0))


def test_a_trajectory_moving_a_joint_the_program_cannot_carry_is_refused():
    traj, mapping = known_trajectory()
    positions = traj.positions.copy()
    positions[:, 0] = [0.0, 0.1, 0.2]
    moving = JointTrajectory(traj.joint_names, traj.time, positions, traj.velocities)
    with pytest.raises(InputError, match="carries the motion of joint_2 only; this trajectory also moves joint_1"):
        comau_rows(moving, mapping)


def test_the_joints_the_program_leaves_out_are_named_with_their_start_pose():
    robot = load_robot()
    one = mapping_for(robot)  # joint_2 in slot 3: joint_3's own slot; slot 6 the speed
    assert joints_left_out(one) == (
        "the Comau program holds in slot 3 joint_2's position and slot 6 its speed: joint_3 (start pose "
        f"{np.degrees(one.start_pose['joint_3']):.4g} deg) and joint_6 (start pose 0 deg) are in no slot and stay "
        "where the main program placed the arm")
    whole = mapping_for(robot, ("joint_2", "joint_3"))  # every joint in its own slot but the speed's
    assert joints_left_out(whole).startswith("the Comau program holds in slot 6 its speed: joint_6 (start pose ")
    assert "joint_3" not in joints_left_out(whole)


def test_points_further_apart_than_a_controller_period_are_no_program(tmp_path):
    """The program holds no time: a tester's two points at rest 2 rad and 10 s apart (a motion the
    check passes, the quintic between them within every limit) became two rows at speed 0."""
    from rlff.robot.comau import MAX_ROW_STEP
    from rlff.robot.formats import export_trajectory

    mapping = mapping_for(load_robot())
    positions = np.tile(mapping.pose(-1.2), (2, 1))
    positions[1, 1] += 2.0
    sparse = JointTrajectory(mapping.robot.joint_names, [0.0, 10.0], positions, np.zeros_like(positions))
    out = tmp_path / "two.txt"
    with pytest.raises(InputError, match=r"two.txt: not written: points 0 and 1 are 10 s apart \(t = 0 to 10 s; 1 of "
                                         r"1 steps longer than 0.01 s\): the Comau program holds no time, the "
                                         r"controller moves from row to row at each row's speed"):
        export_trajectory(sparse, mapping, "comau", out)
    assert not out.exists()
    export_trajectory(sparse, mapping, "json", tmp_path / "two.json")  # a controller's quintic times it
    # the same motion at the longest controller period is a program
    time = np.arange(0.0, 10.0 + 1e-9, MAX_ROW_STEP)
    s = time / 10.0
    dense = np.tile(mapping.pose(-1.2), (time.size, 1))
    dense[:, 1] += 2.0 * (10 * s**3 - 15 * s**4 + 6 * s**5)
    velocities, accelerations = np.zeros_like(dense), np.zeros_like(dense)
    velocities[:, 1] = 2.0 * (30 * s**2 - 60 * s**3 + 30 * s**4) / 10.0
    accelerations[:, 1] = 2.0 * (60 * s - 180 * s**2 + 120 * s**3) / 100.0
    export_trajectory(JointTrajectory(sparse.joint_names, time, dense, velocities, accelerations), mapping, "comau", out)
    assert len(out.read_text().splitlines()) == 1 + time.size

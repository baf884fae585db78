"""``--clip`` of a throw that crosses a position limit at speed, measured in what ``robot export``
writes and what ``sim throw`` simulates (``robot send``: tests/test_robot_clip_send.py).

The throw (tests/lowarm.py) goes 0.2 rad past joint_2's upper limit at 2 rad/s. Clipped, the
joint is held at the limit: the planner brings it to rest there within the acceleration and jerk
limits. It came to rest exactly on the limit before, where a controller's software limit trips,
and the simulated servo stood 8.5 urad past it at the release.
"""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from lowarm import INSIDE, SPEED, UPPER, low_arm_files
from rlff.robot import load_robot
from rlff.robot.export import read_json
from rlff.trajectory import limits
from rlff.trajectory.check import check_trajectory


@pytest.fixture
def low_arm(tmp_path):
    return low_arm_files(tmp_path)


def inside_by(robot, margin: float):
    """``robot``'s joints with every position limit ``margin`` rad further in."""
    return [replace(joint, lower=joint.lower + margin, upper=joint.upper - margin) for joint in robot.joints]


def test_export_brings_a_clipped_joint_to_rest_inside_its_limit(rlff, low_arm, tmp_path):
    robot_file, throw = low_arm
    robot = load_robot(robot_file)
    out = tmp_path / "clipped.json"
    result = rlff("robot", "export", str(throw), "--robot", str(robot_file), "--clip", "-o", str(out))
    assert result.code == 0, result.stderr
    written = read_json(out)
    joint = written.joint_index("joint_2")
    q, v, a = (values[:, joint] for values in (written.positions, written.velocities, written.accelerations))
    # held inside the limit the whole way: at every sample and on the controller's quintic between
    check_trajectory(written, inside_by(robot, INSIDE))
    assert UPPER - q.max() == pytest.approx(limits.CLIP_CLEARANCE, abs=1e-9)
    # at rest there, braked within the limits: no step at the clip point
    assert q[-1] == pytest.approx(UPPER - limits.CLIP_CLEARANCE, abs=1e-12) and v[-1] == 0 and a[-1] == 0
    limit = robot.joint("joint_2").max_acceleration
    assert np.abs(v).max() <= SPEED and np.abs(a).max() <= limit
    assert np.abs(np.diff(v) / np.diff(written.time)).max() <= limit
    assert f"clipped: point 27: joint_2 position 1.35 rad -> {UPPER - limits.CLIP_CLEARANCE:g} rad" in result.stderr


def test_the_simulated_arm_releases_a_clipped_throw_inside_the_limit(rlff, low_arm):
    robot_file, throw = low_arm
    result = rlff("sim", "throw", str(throw), "--robot", str(robot_file), "--clip", "--basket", "1.5", "--json")
    assert result.code == 0, result.stderr
    released = json.loads(result.stdout)["release"]["joint_positions"]["joint_2"]
    assert UPPER - released > INSIDE  # it was 8.5 urad past the limit
    assert UPPER - released == pytest.approx(limits.CLIP_CLEARANCE, abs=1e-3)  # the servo's own error


def test_sim_throw_says_a_release_held_at_a_limit_lets_the_ball_go_at_rest(rlff, low_arm):
    """The clipped release stands still: the only warning had blamed the robot file's signs for a
    ball leaving "backwards" at the servo's 0.01 m/s."""
    robot_file, throw = low_arm
    result = rlff("sim", "throw", str(throw), "--robot", str(robot_file), "--clip", "--basket", "1.5")
    assert result.code == 0, result.stderr
    said = " ".join(result.stderr.split())
    assert (f"warning: {throw}: every joint is at rest at the release (--clip held joint_2 inside a position limit "
            "there): the ball is let go at rest, not thrown") in said
    assert "backwards" not in said and "angle_scale" not in said


def test_without_clip_the_positions_beyond_the_limit_are_named_not_the_held_velocities(rlff, low_arm, tmp_path):
    """A held joint's velocity is set to 0 because its position is clipped: no limit of its own. It
    counted as a fifth value "the robot would not execute", said as one that "moves it against the
    path's direction", and the held velocities before the release as "velocities beyond a limit"."""
    robot_file, throw = low_arm
    result = rlff("robot", "export", str(throw), "--robot", str(robot_file), "-o", str(tmp_path / "o.json"))
    assert result.code == 2 and not (tmp_path / "o.json").exists()
    said = " ".join(result.stderr.split())
    assert ("4 values the robot would not execute as asked: point 27: joint_2 position 1.35 rad beyond the limit "
            "1.3 rad; point 28: joint_2 position 1.4 rad beyond the limit 1.3 rad; point 29: joint_2 position 1.45 "
            "rad beyond the limit 1.3 rad (and 1 more); clip (--clip) clips them") in said
    assert "velocit" not in said


def test_from_python_the_refusal_names_the_clip_argument_beside_the_option(low_arm):
    """plan() without clip said "--clip clips them" to a Python caller, whose argument is clip=True."""
    from rlff.errors import InputError
    from rlff.robot.plan import load_for_robot

    robot_file, throw = low_arm
    with pytest.raises(InputError, match=r"\(and 1 more\); clip \(--clip\) clips them$"):
        load_for_robot(throw, load_robot(robot_file))


def test_plan_names_a_release_speed_in_degrees_not_the_clip():
    """plan() of velocities in deg/s said "clip (--clip) clips it" of 136 rad/s against a limit of
    2.79: a unit slip. A speed beyond the limit that rad/s would not explain still gets the clip."""
    from rlff.errors import InputError
    from rlff.robot import RobotMapping
    from rlff.robot.plan import plan

    mapping = RobotMapping.for_robot(load_robot())
    limit = mapping.robot.joint(mapping.joint).max_velocity
    angle = np.linspace(0.4, 2.2, 30)
    in_degrees = np.degrees(np.linspace(0.5, 0.85 * limit, 30) / mapping.velocity_scale)
    with pytest.raises(InputError, match=r"\(the release\); the path's velocities look like deg/s, not rad/s "
                                         r"\(49 times the limit; as deg/s 2\.373 rad/s, within it\): rlff reads rad "
                                         r"and rad/s, .* rather than clip \(--clip\) them$"):
        plan(mapping, angle, in_degrees)
    velocity = np.linspace(0.5, 1.5 * limit, 30) / mapping.velocity_scale  # a release a little fast
    with pytest.raises(InputError, match=r"\(the release\); clip \(--clip\) clips it") as refused:
        plan(mapping, angle, velocity)
    assert "deg/s" not in str(refused.value)
    # beyond its limit even as deg/s, 70 times it: a slip too (it was offered the clip), not said to be within it
    velocity = np.linspace(0.5, 70 * limit, 30) / mapping.velocity_scale
    with pytest.raises(InputError, match=r"a unit or scale slip, not a throw to clip: point 29: joint_2 velocity "
                                         r"195\.44 rad/s at the release, 70 times the limit") as refused:
        plan(mapping, angle, velocity)
    assert "look like deg/s" not in str(refused.value) and "clip (--clip)" not in str(refused.value)


def test_plan_with_clip_of_the_learning_loop_saturates_what_a_file_s_plan_refuses(tmp_path):
    """plan_path with clip is the learning loop's: its proposals saturate at the limits, never
    refused; a file's path (load_for_robot) is refused a slip with clip too."""
    from importlib import resources

    from rlff.errors import InputError
    from rlff.robot import RobotMapping
    from rlff.robot.plan import load_for_robot, plan_path

    text = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    slip = tmp_path / "slip.toml"
    slip.write_text(text.replace("velocity_scale = 0.25", "velocity_scale = 25", 1))
    robot = load_robot(slip)
    path = {"angle": np.linspace(1.0, 3.0, 30), "velocity": np.full(30, 8.0)}
    planned = plan_path(RobotMapping.for_robot(robot), path, clip=True)
    assert planned.clipped_points and planned.points.velocities[-1, 1] == pytest.approx(2.792)
    throw = tmp_path / "throw.csv"
    pd.DataFrame(path).to_csv(throw, index=False)
    with pytest.raises(InputError, match=r"a unit or scale slip, not a throw to clip: point 29: joint_2 velocity "
                                         r"200 rad/s at the release, 72 times the limit 2\.792 rad/s; .*slip\.toml's "
                                         r"\[throwing\] mapping \(joint_2: angle_offset -1\.65, angle_scale 0\.71, "
                                         r"velocity_scale 25\), through which the path was mapped$"):
        load_for_robot(throw, robot, clip=True)


def test_a_plan_prints_as_one_short_line_not_its_arrays(low_arm):
    """The dataclass' own repr printed every array of both trajectories: kilobytes for one throw."""
    from rlff.robot.plan import load_for_robot

    robot_file, throw = low_arm
    _, planned = load_for_robot(throw, load_robot(robot_file), clip=True)
    traj = planned.trajectory
    assert repr(planned) == (f"RobotPlan({len(traj)} points, {traj.duration:.3f} s, release at {traj.release_time:.3f} "
                             "s, joints=['joint_1', 'joint_2', 'joint_3', 'joint_4', 'joint_5', 'joint_6'], from 31 "
                             f"mapped points, clipped={len(planned.clipped_points.changes)})")
    assert len(planned.clipped_points.changes) > 0 and "\n" not in repr(planned)

"""``--clip`` of a throw that crosses a position limit at speed, measured in what ``robot export``
writes and what ``sim throw`` simulates (``robot send``: tests/test_robot_clip_send.py).

Clipped, a joint is held inside the limit: the planner brings it to rest there within the
acceleration and jerk limits. It came to rest exactly on the limit before, where a controller's
software limit trips, and the simulated servo stood 8.5 urad past it at the release. A release
held there is no throw (tests/lowarm.py's throw 0.2 rad past joint_2's upper limit at 2 rad/s):
refused with or without ``--clip`` since 2026-12-07 (exported with exit 0 before, and ``sim
throw`` warned that the ball was let go at rest); the windup 0.2 rad below a lower limit is held
there and still throws.
"""

from __future__ import annotations

import json
import re
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from lowarm import BEYOND, INSIDE, LOWER, SPEED, UPPER, low_arm_files, windup_arm_files
from rlff.errors import InputError
from rlff.learn.replay import load_for_send
from rlff.robot import load_robot
from rlff.robot.export import read_json
from rlff.trajectory import limits
from rlff.trajectory.check import check_trajectory


@pytest.fixture
def low_arm(tmp_path):
    return low_arm_files(tmp_path)


@pytest.fixture
def windup_arm(tmp_path):
    return windup_arm_files(tmp_path)


def inside_by(robot, margin: float):
    """``robot``'s joints with every position limit ``margin`` rad further in."""
    return [replace(joint, lower=joint.lower + margin, upper=joint.upper - margin) for joint in robot.joints]


#: The refusal of tests/lowarm.py's throw, whose release clipping holds at joint_2's upper limit.
HELD = (f"the ball would not be thrown: the release (joint_2 at {UPPER + BEYOND:g} rad, beyond its limit {UPPER:g} "
        "rad) is beyond a position limit, where clipping would hold it at rest with every driven joint; throw for "
        "a nearer basket (rlff sim reach says how far the arm throws), or give a robot file whose range covers "
        "the release (check ")


def test_export_brings_a_clipped_joint_to_rest_inside_its_limit(rlff, windup_arm, tmp_path):
    robot_file, throw = windup_arm
    robot = load_robot(robot_file)
    out = tmp_path / "clipped.json"
    result = rlff("robot", "export", str(throw), "--robot", str(robot_file), "--clip", "-o", str(out))
    assert result.code == 0, result.stderr
    written = read_json(out)
    joint = written.joint_index("joint_2")
    q, v, a = (values[:, joint] for values in (written.positions, written.velocities, written.accelerations))
    # held inside the limit the whole way: at every sample and on the controller's quintic between
    check_trajectory(written, inside_by(robot, INSIDE))
    assert q.min() - LOWER == pytest.approx(limits.CLIP_CLEARANCE, abs=1e-9)
    # at rest there, leaving it within the limits: no step at the clip point
    assert q[0] == pytest.approx(LOWER + limits.CLIP_CLEARANCE, abs=1e-12) and v[0] == 0 and a[0] == 0
    limit = robot.joint("joint_2").max_acceleration
    assert np.abs(v).max() <= SPEED and np.abs(a).max() <= limit
    assert np.abs(np.diff(v) / np.diff(written.time)).max() <= limit
    assert f"clipped: point 0: joint_2 position -0.7 rad -> {LOWER + limits.CLIP_CLEARANCE:g} rad" in result.stderr
    # and it throws: the release moves, as the path asked
    release = int(np.argmin(np.abs(written.time - written.release_time)))
    assert v[release] == pytest.approx(SPEED)


def test_the_simulated_arm_holds_a_clipped_windup_inside_the_limit_and_throws(rlff, windup_arm):
    robot_file, throw = windup_arm
    result = rlff("sim", "throw", str(throw), "--robot", str(robot_file), "--clip", "--basket", "1.5", "--json")
    assert result.code == 0, result.stderr
    outcome = json.loads(result.stdout)
    # the servo follows the planned trajectory, held CLIP_CLEARANCE inside the limit, to within its
    # own error (INSIDE is more than twice it): it stays more than INSIDE inside the limit
    assert outcome["tracking_error"] <= INSIDE / 2
    assert limits.CLIP_CLEARANCE - outcome["tracking_error"] > INSIDE
    assert outcome["release"]["speed"] > 0 and "at rest" not in result.stderr


@pytest.mark.parametrize("clip", [["--clip"], []])
def test_a_release_held_at_a_limit_is_no_throw_with_or_without_clip(rlff, low_arm, tmp_path, clip):
    """Clipped, the release stood still at the limit: export wrote it with exit 0 (and a file a
    robot trajectory refuses when read back), and sim throw warned that the ball was let go at rest;
    without --clip the refusal offered the clip."""
    robot_file, throw = low_arm
    out = tmp_path / "o.json"
    for command in (("robot", "export", str(throw), "-o", str(out)), ("sim", "throw", str(throw), "--basket", "1.5")):
        result = rlff(*command, "--robot", str(robot_file), *clip)
        assert result.code == 2 and not out.exists(), result.stderr
        said = " ".join(result.stderr.split())
        assert len(result.stderr.strip().splitlines()) == 1 and HELD in said, said
        assert f"{robot_file}'s [throwing] mapping (joint_2: angle_offset -1.65, angle_scale 0.71" in said
        assert "clip (--clip)" not in said and "uncleaned" not in said
    with pytest.raises(InputError, match=rf"^{re.escape(f'{throw}: {HELD}')}"):
        load_for_send(throw, load_robot(robot_file), clip=bool(clip))  # rlff robot send's reading


def test_without_clip_the_positions_beyond_the_limit_are_named_not_the_held_velocities(rlff, windup_arm, tmp_path):
    """A held joint's velocity is set to 0 because its position is clipped: no limit of its own. It
    counted as a fifth value "the robot would not execute", said as one that "moves it against the
    path's direction", and the held velocities before the release as "velocities beyond a limit"."""
    robot_file, throw = windup_arm
    result = rlff("robot", "export", str(throw), "--robot", str(robot_file), "-o", str(tmp_path / "o.json"))
    assert result.code == 2 and not (tmp_path / "o.json").exists()
    said = " ".join(result.stderr.split())
    assert ("4 values the robot would not execute as asked: point 0: joint_2 position -0.7 rad beyond the limit "
            "-0.5 rad; point 1: joint_2 position -0.65 rad beyond the limit -0.5 rad; point 2: joint_2 position -0.6 "
            "rad beyond the limit -0.5 rad (and 1 more); clip (--clip) clips them") in said
    assert "velocit" not in said


def test_from_python_the_refusal_names_the_clip_argument_beside_the_option(windup_arm, low_arm):
    """plan() without clip said "--clip clips them" to a Python caller, whose argument is clip=True."""
    from rlff.robot.plan import load_for_robot

    robot_file, throw = windup_arm
    with pytest.raises(InputError, match=r"\(and 1 more\); clip \(--clip\) clips them$"):
        load_for_robot(throw, load_robot(robot_file))
    robot_file, throw = low_arm
    for clip in (False, True):
        with pytest.raises(InputError, match=rf"^{re.escape(f'{throw}: {HELD}')}"):
            load_for_robot(throw, load_robot(robot_file), clip=clip)


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


def test_a_plan_prints_as_one_short_line_not_its_arrays(windup_arm):
    """The dataclass' own repr printed every array of both trajectories: kilobytes for one throw."""
    from rlff.robot.plan import load_for_robot

    robot_file, throw = windup_arm
    _, planned = load_for_robot(throw, load_robot(robot_file), clip=True)
    traj = planned.trajectory
    assert repr(planned) == (f"RobotPlan({len(traj)} points, {traj.duration:.3f} s, release at {traj.release_time:.3f} "
                             "s, joints=['joint_1', 'joint_2', 'joint_3', 'joint_4', 'joint_5', 'joint_6'], from 31 "
                             f"mapped points, clipped={len(planned.clipped_points.changes)})")
    assert len(planned.clipped_points.changes) > 0 and "\n" not in repr(planned)

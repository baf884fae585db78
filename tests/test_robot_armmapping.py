"""Whole-arm mapping: several human joints drive several robot joints on one time base."""

from __future__ import annotations

from importlib import resources

import numpy as np
import pytest

from rlff.dataset import velocity_column
from rlff.errors import InputError
from rlff.robot import ArmMapping, RobotMapping, load_robot, mapping_for
from rlff.trajectory.limits import CLIP_CLEARANCE
from wholearm import human_throw


@pytest.fixture(scope="module")
def robot():
    return load_robot()


@pytest.fixture(scope="module")
def arm(robot):
    return ArmMapping.for_robot(robot, ("joint_2", "joint_3", "joint_5"))


def table(robot, joint):
    return robot.whole_arm["joints"][joint]


def test_each_driven_joint_follows_its_human_joint_on_one_time_base(robot, arm):
    path = human_throw(3.0)
    traj, report = arm.path_to_robot(path)
    assert not report and traj.joint_names == robot.joint_names
    assert arm.driven_joints == ("joint_3", "joint_2", "joint_5")
    assert arm.human_columns == ("angle", "shoulder", "wrist")
    for joint, human in zip(arm.driven_joints, arm.human_columns, strict=True):
        entry, column = table(robot, joint), robot.index(joint)
        np.testing.assert_allclose(traj.positions[:, column], entry["offset"] + entry["scale"] * path[human])
        np.testing.assert_allclose(traj.velocities[:, column],
                                   entry["scale"] * path[velocity_column(human)] / arm.time_scale)
    np.testing.assert_allclose(traj.time, path["time"] * robot.whole_arm["time_scale"])
    for joint in ("joint_1", "joint_4", "joint_6"):
        column = robot.index(joint)
        assert np.all(traj.positions[:, column] == robot.whole_arm["start_pose"][joint])
        assert np.all(traj.velocities[:, column] == 0)


def test_a_joint_of_the_table_not_asked_for_rests_at_the_start_pose(robot):
    two = ArmMapping.for_robot(robot, ("joint_3", "joint_2"))
    traj, _ = two.path_to_robot(human_throw(3.0, wrist=False))
    assert two.driven_joints == ("joint_3", "joint_2")
    assert np.all(traj.positions[:, robot.index("joint_5")] == robot.whole_arm["start_pose"]["joint_5"])


def test_without_time_the_elbow_times_the_path(robot, arm):
    path = human_throw(3.0)
    timed, _ = arm.path_to_robot(path)
    untimed, _ = arm.path_to_robot({k: v for k, v in path.items() if k != "time"})
    # where the elbow moves, the steps of time_along_path (2 d angle / (v_i + v_i+1)) are those of
    # the exact minimum-jerk time to 1 %; the start from rest is timed differently
    np.testing.assert_allclose(np.diff(untimed.time[10:]), np.diff(timed.time[10:]), rtol=0.01)


def test_the_bearing_turns_joint_1_through_the_whole_throw(robot, arm):
    traj, _ = arm.path_to_robot(human_throw(3.0), bearing=60.0)
    straight, _ = arm.path_to_robot(human_throw(3.0))
    column = robot.index("joint_1")
    np.testing.assert_allclose(traj.positions[:, column], np.radians(60.0))
    others = [i for i in range(len(robot.joints)) if i != column]
    np.testing.assert_array_equal(traj.positions[:, others], straight.positions[:, others])
    with pytest.raises(InputError, match=r"bearing 200 deg turns joint_1 to 3.491 rad, beyond its limits"):
        arm.path_to_robot(human_throw(3.0), bearing=200.0)
    # just past the limit: as many digits as tell the two apart (it read "to 2.967 rad, beyond its
    # limits [-2.967, 2.967] rad (-170 to 170 deg)")
    with pytest.raises(InputError, match=r"^bearing 170 deg turns joint_1 to 2.9671 rad, beyond its limits \[-2.967, "
                                         r"2.967\] rad \(bearings -169.997 to 169.997 deg\)$"):
        arm.path_to_robot(human_throw(3.0), bearing=170.0)


def test_path_from_robot_gives_back_the_human_path(arm):
    path = human_throw(3.0)
    back = arm.path_from_robot(arm.path_to_robot(path)[0])
    assert set(back) == set(path)
    for name, values in path.items():
        np.testing.assert_allclose(back[name], values - (values[0] if name == "time" else 0), atol=1e-12)


def test_max_human_speeds_are_the_robot_limits_in_human_units(robot, arm):
    speeds = arm.max_human_speeds()
    assert set(speeds) == {"velocity", "shoulder_velocity", "wrist_velocity"}
    path = human_throw(3.0)
    for column, limit in speeds.items():
        # at exactly the human limit the robot joint runs at its speed limit
        scaled = dict(path)
        scaled[column] = np.full_like(path[column], limit * (1 - 1e-12))  # rounding
        traj, _ = arm.path_to_robot(scaled)
        joint = arm.driven_joints[[velocity_column(h) for h in arm.human_columns].index(column)]
        np.testing.assert_allclose(np.abs(traj.velocities[:, robot.index(joint)]), robot.joint(joint).max_velocity)
    one = RobotMapping.for_robot(robot)
    assert one.max_human_speeds() == {"velocity": robot.joint("joint_2").max_velocity / one.velocity_scale}


def test_a_point_beyond_a_limit_is_refused_or_clipped_and_reported(robot, arm):
    path = human_throw(3.0)
    path["shoulder"] = path["shoulder"] - 1.3  # the first pose's joint_2 below its lower limit
    with pytest.raises(InputError, match=r"point 0: joint_2 position -1\.[5-9]\d* rad beyond the limit -1.48 rad"):
        arm.path_to_robot(path)
    traj, report = arm.path_to_robot(path, clip=True)
    assert report and {c.joint for c in report.changes} == {"joint_2"}
    clipped = traj.positions[:, robot.index("joint_2")]
    assert clipped[0] == pytest.approx(-1.48 + CLIP_CLEARANCE) and clipped.min() > -1.48  # held inside its limit


def test_missing_columns_are_named(arm):
    path = human_throw(8.0, wrist=False)
    with pytest.raises(InputError, match="the path lacks the columns wrist, wrist_velocity"):
        arm.path_to_robot(path)


@pytest.mark.parametrize(("joints", "message"), [
    (("joint_2", "joint_9"), r"joints \['joint_9'\] are not in .*\[whole_arm\].joints \(mapped: joint_2, joint_3, joint_5\)"),
    (("joint_2", "joint_5"), "must include the one following the elbow .*: joint_3"),
    ((), r"joints \(--joints\) names no joint"),
    # blamed on the robot file ("each robot joint ... may be driven once"), or "must include ...: joint_3"
    (("joint_2", "joint_3", "joint_3"), r"^joint_3 given twice in joints joint_2,joint_3,joint_3 \(--joints\): give "
                                        r"each joint once \(joint_2,joint_3\)$"),
    (("joint_2", "joint_2"), r"^joint_2 given twice in joints joint_2,joint_2 \(--joints\): give each joint once"),
])
def test_joints_the_robot_file_does_not_map_are_refused(robot, joints, message):
    with pytest.raises(InputError, match=message):
        mapping_for(robot, joints)


def test_mapping_for_without_joints_is_the_one_joint_mapping_exactly(robot):
    for joints in (None, ("joint_2",)):
        one = mapping_for(robot, joints)
        assert isinstance(one, RobotMapping) and one == RobotMapping.for_robot(robot)
    assert isinstance(mapping_for(robot, ["joint_2", "joint_3"]), ArmMapping)
    one = RobotMapping.for_robot(robot)
    angle = np.linspace(0.8, 2.9, 20)
    velocity = 4.0 * np.sin(np.linspace(0.1, 1.4, 20))
    old, _ = one.to_robot(angle, velocity)
    new, _ = one.path_to_robot({"angle": angle, "velocity": velocity})
    np.testing.assert_array_equal(new.positions, old.positions)
    np.testing.assert_array_equal(new.time, old.time)
    assert one.driven_joints == ("joint_2",) and one.human_columns == ("angle",)
    turned, _ = one.path_to_robot({"angle": angle, "velocity": velocity}, bearing=-30.0)
    np.testing.assert_allclose(turned.positions[:, robot.index("joint_1")], np.radians(-30.0))
    back = one.path_from_robot(old)
    np.testing.assert_allclose(back["angle"], angle)
    np.testing.assert_allclose(back["time"], old.time / one.time_scale)


def robot_file(tmp_path, change):
    template = (resources.files("rlff") / "robots" / "comau_smart5_six.toml").read_text()
    path = tmp_path / "robot.toml"
    path.write_text(change(template))
    return load_robot(path)


def test_bad_whole_arm_tables_are_refused_naming_the_field(tmp_path):
    no_table = robot_file(tmp_path, lambda text: text[:text.index("[whole_arm]")] + text[text.index("[comau_program]"):])
    with pytest.raises(InputError, match="robot.toml has no \\[whole_arm\\] table"):
        mapping_for(no_table, ("joint_2", "joint_3"))
    assert mapping_for(no_table, None) == RobotMapping.for_robot(no_table)
    no_scale = robot_file(tmp_path, lambda text: text.replace("time_scale = ", "# time_scale = "))
    with pytest.raises(InputError, match=r"\[whole_arm\]: missing field 'time_scale'"):
        mapping_for(no_scale, ("joint_2", "joint_3"))
    bad_human = robot_file(tmp_path, lambda text: text.replace('human = "wrist"', 'human = "knee"'))
    with pytest.raises(InputError, match=r"joints.joint_5: human must be one of angle, shoulder, wrist, got 'knee'"):
        mapping_for(bad_human, ("joint_2", "joint_3", "joint_5"))
    # refused when the file is read, as every command reads it (tests/test_robot_file_sanity.py)
    with pytest.raises(InputError, match=r"robot.toml: \[whole_arm.start_pose\]: joint_4 9 rad is outside its limits"):
        robot_file(tmp_path, lambda text: text.replace("joint_4 = 0.0\njoint_5 = -0.198\njoint_6 = 0.0\n\n# The Comau",
                                                       "joint_4 = 9.0\njoint_5 = -0.198\njoint_6 = 0.0\n\n# The Comau"))


def test_the_path_protocol_example_of_robot_md_runs_on_a_path_fast_along_the_way(robot):
    # it called path_to_robot without clip: a generated whole-arm path whose joint_2 velocities
    # along the way lie beyond the limit (plan_path, executing the first pose and the release,
    # plans it) was an InputError there ("78 values beyond the robot's limits")
    import re
    from pathlib import Path

    page = (Path(__file__).resolve().parents[1] / "docs" / "robot.md").read_text()
    block = re.search(r"\*\*The path protocol\.\*\*.*?```python\n(.*?)```", page, re.S)
    assert block, "docs/robot.md no longer shows the path protocol"
    two = mapping_for(robot, ("joint_2", "joint_3"))
    path = human_throw(3.0)
    path["shoulder_velocity"][:3] = 3 * two.max_human_speeds()["shoulder_velocity"]  # joint_2 at 3x its limit
    with pytest.raises(InputError, match=r"^3 values beyond the robot's limits: point 0: joint_2 velocity"):
        two.path_to_robot(path, bearing=30.0)
    scope = {"path": path}
    exec(block[1], scope)
    assert scope["clipped"].summary() == "clipped 0 positions and 3 velocities at 3 points"
    assert scope["result"].trajectory.positions.shape[1] == len(robot.joint_names)


def test_a_release_held_at_a_limit_is_no_throw_only_when_every_driven_joint_rests(robot, arm):
    """The ball leaves with the joints that still move at the release: one joint held at a position
    limit by clip is still a throw; every driven joint at rest there is none, refused with clip too
    (until 2026-12-07 exported with exit 0, and rlff sim throw warned)."""
    from rlff.robot.plan import plan_path

    path = human_throw(3.0)
    path["shoulder"] = path["shoulder"] - (path["shoulder"][-1] - 0.3)  # joint_2's release below its lower limit
    planned = plan_path(arm, path, clip=True, throw=True)
    release = planned.points.velocities[-1]
    assert release[robot.index("joint_2")] == 0 and release[robot.index("joint_3")] > 0
    at_rest = {name: np.r_[column[:-1], 0.0] if name.endswith("velocity") else column for name, column in path.items()}
    for clip in (False, True):
        with pytest.raises(InputError, match=r"^the ball would not be thrown: the release \(joint_2 at -1\.7\d* rad, "
                                             r"beyond its limit -1\.48 rad\) is beyond a position limit, .*\[whole_arm\] "
                                             r"mapping \(joint_3 offset -1\.891"):
            plan_path(arm, at_rest, clip=clip, throw=True)
